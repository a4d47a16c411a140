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

/// A plane of the state space: the grid's two axes are components [`Slice::axes`], every other
/// component is that of [`Slice::base`]. Built by [`Slice::new`], which checks it (the default:
/// the first two components, the others zero — the pair's whole state).
///
/// ```
/// use geardyn_analysis::grid::Slice;
/// let s = Slice::new((0, 2), [0.0, 0.5, 0.0, 0.0]).unwrap();
/// assert_eq!(s.state(1.0, 2.0), [1.0, 0.5, 2.0, 0.0]);
/// assert!(Slice::new((1, 1), [0.0; 4]).unwrap_err().to_string().contains("distinct"));
/// assert!(Slice::new((0, 4), [0.0; 4]).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slice<const N: usize> {
    axes: (usize, usize),
    base: [f64; N],
}

/// A slice that is no plane of the state.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SliceError {
    /// An axis outside the state or both axes the same.
    #[error("bad slice axes ({0}, {1}): two distinct state components in 0..{2}")]
    Axes(usize, usize, usize),
    /// A base component that is not finite.
    #[error("bad slice base: component {0} is {1}; allowed a finite number")]
    Base(usize, f64),
}

impl<const N: usize> Default for Slice<N> {
    /// The first two components, the others zero (a state of at least two components).
    fn default() -> Self {
        Slice {
            axes: (0, 1),
            base: [0.0; N],
        }
    }
}

impl<const N: usize> Slice<N> {
    /// The plane of components `axes.0` (the grid's `x` axis) and `axes.1` (its `v` axis)
    /// through `base` (the grid values replace those two components).
    pub fn new(axes: (usize, usize), base: [f64; N]) -> Result<Self, SliceError> {
        if axes.0 >= N || axes.1 >= N || axes.0 == axes.1 {
            return Err(SliceError::Axes(axes.0, axes.1, N));
        }
        if let Some((i, &v)) = base
            .iter()
            .enumerate()
            .find(|&(i, v)| i != axes.0 && i != axes.1 && !v.is_finite())
        {
            return Err(SliceError::Base(i, v));
        }
        Ok(Slice { axes, base })
    }

    /// The state components of the grid's two axes.
    pub fn axes(&self) -> (usize, usize) {
        self.axes
    }

    /// The other components of every initial state.
    pub fn base(&self) -> &[f64; N] {
        &self.base
    }

    /// The initial state at grid values `(a, b)`.
    pub fn state(&self, a: f64, b: f64) -> [f64; N] {
        let mut y = self.base;
        y[self.axes.0] = a;
        y[self.axes.1] = b;
        y
    }
}
