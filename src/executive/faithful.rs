//! Goal-faithful commands (DESIGN.md §9): what the executive checks of every command it issues,
//! what it remembers to do so ([`Faithful`]), and the two steps of the cycle that apply the
//! rules (`Executive::keep_faithful` on the planner's command, `Executive::restore_helpers` when
//! no goal is asserted).
//!
//! - **The intended configuration covers only what goals asked for.** While a goal is
//!   asserted, goal interpretation keeps every component the goal does not name where ŝ has it
//!   — not where an earlier goal state had it — unless it is a *helper*: a component the
//!   planner moved for a goal and has not yet brought back to its mode in the goal state (the
//!   PDE switched on for the engine's heating, to be switched off again). A component that
//!   changed by itself (a temperature, a payload that lost its supply, the end of a timed
//!   transition) is therefore never "restored" by a command no goal asked for. When no goal is
//!   asserted the planner only brings helpers back. For a mission, a state variable without an
//!   active XGoal is unconstrained (DESIGN.md §15.3), and after safing nothing but the safe
//!   network's goals commands: safing forgets the helpers.
//! - **No command leaves a mode an active goal requires.** An active goal (a conjunct of the
//!   configuration goal: an asserted RMPL goal or maintenance condition, or a dispatched
//!   XGoal's constraint) *requires* a component's mode when it holds in ŝ and would not hold
//!   with that component moved where the command sends it, every other component as ŝ has it.
//!   Such a command is withheld (the cycle idles) and reported `GoalContradicted`, once until
//!   it changes: a goal that holds is not broken to serve another. A goal that does not hold yet
//!   may pass through the move (reaching it is what the plan is for). The check reads goals
//!   over modes; a goal over attributes (`valve.flow = nominal`) is decided by the model, which
//!   the check does not consult, and is not checked here.
//! - **No chatter.** A component commanded back into a mode it was commanded out of within the
//!   last N cycles (N = [`ExecutiveOptions::chatter_cycles`](super::ExecutiveOptions), 10 by
//!   default), with no diagnosis in between, is reported `Chatter`. It is not withheld (the
//!   plant may need it), but it is a defect of the plan or of the model: every scenario fails on
//!   it unless it says it expects it. One return is the plan's own and no chatter: a helper's
//!   *excursion* — moved out of its mode in the intended configuration to serve another
//!   component's step, then brought back (§6.3.3: the PDE switched on to relay the engine's
//!   commands, off again once the engine fires). Leaving a mode *toward* the intended
//!   configuration and being commanded back is chatter: that is the planner undoing itself.
//!   Chatter is the executive working against itself for the same goals: a return commanded
//!   for another configuration goal than the move out (the program moved on to its next goal,
//!   a mission safed or re-elaborated) is the goals' change, not chatter.

use super::{EventKind, EventLog, Executive};
use crate::logic::{Atom, Formula, ValueId};
use crate::plant::{ComponentId, Plant};
use crate::reconfiguration::{Action, GoalState, PlanFailure};
use crate::sequencer::ConfigurationGoal;

/// A commanded move, remembered for the chatter check.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(super) struct CommandedMove {
    /// The cycle it was commanded in.
    pub cycle: u64,
    /// The component moved.
    pub component: ComponentId,
    /// The mode it was commanded out of.
    pub left: ValueId,
    /// True for a helper's excursion away from its intended mode.
    pub excursion: bool,
    /// The configuration goal it was commanded for, as text (`None` with none asserted).
    pub goal: Option<String>,
}

/// What the executive remembers between cycles to keep its commands goal-faithful.
#[derive(Debug, Clone, Default, Hash)]
pub(super) struct Faithful {
    /// Per component, the goal (as text) it was moved for as a helper, until it is back in its
    /// mode of the intended configuration; `None` for a component no plan moved away.
    pub helpers: Vec<Option<String>>,
    /// The recent commanded moves.
    pub commanded: Vec<CommandedMove>,
    /// The last contradiction reported (goal, command), so that a command withheld cycle after
    /// cycle is reported once.
    pub contradicted: Option<(String, Vec<String>)>,
    /// True when some entry of `helpers` is set: a quiet cycle (no helper out) skips every
    /// per-component loop here.
    any_helper: bool,
}

