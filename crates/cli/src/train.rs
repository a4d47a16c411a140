//! Gear trains on the model commands: `simulate` and `bifurcation` with `--preset planetary`,
//! `--preset two-stage`, `--preset pair` (the single pair written as a train) or `--system FILE`.
//! The train's dynamic model (`geardyn_train::dynamics`) runs through the generic analyses
//! (decided simulation, decided sweep); outputs carry one label, force range and dynamic factor
//! per mesh, and for a planetary stage the load-sharing factor of each planet.

use crate::run_config::ConfigArgs;
use crate::sweep::SimArgs;
use anyhow::{bail, Context, Result};
use geardyn_analysis::classify::{simulate_decided, Decide};
use geardyn_analysis::generic::{decided_sweep, Family};
use geardyn_analysis::simulate::{SimOptions, Summary};
use geardyn_io::figure::{palette, write_figure, Figure, Layer, LegendEntry, Panel, Style};
use geardyn_io::output::write_text;
use geardyn_io::run_record;
use geardyn_model::GearSystem;
use geardyn_train::dynamics::{TrainModel, TrainOperating};
use geardyn_train::TrainSpec;
use std::path::Path;

/// A train and its operating point, from the command line.
pub struct TrainRun {
    /// The description.
    pub spec: TrainSpec,
    /// The dimensionless operating point.
    pub op: TrainOperating,
    /// `preset NAME` or `system FILE`, for titles.
    pub source: String,
    /// The operating fields given by `--set`, in order.
    pub set_fields: Vec<String>,
}

impl TrainRun {
    /// Runs `job` with the checkpoint of the folder `out` (its context: this train's description
    /// and operating point; `force` sets aside a checkpoint of other settings) and the progress
    /// line: how every resumable train analysis runs.
    pub(crate) fn execute<J: geardyn_exec::Job>(
        &self,
        job: &J,
        out: &Path,
        force: bool,
    ) -> Result<J::Output>
    where
        J::Record: serde::Serialize + serde::de::DeserializeOwned,
    {
        let context = serde_json::json!({ "system": self.spec.to_toml(), "operating": self.op });
        Ok(geardyn_exec::execute(
            job,
            Some(&mut geardyn_exec::Checkpointed::folder(
                out, &context, force,
            )?),
            &crate::sweep::progress(out),
        )?)
    }

    /// The description with its operating point (`[operating]`): what `--system` runs again.
    pub fn description(&self) -> String {
        let mut spec = self.spec.clone();
        spec.operating = Some(self.op);
        spec.to_toml()
    }

    /// Writes `system.toml` ([`TrainRun::description`]) and `run.json` into the folder `out` of
    /// command `kind` (`swept`: the parameters it varied).
    pub fn write_record(
        &self,
        out: &Path,
        kind: &str,
        swept: &[run_record::Swept],
        started: std::time::Instant,
    ) -> Result<()> {
        write_text(&out.join("system.toml"), &self.description())?;
        run_record::write_train_record(
            out,
            kind,
            serde_json::json!({
                "name": self.spec.name,
                "source": self.source,
                "operating": self.op,
            }),
            swept,
            started.elapsed().as_secs_f64(),
        )?;
        Ok(())
    }

    /// Refuses swept parameters `axes` that set the stiffness variation's form (`kappa`:
    /// harmonic, `ratio`: rectangular) beside a `--set` or another axis of the other form, which
    /// they would silently replace.
    pub fn check_stiffness_form(&self, axes: &[&str]) -> Result<()> {
        let other = |p: &str| match p {
            "kappa" => Some("ratio"),
            "ratio" => Some("kappa"),
            _ => None,
        };
        for (i, a) in axes.iter().enumerate() {
            let Some(o) = other(a) else { continue };
            if axes[i + 1..].contains(&o) {
                bail!("{a} and {o} both set the stiffness variation's form (harmonic kappa, rectangular ratio): sweep one of them");
            }
            if self.set_fields.iter().any(|f| f == o) {
                bail!("sweeping {a} (the {} stiffness) replaces --set {o} (the {} one): sweep {o}, or leave out --set {o}", if *a == "kappa" { "harmonic" } else { "rectangular" }, if o == "kappa" { "harmonic" } else { "rectangular" });
            }
        }
        Ok(())
    }

