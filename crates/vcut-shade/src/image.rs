//! Images from per-vertex radiance: a headless rasteriser (z-buffer, perspective-correct
//! interpolation of vertex radiance over the triangles, the environment map as background),
//! linear EXR, tone-mapped PNG, and the whole scene as one PLY mesh.
//!
//! **Tone mapping** (PNG only): exposure scale (by default [`auto_exposure`]: the geometry's
//! log-average luminance to 0.18), then the ACES filmic curve in Narkowicz's fit
//! `x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)`, then the sRGB transfer function, 8 bits.
//! Every file is written under a temporary name and renamed.

use crate::frame::Frame;
use glam::{Mat4, Vec3, Vec4};
use std::io::Write;
use std::path::{Path, PathBuf};
use vcut_envmap::EnvMap;
use vcut_scene::Camera;
use vcut_scene::raster::Target;

/// A linear RGB image, row-major from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels.
    pub rgb: Vec<Vec3>,
    /// Whether each pixel shows geometry (false: background).
    pub covered: Vec<bool>,
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImageError {
    /// An OS or encoder error.
    #[error("{}: {reason}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// What failed.
        reason: String,
    },
}

fn write_err(path: &Path, e: impl std::fmt::Display) -> ImageError {
    ImageError::Write { path: path.into(), reason: e.to_string() }
}

/// The camera's view-projection matrix for an image of `aspect` = width / height.
pub fn view_projection(camera: &Camera, aspect: f32) -> Mat4 {
    camera.view_projection(aspect)
}

/// Rasterises every object of `frame` with per-vertex `radiance` (as from `Frame::shade`) seen
/// by `camera`; pixels without geometry show `background` in their view direction (or black).
pub fn rasterize(
    frame: &Frame,
    radiance: &[Vec<Vec3>],
    camera: &Camera,
    width: u32,
    height: u32,
    background: Option<&EnvMap>,
) -> Image {
    let (w, h) = (width.max(1) as usize, height.max(1) as usize);
    let vp = view_projection(camera, w as f32 / h as f32);
    let mut target = Target::new(w, h);
    for (o, rad) in radiance.iter().enumerate().take(frame.object_count()) {
        let crate::FrameObject { mesh, .. } = frame.object(o);
        let clip: Vec<Vec4> = frame.object(o).positions().iter().map(|p| vp * p.extend(1.0)).collect();
        for t in mesh.triangles() {
            target.triangle(t.map(|i| clip[i as usize]), t.map(|i| rad[i as usize]));
        }
    }
    if let Some(env) = background {
        target.background(vp, camera.position, |d| env.radiance(d));
    }
    let Target { rgb, covered, .. } = target;
    Image { width: w as u32, height: h as u32, rgb, covered }
}

/// Rasterises `frame` shaded as `parts` (from [`Frame::shade_parts`]) with the diffuse albedo
/// taken per pixel ([`albedo_image`], so a texture shows at its own resolution, not the mesh's)
/// as `albedo · diffuse + specular`, each part interpolated over the triangles. Where no object
/// is textured it is [`rasterize`] of [`Frame::radiance`] up to rounding (and costs three more
/// passes: use that then).
pub fn rasterize_parts(
    frame: &Frame,
    parts: &[Vec<crate::Parts>],
    camera: &Camera,
    width: u32,
    height: u32,
    background: Option<&EnvMap>,
) -> Image {
    let values = |f: &dyn Fn(&crate::Parts) -> Vec3| -> Vec<Vec<Vec3>> {
        parts.iter().map(|p| p.iter().map(f).collect()).collect()
    };
    // The diffuse part drawn over the background; covered pixels then take albedo and specular.
    let mut image = rasterize(frame, &values(&|p| p.diffuse), camera, width, height, background);
    let specular = rasterize(frame, &values(&|p| p.specular), camera, width, height, None);
    let albedo = albedo_image(frame, camera, width, height);
    for k in 0..image.rgb.len() {
        if image.covered[k] {
            image.rgb[k] = albedo.rgb[k] * image.rgb[k] + specular.rgb[k];
        }
    }
    image
}

/// The frame's picture from its shading (`parts` from [`Frame::shade_parts`] and `radiance`, its
/// [`Frame::radiance`]): [`rasterize_parts`] when an object is textured (its albedo per pixel),
/// else [`rasterize`] of the radiance. What `vcuts render` and the Python `Frame.image` draw.
pub fn frame_image(
    frame: &Frame,
    (parts, radiance): (&[Vec<crate::Parts>], &[Vec<Vec3>]),
    camera: &Camera,
    width: u32,
    height: u32,
    background: Option<&EnvMap>,
) -> Image {
    if frame.has_textures() {
        rasterize_parts(frame, parts, camera, width, height, background)
    } else {
        rasterize(frame, radiance, camera, width, height, background)
    }
}

/// The diffuse albedo each pixel shows: [`Frame::albedo_at`] the texture coordinates
/// interpolated over the visible triangle (an untextured object's `kd` throughout); zero where
/// no object is.
pub fn albedo_image(frame: &Frame, camera: &Camera, width: u32, height: u32) -> Image {
    let draw = |f: &dyn Fn(usize, usize) -> Vec3| {
        let values: Vec<Vec<Vec3>> = (0..frame.object_count())
            .map(|o| (0..frame.object(o).mesh.vertex_count()).map(|v| f(o, v)).collect())
            .collect();
        rasterize(frame, &values, camera, width, height, None)
    };
    let uv = draw(&|o, v| frame.object(o).mesh.uvs().map_or(Vec3::ZERO, |uv| uv[v].extend(0.0)));
    let mut image = draw(&|o, _| Vec3::splat(o as f32));
    for (c, (&covered, uv)) in image.rgb.iter_mut().zip(image.covered.iter().zip(&uv.rgb)) {
        *c = if covered {
            let o = (c.x.round() as usize).min(frame.object_count().saturating_sub(1));
            frame.object(o).albedo_at(frame.object(o).mesh.uvs().map(|_| uv.truncate()))
        } else {
            Vec3::ZERO
        };
    }
    image
}

