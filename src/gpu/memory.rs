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