impl Faithful {
    /// A fresh record for a plant of `components` components.
    pub fn new(components: usize) -> Faithful {
        Faithful {
            helpers: vec![None; components],
            commanded: Vec::new(),
            contradicted: None,
            any_helper: false,
        }
    }

    /// The configuration goal interpretation keeps where the goal allows: a helper's mode in
    /// the intended configuration, ŝ for every other component.
    pub fn keep(&self, modes: &[ValueId], intended: Option<&[ValueId]>) -> Vec<ValueId> {
        let mut keep = modes.to_vec();
        if !self.any_helper {
            return keep;
        }
        if let Some(intended) = intended {
            for (c, helper) in self.helpers.iter().enumerate() {
                if helper.is_some() {
                    if let (Some(k), Some(&m)) = (keep.get_mut(c), intended.get(c)) {
                        *k = m;
                    }
                }
            }
        }
        keep
    }

    /// True when some helper is still away from its intended mode.
    pub fn has_helpers(&self) -> bool {
        self.any_helper
    }

    /// Forgets the helpers that are back in their intended modes.
    pub fn settle(&mut self, modes: &[ValueId], intended: &[ValueId]) {
        if !self.any_helper {
            return;
        }
        for ((helper, here), goal) in self.helpers.iter_mut().zip(modes).zip(intended) {
            if here == goal {
                *helper = None;
            }
        }
        self.any_helper = self.helpers.iter().any(Option::is_some);
    }

    /// Forgets every helper (safing: only the safe network commands from now on).
    pub fn forget_helpers(&mut self) {
        self.helpers.iter_mut().for_each(|h| *h = None);
        self.any_helper = false;
    }

    /// Remembers that `component`, commanded for `goal`, is a helper until it is back in its
    /// intended mode (a component the goal names is not a helper: it is where the goal wants
    /// it).
    pub fn moved(&mut self, component: ComponentId, goal: Option<String>, named: bool) {
        if named {
            return;
        }
        if let Some(slot) = self.helpers.get_mut(component.index()) {
            if slot.is_none() {
                *slot = goal;
            }
            self.any_helper |= slot.is_some();
        }
    }

    /// Records `moved` (a component commanded out of `moved.left`) and whether it chatters:
    /// the number of cycles since the component was commanded out of `to` for the same goal
    /// other than by an excursion, when that is within `window` cycles (see the module doc). A
    /// diagnosis in between ([`Faithful::diagnosed`]) clears the record.
    pub fn commanded(&mut self, moved: CommandedMove, to: ValueId, window: u64) -> Option<u64> {
        let cycle = moved.cycle;
        self.commanded
            .retain(|m| cycle.saturating_sub(m.cycle) <= window);
        let back = self
            .commanded
            .iter()
            .rev()
            .find(|m| {
                m.component == moved.component
                    && m.left == to
                    && !m.excursion
                    && m.goal == moved.goal
            })
            .map(|m| cycle - m.cycle);
        self.commanded.push(moved);
        back
    }

    /// A diagnosis: what was commanded before it is no chatter (the plan changed because ŝ did).
    pub fn diagnosed(&mut self) {
        self.commanded.clear();
    }
}

/// The executive's side of the invariants: bringing helpers back when no goal is asserted, and
/// checking each cycle's command.
impl Executive {
    /// With no goal asserted: the planner's action toward bringing the helpers back to their
    /// intended modes, every other component where ŝ has it; nothing to do without helpers.
    pub(super) fn restore_helpers(&self, modes: &[ValueId]) -> (Option<GoalState>, Option<Action>) {
        let Some(intended) = &self.intended else {
            return (None, None);
        };
        if !self.faithful.has_helpers() {
            return (Some(intended.clone()), Some(Action::Achieved));
        }
        let target = self.faithful.keep(modes, Some(intended.modes()));
        let target = GoalState::new(&self.plant, target, &[]);
        let action = self.reconfiguration.next_action(modes, &target);
        (Some(target), Some(action))
    }

