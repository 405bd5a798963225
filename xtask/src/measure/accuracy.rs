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
use vcut_shade::{Frame, FrameSettings, MergeAlgorithm};

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
    /// two medians of 11: noisy where the rays cost little); 0 where no leaf is cast.
    pub rays_share_edit: f64,
    /// The rays' share of a move: the step's time casting them (`MoveTiming::sun_s`, the mean
    /// step) over the median step.
    pub rays_share_move: f64,
    /// Rays a move step casts (mean).
    pub rays_per_move: f64,
    /// The target error the leaves were chosen for (`SunRays::target`).
    #[serde(default)]
    pub light_target: f64,
    /// The choice's estimate of the error the candidate leaves add through the cuts, none cast.
    #[serde(default)]
    pub light_estimate_cuts: f64,
    /// The same with the chosen leaves cast.
    #[serde(default)]
    pub light_estimate: f64,
    /// Milliseconds the estimate took (on a lighting change).
    #[serde(default)]
    pub estimate_ms: f64,
    /// Rays per vertex of the full cast (a lighting change).
    #[serde(default)]
    pub rays_per_vertex: f64,
    /// Microseconds per vertex of the full cast.
    #[serde(default)]
    pub cast_us_per_vertex: f64,
    /// The same frame refined to completion at rest (`Frame::refine`, every pair a field
    /// reaches), against the exact reference (`null` in rows of runs before refinement).
    #[serde(default)]
    pub rel_l2_exact_refined: Option<f64>,
    /// That refinement's time (ms).
    #[serde(default)]
    pub refine_ms: Option<f64>,
}

/// One point of the target-error sweep: the frame at rest under one map with the leaves chosen
/// for `target`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct KnobRow {
    /// Scene.
    pub scene: String,
    /// Preset.
    pub preset: String,
    /// Map.
    pub map: String,
    /// The target error.
    pub target: f64,
    /// Leaves cast.
    pub leaves: usize,
    /// The choice's estimate with them cast.
    pub estimate: f64,
    /// Relative L2 error against the exact reference.
    pub rel_l2_exact: f64,
    /// Rays per vertex of the full cast.
    pub rays_per_vertex: f64,
    /// Milliseconds of the estimate and of the full cast (a lighting change's extra cost).
    pub choice_ms: f64,
}

