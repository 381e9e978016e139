//! The frame on several threads: every thread of the solver's pool runs the frame's substeps, the
//! stage list of [`crate::solver::stages`], as one team. Each takes its share of the particles in
//! the per-particle passes and of each large color group in the sweeps, so one frame costs one
//! wake-up of the pool instead of a fork and join per group. A thread waits for the others only
//! before the part of its share that touches particles another thread touches too ([`Plan`]), so a
//! thread that is ahead goes on with the rest of its share instead of waiting at every group. In
//! Gauss-Seidel without the global balance or the local mode, the finish pass (which makes the next
//! substep's prediction too) is such a step as well, each thread zeroes the multipliers of its own
//! parts, and the substeps follow one another without a barrier: the team meets only after the
//! frame's first prediction and at its end. The global balance (which scales every velocity between
//! the finish pass and the next prediction), the local mode (whose snapshots and start energies
//! read every particle) and Jacobi (whose sums read every element's corrections) meet at spin
//! barriers around those passes, as does the self-collision: thread 0 checks and finds the
//! candidates while the others wait, and before each pass readies it (the near pairs,
//! [`crate::solver::self_collision::SelfPairs::prepare`]); then each thread gathers its particles'
//! moves against the same iterate ([`crate::solver::self_collision::SelfPairs::moves`]) and adds
//! them. The elements of a group share no particle, the passes touch each particle alone, and two
//! elements that share a particle are visited in the order of their groups, so the positions come
//! out the same, bit for bit, for any thread count. Each thread times its waits, and the solver sums each thread's time
//! working and waiting over the team's frames ([`super::TeamTime`]).

use std::cell::Cell;
use std::ops::Range;
use std::sync::{PoisonError, RwLock};
use std::time::{Duration, Instant};

use crate::math::prelude::*;
use crate::scene::{FAMILY_COUNT, Family, Scene};

use super::super::Pull;
use super::super::barrier::{SpinBarrier, Waited, share};
use super::super::contacts::project_range;
use super::super::energy::EnergyAware;
use super::super::jacobi;
use super::super::particles::{self, FinishStep, WORK_BLOCK};
use super::super::shared::{Prechecked, SharedPositions};
use super::super::stages::{self, Stage};
use super::super::xpbd::StepConstants;
use super::super::{Method, PARALLEL_MIN_GROUP, Settings};
use super::plan::{FamilyPlan, Part, Plan, particle_share};
use super::{
    CpuSolver, FamilyState, JacobiAt, LocalCtx, balance, checked_bound, fuses_predict, jacobi_element, local_adjusted,
    plain_chunk, start_energies, update,
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
    /// The self-collision pass's moves, one per particle.
    dx: SharedPositions<'a, V>,
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
    /// This thread's waits (barriers and steps) in the frame.
    waits: Cell<usize>,
}

impl<V: Vector> CpuSolver<V> {
    /// `true` when the frame runs on the team: Gauss-Seidel or Jacobi (either form, with or
    /// without constraint damping, in every energy-aware mode) on a pool of more than one thread,
    /// with color groups large enough to split.
    pub(super) fn team_applies(&self) -> bool {
        rayon::current_thread_index().is_some() && rayon::current_num_threads() > 1 && self.splittable
    }

