//! Height (counter) merge against the index baseline on the same cuts, shaped like a frame's:
//! one SVC times two objects' fields interpolated from 8 cuts each, 32,768 leaves, from tens to
//! thousands of nodes per cut. The goal is the height merge at ≥ 2× the baseline's speed.
//! `refined_svc_x_2x8` is what a frame runs: exact (binary) field cuts refined once per cell,
//! then per vertex the SVC times two cells, beside the counter merge of the same 17 cuts.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use vcut_cut::Cut;
use vcut_merge::baseline::{self, IndexCut, IndexGroup};
#[path = "../tests/common/mod.rs"]
mod common;

use common::random_cut;
use vcut_merge::{Factor, Group, MergedCut, Refinement, merge, merge_refined};

fn frame_cuts(split: f32, seed: u64) -> (Cut, Vec<Cut>, Vec<Cut>) {
    let svc = random_cut(15, seed, split, 0.35, 0.3);
    let a = (0..8).map(|k| random_cut(15, seed ^ (k + 1), split * 0.9, 0.05, 0.7)).collect();
    let b = (0..8).map(|k| random_cut(15, seed ^ ((k + 1) << 24), split * 0.9, 0.05, 0.7)).collect();
    (svc, a, b)
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("merge_svc_x_2x8");
    g.sample_size(20);
    let wa = [0.125f32; 8];
    for (label, split) in [("small", 0.62f32), ("medium", 0.75), ("large", 0.86)] {
        let (svc, fa, fb) = frame_cuts(split, 42);
        let nodes = svc.len() + fa.iter().chain(&fb).map(Cut::len).sum::<usize>();
        println!("{label}: {nodes} input nodes (svc {})", svc.len());
        let (ra, rb): (Vec<&Cut>, Vec<&Cut>) = (fa.iter().collect(), fb.iter().collect());
        let svc_ref = &svc;
        let groups = [Group::single(&svc_ref), Group { cuts: &ra, weights: &wa }, Group { cuts: &rb, weights: &wa }];
        let mut out = MergedCut::default();
        g.bench_function(format!("height_{label}"), |b| b.iter(|| merge(black_box(&groups), &mut out)));
        let isvc = IndexCut::from_cut(&svc);
        let ia: Vec<IndexCut> = fa.iter().map(IndexCut::from_cut).collect();
        let ib: Vec<IndexCut> = fb.iter().map(IndexCut::from_cut).collect();
        let (ra2, rb2): (Vec<&IndexCut>, Vec<&IndexCut>) = (ia.iter().collect(), ib.iter().collect());
        let isvc_ref = [&isvc];
        let igroups = [
            IndexGroup { cuts: &isvc_ref, weights: &[1.0] },
            IndexGroup { cuts: &ra2, weights: &wa },
            IndexGroup { cuts: &rb2, weights: &wa },
        ];
        g.bench_function(format!("index_{label}"), |b| b.iter(|| baseline::merge(black_box(&igroups), &mut out)));
    }
    g.finish();
    // A frame's merge as the frame runs it: exact (binary) field cuts, each cell's 8 refined
    // once; per vertex the SVC refined alone and merged with two cells.
    let mut g = c.benchmark_group("refined_svc_x_2x8");
    g.sample_size(20);
    for (label, split) in [("medium", 0.75f32), ("large", 0.86)] {
        let svc = random_cut(15, 42, split, 0.35, 0.3);
        let binary = |seed: u64| random_cut(15, seed, split * 0.9, 0.5, 0.5);
        let fa: Vec<Cut> = (0..8).map(|k| binary(42 ^ (k + 1))).collect();
        let fb: Vec<Cut> = (0..8).map(|k| binary(42 ^ ((k + 1) << 24))).collect();
        let (ra, rb): (Vec<&Cut>, Vec<&Cut>) = (fa.iter().collect(), fb.iter().collect());
        let mut cell = Refinement::default();
        g.bench_function(format!("refine_cell_{label}"), |b| b.iter(|| cell.rebuild(black_box(&ra))));
        let (ca, cb) = (Refinement::new(&ra).unwrap(), Refinement::new(&rb).unwrap());
        println!(
            "{label}: cells of {} and {} nodes from 8 cuts of {} nodes on average",
            ca.len(),
            cb.len(),
            fa.iter().map(Cut::len).sum::<usize>() / 8
        );
        let wa = [0.125f32; 8];
        let mut svc_refined = Refinement::default();
        let mut out = MergedCut::default();
        g.bench_function(format!("vertex_{label}"), |b| {
            b.iter(|| {
                svc_refined.rebuild(&[black_box(&svc)]).unwrap();
                let factors = [
                    Factor { refinement: &svc_refined, weights: &[1.0] },
                    Factor { refinement: &ca, weights: &wa },
                    Factor { refinement: &cb, weights: &wa },
                ];
                merge_refined(&factors, &mut out)
            })
        });
        let svc_ref = &svc;
        let groups = [Group::single(&svc_ref), Group { cuts: &ra, weights: &wa }, Group { cuts: &rb, weights: &wa }];
        g.bench_function(format!("counter_{label}"), |b| b.iter(|| merge(black_box(&groups), &mut out)));
        println!("{label}: {} nodes merged", out.heights.len());
    }
    g.finish();
}

criterion_group!(merge_benches, benches);
criterion_main!(merge_benches);
