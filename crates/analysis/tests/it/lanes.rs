//! The lockstep ensemble against the scalar RK4 path: strobe points, final states and every
//! recorded quantity of `simulate` (crossings, counts, durations, extrema, integrals, events,
//! impacts) on case C1 and on the breakage preset.

use crate::common;
use crate::common::lane;

use geardyn_analysis::lanes::simulate_lanes;
use geardyn_analysis::simulate::{simulate, summarize, Method, SimOptions, SimResult};
use geardyn_model::{presets, MeshModel};
use geardyn_solvers::HybridSystem;

/// The first runs of a batch in the lanes with their summaries (what `decide_lanes` starts from).
type FirstRun<'m> = (
    &'m MeshModel,
    (SimResult, geardyn_analysis::simulate::Summary),
);
fn first_runs<'m>(runs: &[(&'m MeshModel, [f64; 2])], opts: &SimOptions) -> Vec<FirstRun<'m>> {
    simulate_lanes(runs, &lane(opts))
        .into_iter()
        .zip(runs)
        .map(|(r, &(m, _))| {
            let r = r.unwrap();
            let s = summarize(m, &r, opts);
            (m, (r, s))
        })
        .collect()
}

/// Case C1 at each `omega`.
fn c1_at(omegas: &[f64]) -> Vec<MeshModel> {
    omegas
        .iter()
        .map(|&w| {
            let mut p = presets::classic();
            p.omega = w;
            MeshModel::new(&p).unwrap()
        })
        .collect()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

/// The items of `a` and `b` side by side, asserted to be as many (`{what}: {name}` otherwise).
fn paired<'a, T>(
    a: &'a [T],
    b: &'a [T],
    what: &str,
    name: &str,
) -> impl Iterator<Item = (&'a T, &'a T)> {
    assert_eq!(a.len(), b.len(), "{what}: {name}");
    a.iter().zip(b)
}

/// Largest deviation between two results (states, times, totals), relative to `1 + |value|`.
fn compare(a: &SimResult, b: &SimResult, tol: f64, what: &str) -> f64 {
    let mut worst = 0.0f64;
    let mut check = |x: f64, y: f64, name: &str| {
        let d = (x - y).abs() / (1.0 + x.abs().max(y.abs()));
        worst = worst.max(d);
        assert!(d <= tol, "{what}: {name}: {x} vs {y} (rel {d:e})");
    };
    for (p, q) in paired(&a.strobe, &b.strobe, what, "strobe count") {
        for i in 0..3 {
            check(p[i], q[i], "strobe");
        }
    }
    assert_eq!(
        a.mesh().counts_per_period,
        b.mesh().counts_per_period,
        "{what}: counts"
    );
    for (p, q) in paired(&a.mesh().crossings, &b.mesh().crossings, what, "crossings") {
        assert_eq!(p.level, q.level);
        check(p.tau, q.tau, "crossing tau");
        check(p.v, q.v, "crossing v");
    }
    for (p, q) in paired(&a.mesh().events, &b.mesh().events, what, "events") {
        assert_eq!(p.kind, q.kind);
        check(p.tau, q.tau, "event tau");
        check(p.v_before, q.v_before, "event v");
        check(p.v_after, q.v_after, "event v after");
        check(p.peak_force, q.peak_force, "event peak force");
    }
    assert_eq!(a.mesh().impacts, b.mesh().impacts, "{what}: impacts");
    for (x, y) in a
        .mesh()
        .impact_force_per_period
        .iter()
        .zip(&b.mesh().impact_force_per_period)
    {
        check(*x, *y, "impact force");
    }
    for i in 0..3 {
        check(a.mesh().durations[i], b.mesh().durations[i], "durations");
    }
    for i in 0..4 {
        check(a.mesh().integrals[i], b.mesh().integrals[i], "integrals");
    }
    check(a.mesh().max_force, b.mesh().max_force, "max force");
    check(a.mesh().min_force, b.mesh().min_force, "min force");
    check(a.mesh().x_range.0, b.mesh().x_range.0, "x min");
    check(a.mesh().x_range.1, b.mesh().x_range.1, "x max");
    assert_eq!(
        a.mesh_strobe.len(),
        b.mesh_strobe.len(),
        "{what}: mesh strobe"
    );
    for (p, q) in a.mesh_strobe.iter().zip(&b.mesh_strobe) {
        check(p[0], q[0], "mesh strobe x");
        check(p[1], q[1], "mesh strobe v");
    }
    check(a.final_state.0, b.final_state.0, "final t");
    check(a.final_state.1[0], b.final_state.1[0], "final x");
    check(a.final_state.1[1], b.final_state.1[1], "final v");
    worst
}

