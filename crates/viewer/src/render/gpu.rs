//! Getting a GPU device without a window, and reading rendered pixels back.
//!
//! Backends: Vulkan and OpenGL ES (through EGL, which reaches Mesa's llvmpipe on a machine with
//! no GPU and no display: EGL surfaceless). Of the adapters found, [`preferred_adapter`] picks a
//! real GPU first, and among CPU renderers llvmpipe's GL before lavapipe's Vulkan, which draws
//! the app's 1920×1080 frame about a fifth slower (23 against 29 frames/s, 2 cores,
//! 2026-11-27). `WGPU_BACKEND=gl` / `vulkan` limits the choice to one. Limits are WebGL2's
//! raised to the adapter's resolution limits, so the GL path works.

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
            desc.backends = default_backends();
        }
        let backends = desc.backends;
        let instance = wgpu::Instance::new(desc);
        let adapter = pick(pollster::block_on(instance.enumerate_adapters(backends))).ok_or(
            GpuError::NoAdapter {
                backends: format!("{backends:?}"),
            },
        )?;
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

    /// Whether the adapter is a CPU renderer (llvmpipe, lavapipe, WARP).
    pub fn is_cpu(&self) -> bool {
        self.adapter.get_info().device_type == wgpu::DeviceType::Cpu
    }

    /// "name (backend, device type)" of the adapter.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
    }
}

/// The backends asked for when `WGPU_BACKEND` names none: GL always, Vulkan only where it
/// could reach a GPU: a Vulkan driver other than Mesa's lavapipe is installed and a GPU's
/// device node exists (`/dev/dri/renderD*`, `/dev/nvidia*`, WSL's `/dev/dxg`). Elsewhere
/// Vulkan can only give lavapipe, which the GL adapter ([`preferred_adapter`]) beats anyway,
/// and merely loading Mesa's Vulkan drivers (`mesa-vulkan-drivers` installs lavapipe, Intel's
/// and AMD's together) makes libwayland print "error: XDG_RUNTIME_DIR is invalid or not set"
/// twice on a machine without a session, on every successful render.
pub fn default_backends() -> wgpu::Backends {
    let manifests: Vec<String> = vulkan_driver_manifests()
        .iter()
        .filter_map(|path| std::fs::read_to_string(path).ok())
        .collect();
    if any_vulkan_driver_beyond_lavapipe(&manifests) && gpu_device_node_exists() {
        wgpu::Backends::VULKAN | wgpu::Backends::GL
    } else {
        wgpu::Backends::GL
    }
}

/// Whether a GPU's device node exists: a DRM render node, NVIDIA's device, or WSL's.
fn gpu_device_node_exists() -> bool {
    let named = |dir: &str, prefix: &str| {
        std::fs::read_dir(dir).is_ok_and(|entries| {
            entries
                .filter_map(Result::ok)
                .any(|e| e.file_name().to_string_lossy().starts_with(prefix))
        })
    };
    named("/dev/dri", "renderD") || named("/dev", "nvidia") || named("/dev", "dxg")
}

/// Whether any of these Vulkan driver manifests (the ICD JSON files the Vulkan loader reads)
/// names a driver other than lavapipe (`libvulkan_lvp.so`), the CPU renderer.
///
/// # Example
/// ```
/// use rollphase_viewer::render::gpu::any_vulkan_driver_beyond_lavapipe;
/// let lavapipe = r#"{"ICD": {"library_path": "libvulkan_lvp.so", "api_version": "1.3.230"}}"#;
/// let nvidia = r#"{"ICD": {"library_path": "libGLX_nvidia.so.0", "api_version": "1.3.277"}}"#;
/// assert!(!any_vulkan_driver_beyond_lavapipe(&[lavapipe.to_string()]));
/// assert!(any_vulkan_driver_beyond_lavapipe(&[lavapipe.to_string(), nvidia.to_string()]));
/// assert!(!any_vulkan_driver_beyond_lavapipe(&[]));
/// ```
pub fn any_vulkan_driver_beyond_lavapipe(manifests: &[String]) -> bool {
    manifests.iter().any(|m| !m.contains("libvulkan_lvp"))
}

