//! Counterexamples as scenarios: the same scenario with the path's firings and landing delays
//! pinned by `choose` and its delivery orders by `deliver`, which `kairos run` follows (an
//! optional rule fires in a run only where `choose` pins it).

use super::{Counterexample, Finding};
use crate::simulation::Scenario;

/// The scenario with the counterexample's firings pinned: a run of it follows the path.
pub fn replay_scenario(scenario: &Scenario, counterexample: &Counterexample) -> Scenario {
    let mut replay = scenario.clone();
    replay.script.pinned = pins(scenario, counterexample).collect();
    replay.script.deliveries = (counterexample.deliveries.iter())
        .map(|d| (d.cycle as f64 * scenario.cycle, d.order.clone()))
        .collect();
    replay
}

/// What `choose` pins: each optional rule's firing time, each interval's delay.
fn pins<'c>(
    scenario: &Scenario,
    counterexample: &'c Counterexample,
) -> impl Iterator<Item = (usize, f64)> + 'c {
    let period = scenario.cycle;
    let fired = (counterexample.choices.iter()).map(move |c| (c.rule, c.cycle as f64 * period));
    let landed = (counterexample.landings.iter())
        .map(move |l| (l.rule, (l.lands - l.fired) as f64 * period));
    fired.chain(landed)
}

/// The scenario file's text with a `choose` field pinning the counterexample's firings and
/// landing delays and a `deliver` field pinning its delivery orders (each when it has some),
/// added right after `Scenario(` (on the first line that starts with it), and a comment saying
/// what the path shows. `None` when no line starts with `Scenario(`. The file's relative paths are
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
    let pins: Vec<String> = pins(scenario, counterexample)
        .map(|(rule, at)| format!("{}: {at:?}", ron_string(&rules[rule].name)))
        .collect();
    let deliver: Vec<String> = (counterexample.deliveries.iter())
        .map(|d| {
            let names: Vec<String> = d
                .order
                .iter()
                .map(|&r| ron_string(&rules[r].name))
                .collect();
            let at = d.cycle as f64 * scenario.cycle;
            format!("(at: {at:?}, order: [{}])", names.join(", "))
        })
        .collect();
    let shows = match &counterexample.finding {
        Finding::Violated { label, reason, .. } => format!("`{label}` fails: {reason}"),
        Finding::Error(message) => format!("the run stops: {message}"),
    };
    let mut inserted = format!(
        "\n    // A counterexample found by `kairos explore`: {}",
        shows.replace('\n', " ")
    );
    if !pins.is_empty() {
        inserted.push_str(&format!("\n    choose: {{ {} }},", pins.join(", ")));
    }
    if !deliver.is_empty() {
        inserted.push_str(&format!("\n    deliver: [{}],", deliver.join(", ")));
    }
    let mut replay = text.clone();
    replay.insert_str(at, &inserted);
    Some(replay)
}

/// A RON string literal.
fn ron_string(text: &str) -> String {
    let escaped = text.replace('\\', "\\\\").replace('"', "\\\"");
    format!("\"{escaped}\"")
}
