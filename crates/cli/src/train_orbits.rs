//! `geardyn orbits` of a gear train: a periodic orbit by shooting (Newton on the stroboscopic
//! map of the whole state, [`find_orbit`]) with its Floquet multipliers, and with `--param` the
//! orbit followed over the values of one operating parameter (natural continuation: each value
//! starts Newton from the orbit of the one before), each stability change located between two
//! values and typed by the multiplier that crosses the unit circle.
//!
//! The pair's orbits follow their branches by pseudo-arclength through folds and switch branches
//! at period doublings (`geardyn_analysis::orbit_branches`, of the pair's plane); a train's
//! branch ends where Newton loses it (a fold, a grazing), which the output says.

use crate::orbits::OrbitArgs;
use crate::sweep::parse_numbers;
use crate::train::{check_work, dynamic_factors, with_model, TrainRun};
use anyhow::{bail, Result};
use geardyn_analysis::bifurcation::{range_values, MAX_RANGE_VALUES};
use geardyn_analysis::classify::{simulate_decided, Decide};
use geardyn_analysis::engine::Engine;
use geardyn_analysis::orbits::{describe_orbit, find_orbit, Multiplier, Orbit, OrbitOptions};
use geardyn_analysis::simulate::{SimOptions, Summary};
use geardyn_io::figure::{palette, write_figure, Figure, Layer, LegendEntry, Panel, Style};
use geardyn_io::output::{write_json, write_text};
use geardyn_io::run_record;
use geardyn_model::GearSystem;
use geardyn_train::dynamics::{TrainModel, TrainOperating};
use std::fmt::Write as _;

/// Values of a train's orbit continuation when `--range` gives only START:STOP.
const DEFAULT_VALUES: usize = 41;

/// One orbit of the branch.
struct Found<const N: usize> {
    value: f64,
    orbit: Orbit<N>,
    summary: Option<Summary>,
    /// Each mesh's deflection at the orbit's stroboscopic point.
    deflections: Vec<f64>,
}

/// `geardyn orbits --preset planetary|two-stage|pair` or `--system FILE`.
pub fn run(t: &TrainRun, a: &OrbitArgs) -> Result<()> {
    if a.switch_up_to != 0 {
        bail!("--switch-up-to: branch switching at doublings is the pair's (its plane); a train's orbit is followed over the values, its doublings located and typed");
    }
    let pair = geardyn_analysis::orbits_request::OrbitsRequest::default();
    if a.ds != pair.ds || a.max_points != pair.max_points {
        bail!("--ds and --max-points set the pair's pseudo-arclength continuation; a train's orbit is followed at the --range START:STOP:COUNT values");
    }
    if a.diagram != crate::orbits::DEFAULT_DIAGRAM {
        bail!("--diagram: the brute-force diagram under the branch is the pair's; for a train run `geardyn bifurcation` over the same range");
    }
    let values = match (&a.param, &a.range) {
        (Some(p), Some(r)) => {
            if !TrainOperating::FIELDS.contains(&p.as_str()) {
                bail!(
                    "--param {p}: a train continues one of {}",
                    TrainOperating::FIELDS.join(", ")
                );
            }
            t.check_stiffness_form(&[p])?;
            let parts = r.split(':').count();
            let spec = if parts == 2 {
                format!("{r}:{DEFAULT_VALUES}")
            } else {
                r.clone()
            };
            let (lo, hi, n) = parse_numbers(
                &spec,
                "--range",
                "START:STOP or START:STOP:COUNT (a train's orbit is found at COUNT values, default 41)",
            )?;
            if lo == hi {
                bail!("bad --range {r:?}: START and STOP are equal; an orbit is followed between two different values");
            }
            let v = range_values("range", (lo, hi, n), MAX_RANGE_VALUES)?;
            for &x in &v {
                let mut op = t.op;
                op.set(p, x).map_err(|e| anyhow::anyhow!("--range: {e}"))?;
            }
            Some((p.clone(), v))
        }
        (Some(_), None) => bail!("--param needs --range START:STOP[:COUNT]"),
        (None, Some(_)) => bail!("--range needs --param NAME"),
        (None, None) => None,
    };
    if !(a.rtol.is_finite() && (1e-14..=1e-4).contains(&a.rtol)) {
        bail!("bad --rtol {}: allowed [1e-14, 1e-4]", a.rtol);
    }
    if let Some(n) = a.period {
        if !(1..=geardyn_analysis::orbits::MAX_ORBIT_PERIOD).contains(&n) {
            bail!(
                "bad --period {n}: allowed 1 ..= {}",
                geardyn_analysis::orbits::MAX_ORBIT_PERIOD
            );
        }
    }
    let cfg = geardyn_io::Config::preset("classic")?;
    let mut sim = cfg.sim_options()?;
    sim.transient_periods = a.transient;
    let cap = cfg.simulation.max_work;
    with_model!(&t.spec, &t.op, |m| {
        check_work(&m, &sim, 1, cap)?;
        run_model(t, &m, a, values.as_ref(), &sim)
    })
}

