//! The executor of geardyn: every analysis is a [`Job`] run by one function, [`execute`], over
//! one [`Store`] interface and watched by one [`Observer`] — whichever face asks (the CLI,
//! Python, a report study, a shard of a distributed plan).
//!
//! * [`job`]: the `Job` trait, [`execute`] and [`execute_items`] (a subset of a job's items: a
//!   shard);
//! * [`store`]: the `Store` trait and the JSONL checkpoint store of a command's folder
//!   ([`store::Checkpointed`]); the Zarr shard store is [`shard::ShardStore`];
//! * [`observer`]: the `Observer` trait and the progress bar;
//! * [`jobs`]: the analyses as jobs (sweeps, basins, continuation, maps, orbits, Lyapunov
//!   exponents, signals, one simulation);
//! * [`request`]: the resolved requests of the grid-shaped commands, one home for the single
//!   command and the merge of a sharded plan;
//! * [`shard`]: a plan split into shards over a Zarr v3 store, run and merged;
//! * [`cancel`]: a run under its own stop request ([`cancel::run_under`]).
//!
//! In the spirit of argmin's executor: the problems (the gear systems) and the solvers know
//! nothing of files, progress or resuming; all of that lives here.
#![warn(missing_docs)]

pub mod cancel;
pub mod error;
pub mod job;
pub mod jobs;
pub mod observer;
pub mod request;
pub mod shard;
pub mod store;

pub use job::{execute, execute_items, ExecError, ItemJob, Job};
pub use jobs::{
    BasinsJob, ContinuationJob, LyapunovJob, MapJob, OrbitsJob, SignalsJob, SimulateJob, SweepJob,
};
pub use observer::{Each, Observer, Progress};
pub use store::{Checkpointed, Store};
