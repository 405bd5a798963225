//! Merging through **refinements**: a group's cuts merged once into their common refinement,
//! each node carrying every member's value. A frame's field samples are shared: the 8 cuts of a
//! trilinear lookup (a *cell*: two spheres × four texels) serve every vertex whose position falls
//! in that cell, each with its own weights. Refining the cell's cuts once leaves each vertex a
//! product of a few factors — SVC × cell A × cell B, three cursors instead of seventeen — where
//! a factor's sum is a dot product of its node's member values (contiguous) with the vertex's
//! weights.
//!
//! [`merge_refined`] gives [`crate::merge`]'s cut to the bit (tested): a refinement's node at a
//! leaf is the lowest of its members' nodes there, so the factor's end, sum (in member order)
//! and zero test are the group's.

use crate::{MergeError, MergedCut, check_groups};
use vcut_cut::Cut;

/// The common refinement of a group's cuts, every node with all members' values.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Refinement {
    pub(crate) root_height: u32,
    pub(crate) members: usize,
    /// Leaf where each node ends.
    pub(crate) ends: Vec<u32>,
    /// Node-major member values: node j's are `values[j·members .. (j+1)·members]` (empty when
    /// the members are binary).
    pub(crate) values: Vec<f32>,
    /// Binary members (every value 0 or 1, at most [`MAX_MASK_MEMBERS`] members — exact fields):
    /// node j's values as a bit mask, member i in bit i. Empty otherwise.
    pub(crate) masks: Vec<u8>,
    /// Whether any member is non-zero on the node (empty for a single member: its value says).
    pub(crate) nonzero: Vec<bool>,
}

/// Largest root height whose binary refinements are built from bitmaps over the leaves (8 KB a
/// member at 2^16 leaves); deeper trees walk the members' nodes.
const BITMAP_MAX_ROOT: u32 = 16;

/// Most members a binary refinement codes as a bit mask (a merge sums a mask through a table of
/// `2^members` partial sums).
pub const MAX_MASK_MEMBERS: usize = 8;

impl Refinement {
    /// The refinement of `cuts` (one or more cuts of one tree).
    pub fn new(cuts: &[&Cut]) -> Result<Refinement, MergeError> {
        let mut r = Refinement::default();
        r.rebuild(cuts)?;
        Ok(r)
    }

    /// Makes this the refinement of `cuts`, reusing its buffers.
    pub fn rebuild(&mut self, cuts: &[&Cut]) -> Result<(), MergeError> {
        let ones = vec![1.0f32; cuts.len()];
        let root = check_groups(std::iter::once((cuts, &ones[..])), |c: &&Cut| c.root_height())?;
        self.root_height = root;
        self.members = cuts.len();
        self.ends.clear();
        self.values.clear();
        self.masks.clear();
        self.nonzero.clear();
        let leaves = 1u32 << root;
        if let [cut] = cuts {
            // One cut: its own nodes (a mask would save nothing), 8 bytes a node.
            self.ends.reserve_exact(cut.len());
            self.values.reserve_exact(cut.len());
            let mut end = 0u32;
            self.ends.extend(cut.heights().iter().map(|&h| {
                end += 1u32 << h;
                end
            }));
            // A single member's node is non-zero where its value is: nothing more to keep.
            self.values.extend_from_slice(cut.values());
            return Ok(());
        }
        let longest = cuts.iter().map(|c| c.len()).max().unwrap_or(0);
        self.ends.reserve(longest * 2);
        self.nonzero.reserve(longest * 2);
        if cuts.len() <= MAX_MASK_MEMBERS {
            self.masks.reserve(longest * 2);
            let built = if root <= BITMAP_MAX_ROOT {
                self.build_bitmaps(cuts, leaves)
            } else {
                self.build_binary(cuts, leaves)
            };
            if built {
                return Ok(());
            }
            self.ends.clear();
            self.masks.clear();
            self.nonzero.clear();
        }
        self.values.reserve(longest * 2 * cuts.len());
        self.build_values(cuts, leaves);
        Ok(())
    }

