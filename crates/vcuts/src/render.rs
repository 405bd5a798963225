//! `cargo xtask render`: a frame from a `.vcuts` file — objects moved, BRDFs edited — as PNG
//! (and EXR, PLY), with merge, shade and raster times, and optionally the error against the
//! exact-direction reference.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::time::Instant;
use vcut_data::InsideSamples;
use vcut_envmap::EnvMap;
use vcut_scene::Camera;
use vcut_shade::glb::write_glb;
use vcut_shade::image::{auto_exposure, frame_image, pixel_errors, rasterize, write_exr, write_ply, write_png};
use vcut_shade::passes::{Pass, render_passes, write_exr_passes};
use vcut_shade::reference::{MonteCarloParams, errors, exact_direction, monte_carlo};
use vcut_shade::{FlatEdges, Frame, FrameCaches, SunRays};

pub use crate::open::{Opened, apply_edits, auto_camera, camera, light_error, open, open_with};
use crate::ssdo::ScreenMode;

/// What `render` draws.
#[derive(clap::ValueEnum, Clone, Copy, PartialEq, Eq, Debug)]
pub enum RenderMode {
    /// The precomputed visibility cuts.
    Cuts,
    /// Screen-space ambient occlusion.
    Ssao,
    /// Screen-space directional occlusion with one bounce.
    Ssdo,
    /// SSDO with a second depth layer.
    SsdoPeeled,
}

impl RenderMode {
    /// The screen-space method, if this is one.
    pub fn screen(self) -> Option<ScreenMode> {
        match self {
            RenderMode::Cuts => None,
            RenderMode::Ssao => Some(ScreenMode::Ssao),
            RenderMode::Ssdo => Some(ScreenMode::Ssdo),
            RenderMode::SsdoPeeled => Some(ScreenMode::SsdoPeeled),
        }
    }
}

/// What `render --compare` (and `reference`) compares the frame with.
#[derive(clap::ValueEnum, Clone, Copy, PartialEq, Eq, Debug)]
pub enum Compare {
    /// The exact-direction reference.
    Exact,
    /// The Monte Carlo reference.
    Mc,
    /// Both references.
    Both,
    /// The ray-traced reference of a screen-space mode.
    Raytraced,
}

impl Compare {
    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Compare::Exact => "exact",
            Compare::Mc => "mc",
            Compare::Both => "both",
            Compare::Raytraced => "raytraced",
        }
    }
}

/// Field samples inside an object (`--inside-samples`).
#[derive(clap::ValueEnum, Clone, Copy, PartialEq, Eq, Debug)]
pub enum Inside {
    /// Blended in as fully occluded.
    Occluded,
    /// Dropped, their weight given to the others.
    Dropped,
}

/// Sets the frame's `Frame::set_flat_edge_leaves` to `edges` (`--flat-edge-leaves` of render and
/// view; an error names the flag).
pub fn set_flat_edges(frame: &mut Frame, edges: FlatEdges) -> Result<()> {
    frame.set_flat_edge_leaves(edges.leaves(frame)).map_err(|e| anyhow::anyhow!("--flat-edge-leaves: {e}"))?;
    Ok(())
}

