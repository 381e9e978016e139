//! The lean in-place kernels of the CPU solver (scalar and SIMD, `SIMD_WIDTH` lanes) against the general XPBD
//! update, the fast `f32` `atan2` against the library, and the team of threads against one thread.

use eapbd::constraints::{
    ALL_LANES, Bend, BendParams, Element, LaneData, SIMD_WIDTH, Spring, SpringMaterial, SpringParams,
};
use eapbd::math::Real;
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, Settings, delta_lambda};
use glam::{Vec3, Vec3A};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const INV_H2: f32 = 3600.0 * 900.0;

/// The general update (`Element::compliant` and `delta_lambda`) of element `e` on `x`.
fn general<E: Element<N>, const N: usize>(e: &E, p: &E::Params, x: &mut [Vec3], w: &[f32], lambda: &mut f32) {
    let idx = e.particles().map(|i| i as usize);
    let xs = idx.map(|i| x[i]);
    let proj = e.compliant(p, &xs);
    let sum: f32 = (0..N).map(|n| w[idx[n]] * proj.grad[n].length_squared()).sum();
    if let Some(d) = delta_lambda(proj.c, sum, proj.alpha * INV_H2, *lambda, 0.0, 0.0) {
        *lambda += d;
        for n in 0..N {
            x[idx[n]] = xs[n] + proj.grad[n] * (w[idx[n]] * d);
        }
    }
}

fn jitter(rng: &mut SmallRng, v: Vec3, s: f32) -> Vec3 {
    v + Vec3::new(rng.random_range(-s..s), rng.random_range(-s..s), rng.random_range(-s..s))
}

/// `SIMD_WIDTH` elements on `SIMD_WIDTH × N` distinct particles, positions from `place`, random
/// inverse masses (one in five pinned) and multipliers.
struct Case {
    x: Vec<Vec3>,
    w: Vec<f32>,
    lambda: [f32; SIMD_WIDTH],
}

fn case(rng: &mut SmallRng, n: usize, place: impl Fn(&mut SmallRng, usize) -> Vec3) -> Case {
    Case {
        x: (0..SIMD_WIDTH * n).map(|i| place(rng, i % n)).collect(),
        w: (0..SIMD_WIDTH * n)
            .map(|_| if rng.random_range(0..5) == 0 { 0.0 } else { rng.random_range(1.0..5000.0) })
            .collect(),
        lambda: std::array::from_fn(|_| rng.random_range(-1e-4..1e-4)),
    }
}

/// Runs the general update, the scalar kernel and the SIMD kernel (where the family has one) on
/// the same `SIMD_WIDTH` elements: the scalar kernel agrees with the general update to `rel` of the
/// correction, and the SIMD lanes equal the scalar kernel bit for bit, in a partial batch too.
fn check<E: Element<N>, const N: usize>(what: &str, es: &[E; SIMD_WIDTH], p: &E::Params, c: &Case, rel: f32) {
    let (mut xg, mut xs, mut xv) = (c.x.clone(), c.x.clone(), c.x.clone());
    let (mut lg, mut ls, mut lv) = (c.lambda, c.lambda, c.lambda);
    // The elements slot by slot, as the solver hands them to the SIMD kernels, for positions of
    // 12 bytes (`Vec3`) and of 16 (`Vec3A`).
    let lanes = |stride| {
        let mut d = LaneData::new(es, std::slice::from_ref(&(0..SIMD_WIDTH as u32)), stride);
        d.set_masses(es, &c.w);
        d
    };
    let (packed, padded) = (lanes(size_of::<Vec3>()), lanes(size_of::<Vec3A>()));
    let (packed, padded) = (
        packed.view::<N>(0..SIMD_WIDTH).expect("complete lanes"),
        padded.view::<N>(0..SIMD_WIDTH).expect("complete lanes"),
    );
    let declined = if E::PLAIN_WIDE {
        E::project_plain_wide(packed.window(0), p, &mut xv[..], &mut lv, INV_H2, 1.0, ALL_LANES)
    } else {
        0
    };
    if E::PLAIN_WIDE {
        check_tails(what, es, p, c, (&xv, &lv, declined));
    }
    for (l, e) in es.iter().enumerate() {
        general(e, p, &mut xg, &c.w, &mut lg[l]);
        let done = e.project_plain(p, &mut xs[..], &c.w, &mut ls[l], INV_H2, 1.0);
        if !E::PLAIN_WIDE {
            e.project_plain(p, &mut xv[..], &c.w, &mut lv[l], INV_H2, 1.0);
        }
        assert_eq!(done, declined & (1 << l) == 0, "{what}: SIMD lane {l} and scalar kernel disagree on declining");
        if !done {
            general(e, p, &mut xs, &c.w, &mut ls[l]);
            general(e, p, &mut xv, &c.w, &mut lv[l]);
        }
    }
    assert_eq!(xs, xv, "{what}: SIMD positions differ from the scalar kernel");
    assert_eq!(ls, lv, "{what}: SIMD multipliers differ from the scalar kernel");
    if E::PLAIN_WIDE && declined == 0 {
        // The padded storage the solver runs on (one 16-byte load and store per particle).
        let mut xa: Vec<Vec3A> = c.x.iter().map(|&p| p.into()).collect();
        let mut la = c.lambda;
        let declined_a = E::project_plain_wide(padded.window(0), p, &mut xa[..], &mut la, INV_H2, 1.0, ALL_LANES);
        assert_eq!(declined_a, 0, "{what}: padded lanes declined");
        let xa: Vec<Vec3> = xa.into_iter().map(Vec3::from).collect();
        assert_eq!(xa, xv, "{what}: padded SIMD positions differ");
        assert_eq!(la, lv, "{what}: padded SIMD multipliers differ");
    }
    for i in 0..c.x.len() {
        let moved = (xg[i] - c.x[i]).length().max(1e-9);
        let err = (xs[i] - xg[i]).length();
        assert!(err <= rel * moved + 1e-7, "{what}: particle {i} off by {err:e} of a move of {moved:e}");
    }
    for l in 0..SIMD_WIDTH {
        assert!(
            (ls[l] - lg[l]).abs() <= rel * (lg[l] - c.lambda[l]).abs() + 1e-9,
            "{what}: λ {l}: {} vs {}",
            ls[l],
            lg[l]
        );
    }
}

