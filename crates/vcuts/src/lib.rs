//! The vcuts command line as library functions: every user command (`inspect`, `directions`,
//! `precompute`, `render`, `reference`, `leaves`, `view`) is a module with its clap arguments
//! and a `run`, so the `vcuts` binary and the developer tasks of `cargo xtask` (`demo`, `bench`)
//! call the same code. Output: key=value lines and tables on stdout; progress, warnings and
//! diagnostics through [`log`] on stderr (`-q` keeps only warnings and errors, `-v` adds
//! debug lines); progress bars on a terminal, periodic log lines otherwise.
//!
//! The viewer (`view`) is the default feature `viewer`; `--no-default-features` builds the
//! headless rest without the GPU and window stack.

pub mod accuracy;
pub mod csv;
pub mod directions;
pub mod distributed;
pub mod farm;
pub mod frame_report;
pub mod inspect;
pub mod leaves;
pub mod machine;
pub mod open;
pub mod outcome;
#[cfg(feature = "plots")]
pub mod plots;
pub mod precompute;
pub mod progress;
pub mod render;
pub mod report;
pub mod resources;
pub mod scaling;
pub mod shard;
pub mod ssdo;
pub mod table1;
pub mod values;
#[cfg(feature = "viewer")]
pub mod view;

use anyhow::{Context, Result};
use clap::Subcommand;

/// Options every command takes (before or after the command's name).
#[derive(clap::Args, Clone, Debug, Default)]
pub struct GlobalArgs {
    /// More output: debug lines (repeat for trace).
    #[arg(short, long, global = true, action = clap::ArgAction::Count, conflicts_with = "quiet")]
    pub verbose: u8,
    /// Less output: only warnings and errors on stderr (no progress); results on stdout stay.
    #[arg(short, long, global = true)]
    pub quiet: bool,
    /// Worker threads for everything that computes (default: every core).
    #[arg(long, global = true, value_name = "N")]
    pub threads: Option<usize>,
    /// Results on stdout as one JSON object (the same keys as the `key=value` lines).
    #[arg(long, global = true)]
    pub json: bool,
}

impl GlobalArgs {
    /// The log level these options ask for.
    pub fn level(&self) -> log::LevelFilter {
        match (self.quiet, self.verbose) {
            (true, _) => log::LevelFilter::Warn,
            (false, 0) => log::LevelFilter::Info,
            (false, 1) => log::LevelFilter::Debug,
            (false, _) => log::LevelFilter::Trace,
        }
    }

    /// Sets up logging (stderr; info lines bare, others with their level) and the worker pool.
    /// Call once, first.
    pub fn init(&self) -> Result<()> {
        use std::io::Write;
        // A second init (tests, or a host that logs already) keeps the first logger.
        let _ = env_logger::Builder::new()
            .filter_level(self.level())
            .format(|buf, record| match record.level() {
                log::Level::Info => writeln!(buf, "{}", record.args()),
                level => writeln!(buf, "{}: {}", level.as_str().to_lowercase(), record.args()),
            })
            .try_init();
        outcome::set_json(self.json);
        if let Some(n) = self.threads {
            anyhow::ensure!(n >= 1, "--threads {n}: at least 1");
            rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("--threads")?;
        }
        Ok(())
    }
}

/// The user commands.
#[derive(Subcommand)]
pub enum Command {
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
    /// A sharded precompute as a batch engine's jobs: `farm slurm` writes (and with --submit
    /// submits) an sbatch array of `precompute --shard` tasks and a gather job after it;
    /// `--resubmit` reruns only the shards that did not finish. `farm kubernetes` writes an
    /// Indexed Job manifest.
    Farm(farm::FarmArgs),
    /// Render a frame from a .vcuts file: move objects (--move NAME=dx,dy,dz), edit BRDFs
    /// (--brdf NAME=blinn-phong:alpha=70), write PNG/EXR/PLY, print merge and shade times, and
    /// with --compare exact the error against the exact-direction reference.
    Render(render::RenderArgs),
    /// The references for a frame (same options as render): the exact-direction reference and
    /// the Monte Carlo one, each with its image and the frame's error against it (per vertex and
    /// per pixel: relative L2 and largest error), and the two references against each other.
    Reference(render::RenderArgs),
    /// Open the interactive viewer on a .vcuts file (or `--scene S` precomputed first, cached):
    /// drag objects, edit BRDFs, rotate the environment, compare with the exact reference; with
    /// --screenshot out.png render the same frame with no window on any wgpu adapter.
    #[cfg(feature = "viewer")]
    View(Box<view::ViewArgs>),
    /// Plant leaves (Wang et al. 2005): build the procedural plant (or load one), precompute the
    /// sun's light-visibility convolution (RLE) and the SH transfer, shade a frame in two passes,
    /// and compare it and the SH-only rendering with the path-traced reference: images and
    /// key=value figures. Leaf parameters, the sun direction or the time of day are settable.
    Leaves(leaves::LeavesArgs),
}

/// Runs one user command.
pub fn run(command: Command) -> Result<()> {
    match command {
        Command::Inspect(args) => inspect::run(&args),
        Command::Directions(args) => directions::run(&args),
        Command::Precompute(args) => precompute::run(&args).map(|_| ()),
        Command::Farm(args) => farm::run(&args),
        Command::Render(args) => render::run(&args).map(|o| outcome::print(&o)),
        Command::Reference(mut args) => {
            args.compare.get_or_insert(render::Compare::Both);
            render::run(&args).map(|o| outcome::print(&o))
        }
        #[cfg(feature = "viewer")]
        Command::View(args) => view::run(&args),
        Command::Leaves(args) => leaves::run(&args),
    }
}

/// Prints, as warnings, what the scene's files hold that is not read (each naming its file).
pub fn warn_ignored(scene: &vcut_scene::Scene) {
    for w in &scene.warnings {
        log::warn!("{w}");
    }
}

/// `vcuts … | head` closes stdout early, and `println!` then panics ("failed printing to
/// stdout: Broken pipe"). Exit quietly instead, as command-line tools do on SIGPIPE (status 141,
/// 128 + SIGPIPE); any other panic is reported as before.
pub fn quiet_on_broken_pipe() {
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

/// The end of a command line program: an error is printed (with its causes) and the process
/// exits with status 1.
pub fn exit_on_error(result: Result<()>) {
    if let Err(e) = result {
        log::error!("{e:#}");
        // Before the logger is up (a bad --threads), say it anyway.
        if !log::log_enabled!(log::Level::Error) {
            eprintln!("error: {e:#}");
        }
        std::process::exit(1);
    }
}
