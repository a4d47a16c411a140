//! `geardyn response` of a gear train: the frequency response by two decided continuation
//! sweeps over one operating parameter, upward and downward (each value from the final state of
//! the one before), with per mesh its label and dynamic force range (peak to peak), the jumps of
//! each sweep (the pair's rule, [`jump_steps`], on the first mesh's force range) and the values
//! where the two sweeps end on different motions (coexistence: a hysteresis loop).

use crate::bifurcation::ResponseArgs;
use crate::sweep::parse_range;
use crate::train::{check_work, sim_options, with_model, Swept, TrainRun};
use anyhow::{bail, Result};
use geardyn_analysis::bifurcation::jump_steps;
use geardyn_analysis::classify::Decide;
use geardyn_analysis::engine::Engine;
use geardyn_analysis::generic::{decided_sweep, DecidedPoint, Family};
use geardyn_analysis::simulate::SimOptions;
use geardyn_io::figure::{palette, write_figure, Figure, Layer, LegendEntry, Panel, Style};
use geardyn_io::output::{write_json, write_text};
use geardyn_io::run_record;
use geardyn_train::dynamics::{TrainModel, TrainOperating};
use std::fmt::Write as _;

/// Two sweeps differ at a value when their labels differ, or both are periodic and their first
/// mesh's force ranges differ by more than this share of the largest range.
const COEXIST: f64 = 0.01;

/// `geardyn response --preset planetary|two-stage|pair` or `--system FILE`.
pub fn response(t: &TrainRun, a: &ResponseArgs) -> Result<()> {
    let param = a.param.as_str();
    if !TrainOperating::FIELDS.contains(&param) {
        bail!(
            "--param {param}: a train sweeps one of {}",
            TrainOperating::FIELDS.join(", ")
        );
    }
    t.check_stiffness_form(&[param])?;
    let values = parse_range(&a.range)?;
    for &v in &values {
        let mut op = t.op;
        op.set(param, v)
            .map_err(|e| anyhow::anyhow!("--range: {e}"))?;
    }
    let (opts, cap) = sim_options(&a.run.sim)?;
    let fam = Swept {
        spec: &t.spec,
        op: t.op,
        param,
    };
    with_model!(&t.spec, &t.op, |m| {
        check_work(&m, &opts, 2 * values.len(), cap)?;
        response_model(t, &fam, &m, &values, &opts, a)
    })
}

/// The first mesh's dynamic force range (peak to peak) of a decided point; NaN without a result.
fn range0<const N: usize>(p: &DecidedPoint<N>) -> f64 {
    p.summary.as_ref().map_or(f64::NAN, |s| {
        s.meshes
            .first()
            .map_or(s.max_force - s.min_force, |m| m.max_force - m.min_force)
    })
}

