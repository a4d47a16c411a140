//! A claim about the motion at a parameter value judged over every attractor the report finds
//! there, not only from rest: the runs of a multi-initial sweep (several random initial states per
//! value, one decided motion each), grouped by the motion they reach, each with its share of the
//! initial states (a coarse basin share: the initial states are uniform in the attractor region).
//!
//! A motion is named by its label (`1-40-40`) or class word (`chaotic`); two attractors of one
//! label at one value count as one here (the basin studies tell them apart by their points).

use crate::classes::Pt;
use crate::readings::{f, pct};

/// One motion reached at one value.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    /// Parameter value.
    pub value: f64,
    /// Label or class word.
    pub name: String,
    /// Share of the value's initial states that reach it, in [0, 1].
    pub share: f64,
    /// Periodic (its name a label).
    pub periodic: bool,
    /// With back-side contact or impact.
    pub back: bool,
    /// Largest mesh force over its runs (dimensionless).
    pub max_force: f64,
}

/// The motions reached at each value of `pts` (one point per run, as
/// [`crate::classes::points`] gives a multi-initial sweep; [`crate::classes::within`] a range of it), in order of value, then of share
/// (largest first).
pub fn found(pts: &[&Pt]) -> Vec<Found> {
    let mut values: Vec<f64> = pts.iter().map(|p| p.value).collect();
    values.sort_by(f64::total_cmp);
    values.dedup();
    let mut out = Vec::new();
    for v in values {
        let at: Vec<&Pt> = pts.iter().copied().filter(|p| p.value == v).collect();
        let mut here: Vec<Found> = Vec::new();
        for p in &at {
            match here.iter_mut().find(|a| a.name == p.name) {
                Some(a) => {
                    a.share += 1.0;
                    a.back |= p.back;
                    a.max_force = a.max_force.max(p.max_force);
                }
                None => here.push(Found {
                    value: v,
                    name: p.name.clone(),
                    share: 1.0,
                    periodic: p.class.periodic(),
                    back: p.back,
                    max_force: p.max_force,
                }),
            }
        }
        for a in &mut here {
            a.share /= at.len() as f64;
        }
        here.sort_by(|a, b| b.share.total_cmp(&a.share).then(a.name.cmp(&b.name)));
        out.extend(here);
    }
    out
}

/// The motions of `found` that satisfy `pred`, by name, each with the values (and shares) where
/// it is reached: `1-40-40 at F = 0.11 (25 %), 0.14 (12 %); chaotic at F = 0.12 (12 %)`, at most
/// `most` values per motion (then `…`). Empty when none does.
pub fn describe(
    found: &[Found],
    pred: impl Fn(&Found) -> bool,
    param: &str,
    most: usize,
) -> String {
    let mut names: Vec<&str> = Vec::new();
    for a in found.iter().filter(|a| pred(a)) {
        if !names.contains(&a.name.as_str()) {
            names.push(&a.name);
        }
    }
    names
        .iter()
        .map(|n| {
            let at: Vec<&Found> = found.iter().filter(|a| a.name == *n && pred(a)).collect();
            let mut s: Vec<String> = at
                .iter()
                .take(most)
                .map(|a| format!("{} ({})", f(a.value), pct(a.share)))
                .collect();
            if at.len() > most {
                s.push("…".into());
            }
            format!("{n} at {param} = {}", s.join(", "))
        })
        .collect::<Vec<_>>()
        .join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(value: f64, name: &str, back: bool, max_force: f64) -> Pt {
        Pt {
            back,
            healthy: !back,
            max_force,
            ..Pt::named(value, name)
        }
    }

    /// Four initial states at one load: three reach the healthy orbit, one the rattle; the
    /// shares are counted per motion and the rattle is named with its load and share.
    #[test]
    fn shares_are_per_motion_and_value() {
        let pts = [
            pt(0.12, "1-20-0", false, 1.2),
            pt(0.12, "1-40-40", true, 3.0),
            pt(0.12, "1-20-0", false, 1.25),
            pt(0.12, "1-20-0", false, 1.2),
            pt(0.14, "1-20-0", false, 1.3),
            pt(0.14, "1-20-0", false, 1.3),
        ];
        let fd = found(&pts.iter().collect::<Vec<_>>());
        assert_eq!(fd.len(), 3);
        assert_eq!((fd[0].name.as_str(), fd[0].share), ("1-20-0", 0.75));
        assert_eq!(fd[0].max_force, 1.25);
        assert_eq!(
            (fd[1].name.as_str(), fd[1].share, fd[1].back),
            ("1-40-40", 0.25, true)
        );
        assert_eq!((fd[2].value, fd[2].share), (0.14, 1.0));
        let d = describe(&fd, |a| a.back, "F", 3);
        assert_eq!(d, format!("1-40-40 at F = {} ({})", f(0.12), pct(0.25)));
        assert_eq!(describe(&fd, |a| a.name == "x", "F", 3), "");
    }
}
