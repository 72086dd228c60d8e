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
    Ok(format!(
        "{}: program {} ({}, {}, {})",
        path.display(),
        thca.name(),
        count(thca.locations().len(), "location"),
        count(thca.table().len(), "variable"),
        count(thca.table().clocks().len(), "clock"),
    ))
}

fn count(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}
