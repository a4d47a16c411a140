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
//! Layout of the fused RK4-stage step ([`Lockstep::step`] here), written out by hand rather than composed
//! from `rhs` because the composition left the lanes waiting on each other: the tables are one
//! row per step (read once per step), the kernel is compiled once per contact clamp and
//! stiffness form (no per-lane branches), and it runs stage by stage over chunks of up to
//! `CHUNK` (16) lanes, so that the RK4 stage chains of the lanes' vector groups (~90 cycles of
//! dependent operations per step) overlap instead of running one group after the other. Every
//! lane still evaluates the expressions of [`MeshModel`] in the same order (no fused
//! multiply-add), so the result of a lane does not depend on the layout nor on the CPU copy of
//! the engine. Units: dimensionless time `tau`, phases in mesh cycles.

// lane loops over several arrays read clearer (and vectorise as intended) with an index
#![allow(clippy::needless_range_loop)]

use crate::mesh_kernel::{self as kernel, Contact, Linear};
use crate::mesh_model::{ContactState, MeshMode, MeshModel};
use crate::params::StiffnessForm;
use crate::phase::cos_cycles;
use geardyn_solvers::dense::{hermite, nested_at};
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

/// Largest table (steps per strobe period) stepped by the affine map: 8 coefficients per lane
/// and step must stay in the core's cache (16 lanes x 1024 steps x 64 bytes = 1 MiB).
const AFFINE_MAX_STEPS: usize = 1024;

/// Per-engine tables of the affine step ([`MeshLanes`] with the affine map): for every step `j`
/// and lane `l`, the RK4 step of the lane's linear contact equation as `y1 = P y0 + q_e + s q_o`
/// (`s = +1` in drive contact, `-1` in back contact): `tab[j][c][l]` with `c` = `P00, P01, P10,
/// P11, q_e0, q_e1, q_o0, q_o1` (`q_e` the response to the excitation and load, `q_o` to the
/// backlash offset). Each lane's column is built when the lane's constants or step change
/// ([`Lockstep::set_lane`]).
#[derive(Clone, Debug)]
pub struct AffineTables<const L: usize> {
    /// The constants each lane's column was built for (`omega`, `c`, `F`, `xi omega^2`, `h`);
    /// NaN: none.
    key: [[f64; 5]; L],
    tab: Vec<[[f64; L]; 8]>,
    /// Per lane, the RK4 step of free flight `x'' = F + xi omega^2 cos` with the lane's step `h`:
    /// `x1 = x0 + h v0 + sep[0] + sep[1] s0_j`, `v1 = v0 + sep[2] + sep[3] s1_j` (`s0_j`, `s1_j`
    /// the step's cosine sums of [`Row`]): `h^2 F / 2`, `h^2 xi omega^2 / 6`, `h F`,
    /// `h xi omega^2 / 6`; and `h` itself (`sep[4]`).
    sep: [[f64; L]; 5],
}

/// Lanes the fused kernel advances stage by stage together ([`MeshLanes::kernel`]). On the C1
/// kernel benchmark (16 lanes, one thread, same run) 16 ran at 5.2 ns per lane-step on AVX2 and
/// 3.6 on AVX-512, against 8.1 / 6.5 for chunks of 4 / 8 lanes and 7.9 for the lane-major loop.
const CHUNK: usize = 16;

