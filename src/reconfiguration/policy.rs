//! Concurrent policies (§6.3.2; Williams & Nayak 1997): one per component, compiled offline.
//! For every (current, target) mode pair the policy names the *next* transition toward the
//! target and what its guard needs ([`Requirement`]): sub-goals on upstream components and a
//! command, or nothing, in which case the planner waits (**Idle**, §6.3.3). Table 6.2 is the
//! engine's.
//!
//! Paths are shortest in transitions (ties go to the transition declared first) and respect
//! [`Reachability`]: from `m`, a path stays in `m`'s reversible region until its last
//! transition, which may leave it only toward a mode of the irreversible frontier. Whether such
//! a final irreversible transition may be taken is decided online: only when the goal names its
//! target explicitly.

use std::collections::VecDeque;

use super::reachability::Reachability;
use super::requirement::{GuardCompiler, Requirement, Unplannable};
use crate::logic::ValueId;
use crate::opsat::TheoryError;
use crate::plant::{Component, ComponentId, ModeKind, Plant};

/// A transition the planner may use, from one source mode (a `"*"` transition gives one step per
/// source mode), with what its guard needs.
#[derive(Debug, Clone, PartialEq)]
pub struct PolicyStep {
    /// The transition, by index into [`Component::transitions`].
    pub transition: usize,
    /// The mode it leaves.
    pub source: ValueId,
    /// The mode it enters.
    pub target: ValueId,
    /// What its guard needs (its cheapest alternative), or why nothing the planner does makes
    /// it hold.
    pub requirement: Result<Requirement, Unplannable>,
    /// Every minimal alternative requirement of its guard, cheapest first (the first is
    /// `requirement`'s); empty when unplannable. A bus fed by regulator A or B has two.
    pub alternatives: Vec<Requirement>,
    /// True when it leaves a fault mode: a repair.
    pub repair: bool,
}

/// One cell of a concurrent policy: what to do in `current` to move toward `target`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PolicyEntry {
    /// Already there.
    Stay,
    /// Take this step next.
    Next {
        /// Index into [`ConcurrentPolicy::steps`].
        step: usize,
        /// True when the step leaves `current`'s reversible region (allowed only toward a
        /// target the goal names).
        irreversible: bool,
    },
    /// No plannable path: Table 6.2's **Failure**.
    Failure,
}

/// The concurrent policy of one component.
#[derive(Debug, Clone, PartialEq)]
pub struct ConcurrentPolicy {
    component: ComponentId,
    mode_count: usize,
    steps: Vec<PolicyStep>,
    /// `entries[current * mode_count + target]`.
    entries: Vec<PolicyEntry>,
    reachability: Reachability,
}

impl ConcurrentPolicy {
    /// Compiles the policy of `id`: its steps' requirements (with `compiler`), its
    /// reachability and every (current, target) entry.
    pub(crate) fn compile(
        plant: &Plant,
        id: ComponentId,
        compiler: &mut GuardCompiler<'_>,
    ) -> Result<ConcurrentPolicy, TheoryError> {
        let component = plant.component(id);
        let steps = planning_steps(component, id, compiler)?;
        let edges: Vec<(ValueId, ValueId)> = steps
            .iter()
            .filter(|s| s.requirement.is_ok())
            .map(|s| (s.source, s.target))
            .collect();
        let reachability = Reachability::new(component, &edges);
        let mode_count = component.modes().len();
        let mut entries = Vec::with_capacity(mode_count * mode_count);
        for m in 0..mode_count {
            entries.extend(first_steps(
                &steps,
                &reachability,
                mode_count,
                ValueId(m as u32),
            ));
        }
        Ok(ConcurrentPolicy {
            component: id,
            mode_count,
            steps,
            entries,
            reachability,
        })
    }

    /// The component the policy is for.
    pub fn component(&self) -> ComponentId {
        self.component
    }

    /// What to do in `current` to move toward `target`.
    pub fn entry(&self, current: ValueId, target: ValueId) -> PolicyEntry {
        self.entries[current.index() * self.mode_count + target.index()]
    }

    /// The number of steps the policy takes from `current` to `target` under nominal
    /// execution (0 when already there); `None` when an entry on the way says Failure.
    pub fn distance(&self, current: ValueId, target: ValueId) -> Option<usize> {
        let mut steps = 0;
        self.walk(current, target, |_| {
            steps += 1;
            true
        })
        .map(|()| steps)
    }

