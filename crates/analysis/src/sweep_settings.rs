//! What a sweep records and from where it starts: the Poincaré sections of a run ([`Section`]),
//! the sweep's mode (fixed initial state, continuation, multi-initial with its box of initial
//! states: [`SweepMode`], [`InitialBox`]) and their checks.

use crate::simulate::Level;
use rand::Rng;
use serde::{Deserialize, Serialize};

/// An unknown section name ([`Section::parse_list`]).
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("unknown section '{0}': allowed {list}", list = Section::ALL.map(Section::name).join(", "))]
pub struct SectionError(pub String);

/// A Poincaré section of the bifurcation diagram.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Section {
    /// Stroboscopic: once per excitation period.
    Strobe,
    /// `x = D_s` upward.
    DsUp,
    /// `x = -D_s` downward.
    DsDown,
    /// `x = D_d` upward.
    DdUp,
    /// `x = -D_d` downward.
    DdDown,
    /// Back-side impacts (state before the impact).
    Impact,
}

impl Section {
    /// All sections.
    pub const ALL: [Section; 6] = [
        Section::Strobe,
        Section::DsUp,
        Section::DsDown,
        Section::DdUp,
        Section::DdDown,
        Section::Impact,
    ];
    /// Name used on the command line and in CSV.
    pub fn name(self) -> &'static str {
        match self {
            Section::Strobe => "strobe",
            Section::DsUp => "ds_up",
            Section::DsDown => "ds_down",
            Section::DdUp => "dd_up",
            Section::DdDown => "dd_down",
            Section::Impact => "impact",
        }
    }
    /// Parses a name.
    pub fn parse(s: &str) -> Option<Section> {
        Section::ALL.into_iter().find(|x| x.name() == s)
    }
    /// Parses a list of names (`--sections strobe,ds_up` split at the commas; Python's
    /// `sections`), each trimmed of spaces; an unknown name is refused with the allowed ones.
    ///
    /// ```
    /// use geardyn_analysis::bifurcation::Section;
    /// assert_eq!(Section::parse_list(["strobe", " impact"]).unwrap(), [Section::Strobe, Section::Impact]);
    /// assert!(Section::parse_list(["nope"]).unwrap_err().to_string().starts_with("unknown section 'nope'"));
    /// ```
    pub fn parse_list<'a>(
        names: impl IntoIterator<Item = &'a str>,
    ) -> Result<Vec<Section>, SectionError> {
        names
            .into_iter()
            .map(|t| Section::parse(t.trim()).ok_or_else(|| SectionError(t.to_string())))
            .collect()
    }
    pub(crate) fn of_level(l: Level) -> Section {
        match l {
            Level::DsUp => Section::DsUp,
            Level::DsDown => Section::DsDown,
            Level::DdUp => Section::DdUp,
            Level::DdDown => Section::DdDown,
        }
    }
}

/// How initial states are chosen.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "mode", rename_all = "snake_case")]
pub enum SweepMode {
    /// Every value from the same initial state.
    Fixed,
    /// Continuation: each value starts from the final state of the previous one, in both
    /// directions (branches `up` and `down`).
    Sweep,
    /// `ics` initial states per value, uniformly random in the box `x0_range x v0_range` from a
    /// generator seeded by `(seed, value index, ic index)`.
    Multi {
        /// Initial states per value.
        ics: usize,
        /// Seed.
        seed: u64,
        /// Range of `x0`.
        x0_range: (f64, f64),
        /// Range of `v0`.
        v0_range: (f64, f64),
    },
}

/// Largest number of initial states per value of a multi-initial sweep or a continuation.
pub const MAX_ICS: usize = 100_000;

