//! Sessions rendered with no window: the same renderer, draw inputs and display transform as
//! the window, into an image read back from the GPU, and written as PNG.

use crate::gpu::{Gpu, GpuError, ViewError};
use crate::leaf::LeafSession;
use crate::render::{SceneRenderer, Viewport, depth_view};
use crate::session::Session;

/// Renders `session`'s frame with no window into a `width × height` RGBA8 image (sRGB-encoded
/// by the shader, exactly as the CPU renderer's PNG).
pub fn screenshot(gpu: &Gpu, session: &mut Session, width: u32, height: u32) -> Result<image::RgbaImage, ViewError> {
    let (width, height) = (width.max(1), height.max(1));
    let screen = if session.mode().screen_space() {
        crate::screen::session_frame(gpu, &vcut_ssdo::gpu::GpuSsdo::new(gpu)?, session, (width, height))?
    } else {
        None
    };
    let session = &*session;
    let mut renderer = SceneRenderer::new(gpu, SCREENSHOT_FORMAT, session.env())?;
    renderer.upload(gpu, session)?;
    let image = screen.as_ref().map(|f| f.output());
    read_back(gpu, (width, height), |encoder, view, depth| {
        renderer.draw(gpu, encoder, (view, depth), session.shown(Viewport::full(width, height)), image.as_ref());
    })
}

/// Renders a leaf session's frame (re-shaded first if needed) with no window into a
/// `width × height` RGBA8 image.
pub fn leaf_screenshot(
    gpu: &Gpu,
    session: &mut LeafSession,
    width: u32,
    height: u32,
) -> Result<image::RgbaImage, ViewError> {
    let (width, height) = (width.max(1), height.max(1));
    session.update(height)?;
    let mut renderer = SceneRenderer::new(gpu, SCREENSHOT_FORMAT, session.env())?;
    renderer.upload_leaves(gpu, &session.mesh())?;
    let session = &*session;
    read_back(gpu, (width, height), |encoder, view, depth| {
        renderer.draw_leaves(gpu, encoder, (view, depth), session.shown(Viewport::full(width, height)));
    })
}

/// Format of headless renders (the shader encodes sRGB).
const SCREENSHOT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Records `draw` into a fresh `width × height` target, submits it and reads the image back.
fn read_back(
    gpu: &Gpu,
    (width, height): (u32, u32),
    draw: impl FnOnce(&mut wgpu::CommandEncoder, &wgpu::TextureView, &wgpu::TextureView),
) -> Result<image::RgbaImage, ViewError> {
    let texture = gpu.checked("render a screenshot", || {
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("screenshot"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SCREENSHOT_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let depth = depth_view(gpu, width, height);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        draw(&mut encoder, &view, &depth);
        gpu.queue.submit([encoder.finish()]);
        texture
    })?;
    let pixels = gpu.read_texture(&texture, (width, height), 4)?;
    image::RgbaImage::from_raw(width, height, pixels)
        .ok_or_else(|| ViewError::Gpu(GpuError::Readback("size mismatch".into())))
}

/// Writes an RGBA image as PNG under a temporary name, then renames it (never half-written).
pub fn write_png(image: &image::RgbaImage, path: &std::path::Path) -> Result<(), ViewError> {
    let fail = |e: &dyn std::fmt::Display| {
        ViewError::Image(vcut_shade::image::ImageError::Write { path: path.into(), reason: e.to_string() })
    };
    let tmp = vcut_envmap::io::temp_name(path);
    if let Err(e) = image.save_with_format(&tmp, image::ImageFormat::Png) {
        let _ = std::fs::remove_file(&tmp);
        return Err(fail(&e));
    }
    std::fs::rename(&tmp, path).map_err(|e| fail(&e))
}
