//! The command line as a user's shell sees it.

use std::process::{Command, Stdio};

#[test]
fn a_closed_stdout_ends_quietly_not_with_a_panic() {
    // `cargo xtask inspect builtin:teapot | head -0`: the reader is gone before the first line.
    let mut child = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["inspect", "builtin:teapot"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(141), "{stderr}");
}
