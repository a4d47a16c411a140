//! Branches of periodic orbits: pseudo-arclength continuation in any parameter, the
//! bifurcations along a branch (period doubling, fold, torus, grazing, corner collision) and
//! branch switching at a doubling. The single orbit, its map and multipliers: [`crate::orbits`].
//! For the single pair (2-D section).

use geardyn_scenario::Scenario;
use serde::Serialize;

use crate::orbits::*;

/// Kind of a bifurcation point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BifurcationKind {
    /// A multiplier through -1.
    PeriodDoubling,
    /// A multiplier through +1 (the branch turns back).
    Fold,
    /// A complex pair through the unit circle.
    Torus,
    /// The sequence of contact events changes (an extremum of `x` at a contact boundary).
    Grazing,
    /// A contact event crosses a mesh-stiffness breakpoint (zone border, broken-tooth edge,
    /// pitch point): the orbit passes through the corner of a contact boundary and a time
    /// boundary, the map's Jacobian jumps, and the multipliers with it. Located when the
    /// stability changes there.
    CornerCollision,
    /// A real multiplier passes through +1 while the branch goes on in the parameter (no fold)
    /// and two new orbits of the same period branch off, one on each side of the old one along
    /// the critical eigenvector ([`Bifurcation::branches`]): a pitchfork, the symmetry-breaking
    /// of a map with a symmetry (on the single pair: the revolution map of an orbit whose mesh
    /// clock doubles, the broken tooth's cycle apart).
    Pitchfork,
    /// As [`BifurcationKind::Pitchfork`] with one new orbit found: a transcritical branch point
    /// (or a pitchfork whose other orbit the search missed).
    BranchPoint,
    /// The stability changed between two branch points with no smooth bifurcation, grazing or
    /// corner collision between them (a border the detectors do not name): reported so that a
    /// change of stability is never silent.
    StabilityChange,
}

impl BifurcationKind {
    /// Every kind, in the order outputs list them.
    pub const ALL: [BifurcationKind; 8] = [
        BifurcationKind::PeriodDoubling,
        BifurcationKind::Fold,
        BifurcationKind::Grazing,
        BifurcationKind::Torus,
        BifurcationKind::CornerCollision,
        BifurcationKind::Pitchfork,
        BifurcationKind::BranchPoint,
        BifurcationKind::StabilityChange,
    ];

    /// The name written in outputs.
    pub fn name(self) -> &'static str {
        match self {
            BifurcationKind::PeriodDoubling => "period-doubling",
            BifurcationKind::Fold => "fold",
            BifurcationKind::Torus => "torus",
            BifurcationKind::Grazing => "grazing",
            BifurcationKind::CornerCollision => "corner-collision",
            BifurcationKind::Pitchfork => "pitchfork",
            BifurcationKind::BranchPoint => "branch-point",
            BifurcationKind::StabilityChange => "stability-change",
        }
    }
}

/// A point of a branch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BranchPoint {
    /// Branch index (0 the first; a doubled branch the next).
    pub branch: usize,
    /// Parameter value.
    pub param: f64,
    /// The orbit.
    pub orbit: Orbit,
}

/// A located bifurcation.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bifurcation {
    /// Kind.
    pub kind: BifurcationKind,
    /// Branch index.
    pub branch: usize,
    /// Parameter value.
    pub param: f64,
    /// The orbit there (on the side of the first of the two bracketing points).
    pub orbit: Orbit,
    /// The new orbits that branch off at a [`BifurcationKind::Pitchfork`] or
    /// [`BifurcationKind::BranchPoint`] (empty for the other kinds).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub branches: Vec<BranchOff>,
}

/// An orbit that branches off at a bifurcation, found near it on the side where the old orbit is
/// unstable.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BranchOff {
    /// Parameter value where it was found.
    pub param: f64,
    /// The orbit.
    pub orbit: Orbit,
}

/// Settings of a continuation.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ContinuationOptions {
    /// Parameter continued (a name `Scenario::with` takes: omega, F, xi, c, kappa, pair.mu, ...).
    pub param: String,
    /// Start value (the first orbit is found here).
    pub start: f64,
    /// Stop value (the branch is followed until it leaves `[min(start, stop), max(start, stop)]`).
    pub stop: f64,
    /// Largest arclength step (in the scaled `(x, x', p)` space).
    pub ds_max: f64,
    /// Most branch points in all (every branch).
    pub max_points: usize,
    /// Follow the doubled branch from each period doubling (up to this period).
    pub switch_up_to: u32,
    /// Shooting settings.
    pub orbit: OrbitOptions,
}