/// The section.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Default)]
pub struct AccuracySection {
    /// Every row.
    pub rows: Vec<AccuracyRow>,
    /// Maps or scenes not measured, and why.
    pub skipped: Vec<String>,
    /// The target-error sweep, per scene and preset under the map whose bright leaves err most
    /// through the cuts where the cost cap does not bind.
    #[serde(default)]
    pub knob: Vec<KnobRow>,
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
            "| scene | preset | map | pose | leaves cast | rel. L2 exact % | max exact % | rel. L2 MC % | cuts only: rel. L2 exact % | rays' share of edit / move % | refined: rel. L2 exact % | refine ms |\n\
             |---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        );
        for r in &self.rows {
            md.push_str(&crate::report::md_row([
                r.scene.clone(),
                r.preset.clone(),
                r.map.clone(),
                r.pose.clone(),
                r.sun_leaves.to_string(),
                pct(r.rel_l2_exact),
                pct(r.max_err_exact),
                r.rel_l2_mc.map_or("—".into(), pct),
                pct(r.rel_l2_exact_cuts_only),
                format!("{} / {}", pct(r.rays_share_edit), pct(r.rays_share_move)),
                r.rel_l2_exact_refined.map_or("—".into(), pct),
                r.refine_ms.map_or("—".into(), |ms| format!("{ms:.0}")),
            ]));
        }
        let mut presets: Vec<&str> = Vec::new();
        for r in &self.rows {
            if !presets.contains(&r.preset.as_str()) {
                presets.push(&r.preset);
            }
        }
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
        if !self.knob.is_empty() {
            md.push_str(
                "\nThe target error (`--light-error`) under the map whose bright leaves err most through the cuts where the cost cap does not bind (per scene and preset), at rest:\n\n\
                 | scene | preset | map | target % | leaves cast | estimate % | rel. L2 exact % | rays per vertex | choice ms |\n\
                 |---|---|---|---:|---:|---:|---:|---:|---:|\n",
            );
            for k in &self.knob {
                md.push_str(&crate::report::md_row([
                    k.scene.clone(),
                    k.preset.clone(),
                    k.map.clone(),
                    pct(k.target),
                    k.leaves.to_string(),
                    pct(k.estimate),
                    pct(k.rel_l2_exact),
                    format!("{:.1}", k.rays_per_vertex),
                    format!("{:.1}", k.choice_ms),
                ]));
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
    let own = frame.settings().clone();
    // Every vertex merged (the exact reference compares all), the sun by rays and not.
    let eager = FrameSettings { deferred_merges: false, sun_rays: true, ..own.clone() };
    let cuts = FrameSettings { sun_rays: false, ..eager.clone() };
    let mut rows = Vec::new();
    let moved = path_step(frame, s.movable) * 4.0;
    for (pose, at) in [("rest", Vec3::ZERO), ("moved", moved)] {
        frame.reconfigure(&eager).context("merging every vertex")?;
        frame.translate(s.movable, at).context("placing the movable object")?;
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
        let sun_leaves = frame.stats().sun_leaves;
        let choice = frame.light_choice().clone();
        let light_concentration = vcut_shade::sun::concentration(frame.light(), &[]);
        let light_concentration_left = vcut_shade::sun::concentration(frame.light(), &choice.cast);
        let edit = edit_ms(frame, s.movable, s.eye, 11);
        let path = move_path(frame, s.movable, s.eye, MergeAlgorithm::Counter, 4)?;
        let steps = path.steps.len().max(1) as f64;
        let sun_ms = path.steps.iter().map(|t| t.sun_s).sum::<f64>() * 1e3 / steps;
        let rays_per_move = path.steps.iter().map(|t| t.sun_rays as f64).sum::<f64>() / steps;
        let mv = path.move_ms;
        frame.translate(s.movable, at)?;
        // Refined where it stands, measured, and the factors dropped again so that the rows
        // after it measure the frame as it was.
        let refined = frame.refine(&vcut_shade::Refinement::default()).context("refining")?;
        let (rel_l2_exact_refined, _) = errors(&frame.shade(s.eye), &exact);
        frame.unrefine().context("dropping the refinement")?;
        frame.reconfigure(&cuts)?;
        let (rel_l2_exact_cuts_only, _) = errors(&frame.shade(s.eye), &exact);
        let edit_cuts = edit_ms(frame, s.movable, s.eye, 11);
        let mv_cuts = move_path(frame, s.movable, s.eye, MergeAlgorithm::Counter, 4)?.move_ms;
        frame.reconfigure(&own)?;
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
            // No leaf cast, no ray: the two edits' difference is the machine's noise.
            rays_share_edit: if sun_leaves == 0 { 0.0 } else { share(edit - edit_cuts, edit) },
            rays_share_move: share(sun_ms, mv),
            rays_per_move,
            light_target: choice.target,
            light_estimate_cuts: choice.estimate_cuts,
            light_estimate: choice.estimate,
            estimate_ms: choice.estimate_s * 1e3,
            rays_per_vertex: choice.rays_per_vertex(),
            cast_us_per_vertex: choice.cast_us_per_vertex(),
            rel_l2_exact_refined: Some(rel_l2_exact_refined),
            refine_ms: Some(refined.seconds * 1e3),
        });
        println!(
            "{} {} {map} {pose}: {sun_leaves} leaves by rays (estimate {:.4} -> {:.4}), rel L2 exact {:.4} (cuts only {:.4}), mc {}",
            s.scene,
            s.preset,
            choice.estimate_cuts,
            choice.estimate,
            rel_l2_exact,
            rel_l2_exact_cuts_only,
            rel_l2_mc.map_or("-".into(), |x| format!("{x:.4}"))
        );
    }
    frame.translate(s.movable, Vec3::ZERO)?;
    Ok(rows)
}

