//! Merging visibility cuts: the paper's counter algorithm over height-coded cuts, and the
//! index-based baseline in the style of Cheslack-Postava 2008 beside it.
//!
//! A merge evaluates a **product of weighted sums** of cuts in one pass — `Π_g Σ_{k∈g} w_k V_k`
//! — which covers the N-way product (every group one cut with weight 1: SVC × fields), the N-way
//! weighted sum (one group: trilinear interpolation of 8 field cuts), and a frame's whole
//! expression (SVC × interp(8 cuts of object A) × interp(8 cuts of object B)) without
//! intermediate cuts. The result is their coarsest common refinement: each emitted node has the
//! lowest height among the current nodes, and its level-order index `2^(H−h) + C/2^h − 1`
//! (C the global leaf counter) comes with it for the light-tree lookup.
//!
//! **Counter algorithm** ([`merge`]): all current nodes are nested (they all contain leaf C).
//! Emit the lowest; advance every cut by `2^h_min` with its own counter (leaves consumed of its
//! current node) and step to its next node when the counter fills it — no index arithmetic, no
//! "advance until nested" search. **Zero skip**: where every cut of a group is zero on its current
//! node, the product is zero over the smallest of those nodes, so one zero node is emitted for the
//! whole range and every cut skips past it (the SVC's zero nodes — directions below the horizon or
//! blocked by the object itself — are the common case).
//!
//! **Baseline** ([`baseline::merge`]): the same expression over index-coded cuts; each step
//! advances every cut until its node (decoded from its index) contains the current leaf, then
//! emits the smallest. It produces exactly the same cut (tested), so the two can be timed on the
//! same inputs.
//!
//! **The seam** ([`prepared`]): callers prepare each group once with an [`Algorithm`] and merge
//! the prepared groups with [`merge_prepared`], one code path for either algorithm.
//!
//! # Example
//! ```
//! use vcut_cut::Cut;
//! use vcut_merge::{MergedCut, merge_product};
//! let svc = Cut::new(2, vec![1, 1], vec![1.0, 0.0]).unwrap();    // left half visible
//! let field = Cut::new(2, vec![0, 0, 1], vec![0.5, 1.0, 1.0]).unwrap();
//! let mut out = MergedCut::default();
//! merge_product(&[&svc, &field], &mut out).unwrap();
//! assert_eq!(out.heights, vec![0, 0, 1]);         // refined where the field is
//! assert_eq!(out.values, vec![0.5, 1.0, 0.0]);    // zero half in one node
//! assert_eq!(out.indices, vec![3, 4, 2]);
//! ```

pub mod baseline;
pub mod prepared;
pub mod refined;
pub mod top_down;
pub mod turn;

pub use prepared::{Algorithm, Prepared, merge_prepared};
pub use refined::{Factor, Refinement, merge_refined};
pub use top_down::merge_top_down;

use vcut_cut::Cut;

/// One factor of the product: `Σ weights[i] · cuts[i]`.
#[derive(Debug, Clone, Copy)]
pub struct Group<'a> {
    /// The cuts summed.
    pub cuts: &'a [&'a Cut],
    /// Their weights (as many as cuts).
    pub weights: &'a [f32],
}

const ONE: [f32; 1] = [1.0];

impl<'a> Group<'a> {
    /// A factor that is one cut with weight 1 (takes `&&Cut` so the group can borrow it as a
    /// one-element slice).
    pub fn single(cut: &'a &'a Cut) -> Group<'a> {
        Group { cuts: std::slice::from_ref(cut), weights: &ONE }
    }
}

/// A merged cut with the level-order index of every node.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MergedCut {
    /// Root height H.
    pub root_height: u32,
    /// Node heights, left to right.
    pub heights: Vec<u8>,
    /// Node values.
    pub values: Vec<f32>,
    /// Level-order index of every node.
    pub indices: Vec<u32>,
}

impl MergedCut {
    fn reset(&mut self, root_height: u32) {
        self.root_height = root_height;
        self.heights.clear();
        self.values.clear();
        self.indices.clear();
    }

    #[inline]
    fn push(&mut self, h: u32, leaf: u64, value: f32) {
        self.heights.push(h as u8);
        self.values.push(value);
        // Leaves number at most 2^24 (checked cuts): every leaf fits in u32.
        self.indices.push(vcut_cut::level_order_index(self.root_height, h, leaf as u32));
    }

    /// Drops the nodes from `len` on.
    fn truncate(&mut self, len: usize) {
        self.heights.truncate(len);
        self.values.truncate(len);
        self.indices.truncate(len);
    }

    /// As a checked [`Cut`] (drops the indices).
    pub fn to_cut(&self) -> Result<Cut, vcut_cut::CutError> {
        Cut::new(self.root_height, self.heights.clone(), self.values.clone())
    }
}

/// Why cuts cannot be merged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MergeError {
    /// Cuts of different trees.
    #[error("cuts of root heights {0} and {1} cannot be merged")]
    RootHeights(u32, u32),
    /// A group whose weights do not match its cuts.
    #[error("group {group}: {weights} weights for {cuts} cuts")]
    Weights {
        /// Group number.
        group: usize,
        /// Weights given.
        weights: usize,
        /// Cuts given.
        cuts: usize,
    },
    /// Nothing to merge.
    #[error("no cuts")]
    Empty,
    /// Prepared groups of different algorithms ([`merge_prepared`]).
    #[error("group {group} was prepared for another merge algorithm than group 0")]
    Mixed {
        /// The first group of another algorithm.
        group: usize,
    },
}

