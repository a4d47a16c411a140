//! Built-in trains from the pair physics: a planetary stage, a two-stage drive and the single
//! pair written as a train. Each takes its parameters (`stage.*`, `stage1.*`, ... fields, set
//! like `pair.*` fields) and builds every mesh's mean stiffness, base radii and every gear's
//! inertia with the potential-energy pair model of geardyn (healthy teeth, steel, 20°, standard
//! addendum, no profile shift).

use crate::description::{Body, Load, Mesh, Shaft, Support, TrainSpec};
use crate::error::{invalid, TrainError};
use geardyn_physics::geometry::PairKind;
use geardyn_physics::planetary::PlanetaryStage;
use geardyn_physics::{PairModel, PairSpec};
use std::f64::consts::PI;

/// Names of the built-in trains.
pub const NAMES: [&str; 3] = ["planetary", "two-stage", "pair"];

/// Steel density (kg/m³) of the gears and the carrier.
const STEEL: f64 = 7850.0;
/// Shear modulus of steel (Pa), for shafts.
const STEEL_SHEAR: f64 = 80e9;

/// A healthy steel pair of the seeds' kind (20°, `ha* = 1`, `c* = 0.25`) built by the pair
/// physics; `field` names the preset's fields in an error.
fn pair(
    kind: PairKind,
    [z1, z2]: [u32; 2],
    module_mm: f64,
    face_mm: f64,
    group: &str,
    names: &[(&str, &str)],
) -> Result<PairModel, TrainError> {
    let spec = PairSpec {
        kind,
        z1,
        z2,
        module_mm,
        face_width_mm: face_mm,
        breakage: None,
        mu: 0.0,
        ..geardyn_physics::presets::breakage()
    };
    spec.build().map_err(|error| match error {
        // a field of the preset: its own name (`stage1.z1`, not the pair's `pair.z1`)
        geardyn_physics::PhysicsError::Invalid {
            field,
            value,
            allowed,
        } => match names.iter().find(|n| n.0 == field) {
            Some((_, own)) => invalid(*own, value, allowed),
            None => TrainError::Pair {
                mesh: format!("{group} pair ({z1}/{z2} teeth)"),
                error: geardyn_physics::PhysicsError::Invalid {
                    field,
                    value,
                    allowed,
                },
            },
        },
        error => TrainError::Pair {
            mesh: format!("{group} pair ({z1}/{z2} teeth)"),
            error,
        },
    })
}

/// Mass of a gear as the pair physics models it: a steel disc of its pitch radius with a bore
/// of half of it (kg).
fn gear_mass(pitch_radius: f64, face: f64) -> f64 {
    STEEL * face * PI * (pitch_radius.powi(2) - (0.5 * pitch_radius).powi(2))
}

/// The planetary stage's settings (`stage.*`).
#[derive(Clone, Debug, PartialEq)]
pub struct PlanetaryParams {
    /// Sun teeth (`stage.sun_teeth`).
    pub sun: u32,
    /// Planet teeth (`stage.planet_teeth`).
    pub planet: u32,
    /// Ring teeth (`stage.ring_teeth`).
    pub ring: u32,
    /// Planets (`stage.planets`).
    pub planets: u32,
    /// Module (`stage.module_mm`, mm).
    pub module_mm: f64,
    /// Face width (`stage.face_width_mm`, mm).
    pub face_width_mm: f64,
    /// Carrier inertia without the planets (`stage.carrier_inertia_kgm2`, kg m²); 0: a steel
    /// disc of the planets' orbit radius and the face width.
    pub carrier_inertia_kgm2: f64,
    /// Nominal input torque on the sun (`stage.input_torque_nm`, N m), recorded in the
    /// description (the dynamic model's load is its dimensionless `F`).
    pub input_torque_nm: f64,
    /// A chipped sun tooth's mesh stiffness loss (`stage.sun_chip`, [0, 1); 0: healthy): the
    /// description's `[fault]` on the sun ([`crate::fault`]).
    pub sun_chip: f64,
    /// Tangential position error of planet 1's pin (`stage.pin_error`, units `b_c` of the
    /// dynamic model, [-100, 100]; ahead in the carrier's sense: that planet takes less load).
    pub pin_error: f64,
}

