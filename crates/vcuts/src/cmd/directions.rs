//! `vcuts directions`: point-repulsion directions, their uniformity, and optionally the
//! direction tree and light tree over them.

use anyhow::{Context, Result};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;
use vcut_dirtree::DirectionTree;
use vcut_lighttree::LightTreeBuilder;
use vcut_sphere::{CacheOutcome, DirectionSet, RepulsionParams, Start};

/// Arguments of `directions`.
#[derive(clap::Args)]
pub struct DirectionsArgs {
    /// Number of directions (a power of two for the tree: 2^6 .. 2^20).
    #[arg(long, default_value_t = 32768, value_parser = crate::options::whole::<usize>("n"), allow_hyphen_values = true)]
    pub n: usize,
    /// Seed of the start.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Start: fibonacci or random.
    #[arg(long, default_value = "fibonacci", value_parser = parse_start)]
    pub start: Start,
    /// Make the set symmetric under turns by 360°/WEDGES about +Y (a power of two dividing N;
    /// 1: no symmetry), as `turn_steps` does in a precompute.
    #[arg(long, default_value_t = 1, value_parser = crate::options::whole::<u32>("wedges"), allow_hyphen_values = true)]
    pub wedges: u32,
    /// With --wedges: bands of latitude the tree splits into above the wedges (a power of two;
    /// 0: chosen as `turn_bands` chooses them in a precompute).
    #[arg(long, default_value_t = 0, value_parser = crate::options::whole::<u32>("bands"), allow_hyphen_values = true)]
    pub bands: u32,
    /// Cache folder for generated sets.
    #[arg(long, default_value = "target/vcut-cache")]
    pub cache_dir: PathBuf,
    /// Regenerate even if cached (and do not write the cache).
    #[arg(long)]
    pub no_cache: bool,
    /// Also build the direction tree and the light tree of this environment map
    /// (a file, a cube folder, builtin:sky or builtin:studio).
    #[arg(long)]
    pub env: Option<String>,
}

/// What `directions` generated and measured.
#[derive(Debug, Clone, Serialize)]
pub struct DirectionsOutcome {
    /// Directions.
    pub n: usize,
    /// The start: `fibonacci` or `random`.
    pub start: &'static str,
    /// Its seed.
    pub seed: u64,
    /// Wedges of its symmetry about +Y (1: none).
    pub wedges: u32,
    /// The cache: `hit PATH`, `stored PATH`, `replaced PATH (why)` or `off`.
    pub cache: String,
    /// Repulsion iterations (when generated).
    pub iterations: Option<u64>,
    /// Subdivision levels (when generated).
    pub levels: Option<u32>,
    /// Whether the repulsion converged (when generated).
    pub converged: Option<bool>,
    /// Seconds to generate or load.
    pub generate_s: f64,
    /// The ideal spacing of N points on the sphere.
    pub ideal_spacing_rad: f64,
    /// The smallest nearest-neighbour distance.
    pub min_nn_rad: f64,
    /// The mean nearest-neighbour distance.
    pub mean_nn_rad: f64,
    /// Their ratio.
    pub min_nn_ratio: f64,
    /// The mean over the ideal.
    pub mean_nn_over_ideal: f64,
    /// The smallest over the ideal.
    pub min_nn_over_ideal: f64,
    /// The coefficient of variation of the Voronoi cells' areas.
    pub cv_cell_area: f64,
    /// The smallest cell over the mean.
    pub cell_area_min_over_mean: f64,
    /// The largest cell over the mean.
    pub cell_area_max_over_mean: f64,
    /// How far the cells' areas sum from 4π.
    pub cell_area_sum_error: f64,
    /// The χ² of the directions over equal-area bins.
    pub chi2: f64,
    /// Its degrees of freedom.
    pub chi2_dof: usize,
    /// Its p-value.
    pub chi2_p: f64,
    /// Seconds for the statistics.
    pub stats_s: f64,
    /// The direction and light trees (with `--env`).
    #[serde(flatten)]
    pub trees: Option<TreesOutcome>,
}

/// The direction tree and the light tree of a map over the directions.
#[derive(Debug, Clone, Serialize)]
pub struct TreesOutcome {
    /// Seconds to build the direction tree.
    pub tree_build_s: f64,
    /// Its height.
    pub tree_height: u32,
    /// Seconds to build the light tree's lookup table.
    pub light_table_s: f64,
    /// Seconds for the exact light tree (2×2 sub-texel patches binned to their nearest leaf).
    pub light_tree_exact_s: f64,
    /// The interactive build's median time.
    pub light_tree_build_ms_median: f64,
    /// The exact tree's root against the map's power.
    pub light_root_rel_error_exact: f64,
    /// The interactive tree's root against the map's power.
    pub light_root_rel_error_fast: f64,
    /// The interactive tree's leaves against texel-centre binning, over the total (green).
    pub light_leaves_l1_fast_vs_centres: f64,
    /// The same against 2×2 sub-texel binning.
    pub light_leaves_l1_fast_vs_subtexel: f64,
}

fn parse_start(s: &str) -> Result<Start, String> {
    match s {
        "fibonacci" => Ok(Start::Fibonacci),
        "random" => Ok(Start::Random),
        _ => Err(format!("{s:?}: expected fibonacci or random")),
    }
}

