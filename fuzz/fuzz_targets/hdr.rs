//! Fuzz target: the Radiance HDR loader fed arbitrary bytes returns a valid map or an error.
//!
//! `vcut-envmap` contains panics of the `image` HDR decoder (safe Rust: an unbounded run-length
//! multiplier) with `catch_unwind`, as for EXR; this target replaces libfuzzer-sys's aborting
//! panic hook with a silent one, so only a panic that escapes `load_bytes` is reported.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use vcut_envmap::io::Format;
use vcut_envmap::{InvalidTexels, load_bytes};

fuzz_target!(
    init: {
        std::panic::set_hook(Box::new(|_| {}));
    },
    |data: &[u8]| {
        if let Ok((map, _)) = load_bytes(data, Format::Hdr, Path::new("fuzz.hdr"), InvalidTexels::Reject) {
            assert!(map.texels().iter().flatten().all(|c| c.is_finite() && *c >= 0.0));
        }
    }
);
