//! Shared by the viewer's tests.

use glam::Vec3;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use vcut_data::Precomputed;
use vcut_envmap::EnvMap;
use vcut_envmap::procedural::PreethamSky;
use vcut_precompute::PrecomputeParams;
use vcut_precompute::run::{Job, NoProgress, precompute};
use vcut_scene::{Camera, Scene, SceneDesc};
use vcut_shade::Frame;
use vcut_view::{Gpu, OrbitCamera, Session};

/// The headless device, or `None` (saying the test was skipped): [`vcut_gpu::test_device`].
pub fn gpu(test: &str) -> Option<Gpu> {
    vcut_gpu::test_device(test)
}

/// The sky the sessions are lit by.
#[allow(dead_code)]
pub fn sky() -> EnvMap {
    PreethamSky::default().bake(256)
}

/// A session on the scene `text` (its files written by `files` into its folder first),
/// precomputed at 1,024 directions, seen from (2.5, 2, 3.5).
#[allow(dead_code)]
pub fn session_of(name: &str, text: &str, files: impl FnOnce(&Path)) -> Session {
    session_with(name, text, &[], files)
}

/// [`session_of`] with precompute parameters `params` (each `(key, value)` as `--set` takes
/// it) on top.
#[allow(dead_code)]
pub fn session_with(name: &str, text: &str, params: &[(&str, &str)], files: impl FnOnce(&Path)) -> Session {
    let dir = std::env::temp_dir().join(format!("vcut-view-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    files(&dir);
    let out = dir.join("scene.vcuts");
    let file = dir.join("test.toml");
    let scene: Scene = SceneDesc::parse(text, &file).unwrap().instantiate(&dir, &file).unwrap();
    let mut p = PrecomputeParams::fast();
    for &(k, v) in [("directions", "1024"), ("field_spheres", "12"), ("field_resolution", "8")].iter().chain(params) {
        p.set(k, v).unwrap();
    }
    let job = Job {
        scene: &scene,
        scene_source: "test.toml".into(),
        environment: "sky".into(),
        params: p,
        cache_dir: None,
        output: out.clone(),
    };
    precompute(&job, &NoProgress, &AtomicBool::new(false)).unwrap();
    let mut data = Precomputed::open(&out).unwrap();
    let env = sky();
    let frame = Frame::open(&mut data, &env, &vcut_shade::FrameSettings::default(), None).unwrap();
    let camera = Camera {
        name: "test".into(),
        position: Vec3::new(2.5, 2.0, 3.5),
        target: Vec3::new(0.0, 0.3, 0.0),
        up: Vec3::Y,
        fov_y_deg: 45.0,
    };
    let _ = std::fs::remove_dir_all(&dir);
    Session::new(frame, env, "builtin:sky", data.svc_origin_offset(), OrbitCamera::from_camera(&camera))
}
