//! The command/observation log `kairos estimate` replays (JSON lines). Reference for users:
//! `docs/reference/estimation-log.md`.
//!
//! One JSON object per line, one line per cycle, in time order:
//! ```text
//! # driver_valve: command the driver on, then see no flow out
//! {"time": 0.0, "observations": {"valve.flow_in": "nominal", "valve.flow_out": "zero"}}
//! {"time": 1.0, "observations": {"valve.flow_out": "zero"}, "commands": {"driver.dcmd_in": "on"}}
//! {"time": 2.0, "observations": {"valve.flow_out": "zero"}}
//! ```
//! - `time`: t(i), seconds, increasing from line to line (a repeated time is an error).
//! - `observations`: o(i), the observables read at t(i) by name; an observable not listed is
//!   unknown that cycle. A numeric observable (the plant model monitors it) may be given a
//!   number, `{"bus.voltage": 28.1}`: its monitor, run over the log in order, turns it into the
//!   value estimation reads (`plant::monitor`; a reading out of range is set aside, noted in
//!   [`LogRecord::monitored`]).
//! - `commands`: μ(i), the controls commanded at t(i), after that cycle's estimate (the
//!   executive's order: observe, estimate, decide, command); a control not listed is idle.
//!
//! The first line's observations condition the initial belief at its time; each later line
//! i+1 is one estimation step with line i's commands, line i+1's observations and time. Blank
//! lines and lines starting with `#` or `//` are comments. Errors point at file:line:column.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use serde::Deserialize;

use super::{EstimationError, ModeEstimator, Update};
use crate::diagnostic::locate::NumberOrName;
use crate::diagnostic::{Diagnostic, Source, SourceErrors, Span, did_you_mean};
use crate::logic::{ValueId, VarId};
use crate::opsat::Theory;
use crate::plant::monitor::{MonitorEvent, MonitorState, Sample};
use crate::plant::{Commands, Observation, Plant};

/// What the monitors did with a line's readings, by observable.
type MonitorEvents = Vec<(VarId, MonitorEvent)>;

/// One cycle of a log.
#[derive(Debug, Clone, PartialEq)]
pub struct LogRecord {
    /// t(i), seconds.
    pub time: f64,
    /// o(i).
    pub observation: Observation,
    /// μ(i), issued after the estimate at t(i).
    pub commands: Commands,
    /// What the monitors of numeric observables did with this line's readings (a value
    /// changed, a reading out of range, a reading gone stale).
    pub monitored: Vec<(VarId, MonitorEvent)>,
    /// The line it was read from (1-based).
    pub line: usize,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RecordLine {
    time: f64,
    #[serde(default)]
    observations: BTreeMap<String, NumberOrName>,
    #[serde(default)]
    commands: BTreeMap<String, String>,
}

/// Reads a log against a plant, reporting every problem with its location.
pub fn parse_log(source: &Source, plant: &Plant) -> Result<Vec<LogRecord>, SourceErrors> {
    let mut records: Vec<LogRecord> = Vec::new();
    let mut errors = Vec::new();
    // The last time read, and its line, even from a line with other errors.
    let mut last: Option<(f64, usize)> = None;
    let mut line_start = 0;
    let mut monitors = vec![MonitorState::new(); plant.monitors().len()];
    for (number, line) in source.text.split_inclusive('\n').enumerate() {
        let start = line_start;
        line_start += line.len();
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') || trimmed.starts_with("//") {
            continue;
        }
        let mut reader = LineReader {
            plant,
            line,
            start,
            errors: &mut errors,
            monitors: &mut monitors,
        };
        let Some(parsed) = reader.parse() else {
            continue;
        };
        if let Some((previous, previous_line)) = last {
            // A repeated time is refused too: each line is a cycle, and a cycle of length zero
            // would count a second estimation step at the same instant.
            if parsed.time <= previous {
                let span = reader.find("time", 0).unwrap_or(start..start + line.len());
                let message = if parsed.time == previous {
                    format!("time {previous} s repeats the time of line {previous_line}")
                } else {
                    format!(
                        "time {} s comes after {previous} s on line {previous_line}",
                        parsed.time
                    )
                };
                reader.errors.push(
                    Diagnostic::new(message, span)
                        .expected("a time later than the line before's (one cycle per line)"),
                );
            }
        }
        last = Some((parsed.time, number + 1));
        if let Some(record) = reader.record(&parsed, number + 1) {
            records.push(record);
        }
    }
    if errors.is_empty() {
        Ok(records)
    } else {
        Err(SourceErrors::new(source.clone(), errors))
    }
}

