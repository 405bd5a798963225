//! The vcuts command line as library functions: every user command (`inspect`, `directions`,
//! `precompute`, `farm`, `render`, `reference`, `leaves`, `view`) is a module of [`cmd`] with its
//! clap arguments and a `run` that returns a typed outcome, so the `vcuts` binary and the
//! developer tasks of `cargo xtask` (`demo`, `bench`) call the same code; beside them what the
//! commands share: opening a `.vcuts` file for a frame ([`open`]), the values they parse
//! ([`values`]), the one printer of outcomes ([`outcome`]: `key=value` lines or `--json`), a
//! frame's report keys ([`frame_report`]), progress ([`progress`]), estimates ([`resources`]) and
//! atomic writes ([`files`]). Progress, warnings and diagnostics go through [`log`] on stderr
//! (`-q` keeps only warnings and errors, `-v` adds debug lines); progress bars on a terminal,
//! periodic log lines otherwise.
//!
//! The viewer (`view`) is the default feature `viewer`; `--no-default-features` builds the
//! headless rest without the GPU and window stack.

pub mod cmd;
pub mod files;
pub mod frame_report;
pub mod open;
pub mod options;
pub mod outcome;
pub mod progress;
pub mod resources;
pub mod values;

pub use cmd::precompute::shard;
#[cfg(feature = "viewer")]
pub use cmd::view;
pub use cmd::{Command, directions, farm, inspect, leaves, precompute, render, run, ssdo};

use anyhow::{Context, Result};

/// Precomputed visibility-cut rendering: photo-real lighting of dynamic scenes under
/// environment light, objects moved and materials edited live.
#[derive(clap::Parser)]
#[command(name = "vcuts", version, arg_required_else_help = true)]
pub struct Cli {
    /// Options every command takes.
    #[command(flatten)]
    pub global: GlobalArgs,
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

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
    #[arg(long, global = true, value_name = "N", value_parser = options::whole::<usize>("threads"), allow_hyphen_values = true)]
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
            rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("--threads")?;
        }
        Ok(())
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