fn response_model<const N: usize>(
    t: &TrainRun,
    fam: &Swept<'_>,
    // (fixes the state dimension)
    _first: &TrainModel<N>,
    values: &[f64],
    opts: &SimOptions,
    a: &ResponseArgs,
) -> Result<()>
where
    for<'b> Swept<'b>: Family<N, System = TrainModel<N>>,
    TrainModel<N>: Engine<N>,
{
    let started = std::time::Instant::now();
    let param = fam.param;
    let _lock = run_record::prepare_folder(&a.out, "response", None, false)?;
    let start = |v: f64| <Swept<'_> as Family<N>>::at(fam, v).static_state();
    let up = decided_sweep(fam, values, start(values[0]), opts, Decide::default(), true);
    let down_values: Vec<f64> = values.iter().rev().copied().collect();
    let down = decided_sweep(
        fam,
        &down_values,
        start(down_values[0]),
        opts,
        Decide::default(),
        true,
    );
    let names: Vec<String> = t.spec.meshes.iter().map(|m| m.name.clone()).collect();
    let mut csv = format!("{param},sweep,class,label");
    for n in &names {
        let _ = write!(
            csv,
            ",\"label {n}\",\"max_force {n}\",\"min_force {n}\",\"force_range {n}\""
        );
    }
    csv += ",error\n";
    for (sweep, pts) in [("up", &up), ("down", &down)] {
        for p in pts.iter() {
            match &p.summary {
                None => {
                    let _ = writeln!(
                        csv,
                        "{},{sweep},failed,failed{},\"{}\"",
                        p.value,
                        ",,,,".repeat(names.len()),
                        p.error.as_ref().map_or(String::new(), |e| e.to_string())
                    );
                }
                Some(s) => {
                    let _ = write!(csv, "{},{sweep},{},{}", p.value, s.motion.word(), s.label);
                    for k in 0..names.len() {
                        let ms = s.meshes.get(k);
                        let (mx, mn) =
                            ms.map_or((s.max_force, s.min_force), |x| (x.max_force, x.min_force));
                        let _ = write!(
                            csv,
                            ",{},{mx},{mn},{}",
                            ms.map_or(s.label.as_str(), |x| x.label.as_str()),
                            mx - mn
                        );
                    }
                    csv += ",\n";
                }
            }
        }
    }
    write_text(&a.out.join("response.csv"), &csv)?;
    // jumps of each sweep, in the order it visited the values
    let mut jumps = Vec::new();
    for (sweep, pts) in [("up", &up), ("down", &down)] {
        let series: Vec<(f64, f64, usize)> = pts
            .iter()
            .filter(|p| p.summary.is_some())
            .map(|p| {
                (
                    p.value,
                    range0(p),
                    p.summary.as_ref().map_or(0, |s| s.period),
                )
            })
            .collect();
        for i in jump_steps(&series) {
            jumps.push(serde_json::json!({
                "sweep": sweep,
                "from": series[i].0,
                "to": series[i + 1].0,
                "force_range_before": series[i].1,
                "force_range_after": series[i + 1].1,
            }));
        }
    }
    // values where the two sweeps end on different motions
    let largest = up
        .iter()
        .chain(&down)
        .map(range0)
        .filter(|r| r.is_finite())
        .fold(0.0, f64::max);
    let coexisting: Vec<f64> = up
        .iter()
        .zip(down.iter().rev())
        .filter(|(u, d)| {
            let labels = |p: &DecidedPoint<N>| p.summary.as_ref().map(|s| s.label.clone());
            // (two records of one chaotic motion differ in their extremes: not two motions)
            let periodic = |p: &DecidedPoint<N>| p.summary.as_ref().is_some_and(|s| s.period > 0);
            labels(u) != labels(d)
                || (periodic(u) && periodic(d) && (range0(u) - range0(d)).abs() > COEXIST * largest)
        })
        .map(|(u, _)| u.value)
        .collect();
    write_json(
        &a.out.join("jumps.json"),
        &serde_json::json!({ "jumps": jumps, "coexisting": coexisting, "mesh": names[0] }),
    )?;
    t.write_record(
        &a.out,
        "response",
        &[run_record::Swept::of(param, values)],
        started,
    )?;
    let series = |pts: &[DecidedPoint<N>]| -> Vec<(f64, f64)> {
        pts.iter()
            .map(|p| (p.value, range0(p)))
            .filter(|p| p.1.is_finite())
            .collect()
    };
    let mut down_sorted = series(&down);
    down_sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    write_figure(
        &a.out.join("response"),
        &Figure {
            title: format!(
                "Response over {param}: {} ({}), {}",
                t.title_name(),
                t.source,
                t.op_text(&[param])
            ),
            x_label: param.into(),
            panels: vec![Panel {
                y_label: format!("force range of {} (peak to peak)", names[0]),
                layers: vec![
                    Layer {
                        points: series(&up),
                        style: Style::Line(2),
                        color: palette(0),
                    },
                    Layer {
                        points: down_sorted,
                        style: Style::Dots(3),
                        color: palette(1),
                    },
                ],
                ..Default::default()
            }],
            legend: vec![
                LegendEntry::line("upward sweep", palette(0)),
                LegendEntry::dot("downward sweep", palette(1)),
            ],
            panel_height: 420,
            ..Default::default()
        },
    )?;
    for j in &jumps {
        println!(
            "jump on the {} sweep between {param} = {} and {}: force range of {} {:.4} -> {:.4}",
            j["sweep"].as_str().unwrap_or(""),
            j["from"],
            j["to"],
            names[0],
            j["force_range_before"].as_f64().unwrap_or(f64::NAN),
            j["force_range_after"].as_f64().unwrap_or(f64::NAN)
        );
    }
    if !coexisting.is_empty() {
        println!(
            "the sweeps end on different motions at {} value(s) of {param} (coexisting motions) in [{}, {}]",
            coexisting.len(),
            coexisting.iter().copied().fold(f64::INFINITY, f64::min),
            coexisting.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        );
    }
    println!(
        "{}: {} values, both sweeps in {:.2} s -> {}",
        t.spec.name,
        values.len(),
        started.elapsed().as_secs_f64(),
        a.out.display()
    );
    Ok(())
}
