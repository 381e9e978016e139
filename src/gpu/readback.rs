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

/// The `T`s in `bytes`, whatever their alignment (in a browser a mapped range is a copy aligned
/// to a byte); a partial last element is left out.
pub fn pod_vec<T: bytemuck::Pod>(bytes: &[u8]) -> Vec<T> {
    let mut out = vec![T::zeroed(); bytes.len() / size_of::<T>()];
    let n = out.len() * size_of::<T>();
    bytemuck::cast_slice_mut::<T, u8>(&mut out).copy_from_slice(&bytes[..n]);
    out
}

/// Maps a `MAP_READ` buffer and copies its contents out, waiting for the device. A browser
/// maps a buffer only after the page's script has returned to it, so there this is an error:
/// the web viewer reads back asynchronously instead.
pub fn map_and_copy<T: bytemuck::Pod>(device: &wgpu::Device, staging: &wgpu::Buffer) -> Result<Vec<T>> {
    if cfg!(target_arch = "wasm32") {
        return Err(Error::Unsupported("waiting for a read-back from the GPU in a web page".into()));
    }
    let (tx, rx) = std::sync::mpsc::channel();
    staging.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| Error::Gpu(format!("readback wait: {e}")))?;
    rx.recv()
        .map_err(|_| Error::Gpu("readback: the map callback never ran".into()))?
        .map_err(|e| Error::Gpu(format!("readback map: {e}")))?;
    let view = staging.get_mapped_range(..).map_err(|e| Error::Gpu(format!("readback range: {e}")))?;
    let out = pod_vec(&view);
    drop(view);
    staging.unmap();
    Ok(out)
}
