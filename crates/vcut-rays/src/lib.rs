//! Ray casting for visibility-cut rendering, one layer below every job that casts rays (the
//! precompute, the shading's sun and references, screen space, leaves, the viewer's picking).
//!
//! - [`Occluder`]: an obvhs CWBVH over the triangles of some meshes; `occluded` is
//!   `!ray_traverse_miss` (the first hit ends traversal), `closest_hit` the nearest triangle,
//!   `inside` votes whether a point is enclosed, `raw_throughput` measures plain occlusion rays/s.
//! - [`origin_offset`] and [`origin`]: the one rule for where a ray leaves a surface — along the
//!   normal by a fraction of the object's bounding radius.
//! - [`ray_triangle`], [`ray_plane`] and [`pick`]: what a cursor's ray hits.
//!
//! # Invariants
//! Queries are pure functions of the meshes and the ray: the same answers whatever the thread
//! count or the BVH's shape. This crate knows nothing about cuts, trees or images.
//!
//! # Example
//! ```
//! use glam::Vec3;
//! use vcut_rays::{Occluder, origin, origin_offset};
//! let ground = vcut_scene::shapes::plane(4.0, 4).unwrap();
//! let ball = vcut_scene::shapes::sphere(0.5, 16, 8).unwrap();
//! let mut above = ball.clone();
//! above.transform(glam::Mat4::from_translation(Vec3::Y));
//! let occ = Occluder::new(&[&above]);
//! // A ray up from the ground's centre, leaving it as every precomputed ray does, hits the ball.
//! let o = origin(Vec3::ZERO, Vec3::Y, origin_offset(1e-4, &ground));
//! assert!(occ.occluded(o, Vec3::Y, f32::INFINITY));
//! assert!(!occ.occluded(o, Vec3::X, f32::INFINITY));
//! ```

use glam::Vec3;
use obvhs::BvhBuildParams;
use obvhs::cwbvh::{CwBvh, builder::build_cwbvh_from_tris};
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use rayon::prelude::*;
use std::time::{Duration, Instant};
use vcut_scene::Mesh;

/// Occlusion queries against a set of triangles.
pub struct Occluder {
    bvh: CwBvh,
    tris: Vec<Triangle>,
    /// Per triangle, the sum of its vertex normals: the side the mesh calls outside.
    outward: Vec<Vec3>,
}

impl Occluder {
    /// Bytes held in memory: the hierarchy's nodes and indices, the triangles and their sides.
    pub fn bytes(&self) -> usize {
        self.bvh.nodes.capacity() * size_of::<obvhs::cwbvh::node::CwBvhNode>()
            + self.bvh.primitive_indices.capacity() * size_of::<u32>()
            + self.bvh.exact_node_aabbs.as_ref().map_or(0, |a| a.capacity() * size_of::<obvhs::aabb::Aabb>())
            + self.tris.capacity() * size_of::<Triangle>()
            + self.outward.capacity() * size_of::<Vec3>()
    }

    /// A CWBVH over the triangles of `meshes` (world space).
    pub fn new(meshes: &[&Mesh]) -> Occluder {
        let tris: Vec<Triangle> = meshes
            .iter()
            .flat_map(|m| {
                m.triangles().iter().map(|t| {
                    let [a, b, c] = t.map(|i| m.positions()[i as usize]);
                    Triangle { v0: a.into(), v1: b.into(), v2: c.into() }
                })
            })
            .collect();
        let outward = meshes
            .iter()
            .flat_map(|m| m.triangles().iter().map(|t| t.map(|i| m.normals()[i as usize]).iter().sum()))
            .collect();
        let bvh = build_cwbvh_from_tris(&tris, BvhBuildParams::medium_build(), &mut Duration::default());
        Occluder { bvh, tris, outward }
    }

    /// Whether anything lies on the segment `origin + t·dir`, `0 < t < tmax` (`dir` unit).
    #[inline]
    pub fn occluded(&self, origin: Vec3, dir: Vec3, tmax: f32) -> bool {
        let ray = Ray::new(origin.into(), dir.into(), 0.0, tmax);
        !self.bvh.ray_traverse_miss(ray, |r, id| self.tris[self.bvh.primitive_indices[id] as usize].intersect(r))
    }

    /// The first triangle on `origin + t·dir`, `0 < t < tmax` (`dir` unit): its index (over the
    /// meshes given to [`Occluder::new`], in order, then their triangles) and its distance.
    pub fn closest_hit(&self, origin: Vec3, dir: Vec3, tmax: f32) -> Option<(usize, f32)> {
        let mut hit = RayHit::none();
        let ray = Ray::new(origin.into(), dir.into(), 0.0, tmax);
        self.bvh
            .ray_traverse(ray, &mut hit, |r, id| self.tris[self.bvh.primitive_indices[id] as usize].intersect(r))
            .then(|| (self.bvh.primitive_indices[hit.primitive_id as usize] as usize, hit.t))
    }

