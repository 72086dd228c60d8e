//! Running the shipped scenarios through `kairos run` and reading their mission logs (shared by
//! the scenario suites: tests/mars_edl_scenarios.rs, tests/spacecraft_deployment.rs). Needs
//! `#[path = "support/cli.rs"] mod cli;` in the test crate.

use std::path::Path;

use crate::cli::kairos;

/// Runs the scenario at `path` (from the crate's root) and returns its mission log, failing
/// with the log if it does not pass (exit code 0 and the `PASS:` line).
pub fn run_passing(path: &str) -> String {
    let (code, stdout, stderr) = kairos(&["run", path]);
    assert_eq!(code, 0, "{path} failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("PASS: "), "{stdout}");
    stdout
}

/// The log has each line (compared with runs of whitespace squeezed, so the column padding does
/// not matter), in this order.
pub fn assert_in_order(log: &str, lines: &[&str]) {
    let squeezed: Vec<String> = log.lines().map(squeeze).collect();
    let mut from = 0;
    for line in lines {
        let wanted = squeeze(line);
        match squeezed[from..].iter().position(|l| l.contains(&wanted)) {
            Some(i) => from += i + 1,
            None => panic!("`{line}` not found (in order) in the mission log:\n{log}"),
        }
    }
}

/// Every file in `dir` is either one of `scenarios` (each with a test in `suite`) or one of
/// `others` (scripts and documentation): a scenario added without a test fails this.
pub fn assert_every_file_is_tested(dir: &str, scenarios: &[&str], others: &[&str], suite: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
    for entry in std::fs::read_dir(&path).expect("the scenario directory exists") {
        let name = entry.expect("an entry").file_name();
        let name = name.to_string_lossy();
        assert!(
            scenarios.contains(&name.as_ref()) || others.contains(&name.as_ref()),
            "{dir}/{name} has no test in {suite}"
        );
    }
}

fn squeeze(line: &str) -> String {
    line.split_whitespace().collect::<Vec<_>>().join(" ")
}
