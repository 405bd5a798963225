//! Payloads of the `.vcuts` sections.
//!
//! **Cut array** (SVC chunks, field spheres): `count u32, root height u8, value format u8
//! (0 f32, 1 f16, 2 u16, 3 u8, 4 u1), flags u8 (bit 0: an "inside the object" bit per cut
//! follows), shape coding u8 (0 heights, 1 split flags)`; then one u32 byte offset into the cut
//! area per block of 32 cuts and one for its end (`⌈count/32⌉ + 1`); then the bit set
//! (`⌈count/8⌉` bytes, padded to 4); then the cut area: per cut its LEB128 byte length and its
//! bytes in the codec of `vcut-cut`. A cut is found from its block's offset by skipping at most
//! 31 lengths: 1–2 bytes per cut instead of a 4-byte offset each.
//!
//! **Directions**: `n u32`, then n × 3 f32 directions (generation order), then n f64 solid
//! angles of their cells, then the direction tree's leaf order (n u32: the direction at each
//! leaf), so a reader can check that the tree it rebuilds is the one the cuts refer to. **Mesh**: name, motion (0 static, 1 movable), material (TOML), vertex
//! and triangle counts, positions, normals, triangles. **Field layout**: centre, radius,
//! spheres, resolution, inner, outer, radial spacing (u32: 0 linear, 1 geometric). Strings are a u32 length and UTF-8 bytes; all
//! little-endian. Every parser checks lengths and returns a reason instead of panicking.

use crate::field::{FieldLayout, RadialSpacing};
use glam::Vec3;
use vcut_scene::{Material, Mesh, MeshError, Motion};

/// Why a section's payload could not be read (the file's reader names the section).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PayloadError {
    /// The payload ends before what its layout says follows.
    #[error("truncated at byte {at} (needs {need} more)")]
    Truncated {
        /// Where the read started.
        at: usize,
        /// Bytes it needed.
        need: usize,
    },
    /// A payload whose size does not match the counts it starts with.
    #[error("{what} need {need} bytes, got {got}")]
    Size {
        /// What the counts say is stored (e.g. "12 directions").
        what: String,
        /// Bytes that takes.
        need: u64,
        /// Bytes there are.
        got: u64,
    },
    /// An enumeration code this version does not know.
    #[error("unknown {what} {code}")]
    UnknownCode {
        /// Which code (e.g. "motion code").
        what: &'static str,
        /// Its value.
        code: u32,
    },
    /// Parts of the payload that contradict each other (a header, offsets and lengths, ranges).
    #[error("{0}")]
    Inconsistent(String),
    /// A string that is not UTF-8.
    #[error("string is not UTF-8")]
    NotUtf8,
    /// The stored material does not parse.
    #[error("material: {0}")]
    Material(String),
    /// The stored mesh breaks a mesh invariant.
    #[error("mesh: {0}")]
    Mesh(MeshError),
}

pub use crate::cut_array::{CUT_BLOCK, CutArray, CutDecodeError, CutFault, CutSource, encode_cut_array, format_code};

