//! Helpers for tests on the shipped plant models: loading, naming variables and modes, building
//! beliefs and logs.
#![allow(dead_code)] // each includer uses a different part

use kairos::diagnostic::Source;
use kairos::estimation::log::{LogRecord, parse_log};
use kairos::estimation::{Belief, PlantEstimate, WeightedState};
use kairos::logic::{ValueId, VarId};
use kairos::plant::{Plant, SystemState};

/// The text of `models/NAME.ron`.
pub fn model_text(name: &str) -> String {
    let path = format!("{}/models/{name}.ron", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// A plant from RON text.
pub fn plant_from(name: &str, text: &str) -> Plant {
    Plant::load(&Source::new(name, text)).unwrap_or_else(|e| panic!("{e}"))
}

/// `models/NAME.ron`, loaded.
pub fn model(name: &str) -> Plant {
    plant_from(name, &model_text(name))
}

/// A variable by name.
pub fn var(plant: &Plant, name: &str) -> VarId {
    plant
        .table()
        .variable_id(name)
        .unwrap_or_else(|| panic!("no `{name}`"))
}

/// `name = value` by names.
pub fn value(plant: &Plant, name: &str, value: &str) -> (VarId, ValueId) {
    let x = var(plant, name);
    let v = plant.table().variable(x).value(value);
    (
        x,
        v.unwrap_or_else(|| panic!("`{value}` is not a value of `{name}`")),
    )
}

/// Mode values for a plant state given by mode names, one per component in order.
pub fn modes(plant: &Plant, names: &[&str]) -> Vec<ValueId> {
    assert_eq!(names.len(), plant.components().len());
    plant
        .components()
        .iter()
        .zip(names)
        .map(|(c, n)| c.mode_named(n).unwrap_or_else(|| panic!("no mode `{n}`")))
        .collect()
}

/// A belief certain of one system state, every component having entered its mode at `time`.
pub fn certain(plant: &Plant, names: &[&str], time: f64) -> Belief {
    let state = SystemState::entered_at(plant, modes(plant, names), time);
    Belief::new(
        plant,
        time,
        vec![WeightedState {
            state,
            probability: 1.0,
        }],
    )
    .expect("a belief")
}

/// The mode name of `component` in an estimate.
pub fn mode_in<'a>(plant: &'a Plant, estimate: &PlantEstimate, component: &str) -> &'a str {
    let id = plant
        .component_named(component)
        .unwrap_or_else(|| panic!("no component `{component}`"));
    &plant.component(id).mode(estimate.modes[id.index()]).name
}

/// The marginal of `component = mode`.
pub fn marginal(plant: &Plant, belief: &Belief, component: &str, mode: &str) -> f64 {
    let (x, v) = value(plant, component, mode);
    belief.marginal(x, v).expect("a mode variable")
}

/// A log from JSON lines.
pub fn log(plant: &Plant, text: &str) -> Vec<LogRecord> {
    parse_log(&Source::new("log.jsonl", text), plant).unwrap_or_else(|e| panic!("{e}"))
}
