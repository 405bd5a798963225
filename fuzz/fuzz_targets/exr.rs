//! Fuzz target: the OpenEXR loader fed arbitrary bytes returns a valid map or an error.
//!
//! `vcut-envmap` contains panics of the `exr` decoder (safe Rust) with `catch_unwind` and turns
//! them into errors. libfuzzer-sys's panic hook would abort even on those contained panics, so
//! this target replaces the hook with the default one: a panic that escapes `load_bytes` still
//! reaches libfuzzer-sys's own `catch_unwind`, which aborts and reports it.
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
        if let Ok((map, _)) = load_bytes(data, Format::Exr, Path::new("fuzz.exr"), InvalidTexels::Clamp) {
            assert!(map.texels().iter().flatten().all(|c| c.is_finite() && *c >= 0.0));
        }
    }
);
