//! The bench report (`report.json`, written by `cargo xtask bench`) as typed values, serialised
//! in one place ([`write_json`]).
//! Key names are an interface (scripts read them): each field is one key; a figure that could
//! not be measured is `null` (an `Option`, or a non-finite `f64`, which JSON writes as `null`).
//! A field is documented where its key's name does not say it all; `docs/benchmarks.md` says
//! how each figure is measured.
#![allow(missing_docs)]

pub mod csv;
pub mod plots;
pub mod table1;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The whole report.
#[derive(Serialize)]
pub struct Report {
    pub quick: bool,
    pub machine: Machine,
    pub directions: Directions,
    pub light_tree_rebuild_ms: f64,
    /// The teapot's (or the first scene's) `merge_speedup`.
    pub merge_speedup: Option<f64>,
    /// The teapot's 4-bit height codec size against the index baseline's.
    pub codec_size_ratio: Option<f64>,
    /// The teapot's `data_size_vs_index`.
    pub stored_size_ratio: Option<f64>,
    pub scenes: BTreeMap<String, SceneFigures>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tradeoff: Option<Tradeoff>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ssdo: Option<SsdoSection>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub leaves: Option<LeavesSection>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scaling: Option<crate::measure::scaling::ScalingSection>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub assembly: Option<crate::bench::assembly::AssemblySection>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distributed: Option<crate::measure::distributed::DistributedSection>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<crate::measure::accuracy::AccuracySection>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turns: Option<crate::bench::turns::TurnsSection>,
    pub bench_s: f64,
}

/// The machine the bench ran on.
#[derive(Serialize)]
pub struct Machine {
    pub cpu: String,
    pub cores: usize,
    pub memory_bandwidth_gb_s: f64,
    /// The first scene's raw ray rate (rays/s of obvhs alone on the precompute's rays).
    pub raw_rays_per_s: f64,
}

/// The 32,768-direction set from the Fibonacci start, and from a random one.
#[derive(Serialize)]
pub struct Directions {
    pub n: usize,
    pub cv_cell_area: f64,
    pub min_nn_ratio: f64,
    pub generate_s: f64,
    pub random: RandomStart,
}

/// The direction set from a random start.
#[derive(Serialize)]
pub struct RandomStart {
    pub seed: u64,
    pub cv_cell_area: f64,
    pub min_nn_ratio: f64,
    pub generate_s: f64,
    pub time_vs_fibonacci: f64,
}

/// What a scene's precompute measured, kept beside its output (`.summary.json`) for `--reuse`.
#[derive(Serialize, Deserialize, Clone, Default)]
pub struct PrecomputeFigures {
    pub precompute_s: f64,
    pub rays_per_s: f64,
    pub raw_rays_per_s: f64,
    pub rays_per_s_vs_raw: f64,
    pub data_bytes_height: u64,
    pub data_bytes_index: u64,
    pub data_bytes_height_codec_4bit: u64,
    pub data_size_vs_index: f64,
}

