//! `kairos check-model MODEL`: load and validate a plant model (DESIGN.md §6.1). The lead wires
//! this into `kairos check FILES…` next to the RMPL checks.

use std::path::Path;

use kairos::plant::Plant;

use super::output::emit;
use super::{Failure, read_source};

/// Loads and validates the plant model at `path`; prints a one-line summary when it is valid and
/// the located errors (exit 2) when not.
pub fn check_model(path: &Path) -> Result<(), Failure> {
    let plant = load_plant(path)?;
    let components = plant.components();
    let modes: usize = components.iter().map(|c| c.modes().len()).sum();
    let transitions: usize = components.iter().map(|c| c.transitions().len()).sum();
    let summary = format!(
        "{}: ok: plant `{}`, {} components, {modes} modes, {transitions} transitions, {} controls, {} observables\n",
        path.display(),
        plant.name(),
        components.len(),
        plant.controls().len(),
        plant.observables().len(),
    );
    emit(&summary).map(|_| ())
}

/// Reads and validates a plant model; errors are bad input.
pub fn load_plant(path: &Path) -> Result<Plant, Failure> {
    let source = read_source(path)?;
    Plant::load(&source).map_err(Failure::bad_input)
}
