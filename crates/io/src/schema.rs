//! The result tables geardyn writes, as data: one home for their column names, order, types and
//! meaning, shared by the CLI's CSV files, the report's CSV files and the Python module's column
//! dicts (docs/configuration.md, "Result tables", lists the same columns).
//!
//! A [`Table`] holds typed columns; [`Table::write_csv`] writes it (one number format per face:
//! the CLI writes every digit, the report six significant ones), and the Python module turns each
//! column into a numpy array of its type. A missing number (a TLE not computed, amplitudes of a
//! failed run) is NaN in a column and an empty cell in a CSV file.

use crate::output::{write_csv, OutputError};
use geardyn_analysis::bifurcation::{Run, TaskResult};
use geardyn_analysis::classify::Motion;
use geardyn_analysis::escape::Lifetime;
use std::path::Path;

/// The values of one column.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    /// Numbers (NaN: none).
    F64(Vec<f64>),
    /// Counts and indices.
    I64(Vec<i64>),
    /// Counts that may be absent (an empty cell in CSV, 0 in Python).
    OptI64(Vec<Option<i64>>),
    /// Flags.
    Bool(Vec<bool>),
    /// Names.
    Str(Vec<String>),
}

impl Values {
    fn len(&self) -> usize {
        match self {
            Values::F64(v) => v.len(),
            Values::I64(v) => v.len(),
            Values::OptI64(v) => v.len(),
            Values::Bool(v) => v.len(),
            Values::Str(v) => v.len(),
        }
    }

    fn cell(&self, i: usize, num: fn(f64) -> String) -> String {
        match self {
            Values::F64(v) if v[i].is_nan() => String::new(),
            Values::F64(v) => num(v[i]),
            Values::I64(v) => v[i].to_string(),
            Values::OptI64(v) => v[i].map_or(String::new(), |x| x.to_string()),
            Values::Bool(v) => v[i].to_string(),
            Values::Str(v) => v[i].clone(),
        }
    }
}

/// A column: its name and values.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// Name (the CSV header, the Python key).
    pub name: String,
    /// Values, one per row.
    pub values: Values,
    /// An input (a parameter value, an initial state): written with every digit whatever the
    /// face's number format, so that it can be given back exactly.
    pub exact: bool,
}

/// A table of equally long typed columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// Columns in order.
    pub columns: Vec<Column>,
}

impl Table {
    /// Appends a column of measured numbers or labels.
    pub fn push(&mut self, name: &str, values: Values) {
        self.columns.push(Column {
            name: name.into(),
            values,
            exact: false,
        });
    }

    /// Appends a column of inputs (written with every digit).
    pub fn push_exact(&mut self, name: &str, values: Values) {
        self.push(name, values);
        if let Some(c) = self.columns.last_mut() {
            c.exact = true;
        }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.values.len())
    }

    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&Values> {
        self.columns
            .iter()
            .find(|c| c.name == name)
            .map(|c| &c.values)
    }

    /// Writes the table as CSV, measured numbers formatted by `num`, inputs with every digit
    /// (NaN: an empty cell).
    pub fn write_csv(&self, path: &Path, num: fn(f64) -> String) -> Result<(), OutputError> {
        let header: Vec<&str> = self.columns.iter().map(|c| c.name.as_str()).collect();
        let rows = (0..self.rows()).map(|i| {
            self.columns
                .iter()
                .map(move |c| c.values.cell(i, if c.exact { full } else { num }))
                .collect::<Vec<String>>()
        });
        write_csv(path, &header, rows)
    }
}

