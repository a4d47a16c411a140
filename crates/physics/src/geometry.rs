//! Involute geometry of external and internal spur pairs (docs/model.md §1–2).
//!
//! SI units inside (metres, radians). Positions on the line of action (LoA) are distances `s`
//! from the pinion's tangency point `N1`, increasing in the direction of approach → recess:
//! contact starts at `A` (gear/ring tip meets the pinion flank) and ends at `D` (pinion tip).
//! The healthy mesh cycle has phase `phi` in `[0, 1)`: the pair entering at `phi = 0` sits at
//! `s = s_A + phi*p_b`, the pair ahead of it at `s + p_b` while `s + p_b <= s_D`.
//!
//! Profile-shift conventions: external gears as ISO 21771 (`x > 0` thickens the tooth). For the
//! internal (ring) gear, `x2 > 0` moves the ring's profile outward, which *thins* its teeth
//! (thickness `pi m/2 - 2 x2 m tan(alpha)` on the reference circle), so that
//! `inv(alpha_w) = inv(alpha) + 2 tan(alpha) (x2 - x1)/(z2 - z1)`.

use crate::error::PhysicsError;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// External pair or internal (pinion inside a ring) pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PairKind {
    /// Two external gears.
    External,
    /// Pinion meshing inside a ring gear.
    Internal,
}

/// Involute function `inv(a) = tan(a) - a`.
pub fn inv(a: f64) -> f64 {
    a.tan() - a
}

/// Inverse of the involute function on `[0, pi/2)` (Newton from a cube-root start).
pub fn inv_inverse(v: f64) -> f64 {
    let mut a = (3.0 * v).cbrt().min(1.5);
    for _ in 0..50 {
        let f = inv(a) - v;
        let df = a.tan().powi(2);
        if df == 0.0 {
            break;
        }
        let step = f / df;
        a -= step;
        if step.abs() < 1e-15 {
            break;
        }
    }
    a
}

/// Input geometry of a pair (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairGeometryInput {
    /// External or internal pair.
    pub kind: PairKind,
    /// Pinion teeth `z1`.
    pub z1: u32,
    /// Gear (or ring) teeth `z2`.
    pub z2: u32,
    /// Module `m` (m).
    pub module: f64,
    /// Reference pressure angle `alpha` (rad).
    pub pressure_angle: f64,
    /// Addendum coefficient `ha*`.
    pub addendum: f64,
    /// Tip-clearance coefficient `c*`.
    pub clearance: f64,
    /// Profile shift of the pinion `x1`.
    pub x1: f64,
    /// Profile shift of the gear/ring `x2`.
    pub x2: f64,
}

/// Derived geometry of a pair (SI units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PairGeometry {
    /// External or internal.
    pub kind: PairKind,
    /// Pinion teeth.
    pub z1: u32,
    /// Gear teeth.
    pub z2: u32,
    /// Module (m).
    pub module: f64,
    /// Reference pressure angle (rad).
    pub alpha: f64,
    /// Pitch radii (m).
    pub r1: f64,
    /// Pitch radius of the gear/ring (m).
    pub r2: f64,
    /// Base radius of the pinion (m).
    pub rb1: f64,
    /// Base radius of the gear/ring (m).
    pub rb2: f64,
    /// Tip radius of the pinion (m).
    pub ra1: f64,
    /// Tip radius of the gear/ring (m) (inner radius of a ring's teeth).
    pub ra2: f64,
    /// Root radius of the pinion (m).
    pub rf1: f64,
    /// Root radius of the gear/ring (m).
    pub rf2: f64,
    /// Operating pressure angle (rad).
    pub alpha_w: f64,
    /// Operating centre distance (m).
    pub a_w: f64,
    /// Base pitch `p_b = pi m cos(alpha)` (m).
    pub pb: f64,
    /// Distance `N1N2` between the tangency points (m).
    pub n1n2: f64,
    /// Start of contact `A` (m from `N1`).
    pub s_a: f64,
    /// End of contact `D` (m from `N1`).
    pub s_d: f64,
    /// Pitch point `P` (m from `N1`).
    pub s_p: f64,
    /// Transverse contact ratio.
    pub eps: f64,
    /// Half tooth angle of the pinion on its base circle (rad).
    pub half_base_angle1: f64,
    /// Half tooth angle of the gear on its base circle (external) or, for a ring, the constant
    /// `beta` of its tooth half-angle `beta + inv(alpha_r)` at radius `r` (rad).
    pub half_base_angle2: f64,
    /// Profile shift of the pinion.
    pub x1: f64,
    /// Profile shift of the gear/ring.
    pub x2: f64,
}

