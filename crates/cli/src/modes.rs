//! `geardyn modes`: natural frequencies, mode shapes and Campbell resonances of a gear train
//! (a built-in one, `--preset planetary|two-stage|pair`, or a description file, `--system`).

use anyhow::{bail, Context, Result};
use clap::Args;
use geardyn_io::figure::{palette, write_figure, Figure, Layer, LegendEntry, Panel, Style};
use geardyn_io::output::write_text;
use geardyn_io::run_record;
use geardyn_train::campbell::{crossings, mesh_families};
use geardyn_train::kinematics::Kinematics;
use geardyn_train::{presets, Modes, TrainSpec};
use std::path::PathBuf;

/// Arguments of `geardyn modes`.
#[derive(Args, Debug)]
pub struct ModesArgs {
    /// Built-in train: planetary (default), two-stage or pair.
    #[arg(long, conflicts_with = "system")]
    preset: Option<String>,
    /// A train description (TOML, as written to system.toml by this command).
    #[arg(long)]
    system: Option<PathBuf>,
    /// A field of the built-in train: NAME=VALUE (repeatable), e.g. --set stage.planets=4
    /// (planetary: stage.sun_teeth, stage.planet_teeth, stage.ring_teeth, stage.planets,
    /// stage.module_mm, stage.face_width_mm, stage.carrier_inertia_kgm2, stage.input_torque_nm;
    /// two-stage: stage1.z1, stage1.z2, stage2.z1, stage2.z2, stage.module_mm,
    /// stage.face_width_mm, shaft.diameter_mm, shaft.length_mm).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    sets: Vec<String>,
    /// Mesh-frequency harmonics in the Campbell diagram (1 ... 20).
    #[arg(long, default_value_t = 3)]
    harmonics: u32,
    /// Highest input speed of the Campbell diagram (rpm); default: where the first harmonic
    /// passes the highest natural frequency by 20 %.
    #[arg(long)]
    max_rpm: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "out/modes")]
    out: PathBuf,
}

fn train(a: &ModesArgs) -> Result<TrainSpec> {
    let mut sets = Vec::new();
    for s in &a.sets {
        let (k, v) = s
            .split_once('=')
            .with_context(|| format!("--set {s}: expected NAME=VALUE"))?;
        let v: f64 = v
            .trim()
            .parse()
            .with_context(|| format!("--set {s}: the value is not a number"))?;
        sets.push((k.trim().to_string(), v));
    }
    match (&a.system, &a.preset) {
        (Some(path), _) => {
            if !sets.is_empty() {
                bail!("--set applies to a built-in train (--preset); edit the description file instead");
            }
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read --system {}", path.display()))?;
            TrainSpec::from_toml(&text).with_context(|| format!("--system {}", path.display()))
        }
        (None, p) => Ok(presets::by_name(
            p.as_deref().unwrap_or("planetary"),
            &sets,
        )?),
    }
}

