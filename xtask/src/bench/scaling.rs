//! The bench's `scaling` section: `builtin:showroom:K` for K = 1 … 64 objects at `fast` and
//! `balanced`, and one teapot tessellated from 10k to ~1M vertices, each point measured by
//! `crate::measure::scaling::measure`; the growth exponents fitted, `scaling.csv`, and log–log plots
//! (`scaling_objects.png`, `scaling_vertices.png`). A point whose frame would not fit in the
//! memory available (extrapolated from the sweep's last point) is skipped and named. The
//! section so far is written to `scaling.json` and `scaling.csv` after every point, so that a
//! sweep stopped part way keeps what it measured.

use crate::measure::scaling::{ScalingPoint, ScalingSection, exponents, goals, measure};
use crate::report::write_atomic;
use anyhow::{Context, Result};
use std::path::Path;
use vcut_scene::budget::{available_memory, human};

/// Teapot tessellations of the vertex sweep (quads per patch edge) and the vertices each
/// gives with the ground: ~10k, 40k, 160k, 1M.
const TESSELLATIONS: [u32; 4] = [18, 36, 74, 186];
/// The same for `--quick`: ~3k and ~10k vertices.
const QUICK_TESSELLATIONS: [u32; 2] = [9, 18];

/// The vertex sweep's scene: the teapot scene's teapot at tessellation `r`.
fn teapot_scene(r: u32) -> String {
    format!(
        r#"[environment]
source = "builtin:sky"
sun_elevation_deg = 35.0
sun_azimuth_deg = 30.0

[[object]]
name = "teapot"
source = "builtin:teapot"
resolution = {r}
moves = true
material = {{ model = "blinn-phong", kd = [0.6, 0.45, 0.3], ks = [0.35, 0.35, 0.35], exponent = 15.0 }}

[[object]]
name = "ground"
source = "builtin:plane"
size = 14.0
resolution = 40
material = {{ model = "lambert", kd = [0.5, 0.5, 0.5] }}

[[camera]]
position = [5.0, 6.0, 10.0]
target = [0.0, 1.2, 0.0]
"#
    )
}

/// What the sweeps measure.
pub struct Sweeps {
    /// The showroom's object counts.
    pub counts: Vec<usize>,
    /// The object sweep's presets.
    pub presets: Vec<String>,
    /// The teapot's tessellations.
    pub tessellations: Vec<u32>,
}

impl Sweeps {
    /// The bench's sweeps (`--quick`: 1–8 objects at `fast`, and ~3k and ~10k vertices), or
    /// those `--scaling-objects`, `--scaling-presets` and `--scaling-tessellations` name
    /// (checked here, before any section runs).
    pub fn of(args: &crate::bench::BenchArgs) -> Result<Sweeps> {
        let quick = args.quick;
        let counts = args
            .scaling_objects
            .clone()
            .unwrap_or_else(|| if quick { vec![1, 2, 4, 8] } else { vec![1, 2, 4, 8, 16, 32, 64] });
        if let Some(k) = counts.iter().find(|&&k| k == 0) {
            anyhow::bail!("--scaling-objects {k}: a showroom holds at least one object");
        }
        let presets = args
            .scaling_presets
            .clone()
            .unwrap_or_else(|| if quick { vec!["fast".into()] } else { vec!["fast".into(), "balanced".into()] });
        if let Some(p) = presets.iter().find(|p| !vcut_data::params::PRESETS.contains(&p.as_str())) {
            anyhow::bail!(
                "--scaling-presets {p}: not a preset (expected one of {})",
                vcut_data::params::PRESETS.join(", ")
            );
        }
        let tessellations = args
            .scaling_tessellations
            .clone()
            .unwrap_or_else(|| if quick { QUICK_TESSELLATIONS.to_vec() } else { TESSELLATIONS.to_vec() });
        Ok(Sweeps { counts, presets, tessellations })
    }
}