    /// The operating point for a title, leaving out the parameters `swept`
    /// (`omega = 1, F = 0.1, xi = 0, c = 0.1, D = 1, rectangular 1.5`).
    pub fn op_text(&self, swept: &[&str]) -> String {
        let op = &self.op;
        let (form, value) = match op.stiffness {
            geardyn_train::dynamics::MeshStiffness::Harmonic { kappa } => ("kappa", kappa),
            geardyn_train::dynamics::MeshStiffness::Rectangular { ratio } => ("ratio", ratio),
        };
        [
            ("omega", op.omega),
            ("F", op.load),
            ("xi", op.xi),
            ("c", op.c),
            ("D", op.d),
            (form, value),
        ]
        .iter()
        .filter(|(n, _)| !swept.contains(n))
        .map(|(n, v)| format!("{n} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
    }

    /// The train's name for figure titles, with the pin errors of its planets if any
    /// (`planetary 25/35/95, 3 planets; pin error planet 1 0.04`).
    pub fn title_name(&self) -> String {
        let errors: Vec<String> = self
            .spec
            .bodies
            .iter()
            .filter(|b| b.pin_error != 0.0)
            .map(|b| format!("{} {}", b.name, b.pin_error))
            .collect();
        if errors.is_empty() {
            self.spec.name.clone()
        } else {
            format!("{}; pin error {}", self.spec.name, errors.join(", "))
        }
    }
}

/// The train the arguments name, if they name one (`--system`, or `--preset` of a train).
pub fn from_args(cfg: &ConfigArgs) -> Result<Option<TrainRun>> {
    let preset = cfg.preset.as_deref().filter(|p| {
        geardyn_train::presets::NAMES.contains(p) && geardyn_io::Config::preset(p).is_err()
    });
    if cfg.system.is_none() && preset.is_none() {
        return Ok(None);
    }
    if cfg.contact.is_some() {
        bail!("--contact applies to the pair model; a train's meshes use the linear law with backlash (docs/model.md, section Gear trains)");
    }
    let mut operating = Vec::new();
    let mut stage = Vec::new();
    for s in &cfg.sets {
        let (k, v) = s
            .split_once('=')
            .with_context(|| format!("--set {s}: expected NAME=VALUE"))?;
        let (k, v) = (k.trim(), v.trim());
        let v: f64 = v
            .parse()
            .with_context(|| format!("--set {s}: the value is not a number"))?;
        if TrainOperating::FIELDS.contains(&k) {
            operating.push((k.to_string(), v));
        } else {
            stage.push((k.to_string(), v));
        }
    }
    let (mut spec, source) = match (&cfg.system, preset) {
        (Some(path), _) => {
            if let Some((k, _)) = stage.first() {
                bail!("--set {k}: not a field of a train's operating point ({}); a description file is edited, not set", TrainOperating::FIELDS.join(", "));
            }
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read --system {}", path.display()))?;
            (
                TrainSpec::from_toml(&text)
                    .with_context(|| format!("--system {}", path.display()))?,
                format!("system {}", path.display()),
            )
        }
        (None, Some(name)) => (
            geardyn_train::presets::by_name(name, &stage)?,
            format!("preset {name}"),
        ),
        (None, None) => unreachable!("checked above"),
    };
    // the description's own operating point (its `[operating]`), then the overrides
    let mut op = spec.operating.take().unwrap_or_default();
    for (k, v) in &operating {
        op.set(k, *v)?;
    }
    geardyn_train::kinematics::Kinematics::of(&spec)?;
    Ok(Some(TrainRun {
        spec,
        op,
        source,
        set_fields: operating.into_iter().map(|(k, _)| k).collect(),
    }))
}

/// The integration settings of a train's run (the defaults with the command's flags) and the
/// cap on the command's work.
pub fn sim_options(sim: &SimArgs) -> Result<(SimOptions, f64)> {
    let mut cfg = geardyn_io::Config::preset("classic")?;
    sim.apply(&mut cfg, &[])?;
    Ok((cfg.sim_options()?, cfg.simulation.max_work))
}

/// Refuses `runs` decided runs of `m` above the work cap.
pub(crate) fn check_work<const N: usize>(
    m: &TrainModel<N>,
    opts: &SimOptions,
    runs: usize,
    cap: f64,
) -> Result<()> {
    let per_run = geardyn_analysis::work::per_run_system(m, opts);
    geardyn_analysis::work::check(runs, per_run, cap).map_err(|e| anyhow::anyhow!(e))?;
    Ok(())
}

/// Runs `$body` with `$m` bound to the train's model in a state of dimension `N`: 8 for up to 4
/// elastic degrees of freedom (exact for a 3-planet stage; the pair and the two-stage drive
/// padded), 16 up to 8 (4 to 7 planets), 24 up to 12, padded with zeros. `TrainModel` steps a
/// padded state exactly as its own (the same numbers: a test), only the integrator's vector work
/// grows; each `N` is a compiled copy of every analysis, about 36 s of this binary's build.
macro_rules! with_model {
    ($spec:expr, $op:expr, |$m:ident| $body:expr) => {{
        let dof = ::geardyn_train::dynamics::elastic_dof($spec);
        with_model!(@arms dof, $spec, $op, $m, $body; 1..=4 => 8, 5..=8 => 16, 9..=12 => 24)
    }};
    (@arms $dof:ident, $spec:expr, $op:expr, $m:ident, $body:expr; $($d:pat => $n:literal),*) => {
        match $dof {
            $($d => {
                let $m = TrainModel::<$n>::new($spec, $op)?;
                $body
            })*
            d => ::anyhow::bail!("the train has {d} elastic degrees of freedom: geardyn integrates trains of 1 to 12"),
        }
    };
}
pub(crate) use with_model;

/// Per mesh: the static force at mean stiffness and the dynamic factor (peak over static).
pub(crate) fn dynamic_factors<const N: usize>(m: &TrainModel<N>, s: &Summary) -> Vec<(f64, f64)> {
    let mesh_max = |k: usize| {
        if s.meshes.is_empty() {
            s.max_force
        } else {
            s.meshes[k].max_force
        }
    };
    m.static_forces()
        .iter()
        .enumerate()
        .map(|(k, &f)| (f, if f > 0.0 { mesh_max(k) / f } else { f64::NAN }))
        .collect()
}

/// `geardyn show` of a train: the resolved description (TOML, ready for `--system`), then as
/// comments the operating point, the speeds and mesh orders per unit input speed, and each
/// mesh's static force at mean stiffness (pin errors and separated meshes included).
pub fn show(t: &TrainRun) -> Result<()> {
    print!("{}", t.description());
    println!(
        "\n# [operating] is the dimensionless operating point (--set omega=, F= (load), xi=, c=, D= (d), kappa= or ratio= (stiffness) override it)"
    );
    let kin = geardyn_train::kinematics::Kinematics::of(&t.spec)?;
    println!(
        "# speed per unit speed of the input ({}):",
        t.spec.load.input
    );
    for (b, r) in t.spec.bodies.iter().zip(&kin.ratios) {
        println!("#   {:<16} {r:.6}", b.name);
    }
    with_model!(&t.spec, &t.op, |m| {
        println!(
            "# per mesh: tooth passes per input revolution, static force at mean stiffness (units k_ref b_c; input {:.0} rpm at this omega):",
            m.input_rpm()
        );
        for (k, (order, f)) in kin.mesh_orders.iter().zip(m.static_forces()).enumerate() {
            println!("#   {:<16} {order:.6}  {f:.6}", m.mesh_name(k));
        }
        Ok(())
    })
}

/// A number for a CSV cell, empty where it is undefined (a dynamic factor of a mesh without
/// static load).
fn finite_or_empty(v: f64) -> String {
    if v.is_finite() {
        v.to_string()
    } else {
        String::new()
    }
}

/// Load-sharing factors: for each group of meshes between one central gear and the planets
/// (bodies on a carrier), `n F_max,j / sum F_max` of each planet `j` — 1 for equal sharing.
pub(crate) fn load_sharing(spec: &TrainSpec, s: &Summary) -> Vec<(String, String, f64)> {
    let carried = |name: &str| {
        spec.body_index(name)
            .is_some_and(|i| spec.bodies[i].carrier.is_some())
    };
    let mut groups: Vec<(String, Vec<(String, f64)>)> = Vec::new();
    for (k, m) in spec.meshes.iter().enumerate() {
        let (central, planet) = match (carried(&m.gears[0]), carried(&m.gears[1])) {
            (false, true) => (&m.gears[0], &m.gears[1]),
            (true, false) => (&m.gears[1], &m.gears[0]),
            _ => continue,
        };
        let f = s.meshes.get(k).map_or(s.max_force, |x| x.max_force);
        match groups.iter_mut().find(|g| &g.0 == central) {
            Some(g) => g.1.push((planet.clone(), f)),
            None => groups.push((central.clone(), vec![(planet.clone(), f)])),
        }
    }
    let mut out = Vec::new();
    for (central, planets) in groups {
        let sum: f64 = planets.iter().map(|p| p.1).sum();
        let n = planets.len() as f64;
        for (p, f) in planets {
            out.push((
                central.clone(),
                p,
                if sum > 0.0 { n * f / sum } else { f64::NAN },
            ));
        }
    }
    out
}

/// `geardyn simulate` of a train.
pub fn simulate(t: &TrainRun, sim: &SimArgs, out: &Path) -> Result<()> {
    let (mut opts, cap) = sim_options(sim)?;
    opts.trajectory = true;
    opts.trajectory_periods = opts.trajectory_periods.clamp(1, 5);
    with_model!(&t.spec, &t.op, |m| {
        check_work(&m, &opts, 1, cap)?;
        simulate_model(t, &m, &opts, out)
    })
}

fn simulate_model<const N: usize>(
    t: &TrainRun,
    m: &TrainModel<N>,
    opts: &SimOptions,
    out: &Path,
) -> Result<()>
where
    TrainModel<N>: geardyn_analysis::engine::Engine<N>,
{
    let started = std::time::Instant::now();
    let _lock = run_record::prepare_folder(out, "simulate", None, false)?;
    let (res, s, used) = simulate_decided(m, m.static_state(), opts, Decide::default())?;
    t.write_record(out, "simulate", &[], started)?;
    let factors = dynamic_factors(m, &s);
    let sharing = load_sharing(&t.spec, &s);
    // meshes.csv
    let mut csv = String::from(
        "mesh,label,max_force,min_force,static_force,dynamic_factor,p_id,separations\n",
    );
    for (k, (f, df)) in factors.iter().enumerate() {
        let ms = s.meshes.get(k);
        csv += &format!(
            "\"{}\",{},{},{},{},{},{},{}\n",
            m.mesh_name(k),
            ms.map_or(s.label.as_str(), |x| x.label.as_str()),
            ms.map_or(s.max_force, |x| x.max_force),
            ms.map_or(s.min_force, |x| x.min_force),
            f,
            finite_or_empty(*df),
            ms.map_or(s.p_id, |x| x.p_id),
            res.meshes[k]
                .events
                .iter()
                .filter(|e| e.kind == geardyn_model::EventKind::DriveExit)
                .count()
        );
    }
    write_text(&out.join("meshes.csv"), &csv)?;
    // strobe.csv: the stroboscopic states as mesh deflections
    let mut st = String::from("tau");
    for k in 0..m.mesh_count() {
        st += &format!(",\"x {}\",\"v {}\"", m.mesh_name(k), m.mesh_name(k));
    }
    st.push('\n');
    for p in &res.strobe {
        st += &format!("{}", p.tau);
        for k in 0..m.mesh_count() {
            let [x, v] = m.mesh_state(p.tau, &p.y, k);
            st += &format!(",{x},{v}");
        }
        st.push('\n');
    }
    write_text(&out.join("strobe.csv"), &st)?;
    let json = serde_json::json!({
        "system": t.spec.name,
        "source": t.source,
        "operating": t.op,
        "input_rpm": m.input_rpm(),
        "omega_ref_rad_s": m.omega_ref(),
        "excitation_period": m.excitation_period(),
        "mesh_cycles_per_period": m.cycles_per_period(),
        "summary": s,
        "static_forces": m.static_forces(),
        "dynamic_factors": factors.iter().map(|x| x.1).collect::<Vec<_>>(),
        "load_sharing": sharing.iter().map(|(c, p, f)| serde_json::json!({"central": c, "planet": p, "factor": f})).collect::<Vec<_>>(),
        "transient_periods_used": used.transient_periods,
        "wall_s": started.elapsed().as_secs_f64(),
    });
    write_text(
        &out.join("summary.json"),
        &serde_json::to_string_pretty(&json)?,
    )?;
    mesh_force_figure(t, m, &res, &out.join("mesh_forces"))?;
    println!(
        "{} ({}), omega = {} (input {:.0} rpm), F = {}: {}, label {}; {} steps in {:.3} s -> {}",
        t.spec.name,
        t.source,
        t.op.omega,
        m.input_rpm(),
        t.op.load,
        s.describe(),
        s.label,
        res.steps,
        started.elapsed().as_secs_f64(),
        out.display()
    );
    for (k, (f, df)) in factors.iter().enumerate() {
        let ms = s.meshes.get(k);
        println!(
            "  {:<16} {:<12} force [{:.4}, {:.4}], static {:.4}, dynamic factor {}",
            m.mesh_name(k),
            ms.map_or(s.label.as_str(), |x| x.label.as_str()),
            ms.map_or(s.min_force, |x| x.min_force),
            ms.map_or(s.max_force, |x| x.max_force),
            f,
            if df.is_finite() {
                format!("{df:.3}")
            } else {
                "undefined (no static load)".into()
            }
        );
    }
    for (c, p, f) in &sharing {
        println!("  load sharing {c}-{p}: {f:.4}");
    }
    Ok(())
}

fn mesh_force_figure<const N: usize>(
    t: &TrainRun,
    m: &TrainModel<N>,
    res: &geardyn_analysis::simulate::SimResult<N>,
    stem: &Path,
) -> Result<()> {
    let cycle = m.mesh_cycle_time();
    let t_end = res.final_state.0;
    let from = t_end - (3.0 * cycle).min(m.excitation_period() * 2.0);
    let mut layers = Vec::new();
    let mut legend = Vec::new();
    for k in 0..m.mesh_count() {
        let pts: Vec<(f64, f64)> = res.meshes[k]
            .trajectory
            .iter()
            .filter(|p| p.tau >= from)
            .map(|p| ((p.tau - from) / cycle, p.mesh_force))
            .collect();
        layers.push(Layer {
            points: pts,
            style: Style::Line(2),
            color: palette(k),
        });
        legend.push(LegendEntry::line(m.mesh_name(k), palette(k)));
    }
    write_figure(
        stem,
        &Figure {
            title: format!(
                "Mesh forces: {} (omega = {}, F = {})",
                t.title_name(),
                t.op.omega,
                t.op.load
            ),
            x_label: "time (mesh cycles of mesh 1)".into(),
            panels: vec![Panel {
                y_label: "mesh force (k_ref b_c)".into(),
                layers,
                hlines: vec![0.0],
                ..Default::default()
            }],
            legend,
            panel_height: 420,
            ..Default::default()
        },
    )?;
    Ok(())
}

/// A train's model over one operating parameter.
pub(crate) struct Swept<'a> {
    pub(crate) spec: &'a TrainSpec,
    pub(crate) op: TrainOperating,
    pub(crate) param: &'a str,
}

impl<'a> Swept<'a> {
    fn op_at(&self, p: f64) -> TrainOperating {
        let mut op = self.op;
        // (values are checked before the sweep starts)
        op.set(self.param, p).expect("checked");
        op
    }
}

macro_rules! family {
    ($($n:literal),*) => {$(
        impl Family<$n> for Swept<'_> {
            type System = TrainModel<$n>;
            fn at(&self, p: f64) -> TrainModel<$n> {
                TrainModel::new(self.spec, &self.op_at(p)).expect("checked")
            }
            fn period(&self, p: f64) -> f64 {
                <Self as Family<$n>>::at(self, p).excitation_period()
            }
        }
    )*};
}
family!(8, 16, 24);

