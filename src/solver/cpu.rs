//! The CPU reference solver, generic over precision (`f32` at run time, `f64` for references).

use std::ops::Range;
use std::sync::Arc;

use glam::Vec3;

use crate::constraints::simd::is_f32;
use crate::constraints::{ALL_LANES, SIMD_WIDTH};
use crate::constraints::{Element, LaneData, LaneView, Positions};
use crate::math::prelude::*;
use crate::metrics::{self, Lambdas};
use crate::scene::{FAMILY_COUNT, Family, Scene};

use super::energy::{EnergyAware, global_scale};
use super::jacobi;
use super::particles::{self, FinishStep};
use super::self_collision;
use super::shared::Prechecked;
use super::stages::{self, FrameStart, Stage};
use super::xpbd::{StepConstants, solve_element};
use super::{Method, Particles, Pull, Settings};

use jacobi_sweep::{JacobiAt, jacobi_element};
use local::{LocalCtx, LocalState, local_adjusted, local_ctx, start_energies};

mod choice;
mod jacobi_sweep;
mod local;
mod plan;
mod pool;
mod project;
mod run;
mod team;
#[cfg(test)]
mod team_tests;
mod team_time;

pub use team_time::TeamTime;

use pool::cores;

/// Per-family solver state: one multiplier per constraint, Jacobi's per-constraint scale, and
/// the local mode's energy at the start of the substep.
#[derive(Clone, Debug, Default)]
struct FamilyState<S> {
    lambda: Vec<S>,
    jacobi_scale: Vec<S>,
    energy_start: Vec<S>,
    /// The family's color groups share no particle, so threads may split them.
    disjoint: bool,
    /// The elements slot by slot for the SIMD kernels ([`LaneData`]): `f32` families that have
    /// them only, built before the first frame of plain Gauss-Seidel, else empty. Its inverse
    /// masses are kept in step with [`Particles::w`] at the start of every such frame
    /// ([`CpuSolver::refresh_lanes`]).
    lanes: LaneData,
    /// One past the largest particle index of the family's elements (0 when it has none): the
    /// lean sweeps check it against the positions' length once, then gather and scatter without
    /// bounds checks ([`Prechecked`]).
    bound: usize,
}

/// Energy bookkeeping (docs/algorithm.md §4 and §7), in `f64`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyLedger {
    /// Work of physical dissipation since the start (J, ≤ 0 for losses): velocity damping and
    /// every contact pass of every substep, in the loop and the final one
    /// (`solver::contacts::Colliders::work`).
    pub dissipated: f64,
    /// `H₀` carried to the next substep by the global balance (J).
    pub carried: Option<f64>,
    /// The last global velocity scale `σ`, or the projection's last scale `s`.
    pub last_scale: f64,
    /// The projection's energy budget `H*` after the last frame (J, heights from the rest centre
    /// of mass; [`super::projection`]); `None` while the projection is off.
    pub budget: Option<f64>,
    /// The linear (kg·m/s) and angular momentum about the origin (kg·m²/s) the projection keeps
    /// for an isolated body, taken with the budget ([`projection::conserved_momenta`]).
    pub momenta: Option<(glam::DVec3, glam::DVec3)>,
    /// The settings of the last projected frame (threads left out).
    pub projected_with: Option<Settings>,
}

