//! The reactive planner (§6.3.2, §6.3.3; Williams & Nayak 1997): given the current modes and
//! the goal state, the *first* control action toward it, computed from the compiled concurrent
//! policies in time that does not depend on the model's size beyond a walk over its components.
//!
//! Goals are achieved serially, most downstream component first (the causal graph's depth
//! order), so that components upstream — the PDE that relays the engine's commands — are
//! returned to their own goal mode last. For a component not in its goal mode, the policy names
//! the next step; its sub-goals on upstream components are achieved first, again downstream
//! first and depth first through their own policies; once they all hold the step's command is
//! issued, or, when the step needs no command (a timed transition), the planner waits
//! (**Idle**) — and meanwhile serves the goals of components the awaited transition does not
//! depend on (neither the waiting component, nor a component or control its guard reads), so
//! that a 20 s attitude slew does not hold up the propulsion controller's mode switch, while
//! the PDE, which relays the heating engine's command, still waits for the engine. A step that leaves a mode's reversible region is taken only toward the
//! component's goal mode and only when the configuration goal named it; repairs out of fault
//! modes are ordinary steps of the policies.

use super::Reconfiguration;
use super::goal::{GoalState, check_state};
use super::policy::{ConcurrentPolicy, PolicyEntry, PolicyStep};
use super::requirement::Requirement;
use crate::logic::{ValueId, VarId};
use crate::plant::{Commands, ComponentId, InputError, ModeKind, Plant, TransitionLaw};

/// A command toward the goal: control assignments for this cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct Command {
    /// The controls to set (non-idle values); every other control stays at its idle value.
    pub assignments: Vec<(VarId, ValueId)>,
    /// The component whose transition the command is meant to cause.
    pub component: ComponentId,
    /// That transition, by index into the component's transitions.
    pub transition: usize,
    /// The component's mode now.
    pub from: ValueId,
    /// The mode the command should bring it to.
    pub to: ValueId,
    /// True when the transition leaves a fault mode.
    pub repair: bool,
    /// The component whose goal mode the command is a step toward: the goal the planner's
    /// descent started from (`engine` for the PDE's `on` that the engine's heating needs), the
    /// commanded component itself when the step is its own.
    pub serves: ComponentId,
}

/// A wait: no command this cycle, because the next step happens by itself (§6.3.3).
#[derive(Debug, Clone, PartialEq)]
pub struct Wait {
    /// The component whose transition is awaited.
    pub component: ComponentId,
    /// That transition, by index into the component's transitions.
    pub transition: usize,
    /// The component's mode now.
    pub from: ValueId,
    /// The mode it is expected to reach.
    pub to: ValueId,
    /// When the transition fires: its window on the component clock for a timed transition.
    pub law: TransitionLaw,
}

/// Why the planner has no action: no compiled policy leads to the goal from here.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanFailure {
    /// The component that cannot be moved, when one is to blame.
    pub component: Option<ComponentId>,
    /// A sentence naming it, its mode and the mode it should reach.
    pub reason: String,
}

/// The reactive planner's answer for one cycle.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Issue these control assignments.
    Command(Command),
    /// Issue nothing (every control idle) and wait for a transition that happens by itself.
    Idle(Wait),
    /// Every component is in its goal mode; every control idle.
    Achieved,
    /// No policy applies (a component in a fault mode without repair, an irreversible step the
    /// goal did not name, a circular requirement).
    Failure(PlanFailure),
}

impl Action {
    /// The full control action μ for the cycle: the command's assignments, idle elsewhere.
    pub fn commands(&self, plant: &Plant) -> Result<Commands, InputError> {
        match self {
            Action::Command(command) => Commands::new(plant, &command.assignments),
            _ => Ok(Commands::idle(plant)),
        }
    }

    /// What to do, for a person: `command PDE.cmd = on`, `command PDE.cmd = reset (repair)`,
    /// `wait, after Uniform(30, 60) s`, `goal achieved`, `no action: ...`.
    pub fn summary(&self, plant: &Plant) -> String {
        match self {
            Action::Command(command) => {
                let table = plant.table();
                let assignments: Vec<String> = command
                    .assignments
                    .iter()
                    .map(|&(x, v)| table.assignment(x, v).to_string())
                    .collect();
                let repair = if command.repair { " (repair)" } else { "" };
                format!("command {}{repair}", assignments.join(", "))
            }
            Action::Idle(wait) => format!("wait, {}", wait.law),
            Action::Achieved => "goal achieved".to_string(),
            Action::Failure(failure) => format!("no action: {}", failure.reason),
        }
    }

