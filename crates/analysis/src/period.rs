//! Minimal period of a stroboscopic sequence.

/// Tolerance of period detection: two stroboscopic points repeat when
/// `|dx| + |dv| <= PERIOD_TOL * (1 + max |state|)` over the whole compared window.
pub const PERIOD_TOL: f64 = 1e-6;

/// Minimal period `n` (in excitation periods, `1 <= n <= max_n`) of the stroboscopic points
/// `pts`, or `None` (chaotic, quasi-periodic or not yet settled). Each of the last `2*n` points is
/// compared with the one `n` before it, so at least `3*n` points are needed.
///
/// ```
/// let pts: Vec<[f64; 2]> = (0..12).map(|j| if j % 2 == 0 { [1.0, 0.0] } else { [2.0, 0.5] }).collect();
/// assert_eq!(geardyn_analysis::period::minimal_period(&pts, 8), Some(2));
/// ```
pub fn minimal_period<const N: usize>(pts: &[[f64; N]], max_n: usize) -> Option<usize> {
    minimal_period_tol(pts, max_n, PERIOD_TOL)
}

/// As [`minimal_period`], with relative tolerance `rel_tol` instead of [`PERIOD_TOL`] (the
/// simulation uses the integrator's own: `crate::simulate::Method::period_tol`).
pub fn minimal_period_tol<const N: usize>(
    pts: &[[f64; N]],
    max_n: usize,
    rel_tol: f64,
) -> Option<usize> {
    let tol = abs_tol(pts, rel_tol);
    let len = pts.len();
    (1..=max_n).find(|&n| len >= 3 * n && repeats(pts, n, len - 2 * n, tol))
}

/// `rel_tol * (1 + max |state|)` over `pts`.
fn abs_tol<const N: usize>(pts: &[[f64; N]], rel_tol: f64) -> f64 {
    let scale = 1.0
        + pts
            .iter()
            .flat_map(|p| p.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()));
    rel_tol * scale
}

/// Whether every point from index `from` on repeats the one `n` before it within `tol`.
fn repeats<const N: usize>(pts: &[[f64; N]], n: usize, from: usize, tol: f64) -> bool {
    (from..pts.len()).all(|j| {
        let d: f64 = (0..N).map(|i| (pts[j][i] - pts[j - n][i]).abs()).sum();
        d <= tol
    })
}

/// Whether the whole sequence `pts` lies on a cycle of period `n`: every point repeats the one
/// `n` before it within `rel_tol * (1 + max |state|)` (the test of [`minimal_period_tol`], over
/// the whole record instead of its end). `false` when the motion reached its orbit only inside
/// the record: statistics of such a record mix transient and steady state.
///
/// ```
/// use geardyn_analysis::period::on_cycle_throughout;
/// let mut pts: Vec<[f64; 1]> = (0..12).map(|j| [(j % 2) as f64]).collect();
/// assert!(on_cycle_throughout(&pts, 2, 1e-9));
/// pts[0][0] = 0.5; // the first point is still transient
/// assert!(!on_cycle_throughout(&pts, 2, 1e-9));
/// ```
pub fn on_cycle_throughout<const N: usize>(pts: &[[f64; N]], n: usize, rel_tol: f64) -> bool {
    n > 0 && repeats(pts, n, n, abs_tol(pts, rel_tol))
}

/// Ratio of the mean lag-`d` difference over the first part of a record to that over its last
/// part above which a period-`n` record is still approaching an orbit of period `d` (a settled
/// period-`n` orbit keeps its lag-`d` differences constant: the ratio is 1 to rounding).
pub const APPROACH_RATIO: f64 = 1.05;