/// Arguments of `render`.
#[derive(clap::Args, Clone)]
pub struct RenderArgs {
    /// The precomputed file (from `cargo xtask precompute`).
    pub input: PathBuf,
    /// Environment map (default: the scene's).
    #[arg(long)]
    pub env: Option<String>,
    /// How the map's radiance is reconstructed between texel centres and integrated: box or
    /// bilinear (lat-long maps; Mitsuba 3's envmap). Default: the scene file's (box).
    #[arg(long)]
    pub reconstruction: Option<vcut_envmap::Reconstruction>,
    /// Move an object: NAME=dx,dy,dz (repeatable; from its rest position).
    #[arg(long = "move", value_name = "NAME=DX,DY,DZ")]
    pub moves: Vec<String>,
    /// Edit a BRDF: NAME=MODEL[:KEY=VALUE,...], e.g. teapot=blinn-phong:alpha=70 (repeatable).
    #[arg(long = "brdf", value_name = "NAME=SPEC")]
    pub brdfs: Vec<String>,
    /// Camera name (default: the scene's first).
    #[arg(long)]
    pub camera: Option<String>,
    /// Image width.
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    /// Image height.
    #[arg(long, default_value_t = 480)]
    pub height: u32,
    /// Exposure applied before tone mapping (PNG only); default: the geometry's log-average
    /// luminance to middle grey.
    #[arg(long)]
    pub exposure: Option<f32>,
    /// Output PNG (tone-mapped: ACES filmic, Narkowicz's fit, sRGB).
    #[arg(short, long, default_value = "target/render/frame.png")]
    pub output: PathBuf,
    /// Also write the linear image as EXR, with its alpha (coverage: 0 where the background
    /// map shows).
    #[arg(long)]
    pub exr: Option<PathBuf>,
    /// Passes the EXR also holds, as layers: a comma-separated list of `albedo`, `normal`,
    /// `depth`, `diffuse`, `specular` (diffuse + specular = the image), or `all`.
    #[arg(long, value_parser = parse_passes, requires = "exr")]
    pub exr_passes: Option<Passes>,
    /// Also write the scene at its current positions as a PLY mesh: per vertex position,
    /// normal and linear outgoing radiance as float `red green blue`, toward the camera where
    /// the camera can see it, else along its normal (so every vertex is shaded).
    #[arg(long)]
    pub export_ply: Option<PathBuf>,
    /// Also write the scene at its current positions as binary glTF (`.glb`) with the shading
    /// baked per vertex (`COLOR_0` tone-mapped as the PNG, `_RADIANCE` linear; every vertex
    /// shaded as in the PLY), an unlit material and the camera: Blender and three.js open it.
    #[arg(long)]
    pub export_glb: Option<PathBuf>,
    /// What to draw: `cuts` (the precomputed visibility cuts) or a screen-space method on the
    /// same geometry and lighting with no precomputation — `ssao`, `ssdo` (directional
    /// occlusion + one indirect bounce), `ssdo-peeled` (with a second depth layer).
    #[arg(long, value_enum, default_value_t = RenderMode::Cuts)]
    pub mode: RenderMode,
    /// Compare with references: `exact` (all leaf directions cast, no clustering), `mc` (Monte
    /// Carlo over every texel of the map, to 1 % standard error per vertex) or `both`; a
    /// screen-space mode with `raytraced` (direct light with visibility plus one bounce).
    #[arg(long, value_enum)]
    pub compare: Option<Compare>,
    /// Field samples inside an object: `occluded` (blended in as fully occluded, the default)
    /// or `dropped` (their weight given to the others); see `vcut_data::InsideSamples`.
    #[arg(long, value_enum, default_value_t = Inside::Occluded)]
    pub inside_samples: Inside,
    /// Carry the sun through the cuts too, as the paper does. By default the leaves of the
    /// light whose error through the cuts is largest are cast by rays at run time, until the
    /// estimated error is within `--light-error` (`vcut_shade::sun`).
    #[arg(long, conflicts_with = "light_error")]
    pub no_sun_rays: bool,
    /// The target error of the light left in the cuts: a relative L2 error in (0, 1), default
    /// 0.002 (or the scene file's `[environment] light_error`). Smaller casts more of the
    /// brightest leaves by rays (at most 32): `light_error_estimate`, `sun_leaves` and
    /// `sun_rays_per_vertex` report the choice and its cost.
    #[arg(long, value_name = "REL")]
    pub light_error: Option<f64>,
    /// The cost cap of `--light-error`: at most N leaves cast by rays (1 to 64, default 32).
    /// Each costs a ray per vertex facing it on a lighting change and a move, and a BRDF
    /// evaluation per vertex facing it on every shading.
    #[arg(long, value_name = "N", conflicts_with = "no_sun_rays", value_parser = clap::value_parser!(u8).range(1..=64))]
    pub light_max_leaves: Option<u8>,
    /// Multiply every field within reach into a vertex's cut, as the paper does. By default a
    /// field whose object lies wholly below the vertex's horizon is left out
    /// (`Frame::set_horizon_culling`).
    #[arg(long)]
    pub no_horizon_culling: bool,
    /// How far a field shadows, in its object's bounding radii (default 6; 10, the default
    /// precompute's outermost sphere, is the paper's reach): shorter is fewer fields per
    /// vertex and cheaper moves, the sky shadows of farther objects left out
    /// (`Frame::set_field_reach`).
    #[arg(long, value_name = "RADII")]
    pub field_reach: Option<f32>,
    /// How finely a flat occluder's (a ground's) shadow follows its edges: a node of up to N
    /// leaves across an edge takes its estimated visible share instead of being split to its
    /// leaves (a power of two; default 1, exact). Larger is a cheaper move on a scene with a
    /// ground, the light near its edges blended (`Frame::set_flat_edge_leaves`); `interactive`
    /// is 1/256 of the directions (`Frame::interactive_flat_edge_leaves`: 128 at the paper
    /// preset, 16 at `fast`).
    #[arg(long, value_name = "N|interactive")]
    pub flat_edge_leaves: Option<FlatEdges>,
    /// Merge every vertex a move changes at once. By default a move merges the vertices facing
    /// the camera and leaves the others until a camera sees them (`Frame::set_deferred_merges`):
    /// the image is the same bit for bit.
    #[arg(long)]
    pub eager_merges: bool,
    /// Keep no merged cut per vertex, only its shading list: less memory (the merged cuts are
    /// the frame's largest part), the same moves, edits and image; a lighting change or a
    /// camera turn merges the vertices it relists again (`Frame::set_merged_cache`).
    #[arg(long)]
    pub no_merged_cache: bool,
    /// Hold the frame's memory (`frame_memory_mb`) to MB: the stored cuts stay in the file
    /// (read from it as merges need them), no merged cuts and no field cells between moves are
    /// kept, and the decoded SVCs only if they fit (`Frame::fit_memory`); `frame_caches` says
    /// which are kept. A warning says when even none fits.
    #[arg(long, value_name = "MB", conflicts_with = "no_merged_cache")]
    pub memory_budget: Option<f64>,
}

