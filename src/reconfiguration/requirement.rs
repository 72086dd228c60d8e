//! What a transition's guard needs, compiled offline (§6.3.2, §6.3.3): the modes its upstream
//! components must be in (sub-goals) and the control assignment to issue once they are, found
//! by asking the plant's [`Theory`] which assignments *entail* the guard.
//!
//! The guard is cut into its top-level conjuncts; conjuncts that depend on a common upstream
//! component or control (see [`Influence`]) are solved together, as one *group*. For a group
//! over controls `K` and upstream components `U`, the compiler tries control assignments with
//! 0, 1, 2, … non-idle values (a transition that fires with every control idle is an **Idle**
//! step — the timed transitions of §6.3.3), and for each, full assignments of `U` over their
//! *nominal* modes (§6.3's first assumption: planning ignores faults). Every assignment that is
//! consistent and entails the group, given the component's source mode and with every other
//! upstream component free over its nominal modes, is shrunk by deletion to a minimal set of
//! mode sub-goals. A sub-goal that every nominal mode satisfies (a tank that is only ever
//! `full`) therefore disappears, as in Table 6.2.
//!
//! **Redundancy** (DESIGN.md §9, beyond §6.3's one requirement per transition): a guard may be
//! entailed by several minimal sets — a bus fed by regulator A *or* B has `reg_a = on` and
//! `reg_b = on`. All of them are kept, per group, at the fewest commands that work; a
//! transition's alternatives are the combinations of its groups' (at most
//! [`MAX_ALTERNATIVES`]), cheapest first (fewest commands, then fewest sub-goals, then the order
//! found). Which one the planner uses is decided online from ŝ (`planner.rs`).
//!
//! A sub-goal names a nominal mode, but other modes of its component — a fault among them —
//! may make the guard hold as well: a heater switch stuck open leaves its heater off exactly as
//! the `open` sub-goal asks. Each alternative records them ([`Requirement::satisfied_by`]), so
//! that a sub-goal already held that way is met, not pursued.
//!
//! For the propulsion engine's `off → heating` (guard `engine.cmd = standby`) this finds
//! `PDE = on` and `PDE.cmd = engine-standby`: the model's interconnection `PDE.engine_cmd =
//! engine.cmd` and the PDE's `on` constraint entail the guard from them.

use super::causal::{Dependencies, Influence, conjuncts};
use crate::logic::{Formula, ValueId, VarId};
use crate::opsat::{Consistency, Literal, Theory, TheoryError};
use crate::plant::{ComponentId, ModeKind, Plant};

/// At most this many candidate assignments are tried per group of a guard; a guard more
/// entangled than that is left unplannable (and says so) rather than stalling compilation.
const CANDIDATE_BUDGET: usize = 20_000;

/// At most this many alternative requirements are kept per transition (the product of its
/// groups' alternatives is cut there, cheapest first within each group).
pub const MAX_ALTERNATIVES: usize = 16;

/// One thing a guard needs, as a policy table shows it (Table 6.2).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Condition {
    /// An upstream component must be in this mode (`valve1 = open`): a sub-goal.
    Mode(ComponentId, ValueId),
    /// A part of the guard over the component's inputs that a command establishes
    /// (`engine.cmd = standby`), shown as the guard writes it.
    Input(Formula),
}

/// What one transition's guard needs: sub-goals first, then a command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Requirement {
    /// Sub-goals: the modes upstream components must be in before the command is issued.
    pub modes: Vec<(ComponentId, ValueId)>,
    /// The control assignments to issue (non-idle values; every other control stays idle).
    /// Empty for a transition that happens by itself: an **Idle** step.
    pub controls: Vec<(VarId, ValueId)>,
    /// What the guard needs as a policy table shows it: mode sub-goals, then the inputs that
    /// the command sets.
    pub conditions: Vec<Condition>,
    /// Other modes (fault modes included) in which a sub-goal's component makes the guard hold
    /// just as well, all else as the requirement says: `(switch1, stuck-open)` next to the
    /// sub-goal `switch1 = open`. Sorted.
    pub satisfied_by: Vec<(ComponentId, ValueId)>,
}

