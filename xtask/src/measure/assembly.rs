//! One point of `cargo xtask bench`'s `assembly` section: a scene precomputed and opened, its
//! central movable object (or the one named) translated along the bench's path and then dragged
//! along it ([`vcut_shade::Frame::drag`]), eager and deferred; the drag's preparation and
//! settle; fields per merged vertex, nodes per merged vertex and ns per node of both; the
//! frame's memory mid-drag; and the error against the exact reference at rest, mid-drag,
//! settled and refined at rest, on a vertex subset; and a drag's first step posted to the
//! frame's worker idle and during a refinement.

#![allow(missing_docs)]

use anyhow::{Context, Result};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::Path;
use vcut_shade::measure::{drag_path, fields_per_merged_vertex, move_path};
use vcut_shade::{BackgroundFrame, Frame, FrameJob, FrameSettings, MergeAlgorithm};

/// Steps of each path.
const STEPS: usize = 4;
/// Vertices the exact reference is compared on (every k-th of the scene's).
const EXACT_SUBSET: usize = 3000;

/// One scene measured.
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct AssemblyPoint {
    /// What the scene stands for: `dense`, `spaced` (the same objects apart) or `engine`.
    pub kind: String,
    /// The scene as given to `precompute --scene`.
    pub scene: String,
    pub preset: String,
    pub objects: usize,
    pub vertices: usize,
    pub dragged_object: String,
    /// Median step of the translated path, every changed vertex merged: merge and shade (ms).
    pub translate_ms_eager: f64,
    /// The same step dragged (rest products; the preparation kept out of the first step).
    pub drag_ms_eager: f64,
    /// `drag_ms_eager` over `translate_ms_eager`, measured in one run.
    pub drag_vs_translate: f64,
    /// A drag's step with deferred merges (the default: the vertices facing the eye).
    pub drag_ms_deferred: f64,
    /// Preparing the rest products, and their vertices and bytes.
    pub prepare_ms: f64,
    pub prepared_vertices: usize,
    pub drag_bytes: usize,
    /// Settling the eager drag: its dragged vertices merged again in full.
    pub settle_ms: f64,
    pub settled_vertices: usize,
    /// Vertices per step: merged when translated, merged on rest products and left as they
    /// were (the dragged object hidden) when dragged.
    pub merged_vertices_translate: usize,
    pub on_rest_vertices: usize,
    pub hidden_vertices: usize,
    pub fields_per_vertex_translate: f64,
    pub fields_per_vertex_drag: f64,
    pub nodes_per_vertex_translate: f64,
    pub nodes_per_vertex_drag: f64,
    pub ns_per_node_translate: f64,
    pub ns_per_node_drag: f64,
    /// What the frame holds mid-drag (`Frame::memory`).
    pub frame_bytes_drag: usize,
    /// Relative L2 against the exact-direction reference at rest, mid-drag (the eager path's
    /// last step, not settled) and settled there, over `exact_subset` vertices.
    pub rel_l2_rest: f64,
    pub rel_l2_drag: f64,
    pub rel_l2_settled: f64,
    pub exact_subset: usize,
    /// The settled frame refined to completion (`Frame::refine`, every pair a field reaches):
    /// its error on the same vertices, the refinement's time and the exact factors' bytes
    /// (`null` in points of runs before refinement).
    #[serde(default)]
    pub rel_l2_refined: Option<f64>,
    #[serde(default)]
    pub refine_ms: Option<f64>,
    #[serde(default)]
    pub refine_bytes: Option<usize>,
    /// A drag's first step (rest products prepared, merged) posted to the frame's idle worker,
    /// and posted 100 ms into a refinement it cancels: from posting to done (ms).
    #[serde(default)]
    pub drag_first_step_idle_ms: Option<f64>,
    #[serde(default)]
    pub drag_first_step_refining_ms: Option<f64>,
}

/// [`AssemblyPoint::drag_first_step_idle_ms`] and `_refining_ms` of object `o` on `frame`
/// (handed to a worker), the shading toward `eye`.
fn drag_beside_refinement(frame: Frame, o: usize, eye: Vec3) -> Result<(f64, f64)> {
    let step = frame.object(o).mesh.bounds().radius * 0.1;
    let worker = BackgroundFrame::new(frame);
    worker.set_eye(eye);
    let first_step = |k: f32| -> Result<f64> {
        let ticket = worker.post(FrameJob::Drag { object: o, translation: Vec3::new(step * k, 0.0, 0.5 * step * k) });
        worker.wait();
        let done = worker.take_finished().into_iter().find(|f| f.ticket == ticket).context("the step ran")?;
        done.merged.context("the drag step")?;
        worker.post(FrameJob::Settle);
        worker.wait();
        Ok((done.finished - done.posted).as_secs_f64() * 1e3)
    };
    let idle = first_step(1.0)?;
    worker.post(FrameJob::Refine { seconds: None, reach: vcut_shade::REFINE_REACH });
    std::thread::sleep(std::time::Duration::from_millis(100));
    let refining = first_step(2.0)?;
    Ok((idle, refining))
}

