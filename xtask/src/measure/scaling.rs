//! How every cost grows with a scene: one point of `cargo xtask bench`'s `scaling` section
//! measured — a scene precomputed, opened as a frame, an object dragged (eager and deferred), a
//! BRDF edit, the error against the exact reference on a vertex subset, and the peak memory
//! of the precompute and of the frame — and the growth exponent fitted to a series.
//!
//! Peaks are `VmHWM` from `/proc/self/status`, started anew before each job (the heap's
//! freed memory given back first: [`vcut_scene::budget::trim_heap`]) and taken over the
//! resident memory before it, so one process measures one job after another.

#![allow(missing_docs)]

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;
use vcut_data::Precomputed;
use vcut_scene::budget::{peak_memory, reset_peak_memory, resident_memory, trim_heap};
use vcut_scene::{Motion, Scene};
use vcut_shade::measure::{edit_ms, move_path};
use vcut_shade::{Frame, FrameCaches, FrameSettings, MergeAlgorithm};
use vcuts::precompute::PrecomputeArgs;

/// One scene measured.
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct ScalingPoint {
    /// `objects` (the showroom's object count grows) or `tessellation` (one object's vertices).
    pub sweep: String,
    pub preset: String,
    /// The scene as given to `precompute --scene`.
    pub scene: String,
    pub objects: usize,
    /// Objects that may move (the showroom's K; the ground is the one more static object).
    pub movable: usize,
    pub vertices: usize,
    pub moved_object: String,
    pub precompute_s: f64,
    pub file_bytes: u64,
    /// Peak resident memory of the precompute over the resident memory before it.
    pub precompute_peak_rss_bytes: Option<u64>,
    pub frame_setup_s: f64,
    /// Peak resident memory of opening the file, setting up the frame, the moves, the edit and
    /// the shadings, over the resident memory before.
    pub frame_peak_rss_bytes: Option<u64>,
    pub frame_peak_bytes_per_vertex: Option<f64>,
    /// What the frame holds after the moves (`Frame::memory`).
    pub frame_bytes: usize,
    pub frame_bytes_per_vertex: f64,
    /// Median step of a drag with every changed vertex merged: merge and shade (ms).
    pub move_ms_eager: f64,
    pub merged_vertices_eager: usize,
    /// The same with deferred merges (the default).
    pub move_ms: f64,
    pub merged_vertices: usize,
    /// Eager: the move's time (lookups, decoding, refining, merging) per vertex it merged.
    pub us_per_merged_vertex: f64,
    /// Eager: nodes of the merged cuts per vertex merged, and the merge's time per node (ns):
    /// their product is most of `us_per_merged_vertex`.
    #[serde(default)]
    pub nodes_per_merged_vertex: f64,
    #[serde(default)]
    pub ns_per_merged_node: f64,
    pub edit_ms: f64,
    /// A frame keeping no cache (`FrameCaches` all off, as `render --memory-budget` with a
    /// budget below its needs) set up for the camera's eye (`Frame::open` with the eye: the
    /// lists of the vertices facing it only): its peak resident memory over the memory before
    /// (setup, an eager drag, a shading), the same per vertex, what it holds after, and its
    /// eager drag.
    pub lean_frame_peak_rss_bytes: Option<u64>,
    pub lean_frame_peak_bytes_per_vertex: Option<f64>,
    pub lean_frame_bytes: usize,
    pub lean_move_ms_eager: f64,
    /// Relative L2 against the exact-direction reference over `exact_subset` vertices (every
    /// k-th of the scene's), at rest.
    pub rel_l2_exact: f64,
    pub exact_subset: usize,
}

