//! A product with a cut known top-down: `S × F` where `S` is one cut (a vertex's SVC, refined)
//! and `F` is not stored but answered node by node — "is every leaf of this node one value?" —
//! as an occluder's exact cut is ([`merge_top_down`]). Walking the tree once for both skips
//! what a stored `F` costs a merge: `F`'s nodes where `S` is zero are never asked for, and no
//! second cursor runs beside `S`'s.
//!
//! # Example
//! ```
//! use vcut_cut::Cut;
//! use vcut_merge::{MergedCut, Refinement, merge_top_down};
//! // S: the left half 0.5, the right half zero; F: 1 on the first leaf only.
//! let svc = Refinement::new(&[&Cut::new(2, vec![1, 1], vec![0.5, 0.0]).unwrap()]).unwrap();
//! let mut out = MergedCut::default();
//! // F answers for no inner node here: its leaves decide.
//! merge_top_down(&svc, |_index, _h, _offset| None, |leaf| if leaf == 0 { 1.0 } else { 0.0 }, &mut out).unwrap();
//! assert_eq!(out.heights, vec![0, 0, 1]);
//! assert_eq!(out.values, vec![0.5, 0.0, 0.0]);
//! ```

use crate::{MergeError, MergedCut, Refinement};

/// Merges `S × F` into `out` (cleared first): `svc` is a one-cut refinement (`S`) and `F` is a
/// cut of the same tree answered top-down — `node(index, h, offset)` gives `Some(v)` when every
/// leaf of the node (level-order `index`, height `h`, first leaf `offset`) has value `v` under
/// `F` and `None` when they differ or it cannot tell; `leaf(offset)` gives a leaf's value.
///
/// `F`'s cut is what that walk builds: a node where `node` answers, else its children, two
/// children of one value joined. Against [`crate::merge_refined`] of `S` and that cut, both
/// weighted 1, the result takes the same value at every leaf and has the same non-zero nodes,
/// each with the same bits (tested); its zeros come in the largest nodes they fill, so never
/// in more nodes than there (`F` is not asked about a zero of `S` at all). Returns the number
/// of emitted nodes.
pub fn merge_top_down(
    svc: &Refinement,
    node: impl FnMut(u32, u32, u32) -> Option<f32>,
    leaf: impl FnMut(u32) -> f32,
    out: &mut MergedCut,
) -> Result<usize, MergeError> {
    let values = svc.single_values().ok_or(MergeError::Weights { group: 0, weights: 1, cuts: svc.members() })?;
    if svc.is_empty() {
        return Err(MergeError::Empty);
    }
    let root = svc.root_height();
    out.reset(root);
    let mut walk = Walk { ends: svc.ends(), values, j: 0, node, leaf, out };
    walk.visit(0, root, 0);
    Ok(out.heights.len())
}

struct Walk<'a, N, L> {
    ends: &'a [u32],
    values: &'a [f32],
    /// `S`'s node holding the visited node's first leaf (nodes come in leaf order).
    j: usize,
    node: N,
    leaf: L,
    out: &'a mut MergedCut,
}

impl<N: FnMut(u32, u32, u32) -> Option<f32>, L: FnMut(u32) -> f32> Walk<'_, N, L> {
    /// Whether S is zero from the current node on up to leaf `end`.
    fn zero_through(&self, end: u32) -> bool {
        let mut k = self.j;
        while self.values[k] == 0.0 {
            if self.ends[k] >= end {
                return true;
            }
            k += 1;
        }
        false
    }

    /// Emits the product over node `index` (height `h`, first leaf `offset`); returns its value
    /// when that is one node.
    fn visit(&mut self, index: u32, h: u32, offset: u32) -> Option<f32> {
        while self.ends[self.j] <= offset {
            self.j += 1;
        }
        let end = offset + (1 << h);
        // Within one node of S (reached by descent, the node is S's own or lies inside it).
        let within = self.ends[self.j] >= end;
        if within {
            let s = self.values[self.j];
            let f = if s == 0.0 {
                Some(0.0)
            } else if h == 0 {
                Some((self.leaf)(offset))
            } else {
                (self.node)(index, h, offset)
            };
            if let Some(f) = f {
                let v = product(s, f);
                self.out.push(h, u64::from(offset), v);
                return Some(v);
            }
        } else if self.zero_through(end) {
            // Over several nodes of S, all zero.
            self.out.push(h, u64::from(offset), 0.0);
            return Some(0.0);
        } else if let Some(f) = (self.node)(index, h, offset) {
            // F one value over several nodes of S: zero, or S's nodes times it.
            if f == 0.0 {
                self.out.push(h, u64::from(offset), 0.0);
                return Some(0.0);
            }
            let mut start = offset;
            while start < end {
                let e = self.ends[self.j];
                self.out.push((e - start).trailing_zeros(), u64::from(start), product(self.values[self.j], f));
                start = e;
                self.j += 1;
            }
            self.j -= 1;
            return None;
        }
        let start = self.out.heights.len();
        let a = self.visit(2 * index + 1, h - 1, offset);
        let b = self.visit(2 * index + 2, h - 1, offset + (1 << (h - 1)));
        match (a, b) {
            // Equal children within one node of S are F's node; zeros join anywhere.
            (Some(a), Some(b)) if a == b && (within || a == 0.0) => {
                self.out.truncate(start);
                self.out.push(h, u64::from(offset), a);
                Some(a)
            }
            _ => None,
        }
    }
}

