//! The leaf viewer: its GPU picture equals the CPU renderer's, and every edit of the leaf panel
//! (sun, material, method, level of detail) changes the frame.

mod common;

use common::gpu;
use vcut_envmap::procedural::PreethamSky;
use vcut_leaf::lvc::{Lvc, LvcParams};
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::plant::{PlantParams, plant};
use vcut_leaf::prt::{PrtParams, Transfer};
use vcut_leaf::shade::{LeafData, SunMethod};
use vcut_scene::Camera;
use vcut_shade::image::tone_map;
use vcut_view::{LeafSession, OrbitCamera};

fn session() -> LeafSession {
    let m = LeafMaterial::default();
    let scene = plant(&PlantParams { leaves: 12, ..PlantParams::default() }, &m).unwrap();
    let lvc = Lvc::compute(&scene, &LvcParams { resolution: 8, ..LvcParams::default() }, |_, _| {});
    let transfer = Transfer::compute(&scene, &PrtParams { rays: 16, ..PrtParams::default() }, |_, _| {});
    let (c, r) = scene.leaf_bounds();
    let camera = Camera {
        name: "t".into(),
        position: c + glam::Vec3::new(0.5, 0.4, 1.0).normalize() * 3.0 * r,
        target: c,
        up: glam::Vec3::Y,
        fov_y_deg: 40.0,
    };
    let env = PreethamSky::default().bake(256);
    LeafSession::new(scene, LeafData::new(lvc, transfer).unwrap(), env, OrbitCamera::from_camera(&camera))
}

fn cpu_image(s: &LeafSession, w: u32, h: u32) -> Vec<u8> {
    let img = vcut_leaf::image::render_triangles(
        s.scene(),
        s.triangles(),
        s.radiance(),
        &s.camera.camera(),
        (w, h),
        Some(s.env()),
    );
    let e = s.exposure_in_use();
    img.rgb.iter().flat_map(|c| [tone_map(c.x, e), tone_map(c.y, e), tone_map(c.z, e)]).collect()
}

#[test]
fn the_leaf_screenshot_matches_the_cpu_renderer_and_follows_every_edit() {
    let Some(gpu) = gpu("the_leaf_screenshot_matches_the_cpu_renderer_and_follows_every_edit") else { return };
    let mut s = session();
    let (w, h) = (320, 240);
    let shot = |s: &mut LeafSession| vcut_view::leaf_screenshot(&gpu, s, w, h).unwrap();
    assert!(s.material().maps[0].is_some(), "the plant's own material, maps included");
    let first = shot(&mut s);
    // Two-sided: each pixel shows the side facing the camera, as the CPU renderer decides it.
    let cpu = cpu_image(&s, w, h);
    let diffs: Vec<u8> =
        first.pixels().zip(cpu.chunks(3)).map(|(p, c)| (0..3).map(|k| p.0[k].abs_diff(c[k])).max().unwrap()).collect();
    let mean = diffs.iter().map(|&d| f64::from(d)).sum::<f64>() / diffs.len() as f64;
    let within = diffs.iter().filter(|&&d| d <= 2).count() as f64 / diffs.len() as f64;
    eprintln!("adapter {}: mean |gpu - cpu| {mean:.3} levels, {:.2} % within 2", gpu.describe(), within * 100.0);
    assert!(mean < 0.5 && within > 0.99, "mean {mean}, within {within}");

    let differs =
        |a: &image::RgbaImage, b: &image::RgbaImage| a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count();
    s.exposure = Some(s.exposure_in_use());
    let base = shot(&mut s);
    s.set_sun(20.0, 200.0);
    let moved = shot(&mut s);
    assert!(differs(&base, &moved) > 500, "the sun moved");
    // A paler leaf, fitted to other measurements.
    let pale =
        LeafMaterial::from_measured(glam::Vec3::new(0.2, 0.3, 0.1), glam::Vec3::new(0.1, 0.2, 0.05), 0.3).unwrap();
    s.set_material(pale);
    let edited = shot(&mut s);
    assert!(differs(&moved, &edited) > 200, "a paler leaf: {}", differs(&moved, &edited));
    s.set_method(SunMethod::ShOnly);
    let sh = shot(&mut s);
    assert!(differs(&edited, &sh) > 200, "SH only");
    // Far away, every leaf at a coarser level.
    s.lod_enabled = true;
    s.camera.distance *= 30.0;
    s.touch();
    s.update(h).unwrap();
    assert_eq!(s.leaves_per_level()[0], 0, "{:?}", s.leaves_per_level());
}

/// The window's edge-ray setting reaches the shader: with rays, the shadow edges between the
/// sun's neighbouring maps are cast; with none, the maps are only blended, and the picture
/// differs there.
#[test]
fn the_edge_ray_setting_reaches_the_sun_map() {
    let mut s = session();
    s.set_sun(37.3, 51.7);
    s.update(240).unwrap();
    let (cast, with_rays) = (s.edge_vertices(), s.radiance().to_vec());
    assert_eq!(s.edge_rays(), 4);
    assert!(cast > 0, "a sun between the maps' directions has shadow edges");
    s.set_edge_rays(0);
    assert!(s.update(240).unwrap());
    assert_eq!(s.edge_vertices(), 0);
    assert_ne!(s.radiance(), &with_rays[..], "blended only: the edge vertices change");
}
