//! Implementing `HybridSystem` for a system of your own: a harmonically forced oscillator hitting
//! a rigid stop. Copy this file as a template.
//!
//! Run: `cargo run --release --example impact_oscillator`

use geardyn::solvers::{Direction, EventAction, Guards, HybridSystem, Integrator, Scheme, Stop};

struct Oscillator {
    omega: f64,
    gap: f64,
    r: f64,
}

impl HybridSystem<2> for Oscillator {
    type Mode = ();
    type TimeTerms = f64; // cos(omega t), shared by the stages at one time
    fn initial_mode(&self, _t: f64, _y: &mut [f64; 2]) {}
    fn time_terms(&self, t: f64) -> f64 {
        (self.omega * t).cos()
    }
    fn rhs(&self, _t: f64, c: &f64, y: &[f64; 2], _m: &(), dy: &mut [f64; 2]) {
        *dy = [y[1], c - 0.1 * y[1] - y[0]];
    }
    fn guards(&self, _t: f64, y: &[f64; 2], _m: &(), g: &mut Guards) {
        g.push(y[0] + self.gap, Direction::Falling); // the stop at x = -gap
    }
    fn on_event(&self, _t: f64, y: &mut [f64; 2], _m: &mut (), _i: usize) -> EventAction {
        y[1] *= -self.r;
        EventAction::Continue
    }
}

fn main() {
    let sys = Oscillator {
        omega: 1.5,
        gap: 0.2,
        r: 0.7,
    };
    let mut it =
        Integrator::new(sys, Scheme::dopri_default(), 0.0, [0.0, 0.0]).expect("valid start");
    let mut impacts = 0;
    while let Ok(stop) = it.step(100.0) {
        match stop {
            Stop::Event { .. } => {
                impacts += 1;
                if impacts <= 5 {
                    let y = it.last_step().y1();
                    println!(
                        "impact at t = {:.6}, speed {:.6} -> {:.6}",
                        it.t(),
                        y[1],
                        it.y()[1]
                    );
                }
            }
            Stop::Tstop => break,
            _ => {}
        }
    }
    println!("{impacts} impacts up to t = 100; {:?}", it.stats());
}
