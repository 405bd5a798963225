//! The bench's `accuracy` section: the bench scenes (teapot and bunny; `--quick` the teapot) at
//! each preset (`--quick`: `fast`), under the built-in maps and (in a full run) every map of the
//! shared assets, at rest and moved — measured by `crate::measure::accuracy::measure_map`; written to
//! `accuracy.json` after every map (a stopped run keeps what it measured), `accuracy.md` and
//! `accuracy.png` (the error per map at rest, with the goals); then the target-error sweep under
//! the map whose bright leaves err most where the cost cap does not bind, per scene and preset
//! (`crate::measure::accuracy::measure_knob`).
//! With `--reuse`, the rows and sweeps an earlier run wrote to `accuracy.json` are kept and only
//! what is missing is measured (a run of hours resumes from its last map).

use crate::measure::accuracy::{
    AccuracyRow, AccuracySection, McCache, Subject, asset_maps, builtin_maps, measure_knob, measure_map,
};
use crate::report::{write_atomic, write_json};
use anyhow::{Context, Result};
use std::path::Path;
use vcut_data::Precomputed;
use vcut_scene::Scene;
use vcut_shade::Frame;
use vcut_shade::measure::first_movable;
use vcut_shade::reference::MonteCarloParams;
use vcut_shade::sun::DEFAULT_MAX_LEAVES;

