//! The decided classification of sweep runs, as every verdict of the report reads it.
//!
//! Each run carries its [`Motion`] (period test, then a significantly positive TLE, else
//! `unsettled`); nothing here parses label text to decide a class. [`tolerant`] removes isolated
//! values at bifurcation points: a single value whose class differs from both neighbours, which
//! agree with each other, takes their class for verdicts (the figures and tables still show it).

use geardyn_analysis::bifurcation::{Run, TaskResult};
use geardyn_analysis::classify::Motion;

/// Class of a run.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// Periodic with this period (excitation periods).
    Periodic(usize),
    /// Significantly positive TLE.
    Chaotic,
    /// TLE zero within its error, no period.
    Quasi,
    /// Not decided.
    Unsettled,
    /// Integration failed.
    Failed,
}

impl Class {
    /// The class of a run.
    pub fn of(run: &Run) -> Class {
        match &run.motion {
            Motion::Periodic { period } => Class::Periodic(*period),
            Motion::Chaotic { .. } => Class::Chaotic,
            // a claim reads the motion in the long run: transient chaos by the orbit it settles
            // on (its lifetime is `Pt::lifetime`)
            Motion::TransientChaos { period, .. } => Class::Periodic(*period),
            Motion::QuasiPeriodic { .. } => Class::Quasi,
            Motion::Unsettled { .. } => Class::Unsettled,
            // failed, diverged, or a class added later
            _ => Class::Failed,
        }
    }

    /// Periodic (in the long run)?
    pub fn periodic(&self) -> bool {
        matches!(self, Class::Periodic(_))
    }

    /// Period, if periodic.
    pub fn period(&self) -> Option<usize> {
        match self {
            Class::Periodic(p) => Some(*p),
            _ => None,
        }
    }
}

/// The name shown for a run: its `n-p-q-r-s` label when periodic, else the motion's word.
pub fn name(run: &Run) -> String {
    match &run.motion {
        Motion::Periodic { .. } | Motion::TransientChaos { .. } => run.label.clone(),
        m => m.word().to_string(),
    }
}

/// One run of a sweep, as the verdicts see it.
#[derive(Clone, Debug, PartialEq)]
pub struct Pt {
    /// Parameter value.
    pub value: f64,
    /// Decided class.
    pub class: Class,
    /// Displayed name (label or motion word).
    pub name: String,
    /// Back-side contact or impact.
    pub back: bool,
    /// Healthy (periodic, no back-side contact).
    pub healthy: bool,
    /// TLE, when computed.
    pub tle: Option<f64>,
    /// Period in mesh cycles (multi-cycle excitation).
    pub mesh_period: Option<usize>,
    /// Largest mesh force.
    pub max_force: f64,
    /// Smallest mesh force.
    pub min_force: f64,
    /// Mean lifetime on the chaotic set of a transient chaos (excitation periods) and its
    /// standard error.
    pub lifetime: Option<(f64, f64)>,
}

impl Pt {
    fn of(value: f64, run: &Run) -> Pt {
        Pt {
            value,
            class: Class::of(run),
            name: name(run),
            back: run.touches_back_side(),
            healthy: run.healthy && run.motion.is_periodic(),
            tle: run.tle,
            mesh_period: run.mesh_period,
            max_force: run.max_force,
            min_force: run.min_force,
            lifetime: match run.motion {
                Motion::TransientChaos {
                    lifetime,
                    lifetime_stderr,
                    ..
                } => Some((lifetime, lifetime_stderr)),
                _ => None,
            },
        }
    }
}

/// The runs of one branch (all initial states), sorted by value.
pub fn points(results: &[TaskResult], branch: u8) -> Vec<Pt> {
    let mut v: Vec<Pt> = results
        .iter()
        .filter(|r| r.task.branch == branch)
        .flat_map(|r| r.runs.iter().map(move |run| Pt::of(r.value, run)))
        .collect();
    v.sort_by(|a, b| a.value.total_cmp(&b.value));
    v
}

