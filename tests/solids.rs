//! Volumetric scenes on the CPU: the cantilever under gravity with every 3D model, a cube that
//! starts with every tetrahedron inverted, and the bunny recovering from the stability study's
//! disturbances.

use eapbd::material::Model;
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, EnergyAware, Settings};
use glam::{Vec3, Vec3A};

fn opts(model: Model) -> SceneOptions {
    SceneOptions { solid: Some(model), ..SceneOptions::default() }
}

#[test]
fn the_beam_sags_and_stays_finite_with_every_model() {
    for model in Model::ALL {
        let mut sv = CpuSolver::<Vec3A>::new(scene::build("beam", &opts(model)).unwrap());
        let start = sv.particles.x.clone();
        let tip = |x: &[Vec3A]| {
            x.iter().filter(|p| p.x > 0.49).map(|p| p.y).sum::<f32>() / x.iter().filter(|p| p.x > 0.49).count() as f32
        };
        for _ in 0..240 {
            sv.step_frame(&Settings { substeps: 4, iterations: 10, damping: 1.0, ..Settings::default() });
        }
        let x = &sv.particles.x;
        assert!(x.iter().all(|p| p.is_finite()), "{model:?}: not finite");
        for (i, p) in x.iter().enumerate() {
            if sv.particles.w[i] == 0.0 {
                assert_eq!(*p, start[i], "{model:?}: the clamped end moved");
            }
        }
        let sag = tip(&start) - tip(x);
        // E = 2 MPa: Euler–Bernoulli predicts about 0.18 m for the 1 m beam; coarse linear tets
        // are stiffer in bending, so only bound it loosely here.
        assert!(sag > 0.02 && sag < 0.5, "{model:?}: tip sag {sag:.3} m");
    }
}

#[test]
fn a_mirrored_cube_regains_positive_volume() {
    for model in [Model::StVK, Model::NeoHookean, Model::MooneyRivlin, Model::ArrudaBoyce] {
        let mut sc = scene::build("cube", &opts(model)).unwrap();
        // Mirror the cube through the plane x = 0: every tetrahedron starts inverted.
        for p in &mut sc.positions {
            p.x = -p.x;
        }
        let tets = sc.tets.clone().unwrap();
        let mut sv = CpuSolver::<Vec3A>::new(sc);
        let det = |sv: &CpuSolver<Vec3A>| -> Vec<f32> {
            tets.elements.iter().map(|t| t.deformation(&t.p.map(|i| sv.particles.x[i as usize])).det()).collect()
        };
        assert!(det(&sv).iter().all(|&d| d < 0.0), "{model:?}: not inverted at the start");
        for _ in 0..300 {
            sv.step_frame(&Settings { substeps: 4, iterations: 10, damping: 2.0, ..Settings::default() });
            assert!(sv.particles.x.iter().all(|p| p.is_finite()), "{model:?}: not finite");
        }
        let d = det(&sv);
        let inverted = d.iter().filter(|&&d| d <= 0.0).count();
        assert_eq!(inverted, 0, "{model:?}: {inverted} of {} tetrahedra still inverted", d.len());
    }
}

/// The stability study's bunny cases that tangle the body (a 1/10 s step onto the ground, every
/// particle at a random 100 m/s, the mirrored start) end with no inverted tetrahedron, at rest.
#[test]
fn the_bunny_recovers_from_every_disturbance_of_the_stability_study() {
    use eapbd::report::stability::{cases, run_case};
    use eapbd::simulation::Backend;
    for name in ["bunny-dt1e-1", "bunny-velocity-100", "bunny-inverted"] {
        let case = cases().into_iter().find(|c| c.name == name).unwrap();
        let o = run_case(&case, Backend::Cpu, None).unwrap();
        assert_eq!(o.inverted_end, 0, "{name}: {} of the tetrahedra still inverted", o.inverted_end);
        assert!(o.passed(), "{name}: {:?}", o.failures());
    }
}

#[test]
fn energy_aware_settings_run_on_tetrahedra() {
    for mode in [EnergyAware::Local, EnergyAware::Global] {
        let mut sv = CpuSolver::<Vec3A>::new(scene::build("cube", &SceneOptions::default()).unwrap());
        for _ in 0..120 {
            sv.step_frame(&Settings { energy_aware: mode, ..Settings::default() });
        }
        assert!(sv.particles.x.iter().all(|p| p.is_finite() && p.y > -0.01), "{mode:?}");
    }
}

#[test]
fn centroid_tetrahedra_pair_each_surface_triangle_with_the_centroid() {
    use eapbd::mesh::TetMesh;
    use eapbd::scene::TetMode;
    let volume = scene::build("cube", &SceneOptions::default()).unwrap();
    let sc = scene::build("cube", &SceneOptions { tets: TetMode::Centroid, ..SceneOptions::default() }).unwrap();
    let tets = sc.tets.as_ref().unwrap();
    // One tetrahedron per surface triangle; the surface vertices plus the centroid.
    assert_eq!(tets.len(), volume.triangles.len());
    assert_eq!(sc.triangles.len(), volume.triangles.len());
    let surface_vertices: std::collections::BTreeSet<u32> = volume.triangles.iter().flatten().copied().collect();
    assert_eq!(sc.num_particles(), surface_vertices.len() + 1);
    let centroid = *sc.positions.last().unwrap();
    assert!(centroid.distance(Vec3::new(0.0, 0.55, 0.0)) < 1e-5, "centroid {centroid}");
    assert!(tets.elements.iter().all(|t| t.p[3] as usize == sc.num_particles() - 1));
    // Same total mass (1000 kg/m³ × 0.027 m³) as the volumetric cube.
    let mass = |s: &eapbd::scene::Scene| s.inv_mass.iter().map(|w| 1.0 / w).sum::<f32>();
    assert!((mass(&sc) - 27.0).abs() < 1e-3 && (mass(&volume) - 27.0).abs() < 1e-3);
    // It falls, lands and keeps its volume.
    let mut sv = CpuSolver::<Vec3A>::new(sc.clone());
    for _ in 0..120 {
        sv.step_frame(&Settings { substeps: 2, iterations: 10, damping: 1.0, ..Settings::default() });
    }
    let x = &sv.particles.x;
    assert!(x.iter().all(|p| p.is_finite() && p.y > -0.01), "fell through or blew up");
    let v: f32 = tets.elements.iter().map(|t| t.volume * t.deformation(&t.p.map(|i| x[i as usize])).det()).sum();
    assert!((v / 0.027 - 1.0).abs() < 0.2, "volume {v} m³ of 0.027");
    assert!(x.iter().map(|p| p.y).fold(f32::MAX, f32::min) < 0.05, "did not land");
    // Surfaces that enclose nothing, or a triangle in the centroid's plane, are refused.
    let open = TetMesh::centroid_fan(&[Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap_err();
    assert!(open.to_string().contains("closed surface"), "{open}");
    assert!(TetMesh::centroid_fan(&[Vec3::ZERO], &[[0, 1, 2]]).is_err());
    // Cloth scenes refuse the option.
    let cloth = scene::build("cloth", &SceneOptions { tets: TetMode::Centroid, ..SceneOptions::default() });
    assert!(cloth.unwrap_err().to_string().contains("--tets"));
}
