//! The accuracy section's measurement on a small scene: a constant map casts no leaf by rays and
//! shades exactly as the cuts alone; under the sky the sun's leaves are cast, and the rays take
//! error away; two suns and a window get their bright leaves cast; the target error moves the
//! error monotonically.

use glam::Vec3;
use vcut_data::Precomputed;
use vcut_shade::Frame;
use vcut_shade::measure::first_movable;
use xtask::measure::accuracy::{AccuracySection, Subject, builtin_maps, measure_map};

use vcut_tests::{Scratch, scratch};

/// The test scene at 1,024 directions (4 field spheres of 4 × 4 texels a face), precomputed in
/// `s`.
fn precomputed(s: &Scratch) -> Precomputed {
    let out = s.join("scene.vcuts");
    let params = [("directions", "1024"), ("field_spheres", "4"), ("field_resolution", "4"), ("svc_chunk", "64")];
    vcut_tests::precompute_text(vcut_tests::BALL_ON_GROUND, &params, &out);
    Precomputed::open(&out).unwrap()
}

#[test]
fn a_constant_map_casts_nothing_and_the_sun_is_cast_by_rays() {
    let s = scratch("accuracy");
    let mut data = precomputed(&s);
    let offset = data.svc_origin_offset();
    let env = vcut_envmap::EnvMap::constant([1.0; 3]);
    let mut frame = Frame::open(&mut data, &env, &vcut_shade::FrameSettings::default(), None).unwrap();
    let movable = first_movable(&frame).unwrap();
    let subject = Subject { scene: "test", preset: "fast", movable, eye: Vec3::new(0.0, 3.0, 5.0), offset };
    let mut section = AccuracySection::default();
    for (name, map) in builtin_maps(true) {
        section.rows.extend(measure_map(&mut frame, &subject, &name, &map, None).unwrap());
    }
    let row = |map: &str, pose: &str| section.rows.iter().find(|r| r.map == map && r.pose == pose).unwrap();
    for pose in ["rest", "moved"] {
        let c = row("constant", pose);
        assert_eq!(c.sun_leaves, 0, "{c:?}");
        assert_eq!(c.rel_l2_exact, c.rel_l2_exact_cuts_only, "no leaf cast: the same shading, bit for bit");
        assert_eq!((c.rays_per_move, c.rays_share_edit, c.rays_share_move), (0.0, 0.0, 0.0));
        let sky = row("sky-30", pose);
        assert!(sky.sun_leaves >= 1, "{sky:?}");
        assert!(sky.rel_l2_exact < sky.rel_l2_exact_cuts_only, "{sky:?}");
    }
    assert!(row("sky-30", "rest").rays_per_move > 0.0);
    let worst = section.worst("fast").unwrap();
    assert!(section.rows.iter().all(|r| r.rel_l2_exact <= worst.rel_l2_exact));
    assert!(section.table().contains("Worst at `fast`"));
}

/// A 256×128 lat-long map of a dim sky (0.2) with bright regions: texels whose direction
/// `bright` accepts get `radiance`.
fn map_with(bright: impl Fn(Vec3) -> bool, radiance: f32) -> vcut_envmap::EnvMap {
    let (w, h) = (256u32, 128u32);
    let texels = (0..w * h)
        .map(|i| {
            let d = vcut_envmap::layout::latlong_dir(
                (f64::from(i % w) + 0.5) / f64::from(w),
                (f64::from(i / w) + 0.5) / f64::from(h),
            );
            if bright(d) { [radiance; 3] } else { [0.2; 3] }
        })
        .collect();
    let layout = vcut_envmap::Layout::LatLong { width: w, height: h };
    vcut_envmap::EnvMap::new(layout, texels, "test map", vcut_envmap::InvalidTexels::Reject).unwrap().0
}

/// The direction at `elevation` degrees above the horizon and `azimuth` degrees from −Z towards +X.
fn dir(elevation: f32, azimuth: f32) -> Vec3 {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    Vec3::new(e.cos() * a.sin(), e.sin(), -e.cos() * a.cos())
}

fn angle_deg(a: Vec3, b: Vec3) -> f32 {
    a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
}

