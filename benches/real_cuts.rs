//! The frame's merge on real cuts: per vertex, its SVC times every other object's field
//! interpolated from 8 samples (inside samples dropped), from a precomputed `.vcuts` file of the
//! built-in teapot scene; the height (counter) merge against the index baseline on the same
//! inputs, in the same run. Also prints bytes per node of the real cuts in each coding.
//!
//! The file: `VCUT_BENCH_VCUTS` if set, else `target/vcuts/teapot-balanced.vcuts`, precomputed
//! here (preset `balanced`, about 20 s on 2 cores) when absent or unreadable. A relative
//! `VCUT_BENCH_VCUTS` is relative to `benches/` (cargo runs benches there).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use vcut_cut::Cut;
use vcut_cut::codec::{self, ShapeCoding, ValueFormat};
use vcut_data::{FieldLayout, Precomputed};
use vcut_merge::baseline::{self, IndexCut, IndexGroup};
use vcut_merge::{Group, MergedCut, merge};
use vcut_precompute::run::{Job, NoProgress, precompute};
use vcut_precompute::{PrecomputeParams, run::cut_sizes};
use vcut_scene::Scene;

/// One vertex's merge inputs: its SVC, then per other object 8 cuts and weights.
struct Frame {
    svc: Cut,
    fields: Vec<(Vec<Cut>, Vec<f32>)>,
}

/// The same inputs index-coded: SVC, then per other object 8 cuts and weights.
type IndexFrame = (IndexCut, Vec<(Vec<IndexCut>, Vec<f32>)>);

fn data_file() -> PathBuf {
    if let Some(p) = std::env::var_os("VCUT_BENCH_VCUTS") {
        return p.into();
    }
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/vcuts/teapot-balanced.vcuts");
    // Absent, or written by an older format version: precompute it.
    if cut_sizes(&path).is_err() {
        println!("precomputing {} (preset balanced) for the merge bench", path.display());
        let scene = Scene::open("builtin:teapot").expect("built-in scene");
        let job = Job {
            scene: &scene,
            scene_source: "builtin:teapot".into(),
            environment: "scene".into(),
            params: PrecomputeParams::balanced(),
            cache_dir: Some(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/vcut-cache")),
            output: path.clone(),
        };
        precompute(&job, &NoProgress, &AtomicBool::new(false)).expect("precompute");
    }
    path
}

/// One field sphere's cuts and inside marks.
type SphereData = (Vec<Cut>, Vec<bool>);

/// Up to `per_object` vertices of every object, each with its frame's inputs at rest.
fn frames(data: &mut Precomputed, per_object: usize) -> Vec<Frame> {
    let layouts: Vec<Option<FieldLayout>> = data.layouts.clone();
    let spheres: Vec<Vec<SphereData>> = layouts
        .iter()
        .enumerate()
        .map(|(o, l)| {
            l.map_or(Vec::new(), |l| (0..l.spheres).map(|s| data.field_sphere(o, s).expect("field")).collect())
        })
        .collect();
    let mut out = Vec::new();
    for o in 0..data.objects.len() {
        let svcs = data.svc_cuts(o).expect("svc");
        let positions = data.objects[o].mesh.positions().to_vec();
        let step = (positions.len() / per_object).max(1);
        for v in (0..positions.len()).step_by(step).take(per_object) {
            let mut fields = Vec::new();
            for (other, l) in layouts.iter().enumerate() {
                let Some(l) = l.filter(|_| other != o) else { continue };
                let Some(mut samples) = l.lookup(positions[v]) else { continue };
                let s = &spheres[other];
                if FieldLayout::drop_inside(&mut samples, |x| s[x.sphere as usize].1[x.point as usize]) == 0 {
                    continue;
                }
                let cuts = samples.iter().map(|x| s[x.sphere as usize].0[x.point as usize].clone()).collect();
                fields.push((cuts, samples.iter().map(|x| x.weight).collect()));
            }
            out.push(Frame { svc: svcs[v].clone(), fields });
        }
    }
    out
}

fn bytes_per_node(data_path: &std::path::Path) {
    let sizes = cut_sizes(data_path).expect("sizes");
    for z in &sizes {
        let n = z.nodes.max(1) as f64;
        println!(
            "{}: {} cuts, {:.1} nodes/cut; bytes/node stored {:.3}, height codec {:.3}, index+f32 {:.3}",
            z.kind,
            z.cuts,
            z.nodes as f64 / z.cuts.max(1) as f64,
            z.bytes as f64 / n,
            z.heights_codec_bytes as f64 / n,
            z.index_baseline_bytes as f64 / n
        );
    }
}

fn benches(c: &mut Criterion) {
    let path = data_file();
    bytes_per_node(&path);
    let mut data = Precomputed::open(&path).expect("open");
    let frames = frames(&mut data, 150);
    let inputs: usize = frames
        .iter()
        .map(|f| f.svc.len() + f.fields.iter().map(|g| g.0.iter().map(Cut::len).sum::<usize>()).sum::<usize>())
        .sum();
    println!("{} vertices, {inputs} input nodes, {} directions", frames.len(), data.directions.len());
    // Codec round trip on real cuts, as a sanity check of what is timed.
    let f0 = &frames[0].svc;
    assert_eq!(
        &ShapeCoding::SplitFlags
            .decode(&codec::encode_split_flags(f0, ValueFormat::F32).unwrap(), f0.root_height(), ValueFormat::F32)
            .unwrap(),
        f0
    );

    let index: Vec<IndexFrame> = frames
        .iter()
        .map(|f| {
            (
                IndexCut::from_cut(&f.svc),
                f.fields.iter().map(|(c, w)| (c.iter().map(IndexCut::from_cut).collect(), w.clone())).collect(),
            )
        })
        .collect();
    let mut g = c.benchmark_group("real_cuts_teapot");
    g.sample_size(20);
    let mut out = MergedCut::default();
    g.bench_function("height_merge", |b| {
        b.iter(|| {
            let mut nodes = 0;
            for f in &frames {
                let svc = &f.svc;
                let refs: Vec<Vec<&Cut>> = f.fields.iter().map(|(c, _)| c.iter().collect()).collect();
                let mut groups = vec![Group::single(&svc)];
                groups.extend(refs.iter().zip(&f.fields).map(|(r, (_, w))| Group { cuts: r, weights: w }));
                nodes += merge(black_box(&groups), &mut out).expect("merge");
            }
            nodes
        })
    });
    g.bench_function("index_merge", |b| {
        b.iter(|| {
            let mut nodes = 0;
            for (svc, fields) in &index {
                let svc_ref = [svc];
                let refs: Vec<Vec<&IndexCut>> = fields.iter().map(|(c, _)| c.iter().collect()).collect();
                let mut groups = vec![IndexGroup { cuts: &svc_ref, weights: &[1.0] }];
                groups.extend(refs.iter().zip(fields).map(|(r, (_, w))| IndexGroup { cuts: r, weights: w }));
                nodes += baseline::merge(black_box(&groups), &mut out).expect("merge");
            }
            nodes
        })
    });
    g.finish();
}

criterion_group!(real, benches);
criterion_main!(real);
