//! A deeper escape test at some of a sweep's chaotic values.
//!
//! The decided sweep calls a value chaotic when none of its escape test's copies leaves the
//! chaotic set: that excludes mean lifetimes below about two decision horizons (6 700 periods
//! at the default horizon), not longer ones. The broken pair at omega = 2.025, F = 0.1 leaks
//! with a lifetime of order 10^5 revolutions; a paper integrating a few hundred periods, and a
//! decision of 10 000, both see chaos there. The report re-decides a few chaotic values, spread
//! over those a sweep finds, with [`DEEP_COPIES`] copies over [`DEEP_HORIZON`] periods' exposure
//! — a fixed cost per page instead of a deeper test at every value — and counts what it finds:
//! the values it re-decides carry that verdict in the claims, the others keep theirs.

use crate::runner::Ctx;
use anyhow::Result;
use geardyn_analysis::bifurcation::{SweepMode, SweepOptions, TaskResult};
use geardyn_analysis::escape::EscapeSettings;
use geardyn_analysis::simulate::SimOptions;
use geardyn_analysis::verdict::Motion;
use geardyn_scenario::Scenario;
use std::path::Path;

/// Copies of the deeper escape test.
pub const DEEP_COPIES: u32 = 64;
/// Decision horizon of the deeper test: its silent copies must cover two of them
/// (`2 x 100 000 / 64` = 3 125 periods each after they spread), excluding lifetimes below
/// `200 000 / ln 20` = 66 800 periods at 95 %.
pub const DEEP_HORIZON: u64 = 100_000;
/// Work budget of one deeper decision (right-hand-side evaluations): the broken pair's 64
/// copies take about 3e9 for 3 125 revolutions (about 15 s on 2 cores).
pub const DEEP_BUDGET: u64 = 4_000_000_000;

/// The settings of a deeper decision of `sim`'s runs.
pub fn deep_sim(sim: SimOptions) -> SimOptions {
    SimOptions {
        decision_periods: DEEP_HORIZON,
        decision_budget: DEEP_BUDGET,
        escape: EscapeSettings {
            copies: DEEP_COPIES,
            periods: 0,
            ..sim.escape
        },
        ..sim
    }
}

/// `k` of the chaotic values among `results` (single-run values), evenly spread over them by
/// rank, the lowest and the highest included.
pub fn chaotic_sample(results: &[TaskResult], k: usize) -> Vec<f64> {
    let chaotic: Vec<f64> = results
        .iter()
        .filter(|r| r.runs.len() == 1 && r.runs[0].motion.is_chaotic())
        .map(|r| r.value)
        .collect();
    spread(chaotic.len(), k)
        .into_iter()
        .map(|i| chaotic[i])
        .collect()
}

/// `k` ranks of `0..n` evenly spread, the first and the last included (all when `n <= k`; the
/// middle one when `k` = 1).
fn spread(n: usize, k: usize) -> Vec<usize> {
    match k {
        _ if n <= k => (0..n).collect(),
        0 => Vec::new(),
        1 => vec![n / 2],
        _ => (0..k)
            .map(|j| (j * (n - 1) + (k - 1) / 2) / (k - 1))
            .collect(),
    }
}

/// The deeper decisions of `k` chaotic values of the fixed sweep `opts` whose `results` are
/// given (checkpointed as `name, deep`); empty when none is chaotic.
pub fn recheck(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    base: &Scenario,
    opts: &SweepOptions,
    results: &[TaskResult],
    k: usize,
) -> Result<Vec<TaskResult>> {
    let values = chaotic_sample(results, k);
    if values.is_empty() || opts.mode != SweepMode::Fixed {
        return Ok(Vec::new());
    }
    let deep = SweepOptions {
        values,
        sim: deep_sim(opts.sim),
        ..opts.clone()
    };
    ctx.sweep(dir, &format!("{name}, deep"), base, &deep)
}

/// Did the deeper test decide (chaotic or transient chaos), rather than run out of budget?
fn decided(d: &TaskResult) -> bool {
    d.runs.first().is_some_and(|r| {
        matches!(
            r.motion,
            Motion::Chaotic { .. } | Motion::TransientChaos { .. }
        )
    })
}

/// `results` with the values of `deep` replaced by their deeper decision where it decided (a
/// deeper test that ran out of budget leaves the ordinary verdict).
pub fn substituted(results: &[TaskResult], deep: &[TaskResult]) -> Vec<TaskResult> {
    results
        .iter()
        .map(|r| {
            deep.iter()
                .filter(|d| decided(d))
                .find(|d| d.value == r.value)
                .map(|d| TaskResult {
                    task: r.task,
                    ..d.clone()
                })
                .unwrap_or_else(|| r.clone())
        })
        .collect()
}

/// What the deeper test found, for a section's readings: how many of the rechecked values
/// leaked (with their lifetimes and orbits) and how many stayed chaotic.
pub fn reading(deep: &[TaskResult], param: &str, unit: &str) -> Option<String> {
    if deep.is_empty() {
        return None;
    }
    let mut leaked = Vec::new();
    let mut stayed = Vec::new();
    let mut budget = Vec::new();
    for d in deep {
        let Some(run) = d.runs.first() else { continue };
        let v = crate::shared::g(d.value);
        match run.motion {
            Motion::TransientChaos { lifetime: l, .. } => leaked.push(format!(
                "{param} = {v} (lifetime ~{} {unit}, then {})",
                crate::shared::g(l.round()),
                run.label
            )),
            Motion::Chaotic { .. } => stayed.push(format!("{param} = {v}")),
            _ => budget.push(format!("{param} = {v}")),
        }
    }
    let mut s = format!(
        "Deeper escape test ({DEEP_COPIES} copies, {} copy-{unit} of exposure, lifetimes below ~{} {unit} excluded when silent) at {} of the chaotic values:",
        crate::shared::g((2 * DEEP_HORIZON) as f64),
        crate::shared::g((2.0 * DEEP_HORIZON as f64 / 20f64.ln()).round()),
        deep.len()
    );
    if !leaked.is_empty() {
        s += &format!(" transient chaos at {}", leaked.join(", "));
    }
    if !stayed.is_empty() {
        s += &format!(
            "{} chaotic at {}",
            if leaked.is_empty() { "" } else { ";" },
            stayed.join(", ")
        );
    }
    if !budget.is_empty() {
        s += &format!(
            "{} its budget ran out at {} (the ordinary verdict stands)",
            if leaked.is_empty() && stayed.is_empty() {
                ""
            } else {
                ";"
            },
            budget.join(", ")
        );
    }
    Some(s + ".")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sample_spreads_over_the_chaotic_values_ends_included() {
        assert_eq!(spread(25, 5), vec![0, 6, 12, 18, 24]);
        assert_eq!(spread(5, 2), vec![0, 4]);
        assert_eq!(spread(7, 3), vec![0, 3, 6]);
        assert_eq!(spread(3, 6), vec![0, 1, 2]);
        assert_eq!(spread(9, 1), vec![4]);
        assert!(spread(4, 0).is_empty());
    }

    #[test]
    fn the_deeper_decision_excludes_lifetimes_ten_times_the_default() {
        let d = deep_sim(SimOptions::default());
        let default = SimOptions::default();
        let span = |s: &SimOptions| s.escape.required(s.decision_periods) * s.escape.copies as u64;
        assert!(
            span(&d) >= 10 * span(&default),
            "{} {}",
            span(&d),
            span(&default)
        );
        assert_eq!(d.method, default.method);
        assert_eq!(d.record_periods, default.record_periods);
    }
}