    /// The transition a command or a wait is for: `(component, from, to)`.
    pub fn intended(&self) -> Option<(ComponentId, ValueId, ValueId)> {
        match self {
            Action::Command(c) => Some((c.component, c.from, c.to)),
            Action::Idle(w) => Some((w.component, w.from, w.to)),
            Action::Achieved | Action::Failure(_) => None,
        }
    }

    /// The summary with the transition it is for: `command PDE.cmd = on (PDE: off -> on)`.
    pub fn describe(&self, plant: &Plant) -> String {
        let summary = self.summary(plant);
        match self.intended() {
            Some((c, from, to)) => {
                let component = plant.component(c);
                format!(
                    "{summary} ({}: {} -> {})",
                    component.name(),
                    component.mode(from).name,
                    component.mode(to).name
                )
            }
            None => summary,
        }
    }
}

/// The reactive planner; see [`Reconfiguration::next_action`].
///
/// Goals are served in the causal graph's downstream-first order; each cycle the first goal
/// not yet reached that can act, acts. A goal's *descent* (the chain of steps and sub-goals
/// down to the component that acts, see [`Progress`]) makes progress when it acts, and nothing
/// else may undo it: a descent that waits on a transition that happens by itself, or whose
/// command is held back, *reserves* for the rest of the cycle every component and control it
/// relies on ([`Reservation`]), and a later goal is served only with a command that touches
/// none of them. Serving a later goal with a component a held-back descent had already moved —
/// a helper it needs in a sub-goal mode — made the planner undo and redo the same step forever
/// (the livelock once seen: `c1` commanded `m3 → m1` for the first goal, then back `m1 → m3`
/// toward its own goal during the first goal's wait).
pub(crate) fn next_action(
    reconfiguration: &Reconfiguration,
    current: &[ValueId],
    goal: &GoalState,
) -> Action {
    let plant = reconfiguration.plant();
    if let Err(reason) = check_state(plant, current).and_then(|()| check_state(plant, goal.modes()))
    {
        return Action::Failure(PlanFailure {
            component: None,
            reason,
        });
    }
    let mut planner = Planner::new(reconfiguration, current, goal);
    // The first wait met, and what the held-back descents rely on.
    let mut wait: Option<Wait> = None;
    let mut reserved = Reservation::default();
    for &c in reconfiguration.causal_graph().downstream_first() {
        let target = goal.mode(c);
        if current[c.index()] == target {
            continue;
        }
        match planner.descend(c, target) {
            Action::Idle(next) => {
                reserved.add(reconfiguration, &planner.trail, Some((&next, current)));
                wait.get_or_insert(next);
            }
            // While a transition that happens by itself is awaited, goals that need none of
            // what the held-back descents rely on go on (the program's concurrent threads, e.g.
            // §7.2.3's landing slew and gravity turn); anything else is held back too.
            Action::Command(command) if wait.is_none() || reserved.allows(&command) => {
                return Action::Command(Command {
                    serves: c,
                    ..command
                });
            }
            Action::Command(_) => reserved.add(reconfiguration, &planner.trail, None),
            action if wait.is_none() => return action,
            _ => {}
        }
    }
    wait.map_or(Action::Achieved, Action::Idle)
}

