//! The motion summary of a record (docs/model.md §5): period (stroboscopic, and in mesh cycles
//! for an excitation period of several), the `n-p-q-r-s` label per mesh, the healthy flag, P_ID
//! and the force extremes. [`summarize`] decides only "periodic"; the decision of the other
//! classes is [`crate::classify`].

use crate::escape::EscapeSummary;
use crate::period::minimal_period_tol;
use crate::record::{MeshRecord, SimResult};
use crate::simulate::SimOptions;
use crate::verdict::{DecidedBy, Motion};
use geardyn_model::GearSystem;
use serde::Serialize;

/// Motion summary (docs/model.md §5).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Minimal period in excitation periods (0 = not periodic).
    pub period: usize,
    /// Minimal period in mesh cycles of the mesh-cycle strobe, when the excitation period spans
    /// several mesh cycles (tooth breakage: one excitation period is one pinion revolution).
    pub mesh_period: Option<usize>,
    /// The decided class of the motion ([`crate::classify`]); [`summarize`] alone decides only
    /// "periodic" and otherwise says `unsettled`.
    pub motion: Motion,
    /// Label `n-p-q-r-s` (`n-p-q` when `D_s = D_d`) of a periodic motion; otherwise the class
    /// word alone (`chaotic`, `unsettled`, ...: a label carries no measured number, so that runs
    /// group by it; the crossing rates are [`Summary::rates`]).
    pub label: String,
    /// Counts `p, q, r, s` over one motion period; if `n = 0` (not periodic) their totals over the
    /// recorded periods.
    pub counts: [u32; 4],
    /// Crossings per excitation period of `x = D_s` upward, `x = -D_s` downward, `x = D_d`
    /// upward and `x = -D_d` downward (`p, q, r, s` per period: the counts over one motion period
    /// divided by its length, or the totals over the record divided by the recorded periods).
    #[serde(default)]
    pub rates: [f64; 4],
    /// Periodic without back-side contact or impact.
    pub healthy: bool,
    /// Dynamic instability proportion.
    pub p_id: f64,
    /// Maximum mesh force.
    pub max_force: f64,
    /// Minimum mesh force.
    pub min_force: f64,
    /// Number of back-side impacts over the recorded periods.
    pub impacts: u64,
    /// Largest impact force over the recorded periods.
    pub max_impact_force: f64,
    /// Excitation periods the motion was followed in all (transient, including the decision's
    /// extensions, plus the record); the exponent windows of the decision are not counted.
    pub periods_integrated: u64,
    /// The evidence that decided [`Summary::motion`] ([`crate::classify`]).
    pub decided_by: DecidedBy,
    /// The ensemble escape test, when it decided the motion ([`DecidedBy::Escape`]: chaotic, or
    /// transient chaos).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub escape: Option<EscapeSummary>,
    /// Per mesh, for a system of several meshes (empty for a single mesh, which the fields above
    /// describe). The fields above then describe the system: the label joins the meshes' labels,
    /// counts and rates are summed over the meshes, P_ID is their mean, the forces the extremes
    /// over the meshes, impacts their total, and the motion is healthy when every mesh is.
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub meshes: Vec<MeshSummary>,
}

/// What a [`Summary`] says of one mesh of a system of several.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshSummary {
    /// Mesh name ([`GearSystem::mesh_name`]).
    pub name: String,
    /// Label `n-p-q-r-s` of this mesh (`n` the system's period), or the class word.
    pub label: String,
    /// Counts `p, q, r, s` (as [`Summary::counts`]).
    pub counts: [u32; 4],
    /// Crossings per excitation period.
    pub rates: [f64; 4],
    /// Periodic without back-side contact or impact at this mesh.
    pub healthy: bool,
    /// Dynamic instability proportion of this mesh.
    pub p_id: f64,
    /// Maximum mesh force.
    pub max_force: f64,
    /// Minimum mesh force.
    pub min_force: f64,
    /// Back-side impacts over the recorded periods.
    pub impacts: u64,
    /// Largest impact force over the recorded periods.
    pub max_impact_force: f64,
}

impl Summary {
    /// Sets the decided motion class (a non-periodic one) and rewrites the label's class word.
    pub fn set_motion(&mut self, motion: Motion) {
        if !self.motion.is_periodic() && !motion.is_periodic() {
            self.label = motion.word().to_string();
            for m in &mut self.meshes {
                m.label = motion.word().to_string();
            }
        }
        self.motion = motion;
    }

