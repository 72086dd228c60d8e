//! The `monitors:` section of a plant file: numeric observables and how their readings become
//! qualitative values ([`crate::plant::monitor`] has the semantics).
//!
//! ```ron
//! monitors: {
//!     "sensor.reading": Monitor(
//!         unit: "°C",
//!         range: (-40.0, 120.0),                 // valid readings, both ends included
//!         values: ["cold", "warm-low", "warm"],  // low to high: values of the observable
//!         thresholds: [                          // one fewer than the values, increasing
//!             (at: 20.0, hysteresis: 0.5),       // cold below 20, warm-low from 20 ...
//!             (at: 27.0, hysteresis: 0.5),
//!         ],
//!         persistence: 3,                        // optional (1): samples before a change
//!         stale: 5.0,                            // optional: seconds a value is held
//!         readings: {                            // optional: the model-driven plant's draw
//!             "cold": Gaussian(10.0, 1.0),       // Gaussian(mean, sd) or Uniform(l, u)
//!             "warm-low": Gaussian(23.5, 1.0),
//!             "warm": Gaussian(30.0, 1.0),
//!         },
//!     ),
//! },
//! ```
//! The key is an observable (or an indexed name of several, all monitored alike).

use std::collections::HashSet;

use serde::Deserialize;

use super::Loader;
use crate::diagnostic::Diagnostic;
use crate::diagnostic::locate::{Entries, Step};
use crate::logic::{ValueId, VarId};
use crate::plant::monitor::{Monitor, Reading, Threshold};

/// `Monitor(...)`.
#[derive(Deserialize)]
#[serde(rename = "Monitor", deny_unknown_fields)]
pub(super) struct MonitorFile {
    #[serde(default)]
    unit: String,
    range: (f64, f64),
    values: Vec<String>,
    #[serde(default)]
    thresholds: Vec<ThresholdFile>,
    #[serde(default = "one")]
    persistence: i64,
    #[serde(default)]
    stale: Option<f64>,
    #[serde(default)]
    readings: Entries<ReadingFile>,
}

fn one() -> i64 {
    1
}

/// `(at: 20.0, hysteresis: 0.5)`.
#[derive(Deserialize)]
#[serde(rename = "Threshold", deny_unknown_fields)]
struct ThresholdFile {
    at: f64,
    #[serde(default)]
    hysteresis: f64,
}

/// A law of readings.
#[derive(Deserialize, Clone, Copy)]
enum ReadingFile {
    Gaussian(f64, f64),
    Uniform(f64, f64),
}

/// Traces the laws of readings for the reference page's check (an enum is traced on its own).
#[cfg(test)]
pub(super) fn trace_reading(tracer: &mut serde_reflection::Tracer) {
    crate::diagnostic::reference::add::<ReadingFile>(tracer);
}

impl Loader {
    /// The monitors, each checked against its observable.
    pub(super) fn monitors(
        &mut self,
        file: &Entries<MonitorFile>,
        observables: &[VarId],
    ) -> Vec<Monitor> {
        let mut monitors: Vec<Monitor> = Vec::new();
        let mut listed = HashSet::new();
        for (written, spec) in &file.0 {
            let key = [Step::Field("monitors"), Step::Key(written)];
            let Some(names) = self.indexed(&key, written) else {
                continue;
            };
            for name in &names {
                let Some(var) = self.attribute(&key, name, "monitored") else {
                    continue;
                };
                if !observables.contains(&var) {
                    let message = format!("`{name}` is monitored but not an observable");
                    self.error(&key, message, "an observable listed in `observables`");
                } else if !listed.insert(var) {
                    let message = format!("`{name}` has two monitors");
                    self.error(
                        &[Step::Field("monitors")],
                        message,
                        "one monitor per observable",
                    );
                } else if let Some(monitor) = self.monitor(written, name, var, spec) {
                    monitors.push(monitor);
                }
            }
        }
        monitors
    }

    fn monitor(
        &mut self,
        written: &str,
        name: &str,
        var: VarId,
        spec: &MonitorFile,
    ) -> Option<Monitor> {
        let at = |field| {
            [
                Step::Field("monitors"),
                Step::Value(written),
                Step::Field(field),
            ]
        };
        let errors = self.errors.len();
        let (lower, upper) = spec.range;
        if !(lower.is_finite() && upper.is_finite() && lower < upper) {
            let message = format!("`{name}`: range ({lower}, {upper}) is not a range");
            self.error(
                &at("range"),
                message,
                "finite bounds, the lower below the upper",
            );
        }
        let values = self.monitor_values(name, var, &spec.values, &at("values"));
        let thresholds = self.thresholds(name, spec, values.len(), written);
        if spec.persistence < 1 || spec.persistence > i64::from(u32::MAX) {
            let message = format!("`{name}`: persistence {} is not a count", spec.persistence);
            self.error(&at("persistence"), message, "1 or more samples");
        }
        if let Some(stale) = spec.stale.filter(|s| !(s.is_finite() && *s > 0.0)) {
            let message = format!("`{name}`: staleness {stale} is not a duration");
            self.error(&at("stale"), message, "seconds, above 0");
        }
        let readings = self.readings(name, var, &values, spec, written);
        (self.errors.len() == errors).then(|| Monitor {
            observable: var,
            unit: spec.unit.clone(),
            range: spec.range,
            values,
            thresholds,
            persistence: spec.persistence.clamp(1, i64::from(u32::MAX)) as u32,
            stale: spec.stale,
            readings,
        })
    }

