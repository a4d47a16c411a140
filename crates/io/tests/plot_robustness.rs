//! Figures of extreme or broken data finish (issue 13): axis ranges stay finite, tick searches
//! bounded, non-finite points skipped and far points clipped; NaN, infinite or empty data never
//! panic.

use geardyn_io::figure::{
    axis_range, palette, write_figure, write_raster, Figure, Layer, LegendEntry, Panel,
    RasterFigure, Style, AXIS_LIMIT,
};
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::Duration;

/// Runs `f` on a thread and fails the test if it has not finished within a minute.
fn within_a_minute<F: FnOnce() + Send + 'static>(what: &str, f: F) {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        f();
        let _ = tx.send(());
    });
    match rx.recv_timeout(Duration::from_secs(60)) {
        Ok(()) => {}
        Err(mpsc::RecvTimeoutError::Timeout) => panic!("{what}: still drawing after 60 s"),
        Err(mpsc::RecvTimeoutError::Disconnected) => panic!("{what}: panicked"),
    }
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("geardyn-plot-rob-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn figure(points: Vec<(f64, f64)>, style: Style, x_range: Option<(f64, f64)>) -> Figure {
    Figure {
        title: "t".into(),
        x_label: "x".into(),
        x_range,
        panels: vec![Panel {
            y_label: "y".into(),
            layers: vec![Layer {
                points,
                style,
                color: palette(0),
            }],
            hlines: vec![0.0, f64::NAN, f64::INFINITY],
            ..Default::default()
        }],
        legend: vec![LegendEntry::line("a", palette(0))],
        ..Default::default()
    }
}

#[test]
fn axis_ranges_are_finite_and_ordered() {
    let cases = [
        (0.0, 1.0),
        (1.0, 0.0),
        (-1e308, 1e308),
        (-f64::MAX, f64::MAX),
        (f64::NEG_INFINITY, f64::INFINITY),
        (f64::NAN, f64::NAN),
        (f64::NAN, 3.0),
        (5.0, 5.0),
        (1e300, 1e300),
        (0.0, f64::INFINITY),
        (1e-320, 2e-320),
    ];
    for (lo, hi) in cases {
        let (a, b) = axis_range(lo, hi);
        assert!(a.is_finite() && b.is_finite(), "{lo} {hi}: {a} {b}");
        assert!(b > a && (b - a).is_finite(), "{lo} {hi}: {a} {b}");
        assert!(a >= -AXIS_LIMIT * 1.01 && b <= AXIS_LIMIT * 1.01);
    }
    assert_eq!(axis_range(0.0, 1.0), (0.0, 1.0));
    assert_eq!(axis_range(2.0, -1.0), (-1.0, 2.0));
}

#[test]
fn figure_of_extreme_data_finishes() {
    let dir = tmp("xy");
    within_a_minute("xy", move || {
        let sets: Vec<Vec<(f64, f64)>> = vec![
            // an axis spanning ~1e308 each way: its width overflows f64
            vec![(-1e308, 0.0), (1e308, 1.0)],
            vec![(0.0, -f64::MAX), (1.0, f64::MAX), (2.0, 0.0)],
            // non-finite data among finite ones
            vec![
                (0.0, 0.0),
                (1.0, f64::NAN),
                (f64::INFINITY, 1.0),
                (2.0, f64::NEG_INFINITY),
                (3.0, 1.0),
            ],
            // nothing finite at all
            vec![(f64::NAN, f64::NAN), (f64::INFINITY, 0.0)],
            // a flat series far out
            vec![(1e300, 1e300), (1e300, 1e300)],
            vec![],
        ];
        for (k, pts) in sets.iter().enumerate() {
            for style in [Style::Line(1), Style::Dots(2)] {
                write_figure(
                    &dir.join(format!("c{k}")),
                    &figure(pts.clone(), style, None),
                )
                .unwrap();
                let svg = std::fs::read_to_string(dir.join(format!("c{k}.svg"))).unwrap();
                assert!(svg.contains("<svg") && !svg.contains("NaN"), "set {k}");
            }
        }
        // no panel at all
        write_figure(&dir.join("empty"), &Figure::default()).unwrap();
        std::fs::remove_dir_all(dir).ok();
    });
}

#[test]
fn figure_with_unbounded_x_range_finishes() {
    let dir = tmp("stacked");
    within_a_minute("stacked", move || {
        let pts = vec![(0.0, 0.0), (1e300, 1.0), (2.0, f64::NAN), (3.0, -1e300)];
        for (k, xr) in [
            (0.0, 1.0),
            (f64::NEG_INFINITY, f64::INFINITY),
            (f64::NAN, f64::NAN),
            (-1e308, 1e308),
            (1.0, 1.0),
        ]
        .into_iter()
        .enumerate()
        {
            let mut fig = figure(pts.clone(), Style::Line(2), Some(xr));
            fig.panels.push(fig.panels[0].clone());
            fig.panels[1].y_range = Some((f64::NAN, f64::INFINITY));
            write_figure(&dir.join(format!("s{k}")), &fig).unwrap();
        }
        std::fs::remove_dir_all(dir).ok();
    });
}

#[test]
fn raster_with_unbounded_ranges_finishes() {
    let dir = tmp("raster");
    within_a_minute("raster", move || {
        let colors = vec![palette(0); 4];
        let fig = RasterFigure {
            title: "t".into(),
            x: (0.0, f64::INFINITY, 2),
            y: (f64::NAN, -1e308, 2),
            colors: colors.clone(),
            colorbar: Some((f64::NAN, f64::INFINITY, "m".into())),
            marks: vec![(f64::NAN, 0.0), (f64::INFINITY, 1.0)],
            ..Default::default()
        };
        write_raster(&dir.join("r"), &fig).unwrap();
        // more cells than colours: drawn partly
        let fig = RasterFigure {
            x: (0.0, 1.0, 3),
            y: (0.0, 1.0, 3),
            colors,
            colorbar: Some((1.0, 1.0, "m".into())),
            legend: vec![LegendEntry::dot("a", palette(1))],
            ..Default::default()
        };
        write_raster(&dir.join("r2"), &fig).unwrap();
        // no cells at all
        write_raster(&dir.join("r3"), &RasterFigure::default()).unwrap();
        std::fs::remove_dir_all(dir).ok();
    });
}
