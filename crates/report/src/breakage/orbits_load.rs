//! Seed A's load sweep seen through its periodic orbits: the branch of the healthy orbit the
//! pair settles on at high load, followed down in F by shooting and pseudo-arclength
//! continuation, drawn over the brute-force diagram of the same range. It says where that orbit
//! stops being an attractor and how (a named bifurcation, a corner collision, or a stability
//! change no smooth test names), which a forward sweep cannot: below that point the sweep shows
//! whatever attracts instead.

use crate::readings::f;
use crate::runner::Ctx;
use crate::Section;
use anyhow::Result;
use geardyn_analysis::orbit_branches::{BifurcationKind, Continuation};
use geardyn_analysis::orbits::describe_orbit;
use geardyn_analysis::orbits_request::OrbitsRequest;
use geardyn_scenario::Scenario;
use std::path::Path;

const SOURCE: &str = "seed A 000 (summary) ¶9; 001 (paper) §4";

/// The load the branch starts from (reached from rest after the default transient: the
/// `1-20-0` orbit of the high loads) and the range followed, at the load sweep's speed.
const START: f64 = 0.088;
const RANGE: (f64, f64) = (0.03, 0.12);
const QUICK_RANGE: (f64, f64) = (0.07, 0.1);

/// A stability change at the lowest stable orbit counts as where it stops attracting when it lies
/// within this distance (in F) of it.
const LOST_NEAR: f64 = 0.01;
/// A real multiplier this close to +1 at an unnamed stability change is said to cross +1.
const MULTIPLIER_ONE: f64 = 0.05;

/// What the study computed: the branch of the high-load orbit.
pub(super) struct OrbitsLoadData {
    /// The scenario at the load sweep's speed.
    scenario: Scenario,
    /// That speed.
    omega: f64,
    /// The range of F followed.
    range: (f64, f64),
    /// The branch, followed down and up from [`START`].
    branch: Continuation,
}

