//! Writers for simulation results: CSV tables and JSON summaries.

use geardyn_analysis::simulate::{SimResult, Summary};
use std::path::Path;

/// Every digit (shortest round-trip form): the CLI's number format.
pub fn full(v: f64) -> String {
    format!("{v}")
}

pub use crate::safe_write::OutputError;

/// Writes a CSV file with the given header and rows (numbers in shortest round-trip form).
pub fn write_csv<R, I>(path: &Path, header: &[&str], rows: I) -> Result<(), OutputError>
where
    I: IntoIterator<Item = R>,
    R: IntoIterator<Item = String>,
{
    let mk = |source| OutputError::Csv {
        path: path.display().to_string(),
        source,
    };
    crate::safe_write::write_via(
        path,
        |tmp| -> Result<(), csv::Error> {
            let mut w = csv::Writer::from_path(tmp)?;
            w.write_record(header)?;
            for r in rows {
                w.write_record(r)?;
            }
            w.flush()?;
            Ok(())
        },
        mk,
    )
}

/// Writes any serialisable value as pretty JSON.
pub fn write_json<T: serde::Serialize>(path: &Path, value: &T) -> Result<(), OutputError> {
    let mut text = serde_json::to_string_pretty(value).expect("serialisable");
    text.push('\n');
    crate::safe_write::write_bytes(path, text.as_bytes())
}

/// Writes a text file.
pub fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    crate::safe_write::write_bytes(path, text.as_bytes())
}

/// `trajectory.csv`: `tau,x,v,mesh_force,state`.
pub fn write_trajectory(path: &Path, res: &SimResult) -> Result<(), OutputError> {
    write_csv(
        path,
        &["tau", "x", "v", "mesh_force", "state"],
        res.mesh().trajectory.iter().map(|p| {
            [
                full(p.tau),
                full(p.x),
                full(p.v),
                full(p.mesh_force),
                p.state.to_string(),
            ]
        }),
    )
}

/// `strobe.csv`: `tau,x,v`, one row per recorded excitation period.
pub fn write_strobe(path: &Path, res: &SimResult) -> Result<(), OutputError> {
    write_csv(
        path,
        &["tau", "x", "v"],
        res.strobe
            .iter()
            .map(|p| [full(p.tau), full(p.y[0]), full(p.y[1])]),
    )
}

/// `events.csv`: `tau,cycle_position,kind,x,v_before,v_after,peak_force`.
pub fn write_events(path: &Path, res: &SimResult) -> Result<(), OutputError> {
    write_csv(
        path,
        &[
            "tau",
            "cycle_position",
            "kind",
            "x",
            "v_before",
            "v_after",
            "peak_force",
        ],
        res.mesh().events.iter().map(|e| {
            let kind = serde_json::to_value(e.kind)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default();
            [
                full(e.tau),
                full(e.cycle_position),
                kind,
                full(e.x),
                full(e.v_before),
                full(e.v_after),
                full(e.peak_force),
            ]
        }),
    )
}

/// `sections.csv`: `section,tau,x,v` for every level crossing.
pub fn write_sections(path: &Path, res: &SimResult) -> Result<(), OutputError> {
    write_csv(
        path,
        &["section", "tau", "x", "v"],
        res.mesh().crossings.iter().map(|c| {
            [
                c.level.name().to_string(),
                full(c.tau),
                full(c.x),
                full(c.v),
            ]
        }),
    )
}

/// `summary.json`.
pub fn write_summary(
    path: &Path,
    summary: &Summary,
    extra: serde_json::Value,
) -> Result<(), OutputError> {
    let mut v = serde_json::to_value(summary).expect("serialisable");
    if let (Some(obj), serde_json::Value::Object(more)) = (v.as_object_mut(), extra) {
        obj.extend(more);
    }
    write_json(path, &v)
}
