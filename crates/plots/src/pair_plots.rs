//! Figures of a physical gear pair along the excitation period: mesh stiffness (healthy and
//! broken), pair stiffness, load sharing, friction factors, half backlash and lubrication.
//! Captions describe the pair shown (a broken pair, or a healthy one).

use crate::figure::{
    palette, write_figure, Figure, FigureError, Layer, LegendEntry, Panel, Style, BROKEN_PAIR,
    HEALTHY_PAIR,
};
use geardyn_physics::PairModel;
use std::path::{Path, PathBuf};

fn line(points: Vec<(f64, f64)>, k: usize) -> Layer {
    Layer {
        points,
        style: Style::Line(2),
        color: palette(k),
    }
}

/// Rows of a pair table as a polyline broken where a pair is out of mesh (value `None`).
fn broken_line(rows: &[(f64, Option<f64>)], lo: f64, hi: f64) -> Vec<(f64, f64)> {
    rows.iter()
        .filter(|r| r.0 >= lo && r.0 <= hi)
        .map(|&(x, v)| (x, v.unwrap_or(f64::NAN)))
        .collect()
}

/// Writes the pair's figures into `dir`; returns `(stem, caption)` of each. `healthy` is the
/// same pair without breakage; `(dd, ds)` the dimensionless half backlash of the two zones;
/// `context` (e.g. the preset and operating point) ends each title when not empty.
pub fn pair_figures(
    dir: &Path,
    pm: &PairModel,
    healthy: &PairModel,
    dd: f64,
    ds: f64,
    context: &str,
) -> Result<Vec<(PathBuf, String)>, FigureError> {
    let broken = pm.eps_b.is_some();
    let cycles = pm.cycles as f64;
    let hk: Vec<(f64, f64)> = (0..pm.cycles)
        .flat_map(|c| {
            healthy
                .rows
                .iter()
                .map(move |r| (c as f64 + r.position, r.k_mesh / 1e6))
        })
        .collect();
    let bk: Vec<(f64, f64)> = pm
        .rows
        .iter()
        .map(|r| (r.position, r.k_mesh / 1e6))
        .collect();
    let nb = pm.spec.breakage.map_or(0, |b| b.broken_cycle) as f64;
    let (lo, hi) = if broken && pm.cycles > 3 {
        ((nb - 1.0).max(0.0), (nb + 2.0).min(cycles))
    } else {
        // (a one-cycle model is drawn repeated over two cycles, as its caption says)
        (0.0, if pm.cycles == 1 { 2.0 } else { cycles.min(2.0) })
    };
    let figures = PairFigures {
        dir,
        pm,
        context,
        broken,
        hk,
        bk,
        nb,
        lo,
        hi,
    };
    let mut figs = vec![figures.mesh_stiffness()?];
    if broken && pm.cycles > 3 {
        figs.push(figures.broken_cycle()?);
    }
    figs.push(figures.sharing_friction(dd, ds)?);
    if pm.rows.iter().any(|r| r.regime1 >= 0) {
        figs.push(figures.lubrication()?);
    }
    Ok(figs)
}

/// What the figures of [`pair_figures`] share.
struct PairFigures<'a> {
    dir: &'a Path,
    pm: &'a PairModel,
    context: &'a str,
    broken: bool,
    /// Mesh stiffness (N/µm) of the healthy pair over the revolution.
    hk: Vec<(f64, f64)>,
    /// Mesh stiffness (N/µm) of the pair shown.
    bk: Vec<(f64, f64)>,
    /// The chipped tooth's cycle (0 without breakage).
    nb: f64,
    /// Window of the detail figures (mesh cycles).
    lo: f64,
    hi: f64,
}