/// The planner's measure of progress toward a goal state, smaller is closer.
///
/// One *descent* per component, in the causal graph's downstream-first order: empty when the
/// component is in its goal mode; otherwise the descent the planner walks for it — the
/// component's distance along its compiled policy to its goal mode, then the rank of the way
/// chosen for its next step (faulty, undone, pending, order: see `Rank`; *pending* is the
/// number of that way's sub-goals still to achieve, from the first unmet one in the planner's
/// order), then that sub-goal's component's distance to the sub-goal mode, and so on down to
/// the component that acts or waits. Descents compare lexicographically, and the list of them
/// too.
///
/// Under nominal execution the measure strictly decreases every cycle, so the planner cannot
/// livelock:
/// - the goal that acts is the first one whose command is not held back, so every descent
///   before it waits or is held back, and reserves what it reads: those stay as they are;
/// - its own descent decreases: the acting component moves one step along a shortest policy
///   path (its distance drops by one), and when it reaches a sub-goal the earlier sub-goals of
///   the same step stay met (they are more downstream, so achieving it cannot move them) and
///   the pending count drops;
/// - a cycle that only waits lets the first awaited transition happen, which is the first
///   descent's own next step;
/// - with several ways to take a step (DESIGN.md §9, redundancy) the planner takes the least
///   rank, which is part of the measure: no fault appears under nominal execution (a repair
///   only clears one), *undone* is fixed by the goal state, and the chosen way's *pending*
///   does not grow (above). So the least rank at a level never grows, and it changes only
///   when another way's rank falls below it — a strict decrease at that level, whatever
///   happens below it. While it stays the same the same way is chosen (the order is part of
///   the rank) and the argument above applies to it. (The ways considered are those whose
///   sub-goals can be achieved from ŝ; under nominal execution components move within their
///   reversible regions, which is what decides that, so the set does not change either.)
///
/// Goals reached stay reached: a descent moves only its component and what is upstream of it,
/// never a component earlier in the order.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Progress {
    /// Per component in downstream-first order: distance, the chosen way's rank (faulty,
    /// undone, pending, order), distance, rank, ..., distance; empty when the component is in
    /// its goal mode.
    pub descents: Vec<Vec<usize>>,
}

/// The measure of progress of `current` toward `goal`; see [`Progress`].
pub(crate) fn progress(
    reconfiguration: &Reconfiguration,
    current: &[ValueId],
    goal: &GoalState,
) -> Progress {
    let mut planner = Planner::new(reconfiguration, current, goal);
    let descents = reconfiguration
        .causal_graph()
        .downstream_first()
        .iter()
        .map(|&c| {
            let target = goal.mode(c);
            if current[c.index()] == target {
                return Vec::new();
            }
            planner.descend(c, target);
            planner
                .trail
                .iter()
                .flat_map(|link| {
                    let rank = link
                        .rank
                        .map(|r| [usize::from(r.faulty), r.undone, r.pending, r.order]);
                    std::iter::once(link.distance).chain(rank.into_iter().flatten())
                })
                .collect()
        })
        .collect();
    Progress { descents }
}

/// What the held-back descents of a cycle rely on: the components on their chains, the
/// sub-goal components of every step on them (met or not), and, for a wait, whatever the
/// awaited guard reads and the sub-goal components of every later step of the waiting chain's
/// ways to their targets (a helper already where a later step needs it, moved meanwhile for a
/// later goal into a mode it cannot come back from, would leave the waiting goal no way on).
/// A later goal is served meanwhile only by a command that touches none of it.
#[derive(Debug, Default)]
struct Reservation {
    components: Vec<ComponentId>,
    controls: Vec<VarId>,
}

impl Reservation {
    fn add(
        &mut self,
        reconfiguration: &Reconfiguration,
        trail: &[Link],
        wait: Option<(&Wait, &[ValueId])>,
    ) {
        for link in trail {
            self.components.push(link.component);
            self.components
                .extend(link.sub_goals.iter().map(|&(u, _)| u));
        }
        if let Some((wait, current)) = wait {
            for link in trail {
                let policy = reconfiguration.policy(link.component);
                let components = &mut self.components;
                policy.walk(current[link.component.index()], link.target, |step| {
                    for (_, requirement) in policy.candidates_between(step.source, step.target) {
                        components.extend(requirement.modes.iter().map(|&(u, _)| u));
                    }
                    true
                });
            }
            self.components.push(wait.component);
            let guard = reconfiguration.guard_dependencies(wait.component, wait.transition);
            self.components.extend(&guard.modes);
            self.controls.extend(&guard.controls);
        }
    }

    /// True when `command` moves no reserved component and sets no reserved control.
    fn allows(&self, command: &Command) -> bool {
        !self.components.contains(&command.component)
            && command
                .assignments
                .iter()
                .all(|(x, _)| !self.controls.contains(x))
    }
}

