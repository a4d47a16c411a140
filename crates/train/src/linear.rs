//! The linear model of a train at mean mesh stiffness: `M theta'' + K theta = 0` in the absolute
//! rotations `theta` (rad) of its bodies that are not fixed.
//!
//! `M` is diagonal: each body's polar inertia, the carrier's increased by `m r²` for every body
//! it carries (a planet's mass at its orbit radius). `K` sums, per mesh, `k a aᵀ` with `a` the
//! deflection's coefficients ([`mesh_coefficients`]), per shaft `k (e_i - e_j)(e_i - e_j)ᵀ`, per
//! elastic support `k e_i e_iᵀ`. Fixed bodies are not coordinates.

use crate::description::{Mesh, TrainSpec};
use geardyn_physics::geometry::PairKind;
use nalgebra::{DMatrix, DVector};

/// A mesh's deflection along its line of action per unit rotation of each body it involves
/// (m/rad): `(body index, coefficient)` for its two gears and, if it has one, its carrier
/// (`-(s_a r_a + s_b r_b)`; see [`crate::description`]).
pub fn mesh_coefficients(spec: &TrainSpec, m: &Mesh) -> Vec<(usize, f64)> {
    let idx = |s: &str| spec.body_index(s).expect("a validated train");
    let (ra, rb) = (m.base_radii_mm[0] * 1e-3, m.base_radii_mm[1] * 1e-3);
    let sa = match m.kind {
        PairKind::External => 1.0,
        PairKind::Internal => -1.0,
    };
    let mut c = vec![(idx(&m.gears[0]), sa * ra), (idx(&m.gears[1]), rb)];
    if let Some(carrier) = &m.carrier {
        c.push((idx(carrier), -(sa * ra + rb)));
    }
    c
}

/// Mass and stiffness matrices of the bodies that are not fixed.
#[derive(Clone, Debug)]
pub struct LinearModel {
    /// Body index of each coordinate.
    pub bodies: Vec<usize>,
    /// Diagonal of `M` (kg m²).
    pub mass: DVector<f64>,
    /// `K` (N m/rad).
    pub stiffness: DMatrix<f64>,
}

impl LinearModel {
    /// The model of a validated train.
    pub fn of(spec: &TrainSpec) -> LinearModel {
        let bodies: Vec<usize> = (0..spec.bodies.len())
            .filter(|&i| !spec.is_fixed(i))
            .collect();
        let n = bodies.len();
        let dof = |b: usize| bodies.iter().position(|&x| x == b);
        let mut mass =
            DVector::from_iterator(n, bodies.iter().map(|&b| spec.bodies[b].inertia_kgm2));
        for body in &spec.bodies {
            if let Some(c) = &body.carrier {
                let ci = spec.body_index(c).expect("validated");
                if let Some(d) = dof(ci) {
                    let r = body.orbit_radius_mm * 1e-3;
                    mass[d] += body.mass_kg * r * r;
                }
            }
        }
        let mut k = DMatrix::zeros(n, n);
        let mut add = |terms: &[(usize, f64)], stiff: f64| {
            for &(bi, ci) in terms {
                for &(bj, cj) in terms {
                    if let (Some(i), Some(j)) = (dof(bi), dof(bj)) {
                        k[(i, j)] += stiff * ci * cj;
                    }
                }
            }
        };
        for m in &spec.meshes {
            add(&mesh_coefficients(spec, m), m.stiffness_n_per_m);
        }
        let idx = |s: &str| spec.body_index(s).expect("validated");
        for s in &spec.shafts {
            add(
                &[(idx(&s.bodies[0]), 1.0), (idx(&s.bodies[1]), -1.0)],
                s.stiffness_nm_per_rad,
            );
        }
        for s in &spec.supports {
            if let Some(ks) = s.stiffness_nm_per_rad {
                add(&[(idx(&s.body), 1.0)], ks);
            }
        }
        LinearModel {
            bodies,
            mass,
            stiffness: k,
        }
    }

    /// Coordinates (bodies not fixed).
    pub fn len(&self) -> usize {
        self.bodies.len()
    }

    /// No coordinates?
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }
}