/// The CPU reference solver: owns a scene and the particle state simulated from it.
#[derive(Clone, Debug)]
pub struct CpuSolver<V: Vector> {
    scene: Scene,
    /// Particle state.
    pub particles: Particles<V>,
    /// Per-family multipliers and scratch, indexed as in [`crate::for_each_family`].
    fam: [FamilyState<V::S>; FAMILY_COUNT],
    /// Jacobi's position corrections (allocated on first Jacobi step).
    dx: Vec<V>,
    jacobi_omega: Option<f32>,
    local: Option<LocalState<V>>,
    /// Energy bookkeeping.
    pub ledger: EnergyLedger,
    rest_com: Vec3,
    /// Constants of the last substep run (for residuals).
    last: Option<StepConstants<V::S>>,
    /// The finish pass's work per block of particles ([`particles::WORK_BLOCK`]).
    work_blocks: Vec<f64>,
    /// The team's work per block, one row of blocks per substep of a frame.
    team_work: Vec<f64>,
    /// The solver's pool for a thread count above one (built on first use).
    pool: Option<(u32, Arc<rayon::ThreadPool>)>,
    /// Whether the next frame runs on the team or on one thread ([`choice::Choice`]).
    choice: choice::Choice,
    /// Some family has a group the team may split ([`team::splittable`]), fixed by the scene.
    splittable: bool,
    /// The team's shares and boundary parts for the pool's thread count (built on first use).
    plan: Option<plan::Plan>,
    /// Jacobi on the team: where each element's corrections go, and the corrections (built on
    /// first use).
    jacobi_slots: Option<(jacobi::Slots, Vec<V>)>,
    /// The inverse masses the families' `lanes` were taken from.
    w_seen: Vec<V::S>,
    /// Each family's color groups ([`stages::color_counts`]).
    colors: [usize; FAMILY_COUNT],
    /// The last frame's stages (kept, so a frame allocates none).
    stages: Vec<Stage>,
    /// The self-collision's candidate pairs of the current substep.
    self_pairs: self_collision::SelfPairs,
    /// The dissipated work at the start of the frame under the projection (J), for its budget.
    dissipated_before: Option<f64>,
    /// The last finish pass's dissipated work (J), for the global balance after it.
    substep_work: f64,
    /// The team's time working and waiting ([`CpuSolver::team_time`]).
    team_time: TeamTime,
}

impl<V: Vector> CpuSolver<V> {
    /// A solver at the scene's initial state.
    pub fn new(scene: Scene) -> Self {
        let mut fam: [FamilyState<V::S>; FAMILY_COUNT] = Default::default();
        let n = scene.num_particles();
        crate::for_each_family!(scene, |i, f| {
            fam[i].lambda = vec![V::S::zero(); f.len()];
            fam[i].disjoint = f.groups_disjoint(n);
            fam[i].bound = f.elements.iter().flat_map(|e| e.particles()).max().map_or(0, |p| p as usize + 1);
        });
        let splittable = team::splittable(&scene, &fam);
        CpuSolver {
            particles: Particles::from_scene(&scene),
            fam,
            dx: Vec::new(),
            jacobi_omega: None,
            local: None,
            ledger: EnergyLedger { last_scale: 1.0, ..EnergyLedger::default() },
            rest_com: scene.rest_center_of_mass(),
            last: None,
            work_blocks: vec![0.0; n.div_ceil(particles::WORK_BLOCK)],
            team_work: Vec::new(),
            pool: None,
            choice: choice::Choice::default(),
            splittable,
            plan: None,
            jacobi_slots: None,
            w_seen: Vec::new(),
            colors: stages::color_counts(&scene),
            stages: Vec::new(),
            self_pairs: Default::default(),
            dissipated_before: None,
            substep_work: 0.0,
            team_time: TeamTime::default(),
            scene,
        }
    }

    /// The scene being simulated.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Back to the scene's initial state.
    pub fn reset(&mut self) {
        *self = CpuSolver::new(self.scene.clone());
    }

    /// Advances one frame of `settings.dt` (call [`Settings::validate`] first).
    pub fn step_frame(&mut self, s: &Settings) {
        // The pulled particle answers the substeps' constraints with its effective inverse mass
        // ([`Pull`]); its own is back for the stages after them.
        let pulled = s.pull.filter(|p| (p.particle as usize) < self.particles.len()).map(|p| {
            let i = p.particle as usize;
            let w = self.particles.w[i];
            self.particles.w[i] = V::S::from_f64(p.effective_inverse_mass(w.to_f64() as f32, s.h()) as f64);
            (i, w)
        });
        let k = self.prepare(s);
        let project = self.before_projection(s);
        let start = FrameStart {
            projection_start: project.is_some_and(|p| p.start),
            balance_start: s.energy_aware == EnergyAware::Global && self.ledger.carried.is_none(),
            self_collision: self.scene.self_collision.is_some(),
        };
        let mut list = std::mem::take(&mut self.stages);
        stages::frame_into(&mut list, &self.colors, s, start);
        let substeps = stages::substeps(&list);
        self.run_stages(&list[..substeps.start], s, &k);
        // The frame runs on a worker of the solver's own pool, whose threads sweep the large
        // groups as a team (a pool of its own: a team waits at spin barriers, which must not meet
        // unrelated work on a shared pool).
        let threads = match s.threads {
            1 => 1,
            0 => rayon::current_num_threads() as u32,
            n => n.min(cores()),
        };
        let frame = &list[substeps.clone()];
        match threads {
            1 => self.substeps(frame, s, &k),
            n => match self.thread_pool(n) {
                Some(pool) => pool.install(|| self.substeps(frame, s, &k)),
                None => self.substeps(frame, s, &k),
            },
        }
        if let Some((i, w)) = pulled {
            self.particles.w[i] = w;
        }
        self.last = Some(k);
        self.dissipated_before = project.map(|p| p.dissipated);
        self.run_stages(&list[substeps.end..], s, &k);
        self.stages = list;
    }

