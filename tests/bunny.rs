//! The bunny: OBJ import and its errors (with random and truncated files), refinement to the
//! paper's counts, the volumetric lattice and its embedded surface, and the three bodies.

use eapbd::mesh::{EmbeddedTets, TriMesh, dihedral_pairs, parse_obj, unique_edges};
use eapbd::scene::{self, Body, SceneOptions};
use eapbd::solver::{CpuSolver, Settings};
use glam::{Vec3, Vec3A};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const BUNNY: &[u8] = include_bytes!("../assets/bunny.obj");

#[test]
fn the_bunny_loads_with_its_counts_and_is_closed() {
    let m = parse_obj(BUNNY).unwrap();
    assert_eq!(m.positions.len(), 1839);
    assert_eq!(m.triangles.len(), 3674);
    assert_eq!(unique_edges(&m.triangles).len(), 5511);
    assert_eq!(dihedral_pairs(&m.triangles).len(), 5511);
    m.validate_closed().unwrap();
    assert!(m.enclosed_volume() > 0.0, "outward orientation");
    // Scaled to 0.3 m tall, standing on y = 0.
    let s = scene::bunny_surface().unwrap();
    let (lo, hi) = s.positions.iter().fold((Vec3::MAX, Vec3::MIN), |(a, b), &p| (a.min(p), b.max(p)));
    assert!(lo.y.abs() < 1e-6 && (hi.y - 0.3).abs() < 1e-5, "{lo} {hi}");
}

#[test]
fn refinement_reaches_the_papers_counts() {
    let s = scene::bunny_surface().unwrap();
    let r = s.refine_to_faces(scene::PAPER_FACES);
    assert_eq!((r.positions.len(), unique_edges(&r.triangles).len(), r.triangles.len()), (4098, 12288, 8192));
    r.validate().unwrap();
    r.validate_closed().unwrap();
    let (v0, v1) = (s.enclosed_volume(), r.enclosed_volume());
    assert!((v1 / v0 - 1.0).abs() < 1e-6, "midpoint splits keep the volume: {v0} → {v1}");
}

