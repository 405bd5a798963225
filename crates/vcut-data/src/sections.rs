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
use vcut_cut::Cut;
use vcut_cut::codec::{self, ShapeCoding, ValueFormat};
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

/// Value format code in the cut array header.
pub fn format_code(f: ValueFormat) -> u8 {
    match f {
        ValueFormat::F32 => 0,
        ValueFormat::F16 => 1,
        ValueFormat::U16 => 2,
        ValueFormat::U8 => 3,
        ValueFormat::U1 => 4,
    }
}

fn format_of(code: u8) -> Option<ValueFormat> {
    Some(match code {
        0 => ValueFormat::F32,
        1 => ValueFormat::F16,
        2 => ValueFormat::U16,
        3 => ValueFormat::U8,
        4 => ValueFormat::U1,
        _ => return None,
    })
}

/// Cuts per block of the cut array's offset index.
pub const CUT_BLOCK: usize = 32;

/// Builds a cut array payload from already encoded cuts.
pub fn encode_cut_array(
    root_height: u32,
    format: ValueFormat,
    coding: ShapeCoding,
    cuts: &[Vec<u8>],
    inside: Option<&[bool]>,
) -> Vec<u8> {
    let n = cuts.len();
    let bits = inside.map_or(0, |_| n.div_ceil(8).div_ceil(4) * 4);
    let mut area = Vec::with_capacity(cuts.iter().map(|c| c.len() + 2).sum());
    let mut blocks = Vec::with_capacity(n.div_ceil(CUT_BLOCK) + 1);
    for (i, c) in cuts.iter().enumerate() {
        if i % CUT_BLOCK == 0 {
            blocks.push(area.len() as u32);
        }
        codec::put_varint(&mut area, c.len() as u64);
        area.extend_from_slice(c);
    }
    blocks.push(area.len() as u32);
    let mut out = Vec::with_capacity(8 + 4 * blocks.len() + bits + area.len());
    out.extend_from_slice(&(n as u32).to_le_bytes());
    let coding_code = u8::from(coding == ShapeCoding::SplitFlags);
    out.extend_from_slice(&[root_height as u8, format_code(format), u8::from(inside.is_some()), coding_code]);
    for b in blocks {
        out.extend_from_slice(&b.to_le_bytes());
    }
    if let Some(inside) = inside {
        let mut set = vec![0u8; bits];
        for (i, _) in inside.iter().enumerate().filter(|(_, x)| **x) {
            set[i / 8] |= 1 << (i % 8);
        }
        out.extend_from_slice(&set);
    }
    out.extend_from_slice(&area);
    out
}

/// A cut of a cut array that does not decode.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("cut {index}: {error}")]
pub struct CutDecodeError {
    /// The cut's index in its array.
    pub index: usize,
    /// What the codec found.
    pub error: codec::DecodeError,
}

