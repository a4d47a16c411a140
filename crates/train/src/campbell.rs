//! The Campbell diagram of a train: each mesh frequency and its harmonics grow in proportion
//! to the input speed; where one meets a natural frequency, the mesh can excite that mode (a
//! resonance speed).
//!
//! **Planet phasing** decides which crossings of a planetary stage are resonances (Parker 2000,
//! "A physical explanation for the effectiveness of planet phasing to suppress planetary gear
//! vibration", J. Sound Vib. 236:561–573, in the rotational model): harmonic `h` of the mesh
//! forces of `N` equally spaced planets around a central gear of `Z` teeth is in phase on every
//! planet when `h Z / N` is whole — it then excites the rotational modes and not the planet
//! modes — and cancels on the central members otherwise, exciting only the planet modes. Each
//! crossing says whether the phasing lets it excite its mode (`excited`).

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
    /// Whether the family's mesh phasing lets this harmonic excite the mode (always for a
    /// family without planets).
    pub excited: bool,
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
        let phasing = planet_phasing(spec, &names);
        for h in 1..=harmonics {
            for (f, mult, kind) in modes.distinct() {
                // mesh frequency per input rpm: order / 60 Hz
                let rpm = 60.0 * f / (f64::from(h) * order);
                if rpm <= max_rpm {
                    let excited = match phasing {
                        Some((z, n)) if (u64::from(h) * u64::from(z)) % u64::from(n) == 0 => {
                            kind == crate::ModeKind::Rotational
                        }
                        Some(_) => kind == crate::ModeKind::Planet,
                        None => true,
                    };
                    out.push(Crossing {
                        meshes: names.clone(),
                        harmonic: h,
                        frequency_hz: f,
                        multiplicity: mult,
                        kind: kind.word(),
                        input_rpm: rpm,
                        excited,
                    });
                }
            }
        }
    }
    out.sort_by(|a, b| a.input_rpm.total_cmp(&b.input_rpm));
    out
}

/// `(Z, N)` of a family of meshes between central gears and `N >= 2` planets (bodies on a
/// carrier): the teeth of the first mesh's central gear and the number of planets; `None`
/// without planets.
fn planet_phasing(spec: &TrainSpec, names: &str) -> Option<(u32, u32)> {
    let carried = |g: &str| {
        spec.body_index(g)
            .is_some_and(|i| spec.bodies[i].carrier.is_some())
    };
    let mut planets = std::collections::BTreeSet::new();
    let mut z = None;
    for m in spec
        .meshes
        .iter()
        .filter(|m| names.split(", ").any(|n| n == m.name))
    {
        for (i, g) in m.gears.iter().enumerate() {
            if carried(g) {
                planets.insert(g.clone());
            } else if z.is_none() {
                z = Some(m.teeth[i]);
            }
        }
    }
    match (z, planets.len()) {
        (Some(z), n) if n >= 2 => Some((z, n as u32)),
        _ => None,
    }
}
