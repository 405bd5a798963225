//! A container of checksummed sections: the format of `.vcuts` (visibility cuts) and `.vleaf`
//! (plant-leaf transfer) files. Each user names its sections with a [`Kind`], whose
//! [`Format`] gives the magic bytes and the version.
//!
//! ```text
//! header (64 bytes)   magic (8 bytes, the format's), version u32, header size u32, table offset
//!                     u64, table length u64, table CRC-32 u32, section count u32, zeros
//! section record      "VSEC", kind u32, a u32, b u32, payload length u64, payload CRC-32 u32,
//!  (32 bytes)         zero u32; then the payload, zero-padded to a multiple of 8 bytes
//! ...
//! table               per section 32 bytes: kind u32, a u32, b u32, CRC-32 u32,
//!                     payload offset u64, payload length u64
//! ```
//! All integers little-endian; payloads start at multiples of 8 bytes, so a file can be
//! memory-mapped and sections read in place. [`Reader`] reads the header and table and then one
//! section at a time, each checked against its CRC-32.
//!
//! [`Writer`] writes to `<name>.partial` and renames it to the final name only once the table
//! is written. Opening a writer on a path whose `.partial` exists keeps every complete, intact
//! section record in it (a run killed mid-write, or stopped by a full disk, loses only the
//! section being written); the caller then re-supplies sections in order, and those already
//! present are kept when the caller's are identical ([`Writer::put`]) or skipped without
//! recomputation ([`Writer::keep`]). When sections are deterministic, a resumed file is
//! byte-identical to an uninterrupted one.
//!
//! # Invariants
//! Readers never panic on damaged or hostile bytes: every problem is a [`FileError`] naming the
//! file and, where it applies, the section. A failed write never leaves a file under the final
//! name.
//!
//! # Example
//! ```
//! use vcut_container::{Format, Kind, Reader, SectionId, Writer};
//!
//! #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
//! struct Note;
//! impl Kind for Note {
//!     const FORMAT: Format = Format { magic: *b"NOTES\0\r\n", version: 1, extension: "notes" };
//!     fn code(self) -> u32 { 1 }
//!     fn from_code(code: u32) -> Option<Note> { (code == 1).then_some(Note) }
//!     fn describe(self, a: u32, _b: u32) -> String { format!("note {a}") }
//! }
//!
//! let path = std::env::temp_dir().join(format!("doc-{}.notes", std::process::id()));
//! let mut w = Writer::open(&path).unwrap();
//! w.put(SectionId::new(Note, 7, 0), b"hello").unwrap();
//! w.finish().unwrap();
//! let mut r = Reader::<Note>::open(&path).unwrap();
//! assert_eq!(r.section(SectionId::new(Note, 7, 0)).unwrap(), b"hello");
//! # std::fs::remove_file(&path).unwrap();
//! ```

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

const HEADER_LEN: u64 = 64;
const RECORD_LEN: u64 = 32;
const ENTRY_LEN: u64 = 32;

/// What distinguishes one container format from another.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Format {
    /// The first 8 bytes of every file.
    pub magic: [u8; 8],
    /// The version written and the only one read.
    pub version: u32,
    /// The file extension, named in errors ("not a usable .vcuts file").
    pub extension: &'static str,
}

/// What a section holds: each format's own enumeration, numbered in the file.
pub trait Kind: Copy + Eq + Ord + std::hash::Hash + std::fmt::Debug + 'static {
    /// The format these sections belong to.
    const FORMAT: Format;
    /// The number stored in the file.
    fn code(self) -> u32;
    /// The kind numbered `code`, if it is one.
    fn from_code(code: u32) -> Option<Self>;
    /// A section of this kind as people read it: `svc (object 0, chunk 3)`.
    fn describe(self, a: u32, b: u32) -> String;
}

/// A section's identity: kind and two numbers whose meaning depends on the kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SectionId<K> {
    /// Kind.
    pub kind: K,
    /// First number.
    pub a: u32,
    /// Second number.
    pub b: u32,
}

impl<K: Kind> SectionId<K> {
    /// A section id.
    pub fn new(kind: K, a: u32, b: u32) -> SectionId<K> {
        SectionId { kind, a, b }
    }
}

impl<K: Kind> std::fmt::Display for SectionId<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.kind.describe(self.a, self.b))
    }
}

/// One entry of the offset table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SectionEntry<K> {
    /// Which section.
    pub id: SectionId<K>,
    /// Byte offset of the payload in the file.
    pub offset: u64,
    /// Payload length in bytes.
    pub len: u64,
    /// CRC-32 of the payload.
    pub crc: u32,
}

