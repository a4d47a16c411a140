//! The verdict on a motion: its class ([`Motion`]: periodic, chaotic, transient chaos, quasi-periodic,
//! unsettled, diverged, failed), the evidence that decided it ([`DecidedBy`]), and the default
//! decision settings (horizon, work budget, the resolution of the follow) that
//! [`crate::simulate::SimOptions`] carries. The rules that reach a verdict are
//! [`crate::classify`].

use serde::{Deserialize, Serialize};

/// A motion whose `|x|` exceeds this many length scales `max(D_s, 1)` has run away (teeth that
/// never meet under a constant load, an unbounded resonance): it is reported as diverged.
pub const DIVERGED_SCALES: f64 = 1e3;
/// Default decision horizon ([`crate::simulate::SimOptions::decision_periods`], excitation periods from the start
/// of a run): a motion with a positive exponent is called chaotic only when it is still not
/// periodic after this many periods. Measured chaotic transients (docs/analyses.md, rule 2;
/// `crates/analysis/examples/transient_lifetimes.rs`) lasted up to 6 965 periods on case C1
/// (`omega` = 1.4271, from rest) and 6 090 revolutions on the broken pair (`omega` = 1.2,
/// `F` = 0.065); the horizon lies above both.
pub const DECISION_PERIODS: u64 = 10_000;
/// Default work budget of one run's decision ([`crate::simulate::SimOptions::decision_budget`]): right-hand-side
/// evaluations in all (the integrators' unit of work: 4 per RK4 step, 6 per DP5 step, plus event
/// location), counted from the start of the run. Measured need: the broken pair at `omega` = 1.2
/// follows 10 000 revolutions in ~170 M evaluations with DP5 and ~820 M with RK4 at 512 steps per
/// cycle, C1 10 000 periods in ~21 M with DP5 and ~3 M with the follow ([`crate::pair_engine::follow_method`]); the
/// budget lies above them. Work per excitation period grows at low frequencies (the broken pair
/// at `omega` = 0.1: ~120 000 per copy and revolution in the escape test's lanes), where the
/// escape test needs ~2.4 10^9 (16 copies x 1 252 revolutions): the budget pays for it (the run is
/// decided chaotic in ~30 s on 2 cores; at 10^9 it was `unsettled`) and still ends a decision
/// that would take ten minutes: such a run is `unsettled` (decided by `budget`), never chaotic.
pub const DECISION_BUDGET: u64 = 3_000_000_000;
/// Largest [`crate::simulate::SimOptions::decision_budget`] accepted (about a day of one core per
/// run).
pub const MAX_DECISION_BUDGET: u64 = 1_000_000_000_000;

/// Default [`crate::simulate::SimOptions::follow_steps`]: fixed-step RK4 steps per natural period (`2 pi` of
/// dimensionless time) of a decision's follow. At `h <= 2 pi / 64` an RK4 step errs by about
/// `(h)^5 / 120 < 1e-7` of the state on the unit natural frequency; on W1 (C1, 200 values) the
/// verdicts came out as with RK4 512 but for one value whose transient ended inside the horizon
/// (docs/analyses.md, rule 2).
pub const FOLLOW_STEPS: u32 = 64;
/// [`crate::simulate::SimOptions::follow_steps`] accepted besides 0: below 16 steps per natural period RK4 leaves
/// its useful accuracy (and at about 2.2 its stability).
pub const FOLLOW_STEPS_RANGE: std::ops::RangeInclusive<u32> = 16..=1_000_000;
/// A TLE (per unit dimensionless time) is significantly positive when it exceeds both this and
/// three standard errors.
pub const TLE_POSITIVE: f64 = 1e-3;
/// An exponent `tle` (standard error `se`) that is positive beyond doubt: above
/// [`TLE_POSITIVE`] and three standard errors.
pub(crate) fn significantly_positive(tle: f64, se: f64) -> bool {
    tle > TLE_POSITIVE && tle > 3.0 * se
}

/// [`significantly_positive`] of `-tle`.
pub(crate) fn significantly_negative(tle: f64, se: f64) -> bool {
    significantly_positive(-tle, se)
}

/// The evidence that decided a run's class (`decided_by` in `summary.json` and runs tables).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DecidedBy {
    /// Periodic: the stroboscopic period test passed (on the first record or a later one).
    PeriodTest,
    /// Periodic: a significantly negative exponent, its period read at the loose tolerance.
    AttractingExponent,
    /// Chaotic: still not periodic at the decision horizon, and the exponent there significantly
    /// positive.
    PersistentChaos,
    /// Chaotic or transient chaos by the ensemble escape test ([`crate::escape`]): a positive
    /// exponent, and none (chaotic) or some (transient chaos) of the perturbed copies of the
    /// state reached a periodic orbit within the test.
    Escape,
    /// Chaotic on the exponents after the first record, with no persistence block: the
    /// persistence check was turned off, or the first record already reached the horizon (a
    /// transient of its own at least as long, or a horizon set below it).
    FirstExponent,
    /// Quasi-periodic: an exponent zero within its error after the extensions.
    ZeroExponent,
    /// Unsettled: the work budget ran out before the decision horizon.
    Budget,
    /// Unsettled: no period and no significant exponent (or no exponent at all).
    #[default]
    Undecided,
    /// Diverged: `|x|` ran away.
    Runaway,
    /// The integration failed.
    Error,
}

