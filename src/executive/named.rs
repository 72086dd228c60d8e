//! What a cycle produced, by name: a flight loop sends observations in as
//! [`NamedValue`]s and gets commands, modes and diagnoses back the same way, never handling the
//! plant's ids. Each accessor takes the plant (`executive.plant()`): a [`Step`] stays a plain
//! value that costs nothing extra per cycle for loops that do not ask.

use super::{NamedValue, Step};
use crate::plant::Plant;

/// One tracked plant state with names: every component's mode (`valve = open`, as a
/// [`NamedValue`] whose variable is the component) and the state's probability. Owned, so that a
/// loop can keep it across cycles while it steps the executive.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedEstimate {
    /// `component = mode` for every component, in the model's order.
    pub modes: Vec<NamedValue>,
    /// Its probability.
    pub probability: f64,
}

impl NamedEstimate {
    /// The `component = mode` pairs where this state differs from `other` (what makes this
    /// hypothesis different from the most likely one).
    pub fn differences_from(&self, other: &NamedEstimate) -> Vec<&NamedValue> {
        let pairs = self.modes.iter().zip(&other.modes);
        pairs.filter(|(a, b)| a != b).map(|(a, _)| a).collect()
    }
}

impl Step {
    /// μ(i) by name, ready for a [`ControlAdapter`](super::adapters::ControlAdapter):
    /// `PDE.cmd = on`. Empty when the cycle commands nothing.
    pub fn commands_named(&self, plant: &Plant) -> Vec<NamedValue> {
        let command = self.command.iter();
        command.map(|&(x, v)| NamedValue::of(plant, x, v)).collect()
    }

    /// ŝ(i) by name: `component = mode` for every component.
    pub fn modes_named(&self, plant: &Plant) -> Vec<NamedValue> {
        named_modes(plant, &self.most_likely)
    }

    /// The most likely mode of the component named `component` (`None` for an unknown name or
    /// before the first estimate).
    pub fn mode_of<'p>(&self, plant: &'p Plant, component: &str) -> Option<&'p str> {
        let id = plant.component_named(component)?;
        let mode = self.most_likely.get(id.index())?;
        Some(plant.component(id).mode(*mode).name.as_str())
    }

    /// The `n` most likely plant states of the belief, by name, most likely first.
    pub fn top_estimates(&self, plant: &Plant, n: usize) -> Vec<NamedEstimate> {
        self.estimates
            .iter()
            .take(n)
            .map(|estimate| NamedEstimate {
                modes: named_modes(plant, &estimate.modes),
                probability: estimate.probability,
            })
            .collect()
    }
}

fn named_modes(plant: &Plant, modes: &[crate::logic::ValueId]) -> Vec<NamedValue> {
    let components = plant.components().iter().zip(modes);
    components
        .map(|(c, &mode)| NamedValue::new(c.name(), c.mode(mode).name.as_str()))
        .collect()
}