impl PairFigures<'_> {
    /// Writes `fig` as `name` in the folder; its stem and caption.
    fn written(
        &self,
        name: &str,
        fig: Figure,
        caption: String,
    ) -> Result<(PathBuf, String), FigureError> {
        let stem = self.dir.join(name);
        write_figure(&stem, &fig)?;
        Ok((stem, caption))
    }

    /// A title, ended by the context when there is one.
    fn titled(&self, t: &str) -> String {
        if self.context.is_empty() {
            t.to_string()
        } else {
            format!("{t}: {}", self.context)
        }
    }

    /// A column of the pair's table over the window, the healthy pair over two cycles when the
    /// model has one cycle.
    fn two(
        &self,
        v: &dyn Fn(&geardyn_physics::pair::StiffnessRow) -> Option<f64>,
    ) -> Vec<(f64, f64)> {
        let reps = if self.pm.cycles == 1 { 2 } else { 1 };
        let rows: Vec<(f64, Option<f64>)> = (0..reps)
            .flat_map(|c| {
                self.pm
                    .rows
                    .iter()
                    .map(move |r| (c as f64 + r.position, v(r)))
            })
            .collect();
        broken_line(&rows, self.lo, self.hi)
    }

    /// Mesh stiffness over the revolution (healthy and broken) or the mesh cycle.
    fn mesh_stiffness(&self) -> Result<(PathBuf, String), FigureError> {
        let mut layers = vec![line(self.hk.clone(), 0)];
        let mut legend = vec![LegendEntry::line(
            if self.broken { "healthy pair" } else { "mesh" },
            palette(0),
        )];
        if self.broken {
            layers.push(line(self.bk.clone(), 1));
            legend.push(LegendEntry::line("broken pair", palette(1)));
        }
        self.written(
            "mesh_stiffness",
            Figure {
                title: self.titled(if self.broken {
                    "Mesh stiffness over one pinion revolution, healthy and broken pair"
                } else {
                    "Mesh stiffness over the mesh cycle"
                }),
                x_label: "position (mesh cycles)".into(),
                x_range: Some((0.0, self.pm.cycles as f64)),
                panels: vec![Panel {
                    y_label: "k_m (N/µm)".into(),
                    layers,
                    ..Default::default()
                }],
                legend,
                ..Default::default()
            },
            if self.broken {
                format!(
                    "Mesh stiffness k_m (N/µm) over the {} mesh cycles of a pinion revolution, healthy and broken pair; the chipped tooth's cycle is cycle {}.",
                    self.pm.cycles,
                    self.pm.spec.breakage.map_or(0, |b| b.broken_cycle)
                )
            } else {
                "Mesh stiffness k_m (N/µm) over one mesh cycle: double-tooth zone, then single-tooth zone.".into()
            },
        )
    }

    /// The revolution shows the chipped tooth's cycle one in 40: the same curves around it.
    fn broken_cycle(&self) -> Result<(PathBuf, String), FigureError> {
        let window = |pts: &[(f64, f64)]| -> Vec<(f64, f64)> {
            pts.iter()
                .copied()
                .filter(|p| p.0 >= self.lo && p.0 <= self.hi)
                .collect()
        };
        self.written(
            "mesh_stiffness_broken_cycle",
            Figure {
                title: self.titled("Mesh stiffness around the chipped tooth's cycle"),
                x_label: "position (mesh cycles)".into(),
                x_range: Some((self.lo, self.hi)),
                panels: vec![Panel {
                    y_label: "k_m (N/µm)".into(),
                    layers: vec![
                        line(window(&self.hk), HEALTHY_PAIR),
                        line(window(&self.bk), BROKEN_PAIR),
                    ],
                    ..Default::default()
                }],
                legend: vec![
                    LegendEntry::line("healthy pair", palette(HEALTHY_PAIR)),
                    LegendEntry::line("broken pair", palette(BROKEN_PAIR)),
                ],
                ..Default::default()
            },
            format!(
                "Mesh stiffness k_m (N/µm) over cycles {}–{} of the revolution, healthy and broken pair: the chipped tooth (cycle {}) leaves mesh early, so the double-tooth zone of its cycle ends {:.3} cycles after the cycle starts instead of {:.3} (eps_b - 1 against eps - 1) and the single-tooth stiffness takes over sooner.",
                self.lo,
                self.hi,
                self.nb,
                self.pm.eps_b.unwrap_or(self.pm.geom.eps) - 1.0,
                self.pm.geom.eps - 1.0
            ),
        )
    }

    /// Pair stiffness, load sharing, friction factors and half backlash over the window.
    fn sharing_friction(&self, dd: f64, ds: f64) -> Result<(PathBuf, String), FigureError> {
        let k1 = self.two(&|r| Some(r.k_pair1 / 1e6));
        let k2 = self.two(&|r| (r.k_pair2 > 0.0).then_some(r.k_pair2 / 1e6));
        let km = self.two(&|r| Some(r.k_mesh / 1e6));
        let l1 = self.two(&|r| Some(r.share1));
        let l2 = self.two(&|r| (r.k_pair2 > 0.0).then_some(r.share2));
        let hd = self.two(&|r| Some(r.h_drive));
        let hb = self.two(&|r| Some(r.h_back));
        let dl = self.two(&|r| Some(if r.single { ds } else { dd }));
        // (the mesh stiffness in the colours of the other pair figures: the broken pair's, with its
        // healthy twin, or the first colour for a pair without breakage)
        let mesh_color = if self.broken { BROKEN_PAIR } else { 0 };
        let mut stiff_layers = vec![line(km, mesh_color), line(k1, 2), line(k2, 3)];
        let mut legend = vec![
            LegendEntry::line(
                if self.broken {
                    "mesh (broken pair)"
                } else {
                    "mesh"
                },
                palette(mesh_color),
            ),
            LegendEntry::line("entering pair", palette(2)),
            LegendEntry::line("leaving pair", palette(3)),
            LegendEntry::line("h, drive side", palette(4)),
            LegendEntry::line("h, back side", palette(5)),
        ];
        if self.broken {
            let hkw: Vec<(f64, f64)> = self
                .hk
                .iter()
                .copied()
                .filter(|p| p.0 >= self.lo && p.0 <= self.hi)
                .collect();
            stiff_layers.insert(0, line(hkw, HEALTHY_PAIR));
            legend.insert(
                1,
                LegendEntry::line("mesh (healthy pair)", palette(HEALTHY_PAIR)),
            );
        }
        self.written(
            "pairs_sharing_friction",
            Figure {
                title: self
                    .titled("Pair stiffness, load sharing, friction factors and half backlash"),
                x_label: "position (mesh cycles)".into(),
                x_range: Some((self.lo, self.hi)),
                panels: vec![
                    Panel {
                        y_label: "stiffness (N/µm)".into(),
                        layers: stiff_layers,
                        ..Default::default()
                    },
                    Panel {
                        y_label: "load share".into(),
                        layers: vec![line(l1, 2), line(l2, 3)],
                        y_range: Some((-0.05, 1.05)),
                        weight: 0.8,
                        ..Default::default()
                    },
                    Panel {
                        y_label: "friction factor h".into(),
                        layers: vec![line(hd, 4), line(hb, 5)],
                        weight: 0.8,
                        ..Default::default()
                    },
                    Panel {
                        y_label: "half backlash D".into(),
                        layers: vec![Layer {
                            points: dl,
                            style: Style::Line(2),
                            color: crate::figure::CHAOTIC,
                        }],
                        weight: 0.6,
                        ..Default::default()
                    },
                ],
                legend,
                ..Default::default()
            },
            if self.broken {
                format!(
                    "Mesh cycles {}–{} around the broken cycle {}: stiffness of each pair and of the mesh (healthy and broken), load shares, friction factors h (drive and back side) and the dimensionless half backlash.",
                    self.lo, self.hi, self.nb
                )
            } else {
                "Two mesh cycles: stiffness of each pair and of the mesh, load shares, friction factors h (drive and back side) and the dimensionless half backlash D_d (double-tooth zone) / D_s (single-tooth zone).".into()
            },
        )
    }

    /// Multi-state lubrication: friction coefficients and the film parameter.
    fn lubrication(&self) -> Result<(PathBuf, String), FigureError> {
        let mu1 = self.two(&|r| Some(r.mu1));
        let mu2 = self.two(&|r| (r.k_pair2 > 0.0).then_some(r.mu2));
        let lam = self.two(&|r| Some(r.lambda1));
        self.written(
            "lubrication",
            Figure {
                title: self.titled(
                    "Lubrication along the cycle, friction coefficients and film parameter",
                ),
                x_label: "position (mesh cycles)".into(),
                x_range: Some((self.lo, self.hi)),
                panels: vec![
                    Panel {
                        y_label: "friction coefficient".into(),
                        layers: vec![line(mu1, 2), line(mu2, 3)],
                        ..Default::default()
                    },
                    Panel {
                        y_label: "Lambda (entering pair)".into(),
                        layers: vec![line(lam, 0)],
                        hlines: vec![1.0, 3.0],
                        ..Default::default()
                    },
                ],
                legend: vec![
                    LegendEntry::line("entering pair", palette(2)),
                    LegendEntry::line("leaving pair", palette(3)),
                    LegendEntry::line("Lambda", palette(0)),
                ],
                ..Default::default()
            },
            "Multi-state lubrication: friction coefficient of each pair (EHL for Lambda > 3, mixed for 1–3, boundary below 1; grey lines) and the film parameter Lambda = h_min/sigma of the entering pair.".into(),
        )
    }
}
