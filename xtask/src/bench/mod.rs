//! `cargo xtask bench [--quick]`: the paper's Table 1 on this machine — per scene the precompute
//! (time, rays/s against the raw figure, data size in our codec and the index baseline), a BRDF
//! edit, an object move with the counter merge and with the index baseline, and the error against
//! the exact-direction and Monte Carlo references — plus the machine, the direction set, the
//! light-tree rebuild, into `target/report/` (`report.json`, `table1.md`, `table1.csv`).
//!
//! **Edit**: the median over 11 shadings after alternating the movable object's Blinn-Phong
//! exponent 15 ↔ 70. **Move**: the median over a path of 8 translations of the movable object
//! (steps of 0.1 r along (1, 0, 0.5), r its bounding radius), each a re-merge of the vertices
//! whose field inputs changed plus a shading; the same path for both merges, each starting from
//! rest. Timings are wall clock on all cores; every figure a goal names is also given as a ratio
//! against its baseline measured in the same run.

pub mod accuracy;
mod args;
pub mod assembly;
pub mod distributed;
pub mod leaves;
pub mod scaling;
pub mod ssdo;
pub mod tradeoff;
pub mod turns;

use crate::report::{
    Directions, Machine, PrecomputeFigures, RandomStart, Report, SceneFigures, Tradeoff, replace_section, write_atomic,
    write_json,
};
pub use args::{BenchArgs, Plan, Section};

use anyhow::{Context, Result, bail};
use glam::Vec3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;
use vcut_data::{InsideSamples, Precomputed};
use vcut_lighttree::LightTreeBuilder;
use vcut_precompute::run::Summary;
use vcut_scene::Scene;
use vcut_scene::budget::human;
use vcut_shade::measure::{edit_ms, first_movable, median, move_path, turn_after_move};
use vcut_shade::reference::{MonteCarloParams, errors, exact_direction, monte_carlo};
use vcut_shade::{FlatEdges, Frame, FrameCaches, FrameSettings, MergeAlgorithm};
use vcut_sphere::{DirectionSet, RepulsionParams};

/// Seconds of each precompute's own work timed for the bench's estimate.
const ESTIMATE_SAMPLE_S: f64 = 1.0;

/// The bench's precomputes — each scene's (unless reused), the trade-off sweep's, the leaf
/// section's — estimated before anything else runs; prints each and the total, and checks the
/// largest peak memory and the total data against what is free. The frames, references and
/// screen-space timings come on top (they are not estimated).
fn estimate(args: &BenchArgs, data_dir: &Path) -> Result<()> {
    let mut rows: Vec<(String, f64, u64, u64)> = Vec::new();
    for name in &args.scenes {
        let preset = scene_preset(args.quick);
        let file = data_dir.join(format!("{name}-{preset}.vcuts"));
        if args.reuse && file.exists() && file.with_extension("summary.json").exists() {
            continue;
        }
        let mut a = vcuts::precompute::PrecomputeArgs::new(&format!("builtin:{name}"), preset);
        a.output = Some(file);
        let e = vcuts::precompute::estimate_only(&a, ESTIMATE_SAMPLE_S)?;
        rows.push((format!("{name} at {preset}"), e.seconds, e.output_bytes, e.peak_bytes));
    }
    if args.measures(Section::Tradeoff) {
        let base = if args.quick { "fast" } else { "balanced" };
        for (key, value, a) in crate::bench::tradeoff::variants("teapot", base, args.quick, data_dir) {
            let e = vcuts::precompute::estimate_only(&a, ESTIMATE_SAMPLE_S)?;
            rows.push((format!("trade-off teapot {key} = {value}"), e.seconds, e.output_bytes, e.peak_bytes));
        }
    }
    if args.measures(Section::Leaves) {
        for (label, e) in crate::bench::leaves::estimates(args.quick, ESTIMATE_SAMPLE_S)? {
            rows.push((label, e.lvc_seconds + e.prt_seconds, e.output_bytes, e.peak_bytes));
        }
    }
    for (label, s, bytes, peak) in &rows {
        println!("estimate: {label}: {s:.1} s, {}, peak {}", human(*bytes), human(*peak));
    }
    let seconds: f64 = rows.iter().map(|r| r.1).sum();
    let bytes: u64 = rows.iter().map(|r| r.2).sum();
    let peak = rows.iter().map(|r| r.3).max().unwrap_or(0);
    println!(
        "estimate: the bench's {} precomputes about {:.1} min on {} threads, {} of data, peak memory {} \
         (the frames, references and screen-space timings come on top)",
        rows.len(),
        seconds / 60.0,
        rayon::current_num_threads(),
        human(bytes),
        human(peak)
    );
    println!("estimate_precompute_s={seconds:.1}");
    println!("estimate_data_mb={:.1}", bytes as f64 / 1e6);
    println!("estimate_peak_mb={:.1}", peak as f64 / 1e6);
    vcuts::resources::check("the bench", peak, (data_dir, bytes), args.force)
}

