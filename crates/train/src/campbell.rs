//! The Campbell diagram of a train: each mesh frequency and its harmonics grow in proportion
//! to the input speed; where one meets a natural frequency, the mesh excites that mode (a
//! resonance speed).

use crate::description::TrainSpec;
use crate::kinematics::Kinematics;
use crate::modes::Modes;
use serde::Serialize;

/// A resonance: harmonic `h` of a mesh-frequency family meeting a natural frequency.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Crossing {
    /// The meshes of the family (one frequency: e.g. every sun–planet and ring–planet mesh of a
    /// planetary stage), by name, joined.
    pub meshes: String,
    /// Harmonic of the mesh frequency.
    pub harmonic: u32,
    /// The natural frequency (Hz).
    pub frequency_hz: f64,
    /// Multiplicity of that frequency.
    pub multiplicity: usize,
    /// Its mode type.
    pub kind: &'static str,
    /// Input speed of the crossing (rpm).
    pub input_rpm: f64,
}

/// Families of meshes of one mesh frequency: `(names, tooth passes per input revolution)`.
pub fn mesh_families(spec: &TrainSpec, k: &Kinematics) -> Vec<(String, f64)> {
    let mut fams: Vec<(Vec<&str>, f64)> = Vec::new();
    for (m, &order) in spec.meshes.iter().zip(&k.mesh_orders) {
        match fams
            .iter_mut()
            .find(|f| (f.1 - order).abs() <= 1e-9 * order)
        {
            Some(f) => f.0.push(&m.name),
            None => fams.push((vec![&m.name], order)),
        }
    }
    fams.into_iter().map(|(n, o)| (n.join(", "), o)).collect()
}

/// Every crossing of harmonics `1..=harmonics` of every mesh family with every elastic natural
/// frequency, at input speeds up to `max_rpm`, by speed.
pub fn crossings(
    spec: &TrainSpec,
    k: &Kinematics,
    modes: &Modes,
    harmonics: u32,
    max_rpm: f64,
) -> Vec<Crossing> {
    let mut out = Vec::new();
    for (names, order) in mesh_families(spec, k) {
        for h in 1..=harmonics {
            for (f, mult, kind) in modes.distinct() {
                // mesh frequency per input rpm: order / 60 Hz
                let rpm = 60.0 * f / (f64::from(h) * order);
                if rpm <= max_rpm {
                    out.push(Crossing {
                        meshes: names.clone(),
                        harmonic: h,
                        frequency_hz: f,
                        multiplicity: mult,
                        kind: kind.word(),
                        input_rpm: rpm,
                    });
                }
            }
        }
    }
    out.sort_by(|a, b| a.input_rpm.total_cmp(&b.input_rpm));
    out
}