/// A group's last, partial batch ([`eapbd::constraints::LaneView::tail`]) of `r` elements, the
/// first of the case's two groups `0..r` and `r..SIMD_WIDTH`, for every `r` below `SIMD_WIDTH`: its
/// lanes update as they do in the whole batch (`whole`: the positions, multipliers and declined
/// lanes after it), and the stand-ins in the other lanes write nothing and are not reported.
/// A view that does not end a group has no partial batch.
fn check_tails<E: Element<N>, const N: usize>(
    what: &str,
    es: &[E; SIMD_WIDTH],
    p: &E::Params,
    c: &Case,
    (x_whole, l_whole, declined_whole): (&[Vec3], &[f32; SIMD_WIDTH], u32),
) {
    for r in 1..SIMD_WIDTH {
        let mut lanes = LaneData::new(es, &[0..r as u32, r as u32..SIMD_WIDTH as u32], size_of::<Vec3>());
        lanes.set_masses(es, &c.w);
        let view = lanes.view::<N>(0..r).expect("complete lanes");
        let (window, active) = view.tail(0).expect("the first group's partial batch");
        assert_eq!(active, (1 << r) - 1);
        if r > 1 {
            let short = lanes.view::<N>(0..r - 1).expect("complete lanes");
            assert!(short.tail(0).is_none(), "{what}: a view ending inside a group has no partial batch");
        }
        let (mut x, mut l) = (c.x.clone(), c.lambda);
        let declined = E::project_plain_wide(window, p, &mut x[..], &mut l, INV_H2, 1.0, active);
        assert_eq!(declined, declined_whole & active, "{what}, {r} lanes: declined");
        for (j, e) in es.iter().enumerate() {
            let moved = j < r && declined & (1 << j) == 0;
            for q in e.particles().map(|q| q as usize) {
                let expected = if moved { x_whole[q] } else { c.x[q] };
                assert_eq!(x[q], expected, "{what}, {r} lanes: element {j}'s particle {q}");
            }
            let expected = if moved { l_whole[j] } else { c.lambda[j] };
            assert_eq!(l[j], expected, "{what}, {r} lanes: element {j}'s multiplier");
        }
    }
}

#[test]
fn spring_kernels_match_the_general_update() {
    let mut rng = SmallRng::seed_from_u64(1);
    let p = SpringParams { material: SpringMaterial::Hookean };
    for _ in 0..500 {
        let c = case(&mut rng, 2, |r, _| jitter(r, Vec3::ZERO, 0.05));
        let es = std::array::from_fn(|l| {
            Spring::new(2 * l as u32, 2 * l as u32 + 1, rng.random_range(0.01..0.05), 1e6, SpringMaterial::Hookean)
        });
        check("spring", &es, &p, &c, 1e-4);
    }
}

