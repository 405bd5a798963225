//! Byte encodings of a [`Cut`]: the height codec and the node-index baseline.
//!
//! **Height codec** (`encode_heights`): LEB128 node count; heights packed least-significant-bit
//! first in 4 bits when the root height H ≤ 15, in 5 bits otherwise (H = 16 for 65,536 leaves
//! needs heights up to 16), padded to a byte; then the values in the chosen [`ValueFormat`],
//! little-endian.
//!
//! **Split-flag shape coding** (`encode_split_flags`, a lossless entropy stage over the same
//! heights): LEB128 node count; then the cut's shape as the top-down selection produced it —
//! walking from the root depth first, one bit per visited node of height > 0: 1 = split into
//! its two children, 0 = a node of the cut (leaves need no bit); padded to a byte; then the
//! values. A cut of n nodes takes at most 2n − 1 shape bits instead of 4n or 5n, whatever H.
//!
//! **Values**: f32, f16, u16, u8 (any value in [0, 1] for the quantised ones), and `u1` — one
//! bit per node for exact binary cuts (fields with error threshold 0 hold only 0 and 1).
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
    /// One bit per value, for cuts whose values are exactly 0 or 1 (exact visibility fields);
    /// other values do not encode.
    U1,
}

impl ValueFormat {
    /// The formats that store any value in [0, 1], finest first.
    pub const ALL: [ValueFormat; 4] = [ValueFormat::F32, ValueFormat::F16, ValueFormat::U16, ValueFormat::U8];

    /// Every format, [`ValueFormat::U1`] last.
    pub const WITH_BINARY: [ValueFormat; 5] =
        [ValueFormat::F32, ValueFormat::F16, ValueFormat::U16, ValueFormat::U8, ValueFormat::U1];

    /// Bytes `n` values take (bit-packed values round up to a byte).
    pub fn value_bytes(self, n: usize) -> usize {
        match self {
            ValueFormat::F32 => 4 * n,
            ValueFormat::F16 | ValueFormat::U16 => 2 * n,
            ValueFormat::U8 => n,
            ValueFormat::U1 => n.div_ceil(8),
        }
    }

    /// The format called `name` (`f32`, `f16`, `u16`, `u8`, `u1`).
    pub fn named(name: &str) -> Option<ValueFormat> {
        Self::WITH_BINARY.into_iter().find(|f| f.name() == name)
    }

    /// Largest absolute error for values in [0, 1]: the quantisation step's half plus f32
    /// rounding in the conversion (at most 1e-6).
    pub fn max_error(self) -> f32 {
        match self {
            ValueFormat::F32 => 0.0,
            ValueFormat::F16 => 1.0 / 4096.0 + 1e-6,
            ValueFormat::U16 => 0.5 / 65535.0 + 1e-6,
            ValueFormat::U8 => 0.5 / 255.0 + 1e-6,
            ValueFormat::U1 => 0.0,
        }
    }

    /// Short name (`f32`, `f16`, `u16`, `u8`).
    pub fn name(self) -> &'static str {
        match self {
            ValueFormat::F32 => "f32",
            ValueFormat::F16 => "f16",
            ValueFormat::U16 => "u16",
            ValueFormat::U8 => "u8",
            ValueFormat::U1 => "u1",
        }
    }
}

/// How a cut's shape is stored (both carry exactly the heights).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ShapeCoding {
    /// The paper's 4-bit (5-bit for H = 16) heights.
    Heights,
    /// The top-down walk's split flags: at most 2n − 1 bits.
    SplitFlags,
}

impl ShapeCoding {
    /// `heights` or `split-flags`.
    pub fn name(self) -> &'static str {
        match self {
            ShapeCoding::Heights => "heights",
            ShapeCoding::SplitFlags => "split-flags",
        }
    }

    /// The coding called `name`.
    pub fn named(name: &str) -> Option<ShapeCoding> {
        [ShapeCoding::Heights, ShapeCoding::SplitFlags].into_iter().find(|c| c.name() == name)
    }

    /// Encodes `cut` in this coding.
    pub fn encode(self, cut: &Cut, format: ValueFormat) -> Result<Vec<u8>, EncodeError> {
        match self {
            ShapeCoding::Heights => encode_heights(cut, format),
            ShapeCoding::SplitFlags => encode_split_flags(cut, format),
        }
    }

    /// Decodes a cut in this coding that fills `bytes` exactly.
    pub fn decode(self, bytes: &[u8], root_height: u32, format: ValueFormat) -> Result<Cut, DecodeError> {
        match self {
            ShapeCoding::Heights => decode_heights(bytes, root_height, format),
            ShapeCoding::SplitFlags => decode_split_flags(bytes, root_height, format),
        }
    }
}

