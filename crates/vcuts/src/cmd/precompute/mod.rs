//! `vcuts precompute`: a scene's SVCs and fields into a `.vcuts` file, with its estimate first, a
//! progress bar and ETA per stage, and a closing summary ([`PrecomputeOutcome`]; the size table
//! in the log). `shard.rs`: `--plan`, `--shard` and `--gather`.

mod outcome;
pub mod shard;

pub use outcome::{
    AgainstOutcome, EstimateOutcome, GatherOutcome, PlanOutcome, PlanSection, PrecomputeOutcome, ShardLoads, Sizes,
    Stages, SummaryOutcome,
};

use crate::progress::Bar;
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use vcut_data::file::SectionId;
use vcut_precompute::PrecomputeParams;
use vcut_precompute::estimate::{Estimate, estimate};
use vcut_precompute::run::{Job, Progress, precompute_shard, precompute_with};
use vcut_scene::{Scene, SceneDesc};

/// Arguments of `precompute`.
#[derive(clap::Args, Clone)]
pub struct PrecomputeArgs {
    /// The scene: builtin:teapot | builtin:bunny | builtin:spheres | builtin:showroom[:N] | builtin:assembly[:N], a .toml scene file, or a mesh.
    #[arg(long, default_value = "builtin:teapot")]
    pub scene: String,
    /// Environment to record for rendering (default: the scene's own); checked to load.
    #[arg(long)]
    pub env: Option<String>,
    /// Preset: fast, balanced or paper (the scene file's [precompute] table and the options
    /// below override it).
    #[arg(long)]
    pub preset: Option<String>,
    /// Output file (default: target/vcuts/<scene>-<preset>.vcuts).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Number of directions (power of two, 64..65,536).
    #[arg(long)]
    pub directions: Option<u32>,
    /// SVC error threshold.
    #[arg(long, value_parser = crate::options::real64("svc-max-error"), allow_hyphen_values = true)]
    pub svc_max_error: Option<f64>,
    /// Field spheres.
    #[arg(long, value_parser = crate::options::whole::<u32>("field-spheres"), allow_hyphen_values = true)]
    pub field_spheres: Option<u32>,
    /// Field cube-map resolution per face.
    #[arg(long, value_parser = crate::options::whole::<u32>("field-resolution"), allow_hyphen_values = true)]
    pub field_resolution: Option<u32>,
    /// Field error threshold (0 = exact, below 0.25).
    #[arg(long, value_parser = crate::options::real64("field-max-error"), allow_hyphen_values = true)]
    pub field_max_error: Option<f64>,
    /// Any parameter as KEY=VALUE (repeatable); `--set help` lists them.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Direction-set cache folder.
    #[arg(long, default_value = "target/vcut-cache")]
    pub cache_dir: PathBuf,
    /// Discard a partial file from an earlier run instead of resuming it.
    #[arg(long)]
    pub fresh: bool,
    /// Print the cut sections with their estimated cost and their split over N shards, and stop.
    #[arg(long, value_name = "N", value_parser = crate::options::whole::<u32>("plan"), conflicts_with_all = ["shard", "gather"], allow_hyphen_values = true)]
    pub plan: Option<u32>,
    /// Compute only shard I of N (0-based) into `<output>.shard-I-of-N.vcuts`; `env/N` takes I
    /// from SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX or AWS_BATCH_JOB_ARRAY_INDEX.
    #[arg(long, value_name = "I/N", conflicts_with = "gather")]
    pub shard: Option<String>,
    /// Join shard files into the file one machine writes (-o, or the first shard's name without
    /// `.shard-I-of-N`), checking every checksum and that no section is missing.
    #[arg(long, value_name = "SHARD_FILES", num_args = 1..)]
    pub gather: Vec<PathBuf>,
    /// The estimate printed before the run.
    #[command(flatten)]
    pub estimate: crate::resources::EstimateArgs,
}

