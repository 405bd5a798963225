//! The trade-off sweeps of `cargo xtask bench`: one scene, a base preset, and one knob varied at a
//! time (the presets themselves, the SVC error and solid-angle thresholds, the number of
//! directions, field spheres, resolution and spacing, value quantisation). Per point: precompute
//! time, data size, merge, shade, edit and move times, and the relative L2 error against the
//! exact-direction reference (cast once per direction count and reused) and the Monte Carlo one
//! (once per scene). Written as `tradeoff.csv` with the Pareto fronts marked, and two plots.

use crate::report::Point;
use anyhow::{Context, Result};
use glam::Vec3;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;
use vcut_data::Precomputed;
use vcut_scene::Scene;
use vcut_shade::measure::{edit_ms, first_movable, median, move_path};
use vcut_shade::reference::{MonteCarloParams, errors, exact_direction, monte_carlo};
use vcut_shade::{Frame, MergeAlgorithm};

/// The sweeps: (knob, values). `quick` keeps them short.
fn sweeps(quick: bool) -> Vec<(&'static str, Vec<&'static str>)> {
    if quick {
        vec![
            ("preset", vec!["fast", "balanced"]),
            ("svc_max_error", vec!["0.02", "0.005"]),
            ("directions", vec!["4096", "8192"]),
            ("field_spheres", vec!["4", "16"]),
            ("field_resolution", vec!["4", "16"]),
            ("field_spacing", vec!["linear"]),
            ("svc_values", vec!["u8", "f32"]),
        ]
    } else {
        vec![
            ("preset", vec!["fast", "balanced", "paper"]),
            ("svc_max_error", vec!["0.02", "0.01", "0.0025"]),
            ("svc_solid_angle_divisor", vec!["32", "64", "256"]),
            ("directions", vec!["4096", "8192", "32768", "65536"]),
            ("field_spheres", vec!["8", "24", "32"]),
            ("field_resolution", vec!["8", "24", "32"]),
            ("field_spacing", vec!["linear"]),
            ("field_inner_flat", vec!["0.2"]),
            ("svc_values", vec!["u8", "f16", "f32"]),
        ]
    }
}

/// Every precompute of the sweeps on `scene_name` from `base`: (knob, value, its arguments, the
/// output in `data_dir`).
pub fn variants(
    scene_name: &str,
    base: &str,
    quick: bool,
    data_dir: &Path,
) -> Vec<(&'static str, &'static str, vcuts::precompute::PrecomputeArgs)> {
    let all: Vec<(&str, &str)> =
        sweeps(quick).into_iter().flat_map(|(k, vs)| vs.into_iter().map(move |v| (k, v))).collect();
    all.into_iter()
        .enumerate()
        .map(|(i, (key, value))| {
            let preset = if key == "preset" { value } else { base };
            let mut args = vcuts::precompute::PrecomputeArgs::new(&format!("builtin:{scene_name}"), preset);
            if key != "preset" {
                args.set.push(format!("{key}={value}"));
            }
            args.output = Some(data_dir.join(format!("tradeoff-{scene_name}-{i}.vcuts")));
            args.fresh = true;
            (key, value, args)
        })
        .collect()
}

/// Marks the points not dominated in (x, error): lower is better in both.
fn pareto(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(x, e)| {
            x.is_finite() && e.is_finite() && !points.iter().any(|&(x2, e2)| x2 <= x && e2 <= e && (x2 < x || e2 < e))
        })
        .collect()
}

/// Runs every sweep on `scene_name` from `base` and returns the points.
pub fn run(scene_name: &str, base: &str, quick: bool, data_dir: &Path, no_mc: bool) -> Result<Vec<Point>> {
    let scene = Scene::open(&format!("builtin:{scene_name}"))?;
    let eye = scene.cameras.first().map(|c| c.position).context("the built-in scene has a camera")?;
    let mut exact_by_n: BTreeMap<usize, Vec<Vec<Vec3>>> = BTreeMap::new();
    let mut mc: Option<Vec<Vec<Vec3>>> = None;
    let mut points = Vec::new();
    let all = variants(scene_name, base, quick, data_dir);
    for (i, (key, value, args)) in all.iter().enumerate() {
        println!("\n== trade-off {}/{}: {scene_name}, {base} with {key} = {value}", i + 1, all.len());
        let file = args.output.clone().context("a variant names its file")?;
        let t = Instant::now();
        let summary = vcuts::precompute::run(args)?.run;
        let summary = summary.context("precompute ran as a dry run")?;
        let precompute_s = t.elapsed().as_secs_f64();
        let mut data = Precomputed::open(&file)?;
        let offset = data.svc_origin_offset();
        let mut frame = Frame::open(&mut data, &scene.environment, &vcut_shade::FrameSettings::default(), None)?;
        let movable = first_movable(&frame).with_context(|| format!("scene {scene_name} has no movable object"))?;
        let shade_ms = edit_ms(&mut frame, movable, eye, 5);
        let path = move_path(&mut frame, movable, eye, MergeAlgorithm::Counter, 4)?;
        let (move_ms, merge_ms) = (path.move_ms, median(path.merge_ms));
        let shaded = frame.shade(eye);
        let n = frame.tree().leaf_count();
        let exact = exact_by_n.entry(n).or_insert_with(|| exact_direction(&frame, eye, offset));
        let rel_l2_exact = errors(&shaded, exact).0;
        if mc.is_none() && !no_mc {
            mc = Some(monte_carlo(&frame, &scene.environment, eye, offset, &MonteCarloParams::default()).0);
        }
        let rel_l2_mc = mc.as_ref().map_or(f64::NAN, |r| errors(&shaded, r).0);
        drop(data);
        std::fs::remove_file(&file).with_context(|| format!("removing {}", file.display()))?;
        let mut figures = BTreeMap::new();
        figures.insert("directions", n as f64);
        figures.insert("precompute_s", precompute_s);
        figures.insert("data_bytes", summary.file_bytes as f64);
        figures.insert("merge_ms", merge_ms);
        figures.insert("shade_ms", shade_ms);
        figures.insert("move_ms", move_ms);
        figures.insert("rel_l2_exact", rel_l2_exact);
        figures.insert("rel_l2_mc", rel_l2_mc);
        println!(
            "{key}={value}: {:.1} MB, move {move_ms:.0} ms, rel L2 {rel_l2_exact:.4}",
            summary.file_bytes as f64 / 1e6
        );
        points.push(Point {
            sweep: key.to_string(),
            value: value.to_string(),
            preset: args.preset.clone().unwrap_or_default(),
            figures,
            pareto_size: false,
            pareto_move: false,
        });
    }
    let err = |p: &Point| p.figures["rel_l2_exact"];
    let by_size = pareto(&points.iter().map(|p| (p.figures["data_bytes"], err(p))).collect::<Vec<_>>());
    let by_move = pareto(&points.iter().map(|p| (p.figures["move_ms"], err(p))).collect::<Vec<_>>());
    for ((p, s), m) in points.iter_mut().zip(by_size).zip(by_move) {
        p.pareto_size = s;
        p.pareto_move = m;
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pareto_front_keeps_only_undominated_points() {
        // (size, error): (3, 0.5) is dominated by (2, 0.4); ties on one axis need a win on the other.
        let pts = [(1.0, 0.9), (2.0, 0.4), (3.0, 0.5), (4.0, 0.1), (4.0, 0.2), (f64::NAN, 0.0)];
        assert_eq!(pareto(&pts), vec![true, true, false, true, false, false]);
    }
}
