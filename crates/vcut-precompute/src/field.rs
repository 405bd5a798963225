//! Visibility cut fields (VCF): per object, the binary visibility V(p, ω) of that object alone at
//! every sample point p of its [`FieldLayout`], cut with the field thresholds (error < 0.25, no
//! solid-angle limit, so only regions of equal visibility merge).
//!
//! Only what can be occluded is traced: from a point outside the object's bounding sphere, a
//! subtree whose bounding cone misses the sphere's cone (half-angle asin(r/d)) is visible as a
//! whole, without rays; points inside the object (a closed surface, by [`Occluder::inside`]) are
//! marked and fully occluded, without rays.

use crate::{Angle, Occluder, RayStats, cone_outside, visit_leaves};
use glam::Vec3;
use rayon::prelude::*;
use vcut_cut::Cut;
use vcut_cut::select::{SelectParams, Selector};
use vcut_data::FieldLayout;
use vcut_dirtree::{Cone, DirectionTree};
use vcut_scene::Mesh;

/// The directions from a point that can meet an object's bounding sphere: those within
/// asin(r/d) of the direction to its centre. From inside the sphere every direction can.
#[derive(Debug, Clone, Copy)]
pub struct BoundingCone {
    axis: Vec3,
    angle: Angle,
    cos: f32,
}

impl BoundingCone {
    /// The cone from `p` around the sphere (`center`, `radius`); `None` inside the sphere.
    pub fn from_point(p: Vec3, center: Vec3, radius: f32) -> Option<BoundingCone> {
        let to_c = center - p;
        let d = to_c.length();
        (d > radius * (1.0 + 1e-5)).then(|| {
            let beta = (radius / d).asin();
            BoundingCone { axis: to_c / d, angle: Angle::new(beta), cos: beta.cos() }
        })
    }

    /// Whether a tree node's whole cone lies outside (all its directions miss the object).
    #[inline]
    pub fn excludes(&self, cone: &Cone) -> bool {
        cone_outside(cone, self.axis, self.angle)
    }

    /// Whether direction `dir` misses the bounding sphere.
    #[inline]
    pub fn misses(&self, dir: Vec3) -> bool {
        dir.dot(self.axis) < self.cos
    }
}

/// V at every leaf (leaf order) from `p` against `occ`, an object inside the sphere
/// (`center`, `radius`): 1 visible, 0 occluded.
pub fn point_visibility(
    occ: &Occluder,
    tree: &DirectionTree,
    p: Vec3,
    center: Vec3,
    radius: f32,
    out: &mut [f32],
) -> RayStats {
    let mut stats = RayStats::default();
    let bound = BoundingCone::from_point(p, center, radius);
    let culled = visit_leaves(
        tree,
        |cone| bound.is_some_and(|b| b.excludes(cone)).then_some(1.0),
        |dir| {
            if bound.is_some_and(|b| b.misses(dir)) {
                stats.resolved_without_ray += 1;
                return 1.0;
            }
            stats.rays_cast += 1;
            if occ.occluded(p, dir, f32::INFINITY) {
                stats.rays_occluded += 1;
                0.0
            } else {
                1.0
            }
        },
        out,
    );
    stats.resolved_without_ray += culled;
    stats
}

/// The exact field cut (error threshold 0) of the object seen from `p`, built in the same walk
/// that casts the rays: a subtree outside the bounding cone is one visible node at once, and
/// siblings that end up as equal constant nodes merge on the way up. Equal to
/// `select(point_visibility(..), SelectParams::field())` (tested) without its O(N) node sums,
/// which dominate for far points where most of the sphere is culled.
pub fn exact_point_cut(occ: &Occluder, tree: &DirectionTree, p: Vec3, center: Vec3, radius: f32) -> (Cut, RayStats) {
    let mut walk = ExactWalk {
        occ,
        tree,
        p,
        bound: BoundingCone::from_point(p, center, radius),
        heights: Vec::new(),
        values: Vec::new(),
        stats: RayStats::default(),
    };
    walk.node(0, tree.height());
    let cut = Cut::new(tree.height(), walk.heights, walk.values)
        .unwrap_or_else(|e| unreachable!("the walk covers every leaf once: {e}"));
    (cut, walk.stats)
}

