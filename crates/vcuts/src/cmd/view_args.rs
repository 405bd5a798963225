//! The arguments and the outcome of `vcuts view`, built with or without the viewer (the
//! feature `viewer`), so the options table and the command line are the same in both builds;
//! the viewer itself is `super::view`.

use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `view`.
#[derive(clap::Args, Clone)]
pub struct ViewArgs {
    /// The precomputed file (from `cargo xtask precompute`); default: `--scene` precomputed.
    pub input: Option<PathBuf>,
    /// Precompute this scene first (cached in target/vcuts/ like the demo's) and view it.
    #[arg(long, conflicts_with = "input")]
    pub scene: Option<String>,
    /// Preset for `--scene`.
    #[arg(long, default_value = "fast")]
    pub preset: String,
    /// Environment map (default: the data's).
    #[arg(long)]
    pub env: Option<String>,
    /// How maps are reconstructed between texel centres and integrated: box or bilinear
    /// (lat-long maps). Default: the data's (box).
    #[arg(long)]
    pub reconstruction: Option<vcut_envmap::Reconstruction>,
    /// Start from this scene camera (default: the scene's first).
    #[arg(long)]
    pub camera: Option<String>,
    /// Move an object first: NAME=dx,dy,dz (repeatable).
    #[arg(long = "move", value_name = "NAME=DX,DY,DZ", allow_hyphen_values = true)]
    pub moves: Vec<crate::values::Move>,
    /// Edit a BRDF first: NAME=MODEL[:KEY=VALUE,...] (repeatable).
    #[arg(long = "brdf", value_name = "NAME=SPEC")]
    pub brdfs: Vec<crate::values::BrdfEdit>,
    /// Environment rotation about +Y, degrees (finite).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = crate::options::real("env-rotation"))]
    pub env_rotation: f32,
    /// Exposure before tone mapping (finite, above 0; default: automatic).
    #[arg(long, value_parser = crate::options::real("exposure"), allow_hyphen_values = true)]
    pub exposure: Option<f32>,
    /// What to show: cuts, exact (the exact-direction reference), difference (heat map), or
    /// the screen-space methods ssao and ssdo (WGSL passes, no precomputation).
    #[arg(long, value_enum, default_value_t = ViewMode::Cuts)]
    pub mode: ViewMode,
    /// Render one frame with no window into this PNG and exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Screenshot width in pixels (1 to 16,384).
    #[arg(long, default_value_t = 1280, value_parser = crate::options::whole::<u32>("width"), allow_hyphen_values = true)]
    pub width: u32,
    /// Screenshot height in pixels (1 to 16,384).
    #[arg(long, default_value_t = 720, value_parser = crate::options::whole::<u32>("height"), allow_hyphen_values = true)]
    pub height: u32,
    /// Close the window after this many frames (scripted runs).
    #[arg(long, value_parser = crate::options::whole::<u64>("frames"), allow_hyphen_values = true)]
    pub frames: Option<u64>,
    /// No longer has an effect (a warning says so): every mouse move of a drag is merged off
    /// the window's thread, a step still waiting replaced by the next. Still checked (ms;
    /// finite, at least 0) so scripts that pass it keep working.
    #[arg(long, value_parser = crate::options::real64("live-move-ms"), allow_hyphen_values = true)]
    pub live_move_ms: Option<f64>,
    /// Drag this object by itself (with `--frames`): one step a frame around a horizontal
    /// circle of a quarter of its radius, for three quarters of the frames, then released. The
    /// outcome has the frame times during the drag and how far the shading lagged.
    #[arg(long, value_name = "NAME", requires = "frames", conflicts_with_all = ["screenshot", "leaves"])]
    pub drag: Option<String>,
    /// Keep the dragging-quality frame at rest. By default, while nothing moves, the window
    /// refines the frame toward the exact reference in slices of a quarter second (field
    /// factors near their sources cast by rays; the panel shows how far), and the next move
    /// cancels it.
    #[arg(long, conflicts_with_all = ["screenshot", "leaves"])]
    pub no_refine: bool,
    /// The frame's settings, as `render`'s (`--no-sun-rays` starts with the panel's "sun by
    /// rays" box unticked, `--light-error` sets its slider, `--flat-edge-leaves interactive`
    /// ticks "ground edges estimated").
    #[command(flatten)]
    pub frame: vcut_shade::FrameArgs,
    /// The plant-leaf viewer instead (`vcut-leaf`: the plant precomputed first, then the sun,
    /// method, level of detail and leaf panel); the plant options below apply.
    #[arg(long, conflicts_with_all = ["input", "scene"])]
    pub leaves: bool,
    /// The plant, leaves and sun (with --leaves).
    #[command(flatten)]
    pub plant: crate::leaves::PlantArgs,
}

