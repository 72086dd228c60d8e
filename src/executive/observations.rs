//! The executive's boundary with the outside: observations and commands by name.
//!
//! Monitors report `variable = value` by name; a name that is not an observable of the plant, or
//! a value outside its domain, is reported as an event and ignored for that cycle — the cycle
//! goes on (DESIGN.md §10, §13). Observables not reported are unknown for the cycle. A numeric
//! observable may be reported as a number ([`Value::Number`]): the plant model's monitor turns
//! it into a value first (`super::monitoring`).

use std::fmt;
use std::hash::{Hash, Hasher};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::events::EventKind;
use crate::logic::{ValueId, VarId};
use crate::plant::{InputError, Observation, Plant};

/// The value of a [`NamedValue`]: a value of the variable's domain, by name, or a reading of a
/// numeric observable (written as a number in traces and logs).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Value {
    /// A value of the variable's domain (`open`, `nominal`).
    Symbol(String),
    /// A reading (`28.1`) of a numeric observable, which its monitor maps to a value.
    Number(f64),
}

impl Value {
    /// The value's name, unless it is a number.
    pub fn symbol(&self) -> Option<&str> {
        match self {
            Value::Symbol(name) => Some(name),
            Value::Number(_) => None,
        }
    }
}

/// Numbers compare bit for bit (a reading equals the same reading, a NaN itself): what the
/// executive's "same report as last cycle" test needs.
impl PartialEq for Value {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Value::Symbol(a), Value::Symbol(b)) => a == b,
            (Value::Number(a), Value::Number(b)) => a.to_bits() == b.to_bits(),
            _ => false,
        }
    }
}

impl Eq for Value {}

/// A value equals a name when it is that symbol (`command.value == "on"`).
impl PartialEq<&str> for Value {
    fn eq(&self, other: &&str) -> bool {
        self.symbol() == Some(*other)
    }
}

impl Hash for Value {
    fn hash<H: Hasher>(&self, state: &mut H) {
        match self {
            Value::Symbol(name) => name.hash(state),
            Value::Number(x) => x.to_bits().hash(state),
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Symbol(name) => f.write_str(name),
            Value::Number(x) => write!(f, "{x}"),
        }
    }
}

impl From<&str> for Value {
    fn from(name: &str) -> Self {
        Value::Symbol(name.to_string())
    }
}

impl From<String> for Value {
    fn from(name: String) -> Self {
        Value::Symbol(name)
    }
}

impl From<&String> for Value {
    fn from(name: &String) -> Self {
        Value::Symbol(name.clone())
    }
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Number(x)
    }
}

/// `variable = value` by name: an observation from a monitor or a command to a control adapter.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct NamedValue {
    /// The variable (`valve1.outlet`, `PDE.cmd`).
    pub variable: String,
    /// Its value (a number only for a reading of a numeric observable).
    pub value: Value,
}

impl NamedValue {
    /// `variable = value`; `value` is a value's name or a number (a reading).
    pub fn new(variable: impl Into<String>, value: impl Into<Value>) -> Self {
        NamedValue {
            variable: variable.into(),
            value: value.into(),
        }
    }

    /// The named form of a typed assignment.
    pub fn of(plant: &Plant, var: VarId, value: ValueId) -> Self {
        let variable = plant.table().variable(var);
        NamedValue::new(variable.name(), variable.value_name(value))
    }
}

impl fmt::Display for NamedValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}", self.variable, self.value)
    }
}

impl<A: Into<String>, B: Into<Value>> From<(A, B)> for NamedValue {
    fn from((variable, value): (A, B)) -> Self {
        NamedValue::new(variable, value)
    }
}

/// The observation of one cycle, typed, and the events its checking raised.
#[derive(Clone)]
pub(crate) struct CheckedObservation {
    pub(crate) values: Vec<(VarId, ValueId)>,
    pub(crate) rejected: Vec<EventKind>,
}

/// The last cycle's report, checked and typed: a monitor that reports what it reported before
/// (every quiet cycle) gets the same answer without resolving names again. Certified:
/// [`check_observation`] and [`Observation::new`] are pure functions of the plant — the
/// executive's, fixed for its life — and the report, which is compared in full, or not at all
/// when it is the very report kept (a shared report, [`Report::Shared`], that is the same
/// allocation: kept alive here, it cannot have changed — comparing the EDL's 30 names every
/// quiet cycle was 1.5 k of its 46 k instructions).
#[derive(Clone, Default)]
pub(crate) struct LastObservation {
    last: Option<(Arc<[NamedValue]>, CheckedObservation, Observation)>,
}

/// A cycle's report as the embedder hands it over.
#[derive(Clone, Copy)]
pub(crate) enum Report<'a> {
    /// Borrowed for the cycle.
    Borrowed(&'a [NamedValue]),
    /// Shared: the same allocation as the last cycle's when nothing changed.
    Shared(&'a Arc<[NamedValue]>),
}

impl Report<'_> {
    /// The reported values.
    pub(crate) fn values(&self) -> &[NamedValue] {
        match self {
            Report::Borrowed(values) => values,
            Report::Shared(values) => values,
        }
    }
}

