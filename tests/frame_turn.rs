//! Turns ([`Frame::turn`]): objects of a file precomputed with a symmetric direction set turn
//! about +Y; their cuts relabel by whole wedges and their geometry turns exactly.

mod frame_scene;

use frame_scene::{ASSEMBLY, EYE, cuts, data, scratch};
use glam::{Quat, Vec3};
use std::f32::consts::TAU;
use vcut_envmap::EnvMap;
use vcut_shade::reference::{errors, exact_direction};
use vcut_shade::{BackgroundFrame, Frame, FrameError, FrameJob, FrameSettings, Refinement, TurnRefusal};

const WEDGES: u32 = 16;
const STEP: f32 = TAU / WEDGES as f32;

fn open(d: &mut vcut_data::Precomputed, settings: &FrameSettings) -> Frame {
    Frame::open(d, &EnvMap::constant([1.0; 3]), settings, None).unwrap()
}

fn turnable(name: &str) -> (std::path::PathBuf, vcut_data::Precomputed) {
    let dir = scratch(name);
    let d = data(ASSEMBLY, &[("turn_steps", "16")], &dir.join("a.vcuts"));
    (dir, d)
}

#[test]
fn a_full_turn_and_a_turn_back_return_every_cut_and_pixel_bit_for_bit() {
    let (_dir, mut d) = turnable("turn-back");
    for deferred in [true, false] {
        let settings = FrameSettings { deferred_merges: deferred, ..FrameSettings::default() };
        let mut frame = open(&mut d, &settings);
        let rest_image = frame.shade(EYE);
        let rest = cuts(&mut frame);
        let b = frame.object_index("b").unwrap();
        let turned = frame.turn(b, 3.0 * STEP).unwrap();
        assert_eq!((turned.steps, turned.wedges), (3, WEDGES));
        assert!(turned.merged > 0 && turned.snap_error.abs() < 1e-6, "{turned:?}");
        assert!(cuts(&mut frame) != rest, "a turn of an asymmetric box changed no cut");
        // A full turn is yaw 0: the mesh at rest and every cut.
        frame.turn(b, TAU).unwrap();
        assert_eq!(frame.object(b).yaw, 0.0);
        assert!(frame.object(b).mesh.positions() == frame.object(b).rest_mesh().positions());
        assert!(cuts(&mut frame) == rest, "deferred {deferred}: a full turn changed the cuts");
        frame.turn(b, 0.7).unwrap();
        frame.translate(b, Vec3::new(0.1, 0.0, 0.0)).unwrap();
        frame.turn(b, -1.9).unwrap();
        frame.translate(b, Vec3::ZERO).unwrap();
        frame.turn(b, 0.0).unwrap();
        assert!(cuts(&mut frame) == rest, "deferred {deferred}: turned and back, the cuts differ");
        assert!(frame.shade(EYE) == rest_image, "deferred {deferred}: turned and back, the image differs");
    }
}