    /// The decision for people ([`Motion::describe`]), saying so when the work budget ended it.
    pub fn describe(&self) -> String {
        match (&self.motion, self.decided_by) {
            (Motion::Unsettled { tle, stderr }, DecidedBy::Budget) => format!(
                "unsettled: the work budget (decision_budget) ran out, or could not pay for the escape test a chaotic verdict needs, after {} periods, before a period appeared or the decision horizon (decision_periods) was reached; TLE {}",
                self.periods_integrated,
                match (tle, stderr) {
                    (Some(t), Some(s)) => format!("{t:.4} ± {s:.4}"),
                    _ => "not computed".into(),
                }
            ),
            (m, _) => m.describe(),
        }
    }

    /// `healthy`, or why not: `non-healthy (back-side contact)` / `non-healthy (not periodic)`.
    /// The seeds' word for non-healthy motions is "unstable"; it does not mean dynamically
    /// unstable (docs/analyses.md).
    pub fn health_text(&self) -> &'static str {
        health_text(self.healthy, self.period > 0)
    }
}

/// See [`Summary::health_text`].
pub fn health_text(healthy: bool, periodic: bool) -> &'static str {
    if healthy {
        "healthy"
    } else if periodic {
        "non-healthy (back-side contact)"
    } else {
        "non-healthy (not periodic)"
    }
}

fn lcm(a: usize, b: usize) -> usize {
    fn gcd(a: usize, b: usize) -> usize {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }
    a / gcd(a, b) * b
}

/// Period, label, healthy flag and P_ID of a simulation.
pub fn summarize<S: GearSystem<N>, const N: usize>(
    sys: &S,
    res: &SimResult<N>,
    opts: &SimOptions,
) -> Summary {
    summarize_tol(sys, res, opts, opts.method.period_tol())
}

/// As [`summarize`], with relative period-test tolerance `period_tol` (the classification uses a
/// looser one only for motions whose Lyapunov exponent shows them attracting:
/// `crate::classify`).
pub fn summarize_tol<S: GearSystem<N>, const N: usize>(
    sys: &S,
    res: &SimResult<N>,
    opts: &SimOptions,
    period_tol: f64,
) -> Summary {
    let pts = res.strobe_states();
    let period = minimal_period_tol(&pts, opts.max_period, period_tol).unwrap_or(0);
    let cycles = sys.cycles_per_period() as usize;
    // The excitation strobe is exact (integrator stops); the mesh-cycle strobe is interpolated.
    // The mesh period is the smallest divisor m of period*cycles at which the mesh strobe
    // repeats to ten times the period tolerance (the interpolant's accuracy), so the two clocks
    // never contradict each other.
    let mesh_period = if cycles > 1 && period > 0 {
        let whole = period * cycles;
        let pts = &res.mesh_strobe;
        let scale = 1.0
            + pts
                .iter()
                .flat_map(|p| p.iter())
                .fold(0.0f64, |m, v| m.max(v.abs()));
        // a hundred times the period tolerance: on the broken pair's 3-60-0 orbit (omega 1.2,
        // F 0.1-0.11) the interpolated strobe repeats after 6 cycles to 2e-6-9e-6 (other shifts:
        // 0.8), and ten times read 6, 60 or 120 cycles at neighbouring loads
        let tol = 100.0 * opts.method.period_tol() * scale;
        (1..=whole)
            .filter(|&m| whole.is_multiple_of(m))
            .find(|&m| {
                pts.len() >= 2 * m
                    && (m..pts.len()).all(|j| {
                        pts[j]
                            .iter()
                            .zip(&pts[j - m])
                            .fold(0.0, |s, (a, b)| s + (a - b).abs())
                            <= tol
                    })
            })
            .or(Some(whole))
    } else {
        None
    };
    // The two clocks agree: a mesh strobe that repeats after m mesh cycles repeats the excitation
    // strobe after lcm(m, cycles) / cycles periods. When that is a proper divisor of the period
    // found, the excitation strobe test failed the shorter period on the integrator's noise
    // (many events per period, as on the breakage pair) and the shorter one is the period.
    let period = match mesh_period {
        Some(m) if period > 0 => {
            let p = lcm(m, cycles) / cycles;
            if p < period && period.is_multiple_of(p) {
                p
            } else {
                period
            }
        }
        _ => period,
    };
    summary_of_period(sys, res, opts, period, mesh_period)
}

/// The summary of a record of the orbit of `period` excitation periods, known by other means
/// (shooting: [`crate::orbits`]): the record is read as that orbit (its last `period` periods
/// give the counts) whatever the period test would say of a record this short.
pub fn summarize_orbit<S: GearSystem<N>, const N: usize>(
    sys: &S,
    res: &SimResult<N>,
    opts: &SimOptions,
    period: usize,
) -> Summary {
    summary_of_period(sys, res, opts, period, None)
}

