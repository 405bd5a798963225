//! Writing whole files: written under `<name>.partial` and renamed, so nothing is ever under
//! the final name until it is complete.

use anyhow::{Context, Result};
use std::path::Path;

/// Writes `bytes` to `path` through `path.partial` and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = path.with_extension("partial");
    std::fs::write(&tmp, bytes).with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))
}
