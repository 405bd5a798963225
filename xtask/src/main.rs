//! `cargo xtask`: the one orchestrating binary. It wires the library crates together; the logic
//! lives in the crates. Run with no arguments for help.

mod bench;
mod directions;
mod inspect;
mod leaves;
mod precompute;
mod render;
mod resources;
mod ssdo;
mod tradeoff;
mod view;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

/// Precomputed visibility-cut rendering: pipeline tasks.
#[derive(Parser)]
#[command(name = "cargo xtask", version, arg_required_else_help = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print what a scene, mesh or environment map holds: objects, vertex and triangle counts,
    /// bounds and bounding spheres; for maps the total power, the brightest texel and the share
    /// of energy in the brightest 0.1 % of texels.
    Inspect(inspect::InspectArgs),
    /// Generate (or load from the cache) N directions by point repulsion and print their
    /// uniformity as key=value lines; with --env, also build the direction tree and light tree.
    Directions(directions::DirectionsArgs),
    /// Precompute a scene's self-visibility cuts and visibility cut fields into a .vcuts file
    /// (resumes an interrupted run; prints time per stage, rays/s against the raw figure, and
    /// data size in the height codec and the index baseline).
    Precompute(precompute::PrecomputeArgs),
    /// Render a frame from a .vcuts file: move objects (--move NAME=dx,dy,dz), edit BRDFs
    /// (--brdf NAME=blinn-phong:alpha=70), write PNG/EXR/PLY, print merge and shade times, and
    /// with --compare exact the error against the exact-direction reference.
    Render(render::RenderArgs),
    /// The references for a frame (same options as render): the exact-direction reference and
    /// the Monte Carlo one, each with its image and the frame's error against it (per vertex and
    /// per pixel: relative L2 and largest error), and the two references against each other.
    Reference(render::RenderArgs),
    /// Measure the paper's Table 1 on this machine: per scene precompute time and rays/s, data
    /// size (ours and the index baseline), BRDF-edit and object-move times with the counter merge
    /// and the index baseline, errors against the references; the machine, the directions and
    /// the light-tree rebuild — into target/report/ (report.json, table1.md, table1.csv).
    Bench(bench::BenchArgs),
    /// Run the main job on the built-in teapot scene under the built-in sky: inspect both, build
    /// the 32,768 directions (cached), the direction tree and the sky's light tree, precompute
    /// the scene at the `fast` preset into target/vcuts/teapot-fast.vcuts (reused while it
    /// matches), render it at rest and with the teapot moved and its BRDF edited, against the
    /// exact-direction reference, and write target/demo/report.md.
    Demo,
    /// Open the interactive viewer on a .vcuts file (or `--scene S` precomputed first, cached):
    /// drag objects, edit BRDFs, rotate the environment, compare with the exact reference; with
    /// --screenshot out.png render the same frame with no window on any wgpu adapter.
    View(view::ViewArgs),
    /// Plant leaves (Wang et al. 2005): build the procedural plant (or load one), precompute the
    /// sun's light-visibility convolution (RLE) and the SH transfer, shade a frame in two passes,
    /// and compare it and the SH-only rendering with the path-traced reference: images and
    /// key=value figures. Leaf parameters, the sun direction or the time of day are settable.
    Leaves(leaves::LeavesArgs),
}

/// `cargo xtask … | head` closes stdout early, and `println!` then panics ("failed printing to
/// stdout: Broken pipe"). Exit quietly instead, as command-line tools do on SIGPIPE (status 141,
/// 128 + SIGPIPE); any other panic is reported as before.
fn quiet_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.starts_with("failed printing to std") && message.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}

fn main() {
    quiet_on_broken_pipe();
    let cli = Cli::parse();
    let result: Result<()> = match cli.command {
        Command::Inspect(args) => inspect::run(&args),
        Command::Directions(args) => directions::run(&args),
        Command::Precompute(args) => precompute::run(&args).map(|_| ()),
        Command::Render(args) => render::run(&args).map(|_| ()),
        Command::Reference(mut args) => {
            args.compare.get_or_insert_with(|| "both".into());
            render::run(&args).map(|_| ())
        }
        Command::Bench(args) => bench::run(&args),
        Command::Demo => demo(),
        Command::View(args) => view::run(&args),
        Command::Leaves(args) => leaves::run(&args),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn demo() -> Result<()> {
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
    args.compare = Some("exact".into());
    let edited = render::run(&args)?;
    println!("\n== the same, the sun through the cuts too, as the paper (--no-sun-rays)");
    args.output = "target/demo/teapot-cuts-only.png".into();
    args.no_sun_rays = true;
    let cuts_only = render::run(&args)?;
    let get =
        |p: &render::Printed, k: &str| p.0.iter().find(|(key, _)| key == k).map_or("-".into(), |(_, v)| v.clone());
    let mut report = String::from(
        "# Demo: the built-in teapot scene under the built-in sky (preset fast)\n\n| | at rest | moved + BRDF edit | the same, sun through the cuts |\n|---|---:|---:|---:|\n",
    );
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
        report.push_str(&format!(
            "| {key} | {} | {} | {} |\n",
            get(&rest, key),
            get(&edited, key),
            get(&cuts_only, key)
        ));
    }
    let path = std::path::Path::new("target/demo/report.md");
    std::fs::write(path, &report).with_context(|| format!("writing {}", path.display()))?;
    println!("\n{report}\nreport={}", path.display());
    Ok(())
}