#[test]
fn a_turn_relabels_the_svcs_and_turns_the_geometry_about_the_bounding_centre() {
    let (_dir, mut d) = turnable("turn-svc");
    let mut frame = open(&mut d, &FrameSettings::default());
    let shape = frame.turn_shape().expect("a symmetric set");
    let b = frame.object_index("b").unwrap();
    let rest: Vec<vcut_cut::Cut> = (0..frame.object(b).mesh.vertex_count()).map(|v| frame.svc(b, v).unwrap()).collect();
    let centre = frame.object(b).mesh.bounds().center;
    // 0.3 rad snaps to one step of 22.5°: the geometry takes 0.3, the cuts one step.
    let turned = frame.turn(b, 0.3).unwrap();
    assert_eq!(turned.steps, 1);
    assert!((turned.snap_error - (STEP - 0.3)).abs() < 1e-6, "{turned:?}");
    for (v, cut) in rest.iter().enumerate() {
        assert!(frame.svc(b, v).unwrap() == cut.turned(shape, 1).unwrap(), "vertex {v}");
    }
    let object = frame.object(b);
    let q = Quat::from_rotation_y(0.3);
    for ((p, n), (p0, n0)) in object
        .mesh
        .positions()
        .iter()
        .zip(object.mesh.normals())
        .zip(object.rest_mesh().positions().iter().zip(object.rest_mesh().normals()))
    {
        assert!(p.distance(q * (*p0 - centre) + centre) < 1e-5, "{p} from {p0}");
        assert!(n.distance(q * *n0) < 1e-5, "{n} from {n0}");
    }
    assert!(object.mesh.bounds().center.distance(centre) < 0.05, "the box strayed from its axis");
    // The translation applies after the turn.
    frame.translate(b, Vec3::new(0.0, 0.2, 0.0)).unwrap();
    let moved = frame.object(b).positions();
    assert!(moved.iter().zip(frame.object(b).mesh.positions()).all(|(m, p)| *m == *p + Vec3::new(0.0, 0.2, 0.0)));
    // Snaps go to the nearest step, either way round; a yaw just short of a full turn is step 0.
    assert_eq!(frame.turn(b, 0.5 * STEP - 0.01).unwrap().steps, 0);
    assert_eq!(frame.turn(b, -0.4 * STEP).unwrap().steps, 0);
    assert_eq!(frame.turn(b, -0.6 * STEP).unwrap().steps, WEDGES - 1);
    let last = frame.turn(b, TAU - 0.01).unwrap();
    assert_eq!(last.steps, 0);
    assert!((last.snap_error - 0.01).abs() < 1e-5, "{last:?}");
}

#[test]
fn turns_are_refused_by_old_files_static_objects_and_bad_yaws_leaving_the_frame() {
    let dir = scratch("turn-refused");
    let mut old = data(ASSEMBLY, &[], &dir.join("old.vcuts"));
    let mut frame = open(&mut old, &FrameSettings::default());
    assert!(frame.turn_shape().is_none());
    let rest = cuts(&mut frame);
    let b = frame.object_index("b").unwrap();
    let err = frame.turn(b, 0.5).unwrap_err();
    assert!(matches!(err, FrameError::Turn { reason: TurnRefusal::NoSymmetry, .. }), "{err}");
    assert!(err.to_string().contains("turn_steps") && err.to_string().contains("(b)"), "{err}");
    assert!(cuts(&mut frame) == rest && frame.object(b).yaw == 0.0);
    let (_dir, mut d) = turnable("turn-refused-2");
    let mut frame = open(&mut d, &FrameSettings::default());
    let rest = cuts(&mut frame);
    let ground = frame.object_index("ground").unwrap();
    let err = frame.turn(ground, 0.5).unwrap_err();
    assert!(matches!(err, FrameError::Turn { reason: TurnRefusal::Static, .. }), "{err}");
    for bad in [f32::NAN, f32::INFINITY] {
        let err = frame.turn(b, bad).unwrap_err();
        assert!(matches!(err, FrameError::Turn { reason: TurnRefusal::NotFinite, .. }), "{err}");
    }
    assert!(cuts(&mut frame) == rest);
}

#[test]
fn a_turned_frame_stays_near_the_exact_reference_of_the_turned_geometry() {
    let (_dir, mut d) = turnable("turn-error");
    let offset = d.svc_origin_offset();
    let mut frame = open(&mut d, &FrameSettings::default());
    let error = |f: &mut Frame| errors(&f.shade(EYE), &exact_direction(f, EYE, offset)).0;
    let at_rest = error(&mut frame);
    let b = frame.object_index("b").unwrap();
    let c = frame.object_index("c").unwrap();
    // A whole step, and a yaw between steps (the cuts then snap).
    for yaw in [2.0 * STEP, 37f32.to_radians()] {
        frame.turn(b, yaw).unwrap();
        frame.turn(c, -yaw).unwrap();
        let turned = error(&mut frame);
        assert!(turned < 1.5 * at_rest + 0.01, "yaw {yaw}: {turned} against {at_rest} at rest");
    }
    // Had the box's cuts not turned, the image would be off: the turn must matter.
    let unturned = {
        let mut f = open(&mut d, &FrameSettings::default());
        f.shade(EYE)
    };
    let reference = exact_direction(&frame, EYE, offset);
    assert!(errors(&unturned, &reference).0 > errors(&frame.shade(EYE), &reference).0);
}

