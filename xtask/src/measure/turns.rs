//! One point of `cargo xtask bench`'s `turns` section: a scene precomputed with a direction set
//! symmetric about +Y (`turn_steps`), its first movable object translated along the bench's
//! path and turned step by step ([`vcut_shade::Frame::turn`]), both eager, in the same run; then
//! the error against the exact reference (the geometry turned by exactly the angle asked for)
//! at rest and after turns of several angles, each with its snap; and, for one angle, the same
//! scene precomputed with the object already turned there, so that what the pose itself errs
//! is told apart from what the turn adds.

#![allow(missing_docs)]

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;
use vcut_shade::MergeAlgorithm;
use vcut_shade::measure::{first_movable, move_path, turn_path};

/// Steps of each path.
const STEPS: usize = 4;
/// Degrees of each step of the turned path: as far round as the translated path goes across
/// (0.1 of the object's radius a step is about 6° at its rim).
const TURN_STEP_DEG: f32 = 6.0;
/// Vertices the exact reference is compared on (every k-th of the scene's).
const EXACT_SUBSET: usize = 4000;
/// The turns the error is measured after (degrees).
pub const ANGLES: [f32; 5] = [5.625, 37.0, 90.0, 137.0, 180.0];

/// The error after one turn.
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct TurnError {
    pub degrees: f32,
    /// The whole wedges the cuts turned by, and the cuts' turn less the geometry's (degrees).
    pub steps: u32,
    pub snap_error_deg: f32,
    /// Relative L2 against the exact reference of the turned geometry, and over the error at
    /// rest.
    pub rel_l2: f64,
    pub vs_rest: f64,
}

/// One scene measured.
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct TurnPoint {
    /// The scene as given to `precompute --scene`.
    pub scene: String,
    pub preset: String,
    /// The direction set's wedges (`turn_steps`) and bands of its tree.
    pub wedges: u32,
    pub vertices: usize,
    pub turned_object: String,
    pub file_bytes: u64,
    /// Median step of the translated path and of the turned one, each with its shading, eager
    /// (ms), and their ratio, measured in one run.
    pub translate_ms_eager: f64,
    pub turn_ms_eager: f64,
    pub turn_vs_translate: f64,
    /// Vertices a step merged, translated and turned.
    pub merged_vertices_translate: usize,
    pub merged_vertices_turn: usize,
    /// Relative L2 against the exact-direction reference at rest, over `exact_subset` vertices.
    pub rel_l2_rest: f64,
    pub exact_subset: usize,
    /// After each turn of [`ANGLES`].
    pub turns: Vec<TurnError>,
    /// The scene precomputed with the object already turned by [`POSE_DEG`] (a scene file
    /// beside the data), against its own exact reference on the same vertices: what the pose
    /// itself errs, without any turn at run time (`null` where the scene is not a built-in or
    /// its loader placed the object elsewhere than the turn does).
    #[serde(default)]
    pub precomputed_at_pose_rel_l2: Option<f64>,
    /// The error after the run-time turn to [`POSE_DEG`] over `precomputed_at_pose_rel_l2`.
    #[serde(default)]
    pub turned_vs_precomputed: Option<f64>,
}

/// The turn a fresh precompute of the turned pose is compared at (degrees).
pub const POSE_DEG: f32 = 37.0;

