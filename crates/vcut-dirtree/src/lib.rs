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
//! A set symmetric under turns by 2π/M about +Y (`vcut_sphere::symmetric`: M blocks of K
//! directions, block `w` the first turned by `w·2π/M`) gets a **wedged** tree
//! ([`DirectionTree::build_wedged`]): its top levels split into bands of latitude (each a set
//! of whole orbits), the next log2 M levels split each band by wedges, and below them every
//! wedge of a band is split in the same order. A turn by `k·2π/M` is then a relabelling of
//! every node within a wedge, and maps every band onto itself ([`DirectionTree::turn`]); the
//! nodes between span part of a band's wedges and have no turned image ([`TurnShape`]).
//! Bands keep the nodes a cut can use compact: a wedge alone runs from pole to pole.
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
    /// Wedges and bands that cannot divide the directions into equal power-of-two blocks.
    #[error(
        "{wedges} wedges in {bands} bands over {dirs} directions: need powers of two, wedges ≥ 2, wedges × bands ≤ N"
    )]
    Wedges {
        /// Wedges asked for.
        wedges: u32,
        /// Bands asked for.
        bands: u32,
        /// Directions given.
        dirs: usize,
    },
    /// A direction or area is not finite (or an area is negative).
    #[error("direction {0} or its cell area is not finite / negative")]
    BadInput(usize),
}

pub use vcut_cut::turn::TurnShape;
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
    shape: Option<TurnShape>,
}

impl DirectionTree {
    /// Builds the tree over `dirs` (unit vectors) with their cell solid angles.
    pub fn build(dirs: &[Vec3], cell_areas: &[f64]) -> Result<DirectionTree, TreeError> {
        Self::check(dirs, cell_areas)?;
        let mut order: Vec<u32> = (0..dirs.len() as u32).collect();
        split(dirs, &mut order);
        Ok(Self::from_order(dirs, cell_areas, order, None))
    }

    /// Builds the wedged tree of a set symmetric in `wedges` wedges of consecutive directions
    /// (see the module docs): the representatives (wedge 0) sorted by height into `bands`
    /// bands, each band into its wedges, each band's wedge 0 split as [`DirectionTree::build`]
    /// splits and its other wedges in the same order.
    pub fn build_wedged(
        dirs: &[Vec3],
        cell_areas: &[f64],
        wedges: u32,
        bands: u32,
    ) -> Result<DirectionTree, TreeError> {
        Self::check(dirs, cell_areas)?;
        let n = dirs.len();
        let bad = || TreeError::Wedges { wedges, bands, dirs: n };
        if !wedges.is_power_of_two() || wedges < 2 || !bands.is_power_of_two() {
            return Err(bad());
        }
        let k = n / wedges as usize;
        if k < bands as usize {
            return Err(bad());
        }
        let mut reps: Vec<u32> = (0..k as u32).collect();
        reps.sort_by(|&a, &b| dirs[b as usize].y.total_cmp(&dirs[a as usize].y).then(a.cmp(&b)));
        let mut order = Vec::with_capacity(n);
        for band in reps.chunks_mut(k / bands as usize) {
            split(dirs, band);
            for w in 0..wedges {
                order.extend(band.iter().map(|&i| w * k as u32 + i));
            }
        }
        let height = n.trailing_zeros();
        let band_height = height - bands.trailing_zeros();
        let shape = TurnShape { wedge_height: band_height - wedges.trailing_zeros(), band_height };
        Ok(Self::from_order(dirs, cell_areas, order, Some(shape)))
    }

    fn check(dirs: &[Vec3], cell_areas: &[f64]) -> Result<(), TreeError> {
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
        Ok(())
    }

    /// The tree whose leaves are `dirs` in `order`.
    fn from_order(dirs: &[Vec3], cell_areas: &[f64], order: Vec<u32>, shape: Option<TurnShape>) -> DirectionTree {
        let n = dirs.len();
        let height = n.trailing_zeros();
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
        DirectionTree { height, leaf_dirs, leaf_to_input: order, input_to_leaf, mean_dir, solid_angle, cone, shape }
    }

    /// The bands a wedged tree of `n` directions in `wedges` wedges gets unless told otherwise:
    /// at least M/8, so that a band's cells at the equator are at most about 2.5 times as tall
    /// as wide, and enough that a cell holds at most 32 directions (`docs/benchmarks.md` has
    /// the measurements behind both); at most one direction of each wedge per band.
    pub fn default_bands(n: usize, wedges: u32) -> u32 {
        let per_wedge = (n / wedges.max(1) as usize).max(1) as u32;
        let by_shape = wedges / 8;
        let by_size = per_wedge / 32;
        by_shape.max(by_size).clamp(1, per_wedge)
    }

    /// A wedged tree's bands and wedges (`None` for an ordinary tree).
    pub fn turn_shape(&self) -> Option<TurnShape> {
        self.shape
    }

    /// Wedges per band, M (1: an ordinary tree).
    pub fn wedges(&self) -> u32 {
        self.shape.map_or(1, |s| s.wedges() as u32)
    }

    /// The node that `index` becomes when the directions turn by `steps · 2π/M` about +Y:
    /// within its band, `steps` wedges on; itself for a band or more. `None` for a node that
    /// spans part of a band's wedges unless the turn moves it by whole multiples of its width
    /// (no node is its image otherwise). In an ordinary tree only whole turns have images.
    pub fn turn(&self, index: u32, steps: u32) -> Option<u32> {
        let Some(shape) = self.shape else { return Some(index) };
        let (h, off) = self.node(index);
        if h >= shape.band_height {
            return Some(index);
        }
        let shift = (u64::from(steps) % shape.wedges()) << shape.wedge_height;
        if shift % (1u64 << h) != 0 {
            return None;
        }
        let band = 1u64 << shape.band_height;
        let start = u64::from(off) / band * band;
        let moved = start + (u64::from(off) - start + shift) % band;
        Some(self.index(h, moved as u32))
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
        // A wedged tree: the leaf `j` places into wedge `w` of a band is wedge 0's leaf `j`
        // turned by `w` (input `w·K` on).
        if let Some(shape) = self.shape {
            let (band, wedge) = (1usize << shape.band_height, 1usize << shape.wedge_height);
            let k = n / shape.wedges() as usize;
            let common = |l: usize| {
                let (start, w) = (l / band * band, l % band / wedge);
                self.leaf_to_input[l] as usize == w * k + self.leaf_to_input[start + l % wedge] as usize
            };
            if let Some(leaf) = (0..n).find(|&l| !common(l)) {
                return bad(format!("leaf {leaf} breaks the wedges' common order"));
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
