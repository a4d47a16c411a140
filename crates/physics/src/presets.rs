//! Physical pairs of the built-in presets (MODEL.md §6). The dimensionless study parameters
//! (`omega`, `F`, `xi`, `D`, `c`) stay those of `geardyn_model::presets`; these pairs supply the
//! stiffness, zones, breakage and friction tables.

use crate::geometry::PairKind;
use crate::mesh_stiffness::{HertzModel, LoadSharing};
use crate::pair::{BreakageSpec, PairSpec};

/// Seed A: external 40/40, m = 3 mm, 20 deg, `ha* = 1`, `c* = 0.25`, steel (206 GPa, 0.3), face
/// width 20 mm (not stated by the seed; a typical value for m = 3), `mu = 0.15`, one pinion tooth
/// with 1.0 mm of its tip chipped off (default severity; configurable), breaking in cycle 0,
/// `b_c = 10 um`.
pub fn breakage() -> PairSpec {
    PairSpec {
        kind: PairKind::External,
        z1: 40,
        z2: 40,
        module_mm: 3.0,
        pressure_angle_deg: 20.0,
        addendum: 1.0,
        clearance: 0.25,
        x1: 0.0,
        x2: 0.0,
        face_width_mm: 20.0,
        youngs_modulus_gpa: 206.0,
        poisson: 0.3,
        density_kg_m3: 7850.0,
        bore_radius_pinion_mm: None,
        bore_radius_gear_mm: None,
        inertia_pinion_kgm2: None,
        inertia_gear_kgm2: None,
        hertz: HertzModel::Linear,
        load_sharing: LoadSharing::Stiffness,
        mu: 0.15,
        breakage: Some(BreakageSpec {
            removed_height_mm: Some(1.0),
            tip_radius_mm: None,
            broken_cycle: 0,
        }),
        samples_per_cycle: 1024,
        characteristic_length_um: 10.0,
        mean_stiffness_n_per_m: None,
        damping_ratio: None,
        operating: None,
    }
}

/// Seed B: pinion 30 / ring 70, m = 3 mm, 20 deg, B = 25 mm, E = 210 GPa, nu = 0.3,
/// `k_av = 4e8 N/m` (stated by the seed; the potential-energy tables are scaled to it), damping
/// ratio 0.07, `b_c = 100 um`, `mu = 0.05` (lubricated; the lubrication model will refine it).
pub fn internal() -> PairSpec {
    PairSpec {
        kind: PairKind::Internal,
        z1: 30,
        z2: 70,
        module_mm: 3.0,
        pressure_angle_deg: 20.0,
        addendum: 1.0,
        clearance: 0.25,
        x1: 0.0,
        x2: 0.0,
        face_width_mm: 25.0,
        youngs_modulus_gpa: 210.0,
        poisson: 0.3,
        density_kg_m3: 7850.0,
        bore_radius_pinion_mm: None,
        bore_radius_gear_mm: None,
        inertia_pinion_kgm2: None,
        inertia_gear_kgm2: None,
        hertz: HertzModel::Linear,
        load_sharing: LoadSharing::Stiffness,
        mu: 0.05,
        breakage: None,
        samples_per_cycle: 1024,
        characteristic_length_um: 100.0,
        mean_stiffness_n_per_m: Some(4e8),
        damping_ratio: Some(0.07),
        operating: None,
    }
}

/// The physical pair of a preset, if it has one.
pub fn by_name(name: &str) -> Option<PairSpec> {
    match name {
        "breakage" => Some(breakage()),
        "internal" => Some(internal()),
        _ => None,
    }
}
