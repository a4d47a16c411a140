//! Top Lyapunov exponent of the Lorenz system through geardyn's public API: the same analysis
//! code that serves the gear model works on any `HybridSystem` + `Variational` implementation.
//!
//! Run: `cargo run --release --example lorenz_tle`

use geardyn::analysis::lyapunov::{tle_two_trajectory, tle_variational, LyapunovOptions};
use geardyn::model::reference::Lorenz;
use geardyn::solvers::Scheme;

fn main() {
    let sys = Lorenz::default(); // sigma = 10, rho = 28, beta = 8/3
    let opts = LyapunovOptions {
        period: 1.0,
        transient_periods: 50,
        periods: 5000,
        d0: 1e-6,
    };
    let var = tle_variational::<_, 3, 7>(sys, Scheme::dopri_default(), 0.0, [1.0, 1.0, 1.0], &opts)
        .expect("integration");
    let two = tle_two_trajectory(sys, Scheme::dopri_default(), 0.0, [1.0, 1.0, 1.0], &opts)
        .expect("integration");
    println!(
        "Lorenz TLE, variational:    {:.4} +- {:.4}",
        var.tle, var.spread
    );
    println!(
        "Lorenz TLE, two-trajectory: {:.4} +- {:.4}",
        two.tle, two.spread
    );
    println!("published (Sprott 2003):    0.9056");
}
