//! The geometry SSDO reads, and its G-buffer: per pixel the two nearest surfaces (depth
//! peeling in one pass: a 2-deep k-buffer), each with position, normal, albedo and view depth.

use glam::{Mat4, Vec3, Vec4};
use vcut_scene::raster::{raster_triangle, to_screen};
use vcut_scene::{Camera, Mesh};

/// One object as SSDO sees it: world-space triangles with vertex normals and a diffuse albedo.
#[derive(Debug, Clone)]
pub struct Object {
    /// World positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals.
    pub normals: Vec<Vec3>,
    /// Triangles (vertex indices).
    pub triangles: Vec<[u32; 3]>,
    /// Diffuse albedo ρ (linear RGB).
    pub albedo: Vec3,
}

impl Object {
    /// `mesh` moved by `translation`, with albedo `albedo`.
    pub fn from_mesh(mesh: &Mesh, translation: Vec3, albedo: Vec3) -> Object {
        Object {
            positions: mesh.positions().iter().map(|&p| p + translation).collect(),
            normals: mesh.normals().to_vec(),
            triangles: mesh.triangles().to_vec(),
            albedo,
        }
    }
}

/// One surface seen through a pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// World position.
    pub position: Vec3,
    /// Unit normal, facing the camera (flipped when the triangle is seen from behind).
    pub normal: Vec3,
    /// Diffuse albedo.
    pub albedo: Vec3,
    /// View depth (clip w: distance along the camera's forward axis).
    pub depth: f32,
    /// Which object.
    pub object: u32,
}

/// Per pixel, the nearest surface and the next one behind it.
#[derive(Debug, Clone)]
pub struct GBuffer {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// The camera's view-projection matrix.
    pub view_proj: Mat4,
    /// The eye.
    pub eye: Vec3,
    /// Nearest surface per pixel (row-major from the top).
    pub first: Vec<Option<Surface>>,
    /// The next surface behind it (the second depth layer), if any.
    pub second: Vec<Option<Surface>>,
}

/// Surfaces closer than this share of the depth count as the same layer (shared edges,
/// coplanar triangles), not as a second one.
const SAME_LAYER: f32 = 1e-4;

impl GBuffer {
    /// Rasterises `objects` seen by `camera` into a `width × height` G-buffer.
    pub fn new(objects: &[Object], camera: &Camera, width: usize, height: usize) -> GBuffer {
        let (w, h) = (width.max(1), height.max(1));
        let view_proj = camera.view_projection(w as f32 / h as f32);
        let mut first: Vec<Option<Surface>> = vec![None; w * h];
        let mut second: Vec<Option<Surface>> = vec![None; w * h];
        for (o, obj) in objects.iter().enumerate() {
            let clip: Vec<Vec4> = obj.positions.iter().map(|p| view_proj * p.extend(1.0)).collect();
            for t in &obj.triangles {
                let c = t.map(|i| clip[i as usize]);
                let Some(s) = to_screen(c, w, h) else { continue };
                let inv_w = c.map(|v| 1.0 / v.w);
                let pos = t.map(|i| obj.positions[i as usize]);
                let nrm = t.map(|i| obj.normals[i as usize]);
                raster_triangle(s, w, h, |k, b0, b1, b2| {
                    // Perspective-correct interpolation.
                    let (q0, q1, q2) = (b0 * inv_w[0], b1 * inv_w[1], b2 * inv_w[2]);
                    let q = q0 + q1 + q2;
                    let depth = 1.0 / q;
                    let position = (pos[0] * q0 + pos[1] * q1 + pos[2] * q2) / q;
                    let mut normal = ((nrm[0] * q0 + nrm[1] * q1 + nrm[2] * q2) / q).normalize_or_zero();
                    if normal.dot(camera.position - position) < 0.0 {
                        normal = -normal;
                    }
                    let surface = Surface { position, normal, albedo: obj.albedo, depth, object: o as u32 };
                    insert(&mut first[k], &mut second[k], surface);
                });
            }
        }
        GBuffer { width: w, height: h, view_proj, eye: camera.position, first, second }
    }

    /// Pixel `(x, y)` and view depth of world point `p`, if in front of the camera.
    #[inline]
    pub fn project(&self, p: Vec3) -> Option<(f32, f32, f32)> {
        let c = self.view_proj * p.extend(1.0);
        if c.w <= 0.01 {
            return None;
        }
        let x = (c.x / c.w * 0.5 + 0.5) * self.width as f32;
        let y = (0.5 - c.y / c.w * 0.5) * self.height as f32;
        Some((x, y, c.w))
    }

    /// The pixel index containing `(x, y)`, if inside the image.
    #[inline]
    pub fn pixel(&self, x: f32, y: f32) -> Option<usize> {
        (x >= 0.0 && y >= 0.0 && x < self.width as f32 && y < self.height as f32)
            .then(|| y as usize * self.width + x as usize)
    }

    /// Pixels that show a surface.
    pub fn covered(&self) -> usize {
        self.first.iter().filter(|s| s.is_some()).count()
    }
}

/// Keeps the two nearest distinct layers.
fn insert(first: &mut Option<Surface>, second: &mut Option<Surface>, s: Surface) {
    match *first {
        None => *first = Some(s),
        Some(f) if s.depth < f.depth => {
            if f.depth - s.depth > SAME_LAYER * f.depth {
                *second = Some(f);
            }
            *first = Some(s);
        }
        Some(f) => {
            if s.depth - f.depth > SAME_LAYER * f.depth && second.is_none_or(|b| s.depth < b.depth) {
                *second = Some(s);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(z: f32, half: f32, albedo: Vec3) -> Object {
        Object {
            positions: vec![
                Vec3::new(-half, -half, z),
                Vec3::new(half, -half, z),
                Vec3::new(half, half, z),
                Vec3::new(-half, half, z),
            ],
            normals: vec![Vec3::Z; 4],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            albedo,
        }
    }

    #[test]
    fn two_quads_give_two_layers_in_depth_order() {
        let camera = Camera {
            name: "c".into(),
            position: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 40.0,
        };
        // The far quad first, so the insertion has to reorder.
        let g = GBuffer::new(&[quad(-1.0, 1.0, Vec3::X), quad(0.0, 0.5, Vec3::Y)], &camera, 64, 64);
        let centre = 32 * 64 + 32;
        let (a, b) = (g.first[centre].unwrap(), g.second[centre].unwrap());
        assert_eq!((a.object, b.object), (1, 0));
        assert!((a.depth - 5.0).abs() < 1e-3 && (b.depth - 6.0).abs() < 1e-3, "{} {}", a.depth, b.depth);
        assert!((a.position - Vec3::new(0.0, 0.0, 0.0)).length() < 0.05);
        // Where only the big quad is: one layer. The corner: nothing.
        let edge = 32 * 64 + 20;
        assert!(g.first[edge].is_some() && g.second[edge].is_none());
        assert!(g.first[0].is_none());
        // Projection round-trips a surface point to its pixel.
        let (x, y, d) = g.project(a.position).unwrap();
        assert_eq!(g.pixel(x, y), Some(centre));
        assert!((d - a.depth).abs() < 1e-3);
    }
}