    /// Runs `list`, a part of the stages [`stages::frame`] lists for `s` (one stage, say), on this
    /// thread after the same preparation as a frame: for stepping through a frame stage by stage,
    /// and for the per-stage parity tests (`tests/gpu_stages.rs`). A finish pass makes the
    /// prediction only when `list` holds it next.
    pub fn step_stages(&mut self, list: &[Stage], s: &Settings) {
        let k = self.prepare(s);
        self.run_stages(list, s, &k);
        self.last = Some(k);
    }

    /// What a frame under `s` needs before its stages: the step's constants (returned), the SIMD
    /// kernels' lanes, Jacobi's scales, the local mode's snapshots, the balance's carried energy
    /// dropped outside the global balance.
    fn prepare(&mut self, s: &Settings) -> StepConstants<V::S> {
        let k = StepConstants::new(s);
        if s.method == Method::GaussSeidel && k.plain() && s.energy_aware != EnergyAware::Local {
            self.refresh_lanes();
        }
        if s.method == Method::Jacobi {
            self.prepare_jacobi(s.jacobi_omega);
        }
        if s.energy_aware == EnergyAware::Local && self.local.is_none() {
            let n = self.particles.len();
            self.local = Some(LocalState { current: vec![V::ZERO; n], previous: vec![V::ZERO; n] });
        }
        if s.energy_aware != EnergyAware::Global {
            self.ledger.carried = None;
        }
        k
    }

    /// Kinetic + gravitational (from the rest centre of mass) + the elastic energy the
    /// constraint forces of the last substep hold ([`metrics::ElasticAccount::held`]; all of it
    /// before the first step) (J).
    pub fn held_energy(&self) -> f64 {
        let p = &self.particles;
        let elastic = metrics::elastic_account(&self.scene, &p.x, self.lambdas(), self.last.as_ref()).held();
        metrics::kinetic(&p.v, &p.w)
            + metrics::gravitational_about(self.scene.gravity, self.rest_com, &p.x, &p.w)
            + elastic
    }

    /// Builds the families' [`FamilyState::lanes`] on first use (offsets for positions of the size
    /// of `V`) and takes their inverse masses again from [`Particles::w`] where it changed since
    /// they were taken (the particles are public: a caller may pin or free one between frames), in
    /// `f32` for the families with a SIMD kernel; before a frame that runs the lean kernels (plain
    /// Gauss-Seidel), the only one that reads them.
    fn refresh_lanes(&mut self) {
        if !is_f32::<V::S>() || self.w_seen == self.particles.w {
            return;
        }
        let w = &self.particles.w;
        crate::for_each_family!(self.scene, |i, f| {
            if family_has_wide(f) {
                let lanes = &mut self.fam[i].lanes;
                if lanes.is_empty() {
                    *lanes = LaneData::new(&f.elements, &f.colors, size_of::<V>());
                }
                lanes.set_masses(&f.elements, w);
            }
        });
        self.w_seen.clone_from(w);
    }

    /// The solver's pool of `threads` ≥ 2 threads (built on first use, kept while the count
    /// stays the same; `None`, one thread, if the system refuses the threads).
    fn thread_pool(&mut self, threads: u32) -> Option<Arc<rayon::ThreadPool>> {
        if self.pool.as_ref().is_none_or(|(n, _)| *n != threads) {
            let pool = pool::build(threads)?;
            self.pool = Some((threads, Arc::new(pool)));
        }
        self.pool.as_ref().map(|(_, p)| p.clone())
    }

    /// The frame's substeps (`frame`, their stages): on the team where it applies, else in order
    /// on this thread.
    fn substeps(&mut self, frame: &[Stage], s: &Settings, k: &StepConstants<V::S>) {
        if self.team_applies() {
            let start = std::time::Instant::now();
            let busy = match self.choice.team() {
                true => self.team_substeps(frame, s, k),
                false => {
                    self.run_stages(frame, s, k);
                    false
                }
            };
            self.choice = self.choice.next(start.elapsed(), busy);
            return;
        }
        self.run_stages(frame, s, k);
    }

