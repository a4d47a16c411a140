//! The ensemble escape test: chaos told from transient chaos (Lai & Tél, *Transient Chaos*,
//! Springer 2011, ch. 1–2).
//!
//! A chaotic **attractor** is invariant: copies of a state on it, perturbed by far less than any
//! physical scale, never leave it. A chaotic **saddle** (transient chaos) leaks: the time a
//! trajectory stays on it is exponentially distributed with a mean lifetime `tau` (the escape
//! rate is `kappa = 1 / tau`), and `N` independent copies leak `N` times as fast. So the test
//! perturbs the state of a run whose exponent is positive into `N` copies (a relative
//! perturbation of [`ESCAPE_PERTURBATION`], far below every length of the model), follows them
//! together and records, for each copy that reaches a periodic orbit, its escape time and its
//! orbit. It ends after [`EscapeSettings::stop_after`] escapes or at its span
//! ([`EscapeSettings::periods`] excitation periods), whichever comes first.
//!
//! **Lifetime.** The escape times are exponential, censored where the test ended (type I at the
//! span, type II at the `k`-th escape): the maximum-likelihood estimate is
//! `tau = (sum of the escape times + censored copies x test length) / k`, with the standard error
//! `tau / sqrt(k)` (the Fisher information of `k` exponential events). With no escape in `N`
//! copies over `H` periods the exposure `N H` excludes lifetimes below `N H / ln 20` at 95 %
//! confidence (`P(no escape) = exp(-N H / tau) < 0.05`): the lower bound [`Lifetime::AtLeast`]
//! states.
//!
//! **Escape time.** The first period from which the copy's stroboscopic points repeat with their
//! period (to the period test's tolerance) to the end of its window: the time it reached the
//! orbit, which includes the approach (tens of periods on a mildly attracting orbit, small beside
//! the lifetimes the test is for). The copies start within `1e-9` of one another and stay
//! correlated until the exponent has grown the perturbation to the attractor's size (`ln(1e9) /
//! lambda`, one to a few dozen periods on the seed pairs): a run whose own trajectory was about to
//! escape takes its copies with it, and the test then reports transient chaos with a short
//! lifetime, which is what it is.
//!
//! The bookkeeping here is generic (any system, any way to advance the copies); the single pair
//! advances them in its lockstep lanes ([`crate::pair_engine`]), a map in the tests.

use crate::period::minimal_period_tol;
use serde::{Deserialize, Serialize};

/// Default number of copies ([`EscapeSettings::copies`]): one full lane engine.
pub const ESCAPE_COPIES: u32 = 16;
/// Default span of the test ([`EscapeSettings::periods`]): 0, the span of
/// [`EscapeSettings::span`] (the copies' spread, then [`ESCAPE_EXPOSURE`] horizons of exposure).
pub const ESCAPE_PERIODS: u64 = 0;
/// Exposure the test needs before it calls a motion chaotic: this many times the decision horizon
/// in copy-periods (after the copies have spread). No escape in it excludes lifetimes below
/// `2 / ln 20 = 0.67` horizons at 95 % confidence — a single trajectory followed to the horizon
/// excludes a third of one — at about the cost of following that trajectory twice as far.
pub const ESCAPE_EXPOSURE: u64 = 2;
/// Shortest default span (excitation periods): time for an escaped copy to show its period.
pub const ESCAPE_MIN_PERIODS: u64 = 100;
/// Largest spread time counted ([`decorrelation_periods`], excitation periods).
pub const ESCAPE_MAX_SPREAD: u64 = 2000;
/// [`EscapeSettings::copies`] accepted besides 0.
pub const ESCAPE_COPIES_RANGE: std::ops::RangeInclusive<u32> = 2..=4096;
/// [`EscapeSettings::periods`] accepted besides 0 (the default span).
pub const ESCAPE_PERIODS_RANGE: std::ops::RangeInclusive<u64> = 100..=1_000_000;
/// Default number of escapes that end the test ([`EscapeSettings::stop_after`]).
pub const ESCAPE_STOP_AFTER: u32 = 4;
/// Relative size of the perturbation of the copies: `|dy_i| <= ESCAPE_PERTURBATION (1 + |y|)`.
pub const ESCAPE_PERTURBATION: f64 = 1e-9;
/// Excitation periods the copies advance between two looks for a period.
pub const ESCAPE_BLOCK: u64 = 100;
/// `-ln(0.05)`: the exposure (copy-periods) over which a lifetime `tau` would give at least one
/// escape with 95 % probability is `tau ln 20`.
pub const LN_20: f64 = 2.995_732_273_553_991;

