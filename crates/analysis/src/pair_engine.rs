//! The single pair's engine: its decisions follow on lockstep lanes of its own mesh kernel and
//! its exponents run in the lanes ([`crate::lanes`], [`crate::lanes_tle`]); which follow is
//! validated for which kind of pair, and at which resolution it runs.

use crate::engine::Engine;
use crate::escape::{escape_test, Copy, EscapeOutcome, EscapeSettings};
use crate::simulate::{simulate, Method, SimError, SimOptions, SimResult};
use geardyn_model::MeshModel;

/// Fewest RK4 steps per mesh cycle of a follow (a mesh cycle much shorter than the natural
/// period still has its stiffness variation resolved).
pub const MIN_FOLLOW_STEPS_PER_CYCLE: u32 = 32;

/// Whether the coarse follow has been shown faithful for `model`'s kind: a contact law the
/// lockstep lanes step themselves (linear, without hysteresis), bilateral — C1, and the broken
/// and internal pairs with impacts, friction and a time-varying backlash. The check
/// (docs/analyses.md, rule 2): the quick reports of the three presets decided with and without the
/// follow differ in no more runs than two runs of the requested integrator whose tolerances
/// differ by 10 % (internal: 156 class changes of 2 048 with the follow, 169 and 176 with rtol
/// 1.1e-9 and 0.9e-9; breakage: 5 of 102, against 3 and 4). Other laws follow with the
/// requested integrator: the lanes do not step them, and the follow was not checked there.
pub fn follow_validated(model: &MeshModel) -> bool {
    crate::lanes::lanes_cover_contact(model) && !model.params().unilateral
}

/// The integrator of a decision's *follow*: the transient of a persistence block, the long part
/// of the decision that records nothing and asks one question only — does the motion leave the
/// chaotic set for a periodic orbit before the horizon? Every record, period test and exponent
/// uses the requested integrator; the follow only carries the state from one block's record to
/// the next, and any faithful pseudo-orbit answers that question as well as another (a chaotic
/// transient's end is a statistical event: two integrations that round differently end it at
/// different times anyway). So it runs as fixed-step RK4 at `opts.follow_steps` steps per
/// natural period, rounded up to the ladder 32, 48, 64, 96, 128, ... steps per mesh cycle (at
/// least [`MIN_FOLLOW_STEPS_PER_CYCLE`]; the runs of a sweep over `omega` share lanes within a
/// rung), which the lockstep lanes advance together; never finer than a requested RK4. `None`: follow with the
/// requested integrator (`follow_steps` = 0, a requested RK4 already as coarse, or a model of a
/// kind the follow has not been shown faithful for: [`follow_validated`]).
///
/// ```
/// use geardyn_analysis::pair_engine::follow_method;
/// use geardyn_analysis::simulate::{Method, SimOptions};
/// let mut p = geardyn_model::presets::classic();
/// p.omega = 1.2;
/// let m = geardyn_model::MeshModel::new(&p).unwrap();
/// // C1 at omega = 1.2: a mesh cycle of 5.24 holds 64 steps of at most 2 pi / 64
/// assert_eq!(follow_method(&m, &SimOptions::default()), Some(Method::Rk4 { steps_per_cycle: 64 }));
/// let off = SimOptions { follow_steps: 0, ..Default::default() };
/// assert_eq!(follow_method(&m, &off), None);
/// // at omega = 0.6 the mesh cycle is twice as long: 107 steps needed, 128 taken
/// p.omega = 0.6;
/// let m = geardyn_model::MeshModel::new(&p).unwrap();
/// assert_eq!(follow_method(&m, &SimOptions::default()), Some(Method::Rk4 { steps_per_cycle: 128 }));
/// // at omega = 0.8: 80 needed, 96 taken
/// p.omega = 0.8;
/// let m = geardyn_model::MeshModel::new(&p).unwrap();
/// assert_eq!(follow_method(&m, &SimOptions::default()), Some(Method::Rk4 { steps_per_cycle: 96 }));
/// ```
pub fn follow_method(model: &MeshModel, opts: &SimOptions) -> Option<Method> {
    if opts.follow_steps == 0 || !follow_validated(model) {
        return None;
    }
    let per_cycle = f64::from(opts.follow_steps) * model.mesh_cycle_time() / std::f64::consts::TAU;
    let need =
        (per_cycle.ceil().min(f64::from(u32::MAX / 2)) as u32).max(MIN_FOLLOW_STEPS_PER_CYCLE);
    // the ladder 32, 48, 64, 96, 128, ...: at most a third more steps than needed
    let two = need.next_power_of_two();
    let steps = if two / 4 * 3 >= need {
        two / 4 * 3
    } else {
        two
    };
    match opts.method {
        Method::Rk4 { steps_per_cycle } if steps_per_cycle <= steps => None,
        _ => Some(Method::Rk4 {
            steps_per_cycle: steps,
        }),
    }
}

