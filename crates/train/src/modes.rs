//! Natural frequencies and mode shapes of a train's linear model ([`crate::linear`]), each mode
//! typed and grouped with the modes of equal frequency.
//!
//! The generalised problem `K phi = omega² M phi` with diagonal `M > 0` is solved as the
//! symmetric one `M^(-1/2) K M^(-1/2) v = omega² v` (nalgebra's symmetric eigensolver), `phi =
//! M^(-1/2) v`. Types (Lin & Parker 1999, J. Vib. Acoust. 121:316–321, in their purely
//! rotational reduction): a **rigid-body** mode turns the train without deflecting it
//! (`omega = 0`); a **planet** mode moves only bodies carried by a carrier (the central members
//! — sun, ring, carrier — stand still); every other mode is a **rotational** mode.

use crate::description::TrainSpec;
use crate::linear::LinearModel;
use nalgebra::DMatrix;
use serde::Serialize;

/// Relative tolerance of equal frequencies (multiplicity) and of zero ones (rigid-body modes,
/// against the highest frequency squared).
pub const FREQUENCY_TOL: f64 = 1e-7;
/// Largest kinetic-energy share of the central members in a planet mode.
pub const PLANET_MODE_TOL: f64 = 1e-9;

/// Type of a mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModeKind {
    /// The train turns without deflection (`omega = 0`).
    RigidBody,
    /// The central members move (and the planets with them).
    Rotational,
    /// Only carried bodies (planets) move.
    Planet,
}

impl ModeKind {
    /// The word in tables.
    pub fn word(self) -> &'static str {
        match self {
            ModeKind::RigidBody => "rigid-body",
            ModeKind::Rotational => "rotational",
            ModeKind::Planet => "planet",
        }
    }
}

/// One mode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Mode {
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// Type.
    pub kind: ModeKind,
    /// Modes sharing this frequency (within [`FREQUENCY_TOL`]), this one included.
    pub multiplicity: usize,
    /// Rotation of each body in the description's order (rad; fixed bodies 0), scaled so that
    /// the largest `|r theta|`-free component is 1 and positive.
    pub shape: Vec<f64>,
    /// Share of the mode's kinetic energy in each body (sums to 1).
    pub energy: Vec<f64>,
}

/// Rigid-body modes of a train: its kinematic free motions (one, for a train that turns with
/// one input: [`crate::kinematics::Kinematics`]), else the eigenvalues `lambda` (of
/// `M^(-1/2) K M^(-1/2)`) below [`FREQUENCY_TOL`] times the largest. (A relative threshold
/// alone would call a real mode rigid in a train of very unequal stiffnesses: a shaft 1e8 times
/// stiffer than a mesh.)
pub fn rigid_modes(spec: &TrainSpec, lambda: &[f64]) -> usize {
    match crate::kinematics::Kinematics::of(spec) {
        Ok(_) => 1,
        Err(_) => {
            let top = lambda.iter().cloned().fold(0.0_f64, f64::max);
            lambda.iter().filter(|&&l| l <= FREQUENCY_TOL * top).count()
        }
    }
}

/// The modes of a train, lowest frequency first.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Modes {
    /// Body names, in the order of [`Mode::shape`].
    pub bodies: Vec<String>,
    /// The modes.
    pub modes: Vec<Mode>,
}

impl Modes {
    /// The modes of a validated train.
    ///
    /// ```
    /// use geardyn_train::{modes::Modes, presets};
    /// let t = presets::planetary(&presets::PlanetaryParams::default()).unwrap();
    /// let m = Modes::of(&t);
    /// // sun, carrier and 3 planets (the ring is fixed): one rigid-body mode, the planet modes
    /// // twice (N - 1), two rotational modes
    /// assert_eq!(m.modes.len(), 5);
    /// assert_eq!(m.count(geardyn_train::ModeKind::Planet), 2);
    /// ```
    pub fn of(spec: &TrainSpec) -> Modes {
        let lin = LinearModel::of(spec);
        let n = lin.len();
        let inv_sqrt: Vec<f64> = lin.mass.iter().map(|m| 1.0 / m.sqrt()).collect();
        let a = DMatrix::from_fn(n, n, |i, j| {
            lin.stiffness[(i, j)] * inv_sqrt[i] * inv_sqrt[j]
        });
        // (symmetrised: rounding of the sums above leaves it symmetric to the last bit anyway)
        let a = (&a + a.transpose()) * 0.5;
        let eig = a.symmetric_eigen();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
        let rigid_n = rigid_modes(spec, eig.eigenvalues.as_slice());
        let carried: Vec<bool> = spec.bodies.iter().map(|b| b.carrier.is_some()).collect();
        let nb = spec.bodies.len();
        let mut modes: Vec<Mode> = order
            .iter()
            .enumerate()
            .map(|(rank, &k)| {
                let lambda = eig.eigenvalues[k];
                let rigid = rank < rigid_n;
                let mut shape = vec![0.0; nb];
                let mut energy = vec![0.0; nb];
                for (d, &b) in lin.bodies.iter().enumerate() {
                    shape[b] = eig.eigenvectors[(d, k)] * inv_sqrt[d];
                    energy[b] = eig.eigenvectors[(d, k)].powi(2);
                }
                let big =
                    shape
                        .iter()
                        .cloned()
                        .fold(0.0_f64, |m, x| if x.abs() > m.abs() { x } else { m });
                if big != 0.0 {
                    shape.iter_mut().for_each(|x| *x /= big);
                }
                let central: f64 = (0..nb).filter(|&b| !carried[b]).map(|b| energy[b]).sum();
                let kind = if rigid {
                    ModeKind::RigidBody
                } else if carried.iter().any(|&c| c) && central < PLANET_MODE_TOL {
                    ModeKind::Planet
                } else {
                    ModeKind::Rotational
                };
                Mode {
                    frequency_hz: if rigid {
                        0.0
                    } else {
                        lambda.sqrt() / std::f64::consts::TAU
                    },
                    kind,
                    multiplicity: 1,
                    shape,
                    energy,
                }
            })
            .collect();
        let fmax = modes.iter().map(|m| m.frequency_hz).fold(0.0, f64::max);
        let same = |a: f64, b: f64| (a - b).abs() <= FREQUENCY_TOL * fmax.max(f64::MIN_POSITIVE);
        let freqs: Vec<f64> = modes.iter().map(|m| m.frequency_hz).collect();
        for m in &mut modes {
            m.multiplicity = freqs.iter().filter(|&&f| same(f, m.frequency_hz)).count();
        }
        Modes {
            bodies: spec.bodies.iter().map(|b| b.name.clone()).collect(),
            modes,
        }
    }

    /// Modes of a kind.
    pub fn count(&self, kind: ModeKind) -> usize {
        self.modes.iter().filter(|m| m.kind == kind).count()
    }

    /// The distinct natural frequencies of elastic modes (Hz), with their multiplicity and kind.
    pub fn distinct(&self) -> Vec<(f64, usize, ModeKind)> {
        let mut out: Vec<(f64, usize, ModeKind)> = Vec::new();
        for m in self.modes.iter().filter(|m| m.kind != ModeKind::RigidBody) {
            if out
                .last()
                .is_none_or(|l| (l.0 - m.frequency_hz).abs() > FREQUENCY_TOL * m.frequency_hz)
            {
                out.push((m.frequency_hz, m.multiplicity, m.kind));
            }
        }
        out
    }
}
