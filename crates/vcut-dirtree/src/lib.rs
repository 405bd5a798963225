//! The direction binary tree of precomputed visibility cuts.
//!
//! A complete, balanced binary tree whose leaves are the N = 2^H directions in a spatially
//! coherent order (recursive median split along the widest axis of each subset's bounding box),
//! so every node covers a contiguous range of leaves. A node is addressed by its height `h`
//! (0 = leaf, `H` = root) and the offset of its first leaf, or by its **level-order index**
//! `2^(H−h) + offset/2^h − 1` (the paper's formula; the root is 0, node k's children are
//! 2k+1 and 2k+2). Per node: the normalised solid-angle-weighted mean direction ω_k, the solid
//! angle |Ω_k| (the sum of its leaves' Voronoi cells) and a bounding cone containing its leaf
//! directions, for culling whole subtrees.
//!
//! # Invariants
//! N is a power of two ≥ 2; leaves are a permutation of the input directions; children partition
//! their parent's leaf range; a parent's solid angle is the sum of its children's; every cone
//! contains its leaves ([`DirectionTree::validate`] checks all of it). This crate knows nothing
//! about visibility, images or rays.
//!
//! # Example
//! ```
//! use glam::Vec3;
//! use vcut_dirtree::{DirectionTree, level_order_index};
//! // The 8 corners of a cube as directions, each with an eighth of the sphere.
//! let dirs: Vec<Vec3> = (0..8)
//!     .map(|i| Vec3::new([-1.0, 1.0][i & 1], [-1.0, 1.0][(i >> 1) & 1], [-1.0, 1.0][i >> 2]).normalize())
//!     .collect();
//! let tree = DirectionTree::build(&dirs, &[std::f64::consts::PI / 2.0; 8]).unwrap();
//! tree.validate().unwrap();
//! assert_eq!(tree.height(), 3);
//! assert_eq!(level_order_index(3, 3, 0), 0);
//! assert!((tree.solid_angle(0) - 4.0 * std::f64::consts::PI).abs() < 1e-12);
//! ```

use glam::{DVec3, Vec3};

/// Why a tree cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TreeError {
    /// A built tree breaking one of its invariants ([`DirectionTree::validate`]).
    #[error("{0}")]
    Invariant(String),
    /// N is not a power of two ≥ 2 (or too large for 32-bit indices).
    #[error("{0} directions: the tree needs a power of two between 2 and 2^30")]
    NotPowerOfTwo(usize),
    /// Cell areas do not match the directions.
    #[error("{areas} cell areas for {dirs} directions")]
    AreaCount {
        /// Areas given.
        areas: usize,
        /// Directions given.
        dirs: usize,
    },
    /// A direction or area is not finite (or an area is negative).
    #[error("direction {0} or its cell area is not finite / negative")]
    BadInput(usize),
}

/// The level-order index of a node and its inverse (defined with the cuts, `vcut_cut`).
pub use vcut_cut::{level_order_index, node_of_index};

/// A bounding cone: every leaf direction `d` of the node has `d·axis ≥ cos_half_angle`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cone {
    /// Unit axis.
    pub axis: Vec3,
    /// Cosine of the half-angle (rounded down, so the cone is conservative).
    pub cos_half_angle: f32,
}

/// The tree. Node arrays are in level order (`2N − 1` entries).
#[derive(Debug, Clone)]
pub struct DirectionTree {
    height: u32,
    leaf_dirs: Vec<Vec3>,
    leaf_to_input: Vec<u32>,
    input_to_leaf: Vec<u32>,
    mean_dir: Vec<Vec3>,
    solid_angle: Vec<f64>,
    cone: Vec<Cone>,
}