/// A number column taken from a record of type `T`: its name and how to read it.
type NumberColumn<T> = (&'static str, fn(&T) -> f64);

pub use crate::output::full;

/// The exponent a run's class was decided on (chaotic: the significantly positive TLE after the
/// persistence run; quasi-periodic and unsettled: the TLE measured, if any), so that a chaotic
/// row carries its evidence even without `--lyapunov`.
pub fn decision_tle(m: &Motion) -> Option<f64> {
    match m {
        Motion::Chaotic { tle, .. }
        | Motion::QuasiPeriodic { tle, .. }
        | Motion::TransientChaos { tle, .. } => Some(*tle),
        Motion::Unsettled { tle, .. } => *tle,
        _ => None,
    }
}

/// The runs table of a sweep (`runs.csv`): one row per run, the swept parameter `param` under
/// its own name first. Columns (docs/configuration.md, "Result tables"):
///
/// | column | type | meaning |
/// |---|---|---|
/// | `<param>` | f64 | the swept parameter's value (dimensionless, or the `pair.*` field's unit) |
/// | `branch` | str | `none`, `up`, `down` (continuation sweeps) |
/// | `ic` | i64 | initial-state index (multi-initial), else 0 |
/// | `x0`, `v0` | f64 | initial state |
/// | `class` | str | periodic, transient-chaos, quasi-periodic, chaotic, unsettled, diverged, failed |
/// | `label` | str | `n-p-q-r-s` when periodic, else the class (no numbers) |
/// | `period` | i64 | period in excitation periods (0 when not periodic) |
/// | `mesh_period` | i64 | period in mesh cycles when an excitation period spans several (0: none) |
/// | `healthy` | bool | periodic without back-side contact or impact |
/// | `back_contact` | bool | touches the back side (impact, back contact, back-side crossing) |
/// | `impacts` | i64 | back-side impacts in the record |
/// | `p_rate` .. `s_rate` | f64 | crossings per excitation period of `x = D_s` up, `-D_s` down, `D_d` up, `-D_d` down |
/// | `p_id` | f64 | dynamic instability proportion |
/// | `max_force`, `min_force` | f64 | mesh-force extrema (units of `k_av b_c`) |
/// | `max_impact_force` | f64 | largest back-side impact force (0: none) |
/// | `mean_x` .. `p2p_force` | f64 | mean, RMS (alternating part) and peak-to-peak of `x` and the mesh force |
/// | `tle` | f64 | top Lyapunov exponent when requested (per unit dimensionless time) |
/// | `decision_tle` | f64 | the exponent the class was decided on |
/// | `transient_used` | i64 | transient periods used (extended while undecided) |
/// | `decided_by` | str | the evidence of the verdict |
/// | `lifetime` | f64 | escape test: mean lifetime on the chaotic set (excitation periods), an estimate, or a lower bound (95 %) when no copy escaped; empty without the test |
/// | `lifetime_stderr` | f64 | the estimate's standard error (empty for a bound) |
/// | `escaped`, `copies` | i64 | escape test: copies that reached a periodic orbit, copies followed (0, 0 without the test) |
/// | `periods_integrated` | i64 | excitation periods followed in all |
/// | `final_x`, `final_v` | f64 | state at the end of the record |
/// | `reason` | str | why a failed or diverged run has no verdict, else empty |
pub fn runs_table(param: &str, results: &[TaskResult]) -> Table {
    let runs: Vec<(&TaskResult, &Run)> = results
        .iter()
        .flat_map(|r| r.runs.iter().map(move |run| (r, run)))
        .collect();
    let f = |g: &dyn Fn(&TaskResult, &Run) -> f64| {
        Values::F64(runs.iter().map(|(r, u)| g(r, u)).collect())
    };
    let i = |g: &dyn Fn(&Run) -> i64| Values::I64(runs.iter().map(|(_, u)| g(u)).collect());
    let b = |g: &dyn Fn(&Run) -> bool| Values::Bool(runs.iter().map(|(_, u)| g(u)).collect());
    let s = |g: &dyn Fn(&TaskResult, &Run) -> String| {
        Values::Str(runs.iter().map(|(r, u)| g(r, u)).collect())
    };
    let amp = |g: fn(&geardyn_analysis::simulate::Amplitudes) -> f64| {
        f(&|_, u| u.amplitudes.as_ref().map_or(f64::NAN, g))
    };
    let rate = |k: usize| f(&|_, u| u.rates.map_or(f64::NAN, |r| r[k]));
    let mut t = run_keyed(param, runs.iter().copied());
    t.push_exact("x0", f(&|_, u| u.y0[0]));
    t.push_exact("v0", f(&|_, u| u.y0[1]));
    t.push("class", s(&|_, u| u.motion.word().to_string()));
    t.push("label", s(&|_, u| u.label.clone()));
    t.push("period", i(&|u| u.period as i64));
    t.push(
        "mesh_period",
        Values::OptI64(
            runs.iter()
                .map(|(_, u)| u.mesh_period.map(|m| m as i64))
                .collect(),
        ),
    );
    t.push("healthy", b(&|u| u.healthy));
    t.push("back_contact", b(&|u| u.touches_back_side()));
    t.push("impacts", i(&|u| u.impacts as i64));
    for (k, name) in ["p_rate", "q_rate", "r_rate", "s_rate"].iter().enumerate() {
        t.push(name, rate(k));
    }
    t.push("p_id", f(&|_, u| u.p_id));
    t.push("max_force", f(&|_, u| u.max_force));
    t.push("min_force", f(&|_, u| u.min_force));
    t.push(
        "max_impact_force",
        f(&|_, u| {
            u.impact_force_per_period
                .iter()
                .copied()
                .fold(0.0, f64::max)
        }),
    );
    let amplitudes: [NumberColumn<geardyn_analysis::simulate::Amplitudes>; 6] = [
        ("mean_x", |a| a.mean_x),
        ("rms_x", |a| a.rms_x),
        ("p2p_x", |a| a.p2p_x),
        ("mean_force", |a| a.mean_force),
        ("rms_force", |a| a.rms_force),
        ("p2p_force", |a| a.p2p_force),
    ];
    for (name, g) in amplitudes {
        t.push(name, amp(g));
    }
    t.push("tle", f(&|_, u| u.tle.unwrap_or(f64::NAN)));
    t.push(
        "decision_tle",
        f(&|_, u| decision_tle(&u.motion).unwrap_or(f64::NAN)),
    );
    t.push("transient_used", i(&|u| u.transient_used as i64));
    t.push("decided_by", s(&|_, u| u.decided_by.name().to_string()));
    let lifetime = |u: &Run| u.escape.as_ref().map(|e| e.lifetime);
    t.push(
        "lifetime",
        f(&|_, u| lifetime(u).map_or(f64::NAN, |l| l.periods())),
    );
    t.push(
        "lifetime_stderr",
        f(&|_, u| match lifetime(u) {
            Some(Lifetime::Estimate { stderr, .. }) => stderr,
            _ => f64::NAN,
        }),
    );
    t.push(
        "escaped",
        i(&|u| u.escape.as_ref().map_or(0, |e| i64::from(e.escaped))),
    );
    t.push(
        "copies",
        i(&|u| u.escape.as_ref().map_or(0, |e| i64::from(e.copies))),
    );
    t.push("periods_integrated", i(&|u| u.periods_integrated as i64));
    t.push("final_x", f(&|_, u| u.final_state[0]));
    t.push("final_v", f(&|_, u| u.final_state[1]));
    t.push("reason", s(&|_, u| u.reason()));
    t
}

/// The cells of a two-parameter map (`map.csv`): the x parameter `x` and the y parameter `y`
/// under their own names first, then `label`, `period`, `healthy`, `max_force`, `min_force`,
/// `p_id`, `impacts`, `tle` (empty when not computed), one row per cell in cell order
/// (`iy * nx + ix`).
pub fn map_table(x: &str, y: &str, cells: &[geardyn_analysis::map2d::MapCell]) -> Table {
    let f = |g: &dyn Fn(&geardyn_analysis::map2d::MapCell) -> f64| {
        Values::F64(cells.iter().map(g).collect())
    };
    let mut t = Table::default();
    t.push_exact(x, f(&|c| c.x));
    t.push_exact(y, f(&|c| c.y));
    t.push(
        "label",
        Values::Str(cells.iter().map(|c| c.label.clone()).collect()),
    );
    t.push(
        "period",
        Values::I64(cells.iter().map(|c| c.period as i64).collect()),
    );
    t.push(
        "healthy",
        Values::Bool(cells.iter().map(|c| c.healthy).collect()),
    );
    // (a cell without a result has no forces: empty, not 0)
    let measured = |v: fn(&geardyn_analysis::map2d::MapCell) -> f64| {
        move |c: &geardyn_analysis::map2d::MapCell| if c.no_result() { f64::NAN } else { v(c) }
    };
    t.push("max_force", f(&measured(|c| c.max_force)));
    t.push("min_force", f(&measured(|c| c.min_force)));
    t.push("p_id", f(&measured(|c| c.p_id)));
    t.push(
        "impacts",
        Values::I64(cells.iter().map(|c| c.impacts as i64).collect()),
    );
    t.push("tle", f(&|c| c.tle.unwrap_or(f64::NAN)));
    t.push(
        "class",
        Values::Str(cells.iter().map(|c| c.motion.word().to_string()).collect()),
    );
    t.push(
        "decided_by",
        Values::Str(
            cells
                .iter()
                .map(|c| c.decided_by.name().to_string())
                .collect(),
        ),
    );
    t.push(
        "periods_integrated",
        Values::I64(cells.iter().map(|c| c.periods_integrated as i64).collect()),
    );
    t
}

/// A table that starts with the columns naming the run of each row: `<param>` (every digit),
/// `branch`, `ic` (the runs table, the section points, the impact forces).
fn run_keyed<'a>(param: &str, rows: impl Iterator<Item = (&'a TaskResult, &'a Run)>) -> Table {
    let rows: Vec<(&TaskResult, &Run)> = rows.collect();
    let mut t = Table::default();
    t.push_exact(
        param,
        Values::F64(rows.iter().map(|(r, _)| r.value).collect()),
    );
    let branches = rows.iter().map(|(r, _)| r.task.branch_name().to_string());
    t.push("branch", Values::Str(branches.collect()));
    t.push(
        "ic",
        Values::I64(rows.iter().map(|(_, u)| u.ic as i64).collect()),
    );
    t
}

