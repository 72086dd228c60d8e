//! The explicit-state explorer of the protocol (mds-goal-networks.md §4.2 "Execution"; the
//! analogue of the seed's Maude `search` and model checking, ¶13): every interleaving of the
//! messages in flight, breadth first, each configuration stored once.
//!
//! # Configurations and steps
//! A configuration is the controller's state, the rover's true pose, the state variable (value
//! and the `endcstr`s it received), the multiset of messages in flight (kept sorted, so equal
//! multisets are equal values), which constraints the environment has sent, and per constraint
//! the value it started from and the commands issued for it (what P-cmds judges). A step either
//! delivers one message in flight — any of them: no channel keeps order — or lets the
//! environment send a constraint whose [`Arrival`] allows it now. Configurations are hashed
//! whole and deduplicated (no fingerprint: they are small, and no collision can merge two).
//!
//! # Properties (§4.2)
//! Checked on every configuration reached; a configuration that violates P-excl, P-cmds or the
//! safety half of P-succ/P-fail (a second `endcstr`, or one with the wrong outcome) is not
//! explored further, so each violation is reported once, at its shortest trace:
//! - **P-succ/P-fail**: every terminal configuration holds exactly one `endcstr` per constraint,
//!   with the scenario's outcome (and, where the scenario says, the number of commands issued
//!   and the rover's final pose).
//! - **P-excl**: the controller never processes two constraints at once.
//! - **P-term**: no terminal configuration lacks an `endcstr` (a deadlock). No divergence: every
//!   delivery consumes a message whose chain to the controller is finite (command → execute →
//!   report → measurement → estimate → `newval`), and the controller can only start chains by
//!   issuing commands, which P-cmds bounds by the course of action — so a path that does not
//!   violate P-cmds is finite, and a path that does is cut there. The explored graph is finite
//!   and acyclic; the search ends.
//! - **P-cmds**: the commands issued for a constraint are a prefix of `coa(v0, c)`, v0 the
//!   state variable's value when the controller started processing it.
//!
//! # Determinism
//! Breadth first in a fixed order (sends by constraint, then deliveries in the messages' order):
//! the same counts and the same (shortest) counterexamples on every run. The spaces are small
//! (hundreds of configurations, BENCHMARKS.md), so the search is sequential.

use std::collections::VecDeque;
use std::fmt;
use std::time::{Duration, Instant};

use rustc_hash::FxHashMap;

use super::{Budget, Limit, memory};
use crate::protocol::Controller;
use crate::protocol::RoverScenario;
use crate::protocol::components::{StateVariable, actuator, estimator, sensor};
use crate::protocol::messages::{ConstraintId, Message};
use crate::protocol::posandhead::{Command, Pose, StateValue, coa};
use crate::protocol::scenario::Arrival;

/// The properties of §4.2, in the order they are reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Property {
    /// Every constraint ends once, with its expected outcome.
    SuccFail,
    /// One constraint processed at a time.
    Excl,
    /// No deadlock before every `endcstr`, no divergence.
    Term,
    /// Commands are a prefix of the course of action.
    Cmds,
}

impl Property {
    /// Every property, in report order.
    pub const ALL: [Property; 4] = [
        Property::SuccFail,
        Property::Excl,
        Property::Term,
        Property::Cmds,
    ];

    /// What the property says.
    pub fn statement(self) -> &'static str {
        match self {
            Property::SuccFail => {
                "every terminal configuration ends each constraint once, as expected"
            }
            Property::Excl => "the controller never processes two constraints at once",
            Property::Term => "no deadlock before every endcstr, no divergence",
            Property::Cmds => "the commands issued are a prefix of coa(v0, c)",
        }
    }
}

impl fmt::Display for Property {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Property::SuccFail => "P-succ/P-fail",
            Property::Excl => "P-excl",
            Property::Term => "P-term",
            Property::Cmds => "P-cmds",
        })
    }
}

/// What was issued for one constraint.
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
struct Issued {
    /// The state variable's value when the controller started processing it.
    start: Option<StateValue>,
    /// The commands issued for it, in order.
    commands: Vec<Command>,
}

/// One configuration of the system.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct Configuration<C> {
    controller: C,
    rover: Pose,
    sv: StateVariable,
    /// Messages in flight, sorted.
    messages: Vec<Message>,
    /// Which constraints the environment has sent.
    sent: Vec<bool>,
    /// Per constraint (by id; a controller may name others, which P-cmds reports).
    issued: Vec<Issued>,
}

