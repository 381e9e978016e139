//! The plain XPBD solver (`--energy-aware off`, no SOR) must stay bit-for-bit what it was before
//! the energy-aware iteration existed. The checksums below were taken from the solver at that
//! point; a change to them is a change of the plain solver's results and must be deliberate.
//!
//! Retaken once, deliberately: the lean spring and bending kernels and the `f32` `atan2` of the
//! bending angle round differently (same update within rounding, `tests/kernels.rs`).
//!
//! Two sets: a build that targets FMA (`eapbd::math::FUSED`, as `target-cpu=native` gives on
//! this project's machines) fuses the in-place kernels' and the `atan2`'s multiply-adds, which
//! rounds differently from a build without it; the set without FMA is the one taken before the
//! kernels fused.

use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, Method, Settings};
use glam::Vec3A;

/// FNV-1a over the bit patterns of positions and velocities.
fn checksum(s: &CpuSolver<Vec3A>) -> u64 {
    let mut h = 0xcbf29ce484222325u64;
    for v in s.particles.x.iter().chain(&s.particles.v) {
        for c in v.to_array() {
            for b in c.to_bits().to_le_bytes() {
                h ^= b as u64;
                h = h.wrapping_mul(0x100000001b3);
            }
        }
    }
    h
}

/// The scenes as they were when the checksums were taken: without self-collision, which
/// `cloth-sphere` has by default since.
fn plain() -> SceneOptions {
    SceneOptions { self_collision: Some(false), ..SceneOptions::default() }
}

fn run(name: &str, s: Settings) -> u64 {
    let mut sv =
        CpuSolver::<Vec3A>::new(scene::build(name, &SceneOptions { resolution: Some(15), ..plain() }).unwrap());
    for _ in 0..60 {
        sv.step_frame(&s);
    }
    checksum(&sv)
}

#[test]
fn plain_solver_results_are_unchanged() {
    let cases = [
        ("cloth", Settings::default()),
        ("cloth", Settings { method: Method::Jacobi, damping: 0.5, ..Settings::default() }),
        ("cloth-sphere", Settings { substeps: 3, iterations: 5, constraint_damping: 1e-3, ..Settings::default() }),
    ];
    let got: Vec<u64> = cases.iter().map(|(n, s)| run(n, *s)).collect();
    println!("{got:#x?}");
    assert_eq!(got, EXPECTED);
}

#[cfg(not(target_feature = "fma"))]
const EXPECTED: [u64; 3] = [0xc66b44a983547616, 0x8dab3227e4f0c11c, 0xcab9cac3af98f480];
#[cfg(target_feature = "fma")]
const EXPECTED: [u64; 3] = [0x814e4aab4c960a15, 0x4e4506d52c9d9bae, 0x3c0c82ea405da016];

/// The energy ledger's dissipated work (every contact pass, in the loop and the final one, and
/// the damping: `solver::contacts`), bit for bit, with contacts and damping, plain and under the
/// global balance (which feeds it back into the velocities), on one thread and on two.
#[test]
fn dissipated_work_is_unchanged() {
    use eapbd::solver::EnergyAware;
    let base = Settings { substeps: 3, iterations: 5, damping: 0.5, ..Settings::default() };
    let cases = [
        base,
        Settings { energy_aware: EnergyAware::Global, ..base },
        Settings { energy_aware: EnergyAware::Local, substeps: 2, iterations: 2, ..base },
    ];
    let mut got = Vec::new();
    for s in cases {
        for threads in [1, 2] {
            let scene = scene::build("cloth-sphere", &SceneOptions { resolution: Some(40), ..plain() });
            let mut sv = CpuSolver::<Vec3A>::new(scene.unwrap());
            for _ in 0..90 {
                sv.step_frame(&Settings { threads, ..s });
            }
            assert!(sv.ledger.dissipated < -1e-3, "contacts and damping dissipate: {}", sv.ledger.dissipated);
            got.push((sv.ledger.dissipated.to_bits(), checksum(&sv)));
        }
    }
    println!("{got:#x?}");
    assert_eq!(got, DISSIPATED);
}

#[cfg(not(target_feature = "fma"))]
const DISSIPATED: [(u64, u64); 6] = [
    (0xc00ab7f7f2e724d4, 0x11757e7ed7f2fa74),
    (0xc00ab7f7f2e724d4, 0x11757e7ed7f2fa74),
    (0xbff25cab6ef6eb1d, 0xdcf251f25615e910),
    (0xbff25cab6ef6eb1d, 0xdcf251f25615e910),
    (0xc012e6405a1480f7, 0xf35d2a2bad4f04d9),
    (0xc012e6405a1480f7, 0xf35d2a2bad4f04d9),
];

#[cfg(target_feature = "fma")]
const DISSIPATED: [(u64, u64); 6] = [
    (0xc00aaf1318727f0b, 0x3e2ea814e3836f48),
    (0xc00aaf1318727f0b, 0x3e2ea814e3836f48),
    (0xbff1440aeb66b2c8, 0x2bc84f51cc3a4a20),
    (0xbff1440aeb66b2c8, 0x2bc84f51cc3a4a20),
    (0xc012f0f6a43d26af, 0x8ad9f2a5e490f141),
    (0xc012f0f6a43d26af, 0x8ad9f2a5e490f141),
];