/// The section points of a sweep (`bifurcation.csv`): `<param>, branch, ic, section, x, v,
/// label`, one row per point (`section` one of strobe, ds_up, ds_down, dd_up, dd_down, impact;
/// `x`, `v` the state there).
pub fn points_table(param: &str, results: &[TaskResult]) -> Table {
    let pts: Vec<(&TaskResult, &Run, f64, f64, &'static str)> = results
        .iter()
        .flat_map(|r| {
            r.runs.iter().flat_map(move |run| {
                run.points
                    .iter()
                    .map(move |&(sec, x, v)| (r, run, x, v, sec.name()))
            })
        })
        .collect();
    let mut t = run_keyed(param, pts.iter().map(|p| (p.0, p.1)));
    t.push(
        "section",
        Values::Str(pts.iter().map(|p| p.4.to_string()).collect()),
    );
    t.push("x", Values::F64(pts.iter().map(|p| p.2).collect()));
    t.push("v", Values::F64(pts.iter().map(|p| p.3).collect()));
    t.push(
        "label",
        Values::Str(pts.iter().map(|p| p.1.label.clone()).collect()),
    );
    t
}

/// The impact-force record of a sweep (`impact_force.csv`): `<param>, branch, ic, period,
/// impact_force`, the largest back-side impact force in each recorded excitation period of each
/// run (0: no impact).
pub fn impact_force_table(param: &str, results: &[TaskResult]) -> Table {
    let rows: Vec<(&TaskResult, &Run, usize, f64)> = results
        .iter()
        .flat_map(|r| {
            r.runs.iter().flat_map(move |run| {
                run.impact_force_per_period
                    .iter()
                    .enumerate()
                    .map(move |(j, &f)| (r, run, j, f))
            })
        })
        .collect();
    let mut t = run_keyed(param, rows.iter().map(|p| (p.0, p.1)));
    t.push(
        "period",
        Values::I64(rows.iter().map(|p| p.2 as i64).collect()),
    );
    t.push(
        "impact_force",
        Values::F64(rows.iter().map(|p| p.3).collect()),
    );
    t
}

/// The stiffness table of a physical pair (`stiffness.csv` of `geardyn stiffness`, of the report's
/// pair sections and `geardyn.stiffness()`), one row per sample of `rows` (zone borders appear
/// twice, one row from each side): `position_cycles` (mesh cycles), `k_pair1_N_per_m`,
/// `k_pair2_N_per_m` (entering and leaving pair, 0 out of contact), `k_mesh_N_per_m`, `share1`,
/// `share2` (load shares), `h_drive`, `h_back` (friction factors), `half_backlash` (units of
/// `b_c`: `D_d` in double-tooth, `D_s` in single-tooth zones), `zone` (`double`, `single`), `mu1`,
/// `mu2` (friction coefficients), `film1_um` (film thickness of the entering pair), `lambda1`
/// (film parameter), `regime1` (`ehl`, `mixed`, `boundary`, `constant_mu`).
pub fn pair_stiffness_table<'a>(
    rows: impl Iterator<Item = &'a geardyn_physics::pair::StiffnessRow> + Clone,
    d_double: f64,
    d_single: f64,
) -> Table {
    let f = |g: fn(&geardyn_physics::pair::StiffnessRow) -> f64| {
        Values::F64(rows.clone().map(g).collect())
    };
    let numbers: [NumberColumn<geardyn_physics::pair::StiffnessRow>; 8] = [
        ("position_cycles", |r| r.position),
        ("k_pair1_N_per_m", |r| r.k_pair1),
        ("k_pair2_N_per_m", |r| r.k_pair2),
        ("k_mesh_N_per_m", |r| r.k_mesh),
        ("share1", |r| r.share1),
        ("share2", |r| r.share2),
        ("h_drive", |r| r.h_drive),
        ("h_back", |r| r.h_back),
    ];
    let mut t = Table::default();
    for (name, g) in numbers {
        t.push(name, f(g));
    }
    t.push(
        "half_backlash",
        Values::F64(
            rows.clone()
                .map(|r| if r.single { d_single } else { d_double })
                .collect(),
        ),
    );
    t.push(
        "zone",
        Values::Str(
            rows.clone()
                .map(|r| (if r.single { "single" } else { "double" }).to_string())
                .collect(),
        ),
    );
    t.push("mu1", f(|r| r.mu1));
    t.push("mu2", f(|r| r.mu2));
    t.push("film1_um", f(|r| r.film1 * 1e6));
    t.push("lambda1", f(|r| r.lambda1));
    t.push(
        "regime1",
        Values::Str(
            rows.map(|r| {
                (match r.regime1 {
                    0 => "ehl",
                    1 => "mixed",
                    2 => "boundary",
                    _ => "constant_mu",
                })
                .to_string()
            })
            .collect(),
        ),
    );
    t
}

