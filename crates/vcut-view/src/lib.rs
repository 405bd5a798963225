//! The interactive viewer of visibility-cut frames, and its headless twin.
//!
//! - [`session::Session`]: what is shown — the frame (merged cuts, per-object BRDFs, the
//!   light tree), the orbit camera, the display mode (precomputed cuts / exact reference
//!   computed progressively / their difference as a heat map), and the cost of every edit.
//!   Every edit the window offers is a method here, so tests drive the same code as a person.
//! - [`gpu`]: the viewer's errors ([`ViewError`]); the device is `vcut_gpu::Gpu` (any adapter,
//!   lavapipe or llvmpipe's OpenGL on a CPU-only machine; what an adapter lacks is an error,
//!   never a panic).
//! - [`screen`]: the screen-space modes, the session's inputs handed to the WGSL passes of
//!   `vcut_ssdo::gpu` (re-exported as [`ssdo`]).
//! - [`render`]: the scene renderer — the environment map as background (bilinear lat-long lookup as
//!   `vcut_envmap::Layout::bilinear`), meshes with interpolated per-vertex colours, and the CPU
//!   renderer's display transform (exposure, ACES filmic in Narkowicz's fit, sRGB) — and
//!   [`headless::screenshot`], the same frame rendered with no window and read back. The
//!   renderer takes draw inputs ([`render::Meshes`], [`render::LeafMesh`], [`render::Shown`]),
//!   which the sessions provide.
//! - [`leaf::LeafSession`]: the plant-leaf renderer of `vcut-leaf` (two passes, editable leaf
//!   material and sun, level of detail), drawn two-sided by the same renderer
//!   ([`headless::leaf_screenshot`] headless).
//! - [`app::run_window`] and [`leaf_app::run_leaf_window`]: the two apps, winit 0.30 + egui
//!   0.37 around the sessions, in one window host (event loop, frame skeleton, camera
//!   gestures).
//!
//! Shading stays on the CPU (the merge and the BRDF sums of `vcut-shade`); the GPU
//! interpolates the per-vertex radiance over the triangles and draws the background, as
//! `vcut_shade::image::rasterize` does on the CPU.

mod albedo;
pub mod app;
pub mod camera;
pub mod gpu;
pub mod headless;
mod host;
pub mod leaf;
pub mod leaf_app;
pub mod render;
pub mod report;
pub mod screen;
pub mod session;
pub mod shown;
/// The WGSL SSAO / SSDO passes, which live beside their CPU twin in `vcut-ssdo`.
pub use vcut_ssdo::gpu as ssdo;
mod window;

pub use app::{ViewOptions, run_window};
pub use camera::OrbitCamera;
pub use gpu::{Gpu, ViewError};
pub use headless::{leaf_screenshot, screenshot};
pub use leaf::{LeafSession, LeafTimings};
pub use leaf_app::{LeafViewOptions, run_leaf_window};
pub use render::SceneRenderer;
pub use session::{Display, Mode, Polled, Session, SessionError, Timings};
