//! Stop requests: a [`Token`] per run, and the process's own request (Ctrl-C).
//!
//! Once a run's token is cancelled ([`Token::cancel`]) or the process's stop is requested
//! ([`request`]), [`Integrator::step`](crate::Integrator::step) fails with
//! [`SolverError::Cancelled`](crate::SolverError::Cancelled) at its next step and the lanes
//! engine ends every busy lane at its next period (and every item it takes after that, before
//! integrating it), so that a computation on any number of threads stops within one excitation
//! period of its slowest run. The analyses never report a run cut this way as finished work
//! (their `on_done` callbacks see only runs that ended before the stop).
//!
//! **Which token a computation obeys.** The check sits in the integrator's step and the lanes'
//! period loop, below every analysis; rather than thread a token through each signature, a
//! thread has a *current* token: [`Token::enter`] makes a token current on the calling thread
//! while its guard lives, [`Token::adopt`] for the rest of a thread's life (the worker threads of a
//! pool made for one run: `geardyn_exec::cancel::run_under` does both). [`requested`] is true when
//! the process's stop is requested or the current token of the calling thread is cancelled. So
//! two runs side by side (two Python threads, two tabs of the explorer) stop independently, and
//! Ctrl-C still stops everything.
//!
//! ```
//! use geardyn_solvers::cancel::{requested, Token};
//!
//! let token = Token::new();
//! assert!(!requested());
//! {
//!     let _current = token.enter();
//!     token.cancel();
//!     assert!(requested()); // this thread's run is cancelled
//! }
//! assert!(!requested()); // another run on this thread is not
//! ```

use std::cell::{Cell, RefCell};
use std::marker::PhantomData;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The process's stop request (Ctrl-C).
static PROCESS: AtomicBool = AtomicBool::new(false);

thread_local! {
    /// The current token's flag of this thread (null: none). Valid while set: an [`Entered`]
    /// guard borrows its token, and an adopted token is kept alive by `ADOPTED`.
    static CURRENT: Cell<*const AtomicBool> = const { Cell::new(std::ptr::null()) };
    static ADOPTED: RefCell<Option<Arc<AtomicBool>>> = const { RefCell::new(None) };
}

/// A stop request for one run: cheap to clone (the clones are one token), checked by the
/// integrations of every thread on which it is current.
#[derive(Clone, Debug, Default)]
pub struct Token(Arc<AtomicBool>);

/// The guard of [`Token::enter`]: the previous current token comes back when it is dropped.
#[must_use = "the token is current only while the guard lives"]
pub struct Entered<'a> {
    previous: *const AtomicBool,
    _token: PhantomData<&'a Token>,
}

impl Drop for Entered<'_> {
    fn drop(&mut self) {
        CURRENT.with(|c| c.set(self.previous));
    }
}

impl Token {
    /// A token not cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks the run to stop (from any thread).
    pub fn cancel(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether [`Token::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// Makes this token the current one of the calling thread while the guard lives.
    pub fn enter(&self) -> Entered<'_> {
        let previous = CURRENT.with(|c| c.replace(Arc::as_ptr(&self.0)));
        Entered {
            previous,
            _token: PhantomData,
        }
    }

    /// Makes this token the current one of the calling thread for the rest of its life (a
    /// worker thread made for one run).
    pub fn adopt(&self) {
        let keep = self.0.clone();
        CURRENT.with(|c| c.set(Arc::as_ptr(&keep)));
        ADOPTED.with(|a| *a.borrow_mut() = Some(keep));
    }
}

/// Asks every integration in the process to stop (Ctrl-C).
pub fn request() {
    PROCESS.store(true, Ordering::SeqCst);
}

/// Withdraws the process's request (call it once the cancelled computation has returned).
pub fn clear() {
    PROCESS.store(false, Ordering::SeqCst);
}

/// Whether the calling thread's computation should stop: the process's stop was requested, or
/// the thread's current token is cancelled.
#[inline(always)]
pub fn requested() -> bool {
    if PROCESS.load(Ordering::Relaxed) {
        return true;
    }
    let flag = CURRENT.with(|c| c.get());
    // SAFETY: a non-null current flag is alive: set by `enter`, whose guard borrows the token
    // and resets it before the borrow ends, or by `adopt`, which keeps the flag in `ADOPTED`
    // for the thread's life.
    !flag.is_null() && unsafe { (*flag).load(Ordering::Relaxed) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_token_stops_only_the_threads_it_is_current_on() {
        let a = Token::new();
        let b = Token::new();
        let _in_a = a.enter();
        let other = {
            let b = b.clone();
            std::thread::spawn(move || {
                let _in_b = b.enter();
                std::thread::sleep(std::time::Duration::from_millis(50));
                requested()
            })
        };
        a.cancel();
        assert!(requested());
        assert!(!other.join().unwrap(), "b's thread saw a's cancel");
        assert!(!b.is_cancelled());
    }

    #[test]
    fn guards_nest_and_restore() {
        let outer = Token::new();
        let inner = Token::new();
        inner.cancel();
        let _o = outer.enter();
        {
            let _i = inner.enter();
            assert!(requested());
        }
        assert!(!requested());
    }

    #[test]
    fn an_adopted_token_outlives_its_owner() {
        let seen = std::thread::spawn(|| {
            let t = Token::new();
            t.adopt();
            t.cancel();
            drop(t);
            requested()
        })
        .join()
        .unwrap();
        assert!(seen);
    }
}
