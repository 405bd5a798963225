//! Shared by the viewer's tests.

use vcut_view::Gpu;

/// The headless device, or `None` (saying the test was skipped): [`vcut_gpu::test_device`].
pub fn gpu(test: &str) -> Option<Gpu> {
    vcut_gpu::test_device(test)
}