impl DirectionTree {
    /// Builds the tree over `dirs` (unit vectors) with their cell solid angles.
    pub fn build(dirs: &[Vec3], cell_areas: &[f64]) -> Result<DirectionTree, TreeError> {
        let n = dirs.len();
        if n < 2 || !n.is_power_of_two() || n > 1 << 30 {
            return Err(TreeError::NotPowerOfTwo(n));
        }
        if cell_areas.len() != n {
            return Err(TreeError::AreaCount { areas: cell_areas.len(), dirs: n });
        }
        if let Some(i) = (0..n).find(|&i| !(dirs[i].is_finite() && cell_areas[i] >= 0.0 && cell_areas[i].is_finite())) {
            return Err(TreeError::BadInput(i));
        }
        let height = n.trailing_zeros();
        let mut order: Vec<u32> = (0..n as u32).collect();
        split(dirs, &mut order);
        let mut input_to_leaf = vec![0u32; n];
        for (leaf, &input) in order.iter().enumerate() {
            input_to_leaf[input as usize] = leaf as u32;
        }
        let leaf_dirs: Vec<Vec3> = order.iter().map(|&i| dirs[i as usize].normalize()).collect();
        let nodes = 2 * n - 1;
        let mut sums = vec![DVec3::ZERO; nodes];
        let mut solid_angle = vec![0.0f64; nodes];
        // Leaves, then parents bottom-up (children of k are 2k+1, 2k+2).
        for leaf in 0..n {
            let k = level_order_index(height, 0, leaf as u32) as usize;
            let a = cell_areas[order[leaf] as usize];
            sums[k] = leaf_dirs[leaf].as_dvec3() * a;
            solid_angle[k] = a;
        }
        for k in (0..n - 1).rev() {
            sums[k] = sums[2 * k + 1] + sums[2 * k + 2];
            solid_angle[k] = solid_angle[2 * k + 1] + solid_angle[2 * k + 2];
        }
        let mean_dir: Vec<Vec3> = (0..nodes)
            .map(|k| {
                let (h, off) = node_of_index(height, k as u32);
                let fallback = leaf_dirs[off as usize + (1usize << h) / 2];
                sums[k].normalize_or(fallback.as_dvec3()).as_vec3()
            })
            .collect();
        let cone = (0..nodes)
            .map(|k| {
                let (h, off) = node_of_index(height, k as u32);
                let axis = mean_dir[k];
                let range = &leaf_dirs[off as usize..off as usize + (1usize << h)];
                let c = range.iter().map(|d| d.dot(axis)).fold(1.0f32, f32::min);
                // Not clamped at −1: a whole-sphere cone must still contain leaves whose dot rounds below −1.
                Cone { axis, cos_half_angle: c - 1e-6 }
            })
            .collect();
        Ok(DirectionTree { height, leaf_dirs, leaf_to_input: order, input_to_leaf, mean_dir, solid_angle, cone })
    }

    /// Root height H = log2 N.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of leaves N.
    pub fn leaf_count(&self) -> usize {
        self.leaf_dirs.len()
    }

    /// Number of nodes 2N − 1.
    pub fn node_count(&self) -> usize {
        self.mean_dir.len()
    }

    /// Leaf directions in tree order.
    pub fn leaf_directions(&self) -> &[Vec3] {
        &self.leaf_dirs
    }

    /// Input index of each leaf.
    pub fn leaf_to_input(&self) -> &[u32] {
        &self.leaf_to_input
    }

    /// Leaf position of each input direction.
    pub fn input_to_leaf(&self) -> &[u32] {
        &self.input_to_leaf
    }

    /// Level-order index of a node.
    pub fn index(&self, h: u32, offset: u32) -> u32 {
        level_order_index(self.height, h, offset)
    }

    /// `(height, offset)` of a level-order index.
    pub fn node(&self, index: u32) -> (u32, u32) {
        node_of_index(self.height, index)
    }

    /// Leaf range of a level-order index.
    pub fn leaf_range(&self, index: u32) -> std::ops::Range<usize> {
        let (h, off) = self.node(index);
        off as usize..off as usize + (1usize << h)
    }

    /// Normalised solid-angle-weighted mean direction ω_k.
    pub fn mean_direction(&self, index: u32) -> Vec3 {
        self.mean_dir[index as usize]
    }

    /// All mean directions, level order.
    pub fn mean_directions(&self) -> &[Vec3] {
        &self.mean_dir
    }

    /// Solid angle |Ω_k| (sum of its leaves' cells).
    pub fn solid_angle(&self, index: u32) -> f64 {
        self.solid_angle[index as usize]
    }

    /// All solid angles, level order.
    pub fn solid_angles(&self) -> &[f64] {
        &self.solid_angle
    }

