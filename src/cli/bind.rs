//! `kairos bind --fprime-dict DICT --plant PLANT [--binding FILE]`: checks a binding of the plant
//! model to an F´ dictionary, or prints a starting one (`kairos::executive::fprime`).

use std::path::Path;

use kairos::executive::fprime::{self, Binding, Dictionary};

use super::{Failure, load_plant, read_source};

/// Checks `binding` (a line saying what is bound, or every error located) or, without one,
/// prints a starting binding on standard output.
pub fn run(dictionary: &Path, plant: &Path, binding: Option<&Path>) -> Result<(), Failure> {
    let dictionary = Dictionary::load(&read_source(dictionary)?).map_err(Failure::bad_input)?;
    let plant = load_plant(plant)?;
    let Some(path) = binding else {
        print!("{}", fprime::suggest(&dictionary, &plant));
        return Ok(());
    };
    let binding =
        Binding::load(&read_source(path)?, &dictionary, &plant).map_err(Failure::bad_input)?;
    println!(
        "{}: ok ({} channel(s) bound to the observables of {}, {} command(s) to its control values)",
        path.display(),
        binding.channels().count(),
        plant.name(),
        binding.commands().len()
    );
    Ok(())
}
