//! The plant model's monitors at the executive's observation boundary: numeric readings become
//! the qualitative values estimation reads, before anything else sees the report
//! (`plant::monitor` has the semantics: range, hysteresis, persistence, staleness).
//!
//! The report that goes on to be checked and typed (`super::observations`) is the monitored
//! one: every observable that is not monitored as reported, each monitored one as its
//! monitor's value (absent while it has none). A plant without monitors skips this step
//! entirely, so the symbolic path costs nothing more; with monitors, a cycle copies the report
//! once and spends a comparison per threshold on each reading. A report whose readings vary
//! from cycle to cycle (noise) still usually maps to the same values, so the typed observation
//! is reused as before.

use std::collections::HashMap;

use super::events::EventKind;
use super::observations::{NamedValue, Value};
use crate::logic::{ValueId, VarId};
use crate::plant::Plant;
use crate::plant::monitor::{MonitorEvent, MonitorState, Sample};

/// Every monitor's state, and what the monitors made of the last report.
#[derive(Debug, Clone, Default)]
pub(crate) struct Monitoring {
    /// Per monitor of the plant, in its order.
    states: Vec<MonitorState>,
    /// The monitored observables by name.
    by_name: HashMap<String, usize>,
    /// Each monitor's value after the last report (`None`: absent).
    outputs: Vec<(VarId, Option<ValueId>)>,
}

impl Monitoring {
    /// Monitors that have seen nothing, one per monitor of `plant`.
    pub(crate) fn new(plant: &Plant) -> Self {
        let table = plant.table();
        let monitors = plant.monitors();
        Monitoring {
            states: vec![MonitorState::new(); monitors.len()],
            by_name: (monitors.iter().enumerate())
                .map(|(m, monitor)| (table.variable(monitor.observable).name().to_string(), m))
                .collect(),
            outputs: Vec::new(),
        }
    }

    /// True when the plant has no monitor (the report goes on as it is).
    pub(crate) fn is_empty(&self) -> bool {
        self.states.is_empty()
    }

    /// Each monitor's value after the last report, by observable.
    pub(crate) fn outputs(&self) -> &[(VarId, Option<ValueId>)] {
        &self.outputs
    }

    /// Feeds the readings of `observed` (at time `now`) to their monitors, in order — a sensor
    /// read faster than the executive cycles reports several readings of one observable in a
    /// cycle — and returns the report estimation reads, pushing what the monitors did as
    /// events: a value changed, a reading refused (out of range: an odd observation), an
    /// observable gone stale.
    pub(crate) fn apply(
        &mut self,
        plant: &Plant,
        now: f64,
        observed: &[NamedValue],
        events: &mut Vec<EventKind>,
    ) -> Vec<NamedValue> {
        let monitors = plant.monitors();
        let table = plant.table();
        let mut sampled = vec![false; self.states.len()];
        let mut report = Vec::with_capacity(observed.len());
        for item in observed {
            let Some(&m) = self.by_name.get(&item.variable) else {
                report.push(item.clone());
                continue;
            };
            let monitor = &monitors[m];
            let variable = table.variable(monitor.observable);
            let sample = match &item.value {
                Value::Number(x) => Sample::Reading(*x),
                Value::Symbol(name) => match variable.value(name) {
                    Some(value) => Sample::Value(value),
                    // Not a value: the check that follows refuses it, with the reason.
                    None => {
                        report.push(item.clone());
                        continue;
                    }
                },
            };
            sampled[m] = true;
            match self.states[m].sample(monitor, now, sample) {
                Some(MonitorEvent::Changed { reading, from, to }) => {
                    events.push(EventKind::Monitored {
                        variable: item.variable.clone(),
                        reading,
                        unit: monitor.unit.clone(),
                        from: from.map(|v| variable.value_name(v).to_string()),
                        to: variable.value_name(to).to_string(),
                    });
                }
                Some(MonitorEvent::OutOfRange { reading }) => {
                    let (lower, upper) = monitor.range;
                    events.push(EventKind::ObservationRejected {
                        variable: item.variable.clone(),
                        value: reading.to_string(),
                        reason: format!(
                            "outside the valid range [{lower}, {upper}]{}",
                            unit(&monitor.unit)
                        ),
                    });
                }
                Some(MonitorEvent::Stale { .. }) | None => {}
            }
        }
        self.outputs.clear();
        for (m, monitor) in monitors.iter().enumerate() {
            let (output, event) = self.states[m].close(monitor, now, sampled[m]);
            let variable = table.variable(monitor.observable);
            if let (Some(MonitorEvent::Stale { last }), Some(limit)) = (event, monitor.stale) {
                events.push(EventKind::Stale {
                    variable: variable.name().to_string(),
                    last,
                    limit,
                });
            }
            if let Some(value) = output {
                report.push(NamedValue::new(variable.name(), variable.value_name(value)));
            }
            self.outputs.push((monitor.observable, output));
        }
        report
    }

    /// Feeds the monitors' state to `state` (the executive's fingerprint: it decides how later
    /// readings are read).
    pub(crate) fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        use std::hash::Hash;
        for monitor in &self.states {
            monitor.fingerprint(state);
        }
        self.outputs.hash(state);
    }
}

fn unit(unit: &str) -> String {
    if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    }
}