    /// DESIGN.md §9's invariants on the cycle's command (the module doc): withheld, and reported
    /// `GoalContradicted`, when it leaves a mode an active goal requires; reported `Chatter`
    /// when it commands a component back into a mode it was commanded out of within N cycles
    /// with no diagnosis in between; a component it moves for a goal it does not name is
    /// remembered as a helper to bring back.
    pub(super) fn keep_faithful(
        &mut self,
        action: &mut Option<Action>,
        goal: Option<&ConfigurationGoal>,
        log: &mut EventLog,
    ) {
        if log
            .events
            .iter()
            .any(|e| matches!(e.kind, EventKind::Diagnosis { .. }))
        {
            self.faithful.diagnosed();
        }
        let Some(Action::Command(command)) = action.as_ref() else {
            self.faithful.contradicted = None;
            return;
        };
        let plant = &self.plant;
        let table = plant.table();
        let goals = active_goals(goal);
        let modes = &self.most_likely;
        if let Some(broken) = contradicted(plant, goals, modes, command.component, command.to) {
            let component = plant.component(command.component);
            let key = (
                broken.display(table).to_string(),
                (command.assignments.iter())
                    .map(|&(x, v)| table.assignment(x, v).to_string())
                    .collect::<Vec<_>>(),
            );
            if self.faithful.contradicted.as_ref() != Some(&key) {
                log.push(EventKind::GoalContradicted {
                    goal: key.0.clone(),
                    command: key.1.clone(),
                    component: command.component,
                    mode: component.mode(command.from).name.clone(),
                });
                self.faithful.contradicted = Some(key);
            }
            let reason = format!(
                "the command would move {} out of {}, which the goal {} requires",
                component.name(),
                component.mode(command.from).name,
                broken.display(table)
            );
            *action = Some(Action::Failure(PlanFailure {
                component: Some(command.component),
                reason,
            }));
            return;
        }
        self.faithful.contradicted = None;
        let (c, from, to) = (command.component, command.from, command.to);
        let window = self.options.chatter_cycles;
        let intended = self.intended.as_ref().map(|s| s.mode(c));
        let goal_text = goal.map(|g| g.formula.display(table).to_string());
        let moved = CommandedMove {
            cycle: log.cycle,
            component: c,
            left: from,
            excursion: command.serves != c && intended == Some(from),
            goal: goal_text.clone(),
        };
        if let Some(cycles) = self.faithful.commanded(moved, to, window) {
            log.push(EventKind::Chatter {
                component: c,
                mode: plant.component(c).mode(to).name.clone(),
                cycles,
            });
        }
        let named = self.intended.as_ref().is_some_and(|s| s.is_named(c)) || command.serves == c;
        let for_goal = goal_text.unwrap_or_else(|| {
            let served = plant.component(command.serves);
            let mode = intended.map_or(to, |_| {
                self.intended
                    .as_ref()
                    .map_or(to, |s| s.mode(command.serves))
            });
            format!("{} = {}", served.name(), served.mode(mode).name)
        });
        self.faithful.moved(c, Some(for_goal), named);
    }
}

/// The active goals of a cycle (DESIGN.md §9): the configuration goal's conjuncts as the
/// program asserted them, or, for a mission (whose goal has none listed), the top-level
/// conjuncts of its formula — one per active XGoal.
fn active_goals(goal: Option<&ConfigurationGoal>) -> Vec<&Formula> {
    fn split<'f>(formula: &'f Formula, out: &mut Vec<&'f Formula>) {
        match formula {
            Formula::And(parts) => parts.iter().for_each(|p| split(p, out)),
            Formula::True => {}
            other => out.push(other),
        }
    }
    let mut goals = Vec::new();
    if let Some(goal) = goal {
        if goal.conjuncts.is_empty() {
            split(&goal.formula, &mut goals);
        } else {
            goals.extend(goal.conjuncts.iter().map(|c| &c.formula));
        }
    }
    goals
}

/// The active goal among `goals` that moving `component` from its mode in `modes` to `to`
/// would break: one that holds in `modes` (decided by the modes alone) and would not hold after
/// the move (see the module doc).
pub(super) fn contradicted<'g>(
    plant: &Plant,
    goals: impl IntoIterator<Item = &'g Formula>,
    modes: &[ValueId],
    component: ComponentId,
    to: ValueId,
) -> Option<&'g Formula> {
    let before = |atom: &Atom| mode_atom(plant, modes, None, atom);
    let after = |atom: &Atom| mode_atom(plant, modes, Some((component, to)), atom);
    let var = plant.component(component).mode_var();
    goals.into_iter().find(|goal| {
        goal.variables().contains(&var)
            && goal.eval(&before) == Some(true)
            && goal.eval(&after) == Some(false)
    })
}