impl RenderArgs {
    /// Defaults for `input` written to `output`.
    pub fn new(input: &Path, output: &Path) -> Self {
        RenderArgs {
            input: input.into(),
            env: None,
            reconstruction: None,
            moves: Vec::new(),
            brdfs: Vec::new(),
            camera: None,
            width: 640,
            height: 480,
            exposure: None,
            output: output.into(),
            exr: None,
            exr_passes: None,
            export_glb: None,
            export_ply: None,
            compare: None,
            mode: RenderMode::Cuts,
            inside_samples: Inside::Occluded,
            no_sun_rays: false,
            light_error: None,
            no_horizon_culling: false,
            field_reach: None,
            flat_edge_leaves: None,
            light_max_leaves: None,
            eager_merges: false,
            no_merged_cache: false,
            memory_budget: None,
        }
    }
}

/// What a render measured and wrote (it prints the same as `key=value` lines).
#[derive(Debug, Default)]
pub struct RenderOutcome {
    /// Seconds to read the data and merge every vertex.
    pub setup_s: f64,
    /// Light-tree leaves cast by rays as the sun.
    pub sun_leaves: usize,
    /// The moves and BRDF edits asked for: their time (ms) and the vertices re-merged.
    pub move_ms: f64,
    /// Vertices the moves re-merged.
    pub moved_vertices: usize,
    /// Where the last move's time went, when there was one.
    pub last_move: Option<vcut_shade::MoveTiming>,
    /// Shading and rasterising the frame (ms); `None` in the screen-space modes.
    pub shade_ms: Option<f64>,
    /// Rasterising the frame (ms); `None` in the screen-space modes.
    pub raster_ms: Option<f64>,
    /// The image written.
    pub png: PathBuf,
    /// The exposure it was written with.
    pub exposure: f32,
    /// Each reference compared with (`--compare`).
    pub comparisons: Vec<Comparison>,
    /// Every `key=value` line printed, in order.
    pub printed: Vec<(String, String)>,
}

