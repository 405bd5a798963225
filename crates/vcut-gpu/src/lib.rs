//! A wgpu device on any adapter — a GPU, lavapipe (Vulkan on the CPU) or llvmpipe (OpenGL on
//! the CPU) — for the workspace's GPU passes (the viewer, the screen-space passes of
//! `vcut-ssdo`). wgpu reports validation errors to a handler that panics by default; here every
//! device reports them to [`Gpu::checked`] scopes or keeps them for [`Gpu::take_errors`], and
//! [`Gpu::require_format`] / [`Gpu::require_downlevel`] check what a pass needs before it is
//! built, so what an adapter lacks becomes a [`GpuError`] naming the adapter, never a panic.
//!
//! [`test_device`] is the rule GPU tests follow: the headless device, or a skip said on stderr
//! without an adapter, unless `VCUT_REQUIRE_GPU=1` makes that a failure.
//!
//! # Example
//! ```no_run
//! use vcut_gpu::Gpu;
//! let gpu = Gpu::headless()?;
//! gpu.require_format(wgpu::TextureFormat::Rgba32Uint, wgpu::TextureUsages::RENDER_ATTACHMENT, "render")?;
//! let texture = gpu.checked("create a texture", || {
//!     gpu.device.create_texture(&wgpu::TextureDescriptor {
//!         label: None,
//!         size: wgpu::Extent3d { width: 4, height: 4, depth_or_array_layers: 1 },
//!         mip_level_count: 1,
//!         sample_count: 1,
//!         dimension: wgpu::TextureDimension::D2,
//!         format: wgpu::TextureFormat::Rgba32Uint,
//!         usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
//!         view_formats: &[],
//!     })
//! })?;
//! let bytes = gpu.read_texture(&texture, (4, 4), 16)?;
//! assert_eq!(bytes.len(), 4 * 4 * 16);
//! # Ok::<(), vcut_gpu::GpuError>(())
//! ```

use std::io::Write;
use std::sync::{Arc, Mutex};

/// Why a GPU operation failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GpuError {
    /// No wgpu adapter at all.
    #[error(
        "no GPU adapter found ({0}). On a machine without a GPU install Mesa's OpenGL \
         (Debian/Ubuntu: `apt-get install libegl-mesa0 libgl1-mesa-dri`) or its CPU Vulkan driver \
         (`apt-get install mesa-vulkan-drivers libvulkan1`), or select a backend with \
         WGPU_BACKEND=vulkan|gl"
    )]
    NoAdapter(String),
    /// The adapter refused a device.
    #[error("the GPU adapter '{adapter}' refused a device: {reason}")]
    Device {
        /// The adapter.
        adapter: String,
        /// Why.
        reason: String,
    },
    /// The adapter lacks a capability a pass needs.
    #[error("the GPU adapter '{adapter}' cannot {what}: {lacks}")]
    Unsupported {
        /// The adapter.
        adapter: String,
        /// What was asked of it (e.g. "run the SSDO passes").
        what: String,
        /// What it lacks.
        lacks: String,
    },
    /// wgpu refused an operation (a validation error, out of memory, or an internal error).
    #[error("the GPU adapter '{adapter}' failed to {what}: {reason}")]
    Gpu {
        /// The adapter.
        adapter: String,
        /// The operation.
        what: String,
        /// wgpu's message, its causes joined by ": ".
        reason: String,
    },
    /// Reading an image back failed.
    #[error("reading the image back from the GPU: {0}")]
    Readback(String),
}

/// A wgpu device and queue, with the errors wgpu reported outside any [`Gpu::checked`] scope.
pub struct Gpu {
    /// The instance.
    pub instance: wgpu::Instance,
    /// The adapter.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    uncaptured: Arc<Mutex<Vec<String>>>,
}

/// wgpu's error as one line: the description's lines (the error and its causes) joined by ": ".
fn one_line(e: &wgpu::Error) -> String {
    let text = match e {
        wgpu::Error::Validation { description, .. } | wgpu::Error::Internal { description, .. } => description.clone(),
        wgpu::Error::OutOfMemory { .. } => "out of GPU memory".to_string(),
    };
    text.lines().map(str::trim).filter(|l| !l.is_empty() && *l != "Caused by:").collect::<Vec<_>>().join(": ")
}

