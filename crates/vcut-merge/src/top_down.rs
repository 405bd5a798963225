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
    use vcut_cut::Cut;

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
