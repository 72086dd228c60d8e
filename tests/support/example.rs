//! Running a shipped example from a test: `cargo test` builds every example beside the tests
//! (target/<profile>/examples), so a test can run the program a user would.

/// Runs the example `name` to its end; asserts it succeeds and that its output has every one
/// of `lines`, and returns that output.
pub fn runs_and_prints(name: &str, lines: &[&str]) -> String {
    let exe = std::env::current_exe().expect("the test knows where it is");
    // target/<profile>/deps/<this test> → target/<profile>/examples/<name>
    let example = exe
        .parent()
        .and_then(|deps| deps.parent())
        .map(|profile| profile.join("examples"))
        .expect("the test runs from target/<profile>/deps")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    let output = std::process::Command::new(&example)
        .output()
        .unwrap_or_else(|e| panic!("{}: {e}", example.display()));
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(output.status.success(), "{stdout}");
    for line in lines {
        assert!(stdout.contains(line), "missing `{line}` in\n{stdout}");
    }
    stdout
}
