//! Helpers: error mapping (the CLI's one-line messages), conversions to Python objects and numpy
//! arrays, and running long work off the interpreter with Ctrl-C and progress.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};
use serde_json::Value;
use std::any::Any;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

/// Maps an error to a Python exception with the message the CLI prints after `error: `
/// (anyhow's `{:#}`): `OSError` for files that cannot be read or written (and output folders that
/// are refused), `RuntimeError` when an
/// integration fails, `ValueError` for everything else (bad parameters and settings).
pub fn to_pyerr(e: anyhow::Error) -> PyErr {
    let msg = format!("{e:#}");
    // the library's wrappers that show an inner error as their own (transparent): their inner
    // error decides the class too
    let mut all: Vec<&(dyn std::error::Error + 'static)> = Vec::new();
    for c in e.chain() {
        all.push(c);
        use geardyn_exec::ExecError;
        match c.downcast_ref::<ExecError>() {
            Some(ExecError::Folder(f)) => all.push(f),
            Some(ExecError::Output(o)) => all.push(o),
            Some(ExecError::Analysis(a)) => all.push(a.as_ref()),
            Some(ExecError::Store(_)) | None => {}
        }
    }
    // (a simulation run as a job: its error inside the executor's)
    for k in 0..all.len() {
        use geardyn_io::simulate_folder::{FolderWriteError, SimulateError};
        match all[k].downcast_ref::<SimulateError>() {
            Some(SimulateError::Folder(f)) => all.push(f),
            Some(SimulateError::Write(FolderWriteError::Output(o))) => all.push(o),
            _ => {}
        }
    }
    let os = all.iter().any(|c| {
        matches!(
            c.downcast_ref::<geardyn_io::ConfigError>(),
            Some(geardyn_io::ConfigError::Read { .. })
        ) || c
            .downcast_ref::<geardyn_io::output::OutputError>()
            .is_some()
            || c.downcast_ref::<std::io::Error>().is_some()
            || c.downcast_ref::<geardyn_io::run_record::FolderError>()
                .is_some()
    });
    let runtime = all.iter().any(|c| {
        c.downcast_ref::<geardyn_analysis::simulate::SimError>()
            .is_some()
            || c.downcast_ref::<geardyn_solvers::SolverError>().is_some()
    });
    if os {
        PyOSError::new_err(msg)
    } else if runtime {
        PyRuntimeError::new_err(msg)
    } else {
        PyValueError::new_err(msg)
    }
}

/// Converts a JSON value (as the CLI writes it: non-finite numbers are `null`) to Python.
pub fn json_to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| json_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        Value::Object(o) => {
            let d = PyDict::new(py);
            for (k, x) in o {
                d.set_item(k, json_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// Any serialisable value as a Python object (through its JSON form).
pub fn ser_to_py<'py, T: serde::Serialize>(py: Python<'py>, v: &T) -> PyResult<Bound<'py, PyAny>> {
    let v = serde_json::to_value(v).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    json_to_py(py, &v)
}

/// A 1-d array.
pub fn arr1<'py, T: numpy::Element>(py: Python<'py>, v: Vec<T>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}

/// A 2-d C-ordered array of `rows x cols` from row-major data.
pub fn arr2<'py, T: numpy::Element>(
    py: Python<'py>,
    v: Vec<T>,
    rows: usize,
    cols: usize,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, v).reshape([rows, cols])?.into_any())
}

/// A column table: name -> array (numbers) or list (strings), in insertion order.
pub struct Columns<'py> {
    pub dict: Bound<'py, PyDict>,
}

impl<'py> Columns<'py> {
    pub fn new(py: Python<'py>) -> Self {
        Columns {
            dict: PyDict::new(py),
        }
    }
    pub fn f64(&self, name: &str, v: Vec<f64>) -> PyResult<()> {
        self.dict.set_item(name, arr1(self.dict.py(), v))
    }
    pub fn i64(&self, name: &str, v: Vec<i64>) -> PyResult<()> {
        self.dict.set_item(name, arr1(self.dict.py(), v))
    }
    pub fn boolean(&self, name: &str, v: Vec<bool>) -> PyResult<()> {
        self.dict.set_item(name, arr1(self.dict.py(), v))
    }
    pub fn str(&self, name: &str, v: Vec<String>) -> PyResult<()> {
        self.dict.set_item(name, PyList::new(self.dict.py(), v)?)
    }
}

/// Shared between the caller (progress, Ctrl-C) and the worker.
#[derive(Default)]
pub struct Ctl {
    done: AtomicU64,
    total: AtomicU64,
    /// Finished items, kept for the partial result of an interrupted call.
    kept: Mutex<Vec<Box<dyn Any + Send>>>,
}

