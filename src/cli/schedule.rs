//! `kairos schedule MISSION`: loads a mission, schedules its goal network (DESIGN.md §15.4;
//! mds-goal-networks.md §2.2) from the plant's most likely initial modes, and prints every time
//! point's window and each state variable's XGoals — or why the network cannot be scheduled
//! (exit 1).

use std::path::Path;

use kairos::goalnet::{display, mission, schedule};
use kairos::reconfiguration::Reconfiguration;

use super::Failure;

/// Loads, schedules and prints.
pub fn run(path: &Path) -> Result<(), Failure> {
    let mission = mission::load(path).map_err(Failure::bad_input)?;
    let reconfiguration = Reconfiguration::compile(&mission.plant)
        .map_err(|e| Failure::bad_input(format!("error: {}: {e}", mission.plant_path)))?;
    let current = mission.plant.most_likely_initial();
    println!("mission: {} (plant {})", mission.name, mission.plant_path);
    match schedule(&mission.network, &reconfiguration, &current) {
        Ok(executable) => {
            print!("{}", display::render(&executable, &mission.plant));
            Ok(())
        }
        Err(error) => Err(Failure::failed(display::explain(
            &error,
            &mission.network,
            &mission.plant,
        ))),
    }
}
