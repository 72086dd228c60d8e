//! Counterexamples as scenarios: the same scenario with the path's firings pinned by `choose`,
//! which `kairos run` follows (an optional rule fires in a run only where `choose` pins it).

use super::{Counterexample, Finding};
use crate::simulation::Scenario;

/// The scenario with the counterexample's firings pinned: a run of it follows the path.
pub fn replay_scenario(scenario: &Scenario, counterexample: &Counterexample) -> Scenario {
    let mut replay = scenario.clone();
    replay.script.pinned = (counterexample.choices.iter())
        .map(|choice| (choice.rule, choice.cycle as f64 * scenario.cycle))
        .collect();
    replay
}

/// The scenario file's text with a `choose` field pinning the counterexample's firings, added
/// right after `Scenario(` (on the first line that starts with it), and a comment saying what
/// the path shows. `None` when no line starts with `Scenario(`. The file's relative paths are
/// relative to the scenario's directory: the replay belongs beside it.
pub fn replay_text(scenario: &Scenario, counterexample: &Counterexample) -> Option<String> {
    let text = &scenario.source.text;
    let mut offset = 0;
    let at = text.split_inclusive('\n').find_map(|line| {
        let start = offset;
        offset += line.len();
        let indent = line.len() - line.trim_start().len();
        line.trim_start()
            .starts_with("Scenario(")
            .then_some(start + indent + "Scenario(".len())
    })?;
    let rules = scenario.script.rules();
    let pins: Vec<String> = (counterexample.choices.iter())
        .map(|choice| {
            let time = choice.cycle as f64 * scenario.cycle;
            format!("{}: {time:?}", ron_string(&rules[choice.rule].name))
        })
        .collect();
    let shows = match &counterexample.finding {
        Finding::Violated { label, reason, .. } => format!("`{label}` fails: {reason}"),
        Finding::Error(message) => format!("the run stops: {message}"),
    };
    let inserted = format!(
        "\n    // A counterexample found by `kairos explore`: {}\n    choose: {{ {} }},",
        shows.replace('\n', " "),
        pins.join(", ")
    );
    let mut replay = text.clone();
    replay.insert_str(at, &inserted);
    Some(replay)
}

/// A RON string literal.
fn ron_string(text: &str) -> String {
    let escaped = text.replace('\\', "\\\\").replace('"', "\\\"");
    format!("\"{escaped}\"")
}