fn model_at<const N: usize>(t: &TrainRun, param: Option<(&str, f64)>) -> Result<TrainModel<N>> {
    let mut op = t.op;
    if let Some((p, v)) = param {
        op.set(p, v)?;
    }
    Ok(TrainModel::<N>::new(&t.spec, &op)?)
}

/// The first orbit's start: with `--period`, the state after the transient; else the decided
/// motion from the static state, which must be periodic (its last stroboscopic point, its
/// period).
fn start<const N: usize>(
    m: &TrainModel<N>,
    a: &OrbitArgs,
    sim: &SimOptions,
) -> Result<([f64; N], u32)>
where
    TrainModel<N>: Engine<N>,
{
    let opts = SimOptions {
        record_periods: sim.record_periods.max(64),
        ..*sim
    };
    let (res, s, _) = simulate_decided(m, m.static_state(), &opts, Decide::default())?;
    let y = res
        .strobe_states()
        .last()
        .copied()
        .unwrap_or(res.final_state.1);
    let period = match (a.period, s.period) {
        (Some(n), _) => n,
        (None, 0) => bail!(
            "the motion from the static state is not periodic ({}): give --period N to seek an orbit of N periods from its last stroboscopic point",
            s.describe()
        ),
        (None, n) => n as u32,
    };
    Ok((y, period))
}

fn found<const N: usize>(m: &TrainModel<N>, value: f64, orbit: Orbit<N>) -> Found<N> {
    let summary = describe_orbit(m, &orbit, 0.0).ok();
    let deflections = (0..m.mesh_count())
        .map(|k| m.mesh_state(0.0, &orbit.y, k)[0])
        .collect();
    Found {
        value,
        orbit,
        summary,
        deflections,
    }
}

/// Why Newton lost the orbit, in a train's terms (the pair's advice names its initial state).
fn lost(e: &geardyn_analysis::orbits::OrbitError) -> String {
    use geardyn_analysis::orbits::OrbitError;
    match e {
        OrbitError::NoConvergence {
            iterations,
            residual,
            ..
        } => format!(
            "Newton's method did not converge from the orbit before in {iterations} iterations (residual {residual:e})"
        ),
        other => other.to_string(),
    }
}

/// The kind of stability change between an orbit and the next, from the leading multiplier on
/// the unstable side.
fn change(mu: Multiplier) -> &'static str {
    if mu.im.abs() > 1e-9 * mu.abs() {
        "Neimark-Sacker (torus)"
    } else if mu.re < 0.0 {
        "period doubling (flip)"
    } else {
        "fold or pitchfork (multiplier +1)"
    }
}

