//! `geardyn signals` of a planetary stage (`--preset planetary`, or `--system FILE` with a held
//! ring): the ring transducer's signal and the sun torque over whole carrier revolutions, their
//! spectra in carrier orders, the mesh order and a faulted tooth's characteristic order
//! (`geardyn_analysis::stage_signals`). `--set stage.sun_chip=0.3` chips a sun tooth.

use crate::train::{with_model, TrainRun};
use anyhow::{anyhow, Result};
use geardyn_analysis::stage_signals::{stage_signals, StageSignals, StageSignalsRequest};
use geardyn_io::figure::{palette, write_figure, Figure, Layer, Panel, Style};
use geardyn_io::output::write_text;
use geardyn_io::run_record;
use geardyn_train::dynamics::{elastic_dof, TrainModel};
use std::fmt::Write as _;
use std::path::Path;

/// Runs the stage's signals into `out`.
pub fn signals(t: &TrainRun, req: &StageSignalsRequest, out: &Path) -> Result<()> {
    let s = with_model!(&t.spec, &t.op, |m| run(t, &m, req))?;
    let _lock = run_record::prepare_folder(out, "signals", None, false)?;
    write_text(&out.join("system.toml"), &t.spec.to_toml())?;
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
        "units": "forces in k_ref b_c (dimensionless), orders per carrier revolution",
    });
    write_text(
        &out.join("summary.json"),
        &serde_json::to_string_pretty(&summary)?,
    )?;
    spectrum_figure(t, &s, &out.join("spectrum"))?;
    println!(
        "signals of {}: {} carrier revolutions; mesh order {:.4}{}; {}",
        t.spec.name,
        s.carrier_revolutions,
        s.mesh_order,
        s.fault_order
            .map_or(String::new(), |f| format!(", fault order {f:.4}")),
        out.display()
    );
    Ok(())
}

fn run<const N: usize>(
    t: &TrainRun,
    m: &TrainModel<N>,
    req: &StageSignalsRequest,
) -> Result<StageSignals>
where
    TrainModel<N>: geardyn_analysis::engine::Engine<N>,
{
    stage_signals(&t.spec, m, (0.0, m.static_state()), req).map_err(|e| anyhow!(e))
}

fn spectrum_figure(t: &TrainRun, s: &StageSignals, stem: &Path) -> Result<()> {
    let top = 2.5 * s.mesh_order;
    let layer = |a: &[f64], k: usize| Layer {
        points: s
            .orders
            .iter()
            .zip(a)
            .skip(1)
            .filter(|(o, _)| **o <= top)
            .map(|(o, a)| (*o, *a))
            .collect(),
        style: Style::Line(1),
        color: palette(k),
    };
    let title = match s.fault_order {
        Some(f) => format!(
            "{}: spectra in carrier orders (mesh order {:.2}, fault order {f:.2})",
            t.spec.name, s.mesh_order
        ),
        None => format!(
            "{}: spectra in carrier orders (mesh order {:.2})",
            t.spec.name, s.mesh_order
        ),
    };
    write_figure(
        stem,
        &Figure {
            title,
            x_label: "order (per carrier revolution)".into(),
            panels: vec![
                Panel {
                    y_label: "ring transducer (k_ref b_c)".into(),
                    layers: vec![layer(&s.sensor_spectrum, 0)],
                    ..Default::default()
                },
                Panel {
                    y_label: "sun torque (k_ref b_c)".into(),
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