/// Settings of the escape test.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EscapeSettings {
    /// Copies of the state followed (0: no escape test; the decision follows the run's own
    /// trajectory to its horizon instead).
    pub copies: u32,
    /// Span of the test (excitation periods); 0: the span whose silence excludes lifetimes below
    /// the decision horizon ([`EscapeSettings::span`]).
    pub periods: u64,
    /// Escapes that end the test early (its lifetime estimate then has a relative standard error
    /// of `1 / sqrt(stop_after)`).
    pub stop_after: u32,
    /// Relative size of the perturbation ([`ESCAPE_PERTURBATION`]).
    pub perturbation: f64,
    /// Excitation periods the copies take to spread over the chaotic set
    /// ([`decorrelation_periods`]): escape times and exposure count from there (set by the
    /// decision from the motion's exponent).
    #[serde(skip)]
    pub spread: u64,
}

impl Default for EscapeSettings {
    fn default() -> Self {
        EscapeSettings {
            copies: ESCAPE_COPIES,
            periods: ESCAPE_PERIODS,
            stop_after: ESCAPE_STOP_AFTER,
            perturbation: ESCAPE_PERTURBATION,
            spread: 0,
        }
    }
}

impl EscapeSettings {
    /// Whether the test runs at all.
    pub fn on(&self) -> bool {
        self.copies > 0
    }

    /// The span (excitation periods) in a decision of horizon `decision_periods`: the one set, or
    /// by default the copies' spread ([`EscapeSettings::spread`]) and then the exposure the
    /// verdict `chaotic` needs ([`EscapeSettings::required`]), at least [`ESCAPE_MIN_PERIODS`].
    ///
    /// ```
    /// use geardyn_analysis::escape::EscapeSettings;
    /// let s = EscapeSettings { spread: 30, ..Default::default() };
    /// assert_eq!(s.span(10_000), 30 + 1250); // 16 copies x 1250 periods = 2 horizons
    /// assert_eq!(s.span(200), 100);
    /// assert_eq!(EscapeSettings { periods: 500, ..s }.span(10_000), 500);
    /// ```
    pub fn span(&self, decision_periods: u64) -> u64 {
        if self.periods > 0 {
            return self.periods;
        }
        self.required(decision_periods).max(ESCAPE_MIN_PERIODS)
    }

    /// The span a silent test must have run to call a motion chaotic in a decision of horizon
    /// `decision_periods`: the spread, then [`ESCAPE_EXPOSURE`] horizons of copy-periods.
    pub fn required(&self, decision_periods: u64) -> u64 {
        let per_copy = (ESCAPE_EXPOSURE * decision_periods).div_ceil(u64::from(self.copies.max(1)));
        self.spread + per_copy
    }
}

/// Excitation periods for copies perturbed by `perturbation` to spread over a chaotic set whose
/// top Lyapunov exponent is `tle` (per unit time), the excitation period lasting `period` units:
/// `ln(1 / perturbation) / (tle period)`, at most [`ESCAPE_MAX_SPREAD`]. Until then the copies are
/// one trajectory: they neither escape independently nor add exposure.
///
/// ```
/// // C1 at omega = 1.3: TLE 0.080, period 2 pi / 1.3: ln(1e9) / 0.387 = 54 periods
/// let d = geardyn_analysis::escape::decorrelation_periods(0.080, std::f64::consts::TAU / 1.3, 1e-9);
/// assert_eq!(d, 54);
/// ```
pub fn decorrelation_periods(tle: f64, period: f64, perturbation: f64) -> u64 {
    let growth = tle * period;
    // (NaN fails both comparisons: the longest spread)
    let valid = growth > 0.0 && perturbation > 0.0 && perturbation < 1.0;
    if !valid {
        return ESCAPE_MAX_SPREAD;
    }
    ((1.0 / perturbation).ln() / growth)
        .ceil()
        .min(ESCAPE_MAX_SPREAD as f64) as u64
}

/// The state of one copy: time, state and the memory of its mode (as a run continues:
/// [`crate::simulate::SimOptions::start_memory`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Copy<const N: usize> {
    /// Time (dimensionless, a stroboscopic instant).
    pub t: f64,
    /// State.
    pub y: [f64; N],
    /// Memory of the mode.
    pub memory: f64,
}