impl Requirement {
    /// True when no command is needed: the planner waits (§6.3.3's Idle).
    pub fn is_idle(&self) -> bool {
        self.controls.is_empty()
    }

    /// True when `u`, in `mode`, meets the sub-goal the requirement has on it: it is in the
    /// sub-goal's mode or in one that serves as well ([`Requirement::satisfied_by`]).
    pub fn is_met(&self, u: ComponentId, goal: ValueId, mode: ValueId) -> bool {
        mode == goal || self.satisfied_by.binary_search(&(u, mode)).is_ok()
    }

    /// The sub-goals not met in `current` (a mode per component), in the planner's order.
    pub fn unmet<'r>(
        &'r self,
        current: &'r [ValueId],
    ) -> impl Iterator<Item = (usize, (ComponentId, ValueId))> + 'r {
        self.modes
            .iter()
            .enumerate()
            .filter(move |&(_, &(u, v))| !self.is_met(u, v, current[u.index()]))
            .map(|(i, &m)| (i, m))
    }
}

/// Why a transition cannot be planned: no command or upstream modes make its guard hold.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Unplannable {
    /// A sentence naming the guard part that cannot be established.
    pub reason: String,
}

/// A group of guard conjuncts that share upstream components or controls.
struct Group<'f> {
    parts: Vec<&'f Formula>,
    deps: Dependencies,
}

/// Cuts a guard into groups of conjuncts with overlapping dependencies, in guard order.
fn groups<'f>(
    plant: &Plant,
    influence: &Influence,
    component: ComponentId,
    guard: &'f Formula,
) -> Vec<Group<'f>> {
    let mut groups: Vec<(usize, Group<'f>)> = Vec::new();
    for (position, part) in conjuncts(guard).into_iter().enumerate() {
        let mut group = Group {
            parts: vec![part],
            deps: influence.dependencies(plant, component, &part.variables()),
        };
        let mut first = position;
        let mut i = 0;
        while i < groups.len() {
            if groups[i].1.deps.overlaps(&group.deps) {
                let (their_first, other) = groups.remove(i);
                first = first.min(their_first);
                group.deps.merge(&other.deps);
                let mut parts = other.parts;
                parts.append(&mut group.parts);
                group.parts = parts;
            } else {
                i += 1;
            }
        }
        groups.push((first, group));
    }
    groups.sort_by_key(|(first, _)| *first);
    groups.into_iter().map(|(_, g)| g).collect()
}

/// A support found for one group: its sub-goals and commands.
#[derive(Debug, Default, Clone)]
struct Support {
    modes: Vec<(ComponentId, ValueId)>,
    controls: Vec<(VarId, ValueId)>,
}

/// One question to the theory: does this source mode, with these commands, make a guard part
/// hold, and under which modes of the upstream components?
struct Query<'q> {
    component: ComponentId,
    source: ValueId,
    upstream: &'q [ComponentId],
    /// Values of the group's controls: the command's, idle for the others.
    controls: Vec<Literal>,
}

/// An odometer over the product of `sizes`, first digit fastest; `None` when exhausted.
fn advance(digits: &mut [usize], sizes: &[usize]) -> bool {
    for (digit, &size) in digits.iter_mut().zip(sizes) {
        *digit += 1;
        if *digit < size {
            return true;
        }
        *digit = 0;
    }
    false
}

/// Every choice of `k` of the `n` positions, in lexicographic order.
fn choose(n: usize, k: usize) -> Vec<Vec<usize>> {
    fn go(start: usize, n: usize, k: usize, prefix: &mut Vec<usize>, out: &mut Vec<Vec<usize>>) {
        if prefix.len() == k {
            out.push(prefix.clone());
            return;
        }
        for i in start..n {
            prefix.push(i);
            go(i + 1, n, k, prefix, out);
            prefix.pop();
        }
    }
    let mut out = Vec::new();
    go(0, n, k, &mut Vec::with_capacity(k), &mut out);
    out
}

