//! Error and energy measures (docs/algorithm.md §7), accumulated in `f64`.

use crate::constraints::{Element, gather};
use crate::math::prelude::*;
use crate::scene::{Family, Scene};
use crate::solver::{CpuSolver, StepConstants};

/// Mean and maximum relative stretch `||d| − l₀| / l₀` over `edges` of rest lengths `rest` (m).
pub fn stretch<V: Vector>(edges: &[[u32; 2]], rest: &[f32], x: &[V]) -> (f64, f64) {
    let (mut sum, mut max) = (0.0f64, 0.0f64);
    for (&[a, b], &l0) in edges.iter().zip(rest) {
        let (a, b, l0) = (a as usize, b as usize, l0 as f64);
        let l = (x[b].to_dvec3() - x[a].to_dvec3()).length();
        let s = if l0 > 0.0 { (l - l0).abs() / l0 } else { 0.0 };
        sum += s;
        max = max.max(s);
    }
    if edges.is_empty() { (0.0, 0.0) } else { (sum / edges.len() as f64, max) }
}

/// The scene's reported edges whose rest vector (between the initial positions) lies along a
/// coordinate axis, with their rest lengths (m): a cloth grid's warp and weft edges without the
/// diagonals, on which the performance issue measures stretch.
pub fn axis_aligned_edges(scene: &Scene) -> (Vec<[u32; 2]>, Vec<f32>) {
    scene
        .edges
        .iter()
        .zip(&scene.edge_rest)
        .filter(|&(&[a, b], _)| {
            let d = (scene.positions[b as usize] - scene.positions[a as usize]).abs();
            d.max_element() > 0.0 && d.max_element() >= (1.0 - 1e-4) * d.length()
        })
        .map(|(&e, &l0)| (e, l0))
        .unzip()
}

/// Kinetic energy `Σ ½ m |v|²` over free particles (J).
pub fn kinetic<V: Vector>(v: &[V], w: &[V::S]) -> f64 {
    v.iter()
        .zip(w)
        .filter(|(_, w)| **w > V::S::zero())
        .map(|(v, w)| 0.5 * v.to_dvec3().length_squared() / w.to_f64())
        .sum()
}

/// Gravitational energy `−Σ m g·(x − x_ref)` over free particles (J) as reported: heights
/// measured from the ground plane (`y = 0` without one), so a body's total energy starts
/// positive and relative drifts are meaningful. (The global balance measures from the rest centre
/// of mass instead, for rounding; the reference only shifts the value.)
pub fn gravitational<V: Vector>(scene: &Scene, x: &[V], w: &[V::S]) -> f64 {
    let floor = scene.ground.map_or(0.0, |g| g.height);
    gravitational_about(scene.gravity, glam::Vec3::new(0.0, floor, 0.0), x, w)
}

/// Gravitational energy `−Σ m g·(x − x_ref)` over free particles (J) for gravity `g` (m/s²) and
/// reference point `x_ref` (m).
pub fn gravitational_about<V: Vector>(g: glam::Vec3, x_ref: glam::Vec3, x: &[V], w: &[V::S]) -> f64 {
    let (g, r) = (g.as_dvec3(), x_ref.as_dvec3());
    x.iter().zip(w).filter(|(_, w)| **w > V::S::zero()).map(|(x, w)| -g.dot(x.to_dvec3() - r) / w.to_f64()).sum()
}

/// The multipliers `λ` of a substep, one slice per family in solve order (empty for a family the
/// scene does not have).
pub type Lambdas<'a, S> = [&'a [S]; crate::scene::FAMILY_COUNT];

/// RMS and maximum of the XPBD residual `|C_j + α̃ λ_j|` over every constraint of `scene`,
/// with the multipliers `λ` of a substep run with constants `k`.
pub fn residual<V: Vector>(scene: &Scene, x: &[V], lambdas: Lambdas<'_, V::S>, k: &StepConstants<V::S>) -> (f64, f64) {
    constraint_pass(scene, x, lambdas, k, false).residual()
}

/// What one visit of every constraint measures: the XPBD residuals' sums and, when asked, the
/// [`ElasticAccount`].
#[derive(Clone, Copy, Debug, Default)]
struct ConstraintPass {
    /// `Σⱼ rⱼ²`, `maxⱼ rⱼ` and the count of the residuals `rⱼ = |Cⱼ + α̃ⱼλⱼ|`.
    squares: f64,
    max: f64,
    count: usize,
    account: ElasticAccount,
}

impl ConstraintPass {
    /// RMS and maximum of the residual (`(0, 0)` without constraints).
    fn residual(&self) -> (f64, f64) {
        if self.count == 0 { (0.0, 0.0) } else { ((self.squares / self.count as f64).sqrt(), self.max) }
    }
}

