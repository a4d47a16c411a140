//! A stroboscopic bifurcation diagram of your own system: the forced double-well Duffing
//! oscillator `x'' + 0.3 x' - x + x^3 = gamma cos(1.2 t)` over the forcing amplitude, through the
//! same generic machinery the gear model uses. Prints the period found at each amplitude.
//!
//! Run: `cargo run --release --example duffing_bifurcation`

use geardyn::analysis::generic::{strobe_bifurcation, Family};
use geardyn::model::reference::Duffing;
use geardyn::solvers::Scheme;

struct Forcing;

impl Family<2> for Forcing {
    type System = Duffing;
    fn at(&self, gamma: f64) -> Duffing {
        Duffing {
            delta: 0.3,
            alpha: -1.0,
            beta: 1.0,
            gamma,
            omega: 1.2,
        }
    }
    fn period(&self, _gamma: f64) -> f64 {
        2.0 * std::f64::consts::PI / 1.2
    }
}

fn main() {
    let values: Vec<f64> = (0..=25).map(|i| 0.20 + 0.01 * i as f64).collect();
    let diagram = strobe_bifurcation(
        &Forcing,
        &values,
        Scheme::dopri_default(),
        [1.0, 0.0],
        300,
        64,
        true,
    );
    for b in &diagram {
        let label = if b.period > 0 {
            format!("period {}", b.period)
        } else {
            "chaotic / quasi-periodic".into()
        };
        println!("gamma = {:.2}: {label}", b.value);
    }
}
