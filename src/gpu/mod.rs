//! The wgpu GPU solver: one compute pipeline per stage and constraint family (WGSL under
//! `shaders/`), built once per device ([`Kernels`]), and per-scene buffers ([`GpuSolver`]) that the
//! renderer reads directly.

mod context;
mod kernels;
mod layout;
mod memory;
mod readback;
pub mod shaders;
mod solver;

pub use context::GpuContext;
pub use kernels::{
    FamilyKind, Kernels, layout as bind_group_layout, pipeline as compute_pipeline, shader_module, storage_entry,
};
pub use layout::{DispatchRange, GpuLedger, GpuProjection, GpuSphere, SimParams};
pub use memory::{GpuMemory, check_fits, largest_buffer};
pub use readback::{map_and_copy, pod_vec, read_buffer};
pub use solver::{GpuEnergies, GpuSelfPairs, GpuSolver, GpuState};
