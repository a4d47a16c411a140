//! A localized tooth fault of one gear of a train (a chipped or cracked tooth): where and when
//! the faulted tooth is in contact in each mesh of its gear.
//!
//! **Model.** While the faulted tooth's pair is in contact, its mesh is softer: by `loss` (a
//! fraction of the mesh stiffness) while that pair carries the load alone (the single-tooth part
//! of its engagement) and by `loss / 2` while it shares the load with the neighbouring pair (the
//! double-tooth parts: each of two pairs carries about half the mesh stiffness). A pair is in
//! contact for `eps` mesh cycles (`eps` the contact ratio): from the start of a double-tooth zone,
//! through the single-tooth zone, to the end of the next double-tooth zone — in the cycle count
//! `s` of the mesh, `[o, o + eps - 1)` half, `[o + eps - 1, o + 1)` full, `[o + 1, o + eps)` half,
//! repeating every `Z` cycles (`Z` the teeth of the faulted gear). This is the lumped form of the
//! potential-energy loss of the pair physics (a chipped tooth's pair is softer, and the loss is
//! shared in the double-tooth zones) — the pair's own breakage model computes that loss; a train
//! takes it as a number.
//!
//! **Where the tooth meets each mesh.** The faulted tooth enters its gear's first mesh at cycle
//! `o = 0` (the tooth numbering's origin). A gear in several meshes around the carrier (a sun, a
//! ring) meets the planet at orbit angle `psi` after turning `psi` or `2 pi - psi` relative to the
//! carrier, depending on its sense: it enters that mesh at `o = Z alpha + (phi_k - phi_0)`, which
//! must be a whole cycle (the tooth enters at the start of a double-tooth zone, as every tooth
//! does). The meshes' geometric phases (`phi_k = frac(Z_s psi / 2 pi)` for the sun,
//! `frac(-Z_r psi / 2 pi)` for the ring, Parker & Lin 2004) make exactly one of the two senses
//! whole — the one the geometry implies (sun and ring turn opposite ways relative to the
//! carrier); when both are whole (in-phase meshes), the sun takes `2 pi - psi` and the ring `psi`,
//! the senses the sequentially phased case fixes. A description whose phases fit neither is
//! refused, naming the mesh.
//!
//! A fault on a planet (its teeth meet the sun and the ring on opposite flanks) or on a gear in
//! several fixed-axis meshes (their positions around it are not in a description) is refused:
//! not modelled.

pub use crate::description::ToothFault;
use crate::description::TrainSpec;
use crate::error::{invalid, TrainError};
use std::f64::consts::TAU;

/// When the faulted tooth is in contact in one mesh, in that mesh's cycle count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaultWindow {
    /// Cycles between two engagements of the faulted tooth (the gear's teeth).
    pub period: f64,
    /// Cycle at which the tooth enters (whole).
    pub offset: f64,
    /// Cycles the tooth's pair is in contact (the contact ratio).
    pub length: f64,
}

impl FaultWindow {
    /// Weight of the fault at cycle `s`: 1 in the single-tooth part of the engagement, 1/2 in
    /// its double-tooth parts, 0 outside it.
    pub fn weight(&self, s: f64) -> f64 {
        let u = (s - self.offset).rem_euclid(self.period);
        let e = self.length - 1.0;
        if u >= self.length {
            0.0
        } else if u < e || u >= 1.0 {
            0.5
        } else {
            1.0
        }
    }

    /// The first border of the weight strictly after cycle `s0 + tol`.
    pub fn next_border(&self, s0: f64, tol: f64) -> f64 {
        let base = self.offset + ((s0 - self.offset) / self.period).floor() * self.period;
        let e = self.length - 1.0;
        [e, 1.0, self.length, self.period, self.period + e]
            .iter()
            .map(|d| base + d)
            .find(|&b| b > s0 + tol)
            .unwrap_or(base + 2.0 * self.period)
    }
}

/// Each mesh's window of a validated train's fault (`None` for meshes without the faulted gear),
/// or an error naming a mesh whose phase does not fit the planet positions.
pub fn windows(spec: &TrainSpec) -> Result<Vec<Option<FaultWindow>>, TrainError> {
    let mut out = vec![None; spec.meshes.len()];
    let Some(f) = &spec.fault else {
        return Ok(out);
    };
    // (the gear and the loss are checked with the description: `TrainSpec::validate`)
    let own: Vec<usize> = (0..spec.meshes.len())
        .filter(|&k| spec.meshes[k].gears.iter().any(|n| n == &f.gear))
        .collect();
    let Some(&first) = own.first() else {
        return Err(invalid(
            "fault.gear",
            format!("{:?}", f.gear),
            "a gear in at least one mesh",
        ));
    };
    // the partner's orbit angle (rad) locates the mesh around the gear
    let position = |k: usize| -> Option<f64> {
        let m = &spec.meshes[k];
        let partner = m.gears.iter().find(|n| *n != &f.gear)?;
        let b = &spec.bodies[spec.body_index(partner)?];
        b.carrier.as_ref().map(|_| b.orbit_angle_deg.to_radians())
    };
    let fixed_axis = own.iter().filter(|&&k| position(k).is_none()).count();
    if own.len() > 1 && fixed_axis > 0 {
        return Err(invalid(
            "fault.gear",
            format!("{:?}", f.gear),
            "a gear in one mesh, or meshing with planets only (the positions of several fixed-axis meshes around a gear are not in a description)",
        ));
    }
    let m0 = &spec.meshes[first];
    let z = f64::from(if m0.gears[0] == f.gear {
        m0.teeth[0]
    } else {
        m0.teeth[1]
    });
    let psi0 = position(first).unwrap_or(0.0);
    for &k in &own {
        let m = &spec.meshes[k];
        let turn = ((position(k).unwrap_or(0.0) - psi0) / TAU).rem_euclid(1.0);
        let dphase = m.phase - m0.phase;
        let whole = |x: f64| (x - x.round()).abs() < 1e-6;
        // (the ring is the second gear of an internal mesh)
        let ring = m.gears[1] == f.gear && m.is_internal();
        let (a, b) = (z * turn + dphase, z * (1.0 - turn) + dphase);
        let offset = match (whole(a), whole(b)) {
            (true, true) if ring => a,
            (true, true) => b,
            (true, false) => a,
            (false, true) => b,
            (false, false) => {
                return Err(invalid(
                    format!("mesh[{k}].phase"),
                    m.phase,
                    format!(
                        "a phase that fits the planet positions for a tooth fault on {:?} (the tooth enters each mesh at a whole cycle)",
                        f.gear
                    ),
                ))
            }
        };
        out[k] = Some(FaultWindow {
            period: z,
            offset: offset.round().rem_euclid(z),
            length: m.contact_ratio,
        });
    }
    Ok(out)
}
