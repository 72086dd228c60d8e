//! The checker of a scenario's expectations ([`super::expectation`]), cycle by cycle as the run
//! goes so that no history has to be kept (DESIGN.md §11: "so `kairos run SCENARIO` exits
//! non-zero when one fails").
//!
//! # The agenda
//!
//! A cycle asks only the expectations that can still move: each waits until its window opens
//! ([`ExpectationKind::opens_at`]) and leaves the agenda once decided or once a cycle past its
//! window's end ([`ExpectationKind::closes_at`]) has asked it. Exact: outside its window a
//! check is `Open` and touches nothing, a decided expectation was never asked again, and the
//! checks of one cycle touch only their own expectation's records (after the events have
//! updated the goals and XGoals they all read), so leaving some out changes no other.
//! Measured on the nominal Mars EDL (55 expectations, 171,577 cycles, its cruise asking 18):
//! closing the windows took the run from 8,384 M to 8,204 M instructions (−2.1 %); the
//! crate's tests compare every verdict with a checker asking every open expectation.

use std::sync::Arc;

use super::condition::{Condition, Cycle};
use super::expectation::{Expectation, ExpectationKind, Outcome, Verdict, Window};
use super::format::EventName;
use super::script::{Delay, ScriptedPlant, TIME_EPSILON};
use crate::diagnostic::Source;
use crate::executive::{Event, EventKind, Step, describe_event};
use crate::logic::{Formula, ValueId, VarId, VarTable};
use crate::plant::{ComponentId, Plant};
use crate::sequencer::LocationId;

#[derive(Debug, Clone, PartialEq)]
enum Progress {
    Open,
    Met(f64),
    Failed(String),
}

/// What the checker needs to know about the model.
#[derive(Clone, Copy)]
pub(crate) struct Names<'a> {
    pub(crate) plant: &'a Plant,
    pub(crate) world: &'a VarTable,
    pub(crate) controls: &'a [(VarId, ValueId)],
    /// The program or mission, for the events' text (`saying`).
    pub(crate) program: &'a Source,
}

/// Checks a scenario's expectations cycle by cycle.
#[derive(Clone)]
pub(crate) struct Checker<'a> {
    expectations: &'a [Expectation],
    names: Names<'a>,
    progress: Vec<Progress>,
    /// The goal each location asserted, as displayed in its `GoalAsserted` event.
    goals: Vec<(LocationId, String)>,
    /// ŝ at the last cycle seen (for failure reasons).
    last_modes: Arc<[ValueId]>,
    last_time: Option<f64>,
    /// First diagnosis seen for each `Diagnosed` expectation outside its tolerance.
    late: Vec<Option<f64>>,
    /// Commands matched so far, for each `CommandsInOrder` expectation.
    matched: Vec<usize>,
    /// The mission's active XGoals: per state variable, its end point and constituent goals
    /// (from the dispatch, withdrawal and firing events).
    active: Vec<ActiveXGoal>,
    /// Per expectation, the flags of its condition's `Once`s (`Always` only).
    memory: Vec<Vec<bool>>,
    /// Per expectation, [`ExpectationKind::opens_at`]: an open expectation is not checked
    /// before. A long run's expectations mostly wait for windows far ahead (the nominal EDL's
    /// 55 through a 16,000 s cruise): asking each of them every cycle was the checker's cost.
    opens: Vec<f64>,
    /// Per expectation, [`ExpectationKind::closes_at`]: nor is it checked after.
    closes: Vec<f64>,
    /// The expectations whose window has not opened yet, latest opening first (the next to
    /// open is last).
    waiting: Vec<usize>,
    /// The expectations asked at each cycle, ascending: opened, not closed, and still open
    /// (a `CommandsInOrder`: not failed). Walking only these, not all expectations, is what
    /// the agenda saves: the nominal EDL's cruise asks 18 of its 55.
    asked: Vec<usize>,
    /// The earliest [`ExpectationKind::closes_at`] in `asked`: `asked` is looked over when a
    /// cycle is past it, or when one of its expectations was decided.
    first_close: f64,
}

