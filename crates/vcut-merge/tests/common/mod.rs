//! Random valid cuts for this crate's property tests and benches (deterministic from a seed);
//! kept out of the public API and included by both with `mod common`.

use vcut_cut::Cut;

/// SplitMix64 step.
fn next(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn unit(state: &mut u64) -> f32 {
    (next(state) >> 40) as f32 / (1u64 << 24) as f32
}

/// A random valid cut of root height `root`: from the root down, every node above the leaves
/// splits with probability `split`; values are uniform in [0, 1], exactly 0 with probability
/// `zero` and exactly 1 with probability `one`.
pub fn random_cut(root: u32, seed: u64, split: f32, zero: f32, one: f32) -> Cut {
    let mut state = seed;
    let mut heights = Vec::new();
    let mut stack = vec![root];
    while let Some(h) = stack.pop() {
        if h > 0 && unit(&mut state) < split {
            stack.push(h - 1);
            stack.push(h - 1);
        } else {
            heights.push(h as u8);
        }
    }
    let values = heights
        .iter()
        .map(|_| {
            let r = unit(&mut state);
            if r < zero {
                0.0
            } else if r < zero + one {
                1.0
            } else {
                unit(&mut state)
            }
        })
        .collect();
    match Cut::new(root, heights, values) {
        Ok(c) => c,
        Err(_) => unreachable!("a depth-first split of the root is always a valid cut"),
    }
}
