//! Periodic orbits of the non-smooth model: shooting on the stroboscopic map, Floquet
//! multipliers, pseudo-arclength continuation in any parameter, and the bifurcations along a
//! branch (period doubling, fold, torus, grazing). docs/analyses.md, "Periodic orbits".
//!
//! **Which systems.** A single orbit — the map [`stroboscopic_map`], shooting [`find_orbit`],
//! [`minimal`], the [`Orbit`] with its multipliers, [`describe_orbit`] — is computed for any
//! [`GearSystem`] of state dimension `N` (1 to 24: [`TangentSpace`] integrates its tangent
//! dynamics), e.g. the two-mass toy [`geardyn_model::reference::TwoMassClearance`]. The branch
//! continuation ([`crate::orbit_branches::continue_orbits`], [`crate::orbits_request::run_orbits`]: pseudo-arclength, bifurcation detection and
//! location, branch switching) is for the single pair ([`geardyn_model::MeshModel`], `N = 2`,
//! parameters of a [`Scenario`](geardyn_scenario::Scenario)) only. For the pair every result is bit-identical to the former
//! pair-only code: the 2 x 2 closed forms ([`eigenvalues`], the 2 x 2 solve) are kept for `N = 2`.
//!
//! * **The map.** `P_n(y)`: the state after `n` excitation periods from `y` at the stroboscopic
//!   phase `tau0`, integrated by the adaptive Dormand–Prince integrator with exact event location.
//!   Its Jacobian (the monodromy matrix `M` at a fixed point) comes from the variational equation
//!   integrated with the flow, mapped by the saltation matrix at every contact event and impact
//!   reset ([`crate::lyapunov::Tangent`], the same code as the Lyapunov exponents): one run per
//!   column ([`TangentSpace::tangent_flow`]), `N` runs.
//! * **Shooting.** Newton's method on `P_n(y) - y = 0` with the Jacobian `M - I`; the orbit's
//!   Floquet multipliers are the eigenvalues of `M` ([`floquet_multipliers`]; 2 x 2: closed form;
//!   larger: the real Schur form; complex pairs kept).
//! * **Continuation** (the pair). Pseudo-arclength in `(x, x', p)`: the tangent of the branch is the null
//!   vector of `[M - I | dP/dp]` (`dP/dp` by central differences), the corrector Newton's method
//!   on the fixed-point equation plus the arclength condition, so folds are passed and unstable
//!   orbits followed like stable ones.
//! * **Bifurcations**, located between two branch points where a test function changes sign:
//!   period doubling `det(M + I)` (a multiplier through -1), torus `det(M) - 1` with a complex
//!   pair (through the unit circle), fold the `p` component of the tangent (a multiplier through
//!   +1: the branch turns back), grazing a change of the orbit's sequence of contact events (an
//!   extremum of `x` reaches a contact boundary). Doubling, torus and grazing points are refined
//!   by bisection in `p` (the orbit corrected at fixed `p`); the continuation goes on with the
//!   new sequence of events, as the flow is exact on both sides.
//! * **Branch switching** at a period doubling onto the doubled branch: Newton for `2n` periods
//!   from the doubling point displaced along the eigenvector of the multiplier -1.
//!
//! Limits: near grazing the saltation matrix is unbounded (multipliers jump there, and Newton may
//! need a smaller step); a contact law with memory (hysteresis of an impact in progress at the
//! stroboscopic instant) adds a dimension the `N x N` map leaves out; a tooth resting on the back
//! stop has a multiplier 0 (a perturbation annihilated).
//!
//! Units: dimensionless time `tau`, displacement in units of the length scale, the parameter in
//! its own unit.

use crate::driver::run_periods;
use crate::lyapunov::TangentSpace;
use crate::simulate::{simulate, Method, SimOptions};
use geardyn_model::GearSystem;
use geardyn_scenario::ScenarioError;
use geardyn_solvers::{Integrator, Scheme, SolverError};
use serde::Serialize;

