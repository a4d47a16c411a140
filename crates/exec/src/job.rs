//! The [`Job`] trait and the one loop that runs every job, [`execute`] (and [`execute_items`]
//! for a subset of a job's items: a shard of a distributed plan).
//!
//! A job says what its items are and how to run the ones not finished yet; [`execute`] reads
//! the finished items from the [`Store`] (trusting a stored record only when the job recognises
//! it as one of its own items, [`Job::id_of`]), runs the rest, hands each record to the store the
//! moment it finishes and tells the [`Observer`]. Cancelling is the solvers' stop request
//! ([`geardyn_solvers::cancel`]): the integrations end at their next step or period, and what
//! finished before is in the store.
//!
//! ```
//! use geardyn_exec::jobs::SweepJob;
//! use geardyn_exec::execute;
//! use geardyn_exec::request::SweepSpec;
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

pub use crate::error::ExecError;
use crate::observer::Observer;
use crate::store::Store;
use std::collections::HashMap;
use std::hash::Hash;
use std::sync::Mutex;

/// One analysis: a fixed list of items, each finished item one record.
pub trait Job: Sync {
    /// What a finished item leaves: given to the store and the observer.
    type Record: Send + Sync;
    /// What names an item.
    type Id: Eq + Hash + Clone;
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

/// A job whose items can run on their own, any subset in any grouping with the same records
/// (the lanes make a point's result independent of its batch): what a shard of a distributed
/// plan runs ([`execute_items`]).
pub trait ItemJob: Job {
    /// Runs `items`, calling `on_done` as each finishes; their records in the order of `items`.
    fn run_items(
        &self,
        items: &[Self::Id],
        on_done: &(dyn Fn(&Self::Record) + Sync),
    ) -> Result<Vec<Self::Record>, ExecError>;
}

/// Runs `job`: resumes from `store` (when given), hands every finished item to it, and tells
/// `observer`. The first store error ends the call as an error after the job (the items
/// computed are not lost to the caller's retry: the records before it are stored).
pub fn execute<J: Job>(
    job: &J,
    mut store: Option<&mut dyn Store<J::Record>>,
    observer: &dyn Observer<J::Record>,
) -> Result<J::Output, ExecError> {
    let stored = match store.as_deref_mut() {
        Some(s) => s.open(job.kind(), job.settings())?,
        None => Vec::new(),
    };
    let mut done = HashMap::new();
    for r in stored {
        if let Some(id) = job.id_of(&r) {
            done.insert(id, r);
        }
    }
    observer.start(job.kind(), job.total() as u64, done.len() as u64);
    let err = Mutex::new(None);
    let out = {
        let sink = store.as_deref();
        let on_done = |r: &J::Record| {
            if let Some(s) = sink {
                if let Err(e) = s.append(r) {
                    err.lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .get_or_insert(e);
                }
            }
            observer.finished(r);
        };
        job.run(done, &on_done)
    };
    observer.end();
    if let Some(s) = store {
        s.close();
    }
    let out = out?;
    match err.into_inner().unwrap_or_else(|e| e.into_inner()) {
        Some(e) => Err(e),
        None => Ok(out),
    }
}

/// Runs `items` of `job` into `store`, all or nothing: a store that holds every item's record
/// (a shard done before) returns them without computing; otherwise the items are computed and the
/// store completes with all of them ([`Store::finish`]). The records come in the order of
/// `items`.
pub fn execute_items<J: ItemJob>(
    job: &J,
    items: &[J::Id],
    store: &mut dyn Store<J::Record>,
    observer: &dyn Observer<J::Record>,
) -> Result<Vec<J::Record>, ExecError> {
    let mut stored: HashMap<J::Id, J::Record> = HashMap::new();
    for r in store.open(job.kind(), job.settings())? {
        if let Some(id) = job.id_of(&r) {
            stored.insert(id, r);
        }
    }
    if !items.is_empty() && items.iter().all(|i| stored.contains_key(i)) {
        observer.start(job.kind(), items.len() as u64, items.len() as u64);
        observer.end();
        store.close();
        return Ok(items.iter().filter_map(|i| stored.remove(i)).collect());
    }
    observer.start(job.kind(), items.len() as u64, 0);
    let out = job.run_items(items, &|r| observer.finished(r));
    observer.end();
    let out = out?;
    if geardyn_solvers::cancel::requested() {
        store.close();
        return Err(ExecError::Store("interrupted".into()));
    }
    store.finish(&out)?;
    store.close();
    Ok(out)
}