/// Undercut of gear `n` (`which`: pinion or gear) of `z` teeth and profile shift `x` in rack
/// generation: `z sin^2(alpha) / 2 >= ha* - x` is needed.
fn undercut(
    which: &str,
    n: u32,
    z: u32,
    x: f64,
    addendum: f64,
    al: f64,
) -> Result<(), PhysicsError> {
    let x_min = addendum - z as f64 * al.sin().powi(2) / 2.0;
    if x < x_min - 1e-9 {
        return Err(PhysicsError::Geometry(format!(
            "{which} undercut: z{n} = {z} with x{n} = {x} needs x{n} >= {x_min:.4} (short by {:.4})",
            x_min - x
        )));
    }
    Ok(())
}

fn bad(field: &str, value: f64, allowed: &str) -> PhysicsError {
    PhysicsError::Invalid {
        field: field.to_string(),
        value,
        allowed: allowed.to_string(),
    }
}

impl PairGeometry {
    /// Computes the geometry and rejects impossible pairs with an error saying what and by how
    /// much.
    ///
    /// ```
    /// use geardyn_physics::geometry::{PairGeometry, PairGeometryInput, PairKind};
    /// let g = PairGeometry::new(&PairGeometryInput {
    ///     kind: PairKind::External, z1: 40, z2: 40, module: 3e-3, pressure_angle: 20f64.to_radians(),
    ///     addendum: 1.0, clearance: 0.25, x1: 0.0, x2: 0.0,
    /// }).unwrap();
    /// assert!((g.eps - 1.7145).abs() < 1e-3);
    /// ```
    pub fn new(i: &PairGeometryInput) -> Result<Self, PhysicsError> {
        let m = i.module;
        if !(m > 0.0 && m < 1.0) {
            return Err(bad("module", m * 1e3, "(0, 1000) mm"));
        }
        let al = i.pressure_angle;
        if !(al > 10f64.to_radians() && al < 35f64.to_radians()) {
            return Err(bad("pressure_angle", al.to_degrees(), "(10, 35) deg"));
        }
        if !(i.addendum > 0.3 && i.addendum < 2.0) {
            return Err(bad("addendum", i.addendum, "(0.3, 2)"));
        }
        if !(i.clearance >= 0.0 && i.clearance < 1.0) {
            return Err(bad("clearance", i.clearance, "[0, 1)"));
        }
        for (f, x) in [("x1", i.x1), ("x2", i.x2)] {
            if !(x > -1.0 && x < 1.5) {
                return Err(bad(f, x, "(-1, 1.5)"));
            }
        }
        if i.z1 < 6 {
            return Err(bad("z1", i.z1 as f64, "an integer >= 6"));
        }
        let (z1, z2) = (i.z1 as f64, i.z2 as f64);
        let r1 = m * z1 / 2.0;
        let r2 = m * z2 / 2.0;
        let rb1 = r1 * al.cos();
        let rb2 = r2 * al.cos();
        let pb = PI * m * al.cos();
        let ra1 = r1 + m * (i.addendum + i.x1);
        let rf1 = r1 - m * (i.addendum + i.clearance - i.x1);
        let half1 = PI / (2.0 * z1) + inv(al) + 2.0 * i.x1 * al.tan() / z1;
        undercut("pinion", 1, i.z1, i.x1, i.addendum, al)?;
        let (ra2, rf2, alpha_w, a_w, half2, n1n2, s_a, s_d);
        match i.kind {
            PairKind::External => {
                if i.z2 < 6 {
                    return Err(bad("z2", z2, "an integer >= 6"));
                }
                undercut("gear", 2, i.z2, i.x2, i.addendum, al)?;
                ra2 = r2 + m * (i.addendum + i.x2);
                rf2 = r2 - m * (i.addendum + i.clearance - i.x2);
                alpha_w = inv_inverse(inv(al) + 2.0 * al.tan() * (i.x1 + i.x2) / (z1 + z2));
                a_w = (rb1 + rb2) / alpha_w.cos();
                half2 = PI / (2.0 * z2) + inv(al) + 2.0 * i.x2 * al.tan() / z2;
                n1n2 = a_w * alpha_w.sin();
                s_a = n1n2 - (ra2 * ra2 - rb2 * rb2).sqrt();
                s_d = (ra1 * ra1 - rb1 * rb1).sqrt();
            }
            PairKind::Internal => {
                // tooth-number difference below ~10 gives tip fouling for 20 deg full-depth teeth
                if i.z2 < i.z1 + 10 {
                    return Err(PhysicsError::Geometry(format!(
                        "internal pair z2 - z1 = {} is below 10: tip interference (fouling) between pinion and ring tips",
                        i.z2 as i64 - i.z1 as i64
                    )));
                }
                ra2 = r2 - m * (i.addendum - i.x2);
                rf2 = r2 + m * (i.addendum + i.clearance + i.x2);
                if ra2 <= rb2 {
                    return Err(PhysicsError::Geometry(format!(
                        "ring tip radius {:.4} mm lies inside its base circle {:.4} mm: non-involute ring tip",
                        ra2 * 1e3,
                        rb2 * 1e3
                    )));
                }
                alpha_w = inv_inverse(inv(al) + 2.0 * al.tan() * (i.x2 - i.x1) / (z2 - z1));
                a_w = (rb2 - rb1) / alpha_w.cos();
                // ring tooth half-angle at radius r: beta + inv(alpha_r)
                half2 = PI / (2.0 * z2) - inv(al) - 2.0 * i.x2 * al.tan() / z2;
                n1n2 = a_w * alpha_w.sin();
                s_a = (ra2 * ra2 - rb2 * rb2).sqrt() - n1n2;
                s_d = (ra1 * ra1 - rb1 * rb1).sqrt();
            }
        }
        let s_p = rb1 * alpha_w.tan();
        if s_a <= 0.0 {
            return Err(PhysicsError::Geometry(format!(
                "tip interference: contact would start {:.4} mm before the pinion's tangency point N1 (gear tip cuts the pinion root)",
                -s_a * 1e3
            )));
        }
        if i.kind == PairKind::External && s_d >= n1n2 {
            return Err(PhysicsError::Geometry(format!(
                "tip interference: the pinion tip passes the gear's tangency point N2 by {:.4} mm",
                (s_d - n1n2) * 1e3
            )));
        }
        let eps = (s_d - s_a) / pb;
        // tooth tip must not be pointed
        let tip_half = half1 - inv((rb1 / ra1).acos());
        if tip_half <= 0.0 {
            return Err(PhysicsError::Geometry(format!(
                "pinion teeth are pointed (tip thickness {:.4} mm): reduce the addendum or the profile shift",
                2.0 * ra1 * tip_half * 1e3
            )));
        }
        Ok(PairGeometry {
            kind: i.kind,
            z1: i.z1,
            z2: i.z2,
            module: m,
            alpha: al,
            r1,
            r2,
            rb1,
            rb2,
            ra1,
            ra2,
            rf1,
            rf2,
            alpha_w,
            a_w,
            pb,
            n1n2,
            s_a,
            s_d,
            s_p,
            eps,
            half_base_angle1: half1,
            half_base_angle2: half2,
            x1: i.x1,
            x2: i.x2,
        })
    }