impl PrecomputeArgs {
    /// The options that say what to compute (scene, environment, preset, parameters, cache,
    /// estimate), as a command line: what each task of a farm runs, with `output`.
    pub fn task_args(&self, output: &Path, cache_dir: &Path) -> Vec<String> {
        let mut a: Vec<String> = vec!["--scene".into(), self.scene.clone()];
        let mut opt = |name: &str, v: Option<String>| {
            if let Some(v) = v {
                a.push(name.into());
                a.push(v);
            }
        };
        opt("--env", self.env.clone());
        opt("--preset", self.preset.clone());
        opt("--directions", self.directions.map(|x| x.to_string()));
        opt("--svc-max-error", self.svc_max_error.map(|x| x.to_string()));
        opt("--field-spheres", self.field_spheres.map(|x| x.to_string()));
        opt("--field-resolution", self.field_resolution.map(|x| x.to_string()));
        opt("--field-max-error", self.field_max_error.map(|x| x.to_string()));
        for kv in &self.set {
            opt("--set", Some(kv.clone()));
        }
        opt("--output", Some(output.display().to_string()));
        opt("--cache-dir", Some(cache_dir.display().to_string()));
        opt("--estimate-seconds", Some(self.estimate.seconds.to_string()));
        if self.estimate.force {
            a.push("--force".into());
        }
        a
    }

    /// Defaults for `scene` with `preset`.
    pub fn new(scene: &str, preset: &str) -> Self {
        PrecomputeArgs {
            scene: scene.into(),
            env: None,
            preset: Some(preset.into()),
            output: None,
            directions: None,
            svc_max_error: None,
            field_spheres: None,
            field_resolution: None,
            field_max_error: None,
            set: Vec::new(),
            cache_dir: "target/vcut-cache".into(),
            fresh: false,
            plan: None,
            shard: None,
            gather: Vec::new(),
            estimate: Default::default(),
        }
    }
}

/// Parameters from the preset, the scene file's `[precompute]` table, then the options.
fn resolve_params(args: &PrecomputeArgs, desc: Option<&SceneDesc>) -> Result<PrecomputeParams> {
    if args.set.iter().any(|s| s == "help") {
        let p = PrecomputeParams::paper();
        println!("parameters (paper preset values):");
        for k in vcut_data::params::KEYS {
            println!("{k} = {}", p.get(k).unwrap_or_default());
        }
        std::process::exit(0);
    }
    let mut overrides: Vec<(String, String)> = Vec::new();
    let mut flag = |k: &str, v: Option<String>| {
        if let Some(v) = v {
            overrides.push((k.into(), v));
        }
    };
    flag("directions", args.directions.map(|x| x.to_string()));
    flag("svc_max_error", args.svc_max_error.map(|x| x.to_string()));
    flag("field_spheres", args.field_spheres.map(|x| x.to_string()));
    flag("field_resolution", args.field_resolution.map(|x| x.to_string()));
    flag("field_max_error", args.field_max_error.map(|x| x.to_string()));
    for kv in &args.set {
        let Some((k, v)) = kv.split_once('=') else { bail!("--set {kv}: expected KEY=VALUE (--set help lists keys)") };
        overrides.push((k.trim().into(), v.trim().into()));
    }
    let pairs: Vec<(&str, &str)> = overrides.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    let table = desc.and_then(|d| d.precompute.as_ref());
    PrecomputeParams::resolve(args.preset.as_deref(), table, &pairs)
        .with_context(|| format!("{}: [precompute] and the command line's parameters", args.scene))
}

/// One progress bar per stage (periodic log lines when stderr is not a terminal).
#[derive(Default)]
struct Bars {
    current: Mutex<Option<Bar>>,
}

impl Progress for Bars {
    fn stage(&self, name: &str, total: u64) {
        let unit = match name {
            "svc" => "vertices",
            "fields" => "field points",
            _ => "steps",
        };
        *self.current.lock().unwrap_or_else(|e| e.into_inner()) = Some(Bar::new(name, total, unit));
    }
    fn advance(&self, n: u64) {
        if let Some(b) = &*self.current.lock().unwrap_or_else(|e| e.into_inner()) {
            b.inc(n);
        }
    }
    fn section(&self, id: SectionId, resumed: bool) {
        if let Some(b) = &*self.current.lock().unwrap_or_else(|e| e.into_inner()) {
            b.set_message(format!("{}{id}", if resumed { "resumed " } else { "" }));
        }
    }
    fn end_stage(&self) {
        if let Some(b) = self.current.lock().unwrap_or_else(|e| e.into_inner()).take() {
            b.finish();
        }
    }
}

