//! [`FrameSettings`] as command-line options (the feature `clap`): what `vcuts render`, `vcuts
//! view` and the examples flatten into their arguments. Every value is checked as it is parsed,
//! so a bad one is clap's error naming the option.

use super::settings::{FieldReach, FlatEdges, FrameCaches, FrameSettings, algorithm_named};
use vcut_data::InsideSamples;
use vcut_merge::Algorithm as MergeAlgorithm;

/// A frame's settings on the command line; each option left out keeps
/// [`FrameSettings::default`]'s value.
#[derive(clap::Args, Debug, Clone, Default, PartialEq)]
pub struct FrameArgs {
    /// Field samples inside an object: `occluded` (blended in as fully occluded, the default)
    /// or `dropped` (their weight given to the others); see `vcut_data::InsideSamples`.
    #[arg(long, value_name = "occluded|dropped", value_parser = parse_inside)]
    pub inside_samples: Option<InsideSamples>,
    /// Keep a field in a vertex's product even when its object lies wholly below the vertex's
    /// horizon (the paper's product of every field within reach).
    #[arg(long)]
    pub no_horizon_culling: bool,
    /// How far a field shadows, in its object's bounding radii (default 6), or `outermost`:
    /// to its outermost sphere (the precompute's `field_outer`, the paper's reach).
    #[arg(long, value_name = "RADII|outermost", allow_hyphen_values = true)]
    pub field_reach: Option<FieldReach>,
    /// How finely a ground's cut follows its edges: a node of at most N leaves across an edge
    /// takes its estimated visible share (a power of two; default 1, exact); `interactive` is
    /// 1/256 of the directions (128 at the paper preset, 16 at `fast`).
    #[arg(long, value_name = "N|interactive", allow_hyphen_values = true)]
    pub flat_edge_leaves: Option<FlatEdges>,
    /// Merge every vertex a move changes at once. By default a move merges the vertices facing
    /// the camera and leaves the others until a camera sees them: the image is the same bit
    /// for bit.
    #[arg(long)]
    pub eager_merges: bool,
    /// The merge moves use: `counter` (the paper's, the default) or `index` (the baseline);
    /// the same cuts bit for bit.
    #[arg(long, value_name = "counter|index", value_parser = parse_algorithm)]
    pub merge_algorithm: Option<MergeAlgorithm>,
    /// Carry the sun through the cuts too, as the paper does. By default the leaves of the
    /// light whose error through the cuts is largest are cast by rays at run time, until the
    /// estimated error is within `--light-error`.
    #[arg(long, conflicts_with_all = ["light_error", "light_max_leaves"])]
    pub no_sun_rays: bool,
    /// Target relative error of the light left in the cuts (default: the scene file's
    /// `[environment] light_error`, else 0.002): the brightest leaves are cast by rays until
    /// the estimated error is within it. Must lie in (0, 1).
    #[arg(long, value_name = "REL", value_parser = parse_light_error, allow_hyphen_values = true)]
    pub light_error: Option<f64>,
    /// At most this many leaves of the light cast by rays (1 to 64; default 32). Each costs a ray
    /// per vertex facing it on a lighting change and a move, and a BRDF evaluation per vertex
    /// facing it on every shading.
    #[arg(long, value_name = "N", value_parser = parse_max_leaves, allow_hyphen_values = true)]
    pub light_max_leaves: Option<u8>,
    /// Keep no merged cut per vertex, only its shading list: less memory (the merged cuts are
    /// the frame's largest part), the same moves, edits and image; a lighting change or a
    /// camera turn merges the vertices it relists again.
    #[arg(long)]
    pub no_merged_cache: bool,
    /// Caches the frame does not keep, comma-separated: `stored` (the file's cuts stay in the
    /// file), `svc` (SVCs decoded at every merge), `cells` (no field cells between moves),
    /// `merged` (as --no-merged-cache).
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = ["stored", "svc", "cells", "merged"])]
    pub no_cache: Vec<String>,
    /// Hold the frame's memory (`frame_memory_mb`) to MB: the stored cuts stay in the file
    /// (read from it as merges need them), no merged cuts and no field cells between moves are
    /// kept, and the decoded SVCs only if they fit; `frame_caches` says which are kept.
    #[arg(long, value_name = "MB", value_parser = parse_budget, conflicts_with = "no_merged_cache", allow_hyphen_values = true)]
    pub memory_budget: Option<u64>,
}

