//! `kairos compile PROGRAM [--entry NAME] [--plant MODEL] [--dot]`: compiles an RMPL program to its THCA and
//! prints a listing of the locations, or a Graphviz drawing.

use std::io::Write;
use std::path::Path;

use kairos::rmpl::{self, LinkOptions};
use kairos::sequencer::dot;

use super::{Failure, read_source};

/// Compiles the program in `path` (its first program, or `entry`) and prints the automaton.
pub fn run(
    path: &Path,
    entry: Option<&str>,
    plant: Option<&Path>,
    as_dot: bool,
) -> Result<(), Failure> {
    let plant = plant.map(super::load_plant).transpose()?;
    let source = read_source(path)?;
    let options = LinkOptions {
        entry,
        plant: plant.as_ref().map(|p| p.table()),
    };
    let thca = rmpl::load(&source, &options).map_err(Failure::bad_input)?;
    let text = if as_dot {
        dot::graph(&thca, &[]).render()
    } else {
        thca.to_string()
    };
    // A reader that closes the pipe early (`| head`) is not an error worth a panic.
    let _ = std::io::stdout().write_all(text.as_bytes());
    Ok(())
}
