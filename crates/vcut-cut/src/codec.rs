//! Byte encodings of a [`Cut`]: the height codec and the node-index baseline.
//!
//! **Height codec** (`encode_heights`): LEB128 node count; heights packed least-significant-bit
//! first in 4 bits when the root height H ≤ 15, in 5 bits otherwise (H = 16 for 65,536 leaves
//! needs heights up to 16), padded to a byte; then the values in the chosen [`ValueFormat`],
//! little-endian.
//!
//! **Index baseline** (`encode_indices`, the representation of Akerlund 2007 and
//! Cheslack-Postava 2008): LEB128 node count; each node's level-order index as u16 when
//! `2^(H+1) − 1` fits (H ≤ 15), u32 otherwise; then f32 values.
//!
//! Decoding never panics on arbitrary bytes (the `cut_decode` fuzz target checks this): it
//! returns a valid [`Cut`] or a [`DecodeError`] saying what is wrong. Encodings are canonical
//! (minimal node count, zero padding), so a decoded f32 cut re-encodes to the same bytes.

use crate::{Cut, CutError};

/// How node values are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ValueFormat {
    /// IEEE f32, exact.
    F32,
    /// IEEE f16: for values in [0, 1] the error is at most 2^-12 ≈ 2.4e-4.
    F16,
    /// `round(v · 65535)` for v in [0, 1]: error at most 0.5/65535 ≈ 7.6e-6.
    U16,
    /// `round(v · 255)` for v in [0, 1]: error at most 0.5/255 ≈ 2.0e-3.
    U8,
}

impl ValueFormat {
    /// All formats, finest first.
    pub const ALL: [ValueFormat; 4] = [ValueFormat::F32, ValueFormat::F16, ValueFormat::U16, ValueFormat::U8];

    /// Bytes per value.
    pub fn bytes(self) -> usize {
        match self {
            ValueFormat::F32 => 4,
            ValueFormat::F16 | ValueFormat::U16 => 2,
            ValueFormat::U8 => 1,
        }
    }

    /// Largest absolute error for values in [0, 1]: the quantisation step's half plus f32
    /// rounding in the conversion (at most 1e-6).
    pub fn max_error(self) -> f32 {
        match self {
            ValueFormat::F32 => 0.0,
            ValueFormat::F16 => 1.0 / 4096.0 + 1e-6,
            ValueFormat::U16 => 0.5 / 65535.0 + 1e-6,
            ValueFormat::U8 => 0.5 / 255.0 + 1e-6,
        }
    }

    /// Short name (`f32`, `f16`, `u16`, `u8`).
    pub fn name(self) -> &'static str {
        match self {
            ValueFormat::F32 => "f32",
            ValueFormat::F16 => "f16",
            ValueFormat::U16 => "u16",
            ValueFormat::U8 => "u8",
        }
    }
}

/// Why a cut cannot be encoded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EncodeError {
    /// A value outside what the format stores.
    #[error("node {node} value {value} is outside [0, 1], which {format} stores")]
    OutOfRange {
        /// Node position.
        node: usize,
        /// Its value.
        value: f32,
        /// The format's name.
        format: &'static str,
    },
}

/// Why bytes do not decode to a cut.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DecodeError {
    /// Fewer bytes than the header promises.
    #[error("truncated: {needed} bytes needed, {got} present")]
    Truncated {
        /// Bytes needed.
        needed: usize,
        /// Bytes present.
        got: usize,
    },
    /// A malformed LEB128 node count.
    #[error("malformed node count")]
    Count,
    /// More nodes than the tree has leaves, or none.
    #[error("{nodes} nodes for a tree of {leaves} leaves")]
    NodeCount {
        /// Nodes claimed.
        nodes: u64,
        /// Leaves.
        leaves: u64,
    },
    /// An index that is not a node of the tree.
    #[error("node {node}: index {index} is not a node of a tree of root height {root}")]
    Index {
        /// Node position.
        node: usize,
        /// The index.
        index: u32,
        /// Root height.
        root: u32,
    },
    /// Non-zero padding bits after the last height.
    #[error("non-zero padding after the heights")]
    Padding,
    /// Bytes left after the cut (with the exact-length decoders).
    #[error("{0} trailing bytes")]
    Trailing(usize),
    /// The decoded nodes do not form a cut.
    #[error("not a valid cut: {0}")]
    Invalid(#[from] CutError),
}

