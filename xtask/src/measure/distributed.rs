//! The bench's `distributed` section: a precompute run whole and as N shards (each a process,
//! as a farm's task is), its plan's balance against the shards' measured times, the CPU the
//! shards cost together against the one run's, the gather's time and peak memory, and a
//! projection of many-object scenes at the `paper` preset over M nodes from measured per-section
//! rates.

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use vcut_data::shard::ShardPlan;
use vcut_precompute::PrecomputeParams;
use vcut_precompute::plan::plan;
use vcut_scene::Scene;

/// One sharded run against the whole run of the same scene.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ShardedRun {
    /// Scene.
    pub scene: String,
    /// Preset.
    pub preset: String,
    /// Shards.
    pub shards: u32,
    /// Cut sections planned.
    pub sections: usize,
    /// The plan's largest shard cost over the mean (rays of the cost model).
    pub plan_balance: f64,
    /// The largest shard's ray-stage seconds over the mean shard's, as measured.
    pub measured_balance: f64,
    /// The one-machine run: wall and CPU seconds of its process.
    pub one_run_s: f64,
    /// CPU seconds (user + system) of the one-machine run's process.
    pub one_run_cpu_s: f64,
    /// Per shard: wall seconds of its process.
    pub shard_s: Vec<f64>,
    /// Per shard: CPU seconds of its process.
    pub shard_cpu_s: Vec<f64>,
    /// Per shard: seconds of its ray stages (SVCs and fields), the work the plan splits.
    pub shard_compute_s: Vec<f64>,
    /// Σ shard CPU seconds / the one run's: what splitting costs in all.
    pub cpu_overhead: f64,
    /// The longest shard's wall seconds over the one run's: the speed-up's inverse when every
    /// shard has a machine of its own.
    pub makespan_vs_one_run: f64,
    /// The gather: wall seconds, peak resident memory, output bytes (its own process).
    pub gather_s: f64,
    /// Peak resident memory of the gather's process.
    pub gather_peak_bytes: u64,
    /// Bytes of the gathered file.
    pub file_bytes: u64,
    /// Whether the gathered file is byte-identical to the one-machine run's.
    pub byte_identical: bool,
    /// The one run's estimated ray-stage seconds over its measured ones (the estimate the
    /// projection's rates come from, checked on a run that was made).
    pub estimate_vs_actual_s: f64,
}

/// Seconds per million planned rays, by section kind, measured at a preset.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
pub struct Rates {
    /// SVC sections.
    pub svc_s_per_mray: f64,
    /// Field sections.
    pub field_s_per_mray: f64,
}

/// A many-object scene at a preset over M nodes, projected.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Projection {
    /// Objects (`builtin:showroom:K`).
    pub objects: usize,
    /// Vertices.
    pub vertices: usize,
    /// Nodes (shards), each a machine like this one.
    pub nodes: u32,
    /// Hours until the last shard ends (the plan's largest shard at the measured rates, plus the
    /// per-shard start-up measured).
    pub hours: f64,
    /// The plan's balance.
    pub balance: f64,
}

/// The section.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct DistributedSection {
    /// Sharded runs measured.
    pub runs: Vec<ShardedRun>,
    /// The preset of the projection.
    pub projection_preset: String,
    /// Where its rates come from (the scene and the estimate's sample).
    pub projection_basis: String,
    /// The rates.
    pub rates: Rates,
    /// Seconds a shard spends outside its ray stages (process start, scene, directions,
    /// estimate sample), measured: the mean over the runs' shards.
    pub shard_startup_s: f64,
    /// The projections.
    pub projections: Vec<Projection>,
}

/// The cost in planned rays of each kind in `plan`'s shards: (svc, field) per shard.
fn kind_loads(plan: &ShardPlan) -> Vec<(u64, u64)> {
    let mut out = vec![(0u64, 0u64); plan.shards() as usize];
    for s in plan.sections() {
        let o = &mut out[s.owner as usize];
        match s.id.kind {
            vcut_data::SectionKind::Svc => o.0 += s.cost,
            _ => o.1 += s.cost,
        }
    }
    out
}

