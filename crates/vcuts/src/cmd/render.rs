//! `vcuts render`: a frame from a `.vcuts` file — objects moved, BRDFs edited — as PNG (and
//! EXR, PLY, glTF), with merge, shade and raster times, and optionally the error against the
//! references. Returns a typed [`RenderOutcome`]; the command prints it.

use crate::resources::ImageCost;
use anyhow::{Context, Result, bail};
use glam::Vec3;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;
use vcut_envmap::EnvMap;
use vcut_scene::Camera;
use vcut_shade::glb::write_glb;
use vcut_shade::image::{Image, auto_exposure, frame_image, pixel_errors, rasterize, write_exr, write_ply, write_png};
use vcut_shade::passes::{Pass, render_passes, write_exr_passes};
use vcut_shade::reference::{MonteCarloParams, errors, exact_direction, monte_carlo};
use vcut_shade::{Frame, FrameArgs, Parts};

use crate::frame_report::FrameReport;
pub use crate::open::{Edits, Opened, TurnReport, apply_edits, auto_camera, camera, open, open_with};
use crate::outcome::ms_since;
use crate::ssdo::ScreenMode;
use crate::values::{BrdfEdit, Move, TurnTo};

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

/// A reference a frame was compared with.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Reference {
    /// Every leaf direction cast ([`exact_direction`]).
    Exact,
    /// Monte Carlo over the map's texels ([`monte_carlo`]).
    Mc,
    /// The ray-traced reference of a screen-space mode.
    Raytraced,
}

impl Reference {
    /// Its name in report keys and file names.
    pub fn name(self) -> &'static str {
        match self {
            Reference::Exact => "exact",
            Reference::Mc => "mc",
            Reference::Raytraced => "raytraced",
        }
    }
}

/// Arguments of `render`.
#[derive(clap::Args, Clone)]
pub struct RenderArgs {
    /// The precomputed file (from `vcuts precompute`).
    pub input: PathBuf,
    /// Environment map (default: the scene's).
    #[arg(long)]
    pub env: Option<String>,
    /// How the map's radiance is reconstructed between texel centres and integrated: box or
    /// bilinear (lat-long maps; Mitsuba 3's envmap). Default: the scene file's (box).
    #[arg(long)]
    pub reconstruction: Option<vcut_envmap::Reconstruction>,
    /// Move an object: NAME=dx,dy,dz (repeatable; from its rest position).
    #[arg(long = "move", value_name = "NAME=DX,DY,DZ", allow_hyphen_values = true)]
    pub moves: Vec<Move>,
    /// Turn an object about +Y: NAME=DEGREES from its rest orientation (repeatable; the file
    /// needs `precompute --set turn_steps=M`; its cuts turn by multiples of 360°/M).
    #[arg(long = "turn", value_name = "NAME=DEGREES", allow_hyphen_values = true)]
    pub turns: Vec<TurnTo>,
    /// Edit a BRDF: NAME=MODEL[:KEY=VALUE,...], e.g. teapot=blinn-phong:alpha=70 (repeatable).
    #[arg(long = "brdf", value_name = "NAME=SPEC")]
    pub brdfs: Vec<BrdfEdit>,
    /// Camera name (default: the scene's first).
    #[arg(long)]
    pub camera: Option<String>,
    /// Image width in pixels (1 to 16,384).
    #[arg(long, default_value_t = 640, value_parser = crate::options::whole::<u32>("width"), allow_hyphen_values = true)]
    pub width: u32,
    /// Image height in pixels (1 to 16,384).
    #[arg(long, default_value_t = 480, value_parser = crate::options::whole::<u32>("height"), allow_hyphen_values = true)]
    pub height: u32,
    /// Exposure applied before tone mapping (PNG only; finite, above 0); default: the
    /// geometry's log-average luminance to middle grey.
    #[arg(long, value_parser = crate::options::real("exposure"), allow_hyphen_values = true)]
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
    /// Refine the frame toward the exact reference before shading: the field factors of
    /// vertices near their sources are cast by rays instead of looked up. `--refine` runs to
    /// completion, `--refine=SECONDS` stops after that long (the visible vertices nearest a
    /// source first). Off by default, so figures stay comparable with earlier reports.
    #[arg(long, value_name = "SECONDS", num_args = 0..=1, require_equals = true, default_missing_value = "inf",
          value_parser = parse_refine_budget)]
    pub refine: Option<f64>,
    /// With `--refine`: refine only the vertices within this many of a source's bounding radii
    /// of its centre (above 0; default `inf`: every pair a field reaches).
    #[arg(long, value_name = "RADII", requires = "refine", value_parser = parse_refine_reach, allow_hyphen_values = true)]
    pub refine_reach: Option<f32>,
    /// The frame's settings: how it looks fields up, merges, caches and casts the sun.
    #[command(flatten)]
    pub frame: FrameArgs,
}