/// Keeps the supports no other support of the same commands is a proper subset of, fewest
/// sub-goals first (stable, so ties keep the order found).
fn minimal_supports(mut found: Vec<Support>) -> Vec<Support> {
    let dominated = |s: &Support, by: &Support| {
        by.controls == s.controls
            && by.modes.len() < s.modes.len()
            && by.modes.iter().all(|m| s.modes.contains(m))
    };
    let keep: Vec<bool> = found
        .iter()
        .map(|s| !found.iter().any(|other| dominated(s, other)))
        .collect();
    let mut kept = keep.iter();
    found.retain(|_| kept.next().copied().unwrap_or(false));
    found.sort_by_key(|s| s.modes.len());
    found
}

/// The first `limit` choices of one support per group, in odometer order (the first group's
/// choice varies fastest), each as an index per group.
fn combinations(per_group: &[Vec<Support>], limit: usize) -> Vec<Vec<usize>> {
    let sizes: Vec<usize> = per_group.iter().map(Vec::len).collect();
    let mut digits = vec![0; sizes.len()];
    let mut out = Vec::new();
    loop {
        out.push(digits.clone());
        if out.len() >= limit || !advance(&mut digits, &sizes) {
            return out;
        }
    }
}

/// One alternative: the chosen support of each group, as sub-goals, commands and conditions
/// (sub-goals of groups met without a command first, then the inputs a command sets).
fn assemble(groups: &[Group<'_>], per_group: &[Vec<Support>], choice: &[usize]) -> Requirement {
    let mut requirement = Requirement {
        modes: Vec::new(),
        controls: Vec::new(),
        conditions: Vec::new(),
        satisfied_by: Vec::new(),
    };
    let mut inputs = Vec::new();
    for ((group, supports), &pick) in groups.iter().zip(per_group).zip(choice) {
        let support = &supports[pick];
        if support.controls.is_empty() {
            requirement
                .conditions
                .extend(support.modes.iter().map(|&(u, v)| Condition::Mode(u, v)));
        } else {
            inputs.extend(group.parts.iter().map(|p| Condition::Input((*p).clone())));
        }
        requirement.modes.extend(&support.modes);
        requirement.controls.extend(&support.controls);
    }
    requirement.conditions.extend(inputs);
    requirement.modes.sort_unstable();
    requirement.controls.sort_unstable();
    requirement
}

/// Compiles guards into [`Requirement`]s with its own copy of the plant's theory.
pub(crate) struct GuardCompiler<'a> {
    plant: &'a Plant,
    influence: &'a Influence,
    theory: Theory,
    /// Per component, "it is in a nominal mode" (`None` when every mode is nominal).
    nominal: Vec<Option<Literal>>,
    /// Per component, its nominal modes.
    nominal_modes: Vec<Vec<ValueId>>,
}

impl<'a> GuardCompiler<'a> {
    /// A compiler over a fresh theory of `plant`.
    pub fn new(plant: &'a Plant, influence: &'a Influence) -> Result<Self, TheoryError> {
        // Compilation asks yes/no questions only (the default theory does not minimise
        // conflicts).
        let mut theory = Theory::new(plant.table().clone(), &plant.constraints())?;
        let mut nominal = Vec::with_capacity(plant.components().len());
        let mut nominal_modes = Vec::with_capacity(plant.components().len());
        for component in plant.components() {
            let modes: Vec<ValueId> = (0..component.modes().len() as u32)
                .map(ValueId)
                .filter(|&m| component.mode(m).kind == ModeKind::Nominal)
                .collect();
            let literal = if modes.len() == component.modes().len() {
                None
            } else {
                let in_nominal = Formula::Or(
                    modes
                        .iter()
                        .map(|&m| Formula::is(component.mode_var(), m))
                        .collect(),
                );
                Some(theory.define(&in_nominal)?)
            };
            nominal.push(literal);
            nominal_modes.push(modes);
        }
        Ok(GuardCompiler {
            plant,
            influence,
            theory,
            nominal,
            nominal_modes,
        })
    }