#[cfg(test)]
thread_local! {
    /// Set by a test to check every open expectation at every cycle, as before the agenda
    /// (`opens`), to compare the two.
    pub(crate) static WITHOUT_AGENDA: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// An XGoal active on a state variable, as its dispatch reported it.
#[derive(Clone)]
struct ActiveXGoal {
    sv: ComponentId,
    end: String,
    goals: Vec<String>,
}

impl<'a> Checker<'a> {
    pub(crate) fn new(expectations: &'a [Expectation], names: Names<'a>) -> Self {
        let memory = (expectations.iter())
            .map(|e| match &e.kind {
                ExpectationKind::Always { condition, .. } => vec![false; condition.slots()],
                _ => Vec::new(),
            })
            .collect();
        let opens = expectations.iter().map(|e| e.kind.opens_at());
        let closes = expectations.iter().map(|e| e.kind.closes_at());
        #[cfg(test)]
        let (opens, closes) = {
            let without = WITHOUT_AGENDA.get();
            let opens = opens.map(move |at| if without { f64::NEG_INFINITY } else { at });
            (
                opens,
                closes.map(move |at| if without { f64::INFINITY } else { at }),
            )
        };
        let opens: Vec<f64> = opens.collect();
        let mut waiting: Vec<usize> = (0..expectations.len()).collect();
        // Stable: expectations opening together are taken in ascending order.
        // (A time that is not a number opens nothing, as `t >= NaN` never holds: last.)
        let key = |i: usize| {
            if opens[i].is_nan() {
                f64::INFINITY
            } else {
                opens[i]
            }
        };
        waiting.sort_by(|&a, &b| key(b).total_cmp(&key(a)).then(b.cmp(&a)));
        Checker {
            opens,
            closes: closes.collect(),
            waiting,
            asked: Vec::new(),
            first_close: f64::INFINITY,
            progress: vec![Progress::Open; expectations.len()],
            late: vec![None; expectations.len()],
            matched: vec![0; expectations.len()],
            memory,
            expectations,
            names,
            goals: Vec::new(),
            last_modes: Arc::from([]),
            last_time: None,
            active: Vec::new(),
        }
    }

    /// True while an eventual expectation is still to be shown.
    pub(crate) fn awaits_something(&self) -> bool {
        self.expectations
            .iter()
            .zip(&self.progress)
            .any(|(e, p)| e.kind.is_eventual() && *p == Progress::Open)
    }

    /// The expectations that have failed already (a never-expectation violated, a sequence
    /// broken, a time passed): a path that shows one is a counterexample at once.
    pub(crate) fn failed(&self) -> impl Iterator<Item = (usize, &str)> {
        self.progress
            .iter()
            .enumerate()
            .filter_map(|(i, p)| match p {
                Progress::Failed(reason) => Some((i, reason.as_str())),
                _ => None,
            })
    }

    /// Feeds what decides the verdicts still to come to `state` (exploration's deduplication):
    /// each expectation's progress (open, met or failed, not when or why), the commands of
    /// each sequence matched so far, the goals asserted (an achievement is matched by its
    /// text), whether a diagnosis came late, the mission's active XGoals and the invariants'
    /// `Once` flags.
    pub(crate) fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        use std::hash::Hash;
        for progress in &self.progress {
            std::mem::discriminant(progress).hash(state);
        }
        self.matched.hash(state);
        self.goals.hash(state);
        for late in &self.late {
            late.is_some().hash(state);
        }
        for active in &self.active {
            (active.sv, &active.end, &active.goals).hash(state);
        }
        self.memory.hash(state);
    }

    /// Checks one cycle.
    pub(crate) fn observe(&mut self, step: &Step, plant: &ScriptedPlant<'_>) {
        for event in &step.events {
            self.track(&event.kind);
        }
        self.open_due(step.time);
        let mut asked = std::mem::take(&mut self.asked);
        // Whether one of them was decided (a sequence: failed) and leaves the agenda.
        let mut decided = false;
        for &i in &asked {
            if let ExpectationKind::CommandsInOrder { commands, window } =
                &self.expectations[i].kind
            {
                let progress = self.check_sequence(i, commands, *window, step);
                decided |= matches!(progress, Progress::Failed(_));
                self.progress[i] = progress;
            } else {
                // Written only when it moved: an open expectation stays open on most cycles.
                match self.check(i, step, plant) {
                    Progress::Open => {}
                    moved => {
                        self.progress[i] = moved;
                        decided = true;
                    }
                }
            }
        }
        // Looked over only when one was decided or a window closed: most cycles neither.
        if decided || step.time > self.first_close {
            asked.retain(|&i| self.still_asked(i, step.time));
            self.first_close = self.first_close_of(&asked);
        }
        self.asked = asked;
        self.last_modes = Arc::clone(&step.most_likely);
        self.last_time = Some(step.time);
    }

    /// Moves the expectations whose window opens by `time` from `waiting` to `asked`, keeping
    /// `asked` ascending.
    fn open_due(&mut self, time: f64) {
        let before = self.asked.len();
        while let Some(&i) = self.waiting.last() {
            if !self.opens_by(i, time) {
                break;
            }
            self.waiting.pop();
            // One opened at `time` may be past its window already (a window shorter than a
            // cycle): asked once, as before the agenda, then let go.
            self.asked.push(i);
            self.first_close = self.first_close.min(self.closes[i]);
        }
        if self.asked.len() != before {
            self.asked.sort_unstable();
        }
    }

    /// The earliest [`ExpectationKind::closes_at`] of these expectations.
    fn first_close_of(&self, asked: &[usize]) -> f64 {
        (asked.iter())
            .map(|&i| self.closes[i])
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether expectation `i`'s window has opened at `time`.
    fn opens_by(&self, i: usize, time: f64) -> bool {
        time >= self.opens[i]
    }

    /// Whether expectation `i`, asked at `time`, is to be asked again: a sequence until it
    /// fails, any other while it is open and its window has not closed.
    fn still_asked(&self, i: usize, time: f64) -> bool {
        match self.expectations[i].kind {
            ExpectationKind::CommandsInOrder { .. } => {
                !matches!(self.progress[i], Progress::Failed(_))
            }
            _ => self.progress[i] == Progress::Open && time <= self.closes[i],
        }
    }

    /// Keeps the goals the program asserts and the mission's active XGoals up to date.
    fn track(&mut self, kind: &EventKind) {
        match kind {
            EventKind::GoalAsserted { goal, location, .. } => {
                self.goals.retain(|(l, _)| l != location);
                self.goals.push((*location, goal.clone()));
            }
            EventKind::TimePointFired { point, .. } | EventKind::TimePointForced { point, .. } => {
                self.active.retain(|a| &a.end != point);
            }
            EventKind::XGoalWithdrawn { sv, .. } => self.active.retain(|a| a.sv != *sv),
            EventKind::XGoalDispatched {
                sv,
                interval: (_, end),
                goals,
                ..
            } => {
                self.active.retain(|a| a.sv != *sv);
                self.active.push(ActiveXGoal {
                    sv: *sv,
                    end: end.clone(),
                    goals: goals.clone(),
                });
            }
            _ => {}
        }
    }

    /// The point fired (on time or forced) in this cycle.
    fn fired(point: &str, step: &Step) -> bool {
        step.events.iter().any(|e| {
            matches!(&e.kind, EventKind::TimePointFired { point: p, .. }
                | EventKind::TimePointForced { point: p, .. } if p == point)
        })
    }

    /// The mission goal `goal` (any, when `None`) was reported failed in this cycle.
    fn mission_goal_failed(goal: Option<&str>, step: &Step) -> bool {
        step.events.iter().any(|e| {
            matches!(&e.kind, EventKind::MissionGoalFailed { goal: g, .. }
                if goal.is_none_or(|goal| goal == g))
        })
    }

    /// Whether an XGoal (with `goal` among its constituents) is active on `sv`; why not if not.
    fn xgoal_active(&self, sv: ComponentId, goal: Option<&str>) -> Result<(), String> {
        let Some(active) = self.active.iter().find(|a| a.sv == sv) else {
            return Err("no XGoal was active on it".to_string());
        };
        match goal {
            Some(goal) if !active.goals.iter().any(|g| g == goal) => Err(format!(
                "its active XGoal merged {}",
                if active.goals.is_empty() {
                    "no goal".to_string()
                } else {
                    active.goals.join(", ")
                }
            )),
            _ => Ok(()),
        }
    }

    fn check(&mut self, i: usize, step: &Step, plant: &ScriptedPlant<'_>) -> Progress {
        let expectations = self.expectations;
        self.check_kind(i, &expectations[i].kind, step, plant)
    }

    /// Checks `kind`, expectation `i` or one of its alternatives.
    fn check_kind(
        &mut self,
        i: usize,
        kind: &ExpectationKind,
        step: &Step,
        plant: &ScriptedPlant<'_>,
    ) -> Progress {
        use ExpectationKind as K;
        let t = step.time;
        let shown = match kind {
            K::AnyOf { members } => {
                for member in members {
                    if let Progress::Met(at) = self.check_kind(i, member, step, plant) {
                        return Progress::Met(at);
                    }
                }
                false
            }
            K::Estimated { state, window } => window.contains(t) && self.estimated(state, step),
            K::EstimatedAt { state, time } => {
                if t < time - TIME_EPSILON {
                    return Progress::Open;
                }
                if self.estimated(state, step) {
                    return Progress::Met(t);
                }
                return Progress::Failed(format!(
                    "at {} ŝ had {}",
                    seconds(t),
                    self.modes_of(state, &step.most_likely)
                ));
            }
            K::NeverEstimated { state, window } => {
                if window.contains(t) && self.estimated(state, step) {
                    return Progress::Failed(format!(
                        "at {} ŝ had {}",
                        seconds(t),
                        self.modes_of(state, &step.most_likely)
                    ));
                }
                return Progress::Open;
            }
            K::Commanded { command, window } => window.contains(t) && self.commanded(command, step),
            K::CommandsInOrder { .. } => return Progress::Open,
            K::NeverCommanded { command, window } => {
                if window.contains(t) && self.commanded(command, step) {
                    return Progress::Failed(format!("commanded at {}", seconds(t)));
                }
                return Progress::Open;
            }
            K::Diagnosed {
                component,
                mode,
                window,
                within,
            } => {
                let diagnosed = step.events.iter().any(|e| {
                    matches!(&e.kind, EventKind::Diagnosis { component: c, mode: m, .. }
                        if c == component && self.names.plant.component(*c).mode_named(m) == Some(*mode))
                });
                if !(diagnosed && window.contains(t)) {
                    return Progress::Open;
                }
                match within {
                    None => true,
                    Some((tolerance, rule)) => {
                        let in_time = plant.first_fired(*rule).is_some_and(|(cycle, time)| {
                            within_tolerance(*tolerance, cycle, time, step)
                        });
                        if !in_time {
                            self.late[i].get_or_insert(t);
                        }
                        in_time
                    }
                }
            }
            K::Achieved { goal, window } => {
                window.contains(t)
                    && step.events.iter().any(|e| match &e.kind {
                        EventKind::GoalAchieved { location, .. } => self
                            .goals
                            .iter()
                            .any(|(l, text)| l == location && text == goal),
                        _ => false,
                    })
            }
            K::GoalFailed { goal, window } => {
                window.contains(t)
                    && step.events.iter().any(|e| match &e.kind {
                        EventKind::GoalFailed { goal: failed, .. } => goal
                            .as_ref()
                            .is_none_or(|g| failed == g || failed.split(" and ").any(|c| c == g)),
                        _ => false,
                    })
            }
            K::Completed { window } => {
                window.contains(t)
                    && step
                        .events
                        .iter()
                        .any(|e| matches!(e.kind, EventKind::ProgramCompleted))
            }
            K::Reported {
                event,
                saying,
                window,
            } => {
                window.contains(t)
                    && (step.events.iter()).any(|e| self.reports(*event, saying.as_deref(), e))
            }
            K::Fired { point, window } => window.contains(t) && Self::fired(point, step),
            K::NeverFired { point, window } => {
                if window.contains(t) && Self::fired(point, step) {
                    return Progress::Failed(format!("fired at {}", seconds(t)));
                }
                return Progress::Open;
            }
            K::Failed { goal, window } => {
                window.contains(t) && Self::mission_goal_failed(Some(goal), step)
            }
            K::NeverFailed { goal, window } => {
                if window.contains(t) && Self::mission_goal_failed(goal.as_deref(), step) {
                    return Progress::Failed(format!("a goal failed at {}", seconds(t)));
                }
                return Progress::Open;
            }
            K::XGoalActive { sv, goal, time } => {
                if t < time - TIME_EPSILON {
                    return Progress::Open;
                }
                return match self.xgoal_active(*sv, goal.as_deref()) {
                    Ok(()) => Progress::Met(t),
                    Err(why) => Progress::Failed(format!("at {}, {why}", seconds(t))),
                };
            }
            K::NeverReported {
                event,
                saying,
                window,
            } => {
                if let Some(e) = step
                    .events
                    .iter()
                    .find(|e| window.contains(t) && self.reports(*event, saying.as_deref(), e))
                {
                    return Progress::Failed(format!(
                        "reported at {} ({:?})",
                        seconds(t),
                        EventName::of(&e.kind)
                    ));
                }
                return Progress::Open;
            }
            K::Recovered { goal, window } => window.contains(t)
                && step.events.iter().any(
                    |e| matches!(&e.kind, EventKind::GoalRecovered { goal: g, .. } if g == goal),
                ),
            K::NeverXGoalActive { sv, goal, window } => {
                if window.contains(t) && self.xgoal_active(*sv, goal.as_deref()).is_ok() {
                    let what = self.active.iter().find(|a| a.sv == *sv);
                    let goals = what.map(|a| a.goals.join(", ")).unwrap_or_default();
                    return Progress::Failed(format!(
                        "at {} an XGoal merging {goals} was active",
                        seconds(t)
                    ));
                }
                return Progress::Open;
            }
            K::Always { condition, window } => {
                let mut memory = std::mem::take(&mut self.memory[i]);
                let holds = self.condition_holds(condition, &mut memory, step, plant);
                self.memory[i] = memory;
                if window.contains(t) && !holds {
                    return Progress::Failed(format!("not at {}", seconds(t)));
                }
                return Progress::Open;
            }
        };
        if shown {
            Progress::Met(t)
        } else {
            Progress::Open
        }
    }

    /// Whether `event` is of kind `name` and, if `saying` is given, says it (its text as the
    /// mission log prints it contains it).
    fn reports(&self, name: EventName, saying: Option<&str>, event: &Event) -> bool {
        is(name, event)
            && saying.is_none_or(|text| {
                describe_event(self.names.plant, self.names.program, &event.kind)
                    .1
                    .contains(text)
            })
    }

    /// Whether `condition` holds at this cycle (updating its `Once` flags in `memory`).
    fn condition_holds(
        &self,
        condition: &Condition,
        memory: &mut [bool],
        step: &Step,
        plant: &ScriptedPlant<'_>,
    ) -> bool {
        let held = |var: VarId| plant.value(var);
        let active = |goal: &str| {
            self.active
                .iter()
                .any(|a| a.goals.iter().any(|g| g == goal))
        };
        let cycle = Cycle {
            plant: self.names.plant,
            world: self.names.world,
            step,
            held: &held,
            active: &active,
            is,
        };
        condition.holds(&cycle, memory)
    }

    /// The next command of a `CommandsInOrder` expectation.
    fn check_sequence(
        &mut self,
        i: usize,
        commands: &[Formula],
        window: Window,
        step: &Step,
    ) -> Progress {
        let so_far = std::mem::replace(&mut self.progress[i], Progress::Open);
        if step.command.is_empty() || !window.contains(step.time) {
            return so_far;
        }
        let issued = self.issued(step);
        let Some(expected) = commands.get(self.matched[i]) else {
            return Progress::Failed(format!(
                "one more command at {}: {issued}",
                seconds(step.time)
            ));
        };
        if !self.commanded(expected, step) {
            return Progress::Failed(format!(
                "command {} of the sequence, at {}, was {issued}",
                self.matched[i] + 1,
                seconds(step.time)
            ));
        }
        self.matched[i] += 1;
        if self.matched[i] == commands.len() {
            Progress::Met(step.time)
        } else {
            Progress::Open
        }
    }

    /// `PDE.cmd = on, landing.cmd = set-success`: a cycle's command.
    fn issued(&self, step: &Step) -> String {
        let shown: Vec<String> = step
            .command
            .iter()
            .map(|&(x, v)| self.names.world.assignment(x, v).to_string())
            .collect();
        shown.join(", ")
    }

    /// ŝ satisfies `state` (a formula over mode variables).
    fn estimated(&self, state: &Formula, step: &Step) -> bool {
        let plant = self.names.plant;
        state.eval_assignment(self.names.world, &|var| {
            mode_value(plant, var, &step.most_likely)
        }) == Some(true)
    }

    /// μ satisfies `command` (a formula over controls; idle values for controls not commanded).
    fn commanded(&self, command: &Formula, step: &Step) -> bool {
        let value = |var: VarId| {
            step.command
                .iter()
                .find(|(x, _)| *x == var)
                .map(|&(_, v)| v)
                .or_else(|| {
                    self.names
                        .controls
                        .iter()
                        .find(|(x, _)| *x == var)
                        .map(|&(_, idle)| idle)
                })
        };
        command.eval_assignment(self.names.world, &value) == Some(true)
    }

    /// `engine = heating, PDE = on`: the modes ŝ gives the components `formula` mentions.
    fn modes_of(&self, formula: &Formula, modes: &[ValueId]) -> String {
        let plant = self.names.plant;
        let mut shown: Vec<String> = Vec::new();
        for var in formula.variables() {
            if let Some(value) = mode_value(plant, var, modes) {
                shown.push(self.names.world.assignment(var, value).to_string());
            }
        }
        shown.dedup();
        shown.join(", ")
    }

    /// The verdicts once the run is over.
    pub(crate) fn finish(&self, plant: &ScriptedPlant<'_>) -> Vec<Verdict> {
        self.expectations
            .iter()
            .zip(&self.progress)
            .enumerate()
            .map(|(i, (expectation, progress))| Verdict {
                label: expectation.label.clone(),
                outcome: match progress {
                    Progress::Met(t) => Outcome::Met { at: Some(*t) },
                    Progress::Failed(reason) => Outcome::Failed {
                        reason: reason.clone(),
                    },
                    Progress::Open if !expectation.kind.is_eventual() => Outcome::Met { at: None },
                    Progress::Open => Outcome::Failed {
                        reason: self.never_shown(i, expectation, plant),
                    },
                },
            })
            .collect()
    }

    fn never_shown(
        &self,
        i: usize,
        expectation: &Expectation,
        plant: &ScriptedPlant<'_>,
    ) -> String {
        use ExpectationKind as K;
        let end = self
            .last_time
            .map_or_else(|| "before any cycle".to_string(), seconds);
        match &expectation.kind {
            K::Estimated { state, .. } => format!(
                "not shown; at the end ({end}) ŝ had {}",
                self.modes_of(state, &self.last_modes)
            ),
            K::EstimatedAt { .. } | K::XGoalActive { .. } => {
                format!("the run ended at {end}, before that time")
            }
            K::CommandsInOrder { commands, .. } => format!(
                "only {} of the {} commands were issued by the end ({end})",
                self.matched[i],
                commands.len()
            ),
            K::Diagnosed { within, .. } => match (within, self.late[i]) {
                (Some((_, rule)), _) if plant.first_fired(*rule).is_none() => {
                    format!("rule `{}` never fired", plant.script().rules()[*rule].name)
                }
                (Some(_), Some(late)) => {
                    format!("diagnosed only at {}, later than allowed", seconds(late))
                }
                _ => format!("not diagnosed by the end ({end})"),
            },
            _ => format!("not shown by the end ({end})"),
        }
    }
}

/// The mode ŝ gives `var` if it is a component's mode variable.
fn mode_value(plant: &Plant, var: VarId, modes: &[ValueId]) -> Option<ValueId> {
    let component = plant.component_of(var)?;
    if plant.component(component).mode_var() != var {
        return None;
    }
    modes.get(component.index()).copied()
}

fn within_tolerance(tolerance: Delay, fired_cycle: u64, fired_time: f64, step: &Step) -> bool {
    match tolerance {
        Delay::Cycles(n) => step.cycle >= fired_cycle && step.cycle - fired_cycle <= n,
        Delay::Seconds(s) => {
            step.time >= fired_time - TIME_EPSILON && step.time - fired_time <= s + TIME_EPSILON
        }
    }
}

/// True when `event` is of the kind `name`.
pub(crate) fn is(name: EventName, event: &Event) -> bool {
    use EventKind as E;
    match (name, &event.kind) {
        (EventName::Repair, E::CommandIssued { repair, .. }) => *repair,
        (name, kind) => name == EventName::of(kind),
    }
}

/// `12.300 s`.
pub(crate) fn seconds(time: f64) -> String {
    format!("{time:.3} s")
}