    /// Where the threads of the team spent their frames since the solver was made or
    /// [`CpuSolver::reset_team_time`]: working or waiting for one another. Empty while every
    /// frame ran on one thread.
    pub fn team_time(&self) -> &TeamTime {
        &self.team_time
    }

    /// Starts [`CpuSolver::team_time`]'s sums again.
    pub fn reset_team_time(&mut self) {
        self.team_time.clear();
    }

    /// Kinetic + gravitational + elastic energy of the current state (J).
    pub fn total_energy(&self) -> f64 {
        let p = &self.particles;
        total_energy(&self.scene, self.rest_com, &p.x, &p.v, &p.w)
    }

    /// Gravitational (from the rest centre of mass) + elastic energy (J).
    pub fn potential_energy(&self) -> f64 {
        let p = &self.particles;
        potential_energy(&self.scene, self.rest_com, &p.x, &p.w)
    }

    /// The global balance ([`balance`]) on the solver's particles.
    fn balance(&mut self, h0: f64, work: f64) {
        let p = &mut self.particles;
        let (sigma, carried) = balance(&self.scene, self.rest_com, &p.x, &mut p.v, &p.w, h0, work);
        self.ledger.carried = Some(carried);
        self.ledger.last_scale = sigma;
    }

    fn predict(&mut self, h: V::S, pull: Option<Pull>) {
        let g = V::from_vec3(self.scene.gravity);
        let p = &mut self.particles;
        let pull = Pull::within(pull, 0..p.len());
        particles::predict(&mut p.x, &mut p.x_prev, &mut p.v, &p.w, g, h, pull);
    }

    /// The final contact pass and the velocity update ([`particles::finish`], with the last
    /// iteration's contact pass and the next substep's prediction as `step` says); returns the
    /// substep's work of physical dissipation `W` (J, ≤ 0 for losses: the in-loop contact
    /// passes' and its own), summed block by block.
    fn finish(&mut self, step: FinishStep<V>) -> f64 {
        let p = &mut self.particles;
        particles::finish(&self.scene, &mut p.x, &mut p.x_prev, &mut p.v, &p.w, step, &mut self.work_blocks);
        self.work_blocks.iter().sum()
    }

    /// RMS and maximum of the XPBD residual `|C_j + α̃ λ_j|` over all constraints, with the
    /// multipliers of the last substep (docs/algorithm.md §7). `(0, 0)` before the first step.
    pub fn residual(&self) -> (f64, f64) {
        let Some(k) = &self.last else { return (0.0, 0.0) };
        metrics::residual(&self.scene, &self.particles.x, self.lambdas(), k)
    }

    /// Total material energy of every constraint family (J), accumulated in `f64`.
    pub fn elastic_energy(&self) -> f64 {
        metrics::elastic_energy(&self.scene, &self.particles.x)
    }

    /// The self-collision's candidates (none without self-collision).
    pub fn self_pairs(&self) -> &self_collision::SelfPairs {
        &self.self_pairs
    }

    /// Multipliers of the last substep, per family in solve order.
    pub fn lambdas(&self) -> Lambdas<'_, V::S> {
        std::array::from_fn(|i| self.fam[i].lambda.as_slice())
    }

    /// Bytes held by the SIMD kernels' copy of the elements slot by slot ([`LaneData`]):
    /// `(per particle, per element)`, the inverse masses it was taken from (4 bytes a particle) and
    /// the copy (for an element with a SIMD kernel, 8 bytes per particle and 8 for its constants);
    /// none before a frame of plain Gauss-Seidel.
    pub fn lane_bytes(&self) -> (usize, usize) {
        let lanes: usize = self.fam.iter().map(|st| st.lanes.bytes()).sum();
        (self.w_seen.len() * size_of::<V::S>(), lanes)
    }

    /// Constants of the last substep run, if any.
    pub fn last_constants(&self) -> Option<&StepConstants<V::S>> {
        self.last.as_ref()
    }
}

/// `true` when a substep's finish pass makes the next substep's prediction in the same visit of
/// each particle ([`particles::finish`]): in every mode but the global balance, which scales the
/// velocities between the two.
fn fuses_predict(s: &Settings) -> bool {
    s.energy_aware != EnergyAware::Global
}

