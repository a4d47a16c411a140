//! The analyses as [`crate::Job`]s, one file each: the grid-shaped ones that resume item by item
//! from a store ([`SweepJob`], [`BasinsJob`], [`ContinuationJob`], [`MapJob`]; the sweep and the
//! map also run any subset of their items, a shard) and the ones that end in one result
//! ([`OrbitsJob`], [`LyapunovJob`], [`SignalsJob`], [`SimulateJob`]), which report their steps
//! to the observer as they go and are computed again when rerun. Each file holds its job's
//! struct and, through `job!`, the parts of its [`crate::Job`] impl that are its own.

/// A job's [`crate::Job`] impl from what differs between jobs: its record and output, its item id
/// (`by`), its kind, its number of items, the item a stored record finished, its settings and its
/// run (each part with the job bound to the name given, `run` also with the items finished before
/// and the callback of each record), and for a job whose items also run on their own its
/// [`crate::ItemJob`] impl (`run_items`, with the items to run and the callback). A job that ends in one result (`steps`) has no items of its
/// own: it announces `steps` (0: not known in advance) and trusts no stored record, so that a
/// rerun computes it again.
macro_rules! job {
    (impl[$($gen:tt)*] $job:ty: $kind:literal, $record:ty => $output:ty, steps $steps:literal;
     settings($js:ident) $settings:expr; run($jr:ident, $on_done:ident) $run:expr) => {
        job!(impl[$($gen)*] $job: $record => $output, by ();
             kind(_j) $kind; total(_j) $steps; id_of(_j, _) None;
             settings($js) $settings; run($jr, _, $on_done) $run);
    };
    (impl[$($gen:tt)*] $job:ty: $record:ty => $output:ty, by $id:ty;
     kind($jk:ident) $kind:expr; total($jt:ident) $total:expr; id_of($ji:ident, $r:pat) $id_of:expr;
     settings($js:ident) $settings:expr; run($jr:ident, $done:pat, $on_done:ident) $run:expr
     $(; run_items($jri:ident, $items:ident, $each:ident) $run_items:expr)?) => {
        #[allow(unused_variables)]
        impl<$($gen)*> $crate::job::Job for $job {
            type Record = $record;
            type Id = $id;
            type Output = $output;
            fn kind(&self) -> &str {
                let $jk = self;
                $kind
            }
            fn settings(&self) -> serde_json::Value {
                let $js = self;
                $settings
            }
            fn total(&self) -> usize {
                let $jt = self;
                $total
            }
            fn id_of(&self, $r: &$record) -> Option<$id> {
                let $ji = self;
                $id_of
            }
            fn run(
                &self,
                $done: std::collections::HashMap<$id, $record>,
                $on_done: &(dyn Fn(&$record) + Sync),
            ) -> Result<$output, $crate::job::ExecError> {
                let $jr = self;
                $run
            }
        }
        $(
            impl $crate::job::ItemJob for $job {
                fn run_items(
                    &self,
                    $items: &[$id],
                    $each: &(dyn Fn(&$record) + Sync),
                ) -> Result<Vec<$record>, $crate::job::ExecError> {
                    let $jri = self;
                    $run_items
                }
            }
        )?
    };
}

mod basins;
mod continuation;
mod lyapunov;
mod map;
mod orbits;
mod signals;
mod simulate;
mod sweep;

pub use basins::BasinsJob;
pub use continuation::ContinuationJob;
pub use lyapunov::LyapunovJob;
pub use map::MapJob;
pub use orbits::OrbitsJob;
pub use signals::SignalsJob;
pub use simulate::SimulateJob;
pub use sweep::SweepJob;

/// A request run on a scenario, one result ([`OrbitsJob`], [`SignalsJob`]).
pub struct RequestJob<'a, R> {
    /// The scenario the request is run on.
    pub scenario: &'a geardyn_scenario::Scenario,
    /// The request (checked when run).
    pub request: &'a R,
}

/// `settings` of a job: its options as JSON (options that cannot serialise make an empty key,
/// which no stored record matches).
pub(crate) fn settings_of(opts: &impl serde::Serialize) -> serde_json::Value {
    serde_json::to_value(opts).unwrap_or_default()
}