/// Why a container file could not be read or written. Every variant names the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FileError {
    /// An OS error.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error (not a `source`: the message already carries it once).
        error: std::io::Error,
    },
    /// Writing a section failed (a full disk, a file-size limit, a device gone): the sections
    /// before it stay in the partial file, which the next run resumes.
    #[error(
        "{}: writing {section}: {error}; the {kept} sections before it are kept there and the next \
         run resumes from them",
        path.display()
    )]
    Write {
        /// The partial file.
        path: PathBuf,
        /// The section being written.
        section: String,
        /// The OS error.
        error: std::io::Error,
        /// Sections complete in the partial file.
        kept: usize,
    },
    /// The header or the offset table is unusable.
    #[error("{}: not a usable .{extension} file: {reason}", path.display())]
    Header {
        /// The file.
        path: PathBuf,
        /// The format's extension.
        extension: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A section is damaged or malformed.
    #[error("{}: section {section}: {reason}", path.display())]
    Section {
        /// The file.
        path: PathBuf,
        /// The section (e.g. `field (object 1, sphere 3)`).
        section: String,
        /// What is wrong.
        reason: String,
    },
    /// The file has no such section.
    #[error("{}: has no section {section}", path.display())]
    Missing {
        /// The file.
        path: PathBuf,
        /// The section asked for.
        section: String,
    },
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    let mut x = [0u8; 8];
    x.copy_from_slice(&b[at..at + 8]);
    u64::from_le_bytes(x)
}

fn padded(len: u64) -> u64 {
    len.div_ceil(8) * 8
}

fn header_bytes(
    format: Format,
    table_offset: u64,
    table_len: u64,
    table_crc: u32,
    count: u32,
) -> [u8; HEADER_LEN as usize] {
    let mut h = [0u8; HEADER_LEN as usize];
    h[0..8].copy_from_slice(&format.magic);
    h[8..12].copy_from_slice(&format.version.to_le_bytes());
    h[12..16].copy_from_slice(&(HEADER_LEN as u32).to_le_bytes());
    h[16..24].copy_from_slice(&table_offset.to_le_bytes());
    h[24..32].copy_from_slice(&table_len.to_le_bytes());
    h[32..36].copy_from_slice(&table_crc.to_le_bytes());
    h[36..40].copy_from_slice(&count.to_le_bytes());
    h
}

fn record_bytes<K: Kind>(id: SectionId<K>, len: u64, crc: u32) -> [u8; RECORD_LEN as usize] {
    let mut r = [0u8; RECORD_LEN as usize];
    r[0..4].copy_from_slice(b"VSEC");
    r[4..8].copy_from_slice(&id.kind.code().to_le_bytes());
    r[8..12].copy_from_slice(&id.a.to_le_bytes());
    r[12..16].copy_from_slice(&id.b.to_le_bytes());
    r[16..24].copy_from_slice(&len.to_le_bytes());
    r[24..28].copy_from_slice(&crc.to_le_bytes());
    r
}

/// The space free for a new file at `path` (on the file system of its nearest existing
/// ancestor folder, so a folder still to be made reports the space it will get), if the system
/// says.
pub fn available_space(path: &Path) -> Option<u64> {
    let absolute = std::path::absolute(path).ok()?;
    let dir = absolute.ancestors().skip(1).find(|d| d.is_dir())?;
    fs4::available_space(dir).ok()
}

/// The temporary name a file is written under.
pub fn partial_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    name.push(".partial");
    path.with_file_name(name)
}

/// Writes a container file section by section, resuming a previous run's partial file.
pub struct Writer<K: Kind> {
    path: PathBuf,
    partial: PathBuf,
    out: BufWriter<File>,
    /// Sections written or kept so far, in order.
    entries: Vec<SectionEntry<K>>,
    /// Intact sections found in the partial file and not yet re-supplied, in order.
    pending: std::collections::VecDeque<SectionEntry<K>>,
    /// End of the last section written or kept (the file position once `pending` is empty).
    end: u64,
    resumed: usize,
}

