//! The dimensionless multi-state gear mesh model (docs/model.md §2–3) as a [`HybridSystem`].
//!
//! State `y = [x, x']`: dimensionless relative displacement on the line of action and its
//! velocity; time `tau`. Equation of motion
//! `x'' + h(phi, side)*F_m = F + xi*omega^2*cos(omega*tau)` with the mesh force `F_m` of the contact
//! state (drive side, separation, back side, or stuck at the back stop of the impact model).
//!
//! Everything that varies along the excitation period — stiffness, half backlash, friction factors —
//! is tabulated once into [`Segment`]s (one per zone piece, adjacent identical pieces merged), and
//! each segment border is a time breakpoint. The mode carries the segment index, so the zone is
//! never recomputed from a rounded time.
//!
//! The mesh force and its tangent terms are those of [`crate::mesh_kernel`], shared with the
//! lockstep lanes ([`crate::MeshLanes`]), so that both evaluate the same operations.
//!
//! **Hysteresis damping** of the dissipative contact laws is set per impact and ends with it (see
//! [`crate::contact_law`]): from the entry speed at a contact entry, cleared ([`EventKind::Settle`])
//! when the velocity turns back into the contact before the teeth separate, zero for an initial
//! state in contact and for a contact started by a backlash jump.
//!
//! **Invariants.** Every located contact event lies on its surface `x = +-D` to within
//! [`SURFACE_TOL`]` * max(D, 1)`, and with the back-side impact model the state never lies beyond
//! the stop (`x >= -D`). A run whose motion outgrows the time resolution of the integrator (the
//! teeth cross the backlash in less than a rounding step of `tau`) breaks the first one; the event
//! handler then sets the state to NaN, which the integrator reports as
//! [`geardyn_solvers::SolverError::NonFinite`] (divergent motion) instead of continuing through the
//! stop.

mod tabulate;
mod validate;

use crate::contact_law::ContactLaw;
use crate::error::ModelError;
use crate::impact::ImpactLaw;
use crate::mesh_kernel::{self as kernel, Contact};
use crate::params::ModelParams;
use crate::phase::cos_cycles;
use geardyn_solvers::{Direction, EventAction, Guards, HybridSystem, Variational};
use serde::Serialize;
use std::f64::consts::PI;

/// Meshing zone of a segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Zone {
    /// Double-tooth zone `[0, eps-1)` (or `[0, eps_b-1)` in the broken cycle).
    Double,
    /// Single-tooth zone `[eps-1, 1)`.
    Single,
    /// "Single-tooth zone II" `[eps_b-1, eps-1)` of the broken cycle.
    SingleII,
}

/// Contact state of the tooth pair (the discrete part of the mode).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactState {
    /// Drive-side contact, `x >= D`.
    Drive,
    /// Tooth separation, `-D < x < D`.
    Separated,
    /// Back-side contact (continuous model), `x <= -D`.
    Back,
    /// Resting on the back stop of the impact model (`x = -D`, `x' = 0`).
    Stuck,
}

impl ContactState {
    /// Integer code used in CSV output: drive 1, separated 0, back -1, stuck -2.
    pub fn code(self) -> i8 {
        match self {
            ContactState::Drive => 1,
            ContactState::Separated => 0,
            ContactState::Back => -1,
            ContactState::Stuck => -2,
        }
    }
}

/// Mode of the mesh model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshMode {
    /// Excitation-period index.
    pub period: i64,
    /// Segment index within the excitation period.
    pub seg: u32,
    /// Contact state.
    pub contact: ContactState,
    /// Hysteresis factor of a dissipative contact law for the current impact: set at a contact
    /// entry from its approach speed, 0 outside an impact (see [`crate::contact_law`]).
    pub chi: f64,
}

/// Kind of a located event, for observers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    /// Drive-side contact begins (`x` rises through `D`).
    DriveEnter,
    /// Drive-side contact ends (`x` falls through `D`).
    DriveExit,
    /// Back-side contact begins (`x` falls through `-D`).
    BackEnter,
    /// Back-side contact ends.
    BackExit,
    /// Back-side impact with restitution.
    Impact,
    /// Impact below the sticking speed: the tooth comes to rest on the back stop.
    Stick,
    /// The tooth leaves the back stop (the free acceleration changed sign).
    Release,
    /// The impact phase of a dissipative contact ends without separation: the velocity turned
    /// back into the contact, the hysteresis factor is cleared (persistent mesh, viscous damping).
    Settle,
}

/// Largest excitation-period index a mode represents (`2^62`, well inside `i64`).
const MAX_PERIOD_INDEX: f64 = 4_611_686_018_427_387_904.0;

