//! `cargo xtask demo`: the main job on the built-in teapot scene under the built-in sky, through
//! the same library functions as the `vcuts` commands; its report from the values `render`
//! returns.

use anyhow::{Context, Result};
use std::collections::HashMap;
use vcuts::render::{self, Compare};
use vcuts::{directions, inspect, outcome, precompute};

/// Runs the demo.
pub fn demo() -> Result<()> {
    println!("== scene builtin:teapot");
    outcome::print(&inspect::run(&inspect::InspectArgs::target("builtin:teapot"))?);
    println!("\n== environment builtin:sky");
    outcome::print(&inspect::run(&inspect::InspectArgs::target("builtin:sky"))?);
    println!("\n== directions, direction tree and light tree (32,768 directions, builtin:sky)");
    outcome::print(&directions::run(&directions::DirectionsArgs {
        n: 32_768,
        seed: 0,
        start: vcut_sphere::Start::Fibonacci,
        cache_dir: "target/vcut-cache".into(),
        no_cache: false,
        env: Some("builtin:sky".into()),
        wedges: 1,
        bands: 0,
    })?);
    println!("\n== precompute builtin:teapot, preset fast (cached after the first run)");
    let file = precompute::cached_or_run("builtin:teapot", "fast")?;
    println!("\n== render at rest (Blinn-Phong exponent 15)");
    let rest = render::run(&render::RenderArgs::new(&file, std::path::Path::new("target/demo/teapot-rest.png")))?;
    outcome::print(&rest);
    println!("\n== render: the teapot moved, its Blinn-Phong exponent 15 -> 70, against the exact reference");
    let mut args = render::RenderArgs::new(&file, std::path::Path::new("target/demo/teapot.png"));
    args.moves.push("teapot=0.6,0,0.4".parse().map_err(anyhow::Error::msg)?);
    args.brdfs.push("teapot=blinn-phong:alpha=70".parse().map_err(anyhow::Error::msg)?);
    args.compare = Some(Compare::Exact);
    let edited = render::run(&args)?;
    outcome::print(&edited);
    println!("\n== the same, the sun through the cuts too, as the paper (--no-sun-rays)");
    args.output = "target/demo/teapot-cuts-only.png".into();
    args.frame.no_sun_rays = true;
    let cuts_only = render::run(&args)?;
    outcome::print(&cuts_only);
    let mut report = String::from(
        "# Demo: the built-in teapot scene under the built-in sky (preset fast)\n\n| | at rest | moved + BRDF edit | the same, sun through the cuts |\n|---|---:|---:|---:|\n",
    );
    // The three outcomes' keys as `render` prints them.
    let columns =
        [&rest, &edited, &cuts_only].map(|o| outcome::lines(o).map(|l| l.into_iter().collect::<HashMap<_, _>>()));
    let [a, b, c] = columns.map(|c| c.unwrap_or_default());
    for key in [
        "setup_s",
        "sun_leaves",
        "move_merge_ms",
        "move_sun_ms",
        "move_merged_vertices",
        "shade_ms",
        "raster_ms",
        "vertex_rel_l2_vs_exact",
        "pixel_rel_l2_vs_exact",
        "png",
        "reference_exact_png",
    ] {
        let [a, b, c] = [&a, &b, &c].map(|o| o.get(key).cloned().unwrap_or_else(|| "-".into()));
        report.push_str(&format!("| {key} | {a} | {b} | {c} |\n"));
    }
    let path = std::path::Path::new("target/demo/report.md");
    std::fs::write(path, &report).with_context(|| format!("writing {}", path.display()))?;
    println!("\n{report}\nreport={}", path.display());
    Ok(())
}
