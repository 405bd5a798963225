//! The cut sections a precompute writes, each with its estimated cost, and their split over N
//! machines ([`vcut_data::shard::ShardPlan`]).
//!
//! **Cost model** (rays, deterministic: every shard computes the same plan on its own). An SVC
//! chunk casts at most the upper hemisphere of every vertex: `vertices × directions / 2`. A field
//! sphere casts, from each of its points, only the directions inside the object's bounding cone,
//! which from distance `d` of a bounding sphere of radius `R` is the share
//! `(1 − √(1 − (R/d)²)) / 2` of the sphere of directions (all of it within the bounding sphere),
//! and points inside the object cast none: `points × directions × share × (1 − inside share)`,
//! the inside share from the field's own inside test on up to [`INSIDE_SAMPLES`] points of the
//! sphere spread over it. What the model leaves out — a ray's cost differs by what it meets
//! (from a flat ground most rays leave the object's bounds at once; from a teapot's surface they
//! traverse its BVH) — is measured against the shards' own times by the bench's `distributed`
//! section.

use crate::Occluder;
use crate::params::PrecomputeParams;
use rayon::prelude::*;
use vcut_data::FieldLayout;
use vcut_data::file::{SectionId, SectionKind, Sections};
use vcut_data::shard::{PlanError, ShardPlan};
use vcut_scene::Scene;

/// One cut section: its id and the vertices or sample points it covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CutSection {
    /// The section (`svc (object, chunk)` or `field (object, sphere)`).
    pub id: SectionId,
    /// Vertices or sample points.
    pub units: u64,
}

/// Points of a field sphere tested for the inside share of its cost.
pub const INSIDE_SAMPLES: usize = 64;

/// The share of all directions inside the bounding cone of a sphere of radius `r` seen from
/// distance `d` of its centre (1 from within it).
pub fn cone_share(r: f64, d: f64) -> f64 {
    if d <= r { 1.0 } else { (1.0 - (1.0 - (r / d).powi(2)).sqrt()) / 2.0 }
}

/// The cut sections of a precompute of `scene` with `params` and field `layouts`, in the order the
/// file holds them: every object's SVC chunks, then every field's spheres.
pub fn cut_sections(scene: &Scene, params: &PrecomputeParams, layouts: &[Option<FieldLayout>]) -> Vec<CutSection> {
    let chunk = params.svc_chunk.max(1) as usize;
    let mut out = Vec::new();
    for (i, o) in scene.objects.iter().enumerate() {
        let n = o.mesh.vertex_count();
        for (c, start) in (0..n).step_by(chunk).enumerate() {
            let units = ((start + chunk).min(n) - start) as u64;
            out.push(CutSection { id: SectionId::svc(i as u32, c as u32), units });
        }
    }
    for (i, l) in layouts.iter().enumerate() {
        let Some(l) = l else { continue };
        let units = l.points_per_sphere() as u64;
        out.extend((0..l.spheres).map(|s| CutSection { id: SectionId::field(i as u32, s), units }));
    }
    out
}

/// The share of sphere `s` of `layout`'s points inside `occ` (the object), on up to
/// [`INSIDE_SAMPLES`] points spread over the sphere.
fn inside_share(occ: &Occluder, layout: &FieldLayout, s: u32) -> f64 {
    let n = layout.points_per_sphere();
    let stride = n.div_ceil(INSIDE_SAMPLES).max(1);
    let tested: Vec<bool> = (0..n).step_by(stride).map(|k| occ.inside(layout.point(s, k as u32))).collect();
    tested.iter().filter(|&&x| x).count() as f64 / tested.len().max(1) as f64
}

/// The estimated rays of each of `sections` (see the module docs).
pub fn costs(
    scene: &Scene,
    params: &PrecomputeParams,
    layouts: &[Option<FieldLayout>],
    sections: &[CutSection],
) -> Vec<u64> {
    let dirs = f64::from(params.directions);
    let occluders: Vec<Option<Occluder>> = layouts
        .par_iter()
        .enumerate()
        .map(|(i, l)| l.as_ref().map(|_| Occluder::new(&[&scene.objects[i].mesh])))
        .collect();
    sections
        .par_iter()
        .map(|c| match c.id.kind {
            SectionKind::Field => {
                let (i, s) = (c.id.a as usize, c.id.b);
                let (Some(l), Some(occ)) = (&layouts[i], &occluders[i]) else { return 0 };
                let share = cone_share(f64::from(l.radius), f64::from(l.sphere_radius(s)));
                (c.units as f64 * dirs * share * (1.0 - inside_share(occ, l, s))).round() as u64
            }
            _ => (c.units as f64 * dirs / 2.0).round() as u64,
        })
        .collect()
}

/// The plan that splits the precompute of `scene` with `params` over `shards` shards.
pub fn plan(scene: &Scene, params: &PrecomputeParams, shards: u32) -> Result<ShardPlan, PlanError> {
    let layouts = crate::setup::field_layouts(scene, params);
    let sections = cut_sections(scene, params, &layouts);
    let costs = costs(scene, params, &layouts, &sections);
    let planned: Vec<(SectionId, u64, u64)> = sections.iter().zip(costs).map(|(s, c)| (s.id, s.units, c)).collect();
    ShardPlan::balance(&planned, shards)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cone_share_is_all_inside_and_falls_with_distance() {
        assert_eq!(cone_share(1.0, 0.5), 1.0);
        assert_eq!(cone_share(1.0, 1.0), 1.0);
        // At d = 2R the cone's half-angle is 30°: (1 − cos 30°) / 2.
        assert!((cone_share(1.0, 2.0) - (1.0 - 0.75f64.sqrt()) / 2.0).abs() < 1e-12);
        assert!(cone_share(1.0, 10.0) < cone_share(1.0, 3.0));
    }
}
