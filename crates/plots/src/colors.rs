//! Colours of figures: the fixed colours of the classes of motion, a palette of many distinct
//! colours, labels that keep their colour across the figures of a command, categorical groups
//! with a bounded legend, and a colour map.

use plotters::style::RGBColor;
use std::collections::BTreeMap;

/// Colour of chaotic motions.
pub const CHAOTIC: RGBColor = RGBColor(0, 0, 0);
/// Colour of quasi-periodic motions.
pub const QUASI: RGBColor = RGBColor(90, 90, 90);
/// Colour of undecided (unsettled) motions.
pub const UNSETTLED: RGBColor = RGBColor(175, 175, 175);
/// Colour of failed runs and of a remainder group ("N other labels"): a light brown, apart
/// from the greys of [`QUASI`] and [`UNSETTLED`] and from the [`palette`].
pub const OTHER: RGBColor = RGBColor(166, 118, 60);
/// Initial states that are no state of the model (behind a rigid back stop): near-white, so the
/// stop's edge reads as the edge of the drawn basins.
pub const INADMISSIBLE: RGBColor = RGBColor(236, 236, 230);

/// Most entries of a categorical legend: beyond it the rarest labels are drawn as one group
/// "N other labels" in [`OTHER`].
pub const LEGEND_MAX: usize = 10;

const DISTINCT: [RGBColor; 24] = [
    // Okabe–Ito (without black)
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(240, 228, 66),
    // then colours chosen to differ from those and from each other (after Kelly's list)
    RGBColor(135, 86, 146),
    RGBColor(190, 0, 50),
    RGBColor(128, 128, 0),
    RGBColor(194, 178, 128),
    RGBColor(0, 0, 128),
    RGBColor(0, 200, 200),
    RGBColor(249, 147, 121),
    RGBColor(150, 220, 100),
    RGBColor(255, 0, 255),
    RGBColor(179, 68, 108),
    RGBColor(70, 70, 200),
    RGBColor(136, 45, 23),
    RGBColor(141, 182, 0),
    RGBColor(200, 160, 255),
    RGBColor(0, 90, 50),
    RGBColor(255, 200, 150),
    RGBColor(160, 0, 200),
];

/// Number of distinct colours of [`palette`] before it repeats.
pub const DISTINCT_COLORS: usize = DISTINCT.len();

/// Palette index of the healthy pair in every figure that shows a pair and its broken twin.
pub const HEALTHY_PAIR: usize = 0;
/// Palette index of the broken pair in those figures.
pub const BROKEN_PAIR: usize = 1;

/// The `k`-th of [`DISTINCT_COLORS`] distinct colours (repeats after that; callers group the
/// rest as "other").
pub fn palette(k: usize) -> RGBColor {
    DISTINCT[k % DISTINCT.len()]
}

/// A named, coloured group of points.
pub type Group = (String, RGBColor, Vec<(f64, f64)>);

/// Colours keyed by label: a label gets a colour of [`palette`] the first time it is asked
/// for and keeps it, so that the figures of one command colour a label alike. Classes of
/// motion have their fixed colours ([`class_color`]).
#[derive(Clone, Debug, Default)]
pub struct LabelColors {
    assigned: BTreeMap<String, RGBColor>,
}

impl LabelColors {
    /// The colour of `label`, assigned now if it has none.
    pub fn color(&mut self, label: &str) -> RGBColor {
        if let Some(c) = class_color(label) {
            return c;
        }
        let next = self.assigned.len();
        *self
            .assigned
            .entry(label.to_string())
            .or_insert_with(|| palette(next))
    }

    /// The colour of `label` if it has one.
    pub fn get(&self, label: &str) -> Option<RGBColor> {
        class_color(label).or_else(|| self.assigned.get(label).copied())
    }
}

/// Fixed colours of the classes of motion that carry no label: chaotic black, quasi-periodic
/// dark grey, unsettled and "not periodic" grey, failed and diverged [`OTHER`].
pub fn class_color(name: &str) -> Option<RGBColor> {
    match name {
        "chaotic" => Some(CHAOTIC),
        "quasi-periodic" => Some(QUASI),
        "unsettled" | "not periodic" => Some(UNSETTLED),
        "failed" | "diverged" => Some(OTHER),
        _ => None,
    }
}

