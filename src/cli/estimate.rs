//! `kairos estimate --plant MODEL --log LOG [--kappa K] [--exact] [--top N] [--json]`: replay a
//! command/observation log (format: `kairos::estimation::log`) through mode estimation and print,
//! per cycle, the most likely plant states with their probabilities.

use std::path::Path;

use kairos::estimation::log::{LogRecord, parse_log, replay};
use kairos::estimation::{
    BeliefUpdate, EstimationEvent, Fallback, ModeEstimator, TimedMe, TimedMeOptions, Update,
};
use kairos::logic::{ValueId, VarId};
use kairos::plant::{Plant, describe_modes};
use serde_json::{Map, Value, json};

use super::load_plant;
use super::output::emit;
use super::{Failure, read_source};

/// What to replay and how to show it.
pub struct EstimateArgs<'a> {
    /// The plant model.
    pub plant: &'a Path,
    /// The log (JSON lines).
    pub log: &'a Path,
    /// κ for TimedME.
    pub kappa: usize,
    /// Use the exact update instead of TimedME.
    pub exact: bool,
    /// Plant states to show per cycle.
    pub top: usize,
    /// JSON lines instead of text.
    pub json: bool,
}

/// Replays the log and prints the estimates.
pub fn run(args: &EstimateArgs) -> Result<(), Failure> {
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
        let options = TimedMeOptions::kappa(args.kappa);
        (
            Box::new(TimedMe::new(options)),
            format!("TimedME, κ = {}", options.kappa),
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
    for (record, update) in records.iter().zip(&updates) {
        let text = if args.json {
            format!("{}\n", as_json(&plant, record, update, args.top))
        } else {
            as_text(&plant, record, update, args.top)
        };
        if !emit(&text)? {
            break;
        }
    }
    Ok(())
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
                Fallback::UnconstrainedFaults => "fell back to unconstrained fault modes",
                Fallback::PreviousBelief => "kept the previous belief",
            }
        ),
        EstimationEvent::SearchCut(cut) => {
            format!("search cut by its {cut:?} budget: the best states found so far")
        }
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
                .zip(&estimate.modes)
                .map(|(c, &m)| (c.mode_var(), m));
            json!({ "probability": estimate.probability, "modes": object(plant, modes) })
        })
        .collect();
    json!({
        "time": record.time,
        "observations": object(plant, record.observation.values().iter().copied()),
        "estimates": estimates,
        "events": update.events.iter().map(event_text).collect::<Vec<_>>(),
        "commands": object(plant, record.commands.issued(plant)),
        "system_states": update.stats.states,
        "sat_calls": update.stats.sat_calls,
    })
}