/// Exposure that maps the log-average luminance of the covered pixels to middle grey 0.18
/// (Reinhard's key value); 1 for an empty or black image.
pub fn auto_exposure(image: &Image) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (c, &cov) in image.rgb.iter().zip(&image.covered) {
        let l = f64::from(0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z);
        if cov && l.is_finite() {
            sum += (1e-6 + l.max(0.0)).ln();
            n += 1;
        }
    }
    if n == 0 {
        return 1.0;
    }
    let avg = (sum / n as f64).exp();
    if avg > 1e-5 { (0.18 / avg) as f32 } else { 1.0 }
}

/// ACES filmic (Narkowicz's fit) of a linear value after `exposure`: the display value in
/// [0, 1], still linear (before the sRGB transfer function).
pub fn aces(x: f32, exposure: f32) -> f32 {
    let x = (x * exposure).max(0.0);
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// ACES filmic (Narkowicz's fit) of a linear value, then sRGB, as 8 bits.
pub fn tone_map(x: f32, exposure: f32) -> u8 {
    let y = aces(x, exposure);
    let s = if y <= 0.003_130_8 { 12.92 * y } else { 1.055 * y.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}

/// Writes the image tone-mapped as PNG (atomically).
pub fn write_png(image: &Image, path: &Path, exposure: f32) -> Result<(), ImageError> {
    let bytes: Vec<u8> = image
        .rgb
        .iter()
        .flat_map(|c| [tone_map(c.x, exposure), tone_map(c.y, exposure), tone_map(c.z, exposure)])
        .collect();
    let buf =
        image::RgbImage::from_raw(image.width, image.height, bytes).ok_or_else(|| write_err(path, "size mismatch"))?;
    let tmp = vcut_envmap::io::temp_name(path);
    buf.save_with_format(&tmp, image::ImageFormat::Png).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        write_err(path, e)
    })?;
    std::fs::rename(&tmp, path).map_err(|e| write_err(path, e))
}

/// Writes the image as linear EXR with its alpha (coverage), atomically: [`crate::passes`]
/// with no pass.
pub fn write_exr(image: &Image, path: &Path) -> Result<(), ImageError> {
    crate::passes::write_exr_passes(image, &[], path)
}

/// Writes the whole scene at its current positions as one binary PLY mesh: per vertex
/// `x y z nx ny nz red green blue` (floats, linear outgoing radiance; give it
/// [`Frame::shade_all`]'s radiance, so every vertex is shaded: toward the camera where it can be
/// seen, else toward its own normal), then faces.
pub fn write_ply(frame: &Frame, radiance: &[Vec<Vec3>], path: &Path) -> Result<(), ImageError> {
    let mut body = Vec::new();
    let mut nv = 0usize;
    let mut faces = Vec::new();
    for (o, rad) in radiance.iter().enumerate().take(frame.object_count()) {
        let crate::FrameObject { mesh, .. } = frame.object(o);
        for ((p, n), c) in frame.object(o).positions().iter().zip(mesh.normals()).zip(rad) {
            for x in [p.x, p.y, p.z, n.x, n.y, n.z, c.x, c.y, c.z] {
                body.extend_from_slice(&x.to_le_bytes());
            }
        }
        faces.extend(mesh.triangles().iter().map(|t| t.map(|i| i + nv as u32)));
        nv += mesh.vertex_count();
    }
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment vcuts: linear outgoing radiance, toward the camera where seen, else along the normal\n\
         element vertex {nv}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\n\
         property float ny\nproperty float nz\nproperty float red\nproperty float green\nproperty float blue\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        faces.len()
    );
    let mut bytes = header.into_bytes();
    bytes.extend_from_slice(&body);
    for t in &faces {
        bytes.push(3);
        for i in t {
            bytes.extend_from_slice(&(*i as i32).to_le_bytes());
        }
    }
    write_file(path, &bytes)
}

/// Writes `bytes` to `path` atomically: to a temporary sibling, then renamed; a failed write
/// leaves nothing behind.
pub(crate) fn write_file(path: &Path, bytes: &[u8]) -> Result<(), ImageError> {
    let tmp = vcut_envmap::io::temp_name(path);
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_data()
    };
    write().map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        write_err(path, e)
    })?;
    std::fs::rename(&tmp, path).map_err(|e| write_err(path, e))
}

/// Relative L2 and largest per-pixel error of `got` against `reference`, over covered pixels.
pub fn pixel_errors(got: &Image, reference: &Image) -> (f64, f64) {
    let pairs = got.rgb.iter().zip(&reference.rgb).zip(&reference.covered);
    crate::reference::relative_errors(pairs.filter(|(_, c)| **c).map(|((a, b), _)| (*a, *b)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tone_mapping_is_monotone_and_bounded() {
        let mut last = 0u8;
        for i in 0..1000 {
            let v = tone_map(i as f32 * 0.01, 1.0);
            assert!(v >= last);
            last = v;
        }
        assert_eq!(tone_map(0.0, 1.0), 0);
        assert_eq!(tone_map(1e6, 1.0), 255);
        assert_eq!(tone_map(f32::NAN, 1.0), 0);
    }
}
