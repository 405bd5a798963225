//! `vcuts view`: the interactive viewer (`vcut-view`) on a `.vcuts` file, or on a scene
//! precomputed first; `--screenshot` renders the same frame with no window.

use crate::outcome::ms_since;
use anyhow::{Context, Result, bail};
use serde::Serialize;
use std::path::PathBuf;
use std::time::{Duration, Instant};
use vcut_view::{Gpu, LeafSession, LeafViewOptions, Mode, OrbitCamera, Session, ViewOptions};

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
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = finite)]
    pub env_rotation: f32,
    /// Exposure before tone mapping (finite, above 0; default: automatic).
    #[arg(long, value_parser = positive, allow_negative_numbers = true)]
    pub exposure: Option<f32>,
    /// What to show: cuts, exact (the exact-direction reference), difference (heat map), or
    /// the screen-space methods ssao and ssdo (WGSL passes, no precomputation).
    #[arg(long, value_enum, default_value_t = ViewMode::Cuts)]
    pub mode: ViewMode,
    /// Render one frame with no window into this PNG and exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Screenshot width in pixels (1 to 16,384).
    #[arg(long, default_value_t = 1280, value_parser = crate::values::side)]
    pub width: u32,
    /// Screenshot height in pixels (1 to 16,384).
    #[arg(long, default_value_t = 720, value_parser = crate::values::side)]
    pub height: u32,
    /// Close the window after this many frames (scripted runs).
    #[arg(long)]
    pub frames: Option<u64>,
    /// Re-merge at every mouse move while dragging if a move costs less than this (ms; finite,
    /// at least 0).
    #[arg(long, default_value_t = 120.0, value_parser = non_negative)]
    pub live_move_ms: f64,
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

/// A finite number (`--env-rotation`).
fn finite(s: &str) -> Result<f32, String> {
    s.parse::<f32>().ok().filter(|x| x.is_finite()).ok_or_else(|| format!("{s:?}: not a finite number"))
}

/// A finite number above 0 (`--exposure`).
fn positive(s: &str) -> Result<f32, String> {
    finite(s).and_then(|x| if x > 0.0 { Ok(x) } else { Err(format!("{s:?}: must be above 0")) })
}

/// A finite number, at least 0 (`--live-move-ms`).
fn non_negative(s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite() && *x >= 0.0)
        .ok_or_else(|| format!("{s:?}: must be a finite number, at least 0"))
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
}

/// `view --leaves`: the plant precomputed, then the leaf window (or a screenshot).
fn run_leaves(args: &ViewArgs) -> Result<ViewOutcome> {
    let p = &args.plant;
    let material = crate::leaves::material(p)?;
    let t = Instant::now();
    let scene = crate::leaves::scene(p, &material)?;
    let (lvc, prt) = crate::leaves::params(p);
    let inputs = vcut_leaf::store::Inputs { scene: &scene, lvc, prt, suns: None };
    let reuse = if p.fresh { vcut_leaf::store::Reuse::Never } else { vcut_leaf::store::Reuse::IfMatching };
    let file = crate::leaves::data_path(p, &inputs);
    let Some(pre) = crate::leaves::precompute(&scene, (&lvc, &prt), None, &file, reuse, p.estimate)?.ready() else {
        return Ok(ViewOutcome::default());
    };
    let mut out = ViewOutcome { store: Some(crate::leaves::StoreOutcome::of(&pre)), ..ViewOutcome::default() };
    let setup_s = t.elapsed().as_secs_f64();
    let env_spec = args.env.as_deref().unwrap_or("builtin:sky");
    let env = crate::inspect::load_envmap(env_spec)?;
    let camera = OrbitCamera::from_camera(&crate::leaves::camera(&scene));
    let lvc_mb = (pre.data.lvc.raw_bytes() as f64 / 1e6, pre.data.lvc.compressed_bytes() as f64 / 1e6);
    let summary = vec![
        ("plant".to_string(), p.plant.to_string()),
        ("vertices".into(), scene.vertex_count().to_string()),
        ("environment".into(), env_spec.to_string()),
        ("sun maps".into(), format!("{:.1} MB raw, {:.1} MB RLE", lvc_mb.0, lvc_mb.1)),
        ("SH transfer".into(), format!("{:.1} MB", pre.data.transfer.bytes() as f64 / 1e6)),
        ("precompute".into(), format!("{setup_s:.1} s")),
    ];
    let mut session = LeafSession::new(scene, pre.data, env, camera);
    if session.data().lvc.vertex_count() == 0 {
        bail!("the plant has no vertices");
    }
    if let Some((e, a)) = crate::leaves::sun_angles(p) {
        session.set_sun(e, a);
    }
    session.set_edge_rays(p.sun_edge_rays);
    session.exposure = args.exposure;
    if let Some(path) = &args.screenshot {
        let gpu = Gpu::headless()?;
        out.adapter = Some(gpu.describe());
        let t = Instant::now();
        let image = vcut_view::leaf_screenshot(&gpu, &mut session, args.width, args.height)?;
        (out.screenshot_ms, out.shade_ms) = (Some(ms_since(t)), Some(session.timings.shade_ms));
        create_parent(path)?;
        vcut_view::headless::write_png(&image, path)?;
        out.png = Some(path.clone());
        return Ok(out);
    }
    let options = LeafViewOptions { title: format!("vcuts leaves — {}", p.plant), summary, max_frames: args.frames };
    vcut_view::run_leaf_window(session, options)?;
    Ok(out)
}

/// Creates `path`'s folder if it has one.
fn create_parent(path: &std::path::Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    Ok(())
}

