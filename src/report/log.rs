//! The mission log of `kairos run` (DESIGN.md §12: "output a person reads first: what the
//! executive believed, decided and did, with times"). One block per cycle in which something
//! notable happened — an event of the executive (§10) or a rule of the scripted plant — and
//! nothing for idle cycles; a summary and the expectations' verdicts at the end.
//!
//! Times are written twice, in seconds (as scenarios, missions and programs write them) and in
//! mission elapsed time `h:mm:ss.sss` (as a flight engineer reads a long run). The cycle header
//! gives each a fixed width — 10 characters for the seconds, 13 for the clock — which is the same
//! range, 999,999.999 s being 277:46:39.999, so the headers of any run shorter than eleven days
//! stay aligned.
//!
//! ```text
//! [    12.000 s   0:00:12.000] #12
//!   plant     rule `PDE latches up` takes effect: pde = latched  (FAULT)
//!   believed  PDE: on -> resettable (p 0.91)
//!   DIAGNOSIS PDE = resettable (p 0.91); evidence: PDE.status = fault; next: PDE = on (p 0.09)
//!   REPAIR    PDE.cmd = reset (PDE: resettable -> on) for engine = standby (programs/mars_edl.rmpl:20:3)
//! ```

use std::fmt::Write;

use crate::executive::{Event, EventKind, describe_event};
use crate::report::timeline::hours_minutes_seconds;
use crate::sequencer::LocationId;
use crate::simulation::{CycleRecord, Outcome, PlantEventKind, RunOutcome, Scenario, StopReason};

/// Which lines of the mission log to print (`kairos run --hide-plant --only … --from … --to …`).
/// The default shows everything. Filtering changes what is printed, never what is reported:
/// the summary, the verdicts and the trace are whole.
#[derive(Debug, Clone, PartialEq)]
pub struct LogFilter {
    /// Leave out the scripted plant's rule lines.
    pub hide_plant: bool,
    /// Only lines that concern one of these components (empty: all): a mode change or a
    /// diagnosis of it, or any other line that names it (a command to it, a goal on it, a rule
    /// setting one of its attributes).
    pub only: Vec<String>,
    /// Only cycles at or after this time, seconds.
    pub from: f64,
    /// Only cycles at or before this time, seconds.
    pub to: f64,
}

impl Default for LogFilter {
    fn default() -> Self {
        LogFilter {
            hide_plant: false,
            only: Vec::new(),
            from: f64::NEG_INFINITY,
            to: f64::INFINITY,
        }
    }
}

impl LogFilter {
    fn shows_time(&self, time: f64) -> bool {
        self.from <= time && time <= self.to
    }

    /// Whether a line of text names one of the components (as a whole word: `valve1` is not
    /// named by `valve10`; `engine.power` names `engine`).
    fn names_one(&self, text: &str) -> bool {
        self.only.is_empty() || self.only.iter().any(|name| names_word(text, name))
    }
}

fn names_word(text: &str, word: &str) -> bool {
    let part_of_name = |c: char| c.is_alphanumeric() || c == '_' || c == '-';
    text.match_indices(word).any(|(at, _)| {
        let before = text[..at].chars().next_back();
        let after = text[at + word.len()..].chars().next();
        !before.is_some_and(part_of_name) && !after.is_some_and(part_of_name)
    })
}

/// Writes the mission log of one scenario run.
pub struct MissionLog<'a> {
    scenario: &'a Scenario,
    filter: LogFilter,
    /// The locations whose goal was reported achieved in the last cycle: an `always` goal is
    /// achieved again every cycle it holds, which is not news (the trace keeps every report).
    achieved: Vec<LocationId>,
}

impl<'a> MissionLog<'a> {
    /// A log for `scenario`.
    pub fn new(scenario: &'a Scenario) -> Self {
        Self::filtered(scenario, LogFilter::default())
    }

    /// A log for `scenario` printing only what `filter` lets through.
    pub fn filtered(scenario: &'a Scenario, filter: LogFilter) -> Self {
        MissionLog {
            scenario,
            filter,
            achieved: Vec::new(),
        }
    }

    /// The heading: what runs, against what, how.
    pub fn header(&self) -> String {
        let s = self.scenario;
        let mut out = format!("scenario  {}\n", s.name);
        if !s.description.is_empty() {
            let _ = writeln!(out, "          {}", s.description.trim());
        }
        let _ = writeln!(
            out,
            "{}   {}{}\nplant     {} ({})\ncycle     {} s until {} s, κ = {}{}",
            if s.program.mission().is_some() {
                "mission"
            } else {
                "program"
            },
            s.program_source.name,
            s.entry
                .as_deref()
                .map(|e| format!(" ({e})"))
                .unwrap_or_default(),
            s.plant.name(),
            s.plant_path,
            s.cycle,
            s.end,
            s.kappa,
            s.deadline
                .map(|d| format!(", deadline {:.1} ms", d.as_secs_f64() * 1e3))
                .unwrap_or_default(),
        );
        out
    }