fn run_model<const N: usize>(
    t: &TrainRun,
    first: &TrainModel<N>,
    a: &OrbitArgs,
    values: Option<&(String, Vec<f64>)>,
    sim: &SimOptions,
) -> Result<()>
where
    TrainModel<N>: Engine<N>,
{
    let started = std::time::Instant::now();
    let param = values.map(|v| v.0.as_str());
    let first_model: TrainModel<N> = match values {
        Some((p, v)) => model_at(t, Some((p, v[0])))?,
        None => first.clone(),
    };
    let (y0, period) = start(&first_model, a, sim)?;
    let opts = OrbitOptions {
        period,
        tau0: 0.0,
        rtol: a.rtol,
        atol: 1e-2 * a.rtol,
        ..OrbitOptions::default()
    };
    let _lock = run_record::prepare_folder(&a.out, "orbits", None, false)?;
    let mut branch: Vec<Found<N>> = Vec::new();
    let mut end = String::new();
    match values {
        None => {
            let o = find_orbit(&first_model, y0, &opts)?;
            branch.push(found(&first_model, f64::NAN, o));
        }
        Some((p, vals)) => {
            let mut y = y0;
            let mut n = period;
            for &v in vals {
                let m: TrainModel<N> = model_at(t, Some((p, v)))?;
                let o = OrbitOptions { period: n, ..opts };
                match find_orbit(&m, y, &o) {
                    Ok(orbit) => {
                        y = orbit.y;
                        n = orbit.period;
                        branch.push(found(&m, v, orbit));
                    }
                    Err(e) => {
                        end = format!(
                            "the branch ends between {p} = {} and {v}: {} (a fold turns the orbit back, or a grazing changes its events; a finer --range COUNT may follow it further)",
                            branch.last().map_or(f64::NAN, |f| f.value),
                            lost(&e)
                        );
                        break;
                    }
                }
            }
            if branch.is_empty() {
                bail!("no orbit at {p} = {}: {end}", vals[0]);
            }
        }
    }
    // stability changes between consecutive values
    let mut changes: Vec<(f64, f64, String, Multiplier)> = Vec::new();
    for w in branch.windows(2) {
        let (b0, b1) = (&w[0], &w[1]);
        if b0.orbit.stable != b1.orbit.stable || b0.orbit.period != b1.orbit.period {
            let unstable = if b0.orbit.stable {
                &b1.orbit
            } else {
                &b0.orbit
            };
            let mu = unstable.multipliers[0];
            let kind = if b0.orbit.period != b1.orbit.period {
                format!(
                    "period {} -> {} (the orbit followed became one of another period: a period doubling, or the end of one, between these values)",
                    b0.orbit.period, b1.orbit.period
                )
            } else {
                change(mu).to_string()
            };
            changes.push((b0.value, b1.value, kind, mu));
        }
    }
    write_outputs(t, first, a, param, &branch, &changes, &end, started)?;
    // in words
    match param {
        None => {
            let f = &branch[0];
            let o = &f.orbit;
            println!(
                "period-{} orbit of {} ({}): {} stroboscopic deflection {:.6}; multipliers {} and {} ({}), label {}, max force {}",
                o.period,
                t.title_name(),
                t.source,
                first.mesh_name(0),
                f.deflections[0],
                mu_text(o.multipliers[0]),
                mu_text(o.multipliers[1]),
                if o.stable { "stable" } else { "unstable" },
                f.summary.as_ref().map_or("-", |s| s.label.as_str()),
                f.summary.as_ref().map_or(f64::NAN, |s| s.max_force),
            );
        }
        Some(p) => {
            println!(
                "{}: {} orbits over {p} ({} stable); {} change(s) of stability or period:",
                t.spec.name,
                branch.len(),
                branch.iter().filter(|f| f.orbit.stable).count(),
                changes.len()
            );
            for (lo, hi, kind, mu) in &changes {
                println!(
                    "  between {p} = {lo} and {hi}: {kind} (leading multiplier {}, |mu| = {:.4})",
                    mu_text(*mu),
                    mu.abs()
                );
            }
            if !end.is_empty() {
                println!("  {end}");
            }
        }
    }
    println!("-> {}", a.out.display());
    Ok(())
}

fn mu_text(m: Multiplier) -> String {
    if m.im == 0.0 {
        format!("{:.6}", m.re)
    } else {
        format!("{:.6}{:+.6}i", m.re, m.im)
    }
}