    /// What the guard of a transition of `component` leaving `source` needs: every minimal
    /// alternative, cheapest first (see the module doc), or why none exists.
    pub fn requirements(
        &mut self,
        component: ComponentId,
        source: ValueId,
        guard: &Formula,
    ) -> Result<Result<Vec<Requirement>, Unplannable>, TheoryError> {
        let groups = groups(self.plant, self.influence, component, guard);
        let mut per_group = Vec::with_capacity(groups.len());
        for group in &groups {
            let supports = self.solve(component, source, group)?;
            if supports.is_empty() {
                return Ok(Err(self.unplannable(group)));
            }
            per_group.push(supports);
        }
        let mut alternatives = Vec::new();
        for choice in combinations(&per_group, MAX_ALTERNATIVES) {
            let mut requirement = assemble(&groups, &per_group, &choice);
            if self.jointly_consistent(component, source, &requirement) {
                requirement.satisfied_by =
                    self.equivalents(component, source, &requirement, guard)?;
                alternatives.push(requirement);
            }
        }
        if alternatives.is_empty() {
            return Ok(Err(Unplannable {
                reason: format!(
                    "the parts of `{}` need commands or modes that exclude each other",
                    guard.display(self.plant.table())
                ),
            }));
        }
        alternatives.sort_by_key(|r| (r.controls.len(), r.modes.len()));
        Ok(Ok(alternatives))
    }

    /// Per sub-goal of `requirement`, the other modes of its component (fault modes too) that
    /// make `guard` hold as well, the rest of the requirement unchanged.
    fn equivalents(
        &mut self,
        component: ComponentId,
        source: ValueId,
        requirement: &Requirement,
        guard: &Formula,
    ) -> Result<Vec<(ComponentId, ValueId)>, TheoryError> {
        let upstream: Vec<ComponentId> = requirement.modes.iter().map(|&(u, _)| u).collect();
        let query = Query {
            component,
            source,
            upstream: &upstream,
            controls: requirement
                .controls
                .iter()
                .map(|&(x, v)| Literal::Is(x, v))
                .collect(),
        };
        let mut out = Vec::new();
        for (i, &(u, v)) in requirement.modes.iter().enumerate() {
            for w in 0..self.plant.component(u).modes().len() as u32 {
                let w = ValueId(w);
                if w == v {
                    continue;
                }
                let mut modes = requirement.modes.clone();
                modes[i] = (u, w);
                if self.supports(&self.assumptions(&query, &modes), guard)? {
                    out.push((u, w));
                }
            }
        }
        out.sort_unstable();
        Ok(out)
    }

    fn unplannable(&self, group: &Group<'_>) -> Unplannable {
        let table = self.plant.table();
        let part = Formula::all(group.parts.iter().map(|p| (*p).clone()));
        let reason = if group.deps.modes.is_empty() && group.deps.controls.is_empty() {
            format!(
                "`{}` depends on no control and no component mode: nothing can make it hold",
                part.display(table)
            )
        } else {
            format!(
                "no command and no nominal modes of the components upstream make `{}` hold",
                part.display(table)
            )
        };
        Unplannable { reason }
    }

    /// The assumptions of a candidate: the source mode, the candidate's sub-goals, every other
    /// upstream component of the query in a nominal mode, and the query's control values.
    fn assumptions(&self, query: &Query<'_>, modes: &[(ComponentId, ValueId)]) -> Vec<Literal> {
        let source = self.plant.component(query.component).mode_var();
        let mut assumptions = vec![Literal::Is(source, query.source)];
        for &u in query.upstream {
            match modes.iter().find(|(w, _)| *w == u) {
                Some(&(_, v)) => {
                    assumptions.push(Literal::Is(self.plant.component(u).mode_var(), v))
                }
                None => assumptions.extend(self.nominal[u.index()]),
            }
        }
        assumptions.extend(query.controls.iter().copied());
        assumptions
    }

    /// Consistent with the model and entailing `formula`.
    fn supports(
        &mut self,
        assumptions: &[Literal],
        formula: &Formula,
    ) -> Result<bool, TheoryError> {
        if self.theory.consistent(assumptions) != Consistency::Consistent {
            return Ok(false);
        }
        self.theory.entails(assumptions, formula)
    }

