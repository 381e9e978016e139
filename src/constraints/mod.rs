//! Constraint families: one module per family, each a set of pure functions (energy, gradient,
//! constraint value in either projection form) over plain element records.
//!
//! Every family implements [`Element`]; the solver is written once against it. The element
//! records are `#[repr(C)]` and `Pod` so the GPU solver can upload them unchanged.

pub mod bending;
mod lanes;
pub mod membrane;
pub(crate) mod simd;
pub mod spring;
pub mod tet;

use crate::math::Vector;

pub use bending::{Bend, BendParams};
pub use lanes::{LANE_CONSTANTS, LaneData, LaneView, LaneWindow};
pub use membrane::{Membrane, MembraneParams, Orthotropic};
pub use simd::WIDTH as SIMD_WIDTH;

/// Every lane of a SIMD batch ([`Element::project_plain_wide`]'s `active` for a whole batch).
pub const ALL_LANES: u32 = (1 << SIMD_WIDTH) - 1;
pub use spring::{Spring, SpringMaterial, SpringParams};
pub use tet::{Tet, TetParams};

/// How a constraint is projected (docs/algorithm.md §2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Form {
    /// Standard XPBD: a signed constraint `C` with `E = C² / (2α)`; stiffness keeps its physical
    /// meaning and the solve converges to implicit Euler.
    #[default]
    Compliant,
    /// The paper's form: the constraint value is the potential energy, `C = E`, solved with a
    /// small fixed compliance (`Settings::energy_compliance`). XPBD then minimises `E² / (2α)`.
    Energy,
}

crate::error::command_names!(Form, "form", { Compliant => "compliant", Energy => "energy" });

/// A constraint value prepared for the XPBD update: `C`, `∇C` per particle and the compliance
/// `α` (m²/N-like units of the form in use; `0` is infinitely stiff).
#[derive(Clone, Copy, Debug)]
pub struct Projection<V: Vector, const N: usize> {
    /// Constraint value `C`.
    pub c: V::S,
    /// Gradient `∇_i C` for each particle of the element.
    pub grad: [V; N],
    /// Compliance `α` (inverse stiffness).
    pub alpha: V::S,
}

/// An element of a constraint family touching `N` particles.
pub trait Element<const N: usize>: Copy + Send + Sync + 'static {
    /// Parameters shared by all elements of the family (material, form constants).
    type Params: Copy + Send + Sync;

    /// Indices of the particles this element touches.
    fn particles(&self) -> [u32; N];

    /// The pairs of particles a picture of the element joins (the viewer's color groups): every
    /// pair unless the family says otherwise (a spring itself, a triangle's three edges, a
    /// tetrahedron's six).
    fn outline(&self) -> Vec<[u32; 2]> {
        let p = self.particles();
        (0..N).flat_map(|i| (i + 1..N).map(move |j| [p[i], p[j]])).collect()
    }

    /// Material potential energy `E(x)` in joules.
    fn energy<V: Vector>(&self, p: &Self::Params, x: &[V; N]) -> V::S;

    /// Gradient of [`Element::energy`] with respect to each particle, in newtons (J/m).
    fn energy_gradient<V: Vector>(&self, p: &Self::Params, x: &[V; N]) -> [V; N];

    /// The constraint used by the projection in the given form. In the energy form it is
    /// `C = E`, `∇C = ∇E`, `α = energy_compliance`.
    #[inline(always)]
    fn constraint<V: Vector>(
        &self,
        p: &Self::Params,
        x: &[V; N],
        form: Form,
        energy_compliance: V::S,
    ) -> Projection<V, N> {
        match form {
            Form::Energy => {
                Projection { c: self.energy(p, x), grad: self.energy_gradient(p, x), alpha: energy_compliance }
            }
            Form::Compliant => self.compliant(p, x),
        }
    }

    /// The compliant-form constraint `C`, `∇C` and `α`, with `E = C² / (2α)`.
    fn compliant<V: Vector>(&self, p: &Self::Params, x: &[V; N]) -> Projection<V, N>;

    /// A leaner kernel for the plain Gauss-Seidel update in the compliant form (no constraint
    /// damping, no local energy-aware mode): `Δλ = ω (−C − α̃λ) / (Σ wᵢ|∇ᵢC|² + α̃)` with
    /// `α̃ = α / h²` (`inv_h2 = 1/h²`), `λ += Δλ`, `xᵢ += wᵢ ∇ᵢC Δλ`, applied to `x` in place.
    /// Returns `false`, changing nothing, where the family has no such kernel or the element is
    /// degenerate; the solver then takes the general path, which gives the same update.
    #[inline(always)]
    fn project_plain<V: Vector, P: Positions<V> + ?Sized>(
        &self,
        _p: &Self::Params,
        _x: &mut P,
        _w: &[V::S],
        _lambda: &mut V::S,
        _inv_h2: V::S,
        _sor: V::S,
    ) -> bool {
        false
    }

    /// `true` where the family overrides [`Element::project_plain_wide`].
    const PLAIN_WIDE: bool = false;

    /// How many of [`Element::lane_constants`] the family uses (the rest are not stored).
    const LANE_CONSTANT_COUNT: usize = 0;

    /// The element's constants the SIMD kernel loads by lane ([`LaneData`]; unused elsewhere).
    #[inline(always)]
    fn lane_constants(&self) -> [f32; LANE_CONSTANTS] {
        [0.0; LANE_CONSTANTS]
    }

    /// [`Element::project_plain`] for [`SIMD_WIDTH`] consecutive elements of one color group at
    /// once, one per SIMD lane, given slot by slot (`lanes`, [`LaneView::window`]: each particle
    /// slot's inverse masses in 1/kg and byte offsets, and the elements' [`Element::lane_constants`])
    /// (called for `f32` only: `lambda` holds exactly [`SIMD_WIDTH`]). Only the lanes set in
    /// `active` hold elements ([`ALL_LANES`] for a whole batch; a group's last, partial batch
    /// fills the rest with stand-ins, [`LaneView::tail`]): the others are computed but neither
    /// written nor reported. Returns a mask of the active lanes it declined (bit `l` set: element
    /// `l` left unchanged for the scalar path).
    #[inline(always)]
    fn project_plain_wide<V: Vector, P: Positions<V> + ?Sized>(
        _lanes: LaneWindow<'_, N>,
        _p: &Self::Params,
        _x: &mut P,
        _lambda: &mut [V::S],
        _inv_h2: V::S,
        _sor: V::S,
        active: u32,
    ) -> u32 {
        active
    }
}