impl<K: Kind> Writer<K> {
    /// Opens `<path>.partial`, keeping its intact sections if it exists (see the module docs).
    pub fn open(path: &Path) -> Result<Writer<K>, FileError> {
        let partial = partial_path(path);
        let io = |error| FileError::Io { path: partial.clone(), error };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|error| FileError::Io { path: dir.into(), error })?;
        }
        let mut file =
            OpenOptions::new().read(true).write(true).create(true).truncate(false).open(&partial).map_err(io)?;
        let found = scan_records::<K>(&mut file).map_err(io)?;
        let found_end = found.last().map_or(HEADER_LEN, |e| e.offset + padded(e.len));
        file.set_len(found_end).map_err(io)?;
        file.seek(SeekFrom::Start(0)).map_err(io)?;
        file.write_all(&header_bytes(K::FORMAT, 0, 0, 0, 0)).map_err(io)?;
        file.seek(SeekFrom::Start(found_end)).map_err(io)?;
        Ok(Writer {
            path: path.into(),
            partial,
            out: BufWriter::with_capacity(1 << 20, file),
            entries: Vec::new(),
            pending: found.into(),
            end: HEADER_LEN,
            resumed: 0,
        })
    }

    /// Sections found intact in the partial file when the writer was opened and not yet used.
    pub fn pending(&self) -> usize {
        self.pending.len()
    }

    /// Sections in the file so far (written or kept).
    pub fn written(&self) -> usize {
        self.entries.len()
    }

    /// Sections kept from a previous run so far.
    pub fn resumed(&self) -> usize {
        self.resumed
    }

    /// Whether the next section of the partial file is `id` (so [`Writer::keep`] can take it
    /// without recomputing it).
    pub fn can_keep(&self, id: SectionId<K>) -> bool {
        self.pending.front().is_some_and(|e| e.id == id)
    }

    /// Keeps the next section of the partial file, which must be `id` ([`Writer::can_keep`]).
    pub fn keep(&mut self, id: SectionId<K>) -> Result<(), FileError> {
        match self.pending.pop_front() {
            Some(e) if e.id == id => {
                self.end = e.offset + padded(e.len);
                self.entries.push(e);
                self.resumed += 1;
                Ok(())
            }
            _ => Err(FileError::Section {
                path: self.partial.clone(),
                section: id.to_string(),
                reason: "not the next section of the partial file".into(),
            }),
        }
    }

    /// [`Writer::keep`], returning the kept section's payload (checked against its CRC-32): for
    /// a caller that continues from what the earlier run computed.
    pub fn keep_payload(&mut self, id: SectionId<K>) -> Result<Vec<u8>, FileError> {
        let entry = match self.pending.front() {
            Some(e) if e.id == id => *e,
            _ => return self.keep(id).map(|_| Vec::new()),
        };
        let io = |error| FileError::Io { path: self.partial.clone(), error };
        // While sections are pending nothing is written: the position is the end of the last
        // intact record, and goes back there.
        self.out.flush().map_err(io)?;
        let file = self.out.get_mut();
        let resume_at = file.stream_position().map_err(io)?;
        let mut payload = vec![0u8; entry.len as usize];
        file.seek(SeekFrom::Start(entry.offset)).map_err(io)?;
        file.read_exact(&mut payload).map_err(io)?;
        file.seek(SeekFrom::Start(resume_at)).map_err(io)?;
        if crc32fast::hash(&payload) != entry.crc {
            return Err(FileError::Section {
                path: self.partial.clone(),
                section: id.to_string(),
                reason: "checksum mismatch (the partial file changed under this run)".into(),
            });
        }
        self.keep(id)?;
        Ok(payload)
    }

    /// Appends a section. If the partial file's next section is the same section with the same
    /// bytes it is kept; if it differs, it and everything after it are discarded. A failed write
    /// is a [`FileError::Write`]: the sections before it stay for the next run.
    pub fn put(&mut self, id: SectionId<K>, payload: &[u8]) -> Result<(), FileError> {
        let crc = crc32fast::hash(payload);
        if let Some(e) = self.pending.front() {
            if e.id == id && e.len == payload.len() as u64 && e.crc == crc {
                return self.keep(id);
            }
            self.discard_pending()?;
        }
        let pad = padded(payload.len() as u64) - payload.len() as u64;
        let written = (|| {
            self.out.write_all(&record_bytes(id, payload.len() as u64, crc))?;
            self.out.write_all(payload)?;
            self.out.write_all(&[0u8; 8][..pad as usize])?;
            // Each finished section reaches the OS at once, so a kill loses at most the next one.
            self.out.flush()
        })();
        if let Err(error) = written {
            return Err(FileError::Write {
                path: self.partial.clone(),
                section: id.to_string(),
                error,
                kept: self.entries.len(),
            });
        }
        let offset = self.end + RECORD_LEN;
        self.entries.push(SectionEntry { id, offset, len: payload.len() as u64, crc });
        self.end = offset + padded(payload.len() as u64);
        Ok(())
    }

    fn discard_pending(&mut self) -> Result<(), FileError> {
        let io = |error| FileError::Io { path: self.partial.clone(), error };
        self.pending.clear();
        self.out.flush().map_err(io)?;
        let file = self.out.get_mut();
        file.set_len(self.end).map_err(io)?;
        file.seek(SeekFrom::Start(self.end)).map_err(io)?;
        Ok(())
    }

    /// Writes the offset table and header and renames the file to its final name. Returns the
    /// final size in bytes.
    pub fn finish(mut self) -> Result<u64, FileError> {
        if !self.pending.is_empty() {
            self.discard_pending()?;
        }
        let io = |error| FileError::Io { path: self.partial.clone(), error };
        let mut table = Vec::with_capacity(self.entries.len() * ENTRY_LEN as usize);
        for e in &self.entries {
            table.extend_from_slice(&e.id.kind.code().to_le_bytes());
            table.extend_from_slice(&e.id.a.to_le_bytes());
            table.extend_from_slice(&e.id.b.to_le_bytes());
            table.extend_from_slice(&e.crc.to_le_bytes());
            table.extend_from_slice(&e.offset.to_le_bytes());
            table.extend_from_slice(&e.len.to_le_bytes());
        }
        self.out.write_all(&table).map_err(io)?;
        self.out.flush().map_err(io)?;
        let header =
            header_bytes(K::FORMAT, self.end, table.len() as u64, crc32fast::hash(&table), self.entries.len() as u32);
        let file = self.out.get_mut();
        file.seek(SeekFrom::Start(0)).map_err(io)?;
        file.write_all(&header).map_err(io)?;
        file.sync_all().map_err(io)?;
        let size = self.end + table.len() as u64;
        std::fs::rename(&self.partial, &self.path).map_err(|error| FileError::Io { path: self.path.clone(), error })?;
        Ok(size)
    }
}

