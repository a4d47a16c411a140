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
//! Arithmetic: each lane evaluates exactly the expressions of [`MeshModel`]'s `rhs` and
//! `mesh_force` (`exc - h*(k*(x -+ D) + c*x')`), with the coefficients taken from the tables. The
//! scalar model evaluates the excitation (and a harmonic stiffness) at the *rounded* time
//! `t0 + k*h`, whose phase differs from the exact grid phase by up to ~ulp(t) — at `t ~ 10^4`
//! about 1e-12, which a lightly damped gear pair amplifies. The lanes therefore correct the
//! tabulated cosine to first order by that difference (a table of its derivative), computed
//! exactly from the lane's time as the scalar model computes its phase; they then follow the scalar
//! path to rounding, not to ulp(t). Piecewise-linear stiffness and friction tables are taken at the
//! exact phase (their rounded-time difference is below 1e-13 relative).

use crate::mesh_model::{ContactState, MeshMode, MeshModel};
use crate::params::StiffnessForm;
use crate::phase::cos_cycles;
use geardyn_solvers::ensemble::{At, Lockstep, Soa, Stage};
use std::f64::consts::PI;

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
    /// Per step and stage (`3*j + stage`): excitation cosine and its derivative by the phase (in
    /// cycles), stiffness and its derivative by the phase, friction factors.
    cos: Vec<f64>,
    dcos: Vec<f64>,
    k: Vec<f64>,
    dk: Vec<f64>,
    hd: Vec<f64>,
    hb: Vec<f64>,
    /// Per step: half backlash.
    d: Vec<f64>,
    /// Per step: may hold a time breakpoint (scalar in every lane).
    scalar: Vec<bool>,
    linear: bool,
    unilateral: bool,
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
        let mut cos = Vec::with_capacity(3 * steps);
        let mut dcos = Vec::with_capacity(3 * steps);
        let mut k = Vec::with_capacity(3 * steps);
        let mut dk = Vec::with_capacity(3 * steps);
        let mut hd = Vec::with_capacity(3 * steps);
        let mut hb = Vec::with_capacity(3 * steps);
        let mut d = Vec::with_capacity(steps);
        for j in 0..steps {
            for s in 0..3 {
                let u = pos(2 * j + s);
                cos.push(cos_cycles(u));
                // d cos(2 pi u) / du = -2 pi sin(2 pi u)
                let dc = -2.0 * PI * cos_cycles(u - 0.25);
                dcos.push(dc);
                k.push(model.stiffness_at(u));
                dk.push(kappa * dc);
                let (a, b) = model.friction_factors_at(u);
                hd.push(a);
                hb.push(b);
            }
            d.push(model.backlash_at(pos(2 * j + 1)));
        }
        // steps that may hold a segment border: (u_j - delta, u_{j+1} + delta], any wrap
        let mut scalar = vec![false; steps];
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
                            scalar[j as usize] = true;
                        }
                    }
                }
            }
        }
        let p = model.params();
        MeshLanes {
            n,
            cycles,
            u0,
            steps,
            inv_n: 1.0 / n as f64,
            cos,
            dcos,
            k,
            dk,
            hd,
            hb,
            d,
            scalar,
            linear: model.contact_law().exponent() == 1.0,
            unilateral: p.unilateral,
        }
    }

    /// Steps per mesh cycle.
    pub fn steps_per_cycle(&self) -> u32 {
        self.n
    }

    /// Steps flagged for the scalar integrator (they may hold a time breakpoint).
    pub fn scalar_steps(&self) -> usize {
        self.scalar.iter().filter(|&&s| s).count()
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

    /// Excitation cosine and stiffness of half-step `m` for a lane at grid position `grid` whose
    /// scalar counterpart evaluates them at the phase `s` (cycles, from its rounded time): the
    /// tabulated values at the exact phase, corrected to first order by the difference
    /// `s - (u0 + grid/n)` reduced to the nearest integer (exact when `n` is a power of two and
    /// the grid starts at phase 0).
    #[inline(always)]
    fn cos_k(&self, m: usize, s: f64, grid: f64) -> (f64, f64) {
        let e = s - (self.u0 + grid * self.inv_n);
        let delta = e - round_near(e);
        (
            self.cos[m] + self.dcos[m] * delta,
            self.k[m] + self.dk[m] * delta,
        )
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
        lanes: &[MeshLane; L],
        x: &[f64; L],
        v: &[f64; L],
        out: &mut [f64; L],
    ) {
        let m = 3 * j + stage as usize;
        let d = self.d[j];
        for l in 0..L {
            let ln = &lanes[l];
            // (MeshModel::mesh_force writes the phase as omega t / (2 pi))
            let (_, k) = self.cos_k(m, ln.w * at.t[l] / (2.0 * PI), at.grid[l]);
            let off = (ln.sd - ln.sb) * d;
            let f = (k * (x[l] - off) + ln.c * v[l]).max(ln.lo).min(ln.hi);
            out[l] = if ln.sd + ln.sb > 0.0 { f } else { 0.0 };
        }
    }
}

