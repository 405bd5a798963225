//! `cargo xtask`: the developer's entry point. The user commands (`inspect`, `directions`,
//! `precompute`, `render`, `reference`, `view`, `leaves`) are the `vcuts` crate's, with the same
//! options as the `vcuts` binary; `demo` and `bench` are developer tasks built on the same
//! library functions. Run with no arguments for help.

use anyhow::Result;
use clap::{Parser, Subcommand};
use xtask::{bench, demo, publish};

/// Precomputed visibility-cut rendering: pipeline tasks.
#[derive(Parser)]
#[command(name = "cargo xtask", version, arg_required_else_help = true)]
struct Cli {
    #[command(flatten)]
    global: vcuts::GlobalArgs,
    #[command(subcommand)]
    command: Command,
}

// Parsed once per process: the size of the largest variant costs nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    #[command(flatten)]
    User(vcuts::Command),
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
    /// Write the generated docs: a bench report's Table 1 into README.md and docs/benchmarks.md
    /// (between their markers, kept in docs/report/) and each library crate's README.md from its
    /// crate documentation; --check only verifies they are current.
    Publish(publish::PublishArgs),
}

fn main() {
    vcuts::quiet_on_broken_pipe();
    let cli = Cli::parse();
    let result: Result<()> = cli.global.init().and_then(|()| match cli.command {
        Command::User(command) => vcuts::run(command),
        Command::Bench(args) => bench::run(&args),
        Command::Demo => demo::demo(),
        Command::Publish(args) => publish::run(&args),
    });
    vcuts::exit_on_error(result);
}