/// Stroboscopic points of C1 from the lanes (RK4, 512 steps per mesh cycle, the affine map in
/// contact) against an independent solution: SciPy's DOP853 at rtol 1e-12 with the contact
/// surfaces located by its own event finder, written from the equations alone
/// (`tests/reference/c1_dop853.py`, which prints the table below). From rest: period-1 orbits
/// (omega 0.6, 0.8, 1.8, 2.0) and the period-2 orbit at 0.95, drive contact and separation; at
/// 1.8 also the coexisting period-3 orbit with back-side contact, from a start in its basin. The
/// lanes converge to the reference at fourth order (largest difference 1.7e-7, 1.1e-8, 6.6e-10,
/// 4.1e-11 at 128, 256, 512, 1024 steps per cycle), so the bound sits just above the 512-step
/// error: twice the step length fails it.
#[test]
fn lanes_strobe_points_match_an_independent_dop853_solution() {
    // (omega, x0, x0', period index j: tau = j 2 pi / omega, x, x')
    #[rustfmt::skip]
    const DOP853: [(f64, f64, f64, u32, f64, f64); 26] = [
        (0.6, 0.0, 0.0, 300, 0.16573028149162605, 0.07680992837479923),
        (0.6, 0.0, 0.0, 301, 0.16573028149175426, 0.07680992837476297),
        (0.6, 0.0, 0.0, 302, 0.1657302814918482, 0.0768099283747867),
        (0.6, 0.0, 0.0, 303, 0.16573028149160376, 0.0768099283748273),
        (0.8, 0.0, 0.0, 300, 0.5222350608331946, 0.03770987458280557),
        (0.8, 0.0, 0.0, 301, 0.5222350608335447, 0.03770987458287334),
        (0.8, 0.0, 0.0, 302, 0.5222350608331197, 0.03770987458289736),
        (0.8, 0.0, 0.0, 303, 0.522235060833253, 0.03770987458291408),
        (0.95, 0.0, 0.0, 300, 0.31539449600128433, 0.016074741397159288),
        (0.95, 0.0, 0.0, 301, 0.9646906654524359, 0.04815136477432116),
        (0.95, 0.0, 0.0, 302, 0.3153944960014137, 0.01607474139718404),
        (0.95, 0.0, 0.0, 303, 0.9646906654523945, 0.048151364774326966),
        (1.8, 0.0, 0.0, 300, 0.8325017730191151, 0.014857342910900776),
        (1.8, 0.0, 0.0, 301, 0.8325017730190151, 0.014857342909703732),
        (1.8, 0.0, 0.0, 302, 0.8325017730188523, 0.014857342910419836),
        (1.8, 0.0, 0.0, 303, 0.8325017730191584, 0.014857342910217891),
        (2.0, 0.0, 0.0, 300, 0.8442416621281409, 0.01416867551594559),
        (2.0, 0.0, 0.0, 301, 0.8442416621279961, 0.014168675516598374),
        (2.0, 0.0, 0.0, 302, 0.8442416621283729, 0.014168675516282252),
        (2.0, 0.0, 0.0, 303, 0.8442416621279587, 0.014168675516158781),
        (1.8, 0.7, -1.48, 600, -0.74625606150643, -0.8677097654441545),
        (1.8, 0.7, -1.48, 601, -1.3583554503602142, 0.9240261121052039),
        (1.8, 0.7, -1.48, 602, 1.9336731824950524, 0.18894464531729188),
        (1.8, 0.7, -1.48, 603, -0.7462560615060233, -0.8677097654441461),
        (1.8, 0.7, -1.48, 604, -1.3583554503601765, 0.9240261121056298),
        (1.8, 0.7, -1.48, 605, 1.9336731824952165, 0.18894464531734512),
    ];
    let mut cases: Vec<(f64, f64, f64)> = Vec::new();
    for &(w, x0, v0, ..) in &DOP853 {
        if !cases.contains(&(w, x0, v0)) {
            cases.push((w, x0, v0));
        }
    }
    let mut worst = 0.0f64;
    for (w, x0, v0) in cases {
        let rows: Vec<_> = DOP853
            .iter()
            .filter(|r| (r.0, r.1, r.2) == (w, x0, v0))
            .collect();
        let first = rows.iter().map(|r| r.3).min().unwrap();
        let last = rows.iter().map(|r| r.3).max().unwrap();
        let m = &c1_at(&[w])[0];
        let opts = SimOptions::rk4(512, first as u64 - 2, (last - first) as u64 + 4);
        let res = simulate_lanes(&[(m, [x0, v0])], &lane(&opts))
            .remove(0)
            .unwrap();
        let period = 2.0 * std::f64::consts::PI / w;
        for &&(_, _, _, j, x, v) in &rows {
            let p = res
                .strobe
                .iter()
                .find(|p| (p[0] - j as f64 * period).abs() < 1e-9 * period)
                .unwrap_or_else(|| panic!("omega {w}: no strobe point at period {j}"));
            let d = (p[1] - x).abs().max((p[2] - v).abs());
            assert!(
                d < 5e-9,
                "omega {w} from ({x0}, {v0}), period {j}: lanes ({}, {}) vs DOP853 ({x}, {v})",
                p[1],
                p[2]
            );
            worst = worst.max(d);
        }
    }
    eprintln!("C1 strobe points, lanes vs DOP853: largest difference {worst:.1e}");
}

