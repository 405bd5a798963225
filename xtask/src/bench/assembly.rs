//! The bench's `assembly` section: parts that touch against the same parts apart.
//! `builtin:assembly:K` (neighbours nearly touching) and `builtin:showroom:K` (the same objects
//! 3 units apart) at `fast` and `balanced`, and the engine of the shared assets on a ground
//! (every part movable, a piston dragged) at `fast` where the assets are — each point measured
//! by `crate::measure::assembly::measure`: the translated and the dragged step, the drag's
//! preparation and settle, fields, nodes and ns per node, memory, and the error against the
//! exact reference at rest, mid-drag and settled. Writes `assembly.json`, `assembly.md` and
//! `assembly.png` (step times per scene) beside the report, the section so far after every
//! point.

use crate::measure::assembly::{AssemblyPoint, measure};
use crate::report::write_atomic;
use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;
use vcut_scene::budget::human;

/// The engine of the shared assets, split into its mesh nodes, every part movable, scaled from
/// millimetres to stand 1.1 units tall on a 4 × 4 ground.
const ENGINE: &str = r#"[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 40
material = { model = "lambert", kd = [0.5, 0.5, 0.5] }

[[object]]
name = "engine"
source = "asset:gltf/2CylinderEngine.glb"
split = "mesh-nodes"
scale = 0.004
translation = [0.0, 0.73, 0.0]
moves = true

[[camera]]
position = [3.0, 2.6, 3.4]
target = [0.0, 0.6, 0.0]
"#;

/// The engine's part dragged.
const PISTON: &str = "engine/Piston_123-844_0_Parts_1";

/// The section: its points, what was left out, and the issue's goals as measured.
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct AssemblySection {
    /// Every scene measured, in order.
    pub points: Vec<AssemblyPoint>,
    /// What was left out, and why.
    pub skipped: Vec<String>,
    /// The issue's goals, as measured.
    pub goals: AssemblyGoals,
}

/// The dense-assembly issue's goals, as measured (`None`: a point it needs was not measured).
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct AssemblyGoals {
    /// The dense arrangement's error at rest over the spaced one's at `fast` (goal ≤ 1.5).
    pub dense_vs_spaced_error_fast: Option<f64>,
    /// The same at `balanced`.
    pub dense_vs_spaced_error_balanced: Option<f64>,
    /// The engine's piston: a drag step eager, with its shading (goal ≤ 150 ms).
    pub engine_drag_ms_eager: Option<f64>,
    /// The engine's frame mid-drag (goal ≤ 600 MB).
    pub engine_frame_bytes: Option<usize>,
}

/// The goals of `points`.
fn goals(points: &[AssemblyPoint]) -> AssemblyGoals {
    let find = |kind: &str, preset: &str| points.iter().find(|p| p.kind == kind && p.preset == preset);
    let ratio = |preset: &str| Some(find("dense", preset)?.rel_l2_rest / find("spaced", preset)?.rel_l2_rest);
    let engine = find("engine", "fast");
    AssemblyGoals {
        dense_vs_spaced_error_fast: ratio("fast"),
        dense_vs_spaced_error_balanced: ratio("balanced"),
        engine_drag_ms_eager: engine.map(|p| p.drag_ms_eager),
        engine_frame_bytes: engine.map(|p| p.frame_bytes_drag),
    }
}

/// The section as a Markdown table.
pub fn table(section: &AssemblySection) -> String {
    let mut md = String::from(
        "| scene | preset | vertices | dragged | translate step ms | drag step ms (deferred) | drag/translate | \
         prepare ms | settle ms | fields/vertex translate → drag | ns/node translate → drag | frame mid-drag | \
         rel. L2 rest / mid-drag / settled | refined at rest: rel. L2, ms, factors | first drag step idle / refining ms |\n\
         |---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for p in &section.points {
        // A scene file is named by what it stands for (its path is the bench's own).
        let scene = if p.scene.starts_with("builtin:") { p.scene.as_str() } else { p.kind.as_str() };
        md += &format!(
            "| {} | {} | {} | {} | {:.1} | {:.1} ({:.1}) | {:.3} | {:.0} | {:.0} | {:.1} → {:.1} | {:.1} → {:.1} | {} | \
             {:.2} % / {:.2} % / {:.2} % | {} | {} |\n",
            scene,
            p.preset,
            p.vertices,
            p.dragged_object,
            p.translate_ms_eager,
            p.drag_ms_eager,
            p.drag_ms_deferred,
            p.drag_vs_translate,
            p.prepare_ms,
            p.settle_ms,
            p.fields_per_vertex_translate,
            p.fields_per_vertex_drag,
            p.ns_per_node_translate,
            p.ns_per_node_drag,
            human(p.frame_bytes_drag as u64),
            p.rel_l2_rest * 100.0,
            p.rel_l2_drag * 100.0,
            p.rel_l2_settled * 100.0,
            refined(p),
            match (p.drag_first_step_idle_ms, p.drag_first_step_refining_ms) {
                (Some(a), Some(b)) => format!("{a:.0} / {b:.0}"),
                _ => "—".into(),
            },
        );
    }
    for s in &section.skipped {
        md += &format!("\nSkipped: {s}\n");
    }
    md
}

