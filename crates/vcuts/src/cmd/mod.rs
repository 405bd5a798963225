//! The user commands, one module each: its clap arguments and its `run`.

pub mod directions;
pub mod farm;
pub mod inspect;
pub mod leaves;
pub mod precompute;
pub mod render;
pub mod ssdo;
#[cfg(feature = "viewer")]
pub mod view;
pub mod view_args;

use anyhow::Result;
use clap::Subcommand;

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
    View(Box<view_args::ViewArgs>),
    /// Plant leaves (Wang et al. 2005): build the procedural plant (or load one), precompute the
    /// sun's light-visibility convolution (RLE) and the SH transfer, shade a frame in two passes,
    /// and compare it and the SH-only rendering with the path-traced reference: images and
    /// key=value figures. Leaf parameters, the sun direction or the time of day are settable.
    Leaves(leaves::LeavesArgs),
}

/// Runs one user command.
pub fn run(command: Command) -> Result<()> {
    match command {
        Command::Inspect(args) => inspect::run(&args).map(|o| crate::outcome::print(&o)),
        Command::Directions(args) => directions::run(&args).map(|o| crate::outcome::print(&o)),
        Command::Precompute(args) => precompute::run(&args).map(|o| crate::outcome::print(&o)),
        Command::Farm(args) => farm::run(&args).map(|o| crate::outcome::print(&o)),
        Command::Render(args) => render::run(&args).map(|o| crate::outcome::print(&o)),
        Command::Reference(mut args) => {
            args.compare.get_or_insert(render::Compare::Both);
            render::run(&args).map(|o| crate::outcome::print(&o))
        }
        #[cfg(feature = "viewer")]
        Command::View(args) => view::run(&args).map(|o| crate::outcome::print(&o)),
        #[cfg(not(feature = "viewer"))]
        Command::View(_) => {
            anyhow::bail!("view: this vcuts was built without the viewer (the feature `viewer`, on by default)")
        }
        Command::Leaves(args) => leaves::run(&args).map(|o| crate::outcome::print(&o)),
    }
}
