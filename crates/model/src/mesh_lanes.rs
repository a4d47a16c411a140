//! The batched counterpart of [`MeshModel`] for the lockstep ensemble
//! ([`geardyn_solvers::ensemble`]): phase tables of every periodic coefficient and the field of
//! `L` lanes at a step phase.
//!
//! With `n` RK4 steps per mesh cycle the grid visits the same positions of the excitation period
//! (`u0 + j/n` mesh cycles, `j < n * cycles`) in every period, so the excitation cosine, the
//! stiffness (per zone and breakage cycle), the friction factors and the half backlash are
//! tabulated once at the start, middle and end of every step ([`MeshLanes::new`]). Nothing in a
//! table depends on `omega`, `F`, `xi` or `c`: lanes of a sweep over those share one table and
//! carry their own constants ([`MeshLane`]: the excitation amplitude `xi omega^2`, the load, the
//! damping, and the contact state). A table depends on the stiffness form, zones, backlash,
//! friction, steps per cycle and the start position `u0` of the grid; two models with equal
//! tables may share lanes (`MeshLanes` compares equal).
//!
//! Covered in lockstep: the separated state of every model, and drive/back contact of the linear
//! contact law (`g(delta) = delta`) without hysteresis (`chi = 0`), unilateral or not. A tooth
//! resting on the back stop, a dissipative impact in progress and the nonlinear contact laws are
//! stepped by the scalar integrator (the engine hands such lanes over), as is every step that may
//! hold a segment border (a time breakpoint) — those steps are flagged in the table.
//!
//! Two arithmetics:
//! * **Affine map** (the default where it applies: linear contact law, bilateral force, equal
//!   friction factors on both flanks — no friction, as in case C1 —, at most
//!   `AFFINE_MAX_STEPS` steps per period). Inside one contact state the equation is linear and
//!   periodically forced, so one RK4 step is an affine map `y1 = P y0 + q` fixed by the step
//!   phase and the state: `P` and the forcing responses are tabulated per lane when the lane's
//!   constants change ([`AffineTables`], built from the RK4 stages at the exact grid phases) and a
//!   step becomes a 2 x 2 multiply-add (separated lanes take the closed form of the RK4 step of
//!   `x'' = F + xi omega^2 cos`). The same RK4 step in exact arithmetic, rounded differently:
//!   equal to the stage-by-stage step to ~1e-15 relative (test `mesh_lanes_affine`), and periodic
//!   orbits equal to the scalar RK4 path to its own rounding floor (~1e-12), while chaotic runs
//!   diverge from it as any two roundings of a chaotic orbit do. About three times fewer
//!   operations per lane-step than the stages.
//! * **RK4 stages** (every other model, and any table after [`MeshLanes::exact`]): each lane
//!   evaluates the expressions of [`MeshModel`]'s `rhs` and `mesh_force`
//!   (`exc - h*(k*(x -+ D) + c*x')`) by calling the same functions ([`crate::mesh_kernel`], with
//!   its linear law), with the coefficients taken from the tables. The scalar
//!   model evaluates the excitation (and a harmonic stiffness) at the *rounded* time `t0 + k*h`,
//!   whose phase differs from the exact grid phase by up to ~ulp(t) — at `t ~ 10^4` about 1e-12,
//!   which a lightly damped gear pair amplifies. The lanes therefore correct the tabulated cosine
//!   to first order by that difference (a table of its derivative), computed exactly from the
//!   lane's time as the scalar model computes its phase; they then follow the scalar path to
//!   rounding, not to ulp(t) (to the bit in the tests). Piecewise-linear stiffness and friction
//!   tables are taken at the exact phase (their rounded-time difference is below 1e-13
//!   relative).
//!
//! Events are decided the same way by both: the interior bound of the Hermite interpolant of the
//! step and, near a surface, the scalar integrator's own midpoint test; a step that may hold an
//! event is taken by the scalar integrator.
//!
//! The RK4-stage step ([`Lockstep::step`] here) is the pair's [`LaneKernel`]
//! ([`Stages`]: its field over lanes from the tables' row of the step, read once per step)
//! driven by the generic lane step [`geardyn_solvers::ensemble::rk4_lanes`], which holds the
//! RK4 stage arithmetic of every lane model and runs the stages over chunks of lanes so that
//! their dependent chains overlap. Every lane evaluates the expressions of [`MeshModel`] in the
//! same order (no fused multiply-add), so the result of a lane does not depend on the layout nor
//! on the CPU copy of the engine. Units: dimensionless time `tau`, phases in mesh cycles.
//!
//! Files: the tables and the [`Lockstep`] implementation here; the stage kernel and the verdict
//! on a step in `stages`; the affine map in `affine`.