/// Rates from an estimate of `scene` with `params`: its predicted SVC and field seconds over
/// the planned rays of each.
pub fn rates(scene: &Scene, params: &PrecomputeParams, svc_s: f64, field_s: f64) -> Result<Rates> {
    let p = plan(scene, params, 1)?;
    let (svc, field) = kind_loads(&p)[0];
    Ok(Rates {
        svc_s_per_mray: svc_s / (svc.max(1) as f64 / 1e6),
        field_s_per_mray: field_s / (field.max(1) as f64 / 1e6),
    })
}

/// The projected hours of `scene` with `params` on `nodes` nodes.
pub fn project(scene: &Scene, params: &PrecomputeParams, nodes: u32, r: Rates, startup_s: f64) -> Result<(f64, f64)> {
    let p = plan(scene, params, nodes).with_context(|| format!("planning {nodes} shards"))?;
    let longest = kind_loads(&p)
        .iter()
        .map(|&(svc, field)| svc as f64 / 1e6 * r.svc_s_per_mray + field as f64 / 1e6 * r.field_s_per_mray)
        .fold(0.0, f64::max);
    Ok(((longest + startup_s) / 3600.0, p.balance_ratio()))
}

/// Rates measured by the estimate of `scene` at `preset` (a sample of `seconds` of its own work).
pub fn measure_rates(scene: &str, preset: &str, seconds: f64) -> Result<Rates> {
    let args = vcuts::precompute::PrecomputeArgs::new(scene, preset);
    let e = vcuts::precompute::estimate_only(&args, seconds)?;
    let r = vcuts::precompute::resolve(&args)?;
    rates(&r.scene, &r.params, e.svc_seconds, e.field_seconds)
}

/// Projections of `builtin:showroom:K` for each K of `objects` at `preset` on each count of
/// `nodes`.
pub fn projections(
    objects: &[usize],
    nodes: &[u32],
    preset: &str,
    r: Rates,
    startup_s: f64,
) -> Result<Vec<Projection>> {
    let params = PrecomputeParams::preset(preset).with_context(|| format!("preset {preset}"))?;
    let mut out = Vec::new();
    for &k in objects {
        let scene = Scene::open(&format!("builtin:showroom:{k}"))?;
        for &m in nodes {
            let (hours, balance) = project(&scene, &params, m, r, startup_s)?;
            out.push(Projection { objects: k, vertices: scene.vertex_count(), nodes: m, hours, balance });
        }
    }
    Ok(out)
}

/// The section's table.
pub fn table(s: &DistributedSection) -> String {
    let mut md = String::from(
        "| scene | preset | shards | plan balance | measured balance | CPU Σ shards / one run | longest shard / one run | gather s | gather peak MB | file MB | identical |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
    );
    for r in &s.runs {
        md.push_str(&format!(
            "| {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.1} | {:.1} | {} |\n",
            r.scene,
            r.preset,
            r.shards,
            r.plan_balance,
            r.measured_balance,
            r.cpu_overhead,
            r.makespan_vs_one_run,
            r.gather_s,
            r.gather_peak_bytes as f64 / 1e6,
            r.file_bytes as f64 / 1e6,
            if r.byte_identical { "yes" } else { "**no**" }
        ));
    }
    md.push_str(&format!(
        "\nProjected at `{}` ({}; {:.1} s start-up per shard):\n\n| objects | vertices | nodes | hours | plan balance |\n|---:|---:|---:|---:|---:|\n",
        s.projection_preset, s.projection_basis, s.shard_startup_s
    ));
    for p in &s.projections {
        md.push_str(&format!("| {} | {} | {} | {:.2} | {:.3} |\n", p.objects, p.vertices, p.nodes, p.hours, p.balance));
    }
    md
}
