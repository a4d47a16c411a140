//! The tabulation of one excitation period into [`Segment`]s: zones, backlash, friction factors
//! and the stiffness of each piece (constant, sampled table, or a physical pair's uniform
//! samples), adjacent identical pieces merged.

use super::{KForm, MeshModel, Segment, Zone};
use crate::params::{StiffnessForm, ZonePiece};

impl MeshModel {
    /// Fills the segments (and their stiffness tables) of one excitation period.
    pub(super) fn tabulate(&mut self, eps: f64, friction_on: bool) {
        if let StiffnessForm::Zoned { pieces } = &self.params.stiffness {
            let pieces = pieces.clone();
            self.tabulate_zoned(&pieces);
            return;
        }
        let p = &self.params;
        let fr = p.friction;
        let mut pieces: Vec<(f64, f64, Zone, f64)> = Vec::new(); // (start, end, zone, lambda) in-cycle
        for n in 0..self.cycles {
            pieces.clear();
            let broken = p.breakage.filter(|b| b.broken_cycle == n);
            let e_dbl = broken.map_or(eps, |b| b.eps_b) - 1.0;
            pieces.push((0.0, e_dbl, Zone::Double, 0.0));
            if e_dbl < eps - 1.0 {
                pieces.push((e_dbl, eps - 1.0, Zone::SingleII, 1.0));
            }
            if friction_on && fr.pitch > eps - 1.0 && fr.pitch < 1.0 {
                pieces.push((eps - 1.0, fr.pitch, Zone::Single, 1.0));
                pieces.push((fr.pitch, 1.0, Zone::Single, -1.0));
            } else {
                let lambda = if friction_on && fr.pitch <= eps - 1.0 {
                    -1.0
                } else {
                    1.0
                };
                pieces.push((eps - 1.0, 1.0, Zone::Single, lambda));
            }
            for &(a, b, zone, lambda) in &pieces {
                if b <= a {
                    continue;
                }
                let (d, hd, hb) = match zone {
                    Zone::Double => (p.d_double, 1.0, 1.0),
                    _ => (
                        p.d_single,
                        1.0 + fr.mu * lambda * fr.arm,
                        1.0 - fr.mu * lambda * fr.arm,
                    ),
                };
                let k = match (&p.stiffness, zone) {
                    (StiffnessForm::Constant { k }, _) => KForm::Const(*k),
                    (StiffnessForm::Harmonic { .. }, _) => KForm::Const(1.0),
                    (StiffnessForm::Rectangular { k_double, .. }, Zone::Double) => {
                        KForm::Const(*k_double)
                    }
                    (StiffnessForm::Rectangular { k_single, .. }, Zone::Single) => {
                        KForm::Const(*k_single)
                    }
                    (_, Zone::SingleII) => KForm::Const(broken.map_or(1.0, |b| b.k_zone2)),
                    // handled before the loop
                    (StiffnessForm::Zoned { .. }, _) => unreachable!("zoned tables return early"),
                    (StiffnessForm::Table { phase, k }, _) => {
                        push_table(&mut self.table_x, &mut self.table_k, phase, k, n, a, b)
                    }
                };
                let seg = Segment {
                    start: n as f64 + a,
                    end: n as f64 + b,
                    zone,
                    d,
                    h_drive: hd,
                    h_back: hb,
                    k,
                    h_tab: None,
                    n_uni: 0,
                    inv_du: 0.0,
                };
                // merge with the previous piece when nothing jumps at the border
                if let Some(last) = self.segs.last_mut() {
                    if last.d == seg.d
                        && last.h_drive == seg.h_drive
                        && last.h_back == seg.h_back
                        && matches!((last.k, seg.k), (KForm::Const(x), KForm::Const(y)) if x == y)
                    {
                        last.end = seg.end;
                        continue;
                    }
                }
                self.segs.push(seg);
            }
        }
        if let Some(last) = self.segs.last_mut() {
            last.end = self.cycles as f64;
        }
    }

    /// The segments of a physical pair's zone pieces (uniform samples of `k`, `h_drive`,
    /// `h_back`).
    fn tabulate_zoned(&mut self, pieces: &[ZonePiece]) {
        // Pieces with equal samples share one copy: the healthy cycles of a pair repeat the
        // same tables (the broken pair: 121 pieces, 5 distinct), and a step that crosses a
        // segment border then reads a few kilobytes that stay in the cache instead of a
        // megabyte that does not (the values read are the same either way).
        let mut seen: std::collections::HashMap<Vec<u64>, u32> = Default::default();
        for pc in pieces {
            let n = pc.k.len();
            let key: Vec<u64> = (pc.k.iter().chain(&pc.h_drive).chain(&pc.h_back))
                .map(|x| x.to_bits())
                .collect();
            let off = *seen.entry(key).or_insert_with(|| {
                let off = self.uniform.len() as u32;
                self.uniform.extend_from_slice(&pc.k);
                self.uniform.extend_from_slice(&pc.h_drive);
                self.uniform.extend_from_slice(&pc.h_back);
                off
            });
            self.segs.push(Segment {
                start: pc.start,
                end: pc.end,
                zone: if pc.zone_ii {
                    Zone::SingleII
                } else if pc.single {
                    Zone::Single
                } else {
                    Zone::Double
                },
                d: if pc.single {
                    self.params.d_single
                } else {
                    self.params.d_double
                },
                h_drive: pc.h_drive[0],
                h_back: pc.h_back[0],
                k: KForm::Uniform { off },
                h_tab: Some((off + n as u32, off + 2 * n as u32)),
                n_uni: n as u32,
                inv_du: (n - 1) as f64 / (pc.end - pc.start),
            });
        }
        if let Some(last) = self.segs.last_mut() {
            last.end = self.cycles as f64;
        }
    }
}

/// Appends the nodes of a sampled stiffness `k(phase)` on the piece `[a, b]` of cycle `n` (the
/// piece's own end values, one-sided, and the interior nodes) to the table.
#[allow(clippy::too_many_arguments)]
fn push_table(
    table_x: &mut Vec<f64>,
    table_k: &mut Vec<f64>,
    phase: &[f64],
    k: &[f64],
    n: u32,
    a: f64,
    b: f64,
) -> KForm {
    let off = table_x.len() as u32;
    let at = |u: f64| {
        let j = phase.partition_point(|&x| x <= u).clamp(1, phase.len() - 1);
        let (x0, x1) = (phase[j - 1], phase[j]);
        k[j - 1] + (k[j] - k[j - 1]) * (u - x0) / (x1 - x0)
    };
    // the zone's own end values (one-sided) plus the interior nodes
    table_x.push(n as f64 + a);
    table_k.push(at(a));
    for (j, &x) in phase.iter().enumerate() {
        if x > a && x < b {
            table_x.push(n as f64 + x);
            table_k.push(k[j]);
        }
    }
    table_x.push(n as f64 + b);
    let kb = {
        // left limit at b
        let j = phase.partition_point(|&x| x < b).clamp(1, phase.len() - 1);
        let (x0, x1) = (phase[j - 1], phase[j]);
        k[j - 1] + (k[j] - k[j - 1]) * (b - x0) / (x1 - x0)
    };
    table_k.push(kb);
    KForm::Table {
        off,
        len: table_x.len() as u32 - off,
    }
}
