//! Where a step's events are: the earliest armed crossing of the trial step (sign changes at
//! the samples, grazes found by a golden-section search on the interpolant), its location
//! polished on the true step map, and the event's handling (reset, new mode, Zeno fallback).

use super::{guards_into, Integrator, Trial};
use crate::hybrid::{Direction, EventAction, Guards, HybridSystem};
use crate::scheme::{Options, Scheme, SolverError, Stop, MAX_GRAZING_SAMPLES};

impl<S: HybridSystem<N>, const N: usize> Integrator<S, N> {
    /// Earliest armed crossing in the trial step: guard index and a bracket in time.
    ///
    /// Sign changes between samples are found first; a sample that is a local extremum of a guard
    /// towards zero (the trajectory turning near the surface) is refined by a golden-section search
    /// on the interpolant, which catches a graze that enters and leaves within one step.
    /// Samples are read element by element from the guard buffers: copying whole freshly written
    /// arrays stalled store forwarding and cost a third of the step time.
    #[inline]
    pub(super) fn find_crossing(
        &self,
        trial: &Trial<S::TimeTerms, N>,
        g0: &Guards,
        g1: &Guards,
    ) -> Option<(usize, f64, f64, f64, f64)> {
        let n = g0.len.min(g1.len);
        if n == 0 {
            return None;
        }
        let m = self.grazing_m;
        let (t0, t1) = (trial.step.t0, trial.step.t1);
        // Fast path (almost every step): no sign change between the ends; only a turning point
        // at the midpoint can hide a graze.
        let any_end_crossing = (0..n).any(|i| g0.direction[i].crossed(g0.value[i], g1.value[i]));
        if !any_end_crossing {
            if m == 0 {
                return None;
            }
            // rigorous skip: the interpolant deviates from its chord by at most
            // max_i 0.25 (|r2| + |r3| + |r4|); guards affine in the state move by at most L times it
            if let Some(l) = self.sys.guard_lipschitz(&self.mode) {
                let r = &trial.step.r;
                let mut dev = 0.0f64;
                for i in 0..N {
                    dev = dev.max(r[2][i].abs() + r[3][i].abs() + r[4][i].abs());
                }
                let margin = 0.25 * l * dev;
                let clear = (0..n).all(|i| {
                    let (p, b) = (g0.value[i], g1.value[i]);
                    (p > 0.0) == (b > 0.0) && p.abs().min(b.abs()) > margin
                });
                if clear {
                    return None;
                }
            }
            let mut gm = Guards::EMPTY;
            let tm = 0.5 * (t0 + t1);
            guards_into(
                &self.sys,
                tm,
                &trial.step.at_theta(0.5),
                &self.mode,
                &mut gm,
            );
            let mut best: Option<(usize, f64, f64, f64, f64)> = None;
            for i in 0..n {
                let (p, a, b) = (g0.value[i], gm.value[i], g1.value[i]);
                let d = g0.direction[i];
                let near = d.near_crossing(p, a, b);
                if near {
                    if let Some(br) = self.graze_search(trial, i, d, t0, p, t1) {
                        if best.is_none_or(|x| br.3 < x.3) {
                            best = Some(br);
                        }
                    }
                }
            }
            return best;
        }
        const INV: [f64; MAX_GRAZING_SAMPLES + 2] = [1.0, 1.0, 0.5, 1.0 / 3.0, 0.25, 0.2];
        let mut ts = [0.0; MAX_GRAZING_SAMPLES + 2];
        let mut gint = [Guards::EMPTY; MAX_GRAZING_SAMPLES];
        ts[0] = t0;
        ts[m + 1] = t1;
        let val = |gint: &[Guards; MAX_GRAZING_SAMPLES], j: usize, i: usize| -> f64 {
            if j == 0 {
                g0.value[i]
            } else if j == m + 1 {
                g1.value[i]
            } else {
                gint[j - 1].value[i]
            }
        };
        for j in 1..=m + 1 {
            if j <= m {
                let th = j as f64 * INV[m + 1];
                ts[j] = t0 + th * (t1 - t0);
                let yb = trial.step.at_theta(th);
                guards_into(&self.sys, ts[j], &yb, &self.mode, &mut gint[j - 1]);
            }
            let mut best: Option<(usize, f64, f64, f64, f64)> = None;
            // a turning point at the previous interior sample (window j-2 .. j)
            if j >= 2 {
                for i in 0..n {
                    let (p, a, b) = (val(&gint, j - 2, i), val(&gint, j - 1, i), val(&gint, j, i));
                    let turning = if a < 0.0 {
                        a > p && a >= b
                    } else {
                        a > 0.0 && a < p && a <= b
                    };
                    if turning {
                        if let Some(br) =
                            self.graze_search(trial, i, g0.direction[i], ts[j - 2], p, ts[j])
                        {
                            if best.is_none_or(|x| br.3 < x.3) {
                                best = Some(br);
                            }
                        }
                    }
                }
                if best.is_some() {
                    return best;
                }
            }
            // earliest root among the guards crossing in [t_{j-1}, t_j]
            for i in 0..n {
                let dir = g0.direction[i];
                let (ga, gb) = (val(&gint, j - 1, i), val(&gint, j, i));
                if dir.crossed(ga, gb) {
                    let br = self.locate(trial, i, dir, ts[j - 1], ga, ts[j], gb);
                    if best.is_none_or(|b| br.3 < b.3) {
                        best = Some(br);
                    }
                }
            }
            if best.is_some() {
                return best;
            }
        }
        None
    }

