//! On-disk cache of generated direction sets, keyed by (N, start, seed, parameters, algorithm
//! version) and reloaded bit-identically. Format (little-endian): magic `VCDIRS01`, u32 algorithm
//! version, u64 N, N × 3 f32, u64 FNV-1a checksum of everything before it. Written to a
//! temporary name and renamed, so a cache file is whole or absent.

use crate::{ALGORITHM_VERSION, DirectionSet, RepulsionParams, SphereError};
use glam::Vec3;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"VCDIRS01";

fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The cache file name for a set.
pub fn file_name(n: usize, p: &RepulsionParams) -> String {
    let knobs =
        format!("{}:{}:{}:{}:{:?}:{}", p.kernel_radius, p.step, p.tolerance, p.max_iterations, p.integrator, p.window);
    let wedges = if p.wedges > 1 { format!("-w{}", p.wedges) } else { String::new() };
    format!(
        "directions-v{ALGORITHM_VERSION}-{}-n{n}{wedges}-seed{}-{:08x}.bin",
        p.start.name(),
        p.seed,
        fnv1a(knobs.as_bytes()) as u32
    )
}

/// Serialises directions.
pub fn encode(dirs: &[Vec3]) -> Vec<u8> {
    let mut out = Vec::with_capacity(28 + dirs.len() * 12);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&ALGORITHM_VERSION.to_le_bytes());
    out.extend_from_slice(&(dirs.len() as u64).to_le_bytes());
    for d in dirs {
        for c in d.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    let sum = fnv1a(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// Parses [`encode`]'s output, checking magic, version, length and checksum.
pub fn decode(bytes: &[u8], path: &Path) -> Result<Vec<Vec3>, SphereError> {
    let bad = |reason: String| SphereError::Cache { path: path.into(), reason };
    if bytes.len() < 28 || &bytes[..8] != MAGIC {
        return Err(bad("not a direction cache file".into()));
    }
    let version = u32::from_le_bytes(bytes[8..12].try_into().map_err(|_| bad("short header".into()))?);
    if version != ALGORITHM_VERSION {
        return Err(bad(format!("algorithm version {version}, expected {ALGORITHM_VERSION}")));
    }
    let n = u64::from_le_bytes(bytes[12..20].try_into().map_err(|_| bad("short header".into()))?) as usize;
    let need = n.checked_mul(12).and_then(|x| x.checked_add(28)).ok_or_else(|| bad("bad count".into()))?;
    if bytes.len() != need {
        return Err(bad(format!("{} bytes, expected {need} for {n} directions", bytes.len())));
    }
    let body = &bytes[..need - 8];
    let sum = u64::from_le_bytes(bytes[need - 8..].try_into().map_err(|_| bad("short".into()))?);
    if fnv1a(body) != sum {
        return Err(bad("checksum mismatch".into()));
    }
    Ok(body[20..]
        .chunks_exact(12)
        .map(|c| {
            let f = |k: usize| f32::from_le_bytes([c[k], c[k + 1], c[k + 2], c[k + 3]]);
            Vec3::new(f(0), f(4), f(8))
        })
        .collect())
}

/// Whether [`DirectionSet::load_or_generate`] found the set in the cache.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CacheOutcome {
    /// Read from this file.
    Hit(PathBuf),
    /// Generated and written to this file.
    Stored(PathBuf),
    /// Generated; the cached file was unusable (the reason) and has been replaced.
    Replaced(PathBuf, String),
}

impl DirectionSet {
    /// Loads the set from `dir` if cached there, otherwise generates and stores it.
    pub fn load_or_generate(
        dir: &Path,
        n: usize,
        params: &RepulsionParams,
        progress: impl FnMut(u32, f64),
    ) -> Result<(DirectionSet, CacheOutcome), SphereError> {
        let path = dir.join(file_name(n, params));
        let mut stale = None;
        if let Ok(bytes) = std::fs::read(&path) {
            match decode(&bytes, &path) {
                Ok(dirs) if dirs.len() == n => {
                    return Ok((DirectionSet::from_directions(dirs, *params)?, CacheOutcome::Hit(path)));
                }
                Ok(_) => stale = Some("wrong count".to_string()),
                Err(e) => stale = Some(e.to_string()),
            }
        }
        let set = DirectionSet::generate(n, params, progress)?;
        std::fs::create_dir_all(dir).map_err(|e| SphereError::Cache { path: dir.into(), reason: e.to_string() })?;
        let tmp = path.with_extension(format!("tmp{}", std::process::id()));
        std::fs::write(&tmp, encode(set.directions()))
            .and_then(|()| std::fs::rename(&tmp, &path))
            .map_err(|e| SphereError::Cache { path: path.clone(), reason: e.to_string() })?;
        let outcome = match stale {
            Some(r) => CacheOutcome::Replaced(path, r),
            None => CacheOutcome::Stored(path),
        };
        Ok((set, outcome))
    }
}
