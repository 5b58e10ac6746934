//! Running the real `shadeballs` binary, as a user does, for the CLI tests.

use std::process::Command;

/// Runs `shadeballs args…`: (exit status was success, stderr).
pub fn shadeballs(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_shadeballs"))
        .args(args)
        .output()
        .expect("run shadeballs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

// The temp folders (one helper for the suite and the crate's own tests: pixels.rs).
pub use crate::pixels::temp_dir;

/// Sends `SIG<signal>` (`INT`, `TERM`) to a running `shadeballs` whose stderr is piped,
/// waits for it, and checks that it exited with `code` naming the signal: its stderr.
pub fn interrupt(child: std::process::Child, signal: &str, code: i32) -> String {
    let killed = Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    println!("SIG{signal} -> {:?}: {stderr}", out.status.code());
    assert_eq!(out.status.code(), Some(code), "{stderr}");
    assert!(
        stderr.contains(&format!("interrupted by SIG{signal}")),
        "{stderr}"
    );
    stderr
}
