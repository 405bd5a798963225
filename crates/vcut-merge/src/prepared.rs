//! The merge seam: one way for a caller to merge a product of weighted sums whichever
//! [`Algorithm`] it runs. A group of cuts (a vertex's SVC, a field cell's samples) is
//! [prepared](Algorithm::prepare) once — refined for the counter merge, index-coded for the
//! baseline — and the prepared groups are then merged by [`merge_prepared`] with per-merge
//! weights, as many times as the caller needs. Both algorithms give the same cut to the bit
//! (tested), so a caller has one code path and times either.
//!
//! # Example
//! ```
//! use vcut_cut::Cut;
//! use vcut_merge::{Algorithm, MergedCut, merge_prepared};
//! let svc = Cut::new(2, vec![1, 1], vec![1.0, 0.0]).unwrap();
//! let field = [Cut::new(2, vec![2], vec![1.0]).unwrap(), Cut::new(2, vec![1, 1], vec![0.0, 1.0]).unwrap()];
//! let mut cuts = [MergedCut::default(), MergedCut::default()];
//! for (algorithm, out) in [Algorithm::Counter, Algorithm::Index].into_iter().zip(&mut cuts) {
//!     let svc = algorithm.prepare(&[&svc]).unwrap();
//!     let cell = algorithm.prepare(&[&field[0], &field[1]]).unwrap();
//!     merge_prepared(&[(&svc, &[1.0]), (&cell, &[0.5, 0.5])], out).unwrap();
//! }
//! assert_eq!(cuts[0], cuts[1]);
//! assert_eq!(cuts[0].values, vec![0.5, 0.0]);
//! ```

use crate::baseline::{self, IndexCut, IndexGroup};
use crate::refined::{Factor, Refinement, merge_refined};
use crate::{MergeError, MergedCut};
use std::borrow::Cow;
use vcut_cut::Cut;

/// Which merge runs. Both give the same merged cut bit for bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Algorithm {
    /// The paper's counter merge over height-coded cuts, through refinements: a group's cuts
    /// are merged once into their common [`Refinement`], then every merge takes a few
    /// refinements ([`merge_refined`]).
    #[default]
    Counter,
    /// The index baseline (Cheslack-Postava 2008 style): a group's cuts converted to level-order
    /// indices, merged by "advance until nested" ([`baseline::merge`]).
    Index,
}

/// A group of cuts of one tree prepared for [`merge_prepared`] by an [`Algorithm`].
#[derive(Debug, Clone, PartialEq)]
pub enum Prepared {
    /// For [`Algorithm::Counter`]: the group's common refinement.
    Refined(Refinement),
    /// For [`Algorithm::Index`]: the group's cuts in index form.
    Indexed(Vec<IndexCut>),
}

impl Default for Prepared {
    fn default() -> Prepared {
        Prepared::Refined(Refinement::default())
    }
}

impl Algorithm {
    /// `cuts` (one or more cuts of one tree) prepared for this algorithm's merge.
    pub fn prepare(self, cuts: &[&Cut]) -> Result<Prepared, MergeError> {
        let mut p = Prepared::default();
        self.prepare_into(cuts, &mut p)?;
        Ok(p)
    }

    /// Makes `into` the preparation of `cuts`, reusing its buffers where it already has this
    /// algorithm's form.
    pub fn prepare_into(self, cuts: &[&Cut], into: &mut Prepared) -> Result<(), MergeError> {
        if cuts.is_empty() {
            return Err(MergeError::Empty);
        }
        match (self, &mut *into) {
            (Algorithm::Counter, Prepared::Refined(r)) => r.rebuild(cuts),
            (Algorithm::Counter, _) => {
                *into = Prepared::Refined(Refinement::new(cuts)?);
                Ok(())
            }
            (Algorithm::Index, _) => {
                let first = cuts[0].root_height();
                if let Some(c) = cuts.iter().find(|c| c.root_height() != first) {
                    return Err(MergeError::RootHeights(first, c.root_height()));
                }
                *into = Prepared::Indexed(cuts.iter().map(|c| IndexCut::from_cut(c)).collect());
                Ok(())
            }
        }
    }
}

impl Prepared {
    /// The algorithm that prepared it.
    pub fn algorithm(&self) -> Algorithm {
        match self {
            Prepared::Refined(_) => Algorithm::Counter,
            Prepared::Indexed(_) => Algorithm::Index,
        }
    }