pub fn run(a: ModesArgs) -> Result<()> {
    let started = std::time::Instant::now();
    if !(1..=20).contains(&a.harmonics) {
        bail!("invalid --harmonics {}: allowed 1 ... 20", a.harmonics);
    }
    if let Some(r) = a.max_rpm {
        if !(r.is_finite() && r > 0.0 && r <= 1e7) {
            bail!("invalid --max-rpm {r}: allowed (0, 1e7] rpm");
        }
    }
    let t = train(&a)?;
    let kin = Kinematics::of(&t)?;
    let modes = Modes::of(&t);
    let fams = mesh_families(&t, &kin);
    let fmax = modes.modes.last().map_or(0.0, |m| m.frequency_hz);
    let lowest_order = fams.iter().map(|f| f.1).fold(f64::INFINITY, f64::min);
    let max_rpm = a
        .max_rpm
        .unwrap_or(1.2 * 60.0 * fmax / lowest_order.max(f64::MIN_POSITIVE));
    let cross = crossings(&t, &kin, &modes, a.harmonics, max_rpm);
    let _lock = run_record::prepare_folder(&a.out, "modes", None, false)?;
    write_text(&a.out.join("system.toml"), &t.to_toml())?;
    run_record::write_train_record(
        &a.out,
        "modes",
        serde_json::json!({ "name": t.name }),
        &[],
        started.elapsed().as_secs_f64(),
    )?;
    // modes.csv: one row per mode, the shape as one column per body
    let mut csv = String::from("mode,frequency_hz,kind,multiplicity");
    for b in &modes.bodies {
        csv += &format!(",shape {b},energy {b}");
    }
    csv.push('\n');
    for (i, m) in modes.modes.iter().enumerate() {
        csv += &format!(
            "{},{},{},{}",
            i + 1,
            m.frequency_hz,
            m.kind.word(),
            m.multiplicity
        );
        for (s, e) in m.shape.iter().zip(&m.energy) {
            csv += &format!(",{s},{e}");
        }
        csv.push('\n');
    }
    write_text(&a.out.join("modes.csv"), &csv)?;
    let mut cc = String::from("meshes,harmonic,frequency_hz,multiplicity,kind,input_rpm,excited\n");
    for c in &cross {
        cc += &format!(
            "\"{}\",{},{},{},{},{},{}\n",
            c.meshes, c.harmonic, c.frequency_hz, c.multiplicity, c.kind, c.input_rpm, c.excited
        );
    }
    write_text(&a.out.join("campbell.csv"), &cc)?;
    let json = serde_json::json!({
        "system": t.name,
        "bodies": modes.bodies,
        "speed_ratios": kin.ratios,
        "mesh_orders": t.meshes.iter().zip(&kin.mesh_orders).map(|(m, o)| serde_json::json!({"mesh": m.name, "phase": m.phase, "tooth_passes_per_input_rev": o})).collect::<Vec<_>>(),
        "fault_orders": t.bodies.iter().enumerate().map(|(i, b)| serde_json::json!({"body": b.name, "tooth_events_per_input_rev": kin.fault_order(&t, i)})).collect::<Vec<_>>(),
        "modes": modes.modes,
        "campbell": cross,
    });
    write_text(
        &a.out.join("modes.json"),
        &serde_json::to_string_pretty(&json)?,
    )?;
    campbell_figure(&a, &t, &modes, &fams, max_rpm, &cross)?;
    let ratio = 1.0 / kin.ratios[t.body_index(&t.load.output).expect("validated")];
    println!(
        "{}: {} coordinates, input {} -> output {} (input/output speed ratio {:.6}{})",
        t.name,
        modes.modes.len(),
        t.load.input,
        t.load.output,
        ratio,
        if ratio < 0.0 {
            ": the output turns the other way"
        } else {
            ""
        }
    );
    println!("  mode  frequency (Hz)  type        multiplicity");
    for (i, m) in modes.modes.iter().enumerate() {
        println!(
            "  {:>4}  {:>14.4}  {:<11} {}",
            i + 1,
            m.frequency_hz,
            m.kind.word(),
            m.multiplicity
        );
    }
    for (names, order) in &fams {
        println!("  mesh frequency {order:.6} x input speed ({names})");
    }
    println!(
        "  {} Campbell crossings up to {max_rpm:.0} rpm -> {}",
        cross.len(),
        a.out.display()
    );
    Ok(())
}

/// Mesh harmonics against the natural frequencies over the input speed.
fn campbell_figure(
    a: &ModesArgs,
    t: &TrainSpec,
    modes: &Modes,
    fams: &[(String, f64)],
    max_rpm: f64,
    cross: &[geardyn_train::campbell::Crossing],
) -> Result<()> {
    let ftop = modes.modes.last().map_or(1.0, |m| m.frequency_hz) * 1.15;
    let mut layers = Vec::new();
    let mut legend = Vec::new();
    for (fi, (names, order)) in fams.iter().enumerate() {
        for h in 1..=a.harmonics {
            let c = palette(fi * a.harmonics as usize + h as usize - 1);
            // (ended inside the frequency range: the plot clamps points outside it)
            let slope = f64::from(h) * order / 60.0;
            let x_end = max_rpm.min(ftop / slope);
            layers.push(Layer {
                points: vec![(0.0, 0.0), (x_end, slope * x_end)],
                style: Style::Line(2),
                color: c,
            });
            let short = if names.len() > 40 {
                format!(
                    "{}…",
                    &names[..names.char_indices().nth(39).map_or(names.len(), |x| x.0)]
                )
            } else {
                names.clone()
            };
            legend.push(LegendEntry::line(
                format!("{h} x mesh frequency ({short})"),
                c,
            ));
        }
    }
    for (excited, grey, text) in [
        (
            true,
            0,
            "resonance: a harmonic on a natural frequency it excites",
        ),
        (
            false,
            170,
            "crossing cancelled by the planet phasing (Parker 2000)",
        ),
    ] {
        let pts: Vec<(f64, f64)> = cross
            .iter()
            .filter(|c| c.excited == excited)
            .map(|c| (c.input_rpm, c.frequency_hz))
            .collect();
        if pts.is_empty() {
            continue;
        }
        let color = plotters::style::RGBColor(grey, grey, grey);
        layers.push(Layer {
            points: pts,
            style: Style::Dots(if excited { 5 } else { 3 }),
            color,
        });
        legend.push(LegendEntry::dot(text, color));
    }
    write_figure(
        &a.out.join("campbell"),
        &Figure {
            title: format!(
                "Campbell diagram: {} (grey lines: natural frequencies, multiplicity in modes.csv)",
                t.name
            ),
            x_label: format!("input speed of {} (rpm)", t.load.input),
            x_range: Some((0.0, max_rpm)),
            panels: vec![Panel {
                y_label: "frequency (Hz)".into(),
                layers,
                y_range: Some((0.0, ftop)),
                hlines: modes.distinct().iter().map(|d| d.0).collect(),
                ..Default::default()
            }],
            legend,
            panel_height: 520,
            ..Default::default()
        },
    )?;
    Ok(())
}
