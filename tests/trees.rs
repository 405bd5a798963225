//! Directions, the direction tree and the light tree together, at the numerical extremes:
//! 2^20 and 65,536 directions, a sun 10^5× the sky, an all-black map, a single bright texel, and
//! every map in the shared assets; the light tree's root is ∫ L dω (within 0.1 %, in practice to
//! f64 rounding) and nothing is NaN.

use glam::Vec3;
use vcut_dirtree::DirectionTree;
use vcut_envmap::procedural::{PreethamSky, Studio};
use vcut_envmap::{EnvMap, InvalidTexels, Layout};
use vcut_lighttree::{LightTree, LightTreeBuilder};
use vcut_sphere::{DirectionSet, RepulsionParams};

fn tree_of(n: usize, params: &RepulsionParams) -> DirectionTree {
    let set = DirectionSet::generate(n, params, |_, _| {}).unwrap();
    let tree = DirectionTree::build(set.directions(), &set.cell_areas()).unwrap();
    tree.validate().unwrap();
    tree
}

fn rel_error(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| if b[i] == 0.0 { a[i].abs() } else { ((a[i] - b[i]) / b[i]).abs() }).fold(0.0, f64::max)
}

fn l1_share(a: &LightTree, b: &LightTree, total: f64) -> f64 {
    a.leaves().iter().zip(b.leaves()).map(|(x, y)| (x[1] - y[1]).abs()).sum::<f64>() / total
}

#[test]
fn trees_at_65536_have_root_height_16_and_exact_totals() {
    let tree = tree_of(65_536, &RepulsionParams::default());
    assert_eq!(tree.height(), 16);
    assert!((tree.solid_angle(0) - 4.0 * std::f64::consts::PI).abs() < 1e-9);
    let mut builder = LightTreeBuilder::new(&tree);
    let sky = PreethamSky::default().bake(512);
    let lights = builder.build(&sky);
    lights.validate().unwrap();
    assert!(rel_error(lights.root(), sky.total_power()) < 1e-9);
}

#[test]
fn a_million_directions_still_work() {
    // 2^20: a short relaxation (the start is already even); the tree and light tree stay exact.
    let params = RepulsionParams { max_iterations: 3, ..RepulsionParams::default() };
    let tree = tree_of(1 << 20, &params);
    assert_eq!(tree.height(), 20);
    let map = Studio::default().bake(256);
    let lights = LightTreeBuilder::new(&tree).build(&map);
    lights.validate().unwrap();
    assert!(rel_error(lights.root(), map.total_power()) < 1e-9);
}

#[test]
fn sun_a_hundred_thousand_times_the_sky_keeps_its_power() {
    let tree = tree_of(32_768, &RepulsionParams::default());
    let mut builder = LightTreeBuilder::new(&tree);
    let mut sky = PreethamSky::from_elevation_azimuth(35.0, 80.0);
    sky.ground_albedo = 0.0;
    let bright = sky.bake(1024);
    let mut dark_sky = sky.clone();
    dark_sky.sun_to_zenith = 0.0;
    let dark = dark_sky.bake(1024);
    for lights in [builder.build_exact(&bright, 2), builder.build(&bright)] {
        lights.validate().unwrap();
        assert!(rel_error(lights.root(), bright.total_power()) < 1e-9);
        let no_sun = builder.build(&dark);
        // The sun's power sits in the leaves within one cell of its direction, exactly.
        let sun_power = bright.total_power()[0] - dark.total_power()[0];
        let spacing = (4.0 * std::f32::consts::PI / 32_768.0).sqrt();
        let near: f64 = (0..tree.leaf_count())
            .filter(|&l| tree.leaf_directions()[l].angle_between(sky.sun_dir.normalize()) < 1.5 * spacing)
            .map(|l| lights.leaves()[l][0] - no_sun.leaves()[l][0])
            .sum();
        assert!((near - sun_power).abs() < 1e-3 * sun_power, "{near} vs {sun_power}");
    }
}

