//! Encode/decode throughput of the height codec (each value format), split-flag decoding (the
//! presets' coding) and the index baseline on a 2,000-node cut of 32,768 leaves; bytes per node
//! of each are printed beside.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use vcut_cut::Cut;
use vcut_cut::codec::{self, ValueFormat};

fn sample_cut() -> Cut {
    // Deterministic cut: split depth-first by a fixed pattern until about 2,000 nodes.
    let mut state = 12345u64;
    let mut heights = Vec::new();
    let mut stack = vec![15u32];
    while let Some(h) = stack.pop() {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        if h > 0 && (state >> 33) % 100 < 84 {
            stack.extend([h - 1, h - 1]);
        } else {
            heights.push(h as u8);
        }
    }
    let values = (0..heights.len()).map(|i| ((i * 37) % 101) as f32 / 100.0).collect();
    Cut::new(15, heights, values).expect("valid")
}

fn benches(c: &mut Criterion) {
    let cut = sample_cut();
    let n = cut.len();
    let mut g = c.benchmark_group("codec");
    g.throughput(Throughput::Elements(n as u64));
    for f in ValueFormat::ALL {
        let bytes = codec::encode_heights(&cut, f).expect("in range");
        println!("height codec {}: {n} nodes, {:.3} bytes/node", f.name(), bytes.len() as f64 / n as f64);
        g.bench_function(format!("encode_heights_{}", f.name()), |b| {
            b.iter(|| codec::encode_heights(black_box(&cut), f))
        });
        g.bench_function(format!("decode_heights_{}", f.name()), |b| {
            b.iter(|| codec::decode_heights(black_box(&bytes), 15, f))
        });
    }
    // Split flags, as the presets store cuts (SVC values in 16 or 8 bits, exact fields in 1).
    for f in [ValueFormat::U16, ValueFormat::U8, ValueFormat::U1] {
        let mut cut = cut.clone();
        if f == ValueFormat::U1 {
            cut.values_mut().iter_mut().for_each(|v| *v = v.round());
        }
        let bytes = codec::encode_split_flags(&cut, f).expect("in range");
        println!("split flags {}: {n} nodes, {:.3} bytes/node", f.name(), bytes.len() as f64 / n as f64);
        g.bench_function(format!("decode_split_flags_{}", f.name()), |b| {
            b.iter(|| codec::decode_split_flags(black_box(&bytes), 15, f))
        });
    }
    let bytes = codec::encode_indices(&cut);
    println!("index baseline: {n} nodes, {:.3} bytes/node", bytes.len() as f64 / n as f64);
    g.bench_function("encode_indices", |b| b.iter(|| codec::encode_indices(black_box(&cut))));
    g.bench_function("decode_indices", |b| b.iter(|| codec::decode_indices(black_box(&bytes), 15)));
    g.finish();
}

criterion_group!(codec_benches, benches);
criterion_main!(codec_benches);