/// How a candidate way of taking a move ranks (see [`Planner::choose`]); smaller first, member
/// by member. Part of the measure of progress ([`Progress`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Rank {
    /// Some unmet sub-goal's component is in a fault mode (it needs a repair).
    faulty: bool,
    /// Sub-goals the goal state wants elsewhere (they would be undone after the move).
    undone: usize,
    /// Sub-goals still to achieve, from the first unmet one on, in the planner's order.
    pending: usize,
    /// The candidate's position among the move's candidates (compiled, cheapest first).
    order: usize,
}

/// How many sub-goals of `requirement`, from the first unmet one in `current` on, are still to
/// achieve.
fn pending(requirement: &Requirement, current: &[ValueId]) -> usize {
    requirement
        .unmet(current)
        .next()
        .map_or(0, |(i, _)| requirement.modes.len() - i)
}

/// One level of a descent: a component on its way to a target, and its next step's
/// sub-goals.
#[derive(Debug)]
struct Link {
    component: ComponentId,
    /// The mode the descent wants it in.
    target: ValueId,
    /// Steps along the component's policy to its target.
    distance: usize,
    /// The next step's sub-goals, in the planner's order.
    sub_goals: Vec<(ComponentId, ValueId)>,
    /// How the way chosen for the next step ranked among the step's candidates ([`Rank`]: its
    /// last-but-one member is how many of its sub-goals, from the first unmet one on, are still
    /// to achieve); `None` when the descent stopped at this level without looking at the step:
    /// a failure.
    rank: Option<Rank>,
}

/// One cycle's depth-first descent through the policies.
struct Planner<'a> {
    reconfiguration: &'a Reconfiguration,
    current: &'a [ValueId],
    goal: &'a GoalState,
    /// The levels of the current descent, from its root (to catch cycles and to measure it).
    trail: Vec<Link>,
    /// Whether a component can be brought to a mode from ŝ, as found this cycle (filled only
    /// for moves with several candidates; a few entries, so a list: a quiet cycle builds
    /// nothing).
    usable: Vec<((ComponentId, ValueId), bool)>,
}

impl<'a> Planner<'a> {
    fn new(
        reconfiguration: &'a Reconfiguration,
        current: &'a [ValueId],
        goal: &'a GoalState,
    ) -> Self {
        Planner {
            reconfiguration,
            current,
            goal,
            trail: Vec::new(),
            usable: Vec::new(),
        }
    }

    /// A fresh descent toward `c = target`; its levels are left in `trail`.
    fn descend(&mut self, c: ComponentId, target: ValueId) -> Action {
        self.trail.clear();
        self.achieve(c, target)
    }

    /// The first action toward `c = target` (`c` is not there yet): down the chain of unmet
    /// sub-goals (a loop, not recursion: a chain may be as long as the plant) to the component
    /// that can act.
    fn achieve(&mut self, mut c: ComponentId, mut target: ValueId) -> Action {
        loop {
            if self.trail.iter().any(|link| link.component == c) {
                return self.fail(
                    c,
                    target,
                    "its own step needs it elsewhere (a circular requirement)",
                );
            }
            let here = self.current[c.index()];
            let reconfiguration = self.reconfiguration;
            let policy = reconfiguration.policy(c);
            let (step_index, irreversible) = match policy.entry(here, target) {
                PolicyEntry::Next { step, irreversible } => (step, irreversible),
                PolicyEntry::Stay => return Action::Achieved,
                PolicyEntry::Failure => {
                    return self.fail(c, target, "no plannable path leads there");
                }
            };
            let step = &policy.steps()[step_index];
            let mut link = Link {
                component: c,
                target,
                distance: policy.distance(here, target).unwrap_or(usize::MAX),
                sub_goals: Vec::new(),
                rank: None,
            };
            let explicit = self.goal.mode(c) == target && self.goal.is_named(c);
            let chosen = match &step.requirement {
                _ if irreversible && !explicit => Err(
                    "the step would be irreversible and the goal does not name the target"
                        .to_string(),
                ),
                Ok(_) => self.choose(policy, step_index),
                Err(_) => Err("the next step's guard cannot be established".to_string()),
            };
            let (step, requirement, rank) = match chosen {
                Ok(chosen) => chosen,
                Err(why) => {
                    self.trail.push(link);
                    return self.fail(c, target, &why);
                }
            };
            // Sub-goals are stored most downstream first (see `Reconfiguration::compile`).
            let unmet = requirement.unmet(self.current).next().map(|(i, _)| i);
            link.sub_goals.clone_from(&requirement.modes);
            link.rank = Some(rank);
            self.trail.push(link);
            match unmet {
                Some(i) => (c, target) = requirement.modes[i],
                None => return self.act(c, step, requirement),
            }
        }
    }