crate::runner::study!(OrbitsLoad { base: &'a Scenario, omega: f64 } "orbits_load" OrbitsLoadData,
    |s, ctx, dir| compute(ctx, s.base, s.omega), |data| render(ctx, dir, data), serde_json::json!(s.omega.to_bits()));

/// Follows the orbit reached from rest at [`START`] down and up in F.
pub(super) fn compute(ctx: &Ctx, base: &Scenario, omega: f64) -> Result<OrbitsLoadData> {
    let b = base.with("omega", omega)?;
    // (a quick page follows fewer points over a shorter range: the branch ends in a singular
    // stretch where the corrector's steps shrink, and the continuation runs on one core)
    let (lo, hi) = ctx.n(QUICK_RANGE, RANGE);
    let max_points = ctx.n(14, 400);
    let req = OrbitsRequest {
        max_points,
        ..Default::default()
    };
    let branch = crate::shared::branch_both_ways(&b, "F", START, (lo, hi), &req)?;
    Ok(OrbitsLoadData {
        scenario: b,
        omega,
        range: (lo, hi),
        branch,
    })
}

/// The orbit figure over the simulated points and the reading of where the orbit stops
/// attracting.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &OrbitsLoadData) -> Result<Section> {
    let (b, omega, (lo, hi), c) = (&data.scenario, data.omega, data.range, &data.branch);
    let (fig, mut readings) = crate::shared::orbit_figure(
        ctx,
        dir,
        b,
        "F",
        (lo, hi),
        [0.0, 0.0],
        // (each value is 360 revolutions of 40 mesh cycles)
        ctx.n(8, 60),
        c,
        "Seed A: periodic orbits over F",
        &format!("The orbit reached from rest at F = {START} followed down and up in F at omega = {omega} (stable orbits as lines, unstable ones as dots, bifurcation points marked), over the stroboscopic points simulated from rest (grey)."),
    )?;
    let stable_low = c
        .points
        .iter()
        .filter(|p| p.orbit.stable)
        .map(|p| p.param)
        .reduce(f64::min);
    let lost = c
        .bifurcations
        .iter()
        .filter(|x| stable_low.is_some_and(|s| (x.param - s).abs() < LOST_NEAR))
        .min_by(|a, b| b.param.total_cmp(&a.param));
    if let (Some(s), Some(x)) = (stable_low, lost) {
        let mu = &x.orbit.multipliers;
        let how = match x.kind {
            BifurcationKind::Pitchfork => pitchfork_text(b, x),
            BifurcationKind::StabilityChange if mu[0].im == 0.0 && (mu[0].re - 1.0).abs() < MULTIPLIER_ONE => {
                "a real multiplier crosses +1 while the branch goes on in F (no fold turns it back, no contact event changes): a stability change none of the smooth tests names".to_string()
            }
            k => format!("a {}", k.name()),
        };
        readings.push(format!(
            "The period-{} orbit of the high loads is an attractor down to F = {}: there {how} (multipliers {} and {}). Below it the orbit goes on unstable: no forward simulation settles on it there.",
            x.orbit.period,
            f(x.param.min(s)),
            f(mu[0].re),
            f(mu[1].re),
        ));
    }
    Ok(Section {
        id: "orbits_load".into(),
        title: "Periodic orbits over F: where the high-load orbit stops attracting".into(),
        seed_ref: SOURCE.into(),
        parameters: format!(
            "F in [{lo}, {hi}] from F = {START}, omega = {omega}, the broken pair"
        ),
        method: "Shooting on the stroboscopic map (Newton, monodromy matrix from the variational equation with saltation matrices, DP5 rtol 1e-11) and pseudo-arclength continuation over F from the orbit reached from rest at the start; every change of stability between two branch points is located by bisection and named (period doubling, fold, torus, grazing, corner collision, or an unnamed stability change).".into(),
        figures: vec![fig],
        readings,
        tables: vec![],
        claims: vec![],
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// Two summaries alike to this relative difference (largest mesh force, P_ID) describe one
/// motion.
const SAME_MOTION: f64 = 1e-6;

/// A pitchfork in words: the multiplier through +1 and the two orbits that branch off, with
/// their labels and mesh periods. On the broken pair the two are one motion seen at two phases
/// of the mesh clock (equal label, forces and P_ID; the referee shifted one by two mesh cycles
/// onto the other): the mesh-cycle motion doubles its period, which the revolution map, with its
/// even number of mesh cycles, sees as a pitchfork.
fn pitchfork_text(b: &Scenario, x: &geardyn_analysis::orbit_branches::Bifurcation) -> String {
    let at = |p: f64, o: &geardyn_analysis::orbits::Orbit| {
        b.with("F", p)
            .ok()
            .and_then(|s| describe_orbit(s.model(), o, 0.0).ok())
    };
    let old = at(x.param, &x.orbit);
    let new: Vec<_> = x
        .branches
        .iter()
        .map(|n| (n, at(n.param, &n.orbit)))
        .collect();
    let mesh = |d: &Option<geardyn_analysis::simulate::Summary>| {
        d.as_ref()
            .and_then(|d| d.mesh_period)
            .map_or(String::new(), |m| format!(" ({m} mesh cycles)"))
    };
    let listed: Vec<String> = new
        .iter()
        .map(|(n, d)| {
            format!(
                "x = {}{}{} ({}, |multiplier| {})",
                f(n.orbit.y[0]),
                d.as_ref()
                    .map_or(String::new(), |d| format!(" {}", d.label)),
                mesh(d),
                if n.orbit.stable { "stable" } else { "unstable" },
                f(n.orbit.multipliers[0].abs())
            )
        })
        .collect();
    let alike = match &new[..] {
        [(_, Some(a)), (_, Some(c))] => {
            let close =
                |u: f64, v: f64| (u - v).abs() <= SAME_MOTION * u.abs().max(v.abs()).max(1.0);
            a.label == c.label && close(a.max_force, c.max_force) && close(a.p_id, c.p_id)
        }
        _ => false,
    };
    let what = if alike {
        format!(
            "one motion at two phases of the mesh clock (equal label, largest mesh force and P_ID): the mesh-cycle motion of the old orbit{} doubles its period, which the revolution map sees as a pitchfork",
            mesh(&old)
        )
    } else {
        "a symmetric pair (equal multipliers)".to_string()
    };
    format!(
        "a pitchfork of the revolution map: a real multiplier crosses +1 while the branch goes on in F (no fold, no contact event changes) and two new orbits of the same period branch off at F = {}, one on each side of the old one: {}; {what}",
        f(x.branches.first().map_or(x.param, |n| n.param)),
        listed.join(" and ")
    )
}
