//! The gear-system interface every analysis of geardyn takes: a non-smooth dynamical system of
//! any number of degrees of freedom whose nonlinearities are gear meshes (or mesh-like contacts
//! with a clearance), each with its own contact state.
//!
//! A [`GearSystem`] is a [`HybridSystem`](geardyn_solvers::HybridSystem) (modes, guards, resets, time breakpoints) that can be
//! linearised ([`Variational`]: saltation at events, for Lyapunov exponents and periodic orbits)
//! and that says what the analyses report of it:
//!
//! * its clocks: the **excitation period** `T_s` (the stroboscopic clock of sections, periods and
//!   labels) and the **mesh cycle** (the fast clock: fixed-step resolutions and trajectory
//!   samples are stated per mesh cycle; one excitation period holds [`GearSystem::cycles_per_period`]
//!   of them);
//! * its **meshes** `k = 0..mesh_count()`: the relative displacement and velocity along the line
//!   of action ([`GearSystem::mesh_state`], units of the characteristic length `b_c`), the
//!   dynamic mesh force ([`GearSystem::mesh_force`], units of `k_av b_c`), the contact state
//!   ([`GearSystem::contact`]), the backlash levels the motion label counts crossings of
//!   ([`GearSystem::backlash_levels`]: label `n-p-q-r-s` per mesh), and which mesh and which kind
//!   each state event is ([`GearSystem::event`]).
//!
//! All quantities are dimensionless (docs/model.md §1): time `tau = omega_n t`.
//!
//! The single spur pair ([`crate::MeshModel`], `N = 2`, one mesh) is one implementation;
//! [`crate::reference::TwoMassClearance`] (`N = 4`, two clearances) is another, used by the tests
//! and the examples to show that an analysis is generic.

use crate::{ContactState, EventKind};
use geardyn_solvers::Variational;

/// A gear system of state dimension `N` (see the module doc).
///
/// # Example: a single degree of freedom with one clearance
/// ```
/// use geardyn_model::system::GearSystem;
/// use geardyn_model::{ContactState, EventKind};
/// use geardyn_solvers::{Direction, Guards, HybridSystem, Variational};
/// /// `x'' + 0.1 x' + k(x) = 0.1 + 0.2 cos(t)`, `k(x)` a spring with a clearance `|x| < 1`.
/// #[derive(Clone)]
/// struct Backlash;
/// impl HybridSystem<2> for Backlash {
///     type Mode = ContactState;
///     type TimeTerms = f64;
///     fn initial_mode(&self, _t: f64, y: &mut [f64; 2]) -> ContactState {
///         if y[0] > 1.0 { ContactState::Drive } else if y[0] < -1.0 { ContactState::Back } else { ContactState::Separated }
///     }
///     fn time_terms(&self, t: f64) -> f64 { t.cos() }
///     fn rhs(&self, _t: f64, c: &f64, y: &[f64; 2], m: &ContactState, dy: &mut [f64; 2]) {
///         let f = match m { ContactState::Drive => y[0] - 1.0, ContactState::Back => y[0] + 1.0, _ => 0.0 };
///         *dy = [y[1], 0.1 + 0.2 * c - 0.1 * y[1] - f];
///     }
///     fn guards(&self, _t: f64, y: &[f64; 2], m: &ContactState, g: &mut Guards) {
///         match m {
///             ContactState::Drive => g.push(y[0] - 1.0, Direction::Falling),
///             ContactState::Back => g.push(y[0] + 1.0, Direction::Rising),
///             _ => { g.push(y[0] - 1.0, Direction::Rising); g.push(y[0] + 1.0, Direction::Falling) }
///         }
///     }
///     fn on_event(&self, _t: f64, _y: &mut [f64; 2], m: &mut ContactState, i: usize) -> geardyn_solvers::EventAction {
///         *m = match (*m, i) { (ContactState::Separated, 0) => ContactState::Drive,
///             (ContactState::Separated, _) => ContactState::Back, _ => ContactState::Separated };
///         geardyn_solvers::EventAction::Continue
///     }
/// }
/// impl Variational<2> for Backlash {
///     fn jacobian(&self, _t: f64, _c: &f64, _y: &[f64; 2], m: &ContactState, j: &mut [[f64; 2]; 2]) {
///         let k = if *m == ContactState::Separated { 0.0 } else { 1.0 };
///         *j = [[0.0, 1.0], [-k, -0.1]];
///     }
///     fn guard_gradient(&self, _t: f64, _y: &[f64; 2], _m: &ContactState, _i: usize) -> ([f64; 2], f64) {
///         ([1.0, 0.0], 0.0)
///     }
/// }
/// impl GearSystem<2> for Backlash {
///     fn excitation_period(&self) -> f64 { std::f64::consts::TAU }
///     fn natural_period(&self) -> f64 { std::f64::consts::TAU }
///     fn mesh_state(&self, _t: f64, y: &[f64; 2], _k: usize) -> [f64; 2] { *y }
///     fn mesh_force(&self, _t: f64, y: &[f64; 2], m: &ContactState, _k: usize) -> f64 {
///         match m { ContactState::Drive => y[0] - 1.0, ContactState::Back => y[0] + 1.0, _ => 0.0 }
///     }
///     fn contact(&self, m: &ContactState, _k: usize) -> ContactState { *m }
///     fn backlash_levels(&self, _k: usize) -> (f64, f64) { (1.0, 1.0) }
///     fn event(&self, before: &ContactState, _after: &ContactState, i: usize) -> (usize, EventKind) {
///         (0, match (before, i) {
///             (ContactState::Separated, 0) => EventKind::DriveEnter,
///             (ContactState::Separated, _) => EventKind::BackEnter,
///             (ContactState::Drive, _) => EventKind::DriveExit,
///             _ => EventKind::BackExit,
///         })
///     }
/// }
/// assert_eq!(Backlash.mesh_cycle_time(), std::f64::consts::TAU);
/// ```
pub trait GearSystem<const N: usize>: Variational<N> + Clone + Sync {
    /// Number of meshes (at least one).
    fn mesh_count(&self) -> usize {
        1
    }