// lane loops over several arrays read clearer (and vectorise as intended) with an index
#![allow(clippy::needless_range_loop)]

use crate::mesh_kernel::{self as kernel, Contact, Linear};
use crate::mesh_model::{ContactState, MeshMode, MeshModel};
use crate::params::StiffnessForm;
use crate::phase::cos_cycles;
#[cfg(doc)]
use geardyn_solvers::ensemble::{rk4_lanes, LaneKernel};
use geardyn_solvers::ensemble::{At, Lockstep, Soa, Stage, StepStart};
use std::f64::consts::PI;

mod affine;
mod stages;

pub use affine::AffineTables;
use affine::AFFINE_MAX_STEPS;
pub use stages::{Stages, StepCoef};

/// Round to nearest by the `1.5 * 2^52` trick (vectorises on any target; `|x| < 2^51`).
#[inline(always)]
fn round_near(x: f64) -> f64 {
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    (x + MAGIC) - MAGIC
}

/// Phase tables of a mesh model for a grid of `n` steps per mesh cycle starting at `u0`.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshLanes {
    n: u32,
    cycles: u32,
    u0: f64,
    steps: usize,
    inv_n: f64,
    /// One row per step: everything a step reads, contiguous (one bounds check, one cache line
    /// pair per step).
    rows: Vec<Row>,
    linear: bool,
    unilateral: bool,
    /// Some stiffness derivative is nonzero (harmonic stiffness): the stiffness takes the
    /// first-order time correction; otherwise `k + 0 * delta == k` and the kernel skips it.
    harmonic: bool,
    /// Steps are taken by the affine map of each lane's tables ([`AffineTables`]) instead of
    /// the RK4 stages (see the module doc).
    affine: bool,
}

/// The phase-table row of one grid step: per stage (start, middle, end) the excitation cosine
/// and its derivative by the phase (in cycles), the stiffness and its derivative by the phase,
/// the friction factors; the half backlash of the step and whether it may hold a time breakpoint.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Row {
    cos: [f64; 3],
    dcos: [f64; 3],
    k: [f64; 3],
    dk: [f64; 3],
    hd: [f64; 3],
    hb: [f64; 3],
    d: f64,
    /// Cosine sums of the RK4 step of free flight: `cos0 + 2 cos_mid`, `cos0 + 4 cos_mid + cos_end`.
    sep: [f64; 2],
    scalar: bool,
}

/// Constants of one lane: contact selectors and the lane model's own amplitudes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshLane {
    /// 1 in drive contact, else 0.
    pub sd: f64,
    /// 1 in back contact, else 0.
    pub sb: f64,
    /// Static load `F`.
    pub load: f64,
    /// Excitation amplitude `xi omega^2`.
    pub xiw2: f64,
    /// Mesh damping `c`.
    pub c: f64,
    /// Mesh frequency `omega` (the lane's phase is `omega t / 2 pi`).
    pub w: f64,
    /// Clamp of the mesh force (`0` / `-inf` for a unilateral drive contact).
    pub lo: f64,
    /// Clamp of the mesh force (`0` / `+inf` for a unilateral back contact).
    pub hi: f64,
}

impl MeshLane {
    const IDLE: MeshLane = MeshLane {
        sd: 0.0,
        sb: 0.0,
        load: 0.0,
        xiw2: 0.0,
        c: 0.0,
        w: 0.0,
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };
}

