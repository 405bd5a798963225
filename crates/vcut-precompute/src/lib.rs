//! Precomputation of visibility cuts.
//!
//! - [`Occluder`]: an obvhs CWBVH over triangles; `occluded` is `!ray_traverse_miss` (the first
//!   hit ends traversal); `inside` votes whether a point is enclosed; and
//!   [`Occluder::raw_throughput`] measures plain occlusion rays/s, the figure the precompute's
//!   own rays/s is compared with.
//! - [`visit_leaves`] walks the direction tree top-down and resolves whole subtrees through their
//!   bounding cones ([`cone_outside`]) without rays.
//! - [`svc`]: per-vertex **self-visibility cuts**: Ṽ(ω) = V(x, ω)·max(0, n·ω) at every leaf
//!   direction, subtrees below the horizon without rays; cuts by the paper's error and
//!   solid-angle thresholds (`vcut_cut::select`).
//! - [`field`]: per-object **visibility cut fields**: binary visibility of the object alone from
//!   every sample point of a `vcut_data::FieldLayout`, rays only inside its bounding cone, points
//!   inside it marked and not traced.
//! - [`params`]: [`PrecomputeParams`] and the presets `fast`, `balanced`, `paper`.
//! - [`run`]: the whole job into a resumable `.vcuts` file, with progress and a summary;
//!   [`setup`]: what it builds before casting rays and the one cut of a vertex or point;
//!   [`estimate`]: its time, rays, output bytes and peak memory from a short timed sample.
//!
//! # Invariants
//! Rays start at the vertex offset along its normal by `origin_offset` × the object's bounding
//! radius, so a closed convex object never shadows itself and a vertex never sees its own faces.
//! Output is a deterministic function of scene and parameters, whatever the thread count.
//! This crate knows nothing about images or shading.
//!
//! # Example
//! ```
//! use vcut_precompute::{Occluder, svc::{SvcParams, self_visibility_cuts}};
//! use vcut_sphere::{DirectionSet, RepulsionParams};
//! use vcut_dirtree::DirectionTree;
//! let set = DirectionSet::generate(256, &RepulsionParams::default(), |_, _| {}).unwrap();
//! let tree = DirectionTree::build(set.directions(), &set.cell_areas()).unwrap();
//! let plane = vcut_scene::shapes::plane(2.0, 2).unwrap();
//! let (cuts, stats) = self_visibility_cuts(&plane, &tree, &SvcParams::default());
//! assert_eq!(cuts.len(), plane.vertex_count());
//! assert_eq!(stats.rays_occluded, 0); // nothing of a plane occludes it
//! ```

pub mod estimate;
pub mod field;
pub mod params;
pub mod run;
pub mod setup;
pub mod svc;

pub use params::PrecomputeParams;

pub use run::{Job, NoProgress, PrecomputeError, Progress, Summary, precompute};

use glam::Vec3;
use obvhs::BvhBuildParams;
use obvhs::cwbvh::{CwBvh, builder::build_cwbvh_from_tris};
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use rayon::prelude::*;
use std::time::{Duration, Instant};
use vcut_dirtree::{Cone, DirectionTree};
use vcut_scene::Mesh;

/// Occlusion queries against a set of triangles.
pub struct Occluder {
    bvh: CwBvh,
    tris: Vec<Triangle>,
    /// Per triangle, the sum of its vertex normals: the side the mesh calls outside.
    outward: Vec<Vec3>,
}

/// Rays cast by a stage, and what was resolved without them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RayStats {
    /// Rays cast.
    pub rays_cast: u64,
    /// Of those, rays that hit something.
    pub rays_occluded: u64,
    /// Leaf directions resolved without a ray (below the horizon, outside the object's bounding
    /// cone, or inside the object), alone or as whole subtrees.
    pub resolved_without_ray: u64,
}

impl std::ops::AddAssign for RayStats {
    fn add_assign(&mut self, o: RayStats) {
        *self = *self + o;
    }
}

impl std::ops::Add for RayStats {
    type Output = RayStats;

    fn add(self, o: RayStats) -> RayStats {
        RayStats {
            rays_cast: self.rays_cast + o.rays_cast,
            rays_occluded: self.rays_occluded + o.rays_occluded,
            resolved_without_ray: self.resolved_without_ray + o.resolved_without_ray,
        }
    }
}

/// An angle by its cosine and sine, for [`cone_outside`] (no trigonometry per node).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Angle {
    cos: f32,
    sin: f32,
}

impl Angle {
    /// The angle `a` radians (0 ≤ a ≤ π).
    pub fn new(a: f32) -> Angle {
        let (sin, cos) = a.sin_cos();
        Angle { cos, sin: sin.max(0.0) }
    }

    /// A right angle (the horizon of a normal).
    pub const RIGHT: Angle = Angle { cos: 0.0, sin: 1.0 };
}

/// Whether every direction of `cone` is at least `angle` away from unit direction `dir`:
/// `dir·axis ≤ cos(angle + half-angle)` while `angle + half-angle < π` (beyond it the cone
/// reaches around to `dir`'s far side and can never be entirely outside).
#[inline]
pub fn cone_outside(cone: &Cone, dir: Vec3, angle: Angle) -> bool {
    let c = cone.cos_half_angle.clamp(-1.0, 1.0);
    let s = (1.0 - c * c).max(0.0).sqrt();
    let sin_sum = angle.sin * c + angle.cos * s;
    sin_sum > 0.0 && dir.dot(cone.axis) <= angle.cos * c - angle.sin * s
}

/// Fills `out` (leaf order) depth-first over `tree`: a subtree whose bounding cone `cull`
/// resolves (`Some(value)`) gets that value without visiting its leaves; every other leaf gets
/// `leaf(direction)`. Returns how many leaves `cull` resolved.
pub fn visit_leaves(
    tree: &DirectionTree,
    cull: impl Fn(&Cone) -> Option<f32>,
    mut leaf: impl FnMut(Vec3) -> f32,
    out: &mut [f32],
) -> u64 {
    let mut culled = 0u64;
    let mut stack = Vec::with_capacity(2 * tree.height() as usize + 2);
    stack.push(0u32);
    while let Some(k) = stack.pop() {
        let range = tree.leaf_range(k);
        if let Some(v) = cull(&tree.cone(k)) {
            out[range.clone()].fill(v);
            culled += range.len() as u64;
            continue;
        }
        if range.len() == 1 {
            out[range.start] = leaf(tree.leaf_directions()[range.start]);
            continue;
        }
        stack.push(2 * k + 2);
        stack.push(2 * k + 1);
    }
    culled
}

impl Occluder {
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
            let mut hit = RayHit::none();
            let ray = Ray::new(p.into(), d.into(), 0.0, f32::INFINITY);
            if self
                .bvh
                .ray_traverse(ray, &mut hit, |r, id| self.tris[self.bvh.primitive_indices[id] as usize].intersect(r))
            {
                let tri = self.bvh.primitive_indices[hit.primitive_id as usize] as usize;
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