/// The file-name stem of a scene spec: `builtin:teapot` → `teapot`, `builtin:showroom:32` →
/// `showroom-32`, `dir/x.toml` → `x`.
pub fn scene_stem(scene: &str) -> String {
    let name = match scene.strip_prefix("builtin:") {
        Some(builtin) => builtin.replace(':', "-"),
        None => scene.rsplit(['/', '\\']).next().unwrap_or_default().trim_end_matches(".toml").to_string(),
    };
    let stem: String = name.chars().filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_').collect();
    if stem.is_empty() { "scene".to_string() } else { stem }
}

/// The default output of `scene` under `preset` (`target/vcuts/<scene>-<preset>.vcuts`),
/// precomputed unless a readable file of this format there already holds this scene with
/// exactly the preset's parameters.
pub fn cached_or_run(scene: &str, preset: &str) -> Result<PathBuf> {
    let params = PrecomputeParams::preset(preset).with_context(|| format!("--preset {preset}"))?;
    cached_or_run_at(
        scene,
        preset,
        &PathBuf::from(format!("target/vcuts/{}-{}.vcuts", scene_stem(scene), params.preset)),
    )
}

/// [`cached_or_run`] into `file`.
pub fn cached_or_run_at(scene: &str, preset: &str, file: &Path) -> Result<PathBuf> {
    cached_or_run_with(scene, preset, &[], file)
}

/// [`cached_or_run_at`] with parameters `sets` (`KEY=VALUE`, as `--set` takes them) on top of
/// the preset: a file there is reused when it holds this scene with exactly those parameters.
pub fn cached_or_run_with(scene: &str, preset: &str, sets: &[String], file: &Path) -> Result<PathBuf> {
    let mut args = PrecomputeArgs::new(scene, preset);
    args.set = sets.to_vec();
    args.output = Some(file.to_path_buf());
    let params = resolve_params(&args, None)?;
    let cached = vcut_data::Precomputed::open(file)
        .map(|d| d.record.scene == scene && d.record.params == params)
        .unwrap_or(false);
    if cached {
        log::info!("precompute: cached in {} (delete it to precompute again)", file.display());
        Ok(file.to_path_buf())
    } else {
        log::info!("precompute {scene}, preset {preset} (SVCs and fields into a .vcuts file)");
        let outcome = run(&args)?;
        crate::outcome::print(&outcome);
        Ok(outcome.file)
    }
}

/// What a `precompute` command line resolves to: the scene, the parameters, the output.
pub struct Resolved {
    /// The scene, loaded.
    pub scene: Scene,
    /// Its parameters: the preset, the scene file's `[precompute]`, `--set`.
    pub params: PrecomputeParams,
    environment: String,
    /// The file it writes.
    pub output: PathBuf,
    load_s: f64,
}

/// What `args` resolve to: the scene loaded, its parameters and output, checked.
pub fn resolve(args: &PrecomputeArgs) -> Result<Resolved> {
    let desc = if args.scene.ends_with(".toml") { Some(SceneDesc::read(Path::new(&args.scene))?) } else { None };
    let params = resolve_params(args, desc.as_ref())?;
    let t = Instant::now();
    let mut scene = Scene::open(&args.scene)?;
    crate::warn_ignored(&scene);
    let load_s = t.elapsed().as_secs_f64();
    // The map the file embeds for its renderer: `--env`'s, else the scene's.
    let environment = match &args.env {
        Some(e) => {
            scene.environment = crate::inspect::load_envmap(e).with_context(|| format!("--env {e}"))?;
            scene.environment_recipe = vcut_scene::desc::EnvironmentDesc::builtin(e);
            e.clone()
        }
        None => "scene".into(),
    };
    let stem = scene_stem(&args.scene);
    let output =
        args.output.clone().unwrap_or_else(|| PathBuf::from(format!("target/vcuts/{stem}-{}.vcuts", params.preset)));
    Ok(Resolved { scene, params, environment, output, load_s })
}

/// The estimate of the precompute `args` describe, from a sample of `seconds` (nothing run).
pub fn estimate_only(args: &PrecomputeArgs, seconds: f64) -> Result<Estimate> {
    let r = resolve(args)?;
    let job = Job {
        scene: &r.scene,
        scene_source: args.scene.clone(),
        environment: r.environment.clone(),
        params: r.params.clone(),
        cache_dir: Some(args.cache_dir.clone()),
        output: r.output.clone(),
    };
    Ok(estimate(&job, std::time::Duration::from_secs_f64(seconds))?.0)
}

/// Runs `precompute` (with `--dry-run`, only its estimate); returns what it did.
pub fn run(args: &PrecomputeArgs) -> Result<PrecomputeOutcome> {
    run_with(args, &Bars::default(), &AtomicBool::new(false))
}

