//! Running the real `shadeballs` binary, as a user does, for the CLI tests.

use std::path::PathBuf;
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

/// A fresh folder under the system temp folder, unique to this process.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("shadeballs-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