#[test]
fn bad_obj_files_get_their_specific_errors() {
    let cases: [(&str, &str); 7] = [
        ("", "no faces"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "vertex"),
        ("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n", "not finite"),
        ("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "zero area"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "OBJ"),
        ("v 0 0\nf 1 1 1\n", "OBJ"),
    ];
    for (text, expected) in cases {
        let e = parse_obj(text.as_bytes()).unwrap_err().to_string();
        assert!(e.contains(expected), "{text:?}: '{e}' does not mention '{expected}'");
    }
    // Quads are split into triangles; an open surface is refused where a closed one is needed.
    let quad = parse_obj(b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    assert_eq!(quad.triangles.len(), 2);
    assert!(quad.validate_closed().unwrap_err().to_string().contains("hole"));
    let e = scene::build_with_surface("bunny", &SceneOptions::default(), quad.clone()).unwrap_err().to_string();
    assert!(e.contains("not a closed surface"), "{e}");
    // ... but the springs body takes it.
    let opts = SceneOptions { body: Some(Body::Springs), ..SceneOptions::default() };
    assert!(scene::build_with_surface("bunny", &opts, quad).is_ok());
    // A surface with no height to scale to the bunny's, or a sliver a billion times wider than
    // tall, is refused rather than simulated at absurd sizes.
    for text in [&b"v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n"[..], b"v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n"] {
        let sliver = parse_obj(text).unwrap();
        let e = scene::build_with_surface("bunny", &opts, sliver).unwrap_err().to_string();
        assert!(e.contains("needs a height"), "{e}");
    }
    let missing = eapbd::mesh::load_obj(std::path::Path::new("/nonexistent/bunny.obj")).unwrap_err().to_string();
    assert!(missing.contains("/nonexistent/bunny.obj"), "{missing}");
}

#[test]
fn random_and_truncated_files_never_panic() {
    let mut rng = SmallRng::seed_from_u64(7);
    let mut parsed = 0;
    for n in 0..400 {
        let bytes: Vec<u8> = if n % 2 == 0 {
            // A truncated bunny, sometimes with a byte changed.
            let mut b = BUNNY[..rng.random_range(0..BUNNY.len())].to_vec();
            if n % 4 == 0 && !b.is_empty() {
                let i = rng.random_range(0..b.len());
                b[i] = rng.random();
            }
            b
        } else {
            // Random lines of OBJ-like tokens.
            let tokens =
                ["v", "f", "vn", "vt", "o", "g", "usemtl", "mtllib", "s", "#", "1", "-1", "0.5", "x", "//", "/"];
            (0..rng.random_range(0..40))
                .map(|_| {
                    let line: Vec<&str> =
                        (0..rng.random_range(1..6)).map(|_| tokens[rng.random_range(0..16)]).collect();
                    line.join(" ") + "\n"
                })
                .collect::<String>()
                .into_bytes()
        };
        if let Ok(m) = parse_obj(&bytes) {
            m.validate().unwrap();
            parsed += 1;
        }
    }
    assert!(parsed > 10, "some truncated bunnies still parse ({parsed})");
}

#[test]
fn the_lattice_fills_the_bunny_and_binds_every_surface_vertex() {
    let s = scene::bunny_surface().unwrap();
    let enclosed = s.enclosed_volume();
    let mut errors = Vec::new();
    for cells in [8, scene::DEFAULT_LATTICE, 28] {
        let e = EmbeddedTets::from_surface(&s, cells).unwrap();
        let mut volume = 0.0f64;
        for t in &e.mesh.tets {
            let [a, b, c, d] = t.map(|i| e.mesh.positions[i as usize].as_dvec3());
            let v = (b - a).cross(c - a).dot(d - a) / 6.0;
            assert!(v > 0.0, "tetrahedron {t:?} has volume {v}");
            volume += v;
        }
        let error = (volume / enclosed - 1.0).abs();
        let cell = 0.3 / cells as f32;
        println!(
            "{cells} cells: {} tets, volume {volume:.4e} of {enclosed:.4e} m³ ({:.1}%), max outside {:.2} cells",
            e.mesh.tets.len(),
            100.0 * error,
            e.max_outside / cell
        );
        errors.push(error);
        assert_eq!(e.bindings.len(), s.positions.len());
        for b in &e.bindings {
            let sum: f32 = b.w.iter().sum();
            assert!((sum - 1.0).abs() < 1e-5, "weights sum to {sum}");
        }
        // Embedded at rest, the surface is where it was (to f32 rounding).
        let back = eapbd::mesh::embedded_positions(&e.bindings, &e.mesh.positions);
        let worst = back.iter().zip(&s.positions).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
        assert!(worst < 1e-5, "embedding misplaces a vertex by {worst} m");
        assert!(e.max_outside <= 1.5 * cell, "a vertex lies {} m outside its tetrahedron", e.max_outside);
    }
    assert!(errors[1] < 0.10, "default lattice volume error {:.1}%", 100.0 * errors[1]);
    assert!(errors[2] < errors[0], "finer lattices fit better: {errors:?}");
}

#[test]
fn every_body_builds_and_the_volume_bunny_lands() {
    for (body, tets) in [(Body::Springs, false), (Body::CentroidTets, true), (Body::Volume, true)] {
        let opts = SceneOptions { body: Some(body), ..SceneOptions::default() };
        let sc = scene::build("bunny", &opts).unwrap();
        assert_eq!(sc.tets.is_some(), tets, "{body:?}");
        assert_eq!(sc.embedding.is_some(), body == Body::Volume, "{body:?}");
    }
    let sc = scene::build("bunny", &SceneOptions { lattice: Some(8), ..SceneOptions::default() }).unwrap();
    let e = sc.embedding.clone().unwrap();
    let mut sv = CpuSolver::<Vec3A>::new(sc);
    for _ in 0..60 {
        sv.step_frame(&Settings { substeps: 2, iterations: 10, ..Settings::default() });
    }
    let surface = e.positions(&sv.particles.positions());
    assert!(surface.iter().all(|p| p.is_finite()));
    let low = surface.iter().map(|p| p.y).fold(f32::MAX, f32::min);
    assert!(low < 0.02 && low > -0.02, "the bunny should rest on the ground, lowest point {low}");
    // The paper's bunny: 15 iterations by default and the refined surface.
    assert_eq!(scene::default_iterations("bunny-paper"), 15);
    let p = scene::build("bunny-paper", &SceneOptions::default()).unwrap();
    assert_eq!((p.num_particles(), p.springs.as_ref().unwrap().len(), p.triangles.len()), (4098, 12288, 8192));
    assert!(p.inv_mass.contains(&0.0), "hangs by its ears");
    let _ = TriMesh::default();
}