fn put_varint(out: &mut Vec<u8>, mut x: u64) {
    loop {
        let b = (x & 0x7f) as u8;
        x >>= 7;
        if x == 0 {
            out.push(b);
            return;
        }
        out.push(b | 0x80);
    }
}

fn get_varint(bytes: &[u8]) -> Result<(u64, usize), DecodeError> {
    let mut x = 0u64;
    for (i, &b) in bytes.iter().enumerate().take(10) {
        x |= u64::from(b & 0x7f) << (7 * i);
        if b & 0x80 == 0 {
            // Canonical only: no trailing zero groups, so every cut has exactly one encoding.
            if b == 0 && i > 0 {
                return Err(DecodeError::Count);
            }
            return Ok((x, i + 1));
        }
    }
    Err(DecodeError::Count)
}

/// Reads and checks the node count: 1 ..= 2^H nodes.
fn read_count(bytes: &[u8], root_height: u32) -> Result<(usize, usize), DecodeError> {
    if root_height > crate::MAX_ROOT_HEIGHT {
        return Err(CutError::RootHeight(root_height).into());
    }
    let (n, at) = get_varint(bytes)?;
    let leaves = 1u64 << root_height;
    if n == 0 || n > leaves {
        return Err(DecodeError::NodeCount { nodes: n, leaves });
    }
    Ok((n as usize, at))
}

/// The node count at the start of an encoded cut (either codec), without decoding the rest.
pub fn decode_count(bytes: &[u8]) -> Result<usize, DecodeError> {
    let (n, _) = get_varint(bytes)?;
    usize::try_from(n).map_err(|_| DecodeError::Count)
}

/// Bits per height for a root height.
pub fn height_bits(root_height: u32) -> u32 {
    if root_height <= 15 { 4 } else { 5 }
}

/// Bytes an index takes in the baseline for a root height.
pub fn index_bytes(root_height: u32) -> usize {
    if root_height <= 15 { 2 } else { 4 }
}

fn put_values(out: &mut Vec<u8>, values: &[f32], format: ValueFormat) -> Result<(), EncodeError> {
    for (node, &v) in values.iter().enumerate() {
        let range = |ok: bool| {
            if ok { Ok(()) } else { Err(EncodeError::OutOfRange { node, value: v, format: format.name() }) }
        };
        match format {
            ValueFormat::F32 => out.extend_from_slice(&v.to_le_bytes()),
            ValueFormat::F16 => {
                range(v.abs() <= 65504.0)?;
                out.extend_from_slice(&half::f16::from_f32(v).to_le_bytes());
            }
            ValueFormat::U16 => {
                range((0.0..=1.0).contains(&v))?;
                out.extend_from_slice(&((v * 65535.0).round() as u16).to_le_bytes());
            }
            ValueFormat::U8 => {
                range((0.0..=1.0).contains(&v))?;
                out.push((v * 255.0).round() as u8);
            }
        }
    }
    Ok(())
}

fn get_values(bytes: &[u8], n: usize, format: ValueFormat) -> Vec<f32> {
    match format {
        ValueFormat::F32 => {
            bytes.chunks_exact(4).take(n).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect()
        }
        ValueFormat::F16 => {
            bytes.chunks_exact(2).take(n).map(|c| half::f16::from_le_bytes([c[0], c[1]]).to_f32()).collect()
        }
        ValueFormat::U16 => {
            bytes.chunks_exact(2).take(n).map(|c| f32::from(u16::from_le_bytes([c[0], c[1]])) / 65535.0).collect()
        }
        ValueFormat::U8 => bytes.iter().take(n).map(|&b| f32::from(b) / 255.0).collect(),
    }
}

/// Size in bytes of a cut of `nodes` nodes in the height codec.
pub fn height_coded_size(nodes: usize, root_height: u32, format: ValueFormat) -> usize {
    let mut v = Vec::new();
    put_varint(&mut v, nodes as u64);
    v.len() + (nodes * height_bits(root_height) as usize).div_ceil(8) + nodes * format.bytes()
}