    /// Whether `p` lies inside a closed surface of the occluder: of 15 rays in fixed directions
    /// (a spherical Fibonacci set, so none runs along the axis-aligned symmetry planes where
    /// tessellations put their edges), at least 12 first hit a triangle from behind (against its
    /// vertex normals). Open surfaces and points outside fail the vote; the margin tolerates a
    /// ray slipping through a crack.
    pub fn inside(&self, p: Vec3) -> bool {
        let golden = std::f32::consts::PI * (3.0 - 5.0f32.sqrt());
        let dirs = (0..15).map(|i| {
            let z = 1.0 - (2 * i + 1) as f32 / 15.0;
            let (s, c) = (golden * i as f32 + 0.3).sin_cos();
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * c, z, r * s)
        });
        let mut behind = 0;
        for d in dirs {
            if let Some((tri, _)) = self.closest_hit(p, d, f32::INFINITY) {
                behind += usize::from(self.outward[tri].dot(d) > 0.0);
            }
        }
        behind >= 12
    }

    /// Occlusion rays per second on all cores for the given rays (origin, unit direction).
    pub fn raw_throughput(&self, rays: &[(Vec3, Vec3)]) -> f64 {
        let start = Instant::now();
        let hits: usize = rays.par_iter().map(|&(o, d)| usize::from(self.occluded(o, d, f32::INFINITY))).sum();
        std::hint::black_box(hits);
        rays.len() as f64 / start.elapsed().as_secs_f64().max(1e-9)
    }
}

/// How far along its normal a ray leaves a point of `mesh`: `fraction` of the mesh's bounding
/// radius (the precompute's `svc_origin_offset`). Far enough that a closed convex object never
/// shadows itself, near enough to miss no contact shadow at the tessellations used here.
pub fn origin_offset(fraction: f32, mesh: &Mesh) -> f32 {
    offset_for_radius(fraction, mesh.bounds().radius)
}

/// [`origin_offset`] for an object (or scene) of bounding radius `radius`.
pub fn offset_for_radius(fraction: f32, radius: f32) -> f32 {
    fraction * radius.max(f32::MIN_POSITIVE)
}

/// Where a ray from point `p` with normal `n` starts, `offset` along the normal.
#[inline]
pub fn origin(p: Vec3, n: Vec3, offset: f32) -> Vec3 {
    p + n * offset
}

/// Distance along the ray (`origin`, `dir`) to triangle (`a`, `b`, `c`) (Möller–Trumbore), if
/// hit in front of the origin.
pub fn ray_triangle(origin: Vec3, dir: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > 0.0).then_some(t)
}

/// Where the ray (`origin`, `dir`) meets the plane through `point` with normal `normal`.
pub fn ray_plane(origin: Vec3, dir: Vec3, point: Vec3, normal: Vec3) -> Option<Vec3> {
    let d = dir.dot(normal);
    if d.abs() < 1e-6 {
        return None;
    }
    let t = (point - origin).dot(normal) / d;
    (t > 0.0).then(|| origin + dir * t)
}

/// The nearest of `objects` (each its triangles and its vertex positions as placed now) the ray
/// (`origin`, `dir`) hits: its index and the distance.
pub fn pick<'a>(
    objects: impl IntoIterator<Item = (&'a [[u32; 3]], &'a [Vec3])>,
    origin: Vec3,
    dir: Vec3,
) -> Option<(usize, f32)> {
    let mut best: Option<(usize, f32)> = None;
    for (o, (triangles, positions)) in objects.into_iter().enumerate() {
        for t in triangles {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            if let Some(d) = ray_triangle(origin, dir, a, b, c)
                && best.is_none_or(|(_, bd)| d < bd)
            {
                best = Some((o, d));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangles_planes_and_picking() {
        let (o, d) = (Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
        let t = ray_triangle(o, d, Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        assert!((t.unwrap() - 5.0).abs() < 1e-6);
        assert!(ray_triangle(o, Vec3::Z, Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::Y).is_none());
        assert_eq!(ray_plane(o, Vec3::Y, Vec3::new(0.0, -1.0, 0.0), Vec3::Y), None);
        let near = ([[0u32, 1, 2]], [Vec3::new(-1.0, -1.0, 1.0), Vec3::new(1.0, -1.0, 1.0), Vec3::new(0.0, 1.0, 1.0)]);
        let far = ([[0u32, 1, 2]], [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)]);
        let hit = pick([(&far.0[..], &far.1[..]), (&near.0[..], &near.1[..])], o, d).unwrap();
        assert_eq!(hit.0, 1);
        assert!((hit.1 - 4.0).abs() < 1e-6);
    }

    #[test]
    fn a_closed_sphere_holds_its_centre_and_occludes_through_it() {
        let ball = vcut_scene::shapes::sphere(1.0, 24, 12).unwrap();
        let occ = Occluder::new(&[&ball]);
        assert!(occ.inside(Vec3::ZERO));
        assert!(!occ.inside(Vec3::new(3.0, 0.0, 0.0)));
        assert!(occ.occluded(Vec3::new(-3.0, 0.0, 0.0), Vec3::X, f32::INFINITY));
        assert!(!occ.occluded(Vec3::new(-3.0, 0.0, 0.0), Vec3::X, 1.5), "tmax stops the ray short");
        // Off the tessellation's vertices (a ray through one exactly can slip between triangles).
        let (_, t) = occ.closest_hit(Vec3::new(-3.0, 0.1, 0.05), Vec3::X, f32::INFINITY).unwrap();
        assert!((t - (3.0 - (1.0f32 - 0.0125).sqrt())).abs() < 0.02, "{t}");
        // A ray leaving the surface by the rule never hits its own convex object.
        let (p, n) = (ball.positions()[5], ball.normals()[5]);
        assert!(!occ.occluded(origin(p, n, origin_offset(1e-4, &ball)), n, f32::INFINITY));
    }
}