/// Whether the sequence `pts`, periodic with minimal period `n` at its end, is still approaching
/// an orbit of a proper divisor `d` of `n`: a slowly decaying flip (or other) mode makes points
/// `d` apart differ by a shrinking amount that is still above the tolerance, while points `n`
/// apart already agree. Detected from the mean lag-`d` difference over the first, middle and
/// last thirds of the record (whole cycles of `n`), when either
/// * the first exceeds [`APPROACH_RATIO`] times the last and ten times the period-test tolerance
///   `rel_tol (1 + max |state|)` (smaller differences may be the integrator's noise), or
/// * the differences exceed the tolerance itself (they are what fails the period-`d` test) and
///   shrink from third to third by [`APPROACH_RATIO`] each time: the steady decay of a mode, which
///   the integrator's noise (a fluctuating or fixed pattern) does not show. On the internal pair
///   at `omega = 0.7` lag-2 differences of 7.7e-6 falling to 2.7e-6 at the rate of the exponent
///   (-0.00137) had made a period-2 orbit read as period 4.
///
/// ```
/// use geardyn_analysis::period::approaches_lower_period;
/// // a period-1 point with a flip mode decaying by 1.5 % per period
/// let flip: Vec<[f64; 1]> = (0..120).map(|j| [1.0 + 1e-3 * (-0.985f64).powi(j)]).collect();
/// assert!(approaches_lower_period(&flip, 2, 1e-6));
/// // the same mode a hundred times smaller and slower: lag-1 differences of 1.6e-5 falling to
/// // 7e-6, above the tolerance 1e-6 (1 + 1) but below ten times it
/// let slow: Vec<[f64; 1]> = (0..120).map(|j| [1.0 + 1e-5 * (-0.99f64).powi(j)]).collect();
/// assert!(approaches_lower_period(&slow, 2, 1e-6));
/// // a fixed pattern of the same size (integrator noise locked to the period) is no approach
/// let fixed: Vec<[f64; 1]> = (0..120).map(|j| [1.0 + 4e-6 * ((j % 2) as f64)]).collect();
/// assert!(!approaches_lower_period(&fixed, 2, 1e-6));
/// // a settled period-2 orbit
/// let p2: Vec<[f64; 1]> = (0..120).map(|j| [(j % 2) as f64]).collect();
/// assert!(!approaches_lower_period(&p2, 2, 1e-6));
/// ```
pub fn approaches_lower_period<const N: usize>(pts: &[[f64; N]], n: usize, rel_tol: f64) -> bool {
    let len = pts.len();
    let tol = abs_tol(pts, rel_tol);
    (1..n).filter(|d| n.is_multiple_of(*d)).any(|d| {
        let diffs: Vec<f64> = (d..len)
            .map(|j| (0..N).map(|i| (pts[j][i] - pts[j - d][i]).abs()).sum())
            .collect();
        let k = diffs.len() / (3 * n);
        if k == 0 {
            return false;
        }
        let w = k * n;
        let first: f64 = diffs[..w].iter().sum();
        let last: f64 = diffs[diffs.len() - w..].iter().sum();
        let mid_at = (diffs.len() - w) / 2;
        let mid: f64 = diffs[mid_at..mid_at + w].iter().sum();
        let steady = first > APPROACH_RATIO * mid && mid > APPROACH_RATIO * last;
        last > 0.0
            && first > APPROACH_RATIO * last
            && (first > 10.0 * tol * w as f64 || (steady && last > tol * w as f64))
    })
}

/// Whether the points of a sequence periodic with minimal period `n` at its end differ, at some
/// proper divisor `d` of `n`, by more than `rel_tol (1 + max |state|)` but at most
/// `rel_loose` times that scale over the last `2n` points: a near-degenerate divisor (a small
/// split of a genuine period `n`, or integration error repeating with period `n`).
///
/// ```
/// use geardyn_analysis::period::lag_split;
/// // a period-1 point with a period-2 wobble of 4e-6: split between 1e-6 and 1e-4
/// let p: Vec<[f64; 1]> = (0..60).map(|j| [1.0 + 4e-6 * ((j % 2) as f64)]).collect();
/// assert!(lag_split(&p, 2, 1e-6, 1e-4));
/// // a clear period 2
/// let q: Vec<[f64; 1]> = (0..60).map(|j| [(j % 2) as f64]).collect();
/// assert!(!lag_split(&q, 2, 1e-6, 1e-4));
/// ```
pub fn lag_split<const N: usize>(pts: &[[f64; N]], n: usize, rel_tol: f64, rel_loose: f64) -> bool {
    let len = pts.len();
    if n < 2 || len < 2 * n + 1 {
        return false;
    }
    let (tol, loose) = (abs_tol(pts, rel_tol), abs_tol(pts, rel_loose));
    (1..n).filter(|d| n.is_multiple_of(*d)).any(|d| {
        let worst = (len - 2 * n..len)
            .filter(|&j| j >= d)
            .map(|j| {
                (0..N)
                    .map(|i| (pts[j][i] - pts[j - d][i]).abs())
                    .sum::<f64>()
            })
            .fold(0.0f64, f64::max);
        worst > tol && worst <= loose
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detects_minimal_not_multiple() {
        let p4: Vec<[f64; 2]> = (0..40).map(|j| [(j % 4) as f64, 0.0]).collect();
        assert_eq!(minimal_period(&p4, 16), Some(4));
        let chaos: Vec<[f64; 2]> = (0..40).map(|j| [(j as f64 * 1.618).fract(), 0.0]).collect();
        assert_eq!(minimal_period(&chaos, 16), None);
        // too short to confirm
        assert_eq!(minimal_period(&p4[..10], 16), None);
    }
}
