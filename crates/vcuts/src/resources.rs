//! Whether a job's estimated peak memory and output fit this machine: refused with what it
//! needs and what there is (unless `--force`), before anything long starts.

use anyhow::{Result, bail};
use std::path::Path;
use vcut_scene::budget::{available_memory, human, resident_memory};

/// The estimate's options, shared by every command that computes for long (`precompute`,
/// `leaves`, `view --leaves`).
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct EstimateArgs {
    /// Print the estimate (what will be computed, rays, time, output bytes, peak memory) and
    /// stop.
    #[arg(long)]
    pub dry_run: bool,
    /// Run even when the estimate exceeds the free memory or disk.
    #[arg(long)]
    pub force: bool,
    /// Seconds of the run's own work to time for the estimate (a shard of N times a share
    /// of it: the N shards together sample as long as one run).
    #[arg(long = "estimate-seconds", default_value_t = 2.0)]
    pub seconds: f64,
}

impl Default for EstimateArgs {
    fn default() -> Self {
        EstimateArgs { dry_run: false, force: false, seconds: 2.0 }
    }
}

impl EstimateArgs {
    /// How long the estimate's sample may run (at most 10 minutes).
    pub fn budget(&self) -> std::time::Duration {
        std::time::Duration::from_secs_f64(self.seconds.clamp(0.0, 600.0))
    }
}

/// Fails when `peak` bytes of memory (this process's whole peak, what it holds now included) or
/// `output.1` bytes written at `output.0` exceed what is free — unless `force`, which says so
/// and goes on.
pub fn check(job: &str, peak: u64, (path, bytes): (&Path, u64), force: bool) -> Result<()> {
    let mut short = Vec::new();
    if let Some(free) = available_memory() {
        let more = peak.saturating_sub(resident_memory().unwrap_or(0));
        if more > free {
            short.push(format!("about {} more memory, {} available", human(more), human(free)));
        }
    }
    if let Some(free) = vcut_container::available_space(path)
        && bytes > free
    {
        short.push(format!("about {} of disk for {}, {} free there", human(bytes), path.display(), human(free)));
    }
    if short.is_empty() {
        return Ok(());
    }
    let what = short.join("; and ");
    if force {
        log::warn!("{job} needs {what}; going on (--force)");
        return Ok(());
    }
    bail!("{job} needs {what}: refused (--force runs it anyway; --dry-run shows the whole estimate)")
}