/// The preset a scene is benched at: the paper's, or with `--quick` the fastest.
fn scene_preset(quick: bool) -> &'static str {
    if quick { "fast" } else { "paper" }
}

/// Rays/s of the precompute's ray stages and the raw figure over the same rays.
fn rays(summary: &Summary) -> (f64, f64) {
    let stages: Vec<_> = summary.stages.iter().filter(|s| s.name != "directions" && s.rays.rays_cast > 0).collect();
    let rays: f64 = stages.iter().map(|s| s.rays.rays_cast as f64).sum();
    let secs: f64 = stages.iter().map(|s| s.compute_seconds).sum();
    let raw_secs: f64 = stages
        .iter()
        .filter(|s| s.raw_rays_per_second > 0.0)
        .map(|s| s.rays.rays_cast as f64 / s.raw_rays_per_second)
        .sum();
    (rays / secs.max(1e-12), if raw_secs > 0.0 { rays / raw_secs } else { 0.0 })
}

/// One scene: precompute, edit, move (both merges), references.
/// What the precompute of a scene measured: kept beside its output (`.summary.json`) so
/// `--reuse` can time frames again without precomputing.
fn precompute_figures(name: &str, preset: &str, data_dir: &Path, reuse: bool) -> Result<(PathBuf, PrecomputeFigures)> {
    let file = data_dir.join(format!("{name}-{preset}.vcuts"));
    let sidecar = file.with_extension("summary.json");
    if reuse
        && file.exists()
        && let Ok(text) = std::fs::read_to_string(&sidecar)
    {
        println!("\n== {name}: reusing {} (precomputed earlier)", file.display());
        let figures = serde_json::from_str(&text).with_context(|| format!("reading {}", sidecar.display()))?;
        return Ok((file, figures));
    }
    println!("\n== {name}: precompute at preset {preset}");
    let mut args = vcuts::precompute::PrecomputeArgs::new(&format!("builtin:{name}"), preset);
    args.output = Some(file.clone());
    args.fresh = true;
    let t = Instant::now();
    let outcome = vcuts::precompute::run(&args)?;
    vcuts::outcome::print(&outcome);
    let (file, summary) = (outcome.file, outcome.run);
    let summary = summary.context("precompute ran as a dry run")?;
    let precompute_s = t.elapsed().as_secs_f64();
    let (rays_per_s, raw_rays_per_s) = rays(&summary);
    let cut_bytes: u64 = summary.sizes.iter().map(|z| z.bytes).sum();
    let index_bytes: u64 = summary.sizes.iter().map(|z| z.index_baseline_bytes).sum();
    let heights_bytes: u64 = summary.sizes.iter().map(|z| z.heights_codec_bytes).sum();
    let other_bytes = summary.file_bytes - cut_bytes;
    let figures = PrecomputeFigures {
        precompute_s,
        rays_per_s,
        raw_rays_per_s,
        rays_per_s_vs_raw: rays_per_s / raw_rays_per_s.max(1e-12),
        data_bytes_height: summary.file_bytes,
        data_bytes_index: other_bytes + index_bytes,
        data_bytes_height_codec_4bit: other_bytes + heights_bytes,
        data_size_vs_index: summary.file_bytes as f64 / (other_bytes + index_bytes) as f64,
    };
    write_json(&sidecar, &figures)?;
    Ok((file, figures))
}