    pub(super) fn grazing_samples(scheme: Scheme, opts: &Options) -> usize {
        match opts.grazing_samples {
            Some(m) => m.min(MAX_GRAZING_SAMPLES),
            // small fixed steps need fewer samples than long adaptive ones
            None => match scheme {
                Scheme::Rk4 { .. } => 1,
                Scheme::DormandPrince { .. } => 3,
            },
        }
    }

    /// The guard `i` turns towards zero inside `[tp, tb]` (it starts at `gpi` at `tp`): find its
    /// extremum on the interpolant and, if that crosses zero in the armed direction, bracket the
    /// first crossing.
    #[cold]
    fn graze_search(
        &self,
        trial: &Trial<S::TimeTerms, N>,
        i: usize,
        dir: Direction,
        tp: f64,
        gpi: f64,
        tb: f64,
    ) -> Option<(usize, f64, f64, f64, f64)> {
        let mut gbuf = Guards::default();
        // move from the start value towards zero: maximise sgn*g
        let sgn = if gpi < 0.0 { 1.0 } else { -1.0 };
        let mut gfun = |t: f64| {
            let y = trial.step.interpolate(t);
            guards_into(&self.sys, t, &y, &self.mode, &mut gbuf);
            sgn * gbuf.value[i]
        };
        const R: f64 = 0.618_033_988_749_894_9;
        let (mut a, mut b) = (tp, tb);
        let mut c = b - R * (b - a);
        let mut d = a + R * (b - a);
        let (mut fc, mut fd) = (gfun(c), gfun(d));
        let tol = 1e-10 * (tb - tp).abs();
        for _ in 0..60 {
            if fc.max(fd) >= 0.0 || (b - a).abs() < tol {
                break;
            }
            if fc > fd {
                b = d;
                d = c;
                fd = fc;
                c = b - R * (b - a);
                fc = gfun(c);
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + R * (b - a);
                fd = gfun(d);
            }
        }
        let (fpk, tpk) = if fc >= fd { (fc, c) } else { (fd, d) };
        if fpk >= 0.0 {
            let g_peak = sgn * fpk;
            if dir.crossed(gpi, g_peak) {
                return Some(self.locate(trial, i, dir, tp, gpi, tpk, g_peak));
            }
        }
        None
    }

    #[allow(clippy::too_many_arguments)]
    fn locate(
        &self,
        trial: &Trial<S::TimeTerms, N>,
        i: usize,
        dir: Direction,
        ta: f64,
        ga: f64,
        tb: f64,
        gb: f64,
    ) -> (usize, f64, f64, f64, f64) {
        let mut gbuf = Guards::default();
        let xtol = 4.0 * f64::EPSILON * tb.abs().max(1.0);
        let br = crate::root::illinois(
            |t| {
                let y = trial.step.interpolate(t);
                guards_into(&self.sys, t, &y, &self.mode, &mut gbuf);
                gbuf.value[i]
            },
            ta,
            ga,
            tb,
            gb,
            xtol,
            |g| dir.on_new_side(ga, g),
        );
        (i, br.a, br.fa, br.b, br.fb)
    }