/// The stiffness table of a dimensionless model (no physical pair): `position_cycles`,
/// `k_dimensionless` (`k / k_av`), `h_drive`, `h_back`, `half_backlash`, at 1024 samples per mesh
/// cycle of the excitation period.
pub fn model_stiffness_table(model: &geardyn_model::MeshModel) -> Table {
    let n = 1024 * model.cycles_per_period() as usize;
    let c = f64::from(model.cycles_per_period());
    let rows: Vec<[f64; 5]> = (0..n)
        .map(|i| {
            let u = c * i as f64 / n as f64;
            let (hd, hb) = model.friction_factors_at(u);
            [u, model.stiffness_at(u), hd, hb, model.backlash_at(u)]
        })
        .collect();
    let mut t = Table::default();
    for (k, name) in [
        "position_cycles",
        "k_dimensionless",
        "h_drive",
        "h_back",
        "half_backlash",
    ]
    .iter()
    .enumerate()
    {
        t.push(name, Values::F64(rows.iter().map(|r| r[k]).collect()));
    }
    t
}

/// A periodic orbit of a branch with the numbers of its record (label, forces, P_ID).
#[derive(Clone, Debug)]
pub struct OrbitRow<'a> {
    /// The branch point (parameter, orbit, multipliers).
    pub point: &'a geardyn_analysis::orbit_branches::BranchPoint,
    /// Label of the orbit's record (n-p-q-r-s).
    pub label: String,
    /// Largest mesh force over the orbit.
    pub max_force: f64,
    /// Proportion of the orbit's time out of drive contact.
    pub p_id: f64,
}

