//! The team's plan for one thread count: every thread's share of every step of a substep (a
//! color group, the contact pass over the particles, or the finish pass), and the part of each
//! share that may touch a particle another thread touches in some step (its *boundary*).
//!
//! Only boundary parts order the threads ([`Progress`]): a thread starts the boundary part
//! of step `s` once every other thread has finished the boundary parts of the steps before `s`,
//! and runs the rest of its share (which touches only particles no other thread touches) without
//! waiting. Two items that share a particle are then visited in the order of their steps, as on
//! one thread, whether they belong to one thread (which runs its steps in order) or to two (then
//! the particle is touched by both, so both items lie in boundary parts and the later one waits
//! for the earlier): the positions are the same, bit for bit, as with a barrier after each group.

use std::ops::Range;

use crate::constraints::{Element, SIMD_WIDTH};
use crate::scene::{FAMILY_COUNT, Family, Scene};

use super::super::PARALLEL_MIN_GROUP;
use super::super::barrier::{Progress, share};
use super::super::particles::WORK_BLOCK;

/// One thread's part of one step: its `share` of the step's items (element indices in the
/// family's color order, or particle indices) and the `boundary` sub-range that may touch a
/// particle some other thread touches.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Part {
    pub share: Range<usize>,
    pub boundary: Range<usize>,
}

impl Part {
    /// The share without its boundary part: before it, then after it.
    pub fn interior(&self) -> [Range<usize>; 2] {
        [self.share.start..self.boundary.start, self.boundary.end..self.share.end]
    }
}

/// How the team runs one family.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum FamilyPlan {
    /// Not in the scene.
    Absent,
    /// Groups not checked disjoint: thread 0 runs the family alone between two barriers.
    Whole,
    /// One step per color group; `parts[group * threads + t]`.
    Split(Vec<Part>),
}

/// The team's plan for `threads` threads (see the module documentation).
#[derive(Clone, Debug)]
pub(super) struct Plan {
    pub threads: usize,
    pub families: [FamilyPlan; FAMILY_COUNT],
    /// The contact pass's parts (`[t]`: thread `t`'s block of particles, its boundary aligned to
    /// whole [`WORK_BLOCK`]s, so that each block's sum of work is made in one visit), when the
    /// scene has colliders.
    pub contacts: Option<Vec<Part>>,
    /// The finish pass's parts (`[t]`: thread `t`'s block of particles, its boundary aligned to
    /// whole [`WORK_BLOCK`]s), for substeps chained without a barrier (`cpu/team.rs`).
    pub finish: Vec<Part>,
    /// The threads' finished steps during a frame.
    pub progress: Progress,
}

/// Thread `t`'s particles in the per-particle passes: whole blocks of [`WORK_BLOCK`] particles
/// (so the finish pass's sum of work per block does not depend on the split).
pub(super) fn particle_share(n: usize, t: usize, threads: usize) -> (Range<usize>, Range<usize>) {
    let blocks = share(0..n.div_ceil(WORK_BLOCK), t, threads, 1);
    ((blocks.start * WORK_BLOCK).min(n)..(blocks.end * WORK_BLOCK).min(n), blocks)
}

/// Thread `t`'s share of a color group: consecutive whole SIMD batches of a group of at least
/// [`PARALLEL_MIN_GROUP`] elements, else the whole group for thread 0.
pub(super) fn group_share(group: Range<usize>, t: usize, threads: usize) -> Range<usize> {
    match group.len() >= PARALLEL_MIN_GROUP {
        true => share(group, t, threads, SIMD_WIDTH),
        false if t == 0 => group,
        false => group.start..group.start,
    }
}

impl Plan {
    /// The plan for `threads` threads; `disjoint[i]`: family `i`'s groups share no particle.
    pub fn new(scene: &Scene, disjoint: &[bool; FAMILY_COUNT], threads: usize) -> Plan {
        let n = scene.num_particles();
        let contacts = scene.ground.is_some() || !scene.spheres.is_empty();
        // Which threads touch each particle (bit t); a count past 64 marks every particle shared.
        let mut touched = vec![0u64; n];
        let bit = |t: usize| if threads <= 64 { 1u64 << t } else { u64::MAX };
        let mut families: [FamilyPlan; FAMILY_COUNT] = std::array::from_fn(|_| FamilyPlan::Absent);
        crate::for_each_family!(scene, |i, f| {
            families[i] = match disjoint[i] {
                true => {
                    mark(f, threads, &mut touched, bit);
                    FamilyPlan::Split(Vec::new())
                }
                false => FamilyPlan::Whole,
            }
        });
        // The per-particle passes (the finish pass, and the contact pass when there are
        // colliders) are steps too.
        for t in 0..threads {
            for p in particle_share(n, t, threads).0 {
                touched[p] |= bit(t);
            }
        }
        let shared = |p: usize| touched[p].count_ones() > 1;
        crate::for_each_family!(scene, |i, f| {
            if let FamilyPlan::Split(parts) = &mut families[i] {
                *parts = split_parts(f, threads, shared);
            }
        });
        // Thread `t`'s block of particles, its boundary aligned to `align` particles.
        let particle_parts = |align: usize| -> Vec<Part> {
            (0..threads)
                .map(|t| {
                    let share = particle_share(n, t, threads).0;
                    let boundary = boundary(share.clone(), align, shared);
                    Part { share, boundary }
                })
                .collect()
        };
        // The contact pass's parts in whole blocks too: each block's sum of work in one visit.
        let contacts = contacts.then(|| particle_parts(WORK_BLOCK));
        let finish = particle_parts(WORK_BLOCK);
        Plan { threads, families, contacts, finish, progress: Progress::new(threads) }
    }
}