/// Groups of a categorical layer: `(name, points)` in the given order (names not in `order`
/// after, alphabetically), with their colours (`fixed`, else from `colors`). At most
/// [`LEGEND_MAX`] groups: beyond that, the fixed ones and the first others are kept and the rest
/// merged into one group "N other labels" in [`OTHER`].
pub fn categorical_keyed(
    groups: BTreeMap<String, Vec<(f64, f64)>>,
    order: &[String],
    fixed: &dyn Fn(&str) -> Option<RGBColor>,
    colors: &mut LabelColors,
) -> Vec<Group> {
    let mut named: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut groups = groups;
    for name in order {
        if let Some(p) = groups.remove(name) {
            named.push((name.clone(), p));
        }
    }
    named.extend(groups);
    let n_fixed = named.iter().filter(|(n, _)| fixed(n).is_some()).count();
    let free = if named.len() <= LEGEND_MAX {
        named.len()
    } else {
        (LEGEND_MAX - 1).saturating_sub(n_fixed)
    };
    let mut out = Vec::new();
    let mut other: Vec<(f64, f64)> = Vec::new();
    let mut others = 0;
    let mut k = 0;
    for (name, pts) in named {
        if let Some(c) = fixed(&name) {
            out.push((name, c, pts));
        } else if k < free {
            let c = colors.color(&name);
            out.push((name, c, pts));
            k += 1;
        } else {
            others += 1;
            other.extend(pts);
        }
    }
    if others > 0 {
        out.push((format!("{others} other labels"), OTHER, other));
    }
    out
}

/// [`categorical_keyed`] with colours of its own.
pub fn categorical(
    groups: BTreeMap<String, Vec<(f64, f64)>>,
    order: &[String],
    fixed: &dyn Fn(&str) -> Option<RGBColor>,
) -> Vec<Group> {
    categorical_keyed(groups, order, fixed, &mut LabelColors::default())
}

/// A perceptually ordered colour map (viridis, five stops, linear in between) for `t` in `[0, 1]`
/// (non-finite `t`: the low end).
pub fn colormap(t: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * 4.0;
    let i = (x as usize).min(3);
    let f = x - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let l = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    RGBColor(l(a.0, b.0), l(a.1, b.1), l(a.2, b.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Euclidean distance of two colours in RGB.
    fn distance(a: RGBColor, b: RGBColor) -> f64 {
        let s = |x: u8, y: u8| (x as f64 - y as f64).powi(2);
        (s(a.0, b.0) + s(a.1, b.1) + s(a.2, b.2)).sqrt()
    }

    #[test]
    fn palette_is_distinct() {
        for i in 0..DISTINCT_COLORS {
            for j in 0..i {
                assert!(distance(palette(i), palette(j)) > 50.0, "{i} {j}");
            }
            for fixed in [CHAOTIC, QUASI, UNSETTLED, OTHER] {
                assert!(distance(palette(i), fixed) > 50.0, "{i}");
            }
        }
    }

    #[test]
    fn other_is_not_a_grey() {
        // the remainder group must not be mistaken for unsettled runs
        assert!(distance(OTHER, UNSETTLED) > 100.0 && distance(OTHER, QUASI) > 80.0);
        let chroma = OTHER.0.max(OTHER.1).max(OTHER.2) - OTHER.0.min(OTHER.1).min(OTHER.2);
        assert!(chroma > 80);
    }

    #[test]
    fn labels_keep_their_colours_and_legends_stay_short() {
        let mut colors = LabelColors::default();
        let names: Vec<String> = (1..=15).map(|k| format!("P{k}")).collect();
        let mut groups: BTreeMap<String, Vec<(f64, f64)>> = names
            .iter()
            .map(|n| (n.clone(), vec![(0.0, 0.0)]))
            .collect();
        groups.insert("chaotic".into(), vec![(1.0, 1.0)]);
        let mut order = names.clone();
        order.insert(3, "chaotic".into());
        let g = categorical_keyed(groups, &order, &class_color, &mut colors);
        assert_eq!(g.len(), LEGEND_MAX);
        assert_eq!(g.last().unwrap().0, "7 other labels");
        assert_eq!(g.last().unwrap().1, OTHER);
        assert_eq!(g.last().unwrap().2.len(), 7);
        assert!(g.iter().any(|x| x.0 == "chaotic" && x.1 == CHAOTIC));
        // a second figure of the same command: the same colour for the same label
        let c3 = colors.get("P3").unwrap();
        let again: BTreeMap<String, Vec<(f64, f64)>> =
            [("P3".to_string(), vec![]), ("P9".to_string(), vec![])].into();
        let g2 = categorical_keyed(
            again,
            &["P9".into(), "P3".into()],
            &class_color,
            &mut colors,
        );
        assert_eq!(g2.iter().find(|x| x.0 == "P3").unwrap().1, c3);
        assert_ne!(g2[0].1, c3);
    }
}
