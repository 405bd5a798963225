//! Long jobs and the disk: an estimate before they start (`--dry-run` prints only that), a
//! refusal when the output cannot fit (unless `--force`), and a full disk, a file-size limit or
//! a read-only output folder giving a clear error that leaves the `.partial` file resumable —
//! the resumed output byte-identical to an uninterrupted run's.
//!
//! The file-size limit runs everywhere (`ulimit -f` with SIGXFSZ ignored, so writes fail with
//! EFBIG as on a full disk). The full disk and the read-only folder need a small tmpfs: mounted
//! where the test may mount one (root in CI), otherwise the test says it skipped that part.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output};

mod common;
use common::scratch;

/// `vcuts precompute` of the test scene into `out`, with `extra` arguments, under the shell
/// prefix `limit` (e.g. a file-size limit).
fn precompute(dir: &Path, out: &Path, extra: &[&str], limit: &str) -> Output {
    let mut cmd = format!(
        "{limit} exec '{}' precompute --scene '{}' --cache-dir '{}' --estimate-seconds 0.2 -o '{}'",
        env!("CARGO_BIN_EXE_vcuts"),
        dir.join("scene.toml").display(),
        dir.join("cache").display(),
        out.display()
    );
    for e in extra {
        cmd.push_str(&format!(" {e}"));
    }
    Command::new("sh").arg("-c").arg(&cmd).output().unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// A fresh run's bytes, the reference every interrupted run must end at.
fn reference(dir: &Path) -> Vec<u8> {
    let out = dir.join("reference.vcuts");
    let o = precompute(dir, &out, &[], "");
    assert!(o.status.success(), "{}", text(&o));
    std::fs::read(out).unwrap()
}

#[test]
fn a_dry_run_prints_the_estimate_and_writes_nothing() {
    let s = scratch("dry");
    let out = s.0.join("dry.vcuts");
    let o = precompute(&s.0, &out, &["--dry-run"], "");
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    for key in [
        "estimate: ",
        "estimate_vertices=",
        "estimate_field_points=",
        "estimate_rays=",
        "estimate_s=",
        "estimate_output_mb=",
        "estimate_peak_mb=",
    ] {
        assert!(t.contains(key), "{key} missing:\n{t}");
    }
    assert!(!out.exists() && !vcut_container::partial_path(&out).exists());
    assert!(!t.contains("output="), "{t}");
}

#[test]
fn a_file_size_limit_stops_the_run_cleanly_and_it_resumes_to_the_same_bytes() {
    let s = scratch("ulimit");
    let whole = reference(&s.0);
    let out = s.0.join("limited.vcuts");
    // 64 blocks (32 kB in sh's 512-byte blocks, 64 kB in bash's): past the first sections.
    let o = precompute(&s.0, &out, &[], "trap '' XFSZ; ulimit -f 64;");
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(!t.contains("panicked"), "{t}");
    assert!(t.contains("limited.vcuts.partial: writing") && t.contains("File too large"), "{t}");
    assert!(t.contains("sections before it are kept there and the next run resumes"), "{t}");
    assert!(!out.exists(), "no output under the final name after a failed write");
    assert!(vcut_container::partial_path(&out).exists());
    let o = precompute(&s.0, &out, &[], "");
    let t = text(&o);
    assert!(o.status.success() && t.contains("resuming from"), "{t}");
    assert_eq!(std::fs::read(&out).unwrap(), whole, "resumed bytes differ");
}

#[test]
fn a_full_disk_and_a_read_only_folder_give_clear_errors_and_a_resumable_partial() {
    let s = scratch("tmpfs");
    let mnt = s.0.join("mnt");
    std::fs::create_dir_all(&mnt).unwrap();
    let mounted = Command::new("mount").args(["-t", "tmpfs", "-o", "size=48k", "tmpfs"]).arg(&mnt).output();
    if !mounted.as_ref().is_ok_and(|o| o.status.success()) {
        let why =
            mounted.map(|o| String::from_utf8_lossy(&o.stderr).trim().to_string()).unwrap_or_else(|e| e.to_string());
        let _ =
            writeln!(std::io::stderr(), "SKIPPED the full-disk and read-only parts: cannot mount a tmpfs here ({why})");
        return;
    }
    let whole = reference(&s.0);
    let out = mnt.join("out.vcuts");
    // The estimate sees the output cannot fit: refused before anything is written.
    let o = precompute(&s.0, &out, &[], "");
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(t.contains("of disk for") && t.contains("free there") && t.contains("--force"), "{t}");
    assert!(!vcut_container::partial_path(&out).exists());
    // Forced, it fills the disk: a clear error, the finished sections kept.
    let o = precompute(&s.0, &out, &["--force"], "");
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(t.contains("out.vcuts.partial: writing") && t.contains("No space left on device"), "{t}");
    assert!(!out.exists() && vcut_container::partial_path(&out).exists());
    // More room: the run resumes and ends at the uninterrupted run's bytes.
    let grown = Command::new("mount").args(["-o", "remount,size=4m"]).arg(&mnt).status().unwrap();
    assert!(grown.success());
    let o = precompute(&s.0, &out, &[], "");
    let t = text(&o);
    assert!(o.status.success() && t.contains("resuming from"), "{t}");
    assert_eq!(std::fs::read(&out).unwrap(), whole, "resumed bytes differ");
    // A read-only output folder: named, nothing written.
    let ro = Command::new("mount").args(["-o", "remount,ro"]).arg(&mnt).status().unwrap();
    assert!(ro.success());
    let other = mnt.join("other.vcuts");
    let o = precompute(&s.0, &other, &[], "");
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(t.contains("other.vcuts.partial") && t.contains("Read-only file system"), "{t}");
    assert!(!other.exists());
}
