//! Fuzz target: light trees from arbitrary maps. A lat-long or cube map of arbitrary size and
//! texel bits (NaN, ±∞, negative, huge included) is either refused by `EnvMap::new` (or clamped,
//! when the input asks) or gives light trees — the tabled build and the exact one — whose nodes
//! are finite, non-negative and each the sum of its children (`LightTree::validate`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;
use vcut_dirtree::DirectionTree;
use vcut_envmap::{EnvMap, InvalidTexels, Layout};
use vcut_lighttree::LightTreeBuilder;
use vcut_sphere::{DirectionSet, RepulsionParams};

/// A 256-direction tree, built once.
fn tree() -> &'static DirectionTree {
    static TREE: OnceLock<DirectionTree> = OnceLock::new();
    TREE.get_or_init(|| {
        let set = DirectionSet::generate(256, &RepulsionParams::default(), |_, _| {}).expect("256 directions");
        DirectionTree::build(set.directions(), &set.cell_areas()).expect("a tree of 256 directions")
    })
}

fuzz_target!(|data: &[u8]| {
    let [shape, a, b, flags, rest @ ..] = data else { return };
    let layout = if shape & 1 == 0 {
        Layout::LatLong { width: u32::from(*a % 32) + 1, height: u32::from(*b % 16) + 1 }
    } else {
        Layout::Cube { size: u32::from(*a % 8) + 1, handedness: Default::default() }
    };
    // Texels from the bytes, 4 a channel (f32 bits), repeated to fill the map.
    let words: Vec<f32> = rest.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    let n = layout.texel_count();
    let texels: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            let w = |k: usize| if words.is_empty() { 1.0 } else { words[(3 * i + k) % words.len()] };
            [w(0), w(1), w(2)]
        })
        .collect();
    let invalid = if flags & 1 == 0 { InvalidTexels::Reject } else { InvalidTexels::Clamp };
    let any_bad = texels.iter().flatten().any(|x| !x.is_finite() || *x < 0.0);
    let map = match EnvMap::new(layout, texels, "fuzz", invalid) {
        Ok((map, _)) => map,
        Err(e) => {
            assert!(any_bad && invalid == InvalidTexels::Reject, "a good map refused: {e}");
            return;
        }
    };
    assert!(!any_bad || invalid == InvalidTexels::Clamp, "a bad texel accepted");
    let tree = tree();
    let mut builder = LightTreeBuilder::new(tree);
    let k = u32::from(flags >> 1) % 3 + 1;
    let (tabled, exact) = (builder.build(&map), builder.build_exact(&map, k));
    for light in [&tabled, &exact] {
        // Finite, non-negative, every node the sum of its children.
        light.validate().expect("a valid light tree");
        assert_eq!(light.height(), tree.height());
    }
});