    /// The leaf where each node of the group's common refinement ends, left to right (for a
    /// one-cut group, the cut's node ends). Borrowed from a refinement, computed from indices.
    pub fn ends(&self) -> Cow<'_, [u32]> {
        match self {
            Prepared::Refined(r) => Cow::Borrowed(r.ends()),
            Prepared::Indexed(cuts) => {
                let root = cuts.first().map_or(0, IndexCut::root_height);
                let mut ends: Vec<u32> = cuts
                    .iter()
                    .flat_map(|c| c.indices().iter().map(move |&i| baseline::node_end(root, i) as u32))
                    .collect();
                ends.sort_unstable();
                ends.dedup();
                Cow::Owned(ends)
            }
        }
    }

    /// Appends to `out` the leaf ranges where every cut of the group is zero, in leaf order
    /// with consecutive ranges joined ([`Refinement::zero_runs`]): where a product with this
    /// group's weighted sum is zero whatever else it multiplies.
    pub fn zero_runs(&self, out: &mut Vec<std::ops::Range<u32>>) {
        match self {
            Prepared::Refined(r) => r.zero_runs(out),
            Prepared::Indexed(cuts) => {
                let mut common: Option<Vec<std::ops::Range<u32>>> = None;
                for c in cuts {
                    let mut runs = Vec::new();
                    for (&i, &v) in c.indices().iter().zip(c.values()) {
                        if v == 0.0 {
                            let (h, start) = vcut_cut::node_of_index(c.root_height(), i);
                            crate::push_run(&mut runs, start..start + (1 << h));
                        }
                    }
                    common = Some(match common {
                        None => runs,
                        Some(a) => intersect(&a, &runs),
                    });
                }
                out.extend(common.unwrap_or_default());
            }
        }
    }

    /// Bytes held (for memory accounting).
    pub fn bytes(&self) -> usize {
        match self {
            Prepared::Refined(r) => r.bytes(),
            Prepared::Indexed(cuts) => {
                cuts.iter().map(|c| c.indices().len() * 4 + c.values().len() * 4).sum::<usize>()
                    + cuts.capacity() * std::mem::size_of::<IndexCut>()
            }
        }
    }
}

/// Merges `Π_f Σ_i w_i · member_i` over prepared groups `(group, weights)` into `out` (cleared
/// first): [`crate::merge`]'s cut for the same groups, by the algorithm that prepared them (all
/// must share one; [`MergeError::Mixed`] otherwise). Returns the number of emitted nodes.
pub fn merge_prepared(factors: &[(&Prepared, &[f32])], out: &mut MergedCut) -> Result<usize, MergeError> {
    let algorithm = factors.first().ok_or(MergeError::Empty)?.0.algorithm();
    if let Some(g) = factors.iter().position(|(p, _)| p.algorithm() != algorithm) {
        return Err(MergeError::Mixed { group: g });
    }
    match algorithm {
        Algorithm::Counter => {
            let refined: Vec<Factor<'_>> = factors
                .iter()
                .map(|&(p, weights)| match p {
                    Prepared::Refined(refinement) => Factor { refinement, weights },
                    Prepared::Indexed(_) => unreachable!("checked above"),
                })
                .collect();
            merge_refined(&refined, out)
        }
        Algorithm::Index => {
            let refs: Vec<Vec<&IndexCut>> = factors
                .iter()
                .map(|(p, _)| match p {
                    Prepared::Indexed(cuts) => cuts.iter().collect(),
                    Prepared::Refined(_) => unreachable!("checked above"),
                })
                .collect();
            let groups: Vec<IndexGroup<'_>> =
                refs.iter().zip(factors).map(|(cuts, &(_, weights))| IndexGroup { cuts, weights }).collect();
            baseline::merge(&groups, out)
        }
    }
}

