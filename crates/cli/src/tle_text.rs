//! The lines a top-Lyapunov-exponent doubling prints, for the pair and the trains alike.

use geardyn_analysis::tle_convergence::{ConvergedTle, Round};

/// One round of the doubling, as it finishes.
pub(crate) fn print_round(r: &Round) {
    println!(
        "  {:>7} periods: TLE {:.6} (at half the run {:.6}), block stderr {:.2e}",
        r.periods, r.tle, r.half, r.stderr
    );
}

/// Whether the doubling converged within `max_periods`.
pub(crate) fn print_convergence(c: &ConvergedTle, max_periods: u64) {
    if c.converged {
        println!(
            "converged: |TLE(N) - TLE(N/2)| and the standard error are below {:.1e}",
            c.tol
        );
    } else {
        println!(
            "WARNING: not converged to {:.1e} within --max-periods {max_periods} (pass a larger cap, or --periods N for a fixed length)",
            c.tol
        );
    }
}
