//! `farm slurm` and `farm kubernetes`: a sharded precompute as the batch engine's own jobs.
//!
//! **Slurm**: an array job (`shards.sbatch`, one task per shard, `%M` of them at once, a log per
//! task) whose tasks run `precompute --shard env/N`, and a gather job (`gather.sbatch`) that
//! depends on it with `afterany` — `afterok` would wait forever once one task failed, even after
//! a requeue — and gathers whatever shard files are there: complete, it writes the output;
//! incomplete, its log names the shards to run again, and `--resubmit` submits only those (and a
//! new gather). Shard tasks resume their partial files, so a rerun loses nothing.
//!
//! **Kubernetes**: an Indexed Job manifest (`JOB_COMPLETION_INDEX` is the shard) and a gather
//! Job, for a cluster with a shared volume; written, not run here.

use crate::files::write_atomic;
use crate::precompute::{PrecomputeArgs, resolve};
use anyhow::{Context, Result, bail};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};
use vcut_data::shard::{missing_shards, shard_path};

/// Arguments of `farm`.
#[derive(clap::Args, Clone)]
pub struct FarmArgs {
    /// The batch engine.
    #[command(subcommand)]
    pub engine: Engine,
}

/// A batch engine `farm` writes jobs for.
#[derive(clap::Subcommand, Clone)]
pub enum Engine {
    /// Slurm: an sbatch array script and a gather job depending on it (afterany).
    Slurm(EngineArgs),
    /// Kubernetes: an Indexed Job manifest and a gather Job (written, not submitted).
    Kubernetes(EngineArgs),
}

/// What both engines take: the precompute's options, the shards, where the scripts go.
#[derive(clap::Args, Clone)]
pub struct EngineArgs {
    /// Shards (array tasks).
    #[arg(long, value_parser = crate::options::whole::<u32>("shards"), allow_hyphen_values = true)]
    pub shards: u32,
    /// At most this many tasks at once (default: all).
    #[arg(long, value_parser = crate::options::whole::<u32>("max-running"), allow_hyphen_values = true)]
    pub max_running: Option<u32>,
    /// Folder of the scripts and logs (default: target/farm/<output stem>).
    #[arg(long)]
    pub dir: Option<PathBuf>,
    /// CPUs per task (Slurm `--cpus-per-task`; the task's `--threads`).
    #[arg(long, value_parser = crate::options::whole::<u32>("cpus-per-task"), allow_hyphen_values = true)]
    pub cpus_per_task: Option<u32>,
    /// An extra `#SBATCH` option for both jobs, e.g. `--partition=cpu` (repeatable).
    #[arg(long = "sbatch", value_name = "OPTION")]
    pub sbatch: Vec<String>,
    /// Submit the jobs (Slurm: `sbatch`); otherwise only write them.
    #[arg(long)]
    pub submit: bool,
    /// Submit only the shards whose files are missing or unfinished, and a new gather.
    #[arg(long, conflicts_with = "submit")]
    pub resubmit: bool,
    /// After submitting, wait for the gather job and report its outcome (fails when the gather
    /// did not complete, naming the shards to resubmit).
    #[arg(long)]
    pub wait: bool,
    /// Container image for Kubernetes (holding the `vcuts` binary on its PATH).
    #[arg(long, default_value = "vcuts:latest")]
    pub image: String,
    /// The precompute to run.
    #[command(flatten)]
    pub precompute: PrecomputeArgs,
}

/// Runs `farm`.
pub fn run(args: &FarmArgs) -> Result<FarmOutcome> {
    match &args.engine {
        Engine::Slurm(a) => slurm(a),
        Engine::Kubernetes(a) => kubernetes(a),
    }
}

/// What `farm` wrote and submitted.
#[derive(Debug, Clone, Default, Serialize)]
pub struct FarmOutcome {
    /// The Slurm array job's script.
    pub slurm_shards_script: Option<PathBuf>,
    /// The Slurm gather job's script.
    pub slurm_gather_script: Option<PathBuf>,
    /// The Slurm jobs' log folder.
    pub slurm_logs: Option<PathBuf>,
    /// The shards submitted (`none`), with `--submit` or `--resubmit`.
    pub slurm_submitted_shards: Option<String>,
    /// The array job's id (`none` when no shard was left to run).
    pub slurm_array_job: Option<String>,
    /// The gather job's id.
    pub slurm_gather_job: Option<String>,
    /// Seconds `--wait` waited.
    pub slurm_wait_s: Option<f64>,
    /// The Kubernetes Indexed Job's manifest.
    pub kubernetes_job: Option<PathBuf>,
    /// The Kubernetes gather Job's manifest.
    pub kubernetes_gather: Option<PathBuf>,
}