/// `--refine=SECONDS`: above 0, `inf` for no limit.
fn parse_refine_budget(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x > 0.0 && !x.is_nan() => Ok(x),
        _ => Err(format!("{s:?}: expected a number of seconds above 0 (or `inf`: to completion)")),
    }
}

/// `--refine-reach RADII`: above 0, `inf` for every pair a field reaches.
fn parse_refine_reach(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x > 0.0 && !x.is_nan() => Ok(x),
        _ => Err(format!("{s:?}: expected a number of radii above 0 (or `inf`)")),
    }
}

impl RenderArgs {
    /// Defaults for `input` written to `output`.
    pub fn new(input: &Path, output: &Path) -> Self {
        RenderArgs {
            input: input.into(),
            env: None,
            reconstruction: None,
            moves: Vec::new(),
            turns: Vec::new(),
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
            refine: None,
            refine_reach: None,
            frame: FrameArgs::default(),
        }
    }
}

/// What a render measured and wrote, its fields named as the keys it prints.
#[derive(Debug, Clone, Serialize)]
pub struct RenderOutcome {
    /// Seconds to read the data and merge every vertex.
    pub setup_s: f64,
    /// The map's reconstruction.
    pub reconstruction: &'static str,
    /// How field lookups treat samples inside an object.
    pub inside_samples: &'static str,
    /// The nodes across a ground's edges whose share is estimated, in leaves (1: exact).
    pub flat_edge_leaves: u32,
    /// The moves and turns asked for: their time (ms).
    pub move_merge_ms: f64,
    /// Vertices the moves and turns re-merged.
    pub move_merged_vertices: usize,
    /// The object turns asked for (`--turn`), each with its snap to the direction set's wedges.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub object_turns: Vec<TurnReport>,
    /// Vertices a camera turn after the moves merged (they faced away from the eye before).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub turn_merged_vertices: Option<usize>,
    /// That turn's time (ms).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub turn_ms: Option<f64>,
    /// The screen-space method's times, in a screen-space mode.
    #[serde(flatten)]
    pub screen: Option<ScreenTimes>,
    /// Shading (ms); `None` in the screen-space modes.
    pub shade_ms: Option<f64>,
    /// The frame's figures: caches, light, merges, last move, memory.
    #[serde(flatten)]
    pub frame: FrameReport,
    /// Rasterising the frame (ms); `None` in the screen-space modes.
    pub raster_ms: Option<f64>,
    /// The image written.
    pub png: PathBuf,
    /// Its tone mapping (the cuts' image).
    pub tone_map: Option<&'static str>,
    /// The exposure it was written with.
    pub exposure: f32,
    /// The EXR written, its passes and their time.
    pub exr: Option<PathBuf>,
    /// The passes the EXR holds besides the image.
    pub exr_passes: Option<String>,
    /// Rendering those passes (ms).
    pub exr_passes_ms: Option<f64>,
    /// The PLY written.
    pub ply: Option<PathBuf>,
    /// The glTF written.
    pub glb: Option<PathBuf>,
    /// Each reference compared with (`--compare`).
    #[serde(flatten)]
    pub comparisons: Comparisons,
}

/// A screen-space mode's times (ms): lighting, the G-buffer, the method.
#[derive(Debug, Clone, Serialize)]
pub struct ScreenTimes {
    /// Prefiltering the lighting.
    pub lighting_ms: f64,
    /// The G-buffer.
    pub gbuffer_ms: f64,
    /// `--mode ssao`.
    pub ssao_ms: Option<f64>,
    /// `--mode ssdo`.
    pub ssdo_ms: Option<f64>,
    /// `--mode ssdo-peeled`.
    pub ssdo_peeled_ms: Option<f64>,
}