/// The first run of each value of one branch (fixed initial state), sorted by value.
pub fn first_points(results: &[TaskResult], branch: u8) -> Vec<Pt> {
    let mut v: Vec<Pt> = results
        .iter()
        .filter(|r| r.task.branch == branch && !r.runs.is_empty())
        .map(|r| Pt::of(r.value, &r.runs[0]))
        .collect();
    v.sort_by(|a, b| a.value.total_cmp(&b.value));
    v
}

/// The runs of a fixed-initial-state sweep, sorted by value.
pub fn fixed_points(results: &[TaskResult]) -> Vec<Pt> {
    first_points(results, 0)
}

/// The same points with isolated classes replaced by their neighbours' (see the module doc).
/// The name of a replaced point becomes the left neighbour's. Only a value inside a stretch of
/// its neighbours' class is replaced: in an alternating stretch (chaotic, periodic, chaotic,
/// periodic) no value is isolated, and replacing each from the original neighbours would swap
/// the classes instead of removing one.
pub fn tolerant(pts: &[Pt]) -> Vec<Pt> {
    let mut out = pts.to_vec();
    for i in 1..pts.len().saturating_sub(1) {
        let (a, b, c) = (&pts[i - 1], &pts[i], &pts[i + 1]);
        // a neighbour that is itself isolated (the value beyond it has b's class) is no stretch
        let alternating = (i >= 2 && pts[i - 2].class == b.class)
            || (i + 2 < pts.len() && pts[i + 2].class == b.class);
        if a.class == c.class && b.class != a.class && !alternating {
            out[i].class = a.class.clone();
            out[i].name = a.name.clone();
            out[i].back = a.back && c.back;
        }
    }
    out
}

/// A run of consecutive values with the same displayed name and back-side flag.
#[derive(Clone, Debug, PartialEq)]
pub struct Interval {
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Name.
    pub name: String,
    /// Class.
    pub class: Class,
    /// Back-side contact at any of its values.
    pub back: bool,
    /// Number of values.
    pub count: usize,
    /// Period in mesh cycles (multi-cycle excitation: the clock of period doubling there).
    pub mesh_period: Option<usize>,
}

impl Interval {
    /// The period on the finest clock: in mesh cycles where an excitation period holds several
    /// (a 3 -> 6 mesh-cycle doubling inside one revolution is a doubling), else in excitation
    /// periods; `None` when not periodic.
    pub fn clock_period(&self) -> Option<usize> {
        self.class.period().map(|n| self.mesh_period.unwrap_or(n))
    }

    /// The name with the mesh-cycle period where there is one: `1-20-0 (3 mesh cycles)`.
    pub fn display(&self) -> String {
        match self.mesh_period {
            Some(1) if self.class.periodic() => format!("{} (1 mesh cycle)", self.name),
            Some(m) if self.class.periodic() => format!("{} ({m} mesh cycles)", self.name),
            _ => self.name.clone(),
        }
    }
}

/// Whether two neighbouring periodic intervals differ by a period doubling on the finest clock
/// ([`Interval::clock_period`]).
pub fn has_doubling(iv: &[Interval]) -> bool {
    iv.windows(2).any(|w| {
        matches!((w[0].clock_period(), w[1].clock_period()), (Some(a), Some(b)) if a == 2 * b || b == 2 * a)
    })
}

/// Intervals of equal name (and mesh-cycle period) along sorted points (one point per value).
pub fn intervals(pts: &[Pt]) -> Vec<Interval> {
    let mut out: Vec<Interval> = Vec::new();
    for p in pts {
        match out.last_mut() {
            Some(l) if l.name == p.name && l.mesh_period == p.mesh_period => {
                l.to = p.value;
                l.back |= p.back;
                l.count += 1;
            }
            _ => out.push(Interval {
                from: p.value,
                to: p.value,
                name: p.name.clone(),
                class: p.class.clone(),
                back: p.back,
                count: 1,
                mesh_period: p.mesh_period,
            }),
        }
    }
    out
}

