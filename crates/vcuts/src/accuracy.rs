//! The bench's `accuracy` section: the bench scenes at rest and with their movable object moved,
//! under every environment map of the shared assets and the built-ins (the sky with its sun at
//! 10°, 30° and 60°, the studio, a constant), at each preset — the frame's error against the
//! exact-direction reference (and at rest the Monte Carlo one, computed once per scene and map
//! since it does not depend on the preset), the same frame with the sun carried by the cuts, the
//! light-tree leaves cast by rays, and what those rays cost an edit and a move.

use anyhow::{Context, Result};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::path::Path;
use vcut_envmap::EnvMap;
use vcut_envmap::procedural::{PreethamSky, Studio};
use vcut_shade::measure::{edit_ms, move_path, path_step};
use vcut_shade::reference::{MonteCarloParams, errors, exact_direction, monte_carlo};
use vcut_shade::{Frame, MergeAlgorithm, SunRays};

/// One scene, preset, map and pose.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct AccuracyRow {
    /// Scene (built-in name).
    pub scene: String,
    /// Preset.
    pub preset: String,
    /// Map (`sky-30`, `studio`, `constant`, or the asset's file name).
    pub map: String,
    /// `rest`, or `moved` (the movable object 0.4 of its radius along (1, 0, 0.5)).
    pub pose: String,
    /// Light-tree leaves cast by rays (the sun rule's choice).
    pub sun_leaves: usize,
    /// √(Σ s²) over the light tree's leaves, s a leaf's share of the light
    /// (`vcut_shade::sun::concentration`): 1 all in one leaf, 1/√N spread evenly.
    pub light_concentration: f64,
    /// The same over the leaves the cuts carry (those not cast by rays).
    pub light_concentration_left: f64,
    /// Relative L2 error against the exact-direction reference.
    pub rel_l2_exact: f64,
    /// Largest error against it, relative to its mean.
    pub max_err_exact: f64,
    /// Relative L2 error against the Monte Carlo reference (`null` without it, and when moved).
    pub rel_l2_mc: Option<f64>,
    /// Largest error against the Monte Carlo reference.
    pub max_err_mc: Option<f64>,
    /// The same frame with every leaf through the cuts (no rays), against the exact reference.
    pub rel_l2_exact_cuts_only: f64,
    /// Median edit (ms) with the rays, and with every leaf through the cuts.
    pub edit_ms: f64,
    /// The edit with no rays.
    pub edit_ms_cuts_only: f64,
    /// Median move step (ms) with the rays, and without.
    pub move_ms: f64,
    /// The move with no rays.
    pub move_ms_cuts_only: f64,
    /// The rays' share of an edit: (edit − edit without rays) / edit, at least 0 (a difference of
    /// two medians of 11: noisy where the rays cost little).
    pub rays_share_edit: f64,
    /// The rays' share of a move: the step's time casting them (`MoveTiming::sun_s`, the mean
    /// step) over the median step.
    pub rays_share_move: f64,
    /// Rays a move step casts (mean).
    pub rays_per_move: f64,
}

/// The section.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Default)]
pub struct AccuracySection {
    /// Every row.
    pub rows: Vec<AccuracyRow>,
    /// Maps or scenes not measured, and why.
    pub skipped: Vec<String>,
}

impl AccuracySection {
    /// The row with the largest error against the exact reference at `preset`.
    pub fn worst(&self, preset: &str) -> Option<&AccuracyRow> {
        self.rows.iter().filter(|r| r.preset == preset).max_by(|a, b| a.rel_l2_exact.total_cmp(&b.rel_l2_exact))
    }

    /// The section as a table: one row per scene, preset, map and pose; then the worst per preset.
    pub fn table(&self) -> String {
        let pct = |x: f64| format!("{:.2}", 100.0 * x);
        let mut md = String::from(
            "| scene | preset | map | pose | leaves cast | rel. L2 exact % | max exact % | rel. L2 MC % | cuts only: rel. L2 exact % | rays' share of edit / move % |\n\
             |---|---|---|---|---:|---:|---:|---:|---:|---:|\n",
        );
        for r in &self.rows {
            md.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} / {} |\n",
                r.scene,
                r.preset,
                r.map,
                r.pose,
                r.sun_leaves,
                pct(r.rel_l2_exact),
                pct(r.max_err_exact),
                r.rel_l2_mc.map_or("—".into(), pct),
                pct(r.rel_l2_exact_cuts_only),
                pct(r.rays_share_edit),
                pct(r.rays_share_move)
            ));
        }
        let mut presets: Vec<&str> = self.rows.iter().map(|r| r.preset.as_str()).collect();
        presets.dedup();
        for p in presets {
            if let Some(w) = self.worst(p) {
                md.push_str(&format!(
                    "\nWorst at `{p}`: {} under {} ({}), {} % against the exact reference.\n",
                    w.scene,
                    w.map,
                    w.pose,
                    pct(w.rel_l2_exact)
                ));
            }
        }
        for s in &self.skipped {
            md.push_str(&format!("\nSkipped: {s}\n"));
        }
        md
    }
}

/// The built-in maps: the sky with its sun at 10°, 30° and 60° (`--quick`: 30°), the studio, a
/// constant.
pub fn builtin_maps(quick: bool) -> Vec<(String, EnvMap)> {
    let elevations: &[f32] = if quick { &[30.0] } else { &[10.0, 30.0, 60.0] };
    let mut out: Vec<(String, EnvMap)> = elevations
        .iter()
        .map(|&e| (format!("sky-{e:.0}"), PreethamSky::from_elevation_azimuth(e, 45.0).bake(1024)))
        .collect();
    out.push(("studio".into(), Studio::default().bake(1024)));
    out.push(("constant".into(), EnvMap::constant([1.0; 3])));
    out
}

