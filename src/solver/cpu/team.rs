//! The frame on several threads: every thread of the solver's pool runs the whole substep loop as
//! one team. Each takes its share of the particles in the per-particle passes and of each large
//! color group in the sweeps, so one frame costs one wake-up of the pool instead of a fork and
//! join per group. A thread waits for the others only before the part of its share that touches
//! particles another thread touches too ([`Plan`]), so a thread that is ahead goes on with the
//! rest of its share instead of waiting at every group. In Gauss-Seidel without the global
//! balance or the local mode, the finish pass (which makes the next substep's prediction too) is
//! such a step as well, each thread zeroes the multipliers of its own parts, and the substeps
//! follow one another without a barrier: the team meets only after the frame's first prediction
//! and at its end. The global balance (which scales every velocity between the finish pass and
//! the next prediction), the local mode (whose snapshots and start energies read every particle)
//! and Jacobi (whose sums read every element's corrections) meet at spin barriers around those
//! passes. The elements of a group share no particle, the passes touch each particle alone, and
//! two elements that share a particle are visited in the order of their groups, so the positions
//! come out the same, bit for bit, for any thread count. Each thread times its waits, and the
//! solver sums each thread's time working and waiting over the team's frames
//! ([`super::TeamTime`]).

use std::cell::Cell;
use std::ops::Range;
use std::time::{Duration, Instant};

use crate::math::prelude::*;
use crate::scene::{FAMILY_COUNT, Family, Scene};

use super::super::barrier::{SpinBarrier, Waited, share};
use super::super::contacts::project_range;
use super::super::energy::EnergyAware;
use super::super::jacobi;
use super::super::particles::{self, FinishStep, WORK_BLOCK};
use super::super::shared::{Prechecked, SharedPositions};
use super::super::xpbd::StepConstants;
use super::super::{Method, PARALLEL_MIN_GROUP, Settings};
use super::plan::{FamilyPlan, Part, Plan, particle_share};
use super::{
    CpuSolver, FamilyState, JacobiAt, LocalCtx, balance, checked_bound, fuses_predict, jacobi_element, local_adjusted,
    plain_chunk, start_energies, total_energy, update,
};
use crate::constraints::{Element, LaneData};

/// `true` when some family the threads may split (its groups checked disjoint in `fam`) has a
/// group of at least [`PARALLEL_MIN_GROUP`] elements; else one thread does it all, faster.
pub(super) fn splittable<S>(scene: &Scene, fam: &[FamilyState<S>; FAMILY_COUNT]) -> bool {
    let mut large = false;
    crate::for_each_family!(scene, |i, f| {
        large |= fam[i].disjoint && f.colors.iter().any(|r| r.len() >= PARALLEL_MIN_GROUP)
    });
    large
}

