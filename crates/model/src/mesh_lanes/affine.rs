//! The affine map of the mesh lanes: where the contact law is linear, bilateral and without
//! friction asymmetry, one RK4 step of a lane is an affine map of its state fixed by the step
//! phase and the contact state; its coefficients are tabulated per lane ([`AffineTables`]) and a
//! step becomes a 2 x 2 multiply-add (see the module doc of [`super`]).

use super::stages::{max_fast, min_fast};
use super::{lane_contact, MeshLane, MeshLaneBlock, MeshLanes};
use crate::mesh_kernel as kernel;
use geardyn_solvers::dense::hermite;
use geardyn_solvers::ensemble::{Soa, StepStart};

/// Largest table (steps per strobe period) stepped by the affine map: 8 coefficients per lane
/// and step must stay in the core's cache (16 lanes x 1024 steps x 64 bytes = 1 MiB).
pub(super) const AFFINE_MAX_STEPS: usize = 1024;

/// Per-engine tables of the affine step ([`MeshLanes`] with the affine map): for every step `j`
/// and lane `l`, the RK4 step of the lane's linear contact equation as `y1 = P y0 + q_e + s q_o`
/// (`s = +1` in drive contact, `-1` in back contact): `tab[j][c][l]` with `c` = `P00, P01, P10,
/// P11, q_e0, q_e1, q_o0, q_o1` (`q_e` the response to the excitation and load, `q_o` to the
/// backlash offset). Each lane's column is built when the lane's constants or step change
/// ([`Lockstep::set_lane`](geardyn_solvers::ensemble::Lockstep::set_lane)).
#[derive(Clone, Debug)]
pub struct AffineTables<const L: usize> {
    /// The constants each lane's column was built for (`omega`, `c`, `F`, `xi omega^2`, `h`);
    /// NaN: none.
    pub(super) key: [[f64; 5]; L],
    pub(super) tab: Vec<[[f64; L]; 8]>,
    /// Per lane, the RK4 step of free flight `x'' = F + xi omega^2 cos` with the lane's step `h`:
    /// `x1 = x0 + h v0 + sep[0] + sep[1] s0_j`, `v1 = v0 + sep[2] + sep[3] s1_j` (`s0_j`, `s1_j`
    /// the step's cosine sums of [`Row`]): `h^2 F / 2`, `h^2 xi omega^2 / 6`, `h F`,
    /// `h xi omega^2 / 6`; and `h` itself (`sep[4]`).
    pub(super) sep: [[f64; L]; 5],
}

impl MeshLanes {
    /// Builds lane `l`'s column of the affine tables for the constants `ln` and step `h`: per
    /// step, the RK4 step of `x' = v`, `v' = a x + b v + g` (`a = -h_f k`, `b = -h_f c` at the
    /// start, middle and end of the step, from the tables at the exact grid phases) applied to
    /// the unit states (the columns of `P`), and to the zero state with the forcing
    /// `g = F + xi omega^2 cos` (`q_e`) and `g = h_f k D` (`q_o`, the backlash offset).
    pub(super) fn build_column<const L: usize>(
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

    /// The affine step of every lane (bit `l`: lane `l`'s step is finite and clears both guards by the interior bound; bit `32 + l`: it is finite): in
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
    #[inline(always)]
    pub(super) fn affine_kernel<const L: usize>(
        &self,
        s: &StepStart<'_, 2, L>,
        ln: &MeshLaneBlock<L>,
        w: &AffineTables<L>,
        y1: &mut Soa<2, L>,
        f1: &mut Soa<2, L>,
    ) -> u64 {
        let StepStart { j, t0, t1, y0, .. } = *s;
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
    /// zero when separated; `h_f` the friction factor), as the affine state step takes them. Of
    /// the step `s` it reads the phase and the times (the tangent's start is `d0`).
    #[inline(always)]
    pub fn tangent_affine_step<const L: usize>(
        &self,
        s: &StepStart<'_, 2, L>,
        ln: &MeshLaneBlock<L>,
        w: &AffineTables<L>,
        d0: [&[f64; L]; 2],
        d1: [&mut [f64; L]; 2],
        ab: [&mut [f64; L]; 2],
    ) {
        let StepStart { j, t0, t1, .. } = *s;
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
}