impl Default for ContinuationOptions {
    fn default() -> Self {
        ContinuationOptions {
            param: "omega".into(),
            start: 0.5,
            stop: 2.0,
            ds_max: 0.02,
            max_points: 2000,
            switch_up_to: 0,
            orbit: OrbitOptions::default(),
        }
    }
}

/// Branches and bifurcations of a continuation.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Continuation {
    /// Branch points, branch by branch, in the order followed.
    pub points: Vec<BranchPoint>,
    /// Bifurcations located.
    pub bifurcations: Vec<Bifurcation>,
    /// Why each branch ended (one line per branch).
    pub ends: Vec<String>,
}

impl Continuation {
    /// Appends the branches of `other` (a continuation from another start over the same
    /// parameter), numbered after this one's.
    pub fn merge(mut self, other: Continuation) -> Continuation {
        let offset = self.ends.len();
        self.points.extend(other.points.into_iter().map(|mut p| {
            p.branch += offset;
            p
        }));
        self.bifurcations
            .extend(other.bifurcations.into_iter().map(|mut b| {
                b.branch += offset;
                b
            }));
        // (each line starts with its branch's number)
        self.ends.extend(other.ends.into_iter().map(|e| {
            let Some(rest) = e.strip_prefix("branch ") else {
                return e;
            };
            let n = rest.chars().take_while(char::is_ascii_digit).count();
            match rest[..n].parse::<usize>() {
                Ok(k) => format!("branch {}{}", k + offset, &rest[n..]),
                Err(_) => e,
            }
        }));
        self
    }
}

/// `P_n - y` and its derivatives in `(y, p)`: `[M - I | dP/dp]`.
struct Extended {
    orbit_eval: MapEval<2>,
    r: [f64; 2],
    jac: [[f64; 3]; 2],
}

struct Problem<'a> {
    base: &'a Scenario,
    param: &'a str,
    o: OrbitOptions,
}

impl Problem<'_> {
    fn model(&self, p: f64) -> Result<Scenario, OrbitError> {
        Ok(self.base.with(self.param, p)?)
    }

    fn dp(&self, p: f64) -> f64 {
        1e-6 * p.abs().max(1e-2)
    }

    fn extended(&self, y: [f64; 2], p: f64, memory: f64) -> Result<Extended, OrbitError> {
        let sc = self.model(p)?;
        let e = map_eval(sc.model(), y, memory, &self.o)?;
        let h = self.dp(p);
        let up = map_only(self.model(p + h)?.model(), y, memory, &self.o)?;
        let dn = map_only(self.model(p - h)?.model(), y, memory, &self.o)?;
        let r = [e.y[0] - y[0], e.y[1] - y[1]];
        let jac = [
            [e.jac[0][0] - 1.0, e.jac[0][1], (up[0] - dn[0]) / (2.0 * h)],
            [e.jac[1][0], e.jac[1][1] - 1.0, (up[1] - dn[1]) / (2.0 * h)],
        ];
        Ok(Extended {
            orbit_eval: e,
            r,
            jac,
        })
    }

    /// The orbit at fixed `p` near `y` (natural-parameter correction), the memory at the
    /// stroboscopic instant starting from `memory`.
    fn at(&self, y: [f64; 2], p: f64, memory: f64) -> Result<Orbit, OrbitError> {
        let sc = self.model(p)?;
        newton(sc.model(), y, memory, &self.o)
    }
}

