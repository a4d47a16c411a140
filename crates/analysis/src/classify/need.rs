//! What a [`Decision`](super::Decision) asks for next: a run, an exponent, an escape test, or
//! nothing (decided).

use crate::escape::{Copy, EscapeSettings};
use crate::simulate::SimOptions;

/// The next integration a [`Decision`](super::Decision) waits for.
#[derive(Clone, Copy, Debug)]
pub enum Need<const N: usize = 2> {
    /// A run of [`simulate`] from `y0` with `opts` (a transient extension, the persistence check
    /// of a positive exponent, or the record again of a periodic run whose head is transient);
    /// hand its result to [`Decision`](super::Decision)(super::Decision)::simulated`].
    Sim {
        /// Initial state.
        y0: [f64; N],
        /// Options of the run (`tau0` is its start time).
        opts: SimOptions,
    },
    /// The TLE of the motion continuing from `(t, y)` ([`Engine::tle`]); hand it to
    /// [`Decision`](super::Decision)(super::Decision)::tle`].
    Tle {
        /// Start time.
        t: f64,
        /// Start state.
        y: [f64; N],
        /// Memory of the start mode ([`SimResult::final_memory`] of the run it continues).
        memory: f64,
        /// Excitation periods of the estimate ([`tle_periods`], or [`TLE_LONG_PERIODS`] for the
        /// last look at a run still undecided).
        periods: u64,
    },
    /// The ensemble escape test ([`Engine::escape`]) of the motion continuing from `start`; hand
    /// its outcome to [`Decision`](super::Decision)(super::Decision)::escaped`].
    Escape {
        /// Where the copies start (the end of the current record).
        start: Copy<N>,
        /// The test's settings (its span cut to the work budget).
        test: EscapeSettings,
    },
    /// Decided: [`Decision`](super::Decision)(super::Decision)::finish`].
    Done,
}
