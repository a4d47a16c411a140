//! The study plans of the presets and the machinery they share (cached sections, checkpointed
//! sweeps with progress bars, figure helpers).

use crate::readings::{class, describe_intervals, f, impact_values, label_intervals};
use crate::{rel, Claim, Figure, Section, Table};
use anyhow::{Context, Result};
use geardyn_analysis::attractor::IdentifyOptions;
use geardyn_analysis::basins::{basins, Axis, BasinOptions, BasinResult};
use geardyn_analysis::bifurcation::{
    detect_jumps, linspace, run_sweep, Section as Sec, SweepMode, SweepOptions, TaskResult,
};
use geardyn_analysis::continuation::{
    continuation, ContinuationOptions, ContinuationResult, ValueAttractors,
};
use geardyn_analysis::map2d::{map2d, MapCell, MapOptions};
use geardyn_analysis::simulate::{simulate, summarize, Method, SimOptions, SimResult};
use geardyn_io::checkpoint::Checkpoint;
use geardyn_io::output::write_csv;
use geardyn_io::plot::{colormap, raster_chart, xy_chart, Chart, Mark, Raster, Series, PALETTE};
use geardyn_io::sweep_output;
use geardyn_io::Config;
use geardyn_model::MeshModel;
use geardyn_physics::PairModel;
use geardyn_scenario::Scenario;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Shared context of a report run.
pub struct Ctx {
    /// Configuration of the preset.
    pub cfg: Config,
    /// The scenario it resolves to (every study starts from it).
    pub scenario: Scenario,
    /// Coarse mode.
    pub quick: bool,
    /// Report directory.
    pub dir: PathBuf,
}