/// The constants of `L` lanes as a structure of arrays (see [`MeshLane`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshLaneBlock<const L: usize> {
    /// 1 in drive contact, else 0.
    pub sd: [f64; L],
    /// 1 in back contact, else 0.
    pub sb: [f64; L],
    /// Static load `F`.
    pub load: [f64; L],
    /// Excitation amplitude `xi omega^2`.
    pub xiw2: [f64; L],
    /// Mesh damping `c`.
    pub c: [f64; L],
    /// Mesh frequency `omega`.
    pub w: [f64; L],
    /// Lower clamp of the mesh force.
    pub lo: [f64; L],
    /// Upper clamp of the mesh force.
    pub hi: [f64; L],
}

impl<const L: usize> MeshLaneBlock<L> {
    /// Sets lane `l`.
    pub fn set(&mut self, l: usize, ln: &MeshLane) {
        self.sd[l] = ln.sd;
        self.sb[l] = ln.sb;
        self.load[l] = ln.load;
        self.xiw2[l] = ln.xiw2;
        self.c[l] = ln.c;
        self.w[l] = ln.w;
        self.lo[l] = ln.lo;
        self.hi[l] = ln.hi;
    }
}

/// A lane's flank for the mesh kernel: the linear law without hysteresis, stiffness `k`, signed
/// half backlash `off = (s_d - s_b) D` (0 when separated), damping `c` and the clamp `[lo, hi]`
/// of a unilateral force.
#[inline(always)]
fn lane_contact(k: f64, off: f64, c: f64, lo: f64, hi: f64) -> Contact<Linear> {
    Contact {
        law: Linear,
        k,
        off,
        schi: 0.0,
        c,
        lo,
        hi,
    }
}

impl MeshLanes {
    /// Tables of `model` for `steps_per_cycle` RK4 steps per mesh cycle, the grid starting at
    /// `tau0`.
    pub fn new(model: &MeshModel, steps_per_cycle: u32, tau0: f64) -> Self {
        let n = steps_per_cycle.max(1);
        let cycles = model.cycles_per_period();
        let steps = n as usize * cycles as usize;
        let u0 = model.cycle_position(tau0);
        let cyc = cycles as f64;
        let pos = |m: usize| {
            // position of half-step m, wrapped into [0, cycles)
            let u = u0 + m as f64 / (2.0 * n as f64);
            if u >= cyc {
                u - cyc
            } else {
                u
            }
        };
        let kappa = match model.params().stiffness {
            StiffnessForm::Harmonic { kappa } => kappa,
            _ => 0.0,
        };
        let mut rows = Vec::with_capacity(steps);
        for j in 0..steps {
            let mut r = Row {
                cos: [0.0; 3],
                dcos: [0.0; 3],
                k: [0.0; 3],
                dk: [0.0; 3],
                hd: [0.0; 3],
                hb: [0.0; 3],
                d: model.backlash_at(pos(2 * j + 1)),
                sep: [0.0; 2],
                scalar: false,
            };
            for s in 0..3 {
                let u = pos(2 * j + s);
                r.cos[s] = cos_cycles(u);
                // d cos(2 pi u) / du = -2 pi sin(2 pi u)
                let dc = -2.0 * PI * cos_cycles(u - 0.25);
                r.dcos[s] = dc;
                r.k[s] = model.stiffness_at(u);
                r.dk[s] = kappa * dc;
                (r.hd[s], r.hb[s]) = model.friction_factors_at(u);
            }
            r.sep = [
                r.cos[0] + 2.0 * r.cos[1],
                r.cos[0] + 4.0 * r.cos[1] + r.cos[2],
            ];
            rows.push(r);
        }
        // steps that may hold a segment border: (u_j - delta, u_{j+1} + delta], any wrap
        let segs = model.segments();
        if segs.len() > 1 {
            let nf = n as f64;
            let delta = 1e-3 / nf;
            for s in segs {
                for shift in [-cyc, 0.0, cyc] {
                    let e = s.end + shift;
                    let jc = ((e - u0) * nf).floor();
                    for dj in -2..=1 {
                        let j = jc + dj as f64;
                        if j < 0.0 || j >= steps as f64 {
                            continue;
                        }
                        let a = u0 + j / nf;
                        let b = u0 + (j + 1.0) / nf;
                        if e > a - delta && e <= b + delta {
                            rows[j as usize].scalar = true;
                        }
                    }
                }
            }
        }
        let harmonic = rows.iter().any(|r| r.dk.iter().any(|&x| x != 0.0));
        let p = model.params();
        let linear = model.contact_law().exponent() == 1.0;
        // one matrix for both flanks: equal friction factors (no friction, or symmetric)
        let symmetric = rows.iter().all(|r| r.hd == r.hb);
        let affine = linear && !p.unilateral && symmetric && steps <= AFFINE_MAX_STEPS;
        MeshLanes {
            n,
            cycles,
            u0,
            steps,
            inv_n: 1.0 / n as f64,
            rows,
            linear,
            unilateral: p.unilateral,
            harmonic,
            affine,
        }
    }