impl Default for PlanetaryParams {
    /// 25 / 35 / 95 teeth, 3 planets, m = 3 mm, 25 mm face: the planets equally spaced
    /// (`(25 + 95) / 3 = 40`), the sun–planet meshes sequentially phased (`25 / 3` not whole),
    /// ratio 4.8; 500 N m on the sun.
    fn default() -> Self {
        PlanetaryParams {
            sun: 25,
            planet: 35,
            ring: 95,
            planets: 3,
            module_mm: 3.0,
            face_width_mm: 25.0,
            carrier_inertia_kgm2: 0.0,
            input_torque_nm: 500.0,
            sun_chip: 0.0,
            pin_error: 0.0,
        }
    }
}

/// A whole number of teeth or planets from a `--set` value.
fn whole(field: &str, v: f64) -> Result<u32, TrainError> {
    if v.is_finite() && v.fract() == 0.0 && (1.0..=10_000.0).contains(&v) {
        Ok(v as u32)
    } else {
        Err(invalid(field, v, "a whole number in [1, 10000]"))
    }
}

impl PlanetaryParams {
    /// The fields `set` knows.
    pub const FIELDS: [&'static str; 10] = [
        "stage.sun_teeth",
        "stage.planet_teeth",
        "stage.ring_teeth",
        "stage.planets",
        "stage.module_mm",
        "stage.face_width_mm",
        "stage.carrier_inertia_kgm2",
        "stage.input_torque_nm",
        "stage.sun_chip",
        "stage.pin_error",
    ];

    /// Set a field (checked when the train is built).
    pub fn set(&mut self, field: &str, v: f64) -> Result<(), TrainError> {
        match field {
            "stage.sun_teeth" => self.sun = whole(field, v)?,
            "stage.planet_teeth" => self.planet = whole(field, v)?,
            "stage.ring_teeth" => self.ring = whole(field, v)?,
            "stage.planets" => {
                // (the range the stage's geometry allows, given here for any value)
                let r = geardyn_physics::planetary::PLANETS;
                let (lo, hi) = (f64::from(*r.start()), f64::from(*r.end()));
                if !(v.is_finite() && v.fract() == 0.0 && (lo..=hi).contains(&v)) {
                    return Err(invalid(field, v, format!("a whole number in [{lo}, {hi}]")));
                }
                self.planets = v as u32;
            }
            "stage.module_mm" => self.module_mm = v,
            "stage.face_width_mm" => self.face_width_mm = v,
            "stage.carrier_inertia_kgm2" => self.carrier_inertia_kgm2 = v,
            "stage.input_torque_nm" => self.input_torque_nm = v,
            "stage.sun_chip" => self.sun_chip = v,
            "stage.pin_error" => self.pin_error = v,
            _ => return Err(unknown(field, &Self::FIELDS)),
        }
        Ok(())
    }
}

fn unknown(field: &str, known: &[&str]) -> TrainError {
    // (a train's runs start at rest in its static deflection: it has no x0, v0)
    let operating = "the operating point's omega, F, xi, c, D, kappa, ratio (a train starts at rest in its static deflection)";
    TrainError::Unknown {
        field: field.to_string(),
        allowed: if known.is_empty() {
            format!("{operating} (this train has no fields of its own)")
        } else {
            format!("one of {}, or {operating}", known.join(", "))
        },
    }
}

/// A module in the range of real gears, [0.05, 100] mm.
fn check_module(m: f64) -> Result<(), TrainError> {
    if m.is_finite() && (0.05..=100.0).contains(&m) {
        Ok(())
    } else {
        Err(invalid("stage.module_mm", m, "[0.05, 100] mm"))
    }
}

