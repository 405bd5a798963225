//! Whether a job's estimated peak memory and output fit this machine: refused with what it
//! needs and what there is (unless `--force`), before anything long starts; and whether an
//! image of the size asked for fits, before anything is allocated for it.

use anyhow::{Result, bail};
use std::path::Path;
use vcut_scene::budget::{available_memory, human, resident_memory};

/// How long an estimate's sample may run (`--estimate-seconds`): at most 10 minutes.
pub const ESTIMATE_SECONDS: vcut_scene::limits::Limit = vcut_scene::limits::Limit::within(0.0, 600.0, "s");

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
    #[arg(long = "estimate-seconds", default_value_t = 2.0, value_parser = crate::options::real64("estimate-seconds"), allow_hyphen_values = true)]
    pub seconds: f64,
}

impl Default for EstimateArgs {
    fn default() -> Self {
        EstimateArgs { dry_run: false, force: false, seconds: 2.0 }
    }
}

impl EstimateArgs {
    /// How long the estimate's sample may run ([`ESTIMATE_SECONDS`]; a value set in code out
    /// of range is held to it).
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

/// Peak bytes a pixel of each command's image takes at most, every output on (the buffers, the
/// references and passes compared or written with it, the PNG/EXR encoders' copies): an upper
/// bound of what `docs/benchmarks.md` ("Image memory") measured, rounded up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageCost {
    /// `render --mode cuts`: the image, its references and its EXR passes.
    Cuts = 192,
    /// `render --mode ssao|ssdo|ssdo-peeled`: the screen-space buffers (two depth layers) and
    /// the ray-traced comparison.
    ScreenSpace = 384,
    /// `leaves`: each part of the breakdown and the references.
    Leaves = 160,
    /// `view --screenshot`: the GPU's targets (in memory on a CPU adapter) and the read-back.
    Screenshot = 32,
}

/// Refuses an image of `width × height` that would take more memory than is available (the
/// memory this process holds now aside), naming `--width` and `--height` and the figures,
/// before anything is allocated for it.
pub fn check_image(width: u32, height: u32, cost: ImageCost) -> Result<()> {
    let Some(free) = available_memory() else { return Ok(()) };
    image_fits(width, height, cost, free)
}

/// [`check_image`] against `free` bytes.
pub fn image_fits(width: u32, height: u32, cost: ImageCost, free: u64) -> Result<()> {
    let need = u64::from(width) * u64::from(height) * cost as u64;
    if need > free {
        bail!(
            "--width {width} --height {height}: an image this size needs about {} of memory ({} bytes a pixel), \
             {} available",
            human(need),
            cost as u64,
            human(free)
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_image_larger_than_memory_is_refused_with_its_figures() {
        let e = image_fits(16_384, 16_384, ImageCost::Cuts, 24 << 30).unwrap_err().to_string();
        assert!(e.starts_with("--width 16384 --height 16384: an image this size needs about 5"), "{e}");
        assert!(e.contains("192 bytes a pixel") && e.contains("available"), "{e}");
        image_fits(1920, 1080, ImageCost::ScreenSpace, 1 << 30).unwrap();
        assert!(image_fits(1920, 1080, ImageCost::ScreenSpace, 1 << 20).is_err());
    }
}