/// State of [`exact_point_cut`]'s walk.
struct ExactWalk<'a> {
    occ: &'a Occluder,
    tree: &'a DirectionTree,
    p: Vec3,
    bound: Option<BoundingCone>,
    heights: Vec<u8>,
    values: Vec<f32>,
    stats: RayStats,
}

impl ExactWalk<'_> {
    /// Appends the cut of node `k` (height `h`); returns whether it is a single node.
    fn node(&mut self, k: u32, h: u32) -> bool {
        if self.bound.is_some_and(|b| b.excludes(&self.tree.cone(k))) {
            self.stats.resolved_without_ray += 1u64 << h;
            self.heights.push(h as u8);
            self.values.push(1.0);
            return true;
        }
        if h == 0 {
            let dir = self.tree.leaf_directions()[self.tree.leaf_range(k).start];
            let v = if self.bound.is_some_and(|b| b.misses(dir)) {
                self.stats.resolved_without_ray += 1;
                1.0
            } else {
                self.stats.rays_cast += 1;
                let hit = self.occ.occluded(self.p, dir, f32::INFINITY);
                self.stats.rays_occluded += u64::from(hit);
                if hit { 0.0 } else { 1.0 }
            };
            self.heights.push(0);
            self.values.push(v);
            return true;
        }
        let left_single = self.node(2 * k + 1, h - 1);
        let right_single = self.node(2 * k + 2, h - 1);
        // Two constant children of equal value are one node of this height.
        let n = self.values.len();
        if left_single && right_single && self.values[n - 1] == self.values[n - 2] {
            let v = self.values[n - 1];
            self.heights.truncate(n - 2);
            self.values.truncate(n - 2);
            self.heights.push(h as u8);
            self.values.push(v);
            return true;
        }
        false
    }
}

/// The cuts of one sphere of a field.
#[derive(Debug, Clone, Default)]
pub struct SphereCuts {
    /// One cut per point, in point order.
    pub cuts: Vec<Cut>,
    /// Whether each point lies inside the object (its cut is a single zero node).
    pub inside: Vec<bool>,
    /// Rays cast for this sphere.
    pub stats: RayStats,
}

/// The field cuts of sphere `s` of `layout` against `occ` (the object alone), in parallel over
/// points. `leaf_areas` are the tree's leaf solid angles in leaf order. With error threshold 0
/// (no solid-angle limit applies to fields) cuts come from [`exact_point_cut`].
pub fn sphere_cuts(
    occ: &Occluder,
    tree: &DirectionTree,
    leaf_areas: &[f64],
    layout: &FieldLayout,
    s: u32,
    params: SelectParams,
) -> SphereCuts {
    let results: Vec<(Cut, bool, RayStats)> = (0..layout.points_per_sphere() as u32)
        .into_par_iter()
        .map_init(
            || (vec![0.0f32; tree.leaf_count()], Selector::default()),
            |scratch, i| point_cut(occ, tree, leaf_areas, layout.point(s, i), layout, params, scratch),
        )
        .collect();
    let mut out = SphereCuts::default();
    for (cut, inside, stats) in results {
        out.cuts.push(cut);
        out.inside.push(inside);
        out.stats += stats;
    }
    out
}

/// The field cut at sample point `p` of `layout` against `occ`, whether `p` is inside the object
/// (then no ray is cast and the cut is fully occluded), and the rays it took. `scratch`: a
/// per-thread leaf-value buffer and selector.
pub fn point_cut(
    occ: &Occluder,
    tree: &DirectionTree,
    leaf_areas: &[f64],
    p: glam::Vec3,
    layout: &FieldLayout,
    params: SelectParams,
    (values, selector): &mut (Vec<f32>, Selector),
) -> (Cut, bool, RayStats) {
    if occ.inside(p) {
        let n = tree.leaf_count() as u64;
        let cut = Cut::root(tree.height(), 0.0).unwrap_or_else(|e| unreachable!("{e}"));
        return (turnable(cut, params), true, RayStats { resolved_without_ray: n, ..RayStats::default() });
    }
    // Exact fields are built in the ray walk itself (no O(N) statistics per point); their nodes
    // are constant, so splitting those without a turned image keeps them exact.
    if params.max_error == 0.0 {
        let (cut, stats) = exact_point_cut(occ, tree, p, layout.center, layout.radius);
        return (turnable(cut, params), false, stats);
    }
    let stats = point_visibility(occ, tree, p, layout.center, layout.radius, values);
    let cut = selector
        .select(values, leaf_areas, params)
        .unwrap_or_else(|_| unreachable!("a tree's leaf count is a power of two"));
    (cut, false, stats)
}