/// Largest distance of a located contact event from its surface `x = +-D`, in units of
/// `max(D, 1)` (dimensionless). Event location is accurate to ~1e-12 in time; a larger distance
/// means the motion outgrew the integrator's time resolution, and the run is stopped.
pub const SURFACE_TOL: f64 = 1e-6;
/// Largest distance (times `max(D, 1)`) from a contact surface of a located event that is read
/// as a grazing approach when the state is on the free side moving away (see `on_event`).
const GRAZING_TOL: f64 = 1e-3;

#[derive(Clone, Copy, Debug, PartialEq)]
enum KForm {
    /// `k0 + kappa*cos(omega*tau)` (kappa global, 0 unless harmonic).
    Const(f64),
    /// Piecewise-linear table: indices into the model's table arrays.
    Table { off: u32, len: u32 },
    /// Uniform samples over the segment (O(1) lookup): offset into `uniform`.
    Uniform { off: u32 },
}

/// One piece of the excitation period with constant zone, backlash and friction factors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Start, in mesh cycles from the start of the excitation period.
    pub start: f64,
    /// End, in mesh cycles.
    pub end: f64,
    /// Zone.
    pub zone: Zone,
    /// Half backlash `D`.
    pub d: f64,
    /// Friction factor of the drive side.
    pub h_drive: f64,
    /// Friction factor of the back side.
    pub h_back: f64,
    k: KForm,
    /// Uniform tables of the friction factors (offsets into `uniform`), when they vary.
    h_tab: Option<(u32, u32)>,
    /// Samples per uniform table of this segment and their spacing inverse (1/cycles).
    n_uni: u32,
    inv_du: f64,
}

/// Smallest half backlash `D_d` (units of `b_c`): a thousand times the integrator's absolute
/// tolerance; the runs at 1e-13 and below ran away although every D from 1e-12 up gives the same
/// bounded orbit.
pub const MIN_BACKLASH: f64 = 1e-9;

/// The dimensionless mesh model. Build it with [`MeshModel::new`] from validated [`ModelParams`].
///
/// ```
/// use geardyn_model::{presets, MeshModel};
/// let m = MeshModel::new(&presets::classic()).unwrap();
/// assert_eq!(m.cycles_per_period(), 1);
/// assert!((m.stiffness_at(0.0) - 1.2).abs() < 1e-12); // 1 + 0.2*cos(0)
/// ```
#[derive(Clone, Debug)]
pub struct MeshModel {
    params: ModelParams,
    omega: f64,
    load: f64,
    xi_w2: f64,
    c: f64,
    kappa: f64,
    cycles: u32,
    cycle_time: f64,
    segs: Vec<Segment>,
    table_x: Vec<f64>,
    table_k: Vec<f64>,
    uniform: Vec<f64>,
    law: ContactLaw,
    unilateral: bool,
    impact: Option<ImpactLaw>,
    impact_peak_factor: f64,
    /// Quasi-static entry speed of the contact law (fade speed of the hysteresis factor).
    v_q: f64,
}

impl MeshModel {
    /// Validates the parameters and tabulates the excitation period.
    pub fn new(p: &ModelParams) -> Result<Self, ModelError> {
        let (omega, eps, impact, friction_on) = validate::scalars(p)?;
        let kappa = validate::stiffness(p)?;
        let cycles = validate::breakage(p, eps)?;

        let mut m = MeshModel {
            params: p.clone(),
            omega,
            load: p.load,
            xi_w2: p.xi * omega * omega,
            c: p.c,
            kappa,
            cycles,
            cycle_time: 2.0 * PI / omega,
            segs: Vec::new(),
            table_x: Vec::new(),
            table_k: Vec::new(),
            uniform: Vec::new(),
            law: p.contact,
            unilateral: p.unilateral,
            impact,
            impact_peak_factor: impact.map_or(1.0, |l| l.peak_factor()),
            v_q: p.contact.quasi_static_speed(p.load),
        };
        m.tabulate(eps, friction_on);
        validate::friction_factors(&m)?;
        Ok(m)
    }

    /// The parameters the model was built from.
    pub fn params(&self) -> &ModelParams {
        &self.params
    }
    /// Segments of the excitation period.
    pub fn segments(&self) -> &[Segment] {
        &self.segs
    }
    /// Mesh cycles per excitation period (1 healthy, `z_p` broken).
    pub fn cycles_per_period(&self) -> u32 {
        self.cycles
    }
    /// Mesh cycle duration `2*pi/omega` (dimensionless time).
    pub fn mesh_cycle_time(&self) -> f64 {
        self.cycle_time
    }
    /// Excitation period `T_s` (dimensionless time).
    pub fn excitation_period(&self) -> f64 {
        self.cycle_time * self.cycles as f64
    }
    /// The contact law.
    pub fn contact_law(&self) -> ContactLaw {
        self.law
    }
    /// The back-side impact law, if the back side is a rigid stop.
    pub fn impact_law(&self) -> Option<ImpactLaw> {
        self.impact
    }
    /// Smallest and largest half backlash over the period (`D_d`, `D_s` where present).
    pub fn backlash_levels(&self) -> (f64, f64) {
        (self.params.d_double, self.params.d_single)
    }

