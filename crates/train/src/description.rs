//! The description of a gear train (TOML, or built by a preset): bodies, meshes, shafts,
//! supports and the load path.
//!
//! ```toml
//! name = "my drive"
//! [[body]]
//! name = "pinion"
//! inertia_kgm2 = 1.2e-4
//! [[body]]
//! name = "gear"
//! inertia_kgm2 = 4.7e-3
//! [[mesh]]
//! name = "stage 1"
//! gears = ["pinion", "gear"]
//! kind = "external"
//! teeth = [20, 50]
//! base_radii_mm = [28.19, 70.48]
//! stiffness_n_per_m = 3.5e8
//! [load]
//! input = "pinion"
//! output = "gear"
//! input_torque_nm = 100.0
//! ```
//!
//! A mesh's deflection along its line of action (m), with absolute angles `theta` of one sense
//! and the axes of both gears on a carrier of angle `theta_c` (0 without a carrier), is
//! `delta = s_a r_a (theta_a - theta_c) + s_b r_b (theta_b - theta_c)` with base radii `r`,
//! `s_a = s_b = 1` for an external pair and `s_a = -1, s_b = 1` for an internal one (`b` the
//! ring): for a sun–planet mesh `u_s + u_p - u_c cos(alpha)` and for a ring–planet mesh
//! `u_r - u_p - u_c cos(alpha)` in Lin & Parker's (1999) rotational coordinates `u = r theta`
//! (base radius, and the orbit radius times `cos(alpha)` for the carrier).

use crate::error::{invalid, TrainError};
use geardyn_physics::geometry::PairKind;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;

/// A whole train.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrainSpec {
    /// Name for tables and figures.
    pub name: String,
    /// Rigid bodies (`[[body]]`).
    #[serde(rename = "body")]
    pub bodies: Vec<Body>,
    /// Gear meshes (`[[mesh]]`).
    #[serde(rename = "mesh")]
    pub meshes: Vec<Mesh>,
    /// Torsional shafts (`[[shaft]]`).
    #[serde(rename = "shaft", default)]
    pub shafts: Vec<Shaft>,
    /// Supports (`[[support]]`).
    #[serde(rename = "support", default)]
    pub supports: Vec<Support>,
    /// Input and output.
    pub load: Load,
    /// A localized tooth fault (`[fault]`), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fault: Option<ToothFault>,
    /// The dimensionless operating point the description is run at (`[operating]`: `omega`,
    /// `load`, `xi`, `c`, `d`, `[operating.stiffness]`), if it states one; the front ends start
    /// from it (else from [`TrainOperating::default`]) and apply their overrides.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub operating: Option<crate::operating::TrainOperating>,
}

/// A localized fault of one tooth (`[fault]` of a description).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToothFault {
    /// The faulted gear (a body's name).
    pub gear: String,
    /// Relative stiffness loss of a mesh while the faulted tooth carries the load alone, in
    /// `[0, 1)` (half of it in the double-tooth zones).
    pub loss: f64,
}

/// A rigid body turning about its axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Unique name.
    pub name: String,
    /// Polar moment of inertia about its own axis (kg m²).
    pub inertia_kgm2: f64,
    /// Mass (kg): with `carrier`, it adds `mass r_orbit²` to the carrier's inertia.
    #[serde(default)]
    pub mass_kg: f64,
    /// The body whose rotation carries this body's axis (a planet's carrier).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub carrier: Option<String>,
    /// Radius of this body's axis on its carrier (mm).
    #[serde(default)]
    pub orbit_radius_mm: f64,
    /// Angle of this body's axis on its carrier (deg, counted in the carrier's sense).
    #[serde(default)]
    pub orbit_angle_deg: f64,
    /// Tangential position error of this body's axis on its carrier (a planet's pin), ahead of
    /// its nominal place in the carrier's positive sense, in the dynamic model's length unit
    /// `b_c` (that of the backlash `D`); in `[-100, 100]`. For the planet's meshes it is a
    /// carrier rotation of `pin_error / orbit_radius`: a pin ahead takes less load
    /// (docs/model.md, planet load sharing).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub pin_error: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Body {
    /// A body on its own fixed axis (not carried), of polar inertia `inertia_kgm2`.
    pub fn on_axis(name: &str, inertia_kgm2: f64) -> Body {
        Body {
            name: name.into(),
            inertia_kgm2,
            mass_kg: 0.0,
            carrier: None,
            orbit_radius_mm: 0.0,
            orbit_angle_deg: 0.0,
            pin_error: 0.0,
        }
    }
}

