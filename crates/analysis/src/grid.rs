//! The grid of initial states of a basin: its axes ([`Axis`]) and the plane of the state they
//! span ([`Slice`]).

use serde::{Deserialize, Serialize};

/// A grid axis `MIN:MAX:N`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// Minimum.
    pub min: f64,
    /// Maximum.
    pub max: f64,
    /// Number of cells.
    pub n: usize,
}

impl Axis {
    /// Cell centre `i`.
    pub fn value(&self, i: usize) -> f64 {
        self.min + (self.max - self.min) * (i as f64 + 0.5) / self.n as f64
    }
}

/// A plane of the state space: the grid's two axes are components `axes.0` and `axes.1`, every
/// other component is that of `base`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slice<const N: usize> {
    /// State components of the grid's `x` and `v` axes.
    pub axes: (usize, usize),
    /// The other components of every initial state.
    pub base: [f64; N],
}

impl<const N: usize> Default for Slice<N> {
    /// The first two components, the others zero.
    fn default() -> Self {
        Slice {
            axes: (0, 1),
            base: [0.0; N],
        }
    }
}

impl<const N: usize> Slice<N> {
    /// The initial state at grid values `(a, b)`.
    pub fn state(&self, a: f64, b: f64) -> [f64; N] {
        let mut y = self.base;
        y[self.axes.0] = a;
        y[self.axes.1] = b;
        y
    }
}
