//! `cargo xtask demo`: the main job on the built-in teapot scene under the built-in sky, through
//! the same library functions as the `vcuts` commands; its report from the values `render`
//! returns.

use anyhow::{Context, Result};
use vcuts::render::{self, Compare};
use vcuts::{directions, inspect, precompute};

/// Runs the demo.
pub fn demo() -> Result<()> {
    println!("== scene builtin:teapot");
    inspect::run(&inspect::InspectArgs::target("builtin:teapot"))?;
    println!("\n== environment builtin:sky");
    inspect::run(&inspect::InspectArgs::target("builtin:sky"))?;
    println!("\n== directions, direction tree and light tree (32,768 directions, builtin:sky)");
    directions::run(&directions::DirectionsArgs {
        n: 32_768,
        seed: 0,
        start: "fibonacci".into(),
        cache_dir: "target/vcut-cache".into(),
        no_cache: false,
        env: Some("builtin:sky".into()),
    })?;
    println!("\n== precompute builtin:teapot, preset fast (cached after the first run)");
    let file = precompute::cached_or_run("builtin:teapot", "fast")?;
    println!("\n== render at rest (Blinn-Phong exponent 15)");
    let rest = render::run(&render::RenderArgs::new(&file, std::path::Path::new("target/demo/teapot-rest.png")))?;
    println!("\n== render: the teapot moved, its Blinn-Phong exponent 15 -> 70, against the exact reference");
    let mut args = render::RenderArgs::new(&file, std::path::Path::new("target/demo/teapot.png"));
    args.moves.push("teapot=0.6,0,0.4".into());
    args.brdfs.push("teapot=blinn-phong:alpha=70".into());
    args.compare = Some(Compare::Exact);
    let edited = render::run(&args)?;
    println!("\n== the same, the sun through the cuts too, as the paper (--no-sun-rays)");
    args.output = "target/demo/teapot-cuts-only.png".into();
    args.no_sun_rays = true;
    let cuts_only = render::run(&args)?;
    let mut report = String::from(
        "# Demo: the built-in teapot scene under the built-in sky (preset fast)\n\n| | at rest | moved + BRDF edit | the same, sun through the cuts |\n|---|---:|---:|---:|\n",
    );
    type Cell = fn(&render::RenderOutcome) -> Option<String>;
    let rows: [(&str, Cell); 11] = [
        ("setup_s", |o| Some(format!("{:.3}", o.setup_s))),
        ("sun_leaves", |o| Some(o.sun_leaves.to_string())),
        ("move_merge_ms", |o| Some(format!("{:.2}", o.move_ms))),
        ("move_sun_ms", |o| o.last_move.map(|t| format!("{:.2}", t.sun_s * 1e3))),
        ("move_merged_vertices", |o| Some(o.moved_vertices.to_string())),
        ("shade_ms", |o| o.shade_ms.map(|x| format!("{x:.2}"))),
        ("raster_ms", |o| o.raster_ms.map(|x| format!("{x:.2}"))),
        ("vertex_rel_l2_vs_exact", |o| o.comparison("exact").and_then(|c| c.vertex_rel_l2).map(|x| format!("{x:.5}"))),
        ("pixel_rel_l2_vs_exact", |o| o.comparison("exact").map(|c| format!("{:.5}", c.pixel_rel_l2))),
        ("png", |o| Some(o.png.display().to_string())),
        ("reference_exact_png", |o| o.comparison("exact").map(|c| c.png.display().to_string())),
    ];
    for (key, cell) in rows {
        let [a, b, c] = [&rest, &edited, &cuts_only].map(|o| cell(o).unwrap_or_else(|| "-".into()));
        report.push_str(&format!("| {key} | {a} | {b} | {c} |\n"));
    }
    let path = std::path::Path::new("target/demo/report.md");
    std::fs::write(path, &report).with_context(|| format!("writing {}", path.display()))?;
    println!("\n{report}\nreport={}", path.display());
    Ok(())
}
