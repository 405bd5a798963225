//! The WGSL SSDO / SSAO passes against the CPU implementation (`vcut-ssdo`) on the same inputs:
//! a ground with two balls under the sky (sun shadow-mapped), SSAO, SSDO, and SSDO peeled.
//! Without a wgpu adapter this says it was skipped, unless `VCUT_REQUIRE_GPU=1`.

mod common;
use common::rect;
use glam::Vec3;
use vcut_gpu::test_device;
use vcut_scene::Camera;
use vcut_ssdo::gpu::GpuSsdo;
use vcut_ssdo::{GBuffer, Lighting, Method, Object, Params, SampleSets, rel_l2, render};

#[test]
fn the_gpu_passes_match_the_cpu_implementation() {
    let Some(gpu) = test_device("the_gpu_passes_match_the_cpu_implementation") else { return };
    let ball = vcut_scene::shapes::sphere(0.5, 32, 16).unwrap();
    let objects = vec![
        rect(Vec3::new(-2.0, 0.0, 2.0), Vec3::new(4.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -4.0), 16, Vec3::splat(0.6)),
        Object::from_mesh(&ball, Vec3::new(0.0, 0.55, 0.0), Vec3::new(0.7, 0.5, 0.3)),
        Object::from_mesh(&ball, Vec3::new(0.9, 0.3, -0.6), Vec3::new(0.2, 0.6, 0.3)),
    ];
    let sky = vcut_envmap::procedural::PreethamSky::default().bake(512);
    let camera = Camera {
        name: "test".into(),
        position: Vec3::new(2.0, 1.6, 2.4),
        target: Vec3::new(0.0, 0.3, 0.0),
        up: Vec3::Y,
        fov_y_deg: 45.0,
    };
    let light = Lighting::new(&sky, &objects, 16);
    let passes = GpuSsdo::new(&gpu).unwrap();
    let (w, h) = (160usize, 120usize);
    let g = GBuffer::new(&objects, &camera, w, h);
    // 32 samples: beyond the 24 whose occlusion the sampling pass hands to the bounce pass.
    let cases =
        [(Method::Ssao, false, 16), (Method::Ssdo, false, 16), (Method::Ssdo, true, 16), (Method::Ssdo, false, 32)];
    for (method, peel, samples) in cases {
        let mut p = Params::for_scene(2.0);
        p.radius = 0.4;
        p.depth_limit = 0.4;
        p.peel = peel;
        p.samples = samples;
        let cpu = render(&g, &light, &SampleSets::halton(p.samples, p.sets), &p, method);
        let frame = passes.frame(&gpu, &objects, &light, &camera, &p, method, (w as u32, h as u32)).unwrap();
        frame.run(&gpu).unwrap();
        let (rgb, covered) = frame.read(&gpu).unwrap();
        let same_cover = covered.iter().zip(&cpu.covered).filter(|(a, b)| a == b).count() as f64 / covered.len() as f64;
        let both: Vec<bool> = covered.iter().zip(&cpu.covered).map(|(a, b)| *a && *b).collect();
        let e = rel_l2(&rgb, &cpu.total(), &both);
        // Per pixel: the share within 2 % of the CPU's value.
        let close = rgb
            .iter()
            .zip(cpu.total())
            .zip(&both)
            .filter(|(_, b)| **b)
            .filter(|((a, c), _)| (**a - *c).abs().max_element() <= 0.02 * c.max_element().max(1e-3))
            .count() as f64
            / both.iter().filter(|b| **b).count() as f64;
        eprintln!(
            "{method:?} peel={peel} samples={samples}: coverage agrees {same_cover:.4}, rel L2 {e:.4}, within 2 %: {close:.4}"
        );
        assert!(same_cover > 0.995, "{method:?}: coverage {same_cover}");
        // The same formulas in the same order: lavapipe agrees to rounding (rel L2 < 5e-5 seen);
        // other GPUs' transcendental functions may differ a little more.
        assert!(
            e < 2e-3 && close > 0.99,
            "{method:?} peel={peel} samples={samples}: gpu vs cpu rel L2 {e}, within 2 %: {close}"
        );
    }
}