/// One scene of Table 1: edit, move (both merges and the knobs), references, memory.
#[derive(Serialize, Default)]
pub struct SceneFigures {
    pub preset: String,
    pub vertices: usize,
    pub objects: usize,
    pub moved_object: String,
    pub setup_s: f64,
    pub edit_ms: f64,
    pub move_ms: f64,
    pub edit_ms_index: f64,
    pub move_ms_index: f64,
    pub move_vs_index: f64,
    pub move_ms_svc_decoded: f64,
    pub svc_cache_bytes: usize,
    pub merge_s_path: f64,
    pub merge_s_path_index: f64,
    pub merge_speedup: f64,
    pub vertices_merged_per_move: usize,
    pub vertices_deferred_per_move: usize,
    pub move_ms_eager: f64,
    pub vertices_merged_per_move_eager: usize,
    pub turn_ms: f64,
    pub turn_merged_vertices: usize,
    pub turn_ms_eager: f64,
    pub exact_reference_ms: f64,
    pub edit_vs_exact_reference: f64,
    pub move_vs_exact_reference: f64,
    pub shade_bytes: usize,
    pub merged_cut_bytes: usize,
    pub rel_l2_exact: f64,
    pub max_err_exact: f64,
    pub rel_l2_exact_inside_dropped: f64,
    pub max_err_exact_inside_dropped: f64,
    pub sun_leaves: usize,
    pub rel_l2_exact_cuts_only: f64,
    pub max_err_exact_cuts_only: f64,
    pub move_ms_cuts_only: f64,
    /// The knob `FrameSettings::flat_edge_leaves` at this many leaves (`FlatEdges::Interactive`):
    /// the eager move and the error.
    pub flat_edge_leaves: u32,
    pub move_ms_eager_flat_edges: f64,
    pub rel_l2_exact_flat_edges: f64,
    pub max_err_exact_flat_edges: f64,
    pub rel_l2_mc: Option<f64>,
    pub mc_reference_s: Option<f64>,
    #[serde(flatten)]
    pub precompute: PrecomputeFigures,
    #[serde(flatten)]
    pub bounds: Option<Bounds>,
}

/// A scene's edit against what memory bandwidth allows (set once the machine is measured).
#[derive(Serialize)]
pub struct Bounds {
    /// Streaming the shading lists once at the measured bandwidth.
    pub shade_bandwidth_bound_ms: f64,
    pub edit_vs_bandwidth_bound: f64,
    /// Streaming the merged cuts themselves once.
    pub merged_cut_stream_ms: f64,
    pub edit_vs_merged_cut_stream: f64,
}

impl SceneFigures {
    /// Sets [`SceneFigures::bounds`] from the memory bandwidth (GB/s).
    pub fn bound(&mut self, bandwidth_gb_s: f64) {
        let bound_ms = self.shade_bytes as f64 / (bandwidth_gb_s * 1e9) * 1e3;
        let stream_ms = self.merged_cut_bytes as f64 / (bandwidth_gb_s * 1e9) * 1e3;
        self.bounds = Some(Bounds {
            shade_bandwidth_bound_ms: bound_ms,
            edit_vs_bandwidth_bound: self.edit_ms / bound_ms,
            merged_cut_stream_ms: stream_ms,
            edit_vs_merged_cut_stream: self.edit_ms / stream_ms,
        });
    }
}

/// The trade-off sweeps.
#[derive(Serialize)]
pub struct Tradeoff {
    pub scene: String,
    pub base_preset: String,
    pub points: Vec<Point>,
}

/// One point of a sweep.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Point {
    /// Which knob (`preset` for the presets themselves).
    pub sweep: String,
    /// Its value.
    pub value: String,
    /// The preset it starts from.
    pub preset: String,
    /// Figures, by report key.
    #[serde(flatten)]
    pub figures: BTreeMap<&'static str, f64>,
    /// On the error-versus-size Pareto front.
    pub pareto_size: bool,
    /// On the error-versus-move-time Pareto front.
    pub pareto_move: bool,
}

/// The screen-space section.
#[derive(Serialize)]
pub struct SsdoSection {
    pub device: String,
    pub cpu_threads: usize,
    pub timing_resolution: [u32; 2],
    pub eval_resolution: [u32; 2],
    pub samples: usize,
    pub sets: usize,
    pub radius: String,
    pub reference: String,
    pub scenes: BTreeMap<String, SsdoScene>,
    /// The first scene's (the teapot's when it ran) GPU times and errors, at the top.
    pub ms_ssao: Option<f64>,
    pub ms_ssdo: Option<f64>,
    pub cost_ratio_vs_ssao: Option<f64>,
    pub rel_l2_ssao: Option<f64>,
    pub rel_l2_ssdo: Option<f64>,
    pub rel_l2_ssdo_peeled: Option<f64>,
}