/// A word for a POSIX shell, single-quoted when it needs to be.
pub fn quote(word: &str) -> String {
    let plain = !word.is_empty() && word.chars().all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c));
    if plain { word.into() } else { format!("'{}'", word.replace('\'', r"'\''")) }
}

/// The farm's paths and the task command line, resolved once.
struct Farm {
    shards: u32,
    output: PathBuf,
    dir: PathBuf,
    /// `precompute` and its options, without `--shard`.
    task: Vec<String>,
    exe: PathBuf,
    cwd: PathBuf,
}

impl Farm {
    fn new(a: &EngineArgs, exe: PathBuf) -> Result<Farm> {
        let p = &a.precompute;
        if p.plan.is_some() || p.shard.is_some() || !p.gather.is_empty() {
            bail!("farm: --plan, --shard and --gather are the farm's to set");
        }
        if a.shards == 0 {
            bail!("farm: --shards must be at least 1");
        }
        if a.max_running == Some(0) {
            bail!("farm: --max-running must be at least 1");
        }
        let r = resolve(p)?;
        let plan = vcut_precompute::plan::plan(&r.scene, &r.params, a.shards)?;
        log::info!(
            "plan: {} sections over {} shards, largest shard {:.3}× the mean (precompute --plan {} prints it)",
            plan.sections().len(),
            a.shards,
            plan.balance_ratio(),
            a.shards
        );
        let absolute = |x: &Path| std::path::absolute(x).with_context(|| x.display().to_string());
        let output = absolute(&r.output)?;
        let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        let dir = absolute(&a.dir.clone().unwrap_or_else(|| PathBuf::from("target/farm").join(&stem)))?;
        let mut task = vec!["precompute".to_string()];
        task.extend(p.task_args(&output, &absolute(&p.cache_dir)?));
        let cwd = std::env::current_dir().context("the current folder")?;
        Ok(Farm { shards: a.shards, output, dir, task, exe, cwd })
    }

    fn shard_files(&self) -> Vec<PathBuf> {
        (0..self.shards).map(|i| shard_path(&self.output, i, self.shards)).collect()
    }

    /// The shards still to run: those without a finished shard file of this run.
    fn missing(&self) -> Result<Vec<u32>> {
        let present: Vec<PathBuf> = self.shard_files().into_iter().filter(|f| f.exists()).collect();
        if present.is_empty() {
            return Ok((0..self.shards).collect());
        }
        let (n, missing) = missing_shards(&present)?;
        if n != self.shards {
            bail!("the shard files in {} are of a {n}-shard plan, not {}", self.dir.display(), self.shards);
        }
        Ok(missing)
    }

    fn command(&self, extra: &[String]) -> String {
        let mut words = vec![quote(&self.exe.display().to_string())];
        words.extend(self.task.iter().map(|w| quote(w)));
        words.extend(extra.iter().map(|w| quote(w)));
        words.join(" ")
    }

    fn gather_command(&self) -> String {
        let files: Vec<String> = self.shard_files().iter().map(|f| quote(&f.display().to_string())).collect();
        format!(
            "files=()\nfor f in {}; do [ -e \"$f\" ] && files+=(\"$f\"); done\n\
             [ ${{#files[@]}} -gt 0 ] || {{ echo \"no shard file finished: run every shard again\" >&2; exit 1; }}\n\
             {} precompute --gather \"${{files[@]}}\" --output {}\n",
            files.join(" "),
            quote(&self.exe.display().to_string()),
            quote(&self.output.display().to_string())
        )
    }
}