/// Settings of shooting and continuation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OrbitOptions {
    /// Excitation periods of the orbit (`n` of `P_n`).
    pub period: u32,
    /// Stroboscopic phase (start time of the map).
    pub tau0: f64,
    /// Relative tolerance of the integration.
    pub rtol: f64,
    /// Absolute tolerance of the integration.
    pub atol: f64,
    /// Newton converges when `|P_n(y) - y|` (max norm) is below `tol (1 + |y|)`.
    pub tol: f64,
    /// Most Newton iterations of one correction.
    pub max_iter: u32,
}

impl Default for OrbitOptions {
    fn default() -> Self {
        OrbitOptions {
            period: 1,
            tau0: 0.0,
            rtol: 1e-11,
            atol: 1e-13,
            tol: 1e-9,
            max_iter: 30,
        }
    }
}

/// A located period doubling (torus) is smooth when a multiplier lies this close to -1 (the unit
/// circle) there; farther, the multipliers jumped across at a grazing.
pub(crate) const CRITICAL: f64 = 1e-2;

/// Largest residual `|P_n(y) - y| / (1 + |y|)` accepted as the integration's noise floor when
/// Newton's steps stop reducing it (see [`find_orbit`]).
pub const NOISE_FLOOR: f64 = 1e-6;

/// Largest orbit period accepted (excitation periods).
pub const MAX_ORBIT_PERIOD: u32 = 256;

/// Failure of an orbit computation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OrbitError {
    /// The integration failed.
    #[error("integrating the orbit failed: {0} (a larger rtol, or a shorter period, may pass)")]
    Solver(#[from] SolverError),
    /// The scenario refused a parameter value.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// Newton's method did not converge.
    #[error("no periodic orbit of period {period} found near x = {x}, x' = {v}: Newton's method did not converge in {iterations} iterations (residual {residual:e}); start closer to the orbit (--set x0= --set v0=, a longer --transient) or try another --period")]
    NoConvergence {
        /// Period sought.
        period: u32,
        /// Last iterate: the first mesh's relative displacement ([`GearSystem::mesh_state`];
        /// the pair's `x`).
        x: f64,
        /// Last iterate: the first mesh's relative velocity (the pair's `x'`).
        v: f64,
        /// Iterations taken.
        iterations: u32,
        /// Last residual.
        residual: f64,
    },
    /// The motion after the transient is not periodic and no period was given.
    #[error("the motion from x0 = {x0}, v0 = {v0} is {motion} after {transient} periods (decided as geardyn simulate decides it): give period N (--period N) to seek an orbit of N excitation periods (stable or not) near it, or start elsewhere (x0, v0)")]
    NotPeriodic {
        /// The decided motion.
        motion: String,
        /// Initial state.
        x0: f64,
        /// Initial state.
        v0: f64,
        /// Transient periods.
        transient: u64,
    },
    /// A setting outside its range.
    #[error("bad {field} {value}: allowed {allowed}")]
    Setting {
        /// The setting.
        field: &'static str,
        /// Its value.
        value: String,
        /// The range.
        allowed: String,
    },
}

/// A Floquet multiplier `re + i im`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Multiplier {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

impl Multiplier {
    /// Modulus.
    pub fn abs(&self) -> f64 {
        self.re.hypot(self.im)
    }
}

/// The eigenvalues of a 2 x 2 matrix, largest modulus first (a complex pair: positive imaginary
/// part first).
pub fn eigenvalues(m: &[[f64; 2]; 2]) -> [Multiplier; 2] {
    let tr = m[0][0] + m[1][1];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let disc = 0.25 * tr * tr - det;
    if disc >= 0.0 {
        let s = disc.sqrt();
        // the larger root without cancellation, the other from the product
        let a = 0.5 * tr + if tr >= 0.0 { s } else { -s };
        let b = if a != 0.0 { det / a } else { 0.5 * tr - s };
        let (a, b) = if a.abs() >= b.abs() { (a, b) } else { (b, a) };
        [Multiplier { re: a, im: 0.0 }, Multiplier { re: b, im: 0.0 }]
    } else {
        let im = (-disc).sqrt();
        [
            Multiplier { re: 0.5 * tr, im },
            Multiplier {
                re: 0.5 * tr,
                im: -im,
            },
        ]
    }
}