impl DecidedBy {
    /// The name written in outputs (`period_test`, `persistent_chaos`, ...).
    pub fn name(self) -> &'static str {
        match self {
            DecidedBy::PeriodTest => "period_test",
            DecidedBy::AttractingExponent => "attracting_exponent",
            DecidedBy::PersistentChaos => "persistent_chaos",
            DecidedBy::Escape => "escape",
            DecidedBy::FirstExponent => "first_exponent",
            DecidedBy::ZeroExponent => "zero_exponent",
            DecidedBy::Budget => "budget",
            DecidedBy::Undecided => "undecided",
            DecidedBy::Runaway => "runaway",
            DecidedBy::Error => "error",
        }
    }
}

/// What a motion is, decided from the evidence.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "class", rename_all = "snake_case")]
pub enum Motion {
    /// The stroboscopic points repeat with this minimal period (excitation periods).
    Periodic {
        /// Period in excitation periods.
        period: usize,
    },
    /// The top Lyapunov exponent is significantly positive.
    Chaotic {
        /// TLE per unit dimensionless time.
        tle: f64,
        /// Its standard error.
        stderr: f64,
    },
    /// Transient chaos: a positive exponent on a chaotic saddle that the motion leaves for a
    /// periodic orbit of this period (the ensemble escape test, [`crate::escape`]); the summary's
    /// label is that orbit's and [`crate::summary::Summary::escape`] holds the test.
    TransientChaos {
        /// Period of the orbit the motion settles on (excitation periods).
        period: usize,
        /// Mean lifetime on the saddle (excitation periods, maximum likelihood).
        lifetime: f64,
        /// Its standard error.
        lifetime_stderr: f64,
        /// TLE on the saddle (per unit dimensionless time).
        tle: f64,
    },
    /// No period after the extended transient, and a TLE of zero within its error.
    QuasiPeriodic {
        /// TLE per unit dimensionless time.
        tle: f64,
        /// Its standard error.
        stderr: f64,
    },
    /// Not decided: no period within the extended transient, TLE not significantly positive.
    Unsettled {
        /// TLE, when it was computed.
        tle: Option<f64>,
        /// Its standard error.
        stderr: Option<f64>,
    },
    /// The motion ran away: `|x|` grew beyond [`DIVERGED_SCALES`] length scales.
    Diverged {
        /// Largest `|x|` reached.
        x_max: f64,
    },
    /// The integration failed (the message says why).
    Failed {
        /// The error.
        reason: String,
    },
}

impl Default for Motion {
    fn default() -> Self {
        Motion::Unsettled {
            tle: None,
            stderr: None,
        }
    }
}

impl Motion {
    /// One word: `periodic`, `chaotic`, `quasi-periodic`, `unsettled`, `failed`.
    pub fn word(&self) -> &'static str {
        match self {
            Motion::Periodic { .. } => "periodic",
            Motion::Chaotic { .. } => "chaotic",
            Motion::TransientChaos { .. } => "transient-chaos",
            Motion::QuasiPeriodic { .. } => "quasi-periodic",
            Motion::Unsettled { .. } => "unsettled",
            Motion::Diverged { .. } => "diverged",
            Motion::Failed { .. } => "failed",
        }
    }

    /// Periodic in the long run? (A transient chaos is: it settles on a periodic orbit.)
    pub fn is_periodic(&self) -> bool {
        matches!(
            self,
            Motion::Periodic { .. } | Motion::TransientChaos { .. }
        )
    }

    /// The period of the motion in the long run (excitation periods), if periodic.
    pub fn period(&self) -> Option<usize> {
        match *self {
            Motion::Periodic { period } | Motion::TransientChaos { period, .. } => Some(period),
            _ => None,
        }
    }

    /// Chaotic?
    pub fn is_chaotic(&self) -> bool {
        matches!(self, Motion::Chaotic { .. })
    }

    /// A description for people: `period 2`, `chaotic (TLE 0.0512 ± 0.0011)`, ...
    pub fn describe(&self) -> String {
        match self {
            Motion::Periodic { period } => format!("period {period}"),
            Motion::Chaotic { tle, stderr } => format!("chaotic (TLE {tle:.4} ± {stderr:.4})"),
            Motion::TransientChaos {
                period,
                lifetime,
                lifetime_stderr,
                tle,
            } => format!(
                "transient chaos (TLE {tle:.4} on a chaotic saddle, mean lifetime {lifetime:.0} ± {lifetime_stderr:.0} excitation periods), then period {period}"
            ),
            Motion::QuasiPeriodic { tle, stderr } => {
                format!("quasi-periodic (TLE {tle:.4} ± {stderr:.4}, no period)")
            }
            Motion::Unsettled { tle, stderr } => match (tle, stderr) {
                (Some(t), Some(s)) => format!(
                    "unsettled: no period within the extended transient, TLE {t:.4} ± {s:.4} not significantly positive"
                ),
                _ => "unsettled: no period detected (not classified further)".into(),
            },
            Motion::Diverged { x_max } => format!(
                "diverged: |x| reached {} (more than {DIVERGED_SCALES} length scales max(D_s, 1))",
                geardyn_model::error::num(*x_max)
            ),
            Motion::Failed { reason } => format!("failed: {reason}"),
        }
    }
}