    /// Position of time `t` in the excitation period, in mesh cycles (`[0, cycles)`).
    pub fn cycle_position(&self, t: f64) -> f64 {
        let s = self.omega * t / (2.0 * PI);
        let c = self.cycles as f64;
        s - (s / c).floor() * c
    }

    /// Segment index containing the position `u` (mesh cycles into the excitation period).
    pub fn segment_index(&self, u: f64) -> usize {
        self.segs
            .partition_point(|s| s.end <= u)
            .min(self.segs.len() - 1)
    }

    /// Smallest friction factor in the uniform tables, if any is not positive.
    fn uniform_h_min(&self) -> Option<f64> {
        let mut worst = None;
        for s in &self.segs {
            if let Some((a, b)) = s.h_tab {
                let n = s.n_uni as usize;
                for &h in self.uniform[a as usize..a as usize + n]
                    .iter()
                    .chain(&self.uniform[b as usize..b as usize + n])
                {
                    if !(h > 0.0) {
                        worst = Some(h);
                    }
                }
            }
        }
        worst
    }

    /// Linear interpolation in a uniform table of `seg` starting at `off`, at position `u`.
    #[inline(always)]
    fn uniform_eval(&self, seg: &Segment, off: u32, u: f64) -> f64 {
        let x = ((u - seg.start) * seg.inv_du).max(0.0);
        let last = seg.n_uni as usize - 1;
        let i = (x as usize).min(last - 1);
        let f = (x - i as f64).min(1.0);
        let base = off as usize + i;
        let (a, b) = (self.uniform[base], self.uniform[base + 1]);
        a + (b - a) * f
    }

    /// Position in the excitation period (mesh cycles) of time `t` in `period`.
    #[inline(always)]
    fn position(&self, t: f64, period: i64) -> f64 {
        self.omega * t * (0.5 / PI) - self.period_start(period)
    }

    /// Start of excitation period `period`, in mesh cycles. Computed in `f64`: exact below 2^53
    /// cycles, and no integer product that could wrap beyond.
    #[inline(always)]
    fn period_start(&self, period: i64) -> f64 {
        period as f64 * self.cycles as f64
    }

    #[inline(always)]
    fn k_of(&self, seg: &Segment, t: f64, cos_wt: f64, period: i64) -> f64 {
        match seg.k {
            KForm::Const(k0) => k0 + self.kappa * cos_wt,
            KForm::Table { off, len } => {
                self.table_eval(off as usize, len as usize, self.position(t, period))
            }
            KForm::Uniform { off } => self.uniform_eval(seg, off, self.position(t, period)),
        }
    }

    /// Friction factors `(h_drive, h_back)` of `seg` at time `t`.
    #[inline(always)]
    fn h_of(&self, seg: &Segment, t: f64, period: i64) -> (f64, f64) {
        match seg.h_tab {
            None => (seg.h_drive, seg.h_back),
            Some((a, b)) => {
                let u = self.position(t, period);
                (self.uniform_eval(seg, a, u), self.uniform_eval(seg, b, u))
            }
        }
    }

    /// Friction factors `(h_drive, h_back)` at position `u` (mesh cycles) of the excitation
    /// period, for tables and plots.
    pub fn friction_factors_at(&self, u: f64) -> (f64, f64) {
        let seg = &self.segs[self.segment_index(u)];
        match seg.h_tab {
            None => (seg.h_drive, seg.h_back),
            Some((a, b)) => (self.uniform_eval(seg, a, u), self.uniform_eval(seg, b, u)),
        }
    }

    /// Half backlash at position `u` (mesh cycles) of the excitation period.
    pub fn backlash_at(&self, u: f64) -> f64 {
        self.segs[self.segment_index(u)].d
    }

    #[inline]
    fn table_eval(&self, off: usize, len: usize, u: f64) -> f64 {
        let xs = &self.table_x[off..off + len];
        let ks = &self.table_k[off..off + len];
        let j = xs.partition_point(|&x| x <= u).clamp(1, len - 1);
        let (x0, x1) = (xs[j - 1], xs[j]);
        ks[j - 1] + (ks[j] - ks[j - 1]) * (u - x0) / (x1 - x0)
    }

