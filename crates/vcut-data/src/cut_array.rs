//! The cut array payload (SVC chunks, field spheres; the layout in [`crate::sections`]): parsed
//! once, its cuts decoded on demand — from memory, or from the file it was read from when its
//! bytes have been evicted ([`CutArray::evict`]), so that a frame holds only the header and the
//! block offsets of cuts it reads a few at a time.

use crate::sections::{PayloadError, u32_at};
use std::fs::File;
use std::path::Path;
use std::sync::Arc;
use vcut_cut::Cut;
use vcut_cut::codec::{self, ShapeCoding, ValueFormat};

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

/// A cut of a cut array that does not decode (or, its array's bytes left on disk, cannot be
/// read).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("cut {index}: {error}")]
pub struct CutDecodeError {
    /// The cut's index in its array.
    pub index: usize,
    /// What went wrong.
    pub error: CutFault,
}

/// Why a stored cut could not be had.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CutFault {
    /// Its bytes do not decode.
    #[error(transparent)]
    Decode(#[from] codec::DecodeError),
    /// Its array's bytes, left in the file ([`CutArray::evict`]), could not be read back, or
    /// no longer match what was checked when the file was opened.
    #[error("{path}: {reason}")]
    Read {
        /// The file.
        path: String,
        /// What failed.
        reason: String,
    },
}

/// A parsed cut array: cuts are decoded on demand, from its payload in memory or, once
/// [`CutArray::evict`]ed, from the file it was read from ([`CutArray::with_source`]).
#[derive(Debug, Clone)]
pub struct CutArray {
    root_height: u32,
    format: ValueFormat,
    coding: ShapeCoding,
    /// Start and length of every cut's bytes in `payload` (empty while evicted: a cut is then
    /// found from its block's offset).
    spans: Vec<(u32, u32)>,
    /// Where the inside bits are in `payload`, if any.
    inside: Option<std::ops::Range<usize>>,
    /// The whole payload, or while evicted its part before the cut bytes (header, block
    /// offsets, inside bits).
    payload: Vec<u8>,
    /// Where the cut bytes start in the payload.
    area: usize,
    count: usize,
    overhead: usize,
    source: Option<CutSource>,
    resident: bool,
    /// While evicted, the CRC-32 of each block's cut bytes as checked at open: a block read
    /// back that differs (the file changed in place) is refused, not decoded.
    block_crcs: Vec<u32>,
}

/// Where a cut array's payload lies in a file: an open handle (reads go to the file opened,
/// even if its path is replaced since), the payload's offset and length, and the checksum it
/// was verified against.
#[derive(Debug, Clone)]
pub struct CutSource {
    /// Unique to this payload in this process (its clones share it): names the block a thread
    /// last read.
    id: u64,
    file: Arc<File>,
    path: Arc<Path>,
    offset: u64,
    len: u64,
    crc: u32,
}

impl CutSource {
    /// The payload of `len` bytes at byte `offset` of `file` (opened from `path`), whose CRC-32
    /// is `crc` (a container section: [`vcut_container::SectionEntry`]).
    pub fn new(file: Arc<File>, path: &Path, offset: u64, len: u64, crc: u32) -> CutSource {
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let id = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        CutSource { id, file, path: path.into(), offset, len, crc }
    }

    fn fault(&self, reason: impl std::fmt::Display) -> CutFault {
        CutFault::Read { path: self.path.display().to_string(), reason: reason.to_string() }
    }

    /// Reads `buf.len()` bytes at payload offset `at`.
    fn read(&self, buf: &mut [u8], at: u64) -> Result<(), CutFault> {
        read_exact_at(&self.file, buf, self.offset + at)
            .map_err(|e| self.fault(format_args!("reading {} bytes at byte {}: {e}", buf.len(), self.offset + at)))
    }
}

#[cfg(unix)]
fn read_exact_at(file: &File, buf: &mut [u8], at: u64) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::read_exact_at(file, buf, at)
}