/// The frame against one reference.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// The reference.
    pub reference: Reference,
    /// Seconds to compute it.
    pub seconds: f64,
    /// Relative L2 error over the vertices (`None` for the screen-space reference) and the
    /// largest vertex error.
    pub vertex: Option<(f64, f64)>,
    /// Relative L2 error over the pixels and the largest pixel error (`None` for the
    /// screen-space reference's largest).
    pub pixel: (f64, Option<f64>),
    /// The reference's image.
    pub png: PathBuf,
}

/// Every comparison made, and the Monte Carlo reference's own figures.
#[derive(Debug, Clone, Default)]
pub struct Comparisons {
    /// Each reference, in the order computed.
    pub list: Vec<Comparison>,
    /// The Monte Carlo reference's samples and unconverged vertices.
    pub mc: Option<(u64, usize)>,
    /// The exact reference against the Monte Carlo one (relative L2, largest error).
    pub exact_vs_mc: Option<(f64, f64)>,
}

impl Comparisons {
    /// The comparison with `reference`, if made.
    pub fn get(&self, reference: Reference) -> Option<&Comparison> {
        self.list.iter().find(|c| c.reference == reference)
    }
}

impl Serialize for Comparisons {
    /// The keys `reference_<name>_s`, `vertex_rel_l2_vs_<name>`, `vertex_max_err_vs_<name>`,
    /// `pixel_rel_l2_vs_<name>`, `pixel_max_err_vs_<name>`, `reference_<name>_png` per
    /// reference; `reference_mc_samples`, `reference_mc_unconverged_vertices`;
    /// `vertex_rel_l2_exact_vs_mc`, `vertex_max_err_exact_vs_mc`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(None)?;
        for c in &self.list {
            let n = c.reference.name();
            m.serialize_entry(&format!("reference_{n}_s"), &c.seconds)?;
            if let Some((l2, max)) = c.vertex {
                m.serialize_entry(&format!("vertex_rel_l2_vs_{n}"), &l2)?;
                m.serialize_entry(&format!("vertex_max_err_vs_{n}"), &max)?;
            }
            m.serialize_entry(&format!("pixel_rel_l2_vs_{n}"), &c.pixel.0)?;
            if let Some(max) = c.pixel.1 {
                m.serialize_entry(&format!("pixel_max_err_vs_{n}"), &max)?;
            }
            m.serialize_entry(&format!("reference_{n}_png"), &c.png)?;
        }
        if let Some((samples, unconverged)) = self.mc {
            m.serialize_entry("reference_mc_samples", &samples)?;
            m.serialize_entry("reference_mc_unconverged_vertices", &unconverged)?;
        }
        if let Some((l2, max)) = self.exact_vs_mc {
            m.serialize_entry("vertex_rel_l2_exact_vs_mc", &l2)?;
            m.serialize_entry("vertex_max_err_exact_vs_mc", &max)?;
        }
        m.end()
    }
}