/// The options that shape the set, for its errors.
fn options(args: &DirectionsArgs) -> String {
    format!("--n {} --start {} --wedges {}", args.n, args.start.name(), args.wedges)
}

/// Runs `directions`.
pub fn run(args: &DirectionsArgs) -> Result<DirectionsOutcome> {
    let start = args.start;
    let params = match start {
        Start::Fibonacci => RepulsionParams { seed: args.seed, ..RepulsionParams::default() },
        Start::Random => RepulsionParams::random(args.seed),
    };
    let params = RepulsionParams { wedges: args.wedges, ..params };
    let bar = crate::progress::Bar::spinner("repulsion");
    let progress = |it: u32, rms: f64| {
        if it.is_multiple_of(5) {
            bar.set_message(format!("iteration {it}, rms step {rms:.2e} spacings"));
        }
    };
    let t = Instant::now();
    let (set, cache) = if args.no_cache {
        (DirectionSet::generate(args.n, &params, progress).with_context(|| options(args))?, None)
    } else {
        let (s, c) = DirectionSet::load_or_generate(&args.cache_dir, args.n, &params, progress)
            .with_context(|| options(args))?;
        (s, Some(c))
    };
    let generate_s = t.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let t = Instant::now();
    let u = set.uniformity();
    let stats_s = t.elapsed().as_secs_f64();
    let r = set.report();
    let generated = !matches!(cache, Some(CacheOutcome::Hit(_)));
    Ok(DirectionsOutcome {
        n: u.n,
        start: start.name(),
        seed: args.seed,
        wedges: set.wedges(),
        cache: match &cache {
            Some(CacheOutcome::Hit(p)) => format!("hit {}", p.display()),
            Some(CacheOutcome::Stored(p)) => format!("stored {}", p.display()),
            Some(CacheOutcome::Replaced(p, why)) => format!("replaced {} ({why})", p.display()),
            None => "off".into(),
        },
        iterations: generated.then_some(u64::from(r.total_iterations)),
        levels: generated.then_some(r.levels),
        converged: generated.then_some(r.converged),
        generate_s,
        ideal_spacing_rad: u.ideal_spacing,
        min_nn_rad: u.min_nn,
        mean_nn_rad: u.mean_nn,
        min_nn_ratio: u.min_nn_ratio,
        mean_nn_over_ideal: u.mean_nn / u.ideal_spacing,
        min_nn_over_ideal: u.min_nn / u.ideal_spacing,
        cv_cell_area: u.cv_cell_area,
        cell_area_min_over_mean: u.cell_area_range.0,
        cell_area_max_over_mean: u.cell_area_range.1,
        cell_area_sum_error: u.cell_area_sum_error,
        chi2: u.chi2,
        chi2_dof: u.chi2_dof,
        chi2_p: u.chi2_p,
        stats_s,
        trees: args.env.as_deref().map(|env| trees(&set, args.bands, env)).transpose()?,
    })
}

/// The direction tree over `set` and the light tree of the map `env` over it, timed and checked.
fn trees(set: &DirectionSet, bands: u32, env: &str) -> Result<TreesOutcome> {
    let map = crate::inspect::load_envmap(env)?;
    let t = Instant::now();
    let tree = match set.wedges() {
        1 => DirectionTree::build(set.directions(), &set.cell_areas())?,
        m => {
            let bands = if bands == 0 { DirectionTree::default_bands(set.len(), m) } else { bands };
            DirectionTree::build_wedged(set.directions(), &set.cell_areas(), m, bands)
                .with_context(|| format!("--wedges {m} --bands {bands}"))?
        }
    };
    let tree_build_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let mut builder = LightTreeBuilder::new(&tree);
    let light_table_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let exact = builder.build_exact(&map, 2);
    let light_tree_exact_s = t.elapsed().as_secs_f64();
    let mut times = Vec::new();
    let mut fast = builder.build(&map);
    for _ in 0..9 {
        let t = Instant::now();
        fast = builder.build(&map);
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let total = map.total_power();
    let rel = |a: [f64; 3]| (0..3).map(|i| ((a[i] - total[i]) / total[i]).abs()).fold(0.0, f64::max);
    // Leaf differences as a share of the total (green): the fast build against exact
    // texel-centre binning (the table's own error) and against 2×2 sub-texel binning.
    let l1 = |a: &vcut_lighttree::LightTree, b: &vcut_lighttree::LightTree| {
        a.leaves().iter().zip(b.leaves()).map(|(x, y)| (x[1] - y[1]).abs()).sum::<f64>() / total[1]
    };
    let exact1 = builder.build_exact(&map, 1);
    Ok(TreesOutcome {
        tree_build_s,
        tree_height: tree.height(),
        light_table_s,
        light_tree_exact_s,
        light_tree_build_ms_median: vcut_shade::measure::median(times),
        light_root_rel_error_exact: rel(exact.root()),
        light_root_rel_error_fast: rel(fast.root()),
        light_leaves_l1_fast_vs_centres: l1(&fast, &exact1),
        light_leaves_l1_fast_vs_subtexel: l1(&fast, &exact),
    })
}
