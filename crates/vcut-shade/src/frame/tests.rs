//! Unit tests of the frame's private parts: shading lists, held values, the lanes.

use super::keys::take_held;
use super::lists::*;
use crate::brdf;
use glam::Vec3;
use vcut_dirtree::DirectionTree;
use vcut_envmap::EnvMap;
use vcut_lighttree::LightTreeBuilder;
use vcut_merge::MergedCut;
use vcut_scene::BrdfModel;
use vcut_scene::Material;

/// A merged node inside a larger SVC node takes its share of the SVC as the SVC node's
/// visibility times its own cosine: an open plane's SVC node split in two by a field that
/// leaves both halves visible shades as the two halves' own means would, where the old
/// weight (the SVC node's mean cosine for both) was off.
#[test]
fn a_split_svc_node_takes_its_own_cosine() {
    let count = 256usize;
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let dirs: Vec<Vec3> = (0..count)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / count as f32;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f32;
            Vec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect();
    let tree = DirectionTree::build(&dirs, &vec![4.0 * std::f64::consts::PI / count as f64; count]).unwrap();
    let light = LightTreeBuilder::new(&tree).build(&EnvMap::constant([1.0; 3]));
    let table = shade_nodes(&tree, &light);
    let n = Vec3::new(0.3, 0.9, 0.2).normalize();
    let root = tree.height();
    let h = 3u32;
    let index = |h: u32, leaf: u32| vcut_cut::level_order_index(root, h, leaf) as usize;
    // The mean of max(0, n·ω) over a node's leaves: an unoccluded SVC's exact value.
    let mean_cos = |h: u32, leaf: u32| {
        let k = index(h, leaf);
        let r = tree.leaf_range(k as u32);
        tree.leaf_directions()[r.clone()].iter().map(|d| n.dot(*d).max(0.0)).sum::<f32>() / r.len() as f32
    };
    // An SVC node wholly above the horizon whose halves' cosines differ.
    let a = (0..(count as u32 >> h))
        .map(|o| o << h)
        .filter(|&leaf| {
            let t = &table[index(h, leaf)];
            n.dot(t.axis) >= t.sin_half && n.dot(t.mean) > 1e-3
        })
        .max_by(|&x, &y| {
            let split = |l: u32| (mean_cos(h - 1, l) - mean_cos(h - 1, l + (1 << (h - 1)))).abs();
            split(x).total_cmp(&split(y))
        })
        .expect("a node above the horizon");
    let svc_ends: Vec<u32> = (1..=(count as u32 >> h)).map(|i| i << h).collect();
    // The product with the field: A split into its halves, each with A's SVC value; and
    // the same cut with every node's own mean.
    let (mut product, mut own) = (MergedCut { root_height: root, ..MergedCut::default() }, MergedCut::default());
    for start in (0..count as u32).step_by(1 << h) {
        let halves: &[(u32, u32)] =
            if start == a { &[(h - 1, start), (h - 1, start + (1 << (h - 1)))] } else { &[(h, start)] };
        for &(g, leaf) in halves {
            product.heights.push(g as u8);
            product.indices.push(index(g, leaf) as u32);
            product.values.push(mean_cos(h, start));
        }
    }
    own.clone_from(&product);
    for (v, &k) in own.values.iter_mut().zip(&product.indices) {
        let (g, leaf) = tree.node(k);
        *v = mean_cos(g, leaf);
    }
    let split = ShadeList::new((&product).into(), n, &table, Some(&svc_ends));
    let exact = ShadeList::new((&own).into(), n, &table, None);
    let old = ShadeList::new((&product).into(), n, &table, None);
    let unpacked = |l: &ShadeList| -> (Vec<usize>, Vec<f32>) { l.entries.iter().map(|&e| unpack(e)).unzip() };
    let ((split_nodes, split_w), (exact_nodes, exact_w), (_, old_w)) =
        (unpacked(&split), unpacked(&exact), unpacked(&old));
    assert_eq!(split_nodes, exact_nodes);
    // Equal up to the weights' rounding (2^-11 relative each).
    for (i, (w, e)) in split_w.iter().zip(&exact_w).enumerate() {
        assert!((w - e).abs() <= 1.5e-3 * e.abs().max(1e-3), "node {i}: {w} vs {e}");
    }
    let worst = old_w.iter().zip(&exact_w).map(|(w, e)| (w - e).abs() / e.abs().max(1e-3)).fold(0.0, f32::max);
    assert!(worst > 1e-2, "the old weights were off by {worst} only: the test splits nothing");
    assert!((split.diffuse - exact.diffuse).abs().max_element() <= 1e-5 * exact.diffuse.max_element());
}

