//! Which runs the pair's lockstep lanes take and how they are laid out: the lane count, the
//! settings and contact laws the lanes step, the chunks over the threads, and the start time of
//! the phase tables runs share. Shared by the lanes of simulations ([`crate::lanes`]) and of
//! exponents ([`crate::lanes_tle`]).

use crate::simulate::{Method, SimOptions};
use geardyn_model::MeshModel;

/// Lanes per engine: four AVX2 registers of `f64` per state component. More independent lanes
/// hide the latency of the RK4 stage chain; on the C1 workload W1 (one thread) 16 lanes ran
/// about 20% faster than 8 and 10% faster than 32.
pub const LANES: usize = 16;

/// Whether [`crate::lanes::simulate_lanes`] can run these settings: fixed-step RK4 without a trajectory and
/// with at least one period to integrate ([`LaneSim::new`] succeeds).
pub fn lanes_apply(opts: &SimOptions) -> bool {
    LaneSim::new(opts).is_ok()
}

/// Simulation settings the lockstep lanes run: fixed-step RK4, no trajectory, at least one period
/// to integrate. The lane analyses take this type, so that settings they cannot run are refused
/// where they are built ([`LaneSim::new`]) and not found out inside a lane engine.
///
/// ```
/// use geardyn_analysis::lanes::LaneSim;
/// use geardyn_analysis::simulate::{Method, SimOptions};
/// assert!(LaneSim::new(&SimOptions::rk4(256, 10, 10)).is_ok());
/// assert!(LaneSim::new(&SimOptions::rk4(256, 0, 0)).is_err());
/// let dp5 = SimOptions { method: Method::Dopri { rtol: 1e-9, atol: 1e-12 }, ..SimOptions::default() };
/// assert!(LaneSim::new(&dp5).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneSim {
    sim: SimOptions,
    steps_per_cycle: u32,
}

/// Why settings cannot run in the lanes ([`LaneSim::new`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NotInLanes {
    /// The lanes step fixed-step RK4 only.
    #[error("the lanes integrate with fixed-step RK4 only (integrator = \"rk4\")")]
    Adaptive,
    /// The lanes keep no trajectory.
    #[error("the lanes keep no trajectory")]
    Trajectory,
    /// Nothing to integrate.
    #[error("the lanes need at least one period to integrate (transient + record > 0)")]
    NoPeriods,
}

impl LaneSim {
    /// `opts` checked for the lanes.
    pub fn new(opts: &SimOptions) -> Result<Self, NotInLanes> {
        let Method::Rk4 { steps_per_cycle } = opts.method else {
            return Err(NotInLanes::Adaptive);
        };
        if opts.trajectory {
            return Err(NotInLanes::Trajectory);
        }
        if opts.transient_periods + opts.record_periods == 0 {
            return Err(NotInLanes::NoPeriods);
        }
        Ok(Self {
            sim: *opts,
            steps_per_cycle: steps_per_cycle.max(1),
        })
    }

    /// RK4 steps per mesh cycle (at least 1).
    pub fn steps_per_cycle(&self) -> u32 {
        self.steps_per_cycle
    }
}

impl std::ops::Deref for LaneSim {
    type Target = SimOptions;
    fn deref(&self) -> &SimOptions {
        &self.sim
    }
}

/// Start time of the phase tables of a run starting at `t0` on a sweep whose runs start at
/// `tau0`: `tau0` when `t0` is at the same phase of the excitation period to rounding (a
/// stroboscopic instant of the sweep: the continuation of a run), so that such runs share the
/// tables (and lanes) of the sweep; else `t0`.
pub(crate) fn table_time(m: &MeshModel, t0: f64, tau0: f64) -> f64 {
    let d = m.cycle_position(t0) - m.cycle_position(tau0);
    let c = m.cycles_per_period() as f64;
    let d = d - (d / c).round() * c;
    if d.abs() < 1e-9 {
        tau0
    } else {
        t0
    }
}

/// Chunk length: whole lane loads, at least eight chunks per thread (rayon balances them; within
/// a chunk, retired lanes refill at once); a batch of fewer than eight lane loads per thread is
/// split into equal chunks, a multiple of the thread count: 18 runs on two threads as 9 + 9, not
/// 16 + 2 (a breakage follow costs about in proportion to its busy lanes, so the 16-lane chunk
/// alone set the wall time while the other thread idled).
pub(crate) fn chunk_len(items: usize, lanes: usize) -> usize {
    let threads = rayon::current_num_threads().max(1);
    let loads = items.div_ceil(lanes);
    if loads >= threads * 8 {
        return lanes * loads.div_ceil(threads * 8);
    }
    let chunks = loads.div_ceil(threads) * threads;
    items.div_ceil(chunks).clamp(1, lanes)
}

/// Whether the lanes step `model`'s contact states themselves: the linear contact law without
/// hysteresis. Otherwise every step in contact is handed to the scalar integrator, and a lone run
/// is faster there than on [`crate::lanes::simulate_lane`].
pub fn lanes_cover_contact(model: &MeshModel) -> bool {
    let law = model.contact_law();
    law.exponent() == 1.0 && law.hysteresis_coefficient() == 0.0
}
