//! Loading real files: the Stanford bunny OBJ, the 2CylinderEngine GLB (82 nodes) and the
//! 1024×512 quarry HDR; plus the built-in teapot scene and sky, which need no files.

use criterion::{Criterion, criterion_group, criterion_main};
use vcut_envmap::InvalidTexels;
use vcut_scene::MeshOptions;
use vcut_scene::loaders::{GltfObjects, ObjObjects, load_file};

fn loading(c: &mut Criterion) {
    let mut g = c.benchmark_group("load");
    g.sample_size(10);
    if let Some(p) = vcut_benches::asset_or_skip("meshes/stanford-bunny.obj") {
        g.bench_function("stanford-bunny.obj", |b| {
            b.iter(|| load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()).unwrap())
        });
    }
    if let Some(p) = vcut_benches::asset_or_skip("gltf/2CylinderEngine.glb") {
        g.bench_function("2CylinderEngine.glb", |b| {
            b.iter(|| load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()).unwrap())
        });
    }
    if let Some(p) = vcut_benches::asset_or_skip("envmaps/quarry_01_1k.hdr") {
        g.bench_function("quarry_01_1k.hdr", |b| b.iter(|| vcut_envmap::load(&p, InvalidTexels::Reject).unwrap()));
    }
    g.bench_function("builtin teapot scene", |b| b.iter(|| vcut_scene::Scene::open("builtin:teapot").unwrap()));
    g.bench_function("builtin sky 1024x512", |b| b.iter(|| vcut_envmap::procedural::PreethamSky::default().bake(1024)));
    g.finish();
}

criterion_group!(benches, loading);
criterion_main!(benches);
