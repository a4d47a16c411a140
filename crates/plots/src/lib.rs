//! Figures of geardyn: one drawing layer ([`figure`]: stacked panels, legends, merged scatter
//! layers, rasters, a palette of many distinct colours; PNG and SVG from the same code with the
//! DejaVu Sans font embedded) and the figures built on it for a pair's stiffness, load shares and
//! friction ([`pair_plots`]) and for vibration signals ([`signal_plots`]). Figures of sweeps,
//! maps and basins are drawn by `geardyn-io` through [`figure`].
#![warn(missing_docs)]

mod colors;
pub mod figure;
pub mod pair_plots;
mod raster;
pub mod signal_plots;
