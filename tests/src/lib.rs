//! Helpers shared by the cross-crate tests: where the shared assets are, scratch folders, a
//! scene file's text precomputed, and small hand-built files (RGBE, GLB) for malformed-input
//! tests.

use std::path::{Path, PathBuf};

/// The shared assets folder, or `None` after printing a notice that `test` was skipped.
///
/// The notice goes straight to the process's stderr: the test harness captures `println!` and
/// `eprintln!` and shows them only for failing tests, and a skip must be seen.
pub fn assets_or_skip(test: &str) -> Option<PathBuf> {
    match vcut_scene::assets::dir() {
        Some(d) => Some(d),
        None => {
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "SKIPPED {test}: shared assets folder not found (set VCUT_ASSETS)");
            None
        }
    }
}

/// A movable ball resting on a flat ground (two Lambertian objects): the smallest scene with a
/// contact, a field and a flat occluder.
pub const BALL_ON_GROUND: &str = r#"
[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 16
material = { model = "lambert", kd = [0.5, 0.5, 0.5] }

[[object]]
name = "ball"
source = "builtin:sphere"
size = 0.5
resolution = 12
translation = [0.0, 0.5, 0.0]
moves = true
material = { model = "lambert", kd = [0.5, 0.5, 0.5] }
"#;

/// The environment maps among the shared assets (lat-long files and the cube folder).
pub const ENVIRONMENT_MAPS: [&str; 6] = [
    "envmaps/quarry_01_1k.hdr",
    "envmaps/royal_esplanade_1k.hdr",
    "envmaps/spruit_sunrise_1k.hdr",
    "envmaps/grace.hdr",
    "envmaps/pisa.hdr",
    "envmaps/pisa_cube",
];

/// A scratch folder, removed when dropped.
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A fresh scratch folder under the system temp dir, unique to this process and `name`.
pub fn scratch(name: &str) -> Scratch {
    let d = std::env::temp_dir().join(format!("vcut-tests-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create scratch dir");
    Scratch(d)
}

/// A flat (uncompressed) Radiance RGBE file of `w × h` texels of one colour.
pub fn rgbe_flat(w: usize, h: usize, rgb: [f32; 3]) -> Vec<u8> {
    let mut out = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
    let max = rgb.iter().cloned().fold(0.0f32, f32::max);
    let texel = if max < 1e-32 {
        [0u8; 4]
    } else {
        let e = max.log2().floor() as i32 + 1;
        let scale = 256.0 / 2f32.powi(e);
        [(rgb[0] * scale) as u8, (rgb[1] * scale) as u8, (rgb[2] * scale) as u8, (e + 128) as u8]
    };
    for _ in 0..w * h {
        out.extend_from_slice(&texel);
    }
    out
}

/// A binary glTF with one triangle, whose buffer declares `declared_len` bytes while the BIN
/// chunk holds `actual_len` (36 bytes are needed for three float positions).
pub fn glb_triangle(declared_len: usize, actual_len: usize) -> Vec<u8> {
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
"bufferViews":[{{"buffer":0,"byteLength":36}}],"buffers":[{{"byteLength":{declared_len}}}]}}"#
    );
    let mut json = json.into_bytes();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let mut bin: Vec<u8> =
        [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0].iter().flat_map(|f| f.to_le_bytes()).collect();
    bin.resize(actual_len, 0);
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// Writes `bytes` to `dir/name` and returns the path.
pub fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).expect("write scratch file");
    p
}

/// Standard base64 (for `data:` URIs in hand-written glTF files).
pub fn base64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n =
            (u32::from(c[0]) << 16) | (u32::from(*c.get(1).unwrap_or(&0)) << 8) | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                out.push(T[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The scene file `text` precomputed into `out` at the `fast` preset with `params` set on top
/// (each `(key, value)` as `precompute --set` takes it), under a constant environment.
pub fn precompute_text(text: &str, params: &[(&str, &str)], out: &Path) -> vcut_precompute::run::Summary {
    use vcut_precompute::run::{Job, NoProgress, precompute};
    let file = Path::new("test.toml");
    let scene = vcut_scene::SceneDesc::parse(text, file).unwrap().instantiate(Path::new("."), file).unwrap();
    let mut p = vcut_precompute::PrecomputeParams::fast();
    for (k, v) in params {
        p.set(k, v).unwrap();
    }
    let job = Job {
        scene: &scene,
        scene_source: "test.toml".into(),
        environment: "constant".into(),
        params: p,
        cache_dir: None,
        output: out.into(),
    };
    precompute(&job, &NoProgress, &std::sync::atomic::AtomicBool::new(false)).unwrap()
}
