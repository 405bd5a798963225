//! The bench's plots (feature `plots`): the trade-off sweeps' error against data size or move
//! time with the Pareto fronts, the scaling section's log–log growth curves, the accuracy
//! section's error per map, and the assembly section's step times per scene. PNG, written atomically; drawn without text where the machine has no
//! sans-serif font.

use crate::bench::assembly::AssemblySection;
use crate::measure::accuracy::AccuracySection;
use crate::measure::assembly::AssemblyPoint;
use crate::measure::scaling::{ScalingPoint, ScalingSection};
use crate::report::Point;
use anyhow::{Context, Result};
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;

/// Registers a system sans-serif font for the plots' text; false if none is found (the plots
/// are then drawn without text).
pub fn font() -> bool {
    let candidates = [
        "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
        "/usr/share/fonts/TTF/DejaVuSans.ttf",
        "/usr/share/fonts/dejavu/DejaVuSans.ttf",
        "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    ];
    for c in candidates {
        if let Ok(bytes) = std::fs::read(c) {
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok() {
                return true;
            }
        }
    }
    false
}

/// A plotting error as an `anyhow` error.
fn err(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow::anyhow!("{e}")
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// A PNG of `size` pixels at `path`: `draw` paints it on a white area (told whether text can be
/// drawn); written beside the path and renamed, so a failed plot leaves nothing behind.
fn chart_png(path: &Path, size: (u32, u32), draw: impl FnOnce(&Area<'_>, bool) -> Result<()>) -> Result<()> {
    let text = font();
    let tmp = path.with_extension("partial.png");
    let drawn = (|| {
        let root = BitMapBackend::new(&tmp, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        draw(&root, text)?;
        root.present().map_err(err)
    })();
    match drawn {
        Ok(()) => std::fs::rename(&tmp, path).with_context(|| format!("writing {}", path.display())),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e.context(format!("plotting {}", path.display())))
        }
    }
}

/// A chart's frame: margins and, when text is drawn, the caption and the axes' label areas.
fn frame<'a, 'b>(
    root: &'a Area<'b>,
    text: bool,
    caption: &str,
    x_label_area: u32,
) -> ChartBuilder<'a, 'b, BitMapBackend<'b>> {
    let mut builder = ChartBuilder::on(root);
    builder.margin(20);
    if text {
        builder.caption(caption, ("sans-serif", 22));
        builder.x_label_area_size(x_label_area).y_label_area_size(70);
    }
    builder
}

/// The series' legend at `position` on a white box of opacity `opacity`.
fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    opacity: f64,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(opacity))
        .border_style(BLACK)
        .draw()
        .map_err(err)
}

/// A series as dots of `radius` joined by a line, labelled in the legend when `label` is given.
fn marked_line<'a, X, Y>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, Cartesian2d<X, Y>>,
    xy: Vec<(f64, f64)>,
    colour: RGBAColor,
    radius: u32,
    label: Option<impl Into<String>>,
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    chart.draw_series(xy.iter().map(|&p| Circle::new(p, radius, colour.filled()))).map_err(err)?;
    let line = chart.draw_series(LineSeries::new(xy, colour.stroke_width(2))).map_err(err)?;
    if let Some(label) = label {
        line.label(label).legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], colour.stroke_width(2)));
    }
    Ok(())
}

