//! Point repulsion from the Fibonacci start for 32,768 and 65,536 directions (goal: 65,536 in
//! ≤ 10 s on 2 cores), the random start at both sizes, and the exact Voronoi cell areas.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use vcut_sphere::{DirectionSet, RepulsionParams};

fn repulsion(c: &mut Criterion) {
    let mut g = c.benchmark_group("repulsion");
    g.sample_size(10);
    for n in [32_768usize, 65_536] {
        g.bench_function(format!("fibonacci_{n}"), |b| {
            b.iter(|| DirectionSet::generate(black_box(n), &RepulsionParams::default(), |_, _| {}).unwrap())
        });
    }
    for n in [32_768usize, 65_536] {
        g.bench_function(format!("random_{n}"), |b| {
            b.iter(|| DirectionSet::generate(black_box(n), &RepulsionParams::random(1), |_, _| {}).unwrap())
        });
    }
    let set = DirectionSet::generate(65_536, &RepulsionParams::default(), |_, _| {}).unwrap();
    g.bench_function("voronoi_cell_areas_65536", |b| b.iter(|| set.cell_areas()));
    g.finish();
}

criterion_group!(benches, repulsion);
criterion_main!(benches);