/// The leaf ranges in both sorted, disjoint lists of ranges.
fn intersect(a: &[std::ops::Range<u32>], b: &[std::ops::Range<u32>]) -> Vec<std::ops::Range<u32>> {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < a.len() && j < b.len() {
        let (start, end) = (a[i].start.max(b[j].start), a[i].end.min(b[j].end));
        if start < end {
            crate::push_run(&mut out, start..end);
        }
        if a[i].end <= b[j].end {
            i += 1;
        } else {
            j += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cut(h: u32, heights: &[u8], values: &[f32]) -> Cut {
        Cut::new(h, heights.to_vec(), values.to_vec()).unwrap()
    }

    #[test]
    fn both_algorithms_give_the_group_merge_and_the_same_ends() {
        let a = cut(3, &[1, 0, 0, 2], &[1.0, 0.0, 1.0, 0.5]);
        let b = cut(3, &[2, 1, 1], &[1.0, 0.25, 0.0]);
        let c = cut(3, &[0, 0, 1, 2], &[0.0, 1.0, 1.0, 1.0]);
        let mut expected = MergedCut::default();
        let a_ref = &a;
        let groups = [crate::Group::single(&a_ref), crate::Group { cuts: &[&b, &c], weights: &[0.75, 0.25] }];
        crate::merge(&groups, &mut expected).unwrap();
        for algorithm in [Algorithm::Counter, Algorithm::Index] {
            let svc = algorithm.prepare(&[&a]).unwrap();
            let cell = algorithm.prepare(&[&b, &c]).unwrap();
            let mut out = MergedCut::default();
            merge_prepared(&[(&svc, &[1.0]), (&cell, &[0.75, 0.25])], &mut out).unwrap();
            assert_eq!(out, expected, "{algorithm:?}");
            assert_eq!(&*svc.ends(), &[2, 3, 4, 8], "{algorithm:?}");
            assert_eq!(&*cell.ends(), &[1, 2, 4, 6, 8], "{algorithm:?}");
        }
    }

    #[test]
    #[allow(clippy::single_range_in_vec_init)] // lists of leaf ranges, some of one range
    fn zero_runs_are_where_every_member_is_zero() {
        let joined = cut(3, &[1, 1, 2], &[0.0, -0.0, 1.0]);
        let b = cut(3, &[2, 1, 1], &[1.0, 0.25, 0.0]);
        let d = cut(3, &[2, 2], &[1.0, 0.0]);
        let binary = cut(3, &[0, 0, 1, 2], &[0.0, 0.0, 1.0, 0.0]);
        let other = cut(3, &[1, 0, 0, 2], &[0.0, 1.0, 0.0, 0.0]);
        let cases: [(&[&Cut], &[std::ops::Range<u32>]); 5] = [
            (&[&joined], &[0..4]),
            (&[&b, &d], &[6..8]),
            (&[&binary, &other], &[0..2, 4..8]),
            (&[&b, &binary], &[6..8]),
            (&[&b, &joined], &[]),
        ];
        for algorithm in [Algorithm::Counter, Algorithm::Index] {
            for (cuts, expected) in cases {
                let mut runs = vec![];
                algorithm.prepare(cuts).unwrap().zero_runs(&mut runs);
                assert_eq!(runs, expected, "{algorithm:?}, {} cuts", cuts.len());
            }
        }
    }

    #[test]
    fn mixed_preparations_and_bad_groups_are_errors() {
        let a = cut(2, &[2], &[1.0]);
        let b = cut(3, &[3], &[1.0]);
        let counter = Algorithm::Counter.prepare(&[&a]).unwrap();
        let index = Algorithm::Index.prepare(&[&a]).unwrap();
        let mut out = MergedCut::default();
        assert_eq!(
            merge_prepared(&[(&counter, &[1.0]), (&index, &[1.0])], &mut out),
            Err(MergeError::Mixed { group: 1 })
        );
        assert_eq!(merge_prepared(&[], &mut out), Err(MergeError::Empty));
        assert!(matches!(
            merge_prepared(&[(&index, &[1.0, 2.0])], &mut out),
            Err(MergeError::Weights { group: 0, weights: 2, cuts: 1 })
        ));
        for algorithm in [Algorithm::Counter, Algorithm::Index] {
            assert_eq!(algorithm.prepare(&[&a, &b]), Err(MergeError::RootHeights(2, 3)));
            assert_eq!(algorithm.prepare(&[]), Err(MergeError::Empty));
        }
        // Reuse keeps the form of the algorithm asked for.
        let mut p = index.clone();
        Algorithm::Counter.prepare_into(&[&a], &mut p).unwrap();
        assert_eq!(p, counter);
    }
}