    /// Samples held by the uniform tables of a zoned stiffness (stiffness and both friction
    /// factors; pieces with equal samples are held once), 0 for the other forms.
    pub fn table_samples(&self) -> usize {
        self.uniform.len()
    }

    /// Stiffness at position `u` in mesh cycles from the start of the excitation period
    /// (`u` in `[0, cycles)`), for tables and plots.
    pub fn stiffness_at(&self, u: f64) -> f64 {
        let seg = &self.segs[self.segment_index(u)];
        match seg.k {
            KForm::Const(k0) => k0 + self.kappa * cos_cycles(u),
            KForm::Table { off, len } => self.table_eval(off as usize, len as usize, u),
            KForm::Uniform { off } => self.uniform_eval(seg, off, u),
        }
    }

    /// Largest mesh stiffness over the excitation period (dimensionless, units of the mean
    /// stiffness), sampled 64 times per segment and at both ends of each: the stiffest contact
    /// state sets the shortest natural period `2 pi / sqrt(k)` a trajectory must resolve.
    pub fn peak_stiffness(&self) -> f64 {
        let mut k = f64::NEG_INFINITY;
        for s in &self.segs {
            let w = s.end - s.start;
            for i in 0..=64 {
                // (the end itself belongs to the next segment)
                let u = s.start + w * (i as f64 / 64.0) * (1.0 - 1e-12);
                k = k.max(self.stiffness_at(u));
            }
        }
        k
    }

    /// Right-hand side of the excitation, `F + xi*omega^2*cos(omega*tau)` (the acceleration of a
    /// separated tooth pair).
    #[inline]
    pub fn excitation(&self, t: f64) -> f64 {
        kernel::excitation(
            self.load,
            self.xi_w2,
            cos_cycles(self.omega * t / (2.0 * PI)),
        )
    }

    /// Dynamic mesh force `F_m` in the given mode (0 when separated or stuck).
    pub fn mesh_force(&self, t: f64, y: &[f64; 2], mode: &MeshMode) -> f64 {
        if matches!(mode.contact, ContactState::Separated | ContactState::Stuck) {
            return 0.0;
        }
        let seg = &self.segs[mode.seg as usize];
        let cos_wt = cos_cycles(self.omega * t / (2.0 * PI));
        self.force_in(seg, t, cos_wt, y, mode)
    }

    /// The flank of `mode` in contact in `seg` at time `t` (its stiffness, signed backlash,
    /// hysteresis and clamp, see [`crate::mesh_kernel`]); `None` when separated or stuck.
    #[inline(always)]
    fn contact(
        &self,
        seg: &Segment,
        t: f64,
        cos_wt: f64,
        mode: &MeshMode,
    ) -> Option<Contact<ContactLaw>> {
        let (s, lo, hi) = match mode.contact {
            ContactState::Drive => (1.0, 0.0, f64::INFINITY),
            ContactState::Back => (-1.0, f64::NEG_INFINITY, 0.0),
            ContactState::Separated | ContactState::Stuck => return None,
        };
        Some(Contact {
            law: self.law,
            k: self.k_of(seg, t, cos_wt, mode.period),
            off: s * seg.d,
            schi: s * mode.chi,
            c: self.c,
            lo,
            hi,
        })
    }

    #[inline(always)]
    fn force_in(&self, seg: &Segment, t: f64, cos_wt: f64, y: &[f64; 2], mode: &MeshMode) -> f64 {
        self.contact(seg, t, cos_wt, mode)
            .map_or(0.0, |ct| ct.force(y[0], y[1], self.unilateral))
    }

    /// Peak back-side impact force for an impact at speed `v` (see [`crate::impact`]); finite
    /// for any finite `v`.
    pub fn impact_peak_force(&self, v: f64) -> f64 {
        self.impact.map_or(0.0, |l| {
            (l.hertz_peak(v.abs()) * self.impact_peak_factor).min(f64::MAX)
        })
    }

    /// Quasi-static entry speed `v_q` of the contact law at this load (see [`crate::contact_law`]).
    pub fn quasi_static_speed(&self) -> f64 {
        self.v_q
    }

    /// What the event of guard `index`, located in mode `before`, was.
    pub fn event_kind(&self, before: &MeshMode, after: &MeshMode, index: usize) -> EventKind {
        match (before.contact, index) {
            (ContactState::Separated, 0) => EventKind::DriveEnter,
            (ContactState::Separated, _) => match (self.impact, after.contact) {
                (None, _) => EventKind::BackEnter,
                (Some(_), ContactState::Stuck) => EventKind::Stick,
                (Some(_), _) => EventKind::Impact,
            },
            (ContactState::Drive | ContactState::Back, 1) => EventKind::Settle,
            (ContactState::Drive, _) => EventKind::DriveExit,
            (ContactState::Back, _) => EventKind::BackExit,
            (ContactState::Stuck, _) => EventKind::Release,
        }
    }

