//! Drags ([`Frame::drag`]): steps merged on rest products, and settles that give back the full
//! product bit for bit, against frames that only translate.

mod frame_scene;

use frame_scene::{ASSEMBLY, EYE, cuts, data, scratch};
use glam::Vec3;
use vcut_envmap::EnvMap;
use vcut_shade::{BackgroundFrame, Frame, FrameError, FrameJob, FrameSettings};

fn open(d: &mut vcut_data::Precomputed, settings: &FrameSettings) -> Frame {
    Frame::open(d, &EnvMap::constant([1.0; 3]), settings, None).unwrap()
}

/// A path of `n` steps from `from` toward the other parts.
fn path(from: Vec3, n: usize) -> Vec<Vec3> {
    (1..=n).map(|k| from + Vec3::new(0.06, 0.0, 0.03) * k as f32).collect()
}

#[test]
fn a_drag_settles_to_the_translation_bit_for_bit() {
    let dir = scratch("drag-settle");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    for deferred in [true, false] {
        let settings = FrameSettings { deferred_merges: deferred, ..FrameSettings::default() };
        let mut dragged = open(&mut d, &settings);
        let mut moved = open(&mut d, &settings);
        let rest = cuts(&mut open(&mut d, &settings));
        let a = dragged.object_index("a").unwrap();
        dragged.shade(EYE);
        moved.shade(EYE);
        let steps = path(Vec3::ZERO, 4);
        for &t in &steps {
            dragged.drag(a, t).unwrap();
            assert_eq!(dragged.dragging(), Some(a));
        }
        let stats = dragged.stats();
        assert!(stats.drag.prepared > 0 && stats.drag.bytes > 0, "{:?}", stats.drag);
        assert_eq!(dragged.memory().drag, stats.drag.bytes);
        let step = stats.last_move;
        assert!(step.on_rest > 0, "{step:?}");
        moved.translate(a, *steps.last().unwrap()).unwrap();
        let full = moved.stats().last_move;
        // Merged on their rest products, the receivers took one field each, not every one.
        assert!(step.fields < full.fields, "drag {step:?} against {full:?}");
        // During the drag the image is the full product's up to rounding.
        let (during, want) = (dragged.shade(EYE), moved.shade(EYE));
        for (a, b) in during.iter().flatten().zip(want.iter().flatten()) {
            assert!((*a - *b).abs().max_element() <= 1e-5 * b.max_element().max(1e-3), "{a} vs {b}");
        }
        // Settled, it is the full product, bit for bit.
        let settled = dragged.settle().unwrap();
        assert!(settled > 0 && dragged.dragging().is_none() && dragged.memory().drag == 0);
        assert_eq!(dragged.stats().drag.settled, settled);
        assert!(dragged.shade(EYE) == moved.shade(EYE), "deferred {deferred}: settled image differs");
        assert!(cuts(&mut dragged) == cuts(&mut moved), "deferred {deferred}: settled cuts differ");
        // Dragged back and settled: the cuts at rest.
        for &t in steps.iter().rev().skip(1).chain([&Vec3::ZERO]) {
            dragged.drag(a, t).unwrap();
        }
        dragged.settle().unwrap();
        assert!(cuts(&mut dragged) == rest, "deferred {deferred}: back at rest, the cuts differ");
    }
}

#[test]
fn moves_edits_and_other_drags_end_a_drag() {
    let dir = scratch("drag-end");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    let mut frame = open(&mut d, &FrameSettings::default());
    let (a, b) = (frame.object_index("a").unwrap(), frame.object_index("b").unwrap());
    frame.drag(a, Vec3::new(0.1, 0.0, 0.0)).unwrap();
    // A drag of another object settles the first.
    frame.drag(b, Vec3::new(0.0, 0.0, -0.1)).unwrap();
    assert_eq!(frame.dragging(), Some(b));
    assert!(frame.stats().drag.settled > 0);
    // A translation settles, and so does a settings change.
    frame.translate(a, Vec3::ZERO).unwrap();
    assert_eq!(frame.dragging(), None);
    frame.drag(a, Vec3::new(0.05, 0.0, 0.0)).unwrap();
    let s = FrameSettings { horizon_culling: !frame.settings().horizon_culling, ..frame.settings().clone() };
    frame.reconfigure(&s).unwrap();
    assert_eq!(frame.dragging(), None);
    // A refused step changes nothing, not even which object is dragged.
    frame.drag(b, Vec3::new(0.0, 0.1, 0.0)).unwrap();
    let before = frame.shade(EYE);
    assert!(frame.drag(a, Vec3::new(f32::NAN, 0.0, 0.0)).is_err());
    assert_eq!(frame.dragging(), Some(b));
    assert!(frame.shade(EYE) == before);
}