/// Measures `scene` at `preset` with `turn_steps = wedges`, precomputed into `data_dir` unless a
/// file there holds it with those parameters.
pub fn measure(scene: &str, preset: &str, wedges: u32, data_dir: &Path) -> Result<TurnPoint> {
    let stem = vcuts::precompute::scene_stem(scene);
    let file = data_dir.join(format!("turns-{stem}-{preset}-{wedges}.vcuts"));
    let file = vcuts::precompute::cached_or_run_with(scene, preset, &[format!("turn_steps={wedges}")], &file)?;
    let super::OpenedFrame { mut frame, eye, offset } = super::open_frame(scene, &file, true)?;
    let o = first_movable(&frame).with_context(|| format!("{scene} has no movable object"))?;
    let shaded = frame.shade(eye);
    let (rel_l2_rest, exact_subset) = super::exact_error(&frame, offset, eye, &shaded, EXACT_SUBSET);
    let translated = move_path(&mut frame, o, eye, MergeAlgorithm::Counter, STEPS)?;
    let turned = turn_path(&mut frame, o, eye, TURN_STEP_DEG, STEPS)?;
    let mut turns = Vec::new();
    let mut pose: Option<(f64, Vec<glam::Vec3>)> = None;
    for degrees in ANGLES {
        let made = frame.turn(o, degrees.to_radians())?;
        let shaded = frame.shade(eye);
        let (rel_l2, _) = super::exact_error(&frame, offset, eye, &shaded, EXACT_SUBSET);
        if degrees == POSE_DEG {
            pose = Some((rel_l2, frame.object(o).positions()));
        }
        turns.push(TurnError {
            degrees,
            steps: made.steps,
            snap_error_deg: made.snap_error.to_degrees(),
            rel_l2,
            vs_rest: rel_l2 / rel_l2_rest,
        });
    }
    frame.turn(o, 0.0)?;
    let name = frame.object(o).name.to_string();
    let precomputed = match &pose {
        Some((_, positions)) => {
            let centre = frame.object(o).turn_centre();
            precomputed_at_pose(scene, preset, wedges, &name, centre, positions, data_dir)?
        }
        None => None,
    };
    Ok(TurnPoint {
        scene: scene.into(),
        preset: preset.into(),
        wedges,
        vertices: (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count()).sum(),
        turned_object: frame.object(o).name.to_string(),
        file_bytes: std::fs::metadata(&file).map(|m| m.len()).unwrap_or(0),
        translate_ms_eager: translated.move_ms,
        turn_ms_eager: turned.move_ms,
        turn_vs_translate: turned.move_ms / translated.move_ms,
        merged_vertices_translate: translated.merged,
        merged_vertices_turn: turned.merged,
        rel_l2_rest,
        exact_subset,
        turns,
        precomputed_at_pose_rel_l2: precomputed,
        turned_vs_precomputed: pose.zip(precomputed).map(|((turned, _), fresh)| turned / fresh),
    })
}

/// The error of built-in `scene` precomputed with object `name` turned by [`POSE_DEG`] about
/// the vertical through `centre` (as `Frame::turn` turns it: its positions there are
/// `positions`), against its own exact reference; `None` (and why, printed) where that cannot
/// be built.
fn precomputed_at_pose(
    scene: &str,
    preset: &str,
    wedges: u32,
    name: &str,
    centre: glam::Vec3,
    positions: &[glam::Vec3],
    data_dir: &Path,
) -> Result<Option<f64>> {
    let skip = |why: &str| {
        println!("turns: {scene} not precomputed at the pose: {why}");
        Ok(None)
    };
    let Some(mut desc) = scene.strip_prefix("builtin:").and_then(vcut_scene::scenes::builtin) else {
        return skip("not a built-in scene");
    };
    let Some(object) = desc.objects.iter_mut().find(|d| d.name.as_deref() == Some(name)) else {
        return skip("its object is not named in the scene");
    };
    if object.rotation_deg[0] != 0.0 || object.rotation_deg[2] != 0.0 || !object.instances.is_empty() {
        return skip("its object turns about more than +Y");
    }
    // World positions turn about the vertical through the centre: the translation follows.
    let turn = glam::Quat::from_rotation_y(POSE_DEG.to_radians());
    object.rotation_deg[1] += POSE_DEG;
    object.translation = (turn * (glam::Vec3::from(object.translation) - centre) + centre).to_array();
    let stem = vcuts::precompute::scene_stem(scene);
    let text = data_dir.join(format!("turns-{stem}-at-{POSE_DEG}.toml"));
    crate::report::write_atomic(&text, desc.to_toml().as_bytes())?;
    let text = text.display().to_string();
    let file = data_dir.join(format!("turns-{stem}-{preset}-{wedges}-at-{POSE_DEG}.vcuts"));
    let file = vcuts::precompute::cached_or_run_with(&text, preset, &[format!("turn_steps={wedges}")], &file)?;
    let super::OpenedFrame { mut frame, eye, offset } = super::open_frame(&text, &file, false)?;
    let o = frame.object_index(name).context("the turned scene lost its object")?;
    let radius = frame.object(o).mesh.bounds().radius;
    let apart = frame.object(o).positions().iter().zip(positions).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
    if frame.object(o).mesh.vertex_count() != positions.len() || apart > 1e-3 * radius {
        return skip(&format!("its loader placed the object {apart} from where the turn does"));
    }
    let shaded = frame.shade(eye);
    Ok(Some(super::exact_error(&frame, offset, eye, &shaded, EXACT_SUBSET).0))
}
