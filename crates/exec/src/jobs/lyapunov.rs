//! The top Lyapunov exponent of one motion as a job.

use super::settings_of;
use crate::job::ExecError;
use geardyn_analysis::lyapunov_request::{LyapunovReport, LyapunovRequest};
use geardyn_analysis::simulate::SimOptions;
use geardyn_analysis::tle_convergence::Round;
use geardyn_model::MeshModel;

/// The exponent of the motion from `y0`: one result; the observer sees each round of the
/// doubling run lengths as it ends.
pub struct LyapunovJob<'a> {
    /// The model.
    pub model: &'a MeshModel,
    /// Integration, transient and record settings.
    pub sim: &'a SimOptions,
    /// Initial state `[x, x']`.
    pub y0: [f64; 2],
    /// The request (checked when run).
    pub request: &'a LyapunovRequest,
}

job! {
    impl[] LyapunovJob<'_>: "lyapunov", Round => LyapunovReport, steps 0;
    settings(j) serde_json::json!({ "request": settings_of(j.request), "sim": settings_of(j.sim), "y0": j.y0 });
    run(j, on_done) j.request.run(j.model, j.sim, j.y0, |r| on_done(r)).map_err(ExecError::analysis)
}
