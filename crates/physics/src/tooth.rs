//! Potential-energy compliance of one tooth (Yang & Lin 1987; Tian 2004; fillet foundation of
//! Sainsot, Velex & Duverger 2004), for external teeth and for the internal teeth of a ring.
//!
//! The tooth is a cantilever along its centreline, from the root circle to the contact point.
//! A unit force along the line of action at the contact point `P` produces, at the section of
//! centreline height `y` (half thickness `h(y)`, area `A = 2hB`, inertia `I = (2h)^3 B/12`), the
//! moment `M = x_P n_y - (y_P - y) n_x`, the shear `V = n_x` and the normal force `N = n_y`. The
//! compliances are
//!
//! `1/k_b = ∫ M²/(E I) dy`, `1/k_s = ∫ 1.2 V²/(G A) dy`, `1/k_a = ∫ N²/(E A) dy`.
//!
//! The involute part is parametrised by its roll angle `u` (exact), the part between a root circle
//! below the base circle and the base circle by a radial line (the usual "improved" model). For
//! an external tooth this reproduces Tian's closed-form integrals exactly (a test checks it).
//! Quadrature: 48-point Gauss–Legendre per part (integrands are smooth; converged to < 1e-10).
//!
//! The fillet-foundation compliance is Sainsot's
//! `1/k_f = cos²(a_m)/(E B) [L*(u_f/S_f)² + M*(u_f/S_f) + P*(1 + Q* tan²(a_m))]`
//! with `a_m` the angle between the force and the normal to the centreline, `u_f` the distance
//! from the root circle to where the force line meets the centreline, `S_f = 2 r_f theta_f` and
//! `L*, M*, P*, Q*` the polynomial fits of Sainsot et al. (J. Mech. Des. 126 (2004) 748) in
//! `h_f = r_f/r_int` and `theta_f`. For a ring tooth the formula is applied with
//! `h_f = r_rim/r_f` (rim outer radius over root radius) — an approximation: Sainsot's fit is for
//! external gear bodies.

use gauss_quad::GaussLegendre;
use std::sync::OnceLock;

fn gl() -> &'static GaussLegendre {
    static GL: OnceLock<GaussLegendre> = OnceLock::new();
    GL.get_or_init(|| GaussLegendre::new(48).expect("48-point Gauss-Legendre"))
}

/// Material and face width.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Young's modulus (Pa).
    pub e: f64,
    /// Poisson's ratio.
    pub nu: f64,
    /// Face width (m).
    pub b: f64,
}

impl Material {
    /// Shear modulus `G = E/(2(1+nu))`.
    pub fn g(&self) -> f64 {
        self.e / (2.0 * (1.0 + self.nu))
    }
}

/// Tooth shape for the energy integrals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToothShape {
    /// External tooth: half tooth angle on the base circle `half_base`, base radius `rb`, root
    /// radius `rf`, bore radius `r_int`.
    External {
        /// Half tooth angle on the base circle (rad).
        half_base: f64,
        /// Base radius (m).
        rb: f64,
        /// Root radius (m).
        rf: f64,
        /// Bore radius (m).
        r_int: f64,
    },
    /// Ring tooth: half tooth angle `beta + inv(alpha_r)` at radius `r`; base radius `rb`, root
    /// radius `rf` (outer), rim outer radius `r_rim`.
    Ring {
        /// Constant `beta` (rad).
        beta: f64,
        /// Base radius (m).
        rb: f64,
        /// Root radius (m).
        rf: f64,
        /// Rim outer radius (m).
        r_rim: f64,
    },
}

/// Compliance components of one tooth for a unit force at the contact point (m/N).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Compliance {
    /// Bending.
    pub bending: f64,
    /// Shear.
    pub shear: f64,
    /// Axial compression.
    pub axial: f64,
    /// Fillet foundation.
    pub foundation: f64,
}

impl Compliance {
    /// Sum of the components.
    pub fn total(&self) -> f64 {
        self.bending + self.shear + self.axial + self.foundation
    }
}

/// Sainsot et al. (2004) coefficients `[A, B, C, D, E, F]` of `L*, M*, P*, Q*`:
/// `X* = A/theta_f² + B h_f² + C h_f/theta_f + D/theta_f + E h_f + F`.
pub const SAINSOT: [[f64; 6]; 4] = [
    [-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045],
    [60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086],
    [-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236],
    [
        -6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904,
    ],
];

/// Sainsot's fillet-foundation compliance (see module doc).
pub fn foundation_compliance(
    mat: &Material,
    alpha_m: f64,
    u_f: f64,
    s_f: f64,
    h_f: f64,
    theta_f: f64,
) -> f64 {
    let x: Vec<f64> = SAINSOT
        .iter()
        .map(|c| {
            c[0] / (theta_f * theta_f)
                + c[1] * h_f * h_f
                + c[2] * h_f / theta_f
                + c[3] / theta_f
                + c[4] * h_f
                + c[5]
        })
        .collect();
    let r = u_f / s_f;
    alpha_m.cos().powi(2) / (mat.e * mat.b)
        * (x[0] * r * r + x[1] * r + x[2] * (1.0 + x[3] * alpha_m.tan().powi(2)))
}

