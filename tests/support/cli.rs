//! Running the `kairos` binary from integration tests.

use std::process::Command;

/// Runs `kairos ARGS...` in the crate's root; returns the exit code (−1 if killed), standard
/// output and standard error.
pub fn kairos(args: &[&str]) -> (i32, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_kairos"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the kairos binary runs");
    (
        output.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}
