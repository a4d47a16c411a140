//! The escape test's steps of a [`Decision`]: asking for the ensemble escape test of a positive
//! exponent ([`crate::escape`]) and taking its outcome.

use super::{Decision, Need, Wait};
use crate::engine::Engine;
use crate::escape::{decorrelation_periods, Copy, EscapeOutcome};
use crate::simulate::{Method, SimOptions};
use crate::verdict::Motion;

impl<S: Engine<N>, const N: usize> Decision<'_, S, N> {
    /// Asks for the escape test of a run whose exponent `tle` is significantly positive, its span
    /// cut to what the work budget pays for; a budget that cannot pay for the span a chaotic
    /// verdict requires ([`EscapeSettings::required`]) ends the decision `unsettled`.
    pub(super) fn escape_test(&mut self, tle: (f64, f64)) {
        self.escape_tried = true;
        let mut test = self.opts.escape;
        test.spread =
            decorrelation_periods(tle.0, self.model.excitation_period(), test.perturbation);
        let per_copy_period = match self
            .model
            .follow_method(&self.opts)
            .unwrap_or(self.opts.method)
        {
            Method::Rk4 { steps_per_cycle } => {
                4 * u64::from(steps_per_cycle) * u64::from(self.model.cycles_per_period().max(1))
            }
            Method::Dopri { .. } => (self.res.rhs_evals / self.integrated().max(1)).max(1),
        };
        let left = self.opts.decision_budget.saturating_sub(self.res.rhs_evals);
        let affordable = left / (u64::from(test.copies) * per_copy_period).max(1);
        let needed = test.required(self.opts.decision_periods);
        test.periods = test.span(self.opts.decision_periods);
        if affordable < needed {
            self.budget_spent = true;
            self.s.set_motion(Motion::Unsettled {
                tle: Some(tle.0),
                stderr: Some(tle.1),
            });
            self.ask(Wait::Done, Need::Done);
            return;
        }
        test.periods = test.periods.min(affordable);
        let (t, y) = self.res.final_state;
        let start = Copy {
            t,
            y,
            memory: self.res.final_memory,
        };
        self.ask(Wait::Escape, Need::Escape { start, test });
    }

    /// The outcome of the escape test [`Need::Escape`] asked for ([`Engine::escape`]; `None`
    /// where the engine does not run it).
    pub fn escaped(&mut self, out: Option<EscapeOutcome<N>>) {
        assert!(
            matches!(self.wait, Wait::Escape),
            "no escape test was asked for"
        );
        let Some(out) = out else {
            self.persist(0);
            return;
        };
        self.escape = Some(out.summary());
        self.res.rhs_evals += out.rhs_evals;
        match out.orbits.first() {
            None => {
                let (l, se) = self
                    .tle
                    .expect("the escape test follows a positive exponent");
                // chaotic when the copies' silence lasted the exposure the verdict requires
                // (copies whose integration failed may leave it short)
                let exposure = out.lifetime.periods() * crate::escape::LN_20;
                let excluded = exposure
                    >= (crate::escape::ESCAPE_EXPOSURE * self.opts.decision_periods) as f64 - 0.5;
                self.s.set_motion(if excluded {
                    Motion::Chaotic { tle: l, stderr: se }
                } else {
                    Motion::Unsettled {
                        tle: Some(l),
                        stderr: Some(se),
                    }
                });
                self.ask(Wait::Done, Need::Done);
            }
            Some(g) => {
                // the asymptotic motion: the orbit most copies settled on, recorded with the
                // requested integrator from where the earliest of them reached it
                let more = SimOptions {
                    tau0: g.state.t,
                    start_memory: g.state.memory,
                    transient_periods: 0,
                    strobe_only: false,
                    ..self.opts
                };
                self.used.transient_periods += g.followed;
                self.ask(
                    Wait::EscapeRecord,
                    Need::Sim {
                        y0: g.state.y,
                        opts: more,
                    },
                );
            }
        }
    }
}
