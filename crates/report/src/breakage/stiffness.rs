//! Contact ratio, mesh stiffness and load sharing of the broken pair against its healthy twin,
//! and `stiffness.csv` (the pair's table, also written by seed B's stiffness study). Checks seed A
//! 000 ¶3–6, 001 §2.2–2.4 (Figs. 2–4, Eqs. 1–7) and 002 §2.1, §4.

use super::{A000, A001};
use crate::claims::{Claim, Verdict};
use crate::readings::f;
use crate::runner::Ctx;
use crate::{Figure, Section};
use anyhow::Result;
use geardyn_physics::PairModel;
use geardyn_scenario::Scenario;
use std::path::Path;

/// Zone II has a lower stiffness when its mean lies at least this share below the healthy
/// pair's at the same phases.
const STIFFNESS_DROP: f64 = 0.1;
/// One tooth pair carries the load in zone II when its average share exceeds this ...
const SHARE_ALONE: f64 = 0.95;
/// ... while in the healthy double-tooth zones the larger share stays below this.
const SHARE_SHARED: f64 = 0.8;

/// What the study computed: the healthy twin and the stiffness and load sharing of zone II.
pub(super) struct StiffnessData {
    /// The healthy twin of the pair (no chipped tooth).
    healthy: PairModel,
    /// Half backlash of the scenario (D_d, D_s), the columns of `stiffness.csv`.
    backlash: (f64, f64),
    /// Contact ratio of the broken cycle.
    eps_b: f64,
    /// The broken mesh cycle.
    broken_cycle: f64,
    /// Mean mesh stiffness in zone II of the broken cycle (N/m).
    k_zone2: f64,
    /// Mean mesh stiffness of the healthy pair at the same phases (N/m).
    k_same_healthy: f64,
    /// The larger pair's mean load share in zone II.
    share_zone2: f64,
    /// The larger pair's mean load share in the healthy double-tooth zones.
    share_double: f64,
}

crate::runner::study!(Stiffness { pm: &'a PairModel, base: &'a Scenario } "stiffness" StiffnessData,
    |s, ctx, dir| compute(s.pm, s.base), |data| render(ctx, dir, s.pm, data));

/// Builds the healthy twin and reads zone II of the broken cycle against it.
pub(super) fn compute(pm: &PairModel, base: &Scenario) -> Result<StiffnessData> {
    let mut hs = pm.spec.clone();
    hs.breakage = None;
    let healthy = hs.build()?;
    let (dd, ds) = (base.params().d_double, base.params().d_single);
    let eps = pm.geom.eps;
    let eb = pm.eps_b.unwrap_or(eps);
    let nb = pm.spec.breakage.map_or(0, |b| b.broken_cycle) as f64;
    let in_cycle = |r: &&geardyn_physics::pair::StiffnessRow, a: f64, b: f64| {
        r.position >= nb + a && r.position < nb + b
    };
    let mean = |v: Vec<f64>| v.iter().sum::<f64>() / v.len().max(1) as f64;
    // zone II of the broken cycle against the same phases of a healthy cycle
    let k_zone2 = mean(
        pm.rows
            .iter()
            .filter(|r| in_cycle(r, eb - 1.0, eps - 1.0))
            .map(|r| r.k_mesh)
            .collect(),
    );
    let k_same_healthy = mean(
        healthy
            .rows
            .iter()
            .filter(|r| r.position >= eb - 1.0 && r.position < eps - 1.0)
            .map(|r| r.k_mesh)
            .collect(),
    );
    let share_zone2 = mean(
        pm.rows
            .iter()
            .filter(|r| in_cycle(r, eb - 1.0, eps - 1.0))
            .map(|r| r.share1.max(r.share2))
            .collect(),
    );
    let share_double = mean(
        healthy
            .rows
            .iter()
            .filter(|r| !r.single)
            .map(|r| r.share1.max(r.share2))
            .collect(),
    );
    Ok(StiffnessData {
        healthy,
        backlash: (dd, ds),
        eps_b: eb,
        broken_cycle: nb,
        k_zone2,
        k_same_healthy,
        share_zone2,
        share_double,
    })
}