/// The frame against one reference.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// `exact`, `mc` or `raytraced`.
    pub reference: &'static str,
    /// Relative L2 error over the vertices (`None` for the screen-space reference).
    pub vertex_rel_l2: Option<f64>,
    /// Relative L2 error over the pixels.
    pub pixel_rel_l2: f64,
    /// The reference's image.
    pub png: PathBuf,
}

impl RenderOutcome {
    fn emit(&mut self, key: impl Into<String>, value: String) {
        let key = key.into();
        println!("{key}={value}");
        self.printed.push((key, value));
    }

    /// The comparison with `reference`, if made.
    pub fn comparison(&self, reference: &str) -> Option<&Comparison> {
        self.comparisons.iter().find(|c| c.reference == reference)
    }
}

/// Runs `render`; returns what it measured and wrote.
pub fn run(args: &RenderArgs) -> Result<RenderOutcome> {
    let mut out = RenderOutcome::default();
    // Checked before the data is read and merged.
    let inside = match args.inside_samples {
        Inside::Occluded => InsideSamples::Occluded,
        Inside::Dropped => InsideSamples::Dropped,
    };
    let budget = match args.memory_budget {
        Some(mb) if !(mb.is_finite() && mb > 0.0) => bail!("--memory-budget {mb}: expected a positive number of MB"),
        Some(mb) => Some((mb * 1e6) as usize),
        None => None,
    };
    // Under a budget the frame keeps no stored cuts, merged cuts or field cells from the start,
    // so that the setup's peak stays low too (it reads one object's arrays at a time and merges
    // in ranges then).
    let caches = match budget {
        Some(_) => FrameCaches { stored: false, svc: true, cells: false, merged: false },
        None => FrameCaches { merged: !args.no_merged_cache, ..FrameCaches::default() },
    };
    let Opened { data, mut frame, env, view, setup_s, .. } =
        open_with(&args.input, args.env.as_deref(), args.reconstruction, caches)?;
    if let Some(budget) = budget {
        frame.fit_memory(budget)?;
        let need = frame.memory().total();
        if need > budget {
            log::warn!(
                "--memory-budget {:.1}: the frame needs {:.1} MB without any cache",
                budget as f64 / 1e6,
                need as f64 / 1e6
            );
        }
    }
    let kept = frame.caches();
    let names: Vec<&str> = [("stored", kept.stored), ("svc", kept.svc), ("cells", kept.cells), ("merged", kept.merged)]
        .iter()
        .filter(|c| c.1)
        .map(|c| c.0)
        .collect();
    out.emit("frame_caches", if names.is_empty() { "none".into() } else { names.join(",") });
    out.setup_s = setup_s;
    out.emit("setup_s", format!("{setup_s:.3}"));
    out.emit("reconstruction", env.reconstruction().name().to_string());
    if inside != InsideSamples::default() {
        frame.set_inside_samples(inside)?;
    }
    out.emit("inside_samples", inside.name().into());
    if args.no_horizon_culling {
        frame.set_horizon_culling(false)?;
    }
    if args.field_reach.is_some() {
        frame.set_field_reach(args.field_reach).map_err(|e| anyhow::anyhow!("--field-reach: {e}"))?;
    }
    if let Some(edges) = args.flat_edge_leaves {
        set_flat_edges(&mut frame, edges)?;
    }
    out.emit("flat_edge_leaves", frame.flat_edge_leaves().to_string());
    if args.no_sun_rays {
        frame.set_sun_rays(None);
    } else {
        let target = light_error(args.light_error, view.as_ref().and_then(|v| v.light_error))?;
        if target.is_some() || args.light_max_leaves.is_some() {
            let rays = frame.sun_rays().unwrap_or_default();
            frame.set_sun_rays(Some(SunRays {
                target: target.unwrap_or(rays.target),
                max_leaves: args.light_max_leaves.map_or(rays.max_leaves, usize::from),
            }));
        }
    }
    out.sun_leaves = frame.sun_leaves();
    out.emit("sun_leaves", format!("{}", out.sun_leaves));
    let choice = frame.light_choice();
    if let Some(rays) = frame.sun_rays() {
        out.emit("light_error_target", format!("{}", choice.target));
        out.emit("light_max_leaves", format!("{}", rays.max_leaves));
        out.emit("light_error_estimate_cuts", format!("{:.5}", choice.estimate_cuts));
        out.emit("light_error_estimate", format!("{:.5}", choice.estimate));
        out.emit("light_choice_ms", format!("{:.2}", choice.estimate_s * 1e3));
        out.emit("sun_rays_per_vertex", format!("{:.2}", choice.rays_per_vertex()));
        out.emit("sun_cast_us_per_vertex", format!("{:.3}", choice.cast_us_per_vertex()));
    }
    frame.set_deferred_merges(!args.eager_merges)?;
    // The moves build the shading lists of the vertices facing the camera (a framing camera
    // may shift with the moves: then shading builds the few others it needs).
    if let Ok(c) = camera(view.as_ref(), args.camera.as_deref(), &frame) {
        frame.set_eye(c.position)?;
    }
    let (move_ms, moved) = apply_edits(&mut frame, &args.brdfs, &args.moves)?;
    (out.move_ms, out.moved_vertices) = (move_ms, moved);
    out.emit("move_merge_ms", format!("{move_ms:.2}"));
    out.emit("move_merged_vertices", format!("{moved}"));
    if moved > 0 {
        // Where the last move's time went (wall clock over all cores).
        let t = frame.last_move();
        out.last_move = Some(t);
        out.emit("move_keys_ms", format!("{:.2}", t.keys_s * 1e3));
        out.emit("move_decode_ms", format!("{:.2}", t.decode_s * 1e3));
        out.emit("move_refine_ms", format!("{:.2}", t.refine_s * 1e3));
        // The merges proper, shading lists built as the nodes are emitted.
        out.emit("move_merge_only_ms", format!("{:.2}", t.merge_s * 1e3));
        out.emit("move_sun_ms", format!("{:.2}", t.sun_s * 1e3));
        out.emit("move_deferred_vertices", format!("{}", t.deferred));
        out.emit("move_fields_per_vertex", format!("{:.2}", t.fields as f64 / t.vertices.max(1) as f64));
    }
    let camera = camera(view.as_ref(), args.camera.as_deref(), &frame)?;
    // A framing camera may have shifted with the moves: the vertices now facing it that a
    // move left are merged here.
    let t = Instant::now();
    let turned = frame.set_eye(camera.position)?;
    if turned > 0 {
        out.emit("turn_merged_vertices", format!("{turned}"));
        out.emit("turn_ms", format!("{:.2}", t.elapsed().as_secs_f64() * 1e3));
    }
    if let Some(mode) = args.mode.screen() {
        return screen_space(args, mode, &frame, &env, &camera, out);
    }
    let t = Instant::now();
    let parts = frame.shade_parts(camera.position, false);
    let radiance = frame.radiance(&parts);
    let shade_ms = t.elapsed().as_secs_f64() * 1e3;
    out.shade_ms = Some(shade_ms);
    out.emit("shade_ms", format!("{shade_ms:.2}"));
    emit_memory(&frame, &mut out);
    let t = Instant::now();
    // A textured object takes its albedo per pixel.
    let image = frame_image(&frame, (&parts, &radiance), &camera, args.width, args.height, Some(&env));
    let raster_ms = t.elapsed().as_secs_f64() * 1e3;
    out.raster_ms = Some(raster_ms);
    out.emit("raster_ms", format!("{raster_ms:.2}"));
    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let exposure = args.exposure.unwrap_or_else(|| auto_exposure(&image));
    write_png(&image, &args.output, exposure)?;
    (out.png, out.exposure) = (args.output.clone(), exposure);
    out.emit("png", format!("{}", args.output.display()));
    out.emit("tone_map", "aces-narkowicz".into());
    out.emit("exposure", format!("{exposure:.4}"));
    if let Some(p) = &args.exr {
        let passes = args.exr_passes.as_ref().map_or(&[][..], |p| p.0.as_slice());
        let t = Instant::now();
        let layers = render_passes(&frame, &parts, &camera, args.width, args.height, passes);
        let passes_ms = t.elapsed().as_secs_f64() * 1e3;
        write_exr_passes(&image, &layers, p)?;
        out.emit("exr", format!("{}", p.display()));
        if !passes.is_empty() {
            out.emit("exr_passes", passes.iter().map(|p| p.name()).collect::<Vec<_>>().join(","));
            out.emit("exr_passes_ms", format!("{passes_ms:.2}"));
        }
    }
    if args.export_ply.is_some() || args.export_glb.is_some() {
        // Every vertex: those the camera cannot see toward their own normals.
        let all = frame.shade_all(camera.position);
        if let Some(p) = &args.export_ply {
            write_ply(&frame, &all, p)?;
            out.emit("ply", format!("{}", p.display()));
        }
        if let Some(p) = &args.export_glb {
            let aspect = args.width.max(1) as f32 / args.height.max(1) as f32;
            write_glb(&frame, &all, &camera, aspect, exposure, p)?;
            out.emit("glb", format!("{}", p.display()));
        }
    }
    let compare = args.compare;
    if compare == Some(Compare::Raytraced) {
        bail!("--compare raytraced: only a screen-space --mode (ssao, ssdo, ssdo-peeled) compares with it");
    }
    let offset = data.svc_origin_offset();
    let stem = args.output.file_stem().and_then(|s| s.to_str()).unwrap_or("frame").to_string();
    let mut refs = Vec::new();
    if matches!(compare, Some(Compare::Exact | Compare::Both)) {
        let t = Instant::now();
        let r = exact_direction(&frame, camera.position, offset);
        out.emit("reference_exact_s", format!("{:.3}", t.elapsed().as_secs_f64()));
        refs.push(("exact", r));
    }
    if matches!(compare, Some(Compare::Mc | Compare::Both)) {
        let t = Instant::now();
        let (r, stats) = monte_carlo(&frame, &env, camera.position, offset, &MonteCarloParams::default());
        out.emit("reference_mc_s", format!("{:.3}", t.elapsed().as_secs_f64()));
        out.emit("reference_mc_samples", format!("{}", stats.samples));
        out.emit("reference_mc_unconverged_vertices", format!("{}", stats.unconverged));
        refs.push(("mc", r));
    }
    // The references are per vertex: with a textured object, the pixel errors compare them with
    // the cuts' image at per-vertex albedo too, so texture detail does not count as error.
    let per_vertex = (frame.has_textures() && !refs.is_empty())
        .then(|| rasterize(&frame, &radiance, &camera, args.width, args.height, Some(&env)));
    let compared = per_vertex.as_ref().unwrap_or(&image);
    for (name, reference) in &refs {
        let (l2, max) = errors(&radiance, reference);
        out.emit(format!("vertex_rel_l2_vs_{name}"), format!("{l2:.5}"));
        out.emit(format!("vertex_max_err_vs_{name}"), format!("{max:.5}"));
        let ref_image = rasterize(&frame, reference, &camera, args.width, args.height, Some(&env));
        let (pl2, pmax) = pixel_errors(compared, &ref_image);
        out.emit(format!("pixel_rel_l2_vs_{name}"), format!("{pl2:.5}"));
        out.emit(format!("pixel_max_err_vs_{name}"), format!("{pmax:.5}"));
        let ref_path = args.output.with_file_name(format!("{stem}-{name}.png"));
        write_png(&ref_image, &ref_path, exposure)?;
        out.emit(format!("reference_{name}_png"), format!("{}", ref_path.display()));
        out.comparisons.push(Comparison { reference: name, vertex_rel_l2: Some(l2), pixel_rel_l2: pl2, png: ref_path });
    }
    if let [(_, exact), (_, mc)] = refs.as_slice() {
        let (l2, max) = errors(exact, mc);
        out.emit("vertex_rel_l2_exact_vs_mc", format!("{l2:.5}"));
        out.emit("vertex_max_err_exact_vs_mc", format!("{max:.5}"));
    }
    Ok(out)
}