impl Gpu {
    /// A device for rendering without a window: the default adapter, else the fallback
    /// (software) one. Honours `WGPU_BACKEND`.
    pub fn headless() -> Result<Gpu, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        Self::with_instance(instance, None)
    }

    /// A device on `instance` able to present to `surface` (if given).
    pub fn with_instance(instance: wgpu::Instance, surface: Option<&wgpu::Surface<'_>>) -> Result<Gpu, GpuError> {
        let mut errors = Vec::new();
        let mut adapter = None;
        for force_fallback_adapter in [false, true] {
            let options = wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter,
                compatible_surface: surface,
                apply_limit_buckets: false,
            };
            match pollster::block_on(instance.request_adapter(&options)) {
                Ok(a) => {
                    adapter = Some(a);
                    break;
                }
                Err(e) => errors.push(e.to_string()),
            }
        }
        let adapter = adapter.ok_or_else(|| GpuError::NoAdapter(errors.join("; ")))?;
        let desc = wgpu::DeviceDescriptor {
            label: Some("vcut-gpu"),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&desc))
            .map_err(|e| GpuError::Device { adapter: describe(&adapter), reason: e.to_string() })?;
        let uncaptured = Arc::new(Mutex::new(Vec::new()));
        let sink = uncaptured.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            sink.lock().unwrap_or_else(|p| p.into_inner()).push(one_line(&e));
        }));
        Ok(Gpu { instance, adapter, device, queue, uncaptured })
    }

    /// "name (backend, device type)".
    pub fn describe(&self) -> String {
        describe(&self.adapter)
    }

    /// The adapter's backend.
    pub fn backend(&self) -> wgpu::Backend {
        self.adapter.get_info().backend
    }

    /// Fails unless the adapter allows `usages` of `format`, saying it cannot `what`.
    pub fn require_format(
        &self,
        format: wgpu::TextureFormat,
        usages: wgpu::TextureUsages,
        what: &str,
    ) -> Result<(), GpuError> {
        let allowed = self.adapter.get_texture_format_features(format).allowed_usages;
        let missing = usages - allowed;
        if missing.is_empty() {
            return Ok(());
        }
        Err(GpuError::Unsupported {
            adapter: self.describe(),
            what: what.into(),
            lacks: format!("{format:?} textures do not support {missing:?} here"),
        })
    }

    /// Fails unless the adapter has `flags`, saying it cannot `what`.
    pub fn require_downlevel(&self, flags: wgpu::DownlevelFlags, what: &str) -> Result<(), GpuError> {
        let missing = flags - self.adapter.get_downlevel_capabilities().flags;
        if missing.is_empty() {
            return Ok(());
        }
        Err(GpuError::Unsupported { adapter: self.describe(), what: what.into(), lacks: format!("{missing:?}") })
    }

    /// Runs `f` (creating resources, recording, submitting) with wgpu's errors caught: the first
    /// validation, out-of-memory or internal error it raised becomes a [`GpuError::Gpu`]
    /// saying what failed, instead of a panic.
    pub fn checked<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scopes = [wgpu::ErrorFilter::Validation, wgpu::ErrorFilter::OutOfMemory, wgpu::ErrorFilter::Internal]
            .map(|filter| self.device.push_error_scope(filter));
        let out = f();
        let mut first = None;
        // Scopes pop innermost first.
        for scope in scopes.into_iter().rev() {
            if let Some(e) = pollster::block_on(scope.pop()) {
                first.get_or_insert(e);
            }
        }
        match first {
            None => Ok(out),
            Some(e) => Err(GpuError::Gpu { adapter: self.describe(), what: what.into(), reason: one_line(&e) }),
        }
    }

    /// The errors wgpu reported outside any [`Gpu::checked`] scope since the last call, as one
    /// [`GpuError::Gpu`] (their messages joined by "; "), if any.
    pub fn take_errors(&self, what: &str) -> Result<(), GpuError> {
        let errors = std::mem::take(&mut *self.uncaptured.lock().unwrap_or_else(|p| p.into_inner()));
        if errors.is_empty() {
            return Ok(());
        }
        Err(GpuError::Gpu { adapter: self.describe(), what: what.into(), reason: errors.join("; ") })
    }

    /// Waits for the submitted work.
    pub fn wait(&self) -> Result<(), GpuError> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map(|_| ()).map_err(|e| GpuError::Gpu {
            adapter: self.describe(),
            what: "finish the submitted work".into(),
            reason: e.to_string(),
        })
    }

    /// A 2-D texture only sampled or loaded (`TEXTURE_BINDING | COPY_DST`, one mip level) of
    /// `format`, `width × height`, filled with `texels`: rows packed one after another, each
    /// `texels.len() / height` bytes.
    pub fn texture_with(
        &self,
        label: &str,
        format: wgpu::TextureFormat,
        (width, height): (u32, u32),
        texels: &[u8],
    ) -> wgpu::Texture {
        let size = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
        let texture = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let row = (texels.len() / height.max(1) as usize) as u32;
        self.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            texels,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(height) },
            size,
        );
        texture
    }

    /// Whether this device can render a `width × height` target: each side within the
    /// device's largest 2D texture (`max_texture_dimension_2d`); `what` names the sides for
    /// the error (`--width 20000 --height 100`).
    pub fn check_target(&self, (width, height): (u32, u32), what: &str) -> Result<(), GpuError> {
        let max = self.device.limits().max_texture_dimension_2d;
        if width.max(height) > max {
            return Err(GpuError::Unsupported {
                adapter: self.describe(),
                what: format!("render a {width} × {height} image ({what})"),
                lacks: format!("its textures are at most {max} pixels on a side"),
            });
        }
        Ok(())
    }

    /// Copies a `width × height` texture of `texel_bytes` per texel (made with `COPY_SRC`) to
    /// the CPU, after the work submitted before: its rows packed one after another. The rows are
    /// read in bands that each fit the device's largest buffer, so any texture the device can
    /// make can be read back.
    pub fn read_texture(
        &self,
        texture: &wgpu::Texture,
        (width, height): (u32, u32),
        texel_bytes: u32,
    ) -> Result<Vec<u8>, GpuError> {
        self.read_texture_in_bands(texture, (width, height), texel_bytes, self.device.limits().max_buffer_size)
    }

    /// [`Gpu::read_texture`] through buffers of at most `band_bytes` (one row at least).
    pub fn read_texture_in_bands(
        &self,
        texture: &wgpu::Texture,
        (width, height): (u32, u32),
        texel_bytes: u32,
        band_bytes: u64,
    ) -> Result<Vec<u8>, GpuError> {
        let line = (texel_bytes * width) as usize;
        let row = (texel_bytes * width).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let band = (band_bytes / u64::from(row)).clamp(1, u64::from(height.max(1))) as u32;
        let mut out = Vec::with_capacity(line * height as usize);
        for y0 in (0..height).step_by(band as usize) {
            let rows = band.min(height - y0);
            self.read_band(texture, (width, y0, rows), (row, line), &mut out)?;
        }
        Ok(out)
    }

    /// Appends rows `y0 .. y0 + rows` of `texture` (each `line` bytes, `row` with the copy's
    /// alignment) to `out`.
    fn read_band(
        &self,
        texture: &wgpu::Texture,
        (width, y0, rows): (u32, u32, u32),
        (row, line): (u32, usize),
        out: &mut Vec<u8>,
    ) -> Result<(), GpuError> {
        let buffer = self.checked("read an image back", || {
            let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: u64::from(row) * u64::from(rows),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder = self.device.create_command_encoder(&Default::default());
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d { x: 0, y: y0, z: 0 },
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(rows),
                    },
                },
                wgpu::Extent3d { width, height: rows, depth_or_array_layers: 1 },
            );
            self.queue.submit([encoder.finish()]);
            buffer
        })?;
        let (tx, rx) = std::sync::mpsc::channel();
        buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        let fail = |e: &dyn std::fmt::Display| GpuError::Readback(e.to_string());
        rx.recv().map_err(|e| fail(&e))?.map_err(|e| fail(&e))?;
        let data = buffer.get_mapped_range(..).map_err(|e| fail(&e))?;
        for y in 0..rows as usize {
            out.extend_from_slice(&data[y * row as usize..y * row as usize + line]);
        }
        drop(data);
        buffer.unmap();
        Ok(())
    }
}

