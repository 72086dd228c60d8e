//! The interactive run report of `kairos run SCENARIO --report run.html`: one
//! self-contained HTML file — no network, no server, the style sheet and a small hand-written
//! script inline — to step through a run the way PLEXIL's viewer steps through a plan and
//! Helios shows a plant's live estimate (thesis §8.1).
//!
//! The page holds:
//! - the run's [`timeline`] (the same SVG as `--timeline`), zoomable (wheel)
//!   and pannable (drag), with a cursor on the current cycle (click to move it);
//! - for the current cycle: the belief (the tracked plant states, most likely first, each with
//!   the modes where it differs from the most likely; and per-component marginals over the
//!   tracked states), the configuration goals and the program's marking, the command and why,
//!   the events and the scripted plant's rules;
//! - a plant schematic: the components and their interconnections (the plant's connections),
//!   each coloured by its estimated mode with the timeline's colours (fault modes red).
//!
//! Keys: `→`/`n` next cycle with an event, `←`/`p` the previous one, `↓`/`j` next cycle,
//! `↑`/`k` previous cycle, `f` next diagnosis, `Home`/`End`. The URL fragment `#keys=f,n` plays
//! keys on load (`#cycle=N` goes to a cycle), so a report can be opened at the moment of
//! interest — and tested in a headless browser.
//!
//! The page's own elements have ids starting `r-` and the schematic's `schematic-`: an inline
//! SVG shares the document's ids and style sheet, and the timeline already uses plain ones.
//!
//! The data is the changes-only trace of every cycle ([`Trace::changes`]: a field appears when
//! it changed) without the phase times, plus the goals and marking when they changed, and each
//! cycle's x on the timeline. The page rebuilds every cycle's state from it on load.

mod schematic;

use serde_json::{Map, Value, json};

use super::timeline::{self, InjectedFault, TimelineInput};
use super::trace::Trace;
use crate::simulation::{CycleRecord, RunOutcome, Scenario};

/// The page's style sheet.
const STYLE: &str = include_str!("html/report.css");
/// The page's script.
const SCRIPT: &str = include_str!("html/report.js");

/// Collects what the report shows, cycle by cycle, during a run.
#[derive(Default)]
pub struct Recorder {
    trace: Trace,
    goals: Option<Vec<String>>,
    marking: Option<Vec<String>>,
    cycles: Vec<Value>,
    times: Vec<f64>,
}

impl Recorder {
    /// An empty recorder.
    pub fn new() -> Recorder {
        Recorder {
            trace: Trace::changes(),
            ..Recorder::default()
        }
    }

    /// Records one cycle of a run of `scenario`.
    pub fn cycle(&mut self, scenario: &Scenario, record: &CycleRecord<'_>) {
        let line = self.trace.line(scenario, record);
        let mut fields: Map<String, Value> = serde_json::from_str(&line).unwrap_or_default();
        // Wall times differ from run to run and are not what a reader steps through.
        fields.remove("micros");
        let goals = goals(scenario, record);
        if self.goals.as_ref() != Some(&goals) {
            fields.insert("goals".into(), json!(goals));
            self.goals = Some(goals);
        }
        let marking = marking(scenario, record);
        if self.marking.as_ref() != Some(&marking) {
            fields.insert("marking".into(), json!(marking));
            self.marking = Some(marking);
        }
        self.cycles.push(Value::Object(fields));
        self.times.push(record.step.time);
    }

    /// The report of the finished run: the HTML document.
    pub fn page(
        &self,
        scenario: &Scenario,
        outcome: &RunOutcome,
        injected: &[InjectedFault],
    ) -> String {
        let input = TimelineInput::of_run(scenario, outcome, injected);
        let svg = timeline::render(&input);
        let xs = timeline::positions(&input, &self.times);
        let data = json!({
            "title": scenario.name,
            "components": schematic::components(&scenario.plant),
            "cycles": self.cycles,
            "x": xs.iter().map(|x| (x * 10.0).round() / 10.0).collect::<Vec<f64>>(),
            "verdicts": outcome.verdicts.iter().map(|v| json!({
                "label": v.label,
                "holds": v.holds(),
            })).collect::<Vec<Value>>(),
        });
        let title = escape(&scenario.name);
        let schematic = schematic::svg(&scenario.plant);
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <title>{title} — kairos run report</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n\
             <header><h1>{title}</h1><p id=\"help\">Keys: → / n next event · ← / p previous event · \
             ↓ / j next cycle · ↑ / k previous cycle · f next diagnosis · Home / End. \
             Timeline: wheel to zoom, drag to pan, click to go to a cycle, double-click to reset.</p></header>\n\
             <section id=\"timeline\">{svg}</section>\n<main>\n\
             <section id=\"now\"><h2 id=\"r-cycle\"></h2><div id=\"r-verdicts\"></div></section>\n\
             <section id=\"schematic\"><h2>Plant (estimated modes)</h2>{schematic}</section>\n\
             <section id=\"happened\"><h2>Events</h2><ul id=\"r-events\"></ul><h3>Plant (script)</h3><ul id=\"r-plant\"></ul><h3>Observation</h3><ul id=\"r-observation\"></ul></section>\n\
             <section id=\"command\"><h2>Command and why</h2><ul id=\"r-commands\"></ul></section>\n\
             <section id=\"belief\"><h2>Belief</h2><table id=\"r-states\"></table><h3>Marginals over the tracked states</h3><table id=\"r-marginals\"></table></section>\n\
             <section id=\"program\"><h2>Goals</h2><ul id=\"r-goals\"></ul><h3>Marking</h3><ul id=\"r-marking\"></ul></section>\n\
             </main>\n<script type=\"application/json\" id=\"r-data\">{data}</script>\n<script>\n{SCRIPT}</script>\n</body>\n</html>\n",
            data = script_safe(&data.to_string()),
        )
    }
}

/// The configuration goals of the cycle, as `formula (line L)` for an RMPL program (a
/// mission's goals are named by their formula alone: its XGoals merge several written goals).
fn goals(scenario: &Scenario, record: &CycleRecord<'_>) -> Vec<String> {
    let Some(goal) = &record.step.goal else {
        return Vec::new();
    };
    goal.conjuncts
        .iter()
        .map(|c| match scenario.program.thca() {
            Some(program) => {
                let (line, _) = program.source().line_col(c.span.start);
                format!("{} (line {line})", c.formula.display(program.table()))
            }
            None => c.formula.display(scenario.plant.table()).to_string(),
        })
        .collect()
}

/// The marked program locations, as `location N (line L)` (none for a mission).
fn marking(scenario: &Scenario, record: &CycleRecord<'_>) -> Vec<String> {
    let Some(program) = scenario.program.thca() else {
        return Vec::new();
    };
    record
        .step
        .marking
        .iter()
        .filter(|&&id| id.index() < program.locations().len())
        .map(|&id| {
            let (line, _) = program.position(id);
            format!("location {} (line {line})", id.number())
        })
        .collect()
}

/// Text made safe inside HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// JSON made safe inside a `<script>` element: `</` cannot end it early (`<\/` is the same
/// JSON string).
fn script_safe(json: &str) -> String {
    json.replace("</", "<\\/")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_and_data_cannot_break_out_of_the_page() {
        assert_eq!(escape("a<b>&\"c\""), "a&lt;b&gt;&amp;&quot;c&quot;");
        let data = json!({"text": "</script><script>alert(1)"}).to_string();
        let safe = script_safe(&data);
        assert!(!safe.contains("</"));
        let back: Value = serde_json::from_str(&safe).expect("still JSON");
        assert_eq!(back["text"], "</script><script>alert(1)");
    }
}
