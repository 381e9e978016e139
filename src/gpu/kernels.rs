//! Compute pipelines of the solver, built once per device and shared by every scene on it. The
//! pipelines of a constraint family, and Jacobi's gather, are compiled on first use, so a device
//! that only runs springs never builds the bending kernels.

use std::sync::OnceLock;

use super::shaders;

/// Bind group layouts and compute pipelines of the solver.
#[derive(Debug)]
pub struct Kernels {
    device: wgpu::Device,
    /// Group 0: particle state, parameters, spheres.
    pub particles_layout: wgpu::BindGroupLayout,
    /// Group 1 for Gauss-Seidel and λ reset: elements, λ.
    pub family_layout: wgpu::BindGroupLayout,
    /// Group 1 for Jacobi: elements, λ, scales, corrections.
    pub family_jacobi_layout: wgpu::BindGroupLayout,
    /// Group 1 for the Jacobi gather: corrections, incidence.
    pub apply_layout: wgpu::BindGroupLayout,
    /// Group 2: the dispatch range (dynamic offset).
    pub range_layout: wgpu::BindGroupLayout,
    /// Group 3 of the per-particle local-mode kernels: snapshots.
    pub local_particles_layout: wgpu::BindGroupLayout,
    /// Group 3 of the per-family local-mode kernels: snapshots, start energies.
    pub local_family_layout: wgpu::BindGroupLayout,
    /// Group 3 of the energy kernels: partial sums, ledger, the projection's state.
    pub energy_layout: wgpu::BindGroupLayout,
    /// Group 1 of the self-collision kernels: its parameters, points, hash words, lists.
    pub self_layout: wgpu::BindGroupLayout,
    /// `predict`.
    pub predict: wgpu::ComputePipeline,
    /// `contacts` (inside the iteration loop, all but the last iteration), its work added to
    /// each particle's dissipated work.
    pub contacts: wgpu::ComputePipeline,
    /// `finish`: the last iteration's contact pass, the final contact pass and the velocity
    /// update.
    pub finish: wgpu::ComputePipeline,
    particles_module: wgpu::ShaderModule,
    jacobi_apply: OnceLock<wgpu::ComputePipeline>,
    local: OnceLock<LocalKernels>,
    energy: OnceLock<EnergyKernels>,
    self_collision: OnceLock<SelfKernels>,
    families: [OnceLock<FamilyKernels>; crate::scene::FAMILY_COUNT],
}

/// Makes [`FamilyKind`] from [`crate::family_list`].
macro_rules! family_kinds {
    ((); $(($index:literal, $field:ident, $kind:ident, $doc:literal, $name:literal, $label:literal, $arity:literal, $source:ident)),* $(,)?) => {
        /// The constraint families the GPU solver runs, in the CPU's order (`kind as usize` is
        /// the family's index in [`crate::for_each_family`]), as [`crate::family_list`] declares
        /// them.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum FamilyKind {
            $(
                #[doc = $doc]
                $kind,
            )*
        }

        impl FamilyKind {
            /// Every family, in solve order.
            pub const ALL: [FamilyKind; crate::scene::FAMILY_COUNT] = [$(FamilyKind::$kind),*];

            /// The family's name (its WGSL module and buffer labels).
            pub fn name(self) -> &'static str {
                match self {
                    $(FamilyKind::$kind => $name,)*
                }
            }

            /// Particles per element.
            pub fn arity(self) -> u32 {
                match self {
                    $(FamilyKind::$kind => $arity,)*
                }
            }

            /// The family's WGSL module as compiled: its [`shaders::solver_head`], then its source.
            pub fn source(self) -> String {
                match self {
                    $(FamilyKind::$kind => shaders::solver_head(Some($index)) + shaders::$source,)*
                }
            }
        }
    };
}

crate::family_list!([family_kinds]());

/// Per-particle kernels of the local energy-aware mode.
#[derive(Debug)]
pub struct LocalKernels {
    /// Snapshots at the start of a substep.
    pub begin: wgpu::ComputePipeline,
    /// Snapshot shift at the start of an iteration.
    pub snapshot: wgpu::ComputePipeline,
}

/// The energy reduction and the global balance.
#[derive(Debug)]
pub struct EnergyKernels {
    /// Partial sums over particles.
    pub particles: wgpu::ComputePipeline,
    /// Totals, ledger update and `σ`.
    pub total: wgpu::ComputePipeline,
    /// `v ← σ v`.
    pub apply_scale: wgpu::ComputePipeline,
    /// The projection's per-workgroup mass moments.
    pub projection_moments: wgpu::ComputePipeline,
    /// The projection's rigid motions (one workgroup).
    pub projection_rigid: wgpu::ComputePipeline,
    /// The projection's per-workgroup kinetic energy to scale.
    pub projection_deform: wgpu::ComputePipeline,
    /// The projection's budget and scale (one workgroup).
    pub projection_scale: wgpu::ComputePipeline,
    /// The projection's velocity update.
    pub projection_apply: wgpu::ComputePipeline,
}

