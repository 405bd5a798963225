//! The exact visibility cut of a flat convex occluder ([`vcut_scene::flat::FlatOutline`]) at
//! a point: the leaves whose direction from the point passes through the polygon are blocked
//! (value 0), the others visible (1) — what casting every leaf's ray against the polygon gives,
//! found top-down with the direction tree's bounding cones instead of rays, and coarsened as a
//! field's threshold-0 cut is (a node holds one value only where all its leaves share it).
//!
//! Along the polygon's edges that cut goes down to the leaves, and walking there is most of
//! its cost: seen from a point above a ground, a far edge crosses a couple of hundred leaves.
//! With `edge_leaves` above 1 ([`flat_cut_in`], [`flat_product`]) a node of at most that many
//! leaves straddling an edge stops the walk and takes its estimated visible share instead
//! (`visible_share`): fewer nodes, each a blend of visible and hidden leaves, as a field's
//! cut holds.
//!
//! A field interpolates such an object's shadow between samples on spheres around it, and near
//! the plane its samples lie on both sides of it (those below see the sky above hidden): a
//! vertex close to a ground plane reads a mix of the two. This cut has no samples to mix.
//!
//! # Example
//! ```
//! use glam::Vec3;
//! use vcut_dirtree::DirectionTree;
//! use vcut_shade::flat::flat_cut;
//! let dirs: Vec<Vec3> = (0..8)
//!     .map(|i| Vec3::new([-1.0, 1.0][i & 1], [-1.0, 1.0][(i >> 1) & 1], [-1.0, 1.0][i >> 2]).normalize())
//!     .collect();
//! let tree = DirectionTree::build(&dirs, &[std::f64::consts::PI / 2.0; 8]).unwrap();
//! // A large square below the point hides exactly the four directions pointing down.
//! let square = [Vec3::new(-9.0, 0.0, -9.0), Vec3::new(-9.0, 0.0, 9.0), Vec3::new(9.0, 0.0, 9.0), Vec3::new(9.0, 0.0, -9.0)];
//! let cut = flat_cut(&tree, &square, Vec3::new(0.0, 1.0, 0.0));
//! let hidden = cut.expand().iter().filter(|v| **v == 0.0).count();
//! assert_eq!(hidden, 4);
//! ```

use glam::{DVec3, Vec3};
use std::ops::Range;
use vcut_cut::Cut;
use vcut_dirtree::DirectionTree;
use vcut_merge::{MergeError, MergedCut, Refinement, merge_top_down};

/// The visibility cut at `p` of the convex polygon `corners` (in order, either way round;
/// both in world space): see the module documentation. A point in the polygon's plane (or a
/// polygon of no area seen from it) is hidden from nothing: the root, visible.
pub fn flat_cut(tree: &DirectionTree, corners: &[Vec3], p: Vec3) -> Cut {
    flat_cut_where(tree, corners, p, &[])
}

/// [`flat_cut`] for a product that is zero on the leaf ranges `zeros` (sorted, disjoint) —
/// a vertex's SVC below its horizon and where the object hides itself — whatever this cut
/// holds there: a node whose leaves all lie in one range is one node of value 0, neither
/// classified nor walked into. The product takes the same value at every leaf and shades the
/// same, for a walk that skips where the vertex cannot see.
pub fn flat_cut_where(tree: &DirectionTree, corners: &[Vec3], p: Vec3, zeros: &[Range<u32>]) -> Cut {
    flat_cut_in(tree, corners, p, zeros, 1, (Vec::new(), Vec::new()))
}

/// [`flat_cut_where`] built in `buffers` (heights and values, cleared first; from
/// [`Cut::into_parts`] of an earlier cut): a frame's move walks one cut per vertex that sees
/// the ground, and reuses one set of buffers per thread instead of growing fresh ones.
/// `edge_leaves` (a power of two; 1: exact): the largest node straddling an edge that takes
/// its estimated visible share instead of being walked into (the module documentation).
pub fn flat_cut_in(
    tree: &DirectionTree,
    corners: &[Vec3],
    p: Vec3,
    zeros: &[Range<u32>],
    edge_leaves: u32,
    buffers: (Vec<u8>, Vec<f32>),
) -> Cut {
    let h = tree.height();
    let (mut heights, mut values) = buffers;
    heights.clear();
    values.clear();
    match edge_planes(corners, p) {
        Some(planes) => {
            let mut walk = Walk { tree, planes: &planes, edge_leaves, zeros, run: 0, heights, values };
            walk.node(0, h, 0);
            (heights, values) = (walk.heights, walk.values);
        }
        None => {
            heights.push(h as u8);
            values.push(1.0);
        }
    }
    Cut::new(h, heights, values).unwrap_or_else(|e| unreachable!("a walk of the tree covers it once: {e}"))
}

