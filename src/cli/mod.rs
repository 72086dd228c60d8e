//! Subcommand implementations for the `kairos` binary.

pub mod check;
pub mod compile;
pub mod estimate;
pub mod graph;
pub mod output;
pub mod plan;
pub mod run;
pub mod solve;

use std::path::Path;

use kairos::diagnostic::Source;

/// Exit code for bad input (unreadable or malformed files, bad arguments).
pub const BAD_INPUT: u8 = 2;

/// Why a subcommand did not succeed, and the exit code that says so.
pub struct Failure {
    /// 1: a run or an expectation failed; 2: bad input.
    pub code: u8,
    /// What to print on standard error.
    pub message: String,
}

impl Failure {
    /// A run that did not succeed (a goal that failed, a plan that did not reach it).
    pub fn failed(message: impl ToString) -> Self {
        Failure {
            code: 1,
            message: message.to_string(),
        }
    }

    /// A failure caused by the input.
    pub fn bad_input(message: impl ToString) -> Self {
        Failure {
            code: BAD_INPUT,
            message: message.to_string(),
        }
    }
}

/// Reads a file into a [`Source`] named by its path as given.
pub fn read_source(path: &Path) -> Result<Source, Failure> {
    Source::read(path).map_err(Failure::bad_input)
}

/// Reads and validates a plant model; its errors are bad input.
pub fn load_plant(path: &Path) -> Result<kairos::plant::Plant, Failure> {
    let source = read_source(path)?;
    kairos::plant::Plant::load(&source).map_err(Failure::bad_input)
}