    fn contact_of(&self, y: &[f64; 2], d: f64) -> ContactState {
        let (x, v) = (y[0], y[1]);
        if x > d || (x == d && v > 0.0) {
            ContactState::Drive
        } else if self.impact.is_none() && (x < -d || (x == -d && v < 0.0)) {
            ContactState::Back
        } else {
            ContactState::Separated
        }
    }

    /// Whether an impact at speed `v` (before the reset) ends with the tooth resting on the stop:
    /// the free motion presses it there and the impact speed or the rebound speed `R |v|` is
    /// below `v_stick`. The rebound counts so that a plastic impact (`R = 0`) under a pressing
    /// load rests instead of leaving the stop at zero speed straight back into it, a crossing
    /// no event can see (the run then went through the stop and ended non-finite).
    fn sticks(&self, t: f64, v: f64, law: ImpactLaw) -> bool {
        self.excitation(t) <= 0.0
            && (v.abs() < law.v_stick || law.restitution * v.abs() <= law.v_stick)
    }

    /// A located event of a separated state that is no crossing: the state is still on the free
    /// side of the surface, within [`GRAZING_TOL`] of it, and moving away (a grazing approach
    /// the event search took for a crossing). Nothing happens there: no reset, no saltation.
    fn grazing_miss(&self, y: &[f64; 2], mode: &MeshMode, index: usize) -> bool {
        let d = self.segs[mode.seg as usize].d;
        let near = GRAZING_TOL * d.max(1.0);
        match (mode.contact, index) {
            (ContactState::Separated, 0) => {
                let g = y[0] - d;
                g < 0.0 && g > -near && y[1] <= 0.0
            }
            (ContactState::Separated, _) => {
                let g = y[0] + d;
                g > 0.0 && g < near && y[1] >= 0.0
            }
            _ => false,
        }
    }

    /// Projects a state onto the admissible set of the impact model (`x >= -D`), applying the
    /// impact law to a state inside the stop that moves into it. Returns the contact state.
    fn project_to_stop(
        &self,
        t: f64,
        y: &mut [f64; 2],
        d: f64,
        law: ImpactLaw,
    ) -> Option<ContactState> {
        if y[0] > -d {
            return None;
        }
        y[0] = -d;
        if y[1] < 0.0 {
            y[1] *= -law.restitution;
        }
        if y[1].abs() <= law.v_stick && self.excitation(t) <= 0.0 {
            y[1] = 0.0;
            return Some(ContactState::Stuck);
        }
        Some(ContactState::Separated)
    }
}

impl HybridSystem<2> for MeshModel {
    type Mode = MeshMode;
    type TimeTerms = f64;

    /// Under the impact law a state behind the rigid back stop (`x < -D` of the zone at `t`) is
    /// not a state of the model: a start there would be projected onto the stop.
    fn admissible(&self, t: f64, y: &[f64; 2]) -> bool {
        if self.impact.is_none() {
            return true;
        }
        let s = self.omega * t / (2.0 * PI);
        let pf = (s / self.cycles as f64).floor();
        let seg = self.segment_index(s - self.period_start(pf as i64));
        !(y[0] < -self.segs[seg].d)
    }

    fn initial_mode(&self, t: f64, y: &mut [f64; 2]) -> MeshMode {
        let s = self.omega * t / (2.0 * PI);
        // the period start is computed in f64 (no wrapping product); a time whose period index
        // does not fit the mode (beyond 2^62 periods, far past the resolution of tau) is an error
        // state, reported by the integrator as a non-finite state
        let pf = (s / self.cycles as f64).floor();
        let period = pf as i64;
        let u = s - self.period_start(period);
        let seg = self.segment_index(u);
        let d = self.segs[seg].d;
        let contact = match self.impact {
            Some(law) => self
                .project_to_stop(t, y, d, law)
                .unwrap_or_else(|| self.contact_of(y, d)),
            None => self.contact_of(y, d),
        };
        if !(pf.abs() < MAX_PERIOD_INDEX) {
            *y = [f64::NAN; 2];
        }
        // an initial state in contact is not an impact: no hysteresis (no memory of the start)
        MeshMode {
            period,
            seg: seg as u32,
            contact,
            chi: 0.0,
        }
    }

    #[inline(always)]
    fn time_terms(&self, t: f64) -> f64 {
        cos_cycles(self.omega * t * (0.5 / PI))
    }

