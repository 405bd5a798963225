//! Precomputation of visibility cuts.
//!
//! - [`Occluder`]: an obvhs CWBVH over triangles; `occluded` is `!ray_traverse_miss` (the first
//!   hit ends traversal), and [`Occluder::raw_throughput`] measures plain occlusion rays/s on the
//!   given rays, the figure the precompute's own rays/s is compared with.
//! - [`svc`]: per-vertex **self-visibility cuts**: Ṽ(ω) = V(x, ω)·max(0, n·ω) at every leaf
//!   direction, against the object's own geometry; whole subtrees of the direction tree whose
//!   bounding cone lies below the horizon are resolved without a ray; the cut is selected by the
//!   paper's error and solid-angle thresholds (`vcut_cut::select`).
//!
//! Status: the SVC stage. Visibility cut fields, presets, the `.vcuts` file and
//! `cargo xtask precompute` follow (issue 5).
//!
//! # Invariants
//! Rays start at the vertex offset along its normal by `origin_offset` × the object's bounding
//! radius, so a closed convex object never shadows itself and a vertex never sees its own faces.
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

pub mod svc;

use glam::Vec3;
use obvhs::BvhBuildParams;
use obvhs::cwbvh::{CwBvh, builder::build_cwbvh_from_tris};
use obvhs::ray::Ray;
use obvhs::triangle::Triangle;
use rayon::prelude::*;
use std::time::{Duration, Instant};
use vcut_scene::Mesh;

/// Occlusion queries against a set of triangles.
pub struct Occluder {
    bvh: CwBvh,
    tris: Vec<Triangle>,
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
        let bvh = build_cwbvh_from_tris(&tris, BvhBuildParams::medium_build(), &mut Duration::default());
        Occluder { bvh, tris }
    }

    /// Whether anything lies on the segment `origin + t·dir`, `0 < t < tmax` (`dir` unit).
    #[inline]
    pub fn occluded(&self, origin: Vec3, dir: Vec3, tmax: f32) -> bool {
        let ray = Ray::new(origin.into(), dir.into(), 0.0, tmax);
        !self.bvh.ray_traverse_miss(ray, |r, id| self.tris[self.bvh.primitive_indices[id] as usize].intersect(r))
    }

    /// Occlusion rays per second on all cores for the given rays (origin, unit direction).
    pub fn raw_throughput(&self, rays: &[(Vec3, Vec3)]) -> f64 {
        let start = Instant::now();
        let hits: usize = rays.par_iter().map(|&(o, d)| usize::from(self.occluded(o, d, f32::INFINITY))).sum();
        std::hint::black_box(hits);
        rays.len() as f64 / start.elapsed().as_secs_f64().max(1e-9)
    }
}
