//! Copying a buffer back to the CPU (only for tests, reports and headless output).

use crate::error::{Error, Result};

/// Copies `size` bytes of `src` (which needs `COPY_SRC`) into a new vector, waiting for the GPU.
pub fn read_buffer<T: bytemuck::Pod>(device: &wgpu::Device, queue: &wgpu::Queue, src: &wgpu::Buffer) -> Result<Vec<T>> {
    let size = src.size();
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("readback") });
    enc.copy_buffer_to_buffer(src, 0, &staging, 0, size);
    queue.submit([enc.finish()]);
    map_and_copy(device, &staging)
}

/// Maps a `MAP_READ` buffer and copies its contents out.
pub fn map_and_copy<T: bytemuck::Pod>(device: &wgpu::Device, staging: &wgpu::Buffer) -> Result<Vec<T>> {
    let (tx, rx) = std::sync::mpsc::channel();
    staging.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| Error::Gpu(format!("readback wait: {e}")))?;
    rx.recv()
        .map_err(|_| Error::Gpu("readback: the map callback never ran".into()))?
        .map_err(|e| Error::Gpu(format!("readback map: {e}")))?;
    let view = staging.get_mapped_range(..).map_err(|e| Error::Gpu(format!("readback range: {e}")))?;
    let out = bytemuck::cast_slice(&view).to_vec();
    drop(view);
    staging.unmap();
    Ok(out)
}
