//! The vibration signals of a pair (and of its healthy twin) as a job.

use super::{settings_of, RequestJob};
use crate::job::ExecError;
use geardyn_analysis::signals::{run_signals, SignalsRequest, SignalsResult};

/// The signals of `request` from `scenario` (the pair, broken or healthy): one item, one result.
pub type SignalsJob<'a> = RequestJob<'a, SignalsRequest>;

job! {
    impl[] SignalsJob<'_>: "signals", SignalsResult => SignalsResult, steps 1;
    settings(j) settings_of(j.request);
    run(j, on_done) {
        let r = run_signals(j.scenario, j.request).map_err(ExecError::analysis)?;
        on_done(&r);
        Ok(r)
    }
}
