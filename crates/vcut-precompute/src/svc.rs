//! Self-visibility cuts (SVC): per vertex, Ṽ(ω) = V(x, ω)·max(0, n·ω) at every leaf direction of
//! the direction tree, against the object's own geometry, then the cut by the paper's thresholds.

use crate::{Occluder, RayStats};
use glam::Vec3;
use rayon::prelude::*;
use vcut_cut::Cut;
use vcut_cut::select::{SelectParams, Selector};
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
            select: SelectParams { max_error: 0.005, max_solid_angle: 4.0 * std::f64::consts::PI / 256.0, turn: None },
            origin_offset: 1e-4,
        }
    }
}

/// Ṽ at every leaf (leaf order) for one vertex: subtrees whose bounding cone lies entirely below
/// the horizon (`n·ω ≤ 0` for every leaf) are zero without rays; other leaves above the horizon
/// cast one occlusion ray from `origin`.
pub fn leaf_visibility(occ: &Occluder, tree: &DirectionTree, origin: Vec3, normal: Vec3, out: &mut [f32]) -> RayStats {
    let mut stats = RayStats::default();
    let culled = crate::visit_leaves(
        tree,
        // Largest n·ω over the cone is cos(max(0, angle(n, axis) − half-angle)).
        |cone| crate::cone_outside(cone, normal, crate::Angle::RIGHT).then_some(0.0),
        |d| {
            let c = normal.dot(d);
            if c <= 0.0 {
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
            }
        },
        out,
    );
    stats.resolved_without_ray += culled;
    stats
}

/// The SVC of every vertex of `mesh` (its own geometry only), in parallel over vertices.
pub fn self_visibility_cuts(mesh: &Mesh, tree: &DirectionTree, params: &SvcParams) -> (Vec<Cut>, RayStats) {
    let occ = Occluder::new(&[mesh]);
    let leaf_areas: Vec<f64> = (0..tree.leaf_count()).map(|l| tree.solid_angle(tree.index(0, l as u32))).collect();
    let offset = params.origin_offset * mesh.bounds().radius.max(f32::MIN_POSITIVE);
    let results: Vec<(Cut, RayStats)> = mesh
        .positions()
        .par_iter()
        .zip(mesh.normals().par_iter())
        .map_init(
            || (vec![0.0f32; tree.leaf_count()], Selector::default()),
            |(values, selector), (&p, &n)| {
                let stats = leaf_visibility(&occ, tree, p + n * offset, n, values);
                let cut = selector
                    .select(values, &leaf_areas, params.select)
                    .unwrap_or_else(|_| unreachable!("a tree's leaf count is a power of two"));
                (cut, stats)
            },
        )
        .collect();
    let stats = results.iter().fold(RayStats::default(), |a, r| a + r.1);
    (results.into_iter().map(|r| r.0).collect(), stats)
}