/// The rows and sweeps of an earlier run's `accuracy.json` (none where there is no such file);
/// its skipped list is measured again.
fn earlier(out: &Path) -> Result<AccuracySection> {
    let path = out.join("accuracy.json");
    match std::fs::read_to_string(&path) {
        Ok(text) => {
            let mut s: AccuracySection =
                serde_json::from_str(&text).with_context(|| format!("{}: not an accuracy section", path.display()))?;
            s.skipped.clear();
            println!("accuracy: reusing {} rows of {}", s.rows.len(), path.display());
            Ok(s)
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(AccuracySection::default()),
        Err(e) => Err(e).with_context(|| format!("reading {}", path.display())),
    }
}

/// The map the target-error sweep of `scene` at `preset` runs under: of the maps at rest whose
/// choice stopped short of the cost cap (so the target decides how many leaves are cast), the
/// one whose bright leaves err most through the cuts (the estimate with none cast); if the cap
/// bound every map, the one erring most.
fn sweep_map(rows: &[AccuracyRow], scene: &str, preset: &str) -> Option<String> {
    let rest = || rows.iter().filter(|r| r.scene == scene && r.preset == preset && r.pose == "rest");
    let most = |r: &mut dyn Iterator<Item = &AccuracyRow>| {
        r.max_by(|a, b| a.light_estimate_cuts.total_cmp(&b.light_estimate_cuts)).map(|r| r.map.clone())
    };
    most(&mut rest().filter(|r| r.sun_leaves < DEFAULT_MAX_LEAVES)).or_else(|| most(&mut rest()))
}

/// Runs the section; `reuse` keeps what an earlier run measured.
pub fn run(quick: bool, no_mc: bool, reuse: bool, data_dir: &Path, out: &Path) -> Result<AccuracySection> {
    let presets: &[&str] = if quick { &["fast"] } else { &["fast", "balanced", "paper"] };
    let scenes: &[&str] = if quick { &["teapot"] } else { &["teapot", "bunny"] };
    let mut section = if reuse { earlier(out)? } else { AccuracySection::default() };
    let measured = |s: &AccuracySection, scene: &str, preset: &str, map: &str| {
        s.rows.iter().filter(|r| r.scene == scene && r.preset == preset && r.map == map).count() >= 2
    };
    let mut maps = builtin_maps(quick);
    if !quick {
        match vcut_scene::assets::dir() {
            Some(dir) => {
                let (found, skipped) = asset_maps(&dir);
                maps.extend(found);
                section.skipped.extend(skipped);
            }
            None => section.skipped.push("the shared assets' maps: no assets folder (VCUT_ASSETS)".into()),
        }
    }
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    std::fs::create_dir_all(data_dir).with_context(|| format!("creating {}", data_dir.display()))?;
    let mc_params = MonteCarloParams::default();
    let mut mc = McCache::new();
    for &name in scenes {
        let spec = format!("builtin:{name}");
        let scene = match Scene::open(&spec) {
            Ok(s) => s,
            Err(e) => {
                section.skipped.push(format!("scene {name}: {e}"));
                continue;
            }
        };
        let eye = scene.cameras.first().map(|c| c.position).context("the built-in scene has a camera")?;
        for &preset in presets {
            let swept = section.knob.iter().any(|k| k.scene == name && k.preset == preset);
            if swept && maps.iter().all(|(m, _)| measured(&section, name, preset, m)) {
                println!("\n== accuracy: {name} at {preset}: measured before");
                continue;
            }
            println!("\n== accuracy: {name} at {preset}, {} maps", maps.len());
            let file =
                vcuts::precompute::cached_or_run_at(&spec, preset, &data_dir.join(format!("{name}-{preset}.vcuts")))?;
            let mut data = Precomputed::open(&file)?;
            let offset = data.svc_origin_offset();
            let mut frame = Frame::open(&mut data, &scene.environment, &vcut_shade::FrameSettings::default(), None)?;
            let movable = first_movable(&frame).with_context(|| format!("scene {name} has no movable object"))?;
            let subject = Subject { scene: name, preset, movable, eye, offset };
            for (map, env) in &maps {
                if measured(&section, name, preset, map) {
                    continue;
                }
                let cache = (!no_mc).then_some((&mut mc, &mc_params));
                section.rows.extend(measure_map(&mut frame, &subject, map, env, cache)?);
                write_json(&out.join("accuracy.json"), &section)?;
            }
            if swept {
                continue;
            }
            if let Some((map, env)) =
                sweep_map(&section.rows, name, preset).and_then(|w| maps.iter().find(|(m, _)| *m == w))
            {
                section.knob.extend(measure_knob(&mut frame, &subject, map, env)?);
                write_json(&out.join("accuracy.json"), &section)?;
            }
        }
    }
    let md = section.table();
    println!("\n{md}");
    write_atomic(&out.join("accuracy.md"), md.as_bytes())?;
    crate::report::plots::accuracy(&section, &out.join("accuracy.png"))?;
    Ok(section)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A teapot row at `fast` under `map` in `pose`, `leaves` cast, `estimate` with none cast.
    fn row(map: &str, pose: &str, leaves: usize, estimate: f64) -> serde_json::Value {
        serde_json::json!({
            "scene": "teapot", "preset": "fast", "map": map, "pose": pose, "sun_leaves": leaves,
            "light_concentration": 0.5, "light_concentration_left": 0.1, "rel_l2_exact": 0.01,
            "max_err_exact": 0.1, "rel_l2_mc": null, "max_err_mc": null,
            "rel_l2_exact_cuts_only": 0.02, "edit_ms": 1.0, "edit_ms_cuts_only": 1.0, "move_ms": 2.0,
            "move_ms_cuts_only": 2.0, "rays_share_edit": 0.0, "rays_share_move": 0.1, "rays_per_move": 3.0,
            "light_estimate_cuts": estimate
        })
    }

    #[test]
    fn the_sweep_runs_where_the_target_decides_not_the_cap() {
        let rows = |r: Vec<serde_json::Value>| -> Vec<AccuracyRow> { serde_json::from_value(r.into()).unwrap() };
        let capped = row("windows", "rest", DEFAULT_MAX_LEAVES, 0.09);
        let all = rows(vec![
            capped.clone(),
            row("sun", "rest", 2, 0.05),
            row("dim", "rest", 0, 0.001),
            row("sun", "moved", 2, 0.5),
        ]);
        assert_eq!(sweep_map(&all, "teapot", "fast").as_deref(), Some("sun"));
        assert_eq!(sweep_map(&rows(vec![capped]), "teapot", "fast").as_deref(), Some("windows"));
        assert_eq!(sweep_map(&all, "bunny", "fast"), None);
    }

    /// What `--reuse` finds complete is not measured again: the run neither precomputes nor
    /// opens a frame, and keeps the rows and sweeps it read.
    #[test]
    fn a_reused_run_measures_only_what_is_missing() {
        let out = std::env::temp_dir().join(format!("xtask-accuracy-reuse-{}", std::process::id()));
        std::fs::create_dir_all(&out).unwrap();
        let row = |map: &str, pose: &str| row(map, pose, 1, 0.01);
        let rows: Vec<_> = builtin_maps(true).iter().flat_map(|(m, _)| [row(m, "rest"), row(m, "moved")]).collect();
        let knob = serde_json::json!({"scene": "teapot", "preset": "fast", "map": "studio", "target": 0.002,
            "leaves": 3, "estimate": 0.001, "rel_l2_exact": 0.01, "rays_per_vertex": 5.0, "choice_ms": 1.0});
        let earlier = serde_json::json!({"rows": rows, "skipped": ["old"], "knob": [knob]});
        std::fs::write(out.join("accuracy.json"), earlier.to_string()).unwrap();
        let data = out.join("data");
        let section = run(true, true, true, &data, &out).unwrap();
        assert_eq!(section.rows.len(), rows.len());
        assert_eq!(section.knob.len(), 1);
        assert!(section.skipped.is_empty(), "{:?}", section.skipped);
        assert!(std::fs::read_dir(&data).unwrap().next().is_none(), "precomputed what was measured before");
        assert!(std::fs::read_to_string(out.join("accuracy.md")).unwrap().contains("Worst at `fast`"));
        // A file that is not an accuracy section is refused by name, not measured over.
        std::fs::write(out.join("accuracy.json"), "{\"rows\": 3}").unwrap();
        let e = format!("{:#}", run(true, true, true, &data, &out).unwrap_err());
        assert!(e.contains("accuracy.json: not an accuracy section"), "{e}");
        std::fs::remove_dir_all(&out).unwrap();
    }
}