/// Measures `scene` at `preset` (`kind`: what it stands for), dragging `object` (default: the
/// central movable one), precomputed into `data_dir` unless a file there holds it at `preset`.
pub fn measure(kind: &str, scene: &str, preset: &str, object: Option<&str>, data_dir: &Path) -> Result<AssemblyPoint> {
    let file = data_dir.join(format!("assembly-{}-{preset}.vcuts", vcuts::precompute::scene_stem(scene)));
    let file = vcuts::precompute::cached_or_run_at(scene, preset, &file)?;
    let super::OpenedFrame { mut frame, eye, offset } = super::open_frame(scene, &file, true)?;
    let o = match object {
        Some(name) => frame.object_index(name).with_context(|| format!("{scene}: no object {name}"))?,
        None => super::central_movable(&frame).with_context(|| format!("{scene} has no movable object"))?,
    };
    let shaded = frame.shade(eye);
    let (rel_l2_rest, exact_subset) = super::exact_error(&frame, offset, eye, &shaded, EXACT_SUBSET);
    let translated = move_path(&mut frame, o, eye, MergeAlgorithm::Counter, STEPS)?;
    let dragged = drag_path(&mut frame, o, eye, STEPS)?;
    let frame_bytes_drag = frame.memory().total();
    let shaded = frame.shade(eye);
    let (rel_l2_drag, _) = super::exact_error(&frame, offset, eye, &shaded, EXACT_SUBSET);
    let settled = frame.settle()?;
    let settle_ms = frame.stats().drag.settle_s * 1e3;
    let shaded = frame.shade(eye);
    let (rel_l2_settled, _) = super::exact_error(&frame, offset, eye, &shaded, EXACT_SUBSET);
    let refined = frame.refine(&vcut_shade::Refinement::default())?;
    let shaded = frame.shade(eye);
    let (rel_l2_refined, _) = super::exact_error(&frame, offset, eye, &shaded, EXACT_SUBSET);
    frame.unrefine()?;
    frame.reconfigure(&FrameSettings::default())?;
    let deferred = drag_path(&mut frame, o, eye, STEPS)?;
    frame.settle()?;
    let (objects, vertices, dragged_object) = (
        frame.object_count(),
        (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count()).sum(),
        frame.object(o).name.to_string(),
    );
    let (idle, refining) = drag_beside_refinement(frame, o, eye)?;
    let (t, d) = (&translated, &dragged.path);
    let per_step =
        |f: fn(&vcut_shade::MoveTiming) -> usize| d.steps.iter().map(f).sum::<usize>() / d.steps.len().max(1);
    Ok(AssemblyPoint {
        kind: kind.into(),
        scene: scene.into(),
        preset: preset.into(),
        objects,
        vertices,
        dragged_object,
        translate_ms_eager: t.move_ms,
        drag_ms_eager: d.move_ms,
        drag_vs_translate: d.move_ms / t.move_ms,
        drag_ms_deferred: deferred.path.move_ms,
        prepare_ms: dragged.drag.prepare_s * 1e3,
        prepared_vertices: dragged.drag.prepared,
        drag_bytes: dragged.drag.bytes,
        settle_ms,
        settled_vertices: settled,
        merged_vertices_translate: t.merged,
        on_rest_vertices: per_step(|m| m.on_rest),
        hidden_vertices: per_step(|m| m.hidden),
        fields_per_vertex_translate: fields_per_merged_vertex(&t.steps),
        fields_per_vertex_drag: fields_per_merged_vertex(&d.steps),
        nodes_per_vertex_translate: t.nodes_per_merged_vertex(),
        nodes_per_vertex_drag: d.nodes_per_merged_vertex(),
        ns_per_node_translate: t.ns_per_merged_node(),
        ns_per_node_drag: d.ns_per_merged_node(),
        frame_bytes_drag,
        rel_l2_rest,
        rel_l2_drag,
        rel_l2_settled,
        exact_subset,
        rel_l2_refined: Some(rel_l2_refined),
        refine_ms: Some(refined.seconds * 1e3),
        refine_bytes: Some(refined.bytes),
        drag_first_step_idle_ms: Some(idle),
        drag_first_step_refining_ms: Some(refining),
    })
}