/// Maximal ranges `(first, last, count)` of consecutive values whose class satisfies `pred`.
pub fn ranges(pts: &[Pt], pred: impl Fn(&Pt) -> bool) -> Vec<(f64, f64, usize)> {
    let mut out: Vec<(f64, f64, usize)> = Vec::new();
    let mut open = false;
    for p in pts {
        if pred(p) {
            if open {
                if let Some(l) = out.last_mut() {
                    l.1 = p.value;
                    l.2 += 1;
                }
            } else {
                out.push((p.value, p.value, 1));
                open = true;
            }
        } else {
            open = false;
        }
    }
    out
}

/// Bands `(first, last, count, windows)` of values satisfying `pred` in which runs of at most
/// `max_gap` consecutive other values are kept as windows (`(first, last)` of each) instead of
/// ending the band: a chaotic band with narrow periodic windows is one band, as a dynamicist
/// reads a bifurcation diagram. `count` counts the values satisfying `pred`.
#[allow(clippy::type_complexity)]
pub fn bands(
    pts: &[Pt],
    pred: impl Fn(&Pt) -> bool,
    max_gap: usize,
) -> Vec<(f64, f64, usize, Vec<(f64, f64)>)> {
    let mut out: Vec<(f64, f64, usize, Vec<(f64, f64)>)> = Vec::new();
    let mut gap: Vec<f64> = Vec::new();
    for p in pts {
        if pred(p) {
            match out.last_mut() {
                Some(b) if gap.len() <= max_gap => {
                    if let (Some(&a), Some(&z)) = (gap.first(), gap.last()) {
                        b.3.push((a, z));
                    }
                    b.1 = p.value;
                    b.2 += 1;
                }
                _ => out.push((p.value, p.value, 1, Vec::new())),
            }
            gap.clear();
        } else {
            gap.push(p.value);
        }
    }
    out
}

/// Values whose verdict (label or class word) differs between two sweeps of the same values, `a`
/// and its twin `b` with another integrator and transient ([`crate::runner::twin_sim`]): next to
/// a crisis or a bifurcation the verdict there depends on how it was computed, so it is flagged
/// and not counted as decided.
pub fn fragile(a: &[Pt], b: &[Pt]) -> Vec<f64> {
    a.iter()
        .filter(|p| {
            b.iter()
                .find(|q| q.value == p.value)
                .is_some_and(|q| q.name != p.name)
        })
        .map(|p| p.value)
        .collect()
}

/// Points with values in `[lo, hi]`.
pub fn within(pts: &[Pt], lo: f64, hi: f64) -> Vec<&Pt> {
    pts.iter()
        .filter(|p| p.value >= lo - 1e-12 && p.value <= hi + 1e-12)
        .collect()
}

/// Share of `pts` satisfying `pred` (0 when empty).
pub fn share(pts: &[&Pt], pred: impl Fn(&Pt) -> bool) -> f64 {
    if pts.is_empty() {
        0.0
    } else {
        pts.iter().filter(|p| pred(p)).count() as f64 / pts.len() as f64
    }
}

/// Distinct names among points, in order of first appearance.
pub fn names(pts: &[&Pt]) -> Vec<String> {
    let mut v: Vec<String> = Vec::new();
    for p in pts {
        if !v.contains(&p.name) {
            v.push(p.name.clone());
        }
    }
    v
}

/// The distinct values of `pts` in `[lo, hi]`, in their order (neighbours deduplicated).
pub fn values_in(pts: &[Pt], lo: f64, hi: f64) -> Vec<f64> {
    let mut vals: Vec<f64> = pts
        .iter()
        .map(|p| p.value)
        .filter(|v| *v >= lo && *v <= hi)
        .collect();
    vals.dedup();
    vals
}

#[cfg(test)]
impl Pt {
    /// A point of `class` named `name` at `value`, nothing else set (for tests).
    pub(crate) fn at(value: f64, class: Class, name: &str) -> Pt {
        Pt {
            value,
            class,
            name: name.into(),
            back: false,
            healthy: false,
            tle: None,
            mesh_period: None,
            max_force: 0.0,
            min_force: 0.0,
            lifetime: None,
        }
    }

