//! [`PairSpec::build`]: from the dimensional pair to the dimensionless tables of the mesh model
//! (bores and inertias, the static load, the sampled cycles scaled to the mean stiffness, the
//! zone pieces of the excitation period, and the half backlash per zone at the operating point).

use super::sampling::{CycleSampler, Piece};
use super::{bad, PairModel, PairSpec, StiffnessRow};
use crate::breakage::{broken_contact, Chip};
use crate::error::PhysicsError;
use crate::geometry::{PairGeometry, PairGeometryInput, PairKind};
use crate::mesh_stiffness::{HertzModel, StiffnessModel};
use crate::tooth::Material;
use geardyn_model::ZonePiece;
use std::f64::consts::PI;

impl PairSpec {
    /// Builds geometry, stiffness tables and normalisation.
    pub fn build(&self) -> Result<PairModel, PhysicsError> {
        self.validate()?;
        let geom = PairGeometry::new(&PairGeometryInput {
            kind: self.kind,
            z1: self.z1,
            z2: self.z2,
            module: self.module_mm * 1e-3,
            pressure_angle: self.pressure_angle_deg.to_radians(),
            addendum: self.addendum,
            clearance: self.clearance,
            x1: self.x1,
            x2: self.x2,
        })?;
        geom.check_two_zone()?;
        let b = self.face_width_mm * 1e-3;
        let mat = Material {
            e: self.youngs_modulus_gpa * 1e9,
            nu: self.poisson,
            b,
        };
        let (r_int1, r_int2) = self.bores(&geom)?;
        let rho = self.density_kg_m3;
        let disk = |ro: f64, ri: f64| rho * b * PI * (ro.powi(4) - ri.powi(4)) / 2.0;
        let i_p = self
            .inertia_pinion_kgm2
            .unwrap_or_else(|| disk(geom.r1, r_int1));
        let i_g = self.inertia_gear_kgm2.unwrap_or_else(|| match self.kind {
            PairKind::External => disk(geom.r2, r_int2),
            PairKind::Internal => disk(r_int2, geom.r2),
        });
        let m_e = i_p * i_g / (geom.rb1 * geom.rb1 * i_g + geom.rb2 * geom.rb2 * i_p);
        let static_load = self.static_load(&geom)?;
        let sm = StiffnessModel {
            geom,
            mat,
            r_int1,
            r_int2,
            hertz: self.hertz,
            static_load,
            thermal: self
                .thermal
                .map(|t| (t.expansion_per_k, t.temperature_rise_k)),
        };
        let e_red = mat.e / (1.0 - mat.nu * mat.nu);
        let omega1 = self
            .operating
            .map_or(0.0, |o| o.speed_rpm * 2.0 * PI / 60.0);
        let omega2 = omega1 * self.z1 as f64 / self.z2 as f64;
        let (eps_b, s_d1, broken_cycle) = self.broken_contact(&geom)?;
        let cycles = if eps_b.is_some() { self.z1 } else { 1 };
        // one healthy cycle and, if broken, the broken cycle: samples of each zone piece
        let sampler = CycleSampler {
            spec: self,
            geom: &geom,
            sm: &sm,
            m_e,
            i_p,
            i_g,
            omega1,
            omega2,
            static_load,
            b,
            e_red,
            eps_b,
            s_d1,
        };
        let healthy = sampler.cycle(false);
        let k_int = trapezoid_mean(&healthy);
        // optional prescribed mean: scale every stiffness (shares and friction are unchanged)
        let scale = match self.mean_stiffness_n_per_m {
            Some(k) => k / k_int,
            None => 1.0,
        };
        let k_av = k_int * scale;
        let broken = if eps_b.is_some() {
            Some(sampler.cycle(true))
        } else {
            None
        };
        let (pieces, rows_all) =
            period(cycles, &healthy, broken.as_ref(), broken_cycle, scale, k_av);
        let b_c = self.characteristic_length_um * 1e-6;
        let backlash = self.backlash(&geom, &healthy, scale, k_av, b_c)?;
        Ok(PairModel {
            geom,
            eps_b,
            k_av,
            i_p,
            i_g,
            m_e,
            omega_n: (k_av / m_e).sqrt(),
            b_c,
            cycles,
            rows: rows_all,
            pieces,
            backlash,
            spec: self.clone(),
        })
    }

