//! The container end to end: round trips with lazy reads, a killed run resumed from any byte
//! to the same bytes, damage and truncation named.

use std::path::{Path, PathBuf};
use vcut_container::{Format, Kind, Reader, SectionId, Writer, available_space, partial_path};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum T {
    Chunk = 5,
    Other = 6,
}

impl Kind for T {
    const FORMAT: Format = Format { magic: *b"VTEST\0\r\n", version: 2, extension: "vtest" };
    fn code(self) -> u32 {
        self as u32
    }
    fn from_code(code: u32) -> Option<T> {
        [T::Chunk, T::Other].into_iter().find(|k| k.code() == code)
    }
    fn describe(self, a: u32, b: u32) -> String {
        format!("{} (object {a}, chunk {b})", if self == T::Chunk { "chunk" } else { "other" })
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vcut-data-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir.join("out.vtest")
}

fn sections() -> Vec<(SectionId<T>, Vec<u8>)> {
    (0..6u32).map(|i| (SectionId::new(T::Chunk, 0, i), (0..(i * 13 + 5)).map(|x| (x * i) as u8).collect())).collect()
}

fn write_all(path: &Path, secs: &[(SectionId<T>, Vec<u8>)]) -> u64 {
    let mut w = Writer::open(path).unwrap();
    for (id, p) in secs {
        w.put(*id, p).unwrap();
    }
    w.finish().unwrap()
}

#[test]
fn round_trip_and_lazy_reads() {
    let path = scratch("rt");
    let secs = sections();
    let size = write_all(&path, &secs);
    assert!(!partial_path(&path).exists());
    let mut r = Reader::<T>::open(&path).unwrap();
    assert_eq!(r.size(), size);
    assert_eq!(r.entries().len(), 6);
    for (id, p) in secs.iter().rev() {
        assert_eq!(&r.section(*id).unwrap(), p);
        assert_eq!(r.entries().iter().find(|e| e.id == *id).unwrap().offset % 8, 0);
    }
    let e = r.section(SectionId::new(T::Other, 0, 0)).unwrap_err();
    assert!(e.to_string().contains("has no section other (object 0, chunk 0)"), "{e}");
}

#[test]
fn resume_from_any_cut_point_gives_the_same_bytes() {
    let path = scratch("resume");
    let secs = sections();
    write_all(&path, &secs);
    let whole = std::fs::read(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    // A run that wrote three sections, then was killed at every possible byte afterwards.
    let mut w = Writer::<T>::open(&path).unwrap();
    for (id, p) in &secs[..4] {
        w.put(*id, p).unwrap();
    }
    drop(w);
    let partial = std::fs::read(partial_path(&path)).unwrap();
    for cut in [partial.len(), partial.len() - 1, partial.len() - 40, 64, 10, 0] {
        std::fs::write(partial_path(&path), &partial[..cut]).unwrap();
        let mut w = Writer::<T>::open(&path).unwrap();
        let mut computed = 0;
        for (id, p) in &secs {
            if w.can_keep(*id) {
                // Either way of keeping a section; the payload read back is the one written.
                if id.b % 2 == 1 {
                    assert_eq!(&w.keep_payload(*id).unwrap(), p);
                } else {
                    w.keep(*id).unwrap();
                }
            } else {
                computed += 1;
                w.put(*id, p).unwrap();
            }
        }
        w.finish().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), whole, "cut at byte {cut}");
        assert!(computed >= 2 && (cut < partial.len() || computed == 2), "cut {cut}: {computed} recomputed");
    }
    // A partial file from different inputs: the differing section and all after it are rewritten.
    let mut other = secs.clone();
    other[1].1[0] ^= 1;
    std::fs::write(partial_path(&path), &partial).unwrap();
    write_all(&path, &other);
    let resumed = std::fs::read(&path).unwrap();
    write_all(&path, &other);
    assert!(resumed == std::fs::read(&path).unwrap(), "a partial file of other inputs left traces");
    let mut r = Reader::<T>::open(&path).unwrap();
    assert_eq!(r.section(other[1].0).unwrap(), other[1].1);
    r.verify().unwrap();
}

#[test]
fn damage_is_refused_naming_the_section() {
    let path = scratch("damage");
    write_all(&path, &sections());
    let whole = std::fs::read(&path).unwrap();
    let r = Reader::<T>::open(&path).unwrap();
    let e = *r.entries().iter().find(|e| e.id.b == 3).unwrap();
    drop(r);
    let mut flipped = whole.clone();
    flipped[e.offset as usize + 2] ^= 0x10;
    std::fs::write(&path, &flipped).unwrap();
    let mut r = Reader::<T>::open(&path).unwrap();
    let err = r.verify().unwrap_err().to_string();
    assert!(err.contains("section chunk (object 0, chunk 3): checksum mismatch"), "{err}");
    assert!(available_space(&path).is_some_and(|b| b > 0));
    assert!(available_space(&path.join("not/yet/made.vtest")).is_some());
    for cut in [whole.len() - 1, whole.len() / 2, 70, 3] {
        std::fs::write(&path, &whole[..cut]).unwrap();
        let err = Reader::<T>::open(&path).err().unwrap().to_string();
        assert!(err.contains("out.vtest") && (err.contains("truncated") || err.contains("shorter")), "{cut}: {err}");
    }
    let mut bad = whole.clone();
    bad[0] = b'X';
    std::fs::write(&path, &bad).unwrap();
    assert!(Reader::<T>::open(&path).err().unwrap().to_string().contains("magic bytes (not a .vtest file)"));
}