/// One scene in screen space.
#[derive(Serialize, Clone)]
pub struct SsdoScene {
    #[serde(flatten)]
    pub gpu: Option<SsdoGpu>,
    pub rel_l2_ssao: f64,
    pub rel_l2_ssdo: f64,
    pub rel_l2_ssdo_peeled: f64,
    pub ms_ssao_cpu: f64,
    pub ms_ssdo_cpu: f64,
    pub ms_ssdo_peeled_cpu: f64,
    pub cost_ratio_vs_ssao_cpu: f64,
    pub reference_s: f64,
    pub vertices: usize,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub grey_albedo_objects: Vec<String>,
}

/// The WGSL passes' times on the first adapter.
#[derive(Serialize, Clone)]
pub struct SsdoGpu {
    pub gpu_adapter: String,
    /// Every pass submitted and waited for alone (median ms), by pass label.
    pub passes_ms_ssao: BTreeMap<String, f64>,
    pub passes_ms_ssdo: BTreeMap<String, f64>,
    pub passes_ms_ssdo_peeled: BTreeMap<String, f64>,
    pub ms_ssao: f64,
    pub ms_ssdo: f64,
    pub ms_ssdo_peeled: f64,
    pub cost_ratio_vs_ssao: f64,
}

/// The plant-leaf section.
#[derive(Serialize)]
pub struct LeavesSection {
    pub vertices_100k: usize,
    pub vertices_500k: usize,
    pub quick: bool,
    pub rle_ratio: f64,
    pub rle_ratio_cosine_baked: f64,
    pub lvc_raw_bytes: usize,
    pub lvc_rle_bytes: usize,
    pub lvc_s: f64,
    pub prt_s: f64,
    pub prt_rays: u32,
    pub transfer_bytes: usize,
    pub decode_ms_100k: f64,
    pub shade_ms_100k: f64,
    pub shade_ms_500k: f64,
    /// A sun move's preparation: the maps around the sun decoded and blended.
    pub sun_change_ms_100k: f64,
    pub sun_change_ms_500k: f64,
    pub prt_s_500k: f64,
    pub rel_l2_lvc_prt: f64,
    pub rel_l2_sh_only: f64,
    pub reference_noise_rel_l2: f64,
    pub reference_vertices: usize,
    pub reference_paths: u32,
    pub reference_s: f64,
    pub goals: LeafGoals,
    pub images: Vec<PathBuf>,
}

/// The leaf renderer's goals (the paper's figures).
#[derive(Serialize)]
pub struct LeafGoals {
    pub rle_ratio_min: f64,
    pub decode_ms_100k_max: f64,
    pub shade_ms_100k_max: f64,
    pub shade_ms_500k_max: f64,
    /// The two passes against the path tracer at 100k vertices (issue 28).
    pub rel_l2_lvc_prt_max: f64,
}

impl LeafGoals {
    pub const PAPER: LeafGoals = LeafGoals {
        rle_ratio_min: 8.0,
        decode_ms_100k_max: 2.0,
        shade_ms_100k_max: 28.0,
        shade_ms_500k_max: 100.0,
        rel_l2_lvc_prt_max: 0.08,
    };
}

/// One row of a Markdown table: its cells between pipes, with a newline.
pub fn md_row<I: IntoIterator<Item = String>>(cells: I) -> String {
    let cells: Vec<String> = cells.into_iter().collect();
    format!("| {} |\n", cells.join(" | "))
}

/// Writes `value` as pretty JSON to `path` whole (a temporary file renamed into place).
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<()> {
    write_atomic(path, serde_json::to_string_pretty(value)?.as_bytes())
}

/// Replaces section `key` of the report at `path` (kept otherwise; created when absent).
pub fn replace_section(path: &Path, key: &str, section: &impl Serialize) -> Result<()> {
    let mut report: serde_json::Map<String, serde_json::Value> = match std::fs::read_to_string(path) {
        Ok(text) => serde_json::from_str(&text).with_context(|| format!("{}", path.display()))?,
        Err(_) => serde_json::Map::new(),
    };
    report.insert(key.into(), serde_json::to_value(section)?);
    write_json(path, &report)
}

pub use vcuts::files::write_atomic;
