//! Fuzz target: sampling parameters. Arbitrary `key=value` lines set on a preset's
//! `PrecomputeParams` are refused with a `ParamError` or, once `check` accepts them, round-trip
//! through the file's record (`to_toml` / `from_toml`) unchanged; and a direction set generated
//! with arbitrary repulsion parameters (NaN, ±∞, huge included) is refused or holds finite unit
//! directions, from which a direction tree builds.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vcut_dirtree::DirectionTree;
use vcut_precompute::PrecomputeParams;
use vcut_sphere::{DirectionSet, Integrator, RepulsionParams, Start};

fn f64_at(b: &[u8], i: usize) -> f64 {
    let mut w = [0u8; 8];
    for (k, x) in w.iter_mut().enumerate() {
        *x = b.get(i * 8 + k).copied().unwrap_or(0);
    }
    f64::from_le_bytes(w)
}

fuzz_target!(|data: &[u8]| {
    let [preset, n, flags, iterations, window, rest @ ..] = data else { return };
    // Parameters: the text after 24 bytes of floats, one `key=value` a line.
    let text = String::from_utf8_lossy(rest.get(24..).unwrap_or_default());
    let mut params = match preset % 3 {
        0 => PrecomputeParams::fast(),
        1 => PrecomputeParams::balanced(),
        _ => PrecomputeParams::paper(),
    };
    for line in text.lines() {
        if let Some((k, v)) = line.split_once('=') {
            let _ = params.set(k.trim(), v.trim());
        }
    }
    params.settle();
    if params.check().is_ok() {
        let back = PrecomputeParams::from_toml(&params.to_toml()).expect("a checked record reads back");
        assert_eq!(back, params, "the record changed the parameters");
    }

    let repulsion = RepulsionParams {
        start: if flags & 1 == 0 { Start::Fibonacci } else { Start::Random },
        seed: u64::from(*flags),
        kernel_radius: f64_at(rest, 0),
        step: f64_at(rest, 1),
        tolerance: f64_at(rest, 2),
        max_iterations: u32::from(*iterations),
        integrator: if flags & 2 == 0 { Integrator::Descent } else { Integrator::Fire },
        window: u32::from(*window),
        wedges: 1 << ((flags >> 2) & 7),
    };
    let n = usize::from(*n) + 1;
    if let Ok(set) = DirectionSet::generate(n, &repulsion, |_, _| {}) {
        assert_eq!(set.len(), n);
        assert!(set.directions().iter().all(|d| d.is_finite() && (d.length() - 1.0).abs() <= 1e-4));
        let areas = set.cell_areas();
        assert!(areas.iter().all(|a| a.is_finite() && *a >= 0.0), "cell areas {areas:?}");
        if let Ok(tree) = DirectionTree::build(set.directions(), &areas) {
            assert!(tree.height() >= 2);
        }
        let bands = 1 << ((flags >> 5) & 3);
        if let Ok(tree) = DirectionTree::build_wedged(set.directions(), &areas, set.wedges(), bands) {
            tree.validate().expect("a wedged tree keeps its invariants");
            let shape = tree.turn_shape().expect("a wedged tree has a turn shape");
            let first = tree.index(shape.wedge_height, 0);
            assert_eq!(tree.turn(first, set.wedges()), Some(first), "a full turn is the identity");
        }
    }
});