    /// Inner radii of the pinion and gear bodies (m): given, or half the pitch radius (a ring
    /// gear: three modules outside its root circle); each inside its root circle (a ring's rim
    /// outside it).
    fn bores(&self, geom: &PairGeometry) -> Result<(f64, f64), PhysicsError> {
        let m = geom.module;
        let r_int1 = self
            .bore_radius_pinion_mm
            .map_or(0.5 * geom.r1, |r| r * 1e-3);
        let r_int2 = self.bore_radius_gear_mm.map_or(
            match self.kind {
                PairKind::External => 0.5 * geom.r2,
                PairKind::Internal => geom.rf2 + 3.0 * m,
            },
            |r| r * 1e-3,
        );
        if !(r_int1 > 0.0 && r_int1 < geom.rf1) {
            return Err(bad(
                "bore_radius_pinion_mm",
                r_int1 * 1e3,
                &format!("(0, {:.3}) mm (inside the root circle)", geom.rf1 * 1e3),
            ));
        }
        match self.kind {
            PairKind::External if !(r_int2 > 0.0 && r_int2 < geom.rf2) => {
                return Err(bad(
                    "bore_radius_gear_mm",
                    r_int2 * 1e3,
                    &format!("(0, {:.3}) mm (inside the root circle)", geom.rf2 * 1e3),
                ));
            }
            PairKind::Internal if r_int2 <= geom.rf2 => {
                return Err(bad(
                    "bore_radius_gear_mm",
                    r_int2 * 1e3,
                    &format!(
                        "({:.3}, inf) mm (ring rim outside its root circle)",
                        geom.rf2 * 1e3
                    ),
                ));
            }
            _ => {}
        }
        Ok((r_int1, r_int2))
    }

    /// The static mesh load (N) of the Hertz model: `T / r_b1` with an operating torque.
    fn static_load(&self, geom: &PairGeometry) -> Result<f64, PhysicsError> {
        Ok(match (self.hertz, &self.operating) {
            (HertzModel::Linear, Some(op)) => op.torque_nm / geom.rb1,
            (HertzModel::Linear, None) => 0.0,
            (HertzModel::Nonlinear, Some(op)) if op.torque_nm > 0.0 => op.torque_nm / geom.rb1,
            (HertzModel::Nonlinear, _) => {
                return Err(bad("hertz", 0.0, "\"linear\", or \"nonlinear\" together with pair.operating.torque_nm > 0 (the Hertz stiffness depends on the load)"));
            }
        })
    }

    /// The broken tooth, if any: the contact ratio of its pair, the end of its double contact
    /// and the cycle it meshes in.
    #[allow(clippy::type_complexity)]
    fn broken_contact(
        &self,
        geom: &PairGeometry,
    ) -> Result<(Option<f64>, f64, Option<u32>), PhysicsError> {
        Ok(match &self.breakage {
            None => (None, geom.s_d, None),
            Some(bs) => {
                let chip = match (bs.removed_height_mm, bs.tip_radius_mm) {
                    (Some(h), None) => Chip::RemovedHeight(h * 1e-3),
                    (None, Some(r)) => Chip::TipRadius(r * 1e-3),
                    _ => {
                        return Err(bad(
                            "breakage",
                            0.0,
                            "exactly one of removed_height_mm or tip_radius_mm",
                        ));
                    }
                };
                if bs.broken_cycle >= self.z1 {
                    return Err(bad(
                        "breakage.broken_cycle",
                        bs.broken_cycle as f64,
                        &format!("[0, {}] (z1 - 1)", self.z1 - 1),
                    ));
                }
                let (eb, sd1) = broken_contact(geom, chip)?;
                (Some(eb), sd1, Some(bs.broken_cycle))
            }
        })
    }