/// One step from a configuration to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    /// The environment sends this constraint to the controller.
    Send(ConstraintId),
    /// This message is delivered to its recipient.
    Deliver(Message),
}

/// A violated property and the shortest trace that shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct Counterexample {
    /// The property violated.
    pub property: Property,
    /// How, in words.
    pub reason: String,
    /// The trace from the initial configuration, one step a line: what was sent or delivered,
    /// and what its recipient sent in answer.
    pub trace: Vec<String>,
}

/// What an exploration found.
#[derive(Debug, Clone, PartialEq)]
pub struct ProtocolExploration {
    /// Distinct configurations reached.
    pub states: u64,
    /// Steps between them (edges of the explored graph).
    pub transitions: u64,
    /// Distinct terminal configurations (nothing in flight, nothing left to send).
    pub terminals: u64,
    /// Configurations not explored further because they violate a property.
    pub stopped: u64,
    /// Configurations outside the scenario, not explored further: a constraint that must
    /// arrive while another is processed was not sent before that one ended.
    pub excluded: u64,
    /// Interleavings: the number of distinct paths from the initial configuration to a
    /// terminal one. `None` if a path count could not be kept exact (a step to a configuration
    /// reached by a shorter route) or overflowed.
    pub paths: Option<u128>,
    /// The most steps the shortest route to a configuration takes.
    pub depth: usize,
    /// True when the budget stopped the search before every configuration was explored.
    pub cut: bool,
    /// What stopped it then.
    pub limit: Option<Limit>,
    /// The shortest counterexample of each violated property, in [`Property::ALL`]'s order.
    pub counterexamples: Vec<Counterexample>,
    /// Wall time.
    pub wall: Duration,
}

impl ProtocolExploration {
    /// True when every configuration was explored and no property is violated.
    pub fn holds(&self) -> bool {
        !self.cut && self.counterexamples.is_empty()
    }
}

/// The search's bookkeeping: configurations by index, how each was first reached.
struct Search<'a, C> {
    scenario: &'a RoverScenario,
    states: Vec<Configuration<C>>,
    index: FxHashMap<Configuration<C>, usize>,
    /// The configuration and step each was first reached from.
    parent: Vec<Option<(usize, Step)>>,
    level: Vec<usize>,
    paths: Vec<u128>,
    exact_paths: bool,
    terminal: Vec<usize>,
    found: Vec<Counterexample>,
}

/// Explores every interleaving of `scenario` with `controller` (in its initial state), within
/// `budget` and, once the process holds `memory` bytes ([`memory::resident_bytes`]), no
/// further: the configurations stored grow with the scenario's constraints (40 of them reached
/// gigabytes in seconds), and a cut search says so.
pub fn explore<C: Controller>(
    scenario: &RoverScenario,
    controller: C,
    budget: Budget,
    memory: u64,
) -> ProtocolExploration {
    let started = Instant::now();
    let mut search = Search::initial(scenario, controller);
    let (mut transitions, mut stopped, mut excluded, mut limit) = (0, 0, 0, None);
    let mut queue = VecDeque::from([0usize]);
    let mut checked = 0;
    while let Some(at) = queue.pop_front() {
        limit = out_of_budget(budget, search.states.len(), started);
        if limit.is_none() && search.states.len() >= checked + memory::CHECK_EVERY as usize {
            checked = search.states.len();
            if memory::resident_bytes().is_some_and(|bytes| bytes >= memory) {
                limit = Some(Limit::Memory);
            }
        }
        if limit.is_some() {
            break;
        }
        if search.check_safety(at) {
            stopped += 1;
            continue;
        }
        if window_missed(scenario, &search.states[at]) {
            excluded += 1;
            continue;
        }
        let steps = enabled(scenario, &search.states[at]);
        if steps.is_empty() {
            search.terminal.push(at);
            search.check_terminal(at);
        }
        for step in steps {
            transitions += 1;
            let (next, _) = apply(scenario, &search.states[at], step);
            if let Some(new) = search.reach(at, step, next) {
                queue.push_back(new);
            }
        }
    }
    let paths = search.terminal_paths();
    let terminals = search.terminal.len() as u64;
    let mut counterexamples = search.found;
    counterexamples.sort_by_key(|c| c.property);
    ProtocolExploration {
        states: search.states.len() as u64,
        transitions,
        terminals,
        stopped,
        excluded,
        paths,
        depth: search.level.iter().copied().max().unwrap_or(0),
        cut: limit.is_some(),
        limit,
        counterexamples,
        wall: started.elapsed(),
    }
}

