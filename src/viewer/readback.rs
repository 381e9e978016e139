//! Statistics of the GPU backend without stalling a frame: the state is copied on the device
//! into staging buffers at the end of a frame, mapped asynchronously, and measured on the CPU
//! when the mapping has completed (a frame or two later). One copy is in flight at a time.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{Vec3, Vec4};

use crate::gpu::{GpuSolver, pod_vec};
use crate::metrics::{FrameStats, StateView};
use crate::scene::FAMILY_COUNT;
use crate::solver::{Settings, StepConstants};

/// What a staging buffer holds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    Positions,
    Velocities,
    Lambda(usize, u32),
    Timestamps,
}

/// A completed snapshot.
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// The statistics of the copied frame.
    pub stats: FrameStats,
    /// Positions of the copied frame (m).
    pub positions: Vec<Vec3>,
    /// Velocities of the copied frame (m/s).
    pub velocities: Vec<Vec3>,
    /// GPU time of the frame's solver commands (ms), where the device has timestamps.
    pub gpu_ms: Option<f64>,
}

/// The frame whose copy is in flight.
#[derive(Clone, Copy, Debug)]
struct InFlight {
    frame: u32,
    settings: Settings,
    stepped: bool,
    mapping: bool,
}

/// Staging buffers of one GPU scene and the copy in flight.
#[derive(Debug)]
pub struct StatsReadback {
    staging: Vec<(Slot, wgpu::Buffer)>,
    in_flight: Option<InFlight>,
    mapped: Arc<AtomicUsize>,
    failed: Arc<AtomicUsize>,
    timestamp_period_ns: f32,
}

fn staging(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("stats staging"),
        size,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    })
}

impl StatsReadback {
    /// Staging buffers for `gpu`'s state, and for two timestamps when `timestamps` is set.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, gpu: &GpuSolver, timestamps: bool) -> Self {
        let mut s = vec![
            (Slot::Positions, staging(device, gpu.x.size())),
            (Slot::Velocities, staging(device, gpu.velocities().size())),
        ];
        for (i, b, len) in gpu.lambda_buffers() {
            s.push((Slot::Lambda(i, len), staging(device, b.size())));
        }
        if timestamps {
            s.push((Slot::Timestamps, staging(device, 16)));
        }
        StatsReadback {
            staging: s,
            in_flight: None,
            mapped: Arc::new(AtomicUsize::new(0)),
            failed: Arc::new(AtomicUsize::new(0)),
            timestamp_period_ns: queue.get_timestamp_period(),
        }
    }

    /// `true` when no copy is in flight.
    pub fn is_idle(&self) -> bool {
        self.in_flight.is_none()
    }

    /// Records the copy of `gpu`'s state (and of `resolved` timestamps) after frame `frame`,
    /// stepped with `settings`. Call only when idle.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        gpu: &GpuSolver,
        resolved: Option<&wgpu::Buffer>,
        frame: u32,
        settings: &Settings,
        stepped: bool,
    ) {
        let lambdas: Vec<(usize, &wgpu::Buffer, u32)> = gpu.lambda_buffers().collect();
        for (slot, dst) in &self.staging {
            let src = match slot {
                Slot::Positions => Some(&gpu.x),
                Slot::Velocities => Some(gpu.velocities()),
                Slot::Lambda(i, _) => lambdas.iter().find(|(k, _, _)| k == i).map(|(_, b, _)| *b),
                Slot::Timestamps => resolved,
            };
            if let Some(src) = src {
                encoder.copy_buffer_to_buffer(src, 0, dst, 0, dst.size().min(src.size()));
            }
        }
        self.in_flight = Some(InFlight { frame, settings: *settings, stepped, mapping: false });
    }

    /// Starts mapping the staging buffers (after the recording encoder was submitted).
    pub fn after_submit(&mut self) {
        let Some(f) = &mut self.in_flight else { return };
        if f.mapping {
            return;
        }
        f.mapping = true;
        self.mapped.store(0, Ordering::SeqCst);
        self.failed.store(0, Ordering::SeqCst);
        for (_, b) in &self.staging {
            let (mapped, failed) = (self.mapped.clone(), self.failed.clone());
            b.slice(..).map_async(wgpu::MapMode::Read, move |r| {
                if r.is_err() {
                    failed.fetch_add(1, Ordering::SeqCst);
                }
                mapped.fetch_add(1, Ordering::SeqCst);
            });
        }
    }

    /// The snapshot, once every mapping has completed (the caller polls the device).
    pub fn take(&mut self, gpu: &GpuSolver) -> Option<Snapshot> {
        let f = self.in_flight?;
        if !f.mapping || self.mapped.load(Ordering::SeqCst) < self.staging.len() {
            return None;
        }
        self.in_flight = None;
        let ok = self.failed.load(Ordering::SeqCst) == 0;
        let mut x: Vec<Vec4> = Vec::new();
        let mut v: Vec<Vec4> = Vec::new();
        let mut lambdas: [Vec<f32>; FAMILY_COUNT] = Default::default();
        let mut ticks: Vec<u64> = Vec::new();
        for (slot, b) in &self.staging {
            if ok && let Ok(view) = b.get_mapped_range(..) {
                match *slot {
                    Slot::Positions => x = pod_vec(&view),
                    Slot::Velocities => v = pod_vec(&view),
                    Slot::Lambda(i, len) => {
                        let mut l: Vec<f32> = pod_vec(&view);
                        l.truncate(len as usize);
                        lambdas[i] = l;
                    }
                    Slot::Timestamps => ticks = pod_vec(&view),
                }
            }
            b.unmap();
        }
        if !ok {
            return None;
        }
        let n = gpu.scene().num_particles();
        x.truncate(n);
        v.truncate(n);
        let positions: Vec<Vec3> = x.iter().map(|p| p.truncate()).collect();
        let velocities: Vec<Vec3> = v.iter().map(|p| p.truncate()).collect();
        let w: Vec<f32> = x.iter().map(|p| p.w).collect();
        let k = StepConstants::<f32>::new(&f.settings);
        let view = StateView {
            x: &positions,
            v: &velocities,
            w: &w,
            lambdas: std::array::from_fn(|i| lambdas[i].as_slice()),
            constants: f.stepped.then_some(&k),
            dissipated: v.iter().map(|p| p.w as f64).sum(),
        };
        let stats = FrameStats::of_state(gpu.scene(), &view, f.frame, 0.0);
        let gpu_ms = match ticks.as_slice() {
            [t0, t1, ..] if t1 >= t0 && *t0 > 0 => Some((t1 - t0) as f64 * self.timestamp_period_ns as f64 * 1e-6),
            _ => None,
        };
        Some(Snapshot { stats, positions, velocities, gpu_ms })
    }
}
