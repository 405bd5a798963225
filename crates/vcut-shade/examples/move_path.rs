//! Where an object move's time goes: moves `OBJECT` (default: the first movable one) along
//! `STEPS` translations of 0.1 r along (1, 0, 0.5) — the path `cargo xtask bench` times — and
//! prints, per step and as medians, the re-merge split into field lookups (keys), field-cut
//! decoding, refining the field cells, and merging (shading lists built as nodes are emitted),
//! then the shade time.
//!
//! `cargo run --release -p vcut-shade --example move_path -- FILE.vcuts [OBJECT] [STEPS]
//! [FRAME OPTIONS]`: the frame takes the options `vcuts render` takes for its settings
//! (`--eager-merges`, `--no-cache stored,svc,cells,merged`, `--field-reach R`,
//! `--flat-edge-leaves N|interactive`, `--no-sun-rays`, …; `FrameArgs`). `--vs-index` also times
//! the index baseline over the same path (`index_move_ms`, move + shade), between two rounds of
//! the frame's own merge, for a ratio in one run; `--cold` times the frame's first path (by
//! default a first round over it comes before, so the timed one sees a warm frame); `--drag`
//! drags the object along the timed path (`Frame::drag`) after translating it along the same
//! path (`drag_vs_translate`, move and shade) and prints the drag's preparation
//! (`drag_prepare_ms`, kept out of the first step) and its settle (`drag_settle_ms`). The
//! environment variables of earlier versions still set the same: `EAGER=1`, `NO_SVC_CACHE=1`,
//! `NO_SUN_RAYS=1`, `NO_MERGED_CACHE=1`, `NO_CELL_CACHE=1`, `NO_STORED_CACHE=1`, `FIELD_REACH=R`,
//! `FLAT_EDGE_LEAVES=N`, `VS_INDEX=1`, `COLD=1`. Over the path it prints the merged cuts' nodes
//! per re-merged vertex, the merge's nanoseconds per node and the move's microseconds per
//! re-merged vertex. Last, a lighting change (`relight_ms`: light tree and the shading lists
//! facing the eye; a merge of those without the merged cache), the camera turned to the other
//! side after it (`turn_ms`: the lists it now sees), a BRDF edit (`edit_ms`: the exponent
//! changed, every vertex shaded) and the frame's memory (`frame_memory_mb`; `setup_peak_mb`: the
//! peak of opening the file and setting the frame up, over the memory before, with the caches
//! asked off off from the start).

use clap::Parser;
use glam::Vec3;
use std::path::PathBuf;
use std::time::Instant;
use vcut_data::Precomputed;
use vcut_envmap::procedural;
use vcut_scene::budget::{peak_memory, reset_peak_memory, resident_memory, trim_heap};
use vcut_shade::measure::{edit_ms, first_movable, median, path_step};
use vcut_shade::{Frame, FrameArgs, FrameSettings, MergeAlgorithm};

/// The arguments: the file, the object and the steps, the frame's settings.
#[derive(Parser)]
struct Args {
    /// The precomputed file.
    file: PathBuf,
    /// The object moved (default: the first movable one).
    object: Option<String>,
    /// Steps of the path.
    #[arg(default_value_t = 8)]
    steps: usize,
    /// Also time the index baseline over the same path.
    #[arg(long)]
    vs_index: bool,
    /// Time the frame's first path (no warm-up round).
    #[arg(long)]
    cold: bool,
    /// Drag the object along the timed path (`Frame::drag`: the receivers it reaches merge on
    /// their rest products) and settle after it; prints the preparation and the settle apart.
    #[arg(long)]
    drag: bool,
    #[command(flatten)]
    frame: FrameArgs,
}

/// User + system CPU seconds of this process so far (Linux, whose clock ticks are 1/100 s;
/// `None` elsewhere).
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// The settings the options ask for, with the environment variables of earlier versions.
fn settings(args: &FrameArgs) -> Result<FrameSettings, String> {
    let mut s = args.settings();
    let set = |name: &str| std::env::var_os(name).is_some();
    for (var, cache) in [
        ("NO_STORED_CACHE", "stored"),
        ("NO_SVC_CACHE", "svc"),
        ("NO_CELL_CACHE", "cells"),
        ("NO_MERGED_CACHE", "merged"),
    ] {
        if set(var) {
            s.caches = s.caches.without(cache).unwrap_or(s.caches);
        }
    }
    s.deferred_merges &= !set("EAGER");
    s.sun_rays &= !set("NO_SUN_RAYS");
    if let Some(r) = std::env::var_os("FIELD_REACH") {
        s.field_reach = r.to_string_lossy().parse().map_err(|e| format!("FIELD_REACH: {e}"))?;
    }
    if let Some(n) = std::env::var_os("FLAT_EDGE_LEAVES") {
        s.flat_edge_leaves = n.to_string_lossy().parse().map_err(|e| format!("FLAT_EDGE_LEAVES: {e}"))?;
    }
    Ok(s)
}