    /// The block of one cycle, or `None` when nothing notable happened in it.
    pub fn cycle(&mut self, record: &CycleRecord<'_>) -> Option<String> {
        let s = self.scenario;
        let step = record.step;
        let mut lines = String::new();
        for (k, event) in record.plant_events.iter().enumerate() {
            // A rule that fires and takes effect at once (its `Applied` follows its `Fired`) is
            // shown once, by its effect.
            let immediate = event.kind == PlantEventKind::Fired
                && record.plant_events.get(k + 1).is_some_and(|next| {
                    next.rule == event.rule && next.kind == PlantEventKind::Applied
                });
            if immediate {
                continue;
            }
            let rule = &s.script.rules()[event.rule];
            let what = match event.kind {
                PlantEventKind::Fired => format!("rule `{}` fired", rule.name),
                PlantEventKind::Applied => format!(
                    "rule `{}` takes effect: {}",
                    rule.name,
                    rule.effect.describe(s.script.variables())
                ),
            };
            let fault = if rule.fault { "  (FAULT)" } else { "" };
            if !self.filter.hide_plant && self.filter.names_one(&what) {
                let _ = writeln!(lines, "  {:<12} {what}{fault}", "plant");
            }
        }
        let mut achieved = Vec::new();
        for event in &step.events {
            if let EventKind::GoalAchieved { location, .. } = event.kind {
                achieved.push(location);
                if self.achieved.contains(&location) {
                    continue;
                }
            }
            if self.concerns_shown_components(&event.kind) {
                let _ = writeln!(lines, "  {}", self.event_line(event));
            }
        }
        self.achieved = achieved;
        let shown = !lines.is_empty() && self.filter.shows_time(step.time);
        shown.then(|| {
            format!(
                "[{:>10.3} s {:>13}] #{}\n{lines}",
                step.time,
                hours_minutes_seconds(step.time),
                step.cycle
            )
        })
    }

    /// `--only`: a mode change or diagnosis by its component, any other event by its text.
    fn concerns_shown_components(&self, kind: &EventKind) -> bool {
        let plant = &self.scenario.plant;
        match kind {
            _ if self.filter.only.is_empty() => true,
            EventKind::ModeChanged { component, .. } | EventKind::Diagnosis { component, .. } => {
                let name = plant.component(*component).name();
                self.filter.only.iter().any(|n| n == name)
            }
            other => {
                let (_, text) = describe_event(plant, &self.scenario.program_source, other);
                self.filter.names_one(&text)
            }
        }
    }

    fn event_line(&self, event: &Event) -> String {
        let s = self.scenario;
        let (tag, text) = describe_event(&s.plant, &s.program_source, &event.kind);
        format!("{tag:<12} {text}")
    }

    /// The summary: how the run ended, its timing, and every expectation's verdict.
    pub fn summary(&self, outcome: &RunOutcome) -> String {
        let stop = match outcome.stop {
            StopReason::EndTime => "the end time",
            StopReason::Settled => "nothing more could happen",
        };
        let mut out = format!(
            "\nrun ended at {:.3} s ({}) after {} cycles ({stop}); program {}\n",
            outcome.last_time,
            hours_minutes_seconds(outcome.last_time),
            outcome.cycles,
            if outcome.completed {
                "completed"
            } else {
                "not completed"
            }
        );
        let _ = writeln!(
            out,
            "wall time {:.1} ms, slowest cycle {:.2} ms, {} deadline overrun{}",
            outcome.wall.as_secs_f64() * 1e3,
            outcome.slowest_cycle.as_secs_f64() * 1e3,
            outcome.overruns,
            if outcome.overruns == 1 { "" } else { "s" }
        );
        let _ = writeln!(out, "\nexpectations");
        for verdict in &outcome.verdicts {
            match &verdict.outcome {
                Outcome::Met { at: Some(t) } => {
                    let _ = writeln!(
                        out,
                        "  ok     {} (at {t:.3} s, {})",
                        verdict.label,
                        hours_minutes_seconds(*t)
                    );
                }
                Outcome::Met { at: None } => {
                    let _ = writeln!(out, "  ok     {}", verdict.label);
                }
                Outcome::Failed { reason } => {
                    let _ = writeln!(out, "  FAILED {}: {reason}", verdict.label);
                }
            }
        }
        let failed = outcome.verdicts.iter().filter(|v| !v.holds()).count();
        if failed == 0 {
            let _ = writeln!(out, "\nPASS: {} expectations hold", outcome.verdicts.len());
        } else {
            let _ = writeln!(
                out,
                "\nFAIL: {failed} of {} expectations do not hold",
                outcome.verdicts.len()
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::names_word;

    #[test]
    fn a_component_is_named_as_a_whole_word() {
        assert!(names_word(
            "PDE.cmd = open2: valve2: closed -> open",
            "valve2"
        ));
        assert!(names_word("rule sets engine.power = zero", "engine"));
        assert!(!names_word("valve10 = open", "valve1"));
        assert!(!names_word("alt_12m_trigger = triggered", "trigger"));
        assert!(!names_word("slew-to-landing", "landing"));
        assert!(names_word("landing = success", "landing"));
    }
}
