//! Rigid-body kinematics of a train: the speed of every body per unit input speed, from the
//! meshes' rolling conditions (no deflection rate: `a · Omega = 0`, [`crate::linear::mesh_coefficients`]),
//! rigid shafts (`Omega_i = Omega_j`) and supports (a fixed or elastically supported body
//! stands still in steady operation).
//!
//! The conditions must leave exactly one free motion, the input's: a train with more (a
//! differential with no body held, a gear meshing with nothing) or none (a locked train) is
//! refused with the count.

use crate::description::TrainSpec;
use crate::error::TrainError;
use crate::linear::mesh_coefficients;
use nalgebra::DMatrix;

/// Relative tolerance of a zero singular value of the rolling conditions.
const RANK_TOL: f64 = 1e-9;

/// Speeds per unit input speed and mesh frequencies.
#[derive(Clone, Debug, PartialEq)]
pub struct Kinematics {
    /// Speed of each body (in the description's order) per unit speed of `load.input`.
    pub ratios: Vec<f64>,
    /// Per mesh: tooth passes per input revolution (the first gear's teeth times its
    /// revolutions relative to the mesh's carrier).
    pub mesh_orders: Vec<f64>,
}

impl Kinematics {
    /// The kinematics of a validated train.
    pub fn of(spec: &TrainSpec) -> Result<Kinematics, TrainError> {
        let n = spec.bodies.len();
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for m in &spec.meshes {
            let mut r = vec![0.0; n];
            for (b, c) in mesh_coefficients(spec, m) {
                r[b] += c;
            }
            rows.push(r);
        }
        let idx = |s: &str| spec.body_index(s).expect("validated");
        for s in &spec.shafts {
            let mut r = vec![0.0; n];
            r[idx(&s.bodies[0])] = 1.0;
            r[idx(&s.bodies[1])] = -1.0;
            rows.push(r);
        }
        for s in &spec.supports {
            let mut r = vec![0.0; n];
            r[idx(&s.body)] = 1.0;
            rows.push(r);
        }
        // the scale of each row is its own (m for meshes, 1 for shafts): normalise
        for r in &mut rows {
            let s = r.iter().map(|x| x * x).sum::<f64>().sqrt();
            r.iter_mut().for_each(|x| *x /= s);
        }
        let c = DMatrix::from_fn(rows.len(), n, |i, j| rows[i][j]);
        let ctc = c.transpose() * &c;
        let eig = ctc.symmetric_eigen();
        let top = eig
            .eigenvalues
            .iter()
            .cloned()
            .fold(0.0_f64, f64::max)
            .max(1.0);
        let free: Vec<usize> = (0..n)
            .filter(|&i| eig.eigenvalues[i] < RANK_TOL * top)
            .collect();
        if free.len() != 1 {
            return Err(TrainError::Kinematics(format!(
                "the train has {} free motion{} for one input: {}",
                free.len(),
                if free.len() == 1 { "" } else { "s" },
                if free.is_empty() {
                    "it is locked (the meshes, shafts and supports leave no motion: a fixed body on the load path, or tooth counts that do not close)"
                } else {
                    "a body turns freely or the train is a differential (hold a body with a support, or join it by a mesh or shaft)"
                }
            )));
        }
        let v = eig.eigenvectors.column(free[0]);
        let input = idx(&spec.load.input);
        if v[input].abs() < 1e-12 {
            return Err(TrainError::Kinematics(format!(
                "no load path: load.input {:?} cannot turn (it is held by the rest of the train)",
                spec.load.input
            )));
        }
        let held: Vec<usize> = spec.supports.iter().map(|s| idx(&s.body)).collect();
        // (a held body stands still exactly, not to the eigensolver's rounding)
        let ratios: Vec<f64> = (0..n)
            .map(|i| {
                if held.contains(&i) {
                    0.0
                } else {
                    v[i] / v[input]
                }
            })
            .collect();
        let mesh_orders = spec
            .meshes
            .iter()
            .map(|m| {
                let a = idx(&m.gears[0]);
                let carrier = m.carrier.as_deref().map_or(0.0, |c| ratios[idx(c)]);
                f64::from(m.teeth[0]) * (ratios[a] - carrier).abs()
            })
            .collect();
        Ok(Kinematics {
            ratios,
            mesh_orders,
        })
    }
}

impl Kinematics {
    /// Meshing events per input revolution of one tooth of the gear `body` (a local fault's
    /// characteristic order): for each mesh the gear takes part in, its revolutions relative to
    /// that mesh's carrier per input revolution. A chipped sun tooth of a stage with `N` planets
    /// meets a planet `N (Omega_s - Omega_c) / Omega_s` times per sun revolution (McFadden &
    /// Smith 1985: the sun-fault frequency `N f_m / Z_s`).
    pub fn fault_order(&self, spec: &TrainSpec, body: usize) -> f64 {
        let idx = |s: &str| spec.body_index(s).expect("validated");
        spec.meshes
            .iter()
            .filter(|m| m.gears.iter().any(|g| idx(g) == body))
            .map(|m| {
                let carrier = m.carrier.as_deref().map_or(0.0, |c| self.ratios[idx(c)]);
                (self.ratios[body] - carrier).abs()
            })
            .sum()
    }
}