#[test]
fn black_map_and_single_bright_texel() {
    let tree = tree_of(4096, &RepulsionParams::default());
    let mut builder = LightTreeBuilder::new(&tree);
    let layout = Layout::LatLong { width: 256, height: 128 };
    let (black, _) = EnvMap::new(layout, vec![[0.0; 3]; layout.texel_count()], "black", InvalidTexels::Reject).unwrap();
    let lights = builder.build(&black);
    lights.validate().unwrap();
    assert!(lights.nodes().iter().all(|v| *v == [0.0; 3]));
    let mut texels = vec![[0.0f32; 3]; layout.texel_count()];
    let t = layout.texel_of(Vec3::new(0.3, 0.5, -0.8));
    texels[t] = [1.0e6, 2.0e6, 3.0e6];
    let (one, _) = EnvMap::new(layout, texels, "one", InvalidTexels::Reject).unwrap();
    for lights in [builder.build(&one), builder.build_exact(&one, 1)] {
        let lit: Vec<_> = lights.leaves().iter().filter(|v| v[0] > 0.0).collect();
        assert_eq!(lit.len(), 1, "one texel lands in one leaf");
        assert!(rel_error(*lit[0], one.total_power()) < 1e-12);
        assert!(lights.nodes().iter().flatten().all(|x| x.is_finite()));
    }
}

#[test]
fn fast_rebuild_matches_exact_binning_and_follows_rotation() {
    let tree = tree_of(8192, &RepulsionParams::default());
    let mut builder = LightTreeBuilder::new(&tree);
    let mut map = PreethamSky::default().bake(512);
    for yaw in [0.0, 37.0, 210.0, 0.123] {
        map.set_rotation_y_degrees(yaw);
        let fast = builder.build(&map);
        let exact = builder.build_exact(&map, 1);
        let total = map.total_power();
        assert!(rel_error(fast.root(), total) < 1e-9 && rel_error(exact.root(), total) < 1e-9);
        let l1 = l1_share(&fast, &exact, total[1]);
        assert!(l1 < 0.02, "yaw {yaw}: fast and exact binning differ by {l1}");
    }
    // A rotation that is not about +Y takes the cube-table path; same agreement.
    map.set_rotation(glam::Quat::from_rotation_x(0.7) * glam::Quat::from_rotation_y(0.3));
    let (fast, exact) = (builder.build(&map), builder.build_exact(&map, 1));
    assert!(rel_error(fast.root(), map.total_power()) < 1e-9);
    let l1 = l1_share(&fast, &exact, map.total_power()[1]);
    assert!(l1 < 0.02, "tilted: fast and exact binning differ by {l1}");
    // Rotating moves the sun's leaf.
    map.set_rotation_y_degrees(0.0);
    let before = builder.build(&map);
    map.set_rotation_y_degrees(90.0);
    let after = builder.build(&map);
    let brightest =
        |l: &LightTree| (0..l.leaves().len()).max_by(|&a, &b| l.leaves()[a][0].total_cmp(&l.leaves()[b][0])).unwrap();
    let (a, b) = (tree.leaf_directions()[brightest(&before)], tree.leaf_directions()[brightest(&after)]);
    let rotated = glam::Quat::from_rotation_y(90f32.to_radians()) * a;
    assert!(rotated.angle_between(b) < 0.05, "{a} rotated is {rotated}, brightest after is {b}");
}

#[test]
fn every_asset_map_integrates_exactly() {
    let Some(assets) = vcut_tests::assets_or_skip("every_asset_map_integrates_exactly") else { return };
    let tree = tree_of(4096, &RepulsionParams::default());
    let mut builder = LightTreeBuilder::new(&tree);
    for rel in vcut_tests::ENVIRONMENT_MAPS {
        let (map, _) = vcut_envmap::load(&assets.join(rel), InvalidTexels::Reject).unwrap();
        let lights = builder.build(&map);
        lights.validate().unwrap();
        let e = rel_error(lights.root(), map.total_power());
        assert!(e < 1e-3, "{rel}: root differs from the map's power by {e}");
        assert!(e < 1e-9, "{rel}: {e}");
    }
    for map in [Studio::default().bake(1024), PreethamSky::default().bake(1024)] {
        assert!(rel_error(builder.build(&map).root(), map.total_power()) < 1e-9);
    }
}
