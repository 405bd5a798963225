//! The SVC stage on the teapot (8,257 vertices, 32,768 directions) against the raw occlusion
//! throughput of the same BVH: rays cast per second by the stage (counting only rays actually
//! cast) over plain `occluded` calls on the same rays, measured in the same run (goal ≥ 0.8×).

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use std::time::Instant;
use vcut_dirtree::DirectionTree;
use vcut_precompute::Occluder;
use vcut_precompute::svc::{SvcParams, self_visibility_cuts};
use vcut_sphere::{DirectionSet, RepulsionParams};

fn benches(c: &mut Criterion) {
    let set = DirectionSet::generate(32_768, &RepulsionParams::default(), |_, _| {}).expect("directions");
    let tree = DirectionTree::build(set.directions(), &set.cell_areas()).expect("tree");
    let (teapot, _) = vcut_scene::teapot::teapot(16).expect("teapot");
    // The whole stage, timed once (it takes seconds); criterion times the raw rays below.
    let start = Instant::now();
    let (_, stats) = self_visibility_cuts(&teapot, &tree, &SvcParams::default());
    let stage_s = start.elapsed().as_secs_f64();
    let stage_rate = stats.rays_cast as f64 / stage_s;
    // Raw: the same kind of rays (vertex origins, upper-hemisphere leaf directions), plain calls.
    let occ = Occluder::new(&[&teapot]);
    let offset = 1e-4 * teapot.bounds().radius;
    let rays: Vec<(Vec3, Vec3)> = (0..teapot.vertex_count())
        .step_by(7)
        .flat_map(|v| {
            let (p, n) = (teapot.positions()[v], teapot.normals()[v]);
            tree.leaf_directions()
                .iter()
                .step_by(61)
                .filter(move |d| n.dot(**d) > 0.0)
                .map(move |&d| (p + n * offset, d))
        })
        .collect();
    let raw_rate = occ.raw_throughput(&rays);
    println!(
        "svc teapot: {} rays cast, {} resolved without a ray, {:.2} s, {:.3e} rays/s; raw {:.3e} rays/s; ratio {:.3}",
        stats.rays_cast,
        stats.resolved_without_ray,
        stage_s,
        stage_rate,
        raw_rate,
        stage_rate / raw_rate
    );
    let mut g = c.benchmark_group("svc");
    g.sample_size(10);
    g.bench_function("raw_occlusion_rays", |b| b.iter(|| occ.raw_throughput(&rays)));
    g.finish();
}

criterion_group!(svc_benches, benches);
criterion_main!(svc_benches);
