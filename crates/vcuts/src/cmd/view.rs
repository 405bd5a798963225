//! `vcuts view`: the interactive viewer (`vcut-view`) on a `.vcuts` file, or on a scene
//! precomputed first; `--screenshot` renders the same frame with no window.

pub use super::view_args::{ViewArgs, ViewMode, ViewOutcome};
use crate::outcome::ms_since;
use anyhow::{Context, Result, bail};
use std::time::{Duration, Instant};
use vcut_view::report::ScriptedDrag;
use vcut_view::{Gpu, LeafSession, LeafViewOptions, Mode, OrbitCamera, Session, ViewOptions};

/// The GPU a screenshot renders on, and how long it took to set up.
struct Headless {
    gpu: Gpu,
    setup_ms: f64,
}

/// The headless GPU for `--screenshot`, refused when the image is larger than memory or than
/// the device's textures.
fn headless(args: &ViewArgs) -> Result<Headless> {
    crate::resources::check_image(args.width, args.height, crate::resources::ImageCost::Screenshot)?;
    let t = Instant::now();
    let gpu = Gpu::headless()?;
    let setup_ms = ms_since(t);
    gpu.check_target((args.width, args.height), &format!("--width {} --height {}", args.width, args.height))?;
    Ok(Headless { gpu, setup_ms })
}

/// `view --leaves`: the plant precomputed, then the leaf window (or a screenshot).
fn run_leaves(args: &ViewArgs, gpu: Option<Headless>) -> Result<ViewOutcome> {
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
    if let (Some(path), Some(Headless { gpu, .. })) = (&args.screenshot, gpu) {
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

/// The viewer's mode for `--mode`.
fn mode(m: ViewMode) -> Mode {
    match m {
        ViewMode::Cuts => Mode::Cuts,
        ViewMode::Exact => Mode::Exact,
        ViewMode::Difference => Mode::Difference,
        ViewMode::Ssao => Mode::Ssao,
        ViewMode::Ssdo => Mode::Ssdo,
    }
}

/// Runs `view`: the window, or with `--screenshot` one frame into a PNG.
pub fn run(args: &ViewArgs) -> Result<ViewOutcome> {
    // A screenshot's GPU is set up first: a size it cannot render is refused before the frame.
    let gpu = args.screenshot.as_ref().map(|_| headless(args)).transpose()?;
    if args.leaves {
        return run_leaves(args, gpu);
    }
    let input = match (&args.input, &args.scene) {
        (Some(p), _) => p.clone(),
        (None, scene) => crate::precompute::cached_or_run(scene.as_deref().unwrap_or("builtin:teapot"), &args.preset)?,
    };
    let settings = args.frame.settings();
    let opened =
        crate::render::open_with(&input, args.env.as_deref(), args.reconstruction, &settings, args.camera.as_deref())?;
    let crate::render::Opened { data, mut frame, env, env_name, view, setup_s } = opened;
    crate::render::apply_edits(&mut frame, &args.brdfs, &args.moves, &[])?;
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
    session.set_mode(mode(args.mode))?;
    if let Some(path) = &args.screenshot {
        let gpu = gpu.context("a screenshot's GPU is set up first")?;
        return screenshot(args, &mut session, path, gpu);
    }
    let report = window(args, session, (&input, summary), (env, env_name))?;
    Ok(ViewOutcome { window: Some(report), ..ViewOutcome::default() })
}

/// One frame of `session` with no window into the PNG `path`.
fn screenshot(args: &ViewArgs, session: &mut Session, path: &std::path::Path, gpu: Headless) -> Result<ViewOutcome> {
    let t = Instant::now();
    // The frame's worker done first: the reference steps only while it holds nothing.
    session.update();
    while session.step_reference(Duration::from_secs(3600)) {}
    let reference_s = t.elapsed().as_secs_f64();
    let Headless { gpu, setup_ms } = gpu;
    let mut out = ViewOutcome { adapter: Some(gpu.describe()), gpu_setup_ms: Some(setup_ms), ..Default::default() };
    let t = Instant::now();
    let image = vcut_view::screenshot(&gpu, session, args.width, args.height)?;
    out.screenshot_ms = Some(ms_since(t));
    create_parent(path)?;
    vcut_view::headless::write_png(&image, path)?;
    out.mode = Some(args.mode.name());
    out.exposure = Some(session.exposure_in_use());
    out.shade_ms = Some(session.timings.shade_ms);
    if matches!(mode(args.mode), Mode::Exact | Mode::Difference) {
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
) -> Result<super::view_args::WindowOutcome> {
    if args.live_move_ms.is_some() {
        log::warn!(
            "--live-move-ms no longer changes anything: every mouse move of a drag is merged off the \
             window's thread, a step still waiting replaced by the next"
        );
    }
    let scripted_drag = scripted_drag(args, &session)?;
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
        max_frames: args.frames,
        refine: !args.no_refine,
        scripted_drag,
    };
    Ok(vcut_view::run_window(session, options)?.into())
}

/// `--drag NAME`: the object, dragged for three quarters of `--frames` around a circle of a
/// quarter of its radius.
fn scripted_drag(args: &ViewArgs, session: &Session) -> Result<Option<ScriptedDrag>> {
    let Some(name) = &args.drag else { return Ok(None) };
    let objects = session.objects();
    let Some(object) = objects.iter().position(|o| o.name == *name) else {
        let names: Vec<&str> = objects.iter().map(|o| o.name.as_str()).collect();
        bail!("--drag {name}: no object called '{name}' (objects: {})", names.join(", "));
    };
    if objects[object].motion != vcut_scene::Motion::Movable {
        bail!("--drag {name}: '{name}' is static (precomputed without a visibility field): it cannot move");
    }
    let steps = args.frames.unwrap_or(0) * 3 / 4;
    Ok(Some(ScriptedDrag { object, steps, radius: 0.25 * objects[object].mesh.bounds().radius }))
}
impl From<vcut_view::report::WindowReport> for super::view_args::WindowOutcome {
    fn from(r: vcut_view::report::WindowReport) -> Self {
        Self {
            frames: r.frames,
            drag_frames: r.drag_frames,
            frame_ms_p50: r.frame_ms.p50,
            frame_ms_p95: r.frame_ms.p95,
            frame_ms_max: r.frame_ms.max,
            draw_ms_p50: r.draw_ms.p50,
            draw_ms_p95: r.draw_ms.p95,
            moves_posted: r.steps_posted,
            moves_dropped: r.steps_dropped,
            moves_merged: r.merges,
            merge_ms_mean: r.merge_ms_mean,
            shading_lag_ms_p50: r.shading_lag_ms.p50,
            shading_lag_ms_p95: r.shading_lag_ms.p95,
            shadings: r.shading_lag_ms.count,
            refine_slices: r.refine_slices,
            refined_share: r.refined_share,
        }
    }
}
