//! Subcommand implementations for the `kairos` binary.

pub mod bench;
pub mod bind;
pub mod campaign;
pub mod check;
pub mod compile;
pub mod estimate;
pub mod explore;
pub mod explore_rover;
pub mod graph;
pub mod limits;
pub mod model_args;
pub mod output;
pub mod plan;
pub mod run;
pub mod schedule;
pub mod shards;
pub mod solve;
pub mod window_args;

use std::path::Path;

use kairos::diagnostic::Source;

/// Exit code for bad input (unreadable or malformed files, bad arguments).
pub const BAD_INPUT: u8 = 2;

/// Why a subcommand did not succeed, and the exit code that says so (2 for bad input and for a
/// file that cannot be written, 1 for a run that failed).
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

    /// A file or stream that cannot be read or written (a full disk, a directory without
    /// write permission): exit 2 like bad input, since it says nothing of the run, and exit 1
    /// is kept for a run or an expectation that failed.
    pub fn io(message: impl ToString) -> Self {
        Failure::bad_input(message)
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

/// Above this many plant variables `kairos plan` and `kairos estimate` say, before they start,
/// that the work ahead grows faster than the plant: both ask SAT questions over the whole plant
/// per transition (policy compilation) or per cycle (estimation). Measured in BENCHMARKS.md
/// ("Loading large plants"): 400 variables take a fraction of a second, 4,000 variables tens of
/// seconds.
pub const LARGE_PLANT_VARIABLES: usize = 1_000;

/// Says on standard error, before a long computation on a large plant starts, how large it is
/// and that `what` grows faster than linearly with it (a 10,000-component plant ran
/// for minutes with no output): when the plant has more than [`LARGE_PLANT_VARIABLES`], or when
/// the caller knows its work is `large` for another reason.
pub fn announce_large_plant(path: &Path, plant: &kairos::plant::Plant, what: &str, large: bool) {
    let variables = plant.table().len();
    if variables <= LARGE_PLANT_VARIABLES && !large {
        return;
    }
    let components = plant.components();
    let transitions: usize = components.iter().map(|c| c.transitions().len()).sum();
    let largest = components
        .iter()
        .map(|c| c.modes().len())
        .max()
        .unwrap_or(0);
    eprintln!(
        "note: {}: {}, {}, {}, up to {} in a component; {what} grows faster than linearly \
         with the plant and may take minutes",
        path.display(),
        check::count(components.len(), "component"),
        check::count(variables, "variable"),
        check::count(transitions, "transition"),
        check::count(largest, "mode"),
    );
}
