//! A process-wide request to stop integrating (Ctrl-C in the Python module, or any caller that
//! wants a long computation to end early).
//!
//! Once [`request`] is called, [`Integrator::step`](crate::Integrator::step) fails with
//! [`SolverError::Cancelled`](crate::SolverError::Cancelled) at its next step and the lanes
//! engine ends every busy lane at its next period (and every item it takes after that, before
//! integrating it), so that a computation on any number of threads stops within one excitation
//! period of its slowest run. The analyses never report a run cut this way as finished work (their
//! `on_done` callbacks see only runs that ended before the request). [`clear`] re-arms it.
//!
//! Why one flag for the process rather than a token per call: the check sits in the integrator's
//! step and the engine's period loop, below every analysis; threading a token through each of them
//! would touch every signature for a flag that, like SIGINT for a command-line program, stops
//! everything at once.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks every integration in the process to stop.
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Withdraws the request (call it once the cancelled computation has returned).
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}

/// Whether a stop was requested.
#[inline(always)]
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}
