//! What `precompute` reports: its estimate, a plan, a gather, the run's summary and how the
//! estimate compared; each a part of [`PrecomputeOutcome`], serialised as its keys.

use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};
use std::path::PathBuf;
use vcut_data::shard::ShardPlan;
use vcut_precompute::PrecomputeParams;
use vcut_precompute::estimate::Estimate;
use vcut_precompute::run::Summary;

/// What `precompute` did: the parts that apply, and the file it wrote.
#[derive(Debug, Clone, Default, Serialize)]
pub struct PrecomputeOutcome {
    /// The estimate printed before the run.
    #[serde(flatten)]
    pub estimate: Option<EstimateOutcome>,
    /// `--plan N`: the sections and their split.
    #[serde(flatten)]
    pub plan: Option<PlanOutcome>,
    /// `--gather`: the shard files joined.
    #[serde(flatten)]
    pub gather: Option<GatherOutcome>,
    /// The run's figures.
    #[serde(flatten)]
    pub summary: Option<SummaryOutcome>,
    /// The run's peak memory, and for a whole run its figures against the estimate's.
    #[serde(flatten)]
    pub against: Option<AgainstOutcome>,
    /// The file written (or that would be, with `--dry-run` and `--plan`).
    #[serde(skip)]
    pub file: PathBuf,
    /// The run's summary as the precompute returned it (not with `--dry-run`, `--plan`,
    /// `--gather`).
    #[serde(skip)]
    pub run: Option<Summary>,
}

/// The precompute's estimate from a timed sample of its own work.
#[derive(Debug, Clone, Serialize)]
pub struct EstimateOutcome {
    /// Vertices of SVCs.
    pub estimate_vertices: u64,
    /// Field sample points.
    pub estimate_field_points: u64,
    /// Rays.
    pub estimate_rays: u64,
    /// Seconds.
    pub estimate_s: f64,
    /// Seconds of SVCs.
    pub estimate_svc_s: f64,
    /// Seconds of fields.
    pub estimate_fields_s: f64,
    /// The file's size.
    pub estimate_output_mb: f64,
    /// The peak memory.
    pub estimate_peak_mb: f64,
    /// The sample's seconds.
    pub estimate_sample_s: f64,
}

impl EstimateOutcome {
    /// The keys of `e`.
    pub fn of(e: &Estimate) -> EstimateOutcome {
        EstimateOutcome {
            estimate_vertices: e.vertices,
            estimate_field_points: e.field_points,
            estimate_rays: e.svc_rays + e.field_rays,
            estimate_s: e.seconds,
            estimate_svc_s: e.svc_seconds,
            estimate_fields_s: e.field_seconds,
            estimate_output_mb: mb(e.output_bytes),
            estimate_peak_mb: mb(e.peak_bytes),
            estimate_sample_s: e.sampled.2,
        }
    }

    /// The estimate as a sentence, for the log before the run.
    pub fn sentence(e: &Estimate) -> String {
        let (sv, sp, ss) = e.sampled;
        format!(
            "estimate: {} vertices, {} field points, {:.1} M rays; about {:.1} s on {} threads; output {}; peak \
             memory {} (from a {ss:.1} s sample of {sv} vertices and {sp} points)",
            e.vertices,
            e.field_points,
            (e.svc_rays + e.field_rays) as f64 / 1e6,
            e.seconds,
            rayon::current_num_threads(),
            vcut_scene::budget::human(e.output_bytes),
            vcut_scene::budget::human(e.peak_bytes),
        )
    }
}

/// A plan of the cut sections over N shards.
#[derive(Debug, Clone, Serialize)]
pub struct PlanOutcome {
    /// Each section: its id, vertices or points, share of rays cast, cost and shard.
    pub section: Vec<PlanSection>,
    /// Shards.
    pub plan_shards: u32,
    /// Sections.
    pub plan_sections: usize,
    /// The whole cost, millions of rays.
    pub plan_cost_mrays: f64,
    /// The largest shard's cost over the mean.
    pub plan_balance: f64,
    /// Each shard's sections and cost.
    #[serde(flatten)]
    pub shards: ShardLoads,
}

/// One section of a plan.
#[derive(Debug, Clone, Serialize)]
pub struct PlanSection {
    /// The section.
    pub id: String,
    /// Its vertices or field points.
    pub units: u64,
    /// The share of its rays cast (the rest decided without one).
    pub share: f64,
    /// Its cost, millions of rays.
    pub cost_mrays: f64,
    /// The shard that computes it.
    pub shard: u32,
}

/// Each shard's sections and cost: `shard_<i>_sections`, `shard_<i>_cost_mrays`.
#[derive(Debug, Clone, Default)]
pub struct ShardLoads(pub Vec<(usize, f64)>);