#[allow(clippy::too_many_arguments)]
fn write_outputs<const N: usize>(
    t: &TrainRun,
    m: &TrainModel<N>,
    a: &OrbitArgs,
    param: Option<&str>,
    branch: &[Found<N>],
    changes: &[(f64, f64, String, Multiplier)],
    end: &str,
    started: std::time::Instant,
) -> Result<()> {
    let names: Vec<String> = (0..m.mesh_count()).map(|k| m.mesh_name(k)).collect();
    let mut csv = format!(
        "{},period,stable,mu_abs,mu_re,mu_im,residual,label,max_force,p_id",
        param.unwrap_or("value")
    );
    for n in &names {
        let _ = write!(
            csv,
            ",\"x {n}\",\"label {n}\",\"max_force {n}\",\"dynamic_factor {n}\""
        );
    }
    csv.push('\n');
    for f in branch {
        let o = &f.orbit;
        let mu = o.multipliers[0];
        let s = f.summary.as_ref();
        // (a single mesh's summary is the train's: no list per mesh)
        let mesh = |k: usize| -> Option<(String, f64)> {
            s.and_then(|s| match s.meshes.get(k) {
                Some(x) => Some((x.label.clone(), x.max_force)),
                None if names.len() == 1 => Some((s.label.clone(), s.max_force)),
                None => None,
            })
        };
        let _ = write!(
            csv,
            "{},{},{},{},{},{},{},{},{},{}",
            if f.value.is_nan() {
                String::new()
            } else {
                f.value.to_string()
            },
            o.period,
            o.stable,
            mu.abs(),
            mu.re,
            mu.im,
            o.residual,
            s.map_or(String::new(), |s| s.label.clone()),
            s.map_or(f64::NAN, |s| s.max_force),
            s.map_or(f64::NAN, |s| s.p_id),
        );
        let factors = s.map(|s| {
            let mm: TrainModel<N> = model_at(t, param.map(|p| (p, f.value))).expect("checked");
            dynamic_factors(&mm, s)
        });
        for k in 0..names.len() {
            let ms = mesh(k);
            let df = factors.as_ref().map_or(f64::NAN, |d| d[k].1);
            let _ = write!(
                csv,
                ",{},{},{},{}",
                f.deflections[k],
                ms.as_ref().map_or(String::new(), |x| x.0.clone()),
                ms.as_ref().map_or(f64::NAN, |x| x.1),
                if df.is_finite() {
                    df.to_string()
                } else {
                    String::new()
                }
            );
        }
        csv.push('\n');
    }
    write_text(&a.out.join("branch.csv"), &csv)?;
    let json = serde_json::json!({
        "param": param,
        "orbits": branch.iter().map(|f| serde_json::json!({
            "value": if f.value.is_nan() { None } else { Some(f.value) },
            // (the state in the train's elastic coordinates; the monodromy matrix left out)
            "orbit": {
                "y": f.orbit.y.to_vec(),
                "period": f.orbit.period,
                "stable": f.orbit.stable,
                "multipliers": f.orbit.multipliers.to_vec(),
                "residual": f.orbit.residual,
                "iterations": f.orbit.iterations,
            },
            "summary": f.summary,
        })).collect::<Vec<_>>(),
        "stability_changes": changes.iter().map(|(lo, hi, kind, mu)| serde_json::json!({
            "from": lo, "to": hi, "kind": kind, "multiplier": mu,
        })).collect::<Vec<_>>(),
        "end": if end.is_empty() { None } else { Some(end) },
    });
    write_json(&a.out.join("orbits.json"), &json)?;
    let swept: Vec<run_record::Swept> = param
        .map(|p| {
            vec![run_record::Swept::of(
                p,
                &branch.iter().map(|f| f.value).collect::<Vec<_>>(),
            )]
        })
        .unwrap_or_default();
    t.write_record(&a.out, "orbits", &swept, started)?;
    if let Some(p) = param {
        let stab = |stable: bool| -> Vec<(f64, f64)> {
            branch
                .iter()
                .filter(|f| f.orbit.stable == stable)
                .map(|f| (f.value, f.deflections[0]))
                .collect()
        };
        let mu: Vec<(f64, f64)> = branch
            .iter()
            .map(|f| (f.value, f.orbit.multipliers[0].abs()))
            .collect();
        write_figure(
            &a.out.join("branch"),
            &Figure {
                title: format!(
                    "Periodic orbits over {p}: {} ({}), {}",
                    t.title_name(),
                    t.source,
                    t.op_text(&[p])
                ),
                x_label: p.into(),
                panels: vec![
                    Panel {
                        y_label: format!("x {} (orbit point)", names[0]),
                        layers: vec![
                            Layer {
                                points: stab(true),
                                style: Style::Dots(3),
                                color: palette(0),
                            },
                            Layer {
                                points: stab(false),
                                style: Style::Dots(3),
                                color: palette(3),
                            },
                        ],
                        ..Default::default()
                    },
                    Panel {
                        y_label: "largest |Floquet multiplier|".into(),
                        layers: vec![Layer {
                            points: mu,
                            style: Style::Line(2),
                            color: palette(1),
                        }],
                        hlines: vec![1.0],
                        ..Default::default()
                    },
                ],
                legend: vec![
                    LegendEntry::dot("stable orbit", palette(0)),
                    LegendEntry::dot("unstable orbit", palette(3)),
                ],
                panel_height: 280,
                ..Default::default()
            },
        )?;
    }
    Ok(())
}
