//! Sensitivity of the load sweep to the readings of seed A's text it depends on: the mesh
//! frequency of the sweep and the size of the chip; the claims of the load sweep under every
//! reading. Checks seed A 000 ¶9 (the frequency of the load sweep is not given).

use super::load_sweep::{attractor_sweep, broken_load_claims, HIGH_LOADS};
use super::{sweep, with_chip, AXES, CHIP_MM, OMEGA_LOAD};
use crate::classes::{self, tolerant, Class, Pt};
use crate::interpretations::{axes_table, label_claims, Interpretation};
use crate::readings::{f, ranges_text};
use crate::runner::{Ctx, TableSpec};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::bifurcation::{linspace, Section as Sec, SweepMode, TaskResult};
use geardyn_analysis::simulate::SimOptions;
use geardyn_io::figure::{palette, write_raster, LegendEntry, RasterFigure, CHAOTIC, UNSETTLED};
use geardyn_scenario::Scenario;
use std::path::Path;

/// The seed's "F > 0.1 periodic without impact" holds in the sensitivity table when it holds at
/// every value of [`HIGH_LOADS`] (a share above this).
const HOLDS_EVERYWHERE: f64 = 0.999;

/// A row of the load-sensitivity table for the broken pair's sweep `pts` at `omega` with `mm`
/// removed from the chipped tip, and whether the seed's "F > 0.1 periodic without impact" holds.
fn sensitivity_row(pts: &[Pt], omega: f64, mm: f64) -> (Vec<String>, bool) {
    let hi = classes::within(pts, HIGH_LOADS.0, HIGH_LOADS.1);
    let ok = classes::share(&hi, |p| p.class.periodic() && !p.back) > HOLDS_EVERYWHERE;
    let largest = pts
        .iter()
        .filter(|p| p.back)
        .map(|p| p.value)
        .fold(f64::NAN, f64::max);
    let chaos = classes::ranges(&tolerant(pts), |p| p.class == Class::Chaotic);
    let chaos_txt = ranges_text(&chaos);
    let row = vec![
        f(omega),
        f(mm),
        f(largest),
        chaos_txt,
        pts.last().map_or(String::new(), |p| p.name.clone()),
        (if ok { "yes" } else { "no" }).into(),
    ];
    (row, ok)
}

/// What the study computed: the broken pair's load sweeps under the other readings.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct LoadSensitivityData {
    /// The frequencies.
    omegas: Vec<f64>,
    /// Values of F.
    nf: usize,
    /// The loads.
    fvals: Vec<f64>,
    /// Integration settings.
    sim: SimOptions,
    /// The sweep over F at each frequency (the preset's chip).
    by_omega: Vec<Vec<TaskResult>>,
    /// The sweep over F at [`OMEGA_LOAD`] for each other chip size (`CHIP_MM[1..]`).
    by_chip: Vec<Vec<TaskResult>>,
    /// The multi-initial runs of each frequency reading other than [`OMEGA_LOAD`] (in the
    /// order of `omegas`, that one empty), then of each other chip size.
    attractors: Vec<Vec<TaskResult>>,
}

