//! The machinery every study plan shares: the context (the scenario every study starts from),
//! the [`Study`] trait and the caches of its data or section, checkpointed sweeps,
//! continuations, basins and maps with progress bars.

use crate::{rel, Claim, Figure, Section, Table};
use anyhow::{Context, Result};
use geardyn_analysis::basins::{BasinOptions, BasinResult};
use geardyn_analysis::bifurcation::{SweepMode, SweepOptions, TaskResult};
use geardyn_analysis::classify::DECISION_BUDGET;
use geardyn_analysis::continuation::{ContinuationOptions, ContinuationResult};
use geardyn_analysis::map2d::{MapCell, MapOptions};
use geardyn_analysis::simulate::SimOptions;
use geardyn_exec::{
    execute, BasinsJob, Checkpointed, ContinuationJob, Job, MapJob, Progress, SweepJob,
};
use geardyn_io::checkpoint::fnv1a;
use geardyn_io::Config;
use geardyn_model::MeshModel;
use geardyn_scenario::Scenario;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One study of a plan: what it computes (`compute`, from its request and the context) and how
/// its data is shown (`render`: files, figures, readings; `claims`: the seed's statements checked
/// against the data). The runner caches the data and renders it on every run ([`cached`]), or,
/// where the data cannot be read back, caches the rendered section ([`rendered`]).
pub trait Study: Send + Sync {
    /// What `compute` returns.
    type Data;
    /// The study's id: its folder, its anchor on the page, part of its cache key.
    fn id(&self) -> &'static str;
    /// The settings `compute` takes besides the context (configuration, mode, decision horizon
    /// and budget, which key every study): part of the cache key.
    fn request(&self) -> serde_json::Value {
        serde_json::Value::Null
    }
    /// The sweeps, continuations, basins and runs of the study (checkpointed in `dir`).
    fn compute(&self, ctx: &Ctx, dir: &Path) -> Result<Self::Data>;
    /// The section of `data`: its files in `dir`, figures, tables, readings.
    fn render(&self, ctx: &Ctx, dir: &Path, data: &Self::Data) -> Result<Section>;
    /// Claims checked on `data` besides those `render` states (they follow them on the page).
    fn claims(&self, _data: &Self::Data) -> Vec<Claim> {
        Vec::new()
    }
}

/// Declares a study of a module whose `compute` and `render` functions take its inputs: the
/// struct (the inputs it borrows, filled in by the plan), its id, its data, the calls of
/// `compute` and `render` (with the study `s`, the context `ctx`, the folder `dir` and the data)
/// and, optionally, its request.
macro_rules! study {
    ($name:ident { $($field:ident: $ty:ty),* } $id:literal $data:ty,
     |$s:ident, $ctx:ident, $dir:ident| $compute:expr, |$d:ident| $render:expr $(, $req:expr)?) => {
        #[doc = concat!("The study `", $id, "`: [`compute`], then [`render`].")]
        pub(super) struct $name<'a> {
            $(#[doc = concat!("Its input `", stringify!($field), "`.")] pub(super) $field: $ty,)*
        }

        impl $crate::runner::Study for $name<'_> {
            type Data = $data;

            fn id(&self) -> &'static str {
                $id
            }

            $(fn request(&self) -> serde_json::Value {
                let $s = self;
                $req
            })?

            #[allow(unused_variables)]
            fn compute(&self, $ctx: &$crate::runner::Ctx, $dir: &std::path::Path) -> anyhow::Result<$data> {
                let $s = self;
                $compute
            }

            #[allow(unused_variables)]
            fn render(&self, $ctx: &$crate::runner::Ctx, $dir: &std::path::Path, $d: &$data) -> anyhow::Result<$crate::Section> {
                let $s = self;
                $render
            }
        }
    };
}
pub(crate) use study;

/// A study of a plan as the runner drives it (object safe: a plan is a list of them).
pub trait Planned: Send + Sync {
    /// Computes (or reads from the cache) and renders the study.
    fn run(&self, ctx: &Ctx) -> Result<Section>;
}

/// A plan: its studies, the longest first (they start first).
pub type Plan<'a> = Vec<Box<dyn Planned + 'a>>;

/// A study whose data is cached and rendered on every run.
struct Cached<S>(S);

impl<S: Study> Planned for Cached<S>
where
    S::Data: Serialize + DeserializeOwned,
{
    fn run(&self, ctx: &Ctx) -> Result<Section> {
        ctx.run_cached(&self.0)
    }
}

/// A study whose rendered section is cached (its data holds results the libraries cannot read
/// back).
struct Rendered<S>(S);