#[test]
fn two_suns_and_a_window_get_their_bright_leaves_cast_and_the_target_moves_the_error() {
    let s = scratch("accuracy-suns");
    let mut data = precomputed(&s);
    let offset = data.svc_origin_offset();
    let mut frame =
        Frame::open(&mut data, &vcut_envmap::EnvMap::constant([1.0; 3]), &vcut_shade::FrameSettings::default(), None)
            .unwrap();
    let eye = Vec3::new(0.0, 3.0, 5.0);
    let cast_dirs = |frame: &Frame| -> Vec<Vec3> {
        frame.light_choice().cast.iter().map(|&l| frame.tree().leaf_directions()[l as usize]).collect()
    };
    let error = |frame: &mut Frame| {
        let exact = vcut_shade::reference::exact_direction(frame, eye, offset);
        vcut_shade::reference::errors(&frame.shade(eye), &exact).0
    };

    // Two suns 2° across, 10⁴ times the sky, 80° apart: each gets a leaf within 10°.
    let suns = [dir(40.0, 20.0), dir(50.0, 120.0)];
    frame.set_environment(&map_with(|d| suns.iter().any(|&s| angle_deg(d, s) < 1.0), 2000.0));
    let cast = cast_dirs(&frame);
    for sun in suns {
        assert!(cast.iter().any(|&d| angle_deg(d, sun) < 10.0), "no leaf cast near the sun at {sun}: {cast:?}");
    }
    let with_rays = error(&mut frame);
    frame.reconfigure(&vcut_shade::FrameSettings { sun_rays: false, ..frame.settings().clone() }).unwrap();
    let cuts_only = error(&mut frame);
    assert!(with_rays < cuts_only, "two suns: {with_rays} with rays, {cuts_only} through the cuts");

    // A window 30° wide and 20° high, 150 times the sky: its leaves are cast, nothing outside it.
    let window = |d: Vec3| {
        let (e, a) = (d.y.asin().to_degrees(), d.x.atan2(-d.z).to_degrees());
        (20.0..40.0).contains(&e) && (-15.0..15.0).contains(&a)
    };
    let window_map = map_with(window, 30.0);
    frame.reconfigure(&vcut_shade::FrameSettings { sun_rays: true, ..frame.settings().clone() }).unwrap();
    frame.set_environment(&window_map);
    let cast = cast_dirs(&frame);
    assert!(!cast.is_empty(), "the window casts nothing");
    for d in &cast {
        // Within the window or one leaf (about 6° across at 1,024 directions) from its edge.
        assert!(angle_deg(*d, dir(30.0, 0.0)) < 18.0 + 8.0, "a leaf cast outside the window: {d}");
    }
    let with_rays = error(&mut frame);
    frame.reconfigure(&vcut_shade::FrameSettings { sun_rays: false, ..frame.settings().clone() }).unwrap();
    let cuts_only = error(&mut frame);
    assert!(with_rays < cuts_only, "window: {with_rays} with rays, {cuts_only} through the cuts");

    // The target: smaller casts the same leaves and more, and the error does not grow.
    frame.reconfigure(&vcut_shade::FrameSettings { sun_rays: true, ..frame.settings().clone() }).unwrap();
    let before = frame.settings().clone();
    let movable = first_movable(&frame).unwrap();
    let subject = Subject { scene: "test", preset: "fast", movable, eye, offset };
    let knob = xtask::measure::accuracy::measure_knob(&mut frame, &subject, "window", &window_map).unwrap();
    assert_eq!(knob.len(), xtask::measure::accuracy::KNOB_TARGETS.len());
    for pair in knob.windows(2) {
        assert!(pair[1].leaves >= pair[0].leaves, "{pair:?}");
        assert!(pair[1].rel_l2_exact <= pair[0].rel_l2_exact + 1e-6, "{pair:?}");
    }
    let (loose, tight) = (&knob[0], &knob[knob.len() - 1]);
    assert!(tight.leaves > loose.leaves && tight.rel_l2_exact < loose.rel_l2_exact, "{loose:?} {tight:?}");
    assert_eq!(frame.settings(), &before, "the sweep restores the setting");
}
