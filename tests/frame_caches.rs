//! The frame's caches — merged cuts, stored cuts left in the file, lists for a known eye —
//! hold less or start sooner and shade the same.

mod frame_scene;

use frame_scene::{BALL_ABOVE_GROUND, EYE, data, scratch, set, try_set};
use glam::Vec3;
use std::io::Write;
use vcut_data::Precomputed;
use vcut_envmap::EnvMap;
use vcut_scene::Material;
use vcut_shade::{CutFailure, Frame, FrameCaches, FrameError};

#[test]
fn without_the_merged_cache_a_frame_holds_less_and_shades_the_same() {
    let dir = scratch("lean");
    let path = dir.join("b.vcuts");
    let mut d = data(BALL_ABOVE_GROUND, &[], &path);
    let env = EnvMap::constant([1.0; 3]);
    let (moved, behind) = (Vec3::new(0.3, 0.1, -0.2), Vec3::new(-3.0, 2.0, -5.0));
    let mut full = Frame::open(&mut d, &env, &vcut_shade::FrameSettings::default(), None).unwrap();
    let lean_caches = FrameCaches { merged: false, ..FrameCaches::default() };
    let mut lean = Frame::open(
        &mut Precomputed::open(&path).unwrap(),
        &env,
        &vcut_shade::FrameSettings { caches: lean_caches, ..Default::default() },
        None,
    )
    .unwrap();
    assert_eq!((full.stats().caches, lean.stats().caches), (FrameCaches::default(), lean_caches));
    let (m_full, m_lean) = (full.memory(), lean.memory());
    assert!(m_full.merged > 0 && m_lean.merged == 0, "{m_full:?} {m_lean:?}");
    assert!(m_lean.total() < m_full.total());
    assert!(lean.shade(EYE) == full.shade(EYE));
    // A move and a BRDF edit cost the same merges.
    let ball = full.object_index("ball").unwrap();
    assert_eq!(lean.translate(ball, moved).unwrap(), full.translate(ball, moved).unwrap());
    let gold = Material::blinn_phong([0.5, 0.4, 0.1], [0.4, 0.4, 0.4], 40.0);
    let before = lean.stats().merges;
    lean.set_material(ball, gold);
    full.set_material(ball, gold);
    assert_eq!(lean.stats().merges, before, "a BRDF edit merges nothing");
    assert!(lean.shade(EYE) == full.shade(EYE));
    // Every cut, waiting ones too, merged on request is the kept one.
    assert!(lean.pending_merges() > 0);
    let every = |f: &Frame| -> Vec<(usize, usize)> {
        (0..f.object_count()).flat_map(|o| (0..f.object(o).mesh.vertex_count()).map(move |v| (o, v))).collect()
    };
    assert!(every(&lean).into_iter().all(|(o, v)| lean.merged(o, v).unwrap() == full.merged(o, v).unwrap()));
    // A lighting change merges the vertices facing the eye again (the others' lists wait)...
    assert_eq!(lean.merge_pending().unwrap(), full.merge_pending().unwrap());
    let sky = EnvMap::constant([0.5, 1.0, 1.0]);
    let before = lean.stats().merges;
    lean.set_environment(&sky);
    full.set_environment(&sky);
    assert!(lean.stats().merges > before);
    assert!(lean.shade(EYE) == full.shade(EYE));
    // ... and a camera turn those it now sees, where the full frame lists them from its cuts.
    let (turn_full, turn_lean) = (full.set_eye(behind).unwrap(), lean.set_eye(behind).unwrap());
    assert!(turn_full == 0 && turn_lean > 0, "{turn_lean}, {turn_full}");
    assert!(lean.shade(behind) == full.shade(behind));
    set(&mut lean, |s| s.sun_rays = false);
    set(&mut full, |s| s.sun_rays = false);
    assert!(lean.shade(EYE) == full.shade(EYE));
    // Turned on again, the cache is filled with the same cuts.
    set(&mut lean, |s| s.caches.merged = true);
    assert!(lean.memory().merged > 0);
    assert!(every(&lean).into_iter().all(|(o, v)| *lean.merged(o, v).unwrap() == *full.merged(o, v).unwrap()));
    assert!(lean.shade(EYE) == full.shade(EYE));
    // A budget keeps the decoded SVCs if they fit, and no other cache: none under the frame's
    // floor.
    let floor = FrameCaches::NONE;
    set(&mut lean, |s| s.memory_budget = Some(1));
    assert_eq!(lean.stats().caches, floor);
    let m = lean.memory();
    assert_eq!((m.svc_cache, m.field_cache, m.merged), (0, 0, 0));
    assert!(lean.shade(behind) == full.shade(behind));
    // Moves without any cache: the same merges and images, and nothing kept.
    assert_eq!(lean.translate(ball, Vec3::ZERO).unwrap(), full.translate(ball, Vec3::ZERO).unwrap());
    assert_eq!(lean.memory().field_cache, 0);
    assert!(lean.shade(behind) == full.shade(behind));
    // A budget with room keeps the SVCs only; one below what they take, none.
    let (m, svc) = (full.memory(), full.memory().svc_cache);
    set(&mut full, |s| s.memory_budget = Some(u64::MAX));
    assert_eq!(full.stats().caches, FrameCaches { svc: true, ..floor });
    assert!(full.memory().stored * 4 < m.stored, "{:?} of {m:?}", full.memory());
    assert!(full.memory().total() <= m.total() - m.merged - m.field_cache - m.stored / 2);
    let tight = (full.memory().total() - svc + 1) as u64;
    set(&mut full, |s| s.memory_budget = Some(tight));
    assert_eq!(full.stats().caches, floor);
    assert!(lean.shade(EYE) == full.shade(EYE));
    // Without the budget the caches asked for come back (the merged cuts filled: one merge
    // each), and shade the same.
    let before = full.stats().merges;
    set(&mut full, |s| s.memory_budget = None);
    assert_eq!(full.stats().caches, FrameCaches::default());
    let vertices: u64 = (0..full.object_count()).map(|o| full.object(o).mesh.vertex_count() as u64).sum();
    assert_eq!(full.stats().merges - before, vertices);
    assert!(lean.shade(EYE) == full.shade(EYE));
}