impl<S: Study> Planned for Rendered<S> {
    fn run(&self, ctx: &Ctx) -> Result<Section> {
        ctx.run_rendered(&self.0)
    }
}

/// `study` in a plan, its data cached in `ROOT/.cache/<preset>/<id>.data.json`, keyed by its request and the
/// source of the library crates it computes through: editing the report (a rendering, a
/// claim's wording, a comment) renders the cached data again instead of recomputing it.
pub fn cached<'a, S: Study + 'a>(study: S) -> Box<dyn Planned + 'a>
where
    S::Data: Serialize + DeserializeOwned,
{
    Box::new(Cached(study))
}

/// `study` in a plan, its rendered section cached in `DIR/<id>/section.json`, keyed by its
/// request and the source of the report and of the libraries (for data that holds results the
/// libraries give no `Deserialize` for: continuations, basins, recorded runs, signals).
pub fn rendered<'a, S: Study + 'a>(study: S) -> Box<dyn Planned + 'a> {
    Box::new(Rendered(study))
}

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
    /// The configuration's integrator and follow (`[simulation]` `method`, `rtol`, `atol`,
    /// `steps_per_cycle`, `follow_steps`; `--set` sets them): every decided run of the plan uses
    /// them, and its decision horizon and budget ([`Ctx::decision`]). Transients and records are
    /// the plan's own.
    pub integration: SimOptions,
    /// Whether the horizon and the budget of `integration` were given by the caller
    /// ([`crate::ReportOptions::decision_given`]).
    pub decision_given: (bool, bool),
}

/// Decision horizon of a `--quick` report (excitation periods): a coarse look, an order of
/// magnitude below the measured transients that the default horizon covers; the page says so.
/// (300 halved the quick breakage report's time but called 9 loads of its load sweep chaotic
/// instead of 6: transients read as chaos; a coarse page must not be more lenient than that.)
pub const QUICK_DECISION_PERIODS: u64 = 1_000;
/// Work budget of one run's decision in a `--quick` report (right-hand-side evaluations): a tenth
/// of the default, 3 10^8. It pays the quick horizon's escape test (2 000 copy-periods) up to
/// ~1.5 10^5 evaluations per copy and period (the broken pair's 1.2 10^5 at omega = 0.1
/// included); costlier runs are `unsettled` (decided by `budget`) in the quick report instead of
/// costing minutes each.
pub const QUICK_DECISION_BUDGET: u64 = DECISION_BUDGET / 10;

/// The decision horizon and work budget of a report's runs: the configuration's (the defaults,
/// or what `--decision-periods`, `--decision-budget` or `--set` gave: `given`); a `--quick`
/// report takes [`QUICK_DECISION_PERIODS`] and [`QUICK_DECISION_BUDGET`] for those not given.
pub fn decision_of(integration: &SimOptions, quick: bool, given: (bool, bool)) -> (u64, u64) {
    let (p, b) = (integration.decision_periods, integration.decision_budget);
    (
        if quick && !given.0 {
            QUICK_DECISION_PERIODS
        } else {
            p
        },
        if quick && !given.1 {
            QUICK_DECISION_BUDGET
        } else {
            b
        },
    )
}

impl Ctx {
    /// The decision horizon and budget of every decided run of the plan ([`decision_of`]).
    pub fn decision(&self) -> (u64, u64) {
        decision_of(&self.integration, self.quick, self.decision_given)
    }

    /// `quick` or `full`, by mode.
    pub fn n<T>(&self, quick: T, full: T) -> T {
        if self.quick {
            quick
        } else {
            full
        }
    }

    /// Dormand–Prince settings with `(quick, full)` transient and recorded periods, decided at
    /// [`Ctx::decision`] (the full report at the default horizon unless the configuration sets
    /// another, the quick one at [`QUICK_DECISION_PERIODS`] unless one is given).
    pub fn sim(&self, transient: (u64, u64), record: (u64, u64)) -> SimOptions {
        SimOptions {
            method: self.integration.method,
            follow_steps: self.integration.follow_steps,
            transient_periods: self.n(transient.0, transient.1),
            record_periods: self.n(record.0, record.1),
            decision_periods: self.decision().0,
            decision_budget: self.decision().1,
            ..Default::default()
        }
    }

    /// The preset's scenario (every study derives from it with `with`/`with_all`).
    pub fn base(&self) -> Result<Scenario> {
        Ok(self.scenario.clone())
    }