/// Error against data size or move time (`x_key`), one colour per sweep and each point labelled
/// with its value, the Pareto front joined: `path` (PNG).
pub fn tradeoff(points: &[Point], x_key: &'static str, x_label: &str, path: &Path) -> Result<()> {
    let scale = if x_key == "data_bytes" { 1e-6 } else { 1.0 };
    let xy: Vec<(f64, f64)> = points.iter().map(|p| (p.figures[x_key] * scale, p.figures["rel_l2_exact"])).collect();
    let finite: Vec<&(f64, f64)> =
        xy.iter().filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0).collect();
    if finite.is_empty() {
        return Ok(());
    }
    let x1 = finite.iter().fold(f64::MIN, |a, p| a.max(p.0));
    let y1 = finite.iter().fold(f64::MIN, |a, p| a.max(p.1));
    chart_png(path, (900, 600), |root, text| {
        let caption = format!("relative L2 vs exact reference against {x_label}");
        let mut chart =
            frame(root, text, &caption, 45).build_cartesian_2d(0.0..x1 * 1.3, 0.0..y1 * 1.15).map_err(err)?;
        if text {
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc("relative L2 (exact reference)")
                .x_labels(12)
                .y_labels(12)
                .y_label_formatter(&|y| format!("{y:.3}"))
                .draw()
                .map_err(err)?;
        }
        let sweeps: Vec<String> = points.iter().map(|p| p.sweep.clone()).fold(Vec::new(), |mut v, s| {
            if !v.contains(&s) {
                v.push(s);
            }
            v
        });
        for (k, sweep) in sweeps.iter().enumerate() {
            let colour = Palette99::pick(k).to_rgba();
            let series: Vec<(f64, f64, String)> = points
                .iter()
                .zip(&xy)
                .filter(|(p, _)| &p.sweep == sweep)
                .map(|(p, &(x, y))| (x, y, if text { p.value.clone() } else { String::new() }))
                .collect();
            let drawn = chart
                .draw_series(series.into_iter().map(|(x, y, label)| {
                    EmptyElement::at((x, y))
                        + Circle::new((0, 0), 6, colour.filled())
                        + Text::new(label, (8, -14), ("sans-serif", 13))
                }))
                .map_err(err)?;
            if text {
                drawn.label(sweep.as_str()).legend(move |(x, y)| Circle::new((x, y), 5, colour.filled()));
            }
        }
        let on_front = |p: &Point| if x_key == "data_bytes" { p.pareto_size } else { p.pareto_move };
        let mut front: Vec<(f64, f64)> = points.iter().zip(&xy).filter(|(p, _)| on_front(p)).map(|(_, &q)| q).collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart.draw_series(LineSeries::new(front, BLACK.stroke_width(2))).map_err(err)?;
        if text {
            legend(&mut chart, SeriesLabelPosition::LowerRight, 0.8)?;
        }
        Ok(())
    })
}

/// The figures drawn, their labels and the unit each is scaled to.
const DRAWN: [(&str, &str, f64); 6] = [
    ("move_ms_eager", "move, eager (ms)", 1.0),
    ("us_per_merged_vertex", "µs per merged vertex", 1.0),
    ("frame_peak_rss_bytes", "frame peak (MB)", 1e-6),
    ("lean_frame_peak_rss_bytes", "frame peak, no cache (MB)", 1e-6),
    ("precompute_s", "precompute (s)", 1.0),
    ("edit_ms", "BRDF edit (ms)", 1.0),
];

/// A log–log plot of sweep `sweep`: every drawn figure at every preset, its fitted exponent in
/// the legend. Nothing is written for a sweep of fewer than two sizes: one point shows no growth
/// (and `cargo xtask publish` then keeps the plot published before, e.g. the object sweep's when
/// a run measured only the vertex sweep).
pub fn scaling(section: &ScalingSection, sweep: &str, x_label: &str, path: &Path) -> Result<()> {
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
    let (x0, x1) = all.iter().fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.0), a.1.max(p.0)));
    if all.is_empty() || x1 <= x0 {
        return Ok(());
    }
    let (y0, y1) = all.iter().fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.1), a.1.max(p.1)));
    chart_png(path, (1000, 650), |root, text| {
        let caption = format!("how the costs grow with {x_label} (log–log)");
        let mut chart = frame(root, text, &caption, 45)
            .build_cartesian_2d((x0 / 1.3..x1 * 1.3).log_scale(), (y0 / 2.0..y1 * 4.0).log_scale())
            .map_err(err)?;
        if text {
            chart.configure_mesh().x_desc(x_label).draw().map_err(err)?;
        }
        for (k, (label, xy)) in series.into_iter().enumerate() {
            let colour = Palette99::pick(k).to_rgba();
            marked_line(&mut chart, xy, colour, 4, text.then_some(label))?;
        }
        if text {
            legend(&mut chart, SeriesLabelPosition::UpperLeft, 0.85)?;
        }
        Ok(())
    })
}