impl Serialize for ShardLoads {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        for (i, (sections, cost)) in self.0.iter().enumerate() {
            m.serialize_entry(&format!("shard_{i}_sections"), sections)?;
            m.serialize_entry(&format!("shard_{i}_cost_mrays"), cost)?;
        }
        m.end()
    }
}

impl PlanOutcome {
    /// The keys of `plan` for a precompute of `params`.
    pub fn of(plan: &ShardPlan, params: &PrecomputeParams) -> PlanOutcome {
        let dirs = f64::from(params.directions);
        let section = plan
            .sections()
            .iter()
            .map(|s| PlanSection {
                id: s.id.to_string(),
                units: s.units,
                share: s.cost as f64 / (s.units.max(1) as f64 * dirs),
                cost_mrays: s.cost as f64 / 1e6,
                shard: s.owner,
            })
            .collect();
        let loads = plan.loads();
        let shards = loads
            .iter()
            .enumerate()
            .map(|(i, load)| (plan.sections().iter().filter(|s| s.owner == i as u32).count(), *load as f64 / 1e6))
            .collect();
        PlanOutcome {
            section,
            plan_shards: plan.shards(),
            plan_sections: plan.sections().len(),
            plan_cost_mrays: loads.iter().sum::<u64>() as f64 / 1e6,
            plan_balance: plan.balance_ratio(),
            shards: ShardLoads(shards),
        }
    }
}

/// Shard files gathered into one.
#[derive(Debug, Clone, Serialize)]
pub struct GatherOutcome {
    /// The file written.
    pub output: PathBuf,
    /// Shards joined.
    pub gather_shards: u32,
    /// Sections copied.
    pub gather_sections: usize,
    /// The file's size.
    pub gather_mb: f64,
    /// Seconds.
    pub gather_s: f64,
    /// The process's peak memory.
    pub gather_peak_rss_mb: Option<f64>,
}

/// A run's figures: per stage its time and rays, per kind of cut its count and sizes, the file.
#[derive(Debug, Clone, Serialize)]
pub struct SummaryOutcome {
    /// The file written.
    pub output: PathBuf,
    /// The preset.
    pub preset: String,
    /// Seconds in all.
    pub total_s: f64,
    /// `<stage>_s`, `<stage>_rays_cast`, … per stage.
    #[serde(flatten)]
    pub stages: Stages,
    /// The objects with a field (`none`).
    pub fields: String,
    /// Field sample points inside their object (not traced).
    pub field_inside_points: u64,
    /// `<kind>_cuts`, `<kind>_nodes_mean`, … per kind of cut.
    #[serde(flatten)]
    pub sizes: Sizes,
    /// The file's size.
    pub file_mb: f64,
    /// The cuts' size as stored.
    pub cuts_mb: f64,
    /// The same in the height codec.
    pub cuts_heights_codec_mb: f64,
    /// The same as level-order indices and f32 values (the baseline).
    pub cuts_index_baseline_mb: f64,
    /// Stored over the baseline.
    pub cuts_size_vs_baseline: Option<f64>,
}

/// The stages of a run, serialised under their names.
#[derive(Debug, Clone)]
pub struct Stages(pub Vec<vcut_precompute::run::StageSummary>);

impl Serialize for Stages {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        for st in &self.0 {
            let n = st.name;
            m.serialize_entry(&format!("{n}_s"), &st.seconds)?;
            if n == "directions" {
                continue;
            }
            m.serialize_entry(&format!("{n}_rays_cast"), &st.rays.rays_cast)?;
            m.serialize_entry(&format!("{n}_rays_occluded"), &st.rays.rays_occluded)?;
            m.serialize_entry(&format!("{n}_resolved_without_ray"), &st.rays.resolved_without_ray)?;
            m.serialize_entry(&format!("{n}_rays_per_s"), &st.rays_per_second().round())?;
            m.serialize_entry(&format!("{n}_raw_rays_per_s"), &st.raw_rays_per_second.round())?;
            if st.raw_rays_per_second > 0.0 && st.rays.rays_cast > 0 {
                m.serialize_entry(&format!("{n}_rays_per_s_vs_raw"), &(st.rays_per_second() / st.raw_rays_per_second))?;
            }
            m.serialize_entry(&format!("{n}_sections_computed"), &st.computed)?;
            m.serialize_entry(&format!("{n}_sections_resumed"), &st.resumed)?;
        }
        m.end()
    }
}

/// The cuts' sizes per kind, serialised under the kind's name.
#[derive(Debug, Clone)]
pub struct Sizes(pub Vec<vcut_precompute::run::CutSizes>);