    /// The same tables with the lanes' steps taken by the RK4 stages even where the affine map
    /// applies: every lane then follows the scalar integrator's RK4 path to the bit (see the
    /// module doc).
    pub fn exact(mut self) -> Self {
        self.affine = false;
        self
    }

    /// Whether the lanes' steps are taken by the affine map (see the module doc).
    pub fn is_affine(&self) -> bool {
        self.affine
    }

    /// Steps per mesh cycle.
    pub fn steps_per_cycle(&self) -> u32 {
        self.n
    }

    /// Steps flagged for the scalar integrator (they may hold a time breakpoint).
    pub fn scalar_steps(&self) -> usize {
        self.rows.iter().filter(|r| r.scalar).count()
    }

    /// Start position of the grid in the excitation period (mesh cycles).
    pub fn start_position(&self) -> f64 {
        self.u0
    }

    /// Whether the step at phase `j` ends a mesh cycle (`(j+1) mod n == 0`) or starts one.
    #[inline]
    pub fn near_cycle_end(&self, j: usize) -> bool {
        let r = (j + 1) % self.n as usize;
        r == 0 || r == 1 || self.n == 1
    }

    /// The lane constants of `model` in `mode`, if the batched field covers that mode.
    pub fn lane_of(&self, model: &MeshModel, mode: &MeshMode) -> Option<MeshLane> {
        if mode.chi != 0.0 {
            return None;
        }
        let (sd, sb) = match mode.contact {
            ContactState::Drive => (1.0, 0.0),
            ContactState::Back => (0.0, 1.0),
            ContactState::Separated => (0.0, 0.0),
            ContactState::Stuck => return None,
        };
        if sd + sb > 0.0 && !self.linear {
            return None;
        }
        let p = model.params();
        let (lo, hi) = match (self.unilateral, mode.contact) {
            (true, ContactState::Drive) => (0.0, f64::INFINITY),
            (true, ContactState::Back) => (f64::NEG_INFINITY, 0.0),
            _ => (f64::NEG_INFINITY, f64::INFINITY),
        };
        Some(MeshLane {
            sd,
            sb,
            load: p.load,
            xiw2: p.xi * p.omega * p.omega,
            c: p.c,
            w: p.omega,
            lo,
            hi,
        })
    }

    /// Excitation cosine and stiffness of `stage` of row `r` for a lane at grid position `grid` whose
    /// scalar counterpart evaluates them at the phase `s` (cycles, from its rounded time): the
    /// tabulated values at the exact phase, corrected to first order by the difference
    /// `s - (u0 + grid/n)` reduced to the nearest integer (exact when `n` is a power of two and
    /// the grid starts at phase 0).
    #[inline(always)]
    fn cos_k(&self, r: &Row, stage: usize, s: f64, grid: f64) -> (f64, f64) {
        let delta = self.phase_delta(s, grid);
        (
            r.cos[stage] + r.dcos[stage] * delta,
            r.k[stage] + r.dk[stage] * delta,
        )
    }