/// The self-collision's kernels (`shaders/solver/self_collision.wgsl`), in the order a substep
/// runs them.
#[derive(Debug)]
pub struct SelfKernels {
    /// Whether the candidates are stale (one workgroup).
    pub check: wgpu::ComputePipeline,
    /// The hash's counts to zero.
    pub clear: wgpu::ComputePipeline,
    /// Particles per bucket.
    pub count: wgpu::ComputePipeline,
    /// The buckets' starts (one workgroup).
    pub prefix: wgpu::ComputePipeline,
    /// Particles into their buckets.
    pub scatter: wgpu::ComputePipeline,
    /// Each particle's candidates.
    pub find: wgpu::ComputePipeline,
    /// Each particle's move in a pass.
    pub project: wgpu::ComputePipeline,
    /// The moves added to the positions.
    pub apply: wgpu::ComputePipeline,
}

/// The kernels of a constraint family.
#[derive(Debug)]
pub struct FamilyKernels {
    /// One color group, Gauss-Seidel.
    pub gauss_seidel: wgpu::ComputePipeline,
    /// One color group, Gauss-Seidel, local energy-aware mode.
    pub gauss_seidel_local: wgpu::ComputePipeline,
    /// A run of one-element color groups, Gauss-Seidel in their order by one invocation.
    pub gauss_seidel_run: wgpu::ComputePipeline,
    /// [`FamilyKernels::gauss_seidel_run`] in the local energy-aware mode.
    pub gauss_seidel_local_run: wgpu::ComputePipeline,
    /// All elements, Jacobi.
    pub jacobi: wgpu::ComputePipeline,
    /// All elements, Jacobi, local energy-aware mode.
    pub jacobi_local: wgpu::ComputePipeline,
    /// λ = 0.
    pub clear: wgpu::ComputePipeline,
    /// Local mode: energies at the start of the substep.
    pub local_begin: wgpu::ComputePipeline,
    /// Partial sums of the family's energy.
    pub energy: wgpu::ComputePipeline,
}

/// A compute-stage storage buffer entry of a bind group layout.
pub fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn uniform(binding: u32, dynamic: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: dynamic,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A bind group layout of `entries`.
pub fn layout(device: &wgpu::Device, label: &str, entries: &[wgpu::BindGroupLayoutEntry]) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries })
}

