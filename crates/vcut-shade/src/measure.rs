//! The timed paths every measurement of a frame uses — `cargo xtask bench`, its trade-off
//! sweeps and the `move_path` example — so they time the same work: a move along a fixed path,
//! a BRDF edit, a camera turn after a move. Medians, not means: the machines are shared.

use crate::{Frame, FrameError, FrameSettings, MergeAlgorithm, MoveTiming};
use glam::Vec3;
use std::time::Instant;
use vcut_scene::{Material, Motion};

/// The middle value (the upper one of an even count); NaN for none.
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() { f64::NAN } else { v[v.len() / 2] }
}

/// The first movable object of `frame`, if any.
pub fn first_movable(frame: &Frame) -> Option<usize> {
    (0..frame.object_count()).find(|&o| frame.object(o).motion == Motion::Movable)
}

/// One step of the move path of object `o`: 0.1 of its bounding radius along (1, 0, 0.5).
pub fn path_step(frame: &Frame, o: usize) -> Vec3 {
    Vec3::new(1.0, 0.0, 0.5) * 0.1 * frame.object(o).mesh.bounds().radius
}

/// Median time of a BRDF edit: `runs` shadings, each after switching object `o`'s Blinn-Phong
/// exponent 70 ↔ 15; its material is restored after.
pub fn edit_ms(frame: &mut Frame, o: usize, eye: Vec3, runs: usize) -> f64 {
    let rest = *frame.object(o).material;
    let ms = median(
        (0..runs)
            .map(|i| {
                let exponent = if i % 2 == 0 { 70.0 } else { 15.0 };
                frame.set_material(o, Material { exponent, ..rest });
                let t = Instant::now();
                std::hint::black_box(frame.shade(eye));
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect(),
    );
    frame.set_material(o, rest);
    ms
}

/// What a move path measured.
pub struct PathTiming {
    /// Median time of one step: re-merge plus shade (ms).
    pub move_ms: f64,
    /// Merge time of every step (ms).
    pub merge_ms: Vec<f64>,
    /// Vertices re-merged per step, on average.
    pub merged: usize,
    /// Vertices per step whose merge waits (facing away from the eye), on average.
    pub deferred: usize,
    /// Where every step's move time went.
    pub steps: Vec<MoveTiming>,
}

impl PathTiming {
    /// Median over the steps of the move's time per vertex it merged (µs: lookups, decoding,
    /// refining and merging, without the sun's rays and the shading); NaN if no step merged.
    pub fn us_per_merged_vertex(&self) -> f64 {
        median(
            self.steps
                .iter()
                .filter(|t| t.vertices > 0)
                .map(|t| (t.keys_s + t.decode_s + t.refine_s + t.merge_s) * 1e6 / t.vertices as f64)
                .collect(),
        )
    }

    /// Nodes of the merged cuts per vertex the steps merged: how fine the products are (a
    /// merge emits every node once and lists it). NaN if no step merged.
    pub fn nodes_per_merged_vertex(&self) -> f64 {
        let (nodes, vertices) = self.steps.iter().fold((0, 0), |(n, v), t| (n + t.nodes, v + t.vertices));
        if vertices == 0 { f64::NAN } else { nodes as f64 / vertices as f64 }
    }

    /// Median over the steps of the merge's time (merging and listing, wall clock) per node
    /// it emitted (ns); NaN if no step merged.
    pub fn ns_per_merged_node(&self) -> f64 {
        median(self.steps.iter().filter(|t| t.nodes > 0).map(|t| t.merge_s * 1e9 / t.nodes as f64).collect())
    }
}

/// Moves object `o` from rest along `steps` steps of [`path_step`] with `algorithm`, shading
/// from `eye` after each, then back to rest (with the frame's own merge again).
pub fn move_path(
    frame: &mut Frame,
    o: usize,
    eye: Vec3,
    algorithm: MergeAlgorithm,
    steps: usize,
) -> Result<PathTiming, FrameError> {
    let step = path_step(frame, o);
    let own = frame.settings().clone();
    frame.reconfigure(&FrameSettings { merge_algorithm: algorithm, ..own.clone() })?;
    frame.translate(o, Vec3::ZERO)?;
    let timing = timed_path(frame, eye, steps, |f, i| Ok((f.translate(o, step * i as f32)?, 0.0)))?;
    frame.translate(o, Vec3::ZERO)?;
    frame.reconfigure(&own)?;
    Ok(timing)
}

/// `steps` steps of a path, each `step(frame, i)` (i from 1: the vertices it merged and the
/// seconds of it left out of its time) then a shading from `eye`, timed.
fn timed_path(
    frame: &mut Frame,
    eye: Vec3,
    steps: usize,
    mut step: impl FnMut(&mut Frame, usize) -> Result<(usize, f64), FrameError>,
) -> Result<PathTiming, FrameError> {
    let (mut times, mut merge_ms, mut merged, mut deferred, mut timings) = (Vec::new(), Vec::new(), 0, 0, Vec::new());
    for i in 1..=steps {
        let t = Instant::now();
        let (n, left_out) = step(frame, i)?;
        merged += n;
        std::hint::black_box(frame.shade(eye));
        times.push((t.elapsed().as_secs_f64() - left_out) * 1e3);
        let last = frame.stats().last_move;
        merge_ms.push(last.merge_s * 1e3);
        deferred += last.deferred;
        timings.push(last);
    }
    let n = steps.max(1);
    Ok(PathTiming { move_ms: median(times), merge_ms, merged: merged / n, deferred: deferred / n, steps: timings })
}

/// Turns object `o` from rest through `steps` turns of `degrees` each ([`Frame::turn`]),
/// shading from `eye` after each, then back to rest: the turn's [`move_path`].
pub fn turn_path(frame: &mut Frame, o: usize, eye: Vec3, degrees: f32, steps: usize) -> Result<PathTiming, FrameError> {
    frame.turn(o, 0.0)?;
    let timing = timed_path(frame, eye, steps, |f, i| Ok((f.turn(o, (degrees * i as f32).to_radians())?.merged, 0.0)))?;
    frame.turn(o, 0.0)?;
    Ok(timing)
}

/// What a drag path measured ([`drag_path`]): its steps as a [`PathTiming`] (the first step's
/// time without the drag's preparation) and the drag's own figures.
pub struct DragTiming {
    /// The steps.
    pub path: PathTiming,
    /// The preparation, the rest products' bytes, the vertices given one.
    pub drag: crate::DragStats,
}

/// Drags object `o` from rest along `steps` steps of [`path_step`] ([`Frame::drag`]), shading
/// from `eye` after each; leaves it dragged at the last step, not settled (the caller measures
/// the frame mid-drag, then settles).
pub fn drag_path(frame: &mut Frame, o: usize, eye: Vec3, steps: usize) -> Result<DragTiming, FrameError> {
    let step = path_step(frame, o);
    frame.translate(o, Vec3::ZERO)?;
    let path = timed_path(frame, eye, steps, |f, i| {
        let merged = f.drag(o, step * i as f32)?;
        Ok((merged, if i == 1 { f.stats().drag.prepare_s } else { 0.0 }))
    })?;
    Ok(DragTiming { path, drag: frame.stats().drag })
}

/// Field factors per vertex the steps merged (NaN if none merged).
pub fn fields_per_merged_vertex(steps: &[MoveTiming]) -> f64 {
    let (fields, vertices) = steps.iter().fold((0, 0), |(f, v), t| (f + t.fields, v + t.vertices));
    if vertices == 0 { f64::NAN } else { fields as f64 / vertices as f64 }
}

/// A camera turn right after a move: object `o` moved one step of [`move_path`] while shading
/// from `eye`, then the time to set the eye `behind` (merging what the move left facing away,
/// with deferred merges) and shade from it. Median of `runs`; returns it and the vertices the
/// turn merged. Leaves the object at rest and `eye` set.
pub fn turn_after_move(
    frame: &mut Frame,
    o: usize,
    eye: Vec3,
    behind: Vec3,
    runs: usize,
) -> Result<(f64, usize), FrameError> {
    let step = path_step(frame, o);
    let (mut times, mut merged) = (Vec::new(), 0);
    for i in 0..runs {
        frame.set_eye(eye)?;
        frame.translate(o, step * (1 + i % 2) as f32)?;
        let t = Instant::now();
        merged = frame.set_eye(behind)?;
        std::hint::black_box(frame.shade(behind));
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    frame.set_eye(eye)?;
    frame.translate(o, Vec3::ZERO)?;
    Ok((median(times), merged))
}
