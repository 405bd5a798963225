//! Images of two-sided leaves: the CPU rasteriser of the workspace, each pixel showing the side of
//! its triangle that faces the camera (per-vertex radiance of that side, interpolated
//! perspective-correctly), the environment behind.

use crate::scene::LeafScene;
use crate::shade::TwoSided;
use glam::{Vec3, Vec4};
use vcut_envmap::EnvMap;
use vcut_scene::Camera;
use vcut_scene::raster::{raster_triangle, to_screen};

/// A linear RGB image, row-major from the top, with the pixels that show geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct LeafImage {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Pixels.
    pub rgb: Vec<Vec3>,
    /// Whether each pixel shows geometry.
    pub covered: Vec<bool>,
}

/// Rasterises `scene` with per-vertex two-sided `radiance` seen by `camera`.
pub fn render(
    scene: &LeafScene,
    radiance: &[TwoSided],
    camera: &Camera,
    width: u32,
    height: u32,
    background: Option<&EnvMap>,
) -> LeafImage {
    render_triangles(scene, scene.triangles(), radiance, camera, (width, height), background)
}

/// Rasterises `triangles` (scene vertex indices, e.g. a level-of-detail selection's) with
/// per-vertex `radiance` indexed by scene vertex.
pub fn render_triangles(
    scene: &LeafScene,
    triangles: &[[u32; 3]],
    radiance: &[TwoSided],
    camera: &Camera,
    (width, height): (u32, u32),
    background: Option<&EnvMap>,
) -> LeafImage {
    let (w, h) = (width.max(1) as usize, height.max(1) as usize);
    let vp = camera.view_projection(w as f32 / h as f32);
    let clip: Vec<Vec4> = scene.positions().iter().map(|p| vp * p.extend(1.0)).collect();
    let mut depth = vec![f32::INFINITY; w * h];
    let mut rgb = vec![Vec3::ZERO; w * h];
    let mut covered = vec![false; w * h];
    for t in triangles {
        let c = t.map(|i| clip[i as usize]);
        let Some(s) = to_screen(c, w, h) else { continue };
        // The side facing the camera: by the triangle's winding against the vertex normals.
        let [a, b, cc] = t.map(|i| scene.positions()[i as usize]);
        let geometric = (b - a).cross(cc - a);
        let normals: Vec3 = t.iter().map(|&i| scene.normals()[i as usize]).sum();
        let toward = camera.position - (a + b + cc) / 3.0;
        let front = (geometric.dot(toward) > 0.0) == (geometric.dot(normals) > 0.0);
        let side = usize::from(!front);
        let inv_w = c.map(|v| 1.0 / v.w);
        let attr = t.map(|i| radiance[i as usize][side]);
        raster_triangle(s, w, h, |k, b0, b1, b2| {
            let z = b0 * s[0].z + b1 * s[1].z + b2 * s[2].z;
            if z >= depth[k] {
                return;
            }
            depth[k] = z;
            let q = b0 * inv_w[0] + b1 * inv_w[1] + b2 * inv_w[2];
            rgb[k] = (attr[0] * (b0 * inv_w[0]) + attr[1] * (b1 * inv_w[1]) + attr[2] * (b2 * inv_w[2])) / q;
            covered[k] = true;
        });
    }
    if let Some(env) = background {
        let inv = vp.inverse();
        for py in 0..h {
            for px in 0..w {
                let k = py * w + px;
                if !covered[k] {
                    let ndc = Vec3::new(
                        (px as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                        1.0 - (py as f32 + 0.5) / h as f32 * 2.0,
                        1.0,
                    );
                    rgb[k] = env.radiance((inv.project_point3(ndc) - camera.position).normalize_or_zero());
                }
            }
        }
    }
    LeafImage { width: w as u32, height: h as u32, rgb, covered }
}