/// C1, periodic orbits (period 1 and 2), three initial states each, 300 + 40 periods of 512 steps.
/// Agreement is relative to `1 + |value|`. Its floor is the scalar path's own resolution: event
/// times are located to `4 eps |t|` (4e-12 at `t ~ 4000`), and with damping only in contact the
/// field jumps at the contact surface, so a one-ulp difference in a step (table vs. evaluated
/// cosine) may move a located event by that much and the state by ~1e-13 per event; on these
/// orbits the lanes stay within 1e-12, or within four times that floor, measured here as the
/// deviation of the scalar path from itself when `y0` moves by 1e-15.
#[test]
fn c1_periodic_orbits_equal_the_scalar_rk4_path() {
    let omegas = [0.5, 0.6, 0.7, 0.8, 0.95, 1.7, 1.8, 1.9, 2.0];
    let models = c1_at(&omegas);
    let opts = SimOptions::rk4(512, 300, 40);
    let ics = [[0.0, 0.0], [1.3, -0.4], [-1.2, 0.8]];
    let runs = crate::common::runs_from(&models, &ics);
    let lanes = simulate_lanes(&runs, &lane(&opts));
    let mut worst = 0.0f64;
    for ((m, y0), r) in runs.iter().zip(&lanes) {
        let a = r.as_ref().unwrap();
        let b = simulate(m, *y0, &opts).unwrap();
        let sa = summarize(m, a, &opts);
        let sb = summarize(m, &b, &opts);
        assert!(sb.period > 0, "omega {} is periodic", m.params().omega);
        assert_eq!(
            (&sa.label, sa.period, sa.counts),
            (&sb.label, sb.period, sb.counts)
        );
        assert!(close(sa.p_id, sb.p_id, 1e-12) && close(sa.max_force, sb.max_force, 1e-12));
        // the scalar path's own floor: the same run from y0 moved by 1e-15
        let b2 = simulate(m, [y0[0] + 1e-15, y0[1]], &opts).unwrap();
        let floor = compare(&b2, &b, f64::INFINITY, "floor");
        let tol = (4.0 * floor).max(1e-12);
        let d = compare(a, &b, tol, &format!("omega {}", m.params().omega));
        eprintln!(
            "omega {}: lanes {d:.1e}, scalar floor {floor:.1e}",
            m.params().omega
        );
        worst = worst.max(d);
    }
    eprintln!("C1: largest relative deviation {worst:e}");
}

/// The breakage preset: 120 segment borders per excitation period (zones, pitch point, the
/// broken cycle), drive-side contacts and back-side impacts with restitution; every step with a
/// breakpoint or an event is finished by the scalar integrator. Its damping is light (c = 0.01,
/// quality factor ~100): the scalar path evaluates the excitation at the rounded time
/// `t0 + k*h` (an error of ~ulp(t)), the lanes at the exact phase, and the light damping
/// amplifies that rounding difference to ~1e-12..1e-11 over hundreds of mesh cycles, so the
/// comparison uses 1e-9 on settled motions (ω = 0.3, 0.4 periodic with contact events, 2.0
/// periodic with impacts, 3.0 without events).
#[test]
fn breakage_preset_equals_the_scalar_rk4_path() {
    let models: Vec<MeshModel> = [0.3, 0.4, 2.0, 3.0]
        .iter()
        .map(|&w| {
            let mut p = presets::breakage();
            p.omega = w;
            MeshModel::new(&p).unwrap()
        })
        .collect();
    let opts = SimOptions::rk4(64, 40, 8);
    let runs: Vec<(&MeshModel, [f64; 2])> = models
        .iter()
        .flat_map(|m| [[0.0, 0.0], [0.9, -0.5]].map(move |y| (m, y)))
        .collect();
    let lanes = simulate_lanes(&runs, &lane(&opts));
    let mut worst = 0.0f64;
    for ((m, y0), r) in runs.iter().zip(&lanes) {
        let a = r.as_ref().unwrap();
        let b = simulate(m, *y0, &opts).unwrap();
        worst = worst.max(compare(
            a,
            &b,
            1e-9,
            &format!("breakage omega {}", m.params().omega),
        ));
        let (sa, sb) = (summarize(m, a, &opts), summarize(m, &b, &opts));
        assert_eq!(sa.label, sb.label);
        assert_eq!(sa.period, sb.period);
        assert_eq!(sa.mesh_period, sb.mesh_period);
    }
    eprintln!("breakage: largest relative deviation {worst:e}");
}