/// The budget that is spent with `states` configurations stored, if one is.
fn out_of_budget(budget: Budget, states: usize, started: Instant) -> Option<Limit> {
    match budget {
        Budget::Unbounded => None,
        Budget::States(limit) => (states as u64 > limit).then_some(Limit::States),
        Budget::Time(limit) => (started.elapsed() > limit).then_some(Limit::Time),
    }
}

/// The configuration after `step`, and the messages the step sent.
fn apply<C: Controller>(
    scenario: &RoverScenario,
    from: &Configuration<C>,
    step: Step,
) -> (Configuration<C>, Vec<Message>) {
    let mut next = from.clone();
    let sent = match step {
        Step::Send(id) => {
            next.sent[id] = true;
            vec![Message::Constraint {
                id,
                constraint: scenario.constraints[id].constraint,
            }]
        }
        Step::Deliver(message) => {
            if let Some(i) = next.messages.iter().position(|m| *m == message) {
                next.messages.remove(i);
            }
            next.deliver(&scenario.grid, &message)
        }
    };
    for message in &sent {
        if let Message::Command { id, command } = message {
            if next.issued.len() <= *id {
                next.issued.resize(id + 1, Issued::default());
            }
            next.issued[*id].commands.push(*command);
        }
    }
    for id in next.controller.processing() {
        if next.issued.len() <= id {
            next.issued.resize(id + 1, Issued::default());
        }
        next.issued[id].start.get_or_insert(next.sv.value);
    }
    next.messages.extend(sent.iter().copied());
    next.messages.sort_unstable();
    (next, sent)
}

/// The steps enabled in `config`: sends the scenario allows now, then each
/// distinct message in flight.
fn enabled<C: Controller>(scenario: &RoverScenario, config: &Configuration<C>) -> Vec<Step> {
    let processing = config.controller.processing();
    let mut steps: Vec<Step> = (scenario.constraints.iter().enumerate())
        .filter(|(id, c)| {
            !config.sent[*id]
                && match c.arrives {
                    // Sent in the initial configuration.
                    Arrival::Initially => false,
                    Arrival::Anytime => true,
                    Arrival::WhileProcessing(other) => processing.contains(&other),
                }
        })
        .map(|(id, _)| Step::Send(id))
        .collect();
    let mut messages = config.messages.clone();
    messages.dedup();
    steps.extend(messages.into_iter().map(Step::Deliver));
    steps
}

/// Whether the environment missed a window in `config`: a constraint that arrives
/// `WhileProcessing(j)` is unsent although the controller has processed `j` and no longer
/// does. Such a path is not one of the scenario's, as a constraint sent outside its window
/// would not be.
fn window_missed<C: Controller>(scenario: &RoverScenario, config: &Configuration<C>) -> bool {
    let processing = config.controller.processing();
    (scenario.constraints.iter().enumerate()).any(|(id, c)| match c.arrives {
        Arrival::WhileProcessing(other) => {
            !config.sent[id] && config.issued[other].start.is_some() && !processing.contains(&other)
        }
        Arrival::Initially | Arrival::Anytime => false,
    })
}

impl<C: Controller> Configuration<C> {
    /// Hands `message` to its recipient; what the recipient sends in answer.
    fn deliver(&mut self, grid: &crate::protocol::rover::Grid, message: &Message) -> Vec<Message> {
        match message {
            Message::Constraint { id, constraint } => {
                self.controller.on_constraint(*id, *constraint)
            }
            Message::NewVal(value) => self.controller.on_newval(*value),
            Message::Command { .. } => actuator(message).into_iter().collect(),
            Message::Execute(command) => {
                self.rover = grid.execute(self.rover, *command);
                vec![Message::Report(self.rover)]
            }
            Message::Report(_) => sensor(message).into_iter().collect(),
            Message::Measurement(_) => estimator(message).into_iter().collect(),
            Message::Estimate(_) | Message::EndCstr { .. } => {
                self.sv.receive(message).into_iter().collect()
            }
        }
    }
}

