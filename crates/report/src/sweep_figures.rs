//! The sweep diagram: one panel per section, points coloured by the displayed name of each run
//! (attractor label or class), and the TLE / force / P_ID / impact-force panels; its CSV files
//! hold every point drawn and every run.

use crate::classes;
use crate::runner::Ctx;
use crate::shared::{
    exact, fixed_color, g, safe, section_axis, POINTS_PER_RUN, POINTS_PER_RUN_MULTI,
};
use crate::Figure;
use anyhow::Result;
use geardyn_analysis::bifurcation::{Run, Section as Sec, TaskResult};
use geardyn_analysis::classify::Motion;
use geardyn_io::figure::RGBColor as PlotColor;
use geardyn_io::figure::{categorical, Layer, LegendEntry, Panel, Style, OTHER};
use geardyn_io::output::write_csv;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// What a sweep figure shows besides the sections.
#[derive(Clone, Debug, Default)]
pub struct SweepPanels {
    /// TLE panel (when computed).
    pub tle: bool,
    /// Maximum mesh force panel.
    pub max_force: bool,
    /// P_ID panel.
    pub p_id: bool,
    /// Impact-force record (largest impact force of every recorded excitation period).
    pub impact_force: bool,
}

/// How a label is described in legends: health and, for multi-cycle excitation, every period
/// in mesh cycles that runs of the label have (one label in revolutions can hold a 3 -> 6
/// mesh-cycle doubling).
fn legend_text(
    name: &str,
    healthy: bool,
    mesh_periods: &BTreeSet<usize>,
    periodic: bool,
) -> String {
    if !periodic {
        return name.to_string();
    }
    let mut s = name.to_string();
    if !mesh_periods.is_empty() {
        let list: Vec<String> = mesh_periods.iter().map(|m| m.to_string()).collect();
        let unit = if list == ["1"] {
            "mesh cycle"
        } else {
            "mesh cycles"
        };
        s.push_str(&format!(" ({} {unit})", list.join(", ")));
    }
    s.push_str(if healthy { ", healthy" } else { ", back side" });
    s
}

/// Points (value, y) by displayed name.
type ByName = BTreeMap<String, Vec<(f64, f64)>>;

/// The runs of a sweep sorted for drawing, by displayed name: their section points, the values
/// of the extra panels, the legend facts, and the rows of the CSV files.
#[derive(Default)]
struct Drawn {
    /// Section points per name and section.
    groups: BTreeMap<String, BTreeMap<Sec, Vec<(f64, f64)>>>,
    /// Runs per name.
    counts: HashMap<String, usize>,
    /// Per name: healthy, its periods in mesh cycles, periodic.
    info: HashMap<String, (bool, BTreeSet<usize>, bool)>,
    /// Per name: the runs that reached it after transient chaos (the escape test's verdict).
    transients: HashMap<String, usize>,
    /// Values of the extra panels (`tle`, `max_force`, `p_id`, `impact`) per name.
    extra: BTreeMap<&'static str, ByName>,
    /// Rows of `name_points.csv`.
    point_rows: Vec<Vec<String>>,
    /// Rows of `name_impact_force.csv`.
    impact_rows: Vec<Vec<String>>,
}

impl Drawn {
    /// Every run of `results`.
    fn of(results: &[TaskResult], sections: &[Sec], panels: &SweepPanels) -> Drawn {
        let mut d = Drawn::default();
        for r in results {
            for run in &r.runs {
                let nm = classes::name(run);
                *d.counts.entry(nm.clone()).or_default() += 1;
                if matches!(run.motion, Motion::TransientChaos { .. }) {
                    *d.transients.entry(nm.clone()).or_default() += 1;
                }
                let entry = d.info.entry(nm.clone()).or_insert((
                    run.healthy,
                    BTreeSet::new(),
                    run.motion.is_periodic(),
                ));
                entry
                    .1
                    .extend(run.mesh_period.filter(|_| run.motion.is_periodic()));
                d.add_sections(r, run, &nm, sections);
                d.add_extras(r, run, &nm, panels);
            }
        }
        d
    }

    /// The section points of one run (the last ones, at most a cap per run; a periodic orbit's
    /// points once each).
    fn add_sections(&mut self, r: &TaskResult, run: &Run, nm: &str, sections: &[Sec]) {
        let g_ = self.groups.entry(nm.to_string()).or_default();
        for &sec in sections {
            let mut pts: Vec<&(Sec, f64, f64)> = run.points.iter().filter(|p| p.0 == sec).collect();
            if run.motion.is_periodic() {
                // a periodic orbit repeats its points: keep each once
                let mut seen = std::collections::HashSet::new();
                pts.retain(|p| seen.insert((g(p.1), g(p.2))));
            }
            let cap = if r.runs.len() > 1 {
                POINTS_PER_RUN_MULTI
            } else {
                POINTS_PER_RUN
            };
            let keep = pts.len().min(cap);
            for &&(s, x, v) in pts.iter().skip(pts.len() - keep) {
                let y = if s == Sec::Strobe { x } else { v };
                g_.entry(sec).or_default().push((r.value, y));
                self.point_rows.push(vec![
                    exact(r.value),
                    r.task.branch_name().into(),
                    run.ic.to_string(),
                    s.name().into(),
                    g(x),
                    g(v),
                    nm.to_string(),
                ]);
            }
        }
    }

