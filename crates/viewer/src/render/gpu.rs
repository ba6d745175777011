//! Getting a GPU device without a window, and reading rendered pixels back.
//!
//! Backends: Vulkan where a driver exists (a real GPU, or lavapipe), else OpenGL ES through EGL,
//! which reaches Mesa's llvmpipe on a machine with no GPU and no display (EGL surfaceless).
//! `WGPU_BACKEND=gl` / `vulkan` forces one. Limits are WebGL2's raised to the adapter's
//! resolution limits, so the GL path works.

use thiserror::Error;

/// Why no device could be had.
#[derive(Debug, Error)]
pub enum GpuError {
    /// No adapter on any backend.
    #[error(
        "no GPU adapter found (tried {backends}): install Mesa's drivers for software rendering \
         (Debian/Ubuntu: apt-get install libegl1 libgl1-mesa-dri; for Vulkan also \
         mesa-vulkan-drivers libvulkan1), or run on a machine with a GPU driver"
    )]
    NoAdapter {
        /// The backends tried.
        backends: String,
    },
    /// The adapter refused the device.
    #[error("the GPU adapter {adapter} refused a device: {source}")]
    Device {
        /// Adapter name.
        adapter: String,
        /// Why.
        source: wgpu::RequestDeviceError,
    },
    /// Reading pixels back failed.
    #[error("reading the rendered frame back from the GPU failed: {0}")]
    Readback(String),
}

/// A device and queue with the adapter they came from.
pub struct GpuContext {
    /// The instance.
    pub instance: wgpu::Instance,
    /// The adapter.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl GpuContext {
    /// A device for offscreen rendering; never opens a window or needs a display.
    pub fn headless() -> Result<Self, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if std::env::var_os("WGPU_BACKEND").is_none() {
            desc.backends = wgpu::Backends::VULKAN | wgpu::Backends::GL;
        }
        let backends = format!("{:?}", desc.backends);
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|_| GpuError::NoAdapter { backends })?;
        Self::from_adapter(instance, adapter)
    }

    /// Requests the device on a chosen adapter.
    pub fn from_adapter(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
    ) -> Result<Self, GpuError> {
        let limits = wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits());
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("rollphase"),
            required_features: wgpu::Features::empty(),
            required_limits: limits,
            experimental_features: Default::default(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: Default::default(),
        }))
        .map_err(|source| GpuError::Device {
            adapter: adapter.get_info().name,
            source,
        })?;
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
        })
    }

    /// "name (backend, device type)" of the adapter.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
    }
}

/// An offscreen colour target that can be read back into RGBA8 rows.
pub struct OffscreenTarget {
    /// The texture rendered into.
    pub texture: wgpu::Texture,
    /// Its view.
    pub view: wgpu::TextureView,
    /// Width, height.
    pub size: (u32, u32),
    readback: wgpu::Buffer,
    padded_row: u32,
    bgra: bool,
}

/// Format of offscreen targets (sRGB, so PNGs get the usual gamma).
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// Format of the app's offscreen targets (`bench app`, the windowless tests): non-sRGB, as the
/// window's surface is where one is offered. egui then blends in gamma space, as it is designed
/// to, and its shader skips two sRGB conversions per pixel, which on a CPU renderer is a sixth
/// of a 1920×1080 frame; the 3D renderer's shaders encode their colours themselves
/// (`shaders/output_colour.wgsl`). The bytes read back are sRGB either way.
pub const APP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

impl OffscreenTarget {
    /// A `width`×`height` target in [`OFFSCREEN_FORMAT`].
    pub fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        Self::with_format(device, size, OFFSCREEN_FORMAT)
    }

    /// A `width`×`height` target in `format`, one of the 8-bit RGBA or BGRA formats (the app
    /// reads back frames in its window's format); [`Self::read`] returns RGBA either way.
    pub fn with_format(
        device: &wgpu::Device,
        size: (u32, u32),
        format: wgpu::TextureFormat,
    ) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        // Texture-to-buffer copies need rows padded to 256 bytes.
        let padded_row = (size.0 * 4).div_ceil(256) * 256;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: padded_row as u64 * size.1 as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Self {
            texture,
            view,
            size,
            readback,
            padded_row,
            bgra: matches!(
                format,
                wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
            ),
        }
    }

    /// Waits for the GPU to finish the submitted work (timing "rendering alone").
    pub fn wait(&self, device: &wgpu::Device) -> Result<(), GpuError> {
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback(e.to_string()))
    }

    /// Copies the target to memory: tightly packed RGBA8 rows, top row first.
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<u8>, GpuError> {
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            self.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(self.size.1),
                },
            },
            wgpu::Extent3d {
                width: self.size.0,
                height: self.size.1,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([encoder.finish()]);
        let slice = self.readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait(device)?;
        rx.recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let row = (self.size.0 * 4) as usize;
        let mut out = Vec::with_capacity(row * self.size.1 as usize);
        {
            let data = slice
                .get_mapped_range()
                .map_err(|e| GpuError::Readback(e.to_string()))?;
            for y in 0..self.size.1 as usize {
                let start = y * self.padded_row as usize;
                out.extend_from_slice(&data[start..start + row]);
            }
        }
        self.readback.unmap();
        if self.bgra {
            for px in out.chunks_exact_mut(4) {
                px.swap(0, 2);
            }
        }
        Ok(out)
    }
}
