//! `kairos check FILES...`: parses and links every file and reports every error in each.
//! RMPL programs (`.rmpl`) are checked today; plant models join when their loader lands.

use std::path::Path;

use kairos::rmpl::{self, LinkOptions};

use super::{Failure, read_source};

/// Checks each file; prints a line per good file and fails with every error of the bad ones.
pub fn run(paths: &[impl AsRef<Path>]) -> Result<(), Failure> {
    let mut problems = Vec::new();
    for path in paths.iter().map(AsRef::as_ref) {
        match check_file(path) {
            Ok(summary) => println!("ok: {summary}"),
            Err(failure) => problems.push(failure.message),
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(Failure::bad_input(problems.join("\n\n")))
    }
}

fn check_file(path: &Path) -> Result<String, Failure> {
    if path.extension().and_then(|e| e.to_str()) != Some("rmpl") {
        return Err(Failure::bad_input(format!(
            "error: cannot check {}: expected an RMPL program (.rmpl)",
            path.display()
        )));
    }
    let source = read_source(path)?;
    let thca = rmpl::load(&source, &LinkOptions::default()).map_err(Failure::bad_input)?;
    let clocks = thca.table().clocks().len();
    Ok(format!(
        "{}: program {} ({} locations, {} variables, {} clocks)",
        path.display(),
        thca.name(),
        thca.locations().len(),
        thca.table().len(),
        clocks
    ))
}