/// Visits every constraint once at `x` with the multipliers `λ` of a substep run with constants
/// `k`: its residual `|C + α̃λ|` and, with `energy`, its share of the [`ElasticAccount`].
fn constraint_pass<V: Vector>(
    scene: &Scene,
    x: &[V],
    lambdas: Lambdas<'_, V::S>,
    k: &StepConstants<V::S>,
    energy: bool,
) -> ConstraintPass {
    let mut out = ConstraintPass::default();
    crate::for_each_family!(scene, |i, f| {
        for (e, &l) in f.elements.iter().zip(lambdas[i]) {
            let xs = gather(x, e.particles());
            let proj = e.constraint(&f.params, &xs, k.form, k.energy_compliance);
            let r = (proj.c + proj.alpha * k.inv_h2 * l).abs().to_f64();
            out.squares += r * r;
            out.max = out.max.max(r);
            out.count += 1;
            if energy {
                let energy = e.energy(&f.params, &xs).to_f64();
                let (c_val, alpha, l, inv_h2) = (proj.c.to_f64(), proj.alpha.to_f64(), l.to_f64(), k.inv_h2.to_f64());
                let held = match k.form {
                    // An infinitely stiff constraint (α = 0) has no deformation of its own to hold.
                    crate::constraints::Form::Compliant if c_val != 0.0 && alpha > 0.0 => {
                        (alpha * inv_h2 * l / c_val).powi(2)
                    }
                    crate::constraints::Form::Compliant => 1.0,
                    crate::constraints::Form::Energy => (l * inv_h2).powi(2),
                };
                out.account.material += energy;
                out.account.unresolved += energy * (1.0 - held).max(0.0);
            }
        }
    });
    out
}

/// Total material energy of every constraint family of `scene` at `x` (J).
pub fn elastic_energy<V: Vector>(scene: &Scene, x: &[V]) -> f64 {
    fn family<E: Element<N>, V: Vector, const N: usize>(f: &Family<E, N>, x: &[V]) -> f64 {
        f.elements.iter().map(|e| e.energy(&f.params, &gather(x, e.particles())).to_f64()).sum()
    }
    let mut sum = 0.0;
    crate::for_each_family!(scene, |_i, f| sum += family(f, x));
    sum
}

/// The iterate's elastic energy split into the part the constraint forces hold and the
/// unresolved rest (J).
///
/// For constraint `j` with material energy `Eⱼ(x)` the ratio of the force the solve applied to
/// the material's own force at the iterate is `ρⱼ = |α̃ⱼλⱼ / Cⱼ|` in the compliant form (the
/// force `λⱼ/h²` against `Cⱼ/αⱼ`) and `ρⱼ = |λⱼ| / h²` in the energy form (the force `λⱼ∇E/h²`
/// against `∇E`). The energy the applied force holds is `ρⱼ² Eⱼ` (the energy of the deformation
/// that force would hold; `½ αⱼλⱼ²/h⁴` in the compliant form, exact for energies quadratic in
/// `Cⱼ`), so the held part is `Eⱼ min(1, ρⱼ²)` and the unresolved part `Eⱼ max(0, 1 − ρⱼ²)`.
/// Equivalently, in the compliant form the held deformation is `Cⱼ − rⱼ = −α̃ⱼλⱼ`, the constraint
/// value less its XPBD residual `rⱼ = Cⱼ + α̃ⱼλⱼ`. A converged solve has `rⱼ = 0`, nothing
/// unresolved; an under-converged one leaves stretch that no force backs, and counting it as
/// potential energy is what makes a few iterations look like a gain of hundreds of joules.
/// Without multipliers (before the first step), and for an infinitely stiff constraint
/// (`α = 0`), the whole energy counts as held.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ElasticAccount {
    /// `Σⱼ Eⱼ(x)`, the material energy of the iterate (J).
    pub material: f64,
    /// `Σⱼ Eⱼ max(0, 1 − ρⱼ²)`, the part no constraint force holds (J).
    pub unresolved: f64,
}

impl ElasticAccount {
    /// The part the constraint forces hold, `material − unresolved` (J).
    pub fn held(&self) -> f64 {
        self.material - self.unresolved
    }
}

/// The [`ElasticAccount`] of the iterate `x` with the multipliers `λ` of a substep run with
/// constants `k` (`None`: before the first step, nothing unresolved).
pub fn elastic_account<V: Vector>(
    scene: &Scene,
    x: &[V],
    lambdas: Lambdas<'_, V::S>,
    k: Option<&StepConstants<V::S>>,
) -> ElasticAccount {
    match k {
        Some(k) => constraint_pass(scene, x, lambdas, k, true).account,
        None => ElasticAccount { material: elastic_energy(scene, x), unresolved: 0.0 },
    }
}

/// A simulation state to measure: positions, velocities, inverse masses, and the multipliers
/// and constants of the last substep (if one has run).
#[derive(Clone, Copy, Debug)]
pub struct StateView<'a, V: Vector> {
    /// Positions (m).
    pub x: &'a [V],
    /// Velocities (m/s).
    pub v: &'a [V],
    /// Inverse masses (1/kg).
    pub w: &'a [V::S],
    /// Multipliers: springs, bending, tetrahedra.
    pub lambdas: Lambdas<'a, V::S>,
    /// Constants of the last substep.
    pub constants: Option<&'a StepConstants<V::S>>,
    /// Work of physical dissipation since the start (J).
    pub dissipated: f64,
}

