//! `geardyn signals` of a planetary stage (`--preset planetary`, or `--system FILE` with a held
//! ring): the ring transducer's signal and the sun torque over whole carrier revolutions, their
//! spectra in carrier orders, the mesh order and a faulted tooth's characteristic order
//! (`geardyn_analysis::stage_signals`). `--set stage.sun_chip=0.3` chips a sun tooth.

use crate::train::{with_model, TrainRun};
use anyhow::{anyhow, Result};
use geardyn_analysis::classify::{simulate_decided, Decide};
use geardyn_analysis::simulate::SimOptions;
use geardyn_analysis::stage_signals::{stage_signals, StageSignals, StageSignalsRequest};
use geardyn_io::figure::{palette, write_figure, Figure, Layer, Panel, Style};
use geardyn_io::output::write_text;
use geardyn_io::run_record;
use geardyn_train::dynamics::TrainModel;
use std::fmt::Write as _;
use std::path::Path;

/// Runs the stage's signals into `out`.
pub fn signals(t: &TrainRun, req: &StageSignalsRequest, out: &Path) -> Result<()> {
    let started = std::time::Instant::now();
    let (s, label) = with_model!(&t.spec, &t.op, |m| run(t, &m, req))?;
    let _lock = run_record::prepare_folder(out, "signals", None, false)?;
    t.write_record(out, "signals", &[], started)?;
    let mut csv = String::from("tau,carrier_revolutions,sensor,sun_torque\n");
    for j in 0..s.tau.len() {
        let _ = writeln!(
            csv,
            "{},{},{},{}",
            s.tau[j], s.carrier[j], s.sensor[j], s.sun_torque[j]
        );
    }
    write_text(&out.join("signals.csv"), &csv)?;
    let mut csv = String::from("carrier_order,sensor,sun_torque\n");
    for j in 0..s.orders.len() {
        let _ = writeln!(
            csv,
            "{},{},{}",
            s.orders[j], s.sensor_spectrum[j], s.sun_spectrum[j]
        );
    }
    write_text(&out.join("spectrum.csv"), &csv)?;
    let summary = serde_json::json!({
        "system": t.spec.name,
        "source": t.source,
        "operating_point": t.op,
        "carrier_revolutions": s.carrier_revolutions,
        "excitation_periods": s.periods,
        "planets": s.planets,
        "mesh_order": s.mesh_order,
        "fault": t.spec.fault,
        "fault_order": s.fault_order,
        "motion": label,
        "units": "forces in k_ref b_c (dimensionless), orders per carrier revolution",
    });
    write_text(
        &out.join("summary.json"),
        &serde_json::to_string_pretty(&summary)?,
    )?;
    spectrum_figure(t, &s, &label, &out.join("spectrum"))?;
    println!(
        "signals of {} ({label}): {} carrier revolutions; mesh order {:.4}{}; {}",
        t.spec.name,
        s.carrier_revolutions,
        s.mesh_order,
        s.fault_order
            .map_or(String::new(), |f| format!(", fault order {f:.4}")),
        out.display()
    );
    Ok(())
}

/// Decides the motion from rest (the model commands' defaults), then records from where the
/// decision ended, whole periods of the motion at a time.
fn run<const N: usize>(
    t: &TrainRun,
    m: &TrainModel<N>,
    req: &StageSignalsRequest,
) -> Result<(StageSignals, String)>
where
    TrainModel<N>: geardyn_analysis::engine::Engine<N>,
{
    let (res, summary, _) = simulate_decided(
        m,
        m.static_state(),
        &SimOptions::default(),
        Decide::default(),
    )?;
    let req = StageSignalsRequest {
        motion_periods: summary.period.max(1) as u64,
        ..*req
    };
    let s = stage_signals(&t.spec, m, res.final_state, &req).map_err(|e| anyhow!(e))?;
    Ok((s, summary.label))
}

/// Decibels below a spectrum's largest line (orders above 0), floored at [`FLOOR_DB`]: the
/// cancelled orders sit at rounding level, far below the lines.
const FLOOR_DB: f64 = -160.0;

fn spectrum_figure(t: &TrainRun, s: &StageSignals, label: &str, stem: &Path) -> Result<()> {
    let top = 3.2 * s.mesh_order;
    let layer = |a: &[f64], k: usize| {
        let peak = a
            .iter()
            .skip(1)
            .cloned()
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        Layer {
            points: s
                .orders
                .iter()
                .zip(a)
                .skip(1)
                .filter(|(o, _)| **o <= top)
                .map(|(o, a)| (*o, (20.0 * (a / peak).log10()).max(FLOOR_DB)))
                .collect(),
            style: Style::Line(1),
            color: palette(k),
        }
    };
    let title = match s.fault_order {
        Some(f) => format!(
            "{} ({label}): mesh order {:.2}, sun-tooth fault order {f:.2}",
            t.title_name(),
            s.mesh_order
        ),
        None => format!(
            "{} ({label}): mesh order {:.2}",
            t.title_name(),
            s.mesh_order
        ),
    };
    write_figure(
        stem,
        &Figure {
            title,
            x_label: "order (per carrier revolution)".into(),
            panels: vec![
                Panel {
                    y_label: "ring transducer (dB re its largest line)".into(),
                    layers: vec![layer(&s.sensor_spectrum, 0)],
                    ..Default::default()
                },
                Panel {
                    y_label: "sun torque (dB re its largest line)".into(),
                    layers: vec![layer(&s.sun_spectrum, 1)],
                    ..Default::default()
                },
            ],
            panel_height: 320,
            ..Default::default()
        },
    )?;
    Ok(())
}