#[test]
fn bending_kernels_match_the_general_update() {
    let mut rng = SmallRng::seed_from_u64(2);
    let rest = [Vec3::ZERO, Vec3::new(0.02, 0.0, 0.0), Vec3::new(0.01, 0.0, 0.015), Vec3::new(0.01, 0.0, -0.015)];
    for trial in 0..2000 {
        // Folds of every size, wings on either side, and a few degenerate (collapsed) wings.
        let fold = if trial % 4 == 0 { 0.03 } else { 0.004 };
        let mut c = case(&mut rng, 4, |r, n| jitter(r, rest[n], fold));
        if trial % 97 == 0 {
            c.x[2] = c.x[0];
        }
        let es = std::array::from_fn(|l| {
            let b = 4 * l as u32;
            Bend { p: [b, b + 1, b + 2, b + 3], rest_angle: rng.random_range(-3.1..3.1), k: 1e-3 }
        });
        check("bending", &es, &BendParams, &c, 2e-3);
    }
}

#[test]
fn fast_atan2_matches_the_library() {
    let mut rng = SmallRng::seed_from_u64(3);
    let mut worst = 0.0f32;
    for i in 0..200_000 {
        let scale = 10f32.powi(rng.random_range(-6..6));
        let (y, x) = (rng.random_range(-1.0..1.0) * scale, rng.random_range(-1.0..1.0) * scale);
        let (y, x) = if i % 50 == 0 {
            (y, 0.0)
        } else if i % 51 == 0 {
            (0.0, x)
        } else {
            (y, x)
        };
        let (got, want) = (y.fast_atan2(x), y.atan2(x));
        let err = (got - want).abs();
        worst = worst.max(err / want.abs().max(1e-30));
        assert!(err <= 2.0 * f32::EPSILON * want.abs().max(f32::MIN_POSITIVE), "atan2({y}, {x}): {got} vs {want}");
    }
    for (y, x) in [(0.0f32, 0.0f32), (-0.0, 0.0), (0.0, -0.0), (-0.0, -0.0), (1.0, f32::INFINITY), (f32::NAN, 1.0)] {
        let (got, want) = (y.fast_atan2(x), y.atan2(x));
        assert!(got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()), "atan2({y}, {x}): {got} vs {want}");
    }
    println!("largest relative error: {worst:e}");
}

#[test]
fn threads_give_the_same_result_as_one_thread() {
    // 128 × 128 cloth: spring groups of about 8,000 elements, above the parallel threshold.
    let opts = SceneOptions { resolution: Some(128), stiffness: 1e5, ..SceneOptions::default() };
    let scene = scene::build("cloth", &opts).unwrap();
    let run = |threads| positions_after(&scene, Settings { iterations: 10, threads, ..Settings::default() }, 10);
    let one = run(1);
    assert_eq!(one, run(0), "every core");
    assert_eq!(one, run(2), "two threads");
    assert_eq!(one, run(3), "three threads");
}

#[test]
fn padded_and_packed_positions_give_the_same_bits() {
    // The solver runs on `Vec3A` (16-byte particles, for the SIMD gathers and scatters); the
    // generic code over `Vec3` is the plain reference. Every iteration and mode on both.
    use eapbd::constraints::Form;
    use eapbd::solver::{EnergyAware, Method};
    let cloth = SceneOptions { resolution: Some(32), stiffness: 1e5, ..SceneOptions::default() };
    let base = Settings { iterations: 5, substeps: 2, damping: 0.5, ..Settings::default() };
    let cases = [
        ("cloth-sphere", cloth, base),
        ("cloth-sphere", cloth, Settings { threads: 1, ..base }),
        ("bunny-paper", SceneOptions::default(), base),
        ("cloth-sphere", cloth, Settings { form: Form::Energy, ..base }),
        ("cloth-sphere", cloth, Settings { constraint_damping: 1e-3, ..base }),
        ("cloth-sphere", cloth, Settings { method: Method::Jacobi, ..base }),
        ("cloth-sphere", cloth, Settings { energy_aware: EnergyAware::Local, ..base }),
        ("cloth-sphere", cloth, Settings { energy_aware: EnergyAware::Global, ..base }),
        ("cube", SceneOptions::default(), base),
    ];
    for (name, opts, settings) in cases {
        let scene = scene::build(name, &opts).unwrap();
        let (mut a, mut b) = (CpuSolver::<Vec3>::new(scene.clone()), CpuSolver::<Vec3A>::new(scene));
        for _ in 0..20 {
            a.step_frame(&settings);
            b.step_frame(&settings);
        }
        let what = format!("{name}, {settings:?}");
        assert_eq!(a.particles.positions(), b.particles.positions(), "{what}: positions");
        assert_eq!(a.particles.velocities(), b.particles.velocities(), "{what}: velocities");
        assert_eq!(a.ledger.dissipated.to_bits(), b.ledger.dissipated.to_bits(), "{what}: dissipated work");
    }
}