/// Size in bytes of a cut of `nodes` nodes in the index baseline.
pub fn index_coded_size(nodes: usize, root_height: u32) -> usize {
    let mut v = Vec::new();
    put_varint(&mut v, nodes as u64);
    v.len() + nodes * (index_bytes(root_height) + 4)
}

/// Encodes with the height codec.
pub fn encode_heights(cut: &Cut, format: ValueFormat) -> Result<Vec<u8>, EncodeError> {
    let n = cut.len();
    let bits = height_bits(cut.root_height());
    let mut out = Vec::with_capacity(height_coded_size(n, cut.root_height(), format));
    put_varint(&mut out, n as u64);
    let mut acc = 0u32;
    let mut filled = 0u32;
    for &h in cut.heights() {
        acc |= u32::from(h) << filled;
        filled += bits;
        while filled >= 8 {
            out.push(acc as u8);
            acc >>= 8;
            filled -= 8;
        }
    }
    if filled > 0 {
        out.push(acc as u8);
    }
    put_values(&mut out, cut.values(), format)?;
    Ok(out)
}

/// Decodes a height-coded cut from the start of `bytes`; returns it and the bytes used.
pub fn decode_heights_prefix(bytes: &[u8], root_height: u32, format: ValueFormat) -> Result<(Cut, usize), DecodeError> {
    let (n, mut at) = read_count(bytes, root_height)?;
    let bits = height_bits(root_height);
    let height_bytes = (n * bits as usize).div_ceil(8);
    let needed = at + height_bytes + n * format.bytes();
    if bytes.len() < needed {
        return Err(DecodeError::Truncated { needed, got: bytes.len() });
    }
    let mut heights = Vec::with_capacity(n);
    let mask = (1u32 << bits) - 1;
    let (mut acc, mut filled) = (0u32, 0u32);
    let packed = &bytes[at..at + height_bytes];
    let mut next = packed.iter();
    for _ in 0..n {
        while filled < bits {
            acc |= u32::from(*next.next().unwrap_or(&0)) << filled;
            filled += 8;
        }
        heights.push((acc & mask) as u8);
        acc >>= bits;
        filled -= bits;
    }
    // Padding bits after the last height must be zero (one encoding per cut).
    if acc != 0 {
        return Err(DecodeError::Padding);
    }
    at += height_bytes;
    let values = get_values(&bytes[at..], n, format);
    at += n * format.bytes();
    Ok((Cut::new(root_height, heights, values)?, at))
}

/// Decodes a height-coded cut that fills `bytes` exactly.
pub fn decode_heights(bytes: &[u8], root_height: u32, format: ValueFormat) -> Result<Cut, DecodeError> {
    let (cut, used) = decode_heights_prefix(bytes, root_height, format)?;
    if used != bytes.len() {
        return Err(DecodeError::Trailing(bytes.len() - used));
    }
    Ok(cut)
}