impl Serialize for Sizes {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        for z in &self.0 {
            let k = z.kind;
            let mean = if z.cuts > 0 { z.nodes as f64 / z.cuts as f64 } else { 0.0 };
            m.serialize_entry(&format!("{k}_cuts"), &z.cuts)?;
            m.serialize_entry(&format!("{k}_nodes_mean"), &mean)?;
            m.serialize_entry(&format!("{k}_nodes_max"), &z.max_nodes)?;
            m.serialize_entry(&format!("{k}_mb"), &mb(z.bytes))?;
            m.serialize_entry(&format!("{k}_heights_codec_mb"), &mb(z.heights_codec_bytes))?;
            m.serialize_entry(&format!("{k}_index_baseline_mb"), &mb(z.index_baseline_bytes))?;
        }
        m.end()
    }
}

impl SummaryOutcome {
    /// The keys of the run `s` that wrote `output` in `total_s` seconds under `params`.
    pub fn of(output: PathBuf, s: &Summary, total_s: f64, params: &PrecomputeParams) -> SummaryOutcome {
        let cut_bytes: u64 = s.sizes.iter().map(|z| z.bytes).sum();
        let heights_bytes: u64 = s.sizes.iter().map(|z| z.heights_codec_bytes).sum();
        let base_bytes: u64 = s.sizes.iter().map(|z| z.index_baseline_bytes).sum();
        SummaryOutcome {
            output,
            preset: params.preset.clone(),
            total_s,
            stages: Stages(s.stages.clone()),
            fields: if s.fields.is_empty() { "none".into() } else { s.fields.join(",") },
            field_inside_points: s.inside_points,
            sizes: Sizes(s.sizes.clone()),
            file_mb: mb(s.file_bytes),
            cuts_mb: mb(cut_bytes),
            cuts_heights_codec_mb: mb(heights_bytes),
            cuts_index_baseline_mb: mb(base_bytes),
            cuts_size_vs_baseline: (base_bytes > 0).then(|| cut_bytes as f64 / base_bytes as f64),
        }
    }

    /// The sizes as a table for the log (`params`' codings in the header).
    pub fn table(s: &Summary, params: &PrecomputeParams) -> String {
        let mut t = format!(
            "| section | cuts | mean nodes | stored MB ({}, values {} / {}) | height codec MB | index + f32 baseline MB \
             |\n|---|---:|---:|---:|---:|---:|\n",
            params.shape_coding.name(),
            params.svc_values.name(),
            params.field_values.name()
        );
        for z in &s.sizes {
            let mean = if z.cuts > 0 { z.nodes as f64 / z.cuts as f64 } else { 0.0 };
            t += &format!(
                "| {} | {} | {mean:.1} | {:.2} | {:.2} | {:.2} |\n",
                z.kind,
                z.cuts,
                mb(z.bytes),
                mb(z.heights_codec_bytes),
                mb(z.index_baseline_bytes)
            );
        }
        t + &format!("| whole file | | | {:.2} | | |", mb(s.file_bytes))
    }
}

/// The run's peak memory, and for a whole run its figures against the estimate's.
#[derive(Debug, Clone, Serialize)]
pub struct AgainstOutcome {
    /// The process's peak memory.
    pub peak_rss_mb: f64,
    /// Estimated seconds over actual (of casting rays).
    pub estimate_vs_actual_s: Option<f64>,
    /// Estimated rays over actual.
    pub estimate_vs_actual_rays: Option<f64>,
    /// Estimated output bytes over actual.
    pub estimate_vs_actual_output: Option<f64>,
    /// Estimated peak memory over actual.
    pub estimate_vs_actual_peak: Option<f64>,
}

impl AgainstOutcome {
    /// `s` against `e`; `whole`: a whole run (a shard's figures are a part of the whole the
    /// estimate is about: only its memory compares).
    pub fn of(e: &Estimate, s: &Summary, whole: bool) -> AgainstOutcome {
        let ray_s: f64 = s.stages.iter().filter(|st| st.name != "directions").map(|st| st.seconds).sum();
        let rays: u64 = s.stages.iter().map(|st| st.rays.rays_cast).sum();
        let peak = vcut_scene::budget::peak_memory().unwrap_or(0);
        AgainstOutcome {
            peak_rss_mb: mb(peak),
            estimate_vs_actual_s: whole.then(|| e.seconds / ray_s.max(1e-9)),
            estimate_vs_actual_rays: whole.then(|| (e.svc_rays + e.field_rays) as f64 / rays.max(1) as f64),
            estimate_vs_actual_output: whole.then(|| e.output_bytes as f64 / s.file_bytes.max(1) as f64),
            estimate_vs_actual_peak: (whole && peak > 0).then(|| e.peak_bytes as f64 / peak as f64),
        }
    }
}

fn mb(b: u64) -> f64 {
    b as f64 / 1e6
}
