//! Running a job under its own stop request: [`run_under`] makes a [`Token`] current on the
//! calling thread and on every worker thread of a thread pool made for the run (the analyses'
//! parallel loops run there), so cancelling the token stops this run and no other.
//! Ctrl-C stops every run of the process ([`geardyn_solvers::cancel::request`]).
//!
//! ```
//! use geardyn_exec::cancel::{run_under, Token};
//! use geardyn_analysis::bifurcation::TaskResult;
//! use geardyn_exec::{execute, request::SweepSpec, Each, SweepJob};
//! use geardyn_io::Config;
//!
//! let mut cfg = Config::preset("classic").unwrap();
//! cfg.simulation.transient_periods = 20;
//! cfg.simulation.record_periods = 10;
//! let scenario = cfg.resolve().unwrap();
//! let opts = SweepSpec { values: vec![0.6, 0.7], ..SweepSpec::default() }
//!     .options(&cfg, &scenario)
//!     .unwrap();
//! let token = Token::new();
//! token.cancel(); // (from another thread: a Ctrl-C watcher, a closed browser tab, ...)
//! let finished = std::sync::atomic::AtomicUsize::new(0);
//! let count = Each(|_: &TaskResult| {
//!     finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
//! });
//! let job = SweepJob::new("bifurcation", &scenario, &opts);
//! let _ = run_under(&token, || execute(&job, None, &count));
//! assert_eq!(finished.into_inner(), 0); // stopped before any value was finished
//! ```

pub use geardyn_solvers::cancel::Token;

/// Runs `f` with `token` current on this thread and on the worker threads of a pool made for
/// the run (as many threads as the current pool has, so results do not change: they never
/// depend on which thread computed them).
pub fn run_under<R: Send>(token: &Token, f: impl FnOnce() -> R + Send) -> R {
    let adopt = token.clone();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(rayon::current_num_threads())
        .start_handler(move |_| adopt.adopt())
        .build();
    let _current = token.enter();
    match pool {
        Ok(pool) => pool.install(f),
        // (no threads to be had: the run stays on the global pool, stopped by Ctrl-C only)
        Err(_) => f(),
    }
}