/// Read and write access to particle positions for the in-place kernels: a plain slice, or the
/// solver's view shared by the threads of one color group.
pub trait Positions<V> {
    /// Position of particle `i`.
    fn get(&self, i: usize) -> V;
    /// Moves particle `i` to `v`.
    fn set(&mut self, i: usize, v: V);

    /// Position of the particle at byte offset `at` (its index × the size of `V`, [`LaneData`]).
    #[inline(always)]
    fn get_at(&self, at: u32) -> V {
        self.get(at as usize / size_of::<V>())
    }

    /// Moves the particle at byte offset `at` to `v`.
    #[inline(always)]
    fn set_at(&mut self, at: u32, v: V) {
        self.set(at as usize / size_of::<V>(), v)
    }
}

impl<V: Copy> Positions<V> for [V] {
    #[inline(always)]
    fn get(&self, i: usize) -> V {
        self[i]
    }
    #[inline(always)]
    fn set(&mut self, i: usize, v: V) {
        self[i] = v;
    }
}

/// The compliant form of an energy-based element: `C = √(2E/s)` with `α = 1/s` for the stiffness
/// scale `s`, so `E = C²/(2α)`, and `∇C = ∇E/(s C)`. When `C` vanishes (at rest, where its
/// gradient is undefined) or is not finite, the element is skipped for the iteration (`C = 0`,
/// `∇C = 0`).
pub(crate) fn energy_root<V: Vector, const N: usize>(
    energy: V::S,
    gradient: impl FnOnce() -> [V; N],
    scale: f64,
) -> Projection<V, N> {
    use crate::math::prelude::*;
    let s = V::S::from_f64(scale);
    let c_val = (c::<V::S>(2.0) * energy.max(V::S::zero()) / s).sqrt();
    let alpha = V::S::one() / s;
    if c_val <= c(1e-12) || !c_val.is_finite() {
        return Projection { c: V::S::zero(), grad: [V::ZERO; N], alpha };
    }
    let k = V::S::one() / (s * c_val);
    Projection { c: c_val, grad: gradient().map(|g| g * k), alpha }
}

/// Gathers the positions of an element's particles.
#[inline(always)]
pub fn gather<V: Vector, const N: usize>(x: &[V], idx: [u32; N]) -> [V; N] {
    idx.map(|i| x[i as usize])
}

crate::error::command_names!(SpringMaterial, "material", { Hookean => "hookean", StVK => "stvk-spring" });
