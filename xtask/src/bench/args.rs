//! The bench's options, and which sections a run measures: `--only SECTION` (one, replacing
//! it in an earlier report) or `--sections LIST` (those beside Table 1, default all). The
//! `--only-X` and `--no-X` flags of earlier versions still work, hidden, and map to these.

use anyhow::{Result, bail};
use std::path::PathBuf;

/// A section of the report beside Table 1.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Section {
    /// One knob at a time from a base preset: error against data size and move time.
    Tradeoff,
    /// SSAO / SSDO against the ray-traced reference.
    Ssdo,
    /// The plant-leaf renderer (LVC + PRT against the path-traced reference).
    Leaves,
    /// How every cost grows with objects and vertices.
    Scaling,
    /// Drags in dense assemblies against the same objects apart, and the engine's piston.
    Assembly,
    /// Every map, both scenes, each preset, at rest and moved.
    Accuracy,
    /// A precompute whole and sharded, gathered; the projection over M nodes.
    Distributed,
    /// Objects turning through a symmetric direction set: a turn step beside a translation
    /// step, and the error after turns.
    Turns,
}

impl Section {
    /// Every section, in the order a full run measures them.
    pub const ALL: [Section; 8] = [
        Section::Tradeoff,
        Section::Ssdo,
        Section::Leaves,
        Section::Scaling,
        Section::Assembly,
        Section::Accuracy,
        Section::Distributed,
        Section::Turns,
    ];

    /// Its key in `report.json` and its name on the command line.
    pub fn key(self) -> &'static str {
        match self {
            Section::Tradeoff => "tradeoff",
            Section::Ssdo => "ssdo",
            Section::Leaves => "leaves",
            Section::Scaling => "scaling",
            Section::Assembly => "assembly",
            Section::Accuracy => "accuracy",
            Section::Distributed => "distributed",
            Section::Turns => "turns",
        }
    }
}

/// What a run measures.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Plan {
    /// One section, replacing it in `OUT/report.json`.
    Only(Section),
    /// Table 1 and these sections, into a new report.
    Full(Vec<Section>),
}

/// Arguments of `bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// A first look in a few minutes: smaller presets (named in each scene's `preset`).
    #[arg(long)]
    pub quick: bool,
    /// Output folder.
    #[arg(long, default_value = "target/report")]
    pub out: PathBuf,
    /// Scenes (built-in names), comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "teapot,bunny")]
    pub scenes: Vec<String>,
    /// Skip the Monte Carlo reference (its key is then null).
    #[arg(long)]
    pub no_mc: bool,
    /// Measure only this section, replacing it in OUT/report.json (the rest of an earlier
    /// report is kept).
    #[arg(long, value_enum, conflicts_with_all = ["sections", "plot_only"])]
    pub only: Option<Section>,
    /// The sections a full run measures beside Table 1, comma-separated (default: all of them;
    /// `none` for Table 1 alone).
    #[arg(long, value_delimiter = ',', value_parser = parse_section)]
    pub sections: Option<Vec<Option<Section>>>,
    /// The scaling section's object counts (default 1,2,4,…,64; with --quick 1,2,4,8).
    #[arg(long, value_delimiter = ',')]
    pub scaling_objects: Option<Vec<usize>>,
    /// The presets of the scaling section's object sweep (default fast,balanced; with --quick
    /// fast).
    #[arg(long, value_delimiter = ',')]
    pub scaling_presets: Option<Vec<String>>,
    /// The vertex sweep's teapot tessellations, quads per patch edge (default 18,36,74,186:
    /// ~12k, 43k, 177k and 1.1M vertices with the ground; with --quick 9,18).
    #[arg(long, value_delimiter = ',')]
    pub scaling_tessellations: Option<Vec<u32>>,
    /// Reuse a scene's data file from an earlier run (and the precompute figures kept beside
    /// it) instead of precomputing again: to re-time frames after a change to shading. The
    /// accuracy section keeps the rows of `OUT/accuracy.json` and measures only what is missing.
    #[arg(long)]
    pub reuse: bool,
    /// Only redraw the trade-off plots from `OUT/tradeoff.csv`.
    #[arg(long)]
    pub plot_only: bool,
    /// Print the estimate of the bench's precomputes (time, data bytes, peak memory) and stop.
    #[arg(long)]
    pub dry_run: bool,
    /// Run even when the estimate exceeds the free memory or disk.
    #[arg(long)]
    pub force: bool,
    /// Earlier versions' `--only-X` flags (`--only X` now).
    #[command(flatten)]
    pub earlier: EarlierFlags,
}