struct LineReader<'a> {
    plant: &'a Plant,
    line: &'a str,
    start: usize,
    errors: &'a mut Vec<Diagnostic>,
    /// The monitors' states, carried from line to line.
    monitors: &'a mut [MonitorState],
}

impl LineReader<'_> {
    /// The span of the quoted string `text` in the line, at or after byte `from` of the line.
    fn find(&self, text: &str, from: usize) -> Option<Span> {
        let quoted = format!("\"{text}\"");
        let at = self.line.get(from..)?.find(&quoted)? + from + 1;
        Some(self.start + at..self.start + at + text.len())
    }

    /// The line's JSON, with a usable time; `None` (error recorded) otherwise.
    fn parse(&mut self) -> Option<RecordLine> {
        let text = self.line.trim_end_matches(['\n', '\r']);
        let parsed: RecordLine = match serde_json::from_str(text) {
            Ok(parsed) => parsed,
            Err(e) => {
                let at = self.start + e.column().saturating_sub(1).min(text.len());
                self.errors.push(
                    Diagnostic::new(format!("malformed log line: {e}"), at..at)
                        .expected(r#"{"time": seconds, "observations": {...}, "commands": {...}}"#),
                );
                return None;
            }
        };
        if !parsed.time.is_finite() || parsed.time < 0.0 {
            let span = self.find("time", 0).unwrap_or(self.start..self.start);
            self.errors.push(
                Diagnostic::new(format!("time {} is not a time", parsed.time), span)
                    .expected("seconds, 0 or more"),
            );
            return None;
        }
        Some(parsed)
    }

    /// The record of a parsed line, its names checked against the plant.
    fn record(&mut self, parsed: &RecordLine, number: usize) -> Option<LogRecord> {
        let mut named = BTreeMap::new();
        let mut readings = Vec::new();
        for (name, value) in &parsed.observations {
            match value {
                NumberOrName::Name(value) => _ = named.insert(name.clone(), value.clone()),
                NumberOrName::Number(x) => readings.push((name.as_str(), *x)),
            }
        }
        let reported: Vec<VarId> = (self.plant.observables().iter().copied())
            .chain(self.plant.acknowledgements().iter().map(|a| a.observable))
            .collect();
        let observed = self.assignments(&named, &reported, "an observable");
        let readings = self.readings(&readings);
        let controls: Vec<VarId> = self.plant.controls().iter().map(|c| c.var).collect();
        let commanded = self.assignments(&parsed.commands, &controls, "a control");
        let (observed, commanded, readings) = (observed?, commanded?, readings?);
        let (observed, monitored) = self.monitor(parsed.time, observed, &readings);
        // Both are checked against the plant above, so neither can fail here.
        let observation = Observation::new(self.plant, &observed).ok()?;
        let commands = Commands::new(self.plant, &commanded).ok()?;
        Some(LogRecord {
            time: parsed.time,
            observation,
            commands,
            monitored,
            line: number,
        })
    }

    /// Resolves `name: number` pairs: each must name an observable the plant monitors.
    fn readings(&mut self, pairs: &[(&str, f64)]) -> Option<Vec<(usize, f64)>> {
        let mut out = Vec::with_capacity(pairs.len());
        let mut ok = true;
        for &(name, x) in pairs {
            let monitor =
                (self.plant.table().variable_id(name)).and_then(|var| self.plant.monitor_of(var));
            match monitor {
                Some(m) => out.push((m, x)),
                None => {
                    let span = self.find(name, 0).unwrap_or(self.start..self.start);
                    self.errors.push(
                        Diagnostic::new(format!("`{name}` = {x}: `{name}` is not numeric"), span)
                            .expected("a value's name: only observables the plant model monitors take numbers"),
                    );
                    ok = false;
                }
            }
        }
        ok.then_some(out)
    }

    /// The line's observation through the monitors: readings fed to theirs, a value given for a
    /// monitored observable taken as it is, every monitored observable then its monitor's
    /// value (absent while it has none).
    fn monitor(
        &mut self,
        time: f64,
        mut observed: Vec<(VarId, ValueId)>,
        readings: &[(usize, f64)],
    ) -> (Vec<(VarId, ValueId)>, MonitorEvents) {
        let monitors = self.plant.monitors();
        if monitors.is_empty() {
            return (observed, Vec::new());
        }
        let mut sampled = vec![false; monitors.len()];
        let mut events = Vec::new();
        for (m, monitor) in monitors.iter().enumerate() {
            let given = observed.iter().position(|(x, _)| *x == monitor.observable);
            if let Some(i) = given {
                let (_, value) = observed.remove(i);
                self.monitors[m].sample(monitor, time, Sample::Value(value));
                sampled[m] = true;
            }
        }
        for &(m, x) in readings {
            sampled[m] = true;
            let event = self.monitors[m].sample(&monitors[m], time, Sample::Reading(x));
            events.extend(event.map(|e| (monitors[m].observable, e)));
        }
        for (m, monitor) in monitors.iter().enumerate() {
            let (output, event) = self.monitors[m].close(monitor, time, sampled[m]);
            events.extend(event.map(|e| (monitor.observable, e)));
            observed.extend(output.map(|v| (monitor.observable, v)));
        }
        (observed, events)
    }

    /// Resolves `name: value` pairs against the allowed variables.
    fn assignments(
        &mut self,
        pairs: &BTreeMap<String, String>,
        allowed: &[VarId],
        role: &str,
    ) -> Option<Vec<(VarId, ValueId)>> {
        let table = self.plant.table();
        let mut out = Vec::new();
        let mut ok = true;
        for (name, value) in pairs {
            let name_span = self.find(name, 0).unwrap_or(self.start..self.start);
            let Some(var) = table.variable_id(name).filter(|x| allowed.contains(x)) else {
                let names = allowed.iter().map(|&x| table.variable(x).name());
                let mut diagnostic =
                    Diagnostic::new(format!("`{name}` is not {role} of the plant"), name_span)
                        .expected(format!(
                            "{role}: {}",
                            names.clone().collect::<Vec<_>>().join(", ")
                        ));
                if let Some(close) = did_you_mean(name, names) {
                    diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
                }
                self.errors.push(diagnostic);
                ok = false;
                continue;
            };
            let variable = table.variable(var);
            match variable.value(value) {
                Some(v) => out.push((var, v)),
                None => {
                    let after = name_span.end - self.start;
                    let span = self.find(value, after).unwrap_or(name_span);
                    self.errors.push(
                        Diagnostic::new(format!("`{value}` is not a value of `{name}`"), span)
                            .expected(format!("one of: {}", variable.values().join(", "))),
                    );
                    ok = false;
                }
            }
        }
        ok.then_some(out)
    }
}

