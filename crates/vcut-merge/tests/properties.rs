//! The algebra of the merge, over random valid cuts from 2 to 65,536 leaves: the merged cut is
//! the pointwise operation on the expanded leaves, a valid cut, the coarsest common refinement
//! (up to whole zero nodes), commutative, bounded for convex weights, and identical to the
//! index-based baseline.

use proptest::prelude::*;
use vcut_cut::Cut;
use vcut_merge::baseline::{self, IndexCut, IndexGroup};
mod common;

use common::random_cut;
use vcut_merge::{
    Factor, Group, MergedCut, Refinement, merge, merge_product, merge_refined, merge_top_down, merge_weighted_sum,
};

/// `merge_refined` over the same groups (each refined here).
fn via_refined(groups: &[Group<'_>]) -> MergedCut {
    let refined: Vec<Refinement> = groups.iter().map(|g| Refinement::new(g.cuts).unwrap()).collect();
    let factors: Vec<Factor<'_>> =
        refined.iter().zip(groups).map(|(r, g)| Factor { refinement: r, weights: g.weights }).collect();
    let mut out = MergedCut::default();
    merge_refined(&factors, &mut out).unwrap();
    out
}

/// Start leaves of every node of the coarsest common refinement, plus the end.
fn ccr_boundaries(cuts: &[&Cut]) -> std::collections::BTreeSet<u64> {
    let mut b: std::collections::BTreeSet<u64> = cuts.iter().flat_map(|c| c.offsets()).collect();
    b.insert(1u64 << cuts[0].root_height());
    b
}

fn check_refinement(out: &MergedCut, inputs: &[&Cut]) {
    let cut = out.to_cut().unwrap();
    assert_eq!(cut.level_order_indices().collect::<Vec<_>>(), out.indices, "indices match heights");
    let b = ccr_boundaries(inputs);
    for ((off, &h), &v) in cut.offsets().zip(cut.heights()).zip(cut.values()) {
        let end = off + (1u64 << h);
        assert!(b.contains(&off) && b.contains(&end), "node [{off},{end}) cuts through an input node");
        if v != 0.0 {
            // A non-zero node is exactly one node of the refinement.
            assert_eq!(b.range(off + 1..end).count(), 0, "node [{off},{end}) is coarser than the refinement");
        }
    }
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-5 * (1.0 + a.abs().max(b.abs()))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn product_is_pointwise_valid_and_the_refinement(root in 1u32..=16, n in 1usize..6, seed in any::<u64>(), split in 0.3f32..0.95, zero in 0.0f32..0.4) {
        let cuts: Vec<Cut> = (0..n).map(|k| random_cut(root, seed.wrapping_add(k as u64 * 7919), split, zero, 0.2)).collect();
        let refs: Vec<&Cut> = cuts.iter().collect();
        let mut out = MergedCut::default();
        merge_product(&refs, &mut out).unwrap();
        let merged = out.to_cut().unwrap().expand();
        let leaves: Vec<Vec<f32>> = cuts.iter().map(Cut::expand).collect();
        for (i, m) in merged.iter().enumerate() {
            let p = leaves.iter().fold(1.0f32, |acc, l| acc * l[i]);
            prop_assert!(close(*m, p), "leaf {i}: merged {m}, pointwise {p}");
        }
        check_refinement(&out, &refs);
        // The baseline over index-coded cuts gives exactly the same cut.
        let icuts: Vec<IndexCut> = cuts.iter().map(IndexCut::from_cut).collect();
        let irefs: Vec<&IndexCut> = icuts.iter().collect();
        let groups: Vec<IndexGroup<'_>> = irefs.chunks(1).map(|c| IndexGroup { cuts: c, weights: &[1.0] }).collect();
        let mut base = MergedCut::default();
        baseline::merge(&groups, &mut base).unwrap();
        prop_assert_eq!(base, out);
    }

    #[test]
    fn product_commutes(root in 1u32..=14, seed in any::<u64>()) {
        let a = random_cut(root, seed, 0.7, 0.2, 0.2);
        let b = random_cut(root, seed ^ 0xabcdef, 0.7, 0.2, 0.2);
        let (mut ab, mut ba) = (MergedCut::default(), MergedCut::default());
        merge_product(&[&a, &b], &mut ab).unwrap();
        merge_product(&[&b, &a], &mut ba).unwrap();
        prop_assert_eq!(ab, ba);
    }

    #[test]
    fn convex_interpolation_stays_within_the_inputs(root in 1u32..=16, seed in any::<u64>(), raw in proptest::collection::vec(0.0f32..1.0, 8)) {
        let cuts: Vec<Cut> = (0..8).map(|k| random_cut(root, seed.wrapping_add(k), 0.6, 0.1, 0.3)).collect();
        let refs: Vec<&Cut> = cuts.iter().collect();
        let total: f32 = raw.iter().sum::<f32>() + 1e-3;
        let w: Vec<f32> = raw.iter().map(|x| (x + 1e-3 / 8.0) / total).collect();
        let mut out = MergedCut::default();
        merge_weighted_sum(&refs, &w, &mut out).unwrap();
        check_refinement(&out, &refs);
        let merged = out.to_cut().unwrap().expand();
        let leaves: Vec<Vec<f32>> = cuts.iter().map(Cut::expand).collect();
        for (i, m) in merged.iter().enumerate() {
            let (lo, hi) = leaves.iter().fold((f32::MAX, f32::MIN), |(lo, hi), l| (lo.min(l[i]), hi.max(l[i])));
            prop_assert!(*m >= lo - 1e-5 && *m <= hi + 1e-5, "leaf {i}: {m} outside [{lo}, {hi}]");
            let exact: f32 = leaves.iter().zip(&w).map(|(l, w)| l[i] * w).sum();
            prop_assert!(close(*m, exact));
        }
    }

    /// A frame's whole expression: SVC × interp(8 cuts) × interp(8 cuts), in one pass.
    #[test]
    /// With `binary`, the field cuts hold only 0 and 1 (exact fields), which the merge sums
    /// through a table of masks.
    fn frame_expression_in_one_pass(root in 1u32..=15, seed in any::<u64>(), binary in any::<bool>()) {
        let svc = random_cut(root, seed, 0.6, 0.4, 0.1);
        let (zero, one) = if binary { (0.4, 0.6) } else { (0.1, 0.6) };
        let fa: Vec<Cut> = (0..8).map(|k| random_cut(root, seed ^ (k + 1), 0.5, zero, one)).collect();
        let fb: Vec<Cut> = (0..8).map(|k| random_cut(root, seed ^ ((k + 1) << 20), 0.5, zero, one)).collect();
        if binary {
            prop_assert!(fa.iter().chain(&fb).all(|c| c.values().iter().all(|&v| v == 0.0 || v == 1.0)));
        }
        let (ra, rb): (Vec<&Cut>, Vec<&Cut>) = (fa.iter().collect(), fb.iter().collect());
        let wa = [0.05f32, 0.1, 0.15, 0.2, 0.1, 0.1, 0.2, 0.1];
        let wb = [0.125f32; 8];
        let svc_ref = &svc;
        let groups = [Group::single(&svc_ref), Group { cuts: &ra, weights: &wa }, Group { cuts: &rb, weights: &wb }];
        let mut out = MergedCut::default();
        merge(&groups, &mut out).unwrap();
        let merged = out.to_cut().unwrap().expand();
        let s = svc.expand();
        let la: Vec<Vec<f32>> = fa.iter().map(Cut::expand).collect();
        let lb: Vec<Vec<f32>> = fb.iter().map(Cut::expand).collect();
        for i in 0..merged.len() {
            let ia: f32 = la.iter().zip(&wa).map(|(l, w)| l[i] * w).sum();
            let ib: f32 = lb.iter().zip(&wb).map(|(l, w)| l[i] * w).sum();
            prop_assert!(close(merged[i], s[i] * ia * ib), "leaf {}", i);
        }
        let mut all: Vec<&Cut> = vec![&svc];
        all.extend(&ra);
        all.extend(&rb);
        check_refinement(&out, &all);
        // Baseline agrees exactly.
        let isvc = IndexCut::from_cut(&svc);
        let ia: Vec<IndexCut> = fa.iter().map(IndexCut::from_cut).collect();
        let ib: Vec<IndexCut> = fb.iter().map(IndexCut::from_cut).collect();
        let (ra2, rb2): (Vec<&IndexCut>, Vec<&IndexCut>) = (ia.iter().collect(), ib.iter().collect());
        let isvc_ref = [&isvc];
        let igroups = [IndexGroup { cuts: &isvc_ref, weights: &[1.0] }, IndexGroup { cuts: &ra2, weights: &wa }, IndexGroup { cuts: &rb2, weights: &wb }];
        let mut base = MergedCut::default();
        baseline::merge(&igroups, &mut base).unwrap();
        prop_assert_eq!(&base, &out);
        // So does the merge over cuts with precomputed ends.
        // So does the merge through each group's refinement.
        prop_assert_eq!(via_refined(&groups), out);
    }

    /// The merge through refinements is the counter merge to the bit over any mix of groups —
    /// single cuts, sums of up to 8 (binary or not), zero-heavy cuts whose zero nodes make it
    /// skip by search.
    #[test]
    fn refined_merge_is_the_counter_merge(root in 1u32..=16, seed in any::<u64>(), sizes in proptest::collection::vec(1usize..=8, 1..4), zero in 0.0f32..0.8, split in 0.3f32..0.9) {
        let cuts: Vec<Vec<Cut>> = sizes
            .iter()
            .enumerate()
            .map(|(g, &n)| (0..n).map(|k| random_cut(root, seed ^ ((g * 16 + k + 1) as u64).wrapping_mul(0x9e37), split, zero, 0.3)).collect())
            .collect();
        let refs: Vec<Vec<&Cut>> = cuts.iter().map(|g| g.iter().collect()).collect();
        let weights: Vec<Vec<f32>> = sizes.iter().map(|&n| (0..n).map(|k| (k as f32 + 1.0) / (n * (n + 1) / 2) as f32).collect()).collect();
        let groups: Vec<Group<'_>> = refs.iter().zip(&weights).map(|(c, w)| Group { cuts: c, weights: w }).collect();
        let mut out = MergedCut::default();
        merge(&groups, &mut out).unwrap();
        prop_assert_eq!(&via_refined(&groups), &out);
    }
}

#[test]
fn zero_svc_node_is_one_node_and_skips_the_fields() {
    // SVC: the left half (height 3 of H = 4) is zero; the field is all leaves there.
    let svc = Cut::new(4, vec![3, 2, 2], vec![0.0, 1.0, 0.5]).unwrap();
    let field = Cut::from_leaves(4, (0..16).map(|i| i as f32 / 16.0).collect()).unwrap();
    let mut out = MergedCut::default();
    let steps = merge_product(&[&svc, &field], &mut out).unwrap();
    assert_eq!(out.heights[0], 3, "the zero half is one node");
    assert_eq!(out.values[0], 0.0);
    assert_eq!(steps, 1 + 8);
    assert_eq!(out.indices[0], 1);
    assert_eq!(via_refined(&[Group::single(&&svc), Group::single(&&field)]), out);
}

#[test]
fn mismatched_inputs_are_errors() {
    let a = Cut::root(3, 1.0).unwrap();
    let b = Cut::root(4, 1.0).unwrap();
    let mut out = MergedCut::default();
    assert_eq!(merge_product(&[&a, &b], &mut out), Err(vcut_merge::MergeError::RootHeights(3, 4)));
    assert!(matches!(merge_weighted_sum(&[&a], &[0.5, 0.5], &mut out), Err(vcut_merge::MergeError::Weights { .. })));
    assert_eq!(merge_product(&[], &mut out), Err(vcut_merge::MergeError::Empty));
}

/// The coarsest cut of leaf values (a node of one value where its sibling differs): what a
/// top-down walk of them builds.
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

/// For random S and F (F asked through its leaves, answering for a node only where it has one
/// value over it and a coin says so, as a conservative test would), the top-down product
/// against the counter merge of S and F's walked cut: the same non-zero nodes bit for bit, the
/// same leaves, never more nodes.
#[test]
fn the_top_down_product_has_the_counter_merges_non_zero_nodes_and_leaves() {
    let mut zeros_saved = 0;
    for root in [1, 4, 9, 12] {
        for seed in 0..12u64 {
            let s = random_cut(root, seed, 0.8, 0.3, 0.5);
            let leaves = random_cut(root, seed * 7 + 3, 0.7, 0.3, 0.5).expand();
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
            let f = Refinement::new(&[&coarsest(root, &leaves)]).unwrap();
            let mut full = MergedCut::default();
            let factors = [&svc, &f].map(|r| Factor { refinement: r, weights: &[1.0] });
            merge_refined(&factors, &mut full).unwrap();
            let (a, b) = (top.to_cut().unwrap().expand(), full.to_cut().unwrap().expand());
            assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()), "root {root}, seed {seed}");
            let nonzero = |m: &MergedCut| -> Vec<(u32, u32)> {
                m.indices.iter().zip(&m.values).filter(|(_, v)| **v != 0.0).map(|(i, v)| (*i, v.to_bits())).collect()
            };
            assert_eq!(nonzero(&top), nonzero(&full), "root {root}, seed {seed}");
            // Zeros in the largest nodes they fill: never more nodes than the counter merge.
            assert!(top.heights.len() <= full.heights.len(), "root {root}, seed {seed}");
            zeros_saved += full.heights.len() - top.heights.len();
        }
    }
    // Some of the counter merge's zero ranges are in more nodes than they need.
    assert!(zeros_saved > 0);
}