/// The goals of the many-object issue, as measured.
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct ScalingGoals {
    /// `us_per_merged_vertex` at 32 objects over that at 2, `fast` (goal ≤ 1.5).
    pub us_per_vertex_k32_vs_k2: Option<f64>,
    /// Its two parts: `nodes_per_merged_vertex` at 32 over 2 (how much finer the products of
    /// more fields are: a bound no merge of the same cuts goes below) and `ns_per_merged_node`.
    #[serde(default)]
    pub nodes_per_vertex_k32_vs_k2: Option<f64>,
    #[serde(default)]
    pub ns_per_node_k32_vs_k2: Option<f64>,
    /// `frame_peak_bytes_per_vertex` at `balanced`, the largest over the object sweep (goal ≤ 4096).
    pub frame_peak_bytes_per_vertex_balanced: Option<f64>,
    /// `move_ms_eager` at 32 objects, `fast` (goal ≤ 150).
    pub drag_ms_eager_k32_fast: Option<f64>,
    /// `lean_frame_peak_bytes_per_vertex` at `balanced`, the largest over the object sweep: the
    /// same goal for a frame that keeps no cache.
    pub lean_frame_peak_bytes_per_vertex_balanced: Option<f64>,
    /// `lean_frame_peak_bytes_per_vertex` at `balanced` on the object sweep's largest scene.
    #[serde(default)]
    pub lean_frame_peak_bytes_per_vertex_largest_balanced: Option<f64>,
    /// What each vertex adds to the lean frame's peak at `balanced`: the peaks' difference
    /// between the object sweep's largest and smallest scenes over their vertices' — the cost
    /// per vertex without the frame's fixed part (the direction and light trees and their
    /// tables, the same at any scene size), which dominates a small scene's figure.
    #[serde(default)]
    pub lean_frame_marginal_bytes_per_vertex_balanced: Option<f64>,
}

/// The `scaling` section of the bench report.
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct ScalingSection {
    pub points: Vec<ScalingPoint>,
    /// `SWEEP/PRESET/FIGURE` → the slope of log(figure) against log(objects) or log(vertices).
    pub exponents: BTreeMap<String, f64>,
    pub goals: ScalingGoals,
    /// Points left out, and why (e.g. the frame would not fit in memory).
    pub skipped: Vec<String>,
}

/// The figures whose growth is fitted.
pub const FITTED: [&str; 10] = [
    "precompute_s",
    "file_bytes",
    "frame_peak_rss_bytes",
    "frame_bytes",
    "lean_frame_peak_rss_bytes",
    "lean_move_ms_eager",
    "move_ms_eager",
    "move_ms",
    "us_per_merged_vertex",
    "edit_ms",
];

impl ScalingPoint {
    /// The sweep's x: movable objects or vertices.
    pub fn x(&self) -> f64 {
        if self.sweep == "objects" { self.movable as f64 } else { self.vertices as f64 }
    }

    /// Figure `key` of [`FITTED`] (NaN for an unknown key or a missing peak).
    pub fn figure(&self, key: &str) -> f64 {
        match key {
            "precompute_s" => self.precompute_s,
            "file_bytes" => self.file_bytes as f64,
            "frame_peak_rss_bytes" => self.frame_peak_rss_bytes.map_or(f64::NAN, |b| b as f64),
            "frame_bytes" => self.frame_bytes as f64,
            "lean_frame_peak_rss_bytes" => self.lean_frame_peak_rss_bytes.map_or(f64::NAN, |b| b as f64),
            "lean_move_ms_eager" => self.lean_move_ms_eager,
            "move_ms_eager" => self.move_ms_eager,
            "move_ms" => self.move_ms,
            "us_per_merged_vertex" => self.us_per_merged_vertex,
            "edit_ms" => self.edit_ms,
            _ => f64::NAN,
        }
    }
}

/// The least-squares slope of log y against log x over the pairs where both are finite and
/// positive; `None` with fewer than two distinct x.
pub fn growth_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = logs.len() as f64;
    let (mx, my) = (logs.iter().map(|p| p.0).sum::<f64>() / n, logs.iter().map(|p| p.1).sum::<f64>() / n);
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (logs.len() >= 2 && sxx > 1e-12).then(|| sxy / sxx)
}

/// The exponents of every [`FITTED`] figure over every (sweep, preset) series of `points`.
pub fn exponents(points: &[ScalingPoint]) -> BTreeMap<String, f64> {
    let mut series: BTreeMap<(String, String), Vec<&ScalingPoint>> = BTreeMap::new();
    for p in points {
        series.entry((p.sweep.clone(), p.preset.clone())).or_default().push(p);
    }
    let mut out = BTreeMap::new();
    for ((sweep, preset), ps) in &series {
        for key in FITTED {
            let xy: Vec<(f64, f64)> = ps.iter().map(|p| (p.x(), p.figure(key))).collect();
            if let Some(e) = growth_exponent(&xy) {
                out.insert(format!("{sweep}/{preset}/{key}"), e);
            }
        }
    }
    out
}

