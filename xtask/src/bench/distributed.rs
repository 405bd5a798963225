//! The bench's `distributed` section: each scene precomputed whole and as N shards — every run
//! its own process (this program's `precompute`, as a farm task runs it), timed by wall clock and
//! by the CPU seconds the process used — then gathered by a process of its own (its time and peak
//! memory) and compared byte for byte; and the `paper` preset projected for many-object scenes
//! over M nodes from rates an estimate measured (`crate::measure::distributed`).

use crate::measure::distributed::{DistributedSection, ShardedRun, measure_rates, projections, table};
use crate::measure::machine::children_cpu_seconds;
use crate::report::write_atomic;
use anyhow::{Context, Result, bail};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use vcut_data::shard::shard_path;

/// One process of this program: its key=value lines, wall and CPU seconds.
fn process(args: &[String]) -> Result<(BTreeMap<String, String>, f64, f64)> {
    let exe = std::env::current_exe().context("this program's path")?;
    let cpu0 = children_cpu_seconds().unwrap_or(0.0);
    let t = Instant::now();
    let out = Command::new(&exe).arg("-q").args(args).output().with_context(|| format!("running {}", exe.display()))?;
    let wall = t.elapsed().as_secs_f64();
    let cpu = children_cpu_seconds().unwrap_or(0.0) - cpu0;
    if !out.status.success() {
        bail!("{} {}: {}", exe.display(), args.join(" "), String::from_utf8_lossy(&out.stderr).trim());
    }
    let keys = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_once('=').map(|(k, v)| (k.to_string(), v.to_string())))
        .collect();
    Ok((keys, wall, cpu))
}

fn number(keys: &BTreeMap<String, String>, key: &str) -> Result<f64> {
    keys.get(key).and_then(|v| v.parse().ok()).with_context(|| format!("no {key}= line in the output"))
}

/// One scene whole and in `shards` shards.
fn sharded_run(scene: &str, preset: &str, shards: u32, dir: &Path) -> Result<ShardedRun> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let stem: String = scene.chars().map(|c| if c.is_alphanumeric() { c } else { '-' }).collect();
    let one = dir.join(format!("{stem}-{preset}.vcuts"));
    let sharded = dir.join(format!("{stem}-{preset}-gathered.vcuts"));
    let base = |output: &Path| -> Vec<String> {
        ["precompute", "--scene", scene, "--preset", preset, "--fresh", "-o"]
            .iter()
            .map(|s| s.to_string())
            .chain([output.display().to_string()])
            .collect()
    };
    println!("== distributed: {scene} at {preset}, whole");
    let (keys, one_run_s, one_run_cpu_s) = process(&base(&one))?;
    let estimate_vs_actual_s = number(&keys, "estimate_vs_actual_s")?;
    let compute = |k: &BTreeMap<String, String>| -> Result<f64> { Ok(number(k, "svc_s")? + number(k, "fields_s")?) };
    let (mut shard_s, mut shard_cpu_s, mut shard_compute_s) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..shards {
        println!("== distributed: {scene} at {preset}, shard {i} of {shards}");
        let mut a = base(&sharded);
        a.extend(["--shard".into(), format!("{i}/{shards}")]);
        let (keys, wall, cpu) = process(&a)?;
        shard_s.push(wall);
        shard_cpu_s.push(cpu);
        shard_compute_s.push(compute(&keys)?);
    }
    let files: Vec<PathBuf> = (0..shards).map(|i| shard_path(&sharded, i, shards)).collect();
    let mut a: Vec<String> = vec!["precompute".into(), "--gather".into()];
    a.extend(files.iter().map(|f| f.display().to_string()));
    a.extend(["-o".into(), sharded.display().to_string()]);
    let (keys, _, _) = process(&a)?;
    let byte_identical = std::fs::read(&one)? == std::fs::read(&sharded)?;
    let plan = {
        let (keys, _, _) = process(&[
            "precompute".into(),
            "--scene".into(),
            scene.into(),
            "--preset".into(),
            preset.into(),
            "--plan".into(),
            shards.to_string(),
        ])?;
        (number(&keys, "plan_balance")?, number(&keys, "plan_sections")? as usize)
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    let run = ShardedRun {
        scene: scene.into(),
        preset: preset.into(),
        shards,
        sections: plan.1,
        plan_balance: plan.0,
        measured_balance: max(&shard_compute_s) / mean(&shard_compute_s).max(1e-9),
        one_run_s,
        one_run_cpu_s,
        cpu_overhead: shard_cpu_s.iter().sum::<f64>() / one_run_cpu_s.max(1e-9),
        makespan_vs_one_run: max(&shard_s) / one_run_s.max(1e-9),
        shard_s,
        shard_cpu_s,
        shard_compute_s,
        gather_s: number(&keys, "gather_s")?,
        gather_peak_bytes: (number(&keys, "gather_peak_rss_mb").unwrap_or(0.0) * 1e6) as u64,
        file_bytes: (number(&keys, "gather_mb")? * 1e6) as u64,
        byte_identical,
        estimate_vs_actual_s,
    };
    println!(
        "{scene} {preset}: {shards} shards, plan balance {:.3}, measured {:.3}; CPU Σ shards / one run {:.3}; \
         longest shard / one run {:.3}; gather {:.3} s, peak {:.1} MB; identical {}",
        run.plan_balance,
        run.measured_balance,
        run.cpu_overhead,
        run.makespan_vs_one_run,
        run.gather_s,
        run.gather_peak_bytes as f64 / 1e6,
        run.byte_identical
    );
    for f in files.iter().chain([&one, &sharded]) {
        let _ = std::fs::remove_file(f);
    }
    Ok(run)
}

/// Runs the section: (scene, preset, shards) runs, then the projection.
pub fn run(quick: bool, data_dir: &Path, out: &Path) -> Result<DistributedSection> {
    let runs: &[(&str, &str, u32)] = if quick {
        &[("builtin:teapot", "fast", 4)]
    } else {
        &[("builtin:teapot", "fast", 4), ("builtin:showroom:32", "fast", 8), ("builtin:showroom:32", "balanced", 4)]
    };
    let mut measured = Vec::new();
    for &(scene, preset, shards) in runs {
        measured.push(sharded_run(scene, preset, shards, &data_dir.join("distributed"))?);
    }
    let startup: Vec<f64> =
        measured.iter().flat_map(|r| r.shard_s.iter().zip(&r.shard_compute_s).map(|(w, c)| w - c)).collect();
    let shard_startup_s = startup.iter().sum::<f64>() / startup.len().max(1) as f64;
    let (basis_scene, sample_s) = ("builtin:showroom:8", if quick { 3.0 } else { 20.0 });
    println!("== distributed: rates at paper from the estimate of {basis_scene} ({sample_s} s sample)");
    let rates = measure_rates(basis_scene, "paper", sample_s)?;
    let objects: &[usize] = if quick { &[8, 64] } else { &[8, 32, 64, 128, 256] };
    let projections = projections(objects, &[1, 4, 16, 64], "paper", rates, shard_startup_s)?;
    let section = DistributedSection {
        runs: measured,
        projection_preset: "paper".into(),
        projection_basis: format!("rates from a {sample_s} s estimate sample of {basis_scene}"),
        rates,
        shard_startup_s,
        projections,
    };
    let md = table(&section);
    println!("\n{md}");
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    write_atomic(&out.join("distributed.md"), md.as_bytes())?;
    Ok(section)
}