#[test]
fn rest_products_keep_to_the_memory_budget() {
    let dir = scratch("drag-budget");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    // A budget the frame keeps far within (a budget decides the caches at the start).
    let budgeted = |b: u64| FrameSettings { memory_budget: Some(b), ..FrameSettings::default() };
    let mut free = open(&mut d, &budgeted(1 << 40));
    let total = free.memory().total() as u64;
    let a = free.object_index("a").unwrap();
    free.drag(a, Vec3::new(0.1, 0.0, 0.0)).unwrap();
    let all = free.stats().drag;
    assert!(all.unprepared == 0 && all.prepared > 1, "{all:?}");
    // Room for about half of them beside the frame: the others merge in full, the same cuts.
    let room = all.bytes as u64 / 2;
    let mut tight = open(&mut d, &budgeted(total + room));
    assert_eq!(tight.stats().caches, free.stats().caches, "the budget dropped a cache");
    tight.drag(a, Vec3::new(0.1, 0.0, 0.0)).unwrap();
    let some = tight.stats().drag;
    assert!(some.prepared < all.prepared && some.unprepared > 0, "{some:?}");
    assert!(some.bytes as u64 <= room && tight.memory().total() as u64 <= total + room, "{some:?}");
    tight.settle().unwrap();
    free.settle().unwrap();
    assert!(cuts(&mut tight) == cuts(&mut free));
}

/// Random moves, drags and settles of every part, in any order: settled, the frame's cuts are
/// those of a fresh frame translated to the same places.
#[test]
fn any_sequence_of_moves_drags_and_settles_ends_at_the_fresh_frame() {
    let dir = scratch("drag-sequence");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = move |n: u64| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed % n
    };
    for round in 0..3 {
        let mut frame = open(&mut d, &FrameSettings::default());
        frame.shade(EYE);
        let movable: Vec<usize> = (1..frame.object_count()).collect();
        for _ in 0..8 {
            let o = movable[next(movable.len() as u64) as usize];
            let t = Vec3::new(next(7) as f32 - 3.0, 0.0, next(7) as f32 - 3.0) * 0.05;
            match next(3) {
                0 => {
                    frame.translate(o, t).unwrap();
                }
                1 => {
                    frame.drag(o, t).unwrap();
                }
                _ => {
                    frame.settle().unwrap();
                }
            }
        }
        frame.settle().unwrap();
        let mut fresh = open(&mut d, &FrameSettings::default());
        for &o in &movable {
            fresh.translate(o, frame.object(o).translation).unwrap();
        }
        assert!(cuts(&mut frame) == cuts(&mut fresh), "round {round}");
    }
}