/// One scene: precompute (or reuse), edit, move (both merges), references.
fn bench_scene(name: &str, preset: &str, data_dir: &Path, no_mc: bool, reuse: bool) -> Result<SceneFigures> {
    let (file, pre) = precompute_figures(name, preset, data_dir, reuse)?;
    let scene = Scene::open(&format!("builtin:{name}"))?;
    let eye = scene.cameras.first().map(|c| c.position).context("the built-in scene has a camera")?;
    let mut data = Precomputed::open(&file)?;
    let offset = data.svc_origin_offset();
    let t = Instant::now();
    let base = FrameSettings::default();
    let mut frame = Frame::open(&mut data, &scene.environment, &base, None)?;
    let setup_s = t.elapsed().as_secs_f64();
    let movable = first_movable(&frame).with_context(|| format!("scene {name} has no movable object"))?;
    let vertices: usize = (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count()).sum();

    println!("== {name}: edit, move, references");
    let edit = edit_ms(&mut frame, movable, eye, 11);
    let counter = move_path(&mut frame, movable, eye, MergeAlgorithm::Counter, 8)?;
    // The knob: SVCs decoded at every merge instead of kept decoded.
    let svc_cache_bytes = frame.memory().svc_cache;
    frame.reconfigure(&FrameSettings { caches: FrameCaches { svc: false, ..base.caches }, ..base.clone() })?;
    let svc_decoded = move_path(&mut frame, movable, eye, MergeAlgorithm::Counter, 8)?;
    frame.reconfigure(&base)?;
    let index = move_path(&mut frame, movable, eye, MergeAlgorithm::Index, 8)?;
    // The knob: every vertex a move changes merged at once (no merge waits for a camera), and
    // what a camera turn after a move costs either way.
    let behind = Vec3::new(-eye.x, eye.y, -eye.z);
    let (turn_ms, turn_merged) = turn_after_move(&mut frame, movable, eye, behind, 5)?;
    let eager_settings = FrameSettings { deferred_merges: false, ..base.clone() };
    frame.reconfigure(&eager_settings)?;
    let eager = move_path(&mut frame, movable, eye, MergeAlgorithm::Counter, 8)?;
    let (turn_ms_eager, _) = turn_after_move(&mut frame, movable, eye, behind, 5)?;
    frame.reconfigure(&base)?;
    println!(
        "{name}: move {:.1} ms merging {} vertices ({} wait for a camera), eager {:.1} ms merging {}; \
         a camera turn after a move {turn_ms:.1} ms ({turn_merged} merged), eager {turn_ms_eager:.1} ms",
        counter.move_ms, counter.merged, counter.deferred, eager.move_ms, eager.merged
    );
    frame.reconfigure(&FrameSettings { merge_algorithm: MergeAlgorithm::Index, ..base.clone() })?;
    let edit_index = edit_ms(&mut frame, movable, eye, 11);
    frame.reconfigure(&base)?;
    let (move_ms, move_ms_index) = (counter.move_ms, index.move_ms);
    let merge_s: f64 = counter.merge_ms.iter().sum::<f64>() / 1e3;
    let merge_s_index: f64 = index.merge_ms.iter().sum::<f64>() / 1e3;
    let merged_per_move = counter.merged;

    let shaded = frame.shade(eye);
    let t = Instant::now();
    let exact = exact_direction(&frame, eye, offset);
    let exact_ms = t.elapsed().as_secs_f64() * 1e3;
    let (rel_l2_exact, max_exact) = errors(&shaded, &exact);
    // The knob: field samples inside an object dropped instead of blended in as occluded.
    frame.reconfigure(&FrameSettings { inside_samples: InsideSamples::Dropped, ..base.clone() })?;
    let (rel_l2_dropped, max_dropped) = errors(&frame.shade(eye), &exact);
    frame.reconfigure(&base)?;
    // The knob: the sun carried by the cuts too (the paper) instead of cast by rays.
    let sun_leaves = frame.stats().sun_leaves;
    frame.reconfigure(&FrameSettings { sun_rays: false, ..base.clone() })?;
    let (rel_l2_cuts, max_cuts) = errors(&frame.shade(eye), &exact);
    let cuts_path = move_path(&mut frame, movable, eye, MergeAlgorithm::Counter, 8)?;
    frame.reconfigure(&base)?;
    println!(
        "{name}: the sun ({sun_leaves} leaves) through the cuts: rel L2 vs exact {rel_l2_cuts:.4}, move {:.1} ms",
        cuts_path.move_ms
    );
    // The knob: a ground's cut estimated across its edges in nodes of up to the interactive
    // setting's leaves (1/256 of the directions) instead of split to its leaves; the eager move
    // beside `eager`'s.
    let flat_edge_leaves = FlatEdges::Interactive.leaves(frame.tree().leaf_count());
    let flat = FrameSettings { flat_edge_leaves: FlatEdges::Interactive, ..base.clone() };
    frame.reconfigure(&flat)?;
    let (rel_l2_flat, max_flat) = errors(&frame.shade(eye), &exact);
    frame.reconfigure(&FrameSettings { deferred_merges: false, ..flat })?;
    let flat_path = move_path(&mut frame, movable, eye, MergeAlgorithm::Counter, 8)?;
    frame.reconfigure(&base)?;
    println!(
        "{name}: a ground's edges in nodes of up to {flat_edge_leaves} leaves: rel L2 vs exact {rel_l2_flat:.5} \
         (exact cut {rel_l2_exact:.5}), eager move {:.1} ms (exact cut {:.1})",
        flat_path.move_ms, eager.move_ms
    );
    let mc = if no_mc {
        None
    } else {
        let t = Instant::now();
        let (r, _) = monte_carlo(&frame, &scene.environment, eye, offset, &MonteCarloParams::default());
        Some((errors(&shaded, &r).0, t.elapsed().as_secs_f64()))
    };
    let shade_bytes = frame.stats().shade_bytes;
    let merged_bytes = frame.stats().merged_bytes;
    println!(
        "{name}: edit {edit:.1} ms, move {move_ms:.1} ms (index {move_ms_index:.1} ms), rel L2 vs exact {rel_l2_exact:.4}"
    );
    Ok(SceneFigures {
        preset: preset.into(),
        vertices,
        objects: frame.object_count(),
        moved_object: frame.object(movable).name.to_string(),
        setup_s,
        edit_ms: edit,
        move_ms,
        edit_ms_index: edit_index,
        move_ms_index,
        move_vs_index: move_ms / move_ms_index,
        move_ms_svc_decoded: svc_decoded.move_ms,
        svc_cache_bytes,
        merge_s_path: merge_s,
        merge_s_path_index: merge_s_index,
        merge_speedup: merge_s_index / merge_s.max(1e-12),
        vertices_merged_per_move: merged_per_move,
        vertices_deferred_per_move: counter.deferred,
        move_ms_eager: eager.move_ms,
        vertices_merged_per_move_eager: eager.merged,
        turn_ms,
        turn_merged_vertices: turn_merged,
        turn_ms_eager,
        exact_reference_ms: exact_ms,
        edit_vs_exact_reference: edit / exact_ms,
        move_vs_exact_reference: move_ms / exact_ms,
        shade_bytes,
        merged_cut_bytes: merged_bytes,
        rel_l2_exact,
        max_err_exact: max_exact,
        rel_l2_exact_inside_dropped: rel_l2_dropped,
        max_err_exact_inside_dropped: max_dropped,
        sun_leaves,
        rel_l2_exact_cuts_only: rel_l2_cuts,
        max_err_exact_cuts_only: max_cuts,
        move_ms_cuts_only: cuts_path.move_ms,
        flat_edge_leaves,
        move_ms_eager_flat_edges: flat_path.move_ms,
        rel_l2_exact_flat_edges: rel_l2_flat,
        max_err_exact_flat_edges: max_flat,
        rel_l2_mc: mc.map(|m| m.0),
        mc_reference_s: mc.map(|m| m.1),
        precompute: pre,
        bounds: None,
    })
}