    /// Every step the planner may take, by source mode then declaration order.
    pub fn steps(&self) -> &[PolicyStep] {
        &self.steps
    }

    /// The component's reversible regions and irreversible frontiers.
    pub fn reachability(&self) -> &Reachability {
        &self.reachability
    }

    /// True when the component leaves `mode` by itself: a step out of it needs no command and
    /// no sub-goal (a timed transition such as heating → standby). Goal interpretation offers
    /// such a mode only when the goal names it or the component is already in it.
    pub fn is_transient(&self, mode: ValueId) -> bool {
        self.automatic_exits(mode).next().is_some()
    }

    /// Where the component goes by itself from the transient `mode`, when all its ways out
    /// that need nothing lead to one mode (camera taking-picture → idle); `None` when `mode`
    /// is not transient or the model does not say where it settles.
    pub fn settles_in(&self, mode: ValueId) -> Option<ValueId> {
        let mut exits = self.automatic_exits(mode);
        let first = exits.next()?;
        exits.all(|target| target == first).then_some(first)
    }

    /// The targets of the steps out of `mode` that need no command and no sub-goal.
    fn automatic_exits(&self, mode: ValueId) -> impl Iterator<Item = ValueId> + '_ {
        self.steps
            .iter()
            .filter(move |step| {
                step.source == mode
                    && step
                        .requirement
                        .as_ref()
                        .is_ok_and(|r| r.is_idle() && r.modes.is_empty())
            })
            .map(|step| step.target)
    }

    /// The ways to take the step `step` names: every plannable step with its source and target
    /// (the transitions declared between the two modes, in declaration order) and each of its
    /// alternative requirements, cheapest first — the planner's candidates for that move.
    pub fn candidates(&self, step: usize) -> impl Iterator<Item = (usize, &Requirement)> + '_ {
        let (source, target) = (self.steps[step].source, self.steps[step].target);
        self.candidates_between(source, target)
    }

    /// [`ConcurrentPolicy::candidates`] of the move from `source` to `target`.
    pub fn candidates_between(
        &self,
        source: ValueId,
        target: ValueId,
    ) -> impl Iterator<Item = (usize, &Requirement)> + '_ {
        self.steps
            .iter()
            .enumerate()
            .filter(move |(_, s)| s.source == source && s.target == target)
            .flat_map(|(i, s)| s.alternatives.iter().map(move |r| (i, r)))
    }

    /// Puts every step's sub-goals in the planner's order: by `rank` (a component's position
    /// in the causal graph's downstream-first order).
    pub(crate) fn order_sub_goals(&mut self, rank: &[usize]) {
        for step in &mut self.steps {
            if let Ok(requirement) = &mut step.requirement {
                requirement.modes.sort_by_key(|(u, _)| rank[u.index()]);
            }
            for requirement in &mut step.alternatives {
                requirement.modes.sort_by_key(|(u, _)| rank[u.index()]);
            }
        }
    }

    /// Follows the policy from `from` toward `to`, one step at a time, as the planner would
    /// under nominal execution; `None` when an entry says Failure. The steps visited are
    /// passed to `visit`; `false` from it stops the walk with `None`.
    pub(crate) fn walk(
        &self,
        from: ValueId,
        to: ValueId,
        mut visit: impl FnMut(&PolicyStep) -> bool,
    ) -> Option<()> {
        let mut at = from;
        for _ in 0..=self.mode_count {
            match self.entry(at, to) {
                PolicyEntry::Stay => return Some(()),
                PolicyEntry::Failure => return None,
                PolicyEntry::Next { step, .. } => {
                    let step = &self.steps[step];
                    if !visit(step) {
                        return None;
                    }
                    at = step.target;
                }
            }
        }
        None
    }
}

/// The transitions the planner may use: nominal transitions and repairs (target a nominal
/// mode), one step per source mode, with their requirements.
fn planning_steps(
    component: &Component,
    id: ComponentId,
    compiler: &mut GuardCompiler<'_>,
) -> Result<Vec<PolicyStep>, TheoryError> {
    let mut steps = Vec::new();
    for m in 0..component.modes().len() {
        let source = ValueId(m as u32);
        for &t in component.outgoing(source) {
            let transition = &component.transitions()[t];
            if component.mode(transition.target).kind == ModeKind::Fault {
                continue;
            }
            let (requirement, alternatives) =
                match compiler.requirements(id, source, &transition.guard)? {
                    Ok(alternatives) => (Ok(alternatives[0].clone()), alternatives),
                    Err(unplannable) => (Err(unplannable), Vec::new()),
                };
            steps.push(PolicyStep {
                transition: t,
                source,
                target: transition.target,
                requirement,
                alternatives,
                repair: component.mode(source).kind == ModeKind::Fault,
            });
        }
    }
    Ok(steps)
}

