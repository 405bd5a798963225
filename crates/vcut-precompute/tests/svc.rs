//! Self-visibility cuts on shapes whose answer is known: a closed sphere and a plane never
//! occlude themselves (every ray above the horizon escapes — no acne, no leaks), the teapot
//! does near its spout and handle, and cone culling resolves the lower hemisphere without rays.

use glam::Vec3;
use vcut_dirtree::DirectionTree;
use vcut_precompute::Occluder;
use vcut_precompute::svc::{SvcParams, leaf_visibility, self_visibility_cuts};
use vcut_sphere::{DirectionSet, RepulsionParams};

fn tree(n: usize) -> DirectionTree {
    let set = DirectionSet::generate(n, &RepulsionParams::default(), |_, _| {}).unwrap();
    DirectionTree::build(set.directions(), &set.cell_areas()).unwrap()
}

/// Σ Ṽ·a over leaves divided by Σ max(0, n·ω)·a: the visible share of the cosine lobe.
fn visible_share(tree: &DirectionTree, values: &[f32], normal: Vec3) -> f64 {
    let (mut seen, mut lobe) = (0.0f64, 0.0f64);
    for (l, d) in tree.leaf_directions().iter().enumerate() {
        let a = tree.solid_angle(tree.index(0, l as u32));
        seen += f64::from(values[l]) * a;
        lobe += f64::from(normal.dot(*d).max(0.0)) * a;
    }
    seen / lobe
}

#[test]
fn convex_sphere_and_plane_never_shadow_themselves() {
    let t = tree(1024);
    let sphere = vcut_scene::shapes::sphere(1.0, 40, 20).unwrap();
    let (cuts, stats) = self_visibility_cuts(&sphere, &t, &SvcParams::default());
    assert_eq!(cuts.len(), sphere.vertex_count());
    assert_eq!(stats.rays_occluded, 0, "{stats:?}");
    assert!(stats.rays_cast > 0);
    // About half of every vertex's directions are below its horizon, resolved without rays.
    let per_vertex = (stats.rays_cast + stats.resolved_without_ray) as f64 / sphere.vertex_count() as f64;
    assert_eq!(per_vertex, 1024.0);
    let share = stats.resolved_without_ray as f64 / (stats.rays_cast + stats.resolved_without_ray) as f64;
    assert!((0.45..0.55).contains(&share), "{share}");
    let plane = vcut_scene::shapes::plane(4.0, 8).unwrap();
    let (_, stats) = self_visibility_cuts(&plane, &t, &SvcParams::default());
    assert_eq!(stats.rays_occluded, 0);
}

#[test]
fn cut_values_integrate_the_cosine_lobe() {
    // For an unoccluded vertex the cut's area-weighted values integrate n·ω over the upper
    // hemisphere: π (to the direction discretisation).
    let t = tree(4096);
    let plane = vcut_scene::shapes::plane(1.0, 1).unwrap();
    let (cuts, _) = self_visibility_cuts(&plane, &t, &SvcParams::default());
    let cut = &cuts[0];
    let mut at = 0usize;
    let mut integral = 0.0f64;
    for (&h, &v) in cut.heights().iter().zip(cut.values()) {
        let a: f64 = (at..at + (1 << h)).map(|l| t.solid_angle(t.index(0, l as u32))).sum();
        integral += f64::from(v) * a;
        at += 1 << h;
    }
    assert!((integral - std::f64::consts::PI).abs() < 0.01, "{integral}");
    cut.validate().unwrap();
}

#[test]
fn teapot_shadows_itself_near_the_spout_and_handle() {
    let t = tree(4096);
    let (teapot, _) = vcut_scene::teapot::teapot(8).unwrap();
    let occ = Occluder::new(&[&teapot]);
    let offset = 1e-4 * teapot.bounds().radius;
    let mut values = vec![0.0f32; t.leaf_count()];
    // The body vertex nearest to where the spout joins it (spout along +x, about y = 1.2).
    let spout_root = Vec3::new(2.0, 1.2, 0.0);
    let near = (0..teapot.vertex_count())
        .filter(|&i| teapot.normals()[i].x > 0.8)
        .min_by(|&a, &b| {
            teapot.positions()[a].distance(spout_root).total_cmp(&teapot.positions()[b].distance(spout_root))
        })
        .unwrap();
    let (p, n) = (teapot.positions()[near], teapot.normals()[near]);
    leaf_visibility(&occ, &t, p + n * offset, n, &mut values);
    let share = visible_share(&t, &values, n);
    assert!(share < 0.9, "the spout should block part of the view from {p}: visible {share}");
    // The top of the lid knob sees its whole upper hemisphere.
    let top = (0..teapot.vertex_count())
        .max_by(|&a, &b| teapot.positions()[a].y.total_cmp(&teapot.positions()[b].y))
        .unwrap();
    let (p, n) = (teapot.positions()[top], teapot.normals()[top]);
    leaf_visibility(&occ, &t, p + n * offset, n, &mut values);
    let share = visible_share(&t, &values, n);
    assert!(share > 0.99, "lid top sees {share}");
}

#[test]
fn raw_throughput_is_measured() {
    let sphere = vcut_scene::shapes::sphere(1.0, 32, 16).unwrap();
    let occ = Occluder::new(&[&sphere]);
    let rays: Vec<(Vec3, Vec3)> = (0..2000)
        .map(|i| (Vec3::new(0.0, 0.0, -3.0), Vec3::new((i % 7) as f32 * 0.01, 0.0, 1.0).normalize()))
        .collect();
    assert!(occ.occluded(Vec3::new(0.0, 0.0, -3.0), Vec3::Z, f32::INFINITY));
    assert!(!occ.occluded(Vec3::new(0.0, 0.0, -3.0), -Vec3::Z, f32::INFINITY));
    assert!(!occ.occluded(Vec3::new(0.0, 0.0, -3.0), Vec3::Z, 1.5), "tmax stops before the sphere");
    assert!(occ.raw_throughput(&rays) > 0.0);
}