/// A spur mesh between two bodies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mesh {
    /// Unique name.
    pub name: String,
    /// The two gears' bodies: for an internal mesh the second is the ring.
    pub gears: [String; 2],
    /// `external` or `internal`.
    pub kind: PairKind,
    /// Teeth of the two gears.
    pub teeth: [u32; 2],
    /// Base radii of the two gears (mm).
    pub base_radii_mm: [f64; 2],
    /// Mean mesh stiffness (N/m).
    pub stiffness_n_per_m: f64,
    /// Contact ratio in `[1, 2)`: the double-tooth part of a mesh cycle is `contact_ratio - 1`
    /// (the rectangular stiffness of the dynamic model).
    #[serde(default = "default_contact_ratio")]
    pub contact_ratio: f64,
    /// The carrier whose rotation carries the gears' axes (a planet's carrier), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub carrier: Option<String>,
    /// Phase of the mesh (fraction of a mesh cycle in `[0, 1)`: the mesh goes through the state
    /// of a mesh of phase 0 that much of a mesh period later).
    #[serde(default)]
    pub phase: f64,
}

impl Mesh {
    /// Whether the mesh is internal (its second gear a ring).
    pub fn is_internal(&self) -> bool {
        self.kind == PairKind::Internal
    }
}

/// A torsional shaft between two bodies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shaft {
    /// Unique name.
    pub name: String,
    /// The two bodies.
    pub bodies: [String; 2],
    /// Torsional stiffness (N m/rad).
    pub stiffness_nm_per_rad: f64,
}

/// A body held fixed (no `stiffness`) or on a torsional spring to the ground.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Support {
    /// The body.
    pub body: String,
    /// Torsional stiffness to the ground (N m/rad); absent: fixed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness_nm_per_rad: Option<f64>,
}

/// The load path: torque in at `input`, out at `output`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Load {
    /// Input body.
    pub input: String,
    /// Output body.
    pub output: String,
    /// Input torque (N m).
    pub input_torque_nm: f64,
}

fn default_contact_ratio() -> f64 {
    1.6
}

fn finite_positive(field: String, v: f64, unit: &str) -> Result<(), TrainError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid(field, v, format!("a finite value > 0 ({unit})")))
    }
}

impl TrainSpec {
    /// A description read from TOML and checked ([`TrainSpec::validate`]).
    pub fn from_toml(text: &str) -> Result<TrainSpec, TrainError> {
        let t: TrainSpec = toml::from_str(text).map_err(|e| TrainError::Parse(e.to_string()))?;
        t.validate()?;
        Ok(t)
    }