/// Runs `render`; returns what it measured and wrote.
pub fn run(args: &RenderArgs) -> Result<RenderOutcome> {
    if args.compare == Some(Compare::Raytraced) && args.mode.screen().is_none() {
        bail!("--compare raytraced: only a screen-space --mode (ssao, ssdo, ssdo-peeled) compares with it");
    }
    let cost = if args.mode.screen().is_some() { ImageCost::ScreenSpace } else { ImageCost::Cuts };
    crate::resources::check_image(args.width, args.height, cost)?;
    let settings = args.frame.settings();
    let Opened { data, mut frame, env, view, setup_s, .. } =
        open_with(&args.input, args.env.as_deref(), args.reconstruction, &settings, args.camera.as_deref())?;
    if let Some(budget) = settings.memory_budget {
        let need = frame.memory().total() as u64;
        if need > budget {
            log::warn!(
                "--memory-budget {:.1}: the frame needs {:.1} MB without any cache",
                budget as f64 / 1e6,
                need as f64 / 1e6
            );
        }
    }
    let Edits { move_ms, moved, turns } = apply_edits(&mut frame, &args.brdfs, &args.moves, &args.turns)?;
    let camera = camera(view.as_ref(), args.camera.as_deref(), &frame)?;
    // A framing camera may have shifted with the moves: the vertices now facing it that a
    // move left are merged here.
    let t = Instant::now();
    let turned = frame.set_eye(camera.position)?;
    let turn_ms = ms_since(t);
    if let Some(seconds) = args.refine {
        // A budget past what an instant holds is no limit.
        let deadline = std::time::Duration::try_from_secs_f64(seconds).ok().and_then(|d| Instant::now().checked_add(d));
        let reach = args.refine_reach.unwrap_or(vcut_shade::REFINE_REACH);
        frame.refine(&vcut_shade::Refinement { reach, deadline, cancel: None })?;
    }
    let mut out = RenderOutcome {
        setup_s,
        reconstruction: env.reconstruction().name(),
        inside_samples: settings.inside_samples.name(),
        flat_edge_leaves: settings.flat_edge_leaves.leaves(frame.tree().leaf_count()),
        move_merge_ms: move_ms,
        move_merged_vertices: moved,
        object_turns: turns,
        turn_merged_vertices: (turned > 0).then_some(turned),
        turn_ms: (turned > 0).then_some(turn_ms),
        screen: None,
        shade_ms: None,
        frame: FrameReport::of(&frame, moved > 0),
        raster_ms: None,
        png: args.output.clone(),
        tone_map: None,
        exposure: 1.0,
        exr: None,
        exr_passes: None,
        exr_passes_ms: None,
        ply: None,
        glb: None,
        comparisons: Comparisons::default(),
    };
    if let Some(mode) = args.mode.screen() {
        screen_space(args, mode, &frame, &env, &camera, &mut out)?;
        return Ok(out);
    }
    let t = Instant::now();
    let parts = frame.shade_parts(camera.position, false);
    let radiance = frame.radiance(&parts);
    out.shade_ms = Some(ms_since(t));
    out.frame = FrameReport::of(&frame, moved > 0);
    let t = Instant::now();
    // A textured object takes its albedo per pixel.
    let image = frame_image(&frame, (&parts, &radiance), &camera, args.width, args.height, Some(&env));
    out.raster_ms = Some(ms_since(t));
    write_image(args, &image, &mut out)?;
    out.tone_map = Some("aces-narkowicz");
    exports(args, &mut frame, &parts, &camera, &image, &mut out)?;
    let shaded = Shaded { frame: &frame, radiance: &radiance, image: &image, camera: &camera, env: &env };
    out.comparisons = compare(args, &shaded, data.svc_origin_offset(), out.exposure)?;
    Ok(out)
}

/// Writes the PNG (creating its folder) at `--exposure` or the image's own; records both.
fn write_image(args: &RenderArgs, image: &Image, out: &mut RenderOutcome) -> Result<()> {
    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let exposure = args.exposure.unwrap_or_else(|| auto_exposure(image));
    write_png(image, &args.output, exposure)?;
    (out.png, out.exposure) = (args.output.clone(), exposure);
    Ok(())
}

/// The EXR with its passes, the PLY and the glTF asked for.
fn exports(
    args: &RenderArgs,
    frame: &mut Frame,
    parts: &[Vec<Parts>],
    camera: &Camera,
    image: &Image,
    out: &mut RenderOutcome,
) -> Result<()> {
    if let Some(p) = &args.exr {
        let passes = args.exr_passes.as_ref().map_or(&[][..], |p| p.0.as_slice());
        let t = Instant::now();
        let layers = render_passes(frame, parts, camera, args.width, args.height, passes);
        let passes_ms = ms_since(t);
        write_exr_passes(image, &layers, p)?;
        out.exr = Some(p.clone());
        if !passes.is_empty() {
            out.exr_passes = Some(passes.iter().map(|p| p.name()).collect::<Vec<_>>().join(","));
            out.exr_passes_ms = Some(passes_ms);
        }
    }
    if args.export_ply.is_some() || args.export_glb.is_some() {
        // Every vertex: those the camera cannot see toward their own normals.
        let all = frame.shade_all(camera.position);
        if let Some(p) = &args.export_ply {
            write_ply(frame, &all, p)?;
            out.ply = Some(p.clone());
        }
        if let Some(p) = &args.export_glb {
            let aspect = args.width.max(1) as f32 / args.height.max(1) as f32;
            write_glb(frame, &all, camera, aspect, out.exposure, p)?;
            out.glb = Some(p.clone());
        }
    }
    Ok(())
}

/// A frame as shaded for its image: what the comparisons read.
struct Shaded<'a> {
    frame: &'a Frame,
    radiance: &'a [Vec<Vec3>],
    image: &'a Image,
    camera: &'a Camera,
    env: &'a EnvMap,
}