    /// The phase difference `s - (u0 + grid/n)` reduced to the nearest integer (see
    /// [`MeshLanes::cos_k`]).
    #[inline(always)]
    fn phase_delta(&self, s: f64, grid: f64) -> f64 {
        let e = s - (self.u0 + grid * self.inv_n);
        e - round_near(e)
    }

    /// Mesh force `F_m` of every lane at `stage` of step `j` (0 when separated), as
    /// [`MeshModel::mesh_force`] computes it at the times `at.t`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn force<const L: usize>(
        &self,
        j: usize,
        stage: Stage,
        at: &At<L>,
        ln: &MeshLaneBlock<L>,
        x: &[f64; L],
        v: &[f64; L],
        out: &mut [f64; L],
    ) {
        let r = &self.rows[j];
        let st = stage as usize;
        let d = r.d;
        for l in 0..L {
            // (MeshModel::mesh_force writes the phase as omega t / (2 pi))
            let (_, k) = self.cos_k(r, st, ln.w[l] * at.t[l] / (2.0 * PI), at.grid[l]);
            let off = (ln.sd[l] - ln.sb[l]) * d;
            let f = lane_contact(k, off, ln.c[l], ln.lo[l], ln.hi[l]).force(
                x[l],
                v[l],
                self.unilateral,
            );
            out[l] = if ln.sd[l] + ln.sb[l] > 0.0 { f } else { 0.0 };
        }
    }
}

impl MeshLanes {
    /// Coefficients of the linearised field of every lane at `stage` of step `j` (the tangent
    /// `(dx, dv)` of a lane obeys `dx' = dv`, `dv' = a dx + b dv`), as [`MeshModel`]'s
    /// `jacobian` gives them for the lanes' law (linear, no hysteresis): `a = -h k`, `b = -h c`
    /// in contact, zero when separated or when a unilateral force is clamped. Coefficients from
    /// the tables at the times `at.t`, as [`Lockstep::rhs`] takes them.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn tangent_coefficients<const L: usize>(
        &self,
        j: usize,
        stage: Stage,
        at: &At<L>,
        ln: &MeshLaneBlock<L>,
        y: &Soa<2, L>,
        a: &mut [f64; L],
        b: &mut [f64; L],
    ) {
        let r = &self.rows[j];
        let st = stage as usize;
        let (hd, hb) = (r.hd[st], r.hb[st]);
        let d = r.d;
        for l in 0..L {
            let (_, k) = self.cos_k(r, st, ln.w[l] * at.t[l] * (0.5 / PI), at.grid[l]);
            let hf = ln.sd[l] * hd + ln.sb[l] * hb;
            let contact = ln.sd[l] + ln.sb[l] > 0.0;
            let off = (ln.sd[l] - ln.sb[l]) * d;
            let (al, bl) = lane_contact(k, off, ln.c[l], ln.lo[l], ln.hi[l]).tangent(
                hf,
                y[0][l],
                y[1][l],
                self.unilateral,
            );
            (a[l], b[l]) = if contact { (al, bl) } else { (0.0, 0.0) };
        }
    }
}

impl<const L: usize> Lockstep<2, L> for MeshLanes {
    type Sys = MeshModel;
    type Lanes = MeshLaneBlock<L>;
    type Work = AffineTables<L>;
    const GUARD_DIMS: usize = 2;

    fn new_work(&self) -> AffineTables<L> {
        AffineTables {
            key: [[f64::NAN; 5]; L],
            sep: [[0.0; L]; 5],
            tab: if self.affine {
                vec![[[0.0; L]; 8]; self.steps]
            } else {
                Vec::new()
            },
        }
    }

    fn steps_per_period(&self) -> usize {
        self.steps
    }

    #[inline(always)]
    fn scalar_phase(&self, j: usize) -> bool {
        self.rows[j].scalar
    }

    fn set_lane(
        &self,
        lanes: &mut MeshLaneBlock<L>,
        work: &mut AffineTables<L>,
        l: usize,
        sys: &MeshModel,
        mode: &MeshMode,
        h: f64,
    ) -> bool {
        match self.lane_of(sys, mode) {
            Some(ln) => {
                if self.affine && work.key[l] != [ln.w, ln.c, ln.load, ln.xiw2, h] {
                    self.build_column(work, l, &ln, h);
                }
                lanes.set(l, &ln);
                true
            }
            None => false,
        }
    }

