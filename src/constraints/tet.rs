//! Tetrahedral elements with the 3D elastic models of [`crate::material`] (docs/algorithm.md §3).
//!
//! Particles `[x₀, x₁, x₂, x₃]`; `D_s = [x₁ − x₀, x₂ − x₀, x₃ − x₀]`, `F = D_s D_m⁻¹`, energy
//! `E = V₀ Ψ(F)` (J), gradient `[∇x₁ ∇x₂ ∇x₃] = V₀ P(F) D_m⁻ᵀ`, `∇x₀ = −Σ`. Compliant form:
//! `C = √(2 V₀ Ψ / s)` with `α = 1/s` for the stiffness scale `s` (Young's modulus, Pa), so
//! `E = C²/(2α)`; `∇C = ∇E / (s C)`, and the element is skipped for the iteration when `C`
//! vanishes (at rest, where its gradient is undefined).

use bytemuck::{Pod, Zeroable};

use super::{Element, Form, Projection, energy_root};
use crate::material::{Elastic, M3};
use crate::math::prelude::*;

/// Parameters shared by the tetrahedra of a family.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TetParams {
    /// The model and its constants.
    pub elastic: Elastic,
    /// Stiffness scale `s` of the compliant form (Pa), `α = 1/s`.
    pub scale: f64,
}

/// One tetrahedron. Keep in sync with `Tet` in the WGSL sources.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Tet {
    /// Particles.
    pub p: [u32; 4],
    /// `D_m⁻¹` by columns.
    pub dm_inv: [f32; 9],
    /// Rest volume `V₀` (m³).
    pub volume: f32,
    /// Padding.
    pub pad: [u32; 2],
}

const _: () = assert!(std::mem::size_of::<Tet>() == 64);

impl Tet {
    /// A tetrahedron at rest at positions `x`, or `None` when it is degenerate (zero volume).
    pub fn at_rest(p: [u32; 4], x: &[glam::Vec3]) -> Option<Self> {
        let xs = p.map(|i| x[i as usize].as_dvec3());
        let dm = M3::from_cols(xs[1] - xs[0], xs[2] - xs[0], xs[3] - xs[0]);
        let volume = dm.det() / 6.0;
        let inv = dm.inverse()?;
        if volume.abs() < 1e-15 {
            return None;
        }
        let mut dm_inv = [0.0f32; 9];
        for c in 0..3 {
            for r in 0..3 {
                dm_inv[3 * c + r] = inv.0[c][r] as f32;
            }
        }
        Some(Tet { p, dm_inv, volume: volume.abs() as f32, pad: [0; 2] })
    }

    fn dm_inv<S: Real>(&self) -> M3<S> {
        let mut m = M3::zero();
        for c in 0..3 {
            for r in 0..3 {
                m.0[c][r] = self.dm_inv[3 * c + r].into();
            }
        }
        m
    }

    /// Energy `V₀ Ψ(F)` (J) and its gradient (N) at `x`, from one evaluation of the model
    /// ([`Elastic::energy_stress`](crate::material::Elastic::energy_stress)).
    #[inline(always)]
    pub fn energy_and_gradient<V: Vector>(&self, p: &TetParams, x: &[V; 4]) -> (V::S, [V; 4]) {
        let dm_inv = self.dm_inv::<V::S>();
        let f = M3::from_cols(x[1] - x[0], x[2] - x[0], x[3] - x[0]).mul(&dm_inv);
        let (psi, stress) = p.elastic.energy_stress(&f);
        let volume: V::S = self.volume.into();
        let h = stress.mul(&dm_inv.transpose()).scale(volume);
        let (g1, g2, g3) = (h.col::<V>(0), h.col::<V>(1), h.col::<V>(2));
        (volume * psi, [-(g1 + g2 + g3), g1, g2, g3])
    }

    /// The deformation gradient at `x`.
    pub fn deformation<V: Vector>(&self, x: &[V; 4]) -> M3<V::S> {
        M3::from_cols(x[1] - x[0], x[2] - x[0], x[3] - x[0]).mul(&self.dm_inv())
    }
}

impl Element<4> for Tet {
    type Params = TetParams;

    #[inline]
    fn particles(&self) -> [u32; 4] {
        self.p
    }

    fn energy<V: Vector>(&self, p: &TetParams, x: &[V; 4]) -> V::S {
        <V::S as From<f32>>::from(self.volume) * p.elastic.energy_density(&self.deformation(x))
    }

    fn energy_gradient<V: Vector>(&self, p: &TetParams, x: &[V; 4]) -> [V; 4] {
        self.energy_and_gradient(p, x).1
    }

    /// Both forms from one evaluation of the model ([`Tet::energy_and_gradient`]).
    #[inline(always)]
    fn constraint<V: Vector>(
        &self,
        p: &TetParams,
        x: &[V; 4],
        form: Form,
        energy_compliance: V::S,
    ) -> Projection<V, 4> {
        match form {
            Form::Energy => {
                let (e, grad) = self.energy_and_gradient(p, x);
                Projection { c: e, grad, alpha: energy_compliance }
            }
            Form::Compliant => self.compliant(p, x),
        }
    }

    #[inline(always)]
    fn compliant<V: Vector>(&self, p: &TetParams, x: &[V; 4]) -> Projection<V, 4> {
        let (e, grad) = self.energy_and_gradient(p, x);
        energy_root(e, || grad, p.scale)
    }
}