#[test]
fn output_is_the_same_for_any_thread_count() {
    let models: Vec<MeshModel> = (0..13)
        .map(|i| {
            let mut p = presets::classic();
            p.omega = 0.5 + 0.11 * i as f64;
            MeshModel::new(&p).unwrap()
        })
        .collect();
    let opts = SimOptions::rk4(128, 30, 10);
    let runs: Vec<(&MeshModel, [f64; 2])> = models.iter().map(|m| (m, [0.0, 0.0])).collect();
    let run =
        |threads: usize| crate::common::on_threads(threads, || simulate_lanes(&runs, &lane(&opts)));
    let key = |r: &Vec<Result<SimResult, geardyn_analysis::simulate::SimError>>| {
        serde_json::to_string(
            &r.iter()
                .map(|x| x.as_ref().unwrap().clone())
                .collect::<Vec<_>>(),
        )
        .unwrap()
    };
    let one = key(&run(1));
    assert_eq!(one, key(&run(2)));
    assert_eq!(one, key(&run(5)));
    // the same bytes from the baseline copy of the engine as from the AVX2/FMA and AVX-512 ones
    // (no fused multiply-add anywhere in the lanes; `one` ran on the best copy this CPU has)
    use geardyn_solvers::ensemble::Dispatch;
    for how in [Dispatch::Baseline, Dispatch::Avx2] {
        let copy = geardyn_analysis::lanes::simulate_lanes_dispatch(&runs, &lane(&opts), how);
        assert_eq!(one, key(&copy), "{how:?}");
    }
}

