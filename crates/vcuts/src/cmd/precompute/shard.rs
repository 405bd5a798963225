//! `precompute --plan N`, `--shard I/N` and `--gather`: one precompute split over the machines
//! of a farm. The plan's table, the shard index (given, or from the batch engine's array index),
//! and the gather of the shard files into the one-machine file.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::time::Instant;
use vcut_data::shard::gather;

/// The array-index variables of the batch engines `--shard env/N` reads, in the order tried:
/// Slurm job arrays, Kubernetes Indexed Jobs, AWS Batch array jobs (all 0-based).
pub const INDEX_VARIABLES: [&str; 3] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX", "AWS_BATCH_JOB_ARRAY_INDEX"];

/// Parses `--shard I/N` (0 ≤ I < N) or `--shard env/N` (I from the first of
/// [`INDEX_VARIABLES`] that is set, looked up through `var`).
pub fn parse_spec(spec: &str, var: impl Fn(&str) -> Option<String>) -> Result<(u32, u32)> {
    let Some((i, n)) = spec.split_once('/') else { bail!("--shard {spec}: expected I/N or env/N") };
    let n: u32 = n.trim().parse().with_context(|| format!("--shard {spec}: the shard count {n:?} is not a number"))?;
    if n == 0 {
        bail!("--shard {spec}: the shard count must be at least 1");
    }
    let (i, from) = if i.trim() == "env" {
        let Some((name, value)) = INDEX_VARIABLES.iter().find_map(|v| var(v).map(|x| (*v, x))) else {
            bail!("--shard {spec}: none of {} is set (run it as a task of an array job)", INDEX_VARIABLES.join(", "))
        };
        (value, format!(" ({name})"))
    } else {
        (i.to_string(), String::new())
    };
    let index: u32 =
        i.trim().parse().with_context(|| format!("--shard {spec}: the shard index{from} {i:?} is not a number"))?;
    if index >= n {
        bail!("--shard {spec}: the shard index{from} {index} is not below {n} (indices are 0-based)");
    }
    Ok((index, n))
}

/// The output of a gather with no `-o`: the first shard file's name without its
/// `.shard-I-of-N` part.
pub fn gathered_name(first: &Path) -> Option<PathBuf> {
    let name = first.file_name()?.to_str()?;
    let at = name.find(".shard-")?;
    Some(first.with_file_name(format!("{}.vcuts", &name[..at])))
}

/// `precompute --gather FILES... [-o out]`.
pub fn run_gather(files: &[PathBuf], output: Option<&Path>) -> Result<super::GatherOutcome> {
    let output = match output {
        Some(o) => o.to_path_buf(),
        None => files.first().and_then(|f| gathered_name(f)).context(
            "--gather: no -o given and the first file is not named like a shard file (x.shard-I-of-N.vcuts)",
        )?,
    };
    let t = Instant::now();
    let g = gather(files, &output)?;
    let seconds = t.elapsed().as_secs_f64();
    log::info!("gathered {} shards into {}", g.shards, output.display());
    Ok(super::GatherOutcome {
        output,
        gather_shards: g.shards,
        gather_sections: g.sections,
        gather_mb: g.bytes as f64 / 1e6,
        gather_s: seconds,
        gather_peak_rss_mb: vcut_scene::budget::peak_memory().map(|p| p as f64 / 1e6),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_specs_parse_from_the_line_and_from_each_engine() {
        let none = |_: &str| None;
        assert_eq!(parse_spec("2/4", none).unwrap(), (2, 4));
        for v in INDEX_VARIABLES {
            let only = |name: &str| (name == v).then(|| "3".to_string());
            assert_eq!(parse_spec("env/4", only).unwrap(), (3, 4), "{v}");
        }
        let e = |spec: &str| parse_spec(spec, |n: &str| (n == "SLURM_ARRAY_TASK_ID").then(|| "7".into())).unwrap_err();
        assert!(e("env/4").to_string().contains("SLURM_ARRAY_TASK_ID) 7 is not below 4"), "{}", e("env/4"));
        assert!(e("4/4").to_string().contains("0-based"));
        assert!(e("1/0").to_string().contains("at least 1"));
        assert!(e("x/2").to_string().contains("not a number"));
        assert!(e("3").to_string().contains("expected I/N"));
        assert!(parse_spec("env/2", none).unwrap_err().to_string().contains("JOB_COMPLETION_INDEX"));
    }

    #[test]
    fn the_gathered_name_drops_the_shard_part() {
        assert_eq!(gathered_name(Path::new("o/t.shard-1-of-4.vcuts")), Some(PathBuf::from("o/t.vcuts")));
        assert_eq!(gathered_name(Path::new("o/t.vcuts")), None);
    }
}
