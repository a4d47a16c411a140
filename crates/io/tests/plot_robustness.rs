//! Charts of extreme or broken data finish (issue 13): axis ranges stay finite, tick searches
//! bounded, non-finite points skipped and far points clipped.

use geardyn_io::plot::{
    axis_range, raster_chart, stacked_chart, xy_chart, Chart, Mark, Panel, Raster, Series,
    AXIS_LIMIT, PALETTE,
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

const CHART: Chart<'static> = Chart {
    title: "t",
    x_label: "x",
    y_label: "y",
};

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
fn xy_chart_of_extreme_data_finishes() {
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
            for mark in [Mark::Line, Mark::Dots(2)] {
                xy_chart(
                    &dir.join(format!("c{k}")),
                    &CHART,
                    &[Series {
                        label: "a",
                        points: pts,
                        mark,
                        color: PALETTE[0],
                    }],
                )
                .unwrap();
                let svg = std::fs::read_to_string(dir.join(format!("c{k}.svg"))).unwrap();
                assert!(svg.contains("<svg") && !svg.contains("NaN"), "set {k}");
            }
        }
        std::fs::remove_dir_all(dir).ok();
    });
}

#[test]
fn stacked_chart_with_unbounded_x_range_finishes() {
    let dir = tmp("stacked");
    within_a_minute("stacked", move || {
        let pts = [(0.0, 0.0), (1e300, 1.0), (2.0, f64::NAN), (3.0, -1e300)];
        for (k, xr) in [
            (0.0, 1.0),
            (f64::NEG_INFINITY, f64::INFINITY),
            (f64::NAN, f64::NAN),
            (-1e308, 1e308),
        ]
        .into_iter()
        .enumerate()
        {
            let panels = [Panel {
                y_label: "y",
                series: vec![Series {
                    label: "",
                    points: &pts,
                    mark: Mark::Line,
                    color: PALETTE[1],
                }],
            }];
            stacked_chart(&dir.join(format!("s{k}")), "t", "x", xr, &panels).unwrap();
        }
        std::fs::remove_dir_all(dir).ok();
    });
}

#[test]
fn raster_with_unbounded_ranges_finishes() {
    let dir = tmp("raster");
    within_a_minute("raster", move || {
        let colors = [PALETTE[0]; 4];
        let r = Raster {
            x: (0.0, f64::INFINITY, 2),
            y: (f64::NAN, -1e308, 2),
            colors: &colors,
        };
        raster_chart(
            &dir.join("r"),
            &CHART,
            &r,
            &[],
            Some((f64::NAN, f64::INFINITY)),
        )
        .unwrap();
        // more cells than colours: drawn partly
        let r = Raster {
            x: (0.0, 1.0, 3),
            y: (0.0, 1.0, 3),
            colors: &colors,
        };
        raster_chart(&dir.join("r2"), &CHART, &r, &[], Some((1.0, 1.0))).unwrap();
        std::fs::remove_dir_all(dir).ok();
    });
}