    /// The physical half backlash per zone (double, single) at the operating point, in units of
    /// `b_c` (needs a torque): static half backlash + half the difference of the zone's static
    /// deflection from the mean one (a softer zone deflects the loaded flanks further and opens
    /// the back side) - half the thermal growth of both teeth along the LoA - the oil film on the
    /// back flank.
    fn backlash(
        &self,
        geom: &PairGeometry,
        healthy: &[Piece],
        scale: f64,
        k_av: f64,
        b_c: f64,
    ) -> Result<Option<(f64, f64)>, PhysicsError> {
        let m = geom.module;
        Ok(match &self.operating {
            Some(op) if op.torque_nm > 0.0 => {
                let w = op.torque_nm / geom.rb1;
                let zone_mean = |single: bool, what: &dyn Fn(&StiffnessRow) -> f64| {
                    let v: Vec<f64> = healthy
                        .iter()
                        .filter(|z| z.2 == single)
                        .flat_map(|z| z.4.iter().map(what))
                        .collect();
                    v.iter().sum::<f64>() / v.len().max(1) as f64
                };
                let thermal = self.thermal.map_or(0.0, |t| {
                    t.expansion_per_k * t.temperature_rise_k * PI * m * geom.alpha_w.cos() / 2.0
                });
                let mut d = [0.0; 2];
                for (i, single) in [false, true].into_iter().enumerate() {
                    let k_zone = zone_mean(single, &|r| r.k_mesh) * scale;
                    let film = zone_mean(single, &|r| r.film1);
                    d[i] = op.half_backlash_um * 1e-6 + 0.5 * w * (1.0 / k_zone - 1.0 / k_av)
                        - thermal
                        - film;
                    if d[i] <= 0.0 {
                        return Err(PhysicsError::Geometry(format!(
                            "the backlash closes in the {} zone at this operating point (static {} um, thermal growth {} um, film {} um)",
                            if single { "single-tooth" } else { "double-tooth" },
                            geardyn_model::error::num(op.half_backlash_um),
                            geardyn_model::error::num((thermal * 1e6 * 1e3).round() / 1e3),
                            geardyn_model::error::num((film * 1e6 * 1e3).round() / 1e3)
                        )));
                    }
                }
                Some((d[0] / b_c, d[1] / b_c))
            }
            _ => None,
        })
    }
}

/// `k_av` before scaling: the trapezoidal mean of the mesh stiffness over the healthy cycle.
fn trapezoid_mean(healthy: &[Piece]) -> f64 {
    // k_av: trapezoidal mean over the healthy cycle
    let mut k_int = 0.0;
    for (a, bnd, _, _, rows) in healthy {
        let w = (bnd - a) / (rows.len() - 1) as f64;
        for (j, r) in rows.iter().enumerate() {
            let f = if j == 0 || j + 1 == rows.len() {
                0.5
            } else {
                1.0
            };
            k_int += f * w * r.k_mesh;
        }
    }
    k_int
}

/// The zone pieces of the excitation period (the broken cycle in its place) with the stiffness
/// scaled to the mean and normalised by `k_av`, and every sample row scaled.
fn period(
    cycles: u32,
    healthy: &[Piece],
    broken: Option<&Vec<Piece>>,
    broken_cycle: Option<u32>,
    scale: f64,
    k_av: f64,
) -> (Vec<ZonePiece>, Vec<StiffnessRow>) {
    let mut rows_all = Vec::new();
    let mut pieces = Vec::new();
    for c in 0..cycles {
        let src = match (broken, broken_cycle) {
            (Some(bc), Some(nb)) if nb == c => bc.as_slice(),
            _ => healthy,
        };
        for (a, bnd, single, zone_ii, rows) in src {
            pieces.push(ZonePiece {
                start: c as f64 + a,
                end: c as f64 + bnd,
                single: *single,
                zone_ii: *zone_ii,
                k: rows.iter().map(|r| r.k_mesh * scale / k_av).collect(),
                h_drive: rows.iter().map(|r| r.h_drive).collect(),
                h_back: rows.iter().map(|r| r.h_back).collect(),
            });
            rows_all.extend(rows.iter().map(|r| StiffnessRow {
                position: c as f64 + r.position,
                k_pair1: r.k_pair1 * scale,
                k_pair2: r.k_pair2 * scale,
                k_mesh: r.k_mesh * scale,
                ..*r
            }));
        }
    }
    (pieces, rows_all)
}