/// Kinetic + gravitational + elastic energy of the state `x`, `v` (J).
fn total_energy<V: Vector>(scene: &Scene, rest_com: Vec3, x: &[V], v: &[V], w: &[V::S]) -> f64 {
    metrics::kinetic(v, w) + potential_energy(scene, rest_com, x, w)
}

/// Gravitational (heights from the rest centre of mass `rest_com`) + elastic energy at `x` (J).
fn potential_energy<V: Vector>(scene: &Scene, rest_com: Vec3, x: &[V], w: &[V::S]) -> f64 {
    metrics::gravitational_about(scene.gravity, rest_com, x, w) + metrics::elastic_energy(scene, x)
}

/// The global balance (docs/algorithm.md §4) after a substep that dissipated `work` (J) from a state of energy
/// `h0` (J): scales the free particles' velocities by `σ` ([`global_scale`]); returns `σ` and the
/// energy `H₀ = σ² K₁ + P₁` carried to the next substep.
fn balance<V: Vector>(
    scene: &Scene,
    rest_com: Vec3,
    x: &[V],
    v: &mut [V],
    w: &[V::S],
    h0: f64,
    work: f64,
) -> (f64, f64) {
    let k1 = metrics::kinetic(v, w);
    let p1 = potential_energy(scene, rest_com, x, w);
    let sigma = global_scale(h0, work, k1, p1);
    if sigma != 1.0 {
        let sv = V::S::from_f64(sigma);
        for (v, &w) in v.iter_mut().zip(w) {
            if w > V::S::zero() {
                *v = *v * sv;
            }
        }
    }
    (sigma, sigma * sigma * k1 + p1)
}

/// Gauss-Seidel over the elements `group` of family `f` (one color group).
fn gauss_seidel<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    group: Range<usize>,
    lambda: &mut [V::S],
    (lanes, bound): (&LaneData, usize),
    p: &mut Particles<V>,
    k: &StepConstants<V::S>,
    local: Option<LocalCtx<'_, V>>,
) {
    // Separate instantiations, so the plain sweep carries no trace of the local mode.
    match &local {
        Some(ctx) => sweep(f, group, lambda, p, k, |j, idx, xs, ws, c_val, alpha| {
            local_adjusted(ctx, j, idx, xs, ws, k, c_val, alpha)
        }),
        None if k.plain() => plain_sweep(f, group, lambda, (lanes, bound), &mut p.x, &p.x_prev, &p.w, k),
        None => sweep(f, group, lambda, p, k, |_, _, _, _, c_val, _| c_val),
    }
}

/// The sweep in the compliant form without constraint damping or the local mode: each element
/// takes its family's lean kernel ([`Element::project_plain`], [`SIMD_WIDTH`] at a time where the family has
/// a SIMD kernel and the precision is `f32`) and falls back to the general update where that
/// declines. (On several threads, [`team`] runs the same kernels.)
#[allow(unsafe_code)]
fn plain_sweep<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    group: Range<usize>,
    lambda: &mut [V::S],
    (lanes, bound): (&LaneData, usize),
    x: &mut [V],
    x_prev: &[V],
    w: &[V::S],
    k: &StepConstants<V::S>,
) {
    checked_bound(bound, x.len());
    // SAFETY: every particle index of the family's elements is below `bound` ≤ `x.len()`
    // (checked above), the lanes' offsets are those indices times the size of `V`
    // (`refresh_lanes`), and `plain_chunk` touches only the particles of the elements it is given.
    let x = &mut unsafe { Prechecked::slice(x) };
    let (lo, hi) = (group.start, group.end);
    plain_chunk(&f.elements[lo..hi], &mut lambda[lo..hi], &f.params, x, x_prev, (w, lanes.view(lo..hi)), k);
}

/// Panics unless a family's particle indices (all below `bound`, [`FamilyState::bound`]) lie
/// within `len` particles: the check that lets its sweep run without bounds checks.
#[inline]
fn checked_bound(bound: usize, len: usize) {
    assert!(bound <= len, "an element refers to particle {} of {len}", bound - 1);
}

/// `true` where the family's elements have a SIMD kernel ([`Element::PLAIN_WIDE`]).
fn family_has_wide<E: Element<N>, const N: usize>(_: &Family<E, N>) -> bool {
    E::PLAIN_WIDE
}