    /// A value of an extra panel.
    fn put(&mut self, k: &'static str, nm: &str, x: f64, y: f64) {
        self.extra
            .entry(k)
            .or_default()
            .entry(nm.to_string())
            .or_default()
            .push((x, y));
    }

    /// The TLE, force and P_ID values of one run, and its impact-force record when drawn.
    fn add_extras(&mut self, r: &TaskResult, run: &Run, nm: &str, panels: &SweepPanels) {
        let finite = [
            ("tle", run.tle.unwrap_or(f64::NAN)),
            ("max_force", run.max_force),
            ("p_id", run.p_id),
        ];
        for (k, y) in finite {
            if y.is_finite() {
                self.put(k, nm, r.value, y);
            }
        }
        if panels.impact_force {
            for (j, &fi) in run.impact_force_per_period.iter().enumerate() {
                if fi > 0.0 {
                    self.put("impact", nm, r.value, fi);
                }
                self.impact_rows.push(vec![
                    exact(r.value),
                    r.task.branch_name().into(),
                    run.ic.to_string(),
                    j.to_string(),
                    g(fi),
                ]);
            }
        }
    }

    /// The names in colour order (periodic labels by frequency, then the fixed classes), the
    /// colour of each and the legend.
    fn colours(&self) -> (Vec<String>, HashMap<String, PlotColor>, Vec<LegendEntry>) {
        let counts = &self.counts;
        let mut order: Vec<String> = counts.keys().cloned().collect();
        order.sort_by(|a, b| counts[b].cmp(&counts[a]).then(a.cmp(b)));
        let flat: ByName = order.iter().map(|n| (n.clone(), vec![])).collect();
        let colored = categorical(flat, &order, &fixed_color);
        let mut color_of: HashMap<String, PlotColor> =
            colored.iter().map(|(n, c, _)| (n.clone(), *c)).collect();
        for n in &order {
            color_of.entry(n.clone()).or_insert(OTHER);
        }
        let legend = colored
            .iter()
            .map(|(n, c, _)| {
                let empty = (false, BTreeSet::new(), false);
                let (h, mp, per) = self.info.get(n).unwrap_or(&empty);
                let k = self.transients.get(n).copied().unwrap_or(0);
                let after = match k {
                    0 => String::new(),
                    k => format!(", {k} after transient chaos"),
                };
                LegendEntry::dot(format!("{}{after}", legend_text(n, *h, mp, *per)), *c)
            })
            .collect();
        (order, color_of, legend)
    }

    /// The panels: one per section, then the extra panels asked for.
    fn panels(
        &self,
        sections: &[Sec],
        panels: &SweepPanels,
        order: &[String],
        color_of: &HashMap<String, PlotColor>,
    ) -> Vec<Panel> {
        let layers_of = |by_name: geardyn_io::figure::PointsOf, r: u32| -> Vec<Layer> {
            // draw the most frequent last so that it stays visible; sparse panels get larger
            // dots
            let total: usize = order
                .iter()
                .filter_map(|n| by_name(n))
                .map(|p| p.len())
                .sum();
            let r = if total < 20_000 { r.max(2) } else { r };
            // a periodic attractor is a few points per value: drawn larger than the points of a
            // chaotic band and over them, so that a coexisting orbit is not lost in the band
            let (bands, orbits): (Vec<&String>, Vec<&String>) =
                order.iter().rev().partition(|n| !periodic_name(n));
            bands
                .into_iter()
                .chain(orbits)
                .filter_map(|n| {
                    by_name(n).map(|pts| Layer {
                        points: pts,
                        style: Style::Dots(if periodic_name(n) { r + 2 } else { r }),
                        color: color_of[n],
                    })
                })
                .collect()
        };
        let mut fig_panels: Vec<Panel> = Vec::new();
        for &sec in sections {
            fig_panels.push(Panel {
                y_label: section_axis(sec).into(),
                layers: layers_of(
                    &|n| self.groups.get(n).and_then(|m| m.get(&sec)).cloned(),
                    1,
                ),
                ..Default::default()
            });
        }
        for (shown, k, label, zero) in [
            (
                panels.impact_force,
                "impact",
                "impact force per period",
                false,
            ),
            (panels.max_force, "max_force", "max mesh force", false),
            (panels.p_id, "p_id", "P_ID", false),
            (panels.tle, "tle", "TLE", true),
        ] {
            if let Some(m) = self.extra.get(k).filter(|_| shown) {
                fig_panels.push(Panel {
                    y_label: label.into(),
                    layers: layers_of(&|n| m.get(n).cloned(), 2),
                    hlines: if zero { vec![0.0] } else { vec![] },
                    weight: 0.7,
                    ..Default::default()
                });
            }
        }
        fig_panels
    }
}