impl Ctl {
    /// Announces the number of items.
    pub fn set_total(&self, total: u64, done: u64) {
        self.total.store(total, Ordering::Relaxed);
        self.done.store(done, Ordering::Relaxed);
    }

    /// One item finished (called from the library's `on_done` callbacks, on any thread; they see
    /// no run that a stop request cut short).
    pub fn tick(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }

    /// One item finished: counted, and kept for the partial result of an interrupted call.
    pub fn keep<T: Any + Send>(&self, item: T) {
        self.tick();
        self.kept
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(Box::new(item));
    }

    /// The items kept so far, of type `T`, in the order they finished.
    pub fn take_kept<T: Any>(&self) -> Vec<T> {
        std::mem::take(&mut *self.kept.lock().unwrap_or_else(|e| e.into_inner()))
            .into_iter()
            .filter_map(|b| b.downcast::<T>().ok().map(|b| *b))
            .collect()
    }
}

/// The executor's observer: the total, and every finished item counted and kept.
impl<R: Any + Send + Clone> geardyn_exec::Observer<R> for Ctl {
    fn start(&self, _kind: &str, total: u64, done: u64) {
        self.set_total(total, done);
    }
    fn finished(&self, record: &R) {
        self.keep(record.clone());
    }
}

/// Builds the partial result of an interrupted call from its [`Ctl`] (`None`: nothing to offer).
pub type Partial = Box<dyn FnOnce(Python<'_>, &Ctl) -> PyResult<Option<Py<PyAny>>>>;

/// A [`Partial`]: the kept items of type `T`, as a list of plain Python objects (as in the CLI's
/// checkpoint lines), in the order they finished.
pub fn kept_list<T: Any + serde::Serialize>(
    py: Python<'_>,
    ctl: &Ctl,
) -> PyResult<Option<Py<PyAny>>> {
    let items: Vec<T> = ctl.take_kept();
    Ok(Some(ser_to_py(py, &items)?.unbind()))
}

fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".into()
    }
}

/// The progress display of one call: a tqdm bar when tqdm is installed and the call has a count
/// of items, else a line rewritten on `sys.stderr`.
struct ProgressShow {
    bar: Option<Py<PyAny>>,
    tried: bool,
}

impl ProgressShow {
    fn new() -> Self {
        ProgressShow {
            bar: None,
            tried: false,
        }
    }

    /// A tqdm bar of `total` items (once; `None` without tqdm).
    fn tqdm<'py>(&mut self, py: Python<'py>, what: &str, total: u64) -> Option<Bound<'py, PyAny>> {
        if !self.tried {
            self.tried = true;
            let made = py.import("tqdm").and_then(|m| {
                let kw = PyDict::new(py);
                kw.set_item("total", total)?;
                kw.set_item("desc", what)?;
                kw.set_item("unit", "item")?;
                m.getattr("tqdm")?.call((), Some(&kw))
            });
            self.bar = made.ok().map(|b| b.unbind());
        }
        self.bar.as_ref().map(|b| b.bind(py).clone())
    }

    fn show(&mut self, py: Python<'_>, what: &str, ctl: &Ctl, started: Instant, end: bool) {
        let (done, total) = (
            ctl.done.load(Ordering::Relaxed),
            ctl.total.load(Ordering::Relaxed),
        );
        if total > 0 {
            if let Some(bar) = self.tqdm(py, what, total) {
                let n = bar
                    .getattr("n")
                    .and_then(|n| n.extract::<u64>())
                    .unwrap_or(0);
                if done > n {
                    let _ = bar.call_method1("update", (done - n,));
                }
                if end {
                    let _ = bar.call_method0("close");
                }
                return;
            }
        }
        let secs = started.elapsed().as_secs_f64();
        let line = if total > 0 {
            format!(
                "\r{what}: {done}/{total} ({:.0}%), {secs:.1} s elapsed",
                100.0 * done as f64 / total as f64
            )
        } else {
            format!("\r{what}: {secs:.1} s elapsed")
        };
        let line = if end { line + "\n" } else { line };
        if let Ok(err) = py.import("sys").and_then(|s| s.getattr("stderr")) {
            let _ = err.call_method1("write", (line,));
            let _ = err.call_method0("flush");
        }
    }
}

/// The `KeyboardInterrupt` of an interrupted call, with `partial` made of its finished items
/// (when its worker has stopped: `stopped`).
fn interrupted(
    py: Python<'_>,
    what: &str,
    ctl: &Ctl,
    partial: Option<Partial>,
    stopped: bool,
) -> PyResult<PyErr> {
    let part = match partial {
        Some(make) if stopped => make(py, ctl)?,
        _ => None,
    };
    let e = PyKeyboardInterrupt::new_err(if part.is_some() {
        format!("geardyn {what} interrupted: its finished items are in the exception's `partial`")
    } else {
        format!("geardyn {what} interrupted")
    });
    e.value(py).setattr("partial", part)?;
    Ok(e)
}