/// The accuracy section at rest: per scene and preset, the error against the exact reference
/// under each map (log scale), with the goals' 1 % and 0.5 % lines.
pub fn accuracy(section: &AccuracySection, path: &Path) -> Result<()> {
    let rest: Vec<_> = section.rows.iter().filter(|r| r.pose == "rest" && r.rel_l2_exact > 0.0).collect();
    let mut maps: Vec<&str> = Vec::new();
    for r in &rest {
        if !maps.contains(&r.map.as_str()) {
            maps.push(&r.map);
        }
    }
    let mut keys: Vec<(&str, &str)> = Vec::new();
    for r in &rest {
        if !keys.contains(&(r.scene.as_str(), r.preset.as_str())) {
            keys.push((&r.scene, &r.preset));
        }
    }
    if rest.is_empty() {
        return Ok(());
    }
    let y0 = rest.iter().map(|r| r.rel_l2_exact * 100.0).fold(0.5f64, f64::min) / 2.0;
    // Room above the highest point for the legend.
    let y1 = rest.iter().map(|r| r.rel_l2_exact * 100.0).fold(1.0f64, f64::max) * 6.0;
    chart_png(path, (1200, 700), |root, text| {
        let caption = "error against the exact reference per map, at rest";
        let n = maps.len() as f64;
        let mut chart =
            frame(root, text, caption, 60).build_cartesian_2d(-0.5..n - 0.5, (y0..y1).log_scale()).map_err(err)?;
        if text {
            let names = maps.clone();
            chart
                .configure_mesh()
                .x_labels(maps.len() * 2 + 1)
                .x_label_formatter(&move |x| {
                    let k = x.round();
                    if (x - k).abs() < 1e-6 && k >= 0.0 {
                        // A map file's name without its extension and resolution suffix.
                        names.get(k as usize).map_or(String::new(), |s| {
                            let stem = s.rsplit_once('.').map_or(*s, |(stem, _)| stem);
                            stem.trim_end_matches("_1k").to_string()
                        })
                    } else {
                        String::new()
                    }
                })
                .y_label_formatter(&|y| {
                    // Two significant digits, no float noise: 0.15, 0.5, 2, 10.
                    let digits = (1 - y.abs().max(1e-9).log10().floor() as i32).max(0) as usize;
                    let s = format!("{y:.digits$}");
                    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
                })
                .y_desc("rel. L2 %")
                .draw()
                .map_err(err)?;
        }
        for (goal, label) in [(1.0, "goal at balanced: 1 %"), (0.5, "goal at paper: 0.5 %")] {
            let line = chart
                .draw_series(LineSeries::new([(-0.5, goal), (n - 0.5, goal)], BLACK.mix(0.5).stroke_width(1)))
                .map_err(err)?;
            if text {
                line.label(label).legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], BLACK.mix(0.5)));
            }
        }
        for (k, &(scene, preset)) in keys.iter().enumerate() {
            let colour = Palette99::pick(k).to_rgba();
            let xy: Vec<(f64, f64)> = rest
                .iter()
                .filter(|r| r.scene == scene && r.preset == preset)
                .filter_map(|r| maps.iter().position(|m| *m == r.map).map(|x| (x as f64, r.rel_l2_exact * 100.0)))
                .collect();
            marked_line(&mut chart, xy, colour, 5, text.then(|| format!("{scene}, {preset}")))?;
        }
        if text {
            legend(&mut chart, SeriesLabelPosition::UpperRight, 0.85)?;
        }
        Ok(())
    })
}

/// One of the assembly plot's series: a step time of a point.
type Value = fn(&AssemblyPoint) -> f64;

