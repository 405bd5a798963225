//! A small scene for the command-line tests, and a scratch folder that cleans up after itself
//! (unmounting what a test mounted there).

#![allow(dead_code)]

use std::path::PathBuf;
use std::process::Command;

/// Two objects at the `fast` preset with few directions: precomputes in about a second.
pub const SCENE: &str = r#"
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
translation = [0.0, 0.7, 0.0]
moves = true

[precompute]
preset = "fast"
directions = 256
field_spheres = 4
field_resolution = 4
svc_chunk = 64
"#;

/// A scratch folder holding `scene.toml`; removed when dropped.
pub struct Scratch(pub PathBuf);

impl Drop for Scratch {
    fn drop(&mut self) {
        let mnt = self.0.join("mnt");
        if mnt.exists() {
            let _ = Command::new("umount").arg(&mnt).status();
        }
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A fresh scratch folder for the test `name`.
pub fn scratch(name: &str) -> Scratch {
    let d = std::env::temp_dir().join(format!("vcuts-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    Scratch(d)
}

/// Scene file `scene` in `s` precomputed at `fast` with the extra settings `set` (e.g.
/// `directions=1024`) and opened.
pub fn precomputed(s: &Scratch, scene: &str, set: &[&str]) -> vcut_data::Precomputed {
    let mut args = vcuts::precompute::PrecomputeArgs::new(s.0.join(scene).to_str().unwrap(), "fast");
    args.set = set.iter().map(|x| x.to_string()).collect();
    args.output = Some(s.0.join(scene).with_extension("vcuts"));
    args.cache_dir = s.0.join("cache");
    args.estimate.seconds = 0.1;
    args.preset = None;
    let file = vcuts::precompute::run(&args).unwrap().file;
    vcut_data::Precomputed::open(&file).unwrap()
}