    /// The refinement with masks from bitmaps over the leaves: every member's node starts and
    /// the leaves where it is 1, each set in one pass over its nodes; the refinement's nodes
    /// start at the union's bits, and a node's mask gathers one bit per member where it starts.
    /// No cursors, so nothing waits on the previous node. False (nothing built) if a value is
    /// not 0 or 1.
    fn build_bitmaps(&mut self, cuts: &[&Cut], leaves: u32) -> bool {
        // The bitmaps' buffer stays with the thread: a move refines thousands of new cells, and
        // allocating and zeroing a buffer for each was a measurable share of refining them.
        thread_local! {
            static BITS: std::cell::RefCell<Vec<u64>> = const { std::cell::RefCell::new(Vec::new()) };
        }
        BITS.with_borrow_mut(|bits| self.build_bitmaps_in(cuts, leaves, bits))
    }

    fn build_bitmaps_in(&mut self, cuts: &[&Cut], leaves: u32, bits: &mut Vec<u64>) -> bool {
        let words = (leaves as usize).div_ceil(64);
        // Member i's ones in words [(i+1)·words, (i+2)·words), the union of starts first.
        bits.clear();
        bits.resize(words * (cuts.len() + 1), 0);
        let (starts, ones) = bits.split_at_mut(words);
        for (c, ones) in cuts.iter().zip(ones.chunks_exact_mut(words)) {
            let mut off = 0usize;
            for (&h, &v) in c.heights().iter().zip(c.values()) {
                let is_one = v.to_bits() == 1.0f32.to_bits();
                if !is_one && v.to_bits() != 0 {
                    return false;
                }
                starts[off >> 6] |= 1u64 << (off & 63);
                let size = 1usize << h;
                if is_one {
                    if size >= 64 {
                        ones[off >> 6..(off + size) >> 6].fill(u64::MAX);
                    } else {
                        ones[off >> 6] |= ((1u64 << size) - 1) << (off & 63);
                    }
                }
                off += size;
            }
        }
        let ones = &bits[words..];
        for (w, &word) in bits[..words].iter().enumerate() {
            let mut rest = word;
            while rest != 0 {
                let bit = rest.trailing_zeros();
                rest &= rest - 1;
                let start = (w as u32) << 6 | bit;
                if start > 0 {
                    self.ends.push(start);
                }
                let mut mask = 0u8;
                for i in 0..cuts.len() {
                    mask |= (((ones[i * words + w] >> bit) & 1) as u8) << i;
                }
                self.masks.push(mask);
                self.nonzero.push(mask != 0);
            }
        }
        self.ends.push(leaves);
        true
    }

    /// The refinement with masks; false (and left half-built) at the first value that is not
    /// 0 or 1.
    fn build_binary(&mut self, cuts: &[&Cut], leaves: u32) -> bool {
        let binary = |v: f32| v.to_bits() == 0 || v.to_bits() == 1.0f32.to_bits();
        let mut heights: [&[u8]; MAX_MASK_MEMBERS] = [&[]; MAX_MASK_MEMBERS];
        let mut values: [&[f32]; MAX_MASK_MEMBERS] = [&[]; MAX_MASK_MEMBERS];
        let mut pos = [0usize; MAX_MASK_MEMBERS];
        // Unused slots never end (every end is at most `leaves`).
        let mut end = [u32::MAX; MAX_MASK_MEMBERS];
        let mut mask = 0u8;
        let mut ok = true;
        for (i, c) in cuts.iter().enumerate() {
            heights[i] = c.heights();
            values[i] = c.values();
            // Checked cuts: Σ 2^h = 2^H ≤ 2^24, so every end fits in u32.
            end[i] = 1u32 << heights[i][0];
            ok &= binary(values[i][0]);
            mask |= u8::from(values[i][0] != 0.0) << i;
        }
        loop {
            let next = end.iter().copied().fold(u32::MAX, u32::min);
            self.ends.push(next);
            self.masks.push(mask);
            self.nonzero.push(mask != 0);
            if next >= leaves || !ok {
                return ok;
            }
            // Every member's node contains the emitted one: each moves on at most once (no
            // branch: a member that stays reloads its own node).
            for i in 0..cuts.len() {
                let step = usize::from(end[i] == next);
                let p = pos[i] + step;
                pos[i] = p;
                end[i] += (step as u32) << heights[i][p];
                let v = values[i][p];
                ok &= binary(v);
                mask = (mask & !(1 << i)) | (u8::from(v != 0.0) << i);
            }
        }
    }