/// The assembly section's eager step per scene, translated and dragged (log scale, ms), each
/// scene named by what it stands for and its preset: `path` (PNG).
pub fn assembly(section: &AssemblySection, path: &Path) -> Result<()> {
    let points = &section.points;
    if points.is_empty() {
        return Ok(());
    }
    let times = points.iter().flat_map(|p| [p.translate_ms_eager, p.drag_ms_eager]).filter(|t| *t > 0.0);
    let (y0, y1) = times.fold((f64::MAX, 0.0f64), |(lo, hi), t| (lo.min(t), hi.max(t)));
    let n = points.len() as f64;
    let names: Vec<String> = points.iter().map(|p| format!("{} {}", p.kind, p.preset)).collect();
    chart_png(path, (1000, 600), |root, text| {
        let caption = "a drag step (eager, with shading): translated against dragged";
        let mut chart = frame(root, text, caption, 50)
            .build_cartesian_2d(-0.5..n - 0.5, (y0 / 2.0..y1 * 4.0).log_scale())
            .map_err(err)?;
        if text {
            chart
                .configure_mesh()
                .x_labels(points.len() * 2 + 1)
                .x_label_formatter(&|x| {
                    let k = x.round();
                    if (x - k).abs() < 1e-6 && k >= 0.0 {
                        names.get(k as usize).cloned().unwrap_or_default()
                    } else {
                        String::new()
                    }
                })
                .y_desc("ms")
                .draw()
                .map_err(err)?;
        }
        let series: [(&str, Value); 2] =
            [("translated", |p| p.translate_ms_eager), ("dragged (rest products)", |p| p.drag_ms_eager)];
        for (k, (label, value)) in series.into_iter().enumerate() {
            let colour = Palette99::pick(k).to_rgba();
            let xy: Vec<(f64, f64)> = points.iter().enumerate().map(|(x, p)| (x as f64, value(p))).collect();
            marked_line(&mut chart, xy, colour, 5, text.then_some(label))?;
        }
        if text {
            legend(&mut chart, SeriesLabelPosition::UpperLeft, 0.85)?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plot is a whole PNG at its path, and nothing partial is left beside it.
    fn is_png(path: &Path) -> bool {
        let bytes = std::fs::read(path).unwrap();
        !path.with_extension("partial.png").exists() && bytes.len() > 1000 && bytes.starts_with(b"\x89PNG")
    }

    #[test]
    fn both_plots_write_whole_pngs() {
        let dir = std::env::temp_dir().join(format!("vcuts-plots-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let point = |sweep: &str, value: f64, front: bool| Point {
            sweep: sweep.into(),
            value: format!("{value}"),
            preset: "fast".into(),
            figures: [("data_bytes", value * 1e6), ("move_ms", value), ("rel_l2_exact", 0.1 / value)].into(),
            pareto_size: front,
            pareto_move: front,
        };
        let points = [point("directions", 1.0, true), point("directions", 2.0, true), point("levels", 3.0, false)];
        tradeoff(&points, "data_bytes", "data size (MB)", &dir.join("size.png")).unwrap();
        assert!(is_png(&dir.join("size.png")));
        let at = |objects: usize, preset: &str| ScalingPoint {
            sweep: "objects".into(),
            preset: preset.into(),
            objects: objects + 1,
            movable: objects,
            vertices: 500 * objects,
            move_ms_eager: 3.0 * objects as f64,
            precompute_s: objects as f64,
            ..ScalingPoint::default()
        };
        let section = ScalingSection {
            points: vec![at(1, "fast"), at(2, "fast"), at(4, "fast"), at(1, "balanced"), at(2, "balanced")],
            ..ScalingSection::default()
        };
        scaling(&section, "objects", "objects", &dir.join("objects.png")).unwrap();
        assert!(is_png(&dir.join("objects.png")));
        // A sweep with no points draws nothing and is no error.
        scaling(&section, "tessellation", "vertices", &dir.join("none.png")).unwrap();
        assert!(!dir.join("none.png").exists());
        // Nor does a sweep of one size (a run that measured only the other sweep).
        let one = ScalingSection { points: vec![at(1, "fast"), at(1, "balanced")], ..ScalingSection::default() };
        scaling(&one, "objects", "objects", &dir.join("one.png")).unwrap();
        assert!(!dir.join("one.png").exists());
        let row = |map: &str, preset: &str, e: f64| crate::measure::accuracy::test_row("teapot", preset, map, e);
        let acc = AccuracySection {
            rows: vec![row("sky-30", "fast", 0.02), row("studio", "fast", 0.03), row("sky-30", "paper", 0.004)],
            skipped: Vec::new(),
            knob: Vec::new(),
        };
        accuracy(&acc, &dir.join("accuracy.png")).unwrap();
        assert!(is_png(&dir.join("accuracy.png")));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
