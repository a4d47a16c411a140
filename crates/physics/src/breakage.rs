//! Localized tooth breakage (docs/model.md §2): one pinion tooth with its tip chipped off leaves mesh
//! early at `D1`, at the LoA position of its reduced tip radius `R_ab`.
//! `eps_b = l_AD1 / p_b` with `l_AD1 = s_D1 - s_A` (seed A eq. 2, written from `N1`).

use crate::error::PhysicsError;
use crate::geometry::PairGeometry;

/// Severity of a chipped pinion tip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Chip {
    /// Removed height from the tip, radially (m).
    RemovedHeight(f64),
    /// Remaining (broken) tip radius `R_ab` (m).
    TipRadius(f64),
}

/// Reduced contact ratio `eps_b` and the end of contact `s_D1` (m from `N1`) of the broken tooth.
///
/// ```
/// use geardyn_physics::breakage::{broken_contact, Chip};
/// use geardyn_physics::geometry::{PairGeometry, PairGeometryInput, PairKind};
/// let g = PairGeometry::new(&PairGeometryInput { kind: PairKind::External, z1: 40, z2: 40,
///     module: 3e-3, pressure_angle: 20f64.to_radians(), addendum: 1.0, clearance: 0.25, x1: 0.0, x2: 0.0 }).unwrap();
/// let (eps_b, _) = broken_contact(&g, Chip::RemovedHeight(1e-3)).unwrap();
/// assert!(eps_b < g.eps && eps_b > 1.0);
/// ```
pub fn broken_contact(g: &PairGeometry, chip: Chip) -> Result<(f64, f64), PhysicsError> {
    let r_ab = match chip {
        Chip::RemovedHeight(h) => {
            if !(h >= 0.0 && h < g.ra1 - g.rb1) {
                return Err(PhysicsError::Invalid {
                    field: "breakage.removed_height_mm".into(),
                    value: h * 1e3,
                    allowed: format!(
                        "[0, {:.4}) mm (tip radius minus base radius)",
                        (g.ra1 - g.rb1) * 1e3
                    ),
                });
            }
            g.ra1 - h
        }
        Chip::TipRadius(r) => {
            if !(r > g.rb1 && r <= g.ra1) {
                return Err(PhysicsError::Invalid {
                    field: "breakage.tip_radius_mm".into(),
                    value: r * 1e3,
                    allowed: format!(
                        "({:.4}, {:.4}] mm (base to tip radius)",
                        g.rb1 * 1e3,
                        g.ra1 * 1e3
                    ),
                });
            }
            r
        }
    };
    let s_d1 = g.s_at_pinion_radius(r_ab);
    let eps_b = (s_d1 - g.s_a) / g.pb;
    if !(eps_b > 1.0) {
        return Err(PhysicsError::Geometry(format!(
            "the chip leaves a contact ratio eps_b = {eps_b:.4} <= 1 for the broken tooth: the pair would lose contact (reduce the chip by {:.4} mm)",
            (g.s_a + g.pb - s_d1) * 1e3
        )));
    }
    Ok((eps_b, s_d1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{PairGeometryInput, PairKind};

    fn pair() -> PairGeometry {
        PairGeometry::new(&PairGeometryInput {
            kind: PairKind::External,
            z1: 40,
            z2: 40,
            module: 3e-3,
            pressure_angle: 20f64.to_radians(),
            addendum: 1.0,
            clearance: 0.25,
            x1: 0.0,
            x2: 0.0,
        })
        .unwrap()
    }

    #[test]
    fn eps_b_below_eps_and_tends_to_it() {
        let g = pair();
        let mut last = 0.0;
        for h in [1.2e-3, 0.8e-3, 0.4e-3, 0.1e-3, 1e-7, 0.0] {
            let (eb, _) = broken_contact(&g, Chip::RemovedHeight(h)).unwrap();
            assert!(eb <= g.eps + 1e-12 && eb > last);
            last = eb;
        }
        assert!((last - g.eps).abs() < 1e-12);
        // seed A eq. (2): l_AD1 = R_bp (tan a_ab - tan a) - R_bg tan a + sqrt(R_ag^2 - R_bg^2)
        // (their "R_bg tan a" term is the path from N2 to the pitch point; written for 40/40)
        let r_ab = g.ra1 - 1e-3;
        let a_ab = (g.rb1 / r_ab).acos();
        let l_ad1 = g.rb1 * (a_ab.tan() - g.alpha_w.tan()) - g.rb2 * g.alpha_w.tan()
            + (g.ra2 * g.ra2 - g.rb2 * g.rb2).sqrt();
        let (eb, _) = broken_contact(&g, Chip::TipRadius(r_ab)).unwrap();
        assert!(
            (eb - l_ad1 / g.pb).abs() < 1e-12,
            "{eb} vs {}",
            l_ad1 / g.pb
        );
    }

    #[test]
    fn too_large_chip_is_rejected_with_the_field() {
        let g = pair();
        let e = broken_contact(&g, Chip::RemovedHeight(7e-3)).unwrap_err();
        assert!(e.to_string().contains("removed_height_mm"), "{e}");
        let e = broken_contact(&g, Chip::RemovedHeight(4.0e-3)).unwrap_err();
        assert!(e.to_string().contains("eps_b"), "{e}");
    }
}