/// `svc × ` [`flat_cut`] at `p` merged in one walk of the tree ([`vcut_merge::merge_top_down`]:
/// the polygon's cut is classified only where the one-cut refinement `svc` — a vertex's SVC —
/// is not zero, and never stored): the counter merge's cut of the two, the same value at every
/// leaf and the same non-zero nodes (tested against it); a frame's vertex whose only occluder
/// besides its own object is a ground merges this way. `edge_leaves` as for [`flat_cut_in`],
/// the product then [`vcut_merge::merge_refined`]'s with that cut. Errors as
/// [`vcut_merge::merge_top_down`] (`svc` a group, or of no nodes).
pub fn flat_product(
    tree: &DirectionTree,
    corners: &[Vec3],
    p: Vec3,
    edge_leaves: u32,
    svc: &Refinement,
    out: &mut MergedCut,
) -> Result<usize, MergeError> {
    match edge_planes(corners, p) {
        Some(planes) => {
            let dirs = tree.leaf_directions();
            let node = |index: u32, h: u32, _: u32| node_value(tree, index, h, &planes, edge_leaves);
            merge_top_down(svc, node, |leaf| leaf_value(dirs[leaf as usize], &planes), out)
        }
        None => merge_top_down(svc, |_, _, _| Some(1.0), |_| 1.0, out),
    }
}

/// The inward unit normals of the planes through `p` and each edge of the polygon: a direction
/// passes through the polygon when it is on the inner side of every one. `None` when `p` lies
/// (numerically) in the polygon's plane.
fn edge_planes(corners: &[Vec3], p: Vec3) -> Option<Vec<Vec3>> {
    let n = corners.len();
    if n < 3 {
        return None;
    }
    let q = |i: usize| (corners[i % n] - p).as_dvec3();
    let plane = |i: usize| q(i).cross(q(i + 1));
    let scale = (0..n).map(|i| q(i).length_squared()).fold(0.0, f64::max);
    let inner = (0..n).map(q).sum::<DVec3>() / n as f64;
    // Oriented so the polygon's centre is inside; too thin a wedge (the point in the plane).
    let sign = if (0..n).map(|i| plane(i).dot(inner)).sum::<f64>() < 0.0 { -1.0 } else { 1.0 };
    let mut planes = Vec::with_capacity(n);
    for i in 0..n {
        let m = plane(i);
        if m.length_squared() <= 1e-20 * scale * scale || sign * m.dot(inner) <= 0.0 {
            return None;
        }
        planes.push((m * sign / m.length()).as_vec3());
    }
    Some(planes)
}

/// A walk of the tree down to the polygon's edges, appending the cut in leaf order.
struct Walk<'a> {
    tree: &'a DirectionTree,
    planes: &'a [Vec3],
    edge_leaves: u32,
    zeros: &'a [Range<u32>],
    /// The first range of `zeros` not wholly before the node visited (nodes come in leaf order).
    run: usize,
    heights: Vec<u8>,
    values: Vec<f32>,
}

impl Walk<'_> {
    /// Appends the cut of node `index`'s subtree: a node inside a zero range, wholly inside the
    /// polygon's cone or wholly outside one of its planes is one node, and so is one of at most
    /// `edge_leaves` leaves across an edge ([`node_value`]); a leaf is decided by its
    /// direction; a node whose two children came out as one value each, the same, is that node.
    fn node(&mut self, index: u32, h: u32, offset: u32) {
        let tree = self.tree;
        while self.zeros.get(self.run).is_some_and(|r| r.end <= offset) {
            self.run += 1;
        }
        let zero = self.zeros.get(self.run).is_some_and(|r| r.start <= offset && offset + (1 << h) <= r.end);
        let value = if zero {
            Some(0.0)
        } else if h == 0 {
            Some(leaf_value(tree.leaf_directions()[offset as usize], self.planes))
        } else {
            node_value(tree, index, h, self.planes, self.edge_leaves)
        };
        if let Some(v) = value {
            self.heights.push(h as u8);
            self.values.push(v);
            return;
        }
        let start = self.heights.len();
        self.node(2 * index + 1, h - 1, offset);
        self.node(2 * index + 2, h - 1, offset + (1 << (h - 1)));
        if self.heights.len() == start + 2 && self.values[start] == self.values[start + 1] {
            self.heights.truncate(start);
            self.heights.push(h as u8);
            self.values.truncate(start + 1);
        }
    }
}

