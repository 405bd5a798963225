//! The baseline merge over index-coded cuts (Cheslack-Postava 2008 style): each cut is a list of
//! level-order node indices; at every step each cut is advanced until its node — decoded from
//! its index into (height, first leaf, end) — contains the current leaf ("advance until nested",
//! with no bound on the steps), and the smallest node is emitted. Same expression and same zero
//! skip as [`crate::merge`], so both produce the same cut and can be timed on the same inputs.

use crate::{MergeError, MergedCut, check_groups};
use vcut_cut::Cut;

/// A cut in the index representation: level-order indices and values.
#[derive(Debug, Clone, PartialEq)]
pub struct IndexCut {
    root_height: u32,
    indices: Vec<u32>,
    values: Vec<f32>,
}

impl IndexCut {
    /// The index form of a (valid) cut.
    pub fn from_cut(cut: &Cut) -> IndexCut {
        IndexCut {
            root_height: cut.root_height(),
            indices: cut.level_order_indices().collect(),
            values: cut.values().to_vec(),
        }
    }

    /// Root height.
    pub fn root_height(&self) -> u32 {
        self.root_height
    }

    /// Level-order indices.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// Values.
    pub fn values(&self) -> &[f32] {
        &self.values
    }
}

/// One factor: `Σ weights[i] · cuts[i]`.
#[derive(Debug, Clone, Copy)]
pub struct IndexGroup<'a> {
    /// The cuts summed.
    pub cuts: &'a [&'a IndexCut],
    /// Their weights.
    pub weights: &'a [f32],
}

/// Decodes an index into (height, first leaf, one past the last leaf).
#[inline]
fn node(root: u32, index: u32) -> (u32, u64, u64) {
    let (h, start) = vcut_cut::node_of_index(root, index);
    (h, u64::from(start), u64::from(start) + (1u64 << h))
}

/// One past the last leaf of the node at level-order `index` under a root of height `root`.
pub(crate) fn node_end(root: u32, index: u32) -> u64 {
    node(root, index).2
}

/// Merges `Π_g Σ_{k∈g} w_k V_k` over index-coded cuts into `out` (cleared first).
pub fn merge(groups: &[IndexGroup<'_>], out: &mut MergedCut) -> Result<usize, MergeError> {
    let root = check_groups(groups.iter().map(|g| (g.cuts, g.weights)), |c: &&IndexCut| c.root_height)?;
    out.reset(root);
    let cuts: Vec<&IndexCut> = groups.iter().flat_map(|g| g.cuts.iter().copied()).collect();
    let weights: Vec<f32> = groups.iter().flat_map(|g| g.weights.iter().copied()).collect();
    let mut bounds = Vec::new();
    let mut at = 0;
    for g in groups {
        bounds.push((at, at + g.cuts.len()));
        at += g.cuts.len();
    }
    let mut pos = vec![0usize; cuts.len()];
    let leaves = 1u64 << root;
    let mut leaf = 0u64;
    while leaf < leaves {
        // Advance until nested: every cut's node must contain `leaf`.
        for (k, c) in cuts.iter().enumerate() {
            while pos[k] < c.indices.len() && node(root, c.indices[pos[k]]).2 <= leaf {
                pos[k] += 1;
            }
        }
        let mut h_min = u32::MAX;
        let mut product = 1.0f32;
        let mut zero_h: Option<u32> = None;
        for &(a, b) in &bounds {
            let mut sum = 0.0f32;
            let mut all_zero = true;
            let mut group_min = u32::MAX;
            for k in a..b {
                let (h, _, _) = node(root, cuts[k].indices[pos[k]]);
                let v = cuts[k].values[pos[k]];
                group_min = group_min.min(h);
                sum += weights[k] * v;
                all_zero &= v == 0.0;
            }
            h_min = h_min.min(group_min);
            product *= sum;
            if all_zero {
                zero_h = Some(zero_h.map_or(group_min, |z| z.max(group_min)));
            }
        }
        let (step, value) = match zero_h {
            Some(z) => (z, 0.0),
            None => (h_min, product),
        };
        out.push(step, leaf, value);
        leaf += 1u64 << step;
    }
    Ok(out.heights.len())
}
