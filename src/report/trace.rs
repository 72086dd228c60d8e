//! The JSON-lines trace of `kairos run --trace FILE` (DESIGN.md §12): one object per cycle, every
//! cycle, for tools. Reference for users: `docs/reference/trace.md`.
//!
//! By default a line holds only what changed (a long run's trace stays small — a quiet
//! cycle is its number, time and phase times, about 100 bytes): `observation`, `estimate` and
//! `belief` appear on the first line and then only when they differ from the last line that had
//! them (the belief: other tracked states, another order, or a probability that moved by
//! [`BELIEF_RESOLUTION`] or more since it was written); `command`, `events` and `plant` only when
//! the cycle has some. An absent field therefore
//! means "as before" (or "none this cycle" for the last three). `kairos run --trace-full` writes
//! every field on every line ([`Trace::full`]). Fields:
//!
//! - `cycle`, `time`: the cycle number (from 0) and its time in seconds;
//! - `observation`: what the plant reported, `[{"variable": .., "value": ..}]`, verbatim (a
//!   numeric observable's reading as a number);
//! - `monitored`: what the plant model's monitors made of the readings, the value estimation read
//!   for each numeric observable (`null`: none, or stale), `{"sensor.reading": "warm", ..}`;
//!   only for a plant with monitors, written like `estimate`;
//! - `command`: μ, the non-idle control assignments, as `"PDE.cmd = on"`;
//! - `estimate`: ŝ, the most likely mode of each component, `{"engine": "heating", ..}`;
//! - `belief`: the tracked plant states, most likely first, `[{"p": .., "modes": {..}}]`;
//! - `distance_bound`: an upper bound on the total-variation distance between the belief and
//!   the exact update's (`estimation::Belief::distance_bound`), written like `belief` (on the
//!   first line, then when it moved by [`DISTANCE_RESOLUTION`] or more);
//! - `events`: the executive's events, `[{"kind": "Diagnosis", "text": "PDE = resettable (p 0.91);
//!   evidence: PDE.status = fault; next: PDE = on (p 0.09)", "next": [{"mode": "on", "p": 0.09}],
//!   "evidence": ["PDE.status = fault"]}]` (kinds as `simulation::EventName` spells them; text
//!   as the mission log shows it; `next`, a diagnosis's other candidate modes of the component,
//!   and `evidence`, the observations the previous most likely state stepped by the last
//!   command cannot explain (one entry `a = x & b = y` for a set discrepant only together),
//!   only on a `Diagnosis`; `condition` and `entailed`, the condition
//!   whose entailment preempted and whether it became entailed (`do … watching`) or is not
//!   entailed (`maintaining`), only on a `Preempted`);
//! - `plant`: the scripted plant's rules that fired or took effect, `[{"rule": .., "kind":
//!   "fired" | "applied", "fault": bool}]`;
//! - `micros`: wall time of estimation, the sequencer, reconfiguration and the whole cycle.

use std::borrow::Borrow;

use serde::Serialize;

use crate::executive::describe_event;
use crate::executive::{EventKind, NamedValue};
use crate::simulation::{CycleRecord, EventName, PlantEventKind, Scenario};

#[derive(Serialize)]
struct Line<'a> {
    cycle: u64,
    time: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    observation: Option<&'a [NamedValue]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    monitored: Option<Modes>,
    #[serde(skip_serializing_if = "Option::is_none")]
    command: Option<Vec<String>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    estimate: Option<Modes>,
    #[serde(skip_serializing_if = "Option::is_none")]
    belief: Option<Vec<Belief>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    distance_bound: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    events: Option<Vec<TraceEvent>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    plant: Option<Vec<PlantLine<'a>>>,
    micros: Micros,
}

type Modes = serde_json::Map<String, serde_json::Value>;

#[derive(Serialize, Clone, PartialEq)]
struct Belief {
    p: f64,
    modes: serde_json::Map<String, serde_json::Value>,
}

#[derive(Serialize)]
struct TraceEvent {
    kind: String,
    text: String,
    /// A diagnosis's next candidates, structured for tools (the text has them too).
    #[serde(skip_serializing_if = "Option::is_none")]
    next: Option<Vec<Candidate>>,
    /// A diagnosis's evidence, `variable = value` each, or `a = x & b = y` for a set
    /// discrepant only together (the text has it too).
    #[serde(skip_serializing_if = "Option::is_none")]
    evidence: Option<Vec<String>>,
    /// A preemption's condition, rendered from its formula (the text quotes the program).
    #[serde(skip_serializing_if = "Option::is_none")]
    condition: Option<String>,
    /// Whether that condition became entailed (`do … watching`) or is not entailed
    /// (`maintaining`).
    #[serde(skip_serializing_if = "Option::is_none")]
    entailed: Option<bool>,
}

/// Another mode of a diagnosed component with its marginal.
#[derive(Serialize)]
struct Candidate {
    mode: String,
    p: f64,
}