    /// The description as TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a train serialises")
    }

    /// Index of the body named `name`.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// Whether body `i` is fixed to the ground.
    pub fn is_fixed(&self, i: usize) -> bool {
        self.supports
            .iter()
            .any(|s| s.stiffness_nm_per_rad.is_none() && s.body == self.bodies[i].name)
    }

    /// Every check a train must pass, each error naming its field: names unique and known,
    /// positive finite inertias, radii, stiffnesses and teeth, phases in `[0, 1)`, an internal
    /// mesh's ring larger than its pinion, carriers that are bodies and not carried themselves,
    /// a load path from `load.input` to `load.output`. (That the train turns with exactly one
    /// input is checked by [`crate::kinematics::Kinematics::of`].)
    pub fn validate(&self) -> Result<(), TrainError> {
        if let Some(op) = &self.operating {
            op.validate()?;
        }
        if self.bodies.is_empty() {
            return Err(invalid("body", "[]", "at least two bodies"));
        }
        if self.meshes.is_empty() {
            return Err(invalid("mesh", "[]", "at least one mesh"));
        }
        let mut names = BTreeSet::new();
        for (i, b) in self.bodies.iter().enumerate() {
            if b.name.trim().is_empty() || !names.insert(b.name.as_str()) {
                return Err(invalid(
                    format!("body[{i}].name"),
                    format!("{:?}", b.name),
                    "a non-empty name no other body has",
                ));
            }
            finite_positive(format!("body[{i}].inertia_kgm2"), b.inertia_kgm2, "kg m²")?;
            if !(b.mass_kg.is_finite() && b.mass_kg >= 0.0) {
                return Err(invalid(
                    format!("body[{i}].mass_kg"),
                    b.mass_kg,
                    "a finite value >= 0 (kg)",
                ));
            }
            if !b.orbit_angle_deg.is_finite() {
                return Err(invalid(
                    format!("body[{i}].orbit_angle_deg"),
                    b.orbit_angle_deg,
                    "a finite angle (deg)",
                ));
            }
        }
        self.validate_meshes()?;
        self.validate_links()?;
        self.validate_fault()
    }

    /// The fault's gear and loss (where its tooth meets each mesh is checked with the dynamic
    /// model, `crate::fault::windows`).
    fn validate_fault(&self) -> Result<(), TrainError> {
        let Some(f) = &self.fault else {
            return Ok(());
        };
        if !(f.loss.is_finite() && (0.0..1.0).contains(&f.loss)) {
            return Err(invalid(
                "fault.loss",
                f.loss,
                "[0, 1) (relative stiffness loss)",
            ));
        }
        let g = self.known("fault.gear".into(), &f.gear)?;
        if self.bodies[g].carrier.is_some() {
            return Err(invalid(
                "fault.gear",
                format!("{:?}", f.gear),
                "a gear that is not a planet (a planet's tooth meets the sun and the ring on opposite flanks: not modelled)",
            ));
        }
        Ok(())
    }

    /// The index of the body `name`, or an error naming `field`.
    fn known(&self, field: String, name: &str) -> Result<usize, TrainError> {
        self.body_index(name).ok_or_else(|| {
            invalid(
                field,
                format!("{name:?}"),
                format!("the name of a body ({})", self.body_list()),
            )
        })
    }

    /// Carriers of bodies: bodies, not carried themselves, with an orbit radius.
    fn validate_carriers(&self) -> Result<(), TrainError> {
        for (i, b) in self.bodies.iter().enumerate() {
            if let Some(c) = &b.carrier {
                let ci = self.known(format!("body[{i}].carrier"), c)?;
                if ci == i || self.bodies[ci].carrier.is_some() {
                    return Err(invalid(
                        format!("body[{i}].carrier"),
                        format!("{c:?}"),
                        "another body that is not itself carried (one level of carriers)",
                    ));
                }
                finite_positive(
                    format!("body[{i}].orbit_radius_mm"),
                    b.orbit_radius_mm,
                    "mm",
                )?;
            }
            let on_carrier = b.carrier.is_some();
            if !(b.pin_error.is_finite() && b.pin_error.abs() <= 100.0)
                || (b.pin_error != 0.0 && !on_carrier)
            {
                return Err(invalid(
                    format!("body[{i}].pin_error"),
                    b.pin_error,
                    if on_carrier {
                        "[-100, 100] (units b_c, the length unit of the backlash D)"
                    } else {
                        "0: a position error is that of a carried body's axis (a planet's pin)"
                    },
                ));
            }
        }
        Ok(())
    }

    /// Meshes: names, gears, radii, teeth, stiffness, contact ratio, phase, carrier.
    fn validate_meshes(&self) -> Result<(), TrainError> {
        self.validate_carriers()?;
        let mut mesh_names = BTreeSet::new();
        for (i, m) in self.meshes.iter().enumerate() {
            if m.name.trim().is_empty() || !mesh_names.insert(m.name.as_str()) {
                return Err(invalid(
                    format!("mesh[{i}].name"),
                    format!("{:?}", m.name),
                    "a non-empty name no other mesh has",
                ));
            }
            let a = self.known(format!("mesh[{i}].gears"), &m.gears[0])?;
            let b = self.known(format!("mesh[{i}].gears"), &m.gears[1])?;
            if a == b {
                return Err(invalid(
                    format!("mesh[{i}].gears"),
                    format!("{:?}", m.gears),
                    "two different bodies",
                ));
            }
            for k in 0..2 {
                finite_positive(format!("mesh[{i}].base_radii_mm"), m.base_radii_mm[k], "mm")?;
                if m.teeth[k] == 0 {
                    return Err(invalid(
                        format!("mesh[{i}].teeth"),
                        format!("{:?}", m.teeth),
                        "whole numbers >= 1",
                    ));
                }
            }
            if m.kind == PairKind::Internal && m.base_radii_mm[1] <= m.base_radii_mm[0] {
                return Err(invalid(
                    format!("mesh[{i}].base_radii_mm"),
                    format!("{:?}", m.base_radii_mm),
                    "for an internal mesh the second gear (the ring) larger than the first",
                ));
            }
            finite_positive(
                format!("mesh[{i}].stiffness_n_per_m"),
                m.stiffness_n_per_m,
                "N/m",
            )?;
            if !(m.contact_ratio.is_finite() && (1.0..2.0).contains(&m.contact_ratio)) {
                return Err(invalid(
                    format!("mesh[{i}].contact_ratio"),
                    m.contact_ratio,
                    "[1, 2)",
                ));
            }
            if !(0.0..1.0).contains(&m.phase) {
                return Err(invalid(
                    format!("mesh[{i}].phase"),
                    m.phase,
                    "[0, 1) mesh cycles",
                ));
            }
            if let Some(c) = &m.carrier {
                let ci = self.known(format!("mesh[{i}].carrier"), c)?;
                if ci == a || ci == b {
                    return Err(invalid(
                        format!("mesh[{i}].carrier"),
                        format!("{c:?}"),
                        "a body other than the mesh's gears",
                    ));
                }
            }
        }
        Ok(())
    }

    /// Shafts, supports, every body joined to the train, the load path.
    fn validate_links(&self) -> Result<(), TrainError> {
        for (i, s) in self.shafts.iter().enumerate() {
            let a = self.known(format!("shaft[{i}].bodies"), &s.bodies[0])?;
            let b = self.known(format!("shaft[{i}].bodies"), &s.bodies[1])?;
            if a == b {
                return Err(invalid(
                    format!("shaft[{i}].bodies"),
                    format!("{:?}", s.bodies),
                    "two different bodies",
                ));
            }
            finite_positive(
                format!("shaft[{i}].stiffness_nm_per_rad"),
                s.stiffness_nm_per_rad,
                "N m/rad",
            )?;
        }
        for (i, s) in self.supports.iter().enumerate() {
            self.known(format!("support[{i}].body"), &s.body)?;
            if let Some(k) = s.stiffness_nm_per_rad {
                finite_positive(format!("support[{i}].stiffness_nm_per_rad"), k, "N m/rad")?;
            }
        }
        // every body takes part: a body no mesh, shaft, support or carried body names turns
        // freely (a second free motion)
        for (i, b) in self.bodies.iter().enumerate() {
            let n = b.name.as_str();
            let used = self
                .meshes
                .iter()
                .any(|m| m.gears.iter().any(|g| g == n) || m.carrier.as_deref() == Some(n))
                || self.shafts.iter().any(|s| s.bodies.iter().any(|x| x == n))
                || self.supports.iter().any(|s| s.body == n)
                || self.bodies.iter().any(|x| x.carrier.as_deref() == Some(n));
            if !used {
                return Err(invalid(
                    format!("body[{i}].name"),
                    format!("{n:?}"),
                    "a body some mesh, shaft, support or carried body names (this one is joined to nothing)",
                ));
            }
        }
        let input = self.known("load.input".into(), &self.load.input)?;
        let output = self.known("load.output".into(), &self.load.output)?;
        if input == output {
            return Err(invalid(
                "load.output",
                format!("{:?}", self.load.output),
                "a body other than load.input",
            ));
        }
        if !self.load.input_torque_nm.is_finite() {
            return Err(invalid(
                "load.input_torque_nm",
                self.load.input_torque_nm,
                "a finite torque (N m)",
            ));
        }
        for (field, body) in [("load.input", input), ("load.output", output)] {
            if self.is_fixed(body) {
                return Err(invalid(
                    field,
                    format!("{:?}", self.bodies[body].name),
                    "a body without a fixed support",
                ));
            }
        }
        if !self.connected(input, output) {
            return Err(TrainError::Kinematics(format!(
                "no load path: no chain of meshes and shafts joins load.input {:?} to load.output {:?}",
                self.load.input, self.load.output
            )));
        }
        Ok(())
    }

    /// Whether meshes (through their gears and carriers) and shafts join body `a` to body `b`.
    fn connected(&self, a: usize, b: usize) -> bool {
        let n = self.bodies.len();
        let mut edges: Vec<(usize, usize)> = Vec::new();
        let idx = |s: &str| self.body_index(s).expect("validated");
        for m in &self.meshes {
            let (x, y) = (idx(&m.gears[0]), idx(&m.gears[1]));
            edges.push((x, y));
            if let Some(c) = &m.carrier {
                edges.push((x, idx(c)));
                edges.push((y, idx(c)));
            }
        }
        for s in &self.shafts {
            edges.push((idx(&s.bodies[0]), idx(&s.bodies[1])));
        }
        let mut seen = vec![false; n];
        let mut stack = vec![a];
        seen[a] = true;
        while let Some(i) = stack.pop() {
            for &(x, y) in &edges {
                for (p, q) in [(x, y), (y, x)] {
                    if p == i && !seen[q] {
                        seen[q] = true;
                        stack.push(q);
                    }
                }
            }
        }
        seen[b]
    }

    fn body_list(&self) -> String {
        self.bodies
            .iter()
            .map(|b| b.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }
}