#[test]
fn take_held_moves_out_the_values_of_wanted_keys() {
    let got = take_held(vec![1, 3, 5, 8], vec!["a", "c", "e", "h"], &[0, 3, 4, 8, 9]);
    assert_eq!(got, vec![None, Some("c"), None, Some("h"), None]);
    assert_eq!(take_held(Vec::<u32>::new(), Vec::<u8>::new(), &[1]), vec![None]);
}

/// The eight-lane specular sum is the per-node one up to rounding, for list lengths that
/// fill the lanes, leave a remainder, or are empty.
#[test]
fn lanes_agree_with_the_per_node_sum() {
    let mut seed = 1u64;
    let mut unit = || {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    let n = Vec3::new(0.2, 0.9, 0.1).normalize();
    let table: Vec<SpecularNode> = (0..64)
        .map(|_| {
            // Directions above the horizon of n, lights up to a bright sun.
            let d = (Vec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5) + n).normalize();
            SpecularNode { dir: d, light: Vec3::new(unit(), unit(), unit()) * 1e3 * unit() }
        })
        .collect();
    let wo = Vec3::new(-0.3, 0.8, 0.4).normalize();
    for (model, exponent) in [(BrdfModel::BlinnPhong, 70.0), (BrdfModel::Phong, 15.0)] {
        let m = Material { model, exponent, ..Material::default() };
        let pow = brdf::PowTable::new(exponent).unwrap();
        let lobe = brdf::Lobe::with_pow(&m, n, wo, brdf::Pow::Table(&pow));
        for len in [0usize, 1, 7, 8, 9, 41] {
            let list = ShadeList {
                entries: (0..len as u32).map(|k| pack((k * 7) % 64, unit().max(1e-3))).collect(),
                diffuse: Vec3::ZERO,
                stale: false,
            };
            let each = list.specular(&table, |d| lobe.eval(d));
            let lanes = match lobe {
                brdf::Lobe::BlinnPhong { scale, .. } => {
                    list.specular_lanes(&table, &pow, scale, blinn_phong_argument(n, wo))
                }
                brdf::Lobe::Phong { mirror, scale, .. } => {
                    list.specular_lanes(&table, &pow, scale, phong_argument(mirror))
                }
                _ => unreachable!("two table lobes"),
            };
            let err = (lanes - each).abs().max_element();
            assert!(err <= 1e-5 * each.abs().max_element().max(1e-3), "{model:?}, {len} nodes: {lanes} vs {each}");
            if len > 0 {
                assert!(each.max_element() > 0.0, "{model:?}: the test lights something");
            }
        }
    }
}

/// A list entry keeps its node exactly and its weight to half-float precision, over every
/// node index a tree of 65,536 directions has and weights from the smallest kept up.
#[test]
fn list_entries_round_their_weight_to_half_precision_and_keep_the_node() {
    let mut worst = 0.0f32;
    for k in [0u32, 1, 4_095, 65_534, 131_070] {
        assert!((k as usize) < MAX_NODES);
        for i in 0..2_000 {
            let w = 2f32.powf(-14.0 + 29.0 * i as f32 / 2_000.0) * (1.0 + (i % 7) as f32 / 7.0);
            let (node, back) = unpack(pack(k, w));
            assert_eq!(node, k as usize);
            worst = worst.max((back - w).abs() / w);
        }
    }
    assert!(worst <= 1.0 / 2048.0 + 1e-7 && worst > 1e-5, "worst relative error {worst}");
    assert_eq!(unpack(pack(7, 1.0)), (7, 1.0));
    assert_eq!(unpack(pack(7, 1e9)).1, 65_504.0, "clamped to the largest half float");
}
