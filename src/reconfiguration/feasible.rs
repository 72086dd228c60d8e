//! The modes goal interpretation may choose for each component, given the current state
//! (§6.3.1's "reachable modes", made sound for the reactive planner).
//!
//! [`Reachability`](super::Reachability) is a property of one component's automaton; whether
//! the planner can actually follow its policy also depends on the components upstream: a step
//! whose guard needs `PDE = on` is of no use while the PDE is failed. So, upstream first (in
//! the causal graph's order), each component gets its set of **helper modes**: the modes of its
//! reversible region that its policy reaches from the current mode, and between which it can
//! move back and forth, every step's sub-goals being helper modes of their components. A mode
//! the planner may be asked to hold as a sub-goal is always a helper mode, so the planner never
//! meets a sub-goal it cannot achieve.
//!
//! - A component in a fault mode with a feasible repair must be repaired: its fault mode is not
//!   a helper mode (it could not be returned to once the component has been used). Nor are the
//!   repair modes the repair passes through ([`Reachability`](super::Reachability)), when it
//!   reaches modes of the nominal envelope: the component is moved on to one of those.
//! - A mode of the irreversible frontier is **feasible as a final goal** when the policy reaches
//!   it from every helper mode; goal interpretation offers it only when the configuration goal
//!   names it. So is a mode the policy reaches from the current one and from every helper mode
//!   but cannot leave again with the components upstream as they are (a load kept powered by a
//!   supply stuck on: the way back needs the supply off). From every helper mode, because the
//!   planner may first move the component as a helper for a step downstream (to a mode from
//!   which the policy's way to the final mode needs an upstream mode that cannot be had).
//! - Within a causal unit (a cycle of influence), a sub-goal on a component not yet computed is
//!   trusted only when that component is already in the mode needed (conservative).
//! - A move with several candidates (transitions between the same two modes, alternative
//!   requirements of a guard: DESIGN.md §9, redundancy) is possible when one of them is: a bus
//!   fed by regulator A or B stays reachable while either regulator can be switched on. A
//!   sub-goal is met by a helper mode of its component that is the sub-goal's mode or serves
//!   as well (a switch stuck open, whose only helper mode is that fault, serves `open`). A
//!   blocked move keeps, per candidate, what it lacks, for the goal failure's reason.

use super::policy::{ConcurrentPolicy, PolicyStep};
use super::reachability::members;
use super::requirement::Requirement;
use crate::logic::ValueId;
use crate::plant::{ComponentId, ModeKind, Plant};

/// Per component, the modes goal interpretation may choose.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Feasible {
    /// `helpers[c][v]`: `c` can be moved to `v` and back, as goal or as sub-goal.
    pub helpers: Vec<Vec<bool>>,
    /// `finals[c][v]`: `v` is an irreversible target the policy reaches from every helper mode.
    pub finals: Vec<Vec<bool>>,
    /// Components whose helper modes limited each component's (the causes of a restriction).
    pub blocked_by: Vec<Vec<ComponentId>>,
    /// Per component, the moves it could not make: each with, per alternative way of making it
    /// (DESIGN.md §9, redundancy), the sub-goals that cannot be had.
    pub blocked_moves: Vec<Vec<BlockedMove>>,
}

/// A move of a component that no alternative makes possible from the current state.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct BlockedMove {
    /// The mode it would leave.
    pub source: ValueId,
    /// The mode it would enter.
    pub target: ValueId,
    /// Per alternative, the sub-goals on components upstream that cannot be achieved.
    pub alternatives: Vec<Vec<(ComponentId, ValueId)>>,
}