/// Every map in `<assets>/envmaps` that loads as an environment (a file or a cube-face folder),
/// by name; those that do not are listed with the reason.
pub fn asset_maps(assets: &Path) -> (Vec<(String, EnvMap)>, Vec<String>) {
    let dir = assets.join("envmaps");
    let mut entries: Vec<_> = match std::fs::read_dir(&dir) {
        Ok(r) => r.filter_map(|e| e.ok().map(|e| e.path())).collect(),
        Err(e) => return (Vec::new(), vec![format!("{}: {e}", dir.display())]),
    };
    entries.sort();
    let (mut maps, mut skipped) = (Vec::new(), Vec::new());
    for path in entries {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        match vcut_envmap::load(&path, vcut_envmap::InvalidTexels::Reject) {
            Ok((map, _)) => maps.push((name, map)),
            Err(e) => skipped.push(format!("map {name}: {e}")),
        }
    }
    (maps, skipped)
}

/// Monte Carlo references by (scene, map, pose): they do not depend on the preset.
pub type McCache = HashMap<(String, String, String), Vec<Vec<Vec3>>>;

/// Where a frame is measured: its scene and preset, the object that moves, the eye, the SVCs'
/// ray origin offset.
pub struct Subject<'a> {
    /// Scene name.
    pub scene: &'a str,
    /// Preset.
    pub preset: &'a str,
    /// The movable object.
    pub movable: usize,
    /// The eye.
    pub eye: Vec3,
    /// The SVC rays' origin offset (the references cast from the same points).
    pub offset: f32,
}

/// Rows of `frame` under `env` (named `map`): at rest and moved. With `mc`, the Monte Carlo
/// reference too (from the cache, or computed with `mc.1` and kept).
pub fn measure_map(
    frame: &mut Frame,
    s: &Subject<'_>,
    map: &str,
    env: &EnvMap,
    mut mc: Option<(&mut McCache, &MonteCarloParams)>,
) -> Result<Vec<AccuracyRow>> {
    frame.set_environment(env);
    let mut rows = Vec::new();
    let moved = path_step(frame, s.movable) * 4.0;
    for (pose, at) in [("rest", Vec3::ZERO), ("moved", moved)] {
        frame.set_sun_rays(Some(SunRays::default()));
        frame.translate(s.movable, at).context("placing the movable object")?;
        frame.set_deferred_merges(false).context("merging every vertex")?;
        let shaded = frame.shade(s.eye);
        let exact = exact_direction(frame, s.eye, s.offset);
        let (rel_l2_exact, max_err_exact) = errors(&shaded, &exact);
        // The Monte Carlo reference at rest only: it costs what every exact one does together.
        let (rel_l2_mc, max_err_mc) = match mc.as_mut().filter(|_| pose == "rest") {
            Some((cache, params)) => {
                let key = (s.scene.to_string(), map.to_string(), pose.to_string());
                let r = cache.entry(key).or_insert_with(|| monte_carlo(frame, env, s.eye, s.offset, params).0);
                let (l2, max) = errors(&shaded, r);
                (Some(l2), Some(max))
            }
            None => (None, None),
        };
        let sun_leaves = frame.sun_leaves();
        let cast = vcut_shade::sun::sun_leaves(frame.light(), &SunRays::default());
        let light_concentration = vcut_shade::sun::concentration(frame.light(), &[]);
        let light_concentration_left = vcut_shade::sun::concentration(frame.light(), &cast);
        let edit = edit_ms(frame, s.movable, s.eye, 11);
        let path = move_path(frame, s.movable, s.eye, MergeAlgorithm::Counter, 4)?;
        let steps = path.steps.len().max(1) as f64;
        let sun_ms = path.steps.iter().map(|t| t.sun_s).sum::<f64>() * 1e3 / steps;
        let rays_per_move = path.steps.iter().map(|t| t.sun_rays as f64).sum::<f64>() / steps;
        let mv = path.move_ms;
        frame.translate(s.movable, at)?;
        frame.set_sun_rays(None);
        let (rel_l2_exact_cuts_only, _) = errors(&frame.shade(s.eye), &exact);
        let edit_cuts = edit_ms(frame, s.movable, s.eye, 11);
        let mv_cuts = move_path(frame, s.movable, s.eye, MergeAlgorithm::Counter, 4)?.move_ms;
        frame.set_sun_rays(Some(SunRays::default()));
        frame.set_deferred_merges(true)?;
        let share = |part: f64, whole: f64| (part / whole.max(1e-9)).clamp(0.0, 1.0);
        rows.push(AccuracyRow {
            scene: s.scene.into(),
            preset: s.preset.into(),
            map: map.into(),
            pose: pose.into(),
            sun_leaves,
            light_concentration,
            light_concentration_left,
            rel_l2_exact,
            max_err_exact,
            rel_l2_mc,
            max_err_mc,
            rel_l2_exact_cuts_only,
            edit_ms: edit,
            edit_ms_cuts_only: edit_cuts,
            move_ms: mv,
            move_ms_cuts_only: mv_cuts,
            rays_share_edit: share(edit - edit_cuts, edit),
            rays_share_move: share(sun_ms, mv),
            rays_per_move,
        });
        println!(
            "{} {} {map} {pose}: {sun_leaves} leaves by rays, rel L2 exact {:.4} (cuts only {:.4}), mc {}",
            s.scene,
            s.preset,
            rel_l2_exact,
            rel_l2_exact_cuts_only,
            rel_l2_mc.map_or("-".into(), |x| format!("{x:.4}"))
        );
    }
    frame.translate(s.movable, Vec3::ZERO)?;
    Ok(rows)
}
