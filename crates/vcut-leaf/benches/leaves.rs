//! A frame of the leaf renderer on the built-in 48-leaf plant: decoding one sun direction's LVC
//! map, shading both passes for both sides of every vertex (against SH alone), and the level of
//! detail's coarsest selection; plus the run-length codec on a real map. Goals (issue 9, 100k
//! vertices): decode ≤ 2 ms, shade ≤ 28 ms — `cargo xtask bench --only leaves` measures those
//! sizes; this bench tracks the per-vertex costs on a small plant.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use std::hint::black_box;
use vcut_envmap::procedural::PreethamSky;
use vcut_leaf::lod::{Lod, LodParams};
use vcut_leaf::lvc::{Lvc, LvcParams};
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::plant::{PlantParams, plant};
use vcut_leaf::prt::{PrtParams, Transfer};
use vcut_leaf::rle;
use vcut_leaf::shade::{LeafData, Lighting, Shader, SunMethod};

fn frame(c: &mut Criterion) {
    let scene = plant(&PlantParams::default(), &LeafMaterial::default()).expect("built-in plant");
    let lvc = Lvc::compute(&scene, &LvcParams::default(), |_, _| {});
    let transfer = Transfer::compute(&scene, &PrtParams { rays: 64, ..PrtParams::default() }, |_, _| {});
    let data = LeafData::new(lvc, transfer).unwrap();
    let (light, _) = Lighting::from_map(&PreethamSky::default().bake(256));
    let sun = light.sun.expect("the sky has a sun");
    let j = data.lvc.sun_index(sun.dir);
    let (c0, r) = scene.leaf_bounds();
    let eye = c0 + Vec3::new(0.5, 0.4, 1.0) * 3.0 * r;
    let mut g = c.benchmark_group(format!("leaves_{}_vertices", scene.vertex_count()));
    let mut map = vec![0u8; scene.vertex_count()];
    g.bench_function("decode_sun_map", |b| b.iter(|| data.lvc.decode(black_box(j), &mut map).unwrap()));
    let raw = map.clone();
    g.bench_function("rle_encode_map", |b| b.iter(|| rle::encode(black_box(&raw))));
    let mut shader = Shader::new();
    shader.prepare(&scene, &data.lvc, &light).unwrap();
    let mut out = Vec::new();
    g.bench_function("shade_lvc_prt", |b| {
        b.iter(|| shader.shade(&scene, &data, &light, SunMethod::Lvc, black_box(eye), &mut out))
    });
    g.bench_function("shade_sh_only", |b| {
        b.iter(|| shader.shade(&scene, &data, &light, SunMethod::ShOnly, black_box(eye), &mut out))
    });
    let lod = Lod::build(&scene, &data.transfer, &LodParams::default());
    let coarse = lod.select(&scene, &data.transfer, eye, 40.0, 720, Some(lod.level_count() - 1));
    g.bench_function("shade_lod_coarsest", |b| {
        b.iter(|| shader.shade_lod(&scene, &data, &coarse, &light, SunMethod::Lvc, black_box(eye), &mut out))
    });
    g.finish();
}

criterion_group!(benches, frame);
criterion_main!(benches);