/// Basins of C1 at omega = 1.8 on a coarse grid: the cells run in lanes (early capture, then the
/// description of new attractors) and every cell gets the outcome of the scalar path.
#[test]
fn basins_in_lanes_equal_the_scalar_basins() {
    use geardyn_analysis::attractor::Outcome;
    use geardyn_analysis::basins::{basins, basins_scalar, Axis, BasinOptions};
    use std::collections::HashMap;
    let mut p = presets::classic();
    p.omega = 1.8;
    let m = MeshModel::new(&p).unwrap();
    let identify = crate::common::identify_rk4(256, 150, 32);
    let opts = BasinOptions {
        slice: Default::default(),
        x: Axis {
            min: -2.0,
            max: 2.0,
            n: 20,
        },
        v: Axis {
            min: -1.5,
            max: 1.5,
            n: 20,
        },
        identify,
    };
    let cells_a = std::sync::Mutex::new(HashMap::new());
    let cells_b = std::sync::Mutex::new(HashMap::new());
    let a = basins(&m, &opts, &HashMap::new(), |c, o: &Outcome| {
        cells_a.lock().unwrap().insert(c, o.clone());
    });
    let b = basins_scalar(&m, &opts, &HashMap::new(), |c, o: &Outcome| {
        cells_b.lock().unwrap().insert(c, o.clone());
    });
    // Periodic attractors (canonical ids first) and their cells are the same; chaotic cells
    // follow different, equally valid trajectories (a 1e-16 difference grows), so their clouds
    // may be grouped into a different number of non-periodic descriptors: the set of cells on
    // non-periodic attractors must be the same.
    let periodic = |r: &geardyn_analysis::basins::BasinResult| {
        r.attractors
            .iter()
            .filter(|x| x.descriptor.period > 0)
            .count() as i64
    };
    let np = periodic(&b);
    assert!(np >= 2, "{:?}", b.attractors);
    assert_eq!(periodic(&a), np);
    for (c, (&x, &y)) in a.cells.iter().zip(&b.cells).enumerate() {
        if y < np {
            assert_eq!(x, y, "cell {c}");
        } else {
            assert!(x >= np, "cell {c}: {x} vs {y}");
        }
    }
    for (x, y) in a.attractors.iter().zip(&b.attractors).take(np as usize) {
        assert_eq!(x.cells, y.cells);
        assert_eq!(x.descriptor.label, y.descriptor.label);
        for (p, q) in x.descriptor.points.iter().zip(&y.descriptor.points) {
            assert!((p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9);
        }
    }
    let (ca, cb) = (cells_a.into_inner().unwrap(), cells_b.into_inner().unwrap());
    assert_eq!(ca.len(), cb.len());
    let mut same_capture = 0;
    for (c, o) in &ca {
        if let (Outcome::Captured { periods: p, .. }, Outcome::Captured { periods: q, .. }) =
            (o, &cb[c])
        {
            assert_eq!(p, q, "cell {c}");
            same_capture += 1;
        }
    }
    assert!(same_capture > 0);
}

/// A run on a one-lane engine is the same run as in the lockstep lanes, to the last bit
/// (periodic and chaotic C1, breakage with events and breakpoints; a start time other than 0).
#[test]
fn one_lane_engine_equals_the_lockstep_lanes() {
    use geardyn_analysis::lanes::simulate_lane;
    let key = |r: &SimResult| serde_json::to_string(r).unwrap();
    for (preset, omega, n, tau0) in [
        ("classic", 0.8, 128, 0.0),
        ("classic", 1.3, 128, 1234.5678),
        ("breakage", 2.0, 64, 17.25),
    ] {
        let mut p = if preset == "classic" {
            presets::classic()
        } else {
            presets::breakage()
        };
        p.omega = omega;
        let m = MeshModel::new(&p).unwrap();
        let opts = SimOptions {
            method: Method::Rk4 { steps_per_cycle: n },
            tau0,
            transient_periods: 30,
            record_periods: 8,
            ..Default::default()
        };
        let ics = [[0.0, 0.0], [0.9, -0.5], [-1.1, 0.3]];
        let runs: Vec<(&MeshModel, [f64; 2])> = ics.iter().map(|&y| (&m, y)).collect();
        let lanes = simulate_lanes(&runs, &lane(&opts));
        for (&(_, y0), r) in runs.iter().zip(&lanes) {
            let one = simulate_lane(&m, y0, &lane(&opts)).unwrap();
            assert_eq!(
                key(&one),
                key(r.as_ref().unwrap()),
                "{preset} omega {omega}"
            );
        }
    }
}

/// The bifurcation sweep with RK4 runs in lanes: periodic runs equal the scalar `run_once` to
/// rounding; the others are classified from their lanes result, never integrated again
/// (`simulate_decided_from`: TLE and transient extensions continue from the lanes' final state).
/// The lanes' trajectory equals the scalar one to rounding, which chaos amplifies, so a
/// non-periodic run's numbers differ from `run_once` (and a borderline chaotic transient may be
/// decided differently); on these values its class is the same.
#[test]
fn rk4_sweep_in_lanes_equals_scalar_runs() {
    use geardyn_analysis::bifurcation::{
        initial_state, run_once, run_sweep, Section, SweepMode, SweepOptions,
    };
    use geardyn_analysis::classify::{simulate_decided_with, Decide};
    use geardyn_analysis::lanes::simulate_lane_grid;
    let scenario = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    for mode in [
        SweepMode::Fixed,
        SweepMode::Multi {
            ics: 3,
            seed: 7,
            x0_range: (-1.5, 1.5),
            v0_range: (-1.0, 1.0),
        },
    ] {
        let opts = SweepOptions {
            param: "omega".into(),
            values: vec![0.6, 0.8, 1.25, 1.9],
            mode: mode.clone(),
            sim: SimOptions::rk4(128, 100, 24),
            y0: [0.0, 0.0],
            sections: vec![Section::Strobe, Section::DsUp],
            lyapunov: false,
        };
        let res = run_sweep(&scenario, &opts, &Default::default(), |_| {}).unwrap();
        for r in &res {
            let mut p = presets::classic();
            p.omega = r.value;
            let m = MeshModel::new(&p).unwrap();
            for run in &r.runs {
                let y0 = initial_state(&mode, opts.y0, r.task.index, run.ic, |y| {
                    m.admissible(opts.sim.tau0, y)
                });
                assert_eq!(run.y0, y0);
                let s = run_once(&m, y0, run.ic, &opts);
                assert_eq!(run.motion.word(), s.motion.word(), "omega {}", r.value);
                if run.period > 0 {
                    assert_eq!(run.label, s.label, "omega {}", r.value);
                    assert_eq!(run.points.len(), s.points.len());
                    for (a, b) in run.points.iter().zip(&s.points) {
                        assert_eq!(a.0, b.0);
                        assert!((a.1 - b.1).abs() < 1e-9 && (a.2 - b.2).abs() < 1e-9);
                    }
                    continue;
                }
                // non-periodic: exactly the decision continued from the lanes' first run, the
                // transient extensions on a one-lane engine with the sweep's phase tables
                let first = simulate_lanes(&[(&m, y0)], &lane(&opts.sim))
                    .remove(0)
                    .unwrap();
                let sum = summarize(&m, &first, &opts.sim);
                let grid = |m: &MeshModel, y: [f64; 2], o: &SimOptions| {
                    simulate_lane_grid(m, y, &lane(o), opts.sim.tau0)
                };
                let (res, d, used) =
                    simulate_decided_with(&m, (first, sum), &opts.sim, Decide::default(), grid)
                        .unwrap();
                assert_eq!(run.label, d.label, "omega {}", r.value);
                assert_eq!(run.motion, d.motion);
                assert_eq!(run.p_id, d.p_id);
                assert_eq!(run.max_force, d.max_force);
                assert_eq!(run.transient_used, used.transient_periods);
                assert_eq!(run.final_state, res.final_state.1);
                let strobe: Vec<(Section, f64, f64)> = res
                    .strobe
                    .iter()
                    .map(|p| (Section::Strobe, p[1], p[2]))
                    .collect();
                assert_eq!(run.points[..strobe.len()], strobe[..]);
            }
        }
    }
}

/// Exponent requests of two window lengths in one round of `decide_lanes` (the 1000-period look at
/// a run the 100-period exponent leaves undecided, beside the ordinary ones) come back to the
/// runs that asked for them: each batched decision equals the run's own, and the weakly chaotic
/// C1 value (omega = 1.40452261307: 0.019 +- 0.010 over 100 periods) is decided chaotic with the
/// long window's standard error.
#[test]
fn a_long_exponent_look_in_the_lanes_equals_the_decision_of_the_run() {
    use geardyn_analysis::classify::{simulate_decided_with, Decide, Motion};
    use geardyn_analysis::lanes::simulate_lane_grid;
    use geardyn_analysis::lanes_decide::decide_lanes;
    let key = |r: &SimResult| serde_json::to_string(r).unwrap();
    let models = c1_at(&[1.40452261307, 1.3, 0.8]);
    let opts = SimOptions {
        method: Method::Rk4 {
            steps_per_cycle: 512,
        },
        ..Default::default()
    };
    let runs: Vec<(&MeshModel, [f64; 2])> = models.iter().map(|m| (m, [0.0, 0.0])).collect();
    let firsts = first_runs(&runs, &opts);
    let batched = decide_lanes(firsts.clone(), &opts, Decide::default());
    let grid = |m: &MeshModel, y: [f64; 2], o: &SimOptions| simulate_lane_grid(m, y, &lane(o), 0.0);
    let mut motions = Vec::new();
    for ((m, first), b) in firsts.into_iter().zip(batched) {
        let (res, s, _) = simulate_decided_with(m, first, &opts, Decide::default(), grid).unwrap();
        let (bres, bs, _) = b.unwrap();
        assert_eq!(key(&res), key(&bres), "omega {}", m.params().omega);
        assert_eq!(s.motion, bs.motion);
        motions.push(bs.motion);
    }
    match motions[0] {
        Motion::Chaotic { tle, stderr } => assert!(tle > 0.01 && stderr < 0.005, "{tle} {stderr}"),
        ref m => panic!("omega 1.4045: {m:?}"),
    }
    assert!(
        matches!(motions[1], Motion::Chaotic { .. }),
        "{:?}",
        motions[1]
    );
    assert!(motions[2].is_periodic(), "{:?}", motions[2]);
}

/// The decisions of many runs together (`decide_lanes`: TLEs, transient extensions, persistence
/// checks and records again in rounds, the integrations in the lanes) are, to the last bit, the
/// decision of each run alone (`simulate_decided_with` on a one-lane engine with the sweep's
/// phase tables); C1 (periodic, chaotic, extended) and the internal pair near omega = 1.84
/// (chaotic transients landing on an orbit), start times 0 and not 0.
#[test]
fn decisions_in_lanes_equal_the_decision_of_each_run() {
    use geardyn_analysis::classify::{simulate_decided_with, Decide};
    use geardyn_analysis::lanes::simulate_lane_grid;
    use geardyn_analysis::lanes_decide::decide_lanes;
    let key = |r: &SimResult| serde_json::to_string(r).unwrap();
    let mut kinds = [0usize; 3];
    for (preset, omegas, tau0) in [
        ("classic", vec![0.6, 1.1, 1.25, 1.3, 1.45, 1.67, 1.9], 0.0),
        ("classic", vec![1.2, 1.35, 1.6], 33.0),
        ("internal", vec![1.8, 1.82, 1.84, 1.86, 1.88], 0.0),
    ] {
        let models: Vec<MeshModel> = omegas
            .iter()
            .map(|&w| {
                let mut p = if preset == "classic" {
                    presets::classic()
                } else {
                    presets::internal()
                };
                p.omega = w;
                MeshModel::new(&p).unwrap()
            })
            .collect();
        let opts = SimOptions {
            method: Method::Rk4 {
                steps_per_cycle: 64,
            },
            tau0,
            transient_periods: 60,
            record_periods: 30,
            ..Default::default()
        };
        let ics = [[0.0, 0.0], [0.9, -0.5], [-1.1, 0.3]];
        let runs = crate::common::runs_from(&models, &ics);
        let firsts = first_runs(&runs, &opts);
        let batched = decide_lanes(firsts.clone(), &opts, Decide::default());
        let grid =
            |m: &MeshModel, y: [f64; 2], o: &SimOptions| simulate_lane_grid(m, y, &lane(o), tau0);
        for ((m, first), b) in firsts.into_iter().zip(batched) {
            let (res, s, used) =
                simulate_decided_with(m, first, &opts, Decide::default(), grid).unwrap();
            let (bres, bs, bused) = b.unwrap();
            assert_eq!(key(&res), key(&bres), "{preset} omega {}", m.params().omega);
            assert_eq!(s.motion, bs.motion);
            assert_eq!(s.label, bs.label);
            assert_eq!(used.transient_periods, bused.transient_periods);
            let extra = used.transient_periods - opts.transient_periods;
            kinds[0] += (extra == 0) as usize;
            kinds[1] += (extra > 0 && s.motion.is_periodic()) as usize;
            // (a chaotic verdict of the escape test keeps its first record: its copies ran on)
            let escape = s.decided_by == geardyn_analysis::classify::DecidedBy::Escape;
            kinds[2] += ((extra > 0 || escape) && !s.motion.is_periodic()) as usize;
        }
    }
    // decided periodic after more integration (records again, extensions, persistence checks,
    // escape tests) and not periodic after more
    assert!(kinds[1] > 0 && kinds[2] > 0, "{kinds:?}");
}

/// A map with fixed-step RK4 runs its cells in the lanes (`simulate_decided_lanes`): each cell
/// is, to the bit, the decision of its run alone on the lanes' path (a chaotic transient may end
/// elsewhere than on the scalar path: a 1e-16 difference grows), a periodic cell the scalar RK4
/// decision to 1e-9; the same for any thread count, and an interrupted map resumes to the same
/// cells.
#[test]
fn map_in_lanes_equals_the_scalar_decisions() {
    use geardyn_analysis::classify::{simulate_decided, simulate_decided_with, Decide};
    use geardyn_analysis::lanes::simulate_lane_grid;
    use geardyn_analysis::map2d::{map2d, MapOptions};
    use std::collections::HashMap;
    let scenario = geardyn_scenario::Scenario::dimensionless(presets::classic()).unwrap();
    let o = MapOptions {
        x_param: "omega".into(),
        x_values: vec![0.7, 1.0, 1.3, 1.8],
        y_param: "F".into(),
        y_values: vec![0.1, 0.15, 0.2],
        sim: SimOptions::rk4(128, 150, 24),
        y0: [0.0, 0.0],
        lyapunov: false,
    };
    let map = |n: usize| {
        crate::common::on_threads(n, || map2d(&scenario, &o, &HashMap::new(), |_| {}).unwrap())
    };
    let (a, b) = (map(2), map(1));
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap()
    );
    let mut periodic = 0;
    for c in &a {
        let s = scenario.with_all(&[("omega", c.x), ("F", c.y)]).unwrap();
        let m = s.model();
        // the decision continued from the lanes' first run, on a one-lane engine with the
        // map's phase tables: the cell to the last bit
        let first = simulate_lanes(&[(m, o.y0)], &lane(&o.sim))
            .remove(0)
            .unwrap();
        let sum = summarize(m, &first, &o.sim);
        let grid = |m: &MeshModel, y: [f64; 2], so: &SimOptions| {
            simulate_lane_grid(m, y, &lane(so), o.sim.tau0)
        };
        let (_, d, _) =
            simulate_decided_with(m, (first, sum), &o.sim, Decide::default(), grid).unwrap();
        assert_eq!(c.label, d.label, "{} {}", c.x, c.y);
        assert_eq!(c.motion, d.motion);
        assert_eq!(c.max_force, d.max_force);
        assert_eq!(c.p_id, d.p_id);
        if c.period > 0 {
            // and a periodic cell is the scalar RK4 decision to rounding
            periodic += 1;
            let (_, e, _) = simulate_decided(m, o.y0, &o.sim, Decide::default()).unwrap();
            assert_eq!(c.label, e.label, "{} {}", c.x, c.y);
            assert!((c.max_force - e.max_force).abs() < 1e-9);
        }
    }
    assert!(periodic >= 6, "{a:?}");
    // resume: half of the cells done, the rest computed
    let done: HashMap<usize, _> = a.iter().take(5).map(|c| (c.index, c.clone())).collect();
    let r = map2d(&scenario, &o, &done, |_| {}).unwrap();
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&r).unwrap()
    );
}

