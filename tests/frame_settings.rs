//! A frame's settings: given at setup, every vertex merges once; changed with `reconfigure`,
//! each vertex merges at most once and the frame equals one set up under the new settings.

mod frame_scene;

use frame_scene::{BALL_ABOVE_GROUND, EYE, data, scratch};
use glam::Vec3;
use vcut_data::{InsideSamples, Precomputed};
use vcut_shade::{FieldReach, FlatEdges, Frame, FrameCaches, FrameSettings, MergeAlgorithm};

/// Every setting away from its default.
fn every_knob() -> FrameSettings {
    FrameSettings {
        inside_samples: InsideSamples::Dropped,
        horizon_culling: false,
        field_reach: FieldReach::Outermost,
        flat_edge_leaves: FlatEdges::Leaves(4),
        deferred_merges: false,
        merge_algorithm: MergeAlgorithm::Index,
        sun_rays: true,
        light_error: Some(0.0005),
        light_max_leaves: 8,
        caches: FrameCaches { cells: false, ..FrameCaches::default() },
        memory_budget: None,
    }
}

fn vertices(frame: &Frame) -> u64 {
    (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count() as u64).sum()
}

fn sky() -> vcut_envmap::EnvMap {
    vcut_envmap::procedural::PreethamSky::default().bake(128)
}

#[test]
fn every_setting_given_at_setup_merges_each_vertex_once() {
    let dir = scratch("settings-open");
    let mut d = data(BALL_ABOVE_GROUND, &[], &dir.join("b.vcuts"));
    let settings = every_knob();
    let frame = Frame::open(&mut d, &sky(), &settings, Some(EYE)).unwrap();
    let stats = frame.stats();
    assert_eq!(stats.setup_merges, vertices(&frame));
    assert_eq!((stats.merges, stats.pending_merges), (0, 0));
    assert_eq!(frame.settings(), &settings);
    assert!(stats.sun_leaves > 0 && stats.sun_leaves <= 8, "{} sun leaves", stats.sun_leaves);
}

/// From the defaults (without the merged cache, a move waiting for the camera) to every
/// setting changed at once: each vertex merged at most once, and the same cuts and image as a
/// frame set up under those settings.
#[test]
fn a_reconfiguration_merges_each_vertex_at_most_once_and_equals_a_fresh_frame() {
    let dir = scratch("settings-reconfigure");
    let path = dir.join("b.vcuts");
    let mut d = data(BALL_ABOVE_GROUND, &[], &path);
    let env = sky();
    let lean = FrameSettings { caches: FrameCaches { merged: false, ..FrameCaches::default() }, ..Default::default() };
    let mut frame = Frame::open(&mut d, &env, &lean, Some(EYE)).unwrap();
    let ball = frame.object_index("ball").unwrap();
    let moved = Vec3::new(0.4, -0.2, 0.3);
    frame.translate(ball, moved).unwrap();
    assert!(frame.pending_merges() > 0, "the move leaves the ball's far side waiting");
    let before = frame.stats().merges;
    let settings = every_knob();
    let merged = frame.reconfigure(&settings).unwrap() as u64;
    assert_eq!(frame.stats().merges - before, merged);
    assert!(merged <= vertices(&frame), "{merged} merges for {} vertices", vertices(&frame));
    assert_eq!(frame.pending_merges(), 0, "eager now: nothing waits");
    assert_eq!(frame.settings(), &settings);

    let mut fresh = Frame::open(&mut Precomputed::open(&path).unwrap(), &env, &settings, Some(EYE)).unwrap();
    fresh.translate(ball, moved).unwrap();
    // The light's leaves chosen at the same place in both.
    frame.set_environment(&env);
    fresh.set_environment(&env);
    for o in 0..frame.object_count() {
        for v in 0..frame.object(o).mesh.vertex_count() {
            assert!(frame.merged(o, v).unwrap() == fresh.merged(o, v).unwrap(), "object {o} vertex {v}");
        }
    }
    assert!(frame.shade(EYE) == fresh.shade(EYE));
    // And back to the defaults: the frame equals one set up under them.
    frame.reconfigure(&lean).unwrap();
    let mut back = Frame::open(&mut Precomputed::open(&path).unwrap(), &env, &lean, Some(EYE)).unwrap();
    back.translate(ball, moved).unwrap();
    frame.set_environment(&env);
    back.set_environment(&env);
    assert!(frame.shade(EYE) == back.shade(EYE));
}

/// A setting out of range is refused naming its key, and the frame keeps the settings it had.
#[test]
fn a_bad_setting_changes_nothing() {
    let dir = scratch("settings-bad");
    let mut d = data(BALL_ABOVE_GROUND, &[], &dir.join("b.vcuts"));
    let mut frame = Frame::open(&mut d, &sky(), &FrameSettings::default(), Some(EYE)).unwrap();
    let image = frame.shade(EYE);
    for (bad, key) in [
        (FrameSettings { flat_edge_leaves: FlatEdges::Leaves(2048), ..Default::default() }, "flat_edge_leaves"),
        (FrameSettings { field_reach: FieldReach::Radii(-1.0), ..Default::default() }, "field_reach"),
        (FrameSettings { light_error: Some(f64::NAN), ..Default::default() }, "light_error"),
    ] {
        let e = frame.reconfigure(&bad).unwrap_err().to_string();
        assert!(e.starts_with(key), "{e}");
        assert_eq!(frame.settings(), &FrameSettings::default());
    }
    assert!(frame.shade(EYE) == image);
    let e = Frame::open(&mut d, &sky(), &FrameSettings { memory_budget: Some(0), ..Default::default() }, None);
    assert!(e.err().unwrap().to_string().starts_with("memory_budget"));
}
