//! Kernel benchmarks of the lockstep ensemble (run: `cargo bench -p geardyn-analysis --bench
//! ensemble`): the fused `MeshLanes` step of 8 lanes alone, RK4 stages and affine map (AVX2/FMA
//! copy and baseline copy),
//! the whole engine on 16 trajectories of C1 (one thread, a quarter of the periods recorded), and
//! the scalar RK4 integrator on the same work. Best of several repetitions; on a shared machine
//! compare the figures of one run with each other, not across runs.

use geardyn_analysis::driver::{run_periods, Discard};
use geardyn_analysis::lanes::{simulate_lanes, LaneSim};
use geardyn_analysis::simulate::SimOptions;
use geardyn_model::{presets, ContactState, MeshLaneBlock, MeshLanes, MeshMode, MeshModel};
use geardyn_solvers::ensemble::{Lockstep, StepStart};
use geardyn_solvers::{Integrator, Scheme};
use std::time::Instant;

const L: usize = 8;
type Work = <MeshLanes as Lockstep<2, L>>::Work;

#[inline(always)]
fn kernel_loop(t: &MeshLanes, lanes: &MeshLaneBlock<L>, work: &Work, n: usize, h: f64) -> f64 {
    let mut y = [[0.5f64; L]; 2];
    let mut f = [[0.1f64; L]; 2];
    let mut t0 = [0.0f64; L];
    let mut grid = [0.0f64; L];
    let s = <MeshLanes as Lockstep<2, L>>::steps_per_period(t);
    let mut acc = 0u32;
    let mut j = 0;
    for _ in 0..n {
        let mut t1 = [0.0; L];
        for l in 0..L {
            t1[l] = t0[l] + h;
        }
        let mut y1 = [[0.0; L]; 2];
        let mut f1 = [[0.0; L]; 2];
        let st = StepStart {
            j,
            t0: &t0,
            t1: &t1,
            grid: &grid,
            y0: &y,
            f0: &f,
        };
        acc = acc.wrapping_add(<MeshLanes as Lockstep<2, L>>::step(
            t, &st, lanes, work, &mut y1, &mut f1,
        ));
        (y, f, t0) = (y1, f1, t1);
        for g in grid.iter_mut() {
            *g += 1.0;
        }
        j += 1;
        if j == s {
            j = 0;
        }
    }
    y[0][0] + acc as f64
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn kernel_avx2(t: &MeshLanes, lanes: &MeshLaneBlock<L>, work: &Work, n: usize, h: f64) -> f64 {
    kernel_loop(t, lanes, work, n, h)
}

#[inline(never)]
fn kernel_base(t: &MeshLanes, lanes: &MeshLaneBlock<L>, work: &Work, n: usize, h: f64) -> f64 {
    kernel_loop(t, lanes, work, n, h)
}

fn best<F: FnMut() -> f64>(reps: usize, mut f: F) -> f64 {
    (0..reps).map(|_| f()).fold(f64::INFINITY, f64::min)
}

fn main() {
    let mut p = presets::classic();
    p.omega = 1.3;
    let m = MeshModel::new(&p).unwrap();
    let h = m.mesh_cycle_time() / 512.0;
    let n = 1_000_000;
    let per = |s: f64| s * 1e9 / (n as f64 * L as f64);
    for (name, table) in [
        ("RK4 stages", MeshLanes::new(&m, 512, 0.0).exact()),
        ("affine map", MeshLanes::new(&m, 512, 0.0)),
    ] {
        let mut lanes = <MeshLanes as Lockstep<2, L>>::idle_lanes(&table);
        let mut work = <MeshLanes as Lockstep<2, L>>::new_work(&table);
        for l in 0..L {
            let contact = if l % 2 == 0 {
                ContactState::Drive
            } else {
                ContactState::Separated
            };
            let mode = MeshMode {
                period: 0,
                seg: 0,
                contact,
                chi: 0.0,
            };
            assert!(Lockstep::<2, L>::set_lane(
                &table, &mut lanes, &mut work, l, &m, &mode, h
            ));
        }
        let base = best(5, || {
            let t = Instant::now();
            std::hint::black_box(kernel_base(&table, &lanes, &work, n, h));
            t.elapsed().as_secs_f64()
        });
        println!(
            "kernel ({name}), 8 lanes, baseline x86-64: {:.2} ns/lane-step",
            per(base)
        );
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            let avx = best(5, || {
                let t = Instant::now();
                // SAFETY: the CPU has the features
                std::hint::black_box(unsafe { kernel_avx2(&table, &lanes, &work, n, h) });
                t.elapsed().as_secs_f64()
            });
            println!(
                "kernel ({name}), 8 lanes, avx2+fma:        {:.2} ns/lane-step",
                per(avx)
            );
        }
    }
    // the engine: 16 trajectories, 400 periods (300 + 100 recorded), one thread
    let ics: Vec<[f64; 2]> = (0..16).map(|i| [-1.0 + 0.1 * i as f64, 0.0]).collect();
    let runs: Vec<(&MeshModel, [f64; 2])> = ics.iter().map(|&y| (&m, y)).collect();
    let opts = LaneSim::new(&SimOptions::rk4(512, 300, 100)).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut steps = 0;
    let eng = best(3, || {
        let t = Instant::now();
        let r = pool.install(|| simulate_lanes(&runs, &opts));
        steps = r.iter().map(|x| x.as_ref().unwrap().steps).sum::<u64>();
        t.elapsed().as_secs_f64()
    });
    println!(
        "engine, 16 trajectories x 400 periods (100 recorded): {:.2} ns/lane-step",
        eng * 1e9 / steps as f64
    );
    let mut ssteps = 0;
    let sc = best(3, || {
        let mut it = Integrator::new(
            &m,
            Scheme::Rk4 {
                h: m.mesh_cycle_time() / 512.0,
            },
            0.0,
            [0.0, 0.0],
        )
        .unwrap();
        let t = Instant::now();
        run_periods(&mut it, m.excitation_period(), 400, &mut Discard).unwrap();
        ssteps = it.stats().steps;
        t.elapsed().as_secs_f64()
    });
    println!(
        "scalar RK4, 400 periods: {:.2} ns/step",
        sc * 1e9 / ssteps as f64
    );
}
