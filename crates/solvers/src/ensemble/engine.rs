//! The engine of the lockstep ensemble: per-lane bookkeeping (times, grid positions, strobe
//! instants, the scalar integrator that finishes a lane's event steps) around the batched step of
//! a [`Lockstep`] model, and the loop [`drive`] that feeds lanes from a [`LaneDriver`].

use super::{At, End, LaneDriver, LaneStep, Lockstep, Next, Soa, Stage, StepStart};
use crate::hybrid::HybridSystem;
use crate::integrator::{Integrator, Scheme, SolverError, Stats, Stop};

/// Per-lane bookkeeping outside the hot arrays.
struct Slot<'s, S: HybridSystem<N>, const N: usize> {
    integ: Option<Integrator<&'s S, N>>,
    sys: Option<&'s S>,
    lock_rhs: u64,
    /// Work of integrators replaced by a restart.
    prior: Stats,
}

struct Engine<'s, B: Lockstep<N, L>, const N: usize, const L: usize>
where
    B::Sys: 's,
{
    /// States and derivatives, double-buffered: `y[cur]` is current, a lockstep step writes the
    /// other buffer and becomes current (lanes that did not take it are copied over), so a step
    /// costs no per-lane commit.
    y: [Soa<N, L>; 2],
    f: [Soa<N, L>; 2],
    cur: usize,
    t: [f64; L],
    idx: [f64; L],
    origin: [f64; L],
    h: [f64; L],
    tseg: [f64; L],
    kseg: [f64; L],
    period: [f64; L],
    lanes: B::Lanes,
    work: B::Work,
    lock_steps: [u64; L],
    /// busy lanes, lanes the batched field covers, lanes whose `f` must be recomputed
    active: u32,
    lockable: u32,
    stale: u32,
    /// lanes that took lockstep steps since their last scalar step
    progressed: u32,
    slots: [Slot<'s, B::Sys, N>; L],
}

impl<'s, B: Lockstep<N, L>, const N: usize, const L: usize> Engine<'s, B, N, L>
where
    B::Sys: 's,
{
    fn new(batch: &B) -> Self {
        Engine {
            y: [[[0.0; L]; N]; 2],
            f: [[[0.0; L]; N]; 2],
            cur: 0,
            t: [0.0; L],
            idx: [0.0; L],
            origin: [0.0; L],
            h: [0.0; L],
            tseg: [0.0; L],
            kseg: [0.0; L],
            period: [0.0; L],
            lanes: batch.idle_lanes(),
            work: batch.new_work(),
            lock_steps: [0; L],
            active: 0,
            lockable: 0,
            stale: 0,
            progressed: 0,
            slots: core::array::from_fn(|_| Slot {
                integ: None,
                sys: None,
                lock_rhs: 0,
                prior: Stats::default(),
            }),
        }
    }

    /// Takes the lane's state from its integrator (after a start, a restart or scalar steps).
    fn load_from_integ(&mut self, batch: &B, l: usize) {
        let slot = &self.slots[l];
        let integ = slot.integ.as_ref().expect("busy lane");
        let y = integ.y();
        for i in 0..N {
            self.y[self.cur][i][l] = y[i];
        }
        self.t[l] = integ.t();
        let bit = 1u32 << l;
        if batch.set_lane(
            &mut self.lanes,
            &mut self.work,
            l,
            slot.sys.expect("busy lane"),
            integ.mode(),
            self.h[l],
        ) {
            self.lockable |= bit;
            self.stale |= bit;
        } else {
            batch.set_idle(&mut self.lanes, l);
            self.lockable &= !bit;
        }
    }

    fn retire(&mut self, batch: &B, l: usize) {
        let bit = 1u32 << l;
        self.active &= !bit;
        self.lockable &= !bit;
        self.stale &= !bit;
        batch.set_idle(&mut self.lanes, l);
        for b in 0..2 {
            for i in 0..N {
                self.y[b][i][l] = 0.0;
                self.f[b][i][l] = 0.0;
            }
        }
        self.progressed &= !bit;
        let slot = &mut self.slots[l];
        slot.integ = None;
        slot.sys = None;
    }

    /// Memory parameter of lane `l`'s mode (its scalar integrator holds the mode: lockstep steps
    /// change no mode).
    fn memory(&self, l: usize) -> f64 {
        let slot = &self.slots[l];
        match (slot.sys, slot.integ.as_ref()) {
            (Some(sys), Some(integ)) => sys.memory(integ.mode()),
            _ => 0.0,
        }
    }

    fn stats(&self, l: usize) -> Stats {
        let slot = &self.slots[l];
        let mut s = slot.integ.as_ref().map(|i| i.stats()).unwrap_or_default();
        s.steps += slot.prior.steps + self.lock_steps[l];
        s.rejected += slot.prior.rejected;
        s.rhs_evals += slot.prior.rhs_evals + slot.lock_rhs + 4 * self.lock_steps[l];
        s.events += slot.prior.events;
        s.breakpoints += slot.prior.breakpoints;
        s
    }

    /// A fresh integrator for lane `l` at `(t0, y0)`; false (lane retired) if it cannot start.
    #[allow(clippy::too_many_arguments)]
    fn begin<D: LaneDriver<'s, B, N, L>>(
        &mut self,
        batch: &B,
        drv: &mut D,
        l: usize,
        sys: &'s B::Sys,
        t0: f64,
        y0: [f64; N],
        memory: f64,
        h: f64,
    ) -> bool {
        match Integrator::new(sys, Scheme::Rk4 { h }, t0, y0) {
            Ok(integ) => {
                let integ = integ.with_memory(memory);
                let slot = &mut self.slots[l];
                if let Some(old) = slot.integ.take() {
                    let s = old.stats();
                    slot.prior.steps += s.steps;
                    slot.prior.rejected += s.rejected;
                    slot.prior.rhs_evals += s.rhs_evals;
                    slot.prior.events += s.events;
                    slot.prior.breakpoints += s.breakpoints;
                }
                slot.integ = Some(integ);
                slot.sys = Some(sys);
                self.progressed &= !(1 << l);
                self.origin[l] = t0;
                self.idx[l] = 0.0;
                self.h[l] = h;
                self.tseg[l] = t0;
                self.kseg[l] = 0.0;
                self.active |= 1 << l;
                self.load_from_integ(batch, l);
                true
            }
            Err(e) => {
                drv.on_end(l, End::Failed(e));
                self.retire(batch, l);
                false
            }
        }
    }

    fn fill<D: LaneDriver<'s, B, N, L>>(&mut self, batch: &B, drv: &mut D) {
        for l in 0..L {
            while self.active & (1 << l) == 0 {
                let Some(st) = drv.next_item(l) else { break };
                if crate::cancel::requested() {
                    // (not started: it ends at once)
                    drv.on_end(l, End::Failed(SolverError::Cancelled));
                    continue;
                }
                self.period[l] = st.period;
                self.lock_steps[l] = 0;
                self.slots[l].lock_rhs = 0;
                self.slots[l].prior = Stats::default();
                self.begin(batch, drv, l, st.sys, st.t0, st.y0, st.memory, st.h);
            }
        }
    }

    /// Lane `l` takes the step to `target` (grid point `idx + 1`) with its scalar integrator.
    #[cold]
    #[inline(never)]
    fn scalar_step<D: LaneDriver<'s, B, N, L>>(
        &mut self,
        batch: &B,
        drv: &mut D,
        l: usize,
        target: f64,
        period_end: bool,
    ) {
        let mut y = [0.0; N];
        for i in 0..N {
            y[i] = self.y[self.cur][i][l];
        }
        let progressed = self.progressed & (1 << l) != 0;
        self.progressed &= !(1 << l);
        let slot = &mut self.slots[l];
        let sys = slot.sys.expect("busy lane");
        let integ = slot.integ.as_mut().expect("busy lane");
        integ.resume(self.t[l], y, self.idx[l] as i64, progressed);
        loop {
            let before = *integ.mode();
            match integ.step(target) {
                Ok(stop) => {
                    let shown = if stop == Stop::Tstop && !period_end {
                        Stop::Step
                    } else {
                        stop
                    };
                    drv.on_step(
                        l,
                        sys,
                        integ.last_step(),
                        &before,
                        shown,
                        integ.mode(),
                        integ.y(),
                    );
                    match stop {
                        Stop::Tstop => break,
                        Stop::Terminated { .. } => {
                            let (t, y) = (integ.t(), *integ.y());
                            let stats = self.stats(l);
                            let memory = self.memory(l);
                            drv.on_end(
                                l,
                                End::Done {
                                    t,
                                    y,
                                    memory,
                                    stats,
                                },
                            );
                            self.retire(batch, l);
                            return;
                        }
                        _ => {}
                    }
                }
                Err(e) => {
                    drv.on_end(l, End::Failed(e));
                    self.retire(batch, l);
                    return;
                }
            }
        }
        self.idx[l] += 1.0;
        self.load_from_integ(batch, l);
    }

    /// Reports lockstep steps of the lanes in `mask` through [`LaneDriver::on_step`].
    #[cold]
    #[inline(never)]
    fn explain<D: LaneDriver<'s, B, N, L>>(
        &self,
        drv: &mut D,
        st: &LaneStep<'_, B::Lanes, N, L>,
        mut mask: u32,
        period_end: bool,
    ) {
        let stop = if period_end { Stop::Tstop } else { Stop::Step };
        while mask != 0 {
            let l = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let slot = &self.slots[l];
            let (Some(sys), Some(integ)) = (slot.sys, slot.integ.as_ref()) else {
                continue;
            };
            let step = st.step(l);
            let mode = *integ.mode();
            let mut y1 = [0.0; N];
            for i in 0..N {
                y1[i] = st.y1[i][l];
            }
            drv.on_step(l, sys, &step, &mode, stop, &mode, &y1);
        }
    }

    /// Recomputes the start derivative of the stale lanes at the start of step `j`.
    #[inline(always)]
    fn refresh(&mut self, batch: &B, j: usize) {
        let stale = self.stale & self.lockable & self.active;
        if stale == 0 {
            return;
        }
        let mut f = [[0.0; L]; N];
        let at = At {
            t: self.t,
            grid: self.idx,
        };
        let c = self.cur;
        batch.rhs(j, Stage::Start, &at, &self.lanes, &self.y[c], &mut f);
        for l in 0..L {
            if stale & (1 << l) != 0 {
                for i in 0..N {
                    self.f[c][i][l] = f[i][l];
                }
                self.slots[l].lock_rhs += 1;
            }
        }
        self.stale = 0;
    }

    /// One grid step of every busy lane: phase `j` of `s_per`.
    #[inline(always)]
    fn step<D: LaneDriver<'s, B, N, L>>(&mut self, batch: &B, drv: &mut D, j: usize, s_per: usize) {
        let period_end = j + 1 == s_per;
        let mut t1 = [0.0; L];
        if period_end {
            for l in 0..L {
                t1[l] = self.tseg[l] + (self.kseg[l] + 1.0) * self.period[l];
            }
        } else {
            grid_times(&mut t1, &self.origin, &self.idx, &self.h);
        }
        let mut scalar = self.active;
        if !batch.scalar_phase(j) {
            self.refresh(batch, j);
            let c = self.cur;
            let (y0, y1) = pair(&mut self.y, c);
            let (f0, f1) = pair(&mut self.f, c);
            let s = StepStart {
                j,
                t0: &self.t,
                t1: &t1,
                grid: &self.idx,
                y0,
                f0,
            };
            let clear = batch.step(&s, &self.lanes, &self.work, y1, f1);
            let ok = self.active & self.lockable & clear;
            if ok != 0 {
                let st = LaneStep {
                    j,
                    mask: ok,
                    lanes: &self.lanes,
                    grid: &self.idx,
                    t0: &self.t,
                    t1: &t1,
                    y0: &self.y[c],
                    f0: &self.f[c],
                    y1: &self.y[1 - c],
                    f1: &self.f[1 - c],
                };
                let explain = drv.on_lockstep(batch, &st) & ok;
                if explain != 0 {
                    self.explain(drv, &st, explain, period_end);
                }
                // the lanes that took the step advance: one more grid step (an exact integer)
                // and lockstep step; the buffer the step wrote becomes current, with the state of
                // the busy lanes that did not take the step copied over (idle lanes stay at their
                // zero state either way)
                for l in 0..L {
                    self.idx[l] += 1.0;
                    self.lock_steps[l] += 1;
                }
                let mut t = t1;
                let mut keep = self.active & !ok;
                while keep != 0 {
                    let l = keep.trailing_zeros() as usize;
                    keep &= keep - 1;
                    for i in 0..N {
                        self.y[1 - c][i][l] = self.y[c][i][l];
                        self.f[1 - c][i][l] = self.f[c][i][l];
                    }
                    t[l] = self.t[l];
                    self.idx[l] -= 1.0;
                    self.lock_steps[l] -= 1;
                }
                self.t = t;
                self.cur = 1 - c;
                self.progressed |= ok;
            }
            scalar &= !ok;
        }
        while scalar != 0 {
            let l = scalar.trailing_zeros() as usize;
            scalar &= scalar - 1;
            self.scalar_step(batch, drv, l, t1[l], period_end);
        }
    }

    /// Ends every busy lane with [`SolverError::Cancelled`] (a stop was requested).
    #[cold]
    #[inline(never)]
    fn cancel_all<D: LaneDriver<'s, B, N, L>>(&mut self, batch: &B, drv: &mut D) {
        for l in 0..L {
            if self.active & (1 << l) != 0 {
                drv.on_end(l, End::Failed(SolverError::Cancelled));
                self.retire(batch, l);
            }
        }
    }

    /// The strobe instant at the end of a period for every busy lane.
    fn strobe<D: LaneDriver<'s, B, N, L>>(&mut self, batch: &B, drv: &mut D) {
        for l in 0..L {
            if self.active & (1 << l) == 0 {
                continue;
            }
            self.kseg[l] += 1.0;
            let mut y = [0.0; N];
            for i in 0..N {
                y[i] = self.y[self.cur][i][l];
            }
            let before = y;
            let next = drv.on_strobe_set(l, self.t[l], &mut y);
            if (0..N).any(|i| y[i].to_bits() != before[i].to_bits()) {
                // a replaced state: its derivative is recomputed before the next step
                for i in 0..N {
                    self.y[self.cur][i][l] = y[i];
                }
                self.stale |= (1 << l) & self.lockable;
                self.progressed |= 1 << l;
            }
            match next {
                Next::Continue => {}
                Next::Segment => {
                    self.tseg[l] = self.t[l];
                    self.kseg[l] = 0.0;
                }
                Next::Restart => {
                    let sys = self.slots[l].sys.expect("busy lane");
                    let (t, h) = (self.t[l], self.h[l]);
                    let memory = self.memory(l);
                    self.begin(batch, drv, l, sys, t, y, memory, h);
                }
                Next::Finish => {
                    let stats = self.stats(l);
                    let memory = self.memory(l);
                    drv.on_end(
                        l,
                        End::Done {
                            t: self.t[l],
                            y,
                            memory,
                            stats,
                        },
                    );
                    self.retire(batch, l);
                }
            }
        }
    }
}