/// Computes the feasible modes for the state `current` (one mode per component).
pub(crate) fn feasible(
    plant: &Plant,
    policies: &[ConcurrentPolicy],
    upstream_first: &[ComponentId],
    current: &[ValueId],
) -> Feasible {
    let n = current.len();
    let mut state = Feasible {
        helpers: vec![Vec::new(); n],
        finals: vec![Vec::new(); n],
        blocked_by: vec![Vec::new(); n],
        blocked_moves: vec![Vec::new(); n],
    };
    for &c in upstream_first {
        let policy = &policies[c.index()];
        let kinds: Vec<ModeKind> = plant.component(c).modes().iter().map(|m| m.kind).collect();
        let (helpers, finals, blocked, moves) = {
            let mut walker = Walker {
                policy,
                state: &state,
                current,
                blocked: Vec::new(),
                moves: Vec::new(),
            };
            let (helpers, one_way) = walker.helpers(current[c.index()], &kinds);
            let mut finals = walker.finals(current[c.index()], &helpers);
            // As for the irreversible frontier, from every helper mode too: the planner may move
            // the component as a helper for a step downstream before it heads there.
            for v in one_way {
                finals[v.index()] |= members(&helpers).all(|h| walker.reaches(h, v));
            }
            (helpers, finals, walker.blocked, walker.moves)
        };
        state.helpers[c.index()] = helpers;
        state.finals[c.index()] = finals;
        state.blocked_by[c.index()] = blocked;
        state.blocked_moves[c.index()] = moves;
    }
    state
}

/// Walks one component's policy against the helper modes computed so far.
struct Walker<'a> {
    policy: &'a ConcurrentPolicy,
    state: &'a Feasible,
    current: &'a [ValueId],
    blocked: Vec<ComponentId>,
    moves: Vec<BlockedMove>,
}

impl Walker<'_> {
    /// Some candidate of the move `step` makes (a transition between its two modes, with one
    /// of its alternative requirements) has every sub-goal met in the current state or
    /// achievable; otherwise the move is recorded as blocked, with what each candidate lacks.
    fn step_ok(&mut self, step: &PolicyStep) -> bool {
        let mut lacking = Vec::new();
        for (_, requirement) in self.policy.candidates_between(step.source, step.target) {
            let missing: Vec<(ComponentId, ValueId)> = requirement
                .modes
                .iter()
                .copied()
                .filter(|&(u, v)| !self.achievable(requirement, u, v))
                .collect();
            if missing.is_empty() {
                return true;
            }
            if !lacking.contains(&missing) {
                lacking.push(missing);
            }
        }
        for &(u, _) in lacking.iter().flatten() {
            if !self.blocked.contains(&u) {
                self.blocked.push(u);
            }
        }
        let known = self
            .moves
            .iter()
            .any(|m| m.source == step.source && m.target == step.target);
        if !known && !lacking.is_empty() {
            self.moves.push(BlockedMove {
                source: step.source,
                target: step.target,
                alternatives: lacking,
            });
        }
        false
    }

    /// The sub-goal `u = v` of `requirement` can be had: some helper mode of `u` meets it (`v`,
    /// or a mode that serves as well — a switch stuck open, its only helper mode, for `open`).
    /// A component not computed yet (within a causal unit) is trusted only where it is now.
    fn achievable(&self, requirement: &Requirement, u: ComponentId, v: ValueId) -> bool {
        let helpers = &self.state.helpers[u.index()];
        if helpers.is_empty() {
            return requirement.is_met(u, v, self.current[u.index()]);
        }
        members(helpers).any(|w| requirement.is_met(u, v, w))
    }

    /// The planner reaches `to` from `from` by following the policy.
    fn reaches(&mut self, from: ValueId, to: ValueId) -> bool {
        let policy = self.policy;
        policy.walk(from, to, |step| self.step_ok(step)).is_some()
    }

    /// The helper modes, and the modes the policy reaches from `current` that it cannot come
    /// back from with the components upstream as they are (a load that a supply stuck on keeps
    /// powered): feasible as a final goal, which goal interpretation offers when the goal names
    /// it, but no helper.
    fn helpers(&mut self, current: ValueId, kinds: &[ModeKind]) -> (Vec<bool>, Vec<ValueId>) {
        let n = kinds.len();
        let reachability = self.policy.reachability();
        let mut set = vec![false; n];
        for t in reachability.reversible(current) {
            set[t.index()] = self.reaches(current, t);
        }
        // A component on its way through a repair is moved on to where it can stay: of the
        // modes reached, only the most nominal kind is kept — modes of the nominal envelope,
        // else repair modes, else the fault itself. Neither a fault nor a repair mode could be
        // returned to after a repair, so they cannot be helper modes next to the modes it
        // restores; keeping them would let pruning drop those instead.
        let rank = |v: usize| match kinds[v] {
            ModeKind::Fault => 0,
            _ if reachability.is_repair_mode(ValueId(v as u32)) => 1,
            _ => 2,
        };
        let best = (0..n).filter(|&v| set[v]).map(rank).max();
        for (v, member) in set.iter_mut().enumerate() {
            *member &= Some(rank(v)) == best;
        }
        let anchor = set[current.index()].then_some(current);
        let reached = set.clone();
        self.prune(&mut set, anchor);
        let one_way = members(&reached)
            .filter(|v| !set[v.index()] && kinds[v.index()] == ModeKind::Nominal)
            .collect();
        (set, one_way)
    }

    /// Removes modes that cannot be reached from, or cannot return to, another member, until
    /// every pair is mutually reachable; `anchor` (the current mode) is never removed.
    fn prune(&mut self, set: &mut [bool], anchor: Option<ValueId>) {
        loop {
            let members: Vec<ValueId> = members(set).collect();
            let doomed = members.iter().copied().find(|&t| {
                Some(t) != anchor
                    && members
                        .iter()
                        .any(|&x| !self.reaches(x, t) || !self.reaches(t, x))
            });
            match doomed {
                Some(t) => set[t.index()] = false,
                None => return,
            }
        }
    }

    fn finals(&mut self, current: ValueId, helpers: &[bool]) -> Vec<bool> {
        let mut finals = vec![false; helpers.len()];
        let reachability = self.policy.reachability();
        let members: Vec<ValueId> = members(helpers).collect();
        for t in reachability.irreversible(current) {
            let from_current = self.reaches(current, t);
            finals[t.index()] = from_current && members.iter().all(|&x| self.reaches(x, t));
        }
        finals
    }
}

