//! Finding the shared test assets (`shared/assets` beside the repository) that some built-in
//! scenes use, e.g. `builtin:bunny`'s Stanford bunny.
//!
//! Search order: if `VCUT_ASSETS` is set, that folder and nothing else (set it to a folder that
//! does not exist to run as if there were no assets); otherwise `shared/assets` and
//! `../shared/assets` under the current directory and each of its ancestors, then the same under
//! this crate's source folder and its ancestors (so tests and benches find it from anywhere in
//! the workspace).

use crate::SceneError;
use std::path::{Path, PathBuf};

/// The environment variable that names the assets folder explicitly.
pub const ENV_VAR: &str = "VCUT_ASSETS";

fn candidates() -> Vec<PathBuf> {
    let mut out = Vec::new();
    if let Some(dir) = std::env::var_os(ENV_VAR) {
        out.push(PathBuf::from(dir));
        return out;
    }
    let mut roots: Vec<PathBuf> = Vec::new();
    if let Ok(cwd) = std::env::current_dir() {
        roots.push(cwd);
    }
    roots.push(PathBuf::from(env!("CARGO_MANIFEST_DIR")));
    for root in roots {
        for anc in root.ancestors() {
            out.push(anc.join("shared").join("assets"));
            out.push(anc.join("..").join("shared").join("assets"));
        }
    }
    out
}

/// The assets folder, if one is found.
pub fn dir() -> Option<PathBuf> {
    candidates().into_iter().find(|p| p.join("SOURCES.md").is_file() || p.join("meshes").is_dir())
}

/// The path of asset `rel` (e.g. `meshes/stanford-bunny.obj`), or an error that says where it
/// was looked for.
pub fn locate(rel: &str) -> Result<PathBuf, SceneError> {
    let rel_path = Path::new(rel);
    let searched = candidates();
    for c in &searched {
        let p = c.join(rel_path);
        if p.exists() {
            return Ok(p);
        }
    }
    Err(SceneError::AssetMissing {
        name: rel.into(),
        searched: searched.iter().take(6).map(|p| p.display().to_string()).collect::<Vec<_>>().join(", "),
    })
}
