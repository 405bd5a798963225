//! Self-visibility cuts (SVC): per vertex, Ṽ(ω) = V(x, ω)·max(0, n·ω) at every leaf direction of
//! the direction tree, against the object's own geometry, then the cut by the paper's thresholds.

use crate::Occluder;
use glam::Vec3;
use rayon::prelude::*;
use vcut_cut::Cut;
use vcut_cut::select::{SelectParams, select};
use vcut_dirtree::DirectionTree;
use vcut_scene::Mesh;

/// Parameters of the SVC stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SvcParams {
    /// Cut selection thresholds.
    pub select: SelectParams,
    /// Ray origin offset along the vertex normal, as a fraction of the object's bounding radius.
    pub origin_offset: f32,
}

impl Default for SvcParams {
    /// Error threshold 0.005 and solid angle 4π/256 (provisional until the presets of issue 5
    /// are measured); origin offset 1e-4 of the bounding radius.
    fn default() -> Self {
        Self {
            select: SelectParams { max_error: 0.005, max_solid_angle: 4.0 * std::f64::consts::PI / 256.0 },
            origin_offset: 1e-4,
        }
    }
}

/// What the stage did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SvcStats {
    /// Rays cast.
    pub rays_cast: u64,
    /// Of those, rays that hit the object.
    pub rays_occluded: u64,
    /// Leaf directions resolved without a ray (below the horizon, alone or as whole subtrees).
    pub resolved_without_ray: u64,
}

impl SvcStats {
    fn add(self, o: SvcStats) -> SvcStats {
        SvcStats {
            rays_cast: self.rays_cast + o.rays_cast,
            rays_occluded: self.rays_occluded + o.rays_occluded,
            resolved_without_ray: self.resolved_without_ray + o.resolved_without_ray,
        }
    }
}

/// Ṽ at every leaf (leaf order) for one vertex: subtrees whose bounding cone lies entirely below
/// the horizon (`n·ω ≤ 0` for every leaf) are zero without rays; other leaves above the horizon
/// cast one occlusion ray from `origin`.
pub fn leaf_visibility(occ: &Occluder, tree: &DirectionTree, origin: Vec3, normal: Vec3, out: &mut [f32]) -> SvcStats {
    let mut stats = SvcStats::default();
    let mut stack = vec![0u32];
    while let Some(k) = stack.pop() {
        let cone = tree.cone(k);
        let range = tree.leaf_range(k);
        // Largest n·ω over the cone: cos(max(0, angle(n, axis) − half-angle)).
        let cos_axis = normal.dot(cone.axis).clamp(-1.0, 1.0);
        let below = if cone.cos_half_angle <= -1.0 {
            false
        } else {
            let half = cone.cos_half_angle.clamp(-1.0, 1.0).acos();
            cos_axis.acos() - half >= std::f32::consts::FRAC_PI_2
        };
        if below {
            out[range.clone()].fill(0.0);
            stats.resolved_without_ray += range.len() as u64;
            continue;
        }
        if range.len() == 1 {
            let leaf = range.start;
            let d = tree.leaf_directions()[leaf];
            let c = normal.dot(d);
            out[leaf] = if c <= 0.0 {
                stats.resolved_without_ray += 1;
                0.0
            } else {
                stats.rays_cast += 1;
                if occ.occluded(origin, d, f32::INFINITY) {
                    stats.rays_occluded += 1;
                    0.0
                } else {
                    c
                }
            };
            continue;
        }
        stack.push(2 * k + 2);
        stack.push(2 * k + 1);
    }
    stats
}

/// The SVC of every vertex of `mesh` (its own geometry only), in parallel over vertices.
pub fn self_visibility_cuts(mesh: &Mesh, tree: &DirectionTree, params: &SvcParams) -> (Vec<Cut>, SvcStats) {
    let occ = Occluder::new(&[mesh]);
    let leaf_areas: Vec<f64> = (0..tree.leaf_count()).map(|l| tree.solid_angle(tree.index(0, l as u32))).collect();
    let offset = params.origin_offset * mesh.bounds().radius.max(f32::MIN_POSITIVE);
    let results: Vec<(Cut, SvcStats)> = mesh
        .positions()
        .par_iter()
        .zip(mesh.normals().par_iter())
        .map_init(
            || vec![0.0f32; tree.leaf_count()],
            |values, (&p, &n)| {
                let stats = leaf_visibility(&occ, tree, p + n * offset, n, values);
                let cut = select(values, &leaf_areas, params.select)
                    .unwrap_or_else(|_| unreachable!("a tree's leaf count is a power of two"));
                (cut, stats)
            },
        )
        .collect();
    let stats = results.iter().fold(SvcStats::default(), |a, r| a.add(r.1));
    (results.into_iter().map(|r| r.0).collect(), stats)
}
