//! Shared helpers for the whole-pipeline benches: where the shared assets are.

/// Path of asset `rel`, or `None` after printing that the bench was skipped.
pub fn asset_or_skip(rel: &str) -> Option<std::path::PathBuf> {
    match vcut_scene::assets::locate(rel) {
        Ok(p) => Some(p),
        Err(e) => {
            println!("SKIPPED bench on {rel}: {e}");
            None
        }
    }
}
