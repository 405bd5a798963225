//! Whether a job's estimated peak memory and output fit this machine: refused with what it
//! needs and what there is (unless `--force`), before anything long starts.

use anyhow::{Result, bail};
use std::path::Path;
use vcut_scene::budget::{available_memory, human, resident_memory};

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
    if let Some(free) = vcut_container::available_space(path) {
        if bytes > free {
            short.push(format!("about {} of disk for {}, {} free there", human(bytes), path.display(), human(free)));
        }
    }
    if short.is_empty() {
        return Ok(());
    }
    let what = short.join("; and ");
    if force {
        println!("warning: {job} needs {what}; going on (--force)");
        return Ok(());
    }
    bail!("{job} needs {what}: refused (--force runs it anyway; --dry-run shows the whole estimate)")
}
