//! Readings generated from the data: label intervals, impact ranges, extremes.

use geardyn_analysis::bifurcation::TaskResult;

/// Runs of consecutive parameter values with the same label on one branch:
/// `(first value, last value, label, any impact)`.
pub fn label_intervals(results: &[TaskResult], branch: u8) -> Vec<(f64, f64, String, bool)> {
    let mut rs: Vec<&TaskResult> = results.iter().filter(|r| r.task.branch == branch).collect();
    rs.sort_by(|a, b| a.value.total_cmp(&b.value));
    let mut out: Vec<(f64, f64, String, bool)> = Vec::new();
    for r in rs {
        let run = &r.runs[0];
        let label = class(&run.label);
        let impact = run.impacts > 0;
        match out.last_mut() {
            Some(last) if last.2 == label && last.3 == impact => last.1 = r.value,
            _ => out.push((r.value, r.value, label, impact)),
        }
    }
    out
}

/// Label with the crossing rates of non-periodic motions dropped: `chaotic`, `quasi-periodic`,
/// `unsettled`, or the periodic label itself.
pub fn class(label: &str) -> String {
    match label.split_once(" (") {
        Some((word, _)) => word.to_string(),
        None => label.to_string(),
    }
}

/// Human-readable list of label intervals.
pub fn describe_intervals(param: &str, iv: &[(f64, f64, String, bool)]) -> String {
    iv.iter()
        .map(|(a, b, l, imp)| {
            let range = if a == b {
                format!("{param} = {a:.4}")
            } else {
                format!("{param} in [{a:.4}, {b:.4}]")
            };
            format!(
                "{range}: {l}{}",
                if *imp { " with back-side impacts" } else { "" }
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// Values (of one branch) whose runs have back-side impacts.
pub fn impact_values(results: &[TaskResult], branch: u8) -> Vec<f64> {
    let mut v: Vec<f64> = results
        .iter()
        .filter(|r| r.task.branch == branch && r.runs.iter().any(|run| run.impacts > 0))
        .map(|r| r.value)
        .collect();
    v.sort_by(f64::total_cmp);
    v
}

/// Format a number compactly.
pub fn f(v: f64) -> String {
    if v == 0.0 || (v.abs() >= 1e-3 && v.abs() < 1e4) {
        format!("{v:.4}")
    } else {
        format!("{v:.3e}")
    }
}
