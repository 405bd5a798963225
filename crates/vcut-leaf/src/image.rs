//! Images of two-sided leaves (a `vcut_scene::raster::Target`): the CPU rasteriser of the workspace, each pixel showing the side of
//! its triangle that faces the camera (per-vertex radiance of that side, interpolated
//! perspective-correctly), the environment behind.

use crate::scene::LeafScene;
use crate::shade::TwoSided;
use glam::{Vec3, Vec4};
use vcut_envmap::EnvMap;
use vcut_scene::Camera;
use vcut_scene::raster::Target;

/// Rasterises `scene` with per-vertex two-sided `radiance` seen by `camera`.
pub fn render(
    scene: &LeafScene,
    radiance: &[TwoSided],
    camera: &Camera,
    width: u32,
    height: u32,
    background: Option<&EnvMap>,
) -> Target {
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
) -> Target {
    let (w, h) = (width.max(1) as usize, height.max(1) as usize);
    let vp = camera.view_projection(w as f32 / h as f32);
    let clip: Vec<Vec4> = scene.positions().iter().map(|p| vp * p.extend(1.0)).collect();
    let mut target = Target::new(w, h);
    for t in triangles {
        // The side facing the camera: by the triangle's winding against the vertex normals.
        let [a, b, c] = t.map(|i| scene.positions()[i as usize]);
        let geometric = (b - a).cross(c - a);
        let normals: Vec3 = t.iter().map(|&i| scene.normals()[i as usize]).sum();
        let toward = camera.position - (a + b + c) / 3.0;
        let front = (geometric.dot(toward) > 0.0) == (geometric.dot(normals) > 0.0);
        let side = usize::from(!front);
        target.triangle(t.map(|i| clip[i as usize]), t.map(|i| radiance[i as usize][side]));
    }
    if let Some(env) = background {
        target.background(vp, camera.position, |d| env.radiance(d));
    }
    target
}