fn describe(adapter: &wgpu::Adapter) -> String {
    let info = adapter.get_info();
    format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
}

/// The headless device for the GPU test `test`, or `None` — saying on stderr that the test's GPU
/// part was skipped — when there is no adapter. With `VCUT_REQUIRE_GPU=1` (as `.ci/run` sets
/// it) a missing adapter fails the test instead; with `VCUT_REQUIRE_BACKEND=vulkan|gl` the
/// adapter must be on that backend (CI runs the GPU tests on both).
///
/// The notice goes straight to the process's stderr, not through `eprintln!`, which the test
/// harness captures and shows only for failing tests: a skip must be visible in `cargo test`'s
/// output.
pub fn test_device(test: &str) -> Option<Gpu> {
    let require = std::env::var("VCUT_REQUIRE_GPU").is_ok_and(|v| v == "1");
    match Gpu::headless() {
        Ok(g) => {
            if let Ok(want) = std::env::var("VCUT_REQUIRE_BACKEND") {
                let got = format!("{:?}", g.backend()).to_lowercase();
                assert_eq!(got, want.to_lowercase(), "VCUT_REQUIRE_BACKEND={want}: the adapter is {}", g.describe());
            }
            Some(g)
        }
        Err(e) if require => panic!("VCUT_REQUIRE_GPU=1: {e}"),
        Err(e) => {
            let _ = writeln!(std::io::stderr(), "SKIPPED {test} (its GPU part): {e}");
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wgpu_errors_read_as_one_line() {
        let e = wgpu::Error::Validation {
            source: Box::new(std::io::Error::other("x")),
            description: "Validation Error\n\nCaused by:\n  In Device::create_render_pipeline, label = 'gbuffer'\n    Color state [0] is invalid\n      Format Rgba32Float is not renderable\n".into(),
        };
        assert_eq!(
            one_line(&e),
            "Validation Error: In Device::create_render_pipeline, label = 'gbuffer': Color state [0] is invalid: \
             Format Rgba32Float is not renderable"
        );
    }
}
