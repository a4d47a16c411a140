//! B8 (study `map_xi_F`): the maximum dynamic mesh force over the (xi, F) plane, at the omega
//! whose large-(xi, F) corner gives the seed's F_max = 1.340: the peak, the smooth corner, the
//! four bands of strong fluctuation and their link to chaos. Checks seed B 003 §3.5 and 004 §4.5
//! (Fig. 4.8a), §6(3).

use super::{B003, B004, DD_SEED, DS_SEED};
use crate::claims::{Claim, Verdict};
use crate::readings::{f, pct};
use crate::runner::{hdr, Ctx};
use crate::shared::{class_map_figure, line_figure, map_figure, Line, MapView};
use crate::Section;
use anyhow::Result;
use geardyn_analysis::bifurcation::linspace;
use geardyn_analysis::map2d::{MapCell, MapOptions};
use geardyn_analysis::simulate::SimOptions;
use geardyn_scenario::Scenario;
use std::path::Path;

/// The seed's largest maximum dynamic mesh force (003 §3.5, 004 §4.5); the map's omega is
/// chosen to match it.
const F_MAX_SEED: f64 = 1.34;
/// The map's maximum reproduces [`F_MAX_SEED`] within the first distance, partly within the
/// second.
const F_MAX_TOLERANCE: (f64, f64) = (0.03, 0.1);
/// A region is rough (its maximum mesh force fluctuates strongly) when its roughness exceeds
/// this multiple of the roughness outside the seed's four bands.
const ROUGH: f64 = 1.2;

/// The seed's corner of the peak: xi above the first, F above the second.
const PEAK_CORNER: (f64, f64) = (0.2, 0.175);
/// "Small xi and F" of the smooth-corner claim: xi below the first, F below the second.
const SMALL_CORNER: (f64, f64) = (0.04, 0.05);

/// What the study computed: the omega calibration and the map.
#[derive(serde::Serialize, serde::Deserialize)]
pub(super) struct MapData {
    /// The calibration's omegas.
    omegas: Vec<f64>,
    /// Largest mesh force of the large-(xi, F) corner at each omega.
    calibration: Vec<(f64, f64)>,
    /// The omega of the map (its corner maximum closest to [`F_MAX_SEED`]).
    omega: f64,
    /// Cells per axis.
    nm: usize,
    /// The xi values of the map.
    xs: Vec<f64>,
    /// The F values of the map.
    ys: Vec<f64>,
    /// Integration settings of a cell.
    sim: SimOptions,
    /// The cells, row by row over F.
    cells: Vec<MapCell>,
}

