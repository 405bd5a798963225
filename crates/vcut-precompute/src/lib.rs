//! Precomputation of visibility cuts.
//!
//! - Rays go through [`vcut_rays`] ([`Occluder`] re-exported): `raw_throughput` there is the
//!   figure the precompute's own rays/s is compared with.
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
//!   [`plan`]: its cut sections with their cost in rays, split over N shards for a farm;
//!   [`estimate`]: its time, rays, output bytes and peak memory from a short timed sample.
//!
//! # Invariants
//! Rays start at the vertex offset along its normal by `origin_offset` × the object's bounding
//! radius ([`vcut_rays::origin_offset`]), so a closed convex object never shadows itself and a
//! vertex never sees its own faces.
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
/// The parameters (they describe the file, so they live with it in `vcut-data`).
pub use vcut_data::params;
pub mod plan;
pub mod run;
pub mod setup;
pub mod svc;

pub use params::PrecomputeParams;

pub use run::{Job, NoProgress, PrecomputeError, Progress, Summary, precompute};

use glam::Vec3;
use vcut_dirtree::{Cone, DirectionTree};
/// Rays are cast through `vcut-rays`, the layer below every job that casts them.
pub use vcut_rays::Occluder;

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