/// The unit null vector of the 2 x 3 matrix `j` (the cross product of its rows).
fn null_vector(j: &[[f64; 3]; 2]) -> [f64; 3] {
    let (a, b) = (j[0], j[1]);
    let t = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let n = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
    [t[0] / n, t[1] / n, t[2] / n]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Test functions of a branch point: period doubling, torus (NaN without a complex pair).
fn tests(o: &Orbit) -> (f64, f64) {
    let m = &o.monodromy;
    let pd = (m[0][0] + 1.0) * (m[1][1] + 1.0) - m[0][1] * m[1][0];
    let complex = o.multipliers[0].im != 0.0;
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    (pd, if complex { det - 1.0 } else { f64::NAN })
}

/// Continues the branch of period-`opts.orbit.period` orbits through `y0` at `opts.start` in
/// `opts.param` up to `opts.stop` (see the module doc).
///
/// ```
/// use geardyn_analysis::orbit_branches::{continue_orbits, BifurcationKind, ContinuationOptions};
/// use geardyn_analysis::simulate::{simulate, SimOptions};
/// use geardyn_scenario::ScenarioSpec;
/// // case C1, the period-1 branch from omega = 0.8 to 0.95: it doubles near 0.88
/// let sc = ScenarioSpec::preset("classic").unwrap().resolve().unwrap();
/// let at = sc.with("omega", 0.8).unwrap();
/// let sim = SimOptions { record_periods: 1, ..Default::default() };
/// let near = simulate(at.model(), [0.0, 0.0], &sim).unwrap().final_state.1;
/// let opts = ContinuationOptions { start: 0.8, stop: 0.95, ..Default::default() };
/// let c = continue_orbits(&sc, near, &opts, &|_| {}).unwrap();
/// let pd = c.bifurcations.iter().find(|b| b.kind == BifurcationKind::PeriodDoubling).unwrap();
/// assert!((pd.param - 0.88).abs() < 0.01);
/// ```
pub fn continue_orbits(
    base: &Scenario,
    y0: [f64; 2],
    opts: &ContinuationOptions,
    progress: &(dyn Fn(&BranchPoint) + Sync),
) -> Result<Continuation, OrbitError> {
    check(&opts.orbit)?;
    for (field, v) in [("start", opts.start), ("stop", opts.stop)] {
        if !v.is_finite() {
            return Err(OrbitError::Setting {
                field,
                value: geardyn_model::error::num(v),
                allowed: "a finite number".into(),
            });
        }
    }
    if !(opts.ds_max > 0.0 && opts.ds_max.is_finite()) {
        return Err(OrbitError::Setting {
            field: "ds_max",
            value: geardyn_model::error::num(opts.ds_max),
            allowed: "> 0".into(),
        });
    }
    let mut out = Continuation::default();
    // the first orbit at its least period (a period given as a multiple of it would follow the
    // powers of its multipliers)
    let first = {
        let m = base.with(&opts.param, opts.start)?;
        let o = newton(m.model(), y0, 0.0, &opts.orbit)?;
        minimal(m.model(), o, &opts.orbit)?
    };
    let mut queue: Vec<(u32, f64, [f64; 2], f64)> = vec![(first.period, opts.start, first.y, 0.0)];
    while let Some((period, p0, y, dir)) = queue.pop() {
        if out.points.len() >= opts.max_points {
            break;
        }
        let branch = out.ends.len();
        if dir != 0.0 {
            let near = out.points.iter().find(|q| {
                q.orbit.period == period
                    && (q.param - p0).abs() <= 2.0 * opts.ds_max
                    && (q.orbit.y[0] - y[0]).abs().max((q.orbit.y[1] - y[1]).abs())
                        <= 2.0 * opts.ds_max
            });
            if let Some(q) = near {
                out.ends.push(format!(
                    "branch {branch} (period {period}): already followed as branch {}",
                    q.branch
                ));
                continue;
            }
        }
        let prob = Problem {
            base,
            param: &opts.param,
            o: OrbitOptions {
                period,
                ..opts.orbit
            },
        };
        let doublings = follow(&prob, branch, p0, y, dir, opts, &mut out, progress)?;
        for (p, y, v) in doublings {
            if period * 2 <= opts.switch_up_to {
                if let Some((y2, d2)) = switch(&prob, p, y, v, opts) {
                    queue.push((period * 2, p, y2, d2));
                }
            }
        }
    }
    Ok(out)
}

/// A period doubling of a branch: the parameter, the orbit's point and the flip eigenvector.
type Doubling = (f64, [f64; 2], [f64; 2]);

/// Follows one branch from `(p0, y)`; returns its period doublings.
#[allow(clippy::too_many_arguments)]
fn follow(
    prob: &Problem<'_>,
    branch: usize,
    p0: f64,
    y: [f64; 2],
    dir: f64,
    opts: &ContinuationOptions,
    out: &mut Continuation,
    progress: &(dyn Fn(&BranchPoint) + Sync),
) -> Result<Vec<Doubling>, OrbitError> {
    let (lo, hi) = (opts.start.min(opts.stop), opts.start.max(opts.stop));
    let first = match prob
        .at(y, p0, 0.0)
        .and_then(|o| minimal(prob.model(p0)?.model(), o, &prob.o))
    {
        Ok(o) if o.period != prob.o.period && branch > 0 => {
            out.ends.push(format!(
                "branch {branch}: the doubled orbit found is the period-{} orbit",
                o.period
            ));
            return Ok(Vec::new());
        }
        Ok(o) => o,
        Err(e) if branch > 0 => {
            out.ends
                .push(format!("branch {branch}: no orbit at the start ({e})"));
            return Ok(Vec::new());
        }
        Err(e) => return Err(e),
    };
    // the branch goes towards `stop` (or the direction given by a branch switch)
    let want = if dir != 0.0 {
        dir
    } else if opts.stop >= opts.start {
        1.0
    } else {
        -1.0
    };
    let mut cur = BranchPoint {
        branch,
        param: p0,
        orbit: first,
    };
    progress(&cur);
    let first_index = out.points.len();
    let mut left_start = false;
    // the first orbit's points on the section
    let copies: Vec<[f64; 2]> = {
        let one = OrbitOptions {
            period: 1,
            ..prob.o
        };
        let mut v = vec![cur.orbit.y];
        if let Ok(m) = prob.model(p0) {
            let mut y = cur.orbit.y;
            for _ in 1..prob.o.period {
                match map_only(m.model(), y, cur.orbit.memory, &one) {
                    Ok(n) => {
                        y = n;
                        v.push(y);
                    }
                    Err(_) => break,
                }
            }
        }
        v
    };
    out.points.push(cur.clone());
    let ext = prob.extended(cur.orbit.y, p0, cur.orbit.memory)?;
    let mut tan = null_vector(&ext.jac);
    if tan[2] * want < 0.0 {
        tan = [-tan[0], -tan[1], -tan[2]];
    }
    let mut ds = opts.ds_max * 0.25;
    let mut clipped = false;
    let ds_min = opts.ds_max * 1e-6;
    let mut doublings = Vec::new();
    let end = loop {
        if out.points.len() >= opts.max_points {
            break "the point limit was reached".to_string();
        }
        let Some((ext, iters, z)) = correct(prob, &cur, tan, ds) else {
            ds *= 0.5;
            if ds < ds_min {
                break format!(
                    "the corrector failed at {} = {} (step below {ds_min:e}; largest multiplier there {:.4})",
                    prob.param, cur.param, cur.orbit.multipliers[0].abs()
                );
            }
            continue;
        };
        let new_tan = oriented(&ext.jac, tan);
        let next = BranchPoint {
            branch,
            param: z[2],
            orbit: Orbit::from_eval([z[0], z[1]], ext.orbit_eval, prob.o.period, iters),
        };
        // a jump in the event sequence wider than one grazing, or a large turn of the tangent:
        // a smaller step first
        if dot(new_tan, tan) < 0.9 && ds > ds_min * 16.0 {
            ds *= 0.5;
            continue;
        }
        // a step out of the range: once, the step that ends at its end instead (the branch is
        // drawn to the end of the range asked)
        let bound = if next.param > hi { hi } else { lo };
        if (next.param < lo || next.param > hi) && !clipped {
            let frac = (bound - cur.param) / (next.param - cur.param);
            if frac > 1e-6 && frac < 1.0 {
                clipped = true;
                ds *= frac;
                continue;
            }
        }
        // bifurcations between cur and next
        let found_before = out.bifurcations.len();
        let (pd0, ns0) = tests(&cur.orbit);
        let (pd1, ns1) = tests(&next.orbit);
        // (a multiplier that jumps across -1 or the unit circle at a grazing is no smooth
        // bifurcation: the grazing is reported, the jump is not)
        if pd0 * pd1 < 0.0 {
            if let Some(b) = locate(prob, &cur, &next, BifurcationKind::PeriodDoubling) {
                let critical = b
                    .orbit
                    .multipliers
                    .iter()
                    .any(|m| m.im == 0.0 && (m.re + 1.0).abs() < CRITICAL);
                if critical && fresh(out, &b) {
                    let v = flip_vector(&b.orbit.monodromy);
                    doublings.push((b.param, b.orbit.y, v));
                    out.bifurcations.push(b);
                }
            }
        }
        if ns0 * ns1 < 0.0 {
            if let Some(b) = locate(prob, &cur, &next, BifurcationKind::Torus) {
                if (b.orbit.multipliers[0].abs() - 1.0).abs() < CRITICAL && fresh(out, &b) {
                    out.bifurcations.push(b);
                }
            }
        }
        if tan[2] * new_tan[2] < 0.0 {
            // the turning point, refined by bisection in the arclength (else the branch point of
            // extreme parameter of the two)
            let b = refine_fold(prob, &cur, tan, ds).unwrap_or_else(|| {
                if (next.param - cur.param) * tan[2] >= 0.0 {
                    next.clone()
                } else {
                    cur.clone()
                }
            });
            let fold = Bifurcation {
                kind: BifurcationKind::Fold,
                branch,
                param: b.param,
                orbit: b.orbit,
                branches: Vec::new(),
            };
            // a doubled branch turns at the doubling it was born from (the vertex of the
            // pitchfork of the twice-iterated map): that is the doubling, not a fold
            let birth = out
                .bifurcations
                .iter()
                .find(|d| {
                    d.kind == BifurcationKind::PeriodDoubling
                        && 2 * d.orbit.period == fold.orbit.period
                        && (d.param - fold.param).abs() <= 1e-3 * (1.0 + d.param.abs())
                })
                .map(|d| (d.param, d.orbit.period));
            match birth {
                // the branch has come round to a doubling of its parent: beyond it, it would
                // retrace itself at the other phase
                Some((pd, n)) if left_start => {
                    progress(&next);
                    out.points.push(next.clone());
                    break format!(
                        "the branch reached the period doubling of the period-{n} branch at {} = {pd}",
                        prob.param
                    );
                }
                Some(_) => {}
                None => {
                    // a turn at a grazing is the grazing (reported as such)
                    let at_grazing = out.bifurcations.iter().any(|g| {
                        g.kind == BifurcationKind::Grazing
                            && g.orbit.period == fold.orbit.period
                            && (g.param - fold.param).abs() <= 1e-4 * (1.0 + g.param.abs())
                    }) || cur.orbit.event_word() != next.orbit.event_word();
                    if !at_grazing && fresh(out, &fold) {
                        out.bifurcations.push(fold);
                    }
                }
            }
        }
        if cur.orbit.event_word() != next.orbit.event_word() {
            if let Some(b) = locate(prob, &cur, &next, BifurcationKind::Grazing) {
                if fresh(out, &b) {
                    out.bifurcations.push(b);
                }
            }
        }
        if cur.orbit.stable != next.orbit.stable && out.bifurcations.len() == found_before {
            // the multipliers left (or entered) the unit circle with no bifurcation named: an
            // event crossed a stiffness breakpoint, or a border no detector knows
            let kind = if cur.orbit.event_word() == next.orbit.event_word()
                && cur.orbit.itinerary() != next.orbit.itinerary()
            {
                BifurcationKind::CornerCollision
            } else {
                BifurcationKind::StabilityChange
            };
            if let Some(mut b) = locate(prob, &cur, &next, kind) {
                if kind == BifurcationKind::StabilityChange {
                    // a real multiplier through +1 with the branch going on: look for the orbits
                    // that branch off (the side where the old orbit is unstable)
                    let unstable = if cur.orbit.stable { &next } else { &cur };
                    branch_off(prob, &mut b, unstable);
                }
                if fresh(out, &b) {
                    out.bifurcations.push(b);
                }
            }
        }
        if next.param < lo || next.param > hi {
            // the clipped step lands on the end up to the corrector's slack
            if clipped && (next.param - bound).abs() <= 1e-3 * (hi - lo) {
                progress(&next);
                out.points.push(next.clone());
            }
            break format!("{} left [{lo}, {hi}]", prob.param);
        }
        progress(&next);
        out.points.push(next.clone());
        cur = next;
        tan = new_tan;
        if iters <= 3 {
            ds = (ds * 1.5).min(opts.ds_max);
        }
        if cur.param < lo || cur.param > hi {
            break format!("{} left [{lo}, {hi}]", prob.param);
        }
        let scale = prob.base.model().backlash_levels().1.max(1.0);
        if cur.orbit.y[0].abs() > crate::classify::DIVERGED_SCALES * scale {
            break "the orbit ran away".to_string();
        }
        // a closed branch (an isola, or a doubled branch that meets its parent again) is
        // followed once around: it has closed when it comes back to the first orbit, at any of
        // its points on the section (the same orbit, another phase)
        let d = copies
            .iter()
            .map(|c| {
                (cur.orbit.y[0] - c[0])
                    .abs()
                    .max((cur.orbit.y[1] - c[1]).abs())
                    .max((cur.param - p0).abs())
            })
            .fold(f64::INFINITY, f64::min);
        if d > 5.0 * opts.ds_max {
            left_start = true;
        } else if left_start && d < 0.5 * opts.ds_max {
            break "the branch closed on itself".to_string();
        }
        // or it runs round a loop that does not hold its start (through non-smooth turning
        // points): it has come back to a point of its own, many steps ago
        let here = out.points.len() - 1;
        let revisit = out.points[first_index..here.saturating_sub(10).max(first_index)]
            .iter()
            .any(|q| {
                (cur.orbit.y[0] - q.orbit.y[0])
                    .abs()
                    .max((cur.orbit.y[1] - q.orbit.y[1]).abs())
                    .max((cur.param - q.param).abs())
                    < 0.1 * ds.min(opts.ds_max)
            });
        if revisit {
            break "the branch closed on itself (a loop)".to_string();
        }
        // an orbit of even period that became the orbit of half its period counted twice: the
        // doubled branch returned to its parent
        if prob.o.period.is_multiple_of(2) && out.points.len() - first_index > 2 {
            let half = OrbitOptions {
                period: prob.o.period / 2,
                ..prob.o
            };
            if let Ok(img) = prob
                .model(cur.param)
                .and_then(|m| map_only(m.model(), cur.orbit.y, cur.orbit.memory, &half))
            {
                let r = (img[0] - cur.orbit.y[0])
                    .abs()
                    .max((img[1] - cur.orbit.y[1]).abs());
                if r <= 1e3 * prob.o.tol * (1.0 + cur.orbit.y[0].abs()) {
                    break format!(
                        "the branch met the period-{} branch (at {} = {})",
                        half.period, prob.param, cur.param
                    );
                }
            }
        }
    };
    out.ends
        .push(format!("branch {branch} (period {}): {end}", prob.o.period));
    Ok(doublings)
}

/// The pseudo-arclength step of length `ds` from `cur` along `tan`: the predictor, then Newton's
/// method on `P_n(y; p) - y = 0` with the arclength condition; the corrected point `z = (x, x',
/// p)`, its extended Jacobian and the iterations, or `None` when the corrector fails.
fn correct(
    prob: &Problem<'_>,
    cur: &BranchPoint,
    tan: [f64; 3],
    ds: f64,
) -> Option<(Extended, u32, [f64; 3])> {
    let z0 = [cur.orbit.y[0], cur.orbit.y[1], cur.param];
    let pred = [
        z0[0] + ds * tan[0],
        z0[1] + ds * tan[1],
        z0[2] + ds * tan[2],
    ];
    let mut z = pred;
    let mut memory = cur.orbit.memory;
    let mut last_res = f64::INFINITY;
    for it in 0..8 {
        let ext = prob.extended([z[0], z[1]], z[2], memory).ok()?;
        let settled = (ext.orbit_eval.memory - memory).abs() <= prob.o.tol * (1.0 + memory.abs());
        memory = ext.orbit_eval.memory;
        let res = ext.r[0].abs().max(ext.r[1].abs());
        let arc = dot([z[0] - pred[0], z[1] - pred[1], z[2] - pred[2]], tan);
        let scale = 1.0 + z[0].abs().max(z[1].abs());
        // converged, or at the integration's noise floor (as `newton`)
        let floor = res <= NOISE_FLOOR * scale && res > 0.5 * last_res;
        last_res = res;
        if (res <= prob.o.tol * scale || floor) && arc.abs() < 1e-9 && settled {
            return Some((ext, it, z));
        }
        let a = [ext.jac[0], ext.jac[1], tan];
        let dz = solve3(a, [-ext.r[0], -ext.r[1], -arc])?;
        z = [z[0] + dz[0], z[1] + dz[1], z[2] + dz[2]];
        if !z.iter().all(|v| v.is_finite()) {
            return None;
        }
    }
    None
}

/// The null vector of an extended Jacobian, oriented along `tan`.
fn oriented(jac: &[[f64; 3]; 2], tan: [f64; 3]) -> [f64; 3] {
    let t = null_vector(jac);
    if dot(t, tan) < 0.0 {
        [-t[0], -t[1], -t[2]]
    } else {
        t
    }
}

/// The turning point of a branch between `cur` and the point a step `ds` along `tan` beyond it
/// (whose tangent's parameter component has the other sign): bisection in the arclength on
/// that sign, each trial point corrected by [`correct`] (well posed at a fold, unlike Newton's
/// method at fixed parameter).
fn refine_fold(
    prob: &Problem<'_>,
    cur: &BranchPoint,
    tan: [f64; 3],
    ds: f64,
) -> Option<BranchPoint> {
    let (mut a, mut b) = (0.0, ds);
    let mut best = None;
    for _ in 0..50 {
        if b - a <= 1e-10 * ds {
            break;
        }
        let m = 0.5 * (a + b);
        let (ext, iters, z) = correct(prob, cur, tan, m)?;
        if oriented(&ext.jac, tan)[2] * tan[2] > 0.0 {
            a = m;
        } else {
            b = m;
        }
        best = Some(BranchPoint {
            branch: cur.branch,
            param: z[2],
            orbit: Orbit::from_eval([z[0], z[1]], ext.orbit_eval, prob.o.period, iters),
        });
    }
    best
}

/// Whether `b` is not already listed: the same kind at the same parameter (to 1e-7) on a branch
/// of the same period is the same point seen at another phase of the orbit (a branch of period
/// `n` passes through each of its `n` points on the section).
fn fresh(out: &Continuation, b: &Bifurcation) -> bool {
    !out.bifurcations.iter().any(|o| {
        o.kind == b.kind
            && o.orbit.period == b.orbit.period
            && (o.param - b.param).abs() <= 1e-7 * (1.0 + b.param.abs())
    })
}

/// The eigenvector of `m` for its multiplier nearest -1.
fn flip_vector(m: &[[f64; 2]; 2]) -> [f64; 2] {
    eigenvector_near(m, -1.0)
}

/// The unit eigenvector of `m` for its real multiplier nearest `target`.
fn eigenvector_near(m: &[[f64; 2]; 2], target: f64) -> [f64; 2] {
    let mu = eigenvalues(m)
        .into_iter()
        .filter(|u| u.im == 0.0)
        .min_by(|a, b| (a.re - target).abs().total_cmp(&(b.re - target).abs()))
        .map(|u| u.re)
        .unwrap_or(target);
    // (m - mu I) v = 0: v from the row of larger norm
    let a = [m[0][0] - mu, m[0][1]];
    let b = [m[1][0], m[1][1] - mu];
    let r = if a[0].hypot(a[1]) >= b[0].hypot(b[1]) {
        a
    } else {
        b
    };
    let v = [-r[1], r[0]];
    let n = v[0].hypot(v[1]);
    if n > 0.0 {
        [v[0] / n, v[1] / n]
    } else {
        [1.0, 0.0]
    }
}

/// Bisection in `p` between two branch points whose test function (of `kind`) differs, each
/// trial orbit corrected at fixed `p` from the interpolated point.
fn locate(
    prob: &Problem<'_>,
    a: &BranchPoint,
    b: &BranchPoint,
    kind: BifurcationKind,
) -> Option<Bifurcation> {
    let value = |o: &Orbit| match kind {
        BifurcationKind::PeriodDoubling => tests(o).0,
        BifurcationKind::Torus => tests(o).1,
        _ => 0.0,
    };
    let word_a = a.orbit.event_word();
    let itinerary_a = a.orbit.itinerary();
    let side_a = |o: &Orbit| match kind {
        BifurcationKind::Grazing => o.event_word() == word_a,
        BifurcationKind::CornerCollision => o.itinerary() == itinerary_a,
        BifurcationKind::StabilityChange => o.stable == a.orbit.stable,
        _ => value(o) * value(&a.orbit) > 0.0,
    };
    let (mut pa, mut ya, mut oa) = (a.param, a.orbit.y, a.orbit.clone());
    let (mut pb, mut yb) = (b.param, b.orbit.y);
    for _ in 0..60 {
        if (pb - pa).abs() <= 1e-10 * (1.0 + pa.abs()) {
            break;
        }
        let pm = 0.5 * (pa + pb);
        let ym = [0.5 * (ya[0] + yb[0]), 0.5 * (ya[1] + yb[1])];
        let Ok(om) = prob.at(ym, pm, oa.memory) else {
            break;
        };
        // Newton at fixed `p` is ill-conditioned where a multiplier nears +1: an orbit far
        // from the bracket is another branch's, and the bracket is as close as it gets
        let gap = (ya[0] - yb[0]).abs().max((ya[1] - yb[1]).abs());
        let off = (om.y[0] - ym[0]).abs().max((om.y[1] - ym[1]).abs());
        if off > 2.0 * gap + 1e-9 * (1.0 + ym[0].abs().max(ym[1].abs())) {
            break;
        }
        if side_a(&om) {
            (pa, ya, oa) = (pm, om.y, om);
        } else {
            (pb, yb) = (pm, om.y);
        }
    }
    Some(Bifurcation {
        kind,
        branch: a.branch,
        param: 0.5 * (pa + pb),
        orbit: oa,
        branches: Vec::new(),
    })
}

/// A multiplier within this distance of +1 makes a stability change a candidate branch point.
const NEAR_ONE: f64 = 0.05;

/// At a stability change `b` whose leading multiplier is real and near +1, the orbits of the same
/// period that branch off: on the side where the old orbit is unstable, at its branch point
/// `unstable` (the old orbit known there: Newton at fixed parameter is ill-conditioned next to a
/// multiplier +1 and would not find it again), Newton from the old orbit displaced by `±eps`
/// along its eigenvector of the unstable real multiplier. Each orbit found that is neither the
/// old one nor another found one is kept; two (a symmetric pair, one on each side) make the
/// point a [`BifurcationKind::Pitchfork`], one a [`BifurcationKind::BranchPoint`].
fn branch_off(prob: &Problem<'_>, b: &mut Bifurcation, unstable: &BranchPoint) {
    let mu = b.orbit.multipliers[0];
    if mu.im != 0.0 || (mu.re - 1.0).abs() > NEAR_ONE {
        return;
    }
    let old = &unstable.orbit;
    let p = unstable.param;
    let lead = old.multipliers[0];
    if lead.im != 0.0 || lead.re <= 1.0 {
        return;
    }
    let v = eigenvector_near(&old.monodromy, lead.re);
    let scale = 1.0 + old.y[0].abs().max(old.y[1].abs());
    let same =
        |a: [f64; 2], c: [f64; 2]| (a[0] - c[0]).abs().max((a[1] - c[1]).abs()) <= 1e-6 * scale;
    let mut found: Vec<BranchOff> = Vec::new();
    for sign in [1.0, -1.0] {
        for eps in [1e-3, 1e-2, 3e-2, 1e-1] {
            let start = [old.y[0] + sign * eps * v[0], old.y[1] + sign * eps * v[1]];
            let Ok(o) = prob.at(start, p, old.memory) else {
                continue;
            };
            let near = (o.y[0] - old.y[0]).abs().max((o.y[1] - old.y[1]).abs()) <= 0.5 * scale;
            if near
                && o.period == old.period
                && !same(o.y, old.y)
                && !found.iter().any(|f| same(f.orbit.y, o.y))
            {
                found.push(BranchOff { param: p, orbit: o });
                break;
            }
        }
    }
    if !found.is_empty() {
        b.kind = if found.len() >= 2 {
            BifurcationKind::Pitchfork
        } else {
            BifurcationKind::BranchPoint
        };
        b.branches = found;
    }
}

/// The doubled orbit near a period doubling `(p, y)` with flip eigenvector `v`: Newton for twice
/// the period from `y +- eps v`, slightly to either side of `p`; the start and direction of its
/// branch.
fn switch(
    prob: &Problem<'_>,
    p: f64,
    y: [f64; 2],
    v: [f64; 2],
    opts: &ContinuationOptions,
) -> Option<([f64; 2], f64)> {
    let o2 = OrbitOptions {
        period: prob.o.period * 2,
        ..prob.o
    };
    let doubled = Problem {
        base: prob.base,
        param: prob.param,
        o: o2,
    };
    let span = (opts.stop - opts.start).abs().max(1e-6);
    for dp in [1e-3 * span, -1e-3 * span, 1e-2 * span, -1e-2 * span] {
        for eps in [1e-2, 1e-3, 1e-1] {
            let start = [y[0] + eps * v[0], y[1] + eps * v[1]];
            let found = doubled
                .at(start, p + dp, 0.0)
                .ok()
                .filter(|o| (o.y[0] - y[0]).abs().max((o.y[1] - y[1]).abs()) <= 0.5);
            if let Some(o) = found {
                // not the period-n orbit counted twice
                let Ok(sc) = doubled.model(p + dp) else {
                    continue;
                };
                let Ok(img) = map_only(sc.model(), o.y, o.memory, &prob.o) else {
                    continue;
                };
                let d = (img[0] - o.y[0]).abs().max((img[1] - o.y[1]).abs());
                if d > 1e-6 * (1.0 + o.y[0].abs()) {
                    return Some((o.y, dp.signum()));
                }
            }
        }
    }
    None
}
