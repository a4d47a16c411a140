//! The values of a swept parameter: a range checked once for every face ([`range_values`]) and
//! evenly spaced values ([`linspace`]).

/// Most values of a range (`--range`, `range=`, a map's axis).
pub const MAX_RANGE_VALUES: usize = 1_000_000;

/// A range `(START, STOP, COUNT)` that cannot make values.
#[derive(Debug, thiserror::Error)]
#[error("bad {name} ({}, {}, {count}): finite START and STOP (finite difference too) and 1 <= COUNT <= {max}", geardyn_model::error::num(*.start), geardyn_model::error::num(*.stop))]
pub struct RangeError {
    /// What the caller calls the range (`range`, `x`, `y`).
    pub name: String,
    /// Given start.
    pub start: f64,
    /// Given stop.
    pub stop: f64,
    /// Given count.
    pub count: usize,
    /// Most values allowed.
    pub max: usize,
}

/// The `count` values of the range `name` from `start` to `stop` ([`linspace`]), checked: finite
/// ends whose difference is finite too, `1 ..= max` values. The one check of a range for every
/// face (`--range 0.5:2:200`, `range=(0.5, 2, 200)`, a map's `--x omega:0.5:2:40`).
///
/// ```
/// use geardyn_analysis::bifurcation::range_values;
/// assert_eq!(range_values("range", (0.5, 1.0, 2), 10).unwrap(), vec![0.5, 1.0]);
/// let e = range_values("x", (0.5, f64::NAN, 9), 10).unwrap_err();
/// assert!(e.to_string().starts_with("bad x (0.5, NaN, 9)"));
/// ```
pub fn range_values(
    name: &str,
    (start, stop, count): (f64, f64, usize),
    max: usize,
) -> Result<Vec<f64>, RangeError> {
    if !(start.is_finite() && stop.is_finite() && (stop - start).is_finite())
        || count == 0
        || count > max
    {
        return Err(RangeError {
            name: name.to_string(),
            start,
            stop,
            count,
            max,
        });
    }
    Ok(linspace(start, stop, count))
}

/// Evenly spaced values `start..=stop` (`count` of them), each rounded to 12 significant digits.
///
/// The rounding keeps a grid a person typed as decimals decimal: `0.1 + 0.1 * 3` is
/// `0.30000000000000004` in binary, and that is what a record would print and what would run.
/// Rounded, the value that runs is the one written (`0.3`), at most `5e-13` relative from the
/// exact fraction of the interval.
///
/// ```
/// use geardyn_analysis::bifurcation::linspace;
/// assert_eq!(linspace(0.1, 0.5, 5), vec![0.1, 0.2, 0.3, 0.4, 0.5]);
/// assert_eq!(linspace(0.0, 1.0, 4)[1], 0.333333333333);
/// assert_eq!(linspace(-0.1, 0.2, 4), vec![-0.1, 0.0, 0.1, 0.2]);
/// ```
pub fn linspace(start: f64, stop: f64, count: usize) -> Vec<f64> {
    match count {
        0 => vec![],
        1 => vec![start],
        _ => (0..count)
            .map(|i| {
                let v = start + (stop - start) * i as f64 / (count - 1) as f64;
                // a value that is zero but for the rounding of the sum (a grid through zero): the
                // sum's rounding is relative to its terms, not to the range (0.5:1e300 keeps 0.5)
                let zero = i > 0 && v.abs() <= 1e-12 * (start.abs() + (v - start).abs());
                if zero {
                    0.0
                } else {
                    decimal12(v)
                }
            })
            .collect(),
    }
}

/// `v` rounded to 12 significant decimal digits (non-finite values unchanged).
fn decimal12(v: f64) -> f64 {
    if !v.is_finite() {
        return v;
    }
    format!("{v:.11e}").parse().unwrap_or(v)
}