/// The goals as measured by `points` (`None` where a point they need is missing).
pub fn goals(points: &[ScalingPoint]) -> ScalingGoals {
    let at =
        |k: usize, preset: &str| points.iter().find(|p| p.sweep == "objects" && p.movable == k && p.preset == preset);
    // A figure at 32 objects over the same at 2, `fast`.
    let k32_vs_k2 =
        |figure: fn(&ScalingPoint) -> f64| at(32, "fast").zip(at(2, "fast")).map(|(a, b)| figure(a) / figure(b));
    let balanced = || points.iter().filter(|p| p.sweep == "objects" && p.preset == "balanced");
    let (smallest, largest) = (balanced().min_by_key(|p| p.vertices), balanced().max_by_key(|p| p.vertices));
    ScalingGoals {
        us_per_vertex_k32_vs_k2: k32_vs_k2(|p| p.us_per_merged_vertex),
        nodes_per_vertex_k32_vs_k2: k32_vs_k2(|p| p.nodes_per_merged_vertex),
        ns_per_node_k32_vs_k2: k32_vs_k2(|p| p.ns_per_merged_node),
        frame_peak_bytes_per_vertex_balanced: points
            .iter()
            .filter(|p| p.sweep == "objects" && p.preset == "balanced")
            .filter_map(|p| p.frame_peak_bytes_per_vertex)
            .reduce(f64::max),
        drag_ms_eager_k32_fast: at(32, "fast").map(|p| p.move_ms_eager),
        lean_frame_peak_bytes_per_vertex_balanced: points
            .iter()
            .filter(|p| p.sweep == "objects" && p.preset == "balanced")
            .filter_map(|p| p.lean_frame_peak_bytes_per_vertex)
            .reduce(f64::max),
        lean_frame_peak_bytes_per_vertex_largest_balanced: largest.and_then(|p| p.lean_frame_peak_bytes_per_vertex),
        lean_frame_marginal_bytes_per_vertex_balanced: smallest
            .zip(largest)
            .filter(|(a, b)| b.vertices > a.vertices)
            .and_then(|(a, b)| {
                let (pa, pb) = (a.lean_frame_peak_rss_bytes? as f64, b.lean_frame_peak_rss_bytes? as f64);
                Some((pb - pa) / (b.vertices - a.vertices) as f64)
            }),
    }
}

/// Resident memory now (after giving freed heap back), and a new peak started.
pub(crate) fn start_peak() -> Option<u64> {
    trim_heap();
    let before = resident_memory();
    reset_peak_memory().then_some(before).flatten()
}

/// The peak since [`start_peak`] over the memory before it.
pub(crate) fn peak_since(before: Option<u64>) -> Option<u64> {
    Some(peak_memory()?.saturating_sub(before?))
}

