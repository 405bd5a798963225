//! Shared by the viewer's tests.

use vcut_view::Gpu;

/// The headless device, or `None` (saying the test was skipped) without an adapter — unless
/// `VCUT_REQUIRE_GPU=1` (as `.ci/run` sets it), where a missing adapter fails the test.
pub fn gpu() -> Option<Gpu> {
    match Gpu::headless() {
        Ok(g) => Some(g),
        Err(e) if std::env::var("VCUT_REQUIRE_GPU").is_ok_and(|v| v == "1") => panic!("VCUT_REQUIRE_GPU=1: {e}"),
        Err(e) => {
            eprintln!("skipped: {e}");
            None
        }
    }
}