/// The entries of row `from`: a breadth-first search over plannable steps that expands only
/// modes of `from`'s reversible region and enters frontier modes as leaves.
fn first_steps(
    steps: &[PolicyStep],
    reachability: &Reachability,
    mode_count: usize,
    from: ValueId,
) -> Vec<PolicyEntry> {
    let mut first: Vec<Option<usize>> = vec![None; mode_count];
    let mut seen = vec![false; mode_count];
    seen[from.index()] = true;
    let mut queue = VecDeque::from([from]);
    while let Some(at) = queue.pop_front() {
        if !reachability.is_reversible(from, at) {
            continue;
        }
        for (i, step) in steps.iter().enumerate() {
            let next = step.target;
            let allowed =
                reachability.is_reversible(from, next) || reachability.is_irreversible(from, next);
            if step.source != at || step.requirement.is_err() || seen[next.index()] || !allowed {
                continue;
            }
            seen[next.index()] = true;
            first[next.index()] = Some(if at == from {
                i
            } else {
                first[at.index()].unwrap_or(i)
            });
            queue.push_back(next);
        }
    }
    (0..mode_count)
        .map(|t| match first[t] {
            _ if t == from.index() => PolicyEntry::Stay,
            Some(step) => PolicyEntry::Next {
                step,
                irreversible: !reachability.is_reversible(from, steps[step].target),
            },
            None => PolicyEntry::Failure,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::Reconfiguration;
    use super::super::testing::{SWITCH_GADGET, component, load, mode};
    use super::PolicyEntry;

    #[test]
    fn paths_take_one_irreversible_step_at_most_and_only_last() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let gadget = component(&plant, "gadget");
        let policy = reconfiguration.policy(gadget);
        let m = |name| mode(&plant, "gadget", name);
        let next = |from, to| match policy.entry(m(from), m(to)) {
            PolicyEntry::Next { step, irreversible } => {
                let step = &policy.steps()[step];
                let target = &plant.component(gadget).mode(step.target).name;
                Some((target.clone(), irreversible, step.repair))
            }
            PolicyEntry::Stay | PolicyEntry::Failure => None,
        };
        assert_eq!(policy.entry(m("a"), m("a")), PolicyEntry::Stay);
        // a -> b -> c: the irreversible step comes last.
        assert_eq!(next("a", "c"), Some(("b".into(), false, false)));
        assert_eq!(next("b", "c"), Some(("c".into(), true, false)));
        // d would need c as an irreversible intermediate step: never.
        assert_eq!(policy.entry(m("a"), m("d")), PolicyEntry::Failure);
        assert_eq!(policy.entry(m("c"), m("a")), PolicyEntry::Failure);
        assert_eq!(next("c", "d"), Some(("d".into(), false, false)));
        // Repairs: into a reversibly, into c irreversibly; b by way of a.
        assert_eq!(next("broken", "a"), Some(("a".into(), false, true)));
        assert_eq!(next("broken", "b"), Some(("a".into(), false, true)));
        assert_eq!(next("broken", "c"), Some(("c".into(), true, true)));
        assert_eq!(policy.entry(m("broken"), m("d")), PolicyEntry::Failure);
        // e is reached by waiting in a.
        assert_eq!(next("a", "e"), Some(("e".into(), false, false)));
        assert!(policy.is_transient(m("a")));
        assert!(!policy.is_transient(m("e")) && !policy.is_transient(m("b")));
    }

    #[test]
    fn walks_follow_the_entries_to_the_target() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let policy = reconfiguration.policy(component(&plant, "gadget"));
        let m = |name| mode(&plant, "gadget", name);
        let mut visited = Vec::new();
        let walked = policy.walk(m("e"), m("c"), |step| {
            visited.push(step.target);
            true
        });
        assert_eq!(walked, Some(()));
        assert_eq!(visited, [m("a"), m("b"), m("c")]);
        assert_eq!(policy.walk(m("a"), m("d"), |_| true), None);
        assert_eq!(policy.walk(m("a"), m("c"), |_| false), None);
    }
}
