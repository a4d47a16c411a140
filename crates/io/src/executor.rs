//! The executor: one loop for every resumable analysis — sweeps (bifurcation and response),
//! basins of attraction, attractor continuation and two-parameter maps — whichever face asks for
//! it (the CLI, Python, a report study).
//!
//! A [`Job`] says what its items are and how to run the ones not yet finished; [`execute`] reads
//! the finished items from the [`Store`] (a checkpoint file: one verified JSON line per item),
//! runs the rest, appends each one the moment it finishes, and tells an [`Observer`] (a progress
//! bar, Python's progress line and Ctrl-C bookkeeping, or nothing). A stored record is trusted
//! only when the job recognises it as one of its own items ([`Job::id_of`]); anything else is
//! computed again. Cancelling is the process-wide flag of [`geardyn_solvers::cancel`]: the
//! integrations end at their next step or period, and what finished before is in the store.
//!
//! A shard of a distributed plan ([`crate::shard`]) runs the same analyses on a subset of the
//! items and stores them as Zarr chunks instead.
//!
//! ```
//! use geardyn_io::executor::{execute, SweepJob};
//! use geardyn_io::request::SweepSpec;
//! use geardyn_io::Config;
//!
//! let mut cfg = Config::preset("classic").unwrap();
//! cfg.simulation.transient_periods = 20;
//! cfg.simulation.record_periods = 10;
//! let scenario = cfg.resolve().unwrap();
//! let spec = SweepSpec { values: vec![0.6, 0.7], ..SweepSpec::default() };
//! let opts = spec.options(&cfg, &scenario).unwrap();
//! // no store, no observer: the sweep's values, in order
//! let runs = execute(&SweepJob::new("bifurcation", &scenario, &opts), None, &()).unwrap();
//! assert_eq!(runs.len(), 2);
//! assert_eq!(runs[1].value, 0.7);
//! ```

use crate::checkpoint::Checkpoint;
use crate::output::OutputError;
use crate::run_record::{prepare_folder, FolderError, FolderLock};
use geardyn_analysis::attractor::Outcome;
use geardyn_analysis::attractor::Recordable;
use geardyn_analysis::basins::{basins, BasinOptions, BasinResult};
use geardyn_analysis::bifurcation::{run_sweep, tasks, SweepMode, SweepOptions, Task, TaskResult};
use geardyn_analysis::continuation::{
    continuation, ContinuationOptions, ContinuationResult, ValueAttractors,
};
use geardyn_analysis::map2d::{map2d, MapCell, MapOptions};
use geardyn_scenario::Scenario;
use serde::{de::DeserializeOwned, Serialize};
use std::collections::{HashMap, HashSet};
use std::hash::Hash;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Why a job did not run to its end.
#[derive(Debug, thiserror::Error)]
pub enum ExecError {
    /// The output folder cannot take this run (another command's, another run's, in use).
    #[error(transparent)]
    Folder(#[from] FolderError),
    /// The store cannot be read or written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The analysis itself refused or failed (its own error, unchanged).
    #[error(transparent)]
    Analysis(Box<dyn std::error::Error + Send + Sync>),
}

impl ExecError {
    fn analysis(e: impl std::error::Error + Send + Sync + 'static) -> Self {
        ExecError::Analysis(Box::new(e))
    }
}

/// One resumable analysis: a fixed list of items, each finished item one record.
pub trait Job: Sync {
    /// What a finished item leaves: written to the store, given to the observer.
    type Record: Serialize + DeserializeOwned + Send + Sync;
    /// What names an item.
    type Id: Eq + Hash;
    /// The result of the whole job.
    type Output;
    /// The command's name (`bifurcation`, `basins`, ...): the store's kind and the progress label.
    fn kind(&self) -> &str;
    /// Everything that decides the records (besides the scenario the store's context holds): a
    /// store made with other settings is not resumed.
    fn settings(&self) -> serde_json::Value;
    /// Number of items.
    fn total(&self) -> usize;
    /// The item a stored record finished, or `None` when it is not one of this job's items (out
    /// of range, another value, incomplete): such a record is computed again, never trusted.
    fn id_of(&self, record: &Self::Record) -> Option<Self::Id>;
    /// Runs the items not in `done`, calling `on_done` (from any thread) as each one finishes;
    /// the output covers every item, the `done` ones included.
    fn run(
        &self,
        done: HashMap<Self::Id, Self::Record>,
        on_done: &(dyn Fn(&Self::Record) + Sync),
    ) -> Result<Self::Output, ExecError>;
}

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

/// Where finished items are kept so that an interrupted job resumes.
pub struct Store {
    path: PathBuf,
    /// What the job's settings are joined with in the store's key (the configuration).
    context: serde_json::Value,
    /// Prepare the command folder holding the file (and hold its lock); with `force`.
    folder: Option<(PathBuf, bool)>,
}

impl Store {
    /// `out/checkpoint.jsonl` of a command's output folder. [`execute`] prepares the folder and
    /// holds its lock while it runs ([`prepare_folder`]): it refuses a folder holding another
    /// command's results, or a checkpoint made with another configuration or other settings
    /// (unless `force`, which sets that checkpoint aside and starts over).
    pub fn folder(out: &Path, config: &impl Serialize, force: bool) -> Result<Store, ExecError> {
        Ok(Store {
            path: out.join("checkpoint.jsonl"),
            context: to_value(config)?,
            folder: Some((out.to_path_buf(), force)),
        })
    }