/// The eigenvalues of an `N x N` matrix (the Floquet multipliers of a monodromy matrix), largest
/// modulus first, a complex pair kept together (positive imaginary part first).
///
/// `N = 2`: [`eigenvalues`] (closed form). Otherwise the real Schur form (`nalgebra`), each 2 x 2
/// diagonal block by the closed form; NaN for a matrix with a non-finite entry (or whose Schur
/// iteration does not converge).
///
/// ```
/// use geardyn_analysis::orbits::floquet_multipliers;
/// // a rotation by 90 degrees scaled by 0.5, and a real multiplier 2 beside it
/// let m = [[0.0, -0.5, 0.0], [0.5, 0.0, 0.0], [0.0, 0.0, 2.0]];
/// let mu = floquet_multipliers(&m);
/// assert_eq!((mu[0].re, mu[0].im), (2.0, 0.0));
/// assert!((mu[1].im - 0.5).abs() < 1e-15 && (mu[2].im + 0.5).abs() < 1e-15);
/// assert!(mu[1].re.abs() < 1e-15 && mu[2].re == mu[1].re);
/// ```
pub fn floquet_multipliers<const N: usize>(m: &[[f64; N]; N]) -> [Multiplier; N] {
    if N == 2 {
        let mu = eigenvalues(&[[m[0][0], m[0][1]], [m[1][0], m[1][1]]]);
        return std::array::from_fn(|i| mu[i]);
    }
    let nan = Multiplier {
        re: f64::NAN,
        im: f64::NAN,
    };
    if !m.iter().flatten().all(|v| v.is_finite()) {
        return [nan; N];
    }
    // components whose row and column are zero off the diagonal (a padded train's padding:
    // copies of one decay factor) are their own multipliers, exactly; the Schur iteration does
    // not always converge with such a block of equal eigenvalues beside the rest
    let decoupled = |i: usize| (0..N).all(|j| j == i || (m[i][j] == 0.0 && m[j][i] == 0.0));
    let (alone, rest): (Vec<usize>, Vec<usize>) = (0..N).partition(|&i| decoupled(i));
    let mut blocks: Vec<Vec<Multiplier>> = alone
        .iter()
        .map(|&i| {
            vec![Multiplier {
                re: m[i][i],
                im: 0.0,
            }]
        })
        .collect();
    let n = rest.len();
    let a = nalgebra::DMatrix::from_fn(n, n, |i, j| m[rest[i]][rest[j]]);
    let t = if n == 0 {
        a
    } else {
        let Some(schur) = nalgebra::linalg::Schur::try_new(a, f64::EPSILON, 1000 * n) else {
            return [nan; N];
        };
        schur.unpack().1
    };
    // the diagonal blocks: 1 x 1 (a real multiplier) or 2 x 2 (a pair)
    let mut i = 0;
    while i < n {
        if i + 1 < n && t[(i + 1, i)] != 0.0 {
            let b = [
                [t[(i, i)], t[(i, i + 1)]],
                [t[(i + 1, i)], t[(i + 1, i + 1)]],
            ];
            blocks.push(eigenvalues(&b).to_vec());
            i += 2;
        } else {
            blocks.push(vec![Multiplier {
                re: t[(i, i)],
                im: 0.0,
            }]);
            i += 1;
        }
    }
    // a block of two real multipliers is two blocks
    let mut blocks: Vec<Vec<Multiplier>> = blocks
        .into_iter()
        .flat_map(|b| {
            if b.len() == 2 && b[0].im == 0.0 {
                vec![vec![b[0]], vec![b[1]]]
            } else {
                vec![b]
            }
        })
        .collect();
    blocks.sort_by(|a, b| {
        b[0].abs()
            .total_cmp(&a[0].abs())
            .then(b[0].re.total_cmp(&a[0].re))
    });
    let flat: Vec<Multiplier> = blocks.into_iter().flatten().collect();
    std::array::from_fn(|i| flat[i])
}