/// [`run`], reporting progress to `progress` instead of bars, and stopping when `interrupt` is
/// set (the error is then [`vcut_precompute::run::PrecomputeError::Interrupted`]: the finished
/// sections stay in the `.partial` file, which the next run resumes). The Python package's
/// `precompute` is this.
pub fn run_with(args: &PrecomputeArgs, progress: &dyn Progress, interrupt: &AtomicBool) -> Result<PrecomputeOutcome> {
    if !args.gather.is_empty() {
        let gather = shard::run_gather(&args.gather, args.output.as_deref())?;
        return Ok(PrecomputeOutcome { file: gather.output.clone(), gather: Some(gather), ..Default::default() });
    }
    let Resolved { scene, params, environment, output, load_s } = resolve(args)?;
    if let Some(n) = args.plan {
        let plan = vcut_precompute::plan::plan(&scene, &params, n).with_context(|| format!("--plan {n}"))?;
        return Ok(PrecomputeOutcome {
            file: output,
            plan: Some(PlanOutcome::of(&plan, &params)),
            ..Default::default()
        });
    }
    let shard = match &args.shard {
        Some(spec) => {
            let (index, n) = shard::parse_spec(spec, |v| std::env::var(v).ok())?;
            let plan = vcut_precompute::plan::plan(&scene, &params, n)?;
            let load = plan.loads()[index as usize] as f64 / plan.loads().iter().sum::<u64>().max(1) as f64;
            log::info!("shard {index} of {n}: {:.1} % of the plan's cost", 100.0 * load);
            Some((index, plan))
        }
        None => None,
    };
    let output = match &shard {
        Some((index, plan)) => vcut_data::shard::shard_path(&output, *index, plan.shards()),
        None => output,
    };
    let partial = vcut_data::file::partial_path(&output);
    if args.fresh && partial.exists() {
        std::fs::remove_file(&partial).with_context(|| format!("removing {}", partial.display()))?;
    } else if partial.exists() {
        log::info!("resuming from {}", partial.display());
    }
    log::info!(
        "scene {} ({} objects, {} vertices, {} triangles, loaded in {load_s:.2} s), preset {}, {} directions, {} threads",
        args.scene,
        scene.objects.len(),
        scene.vertex_count(),
        scene.triangle_count(),
        params.preset,
        params.directions,
        rayon::current_num_threads()
    );
    let job = Job {
        scene: &scene,
        scene_source: args.scene.clone(),
        environment,
        params: params.clone(),
        cache_dir: Some(args.cache_dir.clone()),
        output: output.clone(),
    };
    // The shards of a farm sample together as long as one run would.
    let budget = args.estimate.budget() / shard.as_ref().map_or(1, |(_, plan)| plan.shards());
    let (estimate, setup) = estimate(&job, budget)?;
    log::info!("{}", EstimateOutcome::sentence(&estimate));
    let mut out = PrecomputeOutcome {
        estimate: Some(EstimateOutcome::of(&estimate)),
        file: output.clone(),
        ..Default::default()
    };
    crate::resources::check("precompute", estimate.peak_bytes, (&output, estimate.output_bytes), args.estimate.force)?;
    if args.estimate.dry_run {
        return Ok(out);
    }
    let t = Instant::now();
    let summary = match &shard {
        Some((index, plan)) => precompute_shard(&job, Some(setup), *index, plan, progress, interrupt)?,
        None => precompute_with(&job, Some(setup), progress, interrupt)?,
    };
    log::info!("{}", SummaryOutcome::table(&summary, &params));
    out.summary = Some(SummaryOutcome::of(output, &summary, t.elapsed().as_secs_f64(), &params));
    out.against = Some(AgainstOutcome::of(&estimate, &summary, shard.is_none()));
    out.run = Some(summary);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::scene_stem;

    #[test]
    fn a_scene_spec_names_its_default_output() {
        for (spec, stem) in [
            ("builtin:teapot", "teapot"),
            ("builtin:showroom:32", "showroom-32"),
            ("builtin:showroom", "showroom"),
            ("scenes/room.toml", "room"),
            ("../meshes/bunny v2.obj", "bunnyv2obj"),
            ("/", "scene"),
        ] {
            assert_eq!(scene_stem(spec), stem, "{spec}");
        }
    }
}