/// `t1 = origin + (idx + 1) h` lane by lane, in whole vector blocks of 8 lanes (the times of a
/// grid step as the scalar integrator computes them). Written as blocks because the plain lane
/// loop was vectorised in odd pieces (8 + 4 + 1 + 2 + 1 lanes) whose loads could not be
/// forwarded from the previous step's stores: a tenth of the engine's time went to that stall.
#[inline(always)]
fn grid_times<const L: usize>(t1: &mut [f64; L], origin: &[f64; L], idx: &[f64; L], h: &[f64; L]) {
    const B: usize = 8;
    let mut t = t1.chunks_exact_mut(B);
    let mut o = origin.chunks_exact(B);
    let mut k = idx.chunks_exact(B);
    let mut hh = h.chunks_exact(B);
    for (((t, o), k), hh) in (&mut t).zip(&mut o).zip(&mut k).zip(&mut hh) {
        for i in 0..B {
            t[i] = o[i] + (k[i] + 1.0) * hh[i];
        }
    }
    let (t, o, k, hh) = (
        t.into_remainder(),
        o.remainder(),
        k.remainder(),
        hh.remainder(),
    );
    for i in 0..t.len() {
        t[i] = o[i] + (k[i] + 1.0) * hh[i];
    }
}

/// The current buffer and the other one of a double buffer.
#[inline(always)]
fn pair<T>(b: &mut [T; 2], cur: usize) -> (&T, &mut T) {
    let [b0, b1] = b;
    if cur == 0 {
        (b0, b1)
    } else {
        (b1, b0)
    }
}

#[inline(always)]
pub(super) fn drive<'s, B, D, const N: usize, const L: usize>(batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    assert!(L >= 1 && L <= 32, "1 to 32 lanes");
    let s_per = batch.steps_per_period();
    assert!(s_per >= 1, "a period has at least one step");
    let mut e: Engine<'s, B, N, L> = Engine::new(batch);
    loop {
        e.fill(batch, drv);
        if e.active == 0 {
            return;
        }
        if crate::cancel::requested() {
            e.cancel_all(batch, drv);
            continue;
        }
        for j in 0..s_per {
            e.step(batch, drv, j, s_per);
            if e.active == 0 {
                break;
            }
        }
        if e.active != 0 {
            e.strobe(batch, drv);
        }
    }
}