/// The coefficients of one step a kernel chunk reads (middle and end stages of a [`Row`]).
#[derive(Clone, Copy)]
struct Coef {
    cm: f64,
    dcm: f64,
    kkm: f64,
    dkm: f64,
    hdm: f64,
    hbm: f64,
    ce: f64,
    dce: f64,
    kke: f64,
    dke: f64,
    hde: f64,
    hbe: f64,
    d: f64,
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

/// The verdict of one lane's step from `y0` (field `f0`) to `y1` (field `f1`) of length `h`:
/// `(clear, finite)`, `clear` when the step is finite and both armed guards (`x - D` unless in
/// back contact, `x + D` unless in drive contact) keep their sign at the ends and stay farther
/// from zero than the interior bound of the Hermite interpolant lets them move (the rigorous
/// bound of the scalar integrator: `0.25 max(|r2| + |r3|)` over `x` and `x'`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn verdict(
    y0: [f64; 2],
    f0: [f64; 2],
    y1: [f64; 2],
    f1: [f64; 2],
    h: f64,
    d: f64,
    sd: f64,
    sb: f64,
) -> (bool, bool) {
    let [_, _, r2x, r3x] = hermite(y0[0], y1[0], f0[0], f1[0], h);
    let [_, _, r2v, r3v] = hermite(y0[1], y1[1], f0[1], f1[1], h);
    // (a NaN in the first sum gives a NaN margin, one in the second is dropped by max_fast: a
    // NaN there comes from a non-finite end, and `finite` keeps such a lane from being clear)
    let dev = max_fast(r2x.abs() + r3x.abs(), r2v.abs() + r3v.abs());
    // all three finite (tested one by one: a plain sum overflows on finite values, and
    // `v * 0` sums were slower)
    let finite = (y1[0].abs() < f64::INFINITY)
        & (y1[1].abs() < f64::INFINITY)
        & (f1[1].abs() < f64::INFINITY);
    let margin = 0.25 * dev;
    // A guard x -+ D keeps its sign at both ends and stays farther than the margin from zero
    // exactly when the smaller end value exceeds the margin or the larger one is below minus
    // it; rounding is monotone, so min(x0, x1) - D is the smaller of x0 - D and x1 - D.
    let (lo, hi) = (min_fast(y0[0], y1[0]), max_fast(y0[0], y1[0]));
    let ca = (lo - d > margin) | (hi - d < -margin);
    let cb = (lo + d > margin) | (hi + d < -margin);
    (finite & ((sb != 0.0) | ca) & ((sd != 0.0) | cb), finite)
}