/// A sweep mode or initial-state setting out of range ([`SweepMode::from_name`], [`check_ics`]).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ModeError {
    /// An unknown mode name.
    #[error("bad mode '{0}': allowed fixed, sweep, multi")]
    Name(String),
    /// Initial states per value out of range.
    #[error("bad ics {0}: allowed 1 ..= {MAX_ICS} (initial states per value)")]
    Ics(usize),
    /// A box of initial states that is not a finite interval.
    #[error("bad {name} ({}, {}): finite MIN <= MAX", geardyn_model::error::num(.range.0), geardyn_model::error::num(.range.1))]
    Range {
        /// `x0_range` or `v0_range`.
        name: &'static str,
        /// The interval given.
        range: (f64, f64),
    },
}

/// Checks a number of initial states per value (`1 ..= MAX_ICS`).
pub fn check_ics(ics: usize) -> Result<usize, ModeError> {
    if (1..=MAX_ICS).contains(&ics) {
        Ok(ics)
    } else {
        Err(ModeError::Ics(ics))
    }
}

fn check_range(name: &'static str, r: (f64, f64)) -> Result<(f64, f64), ModeError> {
    if r.0.is_finite() && r.1.is_finite() && r.0 <= r.1 {
        Ok(r)
    } else {
        Err(ModeError::Range { name, range: r })
    }
}

/// The random initial states of every parameter value, checked and defaulted: those of a
/// multi-initial sweep ([`SweepMode::Multi`]) and of an attractor continuation
/// (`crate::continuation::ContinuationOptions`). Dimensionless: `x0` in backlash units `b_c`,
/// `v0` in `b_c omega_n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialBox {
    /// Initial states per value, `1 ..= MAX_ICS`.
    pub ics: usize,
    /// Seed of the generator (with the value index and the state index).
    pub seed: u64,
    /// `x0` interval, finite, `MIN <= MAX`.
    pub x0_range: (f64, f64),
    /// `v0` interval, finite, `MIN <= MAX`.
    pub v0_range: (f64, f64),
}

impl InitialBox {
    /// The box of `ics` initial states per value ([`check_ics`]) drawn with `seed` from
    /// `x0_range` x `v0_range`, each by default that of the [`attractor_region`] of the largest
    /// half backlash `d_max` — the one place the CLI (`--ics`, `--x0-range`, `--v0-range`) and
    /// Python (`ics`, `x0_range`, `v0_range`) check and default them. The error names the field
    /// and its allowed range.
    ///
    /// ```
    /// use geardyn_analysis::bifurcation::{attractor_region, InitialBox};
    /// let b = InitialBox::new(8, 1, None, Some((-1.0, 1.0)), 0.5).unwrap();
    /// assert_eq!((b.x0_range, b.v0_range), (attractor_region(0.5).0, (-1.0, 1.0)));
    /// assert!(InitialBox::new(0, 1, None, None, 0.5).is_err());
    /// assert!(InitialBox::new(8, 1, Some((1.0, 0.0)), None, 0.5).is_err());
    /// ```
    pub fn new(
        ics: usize,
        seed: u64,
        x0_range: Option<(f64, f64)>,
        v0_range: Option<(f64, f64)>,
        d_max: f64,
    ) -> Result<Self, ModeError> {
        let region = attractor_region(d_max);
        Ok(InitialBox {
            ics: check_ics(ics)?,
            seed,
            x0_range: check_range("x0_range", x0_range.unwrap_or(region.0))?,
            v0_range: check_range("v0_range", v0_range.unwrap_or(region.1))?,
        })
    }
}