#[test]
fn team_frames_match_one_thread_in_every_method_and_form() {
    // Substeps, contacts against the sphere and damping exercise every pass the team splits; the
    // refined bunny surface has elements that spread over the particle arrays; the energy form
    // and constraint damping take the general update instead of the lean kernels; the global
    // energy balance scales the velocities after every substep; the local mode reads its
    // snapshots and start energies in every projection; Jacobi adds up each particle's
    // corrections in the one-thread order.
    use eapbd::constraints::Form;
    use eapbd::solver::{EnergyAware, Method};
    let cloth = SceneOptions { resolution: Some(64), stiffness: 1e5, ..SceneOptions::default() };
    let base = Settings { iterations: 3, substeps: 4, damping: 0.5, ..Settings::default() };
    let cases = [
        ("cloth-sphere", cloth, base),
        ("bunny-paper", SceneOptions::default(), base),
        ("cloth-sphere", cloth, Settings { form: Form::Energy, ..base }),
        ("cloth-sphere", cloth, Settings { constraint_damping: 1e-3, ..base }),
        ("cloth-sphere", cloth, Settings { energy_aware: EnergyAware::Global, ..base }),
        ("cloth-sphere", cloth, Settings { energy_aware: EnergyAware::Local, ..base }),
        ("bunny-paper", SceneOptions::default(), Settings { energy_aware: EnergyAware::Local, ..base }),
        ("cloth-sphere", cloth, Settings { method: Method::Jacobi, ..base }),
        ("bunny-paper", SceneOptions::default(), Settings { method: Method::Jacobi, ..base }),
        ("cloth-sphere", cloth, Settings { method: Method::Jacobi, energy_aware: EnergyAware::Local, ..base }),
    ];
    for (name, opts, settings) in cases {
        let run = |threads| {
            let mut s = CpuSolver::<Vec3A>::new(scene::build(name, &opts).unwrap());
            let settings = Settings { threads, ..settings };
            for _ in 0..30 {
                s.step_frame(&settings);
            }
            (s.particles.x, s.particles.v, s.ledger.dissipated, s.ledger)
        };
        let one = run(1);
        assert!(one.2 < 0.0, "{name}: damping and contacts dissipate ({})", one.2);
        if settings.energy_aware == EnergyAware::Global {
            assert!(one.3.carried.is_some() && one.3.last_scale != 1.0, "{name}: the balance scaled velocities");
        }
        for threads in [2, 3] {
            let many = run(threads);
            let what = format!(
                "{name}, {:?}, {:?} form, β {}, {:?}, {threads} threads",
                settings.method, settings.form, settings.constraint_damping, settings.energy_aware
            );
            assert_eq!(one.0, many.0, "{what}: positions");
            assert_eq!(one.1, many.1, "{what}: velocities");
            assert_eq!(one.2.to_bits(), many.2.to_bits(), "{what}: dissipated work");
            assert_eq!(one.3, many.3, "{what}: energy ledger");
        }
    }
}

#[test]
fn a_family_with_overlapping_groups_runs_whole_on_the_team() {
    // The bending family gathered into one group (its elements share particles): the team runs
    // it on one thread between barriers, and splits the springs around it.
    let opts = SceneOptions { resolution: Some(64), stiffness: 1e5, ..SceneOptions::default() };
    let mut scene = scene::build("cloth-sphere", &opts).unwrap();
    let bends = scene.bends.as_mut().expect("bending");
    bends.colors = std::iter::once(0..bends.elements.len() as u32).collect();
    assert!(!bends.groups_disjoint(scene.positions.len()));
    let run =
        |threads| positions_after(&scene, Settings { iterations: 3, substeps: 2, threads, ..Settings::default() }, 20);
    let one = run(1);
    assert_eq!(one, run(2), "two threads");
    assert_eq!(one, run(3), "three threads");
}