    /// The refinement with every member's value.
    fn build_values(&mut self, cuts: &[&Cut], leaves: u32) {
        let mut pos = vec![0usize; cuts.len()];
        let mut end: Vec<u32> = cuts.iter().map(|c| 1u32 << c.heights()[0]).collect();
        loop {
            let next = end.iter().copied().fold(u32::MAX, u32::min);
            let mut nonzero = false;
            for (c, &p) in cuts.iter().zip(&pos) {
                let v = c.values()[p];
                nonzero |= v != 0.0;
                self.values.push(v);
            }
            self.nonzero.push(nonzero);
            self.ends.push(next);
            if next >= leaves {
                return;
            }
            for ((c, p), e) in cuts.iter().zip(&mut pos).zip(&mut end) {
                let step = usize::from(*e == next);
                *p += step;
                *e += (step as u32) << c.heights()[*p];
            }
        }
    }

    /// The leaf where each node ends, left to right (the last is `2^root_height`).
    pub fn ends(&self) -> &[u32] {
        &self.ends
    }

    /// The values of a one-cut refinement (its cut's values), `None` for a group.
    pub fn single_values(&self) -> Option<&[f32]> {
        (self.members == 1).then_some(&self.values[..])
    }

    /// Root height of the tree.
    pub fn root_height(&self) -> u32 {
        self.root_height
    }

    /// Cuts refined.
    pub fn members(&self) -> usize {
        self.members
    }

    /// Nodes of the refinement.
    pub fn len(&self) -> usize {
        self.ends.len()
    }

    /// Never true for a built refinement (a cut has at least its root).
    pub fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }

    /// Bytes held (for memory accounting).
    pub fn bytes(&self) -> usize {
        self.ends.capacity() * 4 + self.values.capacity() * 4 + self.masks.capacity() + self.nonzero.capacity()
    }

    /// Appends to `out` the leaf ranges where every member is zero (consecutive zero nodes
    /// joined): where a product with this factor is zero whatever the other factors hold.
    pub fn zero_runs(&self, out: &mut Vec<std::ops::Range<u32>>) {
        let mut start = 0u32;
        for (j, &end) in self.ends.iter().enumerate() {
            // One member keeps only its values; a group says per node whether any is non-zero.
            let zero = if self.nonzero.is_empty() { self.values[j] == 0.0 } else { !self.nonzero[j] };
            if zero {
                crate::push_run(out, start..end);
            }
            start = end;
        }
    }

    /// Whether the members are coded as bit masks (all binary).
    pub fn is_binary(&self) -> bool {
        !self.masks.is_empty()
    }
}

/// One factor of the product: `Σ weights[i] · member i` over a refinement.
#[derive(Debug, Clone, Copy)]
pub struct Factor<'a> {
    /// The refined group.
    pub refinement: &'a Refinement,
    /// One weight per member.
    pub weights: &'a [f32],
}

/// First index `i > from` with `ends[i] > leaf`, given `ends[from] <= leaf < ends[last]`:
/// doubling steps, then a binary search in the last step's range.
#[inline]
fn gallop(ends: &[u32], from: usize, leaf: u32) -> usize {
    let mut lo = from;
    let mut step = 1;
    let mut hi = from + 1;
    while hi < ends.len() && ends[hi] <= leaf {
        lo = hi;
        hi += step;
        step *= 2;
    }
    let hi = hi.min(ends.len());
    lo + 1 + ends[lo + 1..hi].partition_point(|&e| e <= leaf)
}

/// Per-factor cursor: node, its end, the factor's sum on it and whether it is non-zero.
#[derive(Clone, Copy)]
struct FactorCursor {
    pos: usize,
    end: u32,
    sum: f32,
    nonzero: bool,
}