    /// Bounding cone of a node's leaf directions.
    pub fn cone(&self, index: u32) -> Cone {
        self.cone[index as usize]
    }

    /// Checks every invariant (for tests): permutation, partition, solid-angle sums, unit mean
    /// directions, cones containing their leaves, index formula round trips.
    pub fn validate(&self) -> Result<(), TreeError> {
        let bad = |what: String| Err(TreeError::Invariant(what));
        let n = self.leaf_count();
        let mut seen = vec![false; n];
        for &i in &self.leaf_to_input {
            if std::mem::replace(&mut seen[i as usize], true) {
                return bad(format!("input {i} appears twice among the leaves"));
            }
        }
        for k in 0..self.node_count() as u32 {
            let (h, off) = self.node(k);
            if self.index(h, off) != k {
                return bad(format!("index {k} does not round-trip through (h={h}, offset={off})"));
            }
            if off % (1 << h) != 0 {
                return bad(format!("node {k} offset {off} not aligned to 2^{h}"));
            }
            if (self.mean_dir[k as usize].length() - 1.0).abs() > 1e-4 {
                return bad(format!("node {k} mean direction not unit"));
            }
            if h > 0 {
                let (l, r) = (2 * k + 1, 2 * k + 2);
                let (lr, rr, pr) = (self.leaf_range(l), self.leaf_range(r), self.leaf_range(k));
                if lr.start != pr.start || lr.end != rr.start || rr.end != pr.end {
                    return bad(format!("children of {k} do not partition {pr:?}: {lr:?} {rr:?}"));
                }
                let sum = self.solid_angle[l as usize] + self.solid_angle[r as usize];
                if (sum - self.solid_angle[k as usize]).abs() > 1e-12 * sum.max(1.0) {
                    return bad(format!("solid angle of {k} is not the sum of its children's"));
                }
            }
            let c = self.cone[k as usize];
            for d in &self.leaf_dirs[self.leaf_range(k)] {
                if d.dot(c.axis) < c.cos_half_angle {
                    return bad(format!("cone of node {k} misses leaf direction {d}"));
                }
            }
        }
        Ok(())
    }
}

/// Recursive median split of `order` (indices into `dirs`) along the widest axis.
fn split(dirs: &[Vec3], order: &mut [u32]) {
    if order.len() <= 1 {
        return;
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &i in order.iter() {
        lo = lo.min(dirs[i as usize]);
        hi = hi.max(dirs[i as usize]);
    }
    let ext = hi - lo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |&a, &b| {
        dirs[a as usize][axis].total_cmp(&dirs[b as usize][axis]).then(a.cmp(&b))
    });
    let (left, right) = order.split_at_mut(mid);
    split(dirs, left);
    split(dirs, right);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_formula_matches_the_paper() {
        // H = 3: root 0; height-2 nodes 1, 2; leaves 7..14.
        assert_eq!(level_order_index(3, 3, 0), 0);
        assert_eq!(level_order_index(3, 2, 0), 1);
        assert_eq!(level_order_index(3, 2, 4), 2);
        assert_eq!(level_order_index(3, 0, 0), 7);
        assert_eq!(level_order_index(3, 0, 7), 14);
        for k in 0..15 {
            let (h, o) = node_of_index(3, k);
            assert_eq!(level_order_index(3, h, o), k);
        }
        // H = 16 (65,536 leaves): the last leaf.
        assert_eq!(level_order_index(16, 0, 65_535), 2 * 65_536 - 2);
        assert_eq!(node_of_index(16, 2 * 65_536 - 2), (0, 65_535));
    }

    #[test]
    fn rejects_bad_counts() {
        assert_eq!(DirectionTree::build(&[Vec3::X; 3], &[1.0; 3]).unwrap_err(), TreeError::NotPowerOfTwo(3));
        assert!(matches!(DirectionTree::build(&[Vec3::X; 4], &[1.0; 3]), Err(TreeError::AreaCount { .. })));
        assert!(matches!(DirectionTree::build(&[Vec3::X; 4], &[1.0, 1.0, f64::NAN, 1.0]), Err(TreeError::BadInput(2))));
    }
}