/// Targets of the sweep, loosest first.
pub const KNOB_TARGETS: [f64; 5] = [0.02, 0.005, 0.002, 0.001, 0.0005];

/// The target-error sweep of `frame` under `env` (named `map`) at rest: one row per target of
/// [`KNOB_TARGETS`]; leaves the frame at its setting before.
pub fn measure_knob(frame: &mut Frame, s: &Subject<'_>, map: &str, env: &EnvMap) -> Result<Vec<KnobRow>> {
    let own = frame.settings().clone();
    frame.set_environment(env);
    frame.translate(s.movable, Vec3::ZERO).context("placing the movable object")?;
    let eager = FrameSettings { deferred_merges: false, sun_rays: true, ..own.clone() };
    frame.reconfigure(&eager).context("merging every vertex")?;
    let exact = exact_direction(frame, s.eye, s.offset);
    let mut rows = Vec::new();
    for target in KNOB_TARGETS {
        frame.reconfigure(&FrameSettings { light_error: Some(target), ..eager.clone() })?;
        let (rel_l2_exact, _) = errors(&frame.shade(s.eye), &exact);
        let c = frame.light_choice();
        rows.push(KnobRow {
            scene: s.scene.into(),
            preset: s.preset.into(),
            map: map.into(),
            target,
            leaves: c.cast.len(),
            estimate: c.estimate,
            rel_l2_exact,
            rays_per_vertex: c.rays_per_vertex(),
            choice_ms: (c.estimate_s + c.cast_s) * 1e3,
        });
        println!(
            "{} {} {map} target {target}: {} leaves, estimate {:.4}, rel L2 exact {rel_l2_exact:.4}",
            s.scene,
            s.preset,
            c.cast.len(),
            c.estimate
        );
    }
    frame.reconfigure(&own)?;
    Ok(rows)
}

/// A row of `scene` at `preset` under `map`, at rest, erring `e` (for tests).
#[cfg(test)]
pub(crate) fn test_row(scene: &str, preset: &str, map: &str, e: f64) -> AccuracyRow {
    AccuracyRow {
        scene: scene.into(),
        preset: preset.into(),
        map: map.into(),
        pose: "rest".into(),
        sun_leaves: 1,
        light_concentration: 0.5,
        light_concentration_left: 0.1,
        rel_l2_exact: e,
        max_err_exact: 0.0,
        rel_l2_mc: None,
        max_err_mc: None,
        rel_l2_exact_cuts_only: e,
        edit_ms: 1.0,
        edit_ms_cuts_only: 1.0,
        move_ms: 1.0,
        move_ms_cuts_only: 1.0,
        rays_share_edit: 0.0,
        rays_share_move: 0.0,
        rays_per_move: 0.0,
        light_target: 0.002,
        light_estimate_cuts: 0.01,
        light_estimate: 0.001,
        estimate_ms: 1.0,
        rays_per_vertex: 1.0,
        cast_us_per_vertex: 1.0,
        rel_l2_exact_refined: None,
        refine_ms: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_names_one_worst_row_per_preset_over_every_scene() {
        let section = AccuracySection {
            rows: vec![
                test_row("teapot", "fast", "m", 0.02),
                test_row("teapot", "paper", "m", 0.004),
                test_row("bunny", "fast", "m", 0.03),
            ],
            ..AccuracySection::default()
        };
        let table = section.table();
        let worst: Vec<&str> = table.lines().filter(|l| l.starts_with("Worst at")).collect();
        assert_eq!(
            worst,
            [
                "Worst at `fast`: bunny under m (rest), 3.00 % against the exact reference.",
                "Worst at `paper`: teapot under m (rest), 0.40 % against the exact reference."
            ]
        );
    }
}