fn main() -> Result<(), String> {
    let args = Args::parse();
    let env = procedural::PreethamSky::default().bake(1024);
    let settings = settings(&args.frame)?;
    // The caches asked off are off from the setup on, so that its peak holds none of them.
    trim_heap();
    let (before, fresh) = (resident_memory(), reset_peak_memory());
    let mut data = Precomputed::open(&args.file).map_err(|e| e.to_string())?;
    let t = Instant::now();
    let mut frame = Frame::open(&mut data, &env, &settings, None).map_err(|e| e.to_string())?;
    println!("setup_s={:.3}", t.elapsed().as_secs_f64());
    if let (Some(b), Some(p), true) = (before, peak_memory(), fresh) {
        // The file opened and the frame set up, over the memory before.
        println!("setup_peak_mb={:.1}", p.saturating_sub(b) as f64 / 1e6);
    }
    println!("sun_leaves={}", frame.stats().sun_leaves);
    println!("svc_cache_mb={:.1}", frame.memory().svc_cache as f64 / 1e6);
    println!("flat_edge_leaves={}", settings.flat_edge_leaves.leaves(frame.tree().leaf_count()));
    let o = match &args.object {
        Some(name) => frame.object_index(name).ok_or(format!("no object {name}"))?,
        None => first_movable(&frame).ok_or("nothing movable")?,
    };
    let steps = args.steps;
    let step = path_step(&frame, o);
    let eye = Vec3::new(0.0, 2.0, 6.0);
    let mut rows: Vec<[f64; 7]> = Vec::new();
    // The path, then (with VS_INDEX set) the index baseline over it and the path again: the
    // machine's speed drifts, the ratio of the two in one run does not.
    // `COLD=1`: no round before the timed one (the path's first drag, as the bench times it).
    let vs_index = args.vs_index || std::env::var_os("VS_INDEX").is_some();
    let cold = args.cold || std::env::var_os("COLD").is_some();
    let rounds = if vs_index { 3 } else { usize::from(!cold) };
    let own = frame.settings().clone();
    let index = FrameSettings { merge_algorithm: MergeAlgorithm::Index, ..own.clone() };
    let mut index_ms = Vec::new();
    for round in 0..rounds {
        frame.reconfigure(if round == 1 { &index } else { &own }).map_err(|e| e.to_string())?;
        frame.translate(o, Vec3::ZERO).map_err(|e| e.to_string())?;
        for i in 1..=steps {
            let t = Instant::now();
            frame.translate(o, step * i as f32).map_err(|e| e.to_string())?;
            std::hint::black_box(frame.shade(eye));
            if round == 1 {
                index_ms.push(t.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    frame.reconfigure(&own).map_err(|e| e.to_string())?;
    frame.translate(o, Vec3::ZERO).map_err(|e| e.to_string())?;
    // With --drag, the same path translated first: the baseline of the drag's ratio, in one run.
    let mut translate_ms = Vec::new();
    if args.drag {
        for i in 1..=steps {
            let t = Instant::now();
            frame.translate(o, step * i as f32).map_err(|e| e.to_string())?;
            std::hint::black_box(frame.shade(eye));
            translate_ms.push(t.elapsed().as_secs_f64() * 1e3);
        }
        frame.translate(o, Vec3::ZERO).map_err(|e| e.to_string())?;
    }
    let (cpu0, wall0) = (cpu_seconds(), Instant::now());
    let mut totals = (0usize, 0usize, 0.0f64, 0.0f64);
    let mut fields = 0usize;
    for i in 1..=steps {
        let t = Instant::now();
        let merged = if args.drag { frame.drag(o, step * i as f32) } else { frame.translate(o, step * i as f32) }
            .map_err(|e| e.to_string())?;
        // The first step of a drag prepares it: that time is reported apart.
        let prepare_ms = if args.drag && i == 1 { frame.stats().drag.prepare_s * 1e3 } else { 0.0 };
        let move_ms = t.elapsed().as_secs_f64() * 1e3 - prepare_ms;
        let t = Instant::now();
        std::hint::black_box(frame.shade(eye));
        let shade_ms = t.elapsed().as_secs_f64() * 1e3;
        let m = frame.stats().last_move;
        let row =
            [move_ms, m.keys_s * 1e3, m.decode_s * 1e3, m.refine_s * 1e3, m.merge_s * 1e3, shade_ms, m.sun_s * 1e3];
        println!(
            "step {i}: {merged} vertices ({} wait), move {:.1} ms (keys {:.1}, decode {:.1}, refine {:.1}, merge and lists {:.1}, sun {:.1}), shade {:.1} ms",
            m.deferred, row[0], row[1], row[2], row[3], row[4], row[6], row[5]
        );
        rows.push(row);
        totals = (totals.0 + m.vertices, totals.1 + m.nodes, totals.2 + m.merge_s, totals.3 + move_ms);
        fields += m.fields;
    }
    // A merge's cost is the walk's output (each node emitted and listed once): nodes per
    // vertex say how fine the vertices' products are, nanoseconds per node what each costs.
    let (vertices, nodes, merge_s, move_ms) = totals;
    println!("nodes_per_merged_vertex={:.0}", nodes as f64 / vertices.max(1) as f64);
    println!("ns_per_merged_node={:.1}", merge_s * 1e9 / nodes.max(1) as f64);
    println!("fields_per_merged_vertex={:.2}", fields as f64 / vertices.max(1) as f64);
    println!("us_per_merged_vertex={:.2}", move_ms * 1e3 / vertices.max(1) as f64);
    if args.drag {
        let d = frame.stats().drag;
        println!("drag_prepare_ms={:.1}", d.prepare_s * 1e3);
        println!("drag_prepared_vertices={}", d.prepared);
        println!("drag_unprepared_vertices={}", d.unprepared);
        println!("drag_memory_mb={:.1}", d.bytes as f64 / 1e6);
        println!("drag_frame_memory_mb={:.1}", frame.memory().total() as f64 / 1e6);
        println!("drag_on_rest_vertices={}", frame.stats().last_move.on_rest);
        println!("drag_hidden_vertices={}", frame.stats().last_move.hidden);
        frame.settle().map_err(|e| e.to_string())?;
        let d = frame.stats().drag;
        println!("drag_settle_ms={:.1}", d.settle_s * 1e3);
        println!("drag_settled_vertices={}", d.settled);
    }
    if let (Some(a), Some(b)) = (cpu0, cpu_seconds()) {
        // Cores busy over the path (of rayon's threads): below their count, serial parts wait.
        println!("path_cores_busy={:.2}", (b - a) / wall0.elapsed().as_secs_f64());
    }
    // A lighting change: the light tree again and the shading lists facing the eye; then the
    // camera turned to the other side builds the lists it now sees.
    let behind = Vec3::new(-eye.x, eye.y, -eye.z);
    let (mut relight, mut turn) = (Vec::new(), Vec::new());
    for _ in 0..5 {
        frame.set_eye(eye).map_err(|e| e.to_string())?;
        let t = Instant::now();
        frame.set_environment(&env);
        relight.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        frame.set_eye(behind).map_err(|e| e.to_string())?;
        turn.push(t.elapsed().as_secs_f64() * 1e3);
    }
    println!("relight_ms={:.2}", median(relight));
    println!("turn_ms={:.2}", median(turn));
    println!("frame_memory_mb={:.1}", frame.memory().total() as f64 / 1e6);
    // A BRDF edit: the movable object's exponent toggled 15 ↔ 70, then shade (no merge).
    println!("edit_ms={:.2}", edit_ms(&mut frame, o, eye, 21));
    let col = |k: usize| median(rows.iter().map(|r| r[k]).collect());
    println!("object={}", frame.object(o).name);
    for (k, name) in
        ["move_ms", "keys_ms", "decode_ms", "refine_ms", "merge_ms", "shade_ms", "sun_ms"].iter().enumerate()
    {
        println!("{name}={:.2}", col(k));
    }
    let move_shade = median(rows.iter().map(|r| r[0] + r[5]).collect());
    println!("move_and_shade_ms={move_shade:.2}");
    if !translate_ms.is_empty() {
        let translate = median(translate_ms);
        println!("translate_move_and_shade_ms={translate:.2}");
        println!("drag_vs_translate={:.3}", move_shade / translate);
    }
    if !index_ms.is_empty() {
        let index = median(index_ms);
        println!("index_move_and_shade_ms={index:.2}");
        println!("vs_index={:.3}", move_shade / index);
    }
    Ok(())
}
