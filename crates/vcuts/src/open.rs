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
use vcut_shade::brdf::parse_spec;
use vcut_shade::{Frame, FrameCaches};

/// A `.vcuts` file opened for rendering.
pub struct Opened {
    /// The data.
    pub data: Precomputed,
    /// Its frame under `env`, every vertex merged.
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

/// Opens `input` under environment `env` (default: the one recorded, else the scene's).
pub fn open(input: &Path, env: Option<&str>) -> Result<Opened> {
    open_with(input, env, None, FrameCaches::default())
}

/// [`open`] with the map reconstructed as `reconstruction` (default: as recorded) and a frame
/// that keeps `caches` ([`Frame::with_caches`]).
pub fn open_with(
    input: &Path,
    env: Option<&str>,
    reconstruction: Option<vcut_envmap::Reconstruction>,
    caches: FrameCaches,
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
    let frame = Frame::with_caches(&mut data, &env, caches)?;
    Ok(Opened { data, frame, env, env_name, view, setup_s: t.elapsed().as_secs_f64() })
}

/// The frame's object named `name`, or an error listing the names.
pub fn object(frame: &Frame, name: &str) -> Result<usize> {
    frame.object_index(name).with_context(|| format!("no object '{name}' (objects: {})", object_names(frame)))
}

/// The frame's object names, comma-separated (for errors).
pub fn object_names(frame: &Frame) -> String {
    (0..frame.object_count()).map(|o| frame.object(o).name).collect::<Vec<_>>().join(", ")
}

/// Applies `--brdf NAME=SPEC` and `--move NAME=DX,DY,DZ` edits; returns the moves' merge
/// milliseconds and the vertices they re-merged.
pub fn apply_edits(frame: &mut Frame, brdfs: &[String], moves: &[String]) -> Result<(f64, usize)> {
    for b in brdfs {
        let Some((name, spec)) = b.split_once('=') else { bail!("--brdf {b}: expected NAME=SPEC") };
        let o = object(frame, name)?;
        let m = parse_spec(*frame.object(o).material, spec).map_err(|e| anyhow::anyhow!("--brdf {b}: {e}"))?;
        frame.set_material(o, m);
    }
    let mut move_ms = 0.0;
    let mut moved = 0;
    for m in moves {
        let Some((name, v)) = m.split_once('=') else { bail!("--move {m}: expected NAME=DX,DY,DZ") };
        let c: Vec<f32> = v
            .split(',')
            .map(|x| x.trim().parse::<f32>())
            .collect::<Result<_, _>>()
            .with_context(|| format!("--move {m}"))?;
        let [dx, dy, dz] = c.as_slice() else { bail!("--move {m}: expected three numbers") };
        let o = object(frame, name)?;
        let t = Instant::now();
        moved += frame.translate(o, Vec3::new(*dx, *dy, *dz))?;
        move_ms += t.elapsed().as_secs_f64() * 1e3;
    }
    Ok((move_ms, moved))
}

/// The target error for the light left in the cuts: `--light-error` when given (refused
/// outside (0, 1)), else the scene file's `[environment] light_error`, else `None` (the
/// frame's default).
pub fn light_error(flag: Option<f64>, scene: Option<f64>) -> Result<Option<f64>> {
    match flag {
        Some(e) if !(e.is_finite() && e > 0.0 && e < 1.0) => {
            bail!("--light-error {e}: must lie in (0, 1): a relative error, e.g. 0.002 for 0.2 %")
        }
        Some(e) => Ok(Some(e)),
        None => Ok(scene),
    }
}

/// The camera called `name` of `view`, else its first, else one framing every object.
pub fn camera(view: Option<&View>, name: Option<&str>, frame: &Frame) -> Result<Camera> {
    let cameras = view.map_or(&[][..], |v| v.cameras.as_slice());
    Ok(match name {
        Some(name) => cameras.iter().find(|c| c.name == name).cloned().with_context(|| {
            let names: Vec<&str> = cameras.iter().map(|c| c.name.as_str()).collect();
            format!("no camera '{name}' (cameras: {})", if names.is_empty() { "none".into() } else { names.join(", ") })
        })?,
        None if !cameras.is_empty() => cameras[0].clone(),
        None => auto_camera(vcut_scene::Bounds::of_points((0..frame.object_count()).flat_map(|o| frame.positions(o)))),
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