/// A compute pipeline for `entry` of `module` with the given groups.
pub fn pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    label: &str,
    entry: &str,
    groups: &[Option<&wgpu::BindGroupLayout>],
) -> wgpu::ComputePipeline {
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: groups,
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// Compiles a WGSL module.
pub fn shader_module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

impl Kernels {
    /// Builds every solver pipeline on `device`.
    pub fn new(device: &wgpu::Device) -> Self {
        let particles_layout = layout(
            device,
            "particles",
            &[
                storage_entry(0, false),
                storage_entry(1, false),
                storage_entry(2, false),
                uniform(3, false),
                storage_entry(4, true),
            ],
        );
        let family_layout = layout(device, "family", &[storage_entry(0, true), storage_entry(1, false)]);
        let family_jacobi_layout = layout(
            device,
            "family-jacobi",
            &[storage_entry(0, true), storage_entry(1, false), storage_entry(2, true), storage_entry(3, false)],
        );
        let apply_layout =
            layout(device, "jacobi-apply", &[storage_entry(0, true), storage_entry(1, true), storage_entry(2, true)]);
        let range_layout = layout(device, "range", &[uniform(0, true)]);
        let local_particles_layout = layout(device, "local-particles", &[storage_entry(0, false)]);
        let local_family_layout = layout(device, "local-family", &[storage_entry(0, true), storage_entry(1, false)]);
        let energy_layout =
            layout(device, "energy", &[storage_entry(2, false), storage_entry(3, false), storage_entry(4, false)]);
        let self_layout = layout(
            device,
            "self-collision",
            &[uniform(0, false), storage_entry(1, false), storage_entry(2, false), storage_entry(3, false)],
        );

        let particles_module = shader_module(device, "particles", &shaders::particles());
        let p = Some(&particles_layout);
        Kernels {
            predict: pipeline(device, &particles_module, "predict", "predict", &[p]),
            contacts: pipeline(device, &particles_module, "contacts", "contacts", &[p]),
            finish: pipeline(device, &particles_module, "finish", "finish", &[p]),
            device: device.clone(),
            particles_module,
            jacobi_apply: OnceLock::new(),
            local: OnceLock::new(),
            energy: OnceLock::new(),
            self_collision: OnceLock::new(),
            families: Default::default(),
            particles_layout,
            family_layout,
            family_jacobi_layout,
            apply_layout,
            range_layout,
            local_particles_layout,
            local_family_layout,
            energy_layout,
            self_layout,
        }
    }

    /// The local mode's per-particle kernels (built on first use).
    pub fn local(&self) -> &LocalKernels {
        self.local.get_or_init(|| {
            let groups = [Some(&self.particles_layout), None, None, Some(&self.local_particles_layout)];
            LocalKernels {
                begin: pipeline(&self.device, &self.particles_module, "local_begin", "local_begin", &groups),
                snapshot: pipeline(&self.device, &self.particles_module, "local_snapshot", "local_snapshot", &groups),
            }
        })
    }

    /// The energy reduction kernels (built on first use).
    pub fn energy(&self) -> &EnergyKernels {
        self.energy.get_or_init(|| {
            let p = Some(&self.particles_layout);
            let e = Some(&self.energy_layout);
            let r = Some(&self.range_layout);
            let m = &self.particles_module;
            let make = |entry: &str, groups: &[Option<&wgpu::BindGroupLayout>]| {
                pipeline(&self.device, m, entry, entry, groups)
            };
            EnergyKernels {
                particles: pipeline(&self.device, m, "energy_particles", "energy_particles", &[p, None, None, e]),
                total: pipeline(
                    &self.device,
                    m,
                    "energy_final",
                    "energy_final",
                    &[p, None, Some(&self.range_layout), e],
                ),
                apply_scale: pipeline(&self.device, m, "apply_scale", "apply_scale", &[p, None, None, e]),
                projection_moments: make("projection_moments", &[p, None, None, e]),
                projection_rigid: make("projection_rigid", &[p, None, r, e]),
                projection_deform: make("projection_deform", &[p, None, None, e]),
                projection_scale: make("projection_scale", &[p, None, r, e]),
                projection_apply: make("projection_apply", &[p, None, None, e]),
            }
        })
    }

    /// The self-collision's kernels (built on first use).
    pub fn self_collision(&self) -> &SelfKernels {
        self.self_collision.get_or_init(|| {
            let m = shader_module(&self.device, "self_collision", &shaders::self_collision());
            let groups = [Some(&self.particles_layout), Some(&self.self_layout)];
            let make = |entry: &str| pipeline(&self.device, &m, entry, entry, &groups);
            SelfKernels {
                check: make("self_check"),
                clear: make("self_clear"),
                count: make("self_count"),
                prefix: make("self_prefix"),
                scatter: make("self_scatter"),
                find: make("self_find"),
                project: make("self_project"),
                apply: make("self_apply"),
            }
        })
    }

    /// `jacobi_apply` (built on first use).
    pub fn jacobi_apply(&self) -> &wgpu::ComputePipeline {
        self.jacobi_apply.get_or_init(|| {
            let groups = [Some(&self.particles_layout), Some(&self.apply_layout)];
            pipeline(&self.device, &self.particles_module, "jacobi_apply", "jacobi_apply", &groups)
        })
    }

    /// The kernels of family `kind` (built on first use).
    pub fn family(&self, kind: FamilyKind) -> &FamilyKernels {
        self.families[kind as usize].get_or_init(|| self.build_family(&kind.source(), kind.name()))
    }

    fn build_family(&self, source: &str, name: &str) -> FamilyKernels {
        let m = shader_module(&self.device, name, source);
        let p = Some(&self.particles_layout);
        let r = Some(&self.range_layout);
        let (f, fj) = (Some(&self.family_layout), Some(&self.family_jacobi_layout));
        let (local, energy) = (Some(&self.local_family_layout), Some(&self.energy_layout));
        let make = |entry: &str, groups: &[Option<&wgpu::BindGroupLayout>]| {
            pipeline(&self.device, &m, &format!("{name}_{entry}"), entry, groups)
        };
        FamilyKernels {
            gauss_seidel: make("gauss_seidel", &[p, f, r]),
            gauss_seidel_local: make("gauss_seidel_local", &[p, f, r, local]),
            gauss_seidel_run: make("gauss_seidel_run", &[p, f, r]),
            gauss_seidel_local_run: make("gauss_seidel_local_run", &[p, f, r, local]),
            jacobi: make("jacobi", &[p, fj, r]),
            jacobi_local: make("jacobi_local", &[p, fj, r, local]),
            clear: make("clear", &[p, f, r]),
            local_begin: make("local_begin", &[p, f, r, local]),
            energy: make("energy", &[p, f, r, energy]),
        }
    }
}

/// Records `pipeline` over `groups` workgroups (the bind groups as set).
pub(crate) fn dispatch(pass: &mut wgpu::ComputePass<'_>, pipeline: &wgpu::ComputePipeline, groups: u32) {
    pass.set_pipeline(pipeline);
    pass.dispatch_workgroups(groups, 1, 1);
}

/// Workgroups (of 64) for `count` items, capped for the grid-stride loops.
pub(crate) fn groups(count: u32) -> u32 {
    count.div_ceil(64).clamp(1, 65535)
}

/// Partial-sum slots of the energy reduction (`PARTIAL_SLOTS` in `shaders/common/types.wgsl`).
/// The particles' slots, each family's and the projection's five moment sums, `REDUCE_GROUPS` each.
pub(crate) const PARTIAL_SLOTS: usize = (1 + crate::scene::FAMILY_COUNT + 5) * 256;

/// Workgroups of an energy reduction over `count` items (at most 256 partial sums each; keep in
/// sync with `REDUCE_GROUPS` in `shaders/common/types.wgsl`).
pub(crate) fn reduce_groups(count: u32) -> u32 {
    count.div_ceil(64).clamp(1, 256)
}