/// Geometry of a profile point: position `(x, y)` (x across, y along the centreline), force
/// direction `n` (unit), and `dy/du`.
#[inline]
fn profile(shape: &ToothShape, u: f64) -> ([f64; 2], [f64; 2], f64) {
    match *shape {
        ToothShape::External { half_base, rb, .. } => {
            let th = half_base - u;
            let (s, c) = th.sin_cos();
            ([rb * (s + u * c), rb * (c - u * s)], [c, -s], rb * u * c)
        }
        ToothShape::Ring { beta, rb, .. } => {
            let th = beta + u;
            let (s, c) = th.sin_cos();
            ([rb * (s - u * c), rb * (c + u * s)], [c, -s], rb * u * c)
        }
    }
}

/// Compliance of the tooth for contact at roll angle `u_k` of its flank.
///
/// ```
/// use geardyn_physics::tooth::{tooth_compliance, Material, ToothShape};
/// let mat = Material { e: 2.06e11, nu: 0.3, b: 0.02 };
/// let shape = ToothShape::External { half_base: 0.0755, rb: 0.0564, rf: 0.05625, r_int: 0.02 };
/// let c = tooth_compliance(&shape, &mat, 0.3);
/// assert!(c.bending > 0.0 && c.shear > 0.0 && c.axial > 0.0 && c.foundation > 0.0);
/// ```
pub fn tooth_compliance(shape: &ToothShape, mat: &Material, u_k: f64) -> Compliance {
    let (p, n, _) = profile(shape, u_k);
    let (e, g, b) = (mat.e, mat.g(), mat.b);
    let integrand = |y: f64, h: f64| -> (f64, f64, f64) {
        let m = p[0] * n[1] - (p[1] - y) * n[0];
        let a = 2.0 * h * b;
        let i = (2.0 * h).powi(3) * b / 12.0;
        (
            m * m / (e * i),
            1.2 * n[0] * n[0] / (g * a),
            n[1] * n[1] / (e * a),
        )
    };
    let mut comp = Compliance::default();
    let mut add = |(kb, ks, ka): (f64, f64, f64), w: f64| {
        comp.bending += kb * w;
        comp.shear += ks * w;
        comp.axial += ka * w;
    };
    let rule = gl();
    let (rf, rb) = match *shape {
        ToothShape::External { rf, rb, .. } | ToothShape::Ring { rf, rb, .. } => (rf, rb),
    };
    match *shape {
        ToothShape::External { half_base, .. } => {
            // involute from max(rb, rf) up to the contact point
            let u0 = if rf > rb {
                (rf * rf / (rb * rb) - 1.0).sqrt()
            } else {
                0.0
            };
            for (x, w) in rule.nodes().zip(rule.weights()) {
                let u = u0 + (u_k - u0) * 0.5 * (x + 1.0);
                let (q, _, dy) = profile(shape, u);
                add(integrand(q[1], q[0]), w * 0.5 * (u_k - u0) * dy);
            }
            if rf < rb {
                // radial flank from the root circle to the base circle
                let (s, c) = half_base.sin_cos();
                for (x, w) in rule.nodes().zip(rule.weights()) {
                    let r = rf + (rb - rf) * 0.5 * (x + 1.0);
                    add(integrand(r * c, r * s), w * 0.5 * (rb - rf) * c);
                }
            }
        }
        ToothShape::Ring { .. } => {
            // involute from the contact point out to the root circle (the ring tooth's root)
            let u_root = (rf * rf / (rb * rb) - 1.0).sqrt();
            for (x, w) in rule.nodes().zip(rule.weights()) {
                let u = u_k + (u_root - u_k) * 0.5 * (x + 1.0);
                let (q, _, dy) = profile(shape, u);
                add(integrand(q[1], q[0]), w * 0.5 * (u_root - u_k) * dy);
            }
        }
    }
    // fillet foundation
    let alpha_m = n[1].abs().atan2(n[0].abs());
    let y_int = p[1] - p[0] * (n[1] / n[0]);
    let (u_f, theta_f, h_f) = match *shape {
        ToothShape::External {
            half_base,
            rb,
            rf,
            r_int,
        } => {
            let theta_f = if rf < rb {
                half_base
            } else {
                half_base - crate::geometry::inv((rb / rf).acos())
            };
            (y_int - rf, theta_f, rf / r_int)
        }
        ToothShape::Ring {
            beta,
            rb,
            rf,
            r_rim,
        } => {
            let theta_f = beta + crate::geometry::inv((rb / rf).acos());
            (rf - y_int, theta_f, r_rim / rf)
        }
    };
    comp.foundation = foundation_compliance(mat, alpha_m, u_f, 2.0 * rf * theta_f, h_f, theta_f);
    comp
}

/// Hertzian contact compliance of Yang & Lin (1987), constant along the path of contact:
/// `1/k_h = 4(1 - nu²)/(pi E B)`.
pub fn hertz_compliance(mat: &Material) -> f64 {
    4.0 * (1.0 - mat.nu * mat.nu) / (std::f64::consts::PI * mat.e * mat.b)
}