    /// Requires `1 < eps < 2` (the two-zone mesh model of docs/model.md §2).
    pub fn check_two_zone(&self) -> Result<(), PhysicsError> {
        if !(self.eps > 1.0 && self.eps < 2.0) {
            return Err(PhysicsError::Geometry(format!(
                "contact ratio {:.4} outside (1, 2): the double/single-zone model needs 1 < eps < 2",
                self.eps
            )));
        }
        Ok(())
    }

    /// Roll angle of the pinion flank at LoA position `s` (`u1 = s/r_b1`).
    pub fn roll_pinion(&self, s: f64) -> f64 {
        s / self.rb1
    }

    /// Roll angle of the gear/ring flank at LoA position `s`.
    pub fn roll_gear(&self, s: f64) -> f64 {
        match self.kind {
            PairKind::External => (self.n1n2 - s) / self.rb2,
            PairKind::Internal => (self.n1n2 + s) / self.rb2,
        }
    }

    /// LoA position of a point of the pinion flank at radius `r` (for a broken tip radius, `D1`).
    pub fn s_at_pinion_radius(&self, r: f64) -> f64 {
        (r * r - self.rb1 * self.rb1).max(0.0).sqrt()
    }

    /// Friction arms `(S_p, S_g)` at LoA position `s`: distances from the contact point to the
    /// tangency points `N1`, `N2` (the moment arms of a friction force about the gear centres).
    pub fn friction_arms(&self, s: f64) -> (f64, f64) {
        match self.kind {
            PairKind::External => (s, self.n1n2 - s),
            PairKind::Internal => (s, self.n1n2 + s),
        }
    }

    /// Sliding direction `lambda` at LoA position `s`: `-1` in approach (before the pitch point,
    /// friction assists the pinion), `+1` in recess (derived in the module doc of `friction`).
    pub fn sliding_direction(&self, s: f64) -> f64 {
        if s < self.s_p {
            -1.0
        } else {
            1.0
        }
    }
}