impl<const L: usize> Lockstep<2, L> for MeshLanes {
    type Sys = MeshModel;
    type Lane = MeshLane;
    const GUARD_DIMS: usize = 2;

    fn steps_per_period(&self) -> usize {
        self.steps
    }

    #[inline(always)]
    fn scalar_phase(&self, j: usize) -> bool {
        self.scalar[j]
    }

    fn lane(&self, sys: &MeshModel, mode: &MeshMode) -> Option<MeshLane> {
        self.lane_of(sys, mode)
    }

    fn idle_lane(&self) -> MeshLane {
        MeshLane {
            sd: 0.0,
            sb: 0.0,
            load: 0.0,
            xiw2: 0.0,
            c: 0.0,
            w: 0.0,
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
        }
    }

    #[inline(always)]
    fn rhs(
        &self,
        j: usize,
        stage: Stage,
        at: &At<L>,
        lanes: &[MeshLane; L],
        y: &Soa<2, L>,
        dy: &mut Soa<2, L>,
    ) {
        let m = 3 * j + stage as usize;
        let (hd, hb) = (self.hd[m], self.hb[m]);
        let d = self.d[j];
        for l in 0..L {
            let ln = &lanes[l];
            // (MeshModel::time_terms writes the phase as omega t (0.5 / pi))
            let (cs, k) = self.cos_k(m, ln.w * at.t[l] * (0.5 / PI), at.grid[l]);
            let (x, v) = (y[0][l], y[1][l]);
            let exc = ln.load + ln.xiw2 * cs;
            let hf = ln.sd * hd + ln.sb * hb;
            let off = (ln.sd - ln.sb) * d;
            let fm = (k * (x - off) + ln.c * v).max(ln.lo).min(ln.hi);
            dy[0][l] = v;
            dy[1][l] = exc - hf * fm;
        }
    }

    #[inline(always)]
    fn clear(
        &self,
        j: usize,
        lanes: &[MeshLane; L],
        y0: &Soa<2, L>,
        y1: &Soa<2, L>,
        dev: &[f64; L],
    ) -> u32 {
        let d = self.d[j];
        let mut mask = 0u32;
        for l in 0..L {
            // guard Lipschitz constant 1 (guards x -+ D, D constant within the step)
            let margin = 0.25 * dev[l];
            let (a0, a1) = (y0[0][l] - d, y1[0][l] - d);
            let (b0, b1) = (y0[0][l] + d, y1[0][l] + d);
            let ca = ((a0 > 0.0) == (a1 > 0.0)) & (a0.abs().min(a1.abs()) > margin);
            let cb = ((b0 > 0.0) == (b1 > 0.0)) & (b0.abs().min(b1.abs()) > margin);
            // x - D is armed unless in back contact, x + D unless in drive contact
            let ok = ((lanes[l].sb != 0.0) | ca) & ((lanes[l].sd != 0.0) | cb);
            mask |= (ok as u32) << l;
        }
        mask
    }
}