/// Why a cut cannot be encoded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
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
#[non_exhaustive]
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
    /// Non-zero padding bits after the last height, shape flag or bit value.
    #[error("non-zero padding bits")]
    Padding,
    /// Split flags that describe a different number of nodes than the count.
    #[error("the split flags describe {described} nodes, the count says {count}")]
    Shape {
        /// Nodes the flags describe (as far as they were read).
        described: usize,
        /// The stored count.
        count: usize,
    },
    /// Bytes left after the cut (with the exact-length decoders).
    #[error("{0} trailing bytes")]
    Trailing(usize),
    /// The decoded nodes do not form a cut.
    #[error("not a valid cut: {0}")]
    Invalid(#[from] CutError),
}

/// Appends `x` as unsigned LEB128 (7 bits per byte, low first), as the codecs store counts.
pub fn put_varint(out: &mut Vec<u8>, mut x: u64) {
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

/// Reads a canonical unsigned LEB128 value from the start of `bytes`: (value, bytes used).
pub fn get_varint(bytes: &[u8]) -> Result<(u64, usize), DecodeError> {
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

/// Packs bits least-significant first.
#[derive(Default)]
struct BitWriter {
    out: Vec<u8>,
    acc: u32,
    filled: u32,
}

impl BitWriter {
    fn push(&mut self, value: u32, bits: u32) {
        self.acc |= value << self.filled;
        self.filled += bits;
        while self.filled >= 8 {
            self.out.push(self.acc as u8);
            self.acc >>= 8;
            self.filled -= 8;
        }
    }

    fn finish(mut self) -> Vec<u8> {
        if self.filled > 0 {
            self.out.push(self.acc as u8);
        }
        self.out
    }
}

fn put_values(out: &mut Vec<u8>, values: &[f32], format: ValueFormat) -> Result<(), EncodeError> {
    if format == ValueFormat::U1 {
        let mut w = BitWriter::default();
        for (node, &v) in values.iter().enumerate() {
            if v != 0.0 && v != 1.0 {
                return Err(EncodeError::OutOfRange { node, value: v, format: format.name() });
            }
            w.push(u32::from(v == 1.0), 1);
        }
        out.extend_from_slice(&w.finish());
        return Ok(());
    }
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
            ValueFormat::U1 => unreachable!("packed above"),
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
        ValueFormat::U1 => {
            let mut values = Vec::with_capacity(n);
            for &b in &bytes[..n.div_ceil(8)] {
                values.extend((0..8).map(|i| f32::from(b >> i & 1)));
            }
            values.truncate(n);
            values
        }
    }
}

/// Whether the padding bits after `n` bit-packed values are zero.
fn values_canonical(bytes: &[u8], n: usize, format: ValueFormat) -> bool {
    format != ValueFormat::U1 || n.is_multiple_of(8) || bytes[n / 8] >> (n % 8) == 0
}

/// Size in bytes of a cut of `nodes` nodes in the height codec.
pub fn height_coded_size(nodes: usize, root_height: u32, format: ValueFormat) -> usize {
    let mut v = Vec::new();
    put_varint(&mut v, nodes as u64);
    v.len() + (nodes * height_bits(root_height) as usize).div_ceil(8) + format.value_bytes(nodes)
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
    let needed = at + height_bytes + format.value_bytes(n);
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
    if !values_canonical(&bytes[at..], n, format) {
        return Err(DecodeError::Padding);
    }
    at += format.value_bytes(n);
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

/// Shape bits of a cut in the split-flag coding.
pub fn split_flag_bits(cut: &Cut) -> usize {
    // One bit per node of the cut above height 0, one per inner node above it (n − 1 of them).
    cut.heights().iter().filter(|&&h| h > 0).count() + cut.len() - 1
}

/// Size in bytes of a cut in the split-flag coding.
pub fn split_flags_size(cut: &Cut, format: ValueFormat) -> usize {
    let mut v = Vec::new();
    put_varint(&mut v, cut.len() as u64);
    v.len() + split_flag_bits(cut).div_ceil(8) + format.value_bytes(cut.len())
}

/// Encodes with the split-flag shape coding (see the module docs).
pub fn encode_split_flags(cut: &Cut, format: ValueFormat) -> Result<Vec<u8>, EncodeError> {
    let mut out = Vec::with_capacity(split_flags_size(cut, format));
    put_varint(&mut out, cut.len() as u64);
    let mut w = BitWriter::default();
    let heights = cut.heights();
    let mut next = 0usize;
    let mut stack = Vec::with_capacity(cut.root_height() as usize + 2);
    stack.push(cut.root_height() as u8);
    while let Some(h) = stack.pop() {
        // A valid cut's next node starts here and is no higher than this node.
        if heights[next] == h {
            if h > 0 {
                w.push(0, 1);
            }
            next += 1;
        } else {
            w.push(1, 1);
            stack.push(h - 1);
            stack.push(h - 1);
        }
    }
    out.extend_from_slice(&w.finish());
    put_values(&mut out, cut.values(), format)?;
    Ok(out)
}

/// Decodes a split-flag-coded cut from the start of `bytes`; returns it and the bytes used.
pub fn decode_split_flags_prefix(
    bytes: &[u8],
    root_height: u32,
    format: ValueFormat,
) -> Result<(Cut, usize), DecodeError> {
    let (n, at) = read_count(bytes, root_height)?;
    if root_height > crate::MAX_ROOT_HEIGHT {
        return Err(CutError::RootHeight(root_height).into());
    }
    // The walk's pending right children, one bit per height: a split at height h leaves its
    // right child (height h − 1) pending and goes on to its left child, and every pending
    // child is lower than the node being walked, so the next node after a leaf is the lowest
    // pending one. Every cut this walk describes is valid (each node a tree node, the leaves
    // covered once), so only the values remain to check.
    let flags = &bytes[at..];
    let mut heights = Vec::with_capacity(n);
    let (mut bit, mut pending, mut h) = (0usize, 0u32, root_height);
    loop {
        if h > 0 {
            let byte =
                *flags.get(bit / 8).ok_or(DecodeError::Truncated { needed: at + bit / 8 + 1, got: bytes.len() })?;
            let split = byte >> (bit % 8) & 1 == 1;
            bit += 1;
            if split {
                h -= 1;
                pending |= 1 << h;
                continue;
            }
        }
        heights.push(h as u8);
        if heights.len() > n {
            return Err(DecodeError::Shape { described: heights.len(), count: n });
        }
        if pending == 0 {
            break;
        }
        h = pending.trailing_zeros();
        pending &= pending - 1;
    }
    if heights.len() != n {
        return Err(DecodeError::Shape { described: heights.len(), count: n });
    }
    let (flag_bytes, clean) =
        if bit % 8 == 0 { (bit / 8, true) } else { (bit.div_ceil(8), flags[bit / 8] >> (bit % 8) == 0) };
    if !clean {
        return Err(DecodeError::Padding);
    }
    let at = at + flag_bytes;
    let needed = at + format.value_bytes(n);
    if bytes.len() < needed {
        return Err(DecodeError::Truncated { needed, got: bytes.len() });
    }
    let values = get_values(&bytes[at..], n, format);
    if !values_canonical(&bytes[at..], n, format) {
        return Err(DecodeError::Padding);
    }
    if let Some(node) = values.iter().position(|v| !v.is_finite()) {
        return Err(CutError::Value { node }.into());
    }
    Ok((Cut::from_valid_walk(root_height, heights, values), needed))
}

/// Decodes a split-flag-coded cut that fills `bytes` exactly.
pub fn decode_split_flags(bytes: &[u8], root_height: u32, format: ValueFormat) -> Result<Cut, DecodeError> {
    let (cut, used) = decode_split_flags_prefix(bytes, root_height, format)?;
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
    fn split_flags_are_the_selection_walk_and_binary_values_take_a_bit() {
        // Root split, left child a node of height 2, right split into 1 and (split into 0, 0).
        let cut = Cut::new(3, vec![2, 1, 0, 0], vec![1.0, 0.0, 1.0, 0.0]).unwrap();
        assert_eq!(split_flag_bits(&cut), 3 + 2);
        let bytes = encode_split_flags(&cut, ValueFormat::U1).unwrap();
        // Count; flags 1 (root) 0 (h2) 1 (h2 right) 0 (h1) 1 (h1 right) → 0b10101; values 0b0101.
        assert_eq!(bytes, vec![4, 0b1_0101, 0b0101]);
        assert_eq!(decode_split_flags(&bytes, 3, ValueFormat::U1).unwrap(), cut);
        assert_eq!(bytes.len(), split_flags_size(&cut, ValueFormat::U1));
        // Height 16 needs no wider field.
        let deep = Cut::new(16, vec![15, 14, 13, 13], vec![1.0, 0.25, 0.0, 0.5]).unwrap();
        let b = encode_split_flags(&deep, ValueFormat::F32).unwrap();
        assert_eq!(decode_split_flags(&b, 16, ValueFormat::F32).unwrap(), deep);
        // A single leaf-height root has no flags at all.
        let leaf = Cut::root(0, 1.0).unwrap();
        assert_eq!(encode_split_flags(&leaf, ValueFormat::U1).unwrap(), vec![1, 1]);
        assert_eq!(decode_split_flags(&[1, 1], 0, ValueFormat::U1).unwrap(), leaf);
        // Errors: fractional values in u1, a count the flags disagree with, dirty padding.
        assert!(matches!(
            encode_split_flags(&Cut::new(1, vec![0, 0], vec![0.5, 1.0]).unwrap(), ValueFormat::U1),
            Err(EncodeError::OutOfRange { node: 0, .. })
        ));
        assert_eq!(
            decode_split_flags(&[3, 0b1_0101, 0], 3, ValueFormat::U1),
            Err(DecodeError::Shape { described: 4, count: 3 })
        );
        assert_eq!(decode_split_flags(&[4, 0b101_0101, 0], 3, ValueFormat::U1), Err(DecodeError::Padding));
        assert_eq!(decode_split_flags(&[4, 0b1_0101, 0b1_0101], 3, ValueFormat::U1), Err(DecodeError::Padding));
        assert_eq!(decode_heights(&[2, 0, 0b100], 1, ValueFormat::U1), Err(DecodeError::Padding));
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