/// Replays a log: the initial belief from the first record, then one update per later record.
/// Returns one [`Update`] per record.
pub fn replay(
    plant: &Plant,
    theory: &mut Theory,
    estimator: &mut dyn ModeEstimator,
    records: &[LogRecord],
) -> Result<Vec<Update>, EstimationError> {
    let mut updates = Vec::with_capacity(records.len());
    replay_with(plant, theory, estimator, records, &mut |_, update, _| {
        updates.push(update.clone());
    })?;
    Ok(updates)
}

/// Replays a log as [`replay`] does, handing each record's index, its update and the wall time
/// the estimator took for it to `visit` instead of keeping them (`kairos bench`: a long log in
/// constant memory).
pub fn replay_with(
    plant: &Plant,
    theory: &mut Theory,
    estimator: &mut dyn ModeEstimator,
    records: &[LogRecord],
    visit: &mut dyn FnMut(usize, &Update, Duration),
) -> Result<(), EstimationError> {
    let Some(first) = records.first() else {
        return Ok(());
    };
    let started = Instant::now();
    let mut last = estimator.initial(plant, theory, first.time, &first.observation)?;
    visit(0, &last, started.elapsed());
    for (index, pair) in records.windows(2).enumerate() {
        let (before, now) = (&pair[0], &pair[1]);
        let started = Instant::now();
        last = estimator.update(
            plant,
            theory,
            &last.belief,
            &before.commands,
            &now.observation,
            now.time,
        )?;
        visit(index + 1, &last, started.elapsed());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::reference;

    /// `docs/reference/estimation-log.md` lists every field a log line accepts, and no other.
    #[test]
    fn the_reference_documents_every_field() {
        let mut tracer = reference::tracer();
        reference::add::<RecordLine>(&mut tracer);
        reference::assert_documented(
            &reference::registry(tracer),
            &[("RecordLine", "estimation-log.md", "The format")],
        );
    }
}