    /// Every minimal support with the fewest commands that work, fewest sub-goals first (see the
    /// module doc); empty when no command and no upstream modes make the group hold.
    fn solve(
        &mut self,
        component: ComponentId,
        source: ValueId,
        group: &Group<'_>,
    ) -> Result<Vec<Support>, TheoryError> {
        let formula = Formula::all(group.parts.iter().map(|p| (*p).clone()));
        let controls = &group.deps.controls;
        let mut budget = CANDIDATE_BUDGET;
        for k in 0..=controls.len() {
            let mut found: Vec<Support> = Vec::new();
            'commands: for chosen in choose(controls.len(), k) {
                for command in self.command_combinations(controls, &chosen) {
                    let query = Query {
                        component,
                        source,
                        upstream: &group.deps.modes,
                        controls: self.control_literals(controls, &command),
                    };
                    for modes in self.minimal_modes(&query, &formula, &mut budget)? {
                        found.push(Support {
                            modes,
                            controls: command.clone(),
                        });
                    }
                    // Nothing beats a support that needs no sub-goal.
                    if budget == 0 || found.iter().any(|s| s.modes.is_empty()) {
                        break 'commands;
                    }
                }
            }
            if !found.is_empty() || budget == 0 {
                return Ok(minimal_supports(found));
            }
        }
        Ok(Vec::new())
    }

    /// Every assignment of non-idle values to the chosen controls (the others stay idle).
    fn command_combinations(
        &self,
        controls: &[VarId],
        chosen: &[usize],
    ) -> Vec<Vec<(VarId, ValueId)>> {
        let options: Vec<Vec<ValueId>> = chosen
            .iter()
            .map(|&i| {
                let var = controls[i];
                let idle = self.idle_value(var);
                self.plant
                    .table()
                    .variable(var)
                    .value_ids()
                    .filter(|&v| Some(v) != idle)
                    .collect()
            })
            .collect();
        if options.iter().any(Vec::is_empty) {
            return Vec::new();
        }
        let sizes: Vec<usize> = options.iter().map(Vec::len).collect();
        let mut digits = vec![0; sizes.len()];
        let mut out = Vec::new();
        loop {
            out.push(
                chosen
                    .iter()
                    .zip(&digits)
                    .zip(&options)
                    .map(|((&i, &d), values)| (controls[i], values[d]))
                    .collect(),
            );
            if !advance(&mut digits, &sizes) {
                return out;
            }
        }
    }

    fn idle_value(&self, control: VarId) -> Option<ValueId> {
        self.plant
            .controls()
            .iter()
            .find(|c| c.var == control)
            .map(|c| c.idle)
    }

    /// The control literals: `command`'s values, idle for the group's other controls.
    fn control_literals(&self, controls: &[VarId], command: &[(VarId, ValueId)]) -> Vec<Literal> {
        controls
            .iter()
            .filter_map(|&k| {
                let value = command
                    .iter()
                    .find(|(x, _)| *x == k)
                    .map(|&(_, v)| v)
                    .or_else(|| self.idle_value(k))?;
                Some(Literal::Is(k, value))
            })
            .collect()
    }

    /// Under the query's commands, every minimal set of upstream modes that makes `formula`
    /// hold: partial assignments of the upstream components by increasing size, each kept when
    /// it supports the formula and contains no smaller support already kept. A support stays
    /// one when more components are fixed (entailment is monotone), so this finds exactly the
    /// minimal ones.
    fn minimal_modes(
        &mut self,
        query: &Query<'_>,
        formula: &Formula,
        budget: &mut usize,
    ) -> Result<Vec<Vec<(ComponentId, ValueId)>>, TheoryError> {
        *budget = budget.saturating_sub(1);
        let free = self.assumptions(query, &[]);
        // Any support is consistent with the formula, so one check rules most commands out.
        let mut with_formula = free.clone();
        with_formula.push(self.theory.define(formula)?);
        if self.theory.consistent(&with_formula) != Consistency::Consistent {
            return Ok(Vec::new());
        }
        if self.supports(&free, formula)? {
            return Ok(vec![Vec::new()]);
        }
        let upstream = query.upstream;
        let mut found: Vec<Vec<(ComponentId, ValueId)>> = Vec::new();
        for size in 1..=upstream.len() {
            for chosen in choose(upstream.len(), size) {
                let sizes: Vec<usize> = chosen
                    .iter()
                    .map(|&i| self.nominal_modes[upstream[i].index()].len())
                    .collect();
                if sizes.contains(&0) {
                    continue;
                }
                let mut digits = vec![0; size];
                loop {
                    if *budget == 0 {
                        return Ok(found);
                    }
                    *budget -= 1;
                    let modes: Vec<(ComponentId, ValueId)> = chosen
                        .iter()
                        .zip(&digits)
                        .map(|(&i, &d)| {
                            let u = upstream[i];
                            (u, self.nominal_modes[u.index()][d])
                        })
                        .collect();
                    let covered = found
                        .iter()
                        .any(|smaller| smaller.iter().all(|m| modes.contains(m)));
                    if !covered && self.supports(&self.assumptions(query, &modes), formula)? {
                        found.push(modes);
                    }
                    if !advance(&mut digits, &sizes) {
                        break;
                    }
                }
            }
        }
        Ok(found)
    }

    /// The whole requirement is consistent (its groups' supports do not contradict).
    fn jointly_consistent(
        &mut self,
        component: ComponentId,
        source: ValueId,
        requirement: &Requirement,
    ) -> bool {
        let upstream: Vec<ComponentId> = requirement.modes.iter().map(|&(u, _)| u).collect();
        let query = Query {
            component,
            source,
            upstream: &upstream,
            controls: requirement
                .controls
                .iter()
                .map(|&(x, v)| Literal::Is(x, v))
                .collect(),
        };
        let assumptions = self.assumptions(&query, &requirement.modes);
        self.theory.consistent(&assumptions) == Consistency::Consistent
    }
}