/// The mean lifetime on the chaotic set, in excitation periods.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Lifetime {
    /// Some copies escaped: the maximum-likelihood estimate and its standard error.
    Estimate {
        /// Mean lifetime (excitation periods).
        periods: f64,
        /// Its standard error.
        stderr: f64,
    },
    /// No copy escaped: lifetimes below this are excluded at 95 % confidence.
    AtLeast {
        /// The bound (excitation periods).
        periods: f64,
    },
}

impl Lifetime {
    /// The maximum-likelihood lifetime of `copies` copies of which those in `escapes` escaped at
    /// the given times, the others censored at `censored_at` periods (see the module doc).
    ///
    /// ```
    /// use geardyn_analysis::escape::Lifetime;
    /// // 4 of 10 copies escaped at 10, 20, 30 and 40 periods, the others stayed 100
    /// let l = Lifetime::from_escapes(10, &[10.0, 20.0, 30.0, 40.0], 100.0);
    /// assert_eq!(l, Lifetime::Estimate { periods: 175.0, stderr: 87.5 });
    /// // none of 10 escaped in 100 periods: tau >= 1000 / ln 20
    /// let Lifetime::AtLeast { periods } = Lifetime::from_escapes(10, &[], 100.0) else { panic!() };
    /// assert!((periods - 333.8).abs() < 0.1);
    /// ```
    pub fn from_escapes(copies: u32, escapes: &[f64], censored_at: f64) -> Lifetime {
        let k = escapes.len();
        let stayed = (copies as usize).saturating_sub(k) as f64;
        let exposure = escapes.iter().sum::<f64>() + stayed * censored_at;
        if k == 0 {
            Lifetime::AtLeast {
                periods: exposure / LN_20,
            }
        } else {
            let tau = exposure / k as f64;
            Lifetime::Estimate {
                periods: tau,
                stderr: tau / (k as f64).sqrt(),
            }
        }
    }

    /// The estimate or the bound (excitation periods).
    pub fn periods(&self) -> f64 {
        match *self {
            Lifetime::Estimate { periods, .. } | Lifetime::AtLeast { periods } => periods,
        }
    }
}

/// Copies that settled on one periodic orbit.
#[derive(Clone, Debug, PartialEq)]
pub struct Settled<const N: usize> {
    /// Period of the orbit (excitation periods).
    pub period: usize,
    /// Copies that settled on it.
    pub count: u32,
    /// The earliest escape time among them (excitation periods from the start of the test).
    pub first: u64,
    /// The final state of the earliest of them (on the orbit).
    pub state: Copy<N>,
    /// Excitation periods that copy was followed (to `state`).
    pub followed: u64,
    /// Its last `period` stroboscopic states (the orbit's points).
    pub points: Vec<[f64; N]>,
}

/// What the escape test found.
#[derive(Clone, Debug, PartialEq)]
pub struct EscapeOutcome<const N: usize> {
    /// Copies followed (those whose integration failed are not counted).
    pub copies: u32,
    /// Escape times of the copies that reached a periodic orbit (excitation periods from the
    /// start of the test), in copy order.
    pub escape_times: Vec<u64>,
    /// Excitation periods the test ran.
    pub periods: u64,
    /// The lifetime it measured or bounds.
    pub lifetime: Lifetime,
    /// The orbits the escaped copies settled on, most copies first (then earliest).
    pub orbits: Vec<Settled<N>>,
    /// Right-hand-side evaluations of the whole test.
    pub rhs_evals: u64,
}

impl<const N: usize> EscapeOutcome<N> {
    /// Whether any copy escaped.
    pub fn escaped(&self) -> bool {
        !self.escape_times.is_empty()
    }

    /// What a run's summary reports of the test.
    pub fn summary(&self) -> EscapeSummary {
        EscapeSummary {
            copies: self.copies,
            escaped: self.escape_times.len() as u32,
            periods: self.periods,
            lifetime: self.lifetime,
            orbits: self
                .orbits
                .iter()
                .map(|g| SettledSummary {
                    period: g.period,
                    count: g.count,
                    first: g.first,
                })
                .collect(),
        }
    }
}