/// The refinement's cell of point `p`: its error, time and factors' memory (`—` for a point
/// measured before refinement).
fn refined(p: &AssemblyPoint) -> String {
    match (p.rel_l2_refined, p.refine_ms, p.refine_bytes) {
        (Some(e), Some(ms), Some(bytes)) => format!("{:.2} %, {ms:.0} ms, {}", e * 100.0, human(bytes as u64)),
        _ => "—".into(),
    }
}

/// Writes the section so far to `out/assembly.json` and `out/assembly.md`.
fn keep(section: &mut AssemblySection, out: &Path) -> Result<()> {
    section.goals = goals(&section.points);
    write_atomic(&out.join("assembly.json"), serde_json::to_string_pretty(section)?.as_bytes())?;
    write_atomic(&out.join("assembly.md"), table(section).as_bytes())?;
    Ok(())
}

/// Runs the section (`quick`: 4 objects at `fast`, no engine).
pub fn run(quick: bool, data_dir: &Path, out: &Path) -> Result<AssemblySection> {
    std::fs::create_dir_all(data_dir).with_context(|| format!("creating {}", data_dir.display()))?;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let (count, presets): (usize, &[&str]) = if quick { (4, &["fast"]) } else { (32, &["fast", "balanced"]) };
    let mut jobs: Vec<(&str, String, &str, Option<&str>)> = Vec::new();
    for &preset in presets {
        jobs.push(("dense", format!("builtin:assembly:{count}"), preset, None));
        jobs.push(("spaced", format!("builtin:showroom:{count}"), preset, None));
    }
    let mut section = AssemblySection::default();
    if !quick {
        match vcut_scene::assets::locate("gltf/2CylinderEngine.glb") {
            Ok(_) => {
                let path = data_dir.join("assembly-engine.toml");
                write_atomic(&path, ENGINE.as_bytes())?;
                jobs.push(("engine", path.display().to_string(), "fast", Some(PISTON)));
            }
            Err(e) => section.skipped.push(format!("the engine: {e}")),
        }
    }
    for (kind, scene, preset, object) in jobs {
        println!("\n== assembly: {scene} at {preset}");
        // The spaced scene drags the object the dense one dragged (the same names).
        let object = object.map(str::to_string).or_else(|| {
            (kind == "spaced")
                .then(|| section.points.iter().rev().find(|p| p.kind == "dense"))
                .flatten()
                .map(|p| p.dragged_object.clone())
        });
        let p = measure(kind, &scene, preset, object.as_deref(), data_dir)?;
        println!(
            "assembly {kind} {preset}: {} vertices, {} dragged: translate {:.1} ms, drag {:.1} ms ({:.3}x; deferred {:.1} ms), \
             prepare {:.0} ms, settle {:.0} ms, fields {:.1} -> {:.1}, frame {}, rel L2 rest {:.4} mid-drag {:.4} settled {:.4} refined {:?} in {:?} ms, first drag step idle {:?} refining {:?} ms",
            p.vertices,
            p.dragged_object,
            p.translate_ms_eager,
            p.drag_ms_eager,
            p.drag_vs_translate,
            p.drag_ms_deferred,
            p.prepare_ms,
            p.settle_ms,
            p.fields_per_vertex_translate,
            p.fields_per_vertex_drag,
            human(p.frame_bytes_drag as u64),
            p.rel_l2_rest,
            p.rel_l2_drag,
            p.rel_l2_settled,
            p.rel_l2_refined,
            p.refine_ms,
            p.drag_first_step_idle_ms,
            p.drag_first_step_refining_ms
        );
        section.points.push(p);
        keep(&mut section, out)?;
    }
    keep(&mut section, out)?;
    crate::report::plots::assembly(&section, &out.join("assembly.png"))?;
    println!("assembly goals: {}", serde_json::to_string(&section.goals)?);
    Ok(section)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn goals_pair_the_dense_and_spaced_points_of_a_preset() {
        let point = |kind: &str, preset: &str, err: f64| AssemblyPoint {
            kind: kind.into(),
            preset: preset.into(),
            scene: format!("builtin:{kind}"),
            rel_l2_rest: err,
            drag_ms_eager: 120.0,
            frame_bytes_drag: 5_000_000,
            ..AssemblyPoint::default()
        };
        let section = AssemblySection {
            points: vec![point("dense", "fast", 0.03), point("spaced", "fast", 0.02), point("engine", "fast", 0.1)],
            skipped: vec!["balanced: not asked".into()],
            goals: AssemblyGoals::default(),
        };
        let g = goals(&section.points);
        assert!((g.dense_vs_spaced_error_fast.unwrap() - 1.5).abs() < 1e-12);
        assert_eq!(g.dense_vs_spaced_error_balanced, None);
        assert_eq!((g.engine_drag_ms_eager, g.engine_frame_bytes), (Some(120.0), Some(5_000_000)));
        let md = table(&section);
        assert_eq!(md.lines().filter(|l| l.starts_with("| builtin:")).count(), 3, "{md}");
        assert!(md.contains("3.00 %") && md.contains("Skipped: balanced"), "{md}");
    }
}
