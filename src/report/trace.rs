//! The JSON-lines trace of `kairos run --trace FILE` (DESIGN.md §12): one object per cycle, every
//! cycle, for tools. Fields:
//!
//! - `cycle`, `time`: the cycle number (from 0) and its time in seconds;
//! - `observation`: what the plant reported, `[{"variable": .., "value": ..}]`, verbatim;
//! - `command`: μ, the non-idle control assignments, as `"PDE.cmd = on"`;
//! - `estimate`: ŝ, the most likely mode of each component, `{"engine": "heating", ..}`;
//! - `belief`: the tracked plant states, most likely first, `[{"p": .., "modes": {..}}]`;
//! - `events`: the executive's events, `[{"kind": "Diagnosis", "text": "PDE = resettable (p 0.91)"}]`
//!   (kinds as `simulation::EventName` spells them; text as the mission log shows it);
//! - `plant`: the scripted plant's rules that fired or took effect, `[{"rule": .., "kind":
//!   "fired" | "applied", "fault": bool}]`;
//! - `micros`: wall time of estimation, the sequencer, reconfiguration and the whole cycle.

use serde::Serialize;

use super::log::describe_event;
use crate::executive::NamedValue;
use crate::simulation::{CycleRecord, EventName, PlantEventKind, Scenario};

#[derive(Serialize)]
struct Line<'a> {
    cycle: u64,
    time: f64,
    observation: &'a [NamedValue],
    command: Vec<String>,
    estimate: serde_json::Map<String, serde_json::Value>,
    belief: Vec<Belief>,
    events: Vec<TraceEvent>,
    plant: Vec<PlantLine<'a>>,
    micros: Micros,
}

#[derive(Serialize)]
struct Belief {
    p: f64,
    modes: serde_json::Map<String, serde_json::Value>,
}

#[derive(Serialize)]
struct TraceEvent {
    kind: String,
    text: String,
}

#[derive(Serialize)]
struct PlantLine<'a> {
    rule: &'a str,
    kind: &'static str,
    fault: bool,
}

#[derive(Serialize)]
struct Micros {
    estimation: u128,
    sequencer: u128,
    reconfiguration: u128,
    total: u128,
}

/// The trace line (JSON, without the newline) of one cycle of `scenario`.
pub fn line(scenario: &Scenario, record: &CycleRecord<'_>) -> String {
    let plant = &scenario.plant;
    let step = record.step;
    let modes = |values: &[crate::logic::ValueId]| {
        plant
            .components()
            .iter()
            .zip(values)
            .map(|(c, &v)| (c.name().to_string(), c.mode(v).name.clone().into()))
            .collect()
    };
    let line = Line {
        cycle: step.cycle,
        time: step.time,
        observation: record.observation,
        command: step
            .command
            .iter()
            .map(|&(x, v)| plant.table().assignment(x, v).to_string())
            .collect(),
        estimate: modes(&step.most_likely),
        belief: step
            .estimates
            .iter()
            .map(|e| Belief {
                p: e.probability,
                modes: modes(&e.modes),
            })
            .collect(),
        events: step
            .events
            .iter()
            .map(|e| TraceEvent {
                kind: format!("{:?}", EventName::of(&e.kind)),
                text: describe_event(plant, &scenario.program_source, &e.kind).1,
            })
            .collect(),
        plant: record
            .plant_events
            .iter()
            .map(|e| {
                let rule = &scenario.script.rules()[e.rule];
                PlantLine {
                    rule: &rule.name,
                    kind: match e.kind {
                        PlantEventKind::Fired => "fired",
                        PlantEventKind::Applied => "applied",
                    },
                    fault: rule.fault,
                }
            })
            .collect(),
        micros: Micros {
            estimation: step.times.estimation.as_micros(),
            sequencer: step.times.sequencer.as_micros(),
            reconfiguration: step.times.reconfiguration.as_micros(),
            total: step.times.total.as_micros(),
        },
    };
    // Every field is a string, a number or a map with string keys: serialisation cannot fail,
    // but a trace line is not worth a panic either.
    serde_json::to_string(&line).unwrap_or_else(|e| format!("{{\"error\":\"{e}\"}}"))
}