impl LastObservation {
    /// `observed` checked ([`check_observation`]) and typed, from the last cycle's answer when
    /// the report is the same; and whether it was (`true`: what is derived from the typed
    /// values alone — missing observables, observation changes — is what it was last cycle).
    pub(crate) fn check(
        &mut self,
        plant: &Plant,
        observed: Report<'_>,
    ) -> Result<(&CheckedObservation, &Observation, bool), InputError> {
        let same = match (&self.last, observed) {
            (None, _) => false,
            (Some((kept, _, _)), Report::Shared(shared)) if Arc::ptr_eq(kept, shared) => true,
            (Some((kept, _, _)), _) => **kept == *observed.values(),
        };
        if !same {
            let checked = check_observation(plant, observed.values());
            let observation = Observation::new(plant, &checked.values)?;
            let kept = match observed {
                Report::Borrowed(values) => Arc::from(values),
                Report::Shared(shared) => Arc::clone(shared),
            };
            self.last = Some((kept, checked, observation));
        }
        let (_, checked, observation) = self.last.as_ref().expect("set above");
        Ok((checked, observation, same))
    }

    /// The last report, typed (none before the first).
    pub(crate) fn observation(&self) -> Option<&Observation> {
        self.last.as_ref().map(|(_, _, observation)| observation)
    }
}

/// Resolves named observations against the plant's observables. Rejects (as events) unknown
/// names, names that are not observables, values outside the domain, and a second, different
/// value for the same observable in one cycle (the first is kept).
pub(crate) fn check_observation(plant: &Plant, observed: &[NamedValue]) -> CheckedObservation {
    let table = plant.table();
    let mut values: Vec<(VarId, ValueId)> = Vec::with_capacity(observed.len());
    let mut rejected = Vec::new();
    for item in observed {
        let reject = |reason: String| EventKind::ObservationRejected {
            variable: item.variable.clone(),
            value: item.value.to_string(),
            reason,
        };
        let Some(var) = table.variable_id(&item.variable) else {
            rejected.push(reject("no such variable in the plant model".to_string()));
            continue;
        };
        if !plant.is_reported(var) {
            rejected.push(reject("not an observable of the plant model".to_string()));
            continue;
        }
        let variable = table.variable(var);
        let Value::Symbol(name) = &item.value else {
            rejected.push(reject(format!(
                "a reading, but {} has no monitor in the plant model (one of: {})",
                item.variable,
                variable.values().join(", ")
            )));
            continue;
        };
        let Some(value) = variable.value(name) else {
            rejected.push(reject(format!(
                "not a value of {} (one of: {})",
                item.variable,
                variable.values().join(", ")
            )));
            continue;
        };
        match values.iter().find(|(x, _)| *x == var) {
            Some(&(_, earlier)) if earlier != value => rejected.push(reject(format!(
                "{} was already reported as {} this cycle",
                item.variable,
                variable.value_name(earlier)
            ))),
            Some(_) => {}
            None => values.push((var, value)),
        }
    }
    CheckedObservation { values, rejected }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Source;

    const PLANT: &str = r#"Plant(
        name: "lamp",
        components: [
            Component(
                name: "lamp",
                attributes: { "light": ["off", "on"] },
                modes: [
                    Mode(name: "ok", constraint: "true", reward: 0),
                ],
                initial: { "ok": 1.0 },
                transitions: [],
            ),
        ],
        controls: {},
        observables: ["lamp.light"],
    )"#;

    fn report(light: &str) -> Vec<NamedValue> {
        vec![NamedValue::new("lamp.light", light)]
    }

    /// DESIGN.md §10: a repeated report gets the last answer, whether it is the very report
    /// kept (a shared one, not compared), an equal one (compared in full), borrowed or shared;
    /// a changed one, through the same `Arc` or not, is checked afresh.
    #[test]
    fn a_report_is_repeated_when_it_is_the_same_or_equal() {
        let plant = Plant::load(&Source::new("lamp.ron", PLANT)).expect("a valid model");
        let mut last = LastObservation::default();
        let typed = |last: &mut LastObservation, report: Report<'_>| {
            let (checked, _, repeated) = last.check(&plant, report).expect("observable");
            (checked.values.clone(), repeated)
        };
        let on: Arc<[NamedValue]> = report("on").into();
        let (values, repeated) = typed(&mut last, Report::Shared(&on));
        assert!(!repeated, "the first report");
        assert_eq!(
            typed(&mut last, Report::Shared(&on)),
            (values.clone(), true)
        );
        let equal: Arc<[NamedValue]> = report("on").into();
        assert_eq!(
            typed(&mut last, Report::Shared(&equal)),
            (values.clone(), true)
        );
        assert_eq!(
            typed(&mut last, Report::Borrowed(&report("on"))),
            (values.clone(), true)
        );
        let off: Arc<[NamedValue]> = report("off").into();
        let (changed, repeated) = typed(&mut last, Report::Shared(&off));
        assert!(!repeated);
        assert_ne!(changed, values);
        assert_eq!(
            typed(&mut last, Report::Borrowed(&report("on"))),
            (values, false)
        );
    }
}