/// A leaf's value: 0 when its direction passes through the polygon (inside every plane).
#[inline]
fn leaf_value(d: Vec3, planes: &[Vec3]) -> f32 {
    if planes.iter().all(|m| m.dot(d) >= 0.0) { 0.0 } else { 1.0 }
}

/// The value of node `index` (height `h` ≥ 1) in the polygon's cut where [`classify`] tells it,
/// else, when it holds at most `edge_leaves` leaves, its [`visible_share`]; `None`: walk into
/// its children.
#[inline]
fn node_value(tree: &DirectionTree, index: u32, h: u32, planes: &[Vec3], edge_leaves: u32) -> Option<f32> {
    classify(tree.cone(index), planes).or_else(|| {
        (1u32 << h <= edge_leaves)
            .then(|| visible_share(tree.mean_direction(index), tree.solid_angle(index) as f32, planes))
    })
}

/// The share of a node's leaves outside the polygon, estimated: the node taken as a flat disk
/// of its solid angle about its mean direction `dir`, each plane holding the part of the disk
/// on its inner side — a disk's centre `x` radii inside a line has `(acos x − x√(1−x²))/π`
/// of its area beyond it — and the hidden part the least any plane holds: exact for one edge,
/// right at the near-straight corners a ground shows from above, more hidden than the leaves
/// at a sharp corner (a few nodes). Their product, the planes taken as independent, would count
/// a node hidden by two planes twice; the test below fails it.
fn visible_share(dir: Vec3, solid_angle: f32, planes: &[Vec3]) -> f32 {
    let r = (solid_angle / std::f32::consts::PI).sqrt();
    let hidden: f32 = planes
        .iter()
        .map(|m| {
            let x = (m.dot(dir) / r).clamp(-1.0, 1.0);
            1.0 - (x.acos() - x * (1.0 - x * x).sqrt()) / std::f32::consts::PI
        })
        .fold(1.0, f32::min);
    1.0 - hidden
}