fn bar(len: u64, msg: &str) -> ProgressBar {
    let pb = ProgressBar::new(len);
    pb.set_style(
        ProgressStyle::with_template("{msg:32} [{bar:30}] {pos}/{len} {elapsed} ETA {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    pb.set_message(msg.to_string());
    pb
}

impl Ctx {
    fn n(&self, quick: usize, full: usize) -> usize {
        if self.quick {
            quick
        } else {
            full
        }
    }

    fn sim(&self, transient: (u64, u64), record: (u64, u64)) -> SimOptions {
        SimOptions {
            method: Method::default(),
            transient_periods: if self.quick { transient.0 } else { transient.1 },
            record_periods: if self.quick { record.0 } else { record.1 },
            ..Default::default()
        }
    }

    fn base(&self) -> Result<Scenario> {
        Ok(self.scenario.clone())
    }

    /// A cached study: reuse `DIR/id/section.json` when its key matches.
    fn study<K: Serialize>(
        &self,
        id: &str,
        key: &K,
        body: impl FnOnce(&Path) -> Result<Section>,
    ) -> Result<Section> {
        let dir = self.dir.join(id);
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        let key = serde_json::to_string(
            &serde_json::json!({ "id": id, "config": self.cfg, "quick": self.quick, "key": key }),
        )?;
        let cache = dir.join("section.json");
        if let Ok(text) = std::fs::read_to_string(&cache) {
            if let Some((k, body_json)) = text.split_once('\n') {
                if k == key {
                    if let Ok(sec) = serde_json::from_str::<Section>(body_json) {
                        eprintln!("{id}: cached");
                        return Ok(sec);
                    }
                }
            }
        }
        let t = std::time::Instant::now();
        let mut sec = body(&dir)?;
        sec.seconds = t.elapsed().as_secs_f64();
        geardyn_io::output::write_text(
            &cache,
            &format!("{key}\n{}", serde_json::to_string(&sec)?),
        )?;
        Ok(sec)
    }

    /// Runs `run` with a checkpoint `dir/name.checkpoint.jsonl` (keyed by `key`) and a progress
    /// bar: `run` receives the records finished earlier (by `key_of`) and a callback that saves
    /// each new record. The first write error is returned after the run.
    fn checkpointed<T, K, R>(
        &self,
        dir: &Path,
        name: &str,
        key: &serde_json::Value,
        total: u64,
        key_of: impl Fn(&T) -> K,
        run: impl FnOnce(&HashMap<K, T>, &(dyn Fn(&T) + Sync)) -> Result<R>,
    ) -> Result<R>
    where
        T: Serialize + serde::de::DeserializeOwned,
        K: Eq + std::hash::Hash,
    {
        let key = serde_json::to_string(key)?;
        let (cp, done) =
            Checkpoint::open::<T>(&dir.join(format!("{name}.checkpoint.jsonl")), &key)?;
        let done: HashMap<K, T> = done.into_iter().map(|t| (key_of(&t), t)).collect();
        let pb = bar(total, name);
        pb.set_position(done.len() as u64);
        let err = std::sync::Mutex::new(None);
        let record = |t: &T| {
            if let Err(e) = cp.append(t) {
                err.lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .get_or_insert(e);
            }
            pb.inc(1);
        };
        let r = run(&done, &record)?;
        pb.finish_and_clear();
        if let Some(e) = err.into_inner().unwrap_or_else(|e| e.into_inner()) {
            return Err(e.into());
        }
        Ok(r)
    }

    fn sweep(
        &self,
        dir: &Path,
        name: &str,
        base: &Scenario,
        opts: &SweepOptions,
    ) -> Result<Vec<TaskResult>> {
        let total = geardyn_analysis::bifurcation::tasks(opts).len() as u64;
        let key =
            serde_json::json!({ "base": base.params(), "pair": base.spec().pair, "opts": opts });
        self.checkpointed(
            dir,
            name,
            &key,
            total,
            |r: &TaskResult| r.task,
            |done, record| Ok(run_sweep(base, opts, done, record)?),
        )
    }

    fn continuation(
        &self,
        dir: &Path,
        name: &str,
        base: &Scenario,
        opts: &ContinuationOptions,
    ) -> Result<ContinuationResult> {
        let key =
            serde_json::json!({ "base": base.params(), "pair": base.spec().pair, "opts": opts });
        self.checkpointed(
            dir,
            name,
            &key,
            opts.values.len() as u64,
            |v: &ValueAttractors| v.index,
            |done, record| Ok(continuation(base, opts, done, record)?),
        )
    }

    fn basins(
        &self,
        dir: &Path,
        name: &str,
        model: &MeshModel,
        opts: &BasinOptions,
    ) -> Result<BasinResult> {
        let key = serde_json::json!({ "params": model.params(), "opts": opts });
        let total = (opts.x.n * opts.v.n) as u64;
        type Cell = (usize, geardyn_analysis::attractor::Outcome);
        self.checkpointed(
            dir,
            name,
            &key,
            total,
            |c: &Cell| c.0,
            |done, record| {
                let done: HashMap<usize, _> = done.iter().map(|(k, v)| (*k, v.1.clone())).collect();
                Ok(basins(model, opts, &done, |c, o| record(&(c, o.clone()))))
            },
        )
    }

    fn map(
        &self,
        dir: &Path,
        name: &str,
        base: &Scenario,
        opts: &MapOptions,
    ) -> Result<Vec<MapCell>> {
        let key =
            serde_json::json!({ "base": base.params(), "pair": base.spec().pair, "opts": opts });
        let total = (opts.x_values.len() * opts.y_values.len()) as u64;
        self.checkpointed(
            dir,
            name,
            &key,
            total,
            |c: &MapCell| c.index,
            |done, record| Ok(map2d(base, opts, done, record)?),
        )
    }

    fn fig(&self, stem: &Path, caption: &str) -> Figure {
        Figure {
            png: rel(&self.dir, &stem.with_extension("png")),
            svg: rel(&self.dir, &stem.with_extension("svg")),
            caption: caption.to_string(),
        }
    }

    fn table(
        &self,
        path: &Path,
        title: &str,
        header: &[&str],
        rows: Vec<Vec<String>>,
    ) -> Result<Table> {
        write_csv(path, header, rows.iter().cloned())?;
        Ok(Table {
            title: title.to_string(),
            csv: rel(&self.dir, path),
            header: header.iter().map(|s| s.to_string()).collect(),
            rows,
        })
    }
}

fn with(base: &Scenario, sets: &[(&str, f64)]) -> Result<Scenario> {
    Ok(base.with_all(sets)?)
}

fn sweep_opts(
    param: &str,
    values: Vec<f64>,
    mode: SweepMode,
    sim: SimOptions,
    sections: Vec<Sec>,
    tle: bool,
) -> SweepOptions {
    SweepOptions {
        param: param.into(),
        values,
        mode,
        sim,
        y0: [0.0, 0.0],
        sections,
        lyapunov: tle,
    }
}

fn verdict(ok: Option<bool>) -> String {
    match ok {
        Some(true) => "reproduced".into(),
        Some(false) => "not reproduced".into(),
        None => "inconclusive".into(),
    }
}

fn chaotic(label: &str) -> bool {
    label.starts_with("chaotic")
}

fn tle_reading(results: &[TaskResult], param: &str) -> Option<String> {
    let pts: Vec<(f64, f64, &str)> = results
        .iter()
        .filter_map(|r| {
            r.runs[0]
                .tle
                .map(|t| (r.value, t, r.runs[0].label.as_str()))
        })
        .collect();
    if pts.is_empty() {
        return None;
    }
    let pos: Vec<f64> = pts.iter().filter(|p| p.1 > 1e-3).map(|p| p.0).collect();
    let agree = pts.iter().filter(|p| (p.1 > 1e-3) == chaotic(p.2)).count();
    Some(format!(
        "TLE > 0.001 at {} of {} values of {param}{}; the sign of the TLE agrees with the period detection (chaotic iff TLE > 0) at {} of {} values.",
        pos.len(),
        pts.len(),
        if pos.is_empty() { String::new() } else { format!(" (from {} to {})", f(pos[0]), f(*pos.last().unwrap_or(&pos[0]))) },
        agree,
        pts.len()
    ))
}

/// Figure of a time window of a simulation: phase portrait with Poincaré and impact points.
fn phase_figure(stem: &Path, title: &str, res: &SimResult) -> Result<()> {
    let stride = (res.trajectory.len() / 30_000).max(1);
    let traj: Vec<(f64, f64)> = res
        .trajectory
        .iter()
        .step_by(stride)
        .map(|p| (p.x, p.v))
        .collect();
    let strobe: Vec<(f64, f64)> = res.strobe.iter().map(|p| (p[1], p[2])).collect();
    let impacts: Vec<(f64, f64)> = res
        .events
        .iter()
        .filter(|e| e.kind == geardyn_model::EventKind::Impact)
        .map(|e| (e.x, e.v_before))
        .collect();
    xy_chart(
        stem,
        &Chart {
            title,
            x_label: "x",
            y_label: "x'",
        },
        &[
            Series {
                label: "trajectory",
                points: &traj,
                mark: Mark::Line,
                color: PALETTE[5],
            },
            Series {
                label: "stroboscopic points",
                points: &strobe,
                mark: Mark::Dots(4),
                color: PALETTE[1],
            },
            Series {
                label: "back-side impacts",
                points: &impacts,
                mark: Mark::Dots(3),
                color: PALETTE[6],
            },
        ],
    )?;
    Ok(())
}

fn stiffness_section(ctx: &Ctx, pm: &PairModel, dir: &Path) -> Result<Section> {
    let mut healthy_spec = pm.spec.clone();
    healthy_spec.breakage = None;
    let healthy = healthy_spec.build()?;
    let params = ctx.base()?;
    let (dd, ds) = (params.params().d_double, params.params().d_single);
    let mut readings_extra: Vec<String> = Vec::new();
    let figs: Vec<Figure> = geardyn_io::pair_plots::pair_figures(dir, pm, &healthy, dd, ds)?
        .iter()
        .map(|(stem, caption)| ctx.fig(stem, caption))
        .collect();
    let lubricated = pm.rows.iter().any(|r| r.regime1 >= 0);
    let nb = pm.spec.breakage.map_or(0, |b| b.broken_cycle) as f64;
    if lubricated {
        let count =
            |c: i8| pm.rows.iter().filter(|r| r.regime1 == c).count() as f64 / pm.rows.len() as f64;
        readings_extra.push(format!(
            "Lubrication: friction coefficient {}–{}, Lambda {}–{}; EHL on {:.0}% of the cycle, mixed on {:.0}%, boundary on {:.0}%.",
            f(pm.rows.iter().map(|r| r.mu1).fold(f64::INFINITY, f64::min)),
            f(pm.rows.iter().map(|r| r.mu1).fold(0.0, f64::max)),
            f(pm.rows.iter().map(|r| r.lambda1).fold(f64::INFINITY, f64::min)),
            f(pm.rows.iter().map(|r| r.lambda1).fold(0.0, f64::max)),
            100.0 * count(0),
            100.0 * count(1),
            100.0 * count(2)
        ));
    }
    if let Some((bd, bs)) = pm.backlash {
        readings_extra.push(format!("Half backlash from the physics at the operating point: D_d = {}, D_s = {} (D_s > D_d: {}).", f(bd), f(bs), bd < bs));
    }
    let mut readings = vec![format!(
        "Contact ratio eps = {}, mean mesh stiffness k_av = {} N/m over a healthy cycle (double-zone maximum {} N/m, single-zone minimum {} N/m); m_e = {} kg, omega_n = {} rad/s.",
        f(pm.geom.eps),
        f(pm.k_av),
        f(healthy.rows.iter().filter(|r| !r.single).map(|r| r.k_mesh).fold(0.0, f64::max)),
        f(healthy.rows.iter().filter(|r| r.single).map(|r| r.k_mesh).fold(f64::INFINITY, f64::min)),
        f(pm.m_e),
        f(pm.omega_n)
    )];
    if let Some(eb) = pm.eps_b {
        let nbi = nb as usize;
        let mean = |rows: &[geardyn_physics::pair::StiffnessRow]| {
            rows.iter().map(|r| r.k_mesh).sum::<f64>() / rows.len() as f64
        };
        let broken_cycle: Vec<_> = pm
            .rows
            .iter()
            .filter(|r| r.position >= nb && r.position < nb + 1.0)
            .copied()
            .collect();
        readings.push(format!(
            "The chipped tooth leaves mesh at D1: eps_b = {} < eps; the double zone of cycle {} shrinks from {} to {} of the cycle, and the mean stiffness of that cycle drops by {:.1}% (single-tooth zone II).",
            f(eb),
            nbi,
            f(pm.geom.eps - 1.0),
            f(eb - 1.0),
            100.0 * (1.0 - mean(&broken_cycle) / mean(&healthy.rows))
        ));
    }
    let fmax = pm
        .rows
        .iter()
        .map(|r| (r.h_drive - 1.0).abs())
        .fold(0.0, f64::max);
    readings.extend(readings_extra);
    readings.push(format!("Friction changes the mesh force by at most {:.2}% (|h - 1| <= {}); h flips from below to above 1 at the pitch point in the single-tooth zone.", 100.0 * fmax, f(fmax)));
    let table = ctx.table(
        &dir.join("stiffness.csv"),
        "Stiffness table (every twelfth of the rows; full table in the CSV)",
        &[
            "position",
            "k_pair1 (N/m)",
            "k_pair2 (N/m)",
            "k_mesh (N/m)",
            "L1",
            "L2",
            "h_drive",
            "h_back",
        ],
        pm.rows
            .iter()
            .map(|r| {
                vec![
                    f(r.position),
                    f(r.k_pair1),
                    f(r.k_pair2),
                    f(r.k_mesh),
                    f(r.share1),
                    f(r.share2),
                    f(r.h_drive),
                    f(r.h_back),
                ]
            })
            .collect(),
    )?;
    let short = Table {
        rows: table
            .rows
            .iter()
            .step_by((table.rows.len() / 12).max(1))
            .take(12)
            .cloned()
            .collect(),
        ..table
    };
    Ok(Section {
        id: "stiffness".into(),
        title: "Mesh stiffness, load sharing, friction and backlash along the excitation period".into(),
        parameters: format!("{:?} pair z1 = {}, z2 = {}, m = {} mm, face width {} mm, E = {} GPa, mu = {}", pm.spec.kind, pm.spec.z1, pm.spec.z2, pm.spec.module_mm, pm.spec.face_width_mm, pm.spec.youngs_modulus_gpa, pm.spec.mu),
        method: format!("Potential-energy method (Hertz, bending, shear, axial; Sainsot fillet foundation), {} samples per mesh cycle; load sharing by pair stiffness; friction factors from the friction arms.", pm.spec.samples_per_cycle),
        figures: figs,
        readings,
        tables: vec![short],
        claims: vec![],
        seconds: 0.0,
    })
}

fn bif_figure(
    ctx: &Ctx,
    stem: &Path,
    param: &str,
    results: &[TaskResult],
    sections: &[Sec],
    title: &str,
    impact_force: bool,
) -> Result<Figure> {
    sweep_output::plot_bifurcation(stem, param, results, sections, title)?;
    let mut fig = ctx.fig(stem, title);
    if impact_force {
        let pts: Vec<(f64, f64)> = results
            .iter()
            .flat_map(|r| {
                r.runs.iter().flat_map(move |run| {
                    run.impact_force_per_period
                        .iter()
                        .map(move |&v| (r.value, v))
                })
            })
            .collect();
        let stem2 = stem.with_file_name(format!(
            "{}_impact_force",
            stem.file_name().and_then(|s| s.to_str()).unwrap_or("fig")
        ));
        xy_chart(
            &stem2,
            &Chart {
                title: "Largest back-side impact force per excitation period",
                x_label: param,
                y_label: "impact force (units of k_av b_c)",
            },
            &[Series {
                label: "",
                points: &pts,
                mark: Mark::Dots(2),
                color: PALETTE[6],
            }],
        )?;
        fig.caption
            .push_str(" The impact-force record is in the next figure.");
        let _ = ctx.fig(&stem2, "");
    }
    Ok(fig)
}

/// Seed A: the external pair with a chipped pinion tooth.
pub fn breakage_plan(ctx: &Ctx) -> Result<Vec<Section>> {
    let mut out = Vec::new();
    let pm = ctx
        .scenario
        .pair_model()
        .cloned()
        .context("the breakage plan needs the physical [pair]")?;
    out.push(ctx.study("stiffness", &(), |dir| stiffness_section(ctx, &pm, dir))?);
    let base = ctx.base()?;
    let healthy_base = base.healthy()?;

    // contact force over a pinion revolution, healthy versus broken
    out.push(ctx.study("revolution", &(), |dir| {
        let sim = SimOptions { trajectory: true, samples_per_cycle: 64, ..ctx.sim((60, 200), (1, 1)) };
        let mb = base.model().clone();
        let mh = healthy_base.model().clone();
        let rb = simulate(&mb, [0.0, 0.0], &sim)?;
        // the healthy model's excitation period is one mesh cycle: run the same time
        let sim_h = SimOptions { transient_periods: sim.transient_periods * mb.cycles_per_period() as u64, record_periods: mb.cycles_per_period() as u64, ..sim };
        let rh = simulate(&mh, [0.0, 0.0], &sim_h)?;
        let t0b = rb.trajectory.first().map_or(0.0, |p| p.tau);
        let t0h = rh.trajectory.first().map_or(0.0, |p| p.tau);
        let cyc = mb.mesh_cycle_time();
        let fb: Vec<(f64, f64)> = rb.trajectory.iter().map(|p| ((p.tau - t0b) / cyc, p.mesh_force)).collect();
        let fh: Vec<(f64, f64)> = rh.trajectory.iter().map(|p| ((p.tau - t0h) / cyc, p.mesh_force)).collect();
        let stem = dir.join("force_revolution");
        xy_chart(&stem, &Chart { title: "Dynamic mesh force over one pinion revolution", x_label: "mesh cycles", y_label: "F_m (units of k_av b_c)" }, &[
            Series { label: "healthy", points: &fh, mark: Mark::Line, color: PALETTE[0] },
            Series { label: "broken", points: &fb, mark: Mark::Line, color: PALETTE[1] },
        ])?;
        let (sb, sh) = (summarize(&mb, &rb, &sim), summarize(&mh, &rh, &sim_h));
        let peak_cycle = fb.iter().max_by(|a, b| a.1.total_cmp(&b.1)).map_or(0.0, |p| p.0);
        Ok(Section {
            id: "revolution".into(),
            title: "Contact force over a pinion revolution: healthy versus broken".into(),
            parameters: format!("omega = {}, F = {}, xi = {}, c = {}, R = {:?}", base.params().omega, base.params().load, base.params().xi, base.params().c, base.params().back_side),
            method: format!("Dormand–Prince 5(4), rtol 1e-9; {} excitation periods of transient, then one pinion revolution ({} mesh cycles).", sim.transient_periods, mb.cycles_per_period()),
            figures: vec![ctx.fig(&stem, "Mesh force over one revolution of the pinion; the broken tooth's cycle starts at 0.")],
            readings: vec![
                format!("Maximum mesh force: healthy {} , broken {} ({:+.1}%); the broken pair's peak lies in mesh cycle {:.0}.", f(rh.max_force), f(rb.max_force), 100.0 * (rb.max_force / rh.max_force - 1.0), peak_cycle.floor()),
                format!("Motion: healthy pair {} ({}), broken pair {} ({}).", sh.label, sh.health_text(), sb.label, sb.health_text()),
            ],
            tables: vec![],
            claims: vec![],
            seconds: 0.0,
        })
    })?);

    // load sweep, broken and healthy
    let nf = ctx.n(40, 150);
    let fvals = linspace(0.005, 0.15, nf);
    let sim = ctx.sim((60, 200), (24, 60));
    out.push(ctx.study("load_sweep", &(nf,), |dir| {
        let secs = vec![Sec::Strobe, Sec::Impact];
        let o = sweep_opts("F", fvals.clone(), SweepMode::Fixed, sim, secs.clone(), false);
        let rb = ctx.sweep(dir, "broken F sweep", &base, &o)?;
        // the healthy pair's excitation period is one mesh cycle: integrate the same time
        let zp = base.model().clone().cycles_per_period() as u64;
        let oh = SweepOptions { sim: SimOptions { transient_periods: sim.transient_periods * zp, record_periods: sim.record_periods * zp, ..sim }, ..o.clone() };
        let rh = ctx.sweep(dir, "healthy F sweep", &healthy_base, &oh)?;
        let fig_b = bif_figure(ctx, &dir.join("bif_F_broken"), "F", &rb, &secs, "Broken pair: bifurcation over the load F (stroboscopic and impact sections)", true)?;
        let fig_bf = ctx.fig(&dir.join("bif_F_broken_impact_force"), "Broken pair: largest back-side impact force per excitation period over F.");
        let fig_h = bif_figure(ctx, &dir.join("bif_F_healthy"), "F", &rh, &secs, "Healthy pair: bifurcation over the load F", false)?;
        let ib = label_intervals(&rb, 0);
        let ih = label_intervals(&rh, 0);
        let (imp_b, imp_h) = (impact_values(&rb, 0), impact_values(&rh, 0));
        let mf = |r: &[TaskResult]| r.iter().map(|t| t.runs[0].max_force).collect::<Vec<f64>>();
        let (mb, mh) = (mf(&rb), mf(&rh));
        let higher = mb.iter().zip(&mh).filter(|(b, h)| b > h).count();
        let half = fvals[fvals.len() / 2];
        let low = imp_b.iter().filter(|v| **v < half).count();
        let high = imp_b.iter().filter(|v| **v >= half).count();
        let claims = vec![
            Claim {
                claim: "A larger load suppresses back-side impact".into(),
                source: "seed A (breakage), load sweep".into(),
                evidence: format!(
                    "broken pair: impacts at {} of {} values with F < {} and {} of {} with F >= {}{}",
                    low,
                    fvals.len() / 2,
                    f(half),
                    high,
                    fvals.len() - fvals.len() / 2,
                    f(half),
                    imp_b.last().map_or(String::new(), |v| format!("; largest F with impacts: {}", f(*v)))
                ),
                verdict: verdict(if imp_b.is_empty() { None } else { Some(low > high) }),
            },
            Claim {
                claim: "Localized breakage raises the maximum mesh force".into(),
                source: "seeds A (breakage)".into(),
                evidence: format!("max mesh force broken > healthy at {higher} of {} load values", fvals.len()),
                verdict: verdict(Some(higher * 2 > fvals.len())),
            },
            Claim {
                claim: "Breakage promotes back-side impact".into(),
                source: "seed A".into(),
                evidence: format!("values with impacts: broken {}, healthy {}", imp_b.len(), imp_h.len()),
                verdict: verdict(if imp_b.len() == imp_h.len() { None } else { Some(imp_b.len() > imp_h.len()) }),
            },
        ];
        let table = ctx.table(
            &dir.join("labels_F.csv"),
            "Motion labels of the broken pair over F (intervals), with back-side impact",
            &["F from", "F to", "label", "back-side impact"],
            ib.iter().map(|(a, b, l, i)| vec![f(*a), f(*b), l.clone(), (if *i { "yes" } else { "no" }).into()]).collect(),
        )?;
        Ok(Section {
            id: "load_sweep".into(),
            title: "Bifurcation over the load F: broken versus healthy".into(),
            parameters: format!("F in [0.005, 0.15] ({} values), omega = {}, xi = {}; fixed initial state (0, 0)", nf, base.params().omega, base.params().xi),
            method: format!("Dormand–Prince 5(4), rtol 1e-9; {} transient + {} recorded excitation periods (each {} mesh cycles) per value; stroboscopic section and back-side impacts (impact velocity).", sim.transient_periods, sim.record_periods, base.model().clone().cycles_per_period()),
            figures: vec![fig_b, fig_bf, fig_h],
            readings: vec![
                format!("Broken: {}.", describe_intervals("F", &ib)),
                format!("Healthy: {}.", describe_intervals("F", &ih)),
                if imp_b.is_empty() { "The broken pair shows no back-side impact over this range.".into() } else { format!("Back-side impacts of the broken pair occur for F between {} and {} ({} values).", f(imp_b[0]), f(*imp_b.last().unwrap_or(&imp_b[0])), imp_b.len()) },
            ],
            tables: vec![table],
            claims,
            seconds: 0.0,
        })
    })?);

    // frequency sweep
    let nw = ctx.n(50, 200);
    out.push(ctx.study("frequency_sweep", &(nw,), |dir| {
        let secs = vec![Sec::Strobe, Sec::Impact];
        let o = sweep_opts("omega", linspace(0.1, 3.0, nw), SweepMode::Fixed, sim, secs.clone(), false);
        let r = ctx.sweep(dir, "broken omega sweep", &base, &o)?;
        let fig = bif_figure(ctx, &dir.join("bif_omega"), "omega", &r, &secs, "Broken pair: bifurcation over omega", true)?;
        let fig2 = ctx.fig(&dir.join("bif_omega_impact_force"), "Largest back-side impact force per excitation period over omega.");
        let iv = label_intervals(&r, 0);
        let chaos = |lo: f64, hi: f64| r.iter().filter(|t| t.value >= lo && t.value < hi && chaotic(&t.runs[0].label)).count();
        let count = |lo: f64, hi: f64| r.iter().filter(|t| t.value >= lo && t.value < hi).count();
        let (cl, nl) = (chaos(0.1, 0.6), count(0.1, 0.6));
        let (cm, nm) = (chaos(0.6, 2.4), count(0.6, 2.4));
        let (ch, nh) = (chaos(2.4, 3.01), count(2.4, 3.01));
        let frac = |c: usize, n: usize| if n > 0 { c as f64 / n as f64 } else { 0.0 };
        Ok(Section {
            id: "frequency_sweep".into(),
            title: "Bifurcation over the mesh frequency omega".into(),
            parameters: format!("omega in [0.1, 3] ({} values), F = {}, xi = {}", nw, base.params().load, base.params().xi),
            method: format!("As the load sweep: {} + {} excitation periods per value, fixed initial state.", sim.transient_periods, sim.record_periods),
            figures: vec![fig, fig2],
            readings: vec![format!("{}.", describe_intervals("omega", &iv))],
            tables: vec![],
            claims: vec![Claim {
                claim: "Chaos appears at low and at high meshing frequency".into(),
                source: "seed A, frequency sweep".into(),
                evidence: format!("non-periodic motion at {cl}/{nl} values with omega < 0.6, {cm}/{nm} in [0.6, 2.4), {ch}/{nh} with omega >= 2.4"),
                verdict: verdict(Some(frac(cl, nl) > frac(cm, nm) && frac(ch, nh) > frac(cm, nm))),
            }],
            seconds: 0.0,
        })
    })?);

    // phase portraits at representative points
    out.push(ctx.study("portraits", &(), |dir| {
        let mut figs = Vec::new();
        let mut readings = Vec::new();
        for (i, fv) in [0.02, 0.12].iter().enumerate() {
            let m = with(&base, &[("F", *fv)])?.model().clone();
            let sim = SimOptions { trajectory: true, samples_per_cycle: 32, ..ctx.sim((40, 150), (4, 10)) };
            let r = simulate(&m, [0.0, 0.0], &sim)?;
            let s = summarize(&m, &r, &sim);
            let stem = dir.join(format!("portrait_{i}"));
            phase_figure(&stem, &format!("Phase portrait, F = {fv}: {}", s.label), &r)?;
            figs.push(ctx.fig(&stem, &format!("F = {fv}: phase portrait, stroboscopic points and back-side impacts.")));
            readings.push(format!("F = {fv}: label {}, {} impacts in {} periods, P_ID = {}, max mesh force {}.", s.label, s.impacts, sim.record_periods, f(s.p_id), f(s.max_force)));
        }
        Ok(Section {
            id: "portraits".into(),
            title: "Phase portraits and Poincaré sections at representative loads".into(),
            parameters: format!("omega = {}, xi = {}; F = 0.02 and 0.12", base.params().omega, base.params().xi),
            method: "Dormand–Prince 5(4); trajectories sampled 32 times per mesh cycle from the dense output.".into(),
            figures: figs,
            readings,
            tables: vec![],
            claims: vec![],
            seconds: 0.0,
        })
    })?);
    Ok(out)
}

fn basin_section(
    ctx: &Ctx,
    dir: &Path,
    name: &str,
    model: &MeshModel,
    n: usize,
    title: &str,
) -> Result<(Figure, Vec<String>, BasinResult)> {
    let d = model.params().d_single;
    let opts = BasinOptions {
        x: Axis {
            min: -2.0 * d,
            max: 2.0 * d,
            n,
        },
        v: Axis {
            min: -1.5,
            max: 1.5,
            n,
        },
        identify: IdentifyOptions {
            sim: SimOptions {
                method: Method::Dopri {
                    rtol: 1e-7,
                    atol: 1e-10,
                },
                transient_periods: 300,
                record_periods: 32,
                ..Default::default()
            },
            ..Default::default()
        },
    };
    let r = ctx.basins(dir, name, model, &opts)?;
    let stem = dir.join(name);
    sweep_output::plot_basins(&stem, title, &r)?;
    let readings = vec![format!(
        "{}: {} attractor(s): {}; divergent {:.3}, unresolved {:.3}; {:.1}% of cells on a basin boundary.",
        title,
        r.attractors.len(),
        r.attractors
            .iter()
            .map(|a| format!("{} ({}, P_ID {}, fraction {:.3})", a.descriptor.label, geardyn_analysis::simulate::health_text(a.descriptor.healthy, a.descriptor.period > 0), f(a.descriptor.p_id), a.fraction))
            .collect::<Vec<_>>()
            .join(", "),
        r.diverged,
        r.failed,
        100.0 * r.boundary_fraction
    )];
    Ok((ctx.fig(&stem, title), readings, r))
}

fn continuation_table(ctx: &Ctx, dir: &Path, param: &str, r: &ContinuationResult) -> Result<Table> {
    let fmt = |l: &Vec<(usize, String, f64, f64)>| {
        l.iter()
            .map(|e| format!("{} [{:.2}–{:.2}]", e.1, e.2, e.3))
            .collect::<Vec<_>>()
            .join(", ")
    };
    ctx.table(
        &dir.join(format!("attractors_{param}.csv")),
        &format!("Attractor evolution over {param}: intervals, healthy and non-healthy attractors with basin fractions"),
        &[&format!("{param} from"), &format!("{param} to"), "healthy attractors", "non-healthy attractors"],
        r.intervals.iter().map(|iv| vec![f(iv.from), f(iv.to), fmt(&iv.healthy), fmt(&iv.unstable)]).collect(),
    )
}

fn continuation_figure(
    ctx: &Ctx,
    stem: &Path,
    param: &str,
    values: &[f64],
    r: &ContinuationResult,
    title: &str,
) -> Result<Figure> {
    sweep_output::plot_continuation(stem, title, param, values, r)?;
    Ok(ctx.fig(stem, title))
}

/// Seed B: the internal pair.
pub fn internal_plan(ctx: &Ctx) -> Result<Vec<Section>> {
    let mut out = Vec::new();
    if let Some(pm) = ctx.scenario.pair_model().cloned() {
        out.push(ctx.study("stiffness", &(), |dir| stiffness_section(ctx, &pm, dir))?);
    }
    let base = ctx.base()?;
    let five = vec![Sec::Strobe, Sec::DsUp, Sec::DsDown, Sec::DdUp, Sec::DdDown];
    let sim = ctx.sim((150, 300), (40, 100));
    for (id, param, lo, hi, fixed, title) in [
        (
            "backlash_sweep",
            "D",
            0.3,
            2.0,
            vec![("xi", 0.27), ("omega", 1.4)],
            "Bifurcation and TLE over the static half backlash D",
        ),
        (
            "xi_sweep",
            "xi",
            0.001,
            0.3,
            vec![("F", 0.05), ("omega", 1.5)],
            "Bifurcation and TLE over the error amplitude xi",
        ),
    ] {
        let n = ctx.n(30, 150);
        out.push(ctx.study(id, &(n, param), |dir| {
            let b = with(&base, &fixed)?;
            let o = sweep_opts(param, linspace(lo, hi, n), SweepMode::Fixed, sim, five.clone(), true);
            let r = ctx.sweep(dir, id, &b, &o)?;
            let fig = bif_figure(ctx, &dir.join(format!("bif_{id}")), param, &r, &five, title, false)?;
            let iv = label_intervals(&r, 0);
            let mut readings = vec![format!("{}.", describe_intervals(param, &iv))];
            readings.extend(tle_reading(&r, param));
            let pid: Vec<(f64, f64)> = r.iter().map(|t| (t.value, t.runs[0].p_id)).collect();
            let stem = dir.join(format!("pid_{id}"));
            xy_chart(&stem, &Chart { title: "Dynamic instability proportion P_ID", x_label: param, y_label: "P_ID" }, &[Series { label: "", points: &pid, mark: Mark::Dots(3), color: PALETTE[1] }])?;
            let fixed_txt: Vec<String> = fixed.iter().map(|(k, v)| format!("{k} = {v}")).collect();
            Ok(Section {
                id: id.into(),
                title: title.into(),
                parameters: format!("{param} in [{lo}, {hi}] ({n} values), {}; other parameters as the preset", fixed_txt.join(", ")),
                method: format!("Dormand–Prince 5(4), {} + {} periods; five sections (stroboscopic, x = ±D_s, ±D_d crossings, velocity shown); TLE by the variational equation with saltation matrices over the recorded periods.", sim.transient_periods, sim.record_periods),
                figures: vec![fig, ctx.fig(&stem, "P_ID over the parameter.")],
                readings,
                tables: vec![],
                claims: vec![],
                seconds: 0.0,
            })
        })?);
    }
    let nm = ctx.n(10, 36);
    out.push(ctx.study("map_xi_F", &(nm,), |dir| {
        let o = MapOptions {
            x_param: "xi".into(),
            x_values: linspace(0.001, 0.3, nm),
            y_param: "F".into(),
            y_values: linspace(0.001, 0.2, nm),
            sim: ctx.sim((100, 300), (20, 60)),
            y0: [0.0, 0.0],
            lyapunov: false,
        };
        let cells = ctx.map(dir, "xi-F map", &base, &o)?;
        let vals: Vec<f64> = cells.iter().map(|c| c.metric("max_force").unwrap_or(f64::NAN)).collect();
        let lo = vals.iter().copied().filter(|v| v.is_finite()).fold(f64::INFINITY, f64::min);
        let hi = vals.iter().copied().filter(|v| v.is_finite()).fold(f64::NEG_INFINITY, f64::max);
        let colors: Vec<_> = vals.iter().map(|v| colormap((v - lo) / (hi - lo).max(1e-12))).collect();
        let (dx, dy) = (0.3 / nm as f64, 0.2 / nm as f64);
        let stem = dir.join("map_max_force");
        raster_chart(&stem, &Chart { title: "Maximum dynamic mesh force over (xi, F)", x_label: "xi", y_label: "F" }, &Raster { x: (0.001 - dx / 2.0, 0.3 + dx / 2.0, nm), y: (0.001 - dy / 2.0, 0.2 + dy / 2.0, nm), colors: &colors }, &[], Some((lo, hi)))?;
        let argmax = cells.iter().max_by(|a, b| a.max_force.total_cmp(&b.max_force));
        let healthy = cells.iter().filter(|c| c.healthy).count();
        Ok(Section {
            id: "map_xi_F".into(),
            title: "Maximum mesh force over the (xi, F) plane".into(),
            parameters: format!("xi in [0.001, 0.3], F in [0.001, 0.2], {nm} x {nm} grid, omega = {}", base.params().omega),
            method: "One run per cell from (0, 0); Dormand–Prince 5(4).".into(),
            figures: vec![ctx.fig(&stem, "Maximum dynamic mesh force (colour bar in units of k_av b_c).")],
            readings: vec![format!(
                "Maximum mesh force ranges from {} to {}{}; {} of {} cells end on a healthy attractor.",
                f(lo),
                f(hi),
                argmax.map_or(String::new(), |c| format!(" (largest at xi = {}, F = {})", f(c.x), f(c.y))),
                healthy,
                cells.len()
            )],
            tables: vec![],
            claims: vec![],
            seconds: 0.0,
        })
    })?);
    // multi-initial and continuation: omega (F = 0.07, xi = 0.23) and F (omega = 1.4, xi = 0.09)
    for (id, param, lo, hi, fixed) in [
        (
            "multi_omega",
            "omega",
            0.5,
            2.5,
            vec![("F", 0.07), ("xi", 0.23)],
        ),
        (
            "multi_F",
            "F",
            0.001,
            0.2,
            vec![("omega", 1.4), ("xi", 0.09)],
        ),
    ] {
        let (n, k) = (ctx.n(16, 48), ctx.n(8, 24));
        out.push(ctx.study(id, &(n, k), |dir| {
            let b = with(&base, &fixed)?;
            let d = b.params().d_single;
            let o = sweep_opts(param, linspace(lo, hi, n), SweepMode::Multi { ics: ctx.n(6, 12), seed: 1, x0_range: (-1.5 * d, 1.5 * d), v0_range: (-1.0, 1.0) }, ctx.sim((150, 300), (24, 60)), vec![Sec::Strobe], false);
            let r = ctx.sweep(dir, &format!("{id} multi-initial"), &b, &o)?;
            let fig = bif_figure(ctx, &dir.join(format!("bif_{id}")), param, &r, &[Sec::Strobe], &format!("Multi-initial bifurcation over {param}, points coloured by attractor label"), false)?;
            let co = ContinuationOptions {
                param: param.into(),
                values: linspace(lo, hi, n),
                ics: k,
                seed: 1,
                x0_range: (-2.0 * d, 2.0 * d),
                v0_range: (-1.5, 1.5),
                identify: IdentifyOptions { sim: SimOptions { method: Method::Dopri { rtol: 1e-7, atol: 1e-10 }, transient_periods: 300, record_periods: 32, ..Default::default() }, ..Default::default() },
            };
            let c = ctx.continuation(dir, &format!("{id} continuation"), &b, &co)?;
            let fig2 = continuation_figure(ctx, &dir.join(format!("cont_{id}")), param, &co.values, &c, &format!("Attractor continuation over {param}: healthy basin fraction and branches"))?;
            let table = continuation_table(ctx, dir, param, &c)?;
            let mut readings: Vec<String> = c.events.iter().take(12).map(|e| format!("Between {param} = {} and {}: {}.", f(e.from), f(e.to), e.text)).collect();
            if c.events.len() > 12 {
                readings.push(format!("... {} events in all (continuation.json).", c.events.len()));
            }
            let max_healthy = c.points.iter().filter(|p| p.healthy).map(|p| p.fraction).fold(0.0, f64::max);
            readings.push(format!("The largest basin fraction of a healthy attractor is {:.2}.", max_healthy));
            geardyn_io::output::write_json(&dir.join("continuation.json"), &c)?;
            let mut claims = vec![];
            if param == "F" {
                let near: Vec<&geardyn_analysis::continuation::BranchPoint> = c.points.iter().filter(|p| (p.value - 0.05).abs() <= 0.02).collect();
                let mut near_multi: Vec<String> = r
                    .iter()
                    .filter(|t| (t.value - 0.05).abs() <= 0.02)
                    .flat_map(|t| t.runs.iter().map(|run| class(&run.label)))
                    .collect();
                near_multi.sort();
                near_multi.dedup();
                let p2 = near.iter().any(|p| p.period == 2) || near_multi.iter().any(|l| l.starts_with("2-"));
                let p4 = near.iter().any(|p| p.period == 4) || near_multi.iter().any(|l| l.starts_with("4-"));
                claims.push(Claim {
                    claim: "Period-2 and period-4 attractors coexist near F = 0.05".into(),
                    source: "seed B, multi-initial F sweep (omega = 1.4, xi = 0.09)".into(),
                    evidence: format!("labels found for F in [0.03, 0.07]: {}", near_multi.join(", ")),
                    verdict: verdict(Some(p2 && p4)),
                });
            } else {
                let half = c.points.iter().filter(|p| p.healthy && p.period == 1 && (p.fraction - 0.5).abs() <= 0.15).count();
                claims.push(Claim {
                    claim: "A healthy period-1 attractor holds about half of the sampled initial states".into(),
                    source: "seed B, attractor continuation over omega".into(),
                    evidence: format!("values where a healthy period-1 attractor has a basin fraction in [0.35, 0.65]: {half} of {n}; largest healthy fraction {max_healthy:.2}"),
                    verdict: verdict(Some(half > 0)),
                });
            }
            let fixed_txt: Vec<String> = fixed.iter().map(|(k, v)| format!("{k} = {v}")).collect();
            Ok(Section {
                id: id.into(),
                title: format!("Coexisting attractors over {param}: multi-initial diagram and continuation"),
                parameters: format!("{param} in [{lo}, {hi}] ({n} values), {}", fixed_txt.join(", ")),
                method: format!("Multi-initial: {} seeded initial states per value; continuation: {k} initial states per value, attractors identified on the stroboscopic section (early capture 1e-4), matched across values by basin overlap.", ctx.n(6, 12)),
                figures: vec![fig, fig2],
                readings,
                tables: vec![table],
                claims,
                seconds: 0.0,
            })
        })?);
    }
    let nb = ctx.n(40, 140);
    out.push(ctx.study("basins", &(nb,), |dir| {
        let mut figs = Vec::new();
        let mut readings = Vec::new();
        for (i, sets) in [vec![("omega", 1.4), ("F", 0.07), ("xi", 0.23)], vec![("omega", 1.4), ("F", 0.05), ("xi", 0.09)]].iter().enumerate() {
            let m = with(&base, sets)?.model().clone();
            let txt: Vec<String> = sets.iter().map(|(k, v)| format!("{k} = {v}")).collect();
            let (fig, r, _) = basin_section(ctx, dir, &format!("basins_{i}"), &m, nb, &format!("Basins at {}", txt.join(", ")))?;
            figs.push(fig);
            readings.extend(r);
        }
        Ok(Section {
            id: "basins".into(),
            title: "Basins of attraction at representative points".into(),
            parameters: format!("{nb} x {nb} initial states (x0 in ±2 D_s, x0' in ±1.5) at phase 0"),
            method: "Automatic attractor identification with early capture; deterministic multi-pass grid; ids sorted healthy first.".into(),
            figures: figs,
            readings,
            tables: vec![],
            claims: vec![],
            seconds: 0.0,
        })
    })?);
    Ok(out)
}

/// Case C1.
pub fn classic_plan(ctx: &Ctx) -> Result<Vec<Section>> {
    let mut out = Vec::new();
    let base = ctx.base()?;
    let n = ctx.n(60, 200);
    let sim = ctx.sim((150, 300), (40, 100));
    out.push(ctx.study("bifurcation", &(n,), |dir| {
        let o = sweep_opts("omega", linspace(0.5, 2.0, n), SweepMode::Fixed, sim, vec![Sec::Strobe], true);
        let r = ctx.sweep(dir, "C1 omega sweep", &base, &o)?;
        let fig = bif_figure(ctx, &dir.join("bif_omega"), "omega", &r, &[Sec::Strobe], "C1: bifurcation over omega with the TLE", false)?;
        let iv = label_intervals(&r, 0);
        let first_p2 = r.iter().find(|t| t.runs[0].period == 2).map(|t| t.value);
        let chaos: Vec<f64> = r.iter().filter(|t| chaotic(&t.runs[0].label)).map(|t| t.value).collect();
        let mut readings = vec![format!("{}.", describe_intervals("omega", &iv))];
        readings.extend(tle_reading(&r, "omega"));
        Ok(Section {
            id: "bifurcation".into(),
            title: "C1: bifurcation diagram and top Lyapunov exponent over omega".into(),
            parameters: format!("omega in [0.5, 2] ({n} values), F = {}, xi = {}, c = {}", base.params().load, base.params().xi, base.params().c),
            method: format!("Dormand–Prince 5(4), {} + {} periods, fixed initial state (0, 0); TLE variational with saltation.", sim.transient_periods, sim.record_periods),
            figures: vec![fig],
            readings,
            tables: vec![],
            claims: vec![Claim {
                claim: "C1 shows period 1, period doubling near omega = 0.9 and chaos around 1.1–1.65".into(),
                source: "docs/model.md §6".into(),
                evidence: format!(
                    "first period-2 value {}; non-periodic values from {} to {} ({} values)",
                    first_p2.map_or("none".into(), f),
                    chaos.first().map_or("-".into(), |v| f(*v)),
                    chaos.last().map_or("-".into(), |v| f(*v)),
                    chaos.len()
                ),
                verdict: verdict(Some(first_p2.is_some_and(|v| (0.8..1.0).contains(&v)) && chaos.first().is_some_and(|v| (1.0..1.25).contains(v)) && chaos.last().is_some_and(|v| (1.5..1.8).contains(v)))),
            }],
            seconds: 0.0,
        })
    })?);
    out.push(ctx.study("response", &(n,), |dir| {
        let o = sweep_opts("omega", linspace(0.5, 2.0, ctx.n(40, 150)), SweepMode::Sweep, sim, vec![], false);
        let r = ctx.sweep(dir, "C1 frequency response", &base, &o)?;
        let stem = dir.join("response");
        sweep_output::plot_response(&stem, "omega", &r, "C1: frequency response, up and down sweeps")?;
        let jumps = detect_jumps(&r);
        let readings = if jumps.is_empty() {
            vec!["No jump detected.".into()]
        } else {
            jumps.iter().map(|j| format!("Jump on the {} sweep between omega = {} and {}: RMS of x {} -> {}.", j.branch, f(j.from), f(j.to), f(j.rms_before), f(j.rms_after))).collect()
        };
        Ok(Section {
            id: "response".into(),
            title: "C1: frequency response with hysteresis".into(),
            parameters: "omega in [0.5, 2], continuation upwards and downwards".into(),
            method: "Each value starts from the final state of the previous one; RMS of the alternating part of x and of the mesh force.".into(),
            figures: vec![ctx.fig(&stem, "RMS of x and of the mesh force, sweep up and down.")],
            readings,
            tables: vec![],
            claims: vec![],
            seconds: 0.0,
        })
    })?);
    let nb = ctx.n(40, 160);
    out.push(ctx.study("basins", &(nb,), |dir| {
        let m = with(&base, &[("omega", 1.8)])?.model().clone();
        let (fig, readings, _) =
            basin_section(ctx, dir, "basins_1_8", &m, nb, "C1 basins at omega = 1.8")?;
        Ok(Section {
            id: "basins".into(),
            title: "C1: basins of attraction in the hysteresis window".into(),
            parameters: format!("omega = 1.8, {nb} x {nb} initial states"),
            method: "Automatic attractor identification with early capture.".into(),
            figures: vec![fig],
            readings,
            tables: vec![],
            claims: vec![],
            seconds: 0.0,
        })
    })?);
    Ok(out)
}