    /// Name of mesh `k` for tables and figures (`mesh` for a single pair).
    fn mesh_name(&self, k: usize) -> String {
        if self.mesh_count() == 1 {
            "mesh".into()
        } else {
            format!("mesh {}", k + 1)
        }
    }

    /// Excitation period `T_s` (dimensionless time): the stroboscopic clock.
    fn excitation_period(&self) -> f64;

    /// Mesh cycles per excitation period (1 unless the period spans several tooth meshes, as a
    /// pinion revolution with one broken tooth does).
    fn cycles_per_period(&self) -> u32 {
        1
    }

    /// Mesh cycle duration (dimensionless time): the unit of fixed-step resolutions and
    /// trajectory sampling.
    fn mesh_cycle_time(&self) -> f64 {
        self.excitation_period() / f64::from(self.cycles_per_period())
    }

    /// Position of time `t` in the excitation period, in mesh cycles (`[0, cycles)`).
    fn cycle_position(&self, t: f64) -> f64 {
        let c = f64::from(self.cycles_per_period());
        let s = t / self.mesh_cycle_time();
        s - (s / c).floor() * c
    }

    /// Shortest natural period of the system in its stiffest contact state (dimensionless time):
    /// a drawn trajectory samples it finely enough. `f64::INFINITY` if unknown.
    fn natural_period(&self) -> f64;

    /// Relative displacement and velocity `[x_k, x_k']` of mesh `k` along its line of action at
    /// time `t` (units `b_c`, `b_c omega_n`; drive-side contact at `x_k >= D`): the deflection of
    /// the mesh, which depends on time where a transmission error excites it.
    fn mesh_state(&self, t: f64, y: &[f64; N], k: usize) -> [f64; 2];

    /// Dynamic mesh force of mesh `k` in `mode` (units `k_av b_c`; 0 when separated).
    fn mesh_force(&self, t: f64, y: &[f64; N], mode: &Self::Mode, k: usize) -> f64;

    /// Contact state of mesh `k` in `mode`.
    fn contact(&self, mode: &Self::Mode, k: usize) -> ContactState;

    /// Half backlash levels `(D_d, D_s)` of mesh `k`: the section levels whose crossings the label
    /// `n-p-q-r-s` counts (`D_d = D_s`: label `n-p-q`).
    fn backlash_levels(&self, k: usize) -> (f64, f64);

    /// The mesh a state event of guard `index` (armed in `before`) belongs to, and its kind.
    fn event(&self, before: &Self::Mode, after: &Self::Mode, index: usize) -> (usize, EventKind);

    /// Peak force of a back-side impact of mesh `k` at relative speed `v` (0 for meshes without a
    /// rigid back stop).
    fn impact_peak_force(&self, _k: usize, _v: f64) -> f64 {
        0.0
    }

    /// The piece of the excitation period `mode` is in, between the system's time breakpoints
    /// ([`geardyn_solvers::HybridSystem::next_breakpoint`]: for the pair its mesh-stiffness
    /// zones, a broken tooth's edges, the pitch point). A periodic orbit's itinerary records it
    /// with each contact event (an event crossing a breakpoint changes the map's Jacobian).
    /// Default 0: no breakpoints.
    fn segment(&self, _mode: &Self::Mode) -> u32 {
        0
    }
}

impl<S: GearSystem<N>, const N: usize> GearSystem<N> for &S {
    geardyn_solvers::forward_methods! { to referent;
        fn mesh_count(&self) -> usize;
        fn mesh_name(&self, k: usize) -> String;
        fn excitation_period(&self) -> f64;
        fn cycles_per_period(&self) -> u32;
        fn mesh_cycle_time(&self) -> f64;
        fn cycle_position(&self, t: f64) -> f64;
        fn natural_period(&self) -> f64;
        fn mesh_state(&self, t: f64, y: &[f64; N], k: usize) -> [f64; 2];
        fn mesh_force(&self, t: f64, y: &[f64; N], mode: &S::Mode, k: usize) -> f64;
        fn contact(&self, mode: &S::Mode, k: usize) -> ContactState;
        fn backlash_levels(&self, k: usize) -> (f64, f64);
        fn event(&self, before: &S::Mode, after: &S::Mode, index: usize) -> (usize, EventKind);
        fn impact_peak_force(&self, k: usize, v: f64) -> f64;
        fn segment(&self, mode: &S::Mode) -> u32;
    }
}
