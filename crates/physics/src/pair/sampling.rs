//! The sampling of one mesh cycle of a [`PairSpec`](super::PairSpec): per zone piece (double,
//! single, a broken tooth's zone II; split where the sliding direction flips at the pitch point)
//! the stiffness of both tooth pairs, their load shares, the lubrication state and the friction
//! factors at `samples_per_cycle` positions per cycle.

use super::{PairSpec, StiffnessRow, PITCH_SPLIT_MIN};
use crate::geometry::{PairGeometry, PairKind};
use crate::lubrication::{friction, ContactConditions, FrictionState, Regime};
use crate::mesh_stiffness::{load_shares, HertzModel, StiffnessModel};

/// One zone piece of a sampled cycle: start, end (mesh cycles), single-tooth zone, zone II of a
/// broken tooth, and its samples.
pub(super) type Piece = (f64, f64, bool, bool, Vec<StiffnessRow>);

/// What the sampling of a cycle reads: the pair, its stiffness model, the effective mass terms,
/// the operating speeds and the breakage's contact end.
pub(super) struct CycleSampler<'a> {
    pub spec: &'a PairSpec,
    pub geom: &'a PairGeometry,
    pub sm: &'a StiffnessModel,
    /// Effective mass and inertias (friction arms of the mesh force).
    pub m_e: f64,
    pub i_p: f64,
    pub i_g: f64,
    /// Angular speeds of pinion and gear (rad/s), the static load (N), the face width (m) and
    /// the reduced modulus (Pa): the lubrication's contact conditions.
    pub omega1: f64,
    pub omega2: f64,
    pub static_load: f64,
    pub b: f64,
    pub e_red: f64,
    /// Contact ratio of the broken pair, if broken, and the end of its double contact.
    pub eps_b: Option<f64>,
    pub s_d1: f64,
}

