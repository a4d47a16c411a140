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

/// A plane of the state space through [`Slice::base`]: the initial state at grid values `(a, b)`
/// is `base + a dx + b dv`. Two kinds are built, each checked: [`Slice::new`], two state
/// components (the grid's values replace them; the default: the first two components, the
/// others zero — the pair's whole state), and [`Slice::along`], two directions (a gear train's
/// mesh deflection and its rate, say).
///
/// ```
/// use geardyn_analysis::grid::Slice;
/// let s = Slice::new((0, 2), [0.0, 0.5, 0.0, 0.0]).unwrap();
/// assert_eq!(s.state(1.0, 2.0), [1.0, 0.5, 2.0, 0.0]);
/// assert!(Slice::new((1, 1), [0.0; 4]).unwrap_err().to_string().contains("distinct"));
/// assert!(Slice::new((0, 4), [0.0; 4]).is_err());
/// // a plane along directions: a = 1, b = 2 from base (1, 1, 0, 0)
/// let d = Slice::along([1.0, 1.0, 0.0, 0.0], [0.5, 0.5, 0.0, 0.0], [0.0, 0.0, 1.0, -1.0]).unwrap();
/// assert_eq!(d.state(1.0, 2.0), [1.5, 1.5, 2.0, -2.0]);
/// assert!(Slice::along([0.0; 4], [1.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0, 0.0]).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slice<const N: usize> {
    plane: Plane<N>,
    base: [f64; N],
}

/// How the grid's values enter the state.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Plane<const N: usize> {
    /// They replace two components (exactly: no arithmetic on them).
    Components(usize, usize),
    /// `base + a dx + b dv`.
    Directions([f64; N], [f64; N]),
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
    /// Directions that do not span a plane (zero, parallel or not finite).
    #[error("bad slice directions: two finite, linearly independent vectors of the state")]
    Directions,
}

impl<const N: usize> Default for Slice<N> {
    /// The first two components, the others zero (a state of at least two components).
    fn default() -> Self {
        Slice {
            plane: Plane::Components(0, 1),
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
        Ok(Slice {
            plane: Plane::Components(axes.0, axes.1),
            base,
        })
    }

    /// The plane `base + a dx + b dv` (`a` on the grid's `x` axis, `b` on its `v` axis).
    pub fn along(base: [f64; N], dx: [f64; N], dv: [f64; N]) -> Result<Self, SliceError> {
        if let Some((i, &v)) = base.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(SliceError::Base(i, v));
        }
        let dot = |a: &[f64; N], b: &[f64; N]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        let (xx, vv, xv) = (dot(&dx, &dx), dot(&dv, &dv), dot(&dx, &dv));
        // (Gram determinant: zero for parallel or vanishing directions)
        let gram = xx * vv - xv * xv;
        if !(gram.is_finite() && gram > 1e-24 * xx * vv) {
            return Err(SliceError::Directions);
        }
        Ok(Slice {
            plane: Plane::Directions(dx, dv),
            base,
        })
    }

    /// The state components of the grid's two axes (`None` for a plane along directions).
    pub fn axes(&self) -> Option<(usize, usize)> {
        match self.plane {
            Plane::Components(i, j) => Some((i, j)),
            Plane::Directions(..) => None,
        }
    }

    /// The other components of every initial state (components slice), or the plane's origin.
    pub fn base(&self) -> &[f64; N] {
        &self.base
    }

    /// The initial state at grid values `(a, b)`.
    pub fn state(&self, a: f64, b: f64) -> [f64; N] {
        let mut y = self.base;
        match &self.plane {
            Plane::Components(i, j) => {
                y[*i] = a;
                y[*j] = b;
            }
            Plane::Directions(dx, dv) => {
                for ((y, dx), dv) in y.iter_mut().zip(dx).zip(dv) {
                    *y += a * dx + b * dv;
                }
            }
        }
        y
    }

    /// Whether this is the default slice (the first two components through zero).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

/// Written into a job's settings (a basin store made on another plane is not resumed):
/// `{"axes": [i, j], "base": [...]}` or `{"dx": [...], "dv": [...], "base": [...]}`.
impl<const N: usize> Serialize for Slice<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(3))?;
        match &self.plane {
            Plane::Components(i, j) => m.serialize_entry("axes", &[*i, *j])?,
            Plane::Directions(dx, dv) => {
                m.serialize_entry("dx", &dx[..])?;
                m.serialize_entry("dv", &dv[..])?;
            }
        }
        m.serialize_entry("base", &self.base[..])?;
        m.end()
    }
}