    /// A checkpoint file of its own (a report study keeps one per computation in its folder); a
    /// file made with another context or other settings is set aside and the job starts over.
    pub fn file(path: &Path, context: &impl Serialize) -> Result<Store, ExecError> {
        Ok(Store {
            path: path.to_path_buf(),
            context: to_value(context)?,
            folder: None,
        })
    }

    fn key(&self, kind: &str, settings: serde_json::Value) -> Result<String, ExecError> {
        let key = serde_json::json!({ "kind": kind, "config": self.context, "settings": settings });
        serde_json::to_string(&key).map_err(ExecError::analysis)
    }

    /// Opens the file (the folder prepared and locked first), returning the records found.
    fn open<R: Serialize + DeserializeOwned>(
        &self,
        kind: &str,
        key: &str,
    ) -> Result<(Checkpoint, Vec<R>), ExecError> {
        let lock: Option<FolderLock> = match &self.folder {
            Some((out, force)) => Some(prepare_folder(out, kind, Some(key), *force)?),
            None => None,
        };
        let (cp, done) = Checkpoint::open::<R>(&self.path, key)?;
        Ok((
            match lock {
                Some(l) => cp.hold(l),
                None => cp,
            },
            done,
        ))
    }
}

fn to_value(v: &impl Serialize) -> Result<serde_json::Value, ExecError> {
    serde_json::to_value(v).map_err(ExecError::analysis)
}

/// Runs `job`: resumes from `store` (when given), appends every finished item to it, and tells
/// `observer`. The first store write error ends the call as an error after the job (the items
/// computed are not lost to the caller's retry: the records before it are stored).
pub fn execute<J: Job>(
    job: &J,
    store: Option<Store>,
    observer: &dyn Observer<J::Record>,
) -> Result<J::Output, ExecError> {
    let (cp, stored) = match store {
        Some(s) => {
            let key = s.key(job.kind(), job.settings())?;
            let (cp, stored) = s.open::<J::Record>(job.kind(), &key)?;
            (Some(cp), stored)
        }
        None => (None, Vec::new()),
    };
    let mut done = HashMap::new();
    for r in stored {
        if let Some(id) = job.id_of(&r) {
            done.insert(id, r);
        }
    }
    observer.start(job.kind(), job.total() as u64, done.len() as u64);
    let err = Mutex::new(None);
    let on_done = |r: &J::Record| {
        if let Some(cp) = &cp {
            if let Err(e) = cp.append(r) {
                err.lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .get_or_insert(e);
            }
        }
        observer.finished(r);
    };
    let out = job.run(done, &on_done);
    observer.end();
    let out = out?;
    match err.into_inner().unwrap_or_else(|e| e.into_inner()) {
        Some(e) => Err(e.into()),
        None => Ok(out),
    }
}

/// A parameter sweep (`bifurcation`, `response`, a report's sweep) of checked options
/// ([`crate::request::SweepSpec::options`]): one item per task, a [`TaskResult`] each.
pub struct SweepJob<'a> {
    kind: &'a str,
    scenario: &'a Scenario,
    opts: &'a SweepOptions,
    tasks: HashSet<Task>,
}

impl<'a> SweepJob<'a> {
    /// The sweep `opts` from `scenario`, stored and shown as `kind`.
    pub fn new(kind: &'a str, scenario: &'a Scenario, opts: &'a SweepOptions) -> Self {
        SweepJob {
            kind,
            scenario,
            opts,
            tasks: tasks(opts).into_iter().collect(),
        }
    }
}