/// The Vulkan driver manifests the loader would read: those `VK_DRIVER_FILES` or
/// `VK_ICD_FILENAMES` name (a colon-separated list of files or folders), else every `*.json`
/// in the loader's standard folders, plus `VK_ADD_DRIVER_FILES`.
fn vulkan_driver_manifests() -> Vec<std::path::PathBuf> {
    use std::path::{Path, PathBuf};
    let split = |v: std::ffi::OsString| -> Vec<PathBuf> { std::env::split_paths(&v).collect() };
    let mut places: Vec<PathBuf> = match std::env::var_os("VK_DRIVER_FILES")
        .or_else(|| std::env::var_os("VK_ICD_FILENAMES"))
    {
        Some(list) => split(list),
        None => {
            let config = std::env::var_os("XDG_CONFIG_DIRS").unwrap_or_else(|| "/etc/xdg".into());
            let data = std::env::var_os("XDG_DATA_DIRS")
                .unwrap_or_else(|| "/usr/local/share:/usr/share".into());
            let mut roots = split(config);
            roots.push(PathBuf::from("/etc"));
            roots.extend(split(data));
            if let Some(home) = std::env::var_os("HOME") {
                roots.push(Path::new(&home).join(".local/share"));
            }
            roots.into_iter().map(|r| r.join("vulkan/icd.d")).collect()
        }
    };
    if let Some(more) = std::env::var_os("VK_ADD_DRIVER_FILES") {
        places.extend(split(more));
    }
    let mut files = Vec::new();
    for place in places {
        match std::fs::read_dir(&place) {
            Ok(entries) => files.extend(
                entries
                    .filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|x| x == "json")),
            ),
            Err(_) if place.is_file() => files.push(place),
            Err(_) => {}
        }
    }
    files
}

/// The adapter [`preferred_adapter`] ranks first of `adapters`, taken out of the list.
pub fn pick(mut adapters: Vec<wgpu::Adapter>) -> Option<wgpu::Adapter> {
    let found: Vec<(wgpu::Backend, wgpu::DeviceType)> = adapters
        .iter()
        .map(|a| {
            let info = a.get_info();
            (info.backend, info.device_type)
        })
        .collect();
    preferred_adapter(&found).map(|k| adapters.swap_remove(k))
}

/// Which of the adapters found (their backend and device type) to draw with: a real GPU before
/// a CPU renderer (discrete, integrated, virtual, then unknown), Vulkan before GL on a GPU, and
/// GL before Vulkan on a CPU, where llvmpipe's GL draws the app faster than lavapipe (the
/// module doc). Ties keep the order found. `None` when nothing was found.
///
/// # Example
/// ```
/// use rollphase_viewer::render::gpu::preferred_adapter;
/// use wgpu::{Backend, DeviceType};
/// // Mesa's two CPU renderers: llvmpipe's GL, wherever lavapipe is listed.
/// let cpu = [(Backend::Vulkan, DeviceType::Cpu), (Backend::Gl, DeviceType::Cpu)];
/// assert_eq!(preferred_adapter(&cpu), Some(1));
/// // A real GPU on Vulkan beats both, and its own GL.
/// let gpu = [(Backend::Gl, DeviceType::DiscreteGpu), (Backend::Gl, DeviceType::Cpu),
///            (Backend::Vulkan, DeviceType::DiscreteGpu)];
/// assert_eq!(preferred_adapter(&gpu), Some(2));
/// assert_eq!(preferred_adapter(&[]), None);
/// ```
pub fn preferred_adapter(found: &[(wgpu::Backend, wgpu::DeviceType)]) -> Option<usize> {
    use wgpu::{Backend, DeviceType};
    let rank = |&(backend, device): &(Backend, DeviceType)| {
        let device_rank = match device {
            DeviceType::DiscreteGpu => 0,
            DeviceType::IntegratedGpu => 1,
            DeviceType::VirtualGpu => 2,
            DeviceType::Other => 3,
            DeviceType::Cpu => 4,
        };
        let backend_rank = match (device, backend) {
            (DeviceType::Cpu, Backend::Gl) => 0,
            (DeviceType::Cpu, Backend::Vulkan) => 1,
            (_, Backend::Vulkan) => 0,
            (_, Backend::Gl) => 1,
            _ => 2,
        };
        (device_rank, backend_rank)
    };
    (0..found.len()).min_by_key(|&k| rank(&found[k]))
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
