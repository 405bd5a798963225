//! The bench's `accuracy` section: the bench scenes (teapot and bunny; `--quick` the teapot) at
//! each preset (`--quick`: `fast`), under the built-in maps and (in a full run) every map of the
//! shared assets, at rest and moved — measured by `vcuts::accuracy::measure_map`; written to
//! `accuracy.json` after every map (a stopped run keeps what it measured), `accuracy.md` and
//! `accuracy.png` (the error per map at rest, with the goals); then the target-error sweep under
//! the map whose bright leaves err most, per scene and preset (`vcuts::accuracy::measure_knob`).

use anyhow::{Context, Result};
use std::path::Path;
use vcut_data::Precomputed;
use vcut_scene::Scene;
use vcut_shade::Frame;
use vcut_shade::measure::first_movable;
use vcut_shade::reference::MonteCarloParams;
use vcuts::accuracy::{AccuracySection, McCache, Subject, asset_maps, builtin_maps, measure_knob, measure_map};
use vcuts::report::{write_atomic, write_json};

/// Runs the section.
pub fn run(quick: bool, no_mc: bool, data_dir: &Path, out: &Path) -> Result<AccuracySection> {
    let presets: &[&str] = if quick { &["fast"] } else { &["fast", "balanced", "paper"] };
    let scenes: &[&str] = if quick { &["teapot"] } else { &["teapot", "bunny"] };
    let mut section = AccuracySection::default();
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
            println!("\n== accuracy: {name} at {preset}, {} maps", maps.len());
            let file =
                vcuts::precompute::cached_or_run_at(&spec, preset, &data_dir.join(format!("{name}-{preset}.vcuts")))?;
            let mut data = Precomputed::open(&file)?;
            let offset = data.svc_origin_offset();
            let mut frame = Frame::new(&mut data, &scene.environment)?;
            let movable = first_movable(&frame).with_context(|| format!("scene {name} has no movable object"))?;
            let subject = Subject { scene: name, preset, movable, eye, offset };
            for (map, env) in &maps {
                let cache = (!no_mc).then_some((&mut mc, &mc_params));
                section.rows.extend(measure_map(&mut frame, &subject, map, env, cache)?);
                write_json(&out.join("accuracy.json"), &section)?;
            }
            // The target-error sweep under the map whose bright leaves err most through the cuts
            // (the choice's estimate with none cast) at rest: where the target matters most.
            let worst = section
                .rows
                .iter()
                .filter(|r| r.scene == name && r.preset == preset && r.pose == "rest")
                .max_by(|a, b| a.light_estimate_cuts.total_cmp(&b.light_estimate_cuts))
                .map(|r| r.map.clone());
            if let Some((map, env)) = worst.and_then(|w| maps.iter().find(|(m, _)| *m == w)) {
                section.knob.extend(measure_knob(&mut frame, &subject, map, env)?);
                write_json(&out.join("accuracy.json"), &section)?;
            }
        }
    }
    let md = section.table();
    println!("\n{md}");
    write_atomic(&out.join("accuracy.md"), md.as_bytes())?;
    vcuts::plots::accuracy(&section, &out.join("accuracy.png"))?;
    Ok(section)
}
