//! Loading a scenario's `simulator: Model(...)`: the model-driven plant's settings, each
//! problem located in the scenario file.

use super::format::{ScenarioFile, SimulatorFile};
use super::load::FileCtx;
use super::model_plant::{ForcedFault, ModelPlantConfig, check_noise};
use crate::diagnostic::locate::Step;
use crate::plant::Plant;

/// The model-driven plant's settings, when the scenario asks for one; `end` is the scenario's
/// end time (a fault forced after it would never happen).
pub(super) fn model_config(
    ctx: &mut FileCtx,
    file: &ScenarioFile,
    plant: &Plant,
    end: f64,
) -> Option<ModelPlantConfig> {
    let SimulatorFile::Model {
        seed,
        faults,
        noise,
    } = file.simulator.as_ref()?;
    let noise = check_noise(*noise).unwrap_or_else(|message| {
        ctx.error(
            &[Step::Field("simulator"), Step::Field("noise")],
            message,
            "the probability that an observation is replaced by a random value, from 0 to 1",
        );
        0.0
    });
    let faults = faults
        .iter()
        .enumerate()
        .filter_map(|(i, text)| forced_fault(ctx, plant, i, text, end))
        .collect();
    Some(ModelPlantConfig {
        seed: *seed,
        faults,
        noise,
    })
}

/// One forced fault, read and checked.
fn forced_fault(
    ctx: &mut FileCtx,
    plant: &Plant,
    i: usize,
    text: &str,
    end: f64,
) -> Option<ForcedFault> {
    let path = [
        Step::Field("simulator"),
        Step::Field("faults"),
        Step::Index(i),
    ];
    match ForcedFault::parse(plant, text) {
        Ok(fault) => match fault.by(end) {
            Ok(fault) => Some(fault),
            Err(message) => {
                ctx.error(&path, message, "a time at or before the scenario's end");
                None
            }
        },
        Err(message) => {
            ctx.error(
                &path,
                message,
                "`component = fault mode @ time`, such as \"valve1 = stuck-closed @ 120 s\"",
            );
            None
        }
    }
}