    #[inline(always)]
    fn rhs(&self, t: f64, cos_wt: &f64, y: &[f64; 2], mode: &MeshMode, dy: &mut [f64; 2]) {
        let seg = &self.segs[mode.seg as usize];
        let exc = kernel::excitation(self.load, self.xi_w2, *cos_wt);
        // one match on the contact state (force_in would match again)
        let acc = match mode.contact {
            ContactState::Drive => {
                let h = self.h_of(seg, t, mode.period).0;
                kernel::acceleration(exc, h, self.force_in(seg, t, *cos_wt, y, mode))
            }
            ContactState::Back => {
                let h = self.h_of(seg, t, mode.period).1;
                kernel::acceleration(exc, h, self.force_in(seg, t, *cos_wt, y, mode))
            }
            ContactState::Separated => exc,
            ContactState::Stuck => {
                *dy = [0.0, 0.0];
                return;
            }
        };
        *dy = [y[1], acc];
    }

    #[inline(always)]
    fn guards(&self, t: f64, y: &[f64; 2], mode: &MeshMode, g: &mut Guards) {
        let d = self.segs[mode.seg as usize].d;
        match mode.contact {
            ContactState::Separated => {
                g.push(y[0] - d, Direction::Rising);
                g.push(y[0] + d, Direction::Falling);
            }
            ContactState::Drive => {
                g.push(y[0] - d, Direction::Falling);
                if mode.chi != 0.0 {
                    // end of the impact: the velocity turns back into the contact
                    g.push(y[1], Direction::Rising);
                }
            }
            ContactState::Back => {
                g.push(y[0] + d, Direction::Rising);
                if mode.chi != 0.0 {
                    g.push(y[1], Direction::Falling);
                }
            }
            ContactState::Stuck => g.push(self.excitation(t), Direction::Rising),
        }
    }

    fn on_event(&self, t: f64, y: &mut [f64; 2], mode: &mut MeshMode, index: usize) -> EventAction {
        let d = self.segs[mode.seg as usize].d;
        // invariant: a contact event lies on its surface (else the run lost its time resolution
        // and may have jumped through the backlash or the stop): stop with an error state
        let surface = match (mode.contact, index) {
            (ContactState::Separated, 0) | (ContactState::Drive, 0) => Some(y[0] - d),
            (ContactState::Separated, _) | (ContactState::Back, 0) => Some(y[0] + d),
            _ => None,
        };
        if let Some(g) = surface {
            // a grazing approach the event search took for a crossing (the guard dipped to
            // within a few 1e-6 of the surface at a step end and turned back): the state is still
            // on the free side and moving away from the surface, so nothing happened
            if self.grazing_miss(y, mode, index) {
                return EventAction::Continue;
            }
            if !(g.abs() <= SURFACE_TOL * d.max(1.0)) {
                *y = [f64::NAN; 2];
                return EventAction::Terminate;
            }
        }
        match (mode.contact, index) {
            (ContactState::Separated, 0) => {
                mode.contact = ContactState::Drive;
                mode.chi = self.law.entry_hysteresis(y[1], self.v_q);
            }
            (ContactState::Separated, _) => match self.impact {
                None => {
                    mode.contact = ContactState::Back;
                    mode.chi = self.law.entry_hysteresis(y[1], self.v_q);
                }
                Some(law) => {
                    // the impact path: onto the stop, moving away from it (or resting on it)
                    y[0] = -d;
                    if self.sticks(t, y[1], law) {
                        y[1] = 0.0;
                        mode.contact = ContactState::Stuck;
                    } else if y[1] < 0.0 {
                        y[1] *= -law.restitution;
                    }
                }
            },
            (ContactState::Stuck, _) => {
                y[1] = 0.0;
                mode.contact = ContactState::Separated;
            }
            (ContactState::Drive, 1) | (ContactState::Back, 1) => {
                // the impact is over; the contact persists with viscous damping only
                mode.chi = 0.0;
            }
            (ContactState::Drive, _) | (ContactState::Back, _) => {
                mode.contact = ContactState::Separated;
                mode.chi = 0.0;
            }
        }
        EventAction::Continue
    }

    /// An accumulation of back-side impacts (restitution near 0, sticking speed 0) ends on the
    /// stop: the tooth rests there, as the sticking rule would put it, when the free
    /// acceleration presses it onto the stop; otherwise the accumulation is a solver error.
    fn zeno_fallback(&self, t: f64, y: &mut [f64; 2], mode: &mut MeshMode, _index: usize) -> bool {
        if self.impact.is_some()
            && mode.contact == ContactState::Separated
            && self.excitation(t) <= 0.0
        {
            *y = [-self.segs[mode.seg as usize].d, 0.0];
            mode.contact = ContactState::Stuck;
            mode.chi = 0.0;
            true
        } else {
            false
        }
    }

