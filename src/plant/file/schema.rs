//! The plant file's schema, as serde reads it (the loader in `file.rs` gives it meaning and
//! locates every error).

use serde::Deserialize;

use super::monitors;
use crate::diagnostic::locate::Entries;
use crate::diagnostic::locate::NumberOrName as Number;

#[derive(Deserialize)]
#[serde(rename = "Plant", deny_unknown_fields)]
pub(super) struct PlantFile {
    pub(super) name: String,
    #[serde(default)]
    pub(super) types: Vec<TypeFile>,
    pub(super) components: Vec<ComponentFile>,
    #[serde(default)]
    pub(super) controls: Entries<String>,
    #[serde(default)]
    pub(super) observables: Vec<String>,
    #[serde(default)]
    pub(super) connections: Vec<String>,
    #[serde(default)]
    pub(super) monitors: Entries<monitors::MonitorFile>,
    #[serde(default)]
    pub(super) acknowledgements: Entries<String>,
}

/// `Type(...)`: a component written once, instantiated by `Component(name, type)`.
#[derive(Deserialize)]
#[serde(rename = "Type", deny_unknown_fields)]
pub(super) struct TypeFile {
    pub(super) name: String,
    #[serde(default)]
    pub(super) parameters: Entries<f64>,
    #[serde(default)]
    pub(super) attributes: Entries<Vec<String>>,
    pub(super) modes: Vec<ModeFile>,
    pub(super) initial: Entries<Number>,
    #[serde(default)]
    pub(super) transitions: Vec<TransitionFile>,
}

#[derive(Deserialize)]
#[serde(rename = "Component", deny_unknown_fields)]
pub(super) struct ComponentFile {
    pub(super) name: String,
    #[serde(default, rename = "type")]
    pub(super) type_name: Option<String>,
    #[serde(default)]
    pub(super) parameters: Entries<f64>,
    #[serde(default)]
    pub(super) attributes: Entries<Vec<String>>,
    #[serde(default)]
    pub(super) modes: Vec<ModeFile>,
    #[serde(default)]
    pub(super) initial: Entries<Number>,
    #[serde(default)]
    pub(super) transitions: Vec<TransitionFile>,
}

pub(super) fn always() -> String {
    "true".to_string()
}

pub(super) fn zero() -> Number {
    Number::Number(0.0)
}

#[derive(Deserialize)]
#[serde(rename = "Mode", deny_unknown_fields)]
pub(super) struct ModeFile {
    pub(super) name: String,
    #[serde(default)]
    pub(super) kind: KindFile,
    #[serde(default = "always")]
    pub(super) constraint: String,
    #[serde(default = "zero")]
    pub(super) reward: Number,
}

#[derive(Deserialize, Default, Clone, Copy)]
pub(super) enum KindFile {
    #[default]
    Nominal,
    Fault,
}

#[derive(Deserialize)]
#[serde(rename = "Transition", deny_unknown_fields)]
pub(super) struct TransitionFile {
    pub(super) from: String,
    pub(super) to: String,
    #[serde(default = "always")]
    pub(super) guard: String,
    pub(super) probability: Option<Number>,
    pub(super) rate: Option<Number>,
    pub(super) after: Option<TimingFile>,
}

#[derive(Deserialize, Clone)]
pub(super) enum TimingFile {
    Uniform(Number, Number),
    Gaussian(Number, Number),
    Exponential(Number),
    Fixed(Number),
}
