//! Files of geardyn: configuration (TOML), data output (CSV/JSON) and plots (PNG/SVG).
//! Everything that touches the file system lives here, not in the physics or analysis crates.
#![warn(missing_docs)]

pub mod checkpoint;
pub mod config;
pub mod describe;
pub mod executor;
pub mod figure;
pub mod npy;
pub mod output;
pub mod pair_plots;
#[cfg(feature = "parquet")]
pub mod parquet_table;
pub mod request;
pub mod sweep_output;

pub mod run_record;
pub mod safe_write;
pub mod schema;
pub mod shard;
pub mod signal_plots;
pub mod simulate_folder;
pub mod zarr;
pub use config::{Config, ConfigError};