/// A parsed cut array owning its payload: cuts are decoded on demand.
#[derive(Debug, Clone)]
pub struct CutArray {
    root_height: u32,
    format: ValueFormat,
    coding: ShapeCoding,
    /// Start and length of every cut's bytes in `payload`.
    spans: Vec<(u32, u32)>,
    /// Where the inside bits are in `payload`, if any.
    inside: Option<std::ops::Range<usize>>,
    payload: Vec<u8>,
    count: usize,
    overhead: usize,
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

impl CutArray {
    /// Parses the header, the block offsets and every cut's length (checked: each block's
    /// lengths end exactly at the next block's offset).
    pub fn parse(payload: Vec<u8>) -> Result<CutArray, PayloadError> {
        let bytes = payload.as_slice();
        let bad = |what: String| Err(PayloadError::Inconsistent(what));
        if bytes.len() < 8 {
            return bad(format!("cut array of {} bytes, shorter than its 8-byte header", bytes.len()));
        }
        let count = u32_at(bytes, 0) as usize;
        let root_height = u32::from(bytes[4]);
        let format = format_of(bytes[5])
            .ok_or(PayloadError::UnknownCode { what: "value format code", code: u32::from(bytes[5]) })?;
        let coding = match bytes[7] {
            0 => ShapeCoding::Heights,
            1 => ShapeCoding::SplitFlags,
            c => return Err(PayloadError::UnknownCode { what: "shape coding", code: u32::from(c) }),
        };
        if root_height > 20 || bytes[6] > 1 {
            return bad("malformed cut array header".into());
        }
        let nblocks = count.div_ceil(CUT_BLOCK) + 1;
        let blocks_end = 8 + 4 * nblocks;
        let bits = if bytes[6] == 1 { count.div_ceil(8).div_ceil(4) * 4 } else { 0 };
        // Every cut takes at least 2 bytes (a length and a count), so a count beyond that is
        // damage, caught before allocating for it.
        if bytes.len() < blocks_end + bits || count > bytes.len() {
            return bad(format!("cut array of {count} cuts truncated: {} bytes", bytes.len()));
        }
        let cuts = &bytes[blocks_end + bits..];
        let block = |j: usize| u32_at(bytes, 8 + 4 * j) as usize;
        if block(nblocks - 1) != cuts.len() {
            return bad(format!("cut offsets end at {}, the cut bytes are {} long", block(nblocks - 1), cuts.len()));
        }
        let mut spans = Vec::with_capacity(count);
        let mut at = 0usize;
        let mut lengths = 0usize;
        for i in 0..count {
            if i % CUT_BLOCK == 0 && block(i / CUT_BLOCK) != at {
                return bad(format!("block offset of cut {i} is {}, its bytes start at {at}", block(i / CUT_BLOCK)));
            }
            let (len, used) = codec::get_varint(&cuts[at.min(cuts.len())..])
                .ok()
                .and_then(|(len, used)| Some((usize::try_from(len).ok()?, used)))
                .ok_or_else(|| PayloadError::Inconsistent(format!("cut {i}: malformed length")))?;
            at += used;
            lengths += used;
            spans.push(((blocks_end + bits + at) as u32, len as u32));
            at = at
                .checked_add(len)
                .filter(|&e| e <= cuts.len())
                .ok_or_else(|| PayloadError::Inconsistent(format!("cut {i} runs past the end")))?;
        }
        if at != cuts.len() {
            return bad(format!("cuts end at {at}, the cut bytes are {} long", cuts.len()));
        }
        let inside = (bits > 0).then_some(blocks_end..blocks_end + bits);
        let overhead = blocks_end + bits + lengths;
        Ok(CutArray { root_height, format, coding, spans, inside, payload, count, overhead })
    }

    /// Bytes of the payload that are not cut bytes (header, block offsets, inside bits, lengths).
    pub fn overhead(&self) -> usize {
        self.overhead
    }

    /// Number of cuts.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Bytes held in memory (the payload and every cut's span).
    pub fn bytes(&self) -> usize {
        self.payload.capacity() + self.spans.capacity() * size_of::<(u32, u32)>()
    }

    /// Whether there are no cuts.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Root height of every cut.
    pub fn root_height(&self) -> u32 {
        self.root_height
    }

    /// Value format of every cut.
    pub fn format(&self) -> ValueFormat {
        self.format
    }

    /// Shape coding of every cut.
    pub fn coding(&self) -> ShapeCoding {
        self.coding
    }

    /// The encoded bytes of cut `i` (`i < len`).
    pub fn cut_bytes(&self, i: usize) -> &[u8] {
        let (start, len) = self.spans[i];
        &self.payload[start as usize..(start + len) as usize]
    }

    /// Decodes cut `i` (`i < len`).
    pub fn cut(&self, i: usize) -> Result<Cut, CutDecodeError> {
        self.coding
            .decode(self.cut_bytes(i), self.root_height, self.format)
            .map_err(|error| CutDecodeError { index: i, error })
    }

    /// Node count of cut `i` without decoding it.
    pub fn node_count(&self, i: usize) -> Result<usize, CutDecodeError> {
        codec::decode_count(self.cut_bytes(i)).map_err(|error| CutDecodeError { index: i, error })
    }

    /// Whether sample `i` lies inside the object (field arrays; `false` elsewhere).
    pub fn inside(&self, i: usize) -> bool {
        self.inside.as_ref().is_some_and(|r| self.payload[r.start + i / 8] >> (i % 8) & 1 == 1)
    }
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