/// A planetary stage: sun (input), carrier (output), fixed ring, `N` equally spaced planets;
/// sun–planet (external) and ring–planet (internal) meshes of the pair physics' mean stiffness,
/// their phases from the planet positions (Parker & Lin 2004).
pub fn planetary(p: &PlanetaryParams) -> Result<TrainSpec, TrainError> {
    check_module(p.module_mm)?;
    let stage = PlanetaryStage::new(p.sun, p.planet, p.ring, p.planets, p.module_mm * 1e-3)
        .map_err(|e| match e {
            geardyn_physics::PhysicsError::Invalid {
                field,
                value,
                allowed,
            } => invalid(
                field.replace("stage.module", "stage.module_mm"),
                if field.ends_with("module") {
                    value * 1e3
                } else {
                    value
                },
                allowed.replace("(m)", "(mm)"),
            ),
            other => TrainError::Pair {
                mesh: "stage".into(),
                error: other,
            },
        })?;
    if !(p.pin_error.is_finite() && p.pin_error.abs() <= 100.0) {
        return Err(invalid(
            "stage.pin_error",
            p.pin_error,
            "[-100, 100] (units b_c, the length unit of the backlash D)",
        ));
    }
    if !(p.face_width_mm.is_finite() && (0.1..=2000.0).contains(&p.face_width_mm)) {
        return Err(invalid(
            "stage.face_width_mm",
            p.face_width_mm,
            "[0.1, 2000] mm",
        ));
    }
    if !(p.carrier_inertia_kgm2.is_finite() && p.carrier_inertia_kgm2 >= 0.0) {
        return Err(invalid(
            "stage.carrier_inertia_kgm2",
            p.carrier_inertia_kgm2,
            "a finite value >= 0 (kg m²; 0: a steel disc)",
        ));
    }
    if !(p.sun_chip.is_finite() && (0.0..1.0).contains(&p.sun_chip)) {
        return Err(invalid(
            "stage.sun_chip",
            p.sun_chip,
            "[0, 1) (relative mesh stiffness loss of a chipped sun tooth; 0: healthy)",
        ));
    }
    if !p.input_torque_nm.is_finite() {
        return Err(invalid(
            "stage.input_torque_nm",
            p.input_torque_nm,
            "a finite torque (N m)",
        ));
    }
    let stage_names = [
        ("module", "stage.module_mm"),
        ("face_width_mm", "stage.face_width_mm"),
    ];
    let sp = pair(
        PairKind::External,
        [p.sun, p.planet],
        p.module_mm,
        p.face_width_mm,
        "sun-planet",
        &[
            ("z1", "stage.sun_teeth"),
            ("z2", "stage.planet_teeth"),
            stage_names[0],
            stage_names[1],
        ],
    )?;
    let rp = pair(
        PairKind::Internal,
        [p.planet, p.ring],
        p.module_mm,
        p.face_width_mm,
        "ring-planet",
        &[
            ("z1", "stage.planet_teeth"),
            ("z2", "stage.ring_teeth"),
            stage_names[0],
            stage_names[1],
        ],
    )?;
    let b = p.face_width_mm * 1e-3;
    let a = stage.centre_distance();
    let carrier_i = if p.carrier_inertia_kgm2 > 0.0 {
        p.carrier_inertia_kgm2
    } else {
        STEEL * b * PI * a.powi(4) / 2.0
    };
    let mut bodies = vec![
        Body::on_axis("sun", sp.i_p),
        Body::on_axis("carrier", carrier_i),
        Body::on_axis("ring", rp.i_g),
    ];
    let meshes = planets(&stage, p, (&sp, &rp), &mut bodies);
    let t = TrainSpec {
        name: format!(
            "planetary {}/{}/{}, {} planets",
            p.sun, p.planet, p.ring, p.planets
        ),
        bodies,
        meshes,
        shafts: vec![],
        supports: vec![Support {
            body: "ring".into(),
            stiffness_nm_per_rad: None,
        }],
        load: Load {
            input: "sun".into(),
            output: "carrier".into(),
            input_torque_nm: p.input_torque_nm,
        },
        fault: (p.sun_chip != 0.0).then(|| crate::fault::ToothFault {
            gear: "sun".into(),
            loss: p.sun_chip,
        }),
        operating: None,
    };
    t.validate()?;
    Ok(t)
}

/// The planets of a stage (pushed onto `bodies`) and their sun–planet and ring–planet meshes,
/// with the geometric phases.
fn planets(
    stage: &PlanetaryStage,
    p: &PlanetaryParams,
    (sp, rp): (&PairModel, &PairModel),
    bodies: &mut Vec<Body>,
) -> Vec<Mesh> {
    let b = p.face_width_mm * 1e-3;
    let a = stage.centre_distance();
    let mut meshes = Vec::new();
    for n in 0..p.planets {
        let name = format!("planet {}", n + 1);
        bodies.push(Body {
            name: name.clone(),
            inertia_kgm2: rp.i_p,
            mass_kg: gear_mass(rp.geom.r1, b),
            carrier: Some("carrier".into()),
            orbit_radius_mm: a * 1e3,
            orbit_angle_deg: stage.planet_angle(n).to_degrees(),
            pin_error: if n == 0 { p.pin_error } else { 0.0 },
        });
        meshes.push(Mesh {
            name: format!("sun-planet {}", n + 1),
            gears: ["sun".into(), name.clone()],
            kind: PairKind::External,
            teeth: [p.sun, p.planet],
            base_radii_mm: [sp.geom.rb1 * 1e3, sp.geom.rb2 * 1e3],
            stiffness_n_per_m: sp.k_av,
            contact_ratio: sp.geom.eps,
            carrier: Some("carrier".into()),
            phase: stage.sun_planet_phase(n),
        });
        meshes.push(Mesh {
            name: format!("ring-planet {}", n + 1),
            gears: [name, "ring".into()],
            kind: PairKind::Internal,
            teeth: [p.planet, p.ring],
            base_radii_mm: [rp.geom.rb1 * 1e3, rp.geom.rb2 * 1e3],
            stiffness_n_per_m: rp.k_av,
            contact_ratio: rp.geom.eps,
            carrier: Some("carrier".into()),
            phase: stage.ring_planet_phase(n),
        });
    }
    meshes
}

