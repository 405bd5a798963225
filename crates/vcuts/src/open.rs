//! Opening a `.vcuts` file for a frame: its environment (recorded, `--env`, or the scene's),
//! reconstruction, edits from the command line, the light-error target and the camera. Shared
//! by `render` and `view`.

use anyhow::{Context, Result, bail};
use glam::Vec3;
use std::path::Path;
use std::time::Instant;
use vcut_data::{Precomputed, View};
use vcut_envmap::EnvMap;
use vcut_scene::{Camera, Scene};
use vcut_shade::{Frame, FrameSettings};

use crate::values::{BrdfEdit, Move, TurnTo};

/// A `.vcuts` file opened for rendering.
pub struct Opened {
    /// The data.
    pub data: Precomputed,
    /// Its frame under `env`, every vertex merged once.
    pub frame: Frame,
    /// The environment lighting it.
    pub env: EnvMap,
    /// The environment's name (a spec `--env` takes, or "scene").
    pub env_name: String,
    /// The scene's cameras and light-error target: the file's own record of them, or (a file
    /// written before it held them) the scene re-opened by its recorded source, when it opens.
    pub view: Option<View>,
    /// Seconds to read the data and merge every vertex.
    pub setup_s: f64,
}

/// Opens `input` under environment `env` (default: the one recorded, else the scene's) with the
/// default settings.
pub fn open(input: &Path, env: Option<&str>) -> Result<Opened> {
    open_with(input, env, None, &FrameSettings::default(), None)
}

/// [`open`] with the map reconstructed as `reconstruction` (default: as recorded), a frame under
/// `settings`, set up facing the camera `camera` names (the file's first without a name, else
/// one framing the objects; a name the file lacks is an error later, when the camera is asked
/// for: then the setup faces no eye).
pub fn open_with(
    input: &Path,
    env: Option<&str>,
    reconstruction: Option<vcut_envmap::Reconstruction>,
    settings: &FrameSettings,
    camera: Option<&str>,
) -> Result<Opened> {
    let mut data = Precomputed::open(input)?;
    let embedded = data.environment()?;
    // A file without its own record of the scene's view and light: the scene, re-opened.
    let needs_scene = embedded.is_none() && env.is_none() && data.record.environment == "scene";
    let scene = if data.view.is_none() || needs_scene {
        match Scene::open(&data.record.scene) {
            Ok(s) => Some(s),
            Err(e) => {
                log::warn!(
                    "{}: written before .vcuts files held their cameras and map, and its scene does not open here \
                     ({e}): the cameras are framed from the objects",
                    input.display()
                );
                None
            }
        }
    } else {
        None
    };
    let view = data.view.clone().or_else(|| scene.as_ref().map(View::of));
    let (env, env_name): (EnvMap, String) = match (env, embedded, &scene) {
        (Some(e), _, _) => (crate::inspect::load_envmap(e).with_context(|| format!("--env {e}"))?, e.to_string()),
        (None, Some(map), _) => (map, data.record.environment.clone()),
        (None, None, Some(s)) if data.record.environment == "scene" => (s.environment.clone(), "scene".into()),
        (None, None, _) if data.record.environment != "scene" => {
            let e = data.record.environment.clone();
            (crate::inspect::load_envmap(&e).with_context(|| format!("{}: its environment {e}", input.display()))?, e)
        }
        (None, None, _) => {
            bail!(
                "{}: its scene '{}' does not open here; name an environment with --env",
                input.display(),
                data.record.scene
            )
        }
    };
    let t = Instant::now();
    let env = match reconstruction {
        Some(r) => env.with_reconstruction(r).with_context(|| format!("--reconstruction {}", r.name()))?,
        None => env,
    };
    let rest = vcut_scene::Bounds::of_points(data.objects.iter().flat_map(|o| o.mesh.positions().iter().copied()));
    let eye = find_camera(view.as_ref(), camera, rest).ok().map(|c| c.position);
    let frame = Frame::open(&mut data, &env, settings, eye).map_err(|e| frame_error(e, input))?;
    Ok(Opened { data, frame, env, env_name, view, setup_s: t.elapsed().as_secs_f64() })
}

/// A frame's error, a setting's named as the command-line option that sets it.
fn frame_error(e: vcut_shade::FrameError, input: &Path) -> anyhow::Error {
    match e {
        vcut_shade::FrameError::Setting(s) => {
            anyhow::anyhow!("{} {}: {}", vcut_shade::FrameArgs::option(s.key), s.value, s.reason)
        }
        e => anyhow::Error::new(e).context(format!("{}", input.display())),
    }
}