crate::runner::study!(MapXiF { lin: &'a Scenario } "map_xi_F" MapData,
    |s, ctx, dir| compute(ctx, s.lin, dir), |data| render(ctx, dir, data));

/// The corner maximum over omega, then the (xi, F) map at the omega that matches the seed.
pub(super) fn compute(ctx: &Ctx, lin: &Scenario, dir: &Path) -> Result<MapData> {
    // the frequency that gives the seed's F_max = 1.340 in the large-(xi, F) corner, near the
    // frequencies of the seed's own xi and F studies (1.5 and 1.4): the corner maximum of a
    // single run jumps with the motion (0.9 to 1.4 over [1.7, 1.9]), so a search over a wide
    // range would land on whichever jump matches
    let omegas = linspace(1.2, 1.6, ctx.n(3, 9));
    let sim = ctx.sim((150, 300), (30, 60));
    let mut cal = Vec::new();
    for &w in &omegas {
        let o = MapOptions {
            x_param: "xi".into(),
            x_values: vec![0.2, 0.25, 0.3],
            y_param: "F".into(),
            y_values: vec![0.175, 0.2],
            sim,
            y0: [0.0, 0.0],
            lyapunov: false,
        };
        let cells = ctx.map(
            dir,
            &format!("corner omega {w}"),
            &lin.with_all(&[("omega", w), ("D_d", DD_SEED), ("D_s", DS_SEED)])?,
            &o,
        )?;
        let mx = cells.iter().map(|c| c.max_force).fold(0.0, f64::max);
        cal.push((w, mx));
    }
    let (w_star, _) = cal
        .iter()
        .copied()
        .min_by(|a, b| {
            (a.1 - F_MAX_SEED)
                .abs()
                .total_cmp(&(b.1 - F_MAX_SEED).abs())
        })
        .unwrap_or((1.5, f64::NAN));
    let nm = ctx.n(12, 50);
    let xs = linspace(0.001, 0.3, nm);
    let ys = linspace(0.001, 0.2, nm);
    let o = MapOptions {
        x_param: "xi".into(),
        x_values: xs.clone(),
        y_param: "F".into(),
        y_values: ys.clone(),
        sim: ctx.sim((100, 300), (24, 60)),
        y0: [0.0, 0.0],
        lyapunov: false,
    };
    let base = lin.with_all(&[("omega", w_star), ("D_d", DD_SEED), ("D_s", DS_SEED)])?;
    let cells = ctx.map(dir, "xi-F map", &base, &o)?;
    Ok(MapData {
        omegas,
        calibration: cal,
        omega: w_star,
        nm,
        xs,
        ys,
        sim: o.sim,
        cells,
    })
}

/// The calibration figure, the maps, the roughness readings and the claims.
pub(super) fn render(ctx: &Ctx, dir: &Path, data: &MapData) -> Result<Section> {
    let (omegas, cal, w_star, nm) = (&data.omegas, &data.calibration, data.omega, data.nm);
    let (xs, ys, cells, sim) = (&data.xs, &data.ys, &data.cells, data.sim);
    let fig_cal = line_figure(
        ctx,
        dir,
        "omega_calibration",
        "Largest mesh force at large (xi, F) against omega",
        "omega",
        vec![(
            "max F_m for xi ≥ 0.2, F ≥ 0.175".into(),
            vec![
                Line { label: "geardyn".into(), points: cal.clone(), dots: false },
                Line { label: "seed F_max = 1.340".into(), points: vec![(omegas[0], 1.34), (omegas[omegas.len() - 1], 1.34)], dots: false },
            ],
        )],
        &[],
        "The seed does not state the frequency of its (xi, F) map; the map is drawn at the omega whose corner maximum is closest to the seed's F_max = 1.340.",
        false,
    )?;
    let map = MapView {
        cells,
        xs,
        ys,
        axes: ("xi", "F"),
        title: &format!(
            "Maximum dynamic mesh force over (xi, F), omega = {}",
            f(w_star)
        ),
    };
    let fig = map_figure(
        ctx, dir, "map_max_force", &map, "max_force",
        &format!("Largest mesh force (units of k_av b_c) of the motion from (0, 0), linear contact law, omega = {} (chosen to match the seed's F_max), D_d = 0.9, D_s = 1 as the xi sweep.", f(w_star)),
    )?;
    let title = format!("Decided motion over (xi, F), omega = {}", f(w_star));
    let fig_c = class_map_figure(
        ctx,
        dir,
        "map_class",
        &MapView {
            title: &title,
            ..map
        },
    )?;
    let peak = cells
        .iter()
        .max_by(|a, b| a.max_force.total_cmp(&b.max_force));
    let (px, py, pv) = peak.map_or((0.0, 0.0, 0.0), |c| (c.x, c.y, c.max_force));
    // roughness: mean |difference| to the right and upper neighbours
    let idx = |i: usize, j: usize| j * nm + i;
    let rough: Vec<f64> = (0..nm * nm)
        .map(|c| {
            let (i, j) = (c % nm, c / nm);
            let mut d = Vec::new();
            if i + 1 < nm {
                d.push((cells[idx(i + 1, j)].max_force - cells[c].max_force).abs());
            }
            if j + 1 < nm {
                d.push((cells[idx(i, j + 1)].max_force - cells[c].max_force).abs());
            }
            d.iter().sum::<f64>() / d.len().max(1) as f64
        })
        .collect();
    let mean_where = |pred: &dyn Fn(&MapCell) -> bool| {
        let v: Vec<f64> = cells
            .iter()
            .zip(&rough)
            .filter(|(c, _)| pred(c))
            .map(|(_, r)| *r)
            .collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    let in_band = |c: &MapCell| {
        (0.044..=0.126).contains(&c.x)
            || (0.236..=0.3).contains(&c.x)
            || c.y <= 0.007
            || (0.055..=0.095).contains(&c.y)
    };
    type CellTest = Box<dyn Fn(&MapCell) -> bool>;
    let bands: [(&str, CellTest); 4] = [
        (
            "xi 0.044–0.126",
            Box::new(|c: &MapCell| (0.044..=0.126).contains(&c.x)),
        ),
        (
            "xi 0.236–0.3",
            Box::new(|c: &MapCell| (0.236..=0.3).contains(&c.x)),
        ),
        ("F 0–0.007", Box::new(|c: &MapCell| c.y <= 0.007)),
        (
            "F 0.055–0.095",
            Box::new(|c: &MapCell| (0.055..=0.095).contains(&c.y)),
        ),
    ];
    let outside = mean_where(&|c| !in_band(c));
    let band_txt: Vec<String> = bands
        .iter()
        .map(|(n, p)| format!("{n}: {}", f(mean_where(&|c| p(c)) / outside.max(1e-12))))
        .collect();
    let band_hits = bands
        .iter()
        .filter(|(_, p)| mean_where(&|c| p(c)) > ROUGH * outside)
        .count();
    let chaotic = |c: &MapCell| c.motion.is_chaotic();
    let rough_chaos = mean_where(&|c| chaotic(c));
    let rough_per = mean_where(&|c| c.motion.is_periodic());
    let small = mean_where(&|c| c.x < SMALL_CORNER.0 && c.y < SMALL_CORNER.1);
    let small_chaos = cells
        .iter()
        .filter(|c| c.x < SMALL_CORNER.0 && c.y < SMALL_CORNER.1 && chaotic(c))
        .count();
    // every omega of the calibration scan once (the map's omega among them)
    let scan: Vec<String> = cal
        .iter()
        .map(|(w, m)| format!("{} at omega = {}", f(*m), f(*w)))
        .collect();
    let claims = vec![
        Claim::new("The largest maximum dynamic mesh force is F_max = 1.340", format!("{B003} §3.5; {B004} §4.5"), "1.340", format!("map maximum {} at omega = {} (the map's grid); corner scan (xi ∈ {{0.2, 0.25, 0.3}} × F ∈ {{0.175, 0.2}}) maxima: {}", f(pv), f(w_star), scan.join(", ")), if (pv - F_MAX_SEED).abs() <= F_MAX_TOLERANCE.0 { Verdict::Reproduced } else if (pv - F_MAX_SEED).abs() <= F_MAX_TOLERANCE.1 { Verdict::Partly } else { Verdict::NotReproduced }, "The seed does not give omega; it was chosen to match F_max (calibration figure), so this row checks that such an omega exists near the seed's other studies (1.4–1.5), not an independent prediction."),
        Claim::new("The peak occurs where both xi and F are large (xi > 0.2, F > 0.175)", format!("{B004} §4.5; {B003} §3.5"), "xi > 0.2, F > 0.175", format!("peak at xi = {}, F = {}", f(px), f(py)), Verdict::of(px > PEAK_CORNER.0 && py > PEAK_CORNER.1), "Largest maximum mesh force on the map grid, compared with the seed's corner xi > 0.2, F > 0.175."),
        Claim::new("For small xi and F the maximum mesh force varies smoothly", format!("{B003} §3.5; {B004} §4.5"), "smooth", format!("mean neighbour difference for xi < 0.04, F < 0.05: {} ({} of the map outside the seed's four bands of strong fluctuation); chaotic cells there: {small_chaos}", f(small), pct(small / outside.max(1e-12))), if small <= ROUGH * outside && small_chaos == 0 { Verdict::Reproduced } else if small <= ROUGH * outside { Verdict::Partly } else { Verdict::NotReproduced }, format!("Roughness = mean absolute difference to the neighbouring cells; smooth = not above {} times the roughness outside the four bands (the rule of the band row below; the corner itself overlaps the band F < 0.007). Where it fails, chaotic cells at small F make the corner rough: chaos at small load also appears in the seed's own load table (Table 5.2, F < 0.0021).", f(ROUGH))),
        Claim::new("F_max fluctuates strongly for xi in (0.044, 0.126) and (0.236, 0.3), F in (0, 0.007) and (0.055, 0.095)", format!("{B004} §4.5, §6(3)"), "four bands", format!("roughness in the band / outside the bands: {}", band_txt.join("; ")), if band_hits == 4 { Verdict::Reproduced } else if band_hits > 0 { Verdict::Partly } else { Verdict::NotReproduced }, format!("A band counts when its roughness exceeds {} times that outside all bands. Bands need not agree: the seed's bands mix the xi sweep (omega = 1.5) and the load sweep (omega = 1.4).", f(ROUGH))),
        Claim::new("The fluctuations coincide with chaotic and back-side meshing behaviour", format!("{B003} §3.5; {B004} §4.5"), "fluctuations where chaotic", format!("roughness of chaotic cells {}, of periodic cells {}", f(rough_chaos), f(rough_per)), Verdict::of(rough_chaos > rough_per), "Decided class of every cell (second map)."),
    ];
    let table = ctx.table(
        &dir.join("omega_calibration.csv"),
        "Largest mesh force at large (xi, F) for each omega",
        &hdr(&["omega", "max F_m (xi ≥ 0.2, F ≥ 0.175)"]),
        cal.iter().map(|(w, m)| vec![f(*w), f(*m)]).collect(),
    )?;
    Ok(Section {
        id: "map_xi_F".into(),
        title: format!("Maximum mesh force over the (xi, F) plane (omega = {})", f(w_star)),
        seed_ref: "003 §3.5; 004 §4.5 (Fig. 4.8a), §6(3)".into(),
        parameters: format!("xi in [0.001, 0.3] × F in [0.001, 0.2], {nm} × {nm} cells; omega = {} (the seed does not state it: chosen where the corner maximum is closest to F_max = 1.340, calibration over omega ∈ [1.2, 1.6], around the seed's xi and F studies at 1.5 and 1.4); D_d = 0.9, D_s = 1 as the xi sweep; linear contact law", f(w_star)),
        method: format!("One run per cell from (0, 0), {} transient + {} recorded excitation periods (the maximum mesh force is taken over the record: a chaotic cell's maximum grows with the record length), decided classification; Dormand–Prince 5(4).", sim.transient_periods, sim.record_periods),
        figures: vec![fig_cal, fig, fig_c],
        readings: vec![format!("Peak {} at xi = {}, F = {}; {} of {} cells chaotic.", f(pv), f(px), f(py), cells.iter().filter(|c| chaotic(c)).count(), cells.len())],
        tables: vec![table],
        claims,
        alternatives: vec![],
        seconds: 0.0,
    })
}
