//! The self-collision's buffers on the GPU and the recording of its stages
//! (`shaders/solver/self_collision.wgsl`), the twins of
//! [`crate::solver::self_collision::SelfPairs`].

use bytemuck::{Pod, Zeroable};
use glam::Vec4;
use wgpu::util::DeviceExt;

use super::{GpuSolver, entry, groups, read_buffer, storage_buffer};
use crate::error::Result;
use crate::gpu::kernels::{Kernels, dispatch};
use crate::scene::SelfCollision;
use crate::solver::self_collision::{CAPACITY, inv_count, margin, neighbour_distance, reach, table_size};

/// The self-collision's candidates read back from the GPU, the twin of
/// [`crate::solver::self_collision::SelfPairs`]'s.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GpuSelfPairs {
    /// The candidate pairs `(i, j)`, `i < j`, in increasing order
    /// ([`crate::solver::self_collision::SelfPairs::pairs`]).
    pub pairs: Vec<(u32, u32)>,
    /// Candidates dropped at the last finding beyond
    /// [`crate::solver::self_collision::CAPACITY`] per particle.
    pub dropped: u64,
    /// Checks that renewed references and searched the candidates anew (the first included).
    pub builds: u64,
}

/// Dispatches of [`crate::solver::stages::Stage::SelfPairs`]: check, clear, count, prefix,
/// scatter, find.
pub(super) const PAIRS_DISPATCHES: usize = 6;
/// Dispatches of [`crate::solver::stages::Stage::SelfCollision`]: project, apply.
pub(super) const PASS_DISPATCHES: usize = 2;

/// `SelfParams` in WGSL.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct SelfParams {
    thickness: f32,
    friction: f32,
    inv_reach: f32,
    reach2: f32,
    margin2: f32,
    neighbour: f32,
    table_size: u32,
    inv_n: f32,
}

/// The self-collision's state on the GPU: its parameters, points (rest positions, the
/// positions the candidates were found at, the pass's moves), the hash's words (bucket starts,
/// fill cursors, then stale, built, dropped, builds) and lists (particles by bucket, candidate
/// counts, candidate lists).
#[derive(Debug)]
pub(super) struct SelfBuffers {
    bind_group: wgpu::BindGroup,
    words: wgpu::Buffer,
    lists: wgpu::Buffer,
    table_size: u32,
    /// Bytes of the buffers.
    pub bytes: u64,
}

impl SelfBuffers {
    /// The buffers for `sc` over `n` particles.
    pub fn new(device: &wgpu::Device, kernels: &Kernels, sc: &SelfCollision, n: usize) -> Self {
        let size = table_size(n);
        let r = reach(sc);
        let m = margin(sc);
        let params = SelfParams {
            thickness: sc.thickness,
            friction: sc.friction,
            inv_reach: 1.0 / r,
            reach2: r * r,
            margin2: m * m,
            neighbour: neighbour_distance(sc),
            table_size: size as u32,
            inv_n: inv_count(n),
        };
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("self-collision params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let mut points: Vec<Vec4> = sc.rest.iter().map(|p| p.extend(0.0)).collect();
        points.resize(3 * n, Vec4::ZERO);
        let none = wgpu::BufferUsages::empty();
        let points = storage_buffer(device, "self-collision points", bytemuck::cast_slice(&points), none);
        let words = storage_buffer(device, "self-collision hash", &vec![0u8; (2 * size + 5) * 4], none);
        let lists = storage_buffer(device, "self-collision lists", &vec![0u8; (2 + CAPACITY) * n * 4], none);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("self-collision"),
            layout: &kernels.self_layout,
            entries: &[entry(0, &params), entry(1, &points), entry(2, &words), entry(3, &lists)],
        });
        let bytes = params.size() + points.size() + words.size() + lists.size();
        SelfBuffers { bind_group, words, lists, table_size: size as u32, bytes }
    }

    /// The word index of the state (stale, built, dropped, builds).
    fn state_at(&self) -> u64 {
        2 * self.table_size as u64 + 1
    }
}

impl GpuSolver {
    /// Records [`crate::solver::stages::Stage::SelfPairs`]: the check, then the hash and the
    /// candidates (each kernel returns at once when the candidates still hold).
    pub(super) fn encode_self_pairs(&self, pass: &mut wgpu::ComputePass<'_>) {
        let Some(sb) = &self.self_collision else { return };
        let k = self.kernels.self_collision();
        pass.set_bind_group(1, &sb.bind_group, &[]);
        let particles = groups(self.n);
        let list: [(&wgpu::ComputePipeline, u32); PAIRS_DISPATCHES] = [
            (&k.check, 1),
            (&k.clear, groups(sb.table_size + 1)),
            (&k.count, particles),
            (&k.prefix, 1),
            (&k.scatter, particles),
            (&k.find, particles),
        ];
        for (pipeline, workgroups) in list {
            dispatch(pass, pipeline, workgroups);
        }
    }

    /// Records [`crate::solver::stages::Stage::SelfCollision`]: each particle's move, then the
    /// moves applied.
    pub(super) fn encode_self_collision(&self, pass: &mut wgpu::ComputePass<'_>) {
        let Some(sb) = &self.self_collision else { return };
        let k = self.kernels.self_collision();
        pass.set_bind_group(1, &sb.bind_group, &[]);
        let list: [&wgpu::ComputePipeline; PASS_DISPATCHES] = [&k.project, &k.apply];
        for pipeline in list {
            dispatch(pass, pipeline, groups(self.n));
        }
    }

    /// Marks the candidates as never found, so the next substep finds them (after the positions
    /// were overwritten).
    pub(super) fn invalidate_self_pairs(&self) {
        if let Some(sb) = &self.self_collision {
            self.queue.write_buffer(&sb.words, (sb.state_at() + 1) * 4, bytemuck::bytes_of(&0u32));
        }
    }

    /// The self-collision's candidates as the GPU holds them (waits for the GPU; `None` without
    /// self-collision): for tests and reports.
    pub fn read_self_pairs(&self) -> Result<Option<GpuSelfPairs>> {
        let Some(sb) = &self.self_collision else { return Ok(None) };
        let n = self.n as usize;
        let words: Vec<u32> = read_buffer(&self.device, &self.queue, &sb.words)?;
        let lists: Vec<u32> = read_buffer(&self.device, &self.queue, &sb.lists)?;
        let state = sb.state_at() as usize;
        let mut pairs = Vec::new();
        for i in 0..n {
            let count = (lists[n + i] as usize).min(CAPACITY);
            let list = &lists[2 * n + i * CAPACITY..][..count];
            pairs.extend(list.iter().filter(|&&j| j as usize > i).map(|&j| (i as u32, j)));
        }
        Ok(Some(GpuSelfPairs { pairs, dropped: words[state + 2] as u64, builds: words[state + 3] as u64 }))
    }
}
