//! What watches a job: the [`Observer`] trait and the progress bar of the CLI and the report
//! ([`Progress`]). Python's progress line and Ctrl-C bookkeeping is another observer (in the
//! Python module).

use std::path::{Path, PathBuf};

/// What watches a job: progress, the partial result of an interrupted call. Every method has a
/// default that does nothing; `()` is the observer that watches nothing.
pub trait Observer<R>: Sync {
    /// The job starts: `total` items, `done` of them found in the store.
    fn start(&self, _kind: &str, _total: u64, _done: u64) {}
    /// One item finished (any thread, after the store has it).
    fn finished(&self, _record: &R) {}
    /// The job ended (whether or not it succeeded).
    fn end(&self) {}
}

impl<R> Observer<R> for () {}

/// A progress bar on stderr (the CLI's commands and the report's studies): the items done of the
/// total, elapsed time and an estimate of the time left; cleared at the end.
pub struct Progress {
    bar: indicatif::ProgressBar,
    /// Say on stderr how many items a resumed job found done.
    announce_resume: Option<PathBuf>,
}

impl Progress {
    /// A bar labelled with the job's kind, or with `label` when given (a report's computation).
    pub fn new(label: Option<&str>) -> Self {
        // one stack of bars for the process: a report's studies run side by side, and bars
        // drawn on their own overwrote each other's line
        static BARS: std::sync::OnceLock<indicatif::MultiProgress> = std::sync::OnceLock::new();
        let bar = BARS
            .get_or_init(indicatif::MultiProgress::new)
            .add(indicatif::ProgressBar::new(0));
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{msg:32} [{bar:40}] {pos}/{len}, {elapsed} elapsed, ETA {eta}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        if let Some(l) = label {
            bar.set_message(l.to_string());
        }
        Progress {
            bar,
            announce_resume: None,
        }
    }

    /// Also prints "resuming: N items already computed in `out`" when the store had some.
    pub fn announcing_resume(mut self, out: &Path) -> Self {
        self.announce_resume = Some(out.to_path_buf());
        self
    }
}

impl<R> Observer<R> for Progress {
    fn start(&self, kind: &str, total: u64, done: u64) {
        if self.bar.message().is_empty() {
            self.bar.set_message(kind.to_string());
        }
        if let (Some(out), true) = (&self.announce_resume, done > 0) {
            eprintln!(
                "resuming: {done} items already computed in {}",
                out.display()
            );
        }
        self.bar.set_length(total);
        self.bar.set_position(done);
        self.bar.reset_eta();
    }
    fn finished(&self, _: &R) {
        self.bar.inc(1);
    }
    fn end(&self) {
        self.bar.finish_and_clear();
    }
}

/// An observer that calls a function on each finished record (a line printed every so many
/// orbits, a round of a Lyapunov run).
pub struct Each<F>(pub F);

impl<R, F: Fn(&R) + Sync> Observer<R> for Each<F> {
    fn finished(&self, record: &R) {
        (self.0)(record)
    }
}
