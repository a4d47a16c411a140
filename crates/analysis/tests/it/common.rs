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

/// The parameters `params` with the named parameters `sets` set, in order
/// ([`geardyn_model::ModelParams::set`]).
pub fn set(
    mut params: geardyn_model::ModelParams,
    sets: &[(&str, f64)],
) -> geardyn_model::ModelParams {
    for &(name, value) in sets {
        params.set(name, value).unwrap();
    }
    params
}

/// The model of `params` with `sets` set ([`set`]).
pub fn model(params: geardyn_model::ModelParams, sets: &[(&str, f64)]) -> geardyn_model::MeshModel {
    geardyn_model::MeshModel::new(&set(params, sets)).unwrap()
}

/// The decided run of `model` from rest with the settings `opts` and the default decision (and
/// the settings it used).
pub fn decided(
    model: &geardyn_model::MeshModel,
    opts: &geardyn_analysis::simulate::SimOptions,
) -> (
    geardyn_analysis::simulate::SimResult<2>,
    geardyn_analysis::summary::Summary,
    geardyn_analysis::simulate::SimOptions,
) {
    geardyn_analysis::classify::simulate_decided(model, [0.0, 0.0], opts, Default::default())
        .unwrap()
}

/// [`decided`] with the default settings.
pub fn decided_from_rest(
    model: &geardyn_model::MeshModel,
) -> (
    geardyn_analysis::simulate::SimResult<2>,
    geardyn_analysis::summary::Summary,
    geardyn_analysis::simulate::SimOptions,
) {
    decided(model, &Default::default())
}

/// The two-mass toy with its clearances ([`geardyn_model::reference::TwoMassClearance`]) under
/// a light load at `omega = 0.5` and forcing amplitude `amplitude`: both meshes separate and
/// re-enter every period at 0.4, twice in a period-2 motion at 0.6.
pub fn rattling(amplitude: f64) -> geardyn_model::reference::TwoMassClearance {
    geardyn_model::reference::TwoMassClearance {
        load: [0.1, 0.05],
        amplitude,
        omega: 0.5,
        ..Default::default()
    }
}

/// The default simulation settings but `transient` and `record` periods.
pub fn periods(transient: u64, record: u64) -> geardyn_analysis::simulate::SimOptions {
    geardyn_analysis::simulate::SimOptions {
        transient_periods: transient,
        record_periods: record,
        ..Default::default()
    }
}

/// Identification with the default settings but `transient` and `record` periods.
pub fn identify_periods(
    transient: u64,
    record: u64,
) -> geardyn_analysis::attractor::IdentifyOptions {
    geardyn_analysis::attractor::IdentifyOptions {
        sim: periods(transient, record),
        ..Default::default()
    }
}

/// `runs` decided in the lanes on a pool of `threads` threads, each decision (unwrapped) read
/// by `read`.
pub fn decided_lanes_on<T: Send>(
    threads: usize,
    runs: &[(&geardyn_model::MeshModel, [f64; 2])],
    opts: &geardyn_analysis::simulate::SimOptions,
    read: impl Fn(
        geardyn_analysis::simulate::SimResult<2>,
        geardyn_analysis::summary::Summary,
        geardyn_analysis::simulate::SimOptions,
    ) -> T,
) -> Vec<T> {
    on_threads(threads, || {
        geardyn_analysis::lanes_decide::simulate_decided_lanes(runs, &lane(opts))
    })
    .into_iter()
    .map(|d| {
        let (r, s, used) = d.unwrap();
        read(r, s, used)
    })
    .collect()
}

/// Every model started from every initial state (model-major), as the lanes take runs.
pub fn runs_from<'a>(
    models: &'a [geardyn_model::MeshModel],
    ics: &[[f64; 2]],
) -> Vec<(&'a geardyn_model::MeshModel, [f64; 2])> {
    models
        .iter()
        .flat_map(|m| ics.iter().map(move |&y| (m, y)))
        .collect()
}

/// The default identification with fixed-step RK4 of `steps_per_cycle` steps per mesh cycle,
/// `transient` then `record` periods.
pub fn identify_rk4(
    steps_per_cycle: u32,
    transient: u64,
    record: u64,
) -> geardyn_analysis::attractor::IdentifyOptions {
    geardyn_analysis::attractor::IdentifyOptions {
        sim: geardyn_analysis::simulate::SimOptions::rk4(steps_per_cycle, transient, record),
        ..Default::default()
    }
}

/// The lifetime of a motion decided transient chaos by the escape test that then settles on the
/// orbit of `period` labelled `label`; panics on any other verdict.
pub fn transient_lifetime(
    s: &geardyn_analysis::simulate::Summary,
    period: usize,
    label: &str,
) -> f64 {
    let geardyn_analysis::verdict::Motion::TransientChaos {
        period: p,
        lifetime,
        ..
    } = s.motion
    else {
        panic!("{:?}", s.motion)
    };
    assert_eq!((p, s.label.as_str()), (period, label));
    assert_eq!(s.decided_by, geardyn_analysis::verdict::DecidedBy::Escape);
    lifetime
}

/// `o` checked for the lanes (the tests' settings are fixed-step RK4).
pub fn lane(o: &geardyn_analysis::simulate::SimOptions) -> geardyn_analysis::lanes::LaneSim {
    geardyn_analysis::lanes::LaneSim::new(o).unwrap()
}