/// The rows of the orbits of a branch: each point with its record
/// ([`geardyn_analysis::orbits_request::orbit_records`]: label, forces and P_ID at its parameter value;
/// `param` the continued parameter, `None` for one orbit at `sc`).
pub fn orbit_rows<'a>(
    sc: &geardyn_scenario::Scenario,
    param: Option<&str>,
    points: &'a [geardyn_analysis::orbit_branches::BranchPoint],
    tau0: f64,
) -> Vec<OrbitRow<'a>> {
    let records = geardyn_analysis::orbits_request::orbit_records(sc, param, points, tau0);
    points
        .iter()
        .zip(records)
        .map(|(point, (label, max_force, p_id))| OrbitRow {
            point,
            label,
            max_force,
            p_id,
        })
        .collect()
}

/// The multiplier columns `mu1_re, mu1_im, mu2_re, mu2_im` (largest modulus first).
fn push_multipliers(t: &mut Table, mus: &[[geardyn_analysis::orbits::Multiplier; 2]]) {
    for i in 0..2 {
        t.push(
            &format!("mu{}_re", i + 1),
            Values::F64(mus.iter().map(|m| m[i].re).collect()),
        );
        t.push(
            &format!("mu{}_im", i + 1),
            Values::F64(mus.iter().map(|m| m[i].im).collect()),
        );
    }
}