#[test]
fn the_team_reports_its_time_working_and_waiting() {
    let scene = scene::build("cloth", &SceneOptions { resolution: Some(64), ..SceneOptions::default() }).unwrap();
    let mut sv = CpuSolver::<Vec3A>::new(scene);
    let s = Settings { threads: 2, ..Settings::default() };
    for _ in 0..5 {
        sv.step_frame(&s);
    }
    let t = sv.team_time();
    if std::thread::available_parallelism().map_or(1, |n| n.get()) < 2 {
        assert_eq!(t.frames, 0, "one core: no team");
        return;
    }
    // The first frame runs on the team; a later one may run on one thread (the team's check).
    assert!((1..=5).contains(&t.frames), "{t:?}");
    assert_eq!((t.busy.len(), t.waited.len()), (2, 2));
    assert!(t.busy.iter().all(|b| !b.is_zero()), "{t:?}");
    assert!((0.0..1.0).contains(&t.wait_fraction()), "{t:?}");
    assert!((0.0..=1.0).contains(&t.barrier_fraction()), "{t:?}");
    assert!(t.at_barriers.iter().zip(&t.waited).all(|(a, w)| a <= w), "{t:?}");
    sv.reset_team_time();
    assert_eq!(sv.team_time().frames, 0);
    // Frames on one thread are not counted.
    sv.step_frame(&Settings { threads: 1, ..s });
    assert_eq!((sv.team_time().frames, sv.team_time().wait_fraction()), (0, 0.0));
}

/// The particle positions after `frames` frames of `scene` with `settings`.
fn positions_after(scene: &eapbd::scene::Scene, settings: Settings, frames: usize) -> Vec<Vec3A> {
    let mut s = CpuSolver::<Vec3A>::new(scene.clone());
    for _ in 0..frames {
        s.step_frame(&settings);
    }
    s.particles.x
}

/// The SIMD kernels take the inverse masses from the solver's copy, slot by slot: a particle pinned
/// or freed between frames (the particles are public) must reach them, on one thread and on the
/// team.
#[test]
fn masses_changed_between_frames_reach_the_simd_kernels() {
    let n = 32;
    let scene = scene::build("cloth", &SceneOptions { resolution: Some(n), ..SceneOptions::default() }).expect("cloth");
    for threads in [1, 2] {
        let mut sv = CpuSolver::<Vec3A>::new(scene.clone());
        let s = Settings { threads, ..Settings::default() };
        for _ in 0..5 {
            sv.step_frame(&s);
        }
        let middle = (n / 2 * n + n / 2) as usize;
        let w_free = sv.particles.w[middle];
        assert!(w_free > 0.0);
        sv.particles.w[middle] = 0.0;
        sv.particles.v[middle] = Vec3A::ZERO;
        let at = sv.particles.x[middle];
        for _ in 0..10 {
            sv.step_frame(&s);
        }
        assert_eq!(sv.particles.x[middle], at, "threads {threads}: a particle pinned between frames moved");
        let corner = (0..sv.particles.w.len()).find(|&j| j != middle && sv.particles.w[j] == 0.0).expect("a pin");
        sv.particles.w[corner] = w_free;
        let before = sv.particles.x[corner];
        for _ in 0..10 {
            sv.step_frame(&s);
        }
        let moved = (sv.particles.x[corner] - before).length();
        assert!(moved > 1e-3, "threads {threads}: a particle freed between frames moved only {moved} m");
    }
}

