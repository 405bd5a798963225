//! The frame loop's costs on the built-in teapot scene: a BRDF edit (shade only) and an object
//! move (re-merge of the vertices whose field inputs changed, then shade), and one timing of the
//! exact-direction reference of the same frame for the ratio. The data file is
//! `VCUT_BENCH_VCUTS` (absolute, or relative to this crate), else
//! `target/vcuts/teapot-balanced.vcuts`, precomputed here when absent or unreadable.
//! Goals (paper preset, 2 cores): edit ≤ 20 ms, move ≤ 150 ms.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use std::hint::black_box;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use vcut_data::Precomputed;
use vcut_precompute::PrecomputeParams;
use vcut_precompute::run::{Job, NoProgress, cut_sizes, precompute};
use vcut_scene::{Material, Scene};
use vcut_shade::Frame;

fn data_file() -> PathBuf {
    if let Some(p) = std::env::var_os("VCUT_BENCH_VCUTS") {
        return p.into();
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let path = root.join("target/vcuts/teapot-balanced.vcuts");
    if cut_sizes(&path).is_err() {
        let scene = Scene::open("builtin:teapot").expect("built-in scene");
        let job = Job {
            scene: &scene,
            scene_source: "builtin:teapot".into(),
            environment: "scene".into(),
            params: PrecomputeParams::balanced(),
            cache_dir: Some(root.join("target/vcut-cache")),
            output: path.clone(),
        };
        precompute(&job, &NoProgress, &AtomicBool::new(false)).expect("precompute");
    }
    path
}

fn benches(c: &mut Criterion) {
    let path = data_file();
    let mut data = Precomputed::open(&path).expect("open");
    let scene = Scene::open("builtin:teapot").expect("scene");
    let mut frame =
        Frame::open(&mut data, &scene.environment, &vcut_shade::FrameSettings::default(), None).expect("frame");
    let eye = scene.cameras[0].position;
    let teapot = frame.object_index("teapot").expect("teapot");
    let nodes: usize = (0..frame.object_count())
        .map(|o| {
            (0..frame.object(o).mesh.vertex_count())
                .map(|v| frame.merged(o, v).expect("merged").values.len())
                .sum::<usize>()
        })
        .sum();
    println!("{} directions, {nodes} merged nodes", data.directions.len());
    let mut g = c.benchmark_group("frame_teapot");
    g.sample_size(10);
    let mut alpha = 15.0f32;
    g.bench_function("brdf_edit", |b| {
        b.iter(|| {
            alpha = if alpha == 15.0 { 70.0 } else { 15.0 };
            let m = Material { exponent: alpha, ..*frame.object(teapot).material };
            frame.set_material(teapot, m);
            black_box(frame.shade(eye))
        })
    });
    let mut step = 0u32;
    g.bench_function("object_move", |b| {
        b.iter(|| {
            step += 1;
            let x = 0.05 * (step % 20) as f32;
            frame.translate(teapot, Vec3::new(x, 0.0, 0.3 * x)).expect("move");
            black_box(frame.shade(eye))
        })
    });
    g.finish();
    let t = Instant::now();
    let shade = frame.shade(eye);
    let shade_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let exact = vcut_shade::reference::exact_direction(&frame, eye, 1e-4);
    let exact_s = t.elapsed().as_secs_f64();
    let (l2, _) = vcut_shade::reference::errors(&shade, &exact);
    println!(
        "exact reference {exact_s:.2} s; shade {:.1} ms = {:.4} of it; relative L2 {l2:.4}",
        shade_s * 1e3,
        shade_s / exact_s
    );
}

criterion_group!(frame, benches);
criterion_main!(frame);