fn slurm(a: &EngineArgs) -> Result<FarmOutcome> {
    let farm = Farm::new(a, std::env::current_exe().context("this program's path")?)?;
    let logs = farm.dir.join("logs");
    std::fs::create_dir_all(&logs).with_context(|| format!("creating {}", logs.display()))?;
    let (shards_path, gather_path) = slurm_scripts(a, &farm, &logs)?;
    let mut out = FarmOutcome {
        slurm_shards_script: Some(shards_path.clone()),
        slurm_gather_script: Some(gather_path.clone()),
        slurm_logs: Some(logs.clone()),
        ..FarmOutcome::default()
    };
    if !a.submit && !a.resubmit {
        log::info!(
            "submit with: sbatch {} (then the gather with --dependency=afterany:<its job id>)",
            shards_path.display()
        );
        return Ok(out);
    }
    let todo = if a.resubmit { farm.missing()? } else { (0..farm.shards).collect() };
    let list: Vec<String> = todo.iter().map(u32::to_string).collect();
    out.slurm_submitted_shards = Some(if list.is_empty() { "none".into() } else { list.join(",") });
    let mut array_id = None;
    if !todo.is_empty() {
        let mut cmd = Command::new("sbatch");
        cmd.arg("--parsable");
        if a.resubmit {
            let limit = a.max_running.map(|m| format!("%{m}")).unwrap_or_default();
            cmd.arg(format!("--array={}{limit}", list.join(",")));
        }
        array_id = Some(sbatch(cmd.arg(&shards_path))?);
    }
    let mut cmd = Command::new("sbatch");
    cmd.arg("--parsable");
    if let Some(id) = &array_id {
        cmd.arg(format!("--dependency=afterany:{id}"));
    }
    let gather_id = sbatch(cmd.arg(&gather_path))?;
    out.slurm_array_job = Some(array_id.clone().unwrap_or_else(|| "none".into()));
    out.slurm_gather_job = Some(gather_id.clone());
    if a.wait {
        out.slurm_wait_s = Some(wait_for(&gather_id, array_id.as_deref())?);
        gathered(&farm, &logs.join(format!("gather-{gather_id}.log")))?;
    }
    Ok(out)
}

/// The array job's and the gather job's scripts, written into the farm's folder.
fn slurm_scripts(a: &EngineArgs, farm: &Farm, logs: &Path) -> Result<(PathBuf, PathBuf)> {
    let head = |name: &str, log: &str| {
        let mut h = format!(
            "#!/bin/bash\n#SBATCH --job-name={name}\n#SBATCH --output={}\n#SBATCH --chdir={}\n",
            logs.join(log).display(),
            farm.cwd.display()
        );
        for o in &a.sbatch {
            h.push_str(&format!("#SBATCH {o}\n"));
        }
        h
    };
    let stem = farm.output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let mut shards = head(&format!("vcuts-{stem}"), "shard-%a.log");
    let last = farm.shards - 1;
    let limit = a.max_running.map(|m| format!("%{m}")).unwrap_or_default();
    shards.push_str(&format!("#SBATCH --array=0-{last}{limit}\n"));
    if let Some(c) = a.cpus_per_task {
        shards.push_str(&format!("#SBATCH --cpus-per-task={c}\n"));
    }
    let mut extra = vec!["--shard".to_string(), format!("env/{}", farm.shards)];
    if let Some(c) = a.cpus_per_task {
        extra.extend(["--threads".into(), c.to_string()]);
    }
    shards.push_str(&format!(
        "# Shard $SLURM_ARRAY_TASK_ID of {n}: resumes its partial file if an earlier run of it stopped.\n\
         set -euo pipefail\nexec {}\n",
        farm.command(&extra),
        n = farm.shards
    ));
    let mut gather = head(&format!("vcuts-{stem}-gather"), "gather-%j.log");
    gather.push_str(
        "# Runs after every shard task ended, done or not (afterany): gathers what is there, or names\n\
         # the shards to run again (farm slurm ... --resubmit).\nset -uo pipefail\n",
    );
    gather.push_str(&farm.gather_command());
    let (shards_path, gather_path) = (farm.dir.join("shards.sbatch"), farm.dir.join("gather.sbatch"));
    write_atomic(&shards_path, shards.as_bytes())?;
    write_atomic(&gather_path, gather.as_bytes())?;
    Ok((shards_path, gather_path))
}

/// Whether the gather job whose log is `log` gathered; an error naming the shards to run
/// again when not.
fn gathered(farm: &Farm, log: &Path) -> Result<()> {
    let text = std::fs::read_to_string(log).unwrap_or_default();
    log::info!("{}: {}", log.display(), text.trim_end());
    if text.contains("gathered ") {
        return Ok(());
    }
    let missing = farm.missing().unwrap_or_default();
    let list: Vec<String> = missing.iter().map(u32::to_string).collect();
    bail!(
        "the gather did not complete (log {}); shards to run again: {} — rerun this command with \
         --resubmit instead of --submit",
        log.display(),
        if list.is_empty() { "none found".into() } else { list.join(",") }
    )
}

/// Submits an sbatch command line; returns the job id.
fn sbatch(cmd: &mut Command) -> Result<String> {
    let out = cmd.output().context("running sbatch (is Slurm installed and on the PATH?)")?;
    if !out.status.success() {
        bail!("sbatch failed: {}", String::from_utf8_lossy(&out.stderr).trim());
    }
    let id = String::from_utf8_lossy(&out.stdout).trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() {
        bail!("sbatch printed no job id");
    }
    Ok(id)
}

