//! Helpers shared by the integration tests.

/// `f` run on a rayon pool of `threads` threads (the thread-count invariance tests).
pub fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// The unforced damped double-well Duffing oscillator `x'' + 0.25 x' - x + x^3 = 0` strobed
/// every 2 time units (DP5): two point attractors `(+-1, 0)`, symmetric under `(x, v) -> (-x, -v)`
/// (the basin tests).
pub fn double_well() -> geardyn_analysis::attractor::StrobeOnly<geardyn_model::reference::Duffing> {
    geardyn_analysis::attractor::StrobeOnly {
        sys: geardyn_model::reference::Duffing {
            delta: 0.25,
            alpha: -1.0,
            beta: 1.0,
            gamma: 0.0,
            omega: 1.0,
        },
        period: 2.0,
        scheme: geardyn_solvers::Scheme::dopri_default(),
    }
}
