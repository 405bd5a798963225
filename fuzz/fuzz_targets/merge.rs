//! Fuzz target: merging arbitrary valid cuts never panics and satisfies the invariants — the
//! result is a valid cut, equals the pointwise product on the leaves, and the index baseline
//! gives the same cut, and so does the merge through refinements.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vcut_cut::Cut;
use vcut_merge::baseline::{self, IndexCut, IndexGroup};
use vcut_merge::{Factor, Group, MergedCut, Refinement, merge, merge_product, merge_refined};

/// Builds a valid cut of root height `root` from bytes: each byte decides split / leaf and value.
fn cut_from(bytes: &mut impl Iterator<Item = u8>, root: u32) -> Cut {
    let mut heights = Vec::new();
    let mut values = Vec::new();
    let mut stack = vec![root];
    while let Some(h) = stack.pop() {
        let b = bytes.next().unwrap_or(0);
        if h > 0 && b & 1 == 1 {
            stack.extend([h - 1, h - 1]);
        } else {
            heights.push(h as u8);
            values.push(match b >> 6 {
                0 => 0.0,
                1 => 1.0,
                _ => f32::from(b >> 1) / 127.0,
            });
        }
    }
    Cut::new(root, heights, values).expect("depth-first splits make a valid cut")
}

fuzz_target!(|data: &[u8]| {
    let Some((&head, rest)) = data.split_first() else { return };
    let root = u32::from(head % 11);
    let n = usize::from(head >> 4) % 5 + 1;
    let mut bytes = rest.iter().copied();
    let cuts: Vec<Cut> = (0..n).map(|_| cut_from(&mut bytes, root)).collect();
    let refs: Vec<&Cut> = cuts.iter().collect();
    let mut out = MergedCut::default();
    merge_product(&refs, &mut out).expect("same root heights");
    let merged = out.to_cut().expect("a valid cut");
    let leaves: Vec<Vec<f32>> = cuts.iter().map(Cut::expand).collect();
    for (i, m) in merged.expand().iter().enumerate() {
        let p = leaves.iter().fold(1.0f32, |a, l| a * l[i]);
        assert!((m - p).abs() <= 1e-5, "leaf {i}: {m} vs {p}");
    }
    let icuts: Vec<IndexCut> = cuts.iter().map(IndexCut::from_cut).collect();
    let irefs: Vec<&IndexCut> = icuts.iter().collect();
    let groups: Vec<IndexGroup<'_>> = irefs.chunks(1).map(|c| IndexGroup { cuts: c, weights: &[1.0] }).collect();
    let mut base = MergedCut::default();
    baseline::merge(&groups, &mut base).expect("same root heights");
    assert_eq!(base, out);
    // Through refinements: every cut alone, then all of them as one weighted sum (binary cuts
    // take the mask path, others keep values).
    let alone: Vec<Refinement> = refs.iter().map(|&c| Refinement::new(&[c]).expect("one cut")).collect();
    let factors: Vec<Factor<'_>> = alone.iter().map(|r| Factor { refinement: r, weights: &[1.0] }).collect();
    let mut refined = MergedCut::default();
    merge_refined(&factors, &mut refined).expect("same root heights");
    assert_eq!(refined, out);
    let weights: Vec<f32> = (1..=n).map(|k| k as f32 / 16.0).collect();
    merge(&[Group { cuts: &refs, weights: &weights }], &mut out).expect("same root heights");
    let all = Refinement::new(&refs).expect("same root heights");
    merge_refined(&[Factor { refinement: &all, weights: &weights }], &mut refined).expect("same root heights");
    assert_eq!(refined, out);
});