/// `--exr-passes`' list.
#[derive(Debug, Clone, PartialEq)]
pub struct Passes(pub Vec<Pass>);

fn parse_passes(list: &str) -> Result<Passes, String> {
    Pass::parse_list(list).map(Passes)
}

/// `render --mode ssao|ssdo|ssdo-peeled`: the screen-space image, and with `--compare` the
/// ray-traced reference of direct light with visibility plus one diffuse bounce.
fn screen_space(
    args: &RenderArgs,
    mode: ScreenMode,
    frame: &Frame,
    env: &EnvMap,
    camera: &Camera,
    mut out: RenderOutcome,
) -> Result<RenderOutcome> {
    let objects = crate::ssdo::objects(frame);
    let t = Instant::now();
    let light = crate::ssdo::lighting(env, &objects);
    out.emit("lighting_ms", format!("{:.2}", t.elapsed().as_secs_f64() * 1e3));
    let f = crate::ssdo::frame(&objects, &light, camera, (args.width, args.height), mode);
    out.emit("gbuffer_ms", format!("{:.2}", f.gbuffer_ms));
    out.emit(format!("{}_ms", mode.key()), format!("{:.2}", f.pass_ms));
    let image = crate::ssdo::image(&f.output);
    for (set, flag) in [
        (args.exr_passes.is_some(), "--exr-passes"),
        (args.export_ply.is_some(), "--export-ply"),
        (args.export_glb.is_some(), "--export-glb"),
    ] {
        if set {
            bail!("{flag}: exports the cuts' shading (--mode cuts); a screen-space mode writes its image only");
        }
    }
    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let exposure = args.exposure.unwrap_or_else(|| auto_exposure(&image));
    write_png(&image, &args.output, exposure)?;
    (out.png, out.exposure) = (args.output.clone(), exposure);
    out.emit("png", format!("{}", args.output.display()));
    out.emit("exposure", format!("{exposure:.4}"));
    if let Some(p) = &args.exr {
        write_exr(&image, p)?;
        out.emit("exr", format!("{}", p.display()));
    }
    if let Some(c) = args.compare {
        if c != Compare::Raytraced {
            bail!("--compare {}: a screen-space mode compares with `raytraced`", c.name());
        }
        let t = Instant::now();
        let r = vcut_ssdo::reference(&objects, &f.gbuffer, &light, &Default::default());
        out.emit("reference_raytraced_s", format!("{:.3}", t.elapsed().as_secs_f64()));
        let e = vcut_ssdo::rel_l2(&f.output.total(), &r.total(), &f.output.covered);
        out.emit("pixel_rel_l2_vs_raytraced", format!("{e:.5}"));
        let stem = args.output.file_stem().and_then(|s| s.to_str()).unwrap_or("frame").to_string();
        let ref_path = args.output.with_file_name(format!("{stem}-raytraced.png"));
        write_png(&crate::ssdo::image(&r), &ref_path, exposure)?;
        out.emit("reference_raytraced_png", format!("{}", ref_path.display()));
        out.comparisons.push(Comparison {
            reference: "raytraced",
            vertex_rel_l2: None,
            pixel_rel_l2: e,
            png: ref_path,
        });
    }
    Ok(out)
}

/// The frame's memory by part (`frame_memory_*_mb`), per vertex, and the process's peak.
fn emit_memory(frame: &Frame, out: &mut RenderOutcome) {
    let m = frame.memory();
    let vertices: usize = (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count()).sum();
    let mb = |b: usize| format!("{:.1}", b as f64 / 1e6);
    out.emit("frame_memory_mb", mb(m.total()));
    out.emit("frame_bytes_per_vertex", format!("{}", m.total() / vertices.max(1)));
    for (part, bytes) in m.parts() {
        out.emit(format!("frame_memory_{part}_mb"), mb(bytes));
    }
    if let Some(peak) = vcut_scene::budget::peak_memory() {
        out.emit("peak_rss_mb", mb(peak as usize));
    }
}
