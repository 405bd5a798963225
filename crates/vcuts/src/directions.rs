//! `cargo xtask directions`: point-repulsion directions, their uniformity, and optionally the
//! direction tree and light tree over them.

use anyhow::{Result, bail};
use std::path::PathBuf;
use std::time::Instant;
use vcut_dirtree::DirectionTree;
use vcut_lighttree::LightTreeBuilder;
use vcut_sphere::{CacheOutcome, DirectionSet, RepulsionParams, Start};

/// Arguments of `directions`.
#[derive(clap::Args)]
pub struct DirectionsArgs {
    /// Number of directions (a power of two for the tree: 2^6 .. 2^20).
    #[arg(long, default_value_t = 32768)]
    pub n: usize,
    /// Seed of the start.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Start: fibonacci or random.
    #[arg(long, default_value = "fibonacci")]
    pub start: String,
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

/// Runs `directions`.
pub fn run(args: &DirectionsArgs) -> Result<()> {
    let start = match args.start.as_str() {
        "fibonacci" => Start::Fibonacci,
        "random" => Start::Random,
        s => bail!("--start {s}: expected fibonacci or random"),
    };
    let params = match start {
        Start::Fibonacci => RepulsionParams { seed: args.seed, ..RepulsionParams::default() },
        Start::Random => RepulsionParams::random(args.seed),
    };
    let bar = crate::progress::Bar::spinner("repulsion");
    let progress = |it: u32, rms: f64| {
        if it.is_multiple_of(5) {
            bar.set_message(format!("iteration {it}, rms step {rms:.2e} spacings"));
        }
    };
    let t = Instant::now();
    let (set, cache) = if args.no_cache {
        (DirectionSet::generate(args.n, &params, progress)?, None)
    } else {
        let (s, c) = DirectionSet::load_or_generate(&args.cache_dir, args.n, &params, progress)?;
        (s, Some(c))
    };
    let gen_s = t.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let t = Instant::now();
    let u = set.uniformity();
    let stats_s = t.elapsed().as_secs_f64();
    let r = set.report();
    println!("n={}", u.n);
    println!("start={}", start.name());
    println!("seed={}", args.seed);
    match &cache {
        Some(CacheOutcome::Hit(p)) => println!("cache=hit {}", p.display()),
        Some(CacheOutcome::Stored(p)) => println!("cache=stored {}", p.display()),
        Some(CacheOutcome::Replaced(p, why)) => println!("cache=replaced {} ({why})", p.display()),
        None => println!("cache=off"),
    }
    if !matches!(cache, Some(CacheOutcome::Hit(_))) {
        println!("iterations={}", r.total_iterations);
        println!("levels={}", r.levels);
        println!("converged={}", r.converged);
    }
    println!("generate_s={gen_s:.3}");
    println!("ideal_spacing_rad={:.6e}", u.ideal_spacing);
    println!("min_nn_rad={:.6e}", u.min_nn);
    println!("mean_nn_rad={:.6e}", u.mean_nn);
    println!("min_nn_ratio={:.4}", u.min_nn_ratio);
    println!("mean_nn_over_ideal={:.4}", u.mean_nn / u.ideal_spacing);
    println!("min_nn_over_ideal={:.4}", u.min_nn / u.ideal_spacing);
    println!("cv_cell_area={:.5}", u.cv_cell_area);
    println!("cell_area_min_over_mean={:.4}", u.cell_area_range.0);
    println!("cell_area_max_over_mean={:.4}", u.cell_area_range.1);
    println!("cell_area_sum_error={:.3e}", u.cell_area_sum_error);
    println!("chi2={:.1}", u.chi2);
    println!("chi2_dof={}", u.chi2_dof);
    println!("chi2_p={:.4}", u.chi2_p);
    println!("stats_s={stats_s:.3}");
    if let Some(env) = &args.env {
        let map = crate::inspect::load_envmap(env)?;
        let t = Instant::now();
        let tree = DirectionTree::build(set.directions(), &set.cell_areas())?;
        println!("tree_build_s={:.3}", t.elapsed().as_secs_f64());
        println!("tree_height={}", tree.height());
        let t = Instant::now();
        let mut builder = LightTreeBuilder::new(&tree);
        println!("light_table_s={:.3}", t.elapsed().as_secs_f64());
        let t = Instant::now();
        let exact = builder.build_exact(&map, 2);
        println!("light_tree_exact_s={:.3}", t.elapsed().as_secs_f64());
        let mut times = Vec::new();
        let mut fast = builder.build(&map);
        for _ in 0..9 {
            let t = Instant::now();
            fast = builder.build(&map);
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
        times.sort_by(f64::total_cmp);
        println!("light_tree_build_ms_median={:.3}", times[times.len() / 2]);
        let total = map.total_power();
        let rel = |a: [f64; 3]| (0..3).map(|i| ((a[i] - total[i]) / total[i]).abs()).fold(0.0, f64::max);
        println!("light_root_rel_error_exact={:.3e}", rel(exact.root()));
        println!("light_root_rel_error_fast={:.3e}", rel(fast.root()));
        // Leaf differences as a share of the total (green): the fast build against exact
        // texel-centre binning (the table's own error) and against 2×2 sub-texel binning.
        let l1 = |a: &vcut_lighttree::LightTree, b: &vcut_lighttree::LightTree| {
            a.leaves().iter().zip(b.leaves()).map(|(x, y)| (x[1] - y[1]).abs()).sum::<f64>() / total[1]
        };
        let exact1 = builder.build_exact(&map, 1);
        println!("light_leaves_l1_fast_vs_centres={:.4e}", l1(&fast, &exact1));
        println!("light_leaves_l1_fast_vs_subtexel={:.4e}", l1(&fast, &exact));
    }
    Ok(())
}