/// A continuation with fixed-step RK4 identifies its initial states in the lanes: the same
/// attractors, points and basin assignments as the continuation with the adaptive DP5 (scalar
/// identification), C1 at omega = 1.8 (two coexisting orbits).
#[test]
fn continuation_in_lanes_agrees_with_the_scalar_identification() {
    use geardyn_analysis::attractor::IdentifyOptions;
    use geardyn_analysis::continuation::{attractors_at, ContinuationOptions};
    let mut p = presets::classic();
    p.omega = 1.8;
    let m = MeshModel::new(&p).unwrap();
    let mut identify_opts = IdentifyOptions::default();
    identify_opts.sim.transient_periods = 150;
    identify_opts.sim.record_periods = 32;
    let mut o = ContinuationOptions {
        param: "omega".into(),
        values: vec![1.8],
        ics: 16,
        seed: 5,
        x0_range: (-2.0, 2.0),
        v0_range: (-1.5, 1.5),
        phase: 0.0,
        identify: identify_opts,
    };
    let dopri = attractors_at(&m, 0, 1.8, &o);
    o.identify.sim.method = Method::Rk4 {
        steps_per_cycle: 512,
    };
    let rk4 = attractors_at(&m, 0, 1.8, &o);
    assert!(dopri.attractors.len() >= 2, "{:?}", dopri.attractors);
    assert_eq!(dopri.attractors.len(), rk4.attractors.len());
    for (a, b) in dopri.attractors.iter().zip(&rk4.attractors) {
        assert_eq!(a.label, b.label);
        assert!(a.period > 0);
        let (p, q) = (a.points[0], b.points[0]);
        assert!(
            (p[0] - q[0]).abs() < 1e-4 && (p[1] - q[1]).abs() < 1e-4,
            "{p:?} {q:?}"
        );
    }
    assert_eq!(dopri.assignment, rk4.assignment);
}

