//! The bench's `turns` section: objects turning about +Y through a symmetric direction set
//! (`turn_steps = 64`). The teapot and bunny scenes at `balanced` (`--quick`: the teapot at
//! `fast`), each point measured by `crate::measure::turns::measure`: a turn step beside a
//! translation step of the same object, eager, in one run, and the error against the exact
//! reference after turns of several angles beside the error at rest. Writes `turns.json` and
//! `turns.md` beside the report, the section so far after every point.

use crate::measure::turns::{TurnPoint, measure};
use crate::report::write_atomic;
use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;
use vcut_scene::budget::human;

/// The wedges of the direction set: turns snap to 5.625°.
const WEDGES: u32 = 64;
/// The turn whose error the goal bounds (degrees).
const GOAL_TURN_DEG: f32 = crate::measure::turns::POSE_DEG;

/// The section: its points and the goals as measured.
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct TurnsSection {
    /// Every scene measured, in order.
    pub points: Vec<TurnPoint>,
    /// The goals, as measured.
    pub goals: TurnGoals,
}

/// The turning issue's goals, as measured (`None`: no point measured it).
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct TurnGoals {
    /// The largest turn step over translation step of the same object (goal ≤ 1).
    pub turn_vs_translate: Option<f64>,
    /// The largest error after a 37° turn over the error at rest, at `balanced` (goal ≤ 1.2).
    pub error_37_vs_rest_balanced: Option<f64>,
    /// The largest error after a 37° turn over the error of the scene precomputed with the
    /// object turned there, at `balanced` (the pose's own error set apart).
    #[serde(default)]
    pub error_37_vs_precomputed_balanced: Option<f64>,
}

/// The goals of `points`.
fn goals(points: &[TurnPoint]) -> TurnGoals {
    let max = |v: Vec<f64>| v.into_iter().reduce(f64::max);
    let balanced = || points.iter().filter(|p| p.preset == "balanced");
    TurnGoals {
        turn_vs_translate: max(points.iter().map(|p| p.turn_vs_translate).collect()),
        error_37_vs_rest_balanced: max(balanced()
            .flat_map(|p| p.turns.iter().filter(|t| t.degrees == GOAL_TURN_DEG).map(|t| t.vs_rest))
            .collect()),
        error_37_vs_precomputed_balanced: max(balanced().filter_map(|p| p.turned_vs_precomputed).collect()),
    }
}

/// The section as a Markdown table: one row per scene, the error after each turn in its own
/// columns.
pub fn table(section: &TurnsSection) -> String {
    let angles: Vec<f32> =
        section.points.first().map(|p| p.turns.iter().map(|t| t.degrees).collect()).unwrap_or_default();
    let mut md = String::from(
        "| scene | preset | wedges | vertices | turned | file | translate step ms | turn step ms | turn/translate | rel. L2 at rest | precomputed at 37° |",
    );
    let mut rule = String::from("|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    for a in &angles {
        md += &format!(" after {a}° (snap) |");
        rule += "---:|";
    }
    md += &format!("\n{rule}\n");
    for p in &section.points {
        md += &format!(
            "| {} | {} | {} | {} | {} | {} | {:.1} | {:.1} | {:.2} | {:.3} % | {} |",
            p.scene,
            p.preset,
            p.wedges,
            p.vertices,
            p.turned_object,
            human(p.file_bytes),
            p.translate_ms_eager,
            p.turn_ms_eager,
            p.turn_vs_translate,
            p.rel_l2_rest * 100.0,
            p.precomputed_at_pose_rel_l2.map_or("—".into(), |e| format!("{:.3} %", e * 100.0))
        );
        for t in &p.turns {
            md += &format!(" {:.3} % ({:+.2}°) |", t.rel_l2 * 100.0, t.snap_error_deg);
        }
        md.push('\n');
    }
    md
}

/// Writes the section so far to `out/turns.json` and `out/turns.md`.
fn keep(section: &mut TurnsSection, out: &Path) -> Result<()> {
    section.goals = goals(&section.points);
    write_atomic(&out.join("turns.json"), serde_json::to_string_pretty(section)?.as_bytes())?;
    write_atomic(&out.join("turns.md"), table(section).as_bytes())?;
    Ok(())
}

/// Runs the section (`quick`: the teapot at `fast`).
pub fn run(quick: bool, data_dir: &Path, out: &Path) -> Result<TurnsSection> {
    std::fs::create_dir_all(data_dir).with_context(|| format!("creating {}", data_dir.display()))?;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let jobs: &[(&str, &str)] = if quick {
        &[("builtin:teapot", "fast")]
    } else {
        &[("builtin:teapot", "balanced"), ("builtin:bunny", "balanced")]
    };
    let mut section = TurnsSection::default();
    for &(scene, preset) in jobs {
        println!("\n== turns: {scene} at {preset}, {WEDGES} wedges");
        let p = measure(scene, preset, WEDGES, data_dir)?;
        println!(
            "turns {scene} {preset}: {} turned: translate {:.1} ms, turn {:.1} ms ({:.2}x), rel L2 rest {:.4}, \
             precomputed at the pose {:?} (turned over it {:?}), after {}",
            p.turned_object,
            p.translate_ms_eager,
            p.turn_ms_eager,
            p.turn_vs_translate,
            p.rel_l2_rest,
            p.precomputed_at_pose_rel_l2,
            p.turned_vs_precomputed,
            p.turns
                .iter()
                .map(|t| format!("{}°: {:.4} ({:.2}x)", t.degrees, t.rel_l2, t.vs_rest))
                .collect::<Vec<_>>()
                .join(", ")
        );
        section.points.push(p);
        keep(&mut section, out)?;
    }
    keep(&mut section, out)?;
    println!("turns goals: {}", serde_json::to_string(&section.goals)?);
    Ok(section)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::turns::TurnError;

    #[test]
    fn goals_take_the_worst_point_and_the_37_degree_turn_at_balanced() {
        let turn = |degrees: f32, vs_rest: f64| TurnError {
            degrees,
            vs_rest,
            rel_l2: 0.004 * vs_rest,
            ..TurnError::default()
        };
        let point = |preset: &str, ratio: f64, at_37: f64| TurnPoint {
            scene: "builtin:teapot".into(),
            preset: preset.into(),
            wedges: 64,
            turn_vs_translate: ratio,
            rel_l2_rest: 0.004,
            turns: vec![turn(5.625, 1.0), turn(37.0, at_37)],
            precomputed_at_pose_rel_l2: Some(0.004 * at_37 / 1.05),
            turned_vs_precomputed: Some(1.05),
            ..TurnPoint::default()
        };
        let mut section =
            TurnsSection { points: vec![point("fast", 1.4, 3.0), point("balanced", 0.9, 1.1)], ..Default::default() };
        section.goals = goals(&section.points);
        assert_eq!(section.goals.turn_vs_translate, Some(1.4));
        assert_eq!(section.goals.error_37_vs_rest_balanced, Some(1.1));
        assert_eq!(section.goals.error_37_vs_precomputed_balanced, Some(1.05));
        let md = table(&section);
        assert!(md.contains("after 37° (snap)") && md.contains("0.440 %"), "{md}");
        assert_eq!(md.lines().filter(|l| l.starts_with("| builtin:teapot")).count(), 2, "{md}");
    }
}