    /// The frame's substeps (`frame`: their stages, [`stages`]) on every thread of the current
    /// pool (see the module documentation); returns `true` when the threads slept at many waits
    /// (the cores may be busy) or waited longer than they worked. Threads that wait longer than
    /// they work take more than twice each one's share of the work a frame, about what one thread
    /// takes for all of it: such a frame is checked against one thread ([`super::choice`]).
    #[allow(unsafe_code)]
    pub(super) fn team_substeps(&mut self, frame: &[Stage], s: &Settings, k: &StepConstants<V::S>) -> bool {
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
            Some((slots, corr)) => (Some(&*slots), &mut corr[..]),
            None => (None, &mut [][..]),
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
        let snapshots = self.local.as_mut().filter(|_| local).map(|l| [&mut l.current, &mut l.previous]);
        // The self-collision's candidates: thread 0 writes them between barriers, every thread
        // reads them in the pass.
        let self_pairs = RwLock::new(&mut self.self_pairs);
        self.dx.resize(n, V::ZERO);
        // SAFETY: the views are used only by the threads of the broadcast below, as the module
        // documentation of `shared` requires: each thread writes the particles of its share of a
        // per-particle pass (`particle_share`, `Plan::finish`, `Plan::contacts`: disjoint ranges)
        // and of its parts of a color group (disjoint elements and, the groups checked disjoint,
        // disjoint particles; families not checked run on thread 0 between barriers), and the
        // multipliers of those elements; a step that touches what another thread's earlier step
        // touched waits for it (`Member::step`, the plan's boundary parts) or for a barrier
        // (`Member::meet`); slices cover only a thread's own range (`read_range`) or an array no
        // thread writes until the next barrier (`read_all`: snapshots, start energies, Jacobi's
        // and the self-collision's positions, Jacobi's corrections, the work rows once every
        // thread has finished its passes); the self-collision's moves are each thread's own range.
        let views = unsafe {
            let fam = self.fam.each_mut().map(|st| {
                let (lambda, start) = (&mut st.lambda[..], &mut st.energy_start[..]);
                (SharedPositions::new(lambda), SharedPositions::new(start), &st.jacobi_scale[..], &st.lanes)
            });
            Views {
                x: SharedPositions::new(&mut p.x),
                x_prev: SharedPositions::new(&mut p.x_prev),
                v: SharedPositions::new(&mut p.v),
                work: SharedPositions::new(&mut self.team_work),
                lambda: fam.map(|f| f.0),
                local: snapshots.map(|[c, p]| [SharedPositions::new(c), SharedPositions::new(p)]),
                energy_start: fam.map(|f| f.1),
                jacobi_scale: fam.map(|f| f.2),
                corr: SharedPositions::new(corr),
                dx: SharedPositions::new(&mut self.dx),
                lanes: fam.map(|f| f.3),
                bound,
            }
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
                waits: Cell::new(0),
            };
            let mut v = views;
            let mine = particle_share(n, me.t, threads).0;
            let mut ledger = ledger;
            let mut step = 0;
            // The substep the stages belong to, and whether the last finish pass made the
            // prediction that follows it.
            let (mut substep, mut predicted) = (0usize, false);
            for (i, &stage) in frame.iter().enumerate() {
                // The local mode's context for family `f`: snapshots and start energies, which no
                // thread writes while the sweeps run.
                let ctx = |f: usize| {
                    v.local.as_ref().map(|[current, previous]| LocalCtx {
                        current: current.read_all(),
                        previous: previous.read_all(),
                        energy_start: v.energy_start[f].read_all(),
                    })
                };
                match stage {
                    Stage::Predict => {
                        if i > 0 {
                            substep += 1;
                        }
                        if !std::mem::take(&mut predicted) {
                            let (x, x_prev) = (v.x.range_mut(mine.clone()), v.x_prev.range_mut(mine.clone()));
                            let pull = Pull::within(s.pull, mine.clone());
                            particles::predict(x, x_prev, v.v.range_mut(mine.clone()), &w[mine.clone()], g, k.h, pull);
                        }
                    }
                    Stage::Clear => {
                        for (lambda, family) in v.lambda.iter_mut().zip(&plan.families) {
                            me.zero_own(lambda, family);
                        }
                        if !chained || substep == 0 {
                            me.meet();
                        }
                    }
                    Stage::LocalBegin => {
                        let Some([current, previous]) = &mut v.local else { continue };
                        // The local mode's snapshots and start energies, each thread its share.
                        previous.range_mut(mine.clone()).copy_from_slice(v.x_prev.read_range(mine.clone()));
                        current.range_mut(mine.clone()).copy_from_slice(v.x.read_range(mine.clone()));
                        crate::for_each_family!(scene, |f_i, f| {
                            let r = share(0..f.len(), me.t, threads, 1);
                            let out = v.energy_start[f_i].range_mut(r.clone());
                            start_energies(f, v.x_prev.read_all(), (k.form, k.energy_compliance), r, out)
                        });
                        me.meet();
                    }
                    Stage::LocalSnapshot => {
                        let Some([current, previous]) = &mut v.local else { continue };
                        me.meet();
                        std::mem::swap(current, previous);
                        current.range_mut(mine.clone()).copy_from_slice(v.x.read_range(mine.clone()));
                        me.meet();
                    }
                    Stage::Sweep { family: f_i, color } => crate::with_family!(scene, f_i, |f| {
                        // Read particle by particle: the other threads' finish passes of the
                        // previous substep may still write theirs (chained substeps).
                        let x_prev = &v.x_prev;
                        let family = &plan.families[f_i];
                        let how = Sweep { plain, bound: v.bound[f_i], local: ctx(f_i) };
                        let w = (w, v.lanes[f_i]);
                        team_group(f, color, v.lambda[f_i], &mut v.x, x_prev, w, k, &me, family, &mut step, how)
                    }),
                    Stage::Jacobi => {
                        let Some(slots) = slots else { continue };
                        // Each thread its share of every family's corrections, then of the
                        // particles' sums, in the one-thread order ([`jacobi::Slots`]).
                        let at = JacobiAt { x: v.x.read_all(), x_prev: v.x_prev.read_all(), w, k };
                        crate::for_each_family!(scene, |f_i, f| {
                            let r = share(0..f.len(), me.t, threads, 1);
                            let (lambda, scale) = (v.lambda[f_i].range_mut(r.clone()), v.jacobi_scale[f_i]);
                            let corr = (&mut v.corr, slots.base[f_i]);
                            jacobi_share(f, r, lambda, scale, at, ctx(f_i).as_ref(), corr)
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
                    }
                    Stage::SelfPairs => {
                        let Some(sc) = &scene.self_collision else { continue };
                        // Every thread's prediction is in before thread 0 reads every position.
                        me.meet();
                        if me.t == 0 {
                            self_pairs.write().unwrap_or_else(PoisonError::into_inner).update(v.x.read_all(), w, sc);
                        }
                        me.meet();
                    }
                    Stage::SelfCollision => {
                        let Some(sc) = &scene.self_collision else { continue };
                        me.meet();
                        // Thread 0 readies the pass (its near partners) once every position is in.
                        if me.t == 0 {
                            let mut pairs = self_pairs.write().unwrap_or_else(PoisonError::into_inner);
                            pairs.prepare(v.x.read_all(), v.x_prev.read_all(), sc, true);
                        }
                        me.meet();
                        let at = (v.x.read_all(), v.x_prev.read_all(), w);
                        let pairs = self_pairs.read().unwrap_or_else(PoisonError::into_inner);
                        pairs.moves(mine.clone(), at, sc, v.dx.range_mut(mine.clone()));
                        drop(pairs);
                        me.meet();
                        for (x, d) in v.x.range_mut(mine.clone()).iter_mut().zip(v.dx.read_range(mine.clone())) {
                            *x += *d;
                        }
                        // The next stage's steps may read the particles of another thread's share.
                        me.meet();
                    }
                    // Jacobi's: each thread its particles, then the team meets before the next
                    // iteration reads every position.
                    Stage::Contacts if jacobi => {
                        let x_prev = v.x_prev.read_range(mine.clone());
                        let work = v.work.range_mut(work_blocks(substep, mine.clone()));
                        let vel = &*v.v.range_mut(mine.clone());
                        project_range(scene, v.x.range_mut(mine.clone()), x_prev, vel, &w[mine.clone()], inv_h, work);
                        me.meet();
                    }
                    Stage::Contacts => {
                        let Some(parts) = plan.contacts.as_ref() else { continue };
                        me.step(&parts[me.t], &mut step, |r| {
                            let work = v.work.range_mut(work_blocks(substep, r.clone()));
                            let (x, vel) = (v.x.range_mut(r.clone()), &*v.v.range_mut(r.clone()));
                            let x_prev = v.x_prev.read_range(r.clone());
                            project_range(scene, x, x_prev, vel, &w[r], inv_h, work)
                        });
                    }
                    Stage::Finish => {
                        predicted = stages::finish_predicts(frame, i);
                        let next = predicted.then_some(g);
                        let finishing =
                            FinishStep { h: k.h, damping, next, in_loop_contacts: s.contacts_in_finish(), pull: None };
                        // The finish pass over the particles `r` (whole blocks), its work in this
                        // substep's row.
                        let mut finish = |r: Range<usize>| {
                            let work = v.work.range_mut(work_blocks(substep, r.clone()));
                            let (x, x_prev, vel) =
                                (v.x.range_mut(r.clone()), v.x_prev.range_mut(r.clone()), v.v.range_mut(r.clone()));
                            let finishing = FinishStep { pull: Pull::within(s.pull, r.clone()), ..finishing };
                            particles::finish(scene, x, x_prev, vel, &w[r], finishing, work);
                        };
                        if chained {
                            me.step(&plan.finish[me.t], &mut step, &mut finish);
                        } else {
                            me.meet();
                            finish(mine.clone());
                        }
                    }
                    Stage::Balance => {
                        // Thread 0 adds this substep's work row in the one-thread order once no
                        // thread writes it, and scales the velocities while the others wait.
                        me.meet();
                        if me.t == 0 {
                            let work = row(v.work.read_all(), blocks, substep);
                            ledger.dissipated += work;
                            if let Some(h0) = ledger.carried {
                                let (x, vel) = (v.x.read_all(), v.v.range_mut(0..n));
                                let (sigma, carried) = balance(scene, rest_com, x, vel, w, h0, work);
                                (ledger.carried, ledger.last_scale) = (Some(carried), sigma);
                            }
                        }
                        me.meet();
                    }
                    // The frame's stages before and after its substeps run on the calling thread.
                    Stage::ProjectionStart | Stage::BalanceStart | Stage::Projection => {}
                }
            }
            if !global {
                // Thread 0 adds the frame's work rows in the one-thread order once no thread
                // writes them.
                me.meet();
                if me.t == 0 {
                    for substep in 0..s.substeps as usize {
                        ledger.dissipated += row(v.work.read_all(), blocks, substep);
                    }
                }
            }
            let waited = me.waited.get();
            (
                ledger,
                me.slept.get(),
                start.elapsed().saturating_sub(waited),
                waited,
                me.at_barrier.get(),
                me.waits.get(),
            )
        });
        self.ledger = totals[0].0;
        self.team_time.add(totals.iter().map(|t| (t.2, t.3, t.4)));
        let waits: usize = totals.iter().map(|t| t.5).sum();
        let slept = barrier.slept() + totals.iter().map(|t| t.1).sum::<usize>();
        let (worked, waited) = totals.iter().fold((Duration::ZERO, Duration::ZERO), |(a, b), t| (a + t.2, b + t.3));
        slept * BUSY_FRACTION > waits || waited > worked
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
        self.waits.set(self.waits.get() + 1);
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
        self.waits.set(self.waits.get() + 1);
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

/// Gauss-Seidel over color group `color` of family `f` by the team, one step per group
/// ([`Plan`]). A family whose groups were not checked disjoint runs whole on thread 0, between a
/// barrier before its first group and one after its last.
#[allow(unsafe_code)]
fn team_group<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    color: usize,
    mut lambda: SharedPositions<'_, V::S>,
    x: &mut SharedPositions<'_, V>,
    x_prev: &SharedPositions<'_, V>,
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
            if color == 0 {
                me.meet();
            }
            if me.t == 0 {
                let range = &f.colors[color];
                chunk(range.start as usize..range.end as usize, x);
            }
            if color + 1 == f.colors.len() {
                me.meet();
            }
        }
        FamilyPlan::Split(parts) => me.step(&parts[color * me.threads + me.t], step, |r| chunk(r, x)),
    }
}

/// A team frame in which more than one wait in this many ended in sleep is suspect: its
/// threads may have waited for one another because the cores run other work too (another
/// process, another solver), or only because its groups are long (a wait past the spin sleeps).
const BUSY_FRACTION: usize = 8;
