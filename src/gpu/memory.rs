//! Device memory held by a [`super::GpuSolver`]: the sizes of the buffers it created, by purpose.

/// Bytes of the device buffers a solver holds, by purpose (each buffer's size as created, before
/// any alignment or sub-allocation overhead of the driver). Buffers allocated on demand (Jacobi,
/// the energy-aware modes) count from the frame that first needs them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GpuMemory {
    /// Particle state: positions with inverse masses, positions at the start of the substep,
    /// velocities with the dissipation ledger (3 × 16 bytes per particle).
    pub particles: u64,
    /// Constraint elements and their multipliers `λ`, every family.
    pub constraints: u64,
    /// Scene-wide buffers whose size does not grow with the mesh: the simulation parameters, the
    /// colliders and the dispatch-range table (one 256-byte entry per color group).
    pub fixed: u64,
    /// Jacobi: per-constraint scales, per-slot corrections and the particle incidence lists.
    pub jacobi: u64,
    /// The energy reduction's partial sums and ledger (`--energy-aware global`).
    pub energy: u64,
    /// The local energy-aware mode's snapshots and start energies.
    pub local: u64,
    /// Self-collision: rest and reference positions, the pass's moves, the hash and each
    /// particle's candidates.
    pub self_collision: u64,
}

impl GpuMemory {
    /// Every buffer together (bytes).
    pub fn total(&self) -> u64 {
        self.particles + self.constraints + self.fixed + self.jacobi + self.energy + self.local + self.self_collision
    }
}

/// The largest device buffer a [`super::GpuSolver`] creates for `scene`, by what it holds, and
/// its size (bytes). With `s: None`, of the buffers made with the solver: the particles'
/// (positions with inverse masses, 16 bytes a particle), each family's elements and multipliers
/// `λ` (4 bytes an element) and the self-collision's candidate lists (`(2 + CAPACITY) × 4` bytes
/// a particle). With `Some(s)`, also of those made when a frame under `s` first needs them:
/// Jacobi's corrections (16 bytes a slot, `arity` slots an element) and the local mode's
/// snapshots (32 bytes a particle). Each is bound whole, so each must fit the device's
/// `max_buffer_size` and `max_storage_buffer_binding_size`.
pub fn largest_buffer(scene: &crate::scene::Scene, s: Option<&crate::solver::Settings>) -> (&'static str, u64) {
    use crate::solver::{EnergyAware, Method};
    let n = scene.num_particles() as u64;
    let mut slots = 0u64;
    let mut sizes = vec![("particle positions", 16 * n)];
    crate::for_each_family!(scene, |i, f| {
        let name = super::FamilyKind::ALL[i].name();
        sizes.push((name, std::mem::size_of_val(&f.elements[..]) as u64));
        sizes.push(("multipliers", 4 * f.len() as u64));
        slots += (super::FamilyKind::ALL[i].arity() as u64) * f.len() as u64;
    });
    if scene.self_collision.is_some() {
        let capacity = crate::solver::self_collision::CAPACITY as u64;
        sizes.push(("self-collision candidates", (2 + capacity) * 4 * n));
    }
    if s.is_some_and(|s| s.method == Method::Jacobi) {
        sizes.push(("Jacobi corrections", 16 * slots));
    }
    if s.is_some_and(|s| s.energy_aware == EnergyAware::Local) {
        sizes.push(("local-mode snapshots", 32 * n));
    }
    sizes.into_iter().max_by_key(|&(_, size)| size).unwrap_or(("particle positions", 0))
}

/// `Ok` when [`largest_buffer`] of `scene` (under `s`, see there) fits `limits`, else an error
/// naming the buffer, its size and the device's limit.
pub fn check_fits(
    scene: &crate::scene::Scene,
    s: Option<&crate::solver::Settings>,
    limits: &wgpu::Limits,
) -> crate::error::Result<()> {
    let (what, size) = largest_buffer(scene, s);
    let limit = limits.max_buffer_size.min(limits.max_storage_buffer_binding_size);
    if size <= limit {
        return Ok(());
    }
    let mb = |b: u64| b as f64 / (1024.0 * 1024.0);
    Err(crate::error::Error::Gpu(format!(
        "this scene needs a GPU buffer of {:.0} MiB ({what}, {} particles), more than this device \
         allows in one buffer ({:.0} MiB): run it on the CPU (--backend cpu) or make it smaller",
        mb(size),
        scene.num_particles(),
        mb(limit)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneOptions, build};

    #[test]
    fn a_scene_too_large_for_the_device_is_refused_with_its_figures() {
        use crate::solver::{Method, Settings};
        let cube = build("cube", &SceneOptions { resolution: Some(10), ..SceneOptions::default() }).expect("cube");
        // 6 000 tetrahedra of 64 bytes, and under Jacobi as many bytes of corrections (4 slots
        // of 16).
        assert_eq!(largest_buffer(&cube, None), ("tets", 6000 * 64));
        let jacobi = Settings { method: Method::Jacobi, ..Settings::default() };
        assert_eq!(largest_buffer(&cube, Some(&jacobi)).1, 6000 * 64);
        assert!(check_fits(&cube, None, &wgpu::Limits::default()).is_ok());
        let small = wgpu::Limits { max_storage_buffer_binding_size: 100_000, ..wgpu::Limits::default() };
        let err = check_fits(&cube, None, &small).expect_err("refused").to_string();
        assert!(err.contains("MiB (tets") && err.contains("--backend cpu"), "{err}");
        // A cloth: its springs fit where Jacobi's corrections (two slots a spring, four a
        // bending element, 16 bytes each) do not.
        let cloth = build("cloth", &SceneOptions::default()).unwrap();
        let (springs, corrections) = (largest_buffer(&cloth, None), largest_buffer(&cloth, Some(&jacobi)));
        assert_eq!(corrections.0, "Jacobi corrections");
        let between = wgpu::Limits { max_storage_buffer_binding_size: springs.1, ..wgpu::Limits::default() };
        assert!(check_fits(&cloth, Some(&Settings::default()), &between).is_ok());
        assert!(check_fits(&cloth, Some(&jacobi), &between).is_err());
        // With self-collision the candidate lists are the largest.
        let drape = build("cloth-drape", &SceneOptions { resolution: Some(16), ..SceneOptions::default() }).unwrap();
        assert_eq!(largest_buffer(&drape, None).0, "self-collision candidates");
    }
}
