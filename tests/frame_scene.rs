//! The scenes and helpers the frame's tests share (`frame.rs`, `frame_caches.rs`, `frame_drag.rs`,
//! `frame_refine.rs`).

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

#[allow(dead_code)]
/// Parts that nearly touch on a ground: every part's field reaches the others' vertices.
pub const ASSEMBLY: &str = r#"
[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 10
material = { model = "lambert", kd = [0.5, 0.5, 0.5] }

[[object]]
name = "a"
source = "builtin:sphere"
size = 0.5
resolution = 8
translation = [0.0, 0.55, 0.0]
moves = true
material = { model = "blinn-phong", kd = [0.3, 0.3, 0.3], ks = [0.3, 0.3, 0.3], exponent = 15.0 }

[[object]]
name = "b"
source = "builtin:box"
size = 0.6
resolution = 4
translation = [0.75, 0.35, 0.1]
moves = true
material = { model = "lambert", kd = [0.6, 0.4, 0.3] }

[[object]]
name = "c"
source = "builtin:sphere"
size = 0.4
resolution = 8
translation = [-0.6, 0.45, 0.4]
moves = true
material = { model = "lambert", kd = [0.2, 0.5, 0.6] }
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

/// Every vertex's merged cut (heights, and values' bits), pending merges done first.
#[allow(dead_code)]
pub fn cuts(frame: &mut vcut_shade::Frame) -> Vec<(Vec<u8>, Vec<u32>)> {
    frame.merge_pending().unwrap();
    (0..frame.object_count())
        .flat_map(|o| (0..frame.object(o).mesh.vertex_count()).map(move |v| (o, v)))
        .map(|(o, v)| {
            let c = frame.merged(o, v).unwrap();
            (c.heights.clone(), c.values.iter().map(|x| x.to_bits()).collect())
        })
        .collect()
}
