//! The GPU: instance, adapter, device and queue, for a window or offscreen.

use std::fmt;

/// Why the demo could not get a GPU (or the software driver).
#[derive(Debug)]
pub enum GpuError {
    /// No adapter: no Vulkan (or other) driver answered.
    NoAdapter(String),
    /// The adapter refused to open a device.
    Device(String),
    /// The window's surface could not be made.
    Surface(String),
}

/// The command that installs Mesa's software Vulkan driver on Debian/Ubuntu.
pub const INSTALL_SOFTWARE_VULKAN: &str = "apt-get install -y mesa-vulkan-drivers libvulkan1";

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter(why) => write!(
                f,
                "no GPU adapter found ({why}); without a GPU, install Mesa's software Vulkan \
                 driver: {INSTALL_SOFTWARE_VULKAN}"
            ),
            GpuError::Device(why) => write!(f, "the GPU adapter refused a device: {why}"),
            GpuError::Surface(why) => write!(f, "cannot draw into the window: {why}"),
        }
    }
}

impl std::error::Error for GpuError {}

/// An open GPU device.
pub struct Gpu {
    /// The adapter the device runs on.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// Opens the default adapter (honouring `WGPU_BACKEND` and friends),
    /// compatible with `surface` when one is given.
    pub fn new(
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface>,
    ) -> Result<Gpu, GpuError> {
        let options =
            wgpu::RequestAdapterOptions { compatible_surface: surface, ..Default::default() };
        let adapter = pollster::block_on(instance.request_adapter(&options))
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let desc = wgpu::DeviceDescriptor {
            label: Some("bvol-falling"),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&desc))
            .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(Gpu { adapter, device, queue })
    }

    /// The adapter's name and backend, for the log and the stats.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
    }
}

/// A new instance with the default backends, from the environment's settings.
pub fn instance() -> wgpu::Instance {
    wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env())
}
