//! Physical pairs of the built-in presets (docs/model.md §6). The dimensionless study parameters
//! (`omega`, `F`, `xi`, `D`, `c`) stay those of `geardyn_model::presets`; these pairs supply the
//! stiffness, zones, breakage and friction tables.

use crate::geometry::PairKind;
use crate::lubrication::LubricationSpec;
use crate::mesh_stiffness::{HertzModel, LoadSharing};
use crate::pair::{BreakageSpec, OperatingPoint, PairSpec, ThermalSpec};

/// Seed A: external 40/40, m = 3 mm, 20 deg, `ha* = 1`, `c* = 0.25`, steel (206 GPa, 0.3), face
/// width 20 mm (not stated by the seed; a typical value for m = 3), `mu = 0.15`, one pinion tooth
/// with 1.0 mm of its tip chipped off (default severity; configurable), breaking in cycle 0,
/// `b_c = 10 um`.
pub fn breakage() -> PairSpec {
    PairSpec {
        face_width_mm: 20.0,
        youngs_modulus_gpa: 206.0,
        hertz: HertzModel::Linear,
        mu: 0.15,
        breakage: Some(BreakageSpec {
            removed_height_mm: Some(1.0),
            tip_radius_mm: None,
            broken_cycle: 0,
        }),
        characteristic_length_um: 10.0,
        ..steel_3mm(PairKind::External, 40, 40)
    }
}

/// Seed B: pinion 30 / ring 70, m = 3 mm, 20 deg, B = 25 mm, E = 210 GPa, nu = 0.3,
/// `k_av = 4e8 N/m` (stated by the seed; the tables are scaled to it), damping ratio 0.07,
/// `b_c = 100 um`; nonlinear Hertz and thermal stiffness (temperature rise 30 K), multi-state
/// lubrication friction with an ISO VG 68-type oil at about 70 C (20 mPa s, 18 1/GPa) on ground
/// flanks (composite roughness 0.4 um) — the seed gives no lubricant data; these are typical.
/// The operating point is the seed's multi-initial study point `omega = 1.4, F = 0.07,
/// xi = 0.23` expressed physically (12 464 rpm, 118.4 N m, E_a = 23 um) with a static half
/// backlash of 100 um; `D_d`, `D_s` then follow from the backlash physics.
pub fn internal() -> PairSpec {
    PairSpec {
        face_width_mm: 25.0,
        youngs_modulus_gpa: 210.0,
        hertz: HertzModel::Nonlinear,
        mu: 0.05,
        lubrication: Some(LubricationSpec {
            viscosity_mpas: 20.0,
            pressure_viscosity_per_gpa: 18.0,
            roughness_um: 0.4,
            boundary_mu: 0.1,
        }),
        thermal: Some(ThermalSpec {
            temperature_rise_k: 30.0,
            expansion_per_k: 11.5e-6,
        }),
        characteristic_length_um: 100.0,
        mean_stiffness_n_per_m: Some(4e8),
        damping_ratio: Some(0.07),
        operating: Some(OperatingPoint {
            speed_rpm: 12463.74,
            torque_nm: 118.4,
            error_amplitude_um: 23.0,
            half_backlash_um: 100.0,
        }),
        ..steel_3mm(PairKind::Internal, 30, 70)
    }
}

/// What both seeds share: m = 3 mm, 20 deg, standard addendum and clearance, no profile shift,
/// steel (nu = 0.3, 7850 kg/m^3), solid disks, stiffness-proportional load sharing, 1024 samples
/// per cycle; the rest neutral (206 GPa, 20 mm, linear Hertz, no friction, breakage, lubrication,
/// thermal growth, operating point; b_c = 10 um).
fn steel_3mm(kind: PairKind, z1: u32, z2: u32) -> PairSpec {
    PairSpec {
        kind,
        z1,
        z2,
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
        mu: 0.0,
        breakage: None,
        lubrication: None,
        thermal: None,
        samples_per_cycle: 1024,
        characteristic_length_um: 10.0,
        mean_stiffness_n_per_m: None,
        damping_ratio: None,
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