/// A node's value as the counter merge forms it with weights 1: `1 · (0 + 1·s) · (0 + 1·f)`,
/// a zero unsigned.
#[inline]
fn product(s: f32, f: f32) -> f32 {
    let v = 1.0f32 * (0.0 + 1.0 * s) * (0.0 + 1.0 * f);
    if v == 0.0 { 0.0 } else { v }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Factor, merge_refined};
    use vcut_cut::Cut;

    /// A cut of root height `root` from a seed: splits and values (from `vals`) by an LCG.
    fn cut(root: u32, mut seed: u64, vals: &[f32]) -> Cut {
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
                values.push(vals[next() as usize % vals.len()]);
            }
        }
        Cut::new(root, heights, values).unwrap()
    }

    /// For random S and F (F asked through its leaves, answering for a node only where F's
    /// cut has one value over it and a coin says so, as a conservative test would), the
    /// top-down product against the counter merge of S and F's walked cut.
    #[test]
    fn the_non_zero_nodes_and_every_leaf_are_the_counter_merges() {
        let mut nodes_saved = 0;
        for root in [1, 4, 9, 12] {
            for seed in 0..12u64 {
                let s = cut(root, seed, &[0.0, 0.25, 0.7, 1.0, 0.0]);
                let f = cut(root, seed * 7 + 3, &[0.0, 1.0, 0.5]);
                let leaves = f.expand();
                let uniform = |h: u32, offset: u32| {
                    let l = &leaves[offset as usize..(offset + (1 << h)) as usize];
                    l.iter().all(|v| *v == l[0]).then_some(l[0])
                };
                let mut coin = seed;
                let node = |_: u32, h: u32, offset: u32| {
                    coin = coin.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                    uniform(h, offset).filter(|_| (coin >> 40) % 3 != 0)
                };
                let svc = Refinement::new(&[&s]).unwrap();
                let mut top = MergedCut::default();
                let n = merge_top_down(&svc, node, |l| leaves[l as usize], &mut top).unwrap();
                assert_eq!(n, top.heights.len());
                // F's walked cut where it can differ from `f`'s: the coarsest of its leaves.
                let walked = coarsest(root, &leaves);
                let mut full = MergedCut::default();
                let fr = Refinement::new(&[&walked]).unwrap();
                merge_refined(
                    &[Factor { refinement: &svc, weights: &[1.0] }, Factor { refinement: &fr, weights: &[1.0] }],
                    &mut full,
                )
                .unwrap();
                let (a, b) = (top.to_cut().unwrap(), full.to_cut().unwrap());
                let (ea, eb) = (a.expand(), b.expand());
                assert!(ea.iter().zip(&eb).all(|(x, y)| x.to_bits() == y.to_bits()), "root {root}, seed {seed}");
                let nonzero = |m: &MergedCut| -> Vec<(u32, u32)> {
                    m.indices
                        .iter()
                        .zip(&m.values)
                        .filter(|(_, v)| **v != 0.0)
                        .map(|(i, v)| (*i, v.to_bits()))
                        .collect()
                };
                assert_eq!(nonzero(&top), nonzero(&full), "root {root}, seed {seed}");
                // Zeros in the largest nodes they fill: never more nodes than the counter merge.
                assert!(top.heights.len() <= full.heights.len(), "root {root}, seed {seed}");
                let zero = |m: &MergedCut| m.values.iter().filter(|v| **v == 0.0).count();
                nodes_saved += zero(&full) - zero(&top);
            }
        }
        // Some of the counter merge's zero ranges are in more nodes than they need.
        assert!(nodes_saved > 0);
    }

    /// The coarsest cut of leaf values (every node of one value where its sibling differs).
    fn coarsest(root: u32, leaves: &[f32]) -> Cut {
        fn walk(h: u32, offset: usize, leaves: &[f32], heights: &mut Vec<u8>, values: &mut Vec<f32>) {
            let l = &leaves[offset..offset + (1 << h)];
            if l.iter().all(|v| *v == l[0]) {
                heights.push(h as u8);
                values.push(l[0]);
            } else {
                walk(h - 1, offset, leaves, heights, values);
                walk(h - 1, offset + (1 << (h - 1)), leaves, heights, values);
            }
        }
        let (mut heights, mut values) = (Vec::new(), Vec::new());
        walk(root, 0, leaves, &mut heights, &mut values);
        Cut::new(root, heights, values).unwrap()
    }

    #[test]
    fn only_a_one_cut_refinement_is_a_top_down_factor() {
        let a = Cut::new(2, vec![1, 1], vec![1.0, 0.0]).unwrap();
        let two = Refinement::new(&[&a, &a]).unwrap();
        let err = merge_top_down(&two, |_, _, _| Some(1.0), |_| 1.0, &mut MergedCut::default()).unwrap_err();
        assert_eq!(err, MergeError::Weights { group: 0, weights: 1, cuts: 2 });
        assert_eq!(
            merge_top_down(&Refinement::default(), |_, _, _| Some(1.0), |_| 1.0, &mut MergedCut::default()),
            Err(MergeError::Weights { group: 0, weights: 1, cuts: 0 })
        );
    }
}