/// `stiffness.csv`, the pair's figures, the readings and the claims.
pub(super) fn render(
    ctx: &Ctx,
    dir: &Path,
    pm: &PairModel,
    data: &StiffnessData,
) -> Result<Section> {
    let figs = stiffness_figures(ctx, dir, pm, &data.healthy, data.backlash)?;
    let eps = pm.geom.eps;
    let (eb, nb) = (data.eps_b, data.broken_cycle);
    let (k_zone2, k_same_healthy) = (data.k_zone2, data.k_same_healthy);
    let (share_zone2, share_double) = (data.share_zone2, data.share_double);
    let drop = 1.0 - k_zone2 / k_same_healthy;
    let claims = vec![
        Claim::new(
            "Breakage lowers the contact ratio: 1 < eps_b < eps_m < 2",
            format!("{A000} ¶4; {A001} §2.2"),
            "1 < eps_b < eps_m < 2",
            format!("eps_m = {}, eps_b = {}", f(eps), f(eb)),
            Verdict::of(1.0 < eb && eb < eps && eps < 2.0),
            format!(
                "Contact ratio from the path of contact AD over the base pitch; eps_b from the path AD1 of the chipped tooth ({} mm removed from the tip, the seed gives no chip size).",
                pm.spec
                    .breakage
                    .and_then(|b| b.removed_height_mm)
                    .map_or("?".into(), f)
            ),
        ),
        Claim::new(
            "eps_b = l_AD1 / p_b (Eq. 1, «epsilonb=pblAD1»)",
            format!("{A001} §2.2, Eq. (1)"),
            "l_AD1 / p_b, between 1 and eps_m",
            format!("l_AD1 / p_b = {}", f(eb)),
            Verdict::of(1.0 < eb && eb < eps),
            "Seed 001 writes fractions denominator first (its «T0=ωpzp2π» is 2π/(ω_p z_p), its exponent «53» is 3/5), so Eq. (1) reads l_AD1 / p_b: the path AD1 of the chipped tooth over the base pitch, as its defining sentence says.",
        ),
        Claim::new(
            "Part of the broken cycle's double-tooth zone becomes single-tooth zone II with lower stiffness",
            format!("{A000} ¶6; {A001} §2.3, §2.4.3"),
            "zone II with reduced stiffness k_ms2",
            format!(
                "zone II = [{}, {}) of cycle {}; mean stiffness there {} % below the healthy pair at the same phases",
                f(eb - 1.0),
                f(eps - 1.0),
                nb,
                f(100.0 * drop)
            ),
            Verdict::of(drop > STIFFNESS_DROP),
            "Potential-energy stiffness of the broken and the healthy pair (stiffness.csv).",
        ),
        Claim::new(
            "In the damaged zone the load shifts: one tooth pair carries it all",
            format!("{A000} ¶6"),
            "uneven load sharing, adjacent tooth overloaded",
            format!(
                "larger pair's load share on average: {} in zone II, {} in healthy double-tooth zones",
                f(share_zone2),
                f(share_double)
            ),
            Verdict::of(share_zone2 > SHARE_ALONE && share_double < SHARE_SHARED),
            "Load shares by pair stiffness (stiffness.csv, columns share1, share2).",
        ),
    ];
    Ok(Section {
        id: "stiffness".into(),
        title: "Contact ratio, mesh stiffness and load sharing of the broken pair".into(),
        seed_ref: "000 ¶3–6; 001 §2.2–2.4 (Figs. 2–4, Eqs. 1–7); 002 §2.1, §4".into(),
        parameters: format!(
            "External pair z1 = z2 = {}, m = {} mm, 20°, ha* = 1, c* = 0.25, face width {} mm (not in the seed), E = {} GPa, mu = {}; chipped tooth in cycle {}",
            pm.spec.z1, f(pm.spec.module_mm), f(pm.spec.face_width_mm), f(pm.spec.youngs_modulus_gpa), f(pm.spec.mu), nb
        ),
        method: format!(
            "Potential-energy method (Hertz, bending, shear, axial compression, fillet foundation), {} samples per mesh cycle; load sharing by pair stiffness; friction factors from the friction arms.",
            pm.spec.samples_per_cycle
        ),
        figures: figs,
        readings: vec![format!(
            "k_av = {} N/m, m_e = {} kg, omega_n = {} rad/s; contact ratio {} (healthy), {} (broken cycle).",
            f(pm.k_av),
            f(pm.m_e),
            f(pm.omega_n),
            f(eps),
            f(eb)
        )],
        tables: vec![],
        claims,
        alternatives: vec![],
        seconds: 0.0,
    })
}

/// Writes `stiffness.csv` of `pm` ([`write_stiffness_csv`]) and the pair's figures, against
/// `healthy` (`pm` itself for a pair without breakage), each with the table as its data.
pub(crate) fn stiffness_figures(
    ctx: &Ctx,
    dir: &Path,
    pm: &PairModel,
    healthy: &PairModel,
    (dd, ds): (f64, f64),
) -> Result<Vec<Figure>> {
    let csv = dir.join("stiffness.csv");
    write_stiffness_csv(&csv, pm, dd, ds)?;
    Ok(
        geardyn_io::pair_plots::pair_figures(dir, pm, healthy, dd, ds, "")?
            .iter()
            .map(|(stem, caption)| ctx.fig(stem, caption, std::slice::from_ref(&csv)))
            .collect(),
    )
}

/// `stiffness.csv`: the pair's table with the columns of `geardyn stiffness`
/// ([`geardyn_io::schema::pair_stiffness_table`]), six significant digits, every `step`-th sample
/// when the table is long; `dd`, `ds` the half backlash of the double- and single-tooth zones.
fn write_stiffness_csv(path: &Path, pm: &PairModel, dd: f64, ds: f64) -> Result<()> {
    let step = (pm.rows.len() / 6000).max(1);
    geardyn_io::schema::pair_stiffness_table(pm.rows.iter().step_by(step), dd, ds)
        .write_csv(path, crate::shared::g)?;
    Ok(())
}