#[cfg(test)]
mod tests {
    use super::super::Reconfiguration;
    use super::super::policy::PolicyStep;
    use super::super::testing::{SWITCH_GADGET, component, load, mode, model};
    use super::{Condition, Requirement};
    use crate::logic::{Formula, parse_formula};
    use crate::plant::Plant;

    fn step<'r>(
        reconfiguration: &'r Reconfiguration,
        plant: &Plant,
        name: &str,
        from: &str,
        to: &str,
    ) -> &'r PolicyStep {
        let c = component(plant, name);
        let (from, to) = (mode(plant, name, from), mode(plant, name, to));
        reconfiguration
            .policy(c)
            .steps()
            .iter()
            .find(|s| s.source == from && s.target == to)
            .unwrap_or_else(|| panic!("no step {name}: {from:?} -> {to:?}"))
    }

    fn requirement(step: &PolicyStep) -> &Requirement {
        step.requirement.as_ref().expect("plannable")
    }

    /// §6.3.3 with Figure 6-12's interconnection: `engine.cmd = standby` is entailed by the PDE
    /// being on and commanded `engine-standby`; the tanks, full in every nominal mode, are no
    /// sub-goal of the fire command.
    #[test]
    fn the_engine_standby_command_goes_through_the_pde() {
        let plant = model("propulsion");
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let table = plant.table();
        let standby = requirement(step(&reconfiguration, &plant, "engine", "off", "heating"));
        let pde = component(&plant, "PDE");
        assert_eq!(standby.modes, [(pde, mode(&plant, "PDE", "on"))]);
        let command = parse_formula("PDE.cmd = engine-standby", table).expect("formula");
        let controls: Vec<Formula> = standby
            .controls
            .iter()
            .map(|&(x, v)| Formula::is(x, v))
            .collect();
        assert_eq!(controls, [command]);
        let input = parse_formula("engine.cmd = standby", table).expect("formula");
        assert_eq!(standby.conditions, [Condition::Input(input)]);
        let fire = requirement(step(
            &reconfiguration,
            &plant,
            "engine",
            "standby",
            "firing",
        ));
        let tanks = [component(&plant, "tank1"), component(&plant, "tank2")];
        assert!(fire.modes.iter().all(|(u, _)| !tanks.contains(u)));
        assert_eq!(fire.modes.len(), 3);
    }

    #[test]
    fn sub_goals_come_before_inputs_and_timed_steps_are_idle() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let to_b = requirement(step(&reconfiguration, &plant, "gadget", "a", "b"));
        let switch_on = (component(&plant, "switch"), mode(&plant, "switch", "on"));
        assert_eq!(to_b.modes, [switch_on]);
        assert!(matches!(
            to_b.conditions.as_slice(),
            [Condition::Mode(u, v), Condition::Input(_)] if (*u, *v) == switch_on
        ));
        assert!(!to_b.is_idle());
        let wait = requirement(step(&reconfiguration, &plant, "gadget", "a", "e"));
        assert!(wait.is_idle() && wait.modes.is_empty() && wait.conditions.is_empty());
    }

    /// DESIGN.md §9 (redundancy): the payload of `models/power.ron` is powered through
    /// regulator A or regulator B; both minimal alternatives are compiled, cheapest first.
    #[test]
    fn every_minimal_alternative_of_a_guard_is_compiled() {
        let plant = model("power");
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let step = step(&reconfiguration, &plant, "payload", "unpowered", "powered");
        let mode = |c: &str, m: &str| {
            (
                component(&plant, c),
                super::super::testing::mode(&plant, c, m),
            )
        };
        let ways: Vec<Vec<(crate::plant::ComponentId, crate::logic::ValueId)>> = step
            .alternatives
            .iter()
            .map(|r| {
                let mut modes = r.modes.clone();
                modes.sort_unstable();
                modes
            })
            .collect();
        let with = |regulator: &str| {
            let mut modes = vec![
                mode("battery", "charged"),
                mode(regulator, "on"),
                mode("load_switch", "closed"),
            ];
            modes.sort_unstable();
            modes
        };
        assert_eq!(ways, [with("reg_a"), with("reg_b")]);
        assert!(step.alternatives.iter().all(Requirement::is_idle));
        assert_eq!(step.requirement.as_ref().ok(), step.alternatives.first());
    }

    /// A fault mode that makes the guard hold as the sub-goal's mode does is recorded: the
    /// thermostat's switch stuck open keeps its heater off exactly as `open` does. Transitions
    /// between the same two modes are candidates of one move.
    #[test]
    fn a_fault_that_serves_a_sub_goal_is_recorded() {
        let plant = model("thermostat");
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let temperature = component(&plant, "temperature");
        let (cold, warming) = (
            mode(&plant, "temperature", "cold"),
            mode(&plant, "temperature", "warming"),
        );
        let policy = reconfiguration.policy(temperature);
        let switch1 = component(&plant, "switch1");
        let (open, stuck_open) = (
            mode(&plant, "switch1", "open"),
            mode(&plant, "switch1", "stuck-open"),
        );
        // The three transitions cold -> warming (heater 1, heater 2, both) are one move's
        // candidates; the second needs switch 1 open.
        assert_eq!(policy.candidates_between(cold, warming).count(), 3);
        let (_, heater2) = policy
            .candidates_between(cold, warming)
            .find(|(_, r)| r.modes.contains(&(switch1, open)))
            .expect("the transition on heater 2 alone needs switch 1 open");
        assert!(heater2.satisfied_by.contains(&(switch1, stuck_open)));
        assert!(heater2.is_met(switch1, open, stuck_open));
        assert!(!heater2.is_met(switch1, open, mode(&plant, "switch1", "closed")));
    }

    #[test]
    fn a_guard_on_what_nothing_determines_is_unplannable() {
        let text = r#"Plant(
            name: "sensor",
            components: [
                Component(
                    name: "alarm",
                    attributes: { "level": ["low", "high"] },
                    modes: [Mode(name: "quiet"), Mode(name: "ringing")],
                    initial: { "quiet": 1.0 },
                    transitions: [
                        (from: "quiet", to: "ringing", guard: "alarm.level = high", probability: 1.0),
                    ],
                ),
            ],
            observables: ["alarm.level"],
        )"#;
        let plant = load(text);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let step = step(&reconfiguration, &plant, "alarm", "quiet", "ringing");
        let reason = &step.requirement.as_ref().expect_err("unplannable").reason;
        assert_eq!(
            reason,
            "`alarm.level = high` depends on no control and no component mode: nothing can make \
             it hold"
        );
    }
}