/// Encodes with the index baseline (f32 values).
pub fn encode_indices(cut: &Cut) -> Vec<u8> {
    let n = cut.len();
    let mut out = Vec::with_capacity(index_coded_size(n, cut.root_height()));
    put_varint(&mut out, n as u64);
    let wide = index_bytes(cut.root_height()) == 4;
    for index in cut.level_order_indices() {
        if wide {
            out.extend_from_slice(&index.to_le_bytes());
        } else {
            out.extend_from_slice(&(index as u16).to_le_bytes());
        }
    }
    for v in cut.values() {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// Decodes an index-coded cut from the start of `bytes`; returns it and the bytes used.
pub fn decode_indices_prefix(bytes: &[u8], root_height: u32) -> Result<(Cut, usize), DecodeError> {
    let (n, mut at) = read_count(bytes, root_height)?;
    let ib = index_bytes(root_height);
    let needed = at + n * (ib + 4);
    if bytes.len() < needed {
        return Err(DecodeError::Truncated { needed, got: bytes.len() });
    }
    let mut heights = Vec::with_capacity(n);
    let nodes = 2 * (1u64 << root_height) - 1;
    for (node, c) in bytes[at..at + n * ib].chunks_exact(ib).enumerate() {
        let index = if ib == 2 {
            u32::from(u16::from_le_bytes([c[0], c[1]]))
        } else {
            u32::from_le_bytes([c[0], c[1], c[2], c[3]])
        };
        if u64::from(index) >= nodes {
            return Err(DecodeError::Index { node, index, root: root_height });
        }
        let depth = 31 - (index + 1).leading_zeros();
        heights.push((root_height - depth) as u8);
    }
    at += n * ib;
    let values = get_values(&bytes[at..], n, ValueFormat::F32);
    at += n * 4;
    let cut = Cut::new(root_height, heights, values)?;
    // Heights fix the offsets; the indices must agree with them.
    let check = &bytes[get_varint(bytes)?.1..];
    for (node, (index, c)) in cut.level_order_indices().zip(check.chunks_exact(ib)).enumerate() {
        let stored = if ib == 2 {
            u32::from(u16::from_le_bytes([c[0], c[1]]))
        } else {
            u32::from_le_bytes([c[0], c[1], c[2], c[3]])
        };
        if stored != index {
            return Err(DecodeError::Index { node, index: stored, root: root_height });
        }
    }
    Ok((cut, at))
}

/// Decodes an index-coded cut that fills `bytes` exactly.
pub fn decode_indices(bytes: &[u8], root_height: u32) -> Result<Cut, DecodeError> {
    let (cut, used) = decode_indices_prefix(bytes, root_height)?;
    if used != bytes.len() {
        return Err(DecodeError::Trailing(bytes.len() - used));
    }
    Ok(cut)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn five_bit_mode_carries_height_16() {
        let cut = Cut::new(16, vec![15, 14, 13, 13], vec![1.0, 0.25, 0.0, 0.5]).unwrap();
        let bytes = encode_heights(&cut, ValueFormat::U8).unwrap();
        // 1 count byte, 4×5 bits = 3 bytes, 4 values.
        assert_eq!(bytes.len(), 1 + 3 + 4);
        let back = decode_heights(&bytes, 16, ValueFormat::U8).unwrap();
        assert_eq!(back.heights(), cut.heights());
        let root = Cut::root(16, 1.0).unwrap();
        assert_eq!(
            decode_heights(&encode_heights(&root, ValueFormat::F32).unwrap(), 16, ValueFormat::F32).unwrap(),
            root
        );
        assert_eq!(decode_indices(&encode_indices(&cut), 16).unwrap(), cut);
    }

    /// Regression (fuzz target `cut_decode`): bytes with non-zero padding decoded to a cut that
    /// re-encoded differently; non-canonical encodings are refused.
    #[test]
    fn non_canonical_encodings_are_refused() {
        assert_eq!(
            decode_heights_prefix(&[0x01, 0x80, 0x0e, 0x00, 0x00, 0x7b], 0, ValueFormat::F32),
            Err(DecodeError::Padding)
        );
        // Count 1 written as two LEB128 bytes.
        assert_eq!(
            decode_heights_prefix(&[0x81, 0x00, 0x00, 0, 0, 0, 0], 0, ValueFormat::F32),
            Err(DecodeError::Count)
        );
    }

    #[test]
    fn bad_bytes_are_errors() {
        let cut = Cut::new(3, vec![2, 1, 0, 0], vec![0.5; 4]).unwrap();
        let bytes = encode_heights(&cut, ValueFormat::F32).unwrap();
        assert!(matches!(
            decode_heights(&bytes[..bytes.len() - 1], 3, ValueFormat::F32),
            Err(DecodeError::Truncated { .. })
        ));
        let mut more = bytes.clone();
        more.push(0);
        assert_eq!(decode_heights(&more, 3, ValueFormat::F32), Err(DecodeError::Trailing(1)));
        assert!(matches!(decode_heights(&[0], 3, ValueFormat::F32), Err(DecodeError::NodeCount { .. })));
        assert!(matches!(decode_heights(&[0xff; 12], 3, ValueFormat::F32), Err(DecodeError::Count)));
        let mut idx = encode_indices(&cut);
        idx[1] = 200;
        assert!(matches!(decode_indices(&idx, 3), Err(DecodeError::Index { .. })));
        assert!(matches!(
            encode_heights(&Cut::new(1, vec![0, 0], vec![1.5, 0.0]).unwrap(), ValueFormat::U8),
            Err(EncodeError::OutOfRange { node: 0, .. })
        ));
    }
}