/// `cut` with no node that lacks a turned image, when the tree is wedged.
fn turnable(cut: Cut, params: SelectParams) -> Cut {
    match params.turn {
        Some(shape) => cut.turnable(shape),
        None => cut,
    }
}

/// The whole field of `mesh` (every sphere), for tests and small layouts; the precompute writes
/// sphere by sphere instead.
pub fn visibility_cut_field(
    mesh: &Mesh,
    tree: &DirectionTree,
    layout: &FieldLayout,
    params: SelectParams,
) -> Vec<SphereCuts> {
    let occ = Occluder::new(&[mesh]);
    let areas = leaf_solid_angles(tree);
    (0..layout.spheres).map(|s| sphere_cuts(&occ, tree, &areas, layout, s, params)).collect()
}

/// The tree's leaf solid angles in leaf order.
pub fn leaf_solid_angles(tree: &DirectionTree) -> Vec<f64> {
    (0..tree.leaf_count()).map(|l| tree.solid_angle(tree.index(0, l as u32))).collect()
}

/// The field layout of the paper around `mesh`'s bounding sphere, its innermost sphere at the
/// mesh's smallest bounding-box half-extent kept within [`inner_flat`·r, `inner`·r]: `inner` for
/// a solid object (within it a receiver would be inside the object), down to `inner_flat` for a
/// flat one (a ground whose receivers stand near its centre, where lookups clamp).
pub fn layout_around(
    mesh: &Mesh,
    spheres: u32,
    resolution: u32,
    [inner, inner_flat]: [f32; 2],
    outer: f32,
    spacing: vcut_data::RadialSpacing,
) -> FieldLayout {
    let b = mesh.bounds();
    let radius = b.radius.max(f32::MIN_POSITIVE);
    let thin = ((b.max - b.min).min_element() * 0.5 / radius).max(inner_flat);
    FieldLayout { center: b.center, radius, spheres, resolution, inner: thin.min(inner), outer, spacing }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vcut_cut::select::select;
    use vcut_sphere::{DirectionSet, RepulsionParams};

    fn tree(n: usize) -> DirectionTree {
        let set = DirectionSet::generate(n, &RepulsionParams::default(), |_, _| {}).unwrap();
        DirectionTree::build(set.directions(), &set.cell_areas()).unwrap()
    }

    #[test]
    fn a_sphere_shadows_exactly_its_cone_and_hides_its_inside() {
        let t = tree(4096);
        let ball = vcut_scene::shapes::sphere(1.0, 48, 24).unwrap();
        let occ = Occluder::new(&[&ball]);
        let mut v = vec![0.0f32; 4096];
        let areas = leaf_solid_angles(&t);
        for d in [1.5f32, 3.0, 8.0] {
            let p = Vec3::new(0.0, 0.0, d);
            let stats = point_visibility(&occ, &t, p, Vec3::ZERO, 1.0, &mut v);
            let occluded: f64 = v.iter().zip(&areas).map(|(x, a)| f64::from(1.0 - x) * a).sum();
            // A unit sphere at distance d subtends 2π(1 − cos asin(1/d)) steradians.
            let exact = 2.0 * std::f64::consts::PI * (1.0 - (1.0 - 1.0 / f64::from(d * d)).sqrt());
            assert!((occluded - exact).abs() < 0.15 * exact + 0.01, "d {d}: {occluded} vs {exact}");
            // Only directions in the bounding cone are traced.
            assert!(
                stats.rays_cast < (4096.0 * (exact / (4.0 * std::f64::consts::PI)) * 2.0 + 64.0) as u64,
                "{stats:?}"
            );
            assert_eq!(stats.rays_cast + stats.resolved_without_ray, 4096);
        }
        assert!(occ.inside(Vec3::new(0.1, 0.2, -0.3)));
        assert!(!occ.inside(Vec3::new(0.0, 1.2, 0.0)));
        let plane = vcut_scene::shapes::plane(2.0, 4).unwrap();
        assert!(!Occluder::new(&[&plane]).inside(Vec3::new(0.0, -0.5, 0.0)), "an open surface has no inside");
    }

    #[test]
    fn the_exact_walk_equals_selection_on_cast_visibility() {
        let t = tree(4096);
        let teapot = vcut_scene::teapot::teapot(6).unwrap().0;
        let occ = Occluder::new(&[&teapot]);
        let b = teapot.bounds();
        let areas = leaf_solid_angles(&t);
        let mut v = vec![0.0f32; 4096];
        for (k, d) in [0.9f32, 1.05, 1.6, 3.0, 9.5].into_iter().enumerate() {
            let dir = Vec3::new(0.3 + k as f32, 0.5, -0.7 * k as f32).normalize();
            let p = b.center + dir * d * b.radius;
            let stats = point_visibility(&occ, &t, p, b.center, b.radius, &mut v);
            let (cut, exact_stats) = exact_point_cut(&occ, &t, p, b.center, b.radius);
            assert_eq!(cut, select(&v, &areas, SelectParams::field()).unwrap(), "distance {d}r");
            assert_eq!(exact_stats, stats);
        }
    }

    #[test]
    fn field_cuts_are_coarse_and_inside_points_are_marked() {
        let t = tree(1024);
        let ball = vcut_scene::shapes::sphere(1.0, 32, 16).unwrap();
        let layout = layout_around(&ball, 4, 4, [0.2, 0.05], 10.0, vcut_data::RadialSpacing::Linear);
        assert_eq!(layout.inner, 0.2, "a solid object keeps the paper's innermost radius");
        let field = visibility_cut_field(&ball, &t, &layout, SelectParams::field());
        assert_eq!(field.len(), 4);
        // The innermost sphere (0.2r) is inside the ball; the others are outside it.
        assert!(
            field[0].inside.iter().all(|&x| x) && field[0].cuts.iter().all(|c| c.len() == 1 && c.values()[0] == 0.0)
        );
        assert!(field[1..].iter().all(|s| s.inside.iter().all(|&x| !x)));
        // Farther spheres see a smaller disc: fewer nodes and fewer rays.
        let nodes = |s: &SphereCuts| s.cuts.iter().map(Cut::len).sum::<usize>();
        assert!(nodes(&field[3]) < nodes(&field[1]) && field[3].stats.rays_cast < field[1].stats.rays_cast);
        for s in &field {
            for c in &s.cuts {
                c.validate().unwrap();
                assert!(c.len() < 1024 / 4, "{} nodes", c.len());
            }
        }
    }

    #[test]
    fn a_flat_object_gets_the_flat_innermost_radius() {
        let spacing = vcut_data::RadialSpacing::Geometric;
        let ground = vcut_scene::shapes::plane(14.0, 8).unwrap();
        assert_eq!(layout_around(&ground, 4, 4, [0.2, 0.05], 10.0, spacing).inner, 0.05);
        // A slab a tenth as thick as it is wide: its half-thickness, within the two bounds.
        let slab = vcut_scene::shapes::sphere(1.0, 32, 16).unwrap();
        let slab = Mesh::from_valid_parts(
            slab.positions().iter().map(|p| *p * Vec3::new(1.0, 0.1, 1.0)).collect(),
            slab.normals().to_vec(),
            slab.triangles().to_vec(),
        )
        .unwrap();
        let inner = layout_around(&slab, 4, 4, [0.2, 0.05], 10.0, spacing).inner;
        assert!((inner - 0.1).abs() < 1e-3, "{inner}");
        // inner_flat at or above inner: the paper's one radius for every object.
        assert_eq!(layout_around(&ground, 4, 4, [0.2, 0.2], 10.0, spacing).inner, 0.2);
    }
}
