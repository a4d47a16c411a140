//! Figures of `geardyn signals`: the spectra in orders with the mesh harmonics marked, and the
//! time-synchronous averages of the healthy twin and the broken pair over one pinion revolution.

use crate::figure::{
    palette, write_figure, Figure, FigureError, Layer, LegendEntry, Panel, Style, BROKEN_PAIR,
    HEALTHY_PAIR,
};
use geardyn_analysis::signals::{SignalsResult, SIGNAL_NAMES};
use std::path::Path;

/// Axis labels of the signals of [`SIGNAL_NAMES`].
const LABELS: [&str; 3] = ["DTE (µm)", "mesh force (N)", "acceleration (m/s²)"];

fn pair_color(pair: &str) -> usize {
    if pair == "broken" {
        BROKEN_PAIR
    } else {
        HEALTHY_PAIR
    }
}

/// Writes `spectrum.png/svg` (Welch amplitude over orders up to `max_harmonic` mesh harmonics,
/// one panel per signal, the mesh harmonics `k z1` as grey vertical lines) and `tsa.png/svg`
/// (the TSA of each signal over the pinion angle) into `dir`; `context` ends the titles.
pub fn signal_figures(
    dir: &Path,
    r: &SignalsResult,
    context: &str,
    max_harmonic: usize,
) -> Result<(), FigureError> {
    let z = r.options.mesh_order as f64;
    let top = (z * (max_harmonic as f64 + 0.5)).min(r.samples_per_rev as f64 / 2.0);
    let grey = plotters::style::RGBColor(170, 170, 170);
    let mut panels = Vec::new();
    for (k, label) in LABELS.iter().enumerate() {
        let mut layers = Vec::new();
        let mut peak = 0.0f64;
        for p in &r.pairs {
            let s = &p.spectra[k];
            let pts: Vec<(f64, f64)> = s
                .orders
                .iter()
                .zip(&s.amplitude)
                .filter(|(o, _)| **o > 0.0 && **o <= top)
                .map(|(o, a)| (*o, *a))
                .collect();
            peak = pts.iter().fold(peak, |m, p| m.max(p.1));
            layers.push(Layer {
                points: pts,
                style: Style::Line(if p.pair == "broken" { 1 } else { 2 }),
                color: palette(pair_color(&p.pair)),
            });
        }
        // the mesh harmonics: vertical segments, broken by NaN points
        let mut marks = Vec::new();
        let mut h = 1.0;
        while h * z <= top {
            marks.extend([(h * z, 0.0), (h * z, peak), (f64::NAN, f64::NAN)]);
            h += 1.0;
        }
        layers.insert(
            0,
            Layer {
                points: marks,
                style: Style::Line(1),
                color: grey,
            },
        );
        panels.push(Panel {
            y_label: label.to_string(),
            layers,
            ..Default::default()
        });
    }
    let mut legend: Vec<LegendEntry> = r
        .pairs
        .iter()
        .map(|p| LegendEntry::line(format!("{} pair", p.pair), palette(pair_color(&p.pair))))
        .collect();
    legend.push(LegendEntry::line(
        format!("mesh harmonics k·z1 (z1 = {})", r.options.mesh_order),
        grey,
    ));
    let titled = |t: &str| {
        if context.is_empty() {
            t.to_string()
        } else {
            format!("{t}: {context}")
        }
    };
    write_figure(
        &dir.join("spectrum"),
        &Figure {
            title: titled("Welch amplitude spectra in orders of the pinion revolution"),
            x_label: "order (cycles per pinion revolution)".into(),
            x_range: Some((0.0, top)),
            panels,
            legend: legend.clone(),
            legend_title: "pair".into(),
            ..Default::default()
        },
    )?;
    let spr = r.samples_per_rev;
    let mut panels = Vec::new();
    for (k, label) in LABELS.iter().enumerate() {
        let layers = r
            .pairs
            .iter()
            .map(|p| Layer {
                points: p.decompositions[k]
                    .tsa
                    .iter()
                    .enumerate()
                    .map(|(i, v)| ((i as f64 + 0.5) * 360.0 / spr as f64, *v))
                    .collect(),
                style: Style::Line(if p.pair == "broken" { 1 } else { 2 }),
                color: palette(pair_color(&p.pair)),
            })
            .collect();
        panels.push(Panel {
            y_label: label.to_string(),
            layers,
            ..Default::default()
        });
    }
    legend.pop();
    write_figure(
        &dir.join("tsa"),
        &Figure {
            title: titled(&format!(
                "Time-synchronous averages over {} pinion revolutions",
                r.revolutions
            )),
            x_label: "pinion angle (degrees from tau0 + whole revolutions)".into(),
            x_range: Some((0.0, 360.0)),
            panels,
            legend,
            legend_title: "pair".into(),
            ..Default::default()
        },
    )?;
    debug_assert_eq!(SIGNAL_NAMES.len(), LABELS.len());
    Ok(())
}