#[test]
fn drags_deferrals_refinements_and_the_worker_agree_with_eager_turns() {
    let (_dir, mut d) = turnable("turn-agree");
    let eager_settings = FrameSettings { deferred_merges: false, ..FrameSettings::default() };
    let mut eager = open(&mut d, &eager_settings);
    let mut deferred = open(&mut d, &FrameSettings::default());
    deferred.shade(EYE);
    let (a, b) = (eager.object_index("a").unwrap(), eager.object_index("b").unwrap());
    for f in [&mut eager, &mut deferred] {
        f.turn(b, 1.1).unwrap();
        f.drag(a, Vec3::new(0.05, 0.0, 0.02)).unwrap();
        f.drag(a, Vec3::new(0.1, 0.0, 0.04)).unwrap();
        // A turn settles the drag.
        f.turn(a, 2.0).unwrap();
        assert_eq!(f.dragging(), None);
    }
    assert!(cuts(&mut eager) == cuts(&mut deferred), "deferred merges differ from eager ones after turns");
    // The worker runs the same turn.
    let worker = BackgroundFrame::new(open(&mut d, &eager_settings));
    for job in [
        FrameJob::Turn { object: b, yaw: 1.1 },
        FrameJob::Translate { object: a, translation: Vec3::new(0.1, 0.0, 0.04) },
        FrameJob::Turn { object: a, yaw: 2.0 },
    ] {
        worker.post(job);
    }
    worker.wait();
    assert!(worker.take_finished().iter().all(|f| f.merged.is_ok()));
    assert!(cuts(&mut worker.frame()) == cuts(&mut eager), "the worker's turns differ");
    // A refined factor of a source belongs to its turn: turned, the source is looked up again.
    eager.set_eye(EYE).unwrap();
    eager.refine(&Refinement::default()).unwrap();
    let refined: Vec<(usize, usize)> = (0..eager.object(a).mesh.vertex_count())
        .filter(|&v| eager.exact_factor(a, v, b).is_some())
        .map(|v| (a, v))
        .collect();
    assert!(!refined.is_empty());
    eager.turn(b, 1.1 + STEP).unwrap();
    assert!(refined.iter().all(|&(o, v)| eager.exact_factor(o, v, b).is_none()), "a factor outlived its turn");
    eager.refine(&Refinement::default()).unwrap();
    assert!(refined.iter().any(|&(o, v)| eager.exact_factor(o, v, b).is_some()), "none refined again");
}

#[test]
fn a_turn_by_whole_steps_matches_the_object_precomputed_turned() {
    let (dir, mut d) = turnable("turn-precomputed");
    let box_at = "translation = [0.75, 0.35, 0.1]";
    assert!(ASSEMBLY.contains(box_at));
    let text = ASSEMBLY.replace(box_at, &format!("{box_at}\nrotation_deg = [0.0, {}, 0.0]", 360.0 / WEDGES as f32));
    let mut turned_file = data(&text, &[("turn_steps", "16")], &dir.join("turned.vcuts"));
    let want = open(&mut turned_file, &FrameSettings::default()).shade(EYE);
    let mut frame = open(&mut d, &FrameSettings::default());
    let unturned = errors(&frame.shade(EYE), &want).0;
    let b = frame.object_index("b").unwrap();
    frame.turn(b, STEP).unwrap();
    // The box's geometry and SVCs are the precomputed ones within rounding; its field is
    // looked up between other samples (those of the turned box stand elsewhere).
    let turned = errors(&frame.shade(EYE), &want).0;
    assert!(turned < 0.05 * unturned && turned < 0.005, "turned {turned}, unturned {unturned}");
}