#[cfg(test)]
mod tests {
    use super::super::Reconfiguration;
    use super::super::testing::{DEADLOCK, SWITCH_GADGET, component, load, state};
    use super::{Feasible, feasible};
    use crate::plant::Plant;

    fn feasible_in(plant: &Plant, modes: &[&str]) -> Feasible {
        let reconfiguration = Reconfiguration::compile(plant).expect("compiles");
        feasible(
            plant,
            reconfiguration.policies(),
            reconfiguration.upstream_first(),
            &state(plant, modes),
        )
    }

    fn names(plant: &Plant, c: &str, flags: &[bool]) -> Vec<String> {
        let component = plant.component(component(plant, c));
        flags
            .iter()
            .enumerate()
            .filter(|(_, on)| **on)
            .map(|(i, _)| component.modes()[i].name.clone())
            .collect()
    }

    #[test]
    fn a_stuck_switch_keeps_the_gadget_out_of_b_and_says_so() {
        let plant = load(SWITCH_GADGET);
        let gadget = component(&plant, "gadget").index();
        let fine = feasible_in(&plant, &["off", "a"]);
        assert_eq!(
            names(&plant, "gadget", &fine.helpers[gadget]),
            ["a", "b", "e"]
        );
        assert_eq!(names(&plant, "gadget", &fine.finals[gadget]), ["c"]);
        let stuck = feasible_in(&plant, &["stuck", "a"]);
        assert_eq!(names(&plant, "switch", &stuck.helpers[0]), ["stuck"]);
        assert_eq!(names(&plant, "gadget", &stuck.helpers[gadget]), ["a", "e"]);
        assert_eq!(stuck.blocked_by[gadget], [component(&plant, "switch")]);
        assert!(stuck.finals[gadget].iter().all(|f| !f));
    }

    #[test]
    fn a_repairable_fault_must_be_repaired() {
        let plant = load(SWITCH_GADGET);
        let gadget = component(&plant, "gadget").index();
        let broken = feasible_in(&plant, &["off", "broken"]);
        assert_eq!(
            names(&plant, "gadget", &broken.helpers[gadget]),
            ["a", "b", "e"]
        );
        assert_eq!(names(&plant, "gadget", &broken.finals[gadget]), ["c"]);
    }

    #[test]
    fn a_cycle_of_influence_is_trusted_only_where_it_already_is() {
        let plant = load(DEADLOCK);
        let stuck = feasible_in(&plant, &["x", "x"]);
        assert_eq!(names(&plant, "p", &stuck.helpers[0]), ["x"]);
        assert_eq!(names(&plant, "q", &stuck.helpers[1]), ["x"]);
    }
}
