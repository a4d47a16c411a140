//! Decisions in the pair's lockstep lanes: the integrations many [`crate::classify::Decision`]s
//! ask for next (transient extensions, persistence blocks, follows, exponents) run together in
//! rounds, a decision whose next run would have a lane to itself finishing alone beside them; the
//! same verdicts as each run decided alone.

// lane loops over several arrays read clearer (and vectorise as intended) with an index
#![allow(clippy::needless_range_loop, clippy::manual_memcpy)]

use crate::classify::{Decide, Decision, Need};
use crate::lane_plan::{lanes_apply, lanes_cover_contact, LaneSim};
use crate::lanes::{simulate_items, simulate_lane_grid, simulate_lanes, Item};
use crate::lanes_tle::tles_of;
use crate::simulate::{summarize, Method, SimError, SimOptions, SimResult, Summary};
use geardyn_model::MeshModel;
use geardyn_solvers::ensemble::Dispatch;
use rayon::prelude::*;

/// Runs per thread in a round of [`decide_lanes`] below which they run on one-lane engines (in
/// parallel) rather than sharing a 16-lane one: on one thread (C1, 512 steps per cycle) a
/// 16-lane engine with k busy lanes took as long as k one-lane engines at k = 4, 2x longer at
/// k = 2, half as long at k = 8.
const LONE_RUNS: usize = 4;

