//! Readings the seed texts leave open, as data.
//!
//! A seed's text often fixes a number only up to a reading: seed B's "damping ratio 0.07" is
//! `c = 2 zeta = 0.14` in its own nondimensionalization, or `c = 0.07` if the table's symbol is
//! taken literally; its backlash levels are the pair's (about 0.002 apart) or a nominal step.
//! Each such choice is an [`Axis`] with the text that makes it ambiguous; an
//! [`Interpretation`] picks one choice per axis. Studies that bear on an axis run their claims
//! under several interpretations; the headline claims use the reading the text states most
//! directly (not the one that reproduces best) and say so, the others stay in
//! `claims_by_interpretation.csv` and in the matrix on the page.

use crate::claims::Claim;
use crate::runner::{hdr, Ctx};
use crate::Table;
use anyhow::Result;
use std::path::Path;

/// One unstated or ambiguous reading of a seed text.
#[derive(Clone, Copy, Debug)]
pub struct Axis {
    /// Short name (`damping`).
    pub name: &'static str,
    /// Where the text is (`seed B 004 Table 3.2`).
    pub source: &'static str,
    /// The words that make it ambiguous.
    pub text: &'static str,
    /// The readings the text allows, the headline one first.
    pub choices: &'static [&'static str],
    /// Why the first choice is the headline one.
    pub why: &'static str,
}

/// One choice per axis (indices into [`Axis::choices`]; 0 is the headline reading).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Interpretation(pub Vec<usize>);

impl Interpretation {
    /// The headline reading of every axis.
    pub fn headline(axes: &[Axis]) -> Interpretation {
        Interpretation(vec![0; axes.len()])
    }

    /// The headline reading with `picks` (axis name, choice index) changed.
    pub fn with(axes: &[Axis], picks: &[(&str, usize)]) -> Interpretation {
        let mut v = vec![0; axes.len()];
        for (name, i) in picks {
            if let Some(a) = axes.iter().position(|a| a.name == *name) {
                v[a] = (*i).min(axes[a].choices.len() - 1);
            }
        }
        Interpretation(v)
    }

    /// Choice index of axis `name` (0 when the axis is not listed).
    pub fn pick(&self, axes: &[Axis], name: &str) -> usize {
        axes.iter()
            .position(|a| a.name == name)
            .map_or(0, |a| self.0[a])
    }

    /// `damping: c = 2 zeta = 0.14; backlash: ...` (every axis).
    pub fn label(&self, axes: &[Axis]) -> String {
        axes.iter()
            .zip(&self.0)
            .map(|(a, &i)| format!("{}: {}", a.name, a.choices[i]))
            .collect::<Vec<_>>()
            .join("; ")
    }

    /// The axes that differ from the headline reading, or `headline` (a short column name).
    pub fn short(&self, axes: &[Axis]) -> String {
        let d: Vec<String> = axes
            .iter()
            .zip(&self.0)
            .filter(|(_, &i)| i != 0)
            .map(|(a, &i)| a.choices[i].to_string())
            .collect();
        if d.is_empty() {
            "headline".into()
        } else {
            d.join(" + ")
        }
    }
}

/// Sets the interpretation of every claim that has none.
pub fn label_claims(claims: &mut [Claim], label: &str) {
    for c in claims.iter_mut().filter(|c| c.interpretation.is_empty()) {
        c.interpretation = label.to_string();
    }
}

/// Rows of the table of axes: axis, source, text, readings, headline and why.
pub fn axis_rows(axes: &[Axis]) -> Vec<Vec<String>> {
    axes.iter()
        .map(|a| {
            vec![
                a.name.to_string(),
                a.source.to_string(),
                a.text.to_string(),
                a.choices.join(" | "),
                a.choices[0].to_string(),
                a.why.to_string(),
            ]
        })
        .collect()
}

/// Header of [`axis_rows`].
pub const AXIS_HEADER: [&str; 6] = ["axis", "source", "text", "readings", "headline", "why"];

/// The table of a seed's axes (`readings.csv` in the study folder `dir`).
pub fn axes_table(ctx: &Ctx, dir: &Path, axes: &[Axis]) -> Result<Table> {
    ctx.table(
        &dir.join("readings.csv"),
        "Readings the text leaves open (the headline reading first)",
        &hdr(&AXIS_HEADER),
        axis_rows(axes),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    const AXES: [Axis; 2] = [
        Axis {
            name: "damping",
            source: "s",
            text: "t",
            choices: &["c = 2 zeta", "c = zeta"],
            why: "w",
        },
        Axis {
            name: "backlash",
            source: "s",
            text: "t",
            choices: &["physical", "nominal"],
            why: "w",
        },
    ];

    #[test]
    fn interpretations_name_every_axis_and_the_changed_ones() {
        let h = Interpretation::headline(&AXES);
        assert_eq!(h.0, vec![0, 0]);
        assert_eq!(h.short(&AXES), "headline");
        let i = Interpretation::with(&AXES, &[("backlash", 1), ("nope", 1)]);
        assert_eq!(i.0, vec![0, 1]);
        assert_eq!(i.pick(&AXES, "backlash"), 1);
        assert_eq!(i.short(&AXES), "nominal");
        assert_eq!(i.label(&AXES), "damping: c = 2 zeta; backlash: nominal");
        // an index past the choices is clamped, not a panic
        assert_eq!(Interpretation::with(&AXES, &[("damping", 9)]).0, vec![1, 0]);
    }
}