/// A movable teapot (it shadows itself: its handle, spout and lid) beside a box on a ground.
const TEAPOT: &str = r#"
[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 10
material = { model = "lambert", kd = [0.5, 0.5, 0.5] }

[[object]]
name = "teapot"
source = "builtin:teapot"
resolution = 4
translation = [0.0, 0.0, 0.0]
moves = true
material = { model = "lambert", kd = [0.7, 0.6, 0.5] }

[[object]]
name = "b"
source = "builtin:box"
size = 0.6
resolution = 4
translation = [1.2, 0.3, 0.1]
moves = true
material = { model = "lambert", kd = [0.6, 0.4, 0.3] }
"#;

#[test]
fn the_suns_rays_follow_a_turn_of_an_object_that_shadows_itself() {
    let dir = scratch("turn-sun");
    let mut d = data(TEAPOT, &[("turn_steps", "16")], &dir.join("t.vcuts"));
    let offset = d.svc_origin_offset();
    let sky = vcut_envmap::procedural::PreethamSky::from_elevation_azimuth(40.0, 30.0).bake(128);
    let mut frame = Frame::open(&mut d, &sky, &FrameSettings::default(), None).unwrap();
    assert!(frame.stats().sun_leaves > 0);
    let rest = frame.shade(EYE);
    let error = |f: &Frame, image: &[Vec<Vec3>]| errors(image, &exact_direction(f, EYE, offset)).0;
    let at_rest = error(&frame, &rest);
    let teapot = frame.object_index("teapot").unwrap();
    frame.turn(teapot, 3.0 * STEP).unwrap();
    assert!(frame.stats().last_move.sun_rays > 0, "a turn cast no sun rays");
    let turned = frame.shade(EYE);
    assert!(turned != rest);
    // The teapot's shadows on itself turned with it: near the exact reference, as at rest.
    let after = error(&frame, &turned);
    assert!(after < 1.3 * at_rest, "turned {after}, at rest {at_rest}");
    // Casting every ray again (the sun off and on) gives what the turn cast.
    frame_scene::set(&mut frame, |s| s.sun_rays = false);
    frame_scene::set(&mut frame, |s| s.sun_rays = true);
    assert!(frame.shade(EYE) == turned, "the turn's sun rays differ from a fresh cast");
    frame.turn(teapot, 0.0).unwrap();
    assert!(frame.shade(EYE) == rest, "turned back, the sun's shadows differ");
}

#[test]
fn between_whole_steps_the_svcs_blend_the_two_turns_around_the_yaw() {
    let dir = scratch("turn-blend");
    let mut d = data(TEAPOT, &[("turn_steps", "16")], &dir.join("t.vcuts"));
    let offset = d.svc_origin_offset();
    let sky = vcut_envmap::procedural::PreethamSky::from_elevation_azimuth(40.0, 30.0).bake(128);
    let mut frame = Frame::open(&mut d, &sky, &FrameSettings::default(), None).unwrap();
    let teapot = frame.object_index("teapot").unwrap();
    let mut error = |steps: f32| {
        frame.turn(teapot, steps * STEP).unwrap();
        errors(&frame.shade(EYE), &exact_direction(&frame, EYE, offset)).0
    };
    let (two, three) = (error(2.0), error(3.0));
    let (between, near_two) = (error(2.5), error(2.2));
    // Blended, the error between steps stays that of the whole steps around it (snapped to the
    // nearest, the SVCs would stand 11° off the geometry at 2.5 steps, and this would fail).
    assert!(between < 1.02 * two.max(three), "2.5 steps: {between}; 2 steps {two}, 3 steps {three}");
    assert!(near_two < 1.02 * two.max(three), "2.2 steps: {near_two}; 2 steps {two}, 3 steps {three}");
}