/// The map `P_n` at one point: the image, its Jacobian and the orbit's contact events.
#[derive(Clone, Debug)]
pub(crate) struct MapEval<const N: usize> {
    pub(crate) y: [f64; N],
    pub(crate) jac: [[f64; N]; N],
    /// Contact state entered at each event, in order from the stroboscopic instant.
    pub(crate) events: Vec<i8>,
    /// Mesh of each event.
    pub(crate) meshes: Vec<usize>,
    /// Segment of the excitation period ([`GearSystem::segment`]) in which each event happened.
    pub(crate) segments: Vec<u32>,
    /// Memory parameter of the mode at the end ([`geardyn_solvers::HybridSystem::memory`]).
    pub(crate) memory: f64,
}

/// The contact events of a run: the contact state each mesh entered, the mesh, and the segment
/// of the excitation period it happened in.
#[derive(Default)]
pub(crate) struct Events {
    codes: Vec<i8>,
    meshes: Vec<usize>,
    segments: Vec<u32>,
}

impl Events {
    /// A step after which the mode changed from `before` to `after`: one event per mesh whose
    /// contact state changed, in mesh order.
    fn record<S: GearSystem<N>, const N: usize>(
        &mut self,
        sys: &S,
        before: &S::Mode,
        after: &S::Mode,
    ) {
        for k in 0..sys.mesh_count() {
            let c = sys.contact(after, k);
            if sys.contact(before, k) != c {
                self.codes.push(c.code());
                self.meshes.push(k);
                self.segments.push(sys.segment(after));
            }
        }
    }
}

/// The integrator of the maps.
pub(crate) fn scheme(o: &OrbitOptions) -> Scheme {
    Scheme::DormandPrince {
        rtol: o.rtol,
        atol: o.atol,
    }
}

/// `P_n(y)` with its Jacobian: one run of the flow and its tangent per column (the events and
/// the image from the first).
pub(crate) fn map_eval<S, const N: usize>(
    sys: &S,
    y: [f64; N],
    memory: f64,
    o: &OrbitOptions,
) -> Result<MapEval<N>, OrbitError>
where
    S: GearSystem<N> + TangentSpace<N>,
{
    let mut ev = Events::default();
    let mut image = y;
    let mut memory_out = memory;
    let mut jac = [[0.0; N]; N];
    let (period, n) = (sys.excitation_period(), u64::from(o.period));
    for k in 0..N {
        let mut d = [0.0; N];
        d[k] = 1.0;
        let f = if k == 0 {
            let mut on = |b: &S::Mode, a: &S::Mode| ev.record(sys, b, a);
            let f = sys.tangent_flow(scheme(o), o.tau0, y, memory, d, period, n, &mut on)?;
            image = f.y;
            memory_out = f.memory;
            f
        } else {
            sys.tangent_flow(scheme(o), o.tau0, y, memory, d, period, n, &mut |_, _| {})?
        };
        for (row, v) in jac.iter_mut().zip(f.d) {
            row[k] = v;
        }
    }
    Ok(MapEval {
        y: image,
        jac,
        events: ev.codes,
        meshes: ev.meshes,
        segments: ev.segments,
        memory: memory_out,
    })
}

/// The stroboscopic map `P_n(y)` of `sys` (`n = opts.period` excitation periods from `y` at
/// `opts.tau0`) and its Jacobian by the variational equation with saltation matrices.
///
/// ```
/// use geardyn_analysis::orbits::{stroboscopic_map, OrbitOptions};
/// use geardyn_model::reference::TwoMassClearance;
/// // the toy in drive contact throughout: a linear map, its Jacobian exp(A T) of det exp(tr A T)
/// let sys = TwoMassClearance { load: [2.0, 1.0], ..Default::default() };
/// let (_, m) = stroboscopic_map(&sys, [2.9, 0.0, 0.9, 0.0], &OrbitOptions::default()).unwrap();
/// let det = nalgebra::Matrix4::from_fn(|i, j| m[i][j]).determinant();
/// // tr A = -(c0 + 2 c1) = -0.3 (unit masses)
/// let t = 2.0 * std::f64::consts::PI / sys.omega;
/// assert!((det - (-0.3 * t).exp()).abs() < 1e-8);
/// ```
pub fn stroboscopic_map<S, const N: usize>(
    sys: &S,
    y: [f64; N],
    opts: &OrbitOptions,
) -> Result<([f64; N], [[f64; N]; N]), OrbitError>
where
    S: GearSystem<N> + TangentSpace<N>,
{
    check(opts)?;
    let e = map_eval(sys, y, 0.0, opts)?;
    Ok((e.y, e.jac))
}