/// Marks the particles of every thread's share of every group of `f`.
fn mark<E: Element<N>, const N: usize>(
    f: &Family<E, N>,
    threads: usize,
    touched: &mut [u64],
    bit: impl Fn(usize) -> u64,
) {
    for range in &f.colors {
        for t in 0..threads {
            for e in &f.elements[group_share(range.start as usize..range.end as usize, t, threads)] {
                for p in e.particles() {
                    touched[p as usize] |= bit(t);
                }
            }
        }
    }
}

/// Every thread's part of every group of `f`, `[group * threads + t]`.
fn split_parts<E: Element<N>, const N: usize>(
    f: &Family<E, N>,
    threads: usize,
    shared: impl Fn(usize) -> bool,
) -> Vec<Part> {
    let mut parts = Vec::with_capacity(f.colors.len() * threads);
    for range in &f.colors {
        for t in 0..threads {
            let share = group_share(range.start as usize..range.end as usize, t, threads);
            let boundary =
                boundary(share.clone(), SIMD_WIDTH, |j| f.elements[j].particles().iter().any(|&p| shared(p as usize)));
            parts.push(Part { share, boundary });
        }
    }
    parts
}

/// The smallest sub-range of `share` holding every item for which `touches_shared` holds, its ends
/// moved out to whole batches of `align` items from the share's start (so the SIMD kernels' batches
/// stay whole); empty, at the share's start, when there is none.
fn boundary(share: Range<usize>, align: usize, touches_shared: impl Fn(usize) -> bool) -> Range<usize> {
    let first = share.clone().find(|&j| touches_shared(j));
    let Some(first) = first else { return share.start..share.start };
    let last = share.clone().rev().find(|&j| touches_shared(j)).unwrap_or(first);
    let lo = share.start + (first - share.start) / align * align;
    let hi = (share.start + (last + 1 - share.start).next_multiple_of(align)).min(share.end);
    lo..hi
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneOptions, build};

    #[test]
    fn boundary_parts_hold_every_item_another_thread_may_touch() {
        let scene = build("cloth", &SceneOptions { resolution: Some(32), ..SceneOptions::default() }).expect("cloth");
        for threads in [2, 3] {
            let plan = Plan::new(&scene, &[true; FAMILY_COUNT], threads);
            let mut owners = vec![0u64; scene.num_particles()];
            let bends = scene.bends.as_ref().expect("bending");
            let FamilyPlan::Split(parts) = &plan.families[1] else { panic!("bending is split") };
            for (g, range) in bends.colors.iter().enumerate() {
                let covered: usize = (0..threads).map(|t| parts[g * threads + t].share.len()).sum();
                assert_eq!(covered, range.len());
                for t in 0..threads {
                    let part = &parts[g * threads + t];
                    assert!(part.share.start <= part.boundary.start && part.boundary.end <= part.share.end);
                    for j in part.share.clone() {
                        for p in bends.elements[j].particles() {
                            owners[p as usize] |= 1 << t;
                        }
                    }
                }
            }
            // An interior element of a thread touches no particle another thread's bending touches.
            for (g, _) in bends.colors.iter().enumerate() {
                for t in 0..threads {
                    for r in parts[g * threads + t].interior() {
                        for j in r {
                            for p in bends.elements[j].particles() {
                                assert_eq!(owners[p as usize], 1 << t, "group {g}, thread {t}, element {j}");
                            }
                        }
                    }
                }
            }
            assert_eq!(parts.len(), bends.colors.len() * threads, "a part per group and thread");
            // The finish pass's parts: every thread's block of particles, the boundary in whole
            // work blocks and holding every particle another thread touches in a sweep.
            for (t, part) in plan.finish.iter().enumerate() {
                assert_eq!(part.share, particle_share(scene.num_particles(), t, threads).0);
                assert_eq!((part.boundary.start - part.share.start) % WORK_BLOCK, 0);
                assert!(part.boundary.end == part.share.end || part.boundary.end % WORK_BLOCK == 0);
                for r in part.interior() {
                    for p in r {
                        assert!(owners[p] & !(1 << t) == 0, "particle {p} of thread {t}'s finish interior");
                    }
                }
            }
        }
    }
}
