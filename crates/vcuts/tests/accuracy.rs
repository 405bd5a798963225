//! The accuracy section's measurement on a small scene: a constant map casts no leaf by rays and
//! shades exactly as the cuts alone; under the sky the sun's leaves are cast, and the rays take
//! error away.

use glam::Vec3;
use vcut_data::Precomputed;
use vcut_shade::Frame;
use vcut_shade::measure::first_movable;
use vcuts::accuracy::{AccuracySection, Subject, builtin_maps, measure_map};

mod common;
use common::scratch;

#[test]
fn a_constant_map_casts_nothing_and_the_sun_is_cast_by_rays() {
    let s = scratch("accuracy");
    let scene = s.0.join("scene.toml");
    let mut args = vcuts::precompute::PrecomputeArgs::new(scene.to_str().unwrap(), "fast");
    args.set = vec!["directions=1024".into()];
    args.output = Some(s.0.join("a.vcuts"));
    args.cache_dir = s.0.join("cache");
    args.estimate.seconds = 0.1;
    args.preset = None;
    let (file, _) = vcuts::precompute::run(&args).unwrap();
    let mut data = Precomputed::open(&file).unwrap();
    let offset = data.svc_origin_offset();
    let env = vcut_envmap::EnvMap::constant([1.0; 3]);
    let mut frame = Frame::new(&mut data, &env).unwrap();
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
        assert_eq!(c.rays_per_move, 0.0);
        let sky = row("sky-30", pose);
        assert!(sky.sun_leaves >= 1, "{sky:?}");
        assert!(sky.rel_l2_exact < sky.rel_l2_exact_cuts_only, "{sky:?}");
    }
    assert!(row("sky-30", "rest").rays_per_move > 0.0);
    let worst = section.worst("fast").unwrap();
    assert!(section.rows.iter().all(|r| r.rel_l2_exact <= worst.rel_l2_exact));
    assert!(section.table().contains("Worst at `fast`"));
}