/// The intact section records of a partial file, in order, up to the first damaged one.
fn scan_records<K: Kind>(file: &mut File) -> std::io::Result<Vec<SectionEntry<K>>> {
    let len = file.metadata()?.len();
    let mut found = Vec::new();
    let mut head = [0u8; HEADER_LEN as usize];
    file.seek(SeekFrom::Start(0))?;
    if len < HEADER_LEN
        || file.read_exact(&mut head).is_err()
        || head[0..8] != K::FORMAT.magic
        || u32_at(&head, 8) != K::FORMAT.version
    {
        return Ok(found);
    }
    let mut at = HEADER_LEN;
    let mut payload = Vec::new();
    while at + RECORD_LEN <= len {
        let mut r = [0u8; RECORD_LEN as usize];
        file.seek(SeekFrom::Start(at))?;
        file.read_exact(&mut r)?;
        let Some(kind) = K::from_code(u32_at(&r, 4)) else { break };
        let plen = u64_at(&r, 16);
        if &r[0..4] != b"VSEC" || at + RECORD_LEN + padded(plen) > len {
            break;
        }
        payload.resize(plen as usize, 0);
        file.read_exact(&mut payload)?;
        let crc = u32_at(&r, 24);
        if crc32fast::hash(&payload) != crc {
            break;
        }
        let id = SectionId::new(kind, u32_at(&r, 8), u32_at(&r, 12));
        found.push(SectionEntry { id, offset: at + RECORD_LEN, len: plen, crc });
        at += RECORD_LEN + padded(plen);
    }
    Ok(found)
}

/// Reads a finished container file lazily: the header and table at open, sections on demand.
/// Generic over the byte source (a `File` by default, or e.g. `std::io::Cursor` in memory).
pub struct Reader<K, R = File> {
    path: PathBuf,
    file: R,
    entries: Vec<SectionEntry<K>>,
    size: u64,
}

impl<K: Kind> Reader<K, File> {
    /// Opens the file and checks its header and offset table.
    pub fn open(path: &Path) -> Result<Reader<K, File>, FileError> {
        let file = File::open(path).map_err(|error| FileError::Io { path: path.into(), error })?;
        Reader::from_source(file, path)
    }

    /// Another handle to the open file (the same file even if its path is replaced since):
    /// for reading a section's bytes later, in place, by their [`SectionEntry::offset`].
    pub fn file_handle(&self) -> Result<File, FileError> {
        self.file.try_clone().map_err(|error| FileError::Io { path: self.path.clone(), error })
    }
}