/// The summary of a record whose period (0: none) is `period`.
fn summary_of_period<S: GearSystem<N>, const N: usize>(
    sys: &S,
    res: &SimResult<N>,
    opts: &SimOptions,
    period: usize,
    mesh_period: Option<usize>,
) -> Summary {
    let meshes: Vec<MeshSummary> = res
        .meshes
        .iter()
        .enumerate()
        .map(|(k, m)| mesh_summary(sys, k, m, period))
        .collect();
    let motion = if period > 0 {
        Motion::Periodic { period }
    } else {
        Motion::default()
    };
    let decided_by = if period > 0 {
        DecidedBy::PeriodTest
    } else {
        DecidedBy::Undecided
    };
    let periods_integrated = opts.transient_periods + res.strobe.len() as u64;
    if let [m] = &meshes[..] {
        return Summary {
            period,
            mesh_period,
            motion,
            label: m.label.clone(),
            counts: m.counts,
            rates: m.rates,
            healthy: m.healthy,
            p_id: m.p_id,
            max_force: m.max_force,
            min_force: m.min_force,
            impacts: m.impacts,
            max_impact_force: m.max_impact_force,
            periods_integrated,
            decided_by,
            escape: None,
            meshes: Vec::new(),
        };
    }
    let label = if period > 0 {
        meshes
            .iter()
            .map(|m| m.label.as_str())
            .collect::<Vec<_>>()
            .join(" ")
    } else {
        motion.word().to_string()
    };
    let mut counts = [0u32; 4];
    let mut rates = [0.0; 4];
    for m in &meshes {
        for i in 0..4 {
            counts[i] += m.counts[i];
            rates[i] += m.rates[i];
        }
    }
    let n = meshes.len().max(1) as f64;
    Summary {
        period,
        mesh_period,
        motion,
        label,
        counts,
        rates,
        healthy: meshes.iter().all(|m| m.healthy),
        p_id: meshes.iter().map(|m| m.p_id).sum::<f64>() / n,
        max_force: meshes
            .iter()
            .map(|m| m.max_force)
            .fold(f64::NEG_INFINITY, f64::max),
        min_force: meshes
            .iter()
            .map(|m| m.min_force)
            .fold(f64::INFINITY, f64::min),
        impacts: meshes.iter().map(|m| m.impacts).sum(),
        max_impact_force: meshes
            .iter()
            .map(|m| m.max_impact_force)
            .fold(0.0, f64::max),
        periods_integrated,
        decided_by,
        escape: None,
        meshes,
    }
}

/// The summary of mesh `k`'s record, the system's period being `period` (0: none).
fn mesh_summary<S: GearSystem<N>, const N: usize>(
    sys: &S,
    k: usize,
    res: &MeshRecord,
    period: usize,
) -> MeshSummary {
    let counts = if period > 0 && res.counts_per_period.len() >= period {
        let mut c = [0u32; 4];
        for row in &res.counts_per_period[res.counts_per_period.len() - period..] {
            for i in 0..4 {
                c[i] += row[i];
            }
        }
        c
    } else {
        // not periodic: totals over the record (the label gives them per period); rounded
        // per-period means would read 0 for a crossing every third period
        let mut c = [0u32; 4];
        for i in 0..4 {
            c[i] = res.counts_per_period.iter().map(|r| r[i]).sum();
        }
        c
    };
    let (dd, ds) = sys.backlash_levels(k);
    let n_lv = if dd == ds { 2 } else { 4 };
    let label = if period > 0 {
        let parts: Vec<String> = counts[..n_lv].iter().map(|c| c.to_string()).collect();
        format!("{}-{}", period, parts.join("-"))
    } else {
        Motion::default().word().to_string()
    };
    let per = if period > 0 {
        period
    } else {
        res.counts_per_period.len().max(1)
    } as f64;
    let rates = counts.map(|c| f64::from(c) / per);
    let [t_drive, t_sep, t_back] = res.durations;
    let total = t_drive + t_sep + t_back;
    let any_back = t_back > 0.0 || res.impacts > 0 || counts[1] > 0 || counts[3] > 0;
    MeshSummary {
        name: sys.mesh_name(k),
        label,
        counts,
        rates,
        healthy: period > 0 && !any_back,
        p_id: if total > 0.0 {
            (t_sep + t_back) / total
        } else {
            0.0
        },
        max_force: res.max_force,
        min_force: res.min_force,
        impacts: res.impacts,
        max_impact_force: res
            .impact_force_per_period
            .iter()
            .cloned()
            .fold(0.0, f64::max),
    }
}