/// Fits the section's exponents and goals to its points so far and writes it to
/// `out/scaling.json` and `out/scaling.csv`.
fn keep(section: &mut ScalingSection, out: &Path) -> Result<()> {
    section.exponents = exponents(&section.points);
    section.goals = goals(&section.points);
    write_atomic(&out.join("scaling.json"), serde_json::to_string_pretty(section)?.as_bytes())?;
    write_atomic(&out.join("scaling.csv"), crate::report::csv::scaling(&section.points).as_bytes())?;
    Ok(())
}

/// Runs the sweeps.
pub fn run(sweeps: &Sweeps, data_dir: &Path, out: &Path) -> Result<ScalingSection> {
    std::fs::create_dir_all(data_dir).with_context(|| format!("creating {}", data_dir.display()))?;
    let mut section = ScalingSection::default();
    let mut jobs: Vec<(&str, String, &str)> = Vec::new();
    for preset in &sweeps.presets {
        jobs.extend(sweeps.counts.iter().map(|k| ("objects", format!("builtin:showroom:{k}"), preset.as_str())));
    }
    for &r in &sweeps.tessellations {
        let path = data_dir.join(format!("scaling-teapot-{r}.toml"));
        write_atomic(&path, teapot_scene(r).as_bytes())?;
        jobs.push(("tessellation", path.display().to_string(), "fast"));
    }
    for (sweep, scene, preset) in jobs {
        if let Some(why) = too_big(&section.points, sweep, preset, &scene)? {
            println!("scaling: skipping {scene} at {preset}: {why}");
            section.skipped.push(format!("{scene} at {preset}: {why}"));
            keep(&mut section, out)?;
            continue;
        }
        println!("\n== scaling: {scene} at {preset}");
        let p = measure(sweep, &scene, preset, data_dir)?;
        println!(
            "scaling {sweep} {preset}: {} objects ({} movable), {} vertices: precompute {:.1} s, frame peak {}, move {:.1} ms eager \
             ({} merged, {:.1} µs each: {:.0} nodes, {:.1} ns each), {:.1} ms deferred, edit {:.1} ms, rel L2 vs exact {:.4}; no cache: frame peak {}, \
             move {:.1} ms eager",
            p.objects,
            p.movable,
            p.vertices,
            p.precompute_s,
            p.frame_peak_rss_bytes.map_or("unknown".into(), human),
            p.move_ms_eager,
            p.merged_vertices_eager,
            p.us_per_merged_vertex,
            p.nodes_per_merged_vertex,
            p.ns_per_merged_node,
            p.move_ms,
            p.edit_ms,
            p.rel_l2_exact,
            p.lean_frame_peak_rss_bytes.map_or("unknown".into(), human),
            p.lean_move_ms_eager
        );
        section.points.push(p);
        keep(&mut section, out)?;
    }
    crate::report::plots::scaling(&section, "objects", "objects", &out.join("scaling_objects.png"))?;
    crate::report::plots::scaling(&section, "tessellation", "vertices", &out.join("scaling_vertices.png"))?;
    println!("scaling exponents: {}", serde_json::to_string(&section.exponents)?);
    Ok(section)
}

/// Why scene `scene` is left out: its frame, at the bytes per vertex of the sweep's last
/// point, would take more than the memory available.
fn too_big(points: &[ScalingPoint], sweep: &str, preset: &str, scene: &str) -> Result<Option<String>> {
    let Some(last) = points.iter().rev().find(|p| p.sweep == sweep && p.preset == preset) else {
        return Ok(None);
    };
    let Some(per_vertex) = last.frame_peak_bytes_per_vertex else { return Ok(None) };
    let vertices = vcut_scene::Scene::open(scene)?.vertex_count();
    let need = (per_vertex * vertices as f64 * 1.2) as u64;
    Ok(available_memory()
        .filter(|&free| need > free)
        .map(|free| format!("its frame needs about {} ({vertices} vertices), {} is free", human(need), human(free))))
}
