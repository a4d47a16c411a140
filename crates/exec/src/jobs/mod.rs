//! The analyses as [`crate::Job`]s, one file each: the grid-shaped ones that resume item by item
//! from a store ([`SweepJob`], [`BasinsJob`], [`ContinuationJob`], [`MapJob`]; the sweep and the
//! map also run any subset of their items, a shard) and the ones that end in one result
//! ([`OrbitsJob`], [`LyapunovJob`], [`SignalsJob`], [`SimulateJob`]), which report their steps
//! to the observer as they go and are computed again when rerun.

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

/// `settings` of a job: its options as JSON (options that cannot serialise make an empty key,
/// which no stored record matches).
pub(crate) fn settings_of(opts: &impl serde::Serialize) -> serde_json::Value {
    serde_json::to_value(opts).unwrap_or_default()
}
