//! Shared by the viewer's tests.

use std::io::Write;
use vcut_view::Gpu;

/// The headless device, or `None` (saying the test was skipped) without an adapter — unless
/// `VCUT_REQUIRE_GPU=1` (as `.ci/run` sets it), where a missing adapter fails the test. With
/// `VCUT_REQUIRE_BACKEND=vulkan|gl` the adapter must be on that backend (CI runs the GPU tests
/// on both).
///
/// The notice goes straight to the process's stderr, not through `eprintln!`, which the test
/// harness captures and shows only for failing tests: a skip must be visible in `cargo test`'s
/// output.
pub fn gpu(test: &str) -> Option<Gpu> {
    let require = std::env::var("VCUT_REQUIRE_GPU").is_ok_and(|v| v == "1");
    match Gpu::headless() {
        Ok(g) => {
            if let Ok(want) = std::env::var("VCUT_REQUIRE_BACKEND") {
                let got = format!("{:?}", g.backend()).to_lowercase();
                assert_eq!(got, want.to_lowercase(), "VCUT_REQUIRE_BACKEND={want}: the adapter is {}", g.describe());
            }
            Some(g)
        }
        Err(e) if require => panic!("VCUT_REQUIRE_GPU=1: {e}"),
        Err(e) => {
            let _ = writeln!(std::io::stderr(), "SKIPPED {test} (its GPU part): {e}");
            None
        }
    }
}