pub(crate) fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// Directions payload.
pub fn encode_directions(dirs: &[Vec3], cell_areas: &[f64], leaf_order: &[u32]) -> Vec<u8> {
    let mut out = Vec::with_capacity(4 + dirs.len() * 24);
    out.extend_from_slice(&(dirs.len() as u32).to_le_bytes());
    for d in dirs {
        for c in d.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    for a in cell_areas {
        out.extend_from_slice(&a.to_le_bytes());
    }
    for i in leaf_order {
        out.extend_from_slice(&i.to_le_bytes());
    }
    out
}

/// Directions, their cell solid angles and the tree's leaf order, as stored.
pub type StoredDirections = (Vec<Vec3>, Vec<f64>, Vec<u32>);

/// Parses a directions payload.
pub fn decode_directions(bytes: &[u8]) -> Result<StoredDirections, PayloadError> {
    let mut r = Cursor::new(bytes);
    let n = r.u32()? as usize;
    if (bytes.len() as u64) != 4 + 24 * n as u64 {
        return Err(PayloadError::Size {
            what: format!("{n} directions"),
            need: 4 + 24 * n as u64,
            got: bytes.len() as u64,
        });
    }
    let dirs = (0..n).map(|_| r.vec3()).collect::<Result<Vec<_>, _>>()?;
    let areas = (0..n).map(|_| r.f64()).collect::<Result<Vec<_>, _>>()?;
    let order = (0..n).map(|_| r.u32()).collect::<Result<Vec<_>, _>>()?;
    Ok((dirs, areas, order))
}

/// One object as stored.
#[derive(Debug, Clone)]
pub struct StoredObject {
    /// Name.
    pub name: String,
    /// Static or movable.
    pub motion: Motion,
    /// Material at precompute time.
    pub material: Material,
    /// Mesh at rest (with its texture coordinates, from its `surface` section).
    pub mesh: Mesh,
    /// Its material's textures (from its `surface` section).
    pub textures: vcut_scene::loaders::MaterialTextures,
}

/// Mesh payload.
pub fn encode_mesh(name: &str, motion: Motion, material: &Material, mesh: &Mesh) -> Vec<u8> {
    let mut out = Vec::new();
    put_str(&mut out, name);
    out.push(u8::from(motion == Motion::Movable));
    put_str(&mut out, &toml::to_string(material).unwrap_or_default());
    out.extend_from_slice(&(mesh.vertex_count() as u32).to_le_bytes());
    out.extend_from_slice(&(mesh.triangle_count() as u32).to_le_bytes());
    for v in mesh.positions().iter().chain(mesh.normals()) {
        for c in v.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    for t in mesh.triangles() {
        for i in t {
            out.extend_from_slice(&i.to_le_bytes());
        }
    }
    out
}

/// Parses a mesh payload (the mesh is validated again).
pub fn decode_mesh(bytes: &[u8]) -> Result<StoredObject, PayloadError> {
    let mut r = Cursor::new(bytes);
    let name = r.str()?;
    let motion = match r.u8()? {
        0 => Motion::Static,
        1 => Motion::Movable,
        m => return Err(PayloadError::UnknownCode { what: "motion code", code: u32::from(m) }),
    };
    let material: Material =
        toml::from_str(&r.str()?).map_err(|e| PayloadError::Material(e.to_string().trim_end().to_string()))?;
    let (nv, nt) = (r.u32()? as usize, r.u32()? as usize);
    if r.rest() != nv * 24 + nt * 12 {
        return Err(PayloadError::Size {
            what: format!("{nv} vertices and {nt} triangles"),
            need: (nv * 24 + nt * 12) as u64,
            got: r.rest() as u64,
        });
    }
    let positions = (0..nv).map(|_| r.vec3()).collect::<Result<Vec<_>, _>>()?;
    let normals = (0..nv).map(|_| r.vec3()).collect::<Result<Vec<_>, _>>()?;
    let triangles = (0..nt).map(|_| Ok([r.u32()?, r.u32()?, r.u32()?])).collect::<Result<Vec<_>, PayloadError>>()?;
    let mesh = Mesh::from_valid_parts(positions, normals, triangles).map_err(PayloadError::Mesh)?;
    Ok(StoredObject { name, motion, material, mesh, textures: Default::default() })
}

/// Field layout payload.
pub fn encode_field_layout(l: &FieldLayout) -> Vec<u8> {
    let mut out = Vec::with_capacity(36);
    for c in l.center.to_array() {
        out.extend_from_slice(&c.to_le_bytes());
    }
    out.extend_from_slice(&l.radius.to_le_bytes());
    out.extend_from_slice(&l.spheres.to_le_bytes());
    out.extend_from_slice(&l.resolution.to_le_bytes());
    out.extend_from_slice(&l.inner.to_le_bytes());
    out.extend_from_slice(&l.outer.to_le_bytes());
    let spacing: u32 = match l.spacing {
        RadialSpacing::Linear => 0,
        RadialSpacing::Geometric => 1,
    };
    out.extend_from_slice(&spacing.to_le_bytes());
    out
}

/// Parses a field layout payload.
pub fn decode_field_layout(bytes: &[u8]) -> Result<FieldLayout, PayloadError> {
    let mut r = Cursor::new(bytes);
    let l = FieldLayout {
        center: r.vec3()?,
        radius: r.f32()?,
        spheres: r.u32()?,
        resolution: r.u32()?,
        inner: r.f32()?,
        outer: r.f32()?,
        spacing: match r.u32()? {
            0 => RadialSpacing::Linear,
            1 => RadialSpacing::Geometric,
            code => return Err(PayloadError::UnknownCode { what: "radial spacing code", code }),
        },
    };
    let ok = r.rest() == 0
        && l.center.is_finite()
        && l.radius > 0.0
        && l.radius.is_finite()
        && (1..=4096).contains(&l.spheres)
        && (1..=4096).contains(&l.resolution)
        && l.inner >= 0.0
        && (l.inner > 0.0 || l.spacing == RadialSpacing::Linear)
        && l.outer > l.inner
        && l.outer.is_finite();
    if ok { Ok(l) } else { Err(PayloadError::Inconsistent(format!("malformed field layout {l:?}"))) }
}

fn put_str(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// A bounds-checked little-endian reader.
pub(crate) struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Cursor { bytes, at: 0 }
    }

    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8], PayloadError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or(PayloadError::Truncated { at: self.at, need: n })?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }

    pub(crate) fn rest(&self) -> usize {
        self.bytes.len() - self.at
    }

    pub(crate) fn u8(&mut self) -> Result<u8, PayloadError> {
        Ok(self.take(1)?[0])
    }

    pub(crate) fn u32(&mut self) -> Result<u32, PayloadError> {
        Ok(u32_at(self.take(4)?, 0))
    }

    pub(crate) fn f32(&mut self) -> Result<f32, PayloadError> {
        Ok(f32::from_bits(self.u32()?))
    }

    fn f64(&mut self) -> Result<f64, PayloadError> {
        let b = self.take(8)?;
        let mut x = [0u8; 8];
        x.copy_from_slice(b);
        Ok(f64::from_le_bytes(x))
    }

    fn vec3(&mut self) -> Result<Vec3, PayloadError> {
        Ok(Vec3::new(self.f32()?, self.f32()?, self.f32()?))
    }

    fn str(&mut self) -> Result<String, PayloadError> {
        let n = self.u32()? as usize;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|_| PayloadError::NotUtf8)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vcut_cut::Cut;
    use vcut_cut::codec::{self, ShapeCoding, ValueFormat};

    #[test]
    fn cut_arrays_round_trip_and_reject_damage() {
        let cuts = [
            Cut::new(3, vec![2, 1, 0, 0], vec![1.0, 0.0, 0.0, 1.0]).unwrap(),
            Cut::new(3, vec![3], vec![0.0]).unwrap(),
        ];
        let enc: Vec<Vec<u8>> = cuts.iter().map(|c| codec::encode_heights(c, ValueFormat::F16).unwrap()).collect();
        let payload = encode_cut_array(3, ValueFormat::F16, ShapeCoding::Heights, &enc, Some(&[false, true]));
        let a = CutArray::parse(payload.clone()).unwrap();
        assert_eq!((a.len(), a.root_height(), a.format()), (2, 3, ValueFormat::F16));
        assert_eq!(a.cut(0).unwrap(), cuts[0]);
        assert_eq!(a.cut(1).unwrap(), cuts[1]);
        assert_eq!((a.node_count(0).unwrap(), a.node_count(1).unwrap()), (4, 1));
        assert!(!a.inside(0) && a.inside(1));
        for cut in 0..payload.len() {
            if let Ok(a) = CutArray::parse(payload[..cut].to_vec()) {
                for i in 0..a.len() {
                    let _ = a.cut(i);
                }
            }
        }
        let mut bad = payload.clone();
        bad[12] = 200;
        assert!(CutArray::parse(bad.clone()).is_err());
        // Split flags and one-bit values.
        let enc: Vec<Vec<u8>> = cuts.iter().map(|c| codec::encode_split_flags(c, ValueFormat::U1).unwrap()).collect();
        let payload = encode_cut_array(3, ValueFormat::U1, ShapeCoding::SplitFlags, &enc, None);
        let a = CutArray::parse(payload.clone()).unwrap();
        assert_eq!(
            (a.coding(), a.cut(0).unwrap(), a.cut(1).unwrap()),
            (ShapeCoding::SplitFlags, cuts[0].clone(), cuts[1].clone())
        );
    }

    #[test]
    fn many_cuts_across_blocks_with_long_lengths() {
        // 100 cuts over 4 blocks; leaf-level cuts of 2^7 f32 values exceed 127 bytes (2-byte lengths).
        let cuts: Vec<Cut> = (0..100u32)
            .map(|i| {
                if i % 3 == 0 {
                    Cut::from_leaves(7, (0..128).map(|k| ((k * i) % 7) as f32).collect()).unwrap()
                } else {
                    Cut::root(7, i as f32).unwrap()
                }
            })
            .collect();
        let enc: Vec<Vec<u8>> = cuts.iter().map(|c| codec::encode_heights(c, ValueFormat::F32).unwrap()).collect();
        let inside: Vec<bool> = (0..100).map(|i| i % 7 == 0).collect();
        let payload = encode_cut_array(7, ValueFormat::F32, ShapeCoding::Heights, &enc, Some(&inside));
        let a = CutArray::parse(payload.clone()).unwrap();
        for (i, c) in cuts.iter().enumerate() {
            assert_eq!(&a.cut(i).unwrap(), c);
            assert_eq!(a.inside(i), inside[i]);
        }
        let stored: usize = enc.iter().map(Vec::len).sum();
        assert_eq!(a.overhead() + stored, payload.len());
        // Damage to any block offset or length is caught at parse, never a panic.
        for at in 8..payload.len().min(400) {
            let mut bad = payload.clone();
            bad[at] ^= 0x81;
            if let Ok(a) = CutArray::parse(bad.clone()) {
                for i in 0..a.len() {
                    let _ = a.cut(i);
                }
            }
        }
    }

    #[test]
    fn meshes_directions_and_layouts_round_trip() {
        let mesh = vcut_scene::shapes::sphere(1.0, 8, 6).unwrap();
        let m = Material::default();
        let bytes = encode_mesh("ball", Motion::Movable, &m, &mesh);
        let got = decode_mesh(&bytes).unwrap();
        assert_eq!((got.name.as_str(), got.motion, got.material, &got.mesh), ("ball", Motion::Movable, m, &mesh));
        for cut in [0, 3, bytes.len() / 2, bytes.len() - 1] {
            assert!(decode_mesh(&bytes[..cut]).is_err());
        }
        let dirs = vec![Vec3::X, Vec3::Y];
        let (d, a, o) = decode_directions(&encode_directions(&dirs, &[1.5, 2.5], &[1, 0])).unwrap();
        assert_eq!((d, a, o), (dirs, vec![1.5, 2.5], vec![1, 0]));
        let l = FieldLayout {
            center: Vec3::ONE,
            radius: 2.0,
            spheres: 4,
            resolution: 3,
            inner: 0.2,
            outer: 10.0,
            spacing: RadialSpacing::Geometric,
        };
        assert_eq!(decode_field_layout(&encode_field_layout(&l)).unwrap(), l);
        let linear = FieldLayout { spacing: RadialSpacing::Linear, ..l };
        assert_eq!(decode_field_layout(&encode_field_layout(&linear)).unwrap(), linear);
        assert!(decode_field_layout(&encode_field_layout(&FieldLayout { inner: 0.0, ..l })).is_err());
        assert!(decode_field_layout(&encode_field_layout(&FieldLayout { radius: -1.0, ..l })).is_err());
    }
}
