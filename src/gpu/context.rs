//! Adapter and device selection.

use crate::error::{Error, Result};

/// A wgpu instance, adapter, device and queue shared by the solver and the renderer.
#[derive(Debug)]
pub struct GpuContext {
    /// The instance (kept alive with its adapter).
    pub instance: wgpu::Instance,
    /// The adapter in use.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// The device's queue.
    pub queue: wgpu::Queue,
}

impl GpuContext {
    /// Opens the default adapter without a window (honouring `WGPU_BACKEND`, `WGPU_ADAPTER_NAME`
    /// and `WGPU_POWER_PREF`). On a machine without a GPU, Mesa's lavapipe (Debian package
    /// `mesa-vulkan-drivers`) provides a Vulkan device on the CPU.
    pub fn new() -> Result<Self> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(adapter_from_env_or_default(&instance))?;
        Self::with_adapter(instance, adapter)
    }

    /// Opens a device on a chosen adapter.
    pub fn with_adapter(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<Self> {
        pollster::block_on(Self::open_device(instance, adapter))
    }

    /// Opens a device on a chosen adapter without blocking (a browser answers only after the
    /// page's script has returned to it).
    pub async fn open_device(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<Self> {
        // Jacobi in the local energy-aware mode binds 10 storage buffers in one stage; ask for
        // up to 16 where the adapter has them (lavapipe and desktop GPUs do).
        let mut required_limits = wgpu::Limits::default().using_resolution(adapter.limits());
        required_limits.max_storage_buffers_per_shader_stage = adapter
            .limits()
            .max_storage_buffers_per_shader_stage
            .clamp(required_limits.max_storage_buffers_per_shader_stage, 16);
        // Scene-sized buffers as large as the adapter allows (wgpu's defaults stop at 256 MiB a
        // buffer and 128 MiB a storage binding; larger scenes are refused by name,
        // `memory::check_fits`).
        required_limits.max_buffer_size = adapter.limits().max_buffer_size;
        required_limits.max_storage_buffer_binding_size = adapter.limits().max_storage_buffer_binding_size;
        // GPU timings (the viewer's solver time) where the adapter has timestamps.
        let required_features =
            adapter.features() & (wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);
        let desc =
            wgpu::DeviceDescriptor { label: Some("eapbd"), required_limits, required_features, ..Default::default() };
        let (device, queue) = adapter
            .request_device(&desc)
            .await
            .map_err(|e| Error::Gpu(format!("cannot open a device on {}: {e}", adapter.get_info().name)))?;
        Ok(GpuContext { instance, adapter, device, queue })
    }

    /// Adapter name and backend, for reports ("unnamed adapter" where the name is withheld, as
    /// browsers do).
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        let name = if info.name.is_empty() { "unnamed adapter" } else { info.name.as_str() };
        format!("{name} ({:?}, {:?})", info.backend, info.device_type)
    }

    /// Blocks until the queue is idle.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| Error::Gpu(format!("waiting for the device: {e}")))
    }
}

/// The adapter named by `WGPU_ADAPTER_NAME` (a case-insensitive part of its name), else the
/// default one. wgpu's own helper panics when the name matches nothing; this names the adapters
/// there are instead.
async fn adapter_from_env_or_default(instance: &wgpu::Instance) -> Result<wgpu::Adapter> {
    if let Ok(wanted) = std::env::var("WGPU_ADAPTER_NAME") {
        let adapters = instance.enumerate_adapters(wgpu::Backends::all()).await;
        let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
        return adapters
            .into_iter()
            .find(|a| a.get_info().name.to_lowercase().contains(&wanted.to_lowercase()))
            .ok_or_else(|| {
                Error::NoAdapter(format!(
                    "WGPU_ADAPTER_NAME={wanted:?} matches none of the adapters found ({})",
                    if names.is_empty() { "none".to_string() } else { names.join(", ") }
                ))
            });
    }
    let options = wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::from_env().unwrap_or_default(),
        ..Default::default()
    };
    instance.request_adapter(&options).await.map_err(|e| Error::NoAdapter(e.to_string()))
}