/// Runs `f` on a worker thread with the interpreter released (the library's own thread pool does
/// the parallel work), polling for Ctrl-C (KeyboardInterrupt) and, with `progress`, printing a
/// progress line on `sys.stderr`.
///
/// Each call runs under a cancel token of its own ([`geardyn_exec::cancel::run_under`]): Ctrl-C
/// cancels it, so the integrations of this call (and of no other: two Python threads calling
/// geardyn stop independently) end at their next step and the lanes at their next period, and
/// the worker returns within about a second; the call then raises `KeyboardInterrupt` whose attribute `partial` holds what
/// `partial` makes of the finished items (or `None`). A second Ctrl-C stops waiting.
pub fn run<T, F>(
    py: Python<'_>,
    what: &str,
    progress: bool,
    partial: Option<Partial>,
    f: F,
) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce(&Ctl) -> anyhow::Result<T> + Send + 'static,
{
    let ctl = Arc::new(Ctl::default());
    let (tx, rx) = mpsc::channel();
    // the receiver is used from inside `detach` closures, which must be `Send`
    let rx = Mutex::new(rx);
    let recv = |rx: &Mutex<mpsc::Receiver<_>>| {
        rx.lock()
            .unwrap_or_else(|e| e.into_inner())
            .recv_timeout(Duration::from_millis(50))
    };
    let token = geardyn_exec::cancel::Token::new();
    let worker_ctl = ctl.clone();
    let worker_token = token.clone();
    let spawned = std::thread::Builder::new()
        .name(format!("geardyn-{what}"))
        .spawn(move || {
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                geardyn_exec::cancel::run_under(&worker_token, || f(&worker_ctl))
            }));
            // whether this call was cancelled while it ran (a run cut by it always sees it here)
            let _ = tx.send((r, worker_token.is_cancelled()));
        });
    if let Err(e) = spawned {
        return Err(PyRuntimeError::new_err(format!(
            "cannot start a worker thread: {e}"
        )));
    }
    let started = Instant::now();
    let mut last = Instant::now();
    let mut shown = ProgressShow::new();
    loop {
        let r = py.detach(|| recv(&rx));
        match r {
            Ok((Ok(_), true)) => {
                // cancelled as it ended: interrupted, with what it finished before
                if progress {
                    shown.show(py, what, &ctl, started, true);
                }
                return Err(interrupted(py, what, &ctl, partial, true)?);
            }
            Ok((Ok(res), false)) => {
                if progress {
                    shown.show(py, what, &ctl, started, true);
                }
                return res.map_err(to_pyerr);
            }
            Ok((Err(payload), _)) => {
                return Err(PyRuntimeError::new_err(format!(
                    "internal error in geardyn: {}",
                    panic_message(payload.as_ref())
                )));
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "internal error in geardyn: the worker ended without a result",
                ))
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if py.check_signals().is_err() {
                    token.cancel();
                    // wait for the worker to stop (runs in flight end at their next step or
                    // period); a second Ctrl-C stops waiting and leaves it to end by itself
                    let mut stopped = false;
                    loop {
                        match py.detach(|| recv(&rx)) {
                            Err(mpsc::RecvTimeoutError::Timeout) => {
                                if py.check_signals().is_err() {
                                    break;
                                }
                            }
                            _ => {
                                stopped = true;
                                break;
                            }
                        }
                    }
                    if progress {
                        shown.show(py, what, &ctl, started, true);
                    }
                    return Err(interrupted(py, what, &ctl, partial, stopped)?);
                }
                if progress && last.elapsed() >= Duration::from_millis(250) {
                    last = Instant::now();
                    shown.show(py, what, &ctl, started, false);
                }
            }
        }
    }
}

/// A result table ([`geardyn_io::schema::Table`]) as a dict of numpy arrays (`float64`, `int64`,
/// `bool`) and numpy unicode arrays for names, keyed by the CSV column names.
pub fn table<'py>(py: Python<'py>, t: &geardyn_io::schema::Table) -> PyResult<Bound<'py, PyDict>> {
    use geardyn_io::schema::Values;
    let c = Columns::new(py);
    for col in &t.columns {
        match &col.values {
            Values::F64(v) => c.f64(&col.name, v.clone())?,
            Values::I64(v) => c.i64(&col.name, v.clone())?,
            // (absent: 0, as documented for the Python tables)
            Values::OptI64(v) => c.i64(&col.name, v.iter().map(|x| x.unwrap_or(0)).collect())?,
            Values::Bool(v) => c.boolean(&col.name, v.clone())?,
            Values::Str(v) => c.str(&col.name, v.clone())?,
        }
    }
    Ok(c.dict)
}
