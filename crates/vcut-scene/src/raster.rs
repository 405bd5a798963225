//! The triangle rasteriser every CPU image of the workspace uses (the cut renderer's
//! images, the screen-space G-buffer, the sun's shadow map): pixel centres, inclusive edges.

use glam::{Vec3, Vec4};

/// Screen positions (x, y in pixels from the top left, z the NDC depth) of a triangle's clip-space
/// corners in a `w × h` image; `None` when a corner reaches behind the near plane (w ≤ 0.01:
/// scenes are viewed from outside).
pub fn to_screen(clip: [Vec4; 3], w: usize, h: usize) -> Option<[Vec3; 3]> {
    if clip.iter().any(|v| v.w <= 0.01) {
        return None;
    }
    Some(clip.map(|v| {
        let n = v.truncate() / v.w;
        Vec3::new((n.x * 0.5 + 0.5) * w as f32, (0.5 - n.y * 0.5) * h as f32, n.z)
    }))
}

/// Calls `f(pixel index, b0, b1, b2)` for every pixel centre inside the screen-space triangle
/// `s` (x, y in pixels) of a `w × h` image, with its barycentric coordinates.
pub fn raster_triangle(s: [Vec3; 3], w: usize, h: usize, mut f: impl FnMut(usize, f32, f32, f32)) {
    let area = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
    if area.is_nan() || area.abs() < 1e-12 {
        return;
    }
    let min = |i: usize| s.iter().map(|v| v[i]).fold(f32::INFINITY, f32::min);
    let max = |i: usize| s.iter().map(|v| v[i]).fold(f32::NEG_INFINITY, f32::max);
    let (x0, x1, y0, y1) = (min(0), max(0), min(1), max(1));
    if x1 < 0.0 || y1 < 0.0 || x0 > w as f32 || y0 > h as f32 {
        return;
    }
    let px0 = x0.floor().max(0.0) as usize;
    let px1 = (x1.ceil().max(0.0) as usize).min(w.saturating_sub(1));
    let py0 = y0.floor().max(0.0) as usize;
    let py1 = (y1.ceil().max(0.0) as usize).min(h.saturating_sub(1));
    for py in py0..=py1 {
        for px in px0..=px1 {
            let (x, y) = (px as f32 + 0.5, py as f32 + 0.5);
            let e = |a: Vec3, b: Vec3| (b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y);
            let b0 = e(s[1], s[2]) / area;
            let b1 = e(s[2], s[0]) / area;
            let b2 = e(s[0], s[1]) / area;
            if b0 >= 0.0 && b1 >= 0.0 && b2 >= 0.0 {
                f(py * w + px, b0, b1, b2);
            }
        }
    }
}

/// An image being rasterised: linear RGB, a z-buffer, and which pixels show geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Pixels, row-major from the top.
    pub rgb: Vec<Vec3>,
    /// NDC depth of the nearest surface so far.
    pub depth: Vec<f32>,
    /// Whether each pixel shows geometry.
    pub covered: Vec<bool>,
}

impl Target {
    /// An empty `width × height` target (black, nothing covered).
    pub fn new(width: usize, height: usize) -> Target {
        let n = width * height;
        Target { width, height, rgb: vec![Vec3::ZERO; n], depth: vec![f32::INFINITY; n], covered: vec![false; n] }
    }

    /// Draws the triangle of clip-space corners `clip` where it is nearest, its colour the
    /// perspective-correct interpolation of the corners' `attr` (attribute/w and 1/w
    /// interpolated). Triangles reaching behind the near plane are skipped.
    pub fn triangle(&mut self, clip: [Vec4; 3], attr: [Vec3; 3]) {
        let (w, h) = (self.width, self.height);
        let Some(s) = to_screen(clip, w, h) else { return };
        let inv_w = clip.map(|v| 1.0 / v.w);
        raster_triangle(s, w, h, |k, b0, b1, b2| {
            let z = b0 * s[0].z + b1 * s[1].z + b2 * s[2].z;
            if z >= self.depth[k] {
                return;
            }
            self.depth[k] = z;
            let q = b0 * inv_w[0] + b1 * inv_w[1] + b2 * inv_w[2];
            self.rgb[k] = (attr[0] * (b0 * inv_w[0]) + attr[1] * (b1 * inv_w[1]) + attr[2] * (b2 * inv_w[2])) / q;
            self.covered[k] = true;
        });
    }

    /// Gives every pixel not covered `radiance(unit direction)` of the ray through its centre,
    /// for a camera at `eye` with view-projection `view_proj`.
    pub fn background(&mut self, view_proj: glam::Mat4, eye: Vec3, radiance: impl Fn(Vec3) -> Vec3) {
        let inv = view_proj.inverse();
        let (w, h) = (self.width, self.height);
        for py in 0..h {
            for px in 0..w {
                let k = py * w + px;
                if self.covered[k] {
                    continue;
                }
                let ndc =
                    Vec3::new((px as f32 + 0.5) / w as f32 * 2.0 - 1.0, 1.0 - (py as f32 + 0.5) / h as f32 * 2.0, 1.0);
                self.rgb[k] = radiance((inv.project_point3(ndc) - eye).normalize_or_zero());
            }
        }
    }
}