/// The orbits of `geardyn orbits` (`branch.csv`): `<param>` (when continued), `branch, x, v,
/// period, label, stable, mu1_re, mu1_im, mu2_re, mu2_im, max_force, p_id`; `x, v` the orbit's
/// point at the stroboscopic phase.
pub fn orbit_branch_table(param: Option<&str>, rows: &[OrbitRow<'_>]) -> Table {
    let mut t = Table::default();
    if let Some(param) = param {
        t.push_exact(
            param,
            Values::F64(rows.iter().map(|r| r.point.param).collect()),
        );
    }
    t.push(
        "branch",
        Values::I64(rows.iter().map(|r| r.point.branch as i64).collect()),
    );
    t.push_exact(
        "x",
        Values::F64(rows.iter().map(|r| r.point.orbit.y[0]).collect()),
    );
    t.push_exact(
        "v",
        Values::F64(rows.iter().map(|r| r.point.orbit.y[1]).collect()),
    );
    t.push(
        "period",
        Values::I64(rows.iter().map(|r| r.point.orbit.period as i64).collect()),
    );
    t.push(
        "label",
        Values::Str(rows.iter().map(|r| r.label.clone()).collect()),
    );
    t.push(
        "stable",
        Values::Bool(rows.iter().map(|r| r.point.orbit.stable).collect()),
    );
    let mus: Vec<_> = rows.iter().map(|r| r.point.orbit.multipliers).collect();
    push_multipliers(&mut t, &mus);
    t.push(
        "max_force",
        Values::F64(rows.iter().map(|r| r.max_force).collect()),
    );
    t.push("p_id", Values::F64(rows.iter().map(|r| r.p_id).collect()));
    t
}

/// The bifurcations of `geardyn orbits` (`bifurcations.csv`): `kind` (one of
/// [`geardyn_analysis::orbit_branches::BifurcationKind::ALL`]), `<param>, branch, x, v, period, mu1_re,
/// mu1_im, mu2_re, mu2_im`.
pub fn bifurcations_table(
    param: &str,
    b: &[geardyn_analysis::orbit_branches::Bifurcation],
) -> Table {
    let mut t = Table::default();
    t.push(
        "kind",
        Values::Str(b.iter().map(|b| b.kind.name().to_string()).collect()),
    );
    t.push_exact(param, Values::F64(b.iter().map(|b| b.param).collect()));
    t.push(
        "branch",
        Values::I64(b.iter().map(|b| b.branch as i64).collect()),
    );
    t.push_exact("x", Values::F64(b.iter().map(|b| b.orbit.y[0]).collect()));
    t.push_exact("v", Values::F64(b.iter().map(|b| b.orbit.y[1]).collect()));
    t.push(
        "period",
        Values::I64(b.iter().map(|b| b.orbit.period as i64).collect()),
    );
    let mus: Vec<_> = b.iter().map(|b| b.orbit.multipliers).collect();
    push_multipliers(&mut t, &mus);
    t
}

/// Labelled orders of `lines.csv`: mesh harmonics and this many shaft sidebands on each side.
pub const LABELLED_SIDEBANDS: usize = 3;

/// `signals.csv` of `geardyn signals` (and `geardyn.signals().signals`): one row per sample of
/// each pair, healthy twin first. Columns: `pair` (`healthy`, `broken`), `tau` (dimensionless
/// time; seconds are `tau / omega_n`), `dte_um` (dynamic transmission error `x b_c`, µm),
/// `mesh_force_N` (`F_m k_av b_c`, N), `acceleration_m_s2` (relative acceleration on the line
/// of action, `x'' b_c omega_n^2`, m/s², the mean over the sample interval). Every digit is
/// written, so that the moments of the raw signals can be recomputed from the file exactly.
pub fn signals_table(r: &geardyn_analysis::signals::SignalsResult) -> Table {
    let mut t = Table::default();
    let each = |g: &dyn Fn(&geardyn_analysis::signals::PairSignals) -> Vec<f64>| {
        Values::F64(r.pairs.iter().flat_map(g).collect())
    };
    t.push(
        "pair",
        Values::Str(
            r.pairs
                .iter()
                .flat_map(|p| std::iter::repeat_n(p.pair.clone(), p.tau.len()))
                .collect(),
        ),
    );
    t.push("tau", each(&|p| p.tau.clone()));
    for (k, name) in geardyn_analysis::signals::SIGNAL_NAMES.iter().enumerate() {
        t.push(name, each(&|p| p.signals[k].clone()));
    }
    t
}

/// `spectrum.csv`: the Welch amplitude spectrum of every signal of every pair, in orders of the
/// pinion revolution. Columns: `pair`, `signal` (a column name of `signals.csv`), `order`
/// (cycles per revolution; the mesh order is `z1`), `amplitude` (unit of the signal).
pub fn spectrum_table(r: &geardyn_analysis::signals::SignalsResult) -> Table {
    let (mut pair, mut signal, mut order, mut amp) = (vec![], vec![], vec![], vec![]);
    for p in &r.pairs {
        for (k, s) in p.spectra.iter().enumerate() {
            for (o, a) in s.orders.iter().zip(&s.amplitude) {
                pair.push(p.pair.clone());
                signal.push(geardyn_analysis::signals::SIGNAL_NAMES[k].to_string());
                order.push(*o);
                amp.push(*a);
            }
        }
    }
    let mut t = Table::default();
    t.push("pair", Values::Str(pair));
    t.push("signal", Values::Str(signal));
    t.push("order", Values::F64(order));
    t.push("amplitude", Values::F64(amp));
    t
}

/// `indicators.csv`: every indicator of every signal of every pair. Columns: `pair`, `signal`,
/// `indicator` (`rms`, `peak_to_peak`, `crest_factor`, `kurtosis` of the raw signal; `fm0`,
/// `fm4`, `m6a`, `m8a`, `na4`, `nb4`, `er`, `sideband_index`, `sideband_level_factor` of its
/// time-synchronous average: docs/analyses.md, "Fault signatures"), `value`.
pub fn indicators_table(r: &geardyn_analysis::signals::SignalsResult) -> Table {
    let (mut pair, mut signal, mut name, mut value) = (vec![], vec![], vec![], vec![]);
    for p in &r.pairs {
        for (k, ind) in p.indicators.iter().enumerate() {
            for (n, v) in ind.named() {
                pair.push(p.pair.clone());
                signal.push(geardyn_analysis::signals::SIGNAL_NAMES[k].to_string());
                name.push(n.to_string());
                value.push(v);
            }
        }
    }
    let mut t = Table::default();
    t.push("pair", Values::Str(pair));
    t.push("signal", Values::Str(signal));
    t.push("indicator", Values::Str(name));
    t.push("value", Values::F64(value));
    t
}

/// `tsa.csv`: the time-synchronous average of every signal over the recorded revolutions.
/// Columns: `pair`, `angle_deg` (pinion angle from the start of the revolution at the sample,
/// degrees), then the signals of `signals.csv`.
pub fn tsa_table(r: &geardyn_analysis::signals::SignalsResult) -> Table {
    let spr = r.samples_per_rev;
    let mut t = Table::default();
    t.push(
        "pair",
        Values::Str(
            r.pairs
                .iter()
                .flat_map(|p| std::iter::repeat_n(p.pair.clone(), spr))
                .collect(),
        ),
    );
    t.push(
        "angle_deg",
        Values::F64(
            r.pairs
                .iter()
                .flat_map(|_| (0..spr).map(|i| (i as f64 + 0.5) * 360.0 / spr as f64))
                .collect(),
        ),
    );
    for (k, name) in geardyn_analysis::signals::SIGNAL_NAMES.iter().enumerate() {
        t.push(
            name,
            Values::F64(
                r.pairs
                    .iter()
                    .flat_map(|p| p.decompositions[k].tsa.iter().copied())
                    .collect(),
            ),
        );
    }
    t
}

/// `lines.csv`: the labelled lines of the time-synchronous average (integer orders, exact, no
/// window): mesh harmonics `meshK` (order `K z1`) and their shaft sidebands `meshK-m`,
/// `meshK+m` (`m = 1 ..= 3`). Columns: `pair`, `signal`, `order`, `label`, `amplitude`.
pub fn lines_table(r: &geardyn_analysis::signals::SignalsResult) -> Table {
    let z = r.options.mesh_order;
    let (mut pair, mut signal, mut order, mut label, mut amp) =
        (vec![], vec![], vec![], vec![], vec![]);
    for p in &r.pairs {
        for (k, d) in p.decompositions.iter().enumerate() {
            for (j, a) in d.lines.iter().enumerate() {
                if let Some(l) = geardyn_analysis::spectrum::order_label(j, z, LABELLED_SIDEBANDS) {
                    pair.push(p.pair.clone());
                    signal.push(geardyn_analysis::signals::SIGNAL_NAMES[k].to_string());
                    order.push(j as i64);
                    label.push(l);
                    amp.push(*a);
                }
            }
        }
    }
    let mut t = Table::default();
    t.push("pair", Values::Str(pair));
    t.push("signal", Values::Str(signal));
    t.push("order", Values::I64(order));
    t.push("label", Values::Str(label));
    t.push("amplitude", Values::F64(amp));
    t
}
