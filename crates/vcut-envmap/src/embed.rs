//! A map as bytes, losslessly: what a `.vcuts` file embeds so that it renders under the light it
//! was precomputed for on any machine, with no map file beside it.
//!
//! Little-endian: `VCENV` and version byte 2; the layout (`0` lat-long: width, height as u32;
//! `1` cube: size as u32 and the handedness byte, `0` mirrored-x, `1` literal); the rotation
//! quaternion (x, y, z, w) and the intensity as f32; the reconstruction byte (`0` box, `1`
//! bilinear; absent in version 1, which is box); the source's name (u32 length, UTF-8); then
//! every texel as three f32. Decoding checks every length and texel (finite, ≥ 0) and names the
//! source in its errors.

use crate::{CubeHandedness, EnvMap, EnvMapError, InvalidTexels, Layout, Reconstruction};
use glam::Quat;

/// `VCENV` and the version written.
const MAGIC: &[u8; 6] = b"VCENV\x02";

/// `map` as bytes (exactly: decoding gives back the same texels, rotation and intensity).
pub fn encode(map: &EnvMap) -> Vec<u8> {
    let mut out = Vec::with_capacity(64 + 12 * map.texels().len());
    out.extend_from_slice(MAGIC);
    match map.layout() {
        Layout::LatLong { width, height } => {
            out.push(0);
            out.extend_from_slice(&width.to_le_bytes());
            out.extend_from_slice(&height.to_le_bytes());
        }
        Layout::Cube { size, handedness } => {
            out.push(1);
            out.extend_from_slice(&size.to_le_bytes());
            out.push(match handedness {
                CubeHandedness::MirroredX => 0,
                CubeHandedness::Literal => 1,
            });
        }
    }
    for x in map.rotation().to_array().into_iter().chain([map.intensity()]) {
        out.extend_from_slice(&x.to_le_bytes());
    }
    out.push(match map.reconstruction() {
        Reconstruction::Box => 0,
        Reconstruction::Bilinear => 1,
    });
    let source = map.source().as_bytes();
    out.extend_from_slice(&(source.len() as u32).to_le_bytes());
    out.extend_from_slice(source);
    for t in map.texels() {
        for c in t {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    out
}

/// Reads bytes [`encode`] wrote; `name` (e.g. the file and section they came from) is named in
/// every error.
pub fn decode(bytes: &[u8], name: &str) -> Result<EnvMap, EnvMapError> {
    let bad = |reason: String| EnvMapError::Shape { path: name.into(), reason };
    let mut r = Cursor { bytes, at: 0 };
    let version = match r.take(MAGIC.len()) {
        Ok(m) if m[..5] == MAGIC[..5] && (1..=2).contains(&m[5]) => m[5],
        _ => return Err(bad("not an embedded environment map (no VCENV 1 or 2 header)".into())),
    };
    let short = |what: &str| bad(format!("truncated in the {what}"));
    let layout = match r.u8().map_err(|_| short("layout"))? {
        0 => {
            let width = r.u32().map_err(|_| short("layout"))?;
            let height = r.u32().map_err(|_| short("layout"))?;
            Layout::LatLong { width, height }
        }
        1 => {
            let size = r.u32().map_err(|_| short("layout"))?;
            let handedness = match r.u8().map_err(|_| short("layout"))? {
                0 => CubeHandedness::MirroredX,
                1 => CubeHandedness::Literal,
                h => return Err(bad(format!("unknown cube handedness {h}"))),
            };
            Layout::Cube { size, handedness }
        }
        k => return Err(bad(format!("unknown layout kind {k}"))),
    };
    let mut q = [0f32; 5];
    for x in &mut q {
        *x = r.f32().map_err(|_| short("rotation and intensity"))?;
    }
    let rotation = Quat::from_array([q[0], q[1], q[2], q[3]]);
    if !rotation.is_finite() || (rotation.length() - 1.0).abs() > 1e-3 {
        return Err(bad(format!("rotation {:?} is not a unit quaternion", &q[..4])));
    }
    if !(q[4].is_finite() && q[4] >= 0.0) {
        return Err(bad(format!("intensity {} is not finite and ≥ 0", q[4])));
    }
    let reconstruction = match version {
        1 => Reconstruction::Box,
        _ => match r.u8().map_err(|_| short("reconstruction"))? {
            0 => Reconstruction::Box,
            1 => Reconstruction::Bilinear,
            k => return Err(bad(format!("unknown reconstruction {k}"))),
        },
    };
    let len = r.u32().map_err(|_| short("source name"))? as usize;
    let source = std::str::from_utf8(r.take(len).map_err(|_| short("source name"))?)
        .map_err(|_| bad("the source name is not UTF-8".into()))?
        .to_owned();
    let rest = r.rest();
    let expected = layout.texel_count();
    let needed = expected.saturating_mul(12);
    if expected == 0 || rest.len() != needed {
        return Err(bad(format!("{} needs {needed} bytes of texels, found {}", layout.describe(), rest.len())));
    }
    let texels = rest
        .chunks_exact(12)
        .map(|t| {
            let c = |k: usize| f32::from_le_bytes([t[4 * k], t[4 * k + 1], t[4 * k + 2], t[4 * k + 3]]);
            [c(0), c(1), c(2)]
        })
        .collect();
    let (mut map, _) = EnvMap::new(layout, texels, format!("{name} (embedded from {source})"), InvalidTexels::Reject)?;
    map.set_rotation(rotation);
    map.set_intensity(q[4]);
    map.with_reconstruction(reconstruction)
}

struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], ()> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len()).ok_or(())?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8, ()> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, ()> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn f32(&mut self) -> Result<f32, ()> {
        Ok(f32::from_bits(self.u32()?))
    }
    fn rest(&self) -> &'a [u8] {
        &self.bytes[self.at..]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_round_trip_exactly_and_damage_is_refused_by_name() {
        let mut sky = crate::procedural::PreethamSky::default().bake(64);
        sky.set_rotation_y_degrees(37.0);
        sky.set_intensity(2.5);
        let cube = EnvMap::new(
            Layout::Cube { size: 2, handedness: CubeHandedness::Literal },
            (0..24).map(|i| [i as f32, 0.5, 1.0]).collect(),
            "cube",
            InvalidTexels::Reject,
        )
        .unwrap()
        .0;
        let bilinear =
            crate::procedural::Studio::default().bake(32).with_reconstruction(Reconstruction::Bilinear).unwrap();
        for map in [sky, cube, EnvMap::constant([0.3, 0.2, 0.1]), bilinear] {
            let bytes = encode(&map);
            let back = decode(&bytes, "t.vcuts: environment").unwrap();
            assert_eq!(back.layout(), map.layout());
            assert_eq!(back.texels(), map.texels());
            assert_eq!(back.rotation(), map.rotation());
            assert_eq!(back.intensity(), map.intensity());
            assert_eq!(back.reconstruction(), map.reconstruction());
            assert_eq!(back.integrated_texels(), map.integrated_texels());
            assert!(back.source().contains(map.source()), "{}", back.source());
            // Every truncation is an error naming the section, never a panic.
            for cut in [0, 5, 7, 12, 30, bytes.len() - 1] {
                let e = decode(&bytes[..cut], "t.vcuts: environment").unwrap_err().to_string();
                assert!(e.contains("t.vcuts: environment"), "{e}");
            }
        }
        let mut nan = encode(&EnvMap::constant([1.0; 3]));
        let n = nan.len();
        nan[n - 4..].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = decode(&nan, "t.vcuts: environment").unwrap_err().to_string();
        assert!(e.contains("NaN"), "{e}");
        // Version 1 (no reconstruction byte) still reads, as box.
        let v2 = encode(&EnvMap::constant([1.0; 3]));
        let mut v1 = v2[..6 + 9 + 20].to_vec();
        v1[5] = 1;
        v1.extend_from_slice(&v2[6 + 9 + 20 + 1..]);
        let old = decode(&v1, "old.vcuts").unwrap();
        assert_eq!((old.reconstruction(), old.texels()), (Reconstruction::Box, EnvMap::constant([1.0; 3]).texels()));
        let mut unknown = v2.clone();
        unknown[6 + 9 + 20] = 7;
        assert!(decode(&unknown, "t").unwrap_err().to_string().contains("reconstruction 7"));
        // Dimensions whose texel bytes overflow (a damaged header): an error, not a panic.
        let huge_latlong = [&b"VCENV\x02\x00"[..], &0x5b00_0010u32.to_le_bytes(), &0xe300_0008u32.to_le_bytes()];
        let huge_cube = [&b"VCENV\x02\x01"[..], &u32::MAX.to_le_bytes(), &[1]];
        for header in [huge_latlong.concat(), huge_cube.concat()] {
            let mut bytes = header;
            bytes.extend_from_slice(&v2[6 + 9..]);
            let e = decode(&bytes, "t.vcuts: environment").unwrap_err().to_string();
            assert!(e.contains("bytes of texels"), "{e}");
        }
    }
}