/// `P_n(y)` alone (no tangent).
pub(crate) fn map_only<S: GearSystem<N>, const N: usize>(
    sys: &S,
    y: [f64; N],
    memory: f64,
    o: &OrbitOptions,
) -> Result<[f64; N], OrbitError> {
    let mut it = Integrator::new(sys, scheme(o), o.tau0, y)?.with_memory(memory);
    run_periods(
        &mut it,
        sys.excitation_period(),
        u64::from(o.period),
        &mut crate::driver::Discard,
    )?;
    Ok(*it.y())
}

/// Largest modulus of the components of `v` (the max norm; NaN-ignoring as `f64::max`, NaN when
/// all are).
pub(crate) fn max_abs<const N: usize>(v: &[f64; N]) -> f64 {
    v[1..].iter().fold(v[0].abs(), |m, x| m.max(x.abs()))
}

/// `max_abs(a - b)`.
pub(crate) fn max_abs_diff<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    max_abs::<N>(&std::array::from_fn(|i| a[i] - b[i]))
}

/// A periodic orbit of a system of state dimension `N` (default: the pair's 2): its point on the
/// stroboscopic section and its stability.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(bound(
    serialize = "[f64; N]: Serialize, [[f64; N]; N]: Serialize, [Multiplier; N]: Serialize"
))]
pub struct Orbit<const N: usize = 2> {
    /// Point on the section at the stroboscopic phase (the pair: `(x, x')`).
    pub y: [f64; N],
    /// Excitation periods.
    pub period: u32,
    /// Monodromy matrix (the Jacobian of `P_n` at `y`).
    pub monodromy: [[f64; N]; N],
    /// Floquet multipliers, largest modulus first ([`floquet_multipliers`]).
    pub multipliers: [Multiplier; N],
    /// Every multiplier inside the unit circle.
    pub stable: bool,
    /// Contact state entered at each event over the orbit, from the stroboscopic instant.
    pub events: Vec<i8>,
    /// Mesh of each of `events` (all 0 for one mesh). Serialized only when an event is on
    /// another mesh than the first (a single mesh's files, the pair's `orbits.json`, are as
    /// before the orbits were generic).
    #[serde(skip_serializing_if = "first_mesh_only")]
    pub event_meshes: Vec<usize>,
    /// Segment of the excitation period ([`GearSystem::segment`]; for the pair the zone piece,
    /// [`geardyn_model::mesh_model::Segment`]) in which each of `events` happened.
    pub segments: Vec<u32>,
    /// `|P_n(y) - y|` (max norm) at `y`.
    pub residual: f64,
    /// Newton iterations taken.
    pub iterations: u32,
    /// Memory parameter of the mode at the stroboscopic instant (the hysteresis factor of an
    /// impact in progress there, [`geardyn_solvers::HybridSystem::memory`]; 0 for laws without
    /// memory): a simulation of the orbit starts with it.
    pub memory: f64,
}

/// Whether every event is on the first mesh.
pub(crate) fn first_mesh_only(meshes: &[usize]) -> bool {
    meshes.iter().all(|&k| k == 0)
}

impl<const N: usize> Orbit<N> {
    pub(crate) fn from_eval(y: [f64; N], e: MapEval<N>, period: u32, iterations: u32) -> Orbit<N> {
        let multipliers = floquet_multipliers(&e.jac);
        let residual = max_abs_diff(&e.y, &y);
        Orbit {
            y,
            period,
            monodromy: e.jac,
            stable: multipliers[0].abs() < 1.0,
            multipliers,
            memory: e.memory,
            events: e.events,
            event_meshes: e.meshes,
            segments: e.segments,
            residual,
            iterations,
        }
    }