/// TLE of the motion continuing from `(t, y)` and its standard error, or `None` if it cannot be
/// computed: the exponent [`crate::classify::Need::Tle`] asks for.
pub fn tle_of(
    model: &MeshModel,
    opts: &SimOptions,
    t: f64,
    y: [f64; 2],
    memory: f64,
) -> Option<(f64, f64)> {
    crate::lanes_tle::tles_of(
        &[(model, t, y, memory)],
        opts,
        crate::classify::tle_periods(opts),
    )
    .pop()
    .flatten()
}

/// The ensemble escape test ([`crate::escape`]) of the pair's motion continuing from `start`
/// with the settings `test`, inside a decision of settings `opts`:
/// the copies advance together in the lockstep lanes, in fixed-step RK4 at the follow's resolution
/// ([`follow_method`]; a requested RK4 as it is), their stroboscopic points read by the period
/// test of that integrator. `None` where the lanes do not step the pair's contact law, or for an
/// adaptive integrator with the follow turned off.
pub fn escape_of(
    model: &MeshModel,
    opts: &SimOptions,
    test: &EscapeSettings,
    start: Copy<2>,
) -> Option<EscapeOutcome<2>> {
    if !test.on() || !follow_validated(model) {
        return None;
    }
    let method = match (follow_method(model, opts), opts.method) {
        (Some(m), _) => m,
        (None, m @ Method::Rk4 { .. }) => m,
        (None, Method::Dopri { .. }) => return None,
    };
    let grid = opts.tau0;
    let advance = |copies: &mut [Copy<2>], periods: u64| {
        let o = SimOptions {
            method,
            transient_periods: 0,
            record_periods: periods,
            trajectory: false,
            strobe_only: true,
            ..*opts
        };
        let Ok(o) = crate::lanes::LaneSim::new(&o) else {
            // nothing to integrate: no copy moves
            return (copies.iter().map(|_| None).collect(), 0);
        };
        let items: Vec<crate::lanes::Item<'_>> = copies
            .iter()
            .enumerate()
            .map(|(out, c)| crate::lanes::Item {
                out,
                model,
                y0: c.y,
                t0: c.t,
                memory: c.memory,
                transient: 0,
                record: periods,
                strobe_only: true,
            })
            .collect();
        let res = crate::lanes::simulate_items(
            &items,
            &o,
            grid,
            geardyn_solvers::ensemble::Dispatch::Auto,
            ESCAPE_LONE_COPIES,
        );
        let mut evals = 0;
        let pts = copies
            .iter_mut()
            .zip(res)
            .map(|(c, r)| {
                let r = r.ok()?;
                evals += r.rhs_evals;
                let (t, y) = r.final_state;
                *c = Copy {
                    t,
                    y,
                    memory: r.final_memory,
                };
                Some(r.strobe.iter().map(|p| p.y).collect())
            })
            .collect();
        (pts, evals)
    };
    Some(escape_test(
        start,
        test,
        opts.max_period,
        method.period_tol(),
        advance,
    ))
}

/// Copies below which the escape test's copies advance on one-lane engines (in parallel) rather
/// than share a lane load ([`crate::lanes_decide`]'s measurement: a 16-lane engine with 4 busy
/// lanes takes as long as 4 one-lane engines).
const ESCAPE_LONE_COPIES: usize = 4;

/// The single pair: follows on a one-lane engine with its phase tables (the integration of a
/// sweep's lanes, so a run decides alike alone and in a sweep) and exponents in the lanes.
impl Engine<2> for MeshModel {
    fn follow_method(&self, opts: &SimOptions) -> Option<Method> {
        follow_method(self, opts)
    }

    fn simulate_in_decision(
        &self,
        y0: [f64; 2],
        o: &SimOptions,
        requested: &SimOptions,
    ) -> Result<SimResult, SimError> {
        match crate::lanes::LaneSim::new(o) {
            Ok(lane) if o.method != requested.method && crate::lanes::lanes_cover_contact(self) => {
                crate::lanes::simulate_lane_grid(self, y0, &lane, requested.tau0)
            }
            _ => simulate(self, y0, o),
        }
    }

    fn escape(
        &self,
        opts: &SimOptions,
        test: &EscapeSettings,
        start: Copy<2>,
    ) -> Option<EscapeOutcome<2>> {
        escape_of(self, opts, test, start)
    }
    fn tle(
        &self,
        opts: &SimOptions,
        t: f64,
        y: [f64; 2],
        memory: f64,
        periods: u64,
    ) -> Option<(f64, f64)> {
        crate::lanes_tle::tles_of(&[(self, t, y, memory)], opts, periods)
            .pop()
            .flatten()
    }
}
