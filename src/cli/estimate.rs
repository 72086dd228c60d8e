//! `kairos estimate --plant MODEL --log LOG [--kappa K] [--history N] [--rerun doubt|surprise]
//! [--exact] [--top N] [--json] [--full]`:
//! replay a command/observation log (format: `kairos::estimation::log`) through mode estimation
//! and print, per cycle, the most likely plant states with their probabilities. Without
//! `--full`, a cycle is printed only when something changed — its observation, a command before
//! or after it, an estimation event, or the top states (another state, another order, or a
//! probability moved by 0.001 or more since last printed) — and the first and last cycles; the
//! text says how many cycles it left out.

use std::path::Path;

use kairos::estimation::PlantEstimate;
use kairos::estimation::log::{LogRecord, parse_log, replay};
use kairos::estimation::{BeliefUpdate, EstimationEvent, Fallback, ModeEstimator, TimedMe, Update};
use kairos::logic::{ValueId, VarId};
use kairos::plant::monitor::MonitorEvent;
use kairos::plant::{Plant, describe_modes};
use kairos::report::trace::BELIEF_RESOLUTION;
use serde_json::{Map, Value, json};

use super::load_plant;
use super::output::emit;
use super::window_args::{WindowArgs, describe};
use super::{Failure, read_source};

/// What to replay and how to show it.
pub struct EstimateArgs<'a> {
    /// The plant model.
    pub plant: &'a Path,
    /// The log (JSON lines).
    pub log: &'a Path,
    /// κ for TimedME.
    pub kappa: usize,
    /// TimedME's history window.
    pub window: WindowArgs,
    /// Use the exact update instead of TimedME.
    pub exact: bool,
    /// Plant states to show per cycle.
    pub top: usize,
    /// JSON lines instead of text.
    pub json: bool,
    /// Every cycle, not only those where something changed.
    pub full: bool,
}

/// Replays the log and prints the estimates.
pub fn run(args: &EstimateArgs) -> Result<(), Failure> {
    if args.exact && args.window.given() {
        return Err(Failure::bad_input(
            "error: --history and --rerun set TimedME's history window; the exact update \
             (--exact) has none",
        ));
    }
    let plant = load_plant(args.plant)?;
    let source = read_source(args.log)?;
    let records = parse_log(&source, &plant).map_err(Failure::bad_input)?;
    super::announce_large_plant(
        args.plant,
        &plant,
        &format!(
            "estimation ({} cycles, each an OPSAT search over the whole plant)",
            records.len()
        ),
        false,
    );
    let mut theory = plant
        .theory()
        .map_err(|e| Failure::bad_input(format!("error: {e}")))?;
    let (mut estimator, label): (Box<dyn ModeEstimator>, String) = if args.exact {
        (Box::new(BeliefUpdate::new()), "exact belief update".into())
    } else {
        let options = args.window.options(args.kappa);
        (
            Box::new(TimedMe::new(options)),
            format!("TimedME, {}", describe(&options)),
        )
    };
    let updates =
        replay(&plant, &mut theory, estimator.as_mut(), &records).map_err(|e| Failure {
            code: 1,
            message: format!("error: estimation stopped: {e}"),
        })?;
    if !args.json {
        let title = format!(
            "plant `{}`, {label}, {} cycles from {}\n",
            plant.name(),
            records.len(),
            args.log.display()
        );
        if !emit(&title)? {
            return Ok(());
        }
    }
    let mut shown: Option<Vec<PlantEstimate>> = None;
    let mut skipped: Vec<f64> = Vec::new();
    for (i, (record, update)) in records.iter().zip(&updates).enumerate() {
        let top: Vec<PlantEstimate> = update
            .belief
            .plant_states()
            .into_iter()
            .take(args.top)
            .collect();
        let news = args.full
            || i == 0
            || i + 1 == records.len()
            || !update.events.is_empty()
            || !record.monitored.is_empty()
            || record.commands.issued(&plant).next().is_some()
            || records[i - 1].commands.issued(&plant).next().is_some()
            || records[i - 1].observation != record.observation
            || !shown.as_deref().is_some_and(|s| same_estimates(s, &top));
        if !news {
            skipped.push(record.time);
            continue;
        }
        let mut text = String::new();
        if let (Some(first), Some(last), false) = (skipped.first(), skipped.last(), args.json) {
            text += &format!(
                "  ... {} cycle{} without change (t = {first:.3} to {last:.3} s)\n",
                skipped.len(),
                if skipped.len() == 1 { "" } else { "s" }
            );
        }
        skipped.clear();
        text += &if args.json {
            format!("{}\n", as_json(&plant, record, update, args.top))
        } else {
            as_text(&plant, record, update, args.top)
        };
        shown = Some(top);
        if !emit(&text)? {
            break;
        }
    }
    Ok(())
}