    /// The event sequence `(mesh, contact state entered)` as a cyclic word, rotated to its least
    /// rotation (an event moving across the stroboscopic instant is no change of the orbit).
    pub fn event_word(&self) -> Vec<(usize, i8)> {
        let w: Vec<(usize, i8)> = self
            .event_meshes
            .iter()
            .copied()
            .zip(self.events.iter().copied())
            .collect();
        least_rotation(&w)
    }

    /// The events `(mesh, contact state entered, segment)` as a cyclic word (least rotation):
    /// the orbit's itinerary through the contact boundaries and the time breakpoints (for the
    /// pair: zone borders, the broken tooth's edges, the pitch point). It changes, with the
    /// contact word unchanged, when an event crosses a breakpoint: there the map is continuous
    /// but its Jacobian jumps (a corner collision).
    pub fn itinerary(&self) -> Vec<(usize, i8, u32)> {
        let w: Vec<(usize, i8, u32)> = self
            .event_meshes
            .iter()
            .zip(&self.events)
            .zip(&self.segments)
            .map(|((&k, &c), &s)| (k, c, s))
            .collect();
        least_rotation(&w)
    }
}

/// The least rotation of a cyclic word (an event moving across the stroboscopic instant is no
/// change of the orbit).
pub(crate) fn least_rotation<T: Clone + Ord>(e: &[T]) -> Vec<T> {
    (0..e.len().max(1))
        .map(|k| {
            let k = k.min(e.len());
            let mut r = e[k..].to_vec();
            r.extend_from_slice(&e[..k]);
            r
        })
        .min()
        .unwrap_or_default()
}

pub(crate) fn check(o: &OrbitOptions) -> Result<(), OrbitError> {
    if o.period == 0 || o.period > MAX_ORBIT_PERIOD {
        return Err(OrbitError::Setting {
            field: "period",
            value: o.period.to_string(),
            allowed: format!("1 ..= {MAX_ORBIT_PERIOD}"),
        });
    }
    for (field, v) in [("rtol", o.rtol), ("atol", o.atol), ("tol", o.tol)] {
        if !(v > 0.0 && v < 1e-2) {
            return Err(OrbitError::Setting {
                field,
                value: geardyn_model::error::num(v),
                allowed: "(0, 0.01)".into(),
            });
        }
    }
    if !o.tau0.is_finite() {
        return Err(OrbitError::Setting {
            field: "tau0",
            value: geardyn_model::error::num(o.tau0),
            allowed: "a finite number".into(),
        });
    }
    Ok(())
}

/// Solves the 2 x 2 system `a z = b`; `None` when singular.
pub(crate) fn solve2(a: &[[f64; 2]; 2], b: [f64; 2]) -> Option<[f64; 2]> {
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    if det.is_nan() || det.abs() <= 1e-14 * scale * scale {
        return None;
    }
    Some([
        (b[0] * a[1][1] - b[1] * a[0][1]) / det,
        (a[0][0] * b[1] - a[1][0] * b[0]) / det,
    ])
}