/// Measures scene `scene` (a `precompute --scene` value) at `preset` in sweep `sweep`,
/// precomputing into `data_dir`.
pub fn measure(sweep: &str, scene: &str, preset: &str, data_dir: &Path) -> Result<ScalingPoint> {
    let file = data_dir.join(format!("scaling-{}-{preset}.vcuts", vcuts::precompute::scene_stem(scene)));
    let mut args = PrecomputeArgs::new(scene, preset);
    args.output = Some(file.clone());
    args.fresh = true;
    let before = start_peak();
    let t = Instant::now();
    let outcome = vcuts::precompute::run(&args)?;
    let (file, summary) = (outcome.file, outcome.run);
    let precompute_s = t.elapsed().as_secs_f64();
    let precompute_peak = peak_since(before);
    let summary = summary.context("precompute ran as a dry run")?;

    let opened = Scene::open(scene)?;
    let eye = opened.cameras.first().map(|c| c.position).context("the scene has no camera")?;
    let before = start_peak();
    let t = Instant::now();
    let mut data = Precomputed::open(&file)?;
    let offset = data.svc_origin_offset();
    let settings = FrameSettings::default();
    let mut frame = Frame::open(&mut data, &opened.environment, &settings, None)?;
    let frame_setup_s = t.elapsed().as_secs_f64();
    let moved = super::central_movable(&frame).with_context(|| format!("{scene} has no movable object"))?;
    let vertices: usize = (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count()).sum();
    frame.set_eye(eye)?;
    let edit = edit_ms(&mut frame, moved, eye, 5);
    frame.reconfigure(&FrameSettings { deferred_merges: false, ..settings.clone() })?;
    let eager = move_path(&mut frame, moved, eye, MergeAlgorithm::Counter, 4)?;
    frame.reconfigure(&settings)?;
    let deferred = move_path(&mut frame, moved, eye, MergeAlgorithm::Counter, 4)?;
    let shaded = frame.shade(eye);
    let frame_peak = peak_since(before);
    let memory = frame.memory().total();

    let (rel_l2_exact, subset) = super::exact_error(&frame, offset, eye, &shaded, 3000);
    let moved_name = frame.object(moved).name.to_string();
    let (objects, movable) = (
        frame.object_count(),
        (0..frame.object_count()).filter(|&o| frame.object(o).motion == Motion::Movable).count(),
    );
    drop((frame, data));

    // The same with no cache kept.
    let before = start_peak();
    let mut data = Precomputed::open(&file)?;
    let none = FrameSettings { caches: FrameCaches::NONE, deferred_merges: false, ..settings };
    let mut lean = Frame::open(&mut data, &opened.environment, &none, Some(eye))?;
    let lean_drag = move_path(&mut lean, moved, eye, MergeAlgorithm::Counter, 4)?;
    std::hint::black_box(lean.shade(eye));
    let lean_peak = peak_since(before);
    let lean_bytes = lean.memory().total();
    Ok(ScalingPoint {
        sweep: sweep.into(),
        preset: preset.into(),
        scene: scene.into(),
        objects,
        movable,
        vertices,
        moved_object: moved_name,
        precompute_s,
        file_bytes: summary.file_bytes,
        precompute_peak_rss_bytes: precompute_peak,
        frame_setup_s,
        frame_peak_rss_bytes: frame_peak,
        frame_peak_bytes_per_vertex: frame_peak.map(|b| b as f64 / vertices as f64),
        frame_bytes: memory,
        frame_bytes_per_vertex: memory as f64 / vertices as f64,
        move_ms_eager: eager.move_ms,
        merged_vertices_eager: eager.merged,
        move_ms: deferred.move_ms,
        merged_vertices: deferred.merged,
        us_per_merged_vertex: eager.us_per_merged_vertex(),
        nodes_per_merged_vertex: eager.nodes_per_merged_vertex(),
        ns_per_merged_node: eager.ns_per_merged_node(),
        edit_ms: edit,
        rel_l2_exact,
        exact_subset: subset,
        lean_frame_peak_rss_bytes: lean_peak,
        lean_frame_peak_bytes_per_vertex: lean_peak.map(|b| b as f64 / vertices as f64),
        lean_frame_bytes: lean_bytes,
        lean_move_ms_eager: lean_drag.move_ms,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponents_recover_a_power_law_and_skip_what_cannot_be_fitted() {
        let xy: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0].iter().map(|&x| (x, 3.0 * x * x)).collect();
        assert!((growth_exponent(&xy).unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(growth_exponent(&[(2.0, 1.0), (2.0, 5.0)]), None);
        assert_eq!(growth_exponent(&[(1.0, 1.0), (2.0, f64::NAN), (4.0, 0.0)]), None);
        let point = |k: usize, us: f64, preset: &str| ScalingPoint {
            sweep: "objects".into(),
            preset: preset.into(),
            movable: k,
            us_per_merged_vertex: us,
            nodes_per_merged_vertex: 100.0 * us,
            move_ms_eager: 10.0 * k as f64,
            frame_peak_bytes_per_vertex: Some(1000.0 * k as f64),
            vertices: 1000 * k,
            lean_frame_peak_rss_bytes: Some(20_000_000 + 3000 * 1000 * k as u64),
            lean_frame_peak_bytes_per_vertex: Some((20_000_000 + 3000 * 1000 * k) as f64 / (1000 * k) as f64),
            ..ScalingPoint::default()
        };
        let points =
            [point(2, 4.0, "fast"), point(32, 6.0, "fast"), point(2, 1.0, "balanced"), point(8, 1.0, "balanced")];
        let e = exponents(&points);
        assert!((e["objects/fast/move_ms_eager"] - 1.0).abs() < 1e-12);
        assert!(!e.contains_key("objects/fast/frame_peak_rss_bytes"));
        let g = goals(&points);
        assert_eq!(g.us_per_vertex_k32_vs_k2, Some(1.5));
        assert_eq!(g.nodes_per_vertex_k32_vs_k2, Some(1.5));
        assert_eq!(g.drag_ms_eager_k32_fast, Some(320.0));
        assert_eq!(g.frame_peak_bytes_per_vertex_balanced, Some(8000.0));
        // 20 MB fixed and 3,000 bytes a vertex: the largest scene's figure, and the fixed part
        // left out of the marginal one.
        assert_eq!(g.lean_frame_peak_bytes_per_vertex_balanced, Some(13_000.0));
        assert_eq!(g.lean_frame_peak_bytes_per_vertex_largest_balanced, Some(5_500.0));
        assert_eq!(g.lean_frame_marginal_bytes_per_vertex_balanced, Some(3_000.0));
    }
}