/// The same plant states in the same order, each probability within the trace's resolution
/// (`report::trace::BELIEF_RESOLUTION`) of what was last shown: nothing worth a line.
fn same_estimates(last: &[PlantEstimate], now: &[PlantEstimate]) -> bool {
    last.len() == now.len()
        && last.iter().zip(now).all(|(a, b)| {
            a.modes == b.modes && (a.probability - b.probability).abs() < BELIEF_RESOLUTION
        })
}

fn assignments(plant: &Plant, values: impl IntoIterator<Item = (VarId, ValueId)>) -> String {
    let shown: Vec<String> = values
        .into_iter()
        .map(|(x, v)| plant.table().assignment(x, v).to_string())
        .collect();
    if shown.is_empty() {
        "nothing".to_string()
    } else {
        shown.join(", ")
    }
}

fn event_text(event: &EstimationEvent) -> String {
    match event {
        EstimationEvent::InconsistentObservation { fallback } => format!(
            "no tracked state explains the observation: {}",
            match fallback {
                Fallback::Reestimated { steps } =>
                    format!("estimated the last {steps} steps again, tracking more states"),
                Fallback::UnconstrainedFaults =>
                    "fell back to unconstrained fault modes".to_string(),
                Fallback::PreviousBelief => "kept the previous belief".to_string(),
            }
        ),
        EstimationEvent::SearchCut(cut) => {
            format!("search cut by its {cut:?} budget: the best states found so far")
        }
    }
}

/// What a numeric observable's monitor did: `bus.voltage = 26.2 V -> low (was nominal)`.
fn monitor_text(plant: &Plant, var: VarId, event: &MonitorEvent) -> String {
    let variable = plant.table().variable(var);
    let unit = (plant.monitor_of(var)).map_or("", |m| plant.monitors()[m].unit.as_str());
    match *event {
        MonitorEvent::Changed { reading, from, to } => format!(
            "{} = {reading} {unit} -> {}{}",
            variable.name(),
            variable.value_name(to),
            from.map_or(String::new(), |v| format!(
                " (was {})",
                variable.value_name(v)
            ))
        ),
        MonitorEvent::OutOfRange { reading } => format!(
            "{} = {reading} {unit}: outside the valid range, set aside",
            variable.name()
        ),
        MonitorEvent::Stale { last } => format!(
            "{}: no reading since {last:.3} s: unknown until the next",
            variable.name()
        ),
    }
}

fn as_text(plant: &Plant, record: &LogRecord, update: &Update, top: usize) -> String {
    let mut out = format!(
        "t = {:.3} s  observed {}\n",
        record.time,
        assignments(plant, record.observation.values().iter().copied())
    );
    for estimate in update.belief.plant_states().iter().take(top) {
        out += &format!(
            "    {:.6}  {}\n",
            estimate.probability,
            describe_modes(plant, &estimate.modes)
        );
    }
    for (var, event) in &record.monitored {
        out += &format!("  ~ {}\n", monitor_text(plant, *var, event));
    }
    for event in &update.events {
        out += &format!("  ! {}\n", event_text(event));
    }
    let issued: Vec<(VarId, ValueId)> = record.commands.issued(plant).collect();
    if !issued.is_empty() {
        out += &format!("  > commanded {}\n", assignments(plant, issued));
    }
    out
}

fn object(plant: &Plant, values: impl IntoIterator<Item = (VarId, ValueId)>) -> Map<String, Value> {
    values
        .into_iter()
        .map(|(x, v)| {
            let variable = plant.table().variable(x);
            (variable.name().to_string(), json!(variable.value_name(v)))
        })
        .collect()
}

fn as_json(plant: &Plant, record: &LogRecord, update: &Update, top: usize) -> Value {
    let estimates: Vec<Value> = update
        .belief
        .plant_states()
        .iter()
        .take(top)
        .map(|estimate| {
            let modes = plant
                .components()
                .iter()
                .zip(estimate.modes.iter())
                .map(|(c, &m)| (c.mode_var(), m));
            json!({ "probability": estimate.probability, "modes": object(plant, modes) })
        })
        .collect();
    json!({
        "time": record.time,
        "observations": object(plant, record.observation.values().iter().copied()),
        "estimates": estimates,
        "events": update.events.iter().map(event_text).collect::<Vec<_>>(),
        "monitored": (record.monitored.iter())
            .map(|(var, event)| monitor_text(plant, *var, event))
            .collect::<Vec<_>>(),
        "commands": object(plant, record.commands.issued(plant)),
        "system_states": update.stats.states,
        "sat_calls": update.stats.sat_calls,
        "discarded": update.stats.discarded,
        "distance_bound": update.belief.distance_bound(),
    })
}
