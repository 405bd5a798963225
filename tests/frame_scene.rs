//! The scene and helpers the frame's tests share (`frame.rs`, `frame_caches.rs`).

use glam::Vec3;
use std::path::{Path, PathBuf};
use vcut_data::Precomputed;

/// A ground and a movable ball above it.
#[allow(dead_code)]
pub const BALL_ABOVE_GROUND: &str = r#"
[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 12
material = { model = "lambert", kd = [0.5, 0.5, 0.5] }

[[object]]
name = "ball"
source = "builtin:sphere"
size = 0.5
resolution = 10
translation = [0.0, 0.8, 0.0]
moves = true
material = { model = "blinn-phong", kd = [0.3, 0.3, 0.3], ks = [0.3, 0.3, 0.3], exponent = 15.0 }
"#;

pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("vcut-shade-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub fn data(text: &str, params: &[(&str, &str)], out: &Path) -> Precomputed {
    let base = [("directions", "1024"), ("field_spheres", "12"), ("field_resolution", "8")];
    vcut_tests::precompute_text(text, &[&base[..], params].concat(), out);
    Precomputed::open(out).unwrap()
}

pub const EYE: Vec3 = Vec3::new(3.0, 4.0, 5.0);

/// `frame` with its settings changed by `change`; returns the vertices it merged.
#[allow(dead_code)]
pub fn set(frame: &mut vcut_shade::Frame, change: impl FnOnce(&mut vcut_shade::FrameSettings)) -> usize {
    try_set(frame, change).unwrap()
}

/// [`set`], its error returned.
#[allow(dead_code)]
pub fn try_set(
    frame: &mut vcut_shade::Frame,
    change: impl FnOnce(&mut vcut_shade::FrameSettings),
) -> Result<usize, vcut_shade::FrameError> {
    let mut s = frame.settings().clone();
    change(&mut s);
    frame.reconfigure(&s)
}