/// Environment maps the panel offers: the built-ins, the data's own, and the shared assets'.
fn env_choices(current: &str) -> Vec<String> {
    let mut v: Vec<String> = ["builtin:sky", "builtin:studio", "builtin:constant"].map(String::from).to_vec();
    if !v.iter().any(|e| e == current) {
        v.insert(0, current.to_string());
    }
    if let Some(dir) = vcut_scene::assets::dir().map(|d| d.join("envmaps"))
        && let Ok(entries) = std::fs::read_dir(&dir)
    {
        let mut files: Vec<String> = entries
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|x| x == "hdr" || x == "exr"))
            .map(|p| p.display().to_string())
            .collect();
        files.sort();
        v.extend(files);
    }
    v
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
    fn mode(self) -> Mode {
        match self {
            ViewMode::Cuts => Mode::Cuts,
            ViewMode::Exact => Mode::Exact,
            ViewMode::Difference => Mode::Difference,
            ViewMode::Ssao => Mode::Ssao,
            ViewMode::Ssdo => Mode::Ssdo,
        }
    }

    fn name(self) -> &'static str {
        match self {
            ViewMode::Cuts => "cuts",
            ViewMode::Exact => "exact",
            ViewMode::Difference => "difference",
            ViewMode::Ssao => "ssao",
            ViewMode::Ssdo => "ssdo",
        }
    }
}

/// Runs `view`: the window, or with `--screenshot` one frame into a PNG.
pub fn run(args: &ViewArgs) -> Result<ViewOutcome> {
    if args.leaves {
        return run_leaves(args);
    }
    let input = match (&args.input, &args.scene) {
        (Some(p), _) => p.clone(),
        (None, scene) => crate::precompute::cached_or_run(scene.as_deref().unwrap_or("builtin:teapot"), &args.preset)?,
    };
    let settings = args.frame.settings();
    let opened =
        crate::render::open_with(&input, args.env.as_deref(), args.reconstruction, &settings, args.camera.as_deref())?;
    let crate::render::Opened { data, mut frame, env, env_name, view, setup_s } = opened;
    crate::render::apply_edits(&mut frame, &args.brdfs, &args.moves)?;
    let camera = crate::render::camera(view.as_ref(), args.camera.as_deref(), &frame)?;
    let vertices: usize = (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count()).sum();
    let summary = vec![
        ("file".to_string(), input.display().to_string()),
        ("preset".into(), data.record.params.preset.clone()),
        ("directions".into(), data.record.params.directions.to_string()),
        (
            "data size".into(),
            std::fs::metadata(&input).map_or("?".into(), |m| format!("{:.1} MB", m.len() as f64 / 1e6)),
        ),
        ("vertices".into(), vertices.to_string()),
        ("objects".into(), format!("{}", frame.object_count())),
        ("setup".into(), format!("{setup_s:.2} s")),
    ];
    let offset = data.svc_origin_offset();
    let mut session = Session::new(frame, env.clone(), &env_name, offset, OrbitCamera::from_camera(&camera));
    session.exposure = args.exposure;
    if args.env_rotation != 0.0 {
        session.set_env_rotation(args.env_rotation);
    }
    session.set_mode(args.mode.mode())?;
    if let Some(path) = &args.screenshot {
        return screenshot(args, &mut session, path);
    }
    window(args, session, (&input, summary), (env, env_name))?;
    Ok(ViewOutcome::default())
}

/// One frame of `session` with no window into the PNG `path`.
fn screenshot(args: &ViewArgs, session: &mut Session, path: &std::path::Path) -> Result<ViewOutcome> {
    let t = Instant::now();
    while session.step_reference(Duration::from_secs(3600)) {}
    let reference_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let gpu = Gpu::headless()?;
    let mut out = ViewOutcome { adapter: Some(gpu.describe()), gpu_setup_ms: Some(ms_since(t)), ..Default::default() };
    let t = Instant::now();
    let image = vcut_view::screenshot(&gpu, session, args.width, args.height)?;
    out.screenshot_ms = Some(ms_since(t));
    create_parent(path)?;
    vcut_view::headless::write_png(&image, path)?;
    out.mode = Some(args.mode.name());
    out.exposure = Some(session.exposure_in_use());
    out.shade_ms = Some(session.timings.shade_ms);
    if matches!(args.mode.mode(), Mode::Exact | Mode::Difference) {
        out.reference_s = Some(reference_s);
        out.vertex_rel_l2_vs_exact = session.reference_error();
    }
    out.screenshot = Some(path.to_path_buf());
    Ok(out)
}

/// The viewer's window on `session` until it closes.
fn window(
    args: &ViewArgs,
    session: Session,
    (input, summary): (&std::path::Path, Vec<(String, String)>),
    (env, env_name): (vcut_envmap::EnvMap, String),
) -> Result<()> {
    let base_env = env;
    let base_name = env_name.clone();
    let reconstruction = base_env.reconstruction();
    let options = ViewOptions {
        title: format!("vcuts viewer — {}", input.display()),
        summary,
        envs: env_choices(&env_name),
        load_env: Box::new(move |name| {
            if name == base_name {
                Ok(base_env.clone())
            } else {
                // Another map takes the same reconstruction (a cube map stays box).
                let map = crate::inspect::load_envmap(name).map_err(|e| format!("{e:#}"))?;
                let cube = matches!(map.layout(), vcut_envmap::Layout::Cube { .. });
                if cube { Ok(map) } else { map.with_reconstruction(reconstruction).map_err(|e| e.to_string()) }
            }
        }),
        live_move_ms: args.live_move_ms,
        max_frames: args.frames,
    };
    vcut_view::run_window(session, options)?;
    Ok(())
}
