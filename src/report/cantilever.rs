//! Closed-form estimates for a uniform cantilever of rectangular section under its own weight,
//! clamped at one end: the references the beam study compares against.

use glam::DVec3;

use crate::scene::Scene;

/// A prismatic cantilever along x: length `L`, section `b × h` (width along z, height along y),
/// density `ρ` and gravity `g`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cantilever {
    /// Length `L` (m).
    pub length: f64,
    /// Width `b` across the load (m).
    pub width: f64,
    /// Height `h` along the load (m).
    pub height: f64,
    /// Density `ρ` (kg/m³).
    pub density: f64,
    /// Gravitational acceleration `g` (m/s²).
    pub gravity: f64,
}

impl Cantilever {
    /// The cantilever a scene's rest shape describes: its bounding box (length along x, height
    /// along y, width along z), the given density (kg/m³) and the scene's gravity.
    pub fn of_scene(scene: &Scene, density: f64) -> Self {
        let (mut lo, mut hi) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
        for p in &scene.positions {
            (lo, hi) = (lo.min(p.as_dvec3()), hi.max(p.as_dvec3()));
        }
        let size = hi - lo;
        Cantilever {
            length: size.x,
            width: size.z,
            height: size.y,
            density,
            gravity: scene.gravity.as_dvec3().length(),
        }
    }

    /// Section area `A = b h` (m²).
    pub fn area(&self) -> f64 {
        self.width * self.height
    }

    /// Weight per length `q = ρ g A` (N/m).
    pub fn load(&self) -> f64 {
        self.density * self.gravity * self.area()
    }

    /// Second moment of area about the bending axis, `I = b h³ / 12` (m⁴).
    pub fn second_moment(&self) -> f64 {
        self.width * self.height.powi(3) / 12.0
    }

    /// Euler–Bernoulli tip deflection under a uniform load, `δ = q L⁴ / (8 E I)` (m), for Young's
    /// modulus `E` (Pa).
    pub fn euler_bernoulli(&self, young: f64) -> f64 {
        self.load() * self.length.powi(4) / (8.0 * young * self.second_moment())
    }

    /// Timoshenko tip deflection: Euler–Bernoulli plus the shear term `q L² / (2 κ G A)` (m),
    /// `G = E / (2(1 + ν))`, with Cowper's shear coefficient for a rectangle
    /// `κ = 10(1 + ν) / (12 + 11ν)`. For a stubby beam (L/h = 5) it is a few percent larger.
    pub fn timoshenko(&self, young: f64, poisson: f64) -> f64 {
        let shear_modulus = young / (2.0 * (1.0 + poisson));
        let kappa = 10.0 * (1.0 + poisson) / (12.0 + 11.0 * poisson);
        self.euler_bernoulli(young) + self.load() * self.length.powi(2) / (2.0 * kappa * shear_modulus * self.area())
    }

    /// First bending angular frequency `ω₁ = 1.8751² √(E I / (ρ A L⁴))` (rad/s).
    pub fn first_frequency(&self, young: f64) -> f64 {
        1.875_104_f64.powi(2)
            * (young * self.second_moment() / (self.density * self.area() * self.length.powi(4))).sqrt()
    }
}