/// The escape test in a run's summary ([`crate::summary::Summary::escape`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EscapeSummary {
    /// Copies followed.
    pub copies: u32,
    /// Copies that reached a periodic orbit.
    pub escaped: u32,
    /// Excitation periods the test ran.
    pub periods: u64,
    /// The lifetime on the chaotic set: an estimate when copies escaped, else a lower bound.
    pub lifetime: Lifetime,
    /// The orbits the copies settled on (period, copies, earliest escape), most copies first.
    pub orbits: Vec<SettledSummary>,
}

/// One orbit of [`EscapeSummary::orbits`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SettledSummary {
    /// Period (excitation periods).
    pub period: usize,
    /// Copies that settled on it.
    pub count: u32,
    /// Earliest escape time (excitation periods from the start of the test).
    pub first: u64,
}

/// The copies of `start`: copy `i` perturbed by a vector drawn uniformly from the ball of radius
/// `perturbation (1 + |y|)` by a generator seeded by `i` (the same copies on any machine and thread count). Copy 0 is the
/// state itself (the run's own trajectory is one of the ensemble).
pub fn copies_of<const N: usize>(start: Copy<N>, n: u32, perturbation: f64) -> Vec<Copy<N>> {
    use rand::{Rng, SeedableRng};
    let norm = start.y.iter().map(|v| v * v).sum::<f64>().sqrt();
    let size = perturbation * (1.0 + norm);
    (0..n)
        .map(|i| {
            if i == 0 {
                return start;
            }
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x6573_6361_7065 ^ u64::from(i));
            // uniform in the ball (rejection from the cube): directions and sizes both vary, so
            // that copies differ even in one dimension
            let mut d = [0.0; N];
            loop {
                for v in d.iter_mut() {
                    *v = rng.gen_range(-1.0..1.0);
                }
                let len = d.iter().map(|v| v * v).sum::<f64>().sqrt();
                if len <= 1.0 && len > 1e-3 {
                    break;
                }
            }
            let mut c = start;
            for (y, v) in c.y.iter_mut().zip(d) {
                *y += size * v;
            }
            c
        })
        .collect()
}

/// One copy during the test.
struct Follow<const N: usize> {
    copy: Copy<N>,
    /// Its stroboscopic states since the start of the test, the last `keep` of them.
    window: Vec<[f64; N]>,
    /// Periods before `window[0]`.
    offset: u64,
    /// `(escape time, period)` once it settled.
    settled: Option<(u64, usize)>,
    failed: bool,
}

/// What one block of the escape test gives back: per copy, its stroboscopic states over the block
/// (one per excitation period; `None` for a copy whose integration failed), and the
/// right-hand-side evaluations of the block.
pub type Advanced<const N: usize> = (Vec<Option<Vec<[f64; N]>>>, u64);

/// The escape test from `start` (see the module doc): `advance(copies, periods)` moves each copy
/// on by `periods` excitation periods ([`Advanced`]); `max_period` and `tol` are the period
/// test's (the relative tolerance of [`minimal_period_tol`]).
pub fn escape_test<const N: usize>(
    start: Copy<N>,
    s: &EscapeSettings,
    max_period: usize,
    tol: f64,
    mut advance: impl FnMut(&mut [Copy<N>], u64) -> Advanced<N>,
) -> EscapeOutcome<N> {
    let max_period = max_period.max(1);
    let keep = (3 * max_period).max(1);
    let mut all: Vec<Follow<N>> = copies_of(start, s.copies, s.perturbation)
        .into_iter()
        .map(|copy| Follow {
            copy,
            window: Vec::new(),
            offset: 0,
            settled: None,
            failed: false,
        })
        .collect();
    let block = ESCAPE_BLOCK.max(keep as u64);
    let mut done = 0u64;
    let mut escapes = 0u32;
    let mut rhs_evals = 0u64;
    while done < s.periods && escapes < s.stop_after.max(1) {
        let len = block.min(s.periods - done);
        let active: Vec<usize> = (0..all.len())
            .filter(|&i| all[i].settled.is_none() && !all[i].failed)
            .collect();
        if active.is_empty() {
            break;
        }
        let mut batch: Vec<Copy<N>> = active.iter().map(|&i| all[i].copy).collect();
        let (pts, evals) = advance(&mut batch, len);
        rhs_evals += evals;
        for ((&i, c), p) in active.iter().zip(batch).zip(pts) {
            let f = &mut all[i];
            let Some(p) = p else {
                f.failed = true;
                continue;
            };
            f.copy = c;
            f.window.extend(p);
            if let Some(period) = minimal_period_tol(&f.window, max_period, tol) {
                let since = settled_since(&f.window, period, tol);
                f.settled = Some((f.offset + since as u64, period));
                escapes += 1;
            } else if f.window.len() > keep {
                let cut = f.window.len() - keep;
                f.window.drain(..cut);
                f.offset += cut as u64;
            }
        }
        done += len;
    }
    let copies = all.iter().filter(|f| !f.failed).count() as u32;
    let escape_times: Vec<u64> = all.iter().filter_map(|f| f.settled.map(|e| e.0)).collect();
    // the clock starts when the copies have spread
    let times: Vec<f64> = escape_times
        .iter()
        .map(|&t| t.saturating_sub(s.spread) as f64)
        .collect();
    let lifetime = Lifetime::from_escapes(copies, &times, done.saturating_sub(s.spread) as f64);
    EscapeOutcome {
        copies,
        escape_times,
        periods: done,
        lifetime,
        orbits: group_orbits(&all, tol),
        rhs_evals,
    }
}