/// Per-thread handles on the solver's arrays (copies of one set of shared views).
#[derive(Clone, Copy)]
struct Views<'a, V: Vector> {
    x: SharedPositions<'a, V>,
    x_prev: SharedPositions<'a, V>,
    v: SharedPositions<'a, V>,
    /// The finish pass's work per block of particles, a row of blocks per substep (J).
    work: SharedPositions<'a, f64>,
    lambda: [SharedPositions<'a, V::S>; FAMILY_COUNT],
    /// The local mode's snapshots (current, previous) and start energies per family.
    local: Option<[SharedPositions<'a, V>; 2]>,
    energy_start: [SharedPositions<'a, V::S>; FAMILY_COUNT],
    /// Jacobi's per-constraint scales and its corrections, one per slot ([`jacobi::Slots`]).
    jacobi_scale: [&'a [V::S]; FAMILY_COUNT],
    corr: SharedPositions<'a, V>,
    /// Each family's elements slot by slot, for the SIMD kernels.
    lanes: [&'a LaneData; FAMILY_COUNT],
    /// Each family's particle-index bound ([`FamilyState::bound`]).
    bound: [usize; FAMILY_COUNT],
}

/// What one thread of the team is.
struct Member<'a> {
    t: usize,
    threads: usize,
    barrier: &'a SpinBarrier,
    plan: &'a Plan,
    /// This thread's waits for the others' steps that ended in sleep.
    slept: Cell<usize>,
    /// This thread's time spent waiting for the others, at the barrier and before steps.
    waited: Cell<Duration>,
    /// The part of `waited` spent at the barrier.
    at_barrier: Cell<Duration>,
}

impl<V: Vector> CpuSolver<V> {
    /// `true` when the frame runs on the team: Gauss-Seidel or Jacobi (either form, with or
    /// without constraint damping, in every energy-aware mode) on a pool of more than one thread,
    /// with color groups large enough to split.
    pub(super) fn team_applies(&self) -> bool {
        rayon::current_thread_index().is_some() && rayon::current_num_threads() > 1 && self.splittable
    }

    /// The frame's substeps on every thread of the current pool (see the module documentation);
    /// returns `true` when the threads slept at many waits (the cores may be busy).
    pub(super) fn team_substeps(&mut self, s: &Settings, k: &StepConstants<V::S>) -> bool {
        let threads = rayon::current_num_threads();
        if self.plan.as_ref().is_none_or(|p| p.threads != threads) {
            let disjoint = self.fam.each_ref().map(|st| st.disjoint);
            self.plan = Some(Plan::new(&self.scene, &disjoint, threads));
        }
        let Some(plan) = self.plan.as_mut() else { return false };
        plan.progress.reset();
        let plan = &*plan;
        let barrier = SpinBarrier::new(threads);
        let n = self.particles.len();
        let scene = &self.scene;
        let jacobi = s.method == Method::Jacobi;
        if jacobi && self.jacobi_slots.is_none() {
            let slots = jacobi::Slots::new(&self.scene);
            let corr = vec![V::ZERO; slots.total];
            self.jacobi_slots = Some((slots, corr));
        }
        let (slots, corr) = match self.jacobi_slots.as_mut().filter(|_| jacobi) {
            Some((slots, corr)) => (Some(&*slots), SharedPositions::new(&mut corr[..])),
            None => (None, SharedPositions::new(&mut [][..])),
        };
        let local = s.energy_aware == EnergyAware::Local;
        if local {
            crate::for_each_family!(scene, |i, f| self.fam[i].energy_start.resize(f.len(), V::S::zero()));
        }
        // The contact and finish passes' work per block of particles, one row per substep: thread
        // 0 adds the rows in the one-thread order once no thread writes them any more.
        let blocks = n.div_ceil(WORK_BLOCK);
        self.team_work.clear();
        self.team_work.resize(blocks * s.substeps as usize, 0.0);
        let p = &mut self.particles;
        let w = &p.w[..];
        let bound = self.fam.each_ref().map(|st| st.bound);
        let fam = self.fam.each_mut().map(|st| {
            let (lambda, start) = (&mut st.lambda[..], &mut st.energy_start[..]);
            (SharedPositions::new(lambda), SharedPositions::new(start), &st.jacobi_scale[..], &st.lanes)
        });
        let views = Views {
            x: SharedPositions::new(&mut p.x),
            x_prev: SharedPositions::new(&mut p.x_prev),
            v: SharedPositions::new(&mut p.v),
            work: SharedPositions::new(&mut self.team_work),
            lambda: fam.map(|f| f.0),
            local: self
                .local
                .as_mut()
                .filter(|_| local)
                .map(|l| [SharedPositions::new(&mut l.current), SharedPositions::new(&mut l.previous)]),
            energy_start: fam.map(|f| f.1),
            jacobi_scale: fam.map(|f| f.2),
            corr,
            lanes: fam.map(|f| f.3),
            bound,
        };
        let (g, damping) = (V::from_vec3(scene.gravity), <V::S as From<f32>>::from(s.damping));
        // Thread 0's ledger; with the global balance it also computes the energies, alone.
        let ledger = self.ledger;
        let global = s.energy_aware == EnergyAware::Global;
        let rest_com = self.rest_com;
        // The lean kernels where the CPU's serial sweep takes them (compliant, undamped).
        let plain = k.plain();
        // The next substep's prediction in each finish pass (every mode but the global balance).
        let fuse = fuses_predict(s);
        // Substeps chained by the step counters alone: the finish pass is a step like the color
        // groups, so a thread that is ahead goes on into the next substep ([`Plan::finish`]).
        // The local mode's snapshots and Jacobi's corrections read every thread's particles.
        let chained = fuse && !local && !jacobi;
        let inv_h = (V::S::one() / k.h).to_f64();
        // The blocks of substep `substep`'s row of work that hold the particles `r` (whole blocks).
        let work_blocks = |substep: usize, r: Range<usize>| {
            let row = substep * blocks;
            row + r.start / WORK_BLOCK..row + r.end.div_ceil(WORK_BLOCK)
        };
        let totals = rayon::broadcast(|ctx| {
            let start = Instant::now();
            let me = Member {
                t: ctx.index(),
                threads,
                barrier: &barrier,
                plan,
                slept: Cell::new(0),
                waited: Cell::default(),
                at_barrier: Cell::default(),
            };
            let mut v = views;
            let mine = particle_share(n, me.t, threads).0;
            let mut ledger = ledger;
            let mut step = 0;
            for substep in 0..s.substeps as usize {
                // The balance's starting energy: carried from the last substep, else measured.
                let mut h0 = ledger.carried;
                if global && substep == 0 && h0.is_none() {
                    if me.t == 0 {
                        h0 = Some(total_energy(scene, rest_com, v.x.read_all(), v.v.read_all(), w));
                    }
                    me.meet();
                }
                if !fuse || substep == 0 {
                    let (x, x_prev) = (v.x.range_mut(mine.clone()), v.x_prev.range_mut(mine.clone()));
                    particles::predict(x, x_prev, v.v.range_mut(mine.clone()), &w[mine.clone()], g, k.h);
                }
                for (lambda, family) in v.lambda.iter_mut().zip(&plan.families) {
                    me.zero_own(lambda, family);
                }
                if !chained || substep == 0 {
                    me.meet();
                }
                if let Some([current, previous]) = &mut v.local {
                    // The local mode's snapshots and start energies, each thread its share.
                    previous.range_mut(mine.clone()).copy_from_slice(&v.x_prev.read_all()[mine.clone()]);
                    current.range_mut(mine.clone()).copy_from_slice(&v.x.read_all()[mine.clone()]);
                    crate::for_each_family!(scene, |i, f| {
                        let r = share(0..f.len(), me.t, threads, 1);
                        let out = v.energy_start[i].range_mut(r.clone());
                        start_energies(f, v.x_prev.read_all(), (k.form, k.energy_compliance), r, out)
                    });
                    me.meet();
                }
                for iteration in 0..s.iterations {
                    if let Some([current, previous]) = &mut v.local
                        && iteration > 0
                    {
                        me.meet();
                        std::mem::swap(current, previous);
                        current.range_mut(mine.clone()).copy_from_slice(&v.x.read_all()[mine.clone()]);
                        me.meet();
                    }
                    let ctx = |i: usize| {
                        v.local.as_ref().map(|[current, previous]| LocalCtx {
                            current: current.read_all(),
                            previous: previous.read_all(),
                            energy_start: v.energy_start[i].read_all(),
                        })
                    };
                    if let Some(slots) = slots {
                        // Jacobi: each thread its share of every family's corrections, then of the
                        // particles' sums, in the one-thread order ([`jacobi::Slots`]).
                        let at = JacobiAt { x: v.x.read_all(), x_prev: v.x_prev.read_all(), w, k };
                        crate::for_each_family!(scene, |i, f| {
                            let r = share(0..f.len(), me.t, threads, 1);
                            let (lambda, scale) = (v.lambda[i].range_mut(r.clone()), v.jacobi_scale[i]);
                            let corr = (&mut v.corr, slots.base[i]);
                            jacobi_share(f, r, lambda, scale, at, ctx(i).as_ref(), corr)
                        });
                        me.meet();
                        let corr = v.corr.read_all();
                        for (x, p) in v.x.range_mut(mine.clone()).iter_mut().zip(mine.clone()) {
                            let mut d = V::ZERO;
                            for &slot in slots.of(p) {
                                d += corr[slot as usize];
                            }
                            *x += d;
                        }
                        if s.contacts_in_loop(iteration) {
                            let x_prev = &v.x_prev.read_all()[mine.clone()];
                            let work = v.work.range_mut(work_blocks(substep, mine.clone()));
                            let vel = &*v.v.range_mut(mine.clone());
                            project_range(
                                scene,
                                v.x.range_mut(mine.clone()),
                                x_prev,
                                vel,
                                &w[mine.clone()],
                                inv_h,
                                work,
                            );
                            me.meet();
                        }
                        continue;
                    }
                    crate::for_each_family!(scene, |i, f| {
                        let x_prev = v.x_prev.read_all();
                        let family = &plan.families[i];
                        let how = Sweep { plain, bound: v.bound[i], local: ctx(i) };
                        let w = (w, v.lanes[i]);
                        team_sweep(f, v.lambda[i], &mut v.x, x_prev, w, k, &me, family, &mut step, how)
                    });
                    if let Some(parts) = plan.contacts.as_ref().filter(|_| s.contacts_in_loop(iteration)) {
                        let x_prev = v.x_prev.read_all();
                        me.step(&parts[me.t], &mut step, |r| {
                            let work = v.work.range_mut(work_blocks(substep, r.clone()));
                            let (x, vel) = (v.x.range_mut(r.clone()), &*v.v.range_mut(r.clone()));
                            project_range(scene, x, &x_prev[r.clone()], vel, &w[r], inv_h, work)
                        });
                    }
                }
                let last = substep + 1 == s.substeps as usize;
                let next = (fuse && !last).then_some(g);
                let finishing = FinishStep { h: k.h, damping, next, in_loop_contacts: s.contacts_in_finish() };
                // The finish pass over the particles `r` (whole blocks), its work in this
                // substep's row.
                let mut finish = |r: Range<usize>| {
                    let work = v.work.range_mut(work_blocks(substep, r.clone()));
                    let (x, x_prev, vel) =
                        (v.x.range_mut(r.clone()), v.x_prev.range_mut(r.clone()), v.v.range_mut(r.clone()));
                    particles::finish(scene, x, x_prev, vel, &w[r], finishing, work);
                };
                if chained {
                    me.step(&plan.finish[me.t], &mut step, &mut finish);
                } else {
                    me.meet();
                    finish(mine.clone());
                }
                if fuse && !last {
                    // This thread predicted its particles for the next substep in the same pass.
                    continue;
                }
                me.meet();
                // Thread 0 adds the work rows in the one-thread order, once no thread writes
                // them: with the global balance this substep's, which the balance needs before
                // it scales the velocities while the others wait; otherwise the frame's, at its end.
                if me.t == 0 && global {
                    let work = row(v.work.read_all(), blocks, substep);
                    ledger.dissipated += work;
                    if let Some(h0) = h0 {
                        let (x, vel) = (v.x.read_all(), v.v.range_mut(0..n));
                        let (sigma, carried) = balance(scene, rest_com, x, vel, w, h0, work);
                        (ledger.carried, ledger.last_scale) = (Some(carried), sigma);
                    }
                } else if me.t == 0 {
                    for substep in 0..s.substeps as usize {
                        ledger.dissipated += row(v.work.read_all(), blocks, substep);
                    }
                }
                if global {
                    me.meet();
                }
            }
            let waited = me.waited.get();
            (ledger, me.slept.get(), start.elapsed().saturating_sub(waited), waited, me.at_barrier.get())
        });
        self.ledger = totals[0].0;
        self.team_time.add(totals.iter().map(|t| (t.2, t.3, t.4)));
        let whole = plan.families.iter().filter(|f| **f == FamilyPlan::Whole).count();
        let per_iteration = if jacobi { 2 } else { plan.steps + 2 * whole };
        // The last iteration's contact pass runs in the finish pass, without a wait of its own.
        let in_finish = if jacobi { 1 } else { plan.contacts.is_some() as usize } * s.contacts_in_finish() as usize;
        let iterations = s.iterations as usize * per_iteration - in_finish;
        let waits = threads
            * match chained {
                // The finish step each substep, and two barriers a frame.
                true => s.substeps as usize * (iterations + 1) + 2,
                false => {
                    let per_substep =
                        if fuse { 2 } else { 3 + global as usize } + 2 * local as usize * s.iterations as usize;
                    s.substeps as usize * (per_substep + iterations) + fuse as usize
                }
            };
        let slept = barrier.slept() + totals.iter().map(|t| t.1).sum::<usize>();
        slept * BUSY_FRACTION > waits
    }
}

/// Row `substep` of the finish pass's work per block (`blocks` a row), summed in block order (J).
fn row(work: &[f64], blocks: usize, substep: usize) -> f64 {
    work[substep * blocks..(substep + 1) * blocks].iter().sum()
}

impl Member<'_> {
    /// Zeroes the multipliers of this thread's parts of `family` (all of a family run whole, on
    /// thread 0): in Gauss-Seidel no other thread reads or writes them, so no barrier needs to
    /// follow; Jacobi, whose threads take the multipliers by even shares of the array, meets at one
    /// before its sweep.
    fn zero_own<S: Real>(&self, lambda: &mut SharedPositions<'_, S>, family: &FamilyPlan) {
        match family {
            FamilyPlan::Absent => {}
            FamilyPlan::Whole if self.t == 0 => lambda.range_mut(0..lambda.len()).fill(S::zero()),
            FamilyPlan::Whole => {}
            FamilyPlan::Split(parts) => {
                for part in parts.iter().skip(self.t).step_by(self.threads) {
                    lambda.range_mut(part.share.clone()).fill(S::zero());
                }
            }
        }
    }

    /// Waits at the team's barrier for the other threads.
    #[inline]
    fn meet(&self) {
        let waited = self.barrier.wait();
        self.at_barrier.set(self.at_barrier.get() + waited.time);
        self.count(waited);
    }

    /// Adds a wait's time to this thread's.
    #[inline]
    fn count(&self, waited: Waited) {
        self.waited.set(self.waited.get() + waited.time);
    }

    /// This thread's part of step `*step` (`run` over each of its ranges): the boundary part once
    /// the other threads have finished theirs of the steps before, then the rest.
    #[inline]
    fn step(&self, part: &Part, step: &mut usize, mut run: impl FnMut(Range<usize>)) {
        let progress = &self.plan.progress;
        if !part.boundary.is_empty() {
            let waited = progress.wait(self.t, *step);
            self.count(waited);
            self.slept.set(self.slept.get() + usize::from(waited.slept));
            run(part.boundary.clone());
        }
        progress.publish(self.t, *step + 1);
        for r in part.interior() {
            if !r.is_empty() {
                run(r);
            }
        }
        *step += 1;
    }
}

/// Jacobi's update of the elements `range` of `f`: their multipliers `lambda` (indexed from the
/// range's start), and their corrections into the slots of `corr = (slots, family's first slot)`,
/// `N` per element (zero where an element is skipped, which adds nothing: a sum that starts at `+0`
/// never holds `−0`).
fn jacobi_share<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    range: Range<usize>,
    lambda: &mut [V::S],
    scale: &[V::S],
    at: JacobiAt<'_, V>,
    local: Option<&LocalCtx<'_, V>>,
    (slots, base): (&mut SharedPositions<'_, V>, usize),
) {
    let corr = slots.range_mut(base + N * range.start..base + N * range.end);
    for ((j, l), c) in range.zip(lambda).zip(corr.chunks_exact_mut(N)) {
        let out = jacobi_element(&f.elements[j], &f.params, j, l, scale[j], at, local).unwrap_or([V::ZERO; N]);
        c.copy_from_slice(&out);
    }
}

/// Which update a team sweep takes: the local mode's (with its context), else the lean kernels
/// where `plain` ([`plain_chunk`]), else the general update of every element.
struct Sweep<'a, V: Vector> {
    plain: bool,
    /// The family's particle-index bound ([`FamilyState::bound`]).
    bound: usize,
    local: Option<LocalCtx<'a, V>>,
}

/// One Gauss-Seidel sweep of family `f` by the team, one step per color group ([`Plan`]). A
/// family whose groups were not checked disjoint runs whole on thread 0 between two barriers.
#[allow(unsafe_code)]
fn team_sweep<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    mut lambda: SharedPositions<'_, V::S>,
    x: &mut SharedPositions<'_, V>,
    x_prev: &[V],
    (w, lanes): (&[V::S], &LaneData),
    k: &StepConstants<V::S>,
    me: &Member<'_>,
    family: &FamilyPlan,
    step: &mut usize,
    how: Sweep<'_, V>,
) {
    if how.plain && how.local.is_none() {
        checked_bound(how.bound, x.len());
    }
    let mut chunk = |r: Range<usize>, x: &mut SharedPositions<'_, V>| {
        let (start, es, ls) = (r.start, &f.elements[r.clone()], lambda.range_mut(r));
        match &how {
            Sweep { local: Some(ctx), .. } => {
                for (j, (e, l)) in es.iter().zip(ls).enumerate() {
                    let adjust = |xs: &[V; N], ws: &[V::S; N], c_val, alpha| {
                        local_adjusted(ctx, start + j, e.particles(), xs, ws, k, c_val, alpha)
                    };
                    update(e, &f.params, l, x, x_prev, w, k, adjust);
                }
            }
            Sweep { plain: true, .. } => {
                let lanes = lanes.view(start..start + es.len());
                // SAFETY: every particle index of the family's elements is below `bound` ≤
                // `x.len()` (checked once at the top of the sweep), the lanes' offsets are those
                // indices times the size of `V`, `plain_chunk` touches only the particles of the
                // elements it is given, and those are this worker's in the current group.
                let x = &mut unsafe { Prechecked::shared(x) };
                plain_chunk(es, ls, &f.params, x, x_prev, (w, lanes), k)
            }
            Sweep { plain: false, .. } => {
                for (e, l) in es.iter().zip(ls) {
                    update(e, &f.params, l, x, x_prev, w, k, |_, _, c_val, _| c_val);
                }
            }
        }
    };
    match family {
        FamilyPlan::Absent => {}
        FamilyPlan::Whole => {
            me.meet();
            if me.t == 0 {
                for range in &f.colors {
                    chunk(range.start as usize..range.end as usize, x);
                }
            }
            me.meet();
        }
        FamilyPlan::Split(parts) => {
            for g in 0..f.colors.len() {
                me.step(&parts[g * me.threads + me.t], step, |r| chunk(r, x));
            }
        }
    }
}

/// A team frame in which more than one wait in this many ended in sleep is suspect: its
/// threads may have waited for one another because the cores run other work too (another
/// process, another solver), or only because its groups are long (a wait past the spin sleeps).
const BUSY_FRACTION: usize = 8;
