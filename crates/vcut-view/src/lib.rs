//! The interactive viewer of visibility-cut frames, and its headless twin.
//!
//! - [`session::Session`]: what is shown — the frame (merged cuts, per-object BRDFs, the
//!   light tree), the orbit camera, the display mode (precomputed cuts / exact reference
//!   computed progressively / their difference as a heat map), and the cost of every edit.
//!   Every edit the window offers is a method here, so tests drive the same code as a person.
//! - [`gpu`]: a wgpu device on any adapter (lavapipe or llvmpipe's OpenGL on a CPU-only
//!   machine), whose errors — what an adapter lacks — are [`ViewError`]s, never panics.
//! - [`render`]: the scene renderer — the environment map as background (bilinear lat-long lookup as
//!   `vcut_envmap::Layout::bilinear`), meshes with interpolated per-vertex colours, and the CPU
//!   renderer's display transform (exposure, ACES filmic in Narkowicz's fit, sRGB) — and
//!   [`render::screenshot`], the same frame rendered with no window and read back.
//! - [`leaf::LeafSession`]: the plant-leaf renderer of `vcut-leaf` (two passes, editable leaf
//!   material and sun, level of detail), drawn two-sided by the same renderer
//!   ([`render::leaf_screenshot`] headless).
//! - [`app::run_window`]: winit 0.30 + egui 0.37 around them.
//!
//! Shading stays on the CPU (the merge and the BRDF sums of `vcut-shade`); the GPU
//! interpolates the per-vertex radiance over the triangles and draws the background, as
//! `vcut_shade::image::rasterize` does on the CPU.

pub mod app;
pub mod camera;
pub mod gpu;
pub mod leaf;
pub mod leaf_app;
pub mod render;
pub mod session;
pub mod ssdo;
mod window;

pub use app::{ViewOptions, run_window};
pub use camera::OrbitCamera;
pub use gpu::{Gpu, ViewError};
pub use leaf::{LeafSession, LeafTimings};
pub use leaf_app::{LeafViewOptions, run_leaf_window};
pub use render::{SceneRenderer, leaf_screenshot, screenshot};
pub use session::{Display, Mode, Session, Timings};