/// `geardyn bifurcation` of a train: a decided sweep of one operating parameter (fixed initial
/// state: the static deflection at the first value, or a continuation with `sweep`).
pub fn bifurcation(
    t: &TrainRun,
    sim: &SimArgs,
    param: &str,
    values: &[f64],
    (mode, sections, lyapunov): (&str, &str, bool),
    out: &Path,
) -> Result<()> {
    if !TrainOperating::FIELDS.contains(&param) {
        bail!(
            "--param {param}: a train sweeps one of {}",
            TrainOperating::FIELDS.join(", ")
        );
    }
    t.check_stiffness_form(&[param])?;
    let continuation = match mode {
        _ if lyapunov => bail!("--lyapunov: a train's sweep decides each value (its exponent is in the verdict: `chaotic (TLE ...)` in runs.csv); the per-value exponent column is the pair's"),
        _ if sections != "strobe" => bail!("--sections {sections}: a train's sweep records the stroboscopic section only"),
        "fixed" => false,
        "sweep" => true,
        _ => bail!("--mode {mode}: a train sweeps with fixed (one initial state) or sweep (continuation, upward)"),
    };
    for &v in values {
        let mut op = t.op;
        op.set(param, v)?;
    }
    let (opts, cap) = sim_options(sim)?;
    let fam = Swept {
        spec: &t.spec,
        op: t.op,
        param,
    };
    with_model!(&t.spec, &t.op, |m| {
        // (the work per value is nearly the same over an operating parameter: the first's)
        check_work(&m, &opts, values.len(), cap)?;
        sweep_model(t, &fam, &m, param, values, continuation, &opts, out)
    })
}