impl<K: Kind, R: Read + Seek> Reader<K, R> {
    /// Reads the header and offset table from `source`; errors name `path`.
    pub fn from_source(mut file: R, path: &Path) -> Result<Reader<K, R>, FileError> {
        let format = K::FORMAT;
        let io = |error| FileError::Io { path: path.into(), error };
        let bad = |reason: String| FileError::Header { path: path.into(), extension: format.extension, reason };
        let size = file.seek(SeekFrom::End(0)).map_err(io)?;
        file.seek(SeekFrom::Start(0)).map_err(io)?;
        let mut h = [0u8; HEADER_LEN as usize];
        if size < HEADER_LEN {
            return Err(bad(format!("{size} bytes, shorter than the {HEADER_LEN}-byte header")));
        }
        file.read_exact(&mut h).map_err(io)?;
        if h[0..8] != format.magic {
            return Err(bad(format!("wrong magic bytes (not a .{} file)", format.extension)));
        }
        let version = u32_at(&h, 8);
        if version != format.version {
            return Err(bad(format!(
                "format version {version}; this build reads version {} (compute the file again)",
                format.version
            )));
        }
        let (table_offset, table_len, table_crc, count) =
            (u64_at(&h, 16), u64_at(&h, 24), u32_at(&h, 32), u32_at(&h, 36));
        if table_offset == 0 {
            return Err(bad("unfinished (no offset table: the run writing it did not complete)".into()));
        }
        if table_len != u64::from(count) * ENTRY_LEN || table_offset.checked_add(table_len) != Some(size) {
            return Err(bad(format!(
                "offset table ({count} sections at byte {table_offset}, {table_len} bytes) does not end the \
                 {size}-byte file: truncated or damaged"
            )));
        }
        let mut table = vec![0u8; table_len as usize];
        file.seek(SeekFrom::Start(table_offset)).map_err(io)?;
        file.read_exact(&mut table).map_err(io)?;
        if crc32fast::hash(&table) != table_crc {
            return Err(bad("offset table checksum mismatch".into()));
        }
        let mut entries = Vec::with_capacity(count as usize);
        for e in table.chunks_exact(ENTRY_LEN as usize) {
            let kind =
                K::from_code(u32_at(e, 0)).ok_or_else(|| bad(format!("unknown section kind {}", u32_at(e, 0))))?;
            let entry = SectionEntry {
                id: SectionId::new(kind, u32_at(e, 4), u32_at(e, 8)),
                crc: u32_at(e, 12),
                offset: u64_at(e, 16),
                len: u64_at(e, 24),
            };
            if entry.offset < HEADER_LEN + RECORD_LEN
                || entry.offset.checked_add(entry.len).is_none_or(|end| end > table_offset)
            {
                return Err(bad(format!("section {} lies outside the file", entry.id)));
            }
            entries.push(entry);
        }
        Ok(Reader { path: path.into(), file, entries, size })
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// File size in bytes.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// The offset table.
    pub fn entries(&self) -> &[SectionEntry<K>] {
        &self.entries
    }

    /// Whether the file has section `id`.
    pub fn has(&self, id: SectionId<K>) -> bool {
        self.entries.iter().any(|e| e.id == id)
    }

    /// Section `id`'s table entry: where its payload lies and its checksum.
    pub fn entry(&self, id: SectionId<K>) -> Option<SectionEntry<K>> {
        self.entries.iter().find(|e| e.id == id).copied()
    }

    /// Reads section `id` and checks its checksum.
    pub fn section(&mut self, id: SectionId<K>) -> Result<Vec<u8>, FileError> {
        let entry = *self
            .entries
            .iter()
            .find(|e| e.id == id)
            .ok_or_else(|| FileError::Missing { path: self.path.clone(), section: id.to_string() })?;
        let io = |error| FileError::Io { path: self.path.clone(), error };
        let mut payload = Vec::new();
        payload
            .try_reserve_exact(entry.len as usize)
            .map_err(|_| io(std::io::Error::new(std::io::ErrorKind::OutOfMemory, "section larger than memory")))?;
        payload.resize(entry.len as usize, 0);
        self.file.seek(SeekFrom::Start(entry.offset)).map_err(io)?;
        self.file.read_exact(&mut payload).map_err(io)?;
        if crc32fast::hash(&payload) != entry.crc {
            return Err(self.section_error(id, "checksum mismatch (the file is damaged)"));
        }
        Ok(payload)
    }

    /// An error about section `id` of this file.
    pub fn section_error(&self, id: SectionId<K>, reason: impl std::fmt::Display) -> FileError {
        FileError::Section { path: self.path.clone(), section: id.to_string(), reason: reason.to_string() }
    }

    /// Reads and checks every section; returns the first problem.
    pub fn verify(&mut self) -> Result<(), FileError> {
        for id in self.entries.iter().map(|e| e.id).collect::<Vec<_>>() {
            self.section(id)?;
        }
        Ok(())
    }
}