/// Polls `squeue` until none of the jobs is queued or running; returns the seconds waited.
fn wait_for(gather: &str, array: Option<&str>) -> Result<f64> {
    let jobs: Vec<&str> = std::iter::once(gather).chain(array).collect();
    let start = Instant::now();
    loop {
        let out = Command::new("squeue").args(["-h", "-o", "%i %T", "-j", &jobs.join(",")]).output();
        let listed = match out {
            Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout).trim().to_string(),
            // squeue refuses ids it no longer knows: they are done.
            Ok(_) => String::new(),
            Err(e) => bail!("running squeue: {e}"),
        };
        if listed.is_empty() {
            return Ok(start.elapsed().as_secs_f64());
        }
        std::thread::sleep(Duration::from_millis(500));
    }
}

fn kubernetes(a: &EngineArgs) -> Result<FarmOutcome> {
    if a.submit || a.resubmit || a.wait {
        bail!("farm kubernetes only writes the manifests (kubectl apply -f them)");
    }
    let farm = Farm::new(a, PathBuf::from("vcuts"))?;
    std::fs::create_dir_all(&farm.dir).with_context(|| format!("creating {}", farm.dir.display()))?;
    let stem = farm.output.file_stem().map(|s| s.to_string_lossy().to_lowercase()).unwrap_or_default();
    let name: String = stem.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '-' }).collect();
    let json = |w: &str| serde_json::to_string(w).unwrap_or_default();
    let mut args: Vec<String> = farm.task.iter().map(|w| json(w)).collect();
    args.extend([json("--shard"), json(&format!("env/{}", farm.shards))]);
    let resources =
        a.cpus_per_task.map(|c| format!("\n          resources: {{requests: {{cpu: \"{c}\"}}}}")).unwrap_or_default();
    let job = format!(
        "# A sharded vcuts precompute as a Kubernetes Indexed Job: pod i computes shard i\n\
         # (JOB_COMPLETION_INDEX). The output folder {out} must be a volume every pod shares;\n\
         # mount it at the same path. Then run the gather Job (gather.yaml).\n\
         apiVersion: batch/v1\nkind: Job\nmetadata:\n  name: vcuts-{name}-shards\nspec:\n  completionMode: Indexed\n  \
         completions: {n}\n  parallelism: {par}\n  backoffLimitPerIndex: 2\n  template:\n    spec:\n      \
         restartPolicy: Never\n      containers:\n        - name: shard\n          image: {image}\n          \
         workingDir: {cwd}\n          command: [\"vcuts\"]\n          args: [{args}]{resources}\n",
        out = farm.output.parent().unwrap_or(Path::new("/")).display(),
        n = farm.shards,
        par = a.max_running.unwrap_or(farm.shards),
        image = json(&a.image),
        cwd = json(&farm.cwd.display().to_string()),
        args = args.join(", "),
    );
    let files: Vec<String> = farm.shard_files().iter().map(|f| json(&f.display().to_string())).collect();
    let gather = format!(
        "# Gathers the shards of vcuts-{name}-shards once it has finished (kubectl wait --for=condition=complete).\n\
         apiVersion: batch/v1\nkind: Job\nmetadata:\n  name: vcuts-{name}-gather\nspec:\n  backoffLimit: 0\n  \
         template:\n    spec:\n      restartPolicy: Never\n      containers:\n        - name: gather\n          \
         image: {image}\n          workingDir: {cwd}\n          command: [\"vcuts\"]\n          \
         args: [\"precompute\", \"--gather\", {files}, \"--output\", {out}]\n",
        image = json(&a.image),
        cwd = json(&farm.cwd.display().to_string()),
        files = files.join(", "),
        out = json(&farm.output.display().to_string()),
    );
    let (job_path, gather_path) = (farm.dir.join("indexed-job.yaml"), farm.dir.join("gather.yaml"));
    write_atomic(&job_path, job.as_bytes())?;
    write_atomic(&gather_path, gather.as_bytes())?;
    Ok(FarmOutcome { kubernetes_job: Some(job_path), kubernetes_gather: Some(gather_path), ..FarmOutcome::default() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_are_quoted_for_the_shell_only_when_needed() {
        assert_eq!(quote("builtin:teapot"), "builtin:teapot");
        assert_eq!(quote("a b"), "'a b'");
        assert_eq!(quote("it's"), r"'it'\''s'");
        assert_eq!(quote(""), "''");
    }
}
