//! Merges commute with turns: over a wedged tree (`vcut_cut::turn`), the product and the
//! weighted sum of cuts turned by whole wedges are their merge turned, bit for bit, so a frame
//! may relabel a turned object's cuts before merging or the merge after.

use proptest::prelude::*;
use vcut_cut::Cut;
use vcut_cut::turn::TurnShape;
use vcut_merge::{Algorithm, MergedCut, merge_product, merge_weighted_sum};
mod common;

use common::random_cut;

fn merged(cuts: &[Cut], weights: Option<&[f32]>) -> Cut {
    let refs: Vec<&Cut> = cuts.iter().collect();
    let mut out = MergedCut::default();
    match weights {
        Some(w) => merge_weighted_sum(&refs, w, &mut out).unwrap(),
        None => merge_product(&refs, &mut out).unwrap(),
    };
    out.to_cut().unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn the_merge_of_turned_cuts_is_the_turned_merge(
        root in 4u32..=12,
        wedge_levels in 1u32..=4,
        band_levels in 0u32..=3,
        n in 1usize..6,
        seed in any::<u64>(),
        split in 0.3f32..0.95,
        zero in 0.0f32..0.4,
        steps in 0u32..40,
    ) {
        let band_height = root.saturating_sub(band_levels).max(wedge_levels);
        let shape = TurnShape { wedge_height: band_height - wedge_levels, band_height };
        let cuts: Vec<Cut> = (0..n)
            .map(|k| random_cut(root, seed.wrapping_add(k as u64 * 7919), split, zero, 0.2).turnable(shape))
            .collect();
        let turned: Vec<Cut> = cuts.iter().map(|c| c.turned(shape, steps).unwrap()).collect();
        let weights: Vec<f32> = (0..n).map(|k| (k as f32 + 1.0) / (n * (n + 1) / 2) as f32).collect();
        for w in [None, Some(&weights[..])] {
            let whole = merged(&cuts, w);
            prop_assert_eq!(merged(&turned, w), whole.turned(shape, steps).unwrap());
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn a_prepared_group_turned_is_the_group_of_its_cuts_turned(
        root in 4u32..=12,
        wedge_levels in 1u32..=4,
        band_levels in 0u32..=3,
        n in 1usize..4,
        seed in any::<u64>(),
        split in 0.3f32..0.95,
        zero in 0.0f32..0.4,
        binary in 0.0f32..1.0,
        steps in 0u32..40,
        more in 0u32..40,
    ) {
        let band_height = root.saturating_sub(band_levels).max(wedge_levels);
        let shape = TurnShape { wedge_height: band_height - wedge_levels, band_height };
        let cuts: Vec<Cut> = (0..n)
            .map(|k| random_cut(root, seed.wrapping_add(k as u64 * 7919), split, zero, binary).turnable(shape))
            .collect();
        let refs: Vec<&Cut> = cuts.iter().collect();
        let turned: Vec<Cut> = cuts.iter().map(|c| c.turned(shape, steps).unwrap()).collect();
        let turned_refs: Vec<&Cut> = turned.iter().collect();
        let group = Algorithm::Counter.prepare(&refs).unwrap();
        prop_assert_eq!(&group.turned(shape, steps).unwrap(), &Algorithm::Counter.prepare(&turned_refs).unwrap());
        // Turns compose.
        let twice = group.turned(shape, steps).unwrap().turned(shape, more).unwrap();
        prop_assert_eq!(twice, group.turned(shape, steps + more).unwrap());
        prop_assert!(Algorithm::Index.prepare(&refs).unwrap().turned(shape, steps).is_err());
    }
}

#[test]
fn a_group_with_a_node_across_wedges_does_not_turn() {
    let shape = TurnShape { wedge_height: 1, band_height: 3 };
    // Root 3: one node of height 2 spans two of the four wedges.
    let cut = Cut::new(3, vec![2, 1, 1], vec![0.5, 1.0, 0.0]).unwrap();
    let group = Algorithm::Counter.prepare(&[&cut]).unwrap();
    assert!(matches!(group.turned(shape, 1), Err(vcut_merge::turn::TurnError::AboveWedges { node: 0, height: 2 })));
    let later = Cut::new(3, vec![1, 1, 2], vec![0.5, 1.0, 0.0]).unwrap();
    let group = Algorithm::Counter.prepare(&[&later]).unwrap();
    assert!(matches!(group.turned(shape, 1), Err(vcut_merge::turn::TurnError::AboveWedges { node: 2, height: 2 })));
}
