//! A turn by whole wedges of a symmetric direction set relabels an object's cuts: the cuts of
//! the object turned by `k·2π/M` about +Y are its cuts turned by `k` wedges
//! (`vcut_cut::Cut::turned`), within the rounding of the turned geometry in f32.

use glam::{Mat4, Vec3};
use vcut_cut::Cut;
use vcut_cut::select::SelectParams;
use vcut_dirtree::DirectionTree;
use vcut_precompute::Occluder;
use vcut_precompute::field::exact_point_cut;
use vcut_precompute::svc::{SvcParams, self_visibility_cuts};
use vcut_sphere::{DirectionSet, RepulsionParams};

const WEDGES: u32 = 16;

fn wedged_tree() -> DirectionTree {
    let params = RepulsionParams { wedges: WEDGES, ..RepulsionParams::default() };
    let set = DirectionSet::generate(1024, &params, |_, _| {}).unwrap();
    DirectionTree::build_wedged(set.directions(), &set.cell_areas(), WEDGES, 4).unwrap()
}

/// The teapot off the axis (so a turn moves it) and turned by `steps` wedges about +Y.
fn teapot(steps: u32) -> vcut_scene::Mesh {
    let (mut mesh, _) = vcut_scene::teapot::teapot(6).unwrap();
    let turn = steps as f32 * std::f32::consts::TAU / WEDGES as f32;
    mesh.transform(Mat4::from_rotation_y(turn) * Mat4::from_translation(Vec3::new(0.7, 0.1, -0.3)));
    mesh
}

/// The share of leaves where two cuts differ by more than 1e-3, and their mean difference.
fn difference(a: &Cut, b: &Cut) -> (f64, f64) {
    let (a, b) = (a.expand(), b.expand());
    let differ = a.iter().zip(&b).filter(|(x, y)| (*x - *y).abs() > 1e-3).count();
    let mean = a.iter().zip(&b).map(|(x, y)| f64::from((x - y).abs())).sum::<f64>() / a.len() as f64;
    (differ as f64 / a.len() as f64, mean)
}

#[test]
fn the_turned_objects_self_visibility_cuts_are_its_cuts_turned() {
    let tree = wedged_tree();
    let shape = tree.turn_shape().unwrap();
    let params =
        SvcParams { select: SelectParams { turn: Some(shape), ..SvcParams::default().select }, ..SvcParams::default() };
    let (rest, _) = self_visibility_cuts(&teapot(0), &tree, &params);
    let mut worst = (0.0f64, 0.0f64);
    for steps in [1, 5, 11] {
        let (turned, _) = self_visibility_cuts(&teapot(steps), &tree, &params);
        for (v, (a, b)) in rest.iter().zip(&turned).enumerate() {
            assert!(a.heights().iter().all(|&h| !shape.splits(u32::from(h))), "vertex {v}: a node without a turn");
            let (share, mean) = difference(&a.turned(shape, steps).unwrap(), b);
            worst = (worst.0.max(share), worst.1.max(mean));
            assert!(share < 0.01 && mean < 1e-3, "vertex {v}, {steps} steps: {share} of leaves differ, mean {mean}");
        }
    }
    // Grazing rays may flip a few leaves; a wrong relabelling would differ everywhere.
    assert!(worst.0 < 0.01 && worst.1 < 1e-3, "{worst:?}");
    let (turned, _) = self_visibility_cuts(&teapot(1), &tree, &params);
    let wrong =
        rest.iter().zip(&turned).map(|(a, b)| difference(&a.turned(shape, 2).unwrap(), b).0).fold(0.0, f64::max);
    assert!(wrong > 0.1, "a turn by the wrong number of wedges should not match: {wrong}");
}

#[test]
fn the_turned_objects_field_cuts_are_its_cuts_turned() {
    let tree = wedged_tree();
    let shape = tree.turn_shape().unwrap();
    let (rest, turned) = (teapot(0), teapot(3));
    let (occ, occ_turned) = (Occluder::new(&[&rest]), Occluder::new(&[&turned]));
    let (b, bt) = (rest.bounds(), turned.bounds());
    let rot = Mat4::from_rotation_y(3.0 * std::f32::consts::TAU / WEDGES as f32);
    let mut differing = 0;
    for i in 0..64 {
        let t = i as f32 * 0.37;
        let p = b.center + Vec3::new(t.cos(), 0.4 * (1.3 * t).sin(), t.sin()) * b.radius * (1.1 + 0.02 * i as f32);
        let (cut, _) = exact_point_cut(&occ, &tree, p, b.center, b.radius);
        let (cut_turned, _) = exact_point_cut(&occ_turned, &tree, rot.transform_point3(p), bt.center, bt.radius);
        let (share, _) = difference(&cut.turnable(shape).turned(shape, 3).unwrap(), &cut_turned);
        assert!(share < 0.01, "point {i}: {share} of leaves differ");
        differing += usize::from(share > 0.0);
    }
    assert!(differing < 4, "{differing} of 64 points differ anywhere");
}