/// `name_points.csv`, `name_runs.csv` and, with the impact-force panel,
/// `name_impact_force.csv`: the files of the diagram's data.
fn write_sweep_data(
    dir: &Path,
    name: &str,
    param: &str,
    results: &[TaskResult],
    panels: &SweepPanels,
    drawn: Drawn,
) -> Result<Vec<PathBuf>> {
    let pts_csv = dir.join(format!("{name}_points.csv"));
    write_csv(
        &pts_csv,
        &[param, "branch", "ic", "section", "x", "v", "label"],
        drawn.point_rows,
    )?;
    let runs_csv = dir.join(format!("{name}_runs.csv"));
    geardyn_io::schema::runs_table(param, results).write_csv(&runs_csv, g)?;
    let mut data = vec![pts_csv, runs_csv];
    if panels.impact_force {
        let p = dir.join(format!("{name}_impact_force.csv"));
        write_csv(
            &p,
            &[param, "branch", "ic", "period", "impact_force"],
            drawn.impact_rows,
        )?;
        data.push(p);
    }
    Ok(data)
}

/// The sweep diagram `dir/name.png|svg` with `name_points.csv` and `name_runs.csv` (and
/// `name_impact_force.csv`).
#[allow(clippy::too_many_arguments)]
pub fn sweep_figure(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    param: &str,
    results: &[TaskResult],
    sections: &[Sec],
    panels: &SweepPanels,
    title: &str,
    caption: &str,
) -> Result<Figure> {
    let name = &safe(name);
    let drawn = Drawn::of(results, sections, panels);
    let (order, color_of, legend) = drawn.colours();
    let stem = dir.join(name);
    let figure_panels = drawn.panels(sections, panels, &order, &color_of);
    geardyn_io::sweep_output::write_sweep_figure(
        &stem,
        title,
        param,
        results,
        figure_panels,
        legend,
        "motion",
    )?;
    let data = write_sweep_data(dir, name, param, results, panels, drawn)?;
    Ok(ctx.fig(&stem, &with_entry_note(caption, sections), &data))
}

/// Whether a layer's name is a periodic motion's label (not a class word or a branch).
fn periodic_name(n: &str) -> bool {
    n.chars().next().is_some_and(|c| c.is_ascii_digit())
}

/// What a panel at `x = ±D_d` holds besides crossings, appended to a caption that draws one.
const ENTRY_NOTE: &str = " The panels at ±D_d also hold the entries into contact where the backlash drops from D_s to D_d at a zone border and the contact surface passes x (x itself does not cross): there the velocity may have either sign. The n-p-q-r-s label counts them as crossings.";

/// `caption`, with [`ENTRY_NOTE`] when `sections` draw a panel at `±D_d`.
fn with_entry_note(caption: &str, sections: &[Sec]) -> String {
    if sections
        .iter()
        .any(|s| matches!(s, Sec::DdUp | Sec::DdDown))
    {
        format!("{caption}{ENTRY_NOTE}")
    } else {
        caption.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Labels are periodic names; class words and branches are not.
    #[test]
    fn periodic_layers_are_told_by_their_label() {
        assert!(periodic_name("1-40-40") && periodic_name("3-60-0"));
        assert!(!periodic_name("chaotic") && !periodic_name("sweep up") && !periodic_name(""));
    }

    /// A figure with a panel at ±D_d says why its velocities may have either sign; one without
    /// keeps its caption.
    #[test]
    fn a_d_d_panel_explains_its_entries() {
        assert!(with_entry_note("c.", &[Sec::Strobe, Sec::DdDown]).ends_with(ENTRY_NOTE));
        assert_eq!(with_entry_note("c.", &[Sec::Strobe, Sec::DsUp]), "c.");
    }

    #[test]
    fn a_legend_lists_every_mesh_period_of_a_label() {
        let m: BTreeSet<usize> = [6, 3].into_iter().collect();
        assert_eq!(
            legend_text("1-20-0", true, &m, true),
            "1-20-0 (3, 6 mesh cycles), healthy"
        );
        assert_eq!(
            legend_text("1-40-40", false, &BTreeSet::new(), true),
            "1-40-40, back side"
        );
        assert_eq!(legend_text("chaotic", false, &m, false), "chaotic");
        let one: BTreeSet<usize> = [1].into_iter().collect();
        assert_eq!(
            legend_text("1-0-0", true, &one, true),
            "1-0-0 (1 mesh cycle), healthy"
        );
    }
}