/// The stored cuts left in the file: the frame holds only their arrays' headers and block
/// offsets, reads each cut a merge needs from the file it opened (also once its path is gone),
/// and shades what a frame holding them shades; a file changed in place since is refused.
#[test]
fn with_the_stored_cuts_left_in_the_file_a_frame_shades_the_same() {
    let dir = scratch("stored");
    let path = dir.join("s.vcuts");
    let mut d = data(BALL_ABOVE_GROUND, &[], &path);
    let env = EnvMap::constant([1.0; 3]);
    let mut full = Frame::open(&mut d, &env, &vcut_shade::FrameSettings::default(), None).unwrap();
    let none = FrameCaches { stored: false, svc: false, cells: false, merged: false };
    let mut lean = Frame::open(
        &mut Precomputed::open(&path).unwrap(),
        &env,
        &vcut_shade::FrameSettings { caches: none, ..Default::default() },
        None,
    )
    .unwrap();
    assert_eq!(lean.stats().caches, none);
    let (m_full, m_lean) = (full.memory(), lean.memory());
    assert!(m_lean.stored * 4 < m_full.stored, "{m_lean:?} {m_full:?}");
    assert!(lean.shade(EYE) == full.shade(EYE));
    // The path removed: reads go to the file opened.
    let ball = full.object_index("ball").unwrap();
    let ground = full.object_index("ground").unwrap();
    let moved = Vec3::new(0.3, 0.1, -0.2);
    let gone = dir.join("gone.vcuts");
    std::fs::rename(&path, &gone).unwrap();
    assert_eq!(lean.translate(ball, moved).unwrap(), full.translate(ball, moved).unwrap());
    assert!(lean.shade(EYE) == full.shade(EYE));
    assert!(lean.merge_pending().is_ok() && full.merge_pending().is_ok());
    assert!(lean.merged(ground, 7).unwrap() == full.merged(ground, 7).unwrap());
    // Read back into memory (checked against the file's checksums), and out again.
    set(&mut lean, |s| s.caches.stored = true);
    assert_eq!(lean.memory().stored, m_full.stored);
    set(&mut lean, |s| s.caches.stored = false);
    // The file changed in place (every byte after its header): the merges that read it fail,
    // naming the file; nothing panics and the images already shaded stand.
    let len = std::fs::metadata(&gone).unwrap().len();
    let mut bytes = std::fs::read(&gone).unwrap();
    bytes[64..].iter_mut().for_each(|b| *b = b.wrapping_add(1));
    std::fs::OpenOptions::new().write(true).open(&gone).unwrap().write_all(&bytes).unwrap();
    assert_eq!(std::fs::metadata(&gone).unwrap().len(), len);
    let e = lean.translate(ball, Vec3::new(-0.2, 0.1, 0.3)).unwrap_err();
    assert!(matches!(e, FrameError::Cut { error: CutFailure::Decode(_), .. }), "{e}");
    // Named as it was opened.
    assert!(e.to_string().contains(&path.display().to_string()) && e.to_string().contains("changed"), "{e}");
    let e = try_set(&mut lean, |s| s.caches.stored = true).unwrap_err();
    assert!(matches!(e, FrameError::Stored { .. }) && e.to_string().contains("checksum"), "{e}");
}

/// A frame set up for an eye builds the lists of the vertices facing it only, and shades
/// what a frame set up without one shades, toward that eye and after turning away from it.
#[test]
fn a_frame_set_up_for_an_eye_lists_what_faces_it_and_shades_the_same() {
    let dir = scratch("facing");
    let path = dir.join("f.vcuts");
    let mut d = data(BALL_ABOVE_GROUND, &[], &path);
    let env = EnvMap::constant([1.0; 3]);
    let behind = Vec3::new(-3.0, 2.0, -5.0);
    for caches in [FrameCaches::default(), FrameCaches { stored: false, svc: false, cells: false, merged: false }] {
        let mut all =
            Frame::open(&mut d, &env, &vcut_shade::FrameSettings { caches, ..Default::default() }, None).unwrap();
        let mut facing = Frame::open(
            &mut Precomputed::open(&path).unwrap(),
            &env,
            &vcut_shade::FrameSettings { caches, ..Default::default() },
            Some(EYE),
        )
        .unwrap();
        assert!(facing.memory().lists < all.memory().lists, "{:?} {:?}", facing.memory(), all.memory());
        assert!(facing.shade(EYE) == all.shade(EYE));
        let ball = all.object_index("ball").unwrap();
        let moved = Vec3::new(0.2, 0.1, -0.3);
        assert_eq!(facing.translate(ball, moved).unwrap(), all.translate(ball, moved).unwrap());
        assert!(facing.shade(EYE) == all.shade(EYE));
        facing.set_eye(behind).unwrap();
        all.set_eye(behind).unwrap();
        assert!(facing.shade(behind) == all.shade(behind));
    }
}