    fn idle_lanes(&self) -> MeshLaneBlock<L> {
        let i = MeshLane::IDLE;
        MeshLaneBlock {
            sd: [i.sd; L],
            sb: [i.sb; L],
            load: [i.load; L],
            xiw2: [i.xiw2; L],
            c: [i.c; L],
            w: [i.w; L],
            lo: [i.lo; L],
            hi: [i.hi; L],
        }
    }

    fn set_idle(&self, lanes: &mut MeshLaneBlock<L>, l: usize) {
        lanes.set(l, &MeshLane::IDLE);
    }

    #[inline(always)]
    fn rhs(
        &self,
        j: usize,
        stage: Stage,
        at: &At<L>,
        ln: &MeshLaneBlock<L>,
        y: &Soa<2, L>,
        dy: &mut Soa<2, L>,
    ) {
        let r = &self.rows[j];
        let st = stage as usize;
        let (hd, hb) = (r.hd[st], r.hb[st]);
        let d = r.d;
        for l in 0..L {
            let (x, v) = (y[0][l], y[1][l]);
            // (MeshModel::time_terms writes the phase as omega t (0.5 / pi))
            let (cs, k) = self.cos_k(r, st, ln.w[l] * at.t[l] * (0.5 / PI), at.grid[l]);
            let exc = kernel::excitation(ln.load[l], ln.xiw2[l], cs);
            let hf = ln.sd[l] * hd + ln.sb[l] * hb;
            let off = (ln.sd[l] - ln.sb[l]) * d;
            let fm = lane_contact(k, off, ln.c[l], ln.lo[l], ln.hi[l]).force(x, v, self.unilateral);
            dy[0][l] = v;
            dy[1][l] = kernel::acceleration(exc, hf, fm);
        }
    }

    /// The RK4 step of every lane: the tabulated affine map where the table takes it
    /// (`MeshLanes::affine_kernel`), else the RK4 stages of [`rk4_lanes`] over the pair's
    /// [`LaneKernel`] with the scalar model's operations in its order, so its results.
    /// Dispatches once per step to a copy of the stage kernel specialised for the table's contact
    /// clamp and stiffness form ([`MeshLanes::step_stages`]).
    #[inline(always)]
    fn step(
        &self,
        s: &StepStart<'_, 2, L>,
        ln: &MeshLaneBlock<L>,
        work: &AffineTables<L>,
        y1: &mut Soa<2, L>,
        f1: &mut Soa<2, L>,
    ) -> u32 {
        if self.affine {
            let bits = self.affine_kernel::<L>(s, ln, work, y1, f1);
            self.settle(s, ln, y1, f1, bits)
        } else {
            self.step_stages(s, ln, y1, f1)
        }
    }

    #[inline(always)]
    fn clear(
        &self,
        j: usize,
        ln: &MeshLaneBlock<L>,
        y0: &Soa<2, L>,
        y1: &Soa<2, L>,
        dev: &[f64; L],
    ) -> u32 {
        let d = self.rows[j].d;
        let mut ok = [false; L];
        for l in 0..L {
            // guard Lipschitz constant 1 (guards x -+ D, D constant within the step)
            let margin = 0.25 * dev[l];
            let (a0, a1) = (y0[0][l] - d, y1[0][l] - d);
            let (b0, b1) = (y0[0][l] + d, y1[0][l] + d);
            let ca = ((a0 > 0.0) == (a1 > 0.0)) & (a0.abs().min(a1.abs()) > margin);
            let cb = ((b0 > 0.0) == (b1 > 0.0)) & (b0.abs().min(b1.abs()) > margin);
            // x - D is armed unless in back contact, x + D unless in drive contact
            ok[l] = ((ln.sb[l] != 0.0) | ca) & ((ln.sd[l] != 0.0) | cb);
        }
        let mut mask = 0u32;
        for l in 0..L {
            mask |= (ok[l] as u32) << l;
        }
        mask
    }
}