    #[inline]
    fn next_breakpoint(&self, _t: f64, mode: &MeshMode) -> f64 {
        if self.segs.len() == 1 {
            return f64::INFINITY;
        }
        let end = self.segs[mode.seg as usize].end;
        (self.period_start(mode.period) + end) * self.cycle_time
    }

    fn on_breakpoint(&self, t: f64, y: &mut [f64; 2], mode: &mut MeshMode) {
        let d_old = self.segs[mode.seg as usize].d;
        mode.seg += 1;
        if mode.seg as usize == self.segs.len() {
            mode.seg = 0;
            mode.period = mode.period.saturating_add(1);
        }
        let d = self.segs[mode.seg as usize].d;
        let before = mode.contact;
        // invariant of the impact model: never beyond the stop (it was at -d_old until now)
        if self.impact.is_some()
            && before != ContactState::Stuck
            && !(y[0] >= -d_old - SURFACE_TOL * d_old.max(1.0))
        {
            *y = [f64::NAN; 2];
            return;
        }
        let contact = match self.impact {
            // The stop moves with the backlash: if it recedes the tooth is free; if it advances
            // the tooth is carried with it (projection, with the impact law if moving into it).
            Some(_) if before == ContactState::Stuck => {
                if d > d_old {
                    ContactState::Separated
                } else {
                    y[0] = -d;
                    ContactState::Stuck
                }
            }
            Some(law) => self
                .project_to_stop(t, y, d, law)
                .unwrap_or_else(|| self.contact_of(y, d)),
            None => self.contact_of(y, d),
        };
        if contact != before {
            // a contact started (or ended) by a backlash jump is not an impact
            mode.chi = 0.0;
        }
        mode.contact = contact;
    }

    fn max_step(&self) -> f64 {
        self.cycle_time / 16.0
    }

    /// The hysteresis factor `chi` of the current impact.
    fn memory(&self, mode: &MeshMode) -> f64 {
        mode.chi
    }

    /// `chi = p` in contact; outside contact there is no impact and `chi` stays 0.
    fn with_memory(&self, mode: &MeshMode, p: f64) -> MeshMode {
        let chi = match mode.contact {
            ContactState::Drive | ContactState::Back => p,
            ContactState::Separated | ContactState::Stuck => 0.0,
        };
        MeshMode { chi, ..*mode }
    }

    /// An impact in progress is a matter of the contact state alone: two states in the same
    /// contact are in the same impact whatever segment their clocks put them in (a run restarted
    /// at a period boundary may start in the last segment of the period before, another one
    /// advanced to the first segment of the next).
    fn same_regime(&self, a: &MeshMode, b: &MeshMode) -> bool {
        a.contact == b.contact
    }

    /// Contact guards are `x -+ D` with `D` constant within a segment, the end-of-impact guard is
    /// `x'` (unit Lipschitz constant); the release guard of a tooth resting on the stop depends on
    /// time.
    #[inline(always)]
    fn guard_lipschitz(&self, mode: &MeshMode) -> Option<f64> {
        match mode.contact {
            ContactState::Stuck => None,
            _ => Some(1.0),
        }
    }
}

impl Variational<2> for MeshModel {
    fn jacobian(
        &self,
        t: f64,
        cos_wt: &f64,
        y: &[f64; 2],
        mode: &MeshMode,
        jac: &mut [[f64; 2]; 2],
    ) {
        let seg = &self.segs[mode.seg as usize];
        let h = match mode.contact {
            ContactState::Drive => self.h_of(seg, t, mode.period).0,
            ContactState::Back => self.h_of(seg, t, mode.period).1,
            ContactState::Separated => 0.0,
            ContactState::Stuck => {
                *jac = [[0.0; 2]; 2];
                return;
            }
        };
        // (a clamped unilateral force does not depend on the state: the kernel gives (0, 0))
        let (dax, dav) = self
            .contact(seg, t, *cos_wt, mode)
            .map_or((0.0, 0.0), |ct| ct.tangent(h, y[0], y[1], self.unilateral));
        *jac = [[0.0, 1.0], [dax, dav]];
    }

    fn guard_gradient(
        &self,
        t: f64,
        _y: &[f64; 2],
        mode: &MeshMode,
        index: usize,
    ) -> ([f64; 2], f64) {
        match (mode.contact, index) {
            // g = xi w^2 cos(w t) + F: only time-dependent
            (ContactState::Stuck, _) => {
                let w = self.omega;
                ([0.0, 0.0], -self.xi_w2 * w * (w * t).sin())
            }
            // end of an impact: g = x'
            (ContactState::Drive | ContactState::Back, 1) => ([0.0, 1.0], 0.0),
            // g = x -+ D with D constant within a segment
            _ => ([1.0, 0.0], 0.0),
        }
    }

