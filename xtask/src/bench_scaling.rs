//! The bench's `scaling` section: `builtin:showroom:K` for K = 1 … 64 objects at `fast` and
//! `balanced`, and one teapot tessellated from 10k to ~1M vertices, each point measured by
//! `vcuts::scaling::measure`; the growth exponents fitted, `scaling.csv`, and log–log plots
//! (`scaling_objects.png`, `scaling_vertices.png`). A point whose frame would not fit in the
//! memory available (extrapolated from the sweep's last point) is skipped and named.

use anyhow::{Context, Result};
use plotters::prelude::*;
use std::path::Path;
use vcut_scene::budget::{available_memory, human};
use vcuts::report::write_atomic;
use vcuts::scaling::{ScalingPoint, ScalingSection, exponents, goals, measure};

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

/// Runs the sweeps (`quick`: 1–8 objects at `fast`, and ~3k and ~10k vertices).
pub fn run(quick: bool, data_dir: &Path, out: &Path) -> Result<ScalingSection> {
    std::fs::create_dir_all(data_dir).with_context(|| format!("creating {}", data_dir.display()))?;
    let counts: &[usize] = if quick { &[1, 2, 4, 8] } else { &[1, 2, 4, 8, 16, 32, 64] };
    let presets: &[&str] = if quick { &["fast"] } else { &["fast", "balanced"] };
    let tessellations = if quick { &QUICK_TESSELLATIONS[..] } else { &TESSELLATIONS[..] };
    let mut section = ScalingSection::default();
    let mut jobs: Vec<(&str, String, &str)> = Vec::new();
    for &preset in presets {
        jobs.extend(counts.iter().map(|k| ("objects", format!("builtin:showroom:{k}"), preset)));
    }
    for &r in tessellations {
        let path = data_dir.join(format!("scaling-teapot-{r}.toml"));
        write_atomic(&path, teapot_scene(r).as_bytes())?;
        jobs.push(("tessellation", path.display().to_string(), "fast"));
    }
    for (sweep, scene, preset) in jobs {
        if let Some(why) = too_big(&section.points, sweep, preset, &scene)? {
            println!("scaling: skipping {scene} at {preset}: {why}");
            section.skipped.push(format!("{scene} at {preset}: {why}"));
            continue;
        }
        println!("\n== scaling: {scene} at {preset}");
        let p = measure(sweep, &scene, preset, data_dir)?;
        println!(
            "scaling {sweep} {preset}: {} objects ({} movable), {} vertices: precompute {:.1} s, frame peak {}, move {:.1} ms eager \
             ({} merged, {:.1} µs each), {:.1} ms deferred, edit {:.1} ms, rel L2 vs exact {:.4}",
            p.objects,
            p.movable,
            p.vertices,
            p.precompute_s,
            p.frame_peak_rss_bytes.map_or("unknown".into(), human),
            p.move_ms_eager,
            p.merged_vertices_eager,
            p.us_per_merged_vertex,
            p.move_ms,
            p.edit_ms,
            p.rel_l2_exact
        );
        section.points.push(p);
    }
    section.exponents = exponents(&section.points);
    section.goals = goals(&section.points);
    write_atomic(&out.join("scaling.csv"), csv(&section.points).as_bytes())?;
    plot(&section, "objects", "objects", &out.join("scaling_objects.png"))?;
    plot(&section, "tessellation", "vertices", &out.join("scaling_vertices.png"))?;
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

/// Every point as a CSV row.
fn csv(points: &[ScalingPoint]) -> String {
    let mut text = String::from("sweep,preset,objects,movable,vertices");
    for key in vcuts::scaling::FITTED {
        text.push(',');
        text.push_str(key);
    }
    text.push_str(",merged_vertices_eager,rel_l2_exact\n");
    for p in points {
        text.push_str(&format!("{},{},{},{},{}", p.sweep, p.preset, p.objects, p.movable, p.vertices));
        for key in vcuts::scaling::FITTED {
            text.push_str(&format!(",{}", p.figure(key)));
        }
        text.push_str(&format!(",{},{}\n", p.merged_vertices_eager, p.rel_l2_exact));
    }
    text
}

/// The figures drawn, their labels and the unit each is scaled to.
const DRAWN: [(&str, &str, f64); 5] = [
    ("move_ms_eager", "move, eager (ms)", 1.0),
    ("us_per_merged_vertex", "µs per merged vertex", 1.0),
    ("frame_peak_rss_bytes", "frame peak (MB)", 1e-6),
    ("precompute_s", "precompute (s)", 1.0),
    ("edit_ms", "BRDF edit (ms)", 1.0),
];

/// A log–log plot of sweep `sweep`: every drawn figure at every preset, its fitted exponent in
/// the legend.
fn plot(section: &ScalingSection, sweep: &str, x_label: &str, path: &Path) -> Result<()> {
    let points: Vec<&ScalingPoint> = section.points.iter().filter(|p| p.sweep == sweep).collect();
    let series: Vec<(String, Vec<(f64, f64)>)> = DRAWN
        .iter()
        .flat_map(|&(key, label, scale)| {
            let mut presets: Vec<&str> = points.iter().map(|p| p.preset.as_str()).collect();
            presets.dedup();
            let points = &points;
            presets.into_iter().map(move |preset| {
                let xy: Vec<(f64, f64)> = points
                    .iter()
                    .filter(|p| p.preset == preset)
                    .map(|p| (p.x(), p.figure(key) * scale))
                    .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
                    .collect();
                let e = section.exponents.get(&format!("{sweep}/{preset}/{key}"));
                (format!("{label}, {preset}: ∝ x^{}", e.map_or("?".into(), |e| format!("{e:.2}"))), xy)
            })
        })
        .filter(|(_, xy)| !xy.is_empty())
        .collect();
    let all: Vec<(f64, f64)> = series.iter().flat_map(|s| s.1.iter().copied()).collect();
    if all.is_empty() {
        return Ok(());
    }
    let (x0, x1) = all.iter().fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.0), a.1.max(p.0)));
    let (y0, y1) = all.iter().fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.1), a.1.max(p.1)));
    let text = crate::plot::font();
    let tmp = path.with_extension("partial.png");
    {
        let root = BitMapBackend::new(&tmp, (1000, 650)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
        let mut builder = ChartBuilder::on(&root);
        builder.margin(20);
        if text {
            builder.caption(format!("how the costs grow with {x_label} (log–log)"), ("sans-serif", 22));
            builder.x_label_area_size(45).y_label_area_size(70);
        }
        let mut chart = builder
            .build_cartesian_2d((x0 / 1.3..x1 * 1.3).log_scale(), (y0 / 2.0..y1 * 4.0).log_scale())
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        if text {
            chart.configure_mesh().x_desc(x_label).draw().map_err(|e| anyhow::anyhow!("{e}"))?;
        }
        for (k, (label, xy)) in series.into_iter().enumerate() {
            let colour = Palette99::pick(k).to_rgba();
            chart
                .draw_series(xy.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            let line =
                chart.draw_series(LineSeries::new(xy, colour.stroke_width(2))).map_err(|e| anyhow::anyhow!("{e}"))?;
            if text {
                line.label(label).legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], colour.stroke_width(2)));
            }
        }
        if text {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(|e| anyhow::anyhow!("{e}"))?;
        }
        root.present().map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    std::fs::rename(&tmp, path).with_context(|| format!("writing {}", path.display()))
}