/// The tetrahedra's SIMD kernel (every model, in the closed forms) against the general update
/// (the same closed forms in scalar code, or the SVD path where the element is not regular):
/// `SIMD_WIDTH` tetrahedra at small and large strain, some inverted, some collapsed. A lane
/// declines exactly the elements that are not regular (inverted, collapsed, or with a singular
/// value below σ_min), leaving them unchanged for the general update; the others agree with the
/// general update to 5e-3 of the correction (f32 rounding of `Ψ` near rest, where `C = √(2E/s)`
/// turns it into the step, and `wide`'s `ln`/`exp` against the library's), on packed and padded
/// positions alike, bit for bit between the two, and in a partial batch as in a whole one.
#[test]
fn tet_kernels_match_the_general_update() {
    use eapbd::constraints::{Tet, TetParams};
    use eapbd::material::{Elastic, Model, svd};
    let mut rng = SmallRng::seed_from_u64(4);
    let rest = [Vec3::ZERO, Vec3::new(0.02, 0.0, 0.0), Vec3::new(0.0, 0.02, 0.0), Vec3::new(0.0, 0.0, 0.02)];
    for model in Model::ALL {
        let p = TetParams { elastic: Elastic::new(model, 1e6, 0.3).unwrap(), scale: 1e6 };
        let (mut simd, mut declined_total) = (0, 0);
        for trial in 0..400 {
            let spread = [0.0005, 0.003, 0.008][trial % 3];
            let start: Vec<Vec3> = (0..SIMD_WIDTH * 4).map(|i| jitter(&mut rng, rest[i % 4], 0.002)).collect();
            let es: [Tet; SIMD_WIDTH] = std::array::from_fn(|l| {
                let b = 4 * l as u32;
                Tet::at_rest([b, b + 1, b + 2, b + 3], &start).expect("a regular rest shape")
            });
            // Masses and multipliers from `case`; positions: the rest shapes moved at random.
            let mut c = case(&mut rng, 4, |_, n| rest[n]);
            for (i, x) in c.x.iter_mut().enumerate() {
                *x = start[i] + jitter(&mut rng, Vec3::ZERO, spread);
            }
            if trial % 5 == 0 {
                // Lane 1 inverted (its last particle through the opposite face), lane 2 collapsed.
                c.x[7] = c.x[4] - (c.x[7] - c.x[4]);
                c.x[10] = c.x[8];
            }
            let regular = |e: &Tet, x: &[Vec3]| {
                let xs = e.particles().map(|i| x[i as usize].as_dvec3());
                let f = e.deformation::<glam::DVec3>(&xs);
                model == Model::Linear || svd(&f).sigma[2] >= 0.15 * 1.0001
            };
            let lanes = |stride| {
                let mut d = LaneData::new(&es, std::slice::from_ref(&(0..SIMD_WIDTH as u32)), stride);
                d.set_masses(&es, &c.w);
                d
            };
            let (packed, padded) = (lanes(size_of::<Vec3>()), lanes(size_of::<Vec3A>()));
            let (mut xv, mut lv) = (c.x.clone(), c.lambda);
            let view = packed.view::<4>(0..SIMD_WIDTH).expect("complete lanes");
            let declined = Tet::project_plain_wide(view.window(0), &p, &mut xv[..], &mut lv, INV_H2, 1.0, ALL_LANES);
            check_tails(&format!("{model:?}"), &es, &p, &c, (&xv, &lv, declined));
            let mut xa: Vec<Vec3A> = c.x.iter().map(|&q| q.into()).collect();
            let mut la = c.lambda;
            let view = padded.view::<4>(0..SIMD_WIDTH).expect("complete lanes");
            assert_eq!(
                Tet::project_plain_wide(view.window(0), &p, &mut xa[..], &mut la, INV_H2, 1.0, ALL_LANES),
                declined
            );
            assert_eq!(xa.into_iter().map(Vec3::from).collect::<Vec<_>>(), xv, "{model:?}: padded positions differ");
            assert_eq!(la, lv, "{model:?}: padded multipliers differ");
            let (mut xg, mut lg) = (c.x.clone(), c.lambda);
            for (l, e) in es.iter().enumerate() {
                general(e, &p, &mut xg, &c.w, &mut lg[l]);
                let idx = e.particles().map(|i| i as usize);
                if declined & (1 << l) != 0 {
                    declined_total += 1;
                    assert!(
                        idx.iter().all(|&i| xv[i] == c.x[i]) && lv[l] == c.lambda[l],
                        "{model:?}: a declined lane moved"
                    );
                    continue;
                }
                simd += 1;
                assert!(regular(e, &c.x), "{model:?} lane {l}: an element that is not regular took the SIMD kernel");
                for &i in &idx {
                    let moved = (xg[i] - c.x[i]).length().max(1e-9);
                    let err = (xv[i] - xg[i]).length();
                    assert!(
                        err <= 5e-3 * moved + 1e-7,
                        "{model:?}: particle {i} off by {err:e} of a move of {moved:e}"
                    );
                }
                let dl = (lg[l] - c.lambda[l]).abs();
                assert!((lv[l] - lg[l]).abs() <= 5e-3 * dl + 1e-9, "{model:?}: λ {l}: {} vs {}", lv[l], lg[l]);
            }
            if trial % 5 == 0 && model != Model::Linear {
                assert!(declined & 0b110 == 0b110, "{model:?}: the inverted and collapsed lanes were declined");
            }
        }
        let enough_declined = model == Model::Linear || declined_total > 100;
        assert!(simd > 2000 && enough_declined, "{model:?}: {simd} lanes in SIMD, {declined_total} declined");
    }
}