/// The first index of `pts` from which every point repeats the one `n` before it within the
/// period test's tolerance, minus `n`: where the orbit was reached.
fn settled_since<const N: usize>(pts: &[[f64; N]], n: usize, rel_tol: f64) -> usize {
    let tol = rel_tol * scale(pts);
    let mut j = pts.len();
    while j > n {
        let d: f64 = (0..N)
            .map(|i| (pts[j - 1][i] - pts[j - 1 - n][i]).abs())
            .sum();
        if d > tol {
            break;
        }
        j -= 1;
    }
    j - n.min(j)
}

fn scale<const N: usize>(pts: &[[f64; N]]) -> f64 {
    1.0 + pts
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()))
}

/// The settled copies grouped by orbit: two copies share one when they have the same period and
/// every point of one lies within ten times the period test's tolerance of a point of the other
/// (they reached it within that tolerance, possibly at another phase of it).
fn group_orbits<const N: usize>(all: &[Follow<N>], tol: f64) -> Vec<Settled<N>> {
    let mut out: Vec<Settled<N>> = Vec::new();
    let mut order: Vec<&Follow<N>> = all.iter().filter(|f| f.settled.is_some()).collect();
    order.sort_by_key(|f| f.settled.map(|s| s.0));
    for f in order {
        let (time, period) = f.settled.expect("filtered");
        let points: Vec<[f64; N]> = f.window[f.window.len() - period..].to_vec();
        let near = |a: &[f64; N], b: &[f64; N], tol: f64| {
            (0..N).map(|i| (a[i] - b[i]).abs()).sum::<f64>() <= tol
        };
        let found = out.iter_mut().find(|g| {
            let t = 10.0 * tol * scale(&g.points).max(scale(&points));
            g.period == period
                && points
                    .iter()
                    .all(|p| g.points.iter().any(|q| near(p, q, t)))
        });
        match found {
            Some(g) => g.count += 1,
            None => out.push(Settled {
                period,
                count: 1,
                first: time,
                state: f.copy,
                followed: f.offset + f.window.len() as u64,
                points,
            }),
        }
    }
    // most copies first; among equals the earliest (the order they were found in)
    out.sort_by_key(|g| std::cmp::Reverse(g.count));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settled_since_finds_where_the_cycle_begins() {
        let mut pts: Vec<[f64; 1]> = (0..10).map(|j| [j as f64 * 0.37 % 1.0 + 5.0]).collect();
        pts.extend((0..12).map(|j| [(j % 2) as f64]));
        assert_eq!(settled_since(&pts, 2, 1e-9), 10);
    }

    #[test]
    fn copies_are_tiny_distinct_and_repeatable() {
        let start = Copy {
            t: 0.0,
            y: [1.0, -2.0],
            memory: 0.0,
        };
        let a = copies_of(start, 8, 1e-9);
        assert_eq!(a, copies_of(start, 8, 1e-9));
        assert_eq!(a[0], start);
        let norm = 5f64.sqrt();
        for c in &a[1..] {
            let d = ((c.y[0] - 1.0).powi(2) + (c.y[1] + 2.0).powi(2)).sqrt();
            assert!(d > 0.0 && d <= 1e-9 * (1.0 + norm) * (1.0 + 1e-12), "{d}");
        }
        assert_ne!(a[1].y, a[2].y);
    }
}