/// The section flags of earlier versions, kept for scripts: `--no-X` skips section X, `--only-X`
/// is `--only X`.
#[derive(clap::Args, Default)]
pub struct EarlierFlags {
    #[arg(long, hide = true)]
    no_tradeoff: bool,
    #[arg(long, hide = true)]
    no_ssdo: bool,
    #[arg(long, hide = true)]
    no_leaves: bool,
    #[arg(long, hide = true)]
    no_scaling: bool,
    #[arg(long, hide = true)]
    no_accuracy: bool,
    #[arg(long, hide = true)]
    no_distributed: bool,
    #[arg(long, hide = true)]
    only_ssdo: bool,
    #[arg(long, hide = true)]
    only_leaves: bool,
    #[arg(long, hide = true)]
    only_scaling: bool,
    #[arg(long, hide = true)]
    only_accuracy: bool,
    #[arg(long, hide = true)]
    only_distributed: bool,
}

fn parse_section(s: &str) -> Result<Option<Section>, String> {
    use clap::ValueEnum;
    if s == "none" {
        return Ok(None);
    }
    Section::from_str(s, false).map(Some).map_err(|_| {
        let names: Vec<&str> = Section::ALL.iter().map(|s| s.key()).collect();
        format!("{s:?}: expected one of {} or none", names.join(", "))
    })
}

impl BenchArgs {
    /// What this run measures: one section, or Table 1 and the sections asked for; an error
    /// names the flags that contradict each other.
    pub fn plan(&self) -> Result<Plan> {
        let e = &self.earlier;
        let only_flags = [
            (e.only_ssdo, Section::Ssdo),
            (e.only_leaves, Section::Leaves),
            (e.only_scaling, Section::Scaling),
            (e.only_accuracy, Section::Accuracy),
            (e.only_distributed, Section::Distributed),
        ];
        let mut only: Vec<Section> = only_flags.iter().filter(|f| f.0).map(|f| f.1).collect();
        only.extend(self.only);
        only.dedup();
        let skipped = self.skipped();
        match only.as_slice() {
            [] => Ok(Plan::Full(self.full_sections())),
            [one] if skipped.contains(one) => bail!("--only {}: that section is also skipped", one.key()),
            [one] if self.plot_only => bail!("--only {}: --plot-only measures nothing", one.key()),
            [one] => Ok(Plan::Only(*one)),
            more => {
                let names: Vec<&str> = more.iter().map(|s| s.key()).collect();
                bail!("--only: one section at a time, not {}", names.join(" and "))
            }
        }
    }

    /// Whether a full run measures `section`.
    pub fn measures(&self, section: Section) -> bool {
        matches!(self.plan(), Ok(Plan::Full(s)) if s.contains(&section))
    }

    fn skipped(&self) -> Vec<Section> {
        let e = &self.earlier;
        [
            (e.no_tradeoff, Section::Tradeoff),
            (e.no_ssdo, Section::Ssdo),
            (e.no_leaves, Section::Leaves),
            (e.no_scaling, Section::Scaling),
            (e.no_accuracy, Section::Accuracy),
            (e.no_distributed, Section::Distributed),
        ]
        .iter()
        .filter(|f| f.0)
        .map(|f| f.1)
        .collect()
    }

    fn full_sections(&self) -> Vec<Section> {
        let asked: Vec<Section> = match &self.sections {
            Some(list) => list.iter().flatten().copied().collect(),
            None => Section::ALL.to_vec(),
        };
        let skipped = self.skipped();
        Section::ALL.into_iter().filter(|s| asked.contains(s) && !skipped.contains(s)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        bench: BenchArgs,
    }

    fn plan(args: &[&str]) -> Result<Plan> {
        Cli::try_parse_from(std::iter::once("bench").chain(args.iter().copied()))
            .map_err(|e| anyhow::anyhow!("{e}"))?
            .bench
            .plan()
    }

    #[test]
    fn sections_only_and_the_earlier_flags_give_one_plan() {
        assert_eq!(plan(&[]).unwrap(), Plan::Full(Section::ALL.to_vec()));
        assert_eq!(plan(&["--only", "scaling"]).unwrap(), Plan::Only(Section::Scaling));
        assert_eq!(plan(&["--only-scaling"]).unwrap(), Plan::Only(Section::Scaling));
        assert_eq!(
            plan(&["--sections", "accuracy,leaves"]).unwrap(),
            Plan::Full(vec![Section::Leaves, Section::Accuracy])
        );
        assert_eq!(plan(&["--sections", "none"]).unwrap(), Plan::Full(vec![]));
        let rest = vec![
            Section::Ssdo,
            Section::Leaves,
            Section::Scaling,
            Section::Assembly,
            Section::Accuracy,
            Section::Distributed,
            Section::Turns,
        ];
        assert_eq!(plan(&["--no-tradeoff"]).unwrap(), Plan::Full(rest));
        for bad in [&["--only-ssdo", "--only-leaves"][..], &["--only", "ssdo", "--no-ssdo"], &["--only", "fast"]] {
            assert!(plan(bad).is_err(), "{bad:?}");
        }
        assert!(plan(&["--only", "leaves", "--sections", "ssdo"]).is_err());
    }
}