/// The two-stage drive's settings.
#[derive(Clone, Debug, PartialEq)]
pub struct TwoStageParams {
    /// Teeth: stage 1 pinion and wheel, stage 2 pinion and wheel (`stage1.z1`, `stage1.z2`,
    /// `stage2.z1`, `stage2.z2`).
    pub teeth: [u32; 4],
    /// Module of both stages (`stage.module_mm`, mm).
    pub module_mm: f64,
    /// Face width of both stages (`stage.face_width_mm`, mm).
    pub face_width_mm: f64,
    /// Intermediate shaft: diameter and length (`shaft.diameter_mm`, `shaft.length_mm`), steel.
    pub shaft_mm: [f64; 2],
    /// Nominal input torque (`stage.input_torque_nm`, N m), recorded in the description (the
    /// dynamic model's load is its dimensionless `F`).
    pub input_torque_nm: f64,
}

impl Default for TwoStageParams {
    /// 20/50 then 22/61 teeth (ratio 6.93), m = 3 mm, 20 mm face, a steel intermediate shaft of
    /// 40 mm diameter and 150 mm length (`G J / L` = 1.34e5 N m/rad); 100 N m in.
    fn default() -> Self {
        TwoStageParams {
            teeth: [20, 50, 22, 61],
            module_mm: 3.0,
            face_width_mm: 20.0,
            shaft_mm: [40.0, 150.0],
            input_torque_nm: 100.0,
        }
    }
}

impl TwoStageParams {
    /// The fields `set` knows.
    pub const FIELDS: [&'static str; 9] = [
        "stage1.z1",
        "stage1.z2",
        "stage2.z1",
        "stage2.z2",
        "stage.module_mm",
        "stage.face_width_mm",
        "shaft.diameter_mm",
        "shaft.length_mm",
        "stage.input_torque_nm",
    ];

    /// Set a field (checked when the train is built).
    pub fn set(&mut self, field: &str, v: f64) -> Result<(), TrainError> {
        match field {
            "stage1.z1" => self.teeth[0] = whole(field, v)?,
            "stage1.z2" => self.teeth[1] = whole(field, v)?,
            "stage2.z1" => self.teeth[2] = whole(field, v)?,
            "stage2.z2" => self.teeth[3] = whole(field, v)?,
            "stage.module_mm" => self.module_mm = v,
            "stage.face_width_mm" => self.face_width_mm = v,
            "shaft.diameter_mm" => self.shaft_mm[0] = v,
            "shaft.length_mm" => self.shaft_mm[1] = v,
            "stage.input_torque_nm" => self.input_torque_nm = v,
            _ => return Err(unknown(field, &Self::FIELDS)),
        }
        Ok(())
    }

    /// Torsional stiffness of the intermediate shaft, `G pi d⁴ / (32 L)` (N m/rad).
    pub fn shaft_stiffness(&self) -> f64 {
        let (d, l) = (self.shaft_mm[0] * 1e-3, self.shaft_mm[1] * 1e-3);
        STEEL_SHEAR * PI * d.powi(4) / (32.0 * l)
    }
}