    /// The way to take the move `step` names (DESIGN.md §9, redundancy): of its candidates (the
    /// transitions between the two modes and each one's alternative requirements), those whose
    /// unmet sub-goals can all be achieved from ŝ; among them the least [`Rank`]: no component
    /// ŝ believes faulty, then the fewest sub-goals the goal state wants elsewhere (each would
    /// be undone after the move), then the fewest sub-goals still to achieve, then the first
    /// compiled (cheapest). The choice depends only on ŝ and the goal state, and it changes only
    /// to a candidate of smaller rank (see [`Progress`]): the planner never switches back to
    /// undo a step of its own plan. A move with one candidate is taken as it is (its sub-goals
    /// fail on their own if they must).
    fn choose(
        &mut self,
        policy: &'a ConcurrentPolicy,
        step: usize,
    ) -> Result<(&'a PolicyStep, &'a Requirement, Rank), String> {
        let steps = policy.steps();
        let current = self.current;
        let goal = self.goal;
        let mut candidates = policy.candidates(step);
        let Some(first) = candidates.next() else {
            return Err("the next step's guard cannot be established".to_string());
        };
        if candidates.next().is_none() {
            let rank = Rank {
                faulty: false,
                undone: 0,
                pending: pending(first.1, current),
                order: 0,
            };
            return Ok((&steps[first.0], first.1, rank));
        }
        let mut best: Option<(Rank, usize, &'a Requirement)> = None;
        for (order, (i, requirement)) in policy.candidates(step).enumerate() {
            // Sub-goals the goal state wants elsewhere would be undone once the move is made:
            // the planner prefers the way that leaves every helper where the goal state has it.
            let undone = requirement
                .modes
                .iter()
                .filter(|&&(u, v)| !requirement.is_met(u, v, goal.mode(u)))
                .count();
            let mut faulty = false;
            let mut usable = true;
            for (_, (u, v)) in requirement.unmet(current) {
                faulty |= self.is_faulty(u);
                if !self.usable(u, v, 0) {
                    usable = false;
                    break;
                }
            }
            let rank = Rank {
                faulty,
                undone,
                pending: pending(requirement, current),
                order,
            };
            if usable && best.as_ref().is_none_or(|(b, ..)| rank < *b) {
                best = Some((rank, i, requirement));
            }
        }
        match best {
            Some((rank, i, requirement)) => Ok((&steps[i], requirement, rank)),
            None => Err(self.no_candidate(policy, step)),
        }
    }

    /// True when ŝ has `u` in a fault mode.
    fn is_faulty(&self, u: ComponentId) -> bool {
        let component = self.reconfiguration.plant().component(u);
        component.mode(self.current[u.index()]).kind == ModeKind::Fault
    }

    /// True when the planner can bring `u` to `v` from ŝ: every move on its policy's path has a
    /// candidate whose unmet sub-goals can be achieved in turn (a circular need cannot).
    fn usable(&mut self, u: ComponentId, v: ValueId, depth: usize) -> bool {
        if let Some(&(_, known)) = self.usable.iter().find(|(key, _)| *key == (u, v)) {
            return known;
        }
        if depth > self.current.len() {
            return false;
        }
        // Provisionally unusable: a need that comes back round to `u = v` cannot be met.
        self.usable.push(((u, v), false));
        let slot = self.usable.len() - 1;
        let reconfiguration = self.reconfiguration;
        let policy = reconfiguration.policy(u);
        let current = self.current;
        let ok = policy
            .walk(current[u.index()], v, |step| {
                policy
                    .candidates_between(step.source, step.target)
                    .any(|(_, requirement)| {
                        requirement
                            .unmet(current)
                            .all(|(_, (w, m))| w != u && self.usable(w, m, depth + 1))
                    })
            })
            .is_some();
        self.usable[slot].1 = ok;
        ok
    }

    /// Why no candidate of the move `step` names can be used: each alternative with the
    /// sub-goals it cannot have.
    fn no_candidate(&mut self, policy: &'a ConcurrentPolicy, step: usize) -> String {
        let reconfiguration = self.reconfiguration;
        let plant = reconfiguration.plant();
        let current = self.current;
        let mut ways = Vec::new();
        for (_, requirement) in policy.candidates(step) {
            let blocked: Vec<String> = requirement
                .unmet(current)
                .filter(|&(_, (u, v))| !self.usable(u, v, 0))
                .map(|(_, (u, v))| {
                    let component = plant.component(u);
                    format!(
                        "{} = {} ({} is {})",
                        component.name(),
                        component.mode(v).name,
                        component.name(),
                        component.mode(current[u.index()]).name
                    )
                })
                .collect();
            if !blocked.is_empty() && !ways.contains(&blocked.join(" and ")) {
                ways.push(blocked.join(" and "));
            }
        }
        format!("no way to establish its guard: {}", ways.join(", or "))
    }

    /// The step's command, or a wait when it needs none.
    fn act(&self, c: ComponentId, step: &PolicyStep, requirement: &Requirement) -> Action {
        let plant = self.reconfiguration.plant();
        if requirement.is_idle() {
            return Action::Idle(Wait {
                component: c,
                transition: step.transition,
                from: step.source,
                to: step.target,
                law: plant.component(c).transitions()[step.transition].law,
            });
        }
        Action::Command(Command {
            assignments: requirement.controls.clone(),
            component: c,
            transition: step.transition,
            from: step.source,
            to: step.target,
            repair: step.repair,
            serves: c,
        })
    }

    fn fail(&self, c: ComponentId, target: ValueId, why: &str) -> Action {
        let component = self.reconfiguration.plant().component(c);
        Action::Failure(PlanFailure {
            component: Some(c),
            reason: format!(
                "{} cannot be moved from {} to {}: {why}",
                component.name(),
                component.mode(self.current[c.index()]).name,
                component.mode(target).name
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{DEADLOCK, SWITCH_GADGET, component, load, state};
    use super::super::{GoalState, PlanOutcome, Reconfiguration};
    use super::Action;

    #[test]
    fn a_circular_requirement_is_a_failure_not_a_stack_overflow() {
        let plant = load(DEADLOCK);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        assert!(!reconfiguration.causal_graph().is_acyclic());
        let goal = GoalState::new(&plant, state(&plant, &["y", "x"]), &[]);
        let Action::Failure(failure) =
            reconfiguration.next_action(&state(&plant, &["x", "x"]), &goal)
        else {
            panic!("no action");
        };
        assert_eq!(failure.component, Some(component(&plant, "p")));
        assert!(failure.reason.contains("circular"), "{}", failure.reason);
    }

    #[test]
    fn a_named_irreversible_goal_is_reached_and_helpers_restored_last() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let mut theory = plant.theory().expect("theory");
        let start = state(&plant, &["off", "e"]);
        let gadget = component(&plant, "gadget");
        let goal = GoalState::new(&plant, state(&plant, &["off", "c"]), &[gadget]);
        let run = reconfiguration
            .simulate_nominal(&mut theory, &start, &goal, 10)
            .expect("simulates");
        assert_eq!(run.outcome, PlanOutcome::Achieved);
        let actions: Vec<String> = run
            .steps
            .iter()
            .map(|s| s.action.describe(&plant))
            .collect();
        assert_eq!(
            actions,
            [
                "command gadget.cmd = go-a (gadget: e -> a)",
                "command switch.cmd = on (switch: off -> on)",
                "command gadget.cmd = go-b (gadget: a -> b)",
                "command gadget.cmd = go-c (gadget: b -> c)",
                "command switch.cmd = off (switch: on -> off)",
            ]
        );
        let cut = reconfiguration
            .simulate_nominal(&mut theory, &start, &goal, 2)
            .expect("simulates");
        assert_eq!(cut.outcome, PlanOutcome::StepLimit);
        assert_eq!(cut.steps.len(), 2);
    }

    #[test]
    fn waits_name_the_awaited_transition() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let goal = GoalState::new(&plant, state(&plant, &["off", "e"]), &[]);
        let action = reconfiguration.next_action(&state(&plant, &["off", "a"]), &goal);
        assert_eq!(
            action.describe(&plant),
            "wait, after Uniform(1, 2) s (gadget: a -> e)"
        );
        assert_eq!(
            action.commands(&plant).expect("commands"),
            crate::plant::Commands::idle(&plant)
        );
    }
}