    /// The monitor's values: distinct values of the observable.
    fn monitor_values(
        &mut self,
        name: &str,
        var: VarId,
        written: &[String],
        path: &[Step],
    ) -> Vec<ValueId> {
        if written.is_empty() {
            self.error(
                path,
                format!("`{name}`: a monitor needs values"),
                "values, low to high",
            );
        }
        let mut values: Vec<ValueId> = Vec::with_capacity(written.len());
        for (i, value) in written.iter().enumerate() {
            let mut path = path.to_vec();
            path.push(Step::Index(i));
            match self.table.variable(var).value(value) {
                Some(v) if values.contains(&v) => {
                    let message = format!("`{name}`: `{value}` is listed twice");
                    self.error(&path, message, "each value once");
                }
                Some(v) => values.push(v),
                None => {
                    let domain = self.table.variable(var).values().join(", ");
                    let span = self.places.at(&path);
                    self.errors.push(
                        Diagnostic::new(format!("`{value}` is not a value of `{name}`"), span)
                            .expected(format!("a value of `{name}`"))
                            .note(format!("`{name}` takes one of: {domain}")),
                    );
                }
            }
        }
        values
    }

    /// The thresholds: one fewer than the values, inside the range, increasing, bands apart.
    fn thresholds(
        &mut self,
        name: &str,
        spec: &MonitorFile,
        values: usize,
        written: &str,
    ) -> Vec<Threshold> {
        let path = |i: usize, field| {
            [
                Step::Field("monitors"),
                Step::Value(written),
                Step::Field("thresholds"),
                Step::Index(i),
                Step::Field(field),
            ]
        };
        if spec.thresholds.len() + 1 != spec.values.len() {
            let at = [
                Step::Field("monitors"),
                Step::Value(written),
                Step::Field("thresholds"),
            ];
            let message = format!(
                "`{name}`: {} thresholds for {} values",
                spec.thresholds.len(),
                spec.values.len()
            );
            self.error(
                &at,
                message,
                "one threshold between each two neighbouring values",
            );
        }
        let (lower, upper) = spec.range;
        let mut thresholds: Vec<Threshold> = Vec::with_capacity(values.saturating_sub(1));
        for (i, t) in spec.thresholds.iter().enumerate() {
            if !(t.at.is_finite() && lower < t.at && t.at < upper) {
                let message = format!("`{name}`: threshold {} is outside the range", t.at);
                self.error(
                    &path(i, "at"),
                    message,
                    "a threshold inside the valid range",
                );
            } else if !(t.hysteresis.is_finite() && t.hysteresis >= 0.0) {
                let message = format!("`{name}`: hysteresis {} is not a width", t.hysteresis);
                self.error(&path(i, "hysteresis"), message, "0 or more");
            } else if let Some(before) = thresholds
                .last()
                .filter(|b| b.at + b.hysteresis > t.at - t.hysteresis)
            {
                let message = format!(
                    "`{name}`: threshold {} (± {}) is not above {} (± {})",
                    t.at, t.hysteresis, before.at, before.hysteresis
                );
                self.error(
                    &path(i, "at"),
                    message,
                    "increasing thresholds whose hysteresis bands do not overlap",
                );
            } else {
                thresholds.push(Threshold {
                    at: t.at,
                    hysteresis: t.hysteresis,
                });
            }
        }
        thresholds
    }

    /// The readings' laws, for the monitor's values only.
    fn readings(
        &mut self,
        name: &str,
        var: VarId,
        values: &[ValueId],
        spec: &MonitorFile,
        written: &str,
    ) -> Vec<(ValueId, Reading)> {
        let mut readings = Vec::new();
        for (value, law) in &spec.readings.0 {
            let key = [
                Step::Field("monitors"),
                Step::Value(written),
                Step::Field("readings"),
                Step::Key(value),
            ];
            let Some(v) = self
                .table
                .variable(var)
                .value(value)
                .filter(|v| values.contains(v))
            else {
                let message = format!("`{name}`: `{value}` is not one of the monitor's values");
                self.error(&key, message, "a value listed in `values`");
                continue;
            };
            let reading = match *law {
                ReadingFile::Gaussian(mean, sd)
                    if mean.is_finite() && sd.is_finite() && sd > 0.0 =>
                {
                    Reading::Gaussian { mean, sd }
                }
                ReadingFile::Uniform(lower, upper)
                    if lower.is_finite() && upper.is_finite() && lower < upper =>
                {
                    Reading::Uniform { lower, upper }
                }
                _ => {
                    let value_path = [
                        Step::Field("monitors"),
                        Step::Value(written),
                        Step::Field("readings"),
                        Step::Value(value),
                    ];
                    let message = format!("`{name}`: the readings of `{value}` have no spread");
                    self.error(
                        &value_path,
                        message,
                        "Gaussian(mean, sd) with sd above 0, or Uniform(lower, upper) with lower below upper",
                    );
                    continue;
                }
            };
            if readings.iter().any(|(w, _)| *w == v) {
                let message = format!("`{name}`: `{value}` has two laws of readings");
                self.error(&key, message, "each value once");
                continue;
            }
            readings.push((v, reading));
        }
        readings
    }
}