    /// The cache key of a study: its id, its request, the context every study computes from
    /// (configuration, mode, decision horizon and budget) and the code version `source`.
    fn cache_key(&self, id: &str, request: &serde_json::Value, source: &str) -> Result<String> {
        Ok(serde_json::to_string(
            &serde_json::json!({ "id": id, "config": self.cfg, "quick": self.quick, "key": request, "version": 11, "source": source, "decision_periods": self.decision().0, "decision_budget": self.decision().1, "geardyn": env!("CARGO_PKG_VERSION") }),
        )?)
    }

    /// Runs `compute` in the study's folder `DIR/id`, and removes its checkpoints once it is
    /// complete; returns its result and wall time. An interrupted computation is an error (its
    /// finished runs stay in its checkpoints for the next run).
    fn computed<T>(&self, id: &str, compute: impl FnOnce() -> Result<T>) -> Result<(T, f64)> {
        let t = std::time::Instant::now();
        let out = compute()?;
        if geardyn_analysis::cancel::requested() {
            anyhow::bail!("{id}: interrupted (its finished runs are kept in its checkpoints)");
        }
        let seconds = t.elapsed().as_secs_f64();
        if let Ok(rd) = std::fs::read_dir(self.dir.join(id)) {
            for e in rd.filter_map(|e| e.ok()) {
                if e.file_name()
                    .to_string_lossy()
                    .ends_with(".checkpoint.jsonl")
                {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
        eprintln!("{id}: {seconds:.1} s");
        Ok((out, seconds))
    }

    /// The folder of study `id`, created.
    fn study_dir(&self, id: &str) -> Result<PathBuf> {
        let dir = self.dir.join(id);
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        Ok(dir)
    }

    /// Where the data of study `id` is cached: `ROOT/.cache/<preset>/<id>.data.json`, beside the
    /// page folders rather than in them (the data of a sweep, every run with its points, is
    /// larger than its CSV files; a page folder holds what a reader is given, within its size
    /// budget).
    fn data_cache(&self, id: &str) -> Result<PathBuf> {
        let preset = self.dir.file_name().unwrap_or_default();
        let dir = self
            .dir
            .parent()
            .unwrap_or(&self.dir)
            .join(".cache")
            .join(preset);
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        Ok(dir.join(format!("{id}.data.json")))
    }

    /// A study whose data is cached ([`Ctx::data_cache`]: the key, the compute time, the data)
    /// and rendered on every run: a cache whose key differs or whose data does not read is
    /// computed again.
    fn run_cached<S: Study>(&self, study: &S) -> Result<Section>
    where
        S::Data: Serialize + DeserializeOwned,
    {
        let id = study.id();
        let dir = self.study_dir(id)?;
        let key = self.cache_key(id, &study.request(), env!("GEARDYN_LIBRARY_DIGEST"))?;
        let cache = self.data_cache(id)?;
        let hit = std::fs::read_to_string(&cache).ok().and_then(|text| {
            let mut parts = text.splitn(3, '\n');
            let (k, secs, data) = (parts.next()?, parts.next()?, parts.next()?);
            (k == key).then_some(())?;
            Some((
                serde_json::from_str::<S::Data>(data).ok()?,
                secs.parse::<f64>().ok()?,
            ))
        });
        let (data, seconds) = match hit {
            Some(hit) => {
                eprintln!("{id}: cached");
                hit
            }
            None => {
                let (data, seconds) = self.computed(id, || study.compute(self, &dir))?;
                geardyn_io::output::write_text(
                    &cache,
                    &format!("{key}\n{seconds}\n{}", serde_json::to_string(&data)?),
                )?;
                (data, seconds)
            }
        };
        let mut sec = study.render(self, &dir, &data)?;
        sec.claims.extend(study.claims(&data));
        sec.seconds = seconds;
        Ok(sec)
    }

    /// A study whose data the libraries cannot read back: its rendered section is cached
    /// (`DIR/id/section.json`: the key, the digests of its files, the section), keyed by the
    /// source of the report too, and reused only while its files are the ones it wrote (a
    /// truncated or edited CSV is recomputed, never shown as the study's).
    fn run_rendered<S: Study>(&self, study: &S) -> Result<Section> {
        let id = study.id();
        let dir = self.study_dir(id)?;
        let key = self.cache_key(id, &study.request(), env!("GEARDYN_SOURCE_DIGEST"))?;
        let cache = dir.join("section.json");
        if let Ok(text) = std::fs::read_to_string(&cache) {
            let mut parts = text.splitn(3, '\n');
            if let (Some(k), Some(digests), Some(body_json)) =
                (parts.next(), parts.next(), parts.next())
            {
                if k == key {
                    let want: BTreeMap<String, String> =
                        serde_json::from_str(digests).unwrap_or_default();
                    let have = Self::study_digests(&dir);
                    match serde_json::from_str::<Section>(body_json) {
                        Ok(sec) if !want.is_empty() && want == have => {
                            eprintln!("{id}: cached");
                            return Ok(sec);
                        }
                        Ok(_) => {
                            let changed: Vec<&str> = want
                                .iter()
                                .filter(|(f, d)| have.get(*f) != Some(*d))
                                .map(|(f, _)| f.as_str())
                                .chain(
                                    have.keys()
                                        .filter(|f| !want.contains_key(*f))
                                        .map(|f| f.as_str()),
                                )
                                .take(3)
                                .collect();
                            eprintln!(
                                "{id}: the cached study's files changed since it was written ({}): computing it again",
                                changed.join(", ")
                            );
                        }
                        Err(_) => {}
                    }
                }
            }
        }
        let (mut sec, seconds) = self.computed(id, || {
            let data = study.compute(self, &dir)?;
            let mut sec = study.render(self, &dir, &data)?;
            sec.claims.extend(study.claims(&data));
            Ok(sec)
        })?;
        sec.seconds = seconds;
        let digests = serde_json::to_string(&Self::study_digests(&dir))?;
        geardyn_io::output::write_text(
            &cache,
            &format!("{key}\n{digests}\n{}", serde_json::to_string(&sec)?),
        )?;
        Ok(sec)
    }

    /// The studies of a plan side by side (rayon), results in plan order. Each study has its
    /// own folder, checkpoints and cache and reads only the context, so the result of each is
    /// what it is alone; run one after the other, every study's tail (the few long follows of
    /// its last chaotic runs) left a core idle (breakage report: 1.67 of 2 cores busy). The
    /// seconds a section states are its own wall time, shared with the studies beside it.
    pub fn studies(&self, plan: Plan<'_>) -> Result<Vec<Section>> {
        use rayon::prelude::*;
        plan.into_par_iter()
            .with_max_len(1)
            .map(|s| s.run(self))
            .collect()
    }

    /// Digests (FNV-1a, hex) of the files of a finished study folder, by name: everything but the
    /// cache itself, checkpoints and temporary files.
    fn study_digests(dir: &Path) -> BTreeMap<String, String> {
        let mut out = BTreeMap::new();
        let Ok(rd) = std::fs::read_dir(dir) else {
            return out;
        };
        for e in rd.filter_map(|e| e.ok()) {
            let name = e.file_name().to_string_lossy().into_owned();
            if name == "section.json" || name.ends_with(".jsonl") || name.starts_with('.') {
                continue;
            }
            let digest = match e.file_type() {
                Ok(t) if t.is_file() => std::fs::read(e.path())
                    .map_or_else(|_| "unreadable".into(), |b| format!("{:016x}", fnv1a(&b))),
                _ => "not a regular file".into(),
            };
            out.insert(name, digest);
        }
        out
    }

    /// Runs `job` with a checkpoint `dir/name.checkpoint.jsonl` (for the scenario `base`, by
    /// its parameters and pair) and a progress bar labelled `name`.
    fn checkpointed<J: Job>(
        &self,
        dir: &Path,
        name: &str,
        base: &serde_json::Value,
        job: &J,
    ) -> Result<J::Output>
    where
        J::Record: serde::Serialize + serde::de::DeserializeOwned,
    {
        let file = name.replace([' ', '/', '.'], "_");
        let mut store = Checkpointed::file(&dir.join(format!("{file}.checkpoint.jsonl")), base)?;
        Ok(execute(job, Some(&mut store), &Progress::new(Some(name)))?)
    }

    /// A checkpointed sweep.
    pub fn sweep(
        &self,
        dir: &Path,
        name: &str,
        base: &Scenario,
        opts: &SweepOptions,
    ) -> Result<Vec<TaskResult>> {
        self.checkpointed(
            dir,
            name,
            &context(base),
            &SweepJob::new("sweep", base, opts),
        )
    }

    /// A checkpointed attractor continuation.
    pub fn continuation(
        &self,
        dir: &Path,
        name: &str,
        base: &Scenario,
        opts: &ContinuationOptions,
    ) -> Result<ContinuationResult> {
        let job = ContinuationJob {
            scenario: base,
            opts,
        };
        self.checkpointed(dir, name, &context(base), &job)
    }

    /// Checkpointed basins of attraction.
    pub fn basins(
        &self,
        dir: &Path,
        name: &str,
        model: &MeshModel,
        opts: &BasinOptions,
    ) -> Result<BasinResult> {
        let ctx = serde_json::json!({ "params": model.params() });
        self.checkpointed(dir, name, &ctx, &BasinsJob { model, opts })
    }

    /// A checkpointed two-parameter map.
    pub fn map(
        &self,
        dir: &Path,
        name: &str,
        base: &Scenario,
        opts: &MapOptions,
    ) -> Result<Vec<MapCell>> {
        let job = MapJob {
            scenario: base,
            opts,
        };
        self.checkpointed(dir, name, &context(base), &job)
    }

    /// A figure entry for `stem.png`/`stem.svg` with its data files.
    pub fn fig(&self, stem: &Path, caption: &str, data: &[PathBuf]) -> Figure {
        Figure {
            png: rel(&self.dir, &stem.with_extension("png")),
            svg: rel(&self.dir, &stem.with_extension("svg")),
            caption: caption.to_string(),
            data: data.iter().map(|p| rel(&self.dir, p)).collect(),
        }
    }

    /// A table shown on the page, written to `path` as CSV.
    pub fn table(
        &self,
        path: &Path,
        title: &str,
        header: &[String],
        rows: Vec<Vec<String>>,
    ) -> Result<Table> {
        let h: Vec<&str> = header.iter().map(|s| s.as_str()).collect();
        geardyn_io::output::write_csv(path, &h, rows.iter().cloned())?;
        Ok(Table {
            title: title.to_string(),
            csv: rel(&self.dir, path),
            header: header.to_vec(),
            rows,
        })
    }

    /// A table declared by `spec`, written as CSV in `dir`.
    pub fn declared_table(
        &self,
        dir: &Path,
        spec: &TableSpec,
        rows: Vec<Vec<String>>,
    ) -> Result<Table> {
        self.table(&dir.join(spec.file), spec.title, &hdr(spec.columns), rows)
    }
}

/// A table's file name, title and columns, declared once beside the study that fills it.
pub struct TableSpec {
    /// The CSV file's name in the section's folder.
    pub file: &'static str,
    /// The title shown above the table.
    pub title: &'static str,
    /// The column headers.
    pub columns: &'static [&'static str],
}

/// What a report checkpoint of a computation from `base` is keyed by besides its settings.
fn context(base: &Scenario) -> serde_json::Value {
    serde_json::json!({ "base": base.params(), "pair": base.spec().pair })
}

/// The scenario with the linear contact law (seed B's dimensionless studies).
pub fn with_linear_law(s: &Scenario) -> Result<Scenario> {
    let mut spec = s.spec().clone();
    spec.model.contact = geardyn_model::ContactLaw::Linear;
    Ok(spec.resolve()?)
}

/// Sweep options from (0, 0): `param` over `values` in `mode`, with `sections` and, if `tle`,
/// the TLE.
pub fn sweep_options(
    param: &str,
    values: Vec<f64>,
    (mode, sim): (SweepMode, SimOptions),
    sections: Vec<geardyn_analysis::bifurcation::Section>,
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

/// RK4 steps per mesh cycle of a twin run ([`twin_sim`]) of an adaptive one.
pub const TWIN_RK4_STEPS: u32 = 256;

/// The settings of the twin that checks a verdict: the other integrator (fixed-step RK4 of
/// [`TWIN_RK4_STEPS`] steps per mesh cycle for Dormand–Prince, Dormand–Prince for RK4) and twice
/// the transient.
pub fn twin_sim(sim: SimOptions) -> SimOptions {
    use geardyn_analysis::simulate::Method;
    SimOptions {
        method: match sim.method {
            Method::Dopri { .. } => Method::Rk4 {
                steps_per_cycle: TWIN_RK4_STEPS,
            },
            Method::Rk4 { .. } => Method::default(),
        },
        transient_periods: 2 * sim.transient_periods,
        ..sim
    }
}

/// Header strings.
pub fn hdr(h: &[&str]) -> Vec<String> {
    h.iter().map(|s| s.to_string()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quick_report_keeps_a_given_horizon_even_the_default_one() {
        let o = SimOptions::default();
        let d = (o.decision_periods, o.decision_budget);
        assert_eq!(decision_of(&o, false, (false, false)), d);
        assert_eq!(
            decision_of(&o, true, (false, false)),
            (QUICK_DECISION_PERIODS, QUICK_DECISION_BUDGET)
        );
        // given explicitly, the default horizon is kept by a quick report too (it was read as
        // "not given" when the choice compared values)
        assert_eq!(
            decision_of(&o, true, (true, false)),
            (d.0, QUICK_DECISION_BUDGET)
        );
        assert_eq!(decision_of(&o, true, (true, true)), d);
    }
}