#[cfg(windows)]
fn read_exact_at(file: &File, mut buf: &mut [u8], mut at: u64) -> std::io::Result<()> {
    use std::os::windows::fs::FileExt;
    while !buf.is_empty() {
        match file.seek_read(buf, at)? {
            0 => return Err(std::io::ErrorKind::UnexpectedEof.into()),
            n => (buf, at) = (&mut buf[n..], at + n as u64),
        }
    }
    Ok(())
}

#[cfg(not(any(unix, windows)))]
fn read_exact_at(_: &File, _: &mut [u8], _: u64) -> std::io::Result<()> {
    Err(std::io::Error::new(std::io::ErrorKind::Unsupported, "no positional reads on this platform"))
}

/// The block of an evicted array a thread read last: its source's id, its index and bytes.
/// Neighbouring samples of a field lookup lie mostly in one block, so a merge asks for the
/// same block several times in a row.
#[derive(Default)]
struct LastBlock {
    key: Option<(u64, usize)>,
    bytes: Vec<u8>,
}

thread_local! {
    static BLOCK: std::cell::RefCell<LastBlock> = std::cell::RefCell::new(LastBlock::default());
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
        let area = blocks_end + bits;
        Ok(CutArray {
            root_height,
            format,
            coding,
            spans,
            inside,
            payload,
            area,
            count,
            overhead,
            source: None,
            resident: true,
            block_crcs: Vec::new(),
        })
    }

    /// The same array, told where its payload lies in a file so that it can be
    /// [`CutArray::evict`]ed.
    pub fn with_source(mut self, source: CutSource) -> CutArray {
        self.source = Some(source);
        self
    }

    /// Drops the cut bytes from memory, keeping the header, the block offsets and the inside
    /// bits: each cut is then read from the file when asked for (its block's bytes, one
    /// positional read) and decoded. Returns whether the bytes are out of memory now (not
    /// without a [`CutArray::with_source`]).
    pub fn evict(&mut self) -> bool {
        if self.resident && self.source.is_some() {
            let blocks = self.count.div_ceil(CUT_BLOCK);
            self.block_crcs = (0..blocks)
                .map(|b| {
                    let (start, end) = (u32_at(&self.payload, 8 + 4 * b), u32_at(&self.payload, 8 + 4 * (b + 1)));
                    crc32fast::hash(&self.payload[self.area + start as usize..self.area + end as usize])
                })
                .collect();
            self.payload.truncate(self.area);
            self.payload.shrink_to_fit();
            self.spans = Vec::new();
            self.resident = false;
        }
        !self.resident
    }

    /// Reads an evicted array's payload back into memory, checked against its checksum.
    pub fn restore(&mut self) -> Result<(), CutFault> {
        let Some(source) = self.source.clone().filter(|_| !self.resident) else { return Ok(()) };
        let len = usize::try_from(source.len).map_err(|_| source.fault("payload larger than memory"))?;
        let mut payload = vec![0; len];
        source.read(&mut payload, 0)?;
        if crc32fast::hash(&payload) != source.crc {
            return Err(source.fault("checksum mismatch: the file changed since it was opened"));
        }
        let parsed = CutArray::parse(payload).map_err(|e| source.fault(e))?;
        *self = parsed.with_source(source);
        Ok(())
    }

    /// Whether the cut bytes are in memory ([`CutArray::evict`]).
    pub fn is_resident(&self) -> bool {
        self.resident
    }

    /// Runs `f` on cut `i`'s bytes: from memory, or from the file while evicted.
    fn with_bytes<T>(
        &self,
        i: usize,
        f: impl FnOnce(&[u8]) -> Result<T, codec::DecodeError>,
    ) -> Result<T, CutDecodeError> {
        let fail = |error: CutFault| CutDecodeError { index: i, error };
        if let Some(bytes) = self.cut_bytes(i) {
            return f(bytes).map_err(|e| fail(e.into()));
        }
        let source = self.source.as_ref().expect("an evicted array has a source");
        let b = i / CUT_BLOCK;
        let (start, end) = (u32_at(&self.payload, 8 + 4 * b), u32_at(&self.payload, 8 + 4 * (b + 1)));
        if end < start {
            return Err(fail(source.fault(format_args!("block {b}'s offsets run backwards"))));
        }
        BLOCK.with_borrow_mut(|last| {
            if last.key != Some((source.id, b)) {
                last.key = None;
                last.bytes.resize((end - start) as usize, 0);
                source.read(&mut last.bytes, (self.area + start as usize) as u64).map_err(fail)?;
                if crc32fast::hash(&last.bytes) != self.block_crcs[b] {
                    let reason = format_args!("block {b} of cuts changed since the file was opened");
                    return Err(fail(source.fault(reason)));
                }
                last.key = Some((source.id, b));
            }
            let block = &last.bytes;
            let mut at = 0;
            for k in 0..=i % CUT_BLOCK {
                let (len, used) = codec::get_varint(&block[at.min(block.len())..]).map_err(|e| fail(e.into()))?;
                let len = usize::try_from(len).unwrap_or(usize::MAX);
                let bytes =
                    at.checked_add(used).and_then(|s| Some(s..s.checked_add(len)?)).filter(|r| r.end <= block.len());
                let Some(bytes) = bytes else {
                    return Err(fail(source.fault(format_args!("cut {} runs past its block", b * CUT_BLOCK + k))));
                };
                if k == i % CUT_BLOCK {
                    return f(&block[bytes]).map_err(|e| fail(e.into()));
                }
                at = bytes.end;
            }
            unreachable!("the loop returns at its last step")
        })
    }

    /// Bytes of the payload that are not cut bytes (header, block offsets, inside bits, lengths).
    pub fn overhead(&self) -> usize {
        self.overhead
    }

    /// Number of cuts.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Bytes held in memory (the payload, or its part before the cut bytes and the blocks'
    /// checksums while evicted, and every cut's span).
    pub fn bytes(&self) -> usize {
        self.payload.capacity()
            + self.spans.capacity() * size_of::<(u32, u32)>()
            + self.block_crcs.capacity() * size_of::<u32>()
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

    /// The encoded bytes of cut `i` (`i < len`) while they are in memory (`None` while
    /// evicted).
    pub fn cut_bytes(&self, i: usize) -> Option<&[u8]> {
        let &(start, len) = self.spans.get(i)?;
        Some(&self.payload[start as usize..(start + len) as usize])
    }

    /// Decodes cut `i` (`i < len`).
    pub fn cut(&self, i: usize) -> Result<Cut, CutDecodeError> {
        self.with_bytes(i, |bytes| self.coding.decode(bytes, self.root_height, self.format))
    }

    /// Node count of cut `i` without decoding it.
    pub fn node_count(&self, i: usize) -> Result<usize, CutDecodeError> {
        self.with_bytes(i, codec::decode_count)
    }

    /// Whether sample `i` lies inside the object (field arrays; `false` elsewhere).
    pub fn inside(&self, i: usize) -> bool {
        self.inside.as_ref().is_some_and(|r| self.payload[r.start + i / 8] >> (i % 8) & 1 == 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Seek, SeekFrom, Write};

    /// 100 cuts over four blocks (three shapes, values from their index), every third inside.
    fn array() -> (Vec<Cut>, Vec<bool>, Vec<u8>) {
        let cuts: Vec<Cut> = (0..100)
            .map(|i| {
                let v = i as f32 / 100.0;
                match i % 3 {
                    0 => Cut::new(3, vec![3], vec![v]),
                    1 => Cut::new(3, vec![2, 2], vec![v, 1.0 - v]),
                    _ => Cut::new(3, vec![2, 1, 0, 0], vec![v, 0.5, 0.25, 1.0]),
                }
                .unwrap()
            })
            .collect();
        let inside: Vec<bool> = (0..100).map(|i| i % 3 == 0).collect();
        let enc: Vec<Vec<u8>> = cuts.iter().map(|c| codec::encode_heights(c, ValueFormat::F32).unwrap()).collect();
        let payload = encode_cut_array(3, ValueFormat::F32, ShapeCoding::Heights, &enc, Some(&inside));
        (cuts, inside, payload)
    }

    /// `payload` written at byte 24 of a new file (after bytes that are not it), and the array
    /// parsed from it with that file as its source.
    fn on_disk(payload: &[u8], name: &str) -> (CutArray, std::path::PathBuf) {
        let path = std::env::temp_dir().join(format!("vcut-cut-array-{}-{name}", std::process::id()));
        let mut f = File::create(&path).unwrap();
        f.write_all(&[7u8; 24]).unwrap();
        f.write_all(payload).unwrap();
        drop(f);
        let file = Arc::new(File::open(&path).unwrap());
        let source = CutSource::new(file, &path, 24, payload.len() as u64, crc32fast::hash(payload));
        (CutArray::parse(payload.to_vec()).unwrap().with_source(source), path)
    }

    #[test]
    fn an_evicted_array_reads_the_same_cuts_from_its_file() {
        let (cuts, inside, payload) = array();
        let (mut a, path) = on_disk(&payload, "same");
        let resident = a.bytes();
        assert!(a.evict() && !a.is_resident());
        assert!(a.bytes() * 4 < resident, "{} of {resident} bytes kept", a.bytes());
        assert_eq!(a.cut_bytes(5), None);
        // Out of order, so that blocks are read again after others.
        for i in (0..100).rev().chain(0..100).chain((0..100).step_by(7)) {
            assert_eq!(a.cut(i).unwrap(), cuts[i], "cut {i}");
            assert_eq!(a.node_count(i).unwrap(), cuts[i].len());
            assert_eq!(a.inside(i), inside[i]);
        }
        a.restore().unwrap();
        assert!(a.is_resident());
        assert_eq!(a.bytes(), resident);
        assert_eq!((0..100).map(|i| a.cut(i).unwrap()).collect::<Vec<_>>(), cuts);
        // An array with no file to read from keeps its bytes.
        let mut plain = CutArray::parse(payload).unwrap();
        assert!(!plain.evict() && plain.is_resident());
        std::fs::remove_file(path).unwrap();
    }

    #[test]
    fn a_file_changed_after_eviction_is_refused_not_decoded() {
        let (cuts, _, payload) = array();
        let (mut a, path) = on_disk(&payload, "changed");
        a.evict();
        // A value byte of the last cut (block 3) changes in place: that block's cuts are
        // refused, naming the file; the other blocks still read.
        let mut f = std::fs::OpenOptions::new().write(true).open(&path).unwrap();
        f.seek(SeekFrom::Start(24 + payload.len() as u64 - 2)).unwrap();
        f.write_all(&[0x55]).unwrap();
        drop(f);
        let e = a.cut(99).unwrap_err();
        assert_eq!(e.index, 99);
        assert!(
            matches!(&e.error, CutFault::Read { path: p, reason } if p.contains("changed") && reason.contains("block 3")),
            "{e}"
        );
        assert!(a.node_count(96).is_err());
        assert_eq!(a.cut(3).unwrap(), cuts[3]);
        let e = a.clone().restore().unwrap_err();
        assert!(e.to_string().contains("checksum mismatch"), "{e}");
        // Cut short: a read error, not a panic.
        File::options().write(true).open(&path).unwrap().set_len(40).unwrap();
        let e = a.cut(40).unwrap_err();
        assert!(e.to_string().contains("reading"), "{e}");
        assert!(a.restore().is_err());
        std::fs::remove_file(path).unwrap();
    }
}
