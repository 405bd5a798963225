//! The wedged tree of a symmetric direction set: a turn by whole wedges relabels its nodes.

use glam::{Quat, Vec3};
use vcut_dirtree::{DirectionTree, TreeError, TurnShape};
use vcut_sphere::{DirectionSet, RepulsionParams};

fn tree(n: usize, wedges: u32, bands: u32) -> DirectionTree {
    let set = DirectionSet::generate(n, &RepulsionParams { wedges, ..RepulsionParams::default() }, |_, _| {}).unwrap();
    let tree = DirectionTree::build_wedged(set.directions(), &set.cell_areas(), wedges, bands).unwrap();
    tree.validate().unwrap();
    tree
}

#[test]
fn a_turn_by_whole_wedges_maps_every_node_onto_its_turned_directions() {
    let (n, m) = (4096usize, 64u32);
    for bands in [1, 4] {
        let t = tree(n, m, bands);
        let shape = t.turn_shape().unwrap();
        assert_eq!(
            shape,
            TurnShape { wedge_height: 6 - bands.trailing_zeros(), band_height: 12 - bands.trailing_zeros() }
        );
        assert_eq!(t.wedges(), m);
        let step = std::f32::consts::TAU / m as f32;
        for steps in [1u32, 2, 5, 63] {
            let q = Quat::from_rotation_y(steps as f32 * step);
            for k in 0..t.node_count() as u32 {
                let (h, _) = t.node(k);
                let Some(image) = t.turn(k, steps) else {
                    assert!(shape.splits(h), "node {k} of height {h} has no image");
                    continue;
                };
                // Leaf for leaf, the image holds the turned directions; a band or more holds
                // the same directions in another order.
                if h >= shape.band_height {
                    assert_eq!(image, k);
                } else {
                    for (a, b) in t.leaf_range(k).zip(t.leaf_range(image)) {
                        let (d, e) = (t.leaf_directions()[a], t.leaf_directions()[b]);
                        assert!((q * d).distance(e) < 2e-6, "node {k} leaf {a}: {} vs {e}", q * d);
                    }
                    assert!((q * t.mean_direction(k)).distance(t.mean_direction(image)) < 1e-5);
                    assert_eq!(t.solid_angle(k), t.solid_angle(image));
                }
                // Children turn with their parent where they have images.
                if h > 0 && h <= shape.wedge_height {
                    assert_eq!(t.turn(2 * k + 1, steps), Some(2 * image + 1));
                }
            }
        }
        // M single steps come back to every node.
        for k in (0..t.node_count() as u32).filter(|&k| !shape.splits(t.node(k).0)) {
            assert_eq!((0..m).fold(k, |at, _| t.turn(at, 1).unwrap()), k);
        }
        // Bands are latitude bands: each holds heights no other band reaches past.
        let band = 1usize << shape.band_height;
        let ys: Vec<(f32, f32)> = t
            .leaf_directions()
            .chunks(band)
            .map(|c| c.iter().fold((f32::MAX, f32::MIN), |(lo, hi), d| (lo.min(d.y), hi.max(d.y))))
            .collect();
        assert!(ys.windows(2).all(|w| w[0].0 >= w[1].1), "{ys:?}");
    }
}

#[test]
fn an_ordinary_tree_has_one_wedge_and_bad_wedges_are_refused() {
    let set = DirectionSet::generate(256, &RepulsionParams::default(), |_, _| {}).unwrap();
    let t = DirectionTree::build(set.directions(), &set.cell_areas()).unwrap();
    assert_eq!((t.wedges(), t.turn_shape()), (1, None));
    assert_eq!(t.turn(5, 1), Some(5), "a turn of a whole circle");
    let dirs: Vec<Vec3> = set.directions().to_vec();
    for (wedges, bands) in [(0, 1), (3, 1), (512, 1), (4, 3), (64, 8)] {
        assert_eq!(
            DirectionTree::build_wedged(&dirs, &set.cell_areas(), wedges, bands).unwrap_err(),
            TreeError::Wedges { wedges, bands, dirs: 256 }
        );
    }
}