/// A ball behind a block, seen from the ground in front of the block.
const BEHIND: &str = r#"
[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 16
material = { model = "lambert", kd = [0.5, 0.5, 0.5] }

[[object]]
name = "block"
source = "builtin:box"
size = 1.0
resolution = 4
translation = [0.0, 0.5, 0.0]
material = { model = "lambert", kd = [0.6, 0.4, 0.3] }

[[object]]
name = "ball"
source = "builtin:sphere"
size = 0.2
resolution = 8
translation = [0.8, 0.25, 0.0]
moves = true
material = { model = "lambert", kd = [0.2, 0.5, 0.6] }
"#;

/// The vertices a step finds the dragged object hidden from, at its old place and its new,
/// keep their cut: the image is the full merge's up to rounding, and settled, bit for bit.
#[test]
fn receivers_the_dragged_object_is_hidden_from_are_skipped() {
    let dir = scratch("drag-hidden");
    let mut d = data(BEHIND, &[], &dir.join("a.vcuts"));
    let settings = FrameSettings { deferred_merges: false, ..FrameSettings::default() };
    let (mut dragged, mut moved) = (open(&mut d, &settings), open(&mut d, &settings));
    let ball = dragged.object_index("ball").unwrap();
    let steps: Vec<Vec3> = (1..=3).map(|k| Vec3::new(0.0, 0.0, 0.02 * k as f32)).collect();
    for &t in &steps {
        dragged.drag(ball, t).unwrap();
    }
    let step = dragged.stats().last_move;
    assert!(step.hidden > 0 && step.on_rest > 0, "{step:?}");
    moved.translate(ball, *steps.last().unwrap()).unwrap();
    let (during, want) = (dragged.shade(EYE), moved.shade(EYE));
    let worst = during
        .iter()
        .flatten()
        .zip(want.iter().flatten())
        .map(|(a, b)| (*a - *b).abs().max_element() / b.max_element().max(1e-3))
        .fold(0.0f32, f32::max);
    eprintln!("hidden {} of {} merged, worst relative difference {worst:e}", step.hidden, step.vertices);
    assert!(worst <= 1e-5, "{worst}");
    dragged.settle().unwrap();
    assert!(dragged.shade(EYE) == moved.shade(EYE));
    assert!(cuts(&mut dragged) == cuts(&mut moved));
}

#[test]
fn a_background_frame_drops_stale_steps_and_settles_as_the_frame_itself() {
    let dir = scratch("drag-background");
    let mut d = data(ASSEMBLY, &[], &dir.join("a.vcuts"));
    let settings = FrameSettings::default();
    let mut moved = open(&mut d, &settings);
    let a = moved.object_index("a").unwrap();
    let steps = path(Vec3::ZERO, 10);
    let worker = BackgroundFrame::new(open(&mut d, &settings));
    worker.set_eye(EYE);
    // Held here, the frame keeps the worker from starting: every step queues behind the
    // first, each replacing the one before it.
    let held = worker.frame();
    let tickets: Vec<u64> = steps.iter().map(|&t| worker.post(FrameJob::Drag { object: a, translation: t })).collect();
    assert!(worker.busy());
    assert!(worker.try_frame().is_none(), "the worker has work: the frame is not offered");
    drop(held);
    worker.post(FrameJob::Settle);
    worker.wait();
    let stats = worker.stats();
    assert_eq!(stats.posted, 11);
    assert!(stats.dropped >= 8, "{stats:?}");
    assert_eq!(stats.finished + stats.dropped, stats.posted);
    let finished = worker.take_finished();
    assert_eq!(finished.len() as u64, stats.finished);
    assert!(finished.iter().all(|f| f.merged.is_ok()));
    let last = finished.iter().rev().find(|f| matches!(f.job, FrameJob::Drag { .. })).unwrap();
    assert_eq!(last.ticket, *tickets.last().unwrap(), "the last step always runs");
    assert!(matches!(finished.last().unwrap().job, FrameJob::Settle));
    // The shading after the queue ran dry is the settled frame's, bit for bit a translated one's.
    let shading = worker.take_shading().expect("a shading after the last job");
    assert_eq!(shading.after, Some(finished.last().unwrap().ticket));
    moved.translate(a, *steps.last().unwrap()).unwrap();
    assert!(shading.radiance == moved.shade(EYE), "the worker's frame differs from the translated one");
    assert!(cuts(&mut worker.frame()) == cuts(&mut moved));
    // A refused move comes back as the frame's error; the frame is as it was.
    let ticket = worker.post(FrameJob::Translate { object: a, translation: Vec3::splat(1e30) });
    worker.wait();
    let f = worker.take_finished();
    assert_eq!(f.len(), 1);
    assert!(f[0].ticket == ticket && f[0].merged.is_err(), "{:?}", f[0].merged);
    assert_eq!(worker.frame().object(a).translation, *steps.last().unwrap());
    // A job that panics (an object index past the end) is a failed job, and the worker goes on.
    let ticket = worker.post(FrameJob::Drag { object: 99, translation: Vec3::ONE });
    worker.wait();
    let f = worker.take_finished();
    assert!(f[0].ticket == ticket && matches!(f[0].merged, Err(FrameError::Panicked(_))), "{:?}", f[0].merged);
    worker.post(FrameJob::Translate { object: a, translation: Vec3::ZERO });
    worker.wait();
    assert!(worker.take_finished()[0].merged.is_ok(), "the worker runs the next job");
}