/// The truth of a mode atom in `modes` (with `moved` applied); `None` for any other atom.
fn mode_atom(
    plant: &Plant,
    modes: &[ValueId],
    moved: Option<(ComponentId, ValueId)>,
    atom: &Atom,
) -> Option<bool> {
    let Atom::Is(x, v) = *atom else {
        return None;
    };
    let c = plant.component_of(x)?;
    let mode = match moved {
        Some((m, to)) if m == c => to,
        _ => *modes.get(c.index())?,
    };
    Some(mode == v)
}

#[cfg(test)]
mod tests {
    use super::{CommandedMove, Faithful, contradicted};
    use crate::logic::{ValueId, parse_formula};
    use crate::plant::{ComponentId, Plant};
    use std::path::Path;

    fn thermostat() -> Plant {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/thermostat.ron");
        let text = std::fs::read_to_string(&path).expect("the thermostat model is shipped");
        let source = crate::diagnostic::Source::new(path.display().to_string(), text);
        Plant::load(&source).expect("the thermostat loads")
    }

    /// DESIGN.md §9: a command that leaves a mode a holding goal requires contradicts it; one
    /// within a disjunction the goal allows, or toward a goal not yet held, does not.
    #[test]
    fn a_holding_goal_requires_its_modes() {
        let plant = thermostat();
        let table = plant.table();
        let closed_open =
            parse_formula("switch1 = closed and switch2 = open", table).expect("goal");
        let warm =
            parse_formula("temperature = warm-low or temperature = warm", table).expect("goal");
        let mode = |c: &str, m: &str| {
            let id = plant.component_named(c).expect("component");
            (id, plant.component(id).mode_named(m).expect("mode"))
        };
        let state = |pairs: &[(&str, &str)]| -> Vec<ValueId> {
            let mut s = vec![ValueId(0); plant.components().len()];
            for (c, m) in pairs {
                let (id, v) = mode(c, m);
                s[id.index()] = v;
            }
            s
        };
        let holding = state(&[
            ("switch1", "closed"),
            ("switch2", "open"),
            ("temperature", "warm-low"),
        ]);
        let goals = [closed_open.clone(), warm.clone()];
        let (s1, open) = mode("switch1", "open");
        assert_eq!(
            contradicted(&plant, &goals, &holding, s1, open),
            Some(&closed_open)
        );
        let (t, w) = mode("temperature", "warm");
        assert_eq!(contradicted(&plant, &goals, &holding, t, w), None);
        let reaching = state(&[("switch1", "open"), ("switch2", "closed")]);
        let (s2, open2) = mode("switch2", "open");
        assert_eq!(contradicted(&plant, &goals, &reaching, s2, open2), None);
    }

    /// A component commanded back into the mode it left within the window is chatter; after a
    /// diagnosis, past the window, or after a helper's excursion, it is not.
    #[test]
    fn chatter_is_a_return_within_the_window() {
        let mut faithful = Faithful::new(2);
        let c = ComponentId(0);
        let (a, b) = (ValueId(0), ValueId(1));
        let goal = Some("g".to_string());
        let at = |faithful: &mut Faithful, cycle, left, to, excursion, goal: &Option<String>| {
            let moved = CommandedMove {
                cycle,
                component: c,
                left,
                excursion,
                goal: goal.clone(),
            };
            faithful.commanded(moved, to, 10)
        };
        assert_eq!(at(&mut faithful, 1, a, b, false, &goal), None);
        assert_eq!(at(&mut faithful, 4, b, a, false, &goal), Some(3));
        faithful.diagnosed();
        assert_eq!(at(&mut faithful, 5, a, b, false, &goal), None);
        assert_eq!(at(&mut faithful, 20, b, a, false, &goal), None);
        // A helper's excursion and its return: the plan's own.
        assert_eq!(at(&mut faithful, 31, a, b, true, &goal), None);
        assert_eq!(at(&mut faithful, 34, b, a, false, &goal), None);
        // Back for another goal: the goals changed.
        assert_eq!(at(&mut faithful, 45, a, b, false, &goal), None);
        assert_eq!(
            at(&mut faithful, 46, b, a, false, &Some("h".to_string())),
            None
        );
    }
}