/// [`plain_sweep`] over consecutive elements of one color group: `w` the particles' inverse
/// masses, `lanes` the elements slot by slot ([`LaneData::view`]; the SIMD kernels run where
/// there is one, in whole batches from the chunk's start and, where the last fewer than
/// [`SIMD_WIDTH`] elements end a color group, in one batch padded with stand-ins,
/// [`LaneView::tail`]; elsewhere the scalar kernel takes them).
#[inline(always)]
fn plain_chunk<E: Element<N>, V: Vector, P: Positions<V> + ?Sized, Q: Positions<V> + ?Sized, const N: usize>(
    es: &[E],
    ls: &mut [V::S],
    params: &E::Params,
    x: &mut P,
    x_prev: &Q,
    (w, lanes): (&[V::S], Option<LaneView<'_, N>>),
    k: &StepConstants<V::S>,
) {
    let one = |e: &E, l: &mut V::S, x: &mut P| {
        if !e.project_plain(params, x, w, l, k.inv_h2, k.sor) {
            update(e, params, l, x, x_prev, w, k, |_, _, c_val, _| c_val);
        }
    };
    let mut j = 0;
    if let Some(lanes) = lanes.filter(|l| E::PLAIN_WIDE && is_f32::<V::S>() && l.len() == es.len()) {
        while j < es.len() {
            let n = (es.len() - j).min(SIMD_WIDTH);
            let mut declined = if n == SIMD_WIDTH {
                let l = &mut ls[j..j + SIMD_WIDTH];
                E::project_plain_wide(lanes.window(j), params, x, l, k.inv_h2, k.sor, ALL_LANES)
            } else if let Some((window, active)) = lanes.tail(j) {
                let mut l = [V::S::zero(); SIMD_WIDTH];
                l[..n].copy_from_slice(&ls[j..]);
                let declined = E::project_plain_wide(window, params, x, &mut l, k.inv_h2, k.sor, active);
                ls[j..].copy_from_slice(&l[..n]);
                declined
            } else {
                break;
            };
            while declined != 0 {
                let l = declined.trailing_zeros() as usize;
                one(&es[j + l], &mut ls[j + l], x);
                declined &= declined - 1;
            }
            j += n;
        }
    }
    for (e, l) in es[j..].iter().zip(&mut ls[j..]) {
        one(e, l, x);
    }
}

/// The general update of one element: gather, project, write back. `adjust(positions, inverse
/// masses, C, α)` gives the constraint value to project.
#[inline(always)]
fn update<E: Element<N>, V: Vector, P: Positions<V> + ?Sized, Q: Positions<V> + ?Sized, const N: usize>(
    e: &E,
    params: &E::Params,
    l: &mut V::S,
    x: &mut P,
    x_prev: &Q,
    w: &[V::S],
    k: &StepConstants<V::S>,
    adjust: impl FnOnce(&[V; N], &[V::S; N], V::S, V::S) -> V::S,
) {
    let idx = e.particles();
    let xs = idx.map(|i| x.get(i as usize));
    let ws = idx.map(|i| w[i as usize]);
    let adj = |c_val, alpha| adjust(&xs, &ws, c_val, alpha);
    if let Some((grad, d)) = solve_element(e, params, &xs, &ws, x_prev, *l, k, adj) {
        *l += d;
        for n in 0..N {
            x.set(idx[n] as usize, xs[n] + grad[n] * (ws[n] * d));
        }
    }
}

/// The Gauss-Seidel sweep of the elements `group` (one color group), with `adjust(j, particles,
/// positions, inverse masses, C, α)` giving the constraint value to project.
#[inline(always)]
fn sweep<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    group: Range<usize>,
    lambda: &mut [V::S],
    p: &mut Particles<V>,
    k: &StepConstants<V::S>,
    adjust: impl Fn(usize, [u32; N], &[V; N], &[V::S; N], V::S, V::S) -> V::S,
) {
    let lo = group.start;
    for (j, (e, l)) in f.elements[group.clone()].iter().zip(&mut lambda[group]).enumerate() {
        let adj = |xs: &[V; N], ws: &[V::S; N], c_val, alpha| adjust(lo + j, e.particles(), xs, ws, c_val, alpha);
        update(e, &f.params, l, &mut p.x[..], &p.x_prev[..], &p.w, k, adj);
    }
}
