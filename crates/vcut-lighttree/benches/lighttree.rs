//! Light-tree benches: exact build from a 1024×512 map, and the fast rebuild after a rotation
//! (the interactive path; goal ≤ 5 ms for 32,768 leaves), with the direction tree build beside.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use vcut_dirtree::DirectionTree;
use vcut_lighttree::LightTreeBuilder;
use vcut_sphere::{DirectionSet, RepulsionParams};

fn benches(c: &mut Criterion) {
    let set = DirectionSet::generate(32_768, &RepulsionParams::default(), |_, _| {}).expect("directions");
    let areas = set.cell_areas();
    let mut g = c.benchmark_group("lighttree_32768");
    g.sample_size(10);
    g.bench_function("direction_tree_build", |b| b.iter(|| DirectionTree::build(black_box(set.directions()), &areas)));
    let tree = DirectionTree::build(set.directions(), &areas).expect("tree");
    g.bench_function("builder_table", |b| b.iter(|| LightTreeBuilder::new(black_box(&tree))));
    let mut map = vcut_envmap::procedural::PreethamSky::default().bake(1024);
    let mut builder = LightTreeBuilder::new(&tree);
    g.bench_function("exact_build_1024x512_2x2", |b| b.iter(|| builder.build_exact(black_box(&map), 2)));
    let mut angle = 0.0f32;
    g.bench_function("rebuild_after_rotation_1024x512", |b| {
        b.iter(|| {
            angle += 7.0;
            map.set_rotation_y_degrees(angle);
            builder.build(black_box(&map))
        })
    });
    g.finish();
}

criterion_group!(lighttree, benches);
criterion_main!(lighttree);
