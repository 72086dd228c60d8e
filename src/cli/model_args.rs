//! `--fault` and `--noise`, shared by `kairos run` and `kairos campaign`: forced
//! faults and sensor noise for a scenario's model-driven plant, given on the command line. A
//! campaign run with them is replayed by `kairos run` with the same options and the run's seed.

use kairos::simulation::Scenario;

use super::Failure;

/// The model-driven plant's options.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ModelArgs {
    /// Force a fault, such as "valve1 = stuck-closed @ 17103 s": the component is put in the
    /// mode at the first cycle at or after the time. Repeatable; added to the scenario's.
    #[arg(long = "fault", value_name = "COMPONENT = MODE @ T s")]
    pub faults: Vec<String>,
    /// Sensor noise: the probability that an observation is replaced by a random value of its
    /// domain, in place of the scenario's.
    #[arg(long, value_name = "q")]
    pub noise: Option<f64>,
}

impl ModelArgs {
    /// Applies the options to `scenario`; an error names the option, its text, what is wrong
    /// and what was expected.
    pub fn apply(&self, scenario: &mut Scenario) -> Result<(), Failure> {
        for text in &self.faults {
            let expected = format!(
                "`component = mode @ T s`: a component of {}, one of its fault modes, and \
                 0 ≤ T ≤ {} s (the scenario's end)",
                scenario.plant_path, scenario.end
            );
            scenario.force_fault(text).map_err(|message| {
                Failure::bad_input(format!(
                    "error: --fault \"{text}\": {message}\n  expected: {expected}"
                ))
            })?;
        }
        if let Some(noise) = self.noise {
            scenario.set_noise(noise).map_err(|message| {
                Failure::bad_input(format!(
                    "error: --noise {noise}: {message}\n  expected: a probability from 0 to 1"
                ))
            })?;
        }
        Ok(())
    }

    /// The options as they are written on the command line, to replay a run with them.
    pub fn command_line(&self) -> String {
        let faults = self.faults.iter().map(|f| format!(" --fault \"{f}\""));
        let noise = self.noise.map(|q| format!(" --noise {q}"));
        faults.chain(noise).collect()
    }
}