/// 0 when every direction of `cone` is inside all the planes, 1 when all are outside one,
/// `None` when the cone straddles.
fn classify(cone: vcut_dirtree::Cone, planes: &[Vec3]) -> Option<f32> {
    let c = cone.cos_half_angle;
    if c <= 0.0 {
        return None;
    }
    let s = (1.0 - c * c).max(0.0).sqrt();
    let mut inside = true;
    for m in planes {
        let d = m.dot(cone.axis);
        if d < -s {
            return Some(1.0);
        }
        inside &= d >= s;
    }
    inside.then_some(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vcut_rays::Occluder;
    use vcut_scene::flat::FlatOutline;
    use vcut_sphere::{DirectionSet, RepulsionParams};

    fn tree(n: usize) -> DirectionTree {
        let set = DirectionSet::generate(n, &RepulsionParams::default(), |_, _| {}).unwrap();
        DirectionTree::build(set.directions(), &set.cell_areas()).unwrap()
    }

    /// The cut's leaves against every leaf's ray cast at the mesh, and the cut as coarse as a
    /// threshold-0 cut: no two sibling nodes of one value side by side.
    fn check(tree: &DirectionTree, mesh: &vcut_scene::Mesh, p: Vec3) -> Cut {
        let outline = FlatOutline::of(mesh).unwrap();
        let cut = flat_cut(tree, outline.corners(), p);
        let occ = Occluder::new(&[mesh]);
        let leaves = cut.expand();
        let dirs = tree.leaf_directions();
        let wrong = (0..dirs.len()).filter(|&l| (leaves[l] == 0.0) != occ.occluded(p, dirs[l], f32::INFINITY)).count();
        // Rays grazing an edge may go either way: at most a few leaves in thousands.
        assert!(wrong <= 2, "{wrong} leaves differ from the rays at {p}");
        let offsets: Vec<u64> = cut.offsets().collect();
        for i in 1..cut.len() {
            let (h, o) = (cut.heights()[i - 1], offsets[i - 1]);
            let siblings = cut.heights()[i] == h && o % (2u64 << h) == 0;
            assert!(!(siblings && cut.values()[i] == cut.values()[i - 1]), "nodes {} and {i} are one node", i - 1);
        }
        cut
    }

    #[test]
    fn the_cut_is_what_every_leafs_ray_says() {
        let t = tree(4096);
        let ground = vcut_scene::shapes::plane(14.0, 8).unwrap();
        for p in [
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(6.5, 0.05, -6.0),
            Vec3::new(2.0, 3.0, 1.0),
            Vec3::new(9.0, 2.0, 0.0),
            Vec3::new(1.0, -0.5, 2.0),
        ] {
            let cut = check(&t, &ground, p);
            let hidden = cut.expand().iter().filter(|v| **v == 0.0).count();
            assert!(hidden > 0 && hidden < t.leaf_count(), "{p}: {hidden} hidden");
        }
        // A small tilted triangle far away hides a few leaves.
        let p = vec![Vec3::new(3.0, 0.0, 0.0), Vec3::new(3.0, 1.0, 0.2), Vec3::new(3.2, 0.3, 1.0)];
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let tri = vcut_scene::Mesh::from_valid_parts(p, vec![n; 3], vec![[0, 1, 2]]).unwrap();
        check(&t, &tri, Vec3::ZERO);
    }

    #[test]
    fn zero_ranges_are_one_node_each_and_the_rest_is_the_exact_cut() {
        let t = tree(4096);
        let ground = vcut_scene::shapes::plane(14.0, 8).unwrap();
        let outline = FlatOutline::of(&ground).unwrap();
        for p in [Vec3::new(0.0, 1.0, 0.0), Vec3::new(6.5, 0.05, -6.0), Vec3::new(2.0, 3.0, 1.0)] {
            let exact = flat_cut(&t, outline.corners(), p);
            // Ranges of every size and alignment, some joined, some holding no edge at all.
            let zeros = [0..1000, 1000..1500, 1501..1502, 2048..3072, 3500..4000];
            let masked = flat_cut_where(&t, outline.corners(), p, &zeros);
            // Outside the ranges the exact cut's values; a node within one range is 0.
            let (a, b) = (exact.expand(), masked.expand());
            for l in (0..t.leaf_count()).filter(|&l| !zeros.iter().any(|r| r.contains(&(l as u32)))) {
                assert_eq!(b[l], a[l], "{p}, leaf {l}");
            }
            for ((h, o), v) in masked.heights().iter().zip(masked.offsets()).zip(masked.values()) {
                let node = o as u32..o as u32 + (1 << h);
                if zeros.iter().any(|r| r.start <= node.start && node.end <= r.end) {
                    assert_eq!(*v, 0.0, "{p}: node {node:?}");
                }
            }
            assert!(masked.len() < exact.len(), "{p}: {} nodes, exact {}", masked.len(), exact.len());
            // No ranges: the exact cut.
            assert_eq!(flat_cut_where(&t, outline.corners(), p, &[]), exact);
            // Built in an earlier cut's buffers (longer than it, holding other nodes): the same.
            let reused = flat_cut_in(&t, outline.corners(), p, &zeros, 1, exact.clone().into_parts());
            assert_eq!(reused, masked, "{p}");
            assert_eq!(flat_cut_in(&t, outline.corners(), p, &[], 1, reused.into_parts()), exact);
        }
    }

    #[test]
    fn the_product_in_one_walk_is_the_counter_merges() {
        let t = tree(4096);
        let ground = vcut_scene::shapes::plane(14.0, 8).unwrap();
        let outline = FlatOutline::of(&ground).unwrap();
        for (p, n) in [
            (Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 0.2, 0.0)),
            (Vec3::new(6.5, 0.05, -6.0), Vec3::new(0.0, 1.0, 0.0)),
            (Vec3::new(2.0, 3.0, 1.0), Vec3::new(-0.3, -1.0, 0.2)),
            (Vec3::new(1.0, 0.0, 2.0), Vec3::new(0.0, 0.0, 1.0)),
        ] {
            // An SVC-like cut: zero where a large square beneath the normal hides the sky (the
            // object's own lower half), elsewhere values in four steps by node.
            let n = n.normalize();
            let side = n.any_orthonormal_vector() * 40.0;
            let square = [side, n.cross(side), -side, -n.cross(side)].map(|c| c - n * 0.01);
            let mut own = flat_cut(&t, &square, Vec3::ZERO);
            for (i, v) in own.values_mut().iter_mut().enumerate() {
                *v *= [0.25, 0.5, 0.75, 1.0][i % 4];
            }
            let svc = Refinement::new(&[&own]).unwrap();
            // Exact, and with edge nodes of up to 16 leaves estimated: the same cut either way.
            for edge in [1, 16] {
                let cut = flat_cut_in(&t, outline.corners(), p, &[], edge, Default::default());
                let flat = Refinement::new(&[&cut]).unwrap();
                let (mut one, mut merged) = (MergedCut::default(), MergedCut::default());
                flat_product(&t, outline.corners(), p, edge, &svc, &mut one).unwrap();
                let factors = [&svc, &flat].map(|r| vcut_merge::Factor { refinement: r, weights: &[1.0] });
                vcut_merge::merge_refined(&factors, &mut merged).unwrap();
                let nonzero = |m: &MergedCut| -> Vec<(u32, u32)> {
                    m.indices
                        .iter()
                        .zip(&m.values)
                        .filter(|(_, v)| **v != 0.0)
                        .map(|(i, v)| (*i, v.to_bits()))
                        .collect()
                };
                assert_eq!(nonzero(&one), nonzero(&merged), "{p}, {edge}");
                assert!(!nonzero(&one).is_empty(), "{p}");
                assert_eq!(one.to_cut().unwrap().expand(), merged.to_cut().unwrap().expand(), "{p}, {edge}");
                assert!(one.heights.len() <= merged.heights.len(), "{p}, {edge}");
            }
        }
    }

    #[test]
    fn edge_nodes_of_up_to_n_leaves_take_their_visible_share() {
        let t = tree(4096);
        let ground = vcut_scene::shapes::plane(14.0, 8).unwrap();
        let outline = FlatOutline::of(&ground).unwrap();
        for p in [Vec3::new(0.0, 1.0, 0.0), Vec3::new(6.5, 0.05, -6.0), Vec3::new(2.0, 3.0, 1.0)] {
            let exact = flat_cut(&t, outline.corners(), p);
            let leaves = exact.expand();
            for edge in [2u32, 16, 64] {
                let cut = flat_cut_in(&t, outline.corners(), p, &[], edge, Default::default());
                let fewer = if edge >= 16 { cut.len() < exact.len() } else { cut.len() <= exact.len() };
                assert!(fewer, "{p}, {edge}: {} nodes, exact {}", cut.len(), exact.len());
                // Blends only in nodes across an edge no larger than asked.
                let mut blended = 0usize;
                for (h, &v) in cut.heights().iter().zip(cut.values()) {
                    if v != 0.0 && v != 1.0 {
                        assert!(0.0 < v && v < 1.0 && (1u32 << h) <= edge, "{p}, {edge}: {v} at height {h}");
                        blended += 1 << h;
                    }
                }
                assert!(blended > 0, "{p}, {edge}");
                // The visible leaves the estimates add up to, and how far each leaf's value is
                // from its own: near the exact cut's, against the leaves blended.
                let coarse = cut.expand();
                let net: f32 = coarse.iter().zip(&leaves).map(|(c, e)| c - e).sum();
                let off: f32 = coarse.iter().zip(&leaves).map(|(c, e)| (c - e).abs()).sum();
                assert!(net.abs() <= 0.05 * blended as f32, "{p}, {edge}: {net} leaves off over {blended}");
                assert!(off <= 0.5 * blended as f32, "{p}, {edge}: {off} off over {blended}");
            }
        }
    }

    #[test]
    fn a_point_in_the_plane_sees_everything() {
        let t = tree(256);
        let ground = vcut_scene::shapes::plane(4.0, 2).unwrap();
        let outline = FlatOutline::of(&ground).unwrap();
        assert_eq!(flat_cut(&t, outline.corners(), Vec3::new(0.5, 0.0, 0.5)), Cut::root(8, 1.0).unwrap());
        // Above it, but beside it in the plane's extension and level: nothing hidden either.
        let beside = flat_cut(&t, outline.corners(), Vec3::new(5.0, 0.0, 0.0));
        assert_eq!(beside, Cut::root(8, 1.0).unwrap());
    }
}