impl<'a, V: Vector> StateView<'a, V> {
    /// A CPU solver's current state.
    pub fn of_solver(solver: &'a CpuSolver<V>) -> Self {
        let p = &solver.particles;
        StateView {
            x: &p.x,
            v: &p.v,
            w: &p.w,
            lambdas: solver.lambdas(),
            constants: solver.last_constants(),
            dissipated: solver.ledger.dissipated,
        }
    }
}

/// What is reported for a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// Frame number (1 after the first step).
    pub frame: u32,
    /// Wall-clock time of the frame's solve (ms).
    pub time_ms: f64,
    /// RMS of `|C + α̃λ|`.
    pub residual_rms: f64,
    /// Maximum of `|C + α̃λ|`.
    pub residual_max: f64,
    /// Mean relative stretch.
    pub stretch_mean: f64,
    /// Maximum relative stretch.
    pub stretch_max: f64,
    /// Kinetic energy (J).
    pub kinetic: f64,
    /// Gravitational energy (J).
    pub gravitational: f64,
    /// Elastic energy the constraint forces hold (J): the iterate's material energy less
    /// [`FrameStats::unresolved`] ([`ElasticAccount::held`]).
    pub elastic: f64,
    /// The iterate's material energy that no constraint force holds (J,
    /// [`ElasticAccount::unresolved`]): unresolved stretch, not energy of the body. Reported apart
    /// and left out of [`FrameStats::total`].
    pub unresolved: f64,
    /// Work of physical dissipation since the start (J, ≤ 0 for losses): velocity damping and
    /// every contact pass, in the loop and the final one. `total − dissipated` is what an exact integrator would conserve.
    pub dissipated: f64,
}

impl FrameStats {
    /// Kinetic + gravitational + held elastic energy (J): the energy of the body, without the
    /// unresolved part.
    pub fn total(&self) -> f64 {
        self.kinetic + self.gravitational + self.elastic
    }

    /// The iterate's whole material energy, held and unresolved (J).
    pub fn material(&self) -> f64 {
        self.elastic + self.unresolved
    }

    /// `true` when every figure is finite.
    pub fn is_finite(&self) -> bool {
        [self.residual_rms, self.residual_max, self.stretch_mean, self.stretch_max, self.total()]
            .iter()
            .all(|v| v.is_finite())
    }

    /// Measures a CPU solver's current state.
    pub fn measure<V: Vector>(solver: &CpuSolver<V>, frame: u32, time_ms: f64) -> Self {
        Self::of_state(solver.scene(), &StateView::of_solver(solver), frame, time_ms)
    }

    /// Measures any backend's state of `scene`.
    pub fn of_state<V: Vector>(scene: &Scene, s: &StateView<'_, V>, frame: u32, time_ms: f64) -> Self {
        // One visit of every constraint gives both the residual and the account.
        let ((residual_rms, residual_max), account) = match s.constants {
            Some(k) => {
                let pass = constraint_pass(scene, s.x, s.lambdas, k, true);
                (pass.residual(), pass.account)
            }
            None => ((0.0, 0.0), elastic_account(scene, s.x, s.lambdas, None)),
        };
        let (stretch_mean, stretch_max) = stretch(&scene.edges, &scene.edge_rest, s.x);
        FrameStats {
            frame,
            time_ms,
            residual_rms,
            residual_max,
            stretch_mean,
            stretch_max,
            kinetic: kinetic(s.v, s.w),
            gravitational: gravitational(scene, s.x, s.w),
            elastic: account.held(),
            unresolved: account.unresolved,
            dissipated: s.dissipated,
        }
    }

    /// Column names of [`FrameStats::csv_row`].
    pub const CSV_HEADER: &'static str = "frame,time_ms,residual_rms,residual_max,stretch_mean,stretch_max,kinetic_j,gravitational_j,elastic_j,total_j,dissipated_j,unresolved_j";

    /// One CSV row.
    pub fn csv_row(&self) -> String {
        format!(
            "{},{:.4},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e}",
            self.frame,
            self.time_ms,
            self.residual_rms,
            self.residual_max,
            self.stretch_mean,
            self.stretch_max,
            self.kinetic,
            self.gravitational,
            self.elastic,
            self.total(),
            self.dissipated,
            self.unresolved
        )
    }
}

impl std::fmt::Display for FrameStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let FrameStats { frame, time_ms, residual_rms, residual_max, stretch_mean, stretch_max, kinetic, .. } = *self;
        let (gravitational, elastic, total) = (self.gravitational, self.elastic, self.total());
        let (dissipated, unresolved) = (self.dissipated, self.unresolved);
        write!(
            f,
            "frame {frame:5}  {time_ms:8.3} ms  residual rms {residual_rms:.3e} max {residual_max:.3e}  \
             stretch mean {stretch_mean:.3e} max {stretch_max:.3e}  KE {kinetic:.4e} J  GPE {gravitational:+.4e} J  \
             elastic {elastic:.4e} J  total {total:+.4e} J  dissipated {dissipated:+.3e} J  unresolved {unresolved:.3e} J"
        )
    }
}
