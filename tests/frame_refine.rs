//! Refinement at rest ([`Frame::refine`]): exact field factors cast by rays, kept per pair,
//! deterministic, cancellable, within the memory budget.

mod frame_scene;

use frame_scene::{ASSEMBLY, EYE, cuts, data, scratch};
use glam::Vec3;
use std::sync::atomic::AtomicBool;
use vcut_envmap::EnvMap;
use vcut_shade::reference::{errors, exact_direction};
use vcut_shade::{BackgroundFrame, Frame, FrameJob, FrameSettings, Refinement};

fn open(d: &mut vcut_data::Precomputed, settings: &FrameSettings) -> Frame {
    let mut f = Frame::open(d, &EnvMap::constant([1.0; 3]), settings, None).unwrap();
    f.set_eye(EYE).unwrap();
    f
}

/// Every pair a field reaches (the default).
fn all() -> Refinement<'static> {
    Refinement::default()
}

/// The error against the exact reference toward [`EYE`].
fn error(frame: &mut Frame, offset: f32) -> f64 {
    let shaded = frame.shade(EYE);
    errors(&shaded, &exact_direction(frame, EYE, offset)).0
}

#[test]
fn a_refined_factor_is_the_sources_visibility_cast_by_rays() {
    let dir = scratch("refine-factor");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    let mut frame = open(&mut d, &FrameSettings::default());
    let stats = frame.refine(&all()).unwrap();
    assert!(stats.cast > 100 && stats.complete(), "{stats:?}");
    let tree = frame.tree().clone();
    let mut checked = 0;
    for o in 0..frame.object_count() {
        for v in (0..frame.object(o).mesh.vertex_count()).step_by(7) {
            for (j, _) in frame.field_sources(o, v) {
                let Some(cut) = frame.exact_factor(o, v, j) else { continue };
                // Source j alone, where it stands, from the vertex's ray origin: leaf for leaf.
                let occ = vcut_rays::Occluder::new(&[frame.object(j).mesh]);
                let origin = frame.ray_origin(o, v) - frame.object(j).translation;
                let leaves = cut.expand();
                for (l, d) in tree.leaf_directions().iter().enumerate() {
                    let visible = if occ.occluded(origin, *d, f32::INFINITY) { 0.0 } else { 1.0 };
                    assert_eq!(leaves[l], visible, "object {o} vertex {v} source {j} leaf {l}");
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 20, "{checked} factors checked");
}

#[test]
fn refinement_brings_the_frame_toward_the_exact_reference() {
    let dir = scratch("refine-error");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    let offset = d.svc_origin_offset();
    let mut frame = open(&mut d, &FrameSettings::default());
    let a = frame.object_index("a").unwrap();
    for step in [Vec3::ZERO, Vec3::new(0.1, 0.0, -0.05)] {
        frame.translate(a, step).unwrap();
        let before = error(&mut frame, offset);
        frame.refine(&Refinement { reach: 2.0, ..Refinement::default() }).unwrap();
        let near = error(&mut frame, offset);
        frame.refine(&all()).unwrap();
        let after = error(&mut frame, offset);
        assert!(near < before && after <= near, "{before} -> {near} (reach 2) -> {after} (all)");
        assert!(after < 0.7 * before, "{before} -> {after}");
    }
    // Shaded from another eye after a move, without announcing it: vertices facing it wait for
    // their merge; a refinement merges them and still completes.
    frame.translate(a, Vec3::ZERO).unwrap();
    frame.shade(Vec3::new(-4.0, 3.0, -5.0));
    assert!(frame.pending_merges() > 0);
    assert!(frame.refine(&all()).unwrap().complete());
    assert_eq!(frame.pending_merges(), 0);
}

#[test]
fn a_refined_frame_depends_on_the_scene_only() {
    let dir = scratch("refine-determinism");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    let settings = FrameSettings::default();
    let mut plain = open(&mut d, &settings);
    let unrefined = cuts(&mut plain);
    // Refined at once, on one thread.
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let mut once = open(&mut d, &settings);
    one.install(|| once.refine(&all())).unwrap();
    let refined = cuts(&mut once);
    assert!(refined != unrefined);
    // Interrupted again and again, moved and back, on two threads.
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let mut pieces = open(&mut d, &settings);
    let a = pieces.object_index("a").unwrap();
    let past = Some(std::time::Instant::now());
    let mut passes = 0;
    two.install(|| {
        pieces.refine(&Refinement { deadline: past, ..all() }).unwrap();
        pieces.translate(a, Vec3::new(0.2, 0.0, 0.1)).unwrap();
        pieces.refine(&Refinement { deadline: past, ..all() }).unwrap();
        pieces.translate(a, Vec3::ZERO).unwrap();
        while !pieces.refine(&Refinement { deadline: past, ..all() }).unwrap().complete() {
            passes += 1;
        }
    });
    assert!(passes > 2, "the refinement was interrupted {passes} times");
    assert!(cuts(&mut pieces) == refined, "an interrupted refinement differs from one at once");
    assert!(pieces.shade(EYE) == once.shade(EYE));
    // Dropping the factors gives back the unrefined frame.
    once.unrefine().unwrap();
    assert!(cuts(&mut once) == unrefined);
}

#[test]
fn a_cancelled_refinement_casts_nothing_and_a_move_cancels_it() {
    let dir = scratch("refine-cancel");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    let settings = FrameSettings::default();
    let mut frame = open(&mut d, &settings);
    let before = cuts(&mut frame);
    let cancel = AtomicBool::new(true);
    let stats = frame.refine(&Refinement { cancel: Some(&cancel), ..all() }).unwrap();
    assert!(stats.cancelled && stats.cast == 0 && !stats.complete(), "{stats:?}");
    assert!(cuts(&mut frame) == before);
    // A move posted behind a queued refinement drops it; the frame is the moved one.
    let worker = BackgroundFrame::new(open(&mut d, &settings));
    let a = frame.object_index("a").unwrap();
    let held = worker.frame();
    worker.post(FrameJob::Refine { seconds: None, reach: f32::INFINITY });
    let moved = worker.post(FrameJob::Translate { object: a, translation: Vec3::X * 0.1 });
    drop(held);
    worker.wait();
    let finished = worker.take_finished();
    assert_eq!(finished.len(), 1);
    assert_eq!(finished[0].ticket, moved);
    let stats = worker.stats();
    assert_eq!((stats.refines_posted, stats.refines_dropped, stats.refines_finished), (1, 1, 0));
    assert_eq!((stats.posted, stats.dropped, stats.finished), (1, 0, 1));
    frame.translate(a, Vec3::X * 0.1).unwrap();
    assert!(cuts(&mut worker.frame()) == cuts(&mut frame));
    // A refinement run to its end on the worker reports what it did.
    worker.post(FrameJob::Refine { seconds: None, reach: f32::INFINITY });
    worker.wait();
    let r = worker.take_finished().pop().unwrap().refined.expect("a refinement's figures");
    assert!(r.complete() && r.cast > 0, "{r:?}");
}

#[test]
fn exact_factors_stay_within_the_memory_budget() {
    let dir = scratch("refine-budget");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    let mut frame = open(&mut d, &FrameSettings::default());
    let full = frame.refine(&all()).unwrap();
    // A frame under a budget keeps fewer caches: room for half the factors beside those.
    let budgeted = |b: usize| FrameSettings { memory_budget: Some(b as u64), ..FrameSettings::default() };
    let budget = open(&mut d, &budgeted(1 << 40)).memory().total() + full.bytes / 2;
    let mut lean = open(&mut d, &budgeted(budget));
    let room = budget - lean.memory().total();
    let stats = lean.refine(&all()).unwrap();
    assert!(stats.over_budget > 0 && stats.cast > 0 && !stats.complete(), "{stats:?}");
    assert!(stats.bytes <= room && lean.memory().exact == stats.bytes, "{stats:?}, room {room}");
}
