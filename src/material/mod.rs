//! Continuum materials: 3×3 matrices, the signed SVD, second-order forward differentiation, and
//! the 3D elastic models (energy density and stress).

pub mod hyperdual;
pub mod invariants;
pub mod mat3;
pub mod models;
pub mod svd;

pub use mat3::M3;
pub use models::{Elastic, Model, SIGMA_MIN};
pub use svd::{Svd, svd};