    /// Polishes the crossing on the true step map, lands on the new side, applies the event.
    pub(super) fn handle_event(
        &mut self,
        idx: usize,
        ta: f64,
        ga: f64,
        tb: f64,
        gb: f64,
        h_max: f64,
    ) -> Result<Stop, SolverError> {
        let t0 = self.t;
        let dir = self.gbuf[self.gcur].direction[idx];
        let g_start = self.gbuf[self.gcur].value[idx];
        let xtol = 4.0 * f64::EPSILON * tb.abs().max(1.0);
        let mut gbuf = Guards::default();
        // secant iterations on phi(h) = g(step(h)), started from the interpolant's root
        let slope = if tb != ta { (gb - ga) / (tb - ta) } else { 0.0 };
        let mut h = (tb - t0).clamp(0.0, h_max);
        let mut tr = self.trial(h);
        guards_into(&self.sys, t0 + h, &tr.y1, &self.mode, &mut gbuf);
        let mut phi = gbuf.value[idx];
        let mut prev: Option<(f64, f64)> = None;
        let mut slope = slope;
        for _ in 0..6 {
            if phi == 0.0 || !slope.is_finite() || slope == 0.0 {
                break;
            }
            if let Some((hp, pp)) = prev {
                if h != hp && phi != pp {
                    slope = (phi - pp) / (h - hp);
                }
            }
            let dh = -phi / slope;
            if !dh.is_finite() {
                break;
            }
            let h_new = (h + dh).clamp(0.0, h_max);
            if (h_new - h).abs() <= xtol {
                break;
            }
            prev = Some((h, phi));
            h = h_new;
            tr = self.trial(h);
            guards_into(&self.sys, t0 + h, &tr.y1, &self.mode, &mut gbuf);
            phi = gbuf.value[idx];
        }
        // make sure the state lies on the new side (so the new mode is consistent with it)
        let mut nudge = xtol;
        for _ in 0..40 {
            if dir.on_new_side(g_start, phi) || h >= h_max {
                break;
            }
            h = (h + nudge).min(h_max);
            nudge *= 2.0;
            tr = self.trial(h);
            guards_into(&self.sys, t0 + h, &tr.y1, &self.mode, &mut gbuf);
            phi = gbuf.value[idx];
        }
        if tr.y1.iter().any(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite { t: t0 + h });
        }
        self.stats.steps += 1;
        self.stats.events += 1;
        self.t = t0 + h;
        self.y = tr.y1;
        self.last = tr.step;
        // --- accumulation of events (Zeno): closer than a fraction of the step-size scale
        let scale = match self.scheme {
            Scheme::Rk4 { h } => h,
            Scheme::DormandPrince { .. } => h_max.max(self.h_next.min(self.sys.max_step())),
        };
        let quick = Self::snap(self.t).max(self.opts.zeno_interval * scale);
        // (NaN before the first event: not accumulating)
        if self.t - self.last_event_t <= quick {
            if self.events_without_progress == 0 {
                self.zeno_run_start = self.last_event_t;
            }
            self.events_without_progress += 1;
        } else {
            self.events_without_progress = 0;
        }
        self.last_event_t = self.t;
        let action = self.sys.on_event(self.t, &mut self.y, &mut self.mode, idx);
        if self.events_without_progress > self.opts.max_events_without_progress
            && action == EventAction::Continue
        {
            let count = self.events_without_progress;
            let span = self.t - self.zeno_run_start;
            if self.zeno_fallback_pending
                || !self
                    .sys
                    .zeno_fallback(self.t, &mut self.y, &mut self.mode, idx)
            {
                return Err(SolverError::Zeno {
                    t: self.t,
                    count,
                    span,
                });
            }
            self.zeno_fallback_pending = true;
            self.events_without_progress = 0;
        }
        self.f0_valid = false;
        self.g0_valid = false;
        self.next_bp = self.sys.next_breakpoint(self.t, &self.mode);
        if self.y.iter().any(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite { t: self.t });
        }
        Ok(match action {
            EventAction::Continue => Stop::Event { index: idx },
            EventAction::Terminate => Stop::Terminated { index: idx },
        })
    }
}