/// What `view --screenshot` measured and wrote (nothing for a window).
#[derive(Debug, Clone, Default, Serialize)]
pub struct ViewOutcome {
    /// `--leaves`: where the leaf data is and what was done to get it.
    #[serde(flatten)]
    pub store: Option<crate::leaves::StoreOutcome>,
    /// The wgpu adapter.
    pub adapter: Option<String>,
    /// Setting the GPU up (ms).
    pub gpu_setup_ms: Option<f64>,
    /// The screenshot's frame (ms).
    pub screenshot_ms: Option<f64>,
    /// What it shows.
    pub mode: Option<&'static str>,
    /// Its exposure.
    pub exposure: Option<f32>,
    /// Shading (ms).
    pub shade_ms: Option<f64>,
    /// The exact reference's time (exact and difference modes).
    pub reference_s: Option<f64>,
    /// The frame against the exact reference (exact and difference modes).
    pub vertex_rel_l2_vs_exact: Option<f64>,
    /// The screenshot written.
    pub screenshot: Option<PathBuf>,
    /// `--leaves`: the screenshot written.
    pub png: Option<PathBuf>,
    /// A window: what it measured ([`WindowOutcome`]).
    #[serde(flatten)]
    pub window: Option<WindowOutcome>,
}

/// What a window run measured (`vcut_view::report::WindowReport`); frame times over the
/// `--drag` frames, or every frame but the first without one.
#[derive(Debug, Clone, Default, Serialize)]
pub struct WindowOutcome {
    /// Frames drawn.
    pub frames: u64,
    /// Frames drawn during the `--drag`.
    pub drag_frames: u64,
    /// Frame times (ms): the median.
    pub frame_ms_p50: f64,
    /// Frame times (ms): the 95th percentile.
    pub frame_ms_p95: f64,
    /// Frame times (ms): the largest.
    pub frame_ms_max: f64,
    /// Of those frames, the time from taking the window's texture to presenting it (ms): the
    /// median.
    pub draw_ms_p50: f64,
    /// The same: the 95th percentile.
    pub draw_ms_p95: f64,
    /// Moves posted to the frame's worker.
    pub moves_posted: u64,
    /// Of those, dropped as stale (a later drag step replaced them before they ran).
    pub moves_dropped: u64,
    /// Moves the worker merged (settles included).
    pub moves_merged: u64,
    /// Mean time of a move's merge on the worker (ms).
    pub merge_ms_mean: f64,
    /// How long a shading arrived after the move it follows (ms): the median.
    pub shading_lag_ms_p50: f64,
    /// How long a shading arrived after the move it follows (ms): the 95th percentile.
    pub shading_lag_ms_p95: f64,
    /// Shadings that arrived after a move.
    pub shadings: usize,
    /// Refinement slices the window ran at rest (0 with `--no-refine`).
    pub refine_slices: u64,
    /// The share of the field factors exact when the window closed (`null`: no refinement
    /// since the last move).
    pub refined_share: Option<f64>,
}

/// What the viewer shows first (`--mode`).
#[derive(clap::ValueEnum, Clone, Copy, PartialEq, Eq, Debug)]
pub enum ViewMode {
    /// The visibility cuts.
    Cuts,
    /// The exact-direction reference.
    Exact,
    /// The difference as a heat map.
    #[value(alias = "diff")]
    Difference,
    /// Screen-space ambient occlusion (WGSL passes).
    Ssao,
    /// Screen-space directional occlusion (WGSL passes).
    Ssdo,
}

impl ViewMode {
    /// The mode's name, as `--mode` takes it.
    pub fn name(self) -> &'static str {
        match self {
            ViewMode::Cuts => "cuts",
            ViewMode::Exact => "exact",
            ViewMode::Difference => "difference",
            ViewMode::Ssao => "ssao",
            ViewMode::Ssdo => "ssdo",
        }
    }
}
