//! A plant's leaf data — the sun's light-visibility maps and the SH transfer — kept in a
//! `.vleaf` file: loaded when it holds them, else estimated (checked against the free memory
//! and disk), computed, resuming a partial file, and saved; and what that did, as report keys.

use super::plant::PlantArgs;
use crate::progress::Bar;
use crate::resources::EstimateArgs;
use anyhow::Result;
use serde::Serialize;
use std::path::{Path, PathBuf};
use vcut_leaf::lvc::LvcParams;
use vcut_leaf::prt::PrtParams;
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::LeafData;
use vcut_leaf::store::{Inputs, LeafEstimate, Reuse};
use vcut_scene::budget::human;

/// A progress bar over a plant's vertices.
pub fn bar(len: usize, what: &str) -> Bar {
    Bar::new(what, len as u64, "vertices")
}

/// Everything precomputed for a scene.
pub struct Precomputed {
    /// The LVC maps and the SH transfer.
    pub data: LeafData,
    /// Seconds: LVC, PRT (0 when loaded).
    pub seconds: (f64, f64),
    /// Where they are saved, and what loading, resuming or computing them did.
    pub file: PathBuf,
    /// What the store did.
    pub outcome: vcut_leaf::store::Outcome,
    /// The estimate, when they were computed, and how it compared.
    pub estimate: Option<(LeafEstimateOutcome, AgainstOutcome)>,
}

/// The `.vleaf` file of these inputs: `--leaf-data`, else `target/vleaf/<plant>-<inputs' CRC>.vleaf`.
pub fn data_path(args: &PlantArgs, inputs: &Inputs<'_>) -> PathBuf {
    args.leaf_data.clone().unwrap_or_else(|| {
        let name = args.plant.to_string();
        let stem: String = Path::new(&name)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "plant".into())
            .chars()
            .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_')
            .collect();
        PathBuf::from("target/vleaf").join(inputs.file_name(&stem))
    })
}

/// What [`precompute`] gives: the data, or after a dry run the estimate (none when the file
/// already holds the data).
pub enum Prepared {
    /// The data, loaded or computed.
    Ready(Box<Precomputed>),
    /// A dry run: nothing computed.
    DryRun(Option<LeafEstimateOutcome>),
}

impl Prepared {
    /// The data, unless this was a dry run.
    pub fn ready(self) -> Option<Precomputed> {
        match self {
            Prepared::Ready(p) => Some(*p),
            Prepared::DryRun(_) => None,
        }
    }
}

/// The LVC maps (every sun direction, or only `suns`) and the transfer of `scene`, in `file`:
/// loaded when it holds them (and `reuse` allows), else estimated (logged, checked against the
/// free memory and disk), computed — resuming a partial file — and saved there.
pub fn precompute(
    scene: &LeafScene,
    (lvc, prt): (&LvcParams, &PrtParams),
    suns: Option<&[usize]>,
    file: &Path,
    reuse: Reuse,
    est: EstimateArgs,
) -> Result<Prepared> {
    let inputs = Inputs { scene, lvc: *lvc, prt: *prt, suns };
    let loads = reuse == Reuse::IfMatching && file.exists() && vcut_leaf::store::holds(file, &inputs).is_ok();
    let estimate = (!loads).then(|| vcut_leaf::store::estimate(&inputs, est.budget()));
    if let Some(e) = &estimate {
        log::info!("{}", LeafEstimateOutcome::sentence(e));
        crate::resources::check("the leaf precompute", e.peak_bytes, (file, e.output_bytes), est.force)?;
        if est.dry_run {
            return Ok(Prepared::DryRun(Some(LeafEstimateOutcome::of(e))));
        }
    } else if est.dry_run {
        log::info!("estimate: nothing to compute: {} holds this plant's leaf data", file.display());
        return Ok(Prepared::DryRun(None));
    }
    let bars = [bar(scene.vertex_count(), "LVC"), bar(scene.vertex_count(), "PRT")];
    let progress = |stage: &str, done: usize, _total: usize| {
        bars[usize::from(stage == "PRT")].set_position(done as u64);
    };
    let (data, outcome) = vcut_leaf::store::precompute(&inputs, file, reuse, &progress)?;
    bars.iter().for_each(Bar::finish_and_clear);
    if let Some(why) = &outcome.replaced {
        log::info!("leaf data: not reused ({why}); computed again");
    }
    let seconds = (outcome.lvc_s, outcome.prt_s);
    let estimate = estimate
        .map(|e| (LeafEstimateOutcome::of(&e), AgainstOutcome::of(&e, seconds.0 + seconds.1, outcome.file_bytes)));
    Ok(Prepared::Ready(Box::new(Precomputed { data, seconds, file: file.into(), outcome, estimate })))
}