/// How a factor's sum is formed on a node.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    /// Binary members: a table lookup by mask.
    Masks,
    /// One member: `0 + w·v`, as the counter merge adds it.
    One,
    /// Several members with values: their products with the weights, added in member order.
    Many,
}

/// A factor while merging: its refinement's arrays, weights, and for a binary refinement the
/// sum of every mask (`table[m]` = Σ of the weights of m's members, added in member order as the
/// counter merge adds `w · 1`; adding `w · 0` changes no bit).
struct Prepared<'a> {
    ends: &'a [u32],
    masks: &'a [u8],
    values: &'a [f32],
    nonzero: &'a [bool],
    weights: &'a [f32],
    kind: Kind,
    table: Vec<f32>,
}

impl<'a> Prepared<'a> {
    fn new(factor: Factor<'a>) -> Prepared<'a> {
        let r = factor.refinement;
        let mut table = Vec::new();
        let kind = if r.is_binary() {
            table.resize(1 << r.members, 0.0f32);
            for m in 1..table.len() {
                let high = usize::BITS - 1 - m.leading_zeros();
                table[m] = table[m & !(1 << high)] + factor.weights[high as usize];
            }
            Kind::Masks
        } else if r.members == 1 {
            Kind::One
        } else {
            Kind::Many
        };
        Prepared {
            ends: &r.ends,
            masks: &r.masks,
            values: &r.values,
            nonzero: &r.nonzero,
            weights: factor.weights,
            kind,
            table,
        }
    }

    #[inline(always)]
    fn settle(&self, pos: usize) -> FactorCursor {
        let end = self.ends[pos];
        match self.kind {
            Kind::Masks => {
                let m = self.masks[pos];
                FactorCursor { pos, end, sum: self.table[usize::from(m)], nonzero: m != 0 }
            }
            Kind::One => {
                let v = self.values[pos];
                FactorCursor { pos, end, sum: 0.0 + self.weights[0] * v, nonzero: v != 0.0 }
            }
            Kind::Many => {
                let m = self.weights.len();
                let mut sum = 0.0f32;
                for (w, v) in self.weights.iter().zip(&self.values[pos * m..pos * m + m]) {
                    sum += w * v;
                }
                FactorCursor { pos, end, sum, nonzero: self.nonzero[pos] }
            }
        }
    }
}

/// Merges `Π_f Σ_i w_i M_i` over refined factors into `out` (cleared first): the cut
/// [`crate::merge`] gives for the groups the factors refine. Returns the number of emitted
/// nodes.
pub fn merge_refined(factors: &[Factor<'_>], out: &mut MergedCut) -> Result<usize, MergeError> {
    let mut root = None;
    for (g, f) in factors.iter().enumerate() {
        let r = f.refinement;
        if f.weights.len() != r.members || r.is_empty() {
            return Err(MergeError::Weights { group: g, weights: f.weights.len(), cuts: r.members });
        }
        match root {
            None => root = Some(r.root_height),
            Some(h) if h != r.root_height => return Err(MergeError::RootHeights(h, r.root_height)),
            _ => {}
        }
    }
    let root = root.ok_or(MergeError::Empty)?;
    out.reset(root);
    let prepared: Vec<Prepared<'_>> = factors.iter().map(|&f| Prepared::new(f)).collect();
    // A frame's vertex has two or three factors (SVC × one or two cells): with their number
    // known where the walk is inlined, the cursors stay in registers.
    match prepared.as_slice() {
        [a, b] => walk(&[a, b], &mut [a.settle(0), b.settle(0)], root, out),
        [a, b, c] => walk(&[a, b, c], &mut [a.settle(0), b.settle(0), c.settle(0)], root, out),
        _ => {
            let refs: Vec<&Prepared<'_>> = prepared.iter().collect();
            walk(&refs, &mut prepared.iter().map(|p| p.settle(0)).collect::<Vec<_>>(), root, out)
        }
    }
    Ok(out.heights.len())
}

/// [`merge_refined`]'s walk: `cursors` start on each factor's first node.
#[inline(always)]
fn walk(prepared: &[&Prepared<'_>], cursors: &mut [FactorCursor], root: u32, out: &mut MergedCut) {
    let leaves = 1u32 << root;
    let mut leaf = 0u32;
    loop {
        let mut next = u32::MAX;
        let mut zero_end = 0u32;
        let mut product = 1.0f32;
        for c in cursors.iter() {
            product *= c.sum;
            next = next.min(c.end);
            if !c.nonzero {
                zero_end = zero_end.max(c.end);
            }
        }
        let (target, value) = if zero_end > 0 { (zero_end, 0.0) } else { (next, product) };
        out.push((target - leaf).trailing_zeros(), u64::from(leaf), value);
        leaf = target;
        if leaf >= leaves {
            break;
        }
        for (c, p) in cursors.iter_mut().zip(prepared) {
            if c.end <= leaf {
                // Outside zero ranges every node contains the emitted one (one step on); a zero
                // range may span many nodes.
                let pos = if c.end == leaf { c.pos + 1 } else { gallop(p.ends, c.pos, leaf) };
                *c = p.settle(pos);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A binary cut of root height `root` from a seed (splits and values from an LCG).
    fn binary_cut(root: u32, mut seed: u64) -> Cut {
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (seed >> 33) as u32
        };
        let (mut heights, mut values, mut stack) = (Vec::new(), Vec::new(), vec![root]);
        while let Some(h) = stack.pop() {
            if h > 0 && next() % 8 < 5 {
                stack.extend([h - 1, h - 1]);
            } else {
                heights.push(h as u8);
                values.push((next() % 2) as f32);
            }
        }
        Cut::new(root, heights, values).unwrap()
    }

    #[test]
    fn bitmaps_and_the_walk_build_the_same_refinement() {
        for root in [1, 5, 6, 7, 12, 16] {
            for seed in 0..6u64 {
                let cuts: Vec<Cut> = (0..8).map(|k| binary_cut(root, seed * 31 + k)).collect();
                let refs: Vec<&Cut> = cuts.iter().collect();
                let (mut a, mut b) = (Refinement::default(), Refinement::default());
                for r in [&mut a, &mut b] {
                    r.root_height = root;
                    r.members = refs.len();
                }
                assert!(a.build_bitmaps(&refs, 1 << root));
                assert!(b.build_binary(&refs, 1 << root));
                assert_eq!(a, b, "root {root}, seed {seed}");
                assert_eq!(Refinement::new(&refs).unwrap(), a);
                assert!(a.is_binary() && a.len() >= refs.iter().map(|c| c.len()).max().unwrap());
            }
        }
    }

    #[test]
    fn deep_trees_walk_and_non_binary_values_keep_values() {
        // Beyond the bitmaps' depth the walk builds the masks.
        let cuts: Vec<Cut> = (0..3).map(|k| binary_cut(18, k)).collect();
        let refs: Vec<&Cut> = cuts.iter().collect();
        let r = Refinement::new(&refs).unwrap();
        assert!(r.is_binary());
        assert_eq!(*r.ends.last().unwrap(), 1 << 18);
        let w = [0.2f32, 0.3, 0.5];
        let (mut a, mut b) = (MergedCut::default(), MergedCut::default());
        crate::merge(&[crate::Group { cuts: &refs, weights: &w }], &mut a).unwrap();
        merge_refined(&[Factor { refinement: &r, weights: &w }], &mut b).unwrap();
        assert_eq!(a, b);
        // A value that is neither 0 nor 1 (or −0) anywhere makes it keep values.
        for odd in [0.5f32, -0.0] {
            let mut c = binary_cut(12, 7);
            let last = c.len() - 1;
            c.values_mut()[last] = odd;
            let r = Refinement::new(&[&binary_cut(12, 8), &c]).unwrap();
            assert!(!r.is_binary());
            assert_eq!(r.values.len(), r.len() * 2);
        }
        // Nine members are more than a mask holds.
        let nine: Vec<Cut> = (0..9).map(|k| binary_cut(10, k)).collect();
        assert!(!Refinement::new(&nine.iter().collect::<Vec<_>>()).unwrap().is_binary());
    }
}