/// The frame's object named `name`, or an error listing the names.
pub fn object(frame: &Frame, name: &str) -> Result<usize> {
    frame.object_index(name).with_context(|| format!("no object '{name}' (objects: {})", object_names(frame)))
}

/// The frame's object names, comma-separated (for errors).
pub fn object_names(frame: &Frame) -> String {
    (0..frame.object_count()).map(|o| frame.object(o).name).collect::<Vec<_>>().join(", ")
}

/// What [`apply_edits`] did: the moves' and turns' time and merges, and each turn's snap.
#[derive(Debug, Clone, Default)]
pub struct Edits {
    /// The moves and turns (ms).
    pub move_ms: f64,
    /// Vertices they re-merged.
    pub moved: usize,
    /// Each turn, as made.
    pub turns: Vec<TurnReport>,
}

/// One object turn of `--turn`, as the frame made it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TurnReport {
    /// The object.
    pub object: String,
    /// The yaw asked for (degrees).
    pub degrees: f32,
    /// The whole wedges its field samples turned by (the yaw snapped to the nearest multiple of
    /// 360°/`wedges`; its SVCs blend the two around it).
    pub steps: u32,
    /// The wedges of the file's symmetric direction set (`turn_steps`).
    pub wedges: u32,
    /// The field samples' turn less the geometry's (degrees; at most 180°/`wedges` either way).
    pub snap_error_deg: f32,
}

/// Applies the BRDF edits, then the moves, then the turns (a translation applies after the
/// turn whatever the order), each error naming its option and value.
pub fn apply_edits(frame: &mut Frame, brdfs: &[BrdfEdit], moves: &[Move], turns: &[TurnTo]) -> Result<Edits> {
    for b in brdfs {
        let o = object(frame, &b.object).with_context(|| format!("--brdf {b}"))?;
        let m = b.apply(*frame.object(o).material).with_context(|| format!("--brdf {b}"))?;
        frame.set_material(o, m);
    }
    let mut edits = Edits::default();
    for m in moves {
        let o = object(frame, &m.object).with_context(|| format!("--move {m}"))?;
        let t = Instant::now();
        edits.moved += frame.translate(o, m.translation).with_context(|| format!("--move {m}"))?;
        edits.move_ms += t.elapsed().as_secs_f64() * 1e3;
    }
    for turn in turns {
        let o = object(frame, &turn.object).with_context(|| format!("--turn {turn}"))?;
        let t = Instant::now();
        let made = frame.turn(o, turn.degrees.to_radians()).with_context(|| format!("--turn {turn}"))?;
        edits.move_ms += t.elapsed().as_secs_f64() * 1e3;
        edits.moved += made.merged;
        edits.turns.push(TurnReport {
            object: turn.object.clone(),
            degrees: turn.degrees,
            steps: made.steps,
            wedges: made.wedges,
            snap_error_deg: made.snap_error.to_degrees(),
        });
    }
    Ok(edits)
}

/// The camera called `name` of `view`, else its first, else one framing every object.
pub fn camera(view: Option<&View>, name: Option<&str>, frame: &Frame) -> Result<Camera> {
    let placed = vcut_scene::Bounds::of_points((0..frame.object_count()).flat_map(|o| frame.object(o).positions()));
    find_camera(view, name, placed)
}

/// The camera called `name` of `view`, else its first, else one framing `bounds`.
fn find_camera(view: Option<&View>, name: Option<&str>, bounds: vcut_scene::Bounds) -> Result<Camera> {
    let cameras = view.map_or(&[][..], |v| v.cameras.as_slice());
    Ok(match name {
        Some(name) => cameras.iter().find(|c| c.name == name).cloned().with_context(|| {
            let names: Vec<&str> = cameras.iter().map(|c| c.name.as_str()).collect();
            format!("no camera '{name}' (cameras: {})", if names.is_empty() { "none".into() } else { names.join(", ") })
        })?,
        None if !cameras.is_empty() => cameras[0].clone(),
        None => auto_camera(bounds),
    })
}

/// A camera framing bounds `b` from above and to the front right.
pub fn auto_camera(b: vcut_scene::Bounds) -> Camera {
    Camera {
        name: "auto".into(),
        position: b.center + Vec3::new(0.6, 0.5, 1.0).normalize() * b.radius * 2.5,
        target: b.center,
        up: Vec3::Y,
        fov_y_deg: 40.0,
    }
}
