//! The analysis crate's integration tests, one module per subject, in one test binary: one link
//! and one copy of the engines the tests instantiate, instead of nineteen. `cancel.rs` stays
//! apart: it raises the process-wide stop flag, which would cut the other tests' runs short.

mod attractor_identity;
mod basins;
mod basins_resume;
mod bifurcation;
mod classification;
mod common;
mod contact_memory;
mod continuation;
mod decision_horizon;
mod escape;
mod generic;
mod impact_range;
mod invariants;
mod lanes;
mod lanes_tle;
mod lyapunov;
mod lyapunov_memory;
mod mesh_model;
mod orbits;
mod orbits_system;
mod shards;
mod strobe_only;
mod system;
mod trains;