/// `a.max(b)` for a non-NaN `a` (then equal to `f64::max` for any `b`, NaN included; one
/// instruction instead of three).
#[inline(always)]
fn max_fast(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// `a.min(b)` for non-NaN operands (equal to `f64::min` there; one instruction).
#[inline(always)]
fn min_fast(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
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

    /// Builds lane `l`'s column of the affine tables for the constants `ln` and step `h`: per
    /// step, the RK4 step of `x' = v`, `v' = a x + b v + g` (`a = -h_f k`, `b = -h_f c` at the
    /// start, middle and end of the step, from the tables at the exact grid phases) applied to
    /// the unit states (the columns of `P`), and to the zero state with the forcing
    /// `g = F + xi omega^2 cos` (`q_e`) and `g = h_f k D` (`q_o`, the backlash offset).
    fn build_column<const L: usize>(
        &self,
        w: &mut AffineTables<L>,
        l: usize,
        ln: &MeshLane,
        h: f64,
    ) {
        for (j, r) in self.rows.iter().enumerate() {
            let mut a = [0.0; 3];
            let mut b = [0.0; 3];
            let mut ge = [0.0; 3];
            let mut go = [0.0; 3];
            for s in 0..3 {
                let hf = r.hd[s];
                (a[s], b[s]) =
                    lane_contact(r.k[s], 0.0, ln.c, 0.0, 0.0).tangent(hf, 0.0, 0.0, false);
                ge[s] = kernel::excitation(ln.load, ln.xiw2, r.cos[s]);
                go[s] = hf * r.k[s] * r.d;
            }
            let rk4 = |x0: f64, v0: f64, g: [f64; 3]| {
                let acc = |s: usize, x: f64, v: f64| a[s] * x + b[s] * v + g[s];
                let (k1x, k1v) = (v0, acc(0, x0, v0));
                let (x2, v2) = (x0 + 0.5 * h * k1x, v0 + 0.5 * h * k1v);
                let (k2x, k2v) = (v2, acc(1, x2, v2));
                let (x3, v3) = (x0 + 0.5 * h * k2x, v0 + 0.5 * h * k2v);
                let (k3x, k3v) = (v3, acc(1, x3, v3));
                let (x4, v4) = (x0 + h * k3x, v0 + h * k3v);
                let (k4x, k4v) = (v4, acc(2, x4, v4));
                (
                    x0 + h / 6.0 * (k1x + 2.0 * (k2x + k3x) + k4x),
                    v0 + h / 6.0 * (k1v + 2.0 * (k2v + k3v) + k4v),
                )
            };
            let (p00, p10) = rk4(1.0, 0.0, [0.0; 3]);
            let (p01, p11) = rk4(0.0, 1.0, [0.0; 3]);
            let (qe0, qe1) = rk4(0.0, 0.0, ge);
            let (qo0, qo1) = rk4(0.0, 0.0, go);
            let e = &mut w.tab[j];
            for (c, v) in [p00, p01, p10, p11, qe0, qe1, qo0, qo1]
                .into_iter()
                .enumerate()
            {
                e[c][l] = v;
            }
        }
        let sep = [
            h * h * 0.5 * ln.load,
            h * h * (1.0 / 6.0) * ln.xiw2,
            h * ln.load,
            h * (1.0 / 6.0) * ln.xiw2,
            h,
        ];
        for (c, v) in sep.into_iter().enumerate() {
            w.sep[c][l] = v;
        }
        w.key[l] = [ln.w, ln.c, ln.load, ln.xiw2, h];
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

    /// For a lane whose step has no guard sign change at its ends but does not clear the interior
    /// bound: the scalar integrator's next test (`find_crossing`): the guards at the midpoint of
    /// the Hermite interpolant and the vertex of the parabola through the three samples. `true`
    /// when that test finds no guard near zero (the scalar step would be an ordinary one); `false`
    /// when the scalar integrator must take the step (an event at an end, or a possible graze).
    #[allow(clippy::too_many_arguments)]
    #[cold]
    #[inline(never)]
    fn no_event_by_midpoint<const L: usize>(
        &self,
        d: f64,
        sd: f64,
        sb: f64,
        h: f64,
        l: usize,
        y0: &Soa<2, L>,
        f0: &Soa<2, L>,
        y1: &Soa<2, L>,
        f1: &Soa<2, L>,
    ) -> bool {
        // Hermite interpolant of x (Step::hermite) at theta = 1/2 (Step::at_theta)
        let [r0, r1, r2, r3] = hermite(y0[0][l], y1[0][l], f0[0][l], f1[0][l], h);
        let xm = nested_at([r0, r1, r2, r3, 0.0], 0.5);
        let x1 = y1[0][l];
        // armed guards: (value at start, middle, end, rising?)
        let mut guards = [(0.0, 0.0, 0.0, false); 2];
        let mut n = 0;
        if sb == 0.0 {
            // x - D: rising when separated, falling in drive contact
            guards[n] = (r0 - d, xm - d, x1 - d, sd == 0.0);
            n += 1;
        }
        if sd == 0.0 {
            // x + D: falling when separated, rising in back contact
            guards[n] = (r0 + d, xm + d, x1 + d, sb != 0.0);
            n += 1;
        }
        let crossed = |rising: bool, a: f64, b: f64| {
            if rising {
                a <= 0.0 && b > 0.0
            } else {
                a >= 0.0 && b < 0.0
            }
        };
        for &(p, _, b, rising) in &guards[..n] {
            if crossed(rising, p, b) {
                return false;
            }
        }
        for &(p, a, b, rising) in &guards[..n] {
            let curv = p - 2.0 * a + b;
            let near = if crossed(rising, p, a) || crossed(rising, a, b) {
                true
            } else if curv != 0.0 {
                let th = 0.5 + 0.25 * (p - b) / curv;
                let vertex = a - (b - p) * (b - p) / (8.0 * curv);
                th > 0.0
                    && th < 1.0
                    && (vertex.signum() != p.signum() || vertex.abs() < 0.5 * p.abs().min(b.abs()))
            } else {
                false
            };
            if near {
                return false;
            }
        }
        true
    }

    /// The fused RK4 step of every lane (see [`Lockstep::step`]), specialised at compile time
    /// for the unilateral clamp (`UNI`) and for a stiffness with a time correction (`HARM`;
    /// without it `k + dk * delta` is `k + 0 * delta == k` exactly, as `delta` is finite).
    /// Returns bit `l` set when lane `l`'s step is finite and clears both guards by the interior
    /// bound, and bit `32 + l` when it is finite. `max`/`min` are plain comparisons: the `max`
    /// chain equals `f64::max`'s for any operand, the `min` only differs on a NaN state, whose
    /// lane is not finite and therefore not cleared either way.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn kernel<const UNI: bool, const HARM: bool, const L: usize>(
        &self,
        j: usize,
        t0: &[f64; L],
        t1: &[f64; L],
        grid: &[f64; L],
        ln: &MeshLaneBlock<L>,
        y0: &Soa<2, L>,
        f0: &Soa<2, L>,
        y1: &mut Soa<2, L>,
        f1: &mut Soa<2, L>,
    ) -> u64 {
        // the row of step j, read once: middle (k2, k3) and end (k4, f1) coefficients
        let r = &self.rows[j];
        let co = Coef {
            cm: r.cos[1],
            dcm: r.dcos[1],
            kkm: r.k[1],
            dkm: r.dk[1],
            hdm: r.hd[1],
            hbm: r.hb[1],
            ce: r.cos[2],
            dce: r.dcos[2],
            kke: r.k[2],
            dke: r.dk[2],
            hde: r.hd[2],
            hbe: r.hb[2],
            d: r.d,
        };
        // Stage-major within chunks of up to `CHUNK` lanes: each stage is one loop over the
        // chunk, so the independent chains of its vector groups sit side by side in the
        // instruction stream and overlap; a lane-major loop ran each group's ~90-cycle chain of
        // dependent stages before starting the next, and the groups hardly overlapped.
        let mut bits = [0u64; L];
        if L <= CHUNK {
            self.chunk::<UNI, HARM, L, L>(0, &co, t0, t1, grid, ln, y0, f0, y1, f1, &mut bits);
        } else if L.is_multiple_of(CHUNK) {
            for c in 0..L / CHUNK {
                let c0 = c * CHUNK;
                self.chunk::<UNI, HARM, CHUNK, L>(
                    c0, &co, t0, t1, grid, ln, y0, f0, y1, f1, &mut bits,
                );
            }
        } else {
            for l in 0..L {
                self.chunk::<UNI, HARM, 1, L>(l, &co, t0, t1, grid, ln, y0, f0, y1, f1, &mut bits);
            }
        }
        let mut all = 0u64;
        for b in bits {
            all |= b;
        }
        all
    }

    /// Lanes `c0..c0 + CH` of [`MeshLanes::kernel`], stage by stage.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn chunk<const UNI: bool, const HARM: bool, const CH: usize, const L: usize>(
        &self,
        c0: usize,
        co: &Coef,
        t0: &[f64; L],
        t1: &[f64; L],
        grid: &[f64; L],
        ln: &MeshLaneBlock<L>,
        y0: &Soa<2, L>,
        f0: &Soa<2, L>,
        y1: &mut Soa<2, L>,
        f1: &mut Soa<2, L>,
        bits: &mut [u64; L],
    ) {
        let Coef {
            cm,
            dcm,
            kkm,
            dkm,
            hdm,
            hbm,
            ce,
            dce,
            kke,
            dke,
            hde,
            hbe,
            d,
        } = *co;
        let mut h = [0.0; CH];
        let mut h2 = [0.0; CH];
        let mut h6 = [0.0; CH];
        let mut off = [0.0; CH];
        let mut km = [0.0; CH];
        let mut ke = [0.0; CH];
        let mut excm = [0.0; CH];
        let mut exce = [0.0; CH];
        let mut hfm = [0.0; CH];
        let mut hfe = [0.0; CH];
        for i in 0..CH {
            let l = c0 + i;
            h[i] = t1[l] - t0[l];
            h2[i] = 0.5 * h[i];
            h6[i] = h[i] * (1.0 / 6.0);
            let (tm, te) = (t0[l] + h2[i], t0[l] + h[i]);
            let (sd, sb) = (ln.sd[l], ln.sb[l]);
            off[i] = (sd - sb) * d;
            // stage coefficients (as cos_k)
            let dm = self.phase_delta(ln.w[l] * tm * (0.5 / PI), grid[l] + 0.5);
            let de = self.phase_delta(ln.w[l] * te * (0.5 / PI), grid[l] + 1.0);
            let (csm, cse) = (cm + dcm * dm, ce + dce * de);
            km[i] = if HARM { kkm + dkm * dm } else { kkm };
            ke[i] = if HARM { kke + dke * de } else { kke };
            excm[i] = kernel::excitation(ln.load[l], ln.xiw2[l], csm);
            exce[i] = kernel::excitation(ln.load[l], ln.xiw2[l], cse);
            hfm[i] = sd * hdm + sb * hbm;
            hfe[i] = sd * hde + sb * hbe;
        }
        let acc = |i: usize, exc: f64, hf: f64, k: f64, x: f64, v: f64| {
            let l = c0 + i;
            let fm = lane_contact(k, off[i], ln.c[l], ln.lo[l], ln.hi[l]).force(x, v, UNI);
            kernel::acceleration(exc, hf, fm)
        };
        let (x0, v0) = (&y0[0], &y0[1]);
        let (a0x, a0v) = (&f0[0], &f0[1]);
        let mut k2x = [0.0; CH];
        let mut k2v = [0.0; CH];
        for i in 0..CH {
            let l = c0 + i;
            let (xt, vt) = (x0[l] + h2[i] * a0x[l], v0[l] + h2[i] * a0v[l]);
            k2x[i] = vt;
            k2v[i] = acc(i, excm[i], hfm[i], km[i], xt, vt);
        }
        let mut k3x = [0.0; CH];
        let mut k3v = [0.0; CH];
        for i in 0..CH {
            let l = c0 + i;
            let (xt, vt) = (x0[l] + h2[i] * k2x[i], v0[l] + h2[i] * k2v[i]);
            k3x[i] = vt;
            k3v[i] = acc(i, excm[i], hfm[i], km[i], xt, vt);
        }
        let mut k4x = [0.0; CH];
        let mut k4v = [0.0; CH];
        for i in 0..CH {
            let l = c0 + i;
            let (xt, vt) = (x0[l] + h[i] * k3x[i], v0[l] + h[i] * k3v[i]);
            k4x[i] = vt;
            k4v[i] = acc(i, exce[i], hfe[i], ke[i], xt, vt);
        }
        for i in 0..CH {
            let l = c0 + i;
            let x1 = x0[l] + h6[i] * (a0x[l] + 2.0 * (k2x[i] + k3x[i]) + k4x[i]);
            let v1 = v0[l] + h6[i] * (a0v[l] + 2.0 * (k2v[i] + k3v[i]) + k4v[i]);
            y1[0][l] = x1;
            y1[1][l] = v1;
            f1[0][l] = v1;
            f1[1][l] = acc(i, exce[i], hfe[i], ke[i], x1, v1);
        }
        for i in 0..CH {
            let l = c0 + i;
            let (ok, finite) = verdict(
                [x0[l], v0[l]],
                [a0x[l], a0v[l]],
                [y1[0][l], y1[1][l]],
                [f1[0][l], f1[1][l]],
                h[i],
                d,
                ln.sd[l],
                ln.sb[l],
            );
            bits[l] = ((ok as u64) << l) | ((finite as u64) << (32 + l));
        }
    }

    /// The RK4 stage kernel for the table's clamp and stiffness form (its bits as
    /// [`MeshLanes::kernel`] returns them).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn stage_bits<const L: usize>(
        &self,
        j: usize,
        t0: &[f64; L],
        t1: &[f64; L],
        grid: &[f64; L],
        ln: &MeshLaneBlock<L>,
        y0: &Soa<2, L>,
        f0: &Soa<2, L>,
        y1: &mut Soa<2, L>,
        f1: &mut Soa<2, L>,
    ) -> u64 {
        match (self.unilateral, self.harmonic) {
            (false, false) => self.kernel::<false, false, L>(j, t0, t1, grid, ln, y0, f0, y1, f1),
            (false, true) => self.kernel::<false, true, L>(j, t0, t1, grid, ln, y0, f0, y1, f1),
            (true, false) => self.kernel::<true, false, L>(j, t0, t1, grid, ln, y0, f0, y1, f1),
            (true, true) => self.kernel::<true, true, L>(j, t0, t1, grid, ln, y0, f0, y1, f1),
        }
    }

    /// The lanes that take a kernel's step (`bits`: clear, and finite in the upper half): the
    /// clear ones, and the finite ones near a surface without a sign change at the ends whose
    /// step the scalar integrator's midpoint test would take as an ordinary one (rare: next to
    /// events).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn settle<const L: usize>(
        &self,
        j: usize,
        t0: &[f64; L],
        t1: &[f64; L],
        ln: &MeshLaneBlock<L>,
        y0: &Soa<2, L>,
        f0: &Soa<2, L>,
        y1: &Soa<2, L>,
        f1: &Soa<2, L>,
        bits: u64,
    ) -> u32 {
        let mut mask = bits as u32;
        let mut rest = (bits >> 32) as u32 & !mask;
        if rest != 0 {
            let d = self.rows[j].d;
            while rest != 0 {
                let l = rest.trailing_zeros() as usize;
                rest &= rest - 1;
                let h = t1[l] - t0[l];
                if self.no_event_by_midpoint(d, ln.sd[l], ln.sb[l], h, l, y0, f0, y1, f1) {
                    mask |= 1 << l;
                }
            }
        }
        mask
    }

    /// The RK4 step of every lane by the stages (the scalar integrator's arithmetic, so its
    /// results) on any table, affine or not; returns the lanes that take it, as
    /// [`Lockstep::step`]. For callers that need the state's scalar trajectory bit for bit (the
    /// Lyapunov lanes: the decisions that continue from their end state).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn step_stages<const L: usize>(
        &self,
        j: usize,
        t0: &[f64; L],
        t1: &[f64; L],
        grid: &[f64; L],
        ln: &MeshLaneBlock<L>,
        y0: &Soa<2, L>,
        f0: &Soa<2, L>,
        y1: &mut Soa<2, L>,
        f1: &mut Soa<2, L>,
    ) -> u32 {
        let bits = self.stage_bits(j, t0, t1, grid, ln, y0, f0, y1, f1);
        self.settle(j, t0, t1, ln, y0, f0, y1, f1, bits)
    }

    /// The affine step of every lane (see [`MeshLanes::kernel`] for the returned bits): in
    /// contact `y1 = P y0 + q_e + s q_o` from the lane's column of `w`, when separated the RK4
    /// step of `x'' = F + xi omega^2 cos` in closed form (`x0 + h v0 + h^2 (e0 + 2 em) / 6`,
    /// `v0 + h (e0 + 4 em + ee) / 6`, from the lane's constants and the row's cosine sums); then
    /// the end field and the interior bound. Coefficients at the exact grid phases, with the
    /// lane's nominal step (no rounded-time correction).
    ///
    /// The interior bound is taken over `x` alone: both guards of the states this map covers
    /// (`x -+ D`, drive or back contact and free flight of a bilateral linear law) depend on `x`
    /// only, so the Hermite deviation of `x'` cannot move them (the bound of the RK4 stage kernel
    /// and of the scalar integrator, over both components, is wider than they need here; it
    /// flagged for the scalar integrator steps that could hold no event). And one finiteness test:
    /// a finite end acceleration `F + xi w^2 cos - h_f (k (x - s D) + c x')` implies a finite
    /// `x` and `x'` (an infinite or NaN one makes it infinite or NaN, `0 * inf` included).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn affine_kernel<const L: usize>(
        &self,
        j: usize,
        t0: &[f64; L],
        t1: &[f64; L],
        ln: &MeshLaneBlock<L>,
        w: &AffineTables<L>,
        y0: &Soa<2, L>,
        y1: &mut Soa<2, L>,
        f1: &mut Soa<2, L>,
    ) -> u64 {
        let r = &self.rows[j];
        let e = &w.tab[j];
        let ce = r.cos[2];
        let [s0, s1] = r.sep;
        let (kke, hde, d) = (r.k[2], r.hd[2], r.d);
        // verdicts as lane bits, OR-reduced (as in the RK4 kernel): stays in registers
        let mut bits = [0u64; L];
        for l in 0..L {
            let (x0, v0) = (y0[0][l], y0[1][l]);
            let (sd, sb) = (ln.sd[l], ln.sb[l]);
            let s = sd - sb;
            let xc = e[0][l] * x0 + e[1][l] * v0 + (e[4][l] + s * e[6][l]);
            let vc = e[2][l] * x0 + e[3][l] * v0 + (e[5][l] + s * e[7][l]);
            let xs = x0 + w.sep[4][l] * v0 + (w.sep[0][l] + w.sep[1][l] * s0);
            let vs = v0 + (w.sep[2][l] + w.sep[3][l] * s1);
            let on = sd + sb;
            let contact = on > 0.0;
            let x1 = if contact { xc } else { xs };
            let v1 = if contact { vc } else { vs };
            let ee = kernel::excitation(ln.load[l], ln.xiw2[l], ce);
            // (bilateral: the affine map is taken only without the clamp)
            let fm = lane_contact(kke, s * d, ln.c[l], 0.0, 0.0).force(x1, v1, false);
            let a1 = kernel::acceleration(ee, on * hde, fm);
            y1[0][l] = x1;
            y1[1][l] = v1;
            f1[0][l] = v1;
            f1[1][l] = a1;
            let finite = a1.abs() < f64::INFINITY;
            // the interior bound over x (its derivative at the start is v0, at the end v1)
            let h = t1[l] - t0[l];
            let [_, _, r2, r3] = hermite(x0, x1, v0, v1, h);
            let margin = 0.25 * (r2.abs() + r3.abs());
            let (lo, hi) = (min_fast(x0, x1), max_fast(x0, x1));
            let ca = (lo - d > margin) | (hi - d < -margin);
            let cb = (lo + d > margin) | (hi + d < -margin);
            let clear = finite & ((sb != 0.0) | ca) & ((sd != 0.0) | cb);
            bits[l] = ((clear as u64) << l) | ((finite as u64) << (32 + l));
        }
        bits.iter().fold(0, |m, b| m | b)
    }

    /// The RK4 step of the tangent `(dx, dx')` of every lane on an affine table (see
    /// [`MeshLanes::is_affine`]): the variational equation `dx' = dx'`, `dx'' = a dx + b dx'` of
    /// a linear law is the state equation without its forcing, so in contact its RK4 step is the
    /// linear part `P` of the state's affine step (the same table column); when separated it is
    /// `(dx + h dx', dx')`. Also the end coefficients `(a, b)` (`-h_f k`, `-h_f c` in contact,
    /// zero when separated; `h_f` the friction factor), as the affine state step takes them.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn tangent_affine_step<const L: usize>(
        &self,
        j: usize,
        t0: &[f64; L],
        t1: &[f64; L],
        ln: &MeshLaneBlock<L>,
        w: &AffineTables<L>,
        d0: [&[f64; L]; 2],
        d1: [&mut [f64; L]; 2],
        ab: [&mut [f64; L]; 2],
    ) {
        debug_assert!(self.affine, "tangent_affine_step needs an affine table");
        let r = &self.rows[j];
        let e = &w.tab[j];
        let (kke, hde) = (r.k[2], r.hd[2]);
        let [dx1, dv1] = d1;
        let [a, b] = ab;
        for l in 0..L {
            let (dx, dv) = (d0[0][l], d0[1][l]);
            let contact = ln.sd[l] + ln.sb[l] > 0.0;
            let h = t1[l] - t0[l];
            let (xc, vc) = (e[0][l] * dx + e[1][l] * dv, e[2][l] * dx + e[3][l] * dv);
            dx1[l] = if contact { xc } else { dx + h * dv };
            dv1[l] = if contact { vc } else { dv };
            let hf = (ln.sd[l] + ln.sb[l]) * hde;
            (a[l], b[l]) = lane_contact(kke, 0.0, ln.c[l], 0.0, 0.0).tangent(hf, dx, dv, false);
        }
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
    /// (`MeshLanes::affine_kernel`), else the RK4 stages fused into one pass per lane (the whole
    /// step of a lane lives in registers; the loop over lanes vectorises) with the scalar
    /// model's operations in its order, so its results. Dispatches once per step to a copy of
    /// the stage kernel specialised for the table's contact clamp and stiffness form
    /// (`MeshLanes::kernel`).
    #[inline(always)]
    fn step(
        &self,
        j: usize,
        t0: &[f64; L],
        t1: &[f64; L],
        grid: &[f64; L],
        ln: &MeshLaneBlock<L>,
        work: &AffineTables<L>,
        y0: &Soa<2, L>,
        f0: &Soa<2, L>,
        y1: &mut Soa<2, L>,
        f1: &mut Soa<2, L>,
    ) -> u32 {
        let bits = if self.affine {
            self.affine_kernel::<L>(j, t0, t1, ln, work, y0, y1, f1)
        } else {
            self.stage_bits(j, t0, t1, grid, ln, y0, f0, y1, f1)
        };
        self.settle(j, t0, t1, ln, y0, f0, y1, f1, bits)
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

#[cfg(test)]
mod tests {
    use super::verdict;

    /// The verdict as the scalar integrator states it: each armed guard keeps its sign at both
    /// ends and both end values are farther from zero than the margin.
    #[allow(clippy::too_many_arguments)]
    fn direct(
        y0: [f64; 2],
        f0: [f64; 2],
        y1: [f64; 2],
        f1: [f64; 2],
        h: f64,
        d: f64,
        sd: f64,
        sb: f64,
    ) -> bool {
        let mut dev = 0.0f64;
        for i in 0..2 {
            let r1 = y1[i] - y0[i];
            let r2 = h * f0[i] - r1;
            let r3 = r1 - h * f1[i] - r2;
            dev = dev.max(r2.abs() + r3.abs());
        }
        let m = 0.25 * dev;
        let keeps = |a: f64, b: f64| ((a > 0.0) == (b > 0.0)) && a.abs().min(b.abs()) > m;
        let finite = y1.iter().chain(f1.iter()).all(|v| v.is_finite());
        finite
            && (sb != 0.0 || keeps(y0[0] - d, y1[0] - d))
            && (sd != 0.0 || keeps(y0[0] + d, y1[0] + d))
    }

    #[test]
    fn verdict_equals_the_direct_statement() {
        // a small deterministic generator (values near the surfaces, exact zeros, signed zeros)
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let d = 1.0;
        let picks = [
            -1.0,
            1.0,
            -0.0,
            0.0,
            1.0 + 1e-12,
            -1.0 - 1e-12,
            0.999_999,
            2.5,
            -3.0,
            // overflow of the step's sums, the smallest subnormal
            1e308,
            -1e308,
            f64::MAX,
            5e-324,
        ];
        let mut checked = 0;
        for _ in 0..200_000 {
            let mut v = [0.0; 8];
            for x in v.iter_mut() {
                let r = next();
                *x = if r % 3 == 0 {
                    picks[(r >> 8) as usize % picks.len()]
                } else {
                    ((r >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 4.0
                };
            }
            let (sd, sb) = match next() % 3 {
                0 => (1.0, 0.0),
                1 => (0.0, 1.0),
                _ => (0.0, 0.0),
            };
            let h = 1e-2 * (1 + next() % 4) as f64;
            let (y0, f0, y1, f1) = ([v[0], v[1]], [v[2], v[3]], [v[4], v[5]], [v[6], v[7]]);
            assert_eq!(
                verdict(y0, f0, y1, f1, h, d, sd, sb).0,
                direct(y0, f0, y1, f1, h, d, sd, sb),
                "{y0:?} {f0:?} {y1:?} {f1:?} {h} {sd} {sb}"
            );
            checked += 1;
        }
        assert_eq!(checked, 200_000);
        // a non-finite end is never clear
        let nan = f64::NAN;
        assert!(
            !verdict(
                [0.0, 0.0],
                [0.0, 0.0],
                [nan, 0.0],
                [0.0, 0.0],
                0.01,
                d,
                0.0,
                0.0
            )
            .0
        );
        assert!(
            !verdict(
                [0.0, 0.0],
                [0.0, 0.0],
                [0.0, 0.0],
                [0.0, f64::INFINITY],
                0.01,
                d,
                0.0,
                0.0
            )
            .1
        );
    }
}