/// The leaf precompute's estimate.
#[derive(Debug, Clone, Serialize)]
pub struct LeafEstimateOutcome {
    /// Vertices.
    pub estimate_vertices: u64,
    /// Rays.
    pub estimate_rays: u64,
    /// Seconds of the maps.
    pub estimate_lvc_s: f64,
    /// Seconds of the transfer.
    pub estimate_prt_s: f64,
    /// The file's size.
    pub estimate_output_mb: f64,
    /// The peak memory.
    pub estimate_peak_mb: f64,
    /// The sample's seconds.
    pub estimate_sample_s: f64,
}

impl LeafEstimateOutcome {
    /// The keys of `e`.
    pub fn of(e: &LeafEstimate) -> LeafEstimateOutcome {
        LeafEstimateOutcome {
            estimate_vertices: e.vertices,
            estimate_rays: e.lvc_rays + e.prt_rays,
            estimate_lvc_s: e.lvc_seconds,
            estimate_prt_s: e.prt_seconds,
            estimate_output_mb: e.output_bytes as f64 / 1e6,
            estimate_peak_mb: e.peak_bytes as f64 / 1e6,
            estimate_sample_s: e.sampled.2,
        }
    }

    /// The estimate as a sentence, for the log before the run.
    pub fn sentence(e: &LeafEstimate) -> String {
        let (lv, pv, ss) = e.sampled;
        format!(
            "estimate: {} vertices, {:.1} M rays; about {:.1} s on {} threads (LVC {:.1} s, PRT {:.1} s); file {}; \
             peak memory {} (from a {ss:.1} s sample of {lv} + {pv} vertices)",
            e.vertices,
            (e.lvc_rays + e.prt_rays) as f64 / 1e6,
            e.lvc_seconds + e.prt_seconds,
            rayon::current_num_threads(),
            e.lvc_seconds,
            e.prt_seconds,
            human(e.output_bytes),
            human(e.peak_bytes),
        )
    }
}

/// The computed figures against the estimate's.
#[derive(Debug, Clone, Serialize)]
pub struct AgainstOutcome {
    /// The process's peak memory.
    pub peak_rss_mb: f64,
    /// Estimated seconds over actual.
    pub estimate_vs_actual_s: f64,
    /// Estimated output bytes over actual.
    pub estimate_vs_actual_output: f64,
    /// Estimated peak memory over actual.
    pub estimate_vs_actual_peak: Option<f64>,
}

impl AgainstOutcome {
    fn of(e: &LeafEstimate, seconds: f64, file_bytes: u64) -> AgainstOutcome {
        let peak = vcut_scene::budget::peak_memory().unwrap_or(0);
        AgainstOutcome {
            peak_rss_mb: peak as f64 / 1e6,
            estimate_vs_actual_s: (e.lvc_seconds + e.prt_seconds) / seconds.max(1e-9),
            estimate_vs_actual_output: e.output_bytes as f64 / file_bytes.max(1) as f64,
            estimate_vs_actual_peak: (peak > 0).then(|| e.peak_bytes as f64 / peak as f64),
        }
    }
}

/// Where the leaf data is and what was done to get it.
#[derive(Debug, Clone, Serialize)]
pub struct StoreOutcome {
    /// The `.vleaf` file.
    pub leaf_data: PathBuf,
    /// Whether it was loaded (else computed).
    pub leaf_data_loaded: bool,
    /// Its size.
    pub leaf_data_bytes: u64,
    /// Seconds to load it.
    pub leaf_data_load_s: Option<f64>,
    /// Map chunks a computation resumed from a partial file.
    pub lvc_chunks_resumed: Option<usize>,
}

impl StoreOutcome {
    /// What `pre`'s store did.
    pub fn of(pre: &Precomputed) -> StoreOutcome {
        let o = &pre.outcome;
        StoreOutcome {
            leaf_data: pre.file.clone(),
            leaf_data_loaded: o.loaded,
            leaf_data_bytes: o.file_bytes,
            leaf_data_load_s: o.loaded.then_some(o.load_s),
            lvc_chunks_resumed: (!o.loaded).then_some(o.lvc_chunks_resumed),
        }
    }
}