impl CycleSampler<'_> {
    /// The lubrication state of a contact at `s` carrying the load share `share` (none without
    /// lubrication).
    fn lubricated(&self, s: f64, share: f64) -> Option<FrictionState> {
        let lub = self.spec.lubrication.as_ref()?;
        let geom = self.geom;
        let (r1, r2) = geom.friction_arms(s);
        let r = match geom.kind {
            PairKind::External => r1 * r2 / (r1 + r2),
            PairKind::Internal => r1 * r2 / (r2 - r1),
        };
        let c = ContactConditions {
            u1: self.omega1 * r1,
            u2: self.omega2 * r2,
            r,
            w: self.static_load * share.max(1e-3) / self.b,
            e_red: self.e_red,
        };
        Some(friction(&c, lub))
    }

    /// The friction arm term of a contact at `s`: `m_e (rb1 s_p / I_p + rb2 s_g / I_g)`.
    fn arms(&self, s: f64) -> f64 {
        let geom = self.geom;
        let (sp, sg) = geom.friction_arms(s);
        self.m_e * (geom.rb1 * sp / self.i_p + geom.rb2 * sg / self.i_g)
    }

    /// The pieces of one cycle, healthy or broken (the broken tooth's cycle).
    pub fn cycle(&self, broken: bool) -> Vec<Piece> {
        let (spec, geom) = (self.spec, self.geom);
        let n = spec.samples_per_cycle as usize;
        let mu = spec.mu;
        let eps = geom.eps;
        let e_dbl = if broken {
            self.eps_b.unwrap_or(eps) - 1.0
        } else {
            eps - 1.0
        };
        let mut out = Vec::new();
        let mut pieces = vec![(0.0, e_dbl, false, false)];
        if broken && e_dbl < eps - 1.0 {
            pieces.push((e_dbl, eps - 1.0, true, true));
        }
        pieces.push((eps - 1.0, 1.0, true, false));
        // The sliding direction of a pair flips where it passes the pitch point: the friction
        // factor jumps there, so that instant is a piece border (a time breakpoint the
        // integrator steps onto), not a jump smeared across one table interval.
        // (the crossings of the pair entering at the cycle's start and of the one ahead of
        // it, in ascending order; none without friction)
        let pitch = (geom.s_p - geom.s_a) / geom.pb;
        let flips: &[f64] = if mu > 0.0 || spec.lubrication.is_some() {
            &[pitch - 1.0, pitch]
        } else {
            &[]
        };
        let pieces: Vec<_> = pieces
            .into_iter()
            .flat_map(|(a, bnd, single, zone_ii)| {
                let mut ends = vec![a];
                ends.extend(
                    flips
                        .iter()
                        .filter(|&&f| f > a + PITCH_SPLIT_MIN && f < bnd - PITCH_SPLIT_MIN),
                );
                ends.push(bnd);
                ends.windows(2)
                    .map(|w| (w[0], w[1], single, zone_ii))
                    .collect::<Vec<_>>()
            })
            .collect();
        for (a, bnd, single, zone_ii) in pieces {
            // a sample on the pitch point takes the direction of the piece it belongs to
            // (that of the pair's position at the piece's middle)
            let mid = geom.s_a + 0.5 * (a + bnd) * geom.pb;
            let direction = |s: f64, s_mid: f64| {
                if (s - geom.s_p).abs() <= PITCH_SPLIT_MIN * geom.pb {
                    geom.sliding_direction(s_mid)
                } else {
                    geom.sliding_direction(s)
                }
            };
            let cnt = (((bnd - a) * n as f64).ceil() as usize).max(2);
            let mut rows = Vec::with_capacity(cnt + 1);
            for j in 0..=cnt {
                let phi = a + (bnd - a) * j as f64 / cnt as f64;
                let s0 = geom.s_a + phi * geom.pb;
                let s1 = s0 + geom.pb;
                let end1 = if broken { self.s_d1 } else { geom.s_d };
                let in1 = !single && s1 <= end1 + 1e-12;
                let contact = [true, in1];
                let frac = if e_dbl > 0.0 {
                    (phi / e_dbl).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let mut k = [
                    self.sm.pair_stiffness(s0, if in1 { 0.5 } else { 1.0 }),
                    if in1 {
                        self.sm.pair_stiffness(s1, 0.5)
                    } else {
                        0.0
                    },
                ];
                let mut l = load_shares(spec.load_sharing, k, contact, frac, 0);
                if spec.hertz == HertzModel::Nonlinear
                    || self.sm.thermal.is_some_and(|t| t.1 != 0.0)
                {
                    // one fixed-point pass: Hertz stiffness at the pair's own load share
                    k = [
                        self.sm.pair_stiffness(s0, l[0]),
                        if in1 {
                            self.sm.pair_stiffness(s1, l[1])
                        } else {
                            0.0
                        },
                    ];
                    l = load_shares(spec.load_sharing, k, contact, frac, 0);
                }
                let st0 = self.lubricated(s0, l[0]);
                let st1 = if in1 { self.lubricated(s1, l[1]) } else { None };
                let mu0 = st0.map_or(mu, |st| st.mu);
                let mu1 = if in1 { st1.map_or(mu, |st| st.mu) } else { 0.0 };
                let mut fr = mu0 * direction(s0, mid) * self.arms(s0) * l[0];
                if in1 {
                    fr += mu1 * direction(s1, mid + geom.pb) * self.arms(s1) * l[1];
                }
                rows.push(StiffnessRow {
                    position: phi,
                    k_pair1: k[0],
                    k_pair2: k[1],
                    k_mesh: k[0] + k[1],
                    share1: l[0],
                    share2: l[1],
                    h_drive: 1.0 + fr,
                    h_back: 1.0 - fr,
                    single,
                    mu1: mu0,
                    mu2: mu1,
                    film1: st0.map_or(0.0, |st| st.film),
                    lambda1: st0.map_or(0.0, |st| st.lambda),
                    regime1: st0.map_or(-1, |st| match st.regime {
                        Regime::Ehl => 0,
                        Regime::Mixed => 1,
                        Regime::Boundary => 2,
                    }),
                });
            }
            out.push((a, bnd, single, zone_ii, rows));
        }
        out
    }
}