/// [`simulate_decided_from`](crate::classify::simulate_decided_from) of many runs of a lanes
/// sweep at once: each `(model, first)` is a run of [`simulate_lanes`] with `opts` and its
/// `summarize`; the decisions (`Decision`, the code of
/// [`simulate_decided_with`](crate::classify::simulate_decided_with)) go in rounds, each round
/// running the TLEs asked for (scalar, in parallel) and all the integrations asked for
/// (transient extensions, persistence checks, records again) together in the lanes. Those
/// integrations continue a run from a stroboscopic instant and share the phase tables of the
/// sweep ([`simulate_lane_grid`] with `opts.tau0` is the same run on one lane); results in input
/// order, each the decision [`simulate_decided_with`](crate::classify::simulate_decided_with)
/// reaches with [`simulate_lane_grid`].
pub fn decide_lanes(
    runs: Vec<(&MeshModel, (SimResult, Summary))>,
    opts: &SimOptions,
    how: Decide,
) -> Vec<Result<(SimResult, Summary, SimOptions), SimError>> {
    type Out = Result<(SimResult, Summary, SimOptions), SimError>;
    let mut ds: Vec<Option<Decision<'_>>> = runs
        .into_iter()
        .map(|(m, first)| Some(Decision::new(m, first, opts, how)))
        .collect();
    let models: Vec<&MeshModel> = ds.iter().flatten().map(|d| d.model()).collect();
    let lone = LONE_RUNS * rayon::current_num_threads().max(1);
    // the decisions finished on their own (see `decide_alone`), pushed once each
    let alone: std::sync::Mutex<Vec<(usize, Out)>> = std::sync::Mutex::new(Vec::new());
    rayon::scope(|scope| loop {
        // A decision whose next integration would run on a one-lane engine anyway (its rung
        // has fewer than `lone` runs) leaves the rounds and finishes on its own, beside them:
        // a round waits for its slowest integration, and a few long follows at low omega
        // (many steps per period) otherwise kept a core idle for most of a round.
        let mut rung: std::collections::HashMap<u32, usize> = Default::default();
        for d in ds.iter().flatten() {
            if let Need::Sim { opts: o, .. } = d.need() {
                if let (true, Method::Rk4 { steps_per_cycle }) = (lanes_apply(&o), o.method) {
                    *rung.entry(steps_per_cycle).or_default() += 1;
                }
            }
        }
        for (i, slot) in ds.iter_mut().enumerate() {
            let detach = slot.as_ref().is_some_and(|d| match d.need() {
                Need::Sim { opts: o, .. } => match o.method {
                    Method::Rk4 { steps_per_cycle } if lanes_apply(&o) => {
                        rung[&steps_per_cycle] < lone
                    }
                    _ => false,
                },
                _ => false,
            });
            if detach {
                let mut d = slot.take().expect("checked above");
                let alone = &alone;
                scope.spawn(move |_| {
                    decide_alone(&mut d, opts);
                    let r = d.finish();
                    alone.lock().expect("no panic holds it").push((i, r));
                });
            }
        }
        // the escape tests side by side (each advances its copies in parallel lanes too)
        ds.par_iter_mut().flatten().for_each(|d| {
            if let Need::Escape { start, test } = d.need() {
                let out = crate::pair_engine::escape_of(d.model(), opts, &test, start);
                d.escaped(out);
            }
        });
        let mut tles: Vec<(usize, f64, [f64; 2], f64, u64)> = Vec::new();
        let mut sims: Vec<(Item<'_>, SimOptions)> = Vec::new();
        let mut sim_of: Vec<usize> = Vec::new();
        for (i, d) in ds.iter().enumerate() {
            let Some(d) = d else { continue };
            match d.need() {
                Need::Tle {
                    t,
                    y,
                    memory,
                    periods,
                } => tles.push((i, t, y, memory, periods)),
                Need::Sim { y0, opts: o } => {
                    sims.push((
                        Item {
                            out: sims.len(),
                            model: models[i],
                            y0,
                            t0: o.tau0,
                            memory: o.start_memory,
                            transient: o.transient_periods,
                            record: o.record_periods,
                            strobe_only: o.strobe_only,
                        },
                        o,
                    ));
                    sim_of.push(i);
                }
                Need::Escape { .. } => unreachable!("escape tests run before the round"),
                Need::Done => {}
            }
        }
        if tles.is_empty() && sims.is_empty() {
            break;
        }
        let (tle_res, sim_res) = rayon::join(
            || {
                // one batch per window length (the last look at an undecided run is longer),
                // results back in the order asked
                let mut out: Vec<Option<(f64, f64)>> = vec![None; tles.len()];
                let mut lengths: Vec<u64> = tles.iter().map(|e| e.4).collect();
                lengths.sort_unstable();
                lengths.dedup();
                for len in lengths {
                    let (idx, runs): (Vec<usize>, Vec<crate::lanes_tle::TleStart<'_>>) = tles
                        .iter()
                        .enumerate()
                        .filter(|(_, e)| e.4 == len)
                        .map(|(k, &(i, t, y, m, _))| (k, (models[i], t, y, m)))
                        .unzip();
                    for (k, r) in idx.into_iter().zip(tles_of(&runs, opts, len)) {
                        out[k] = r;
                    }
                }
                out
            },
            || run_needs(&sims, opts.tau0),
        );
        for (&(i, ..), r) in tles.iter().zip(tle_res) {
            ds[i].as_mut().expect("in the rounds").tle(r);
        }
        for (&i, r) in sim_of.iter().zip(sim_res) {
            ds[i].as_mut().expect("in the rounds").simulated(r);
        }
    });
    let mut out: Vec<Option<Out>> = ds.into_iter().map(|d| d.map(|d| d.finish())).collect();
    for (i, r) in alone.into_inner().expect("no panic holds it") {
        out[i] = Some(r);
    }
    out.into_iter()
        .map(|r| r.expect("every run is decided"))
        .collect()
}

/// Takes decision `d` to its end alone: each integration it asks for is the one a round of
/// [`decide_lanes`] would run for it (a follow or record in fixed-step RK4 on the sweep's phase
/// tables, one lane; the adaptive integrator's records as they are; the exponents of
/// [`tles_of`]), each with the same result alone as among others, so the decision is the same.
fn decide_alone(d: &mut Decision<'_>, opts: &SimOptions) {
    loop {
        match d.need() {
            Need::Sim { y0, opts: o } => {
                let r = match LaneSim::new(&o) {
                    Ok(lane) => simulate_lane_grid(d.model(), y0, &lane, opts.tau0),
                    Err(_) => crate::simulate::simulate(d.model(), y0, &o),
                };
                d.simulated(r);
            }
            Need::Tle {
                t,
                y,
                memory,
                periods,
            } => {
                let r = tles_of(&[(d.model(), t, y, memory)], opts, periods)
                    .pop()
                    .flatten();
                d.tle(r);
            }
            Need::Escape { start, test } => {
                let out = crate::pair_engine::escape_of(d.model(), opts, &test, start);
                d.escaped(out);
            }
            Need::Done => return,
        }
    }
}

/// The integrations a round of [`decide_lanes`] asks for (`sims[k]`: output `k` with its options),
/// results in that order: fixed-step RK4 ones together in the lanes (one batch per step size: the requested RK4, or a follow's,
/// [`crate::classify::follow_method`]), with the phase tables of the sweep's `tau0`; the others
/// (the adaptive integrator's records) one by one, in parallel.
fn run_needs(sims: &[(Item<'_>, SimOptions)], tau0: f64) -> Vec<Result<SimResult, SimError>> {
    let lanes: Vec<(Item<'_>, LaneSim)> = sims
        .iter()
        .filter_map(|(it, o)| LaneSim::new(o).ok().map(|l| (*it, l)))
        .collect();
    let in_lanes = |(_, o): &(Item<'_>, SimOptions)| LaneSim::new(o).is_ok();
    let mut steps: Vec<u32> = lanes.iter().map(|(_, l)| l.steps_per_cycle()).collect();
    steps.sort_unstable();
    steps.dedup();
    let lone = LONE_RUNS * rayon::current_num_threads().max(1);
    let mut out: Vec<Option<Result<SimResult, SimError>>> = (0..sims.len()).map(|_| None).collect();
    let (batches, single) = rayon::join(
        || {
            // the rungs side by side: a rung of a few long follows would otherwise leave a core
            // idle until it ends
            steps
                .par_iter()
                .map(|&n| {
                    let mut items: Vec<(Item<'_>, LaneSim)> = lanes
                        .iter()
                        .filter(|(_, l)| l.steps_per_cycle() == n)
                        .copied()
                        .collect();
                    // longest first, so that the lanes of a chunk retire together (the results
                    // do not depend on the order)
                    items.sort_by_key(|(it, _)| std::cmp::Reverse(it.transient));
                    let o = items[0].1;
                    let batch: Vec<Item<'_>> = items
                        .iter()
                        .enumerate()
                        .map(|(k, (it, _))| Item { out: k, ..*it })
                        .collect();
                    let res = simulate_items(&batch, &o, tau0, Dispatch::Auto, lone);
                    items
                        .into_iter()
                        .map(|(it, _)| it.out)
                        .zip(res)
                        .collect::<Vec<_>>()
                })
                .collect::<Vec<_>>()
        },
        || {
            sims.par_iter()
                .filter(|s| !in_lanes(s))
                .map(|(it, o)| (it.out, crate::simulate::simulate(it.model, it.y0, o)))
                .collect::<Vec<_>>()
        },
    );
    for (k, r) in batches.into_iter().flatten().chain(single) {
        out[k] = Some(r);
    }
    out.into_iter()
        .map(|r| r.expect("every integration has a result"))
        .collect()
}

/// A decided run: the record, its summary and the settings of the record.
pub type Decided = Result<(SimResult, Summary, SimOptions), SimError>;

/// The decisions ([`simulate_decided`](crate::classify::simulate_decided)) of many runs whose
/// first runs `first` came from [`simulate_lanes`] or, with the adaptive integrator, from
/// [`simulate`](crate::simulate::simulate) (`runs[i]` gave `first[i]`): the runs whose
/// contact the lanes cover ([`lanes_cover_contact`]) are decided together ([`decide_lanes`]),
/// the others one by one from their lanes record, and a run the lanes could not finish is
/// decided by the scalar path from its start. Results in input order.
pub fn decide_lane_runs(
    runs: &[(&MeshModel, [f64; 2])],
    first: Vec<Result<SimResult, SimError>>,
    opts: &SimOptions,
) -> Vec<Decided> {
    let mut batched = Vec::new();
    let mut single = Vec::new();
    for (j, (&(m, y0), r)) in runs.iter().zip(first).enumerate() {
        match r {
            Ok(res) if lanes_cover_contact(m) => batched.push((j, m, res)),
            r => single.push((j, m, y0, r)),
        }
    }
    let (a, b) = rayon::join(
        || {
            let (idx, firsts): (Vec<usize>, Vec<_>) = batched
                .into_iter()
                .map(|(j, m, res)| {
                    let s = summarize(m, &res, opts);
                    (j, (m, (res, s)))
                })
                .unzip();
            idx.into_iter()
                .zip(decide_lanes(firsts, opts, Decide::default()))
                .collect::<Vec<_>>()
        },
        || {
            single
                .into_par_iter()
                .map(|(j, m, y0, r)| {
                    let d = match r {
                        Ok(res) => {
                            let s = summarize(m, &res, opts);
                            crate::classify::simulate_decided_from(
                                m,
                                (res, s),
                                opts,
                                Decide::default(),
                            )
                        }
                        Err(_) => crate::classify::simulate_decided(m, y0, opts, Decide::default()),
                    };
                    (j, d)
                })
                .collect::<Vec<_>>()
        },
    );
    let mut out: Vec<Option<Decided>> = (0..runs.len()).map(|_| None).collect();
    for (j, d) in a.into_iter().chain(b) {
        out[j] = Some(d);
    }
    out.into_iter()
        .map(|d| d.expect("every run is decided"))
        .collect()
}

/// [`simulate_decided`](crate::classify::simulate_decided) of every `(model, y0)` with
/// fixed-step RK4 ([`LaneSim`]): the first runs in lockstep lanes, then
/// [`decide_lane_runs`]. Results in input order, the same for any thread count.
pub fn simulate_decided_lanes(runs: &[(&MeshModel, [f64; 2])], opts: &LaneSim) -> Vec<Decided> {
    decide_lane_runs(runs, simulate_lanes(runs, opts), opts)
}