/// The two trade-off plots.
fn plots(points: &[crate::report::Point], out: &Path) -> Result<()> {
    crate::report::plots::tradeoff(points, "data_bytes", "data size (MB)", &out.join("tradeoff_size.png"))?;
    crate::report::plots::tradeoff(points, "move_ms", "object move (ms)", &out.join("tradeoff_move.png"))?;
    println!("plots={}", out.join("tradeoff_size.png").display());
    Ok(())
}

/// Runs `bench`.
pub fn run(args: &BenchArgs) -> Result<()> {
    for s in &args.scenes {
        if !["teapot", "bunny", "spheres"].contains(&s.as_str()) {
            bail!("--scenes {s}: expected teapot, bunny or spheres");
        }
    }
    let sweeps = crate::bench::scaling::Sweeps::of(args)?;
    if args.plot_only {
        let path = args.out.join("tradeoff.csv");
        let text = std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
        let points = crate::report::csv::parse_tradeoff(&text).with_context(|| format!("{}", path.display()))?;
        return plots(&points, &args.out);
    }
    let sections = match args.plan()? {
        Plan::Only(section) => {
            let path = args.out.join("report.json");
            std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
            let data_dir = args.out.join("data");
            std::fs::create_dir_all(&data_dir).with_context(|| format!("creating {}", data_dir.display()))?;
            measure_section(args, section, &sweeps, &data_dir, &path)?;
            println!("report={}", path.display());
            return Ok(());
        }
        Plan::Full(sections) => sections,
    };
    let data_dir = args.out.join("data");
    estimate(args, &data_dir)?;
    if args.dry_run {
        return Ok(());
    }
    std::fs::create_dir_all(&data_dir).with_context(|| format!("creating {}", data_dir.display()))?;
    let started = Instant::now();

    println!("== machine");
    let bandwidth = crate::measure::machine::memory_bandwidth();
    println!("memory_bandwidth_gb_s={bandwidth:.2}");

    println!("== directions (32,768) and the light tree");
    // Both starts generated afresh in this run, so their times compare.
    let timed = |params: &RepulsionParams| -> Result<(DirectionSet, f64)> {
        let t = Instant::now();
        let s = DirectionSet::generate(32_768, params, |_, _| {})?;
        Ok((s, t.elapsed().as_secs_f64()))
    };
    let (set, fib_s) = timed(&RepulsionParams::default())?;
    let u = set.uniformity();
    let (random, random_s) = timed(&RepulsionParams::random(1))?;
    let ru = random.uniformity();
    println!(
        "random start (seed 1): cv_cell_area={:.5} min_nn_ratio={:.4}, {:.2}x the Fibonacci start's time",
        ru.cv_cell_area,
        ru.min_nn_ratio,
        random_s / fib_s
    );
    let tree = vcut_dirtree::DirectionTree::build(set.directions(), &set.cell_areas())?;
    let sky = vcut_envmap::procedural::PreethamSky::default().bake(1024);
    let mut builder = LightTreeBuilder::new(&tree);
    let rebuild_ms = median(
        (0..11)
            .map(|_| {
                let t = Instant::now();
                std::hint::black_box(builder.build(&sky));
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect(),
    );

    let mut scenes = BTreeMap::new();
    for name in &args.scenes {
        let preset = scene_preset(args.quick);
        let mut figures = bench_scene(name, preset, &data_dir, args.no_mc, args.reuse)?;
        figures.bound(bandwidth);
        scenes.insert(name.clone(), figures);
    }
    let first = scenes.values().next();
    let raw = first.map(|s| s.precompute.raw_rays_per_s).unwrap_or(f64::NAN);
    let teapot = scenes.get("teapot").or(first);
    let mut report = Report {
        quick: args.quick,
        machine: Machine {
            cpu: crate::measure::machine::cpu_name(),
            cores: rayon::current_num_threads(),
            memory_bandwidth_gb_s: bandwidth,
            raw_rays_per_s: raw,
        },
        directions: Directions {
            n: u.n,
            cv_cell_area: u.cv_cell_area,
            min_nn_ratio: u.min_nn_ratio,
            generate_s: fib_s,
            random: RandomStart {
                seed: 1,
                cv_cell_area: ru.cv_cell_area,
                min_nn_ratio: ru.min_nn_ratio,
                generate_s: random_s,
                time_vs_fibonacci: random_s / fib_s,
            },
        },
        light_tree_rebuild_ms: rebuild_ms,
        merge_speedup: teapot.map(|s| s.merge_speedup),
        codec_size_ratio: teapot
            .map(|s| s.precompute.data_bytes_height_codec_4bit as f64 / s.precompute.data_bytes_index as f64),
        stored_size_ratio: teapot.map(|s| s.precompute.data_size_vs_index),
        scenes,
        tradeoff: None,
        ssdo: None,
        leaves: None,
        scaling: None,
        assembly: None,
        distributed: None,
        accuracy: None,
        turns: None,
        bench_s: 0.0,
    };
    for section in sections {
        match section {
            Section::Tradeoff => report.tradeoff = Some(tradeoff_section(args, &data_dir)?),
            Section::Ssdo => report.ssdo = Some(ssdo_section(args)?),
            Section::Leaves => report.leaves = Some(crate::bench::leaves::run(args.quick, &args.out.join("leaves"))?),
            Section::Scaling => report.scaling = Some(crate::bench::scaling::run(&sweeps, &data_dir, &args.out)?),
            Section::Assembly => report.assembly = Some(crate::bench::assembly::run(args.quick, &data_dir, &args.out)?),
            Section::Accuracy => {
                report.accuracy =
                    Some(crate::bench::accuracy::run(args.quick, args.no_mc, args.reuse, &data_dir, &args.out)?)
            }
            Section::Distributed => {
                report.distributed = Some(crate::bench::distributed::run(args.quick, &data_dir, &args.out)?)
            }
            Section::Turns => report.turns = Some(crate::bench::turns::run(args.quick, &data_dir, &args.out)?),
        }
    }
    report.bench_s = started.elapsed().as_secs_f64();
    let (md, csv) = crate::report::table1::table1(&report.scenes);
    write_json(&args.out.join("report.json"), &report)?;
    write_atomic(&args.out.join("table1.md"), md.as_bytes())?;
    write_atomic(&args.out.join("table1.csv"), csv.as_bytes())?;
    println!("\n{md}");
    println!("report={}", args.out.join("report.json").display());
    Ok(())
}

/// One section measured on its own, replacing its part of the report at `path` (the rest of an
/// earlier report is kept).
fn measure_section(
    args: &BenchArgs,
    section: Section,
    sweeps: &crate::bench::scaling::Sweeps,
    data_dir: &Path,
    path: &Path,
) -> Result<()> {
    let key = section.key();
    match section {
        Section::Tradeoff => replace_section(path, key, &tradeoff_section(args, data_dir)?),
        Section::Ssdo => replace_section(path, key, &ssdo_section(args)?),
        Section::Leaves => {
            replace_section(path, key, &crate::bench::leaves::run(args.quick, &args.out.join("leaves"))?)
        }
        Section::Scaling => replace_section(path, key, &crate::bench::scaling::run(sweeps, data_dir, &args.out)?),
        Section::Assembly => replace_section(path, key, &crate::bench::assembly::run(args.quick, data_dir, &args.out)?),
        Section::Accuracy => replace_section(
            path,
            key,
            &crate::bench::accuracy::run(args.quick, args.no_mc, args.reuse, data_dir, &args.out)?,
        ),
        Section::Distributed => {
            replace_section(path, key, &crate::bench::distributed::run(args.quick, data_dir, &args.out)?)
        }
        Section::Turns => replace_section(path, key, &crate::bench::turns::run(args.quick, data_dir, &args.out)?),
    }
}

/// The `tradeoff` section: one knob at a time from a base preset on the teapot scene, its
/// table and plots beside the report.
fn tradeoff_section(args: &BenchArgs, data_dir: &Path) -> Result<Tradeoff> {
    let base = if args.quick { "fast" } else { "balanced" };
    let points = crate::bench::tradeoff::run("teapot", base, args.quick, data_dir, args.no_mc)?;
    write_atomic(&args.out.join("tradeoff.csv"), crate::report::csv::tradeoff(&points).as_bytes())?;
    plots(&points, &args.out)?;
    Ok(Tradeoff { scene: "teapot".into(), base_preset: base.into(), points })
}

/// The `ssdo` section: the scenes asked for (and, in a full run, the plant).
fn ssdo_section(args: &BenchArgs) -> Result<crate::report::SsdoSection> {
    println!("== screen space: SSAO, SSDO, SSDO peeled against the ray-traced reference");
    let mut names = args.scenes.clone();
    if !args.quick && !names.iter().any(|n| n == "plant") {
        names.push("plant".into());
    }
    let (eval, rays, runs) = if args.quick { ((320, 180), 64, 5) } else { ((640, 360), 256, 9) };
    crate::bench::ssdo::run(&names, (1280, 720), eval, rays, runs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_are_the_middle_value() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
        assert!(median(Vec::new()).is_nan());
    }
}