/// Solves the `N x N` system `a z = b`: [`solve2`] for `N = 2`, else Gaussian elimination with
/// partial pivoting; `None` when (numerically) singular.
#[allow(clippy::needless_range_loop)]
pub(crate) fn solve_n<const N: usize>(a: &[[f64; N]; N], b: [f64; N]) -> Option<[f64; N]> {
    if N == 2 {
        let z = solve2(&[[a[0][0], a[0][1]], [a[1][0], a[1][1]]], [b[0], b[1]])?;
        return Some(std::array::from_fn(|i| z[i]));
    }
    let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let (mut a, mut b) = (*a, b);
    for c in 0..N {
        let p = (c..N).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].is_nan() || a[p][c].abs() <= 1e-14 * scale {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..N {
            let f = a[r][c] / a[c][c];
            for k in c..N {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut z = [0.0; N];
    for r in (0..N).rev() {
        let mut s = b[r];
        for k in r + 1..N {
            s -= a[r][k] * z[k];
        }
        z[r] = s / a[r][r];
    }
    z.iter().all(|v| v.is_finite()).then_some(z)
}

/// Solves the 3 x 3 system `a z = b` by Gaussian elimination with partial pivoting.
#[allow(clippy::needless_range_loop)]
pub(crate) fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for c in 0..3 {
        let p = (c..3).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].is_nan() || a[p][c].abs() <= 1e-300 {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..3 {
            let f = a[r][c] / a[c][c];
            for k in c..3 {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut z = [0.0; 3];
    for r in (0..3).rev() {
        let mut s = b[r];
        for k in r + 1..3 {
            s -= a[r][k] * z[k];
        }
        z[r] = s / a[r][r];
    }
    z.iter().all(|v| v.is_finite()).then_some(z)
}

/// A periodic orbit of `n = opts.period` excitation periods of `sys` near `y0` by Newton's
/// method on the stroboscopic map (see the module doc), at its least period ([`minimal`]).
///
/// Newton's method converges from a state near the orbit: a state on the attractor (after a
/// transient), or a point of a neighbouring orbit.
///
/// ```
/// use geardyn_analysis::orbits::{find_orbit, OrbitOptions};
/// use geardyn_analysis::simulate::{simulate, SimOptions};
/// use geardyn_model::{presets, MeshModel};
/// // C1 at omega = 0.8: a stable period-1 orbit that leaves contact once per period
/// let mut p = presets::classic();
/// p.omega = 0.8;
/// let m = MeshModel::new(&p).unwrap();
/// let near = simulate(&m, [0.0, 0.0], &SimOptions { record_periods: 1, ..Default::default() })
///     .unwrap()
///     .final_state
///     .1;
/// let orbit = find_orbit(&m, near, &OrbitOptions::default()).unwrap();
/// assert!(orbit.stable && orbit.residual < 1e-8 && orbit.events.len() == 2);
/// ```
///
/// Any [`GearSystem`] (of dimension 1 to 24, [`TangentSpace`]): the two-mass toy, its four
/// multipliers.
///
/// ```
/// use geardyn_analysis::orbits::{find_orbit, OrbitOptions};
/// use geardyn_model::reference::TwoMassClearance;
/// let sys = TwoMassClearance { load: [2.0, 1.0], ..Default::default() };
/// let o = find_orbit(&sys, [2.0, 0.0, 1.0, 0.0], &OrbitOptions::default()).unwrap();
/// assert!(o.stable && o.events.is_empty() && o.multipliers.len() == 4);
/// ```
pub fn find_orbit<S, const N: usize>(
    sys: &S,
    y0: [f64; N],
    opts: &OrbitOptions,
) -> Result<Orbit<N>, OrbitError>
where
    S: GearSystem<N> + TangentSpace<N>,
{
    check(opts)?;
    if sys.mesh_count() == 0 {
        return Err(OrbitError::Setting {
            field: "mesh_count",
            value: "0".into(),
            allowed: "at least one mesh (GearSystem::mesh_count)".into(),
        });
    }
    let o = newton(sys, y0, 0.0, opts)?;
    minimal(sys, o, opts)
}

/// The orbit at its least period: an orbit of `n` periods that is a fixed point of `P_d` for a
/// divisor `d` of `n` is the orbit of period `d` (its multipliers are those of `P_d`, not their
/// `n/d`-th powers). [`find_orbit`] returns its orbit through it.
///
/// ```
/// use geardyn_analysis::orbits::{find_orbit, minimal, OrbitOptions};
/// use geardyn_model::reference::TwoMassClearance;
/// // the period-1 orbit of the linear toy sought as an orbit of 3 periods
/// let sys = TwoMassClearance { load: [2.0, 1.0], ..Default::default() };
/// let opts = OrbitOptions { period: 3, ..Default::default() };
/// let o = find_orbit(&sys, [2.0, 0.0, 1.0, 0.0], &opts).unwrap();
/// assert_eq!(o.period, 1);
/// assert_eq!(minimal(&sys, o.clone(), &opts).unwrap().period, 1);
/// ```
pub fn minimal<S, const N: usize>(
    sys: &S,
    o: Orbit<N>,
    opts: &OrbitOptions,
) -> Result<Orbit<N>, OrbitError>
where
    S: GearSystem<N> + TangentSpace<N>,
{
    let n = o.period;
    for d in (1..n).filter(|d| n.is_multiple_of(*d)) {
        let od = OrbitOptions { period: d, ..*opts };
        let Ok(img) = map_only(sys, o.y, o.memory, &od) else {
            continue;
        };
        let r = max_abs_diff(&img, &o.y);
        if r <= 100.0 * NOISE_FLOOR * (1.0 + max_abs(&o.y)) {
            if let Ok(od_orbit) = newton(sys, o.y, o.memory, &od) {
                return Ok(od_orbit);
            }
        }
    }
    Ok(o)
}

pub(crate) fn newton<S, const N: usize>(
    sys: &S,
    y0: [f64; N],
    memory0: f64,
    o: &OrbitOptions,
) -> Result<Orbit<N>, OrbitError>
where
    S: GearSystem<N> + TangentSpace<N>,
{
    let mut y = y0;
    // the memory at the start is the orbit's own at the end (a fixed point in it too: carried
    // from one iterate to the next)
    let mut memory = memory0;
    let mut residual = f64::INFINITY;
    for it in 0..=o.max_iter {
        let e = map_eval(sys, y, memory, o)?;
        let r: [f64; N] = std::array::from_fn(|i| e.y[i] - y[i]);
        let before = residual;
        residual = max_abs(&r);
        if !residual.is_finite() {
            break;
        }
        let settled = (e.memory - memory).abs() <= o.tol * (1.0 + memory.abs());
        let scale = 1.0 + max_abs(&y);
        // converged, or at the integration's noise floor: a small residual that Newton's steps
        // no longer halve (a map of many mesh cycles carries an error above `tol`)
        let floor = residual <= NOISE_FLOOR * scale && residual > 0.5 * before;
        if (residual <= o.tol * scale || floor) && settled {
            return Ok(Orbit::from_eval(y, e, o.period, it));
        }
        memory = e.memory;
        if it == o.max_iter {
            break;
        }
        // M - I
        let a: [[f64; N]; N] = std::array::from_fn(|i| {
            let mut row = e.jac[i];
            row[i] -= 1.0;
            row
        });
        let Some(mut dy) = solve_n(&a, r.map(|v| -v)) else {
            break;
        };
        // a damped step far from the orbit (the map is only piecewise smooth)
        let len = max_abs(&dy);
        if len > 0.5 * scale {
            let f = 0.5 * scale / len;
            dy = dy.map(|v| v * f);
        }
        y = std::array::from_fn(|i| y[i] + dy[i]);
    }
    // (the orbit's map starts at tau = 0)
    let [x, v] = sys.mesh_state(0.0, &y, 0);
    Err(OrbitError::NoConvergence {
        period: o.period,
        x,
        v,
        iterations: o.max_iter,
        residual,
    })
}

/// The record of an orbit: its label, forces and P_ID from a simulation of one orbit period
/// from the orbit's point (DP5 at the project's default tolerance), read as that orbit
/// ([`crate::simulate::summarize_orbit`]): an unstable orbit leaves its point only by the
/// rounding of one orbit period, amplified by its multipliers.
pub fn describe_orbit<S: GearSystem<N>, const N: usize>(
    sys: &S,
    o: &Orbit<N>,
    tau0: f64,
) -> Result<crate::simulate::Summary, crate::simulate::SimError> {
    let opts = SimOptions {
        method: Method::default(),
        transient_periods: 0,
        record_periods: u64::from(o.period),
        tau0,
        start_memory: o.memory,
        ..Default::default()
    };
    let res = simulate(sys, o.y, &opts)?;
    Ok(crate::simulate::summarize_orbit(
        sys,
        &res,
        &opts,
        o.period as usize,
    ))
}