    fn reset_jacobian(&self, t: f64, y: &[f64; 2], mode: &MeshMode, index: usize) -> [[f64; 2]; 2] {
        if self.grazing_miss(y, mode, index) {
            return [[1.0, 0.0], [0.0, 1.0]];
        }
        match (mode.contact, index, self.impact) {
            (ContactState::Separated, 1, Some(law)) => {
                if self.sticks(t, y[1], law) {
                    // sticking: the velocity is annihilated
                    [[1.0, 0.0], [0.0, 0.0]]
                } else {
                    [[1.0, 0.0], [0.0, -law.restitution]]
                }
            }
            _ => [[1.0, 0.0], [0.0, 1.0]],
        }
    }

    /// The hysteresis factor `chi` is the mode's memory: `d x''/d chi = -h k g(delta) x'` in
    /// contact (either flank), 0 elsewhere and where a unilateral force is clamped.
    fn memory_slope(&self, t: f64, cos_wt: &f64, y: &[f64; 2], mode: &MeshMode) -> [f64; 2] {
        if mode.chi == 0.0 {
            return [0.0, 0.0];
        }
        let seg = &self.segs[mode.seg as usize];
        let (delta, h) = match mode.contact {
            ContactState::Drive => (y[0] - seg.d, self.h_of(seg, t, mode.period).0),
            ContactState::Back => (-y[0] - seg.d, self.h_of(seg, t, mode.period).1),
            ContactState::Separated | ContactState::Stuck => return [0.0, 0.0],
        };
        if self.unilateral && self.force_in(seg, t, *cos_wt, y, mode) == 0.0 {
            return [0.0, 0.0];
        }
        let k = self.k_of(seg, t, *cos_wt, mode.period);
        [0.0, -h * k * self.law.elastic(delta) * y[1]]
    }

    /// `chi` is set at an entry through the contact surface from the entry speed
    /// ([`ContactLaw::entry_hysteresis`]), cleared at the end of an impact, an exit and a contact
    /// change at a zone border, and kept otherwise.
    fn memory_reset(
        &self,
        _t: f64,
        y: &[f64; 2],
        before: &MeshMode,
        after: &MeshMode,
        index: Option<usize>,
    ) -> ([f64; 2], f64) {
        if after.chi == 0.0 {
            return ([0.0, 0.0], 0.0);
        }
        let entry = index.is_some()
            && before.contact == ContactState::Separated
            && matches!(after.contact, ContactState::Drive | ContactState::Back);
        if entry {
            ([0.0, self.law.entry_hysteresis_slope(y[1], self.v_q)], 0.0)
        } else {
            ([0.0, 0.0], 1.0)
        }
    }
}

/// The single spur pair as a gear system: one mesh whose relative displacement is the state's
/// `x` itself.
impl crate::system::GearSystem<2> for MeshModel {
    fn excitation_period(&self) -> f64 {
        MeshModel::excitation_period(self)
    }
    fn cycles_per_period(&self) -> u32 {
        MeshModel::cycles_per_period(self)
    }
    fn mesh_cycle_time(&self) -> f64 {
        MeshModel::mesh_cycle_time(self)
    }
    fn cycle_position(&self, t: f64) -> f64 {
        MeshModel::cycle_position(self, t)
    }
    /// `2 pi / sqrt(k_peak)` of the stiffest mesh state ([`MeshModel::peak_stiffness`], at
    /// least 1).
    fn natural_period(&self) -> f64 {
        2.0 * PI / self.peak_stiffness().max(1.0).sqrt()
    }
    #[inline(always)]
    fn mesh_state(&self, _t: f64, y: &[f64; 2], _k: usize) -> [f64; 2] {
        *y
    }
    #[inline(always)]
    fn mesh_force(&self, t: f64, y: &[f64; 2], mode: &MeshMode, _k: usize) -> f64 {
        MeshModel::mesh_force(self, t, y, mode)
    }
    #[inline(always)]
    fn contact(&self, mode: &MeshMode, _k: usize) -> ContactState {
        mode.contact
    }
    fn backlash_levels(&self, _k: usize) -> (f64, f64) {
        MeshModel::backlash_levels(self)
    }
    fn event(&self, before: &MeshMode, after: &MeshMode, index: usize) -> (usize, EventKind) {
        (0, self.event_kind(before, after, index))
    }
    fn impact_peak_force(&self, _k: usize, v: f64) -> f64 {
        MeshModel::impact_peak_force(self, v)
    }
    /// The segment of the excitation period ([`MeshMode::seg`]).
    #[inline(always)]
    fn segment(&self, mode: &MeshMode) -> u32 {
        mode.seg
    }
}