/// The references `--compare` asks for, each against the frame per vertex and per pixel, its
/// image written beside the output.
fn compare(args: &RenderArgs, shaded: &Shaded<'_>, offset: f32, exposure: f32) -> Result<Comparisons> {
    let Shaded { frame, radiance, image, camera, env } = *shaded;
    let mut out = Comparisons::default();
    let mut refs = Vec::new();
    if matches!(args.compare, Some(Compare::Exact | Compare::Both)) {
        let t = Instant::now();
        refs.push((Reference::Exact, exact_direction(frame, camera.position, offset), t.elapsed().as_secs_f64()));
    }
    if matches!(args.compare, Some(Compare::Mc | Compare::Both)) {
        let t = Instant::now();
        let (r, stats) = monte_carlo(frame, env, camera.position, offset, &MonteCarloParams::default());
        refs.push((Reference::Mc, r, t.elapsed().as_secs_f64()));
        out.mc = Some((stats.samples, stats.unconverged as usize));
    }
    // The references are per vertex: with a textured object, the pixel errors compare them with
    // the cuts' image at per-vertex albedo too, so texture detail does not count as error.
    let per_vertex = (frame.has_textures() && !refs.is_empty())
        .then(|| rasterize(frame, radiance, camera, args.width, args.height, Some(env)));
    let compared = per_vertex.as_ref().unwrap_or(image);
    let stem = args.output.file_stem().and_then(|s| s.to_str()).unwrap_or("frame").to_string();
    for (reference, r, seconds) in &refs {
        let ref_image = rasterize(frame, r, camera, args.width, args.height, Some(env));
        let (pl2, pmax) = pixel_errors(compared, &ref_image);
        let png = args.output.with_file_name(format!("{stem}-{}.png", reference.name()));
        write_png(&ref_image, &png, exposure)?;
        out.list.push(Comparison {
            reference: *reference,
            seconds: *seconds,
            vertex: Some(errors(radiance, r)),
            pixel: (pl2, Some(pmax)),
            png,
        });
    }
    if let [(_, exact, _), (_, mc, _)] = refs.as_slice() {
        out.exact_vs_mc = Some(errors(exact, mc));
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
    out: &mut RenderOutcome,
) -> Result<()> {
    for (set, flag) in [
        (args.exr_passes.is_some(), "--exr-passes"),
        (args.export_ply.is_some(), "--export-ply"),
        (args.export_glb.is_some(), "--export-glb"),
    ] {
        if set {
            bail!("{flag}: exports the cuts' shading (--mode cuts); a screen-space mode writes its image only");
        }
    }
    if let Some(c) = args.compare.filter(|c| *c != Compare::Raytraced) {
        bail!("--compare {}: a screen-space mode compares with `raytraced`", c.name());
    }
    let objects = crate::ssdo::objects(frame);
    let t = Instant::now();
    let light = crate::ssdo::lighting(env, &objects);
    let lighting_ms = ms_since(t);
    let f = crate::ssdo::frame(&objects, &light, camera, (args.width, args.height), mode);
    let pass = |m: ScreenMode| (m == mode).then_some(f.pass_ms);
    out.screen = Some(ScreenTimes {
        lighting_ms,
        gbuffer_ms: f.gbuffer_ms,
        ssao_ms: pass(ScreenMode::Ssao),
        ssdo_ms: pass(ScreenMode::Ssdo),
        ssdo_peeled_ms: pass(ScreenMode::SsdoPeeled),
    });
    let image = crate::ssdo::image(&f.output);
    write_image(args, &image, out)?;
    if let Some(p) = &args.exr {
        write_exr(&image, p)?;
        out.exr = Some(p.clone());
    }
    if args.compare == Some(Compare::Raytraced) {
        let t = Instant::now();
        let r = vcut_ssdo::reference(&objects, &f.gbuffer, &light, &Default::default());
        let seconds = t.elapsed().as_secs_f64();
        let e = vcut_ssdo::rel_l2(&f.output.total(), &r.total(), &f.output.covered);
        let stem = args.output.file_stem().and_then(|s| s.to_str()).unwrap_or("frame").to_string();
        let png = args.output.with_file_name(format!("{stem}-raytraced.png"));
        write_png(&crate::ssdo::image(&r), &png, out.exposure)?;
        out.comparisons.list.push(Comparison {
            reference: Reference::Raytraced,
            seconds,
            vertex: None,
            pixel: (e, None),
            png,
        });
    }
    Ok(())
}
