//! Periodic orbits of the non-smooth model: shooting on the stroboscopic map, Floquet
//! multipliers, pseudo-arclength continuation in any parameter, and the bifurcations along a
//! branch (period doubling, fold, torus, grazing). docs/analyses.md, "Periodic orbits".
//!
//! **Which systems.** A single orbit — the map [`stroboscopic_map`], shooting [`find_orbit`],
//! [`minimal`], the [`Orbit`] with its multipliers, [`describe_orbit`] — is computed for any
//! [`GearSystem`] of state dimension `N` (1 to 24: [`TangentSpace`] integrates its tangent
//! dynamics), e.g. the two-mass toy [`geardyn_model::reference::TwoMassClearance`]. The branch
//! continuation ([`continue_orbits`], [`run_orbits`]: pseudo-arclength, bifurcation detection and
//! location, branch switching) is for the single pair ([`geardyn_model::MeshModel`], `N = 2`,
//! parameters of a [`Scenario`]) only. For the pair every result is bit-identical to the former
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
use geardyn_scenario::{Scenario, ScenarioError};
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
const CRITICAL: f64 = 1e-2;

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
    let a = nalgebra::DMatrix::from_fn(N, N, |i, j| m[i][j]);
    let Some(schur) = nalgebra::linalg::Schur::try_new(a, f64::EPSILON, 1000 * N.max(1)) else {
        return [nan; N];
    };
    let (_, t) = schur.unpack();
    // the diagonal blocks: 1 x 1 (a real multiplier) or 2 x 2 (a pair)
    let mut blocks: Vec<Vec<Multiplier>> = Vec::with_capacity(N);
    let mut i = 0;
    while i < N {
        if i + 1 < N && t[(i + 1, i)] != 0.0 {
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
struct MapEval<const N: usize> {
    y: [f64; N],
    jac: [[f64; N]; N],
    /// Contact state entered at each event, in order from the stroboscopic instant.
    events: Vec<i8>,
    /// Mesh of each event.
    meshes: Vec<usize>,
    /// Segment of the excitation period ([`GearSystem::segment`]) in which each event happened.
    segments: Vec<u32>,
    /// Memory parameter of the mode at the end ([`geardyn_solvers::HybridSystem::memory`]).
    memory: f64,
}

/// The contact events of a run: the contact state each mesh entered, the mesh, and the segment
/// of the excitation period it happened in.
#[derive(Default)]
struct Events {
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
fn scheme(o: &OrbitOptions) -> Scheme {
    Scheme::DormandPrince {
        rtol: o.rtol,
        atol: o.atol,
    }
}

/// `P_n(y)` with its Jacobian: one run of the flow and its tangent per column (the events and
/// the image from the first).
fn map_eval<S, const N: usize>(
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
fn map_only<S: GearSystem<N>, const N: usize>(
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
fn max_abs<const N: usize>(v: &[f64; N]) -> f64 {
    v[1..].iter().fold(v[0].abs(), |m, x| m.max(x.abs()))
}

/// `max_abs(a - b)`.
fn max_abs_diff<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
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
fn first_mesh_only(meshes: &[usize]) -> bool {
    meshes.iter().all(|&k| k == 0)
}

impl<const N: usize> Orbit<N> {
    fn from_eval(y: [f64; N], e: MapEval<N>, period: u32, iterations: u32) -> Orbit<N> {
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
fn least_rotation<T: Clone + Ord>(e: &[T]) -> Vec<T> {
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

fn check(o: &OrbitOptions) -> Result<(), OrbitError> {
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
fn solve2(a: &[[f64; 2]; 2], b: [f64; 2]) -> Option<[f64; 2]> {
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
fn solve_n<const N: usize>(a: &[[f64; N]; N], b: [f64; N]) -> Option<[f64; N]> {
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
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
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

fn newton<S, const N: usize>(
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
    let [x, v] = sys.mesh_state(&y, 0);
    Err(OrbitError::NoConvergence {
        period: o.period,
        x,
        v,
        iterations: o.max_iter,
        residual,
    })
}

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
    /// The stability changed between two branch points with no smooth bifurcation, grazing or
    /// corner collision between them (a border the detectors do not name): reported so that a
    /// change of stability is never silent.
    StabilityChange,
}

impl BifurcationKind {
    /// Every kind, in the order outputs list them.
    pub const ALL: [BifurcationKind; 6] = [
        BifurcationKind::PeriodDoubling,
        BifurcationKind::Fold,
        BifurcationKind::Grazing,
        BifurcationKind::Torus,
        BifurcationKind::CornerCollision,
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
/// use geardyn_analysis::orbits::{continue_orbits, BifurcationKind, ContinuationOptions};
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
            if let Some(b) = locate(prob, &cur, &next, kind) {
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
    let mu = eigenvalues(m)
        .into_iter()
        .filter(|u| u.im == 0.0)
        .min_by(|a, b| (a.re + 1.0).abs().total_cmp(&(b.re + 1.0).abs()))
        .map(|u| u.re)
        .unwrap_or(-1.0);
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
    })
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

/// One request of `geardyn orbits` / `geardyn.orbits()`: its settings, their ranges and
/// defaults in one place ([`OrbitsRequest::check`]), run by [`run_orbits`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OrbitsRequest {
    /// `(parameter, start, stop)` of a continuation; `None`: one orbit.
    pub range: Option<(String, f64, f64)>,
    /// Excitation periods of the orbit; `None`: the period of the motion after the transient.
    pub period: Option<u32>,
    /// Excitation periods simulated from `y0` before Newton's method starts.
    pub transient: u64,
    /// Initial state.
    pub y0: [f64; 2],
    /// Stroboscopic phase.
    pub tau0: f64,
    /// Largest arclength step.
    pub ds: f64,
    /// Most branch points.
    pub max_points: usize,
    /// Branch switching at doublings up to this period (0: none).
    pub switch_up_to: u32,
    /// Relative tolerance of the integration (absolute: 1e-2 times it).
    pub rtol: f64,
}

impl Default for OrbitsRequest {
    fn default() -> Self {
        OrbitsRequest {
            range: None,
            period: None,
            transient: 300,
            y0: [0.0, 0.0],
            tau0: 0.0,
            ds: 0.02,
            max_points: 2000,
            switch_up_to: 0,
            rtol: 1e-11,
        }
    }
}

/// Most branch points of one request.
pub const MAX_BRANCH_POINTS: usize = 1_000_000;

fn setting(field: &'static str, value: String, allowed: impl Into<String>) -> OrbitError {
    OrbitError::Setting {
        field,
        value,
        allowed: allowed.into(),
    }
}

impl OrbitsRequest {
    /// Refuses a setting outside its range (naming it and the range), and a parameter the
    /// scenario does not take at either end of the range.
    pub fn check(&self, sc: &Scenario) -> Result<(), OrbitError> {
        use geardyn_model::error::num;
        if let Some(n) = self.period {
            if n == 0 || n > MAX_ORBIT_PERIOD {
                return Err(setting(
                    "period",
                    n.to_string(),
                    format!("1 ..= {MAX_ORBIT_PERIOD}"),
                ));
            }
        }
        let max = crate::simulate::MAX_PERIODS;
        if self.transient > max {
            return Err(setting(
                "transient",
                self.transient.to_string(),
                format!("0 ..= {max}"),
            ));
        }
        if !(self.ds > 0.0 && self.ds <= 1.0) {
            return Err(setting("ds", num(self.ds), "(0, 1]"));
        }
        if !(1e-14..=1e-6).contains(&self.rtol) {
            return Err(setting("rtol", num(self.rtol), "[1e-14, 1e-6]"));
        }
        if self.max_points == 0 || self.max_points > MAX_BRANCH_POINTS {
            return Err(setting(
                "max_points",
                self.max_points.to_string(),
                format!("1 ..= {MAX_BRANCH_POINTS}"),
            ));
        }
        if self.switch_up_to > MAX_ORBIT_PERIOD {
            return Err(setting(
                "switch_up_to",
                self.switch_up_to.to_string(),
                format!("0 ..= {MAX_ORBIT_PERIOD}"),
            ));
        }
        for (field, v) in [("x0", self.y0[0]), ("v0", self.y0[1]), ("tau0", self.tau0)] {
            if !v.is_finite() {
                return Err(setting(field, num(v), "a finite number"));
            }
        }
        if let Some((p, lo, hi)) = &self.range {
            if !(lo.is_finite() && hi.is_finite()) || lo == hi {
                return Err(setting(
                    "range",
                    format!("{}:{}", num(*lo), num(*hi)),
                    "two different finite numbers START:STOP",
                ));
            }
            sc.with(p, *lo)?;
            sc.with(p, *hi)?;
        }
        Ok(())
    }
}

/// Runs an [`OrbitsRequest`] on `sc`: the initial state after the transient at the start of the
/// range, its period (unless given), then one orbit or the branches. `progress` sees every
/// branch point.
pub fn run_orbits(
    sc: &Scenario,
    req: &OrbitsRequest,
    progress: &(dyn Fn(&BranchPoint) + Sync),
) -> Result<Continuation, OrbitError> {
    req.check(sc)?;
    let start = match &req.range {
        Some((p, lo, _)) => sc.with(p, *lo)?,
        None => sc.clone(),
    };
    let solver = |crate::simulate::SimError::Solver(e)| OrbitError::Solver(e);
    let (near, period) = match req.period {
        Some(n) => {
            let near = if req.transient > 0 {
                let opts = SimOptions {
                    transient_periods: req.transient - 1,
                    record_periods: 1,
                    tau0: req.tau0,
                    ..Default::default()
                };
                simulate(start.model(), req.y0, &opts)
                    .map_err(solver)?
                    .final_state
                    .1
            } else {
                req.y0
            };
            (near, n)
        }
        None => {
            // the period as `geardyn simulate` decides it (transients extended where the motion
            // is still settling), and the start from the decided record's end
            let opts = SimOptions {
                transient_periods: req.transient,
                record_periods: 3 * 32,
                tau0: req.tau0,
                ..Default::default()
            };
            let (res, s, _) = crate::classify::simulate_decided(
                start.model(),
                req.y0,
                &opts,
                crate::classify::Decide::default(),
            )
            .map_err(solver)?;
            if !s.motion.is_periodic() {
                return Err(OrbitError::NotPeriodic {
                    x0: req.y0[0],
                    v0: req.y0[1],
                    transient: s.periods_integrated,
                    motion: s.label.clone(),
                });
            }
            (res.final_state.1, s.period as u32)
        }
    };
    let orbit = OrbitOptions {
        period,
        tau0: req.tau0,
        rtol: req.rtol,
        atol: req.rtol * 1e-2,
        ..Default::default()
    };
    match &req.range {
        Some((p, lo, hi)) => {
            let opts = ContinuationOptions {
                param: p.clone(),
                start: *lo,
                stop: *hi,
                ds_max: req.ds,
                max_points: req.max_points,
                switch_up_to: req.switch_up_to,
                orbit,
            };
            continue_orbits(sc, near, &opts, progress)
        }
        None => {
            let o = find_orbit(start.model(), near, &orbit)?;
            let pt = BranchPoint {
                branch: 0,
                param: f64::NAN,
                orbit: o,
            };
            progress(&pt);
            Ok(Continuation {
                points: vec![pt],
                ends: vec!["one orbit".into()],
                ..Default::default()
            })
        }
    }
}

/// The record of every branch point ([`describe_orbit`] at its parameter value; `param` the
/// continued parameter, `None` for one orbit at `sc`), in parallel: `(label, max_force, p_id)`,
/// an empty label and NaN where the record failed.
pub fn orbit_records(
    sc: &Scenario,
    param: Option<&str>,
    points: &[BranchPoint],
    tau0: f64,
) -> Vec<(String, f64, f64)> {
    use rayon::prelude::*;
    points
        .par_iter()
        .map(|p| {
            let here = match param {
                Some(name) => sc.with(name, p.param).ok(),
                None => Some(sc.clone()),
            };
            match here.and_then(|m| describe_orbit(m.model(), &p.orbit, tau0).ok()) {
                Some(s) => (s.label, s.max_force, s.p_id),
                None => (String::new(), f64::NAN, f64::NAN),
            }
        })
        .collect()
}

/// The brute-force diagram an orbit figure draws beneath the branches: strobe points
/// `(value, x)` of a plain simulation (300 + 60 periods from `y0`, DP5, no decision) at `n`
/// values of `[lo, hi]` of `param`, in parallel; a value whose run fails draws nothing.
pub fn strobe_diagram(
    sc: &Scenario,
    param: &str,
    lo: f64,
    hi: f64,
    n: usize,
    y0: [f64; 2],
    tau0: f64,
) -> Vec<(f64, f64)> {
    if n == 0 {
        return Vec::new();
    }
    let values = crate::bifurcation::linspace(lo.min(hi), lo.max(hi), n.max(2));
    use rayon::prelude::*;
    values
        .par_iter()
        .flat_map_iter(|&v| {
            let opts = SimOptions {
                transient_periods: 300,
                record_periods: 60,
                tau0,
                ..Default::default()
            };
            let pts: Vec<(f64, f64)> = sc
                .with(param, v)
                .ok()
                .and_then(|m| simulate(m.model(), y0, &opts).ok())
                .map(|r| r.strobe.iter().map(|p| (v, p.y[0])).collect())
                .unwrap_or_default();
            pts
        })
        .collect()
}