impl SweepMode {
    /// The mode named `name` (`fixed`, `sweep` or `multi`) — the one place the CLI and the Python
    /// module turn their options into a mode. For `multi`: the [`InitialBox`] of `ics`, `seed`,
    /// `x0_range`, `v0_range` and `d_max`. A range given is checked whatever the mode (a box
    /// that is no interval is a mistake even where it is not used).
    pub fn from_name(
        name: &str,
        ics: usize,
        seed: u64,
        x0_range: Option<(f64, f64)>,
        v0_range: Option<(f64, f64)>,
        d_max: f64,
    ) -> Result<Self, ModeError> {
        for (field, range) in [("x0_range", x0_range), ("v0_range", v0_range)] {
            if let Some(r) = range {
                check_range(field, r)?;
            }
        }
        match name {
            "fixed" => Ok(SweepMode::Fixed),
            "sweep" => Ok(SweepMode::Sweep),
            "multi" => {
                let b = InitialBox::new(ics, seed, x0_range, v0_range, d_max)?;
                Ok(SweepMode::Multi {
                    ics: b.ics,
                    seed: b.seed,
                    x0_range: b.x0_range,
                    v0_range: b.v0_range,
                })
            }
            other => Err(ModeError::Name(other.to_string())),
        }
    }
}

/// Default region `(x0_range, v0_range)` of the initial states that look for coexisting
/// attractors (multi-initial sweeps, attractor continuation, the report's coexistence studies):
/// `x0` in `+-(D + 3 l)`, `v0` in `+-3 l`, with `d_max` = `D` the largest half backlash of the
/// period ([`MeshModel::backlash_levels`]) and `l = max(D, 1)` (dimensionless: lengths in `b_c`,
/// velocities in `b_c omega_n`).
///
/// Why so wide: the attractors, not the backlash, set the scale. On the broken pair at
/// `omega` = 1.2, `F` = 0.07 an impacting `1-40-40` orbit coexists with the healthy `1-20-0`
/// one; it spans `x` in `[-1, 3.82]`, `x'` in `[-2.88, 2.43]` and its basin lies at `x0 > 1.7`:
/// 16 random starts found it 0 times in `+-1.5 x +-1` (the former default) and in
/// `+-2 x +-1.5`, 4 times in `+-3 x +-3`. The region holds that orbit whole.
pub fn attractor_region(d_max: f64) -> ((f64, f64), (f64, f64)) {
    let d = d_max;
    let l = 3.0 * d.max(1.0);
    ((-(d + l), d + l), (-l, l))
}

/// A random initial state in `x0_range` x `v0_range` that the model can start from
/// (`admissible`, [`geardyn_solvers::HybridSystem::admissible`]): drawn again from the same
/// stream while it lies behind a rigid stop. The states are then uniform over the admissible part
/// of the box, and shares of initial states count each state once (a state behind the stop
/// would start from its projection onto the stop: a line of states drawn with the weight of an
/// area). After [`MAX_DRAWS`] refused draws (a box wholly behind the stop) the last one is kept.
pub fn draw_state(
    rng: &mut impl Rng,
    x0_range: (f64, f64),
    v0_range: (f64, f64),
    admissible: impl Fn(&[f64; 2]) -> bool,
) -> [f64; 2] {
    let mut y = [0.0; 2];
    for _ in 0..MAX_DRAWS {
        y = [
            rng.gen_range(x0_range.0..=x0_range.1),
            rng.gen_range(v0_range.0..=v0_range.1),
        ];
        if admissible(&y) {
            break;
        }
    }
    y
}

/// Refuses a box of initial states with no state of the model in it: its largest `x0` (the
/// state of the box that leaves a rigid back stop last) must be `admissible`. Then
/// [`draw_state`] finds one (a box whose admissible part is too thin for [`MAX_DRAWS`] draws
/// keeps a draw behind the stop, which the model projects onto it).
pub fn check_box(
    x0_range: (f64, f64),
    v0_range: (f64, f64),
    admissible: impl Fn(&[f64; 2]) -> bool,
) -> Result<(), String> {
    if admissible(&[x0_range.1, v0_range.0]) || admissible(&[x0_range.1, v0_range.1]) {
        Ok(())
    } else {
        Err(format!(
            "x0_range [{}, {}] lies wholly behind the rigid back stop (x0 < -D): no initial state in it is a state of the model; give a range reaching in front of the stop",
            x0_range.0, x0_range.1
        ))
    }
}

/// Most draws of [`draw_state`].
pub const MAX_DRAWS: usize = 1000;
