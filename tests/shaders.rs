//! Every WGSL source parses and validates with naga (no GPU needed), and every file under
//! `shaders/` is part of a validated module.

use eapbd::gpu::{FamilyKind, shaders};
use wgpu::naga;

#[test]
fn every_shader_module_validates() {
    for (name, source) in shaders::all() {
        let module =
            naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
        assert!(!module.entry_points.is_empty(), "{name} has no entry point");
    }
}

#[test]
fn every_wgsl_file_is_in_a_module() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files = Vec::new();
    let mut dirs = vec![root];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "wgsl") {
                files.push(p);
            }
        }
    }
    assert!(files.len() >= 7, "found {} WGSL files", files.len());
    let modules = shaders::all();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        assert!(modules.iter().any(|(_, src)| src.contains(&text)), "{} is not validated", f.display());
    }
}

#[test]
fn gpu_structs_match_their_wgsl_sizes() {
    // Sizes of the host structs, mirrored in shaders/common/types.wgsl and the solver kernels.
    assert_eq!(std::mem::size_of::<eapbd::gpu::SimParams>(), 224);
    assert_eq!(std::mem::size_of::<eapbd::constraints::Tet>(), 64);
    assert_eq!(std::mem::size_of::<eapbd::constraints::Membrane>(), 32);
    assert_eq!(std::mem::size_of::<eapbd::gpu::GpuLedger>(), 48);
    assert_eq!(std::mem::size_of::<eapbd::gpu::GpuProjection>(), 128);
    assert_eq!(std::mem::size_of::<eapbd::gpu::DispatchRange>(), 16);
    assert_eq!(std::mem::size_of::<eapbd::gpu::GpuSphere>(), 32);
    assert_eq!(std::mem::size_of::<eapbd::constraints::Spring>(), 16);
    assert_eq!(std::mem::size_of::<eapbd::constraints::Bend>(), 24);
    let solver = FamilyKind::ALL.iter().map(|k| k.source()).chain([shaders::particles()]);
    for source in solver {
        let module = naga::front::wgsl::parse_str(&source).unwrap();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        for (handle, ty) in module.types.iter() {
            let expected = match ty.name.as_deref() {
                Some("SimParams") => 224,
                Some("Ledger") => 48,
                Some("Projection") => 128,
                Some("DispatchRange") => 16,
                Some("Sphere") => 32,
                Some("Spring") => 16,
                Some("Bend") => 24,
                Some("Tet") => 64,
                Some("Membrane") => 32,
                _ => continue,
            };
            assert_eq!(layouter[handle].size, expected, "WGSL {:?}", ty.name);
        }
    }
}