/// A decision leaves the rounds of `decide_lanes` and finishes alone, beside them, when its next
/// integration would run on a one-lane engine anyway (fewer than four runs per thread in its
/// follow's rung); both ways give the same decision, to the bit. Ten runs at `omega` = 1.3 share
/// one rung of the follow: batched on one and two threads (10 >= 4, 8), alone on three
/// (10 < 12); the weakly chaotic run at 1.40452 has a rung of its own and goes alone on every
/// thread count. Also balanced chunks: on three threads the ten share no chunk at all.
#[test]
fn a_decision_is_the_same_in_the_rounds_and_alone() {
    let models = c1_at(&[1.3, 1.40452261307]);
    let mut runs: Vec<(&MeshModel, [f64; 2])> = (0..10)
        .map(|k| (&models[0], [0.1 * k as f64, -0.05 * k as f64]))
        .collect();
    runs.push((&models[1], [0.0, 0.0]));
    let opts = SimOptions {
        method: Method::Rk4 {
            steps_per_cycle: 256,
        },
        transient_periods: 100,
        record_periods: 40,
        decision_periods: 3000,
        ..Default::default()
    };
    let on = |threads: usize| {
        common::decided_lanes_on(threads, &runs, &opts, |r, s, used| {
            (
                s.motion,
                s.label,
                s.decided_by,
                s.periods_integrated,
                r.final_state.0.to_bits(),
                r.final_state.1.map(f64::to_bits),
                used.transient_periods,
            )
        })
    };
    let one = on(1);
    let chaotic = one.iter().filter(|d| d.0.is_chaotic()).count();
    assert!(chaotic >= 8, "the follows ran: {one:?}");
    assert_eq!(one, on(2));
    assert_eq!(one, on(3));
}