impl TraceEvent {
    fn new(scenario: &Scenario, kind: &EventKind) -> TraceEvent {
        let (next, evidence) = match kind {
            EventKind::Diagnosis { next, evidence, .. } => (
                Some(
                    next.iter()
                        .map(|(mode, p)| Candidate {
                            mode: mode.clone(),
                            p: *p,
                        })
                        .collect(),
                ),
                Some(evidence.clone()),
            ),
            _ => (None, None),
        };
        let (condition, entailed) = match kind {
            EventKind::Preempted {
                condition,
                entailed,
                ..
            } => (Some(condition.clone()), Some(*entailed)),
            _ => (None, None),
        };
        TraceEvent {
            kind: format!("{:?}", EventName::of(kind)),
            text: describe_event(&scenario.plant, &scenario.program_source, kind).1,
            next,
            evidence,
            condition,
            entailed,
        }
    }
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

/// Writes trace lines, remembering what the last lines said so that unchanged fields can be
/// left out (see the module documentation).
#[derive(Default)]
pub struct Trace {
    full: bool,
    observation: Option<Vec<NamedValue>>,
    monitored: Option<Modes>,
    estimate: Option<Modes>,
    belief: Option<Vec<Belief>>,
    distance_bound: Option<f64>,
}

impl Trace {
    /// A trace that writes only what changed.
    pub fn changes() -> Trace {
        Trace::default()
    }

    /// A trace that writes every field on every line.
    pub fn full() -> Trace {
        Trace {
            full: true,
            ..Trace::default()
        }
    }

    /// The trace line (JSON, without the newline) of one cycle of `scenario`.
    pub fn line(&mut self, scenario: &Scenario, record: &CycleRecord<'_>) -> String {
        let all = line(scenario, record);
        let full = self.full;
        let some = |v: &Vec<_>| full || !v.is_empty();
        let line = Line {
            observation: all
                .observation
                .filter(|o| !repeats(full, &mut self.observation, *o, |a, b| a == b)),
            monitored: all
                .monitored
                .filter(|m| !repeats(full, &mut self.monitored, m, |a, b| a == b)),
            estimate: all
                .estimate
                .filter(|e| !repeats(full, &mut self.estimate, e, |a, b| a == b)),
            belief: all
                .belief
                .filter(|b| !repeats(full, &mut self.belief, b.as_slice(), same_belief)),
            distance_bound: all.distance_bound.filter(|d| {
                !repeats(full, &mut self.distance_bound, d, |a, b| {
                    (a - b).abs() < DISTANCE_RESOLUTION
                })
            }),
            command: all.command.filter(some),
            events: all.events.filter(|v| full || !v.is_empty()),
            plant: all.plant.filter(|v| full || !v.is_empty()),
            ..all
        };
        // Every field is a string, a number or a map with string keys: serialisation cannot
        // fail, but a trace line is not worth a panic either.
        serde_json::to_string(&line).unwrap_or_else(|e| format!("{{\"error\":\"{e}\"}}"))
    }
}

/// True when a changes-only trace has already said `value` (`last` holds something `same` to
/// it); otherwise `last` takes it and the line must say it.
fn repeats<B>(
    full: bool,
    last: &mut Option<B::Owned>,
    value: &B,
    same: impl Fn(&B, &B) -> bool,
) -> bool
where
    B: ?Sized + ToOwned,
{
    if !full && last.as_ref().is_some_and(|l| same(l.borrow(), value)) {
        return true;
    }
    *last = Some(value.to_owned());
    false
}

/// How far a tracked state's probability may drift before a changes-only trace says the belief
/// again: fault hazards move the tail of the belief a little every cycle, which is not news.
pub const BELIEF_RESOLUTION: f64 = 1e-3;

/// How far the distance bound may move before a changes-only trace says it again: it grows a
/// little with every truncation, and a bound is worth reading to a hundredth.
pub const DISTANCE_RESOLUTION: f64 = 1e-2;

/// The same tracked plant states in the same order, each probability within
/// [`BELIEF_RESOLUTION`] of what was last written.
fn same_belief(last: &[Belief], now: &[Belief]) -> bool {
    last.len() == now.len()
        && last
            .iter()
            .zip(now)
            .all(|(a, b)| a.modes == b.modes && (a.p - b.p).abs() < BELIEF_RESOLUTION)
}

/// Every field of one cycle's line.
fn line<'a>(scenario: &'a Scenario, record: &CycleRecord<'a>) -> Line<'a> {
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
    Line {
        cycle: step.cycle,
        time: step.time,
        observation: Some(record.observation),
        monitored: (!step.monitored.is_empty()).then(|| {
            let table = plant.table();
            (step.monitored.iter())
                .map(|&(x, v)| {
                    let variable = table.variable(x);
                    let value = v.map(|v| variable.value_name(v).into());
                    (variable.name().to_string(), value.unwrap_or_default())
                })
                .collect()
        }),
        command: Some(
            step.command
                .iter()
                .map(|&(x, v)| plant.table().assignment(x, v).to_string())
                .collect(),
        ),
        estimate: Some(modes(&step.most_likely)),
        belief: Some(
            step.estimates
                .iter()
                .map(|e| Belief {
                    p: e.probability,
                    modes: modes(&e.modes),
                })
                .collect(),
        ),
        distance_bound: Some(step.distance_bound),
        events: Some(
            step.events
                .iter()
                .map(|e| TraceEvent::new(scenario, &e.kind))
                .collect(),
        ),
        plant: Some(
            record
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
        ),
        micros: Micros {
            estimation: step.times.estimation.as_micros(),
            sequencer: step.times.sequencer.as_micros(),
            reconfiguration: step.times.reconfiguration.as_micros(),
            total: step.times.total.as_micros(),
        },
    }
}
