//! Periodic orbits (one orbit, or a branch continued over a parameter) as a job.

use super::{settings_of, RequestJob};
use crate::job::ExecError;
use geardyn_analysis::orbit_branches::{BranchPoint, Continuation};
use geardyn_analysis::orbits_request::{run_orbits, OrbitsRequest};

/// The orbits of `request` from `scenario`: one result; the observer sees each orbit of the
/// branch as it is found (the total is not known in advance: it starts at 0).
pub type OrbitsJob<'a> = RequestJob<'a, OrbitsRequest>;

job! {
    impl[] OrbitsJob<'_>: "orbits", BranchPoint => Continuation, steps 0;
    settings(j) settings_of(j.request);
    // a branch is one Newton-continued chain: not resumed point by point
    run(j, on_done) run_orbits(j.scenario, j.request, on_done).map_err(ExecError::analysis)
}