/// Appends leaf range `r` to `runs`, joined to the last run when it starts where that ends.
pub(crate) fn push_run(runs: &mut Vec<std::ops::Range<u32>>, r: std::ops::Range<u32>) {
    match runs.last_mut() {
        Some(last) if last.end == r.start => last.end = r.end,
        _ => runs.push(r),
    }
}

/// Checks the groups (cuts, weights) and returns the common root height.
pub(crate) fn check_groups<'a, T: 'a>(
    groups: impl Iterator<Item = (&'a [T], &'a [f32])>,
    root: impl Fn(&T) -> u32,
) -> Result<u32, MergeError> {
    let mut h = None;
    for (g, (cuts, weights)) in groups.enumerate() {
        if cuts.len() != weights.len() || cuts.is_empty() {
            return Err(MergeError::Weights { group: g, weights: weights.len(), cuts: cuts.len() });
        }
        for c in cuts.iter() {
            let r = root(c);
            match h {
                None => h = Some(r),
                Some(h0) if h0 != r => return Err(MergeError::RootHeights(h0, r)),
                _ => {}
            }
        }
    }
    h.ok_or(MergeError::Empty)
}

/// Per-cut cursor of the counter algorithm: the current node and the leaf where it ends (the
/// paper's counter, kept as "leaves until the node is used up" relative to the global counter).
#[derive(Clone, Copy)]
struct Cursor<'a> {
    heights: &'a [u8],
    values: &'a [f32],
    pos: usize,
    end: u64,
}

/// Merges `Π_g Σ_{k∈g} w_k V_k` into `out` (cleared first) with the counter algorithm.
/// Returns the number of merge steps (emitted nodes).
///
/// Each step costs a scan of the cuts' node ends (the lowest current node ends first); only the
/// cuts whose node ends there move on, and only their groups' sums are recomputed — in member
/// order, so the arithmetic is the baseline's to the bit.
pub fn merge(groups: &[Group<'_>], out: &mut MergedCut) -> Result<usize, MergeError> {
    let root = check_groups(groups.iter().map(|g| (g.cuts, g.weights)), |c: &&Cut| c.root_height())?;
    out.reset(root);
    let total: usize = groups.iter().map(|g| g.cuts.len()).sum();
    let mut cursors: Vec<Cursor<'_>> = Vec::with_capacity(total);
    let mut bounds = Vec::with_capacity(groups.len());
    let mut weights = Vec::with_capacity(total);
    for g in groups {
        let start = cursors.len();
        for (c, &w) in g.cuts.iter().zip(g.weights) {
            cursors.push(Cursor { heights: c.heights(), values: c.values(), pos: 0, end: 1u64 << c.heights()[0] });
            weights.push(w);
        }
        bounds.push((start, cursors.len()));
    }
    let mut sums = vec![0.0f32; bounds.len()];
    let mut nonzero = vec![0usize; bounds.len()];
    // Where each group's lowest current node ends; only groups whose cuts moved are rescanned.
    let mut group_end = vec![0u64; bounds.len()];
    let mut dirty = vec![true; bounds.len()];
    let leaves = 1u64 << root;
    let mut leaf = 0u64;
    loop {
        for (g, &(a, b)) in bounds.iter().enumerate() {
            if dirty[g] {
                let (mut sum, mut nz, mut end) = (0.0f32, 0usize, u64::MAX);
                for k in a..b {
                    let c = &cursors[k];
                    let v = c.values[c.pos];
                    sum += weights[k] * v;
                    nz += usize::from(v != 0.0);
                    end = end.min(c.end);
                }
                sums[g] = sum;
                nonzero[g] = nz;
                group_end[g] = end;
                dirty[g] = false;
            }
        }
        // The lowest current node ends first; an all-zero group is zero up to the end of its
        // lowest node, and the widest such range is skipped in one node.
        let mut next = u64::MAX;
        let mut zero_end = 0u64;
        for g in 0..bounds.len() {
            next = next.min(group_end[g]);
            if nonzero[g] == 0 {
                zero_end = zero_end.max(group_end[g]);
            }
        }
        let (target, value) = if zero_end > 0 { (zero_end, 0.0) } else { (next, sums.iter().product::<f32>()) };
        out.push((target - leaf).trailing_zeros(), leaf, value);
        leaf = target;
        if leaf >= leaves {
            break;
        }
        // Only groups whose lowest node has ended can hold cuts that move on.
        for (g, &(a, b)) in bounds.iter().enumerate() {
            if group_end[g] <= leaf {
                for c in &mut cursors[a..b] {
                    while c.end <= leaf {
                        c.pos += 1;
                        c.end += 1u64 << c.heights[c.pos];
                    }
                }
                dirty[g] = true;
            }
        }
    }
    Ok(out.heights.len())
}

/// The N-way product of cuts (each a factor with weight 1).
pub fn merge_product(cuts: &[&Cut], out: &mut MergedCut) -> Result<usize, MergeError> {
    let groups: Vec<Group<'_>> = cuts.iter().map(Group::single).collect();
    merge(&groups, out)
}

/// The weighted sum `Σ w_k V_k` (e.g. trilinear interpolation of 8 field cuts).
pub fn merge_weighted_sum(cuts: &[&Cut], weights: &[f32], out: &mut MergedCut) -> Result<usize, MergeError> {
    merge(&[Group { cuts, weights }], out)
}