/// Load-dependent (nonlinear) Hertzian compliance of Chen & Shao (2011):
/// `k_h = E^0.9 B^0.8 F^0.1 / 1.275` (SI units, `F` the pair's normal load in N).
pub fn hertz_compliance_nonlinear(mat: &Material, load: f64) -> f64 {
    1.275 / (mat.e.powf(0.9) * mat.b.powf(0.8) * load.max(1e-9).powf(0.1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::inv;

    /// Tian (2004) closed forms in the angle variable `a` from `-alpha1` to `alpha2`
    /// (Wu, Zuo & Parey, J. Sound Vib. 317 (2008) 608, eqs. 4–6), integrated by a different rule.
    fn tian(alpha1: f64, alpha2: f64, mat: &Material) -> (f64, f64, f64) {
        let n = 20_000;
        let (e, g, b) = (mat.e, mat.g(), mat.b);
        let (mut kb, mut ks, mut ka) = (0.0, 0.0, 0.0);
        let h = (alpha2 + alpha1) / n as f64;
        for i in 0..=n {
            let a = -alpha1 + i as f64 * h;
            let w = if i == 0 || i == n { 0.5 } else { 1.0 } * h;
            let d = a.sin() + (alpha2 - a) * a.cos();
            let c1 = alpha1.cos();
            kb += w
                * 3.0
                * (1.0 + c1 * ((alpha2 - a) * a.sin() - a.cos())).powi(2)
                * (alpha2 - a)
                * a.cos()
                / (2.0 * e * b * d.powi(3));
            ks += w * 1.2 * (1.0 + mat.nu) * (alpha2 - a) * a.cos() * c1 * c1 / (e * b * d);
            ka += w * (alpha2 - a) * a.cos() * alpha1.sin().powi(2) / (2.0 * e * b * d);
        }
        let _ = g;
        (kb, ks, ka)
    }

    /// A steel tooth of an external gear of `z` teeth, m = 3 mm, 20 degrees, 20 mm wide: its
    /// material, its shape with the root radius `rf(rb, r)` (`r` the pitch radius) and the bore
    /// `r_int`, and its half base angle.
    fn external(z: f64, rf: impl Fn(f64, f64) -> f64, r_int: f64) -> (Material, ToothShape, f64) {
        let (m, al) = (3e-3f64, 20f64.to_radians());
        let rb = m * z / 2.0 * al.cos();
        let half = std::f64::consts::PI / (2.0 * z) + inv(al);
        let mat = Material {
            e: 2e11,
            nu: 0.3,
            b: 0.02,
        };
        let shape = ToothShape::External {
            half_base: half,
            rb,
            rf: rf(rb, m * z / 2.0),
            r_int,
        };
        (mat, shape, half)
    }

    #[test]
    fn involute_part_reproduces_tian_closed_forms() {
        // 20 teeth, m = 3 mm, alpha = 20 deg, root circle above the base circle avoided by
        // putting it at the base circle (Tian's model has no part below the base circle)
        let (mat, shape, half) = external(20.0, |rb, _| rb, 0.01);
        for u_k in [0.2, 0.35, 0.5] {
            let c = tooth_compliance(&shape, &mat, u_k);
            let alpha1 = u_k - half;
            let (kb, ks, ka) = tian(alpha1, half, &mat);
            assert!(
                (c.bending / kb - 1.0).abs() < 1e-6,
                "bending {} vs {}",
                c.bending,
                kb
            );
            assert!(
                (c.shear / ks - 1.0).abs() < 1e-6,
                "shear {} vs {}",
                c.shear,
                ks
            );
            assert!(
                (c.axial / ka - 1.0).abs() < 1e-6,
                "axial {} vs {}",
                c.axial,
                ka
            );
        }
    }

    #[test]
    fn hertz_closed_form() {
        // Yang & Lin: k_h = pi E B / (4 (1 - nu^2)); E = 206 GPa, B = 20 mm -> 3.556e9 N/m
        let mat = Material {
            e: 2.06e11,
            nu: 0.3,
            b: 0.02,
        };
        let k = 1.0 / hertz_compliance(&mat);
        assert!((k - std::f64::consts::PI * 2.06e11 * 0.02 / (4.0 * 0.91)).abs() < 1.0);
        assert!((k / 3.5559e9 - 1.0).abs() < 1e-4, "{k}");
        // the nonlinear law stiffens with load as F^0.1
        let k1 = 1.0 / hertz_compliance_nonlinear(&mat, 1000.0);
        let k2 = 1.0 / hertz_compliance_nonlinear(&mat, 1000.0 * 2f64.powi(10));
        assert!((k2 / k1 - 2.0).abs() < 1e-12);
    }

    #[test]
    fn compliance_grows_towards_the_tip() {
        let (mat, shape, _) = external(40.0, |_, r| r - 1.25 * 3e-3, 0.02);
        let mut last = 0.0;
        for u in [0.15, 0.25, 0.35, 0.45] {
            let c = tooth_compliance(&shape, &mat, u);
            assert!(c.bending > last);
            last = c.bending;
        }
    }
}