impl<'a, C: Controller> Search<'a, C> {
    /// A search holding only the initial configuration: the controller as given, the rover
    /// and state variable as the scenario says, the constraints that arrive initially in
    /// flight.
    fn initial(scenario: &'a RoverScenario, controller: C) -> Self {
        let n = scenario.constraints.len();
        // Constraints that arrive initially are in flight from the start, in no order.
        let initially = |id: &usize| scenario.constraints[*id].arrives == Arrival::Initially;
        let mut messages: Vec<Message> = (0..n)
            .filter(initially)
            .map(|id| Message::Constraint {
                id,
                constraint: scenario.constraints[id].constraint,
            })
            .collect();
        messages.sort_unstable();
        let initial = Configuration {
            controller,
            rover: scenario.rover,
            sv: StateVariable::new(scenario.initial_value()),
            messages,
            sent: (0..n).map(|id| initially(&id)).collect(),
            issued: vec![Issued::default(); n],
        };
        let mut search = Search {
            scenario,
            states: vec![initial.clone()],
            index: FxHashMap::default(),
            parent: vec![None],
            level: vec![0],
            paths: vec![1],
            exact_paths: true,
            terminal: Vec::new(),
            found: Vec::new(),
        };
        search.index.insert(initial, 0);
        search
    }

    /// Stores `next`, reached from `from` by `step`, if new; its index then.
    fn reach(&mut self, from: usize, step: Step, next: Configuration<C>) -> Option<usize> {
        let level = self.level[from] + 1;
        let through = self.paths[from];
        if let Some(&known) = self.index.get(&next) {
            // Path counts stay exact while every step goes one level down (then a
            // configuration's predecessors are all expanded before it).
            self.exact_paths &= self.level[known] == level;
            self.paths[known] = self.paths[known].saturating_add(through);
            return None;
        }
        let id = self.states.len();
        self.index.insert(next.clone(), id);
        self.states.push(next);
        self.parent.push(Some((from, step)));
        self.level.push(level);
        self.paths.push(through);
        Some(id)
    }

    /// The paths to terminal configurations, if counted exactly.
    fn terminal_paths(&self) -> Option<u128> {
        let total = (self.terminal.iter())
            .map(|&i| self.paths[i])
            .try_fold(0u128, u128::checked_add)?;
        (self.exact_paths && total != u128::MAX).then_some(total)
    }

    /// Checks P-excl, P-cmds and the safety half of P-succ/P-fail at `at`; true if violated.
    fn check_safety(&mut self, at: usize) -> bool {
        let config = &self.states[at];
        let mut violations = Vec::new();
        let processing = config.controller.processing();
        if processing.len() > 1 {
            let names: Vec<String> = (processing.iter())
                .map(|&id| format!("`{}`", self.name(id)))
                .collect();
            violations.push((
                Property::Excl,
                format!("the controller processes {} at once", names.join(" and ")),
            ));
        }
        violations.extend(self.command_violation(config).map(|r| (Property::Cmds, r)));
        violations.extend(
            self.ending_violation(config)
                .map(|r| (Property::SuccFail, r)),
        );
        let violated = !violations.is_empty();
        for (property, reason) in violations {
            self.record(property, reason, at);
        }
        violated
    }

    /// P-cmds: commands for a constraint not started, or not a prefix of its course of action.
    fn command_violation(&self, config: &Configuration<C>) -> Option<String> {
        config.issued.iter().enumerate().find_map(|(id, issued)| {
            if issued.commands.is_empty() {
                return None;
            }
            let Some(constraint) = self.scenario.constraints.get(id) else {
                return Some(format!("commands issued for constraint #{id}, not in the scenario"));
            };
            let Some(start) = issued.start else {
                return Some(format!(
                    "commands issued for `{}` before the controller processes it",
                    constraint.name
                ));
            };
            let plan = coa(&start, &constraint.constraint);
            (!plan.starts_with(&issued.commands)).then(|| {
                format!(
                    "the commands issued for `{}`, [{}], are not a prefix of coa({start}, {}) = [{}]",
                    constraint.name,
                    list(&issued.commands),
                    constraint.constraint,
                    list(&plan)
                )
            })
        })
    }

    /// P-succ/P-fail, safety half: no constraint ends twice or with an unexpected outcome.
    fn ending_violation(&self, config: &Configuration<C>) -> Option<String> {
        let ended = &config.sv.ended;
        ended.iter().enumerate().find_map(|(i, (id, outcome))| {
            let name = self.name(*id);
            if ended[..i].iter().any(|(other, _)| other == id) {
                return Some(format!("`{name}` ends twice"));
            }
            let expected = self.scenario.constraints.get(*id)?.expect;
            (*outcome != expected)
                .then(|| format!("`{name}` ends with {outcome}, expected {expected}"))
        })
    }