    /// [`Pt::at`] of a period 1 named `name`, or chaotic when `name` is `chaotic` (for tests).
    pub(crate) fn named(value: f64, name: &str) -> Pt {
        let class = if name == "chaotic" {
            Class::Chaotic
        } else {
            Class::Periodic(1)
        };
        Pt::at(value, class, name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(v: f64, c: Class) -> Pt {
        let name = format!("{c:?}");
        Pt::at(v, c, &name)
    }

    /// A value whose twin ends elsewhere is fragile; one missing from the twin is not judged.
    #[test]
    fn a_verdict_that_changes_with_the_integrator_is_fragile() {
        let a = [
            pt(0.1, Class::Chaotic),
            pt(0.2, Class::Periodic(1)),
            pt(0.3, Class::Chaotic),
        ];
        let b = [pt(0.1, Class::Periodic(1)), pt(0.2, Class::Periodic(1))];
        assert_eq!(fragile(&a, &b), vec![0.1]);
    }

    #[test]
    fn period_doubling_is_read_on_the_mesh_cycle_clock() {
        // one label in revolutions (period 1) whose mesh-cycle period doubles 3 -> 6: a doubling
        // that the excitation-period clock cannot see
        let at = |v: f64, m: Option<usize>| Pt {
            name: "1-20-0".into(),
            mesh_period: m,
            ..pt(v, Class::Periodic(1))
        };
        let iv = intervals(&[at(0.1, Some(3)), at(0.2, Some(3)), at(0.3, Some(6))]);
        assert_eq!(iv.len(), 2);
        assert_eq!(iv[1].display(), "1-20-0 (6 mesh cycles)");
        assert!(has_doubling(&iv));
        // 3 -> 5 mesh cycles is no doubling; without a mesh clock the excitation periods count
        let iv = intervals(&[at(0.1, Some(3)), at(0.2, Some(5))]);
        assert!(!has_doubling(&iv));
        let iv = intervals(&[pt(0.1, Class::Periodic(1)), pt(0.2, Class::Periodic(2))]);
        assert!(has_doubling(&iv));
        let iv = intervals(&[pt(0.1, Class::Periodic(2)), pt(0.2, Class::Chaotic)]);
        assert!(!has_doubling(&iv));
    }

    #[test]
    fn an_isolated_value_at_a_bifurcation_takes_its_neighbours_class() {
        let p = vec![
            pt(0.0, Class::Periodic(1)),
            pt(0.1, Class::Chaotic),
            pt(0.2, Class::Periodic(1)),
            pt(0.3, Class::Periodic(1)),
            pt(0.4, Class::Chaotic),
            pt(0.5, Class::Chaotic),
        ];
        let t = tolerant(&p);
        assert_eq!(t[1].class, Class::Periodic(1));
        assert_eq!(t[4].class, Class::Chaotic);
        let ch = ranges(&t, |p| p.class == Class::Chaotic);
        assert_eq!(ch, vec![(0.4, 0.5, 2)]);
        assert_eq!(intervals(&t).len(), 2);
    }

    #[test]
    fn an_alternating_stretch_is_left_as_it_is() {
        // (the audit's case: chaotic, periodic, chaotic, periodic, periodic had become chaotic,
        // chaotic, periodic, periodic, periodic — the classes swapped, not smoothed)
        let c = [
            Class::Chaotic,
            Class::Periodic(1),
            Class::Chaotic,
            Class::Periodic(1),
            Class::Periodic(1),
        ];
        let p: Vec<Pt> = c
            .iter()
            .enumerate()
            .map(|(i, c)| pt(i as f64, c.clone()))
            .collect();
        let t = tolerant(&p);
        for (a, b) in p.iter().zip(&t) {
            assert_eq!(a.class, b.class);
        }
    }
}
