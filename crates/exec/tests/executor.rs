//! The executor's store: a job resumes from what it stored, and trusts only its own items.

use geardyn_analysis::bifurcation::TaskResult;
use geardyn_exec::request::SweepSpec;
use geardyn_exec::{execute, Checkpointed, Observer, SweepJob};
use geardyn_io::checkpoint::Checkpoint;
use geardyn_io::Config;
use std::sync::atomic::{AtomicU64, Ordering};

/// Counts what the executor reports.
#[derive(Default)]
struct Count {
    found: AtomicU64,
    finished: AtomicU64,
}

impl<R> Observer<R> for Count {
    fn start(&self, _: &str, _: u64, done: u64) {
        self.found.store(done, Ordering::SeqCst);
    }
    fn finished(&self, _: &R) {
        self.finished.fetch_add(1, Ordering::SeqCst);
    }
}

/// A scratch folder removed at the end.
struct Dir(std::path::PathBuf);
impl Dir {
    fn new(name: &str) -> Self {
        let d = std::env::temp_dir().join(format!("geardyn-exec-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        Dir(d)
    }
}
impl Drop for Dir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn sweep() -> (
    Config,
    geardyn_scenario::Scenario,
    geardyn_analysis::bifurcation::SweepOptions,
) {
    let mut cfg = Config::preset("classic").unwrap();
    cfg.simulation.transient_periods = 20;
    cfg.simulation.record_periods = 10;
    let scenario = cfg.resolve().unwrap();
    let spec = SweepSpec {
        values: vec![0.6, 0.7, 0.8],
        ..SweepSpec::default()
    };
    let opts = spec.options(&cfg, &scenario).unwrap();
    (cfg, scenario, opts)
}

/// The records of `job` run with its store in `file` under `cfg`, told to `observer`.
fn run_stored(
    job: &SweepJob,
    file: &std::path::Path,
    cfg: &Config,
    observer: &dyn Observer<TaskResult>,
) -> Vec<TaskResult> {
    execute(
        job,
        Some(&mut Checkpointed::file(file, cfg).unwrap()),
        observer,
    )
    .unwrap()
}

/// Asserts that `a` and `b` are the same records.
fn same(a: &[TaskResult], b: &[TaskResult]) {
    assert_eq!(
        serde_json::to_string(a).unwrap(),
        serde_json::to_string(b).unwrap()
    );
}

#[test]
fn a_finished_job_resumes_without_running_anything_and_gives_the_same_records() {
    let dir = Dir::new("resume");
    let file = dir.0.join("s.checkpoint.jsonl");
    let (cfg, scenario, opts) = sweep();
    let job = SweepJob::new("sweep", &scenario, &opts);
    let first = Count::default();
    let a = run_stored(&job, &file, &cfg, &first);
    assert_eq!(first.finished.load(Ordering::SeqCst), 3);
    let again = Count::default();
    let b = run_stored(&job, &file, &cfg, &again);
    assert_eq!(again.found.load(Ordering::SeqCst), 3);
    assert_eq!(again.finished.load(Ordering::SeqCst), 0);
    same(&a, &b);
    // another context (configuration) is not resumed
    let mut other = cfg.clone();
    other.simulation.record_periods = 11;
    let third = Count::default();
    run_stored(&job, &file, &other, &third);
    assert_eq!(third.found.load(Ordering::SeqCst), 0);
}

#[test]
fn a_stored_record_that_is_not_one_of_the_jobs_items_is_computed_again() {
    let dir = Dir::new("foreign");
    let file = dir.0.join("s.checkpoint.jsonl");
    let (cfg, scenario, opts) = sweep();
    let job = SweepJob::new("sweep", &scenario, &opts);
    let clean = run_stored(&job, &file, &cfg, &());
    // rewrite the store as value 0.7 recorded at another value, and a task out of range: both
    // well-formed lines under the job's own key, neither one of its items
    let text = std::fs::read_to_string(&file).unwrap();
    let key = text.lines().next().unwrap().to_string();
    std::fs::remove_file(&file).unwrap();
    let (cp, _) = Checkpoint::open::<TaskResult>(&file, &key).unwrap();
    let mut wrong_value = clean[1].clone();
    wrong_value.value = 0.75;
    let mut out_of_range = clean[2].clone();
    out_of_range.task.index = 7;
    for r in [&clean[0], &wrong_value, &out_of_range] {
        cp.append(r).unwrap();
    }
    drop(cp);
    let count = Count::default();
    let again = run_stored(&job, &file, &cfg, &count);
    assert_eq!(count.found.load(Ordering::SeqCst), 1);
    assert_eq!(count.finished.load(Ordering::SeqCst), 2);
    same(&again, &clean);
}