/// A two-stage drive: input pinion, stage-1 wheel and stage-2 pinion on an intermediate shaft
/// of finite torsional stiffness, output wheel.
pub fn two_stage(p: &TwoStageParams) -> Result<TrainSpec, TrainError> {
    check_module(p.module_mm)?;
    for (k, f) in [(0, "shaft.diameter_mm"), (1, "shaft.length_mm")] {
        if !(p.shaft_mm[k].is_finite() && (1.0..=10_000.0).contains(&p.shaft_mm[k])) {
            return Err(invalid(f, p.shaft_mm[k], "[1, 10000] mm"));
        }
    }
    if !(p.face_width_mm.is_finite() && (0.1..=2000.0).contains(&p.face_width_mm)) {
        return Err(invalid(
            "stage.face_width_mm",
            p.face_width_mm,
            "[0.1, 2000] mm",
        ));
    }
    if !p.input_torque_nm.is_finite() {
        return Err(invalid(
            "stage.input_torque_nm",
            p.input_torque_nm,
            "a finite torque (N m)",
        ));
    }
    let [z1, z2, z3, z4] = p.teeth;
    let common = [
        ("module", "stage.module_mm"),
        ("face_width_mm", "stage.face_width_mm"),
    ];
    let s1 = pair(
        PairKind::External,
        [z1, z2],
        p.module_mm,
        p.face_width_mm,
        "stage1",
        &[
            ("z1", "stage1.z1"),
            ("z2", "stage1.z2"),
            common[0],
            common[1],
        ],
    )?;
    let s2 = pair(
        PairKind::External,
        [z3, z4],
        p.module_mm,
        p.face_width_mm,
        "stage2",
        &[
            ("z1", "stage2.z1"),
            ("z2", "stage2.z2"),
            common[0],
            common[1],
        ],
    )?;
    let body = Body::on_axis;
    let mesh = |name: &str, g: [&str; 2], z: [u32; 2], m: &PairModel| Mesh {
        name: name.into(),
        gears: [g[0].into(), g[1].into()],
        kind: PairKind::External,
        teeth: z,
        base_radii_mm: [m.geom.rb1 * 1e3, m.geom.rb2 * 1e3],
        stiffness_n_per_m: m.k_av,
        contact_ratio: m.geom.eps,
        carrier: None,
        phase: 0.0,
    };
    let t = TrainSpec {
        name: format!("two-stage {z1}/{z2}, {z3}/{z4}"),
        bodies: vec![
            body("input pinion", s1.i_p),
            body("wheel 1", s1.i_g),
            body("pinion 2", s2.i_p),
            body("output wheel", s2.i_g),
        ],
        meshes: vec![
            mesh("stage 1", ["input pinion", "wheel 1"], [z1, z2], &s1),
            mesh("stage 2", ["pinion 2", "output wheel"], [z3, z4], &s2),
        ],
        shafts: vec![Shaft {
            name: "intermediate shaft".into(),
            bodies: ["wheel 1".into(), "pinion 2".into()],
            stiffness_nm_per_rad: p.shaft_stiffness(),
        }],
        supports: vec![],
        load: Load {
            input: "input pinion".into(),
            output: "output wheel".into(),
            input_torque_nm: p.input_torque_nm,
        },
        fault: None,
        operating: None,
    };
    t.validate()?;
    Ok(t)
}

/// The seed-A pair (40/40, m = 3 mm, 20 mm face, healthy) written as a train: pinion, gear,
/// one mesh.
pub fn single_pair() -> Result<TrainSpec, TrainError> {
    let s = geardyn_physics::presets::breakage();
    let m = pair(
        s.kind,
        [s.z1, s.z2],
        s.module_mm,
        s.face_width_mm,
        "pair",
        &[],
    )?;
    let body = Body::on_axis;
    let t = TrainSpec {
        name: format!("pair {}/{}", s.z1, s.z2),
        bodies: vec![body("pinion", m.i_p), body("gear", m.i_g)],
        meshes: vec![Mesh {
            name: "mesh".into(),
            gears: ["pinion".into(), "gear".into()],
            kind: s.kind,
            teeth: [s.z1, s.z2],
            base_radii_mm: [m.geom.rb1 * 1e3, m.geom.rb2 * 1e3],
            stiffness_n_per_m: m.k_av,
            contact_ratio: m.geom.eps,
            carrier: None,
            phase: 0.0,
        }],
        shafts: vec![],
        supports: vec![],
        load: Load {
            input: "pinion".into(),
            output: "gear".into(),
            input_torque_nm: 100.0,
        },
        fault: None,
        operating: None,
    };
    t.validate()?;
    Ok(t)
}

/// A built-in train by name ([`NAMES`]) with `sets` applied (`field`, value).
pub fn by_name(name: &str, sets: &[(String, f64)]) -> Result<TrainSpec, TrainError> {
    match name {
        "planetary" => {
            let mut p = PlanetaryParams::default();
            for (k, v) in sets {
                p.set(k, *v)?;
            }
            planetary(&p)
        }
        "two-stage" => {
            let mut p = TwoStageParams::default();
            for (k, v) in sets {
                p.set(k, *v)?;
            }
            two_stage(&p)
        }
        "pair" => match sets.first() {
            Some((k, _)) => Err(unknown(k, &[])),
            None => single_pair(),
        },
        _ => Err(invalid(
            "--preset",
            name,
            format!("one of {}", NAMES.join(", ")),
        )),
    }
}
