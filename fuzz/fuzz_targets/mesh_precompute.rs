//! Fuzz target: small arbitrary meshes through the whole precompute. A mesh of up to 8 vertices
//! and 12 triangles (repeated, zero-area, inverted, coincident triangles included), written as
//! an OBJ and placed as a movable object on a ground plane, is refused when it loads with a
//! clear error, or precomputes at tiny parameters into a file that opens, whose frame shades
//! finite, non-negative radiance at rest and after a move.
#![no_main]

use glam::Vec3;
use libfuzzer_sys::fuzz_target;
use std::fmt::Write;
use std::path::PathBuf;
use std::sync::OnceLock;
use std::sync::atomic::AtomicBool;
use vcut_data::Precomputed;
use vcut_precompute::PrecomputeParams;
use vcut_precompute::run::{Job, NoProgress, precompute};
use vcut_scene::{Scene, SceneDesc};
use vcut_shade::Frame;

/// This process's scratch folder.
fn dir() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = std::env::temp_dir().join(format!("vcut-fuzz-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&d).expect("a scratch folder");
        d
    })
}

const SCENE: &str = r#"
[environment]
source = "builtin:sky"
resolution = 64

[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 4

[[object]]
name = "fuzzed"
source = "mesh.obj"
translation = [0.0, 1.0, 0.0]
moves = true
"#;

fuzz_target!(|data: &[u8]| {
    let [nv, nt, rest @ ..] = data else { return };
    let nv = usize::from(*nv % 8) + 1;
    let nt = usize::from(*nt % 12) + 1;
    let mut bytes = rest.iter().copied().chain(std::iter::repeat(0));
    let mut obj = String::new();
    for _ in 0..nv {
        // Coordinates in [-1, 1] on a grid of 1/8, so coincident and collinear points are common.
        let mut c = || f32::from(bytes.next().unwrap_or(0) % 17) / 8.0 - 1.0;
        let (x, y, z) = (c(), c(), c());
        writeln!(obj, "v {x} {y} {z}").unwrap();
    }
    for _ in 0..nt {
        let mut i = || usize::from(bytes.next().unwrap_or(0)) % nv + 1;
        let (a, b, c) = (i(), i(), i());
        writeln!(obj, "f {a} {b} {c}").unwrap();
    }
    let dir = dir();
    std::fs::write(dir.join("mesh.obj"), &obj).expect("writing the mesh");
    let file = dir.join("scene.toml");
    let scene: Scene = match SceneDesc::parse(SCENE, &file).and_then(|d| d.instantiate(dir, &file)) {
        Ok(s) => s,
        Err(e) => {
            let text = e.to_string();
            assert!(text.contains("mesh.obj") || text.contains("fuzzed"), "an error that names nothing: {text}");
            return;
        }
    };
    let mut params = PrecomputeParams::fast();
    for (k, v) in [("directions", "256"), ("field_spheres", "2"), ("field_resolution", "2")] {
        params.set(k, v).expect("tiny parameters");
    }
    let out = dir.join("out.vcuts");
    let _ = std::fs::remove_file(&out);
    let job = Job {
        scene: &scene,
        scene_source: file.display().to_string(),
        environment: "scene".into(),
        params,
        cache_dir: Some(dir.join("cache")),
        output: out.clone(),
    };
    precompute(&job, &NoProgress, &AtomicBool::new(false)).expect("a loaded mesh precomputes");
    let mut data = Precomputed::open(&out).expect("the precompute's file opens");
    let mut frame = Frame::open(&mut data, &scene.environment, &vcut_shade::FrameSettings::default(), None)
        .expect("a frame of the file");
    let eye = Vec3::new(3.0, 4.0, 5.0);
    let finite = |r: &[Vec<Vec3>]| r.iter().flatten().all(|x| x.is_finite() && x.min_element() >= 0.0);
    assert!(finite(&frame.shade(eye)), "non-finite radiance at rest");
    frame.translate(1, Vec3::new(0.3, 0.0, -0.2)).expect("a move");
    assert!(finite(&frame.shade(eye)), "non-finite radiance after a move");
});