#[allow(clippy::too_many_arguments)]
fn sweep_model<const N: usize>(
    t: &TrainRun,
    fam: &Swept<'_>,
    // (fixes the state dimension)
    _first: &TrainModel<N>,
    param: &str,
    values: &[f64],
    continuation: bool,
    opts: &SimOptions,
    out: &Path,
) -> Result<()>
where
    for<'a> Swept<'a>: Family<N, System = TrainModel<N>>,
    TrainModel<N>: geardyn_analysis::engine::Engine<N>,
{
    let started = std::time::Instant::now();
    let _lock = run_record::prepare_folder(out, "bifurcation", None, false)?;
    let y0 = <Swept<'_> as Family<N>>::at(fam, values[0]).static_state();
    let pts = decided_sweep(fam, values, y0, opts, Decide::default(), continuation);
    t.write_record(
        out,
        "bifurcation",
        &[run_record::Swept::of(param, values)],
        started,
    )?;
    let nm = t.spec.meshes.len();
    let names: Vec<String> = t.spec.meshes.iter().map(|m| m.name.clone()).collect();
    let mut runs = format!("{param},class,label");
    for n in &names {
        runs +=
            &format!(",\"label {n}\",\"max_force {n}\",\"min_force {n}\",\"dynamic_factor {n}\"");
    }
    runs += ",load_sharing_max,error\n";
    let mut points = format!("{param},mesh,x\n");
    let mut strobe_layers: Vec<Vec<(f64, f64)>> = vec![Vec::new(); nm];
    let mut force_layers: Vec<Vec<(f64, f64)>> = vec![Vec::new(); nm];
    let mut lsf_layer: Vec<(f64, f64)> = Vec::new();
    let mut classes = std::collections::BTreeMap::<String, usize>::new();
    for p in &pts {
        let model = <Swept<'_> as Family<N>>::at(fam, p.value);
        let Some(s) = &p.summary else {
            runs += &format!(
                "{},failed,failed{},,\"{}\"\n",
                p.value,
                ",,,,".repeat(nm),
                p.error.as_ref().map_or(String::new(), |e| e.to_string())
            );
            continue;
        };
        *classes.entry(s.motion.word().to_string()).or_default() += 1;
        let factors = dynamic_factors(&model, s);
        let sharing = load_sharing(&t.spec, s);
        let lsf = sharing.iter().map(|x| x.2).fold(f64::NAN, f64::max);
        runs += &format!("{},{},{}", p.value, s.motion.word(), s.label);
        for k in 0..nm {
            let ms = s.meshes.get(k);
            let (mx, mn) = ms.map_or((s.max_force, s.min_force), |x| (x.max_force, x.min_force));
            runs += &format!(
                ",{},{},{},{}",
                ms.map_or(s.label.as_str(), |x| x.label.as_str()),
                mx,
                mn,
                finite_or_empty(factors[k].1)
            );
            force_layers[k].push((p.value, mx));
        }
        if lsf.is_finite() {
            runs += &format!(",{lsf},\n");
        } else {
            runs += ",,\n";
        }
        if lsf.is_finite() {
            lsf_layer.push((p.value, lsf));
        }
        for y in &p.strobe {
            for k in 0..nm {
                // (every stroboscopic time is a whole number of every mesh's cycles: tau = 0)
                let x = model.mesh_state(0.0, y, k)[0];
                points += &format!("{},\"{}\",{}\n", p.value, names[k], x);
                strobe_layers[k].push((p.value, x));
            }
        }
    }
    write_text(&out.join("runs.csv"), &runs)?;
    write_text(&out.join("points.csv"), &points)?;
    // the figure: stroboscopic deflection of up to two meshes, every mesh's peak force, the
    // largest load-sharing factor
    let shown: Vec<usize> = (0..nm.min(2)).collect();
    let mut panels: Vec<Panel> = shown
        .iter()
        .map(|&k| Panel {
            y_label: format!("x {} (strobe)", names[k]),
            layers: vec![Layer {
                points: strobe_layers[k].clone(),
                style: Style::Dots(2),
                color: palette(k),
            }],
            hlines: vec![t.op.d, -t.op.d],
            ..Default::default()
        })
        .collect();
    panels.push(Panel {
        y_label: "peak mesh force".into(),
        layers: (0..nm)
            .map(|k| Layer {
                points: force_layers[k].clone(),
                style: Style::Line(2),
                color: palette(k),
            })
            .collect(),
        ..Default::default()
    });
    if !lsf_layer.is_empty() {
        // (equal sharing reads 1 to the force extremes' accuracy, 1e-5: not a scale of 1e-6)
        let hi = lsf_layer.iter().map(|p| p.1).fold(1.05, f64::max);
        panels.push(Panel {
            y_range: Some((0.95, hi + 0.02)),
            y_label: "largest load-sharing factor".into(),
            layers: vec![Layer {
                points: lsf_layer,
                style: Style::Line(2),
                color: palette(0),
            }],
            hlines: vec![1.0],
            ..Default::default()
        });
    }
    write_figure(
        &out.join("bifurcation"),
        &Figure {
            title: format!(
                "{}: decided sweep over {param} ({})",
                t.title_name(),
                t.source
            ),
            x_label: param.into(),
            panels,
            legend: names
                .iter()
                .enumerate()
                .map(|(k, n)| LegendEntry::line(n.clone(), palette(k)))
                .collect(),
            panel_height: 260,
            ..Default::default()
        },
    )?;
    let text: Vec<String> = classes.iter().map(|(c, n)| format!("{n} {c}")).collect();
    println!(
        "{}: {} values of {param} in {:.2} s ({}) -> {}",
        t.spec.name,
        values.len(),
        started.elapsed().as_secs_f64(),
        text.join(", "),
        out.display()
    );
    Ok(())
}
