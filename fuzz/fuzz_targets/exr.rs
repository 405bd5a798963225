//! Fuzz target: the OpenEXR loader fed arbitrary bytes returns a valid map or an error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use vcut_envmap::io::Format;
use vcut_envmap::{InvalidTexels, load_bytes};

fuzz_target!(|data: &[u8]| {
    if let Ok((map, _)) = load_bytes(data, Format::Exr, Path::new("fuzz.exr"), InvalidTexels::Clamp) {
        assert!(map.texels().iter().flatten().all(|c| c.is_finite() && *c >= 0.0));
    }
});