    /// P-term and P-succ/P-fail at a terminal configuration.
    fn check_terminal(&mut self, at: usize) {
        let config = &self.states[at];
        let missing: Vec<String> = (0..self.scenario.constraints.len())
            .filter(|id| !config.sv.ended.iter().any(|(e, _)| e == id))
            .map(|id| {
                let why = if config.sent[id] { "" } else { " (never sent)" };
                format!("`{}`{why}", self.name(id))
            })
            .collect();
        if !missing.is_empty() {
            let reason = format!(
                "deadlock: nothing can happen and no endcstr for {}",
                missing.join(", ")
            );
            self.record(Property::Term, reason, at);
            return;
        }
        if let Some(reason) = self.expectation_violation(config) {
            self.record(Property::SuccFail, reason, at);
        }
    }

    /// The scenario's counts of commands and final pose, at a terminal configuration.
    fn expectation_violation(&self, config: &Configuration<C>) -> Option<String> {
        for (id, constraint) in self.scenario.constraints.iter().enumerate() {
            let issued = config.issued.get(id).map_or(0, |i| i.commands.len());
            match constraint.commands {
                Some(expected) if expected != issued => {
                    return Some(format!(
                        "`{}` ends after {issued} commands, expected {expected}",
                        constraint.name
                    ));
                }
                _ => {}
            }
        }
        match self.scenario.ends_at {
            Some(pose) if pose != config.rover => Some(format!(
                "the rover ends at {}, expected {pose}",
                config.rover
            )),
            _ => None,
        }
    }

    /// Keeps the first (shortest: breadth first) counterexample of `property`.
    fn record(&mut self, property: Property, reason: String, at: usize) {
        if self.found.iter().any(|c| c.property == property) {
            return;
        }
        let trace = self.trace(at);
        self.found.push(Counterexample {
            property,
            reason,
            trace,
        });
    }

    /// The readable trace from the initial configuration to `at`.
    fn trace(&self, at: usize) -> Vec<String> {
        let mut steps = Vec::new();
        let mut cursor = at;
        while let Some((from, step)) = self.parent[cursor] {
            steps.push((from, step));
            cursor = from;
        }
        steps.reverse();
        let name = |id: ConstraintId| self.name(id);
        (steps.iter().enumerate())
            .map(|(k, &(from, step))| {
                let (_, sent) = apply(self.scenario, &self.states[from], step);
                let what = match step {
                    Step::Send(id) => format!("environment sends `{}`", self.name(id)),
                    Step::Deliver(message) => message.describe(&name),
                };
                let answer: Vec<String> = (sent.iter())
                    .filter(|_| matches!(step, Step::Deliver(_)))
                    .map(|m| m.describe(&name))
                    .collect();
                match answer.is_empty() {
                    true => format!("{:>3}. {what}", k + 1),
                    false => format!("{:>3}. {what}  ⇒  {}", k + 1, answer.join("; ")),
                }
            })
            .collect()
    }

    fn name(&self, id: ConstraintId) -> String {
        self.scenario
            .constraints
            .get(id)
            .map_or_else(|| format!("#{id}"), |c| c.name.clone())
    }
}

/// Commands as `turn(E), drive`.
fn list(commands: &[Command]) -> String {
    let names: Vec<String> = commands.iter().map(Command::to_string).collect();
    names.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Source;
    use crate::protocol::CoaController;
    use crate::protocol::scenario::load_source;

    /// Every path from `config` to a terminal configuration, enumerated one by one.
    fn count_paths(scenario: &RoverScenario, config: &Configuration<CoaController>) -> u128 {
        if window_missed(scenario, config) {
            return 0;
        }
        let steps = enabled(scenario, config);
        if steps.is_empty() {
            return 1;
        }
        (steps.into_iter())
            .map(|step| count_paths(scenario, &apply(scenario, config, step).0))
            .sum()
    }

    /// The interleavings the search counts (summed over predecessors, breadth first) are the
    /// paths a plain enumeration finds, on R5 (§4.2), whose space merges paths.
    #[test]
    fn interleavings_are_counted_exactly() {
        let text = include_str!("../../scenarios/rover/r5.ron");
        let scenario = load_source(&Source::new("r5.ron", text)).expect("R5 loads");
        let controller = CoaController::new(scenario.initial_value());
        let explored = explore(&scenario, controller.clone(), Budget::Unbounded, u64::MAX);
        let search = Search::<CoaController>::initial(&scenario, controller);
        let enumerated = count_paths(&scenario, &search.states[0]);
        assert_eq!(explored.paths, Some(enumerated));
        assert!(enumerated > explored.states as u128, "paths merge in R5");
    }
}
