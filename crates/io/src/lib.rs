//! Files of geardyn: configuration (TOML), data output (CSV/JSON/NPY), run records, the
//! checkpoint file format, Zarr arrays and the folders of the commands. The executor that runs
//! analyses over stores of these files is `geardyn-exec`. Everything that
//! touches the file system lives here or below (figures: `geardyn-plots`; atomic writes:
//! `geardyn-files`, re-exported under their old paths), not in the physics or analysis crates.
#![warn(missing_docs)]

pub mod checkpoint;
pub mod config;
pub mod describe;
pub mod npy;
pub mod output;
#[cfg(feature = "parquet")]
pub mod parquet_table;
pub mod sweep_output;

pub mod run_record;
pub mod schema;
pub mod simulate_folder;
pub mod zarr;
pub use config::{Config, ConfigError};
pub use geardyn_files::safe_write;
pub use geardyn_plots::{figure, pair_plots, signal_plots};
