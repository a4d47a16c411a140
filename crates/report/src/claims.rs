//! Claims of the seeds and their verdicts.
//!
//! One row per statement: where the seeds state a thing twice differently, each statement gets
//! its own row. Verdicts:
//!
//! * `reproduced` — the measurement shows what the statement says;
//! * `partly` — the main part holds, a detail (a number, a boundary, a label) differs;
//! * `not reproduced` — the measurement contradicts it; the evidence says what was found and why
//!   it differs;
//! * `seed inconsistent` — the statement contradicts another statement of the seeds (or itself)
//!   and the measurement sides with the other; the evidence names the other statement.

use anyhow::Result;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Verdict of a claim.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Verdict {
    /// The data show it.
    #[serde(rename = "reproduced")]
    Reproduced,
    /// The main part holds, a detail differs.
    #[serde(rename = "partly")]
    Partly,
    /// The data contradict it (the evidence says why).
    #[serde(rename = "not reproduced")]
    NotReproduced,
    /// The seeds contradict themselves; the data side with the other statement.
    #[serde(rename = "seed inconsistent")]
    SeedInconsistent,
}

impl Verdict {
    /// Every verdict, in display order.
    pub const ALL: [Verdict; 4] = [
        Verdict::Reproduced,
        Verdict::Partly,
        Verdict::NotReproduced,
        Verdict::SeedInconsistent,
    ];

    /// The word used in the table.
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Partly => "partly",
            Verdict::NotReproduced => "not reproduced",
            Verdict::SeedInconsistent => "seed inconsistent",
        }
    }

    /// `reproduced` if all hold, `partly` if some, else `not reproduced`.
    pub fn of_parts(parts: &[bool]) -> Verdict {
        let n = parts.iter().filter(|&&b| b).count();
        if n == parts.len() {
            Verdict::Reproduced
        } else if n > 0 {
            Verdict::Partly
        } else {
            Verdict::NotReproduced
        }
    }

    /// `reproduced` if `ok`, else `not reproduced`.
    pub fn of(ok: bool) -> Verdict {
        if ok {
            Verdict::Reproduced
        } else {
            Verdict::NotReproduced
        }
    }
}

/// Longest evidence of a claim (characters): a few sentences, details in the study's CSV files.
pub const EVIDENCE_MAX: usize = 400;

/// A statement of the seeds checked against the data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Claim {
    /// The statement, in the seed's words where possible.
    pub claim: String,
    /// The seed file and figure/table/section it comes from.
    pub source: String,
    /// The reading of the seed text it was measured under
    /// (`Interpretation::label`; every axis of the seed).
    #[serde(default)]
    pub interpretation: String,
    /// What the seed gives (number, interval, label).
    pub seed_value: String,
    /// What geardyn measures.
    pub measured_value: String,
    /// The verdict.
    pub verdict: Verdict,
    /// How it was measured, and why it differs when it does.
    pub evidence: String,
}

impl Claim {
    /// A claim.
    pub fn new(
        claim: impl Into<String>,
        source: impl Into<String>,
        seed_value: impl Into<String>,
        measured_value: impl Into<String>,
        verdict: Verdict,
        evidence: impl Into<String>,
    ) -> Claim {
        // the seed's value and the measured one have their own columns: the evidence says how it
        // was measured and why it differs, in a few sentences (details in the study's CSV files)
        let (seed_value, measured_value) = (seed_value.into(), measured_value.into());
        let evidence: String = evidence.into();
        Claim {
            claim: claim.into(),
            source: source.into(),
            interpretation: String::new(),
            seed_value,
            measured_value,
            verdict,
            evidence,
        }
    }
}

/// Statements of the seeds about the same thing that disagree with each other (`group`: their
/// claim texts): when one of them is reproduced, each other one that is not becomes
/// `seed inconsistent`, and its evidence names the statement the data side with.
pub fn resolve_conflicts(claims: &mut [Claim], group: &[&str]) {
    let Some(winner) = claims
        .iter()
        .find(|c| group.contains(&c.claim.as_str()) && c.verdict == Verdict::Reproduced)
        .map(|c| format!("{} ({})", c.claim, c.source))
    else {
        return;
    };
    for c in claims.iter_mut() {
        if group.contains(&c.claim.as_str())
            && matches!(c.verdict, Verdict::Partly | Verdict::NotReproduced)
        {
            c.verdict = Verdict::SeedInconsistent;
            c.evidence = format!(
                "The seeds state this differently elsewhere; the data reproduce: {winner}. {}",
                c.evidence
            );
        }
    }
}

/// The columns of `claims.csv` and `claims_by_interpretation.csv`.
pub const COLUMNS: [&str; 7] = [
    "claim",
    "source",
    "interpretation",
    "seed_value",
    "measured_value",
    "verdict",
    "evidence",
];

/// Writes `claims.csv` (or `claims_by_interpretation.csv`).
pub fn write_csv(path: &Path, claims: &[&Claim]) -> Result<()> {
    geardyn_io::output::write_csv(
        path,
        &COLUMNS,
        claims.iter().map(|c| {
            vec![
                c.claim.clone(),
                c.source.clone(),
                c.interpretation.clone(),
                c.seed_value.clone(),
                c.measured_value.clone(),
                c.verdict.word().to_string(),
                c.evidence.clone(),
            ]
        }),
    )?;
    Ok(())
}

/// Counts per verdict, in [`Verdict::ALL`] order.
pub fn tally(claims: &[&Claim]) -> [usize; 4] {
    let mut n = [0; 4];
    for c in claims {
        let i = Verdict::ALL
            .iter()
            .position(|v| *v == c.verdict)
            .unwrap_or(0);
        n[i] += 1;
    }
    n
}