impl FrameArgs {
    /// The settings these options ask for, every other one at its default.
    pub fn settings(&self) -> FrameSettings {
        let d = FrameSettings::default();
        let mut caches = if self.no_merged_cache { FrameCaches { merged: false, ..d.caches } } else { d.caches };
        for name in &self.no_cache {
            caches = caches.without(name).unwrap_or(caches);
        }
        FrameSettings {
            inside_samples: self.inside_samples.unwrap_or(d.inside_samples),
            horizon_culling: !self.no_horizon_culling,
            field_reach: self.field_reach.unwrap_or(d.field_reach),
            flat_edge_leaves: self.flat_edge_leaves.unwrap_or(d.flat_edge_leaves),
            deferred_merges: !self.eager_merges,
            merge_algorithm: self.merge_algorithm.unwrap_or(d.merge_algorithm),
            sun_rays: !self.no_sun_rays,
            light_error: self.light_error,
            light_max_leaves: self.light_max_leaves.map_or(d.light_max_leaves, usize::from),
            caches,
            memory_budget: self.memory_budget,
        }
    }

    /// The option that sets the [`FrameSettings`] field `key` (for errors found once the data
    /// is read, such as flat edge leaves above the number of directions).
    pub fn option(key: &str) -> String {
        match key {
            "horizon_culling" => "--no-horizon-culling".into(),
            "deferred_merges" => "--eager-merges".into(),
            "sun_rays" => "--no-sun-rays".into(),
            "caches" => "--no-cache".into(),
            _ => format!("--{}", key.replace('_', "-")),
        }
    }
}

fn parse_inside(s: &str) -> Result<InsideSamples, String> {
    InsideSamples::named(s).ok_or_else(|| format!("{s:?}: expected `occluded` or `dropped`"))
}

fn parse_algorithm(s: &str) -> Result<MergeAlgorithm, String> {
    algorithm_named(s).ok_or_else(|| format!("{s:?}: expected `counter` or `index`"))
}

fn parse_max_leaves(s: &str) -> Result<u8, String> {
    super::settings::LIGHT_MAX_LEAVES.parse_whole(s).map(|n| n as u8)
}

fn parse_light_error(s: &str) -> Result<f64, String> {
    vcut_scene::check::LIGHT_ERROR.parse(s)
}

/// Megabytes to bytes ([`super::settings::BUDGET_MB`]).
fn parse_budget(s: &str) -> Result<u64, String> {
    super::settings::BUDGET_MB.parse(s).map(|mb| ((mb * 1e6) as u64).max(1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        frame: FrameArgs,
    }

    fn parse(args: &[&str]) -> Result<FrameSettings, String> {
        Cli::try_parse_from(std::iter::once("x").chain(args.iter().copied()))
            .map(|c| c.frame.settings())
            .map_err(|e| e.to_string())
    }

    #[test]
    fn no_option_is_the_default_settings() {
        assert_eq!(parse(&[]).unwrap(), FrameSettings::default());
    }

    #[test]
    fn every_option_sets_its_field() {
        let s = parse(&[
            "--inside-samples",
            "dropped",
            "--no-horizon-culling",
            "--field-reach",
            "outermost",
            "--flat-edge-leaves",
            "interactive",
            "--eager-merges",
            "--merge-algorithm",
            "index",
            "--light-error",
            "0.01",
            "--light-max-leaves",
            "8",
            "--no-cache",
            "stored,cells",
            "--memory-budget",
            "2.5",
        ])
        .unwrap();
        let want = FrameSettings {
            inside_samples: InsideSamples::Dropped,
            horizon_culling: false,
            field_reach: FieldReach::Outermost,
            flat_edge_leaves: FlatEdges::Interactive,
            deferred_merges: false,
            merge_algorithm: MergeAlgorithm::Index,
            sun_rays: true,
            light_error: Some(0.01),
            light_max_leaves: 8,
            caches: FrameCaches { stored: false, cells: false, ..FrameCaches::default() },
            memory_budget: Some(2_500_000),
        };
        assert_eq!(s, want);
        assert!(!parse(&["--no-sun-rays"]).unwrap().sun_rays);
        assert!(!parse(&["--no-merged-cache"]).unwrap().caches.merged);
    }

    #[test]
    fn bad_values_are_errors_naming_the_option() {
        for (args, option) in [
            (&["--field-reach", "nan"][..], "--field-reach"),
            (&["--field-reach", "-1"], "--field-reach"),
            (&["--light-error", "-0.5"], "--light-error"),
            (&["--flat-edge-leaves", "-2"], "--flat-edge-leaves"),
            (&["--flat-edge-leaves", "3"], "--flat-edge-leaves"),
            (&["--light-error", "inf"], "--light-error"),
            (&["--light-max-leaves", "65"], "--light-max-leaves"),
            (&["--memory-budget", "0"], "--memory-budget"),
            (&["--memory-budget", "1e300"], "--memory-budget"),
            (&["--no-cache", "lists"], "--no-cache"),
            (&["--merge-algorithm", "fast"], "--merge-algorithm"),
        ] {
            let e = parse(args).unwrap_err();
            assert!(e.contains(option), "{args:?}: {e}");
        }
    }
}