impl Job for SweepJob<'_> {
    type Record = TaskResult;
    type Id = Task;
    type Output = Vec<TaskResult>;
    fn kind(&self) -> &str {
        self.kind
    }
    fn settings(&self) -> serde_json::Value {
        serde_json::to_value(self.opts).unwrap_or_default()
    }
    fn total(&self) -> usize {
        self.tasks.len()
    }
    fn id_of(&self, r: &TaskResult) -> Option<Task> {
        // one of this sweep's tasks, at its value, with every run of it
        let runs_per_task = match self.opts.mode {
            SweepMode::Multi { ics, .. } => ics.max(1),
            _ => 1,
        };
        (self.tasks.contains(&r.task)
            && self.opts.values.get(r.task.index) == Some(&r.value)
            && r.runs.len() == runs_per_task)
            .then_some(r.task)
    }
    fn run(
        &self,
        done: HashMap<Task, TaskResult>,
        on_done: &(dyn Fn(&TaskResult) + Sync),
    ) -> Result<Vec<TaskResult>, ExecError> {
        run_sweep(self.scenario, self.opts, &done, on_done).map_err(ExecError::analysis)
    }
}

/// Attractors continued over a parameter: one item per value, a [`ValueAttractors`] each.
pub struct ContinuationJob<'a> {
    /// The scenario the values are set on.
    pub scenario: &'a Scenario,
    /// Checked options.
    pub opts: &'a ContinuationOptions,
}

impl Job for ContinuationJob<'_> {
    type Record = ValueAttractors;
    type Id = usize;
    type Output = ContinuationResult;
    fn kind(&self) -> &str {
        "continuation"
    }
    fn settings(&self) -> serde_json::Value {
        serde_json::to_value(self.opts).unwrap_or_default()
    }
    fn total(&self) -> usize {
        self.opts.values.len()
    }
    fn id_of(&self, v: &ValueAttractors) -> Option<usize> {
        (v.index < self.total()).then_some(v.index)
    }
    fn run(
        &self,
        done: HashMap<usize, ValueAttractors>,
        on_done: &(dyn Fn(&ValueAttractors) + Sync),
    ) -> Result<ContinuationResult, ExecError> {
        continuation(self.scenario, self.opts, &done, on_done).map_err(ExecError::analysis)
    }
}

/// A basin grid: one item per cell (row-major, x fastest), its [`Outcome`] stored as
/// `(cell, outcome)`.
pub struct BasinsJob<'a, S> {
    /// The model whose basins are drawn.
    pub model: &'a S,
    /// Checked options.
    pub opts: &'a BasinOptions,
}

impl<S: Recordable<2> + Sync> Job for BasinsJob<'_, S> {
    type Record = (usize, Outcome);
    type Id = usize;
    type Output = BasinResult;
    fn kind(&self) -> &str {
        "basins"
    }
    fn settings(&self) -> serde_json::Value {
        serde_json::to_value(self.opts).unwrap_or_default()
    }
    fn total(&self) -> usize {
        self.opts.x.n * self.opts.v.n
    }
    fn id_of(&self, c: &(usize, Outcome)) -> Option<usize> {
        (c.0 < self.total()).then_some(c.0)
    }
    fn run(
        &self,
        done: HashMap<usize, (usize, Outcome)>,
        on_done: &(dyn Fn(&(usize, Outcome)) + Sync),
    ) -> Result<BasinResult, ExecError> {
        let done: HashMap<usize, Outcome> = done.into_iter().map(|(k, v)| (k, v.1)).collect();
        Ok(basins(self.model, self.opts, &done, |c, o| {
            on_done(&(c, o.clone()))
        }))
    }
}

/// A two-parameter map: one item per cell, a [`MapCell`] each.
pub struct MapJob<'a> {
    /// The scenario the two parameters are set on.
    pub scenario: &'a Scenario,
    /// Checked options.
    pub opts: &'a MapOptions,
}

impl Job for MapJob<'_> {
    type Record = MapCell;
    type Id = usize;
    type Output = Vec<MapCell>;
    fn kind(&self) -> &str {
        "map2d"
    }
    fn settings(&self) -> serde_json::Value {
        serde_json::to_value(self.opts).unwrap_or_default()
    }
    fn total(&self) -> usize {
        self.opts.x_values.len() * self.opts.y_values.len()
    }
    fn id_of(&self, c: &MapCell) -> Option<usize> {
        (c.index < self.total()).then_some(c.index)
    }
    fn run(
        &self,
        done: HashMap<usize, MapCell>,
        on_done: &(dyn Fn(&MapCell) + Sync),
    ) -> Result<Vec<MapCell>, ExecError> {
        map2d(self.scenario, self.opts, &done, on_done).map_err(ExecError::analysis)
    }
}

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