crate::runner::study!(LoadSensitivity { base: &'a Scenario } "load_sensitivity" LoadSensitivityData,
    |s, ctx, dir| compute(ctx, s.base, dir), |data| render(ctx, dir, data));

/// The broken pair's load sweep at neighbouring frequencies and for the other chip sizes.
pub(super) fn compute(ctx: &Ctx, base: &Scenario, dir: &Path) -> Result<LoadSensitivityData> {
    let omegas: Vec<f64> = ctx.n(vec![1.0, 1.2, 1.4], vec![1.0, 1.1, 1.2, 1.3, 1.4]);
    let nf = ctx.n(8, 31);
    let fvals = linspace(0.0, 0.15, nf);
    let sim = ctx.sim((30, 80), (12, 30));
    let mut by_omega = Vec::new();
    let mut attractors = Vec::new();
    for &w in &omegas {
        let b = base.with("omega", w)?;
        let o = sweep("F", fvals.clone(), SweepMode::Fixed, sim, vec![Sec::Impact]);
        by_omega.push(ctx.sweep(dir, &format!("F sweep omega {w}"), &b, &o)?);
        attractors.push(if w == OMEGA_LOAD {
            Vec::new()
        } else {
            attractor_sweep(ctx, dir, &format!("multi-initial F omega {w}"), &b, sim)?
        });
    }
    // the chip-size readings at the load sweep's frequency
    let mut by_chip = Vec::new();
    for &mm in CHIP_MM.iter().skip(1) {
        let b = with_chip(base, mm)?.with("omega", OMEGA_LOAD)?;
        let o = sweep("F", fvals.clone(), SweepMode::Fixed, sim, vec![Sec::Impact]);
        by_chip.push(ctx.sweep(dir, &format!("F sweep chip {mm} mm"), &b, &o)?);
        attractors.push(attractor_sweep(
            ctx,
            dir,
            &format!("multi-initial F chip {mm} mm"),
            &b,
            sim,
        )?);
    }
    Ok(LoadSensitivityData {
        omegas,
        nf,
        fvals,
        sim,
        by_omega,
        by_chip,
        attractors,
    })
}

/// The (F, omega) class map, the sensitivity table and the load sweep's claims under every
/// reading.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &LoadSensitivityData) -> Result<Section> {
    let (omegas, nf, fvals, sim) = (&data.omegas, data.nf, &data.fvals, data.sim);
    let mut colors = Vec::new();
    let mut rows = Vec::new();
    let mut alternatives = Vec::new();
    let mut ok_count = 0;
    let multi = |i: usize| classes::points(&data.attractors[i], 0);
    for (i, (&w, r)) in omegas.iter().zip(&data.by_omega).enumerate() {
        let pts = classes::fixed_points(r);
        for p in &pts {
            colors.push(class_color(p));
        }
        // the load sweep's claims at this frequency: another reading of the text
        let reading = format!("omega = {}", f(w));
        if let Some(k) = AXES[0].choices.iter().position(|c| *c == reading) {
            if k > 0 {
                let mut cl = broken_load_claims(&pts, &multi(i), w);
                let it = Interpretation::with(&AXES, &[(AXES[0].name, k)]);
                label_claims(&mut cl, &it.label(&AXES));
                alternatives.extend(cl);
            }
        }
        let (row, ok) = sensitivity_row(&pts, w, CHIP_MM[0]);
        ok_count += usize::from(ok);
        rows.push(row);
    }
    for ((k, &mm), r) in CHIP_MM.iter().enumerate().skip(1).zip(&data.by_chip) {
        let pts = classes::fixed_points(r);
        let mut cl = broken_load_claims(&pts, &multi(omegas.len() + k - 1), OMEGA_LOAD);
        let it = Interpretation::with(&AXES, &[(AXES[1].name, k)]);
        label_claims(&mut cl, &it.label(&AXES));
        alternatives.extend(cl);
        rows.push(sensitivity_row(&pts, OMEGA_LOAD, mm).0);
    }
    let df = 0.15 / (nf - 1).max(1) as f64;
    let stem = dir.join("load_omega_classes");
    let mut cells_csv = Vec::new();
    for (i, &w) in omegas.iter().enumerate() {
        for (j, &fv) in fvals.iter().enumerate() {
            cells_csv.push(vec![
                f(w),
                crate::shared::g(fv),
                colors[i * nf + j].1.to_string(),
            ]);
        }
    }
    write_raster(
        &stem,
        &RasterFigure {
            title: "Broken pair: decided motion over (F, omega)".into(),
            x_label: "F".into(),
            y_label: "omega".into(),
            x: (-df / 2.0, 0.15 + df / 2.0, nf),
            y: {
                let dw = (omegas[omegas.len() - 1] - omegas[0]) / (omegas.len() - 1).max(1) as f64;
                (
                    omegas[0] - dw / 2.0,
                    omegas[omegas.len() - 1] + dw / 2.0,
                    omegas.len(),
                )
            },
            colors: colors.iter().map(|c| c.0).collect(),
            legend: class_legend(),
            legend_title: "motion".into(),
            colorbar: None,
            marks: vec![],
        },
    )?;
    let csv = dir.join("load_omega_classes.csv");
    geardyn_io::output::write_csv(&csv, &["omega", "F", "class"], cells_csv)?;
    let table = ctx.declared_table(dir, &LOAD_SENSITIVITY_TABLE, rows)?;
    let axes = axes_table(ctx, dir, &AXES)?;
    Ok(Section {
        id: "load_sensitivity".into(),
        title: "Sensitivity of the load sweep to the readings of the text: its frequency and the chip size".into(),
        seed_ref: "000 ¶9 (the frequency of the load sweep is not given)".into(),
        parameters: format!(
            "F in [0, 0.15] ({nf} values) at omega ∈ {{{}}} (chip of the preset) and at omega = {} with {} mm removed; xi = 0.05",
            omegas.iter().map(|w| f(*w)).collect::<Vec<_>>().join(", "),
            f(OMEGA_LOAD),
            CHIP_MM[1..].iter().map(|m| f(*m)).collect::<Vec<_>>().join(" and ")
        ),
        method: format!("As the load sweep, {} + {} revolutions per value.", sim.transient_periods, sim.record_periods),
        figures: vec![ctx.fig(&stem, &format!("Decided motion of the broken pair over F at {} mesh frequencies: healthy periodic, periodic with back-side impacts, chaotic, undecided.", omegas.len()), &[csv])],
        readings: vec![format!(
            "The seed's statement (F > 0.1 periodic without impact) holds at {ok_count} of {} frequencies; at exact resonance (omega = 1, damping ratio 0.005) back-side impacts persist to large loads.",
            omegas.len()
        )],
        tables: vec![table, axes],
        claims: vec![],
        alternatives,
        seconds: 0.0,
    })
}

fn class_color(p: &Pt) -> (geardyn_io::figure::RGBColor, &'static str) {
    match p.class {
        Class::Periodic(_) if !p.back => (palette(0), "periodic, no impact"),
        Class::Periodic(_) => (palette(1), "periodic with impacts"),
        Class::Chaotic => (CHAOTIC, "chaotic"),
        Class::Failed => (palette(8), "failed"),
        _ => (UNSETTLED, "undecided"),
    }
}

fn class_legend() -> Vec<LegendEntry> {
    vec![
        LegendEntry::dot("periodic, no impact", palette(0)),
        LegendEntry::dot("periodic with impacts", palette(1)),
        LegendEntry::dot("chaotic", CHAOTIC),
        LegendEntry::dot("undecided / quasi-periodic", UNSETTLED),
    ]
}

/// The table of `load_sensitivity.csv`.
const LOAD_SENSITIVITY_TABLE: TableSpec = TableSpec {
    file: "load_sensitivity.csv",
    title: "The load sweep at neighbouring frequencies",
    columns: &[
        "omega",
        "chip (mm removed)",
        "largest F with impacts",
        "chaotic F",
        "motion at F = 0.15",
        "F > 0.1 periodic without impact",
    ],
};
