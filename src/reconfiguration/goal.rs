//! Goal interpretation (§6.3.1): the maximum-reward state, reachable from the current one, that
//! is consistent with the model and entails the configuration goal — an OCSP solved by OPSAT.
//!
//! - One decision variable per component: its mode, over the modes [`feasible`] allows (its
//!   helper modes, plus an irreversible target when the goal names it), with cost −reward.
//!   A component the goal does not name keeps its *kept* mode — the configuration the plant is
//!   meant to be in, before this goal — unless the goal forces it to change: leaving that mode
//!   costs [`HOLD_COST`], more than any reward. Reward chooses among what must change. Without
//!   this, a goal on one component would switch every other one to its highest-reward mode
//!   (the engine off in the middle of powered descent, as soon as `engine = firing` is no longer
//!   asserted). Ties between equal rewards go to staying put: a move costs [`MOVE_COST`] more. A
//!   *transient* mode, which the component leaves by itself (heating), is offered only when the
//!   goal names it or the component is in it: a goal state should be one the plant stays in.
//! - Constraints: the plant's theory (the caller's, which GI extends with definitions), and the
//!   goal. Candidates come out best first, consistent with the model and the goal; when the goal
//!   is a conjunction of mode assignments that is also entailment, otherwise each candidate is
//!   checked for entailment until one passes.
//! - No candidate: the failure is explained by a conflict. The goal's assignments and each
//!   component's restriction to its allowed modes are assumed together; the theory's minimal
//!   conflict names the goals and the components responsible ("engine = standby is unreachable:
//!   engine is failed"; "conflicting goals: engine = standby and engine = firing cannot hold
//!   together"). The explanation is [`failure`]'s.

mod failure;

pub use failure::{FailureCause, GoalFailed};

use super::feasible::{Feasible, feasible};
use super::{ConcurrentPolicy, Reconfiguration};
use crate::logic::{Atom, Formula, ValueId, VarId};
use crate::opsat::{Literal, Ocsp, SearchOptions, Theory};
use crate::plant::{ComponentId, ModeKind, Plant, describe_modes};
use failure::{Explanation, explain};

/// What moving a component away from its current mode costs on top of −reward: enough to break
/// ties between equal rewards in favour of staying, too little to outweigh any reward.
pub const MOVE_COST: f64 = 1e-6;

/// What leaving its kept mode costs a component the goal does not name: more than any
/// difference of rewards, so goal interpretation changes as few components as the goal needs.
pub const HOLD_COST: f64 = 1e6;

/// At most this many candidates are checked for entailment (only goals that are not plain
/// conjunctions of mode assignments need the check).
const ENTAILMENT_CANDIDATES: u64 = 10_000;

/// The state goal interpretation chose: a mode per component.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalState {
    modes: Vec<ValueId>,
    /// `named[c]`: the configuration goal names `c = modes[c]` explicitly.
    named: Vec<bool>,
    reward: f64,
    /// The transitions that leave this state by themselves, when goal interpretation found no
    /// state the plant rests in ([`GoalState::leaving`]); empty for a resting state.
    leaving: Vec<(ComponentId, usize)>,
}

impl GoalState {
    /// A goal state given directly (for callers that choose it themselves); `named` lists the
    /// components whose goal mode counts as explicitly requested, which is what allows the
    /// planner to take an irreversible transition into it. The reward is the sum of the modes'.
    pub fn new(plant: &Plant, modes: Vec<ValueId>, named: &[ComponentId]) -> GoalState {
        let reward = summed_reward(plant, &modes);
        let mut flags = vec![false; modes.len()];
        for c in named {
            if let Some(flag) = flags.get_mut(c.index()) {
                *flag = true;
            }
        }
        GoalState {
            modes,
            named: flags,
            reward,
            leaving: Vec::new(),
        }
    }

    /// The transitions (component, index into its transitions) that take the plant out of this
    /// state by themselves — with every control idle, their guards hold in it — when goal
    /// interpretation found no state entailing the goal that the plant rests in (DESIGN.md §9).
    /// The planner reaches such a state and the plant leaves it: `kairos plan` says so instead
    /// of alternating commands to its step limit. Empty for a state the plant rests in.
    pub fn leaving(&self) -> &[(ComponentId, usize)] {
        &self.leaving
    }

    /// The goal state to keep once the plant is in `current`: every transient mode the goal
    /// named that the component has reached is replaced by the mode it leaves it for by itself,
    /// and every mode merely kept that the component has left for good by nominal transitions
    /// is replaced by where it is (see [`Reconfiguration::settle`]).
    pub(crate) fn settled(
        &self,
        reconfiguration: &Reconfiguration,
        current: &[ValueId],
    ) -> GoalState {
        let mut settled = self.clone();
        settled.settle(reconfiguration, current);
        settled
    }

    /// [`GoalState::settled`] in place. Named stays named: the way out of a named transient
    /// mode may be irreversible (a repair mode that leads only into a committing mode), and the
    /// planner takes such a step only toward a named mode. The reward, the sum of the modes',
    /// is summed again only if a mode changed (the same modes give the same sum).
    ///
    /// Idempotent: settling a goal state settled on the same `current` changes nothing, so a
    /// caller that keeps a goal state settled on ŝ need not settle it again while ŝ is the same
    /// (the executive skips it then). Component by component, with `here` its current mode:
    /// - named, goal = here: the goal becomes s = `settles_in(here)`, or `here`. If s = here the
    ///   second pass takes this branch again and gives `settles_in(here)` or `here` — s both
    ///   ways. If s ≠ here, the goal is no longer `here`, and a named goal takes no other branch
    ///   that moves it: it stays s.
    /// - not named, left for good: the goal becomes `here`; the second pass asks whether `here`
    ///   was left for good for `here`, which `left_for_good` denies (its kept mode must differ),
    ///   so it stays.
    /// - otherwise the goal is unchanged, and so are the inputs of the second pass: the same
    ///   branch, unchanged again.
    ///
    /// No mode changes in the second pass, so neither does the reward; `named` and `leaving`
    /// are never written. (Property test: `settling_twice_is_settling_once`.)
    pub(crate) fn settle(&mut self, reconfiguration: &Reconfiguration, current: &[ValueId]) {
        let plant = reconfiguration.plant();
        let policies = reconfiguration.policies();
        let goals = self
            .modes
            .iter_mut()
            .zip(&self.named)
            .zip(current)
            .zip(policies);
        let mut changed = false;
        for (((goal, &named), &here), policy) in goals {
            let settled = if named && *goal == here {
                policy.settles_in(here).unwrap_or(here)
            } else if !named && left_for_good(plant, policy, *goal, here) {
                here
            } else {
                *goal
            };
            changed |= settled != *goal;
            *goal = settled;
        }
        if changed {
            self.reward = summed_reward(plant, &self.modes);
        }
    }

    /// The goal mode of every component, by [`ComponentId`].
    pub fn modes(&self) -> &[ValueId] {
        &self.modes
    }

    /// The goal mode of one component.
    pub fn mode(&self, c: ComponentId) -> ValueId {
        self.modes[c.index()]
    }

    /// True when the configuration goal named `c`'s goal mode explicitly (`lander =
    /// separated`): only then may the planner make an irreversible transition into it.
    pub fn is_named(&self, c: ComponentId) -> bool {
        self.named.get(c.index()).copied().unwrap_or(false)
    }

    /// The summed reward of the goal modes (§6.3.1's objective, maximised).
    pub fn reward(&self) -> f64 {
        self.reward
    }

    /// `component = mode, ...` with names.
    pub fn describe(&self, plant: &Plant) -> String {
        describe_modes(plant, &self.modes)
    }
}

/// True when a component kept in `kept` (not named by the goal) is now in `here`, a nominal
/// mode it cannot be brought back from: it got there by itself (an environment event such as an
/// IUS signal setting a flag, a timed transition out of a transient mode), and nobody asked for
/// `kept`, so the intention follows the plant instead of asking the planner for the impossible
/// every cycle. A fault is not followed: losing a kept mode to a fault is reported (no plan).
fn left_for_good(plant: &Plant, policy: &ConcurrentPolicy, kept: ValueId, here: ValueId) -> bool {
    let nominal =
        plant.component(policy.component()).modes()[here.index()].kind == ModeKind::Nominal;
    kept != here && nominal && !policy.reachability().is_reversible(here, kept)
}

/// The transitions whose guards, with every control idle, hold in `state` (see
/// [`GoalState::leaving`]): checked on the model's constraints with the state's modes.
fn leaving(reconfiguration: &Reconfiguration, state: &GoalState) -> Vec<(ComponentId, usize)> {
    let plant = reconfiguration.plant();
    let Ok(mut theory) = Theory::new(plant.table().clone(), &plant.constraints()) else {
        return Vec::new();
    };
    let mut assumptions: Vec<Literal> = plant
        .component_ids()
        .map(|(id, c)| Literal::Is(c.mode_var(), state.mode(id)))
        .collect();
    assumptions.extend(plant.controls().iter().map(|c| Literal::Is(c.var, c.idle)));
    let mut out = Vec::new();
    for (id, component) in plant.component_ids() {
        for &t in component.outgoing(state.mode(id)) {
            let transition = &component.transitions()[t];
            let nominal = component.mode(transition.target).kind != ModeKind::Fault;
            if nominal
                && theory
                    .entails(&assumptions, &transition.guard)
                    .unwrap_or(false)
            {
                out.push((id, t));
            }
        }
    }
    out
}

/// The summed reward of one mode per component.
fn summed_reward(plant: &Plant, modes: &[ValueId]) -> f64 {
    plant
        .components()
        .iter()
        .zip(modes)
        .map(|(c, &m)| c.modes().get(m.index()).map_or(0.0, |mode| mode.reward))
        .sum()
}

/// Checks that `current` gives every component one of its modes.
pub(crate) fn check_state(plant: &Plant, current: &[ValueId]) -> Result<(), String> {
    if current.len() != plant.components().len() {
        return Err(format!(
            "the state gives {} modes for {} components",
            current.len(),
            plant.components().len()
        ));
    }
    for (component, mode) in plant.components().iter().zip(current) {
        if mode.index() >= component.modes().len() {
            return Err(format!(
                "mode #{} is not a mode of `{}`",
                mode.0,
                component.name()
            ));
        }
    }
    Ok(())
}

/// The `component = mode` atoms the goal asserts positively (under no negation), per component.
fn named_modes(plant: &Plant, goal: &Formula) -> Vec<Vec<ValueId>> {
    fn visit(f: &Formula, positive: bool, out: &mut Vec<(VarId, ValueId)>) {
        match f {
            Formula::Atom(Atom::Is(x, v)) if positive => out.push((*x, *v)),
            Formula::Not(g) => visit(g, !positive, out),
            Formula::And(gs) | Formula::Or(gs) => gs.iter().for_each(|g| visit(g, positive, out)),
            Formula::Implies(a, b) => {
                visit(a, !positive, out);
                visit(b, positive, out);
            }
            _ => {}
        }
    }
    let mut atoms = Vec::new();
    visit(goal, true, &mut atoms);
    let mut named = vec![Vec::new(); plant.components().len()];
    for (x, v) in atoms {
        if let Some(c) = plant.component_of(x) {
            named[c.index()].push(v);
        }
    }
    named
}

/// The goal as assumptions, each with the part of the goal it stands for: one literal per
/// assignment of a conjunction of assignments, else one defined literal for the whole goal.
fn goal_parts(theory: &mut Theory, goal: &Formula) -> Result<Vec<(Literal, Formula)>, String> {
    if let Some(assignments) = goal.as_assignments() {
        return Ok(assignments
            .into_iter()
            .map(|(x, v)| (Literal::Is(x, v), Formula::is(x, v)))
            .collect());
    }
    let literal = theory.define(goal).map_err(|e| e.to_string())?;
    Ok(vec![(literal, goal.clone())])
}

/// Goal interpretation; see [`Reconfiguration::interpret`].
pub(crate) fn interpret(
    reconfiguration: &Reconfiguration,
    theory: &mut Theory,
    current: &[ValueId],
    goal: &Formula,
    keep: &[ValueId],
) -> Result<GoalState, GoalFailed> {
    let plant = reconfiguration.plant();
    check_state(plant, current).map_err(GoalFailed::bad_input)?;
    check_state(plant, keep).map_err(GoalFailed::bad_input)?;
    if theory.table() != plant.table() {
        return Err(GoalFailed::bad_input(
            "the theory is not the plant's (use the plant's `theory()`)",
        ));
    }
    if goal.has_external_atoms() {
        return Err(GoalFailed::bad_input(
            "the goal holds a clock or confidence atom: ground it before goal interpretation",
        ));
    }
    let feasible = feasible(
        plant,
        reconfiguration.policies(),
        reconfiguration.upstream_first(),
        current,
    );
    let named = named_modes(plant, goal);
    let domains = domains(reconfiguration, current, &feasible, &named);
    let parts = goal_parts(theory, goal).map_err(GoalFailed::bad_input)?;
    let ocsp = goal_ocsp(plant, (current, keep), &domains, &named, &parts)?;
    // A goal state the plant rests in (see `Reconfiguration::resting`), when there is one;
    // otherwise the goal is one the plant leaves by itself, and the state says so.
    let mut search = Search::NoneConsistent;
    let mut restless = false;
    if let Some(resting) = reconfiguration.resting() {
        let literal = theory
            .define(resting)
            .map_err(|e| GoalFailed::bad_input(e.to_string()))?;
        let mut at_rest = ocsp.clone();
        at_rest.assume(literal);
        search = first_entailing(plant, theory, &at_rest, goal)?;
        restless = !matches!(search, Search::Found(_));
    }
    if !matches!(search, Search::Found(_)) {
        search = first_entailing(plant, theory, &ocsp, goal)?;
    }
    match search {
        Search::Found(modes) => {
            let named: Vec<ComponentId> = plant
                .component_ids()
                .map(|(id, _)| id)
                .filter(|id| named[id.index()].contains(&modes[id.index()]))
                .collect();
            let mut state = GoalState::new(plant, modes, &named);
            if restless {
                state.leaving = leaving(reconfiguration, &state);
            }
            Ok(state)
        }
        Search::NoneEntails { cut } => {
            let scope = if cut {
                format!("among the {ENTAILMENT_CANDIDATES} best reachable states, none")
            } else {
                "no reachable state".to_string()
            };
            Err(GoalFailed {
                reason: format!(
                    "{scope} entails `{}`: the states consistent with it leave it undetermined",
                    goal.display(plant.table())
                ),
                cause: FailureCause::NotEntailed,
            })
        }
        Search::NoneConsistent => Err(explain(
            reconfiguration,
            theory,
            current,
            &Explanation {
                feasible: &feasible,
                domains: &domains,
                named: &named,
                parts: &parts,
            },
        )),
    }
}

/// §6.3.1's OCSP: a decision per component over its allowed modes, cost −reward (plus
/// [`MOVE_COST`] for a move, and [`HOLD_COST`] for leaving the kept mode of a component the goal
/// does not name), the goal's parts that are not mode assignments as assumptions.
fn goal_ocsp(
    plant: &Plant,
    (current, keep): (&[ValueId], &[ValueId]),
    domains: &[Vec<ValueId>],
    named: &[Vec<ValueId>],
    parts: &[(Literal, Formula)],
) -> Result<Ocsp, GoalFailed> {
    let mut ocsp = Ocsp::new();
    for (id, component) in plant.component_ids() {
        let here = current[id.index()];
        let kept = keep[id.index()];
        let held = named[id.index()].is_empty();
        let choices = narrowed(plant, &domains[id.index()], id, parts)
            .into_iter()
            .map(|v| {
                let moving = if v == here { 0.0 } else { MOVE_COST };
                let leaving = if held && v != kept { HOLD_COST } else { 0.0 };
                (v, moving + leaving - component.mode(v).reward)
            });
        if ocsp.decide(component.mode_var(), choices).is_err() {
            return Err(GoalFailed::bad_input(format!(
                "component `{}` has a reward that is not a number",
                component.name()
            )));
        }
    }
    for (literal, _) in parts {
        let on_a_mode = matches!(literal, Literal::Is(x, _) if plant.component_of(*x).is_some());
        if !on_a_mode {
            ocsp.assume(*literal);
        }
    }
    Ok(ocsp)
}

/// What the search for a goal state found.
enum Search {
    /// The best candidate that entails the goal: a mode per component.
    Found(Vec<ValueId>),
    /// Candidates exist but none entails the goal (`cut`: the search gave up first).
    NoneEntails { cut: bool },
    /// No candidate is consistent with the model and the goal.
    NoneConsistent,
}

/// The best candidate entailing `goal`. When the goal is a conjunction of mode assignments
/// (already in the domains) every candidate does; otherwise each is checked.
fn first_entailing(
    plant: &Plant,
    theory: &mut Theory,
    ocsp: &Ocsp,
    goal: &Formula,
) -> Result<Search, GoalFailed> {
    let mode_goal = goal
        .as_assignments()
        .is_some_and(|a| a.iter().all(|&(x, _)| plant.component_of(x).is_some()));
    // One search over all the decisions: GI wants the first entailing candidate, and a
    // decomposed search fetches two solutions of every independent sub-problem before its
    // first (two SAT calls per component of a loosely coupled plant; docs/design/opsat.md).
    let options = SearchOptions {
        decompose: false,
        ..SearchOptions::default()
    };
    let mut candidates = ocsp.enumerate(theory, options);
    let mut tested = 0u64;
    while let Ok(Some(solution)) = candidates.next(theory) {
        let entailed = mode_goal
            || theory
                .entails(&solution.literals(), goal)
                .map_err(|e| GoalFailed::bad_input(e.to_string()))?;
        if entailed {
            return Ok(Search::Found(
                solution.assignment.iter().map(|&(_, v)| v).collect(),
            ));
        }
        tested += 1;
        if tested >= ENTAILMENT_CANDIDATES {
            return Ok(Search::NoneEntails { cut: true });
        }
    }
    Ok(if tested > 0 {
        Search::NoneEntails { cut: false }
    } else {
        Search::NoneConsistent
    })
}

/// `domain` without the modes the goal's own assignments to component `c` exclude. Goal
/// assignments to mode variables narrow the decision instead of being assumed: the same
/// problem, smaller, and OPSAT's conflict-directed search only learns conflicts over its
/// decisions from the candidates, not from assumptions on the decision variables themselves.
fn narrowed(
    plant: &Plant,
    domain: &[ValueId],
    c: ComponentId,
    parts: &[(Literal, Formula)],
) -> Vec<ValueId> {
    let var = plant.component(c).mode_var();
    domain
        .iter()
        .copied()
        .filter(|&v| {
            parts
                .iter()
                .all(|(literal, _)| !matches!(*literal, Literal::Is(x, w) if x == var && w != v))
        })
        .collect()
}

/// Per component, the modes GI may choose: its helper modes and the named feasible finals,
/// without the transient modes (left by themselves) the goal does not name, unless current.
fn domains(
    reconfiguration: &Reconfiguration,
    current: &[ValueId],
    feasible: &Feasible,
    named: &[Vec<ValueId>],
) -> Vec<Vec<ValueId>> {
    reconfiguration
        .policies()
        .iter()
        .enumerate()
        .map(|(c, policy)| {
            let (helpers, finals) = (&feasible.helpers[c], &feasible.finals[c]);
            (0..helpers.len())
                .map(|v| ValueId(v as u32))
                .filter(|v| {
                    let is_named = named[c].contains(v);
                    let holdable = !policy.is_transient(*v) || is_named || *v == current[c];
                    holdable && (helpers[v.index()] || (finals[v.index()] && is_named))
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::Action;
    use super::super::Reconfiguration;
    use super::super::testing::{
        SWITCH_GADGET, TRANSIENT_CHAIN, TRANSIENT_REPAIR, component, load, mode, model, state,
    };
    use super::{FailureCause, GoalState, named_modes};
    use crate::logic::{ValueId, parse_formula};
    use crate::plant::ComponentId;
    use crate::seeded;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(seeded::config(256))]

        /// `GoalState::settle` is idempotent (its documentation's argument; docs/design/
        /// reconfiguration.md, "The intended configuration"): on plants with transient modes
        /// (in a chain, `TRANSIENT_CHAIN`) and modes left for good (it, the Mars lander's EDL,
        /// the engine and camera, the spacecraft's deployment), any goal modes, any named
        /// components and any current state, settling the settled goal on the same state gives
        /// it back, reward bit for bit.
        #[test]
        fn settling_twice_is_settling_once(
            which in 0usize..4,
            goal in proptest::collection::vec((0u32..16, any::<bool>()), 40),
            current in proptest::collection::vec(0u32..16, 40),
            here_is_goal in proptest::collection::vec(any::<bool>(), 40),
        ) {
            let plant = match which {
                0 => load(TRANSIENT_CHAIN),
                1 => model("mars_lander"),
                2 => model("engine_camera"),
                _ => model("spacecraft_deployment"),
            };
            let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
            let modes_of = |c: usize| plant.components()[c].modes().len() as u32;
            let n = plant.components().len();
            let goal_modes: Vec<ValueId> =
                (0..n).map(|c| ValueId(goal[c].0 % modes_of(c))).collect();
            let named: Vec<ComponentId> =
                (0..n).filter(|&c| goal[c].1).map(|c| ComponentId(c as u32)).collect();
            // Half the components where the goal has them, so the named branch is taken.
            let current: Vec<ValueId> = (0..n)
                .map(|c| if here_is_goal[c] { goal_modes[c] } else { ValueId(current[c] % modes_of(c)) })
                .collect();
            let goal = GoalState::new(&plant, goal_modes, &named);
            let once = reconfiguration.settle(&goal, &current);
            let twice = reconfiguration.settle(&once, &current);
            prop_assert_eq!(twice.modes(), once.modes());
            prop_assert_eq!(twice.reward().to_bits(), once.reward().to_bits());
            prop_assert_eq!(&twice, &once);
        }
    }

    #[test]
    fn only_positive_mode_atoms_are_named() {
        let plant = load(SWITCH_GADGET);
        let goal = parse_formula(
            "gadget = c and not gadget = d and (switch = on => gadget = b) and gadget.power = on",
            plant.table(),
        )
        .expect("formula");
        let named = named_modes(&plant, &goal);
        let gadget = component(&plant, "gadget").index();
        assert_eq!(
            named[gadget],
            [mode(&plant, "gadget", "c"), mode(&plant, "gadget", "b")]
        );
        assert!(named[component(&plant, "switch").index()].is_empty());
    }

    #[test]
    fn ties_stay_put_and_transient_modes_are_offered_only_where_the_gadget_is() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let mut theory = plant.theory().expect("theory");
        let gadget = component(&plant, "gadget");
        let anything = parse_formula("true", plant.table()).expect("formula");
        for here in ["a", "e"] {
            let current = state(&plant, &["off", here]);
            let goal = reconfiguration
                .interpret(&mut theory, &current, &anything)
                .expect("a goal state");
            assert_eq!(goal.mode(gadget), mode(&plant, "gadget", here));
        }
        // Leaving e: a, the transient mode, is not offered; b is.
        let not_e = parse_formula("not gadget = e", plant.table()).expect("formula");
        let current = state(&plant, &["off", "e"]);
        let goal = reconfiguration
            .interpret(&mut theory, &current, &not_e)
            .expect("a goal state");
        assert_eq!(goal.mode(gadget), mode(&plant, "gadget", "b"));
    }

    /// The spacecraft deployment: a mode merely kept that the component has left for
    /// good by nominal transitions (an IUS signal setting a flag) is not pursued: before, the
    /// planner reported "no plannable path" for it every cycle no goal was asserted. A kept mode
    /// still reachable (a repairable fault) or lost to a fault without repair stays.
    #[test]
    fn kept_modes_left_for_good_follow_the_plant() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let mut theory = plant.theory().expect("theory");
        let gadget = component(&plant, "gadget");
        let switch = component(&plant, "switch");
        let off = parse_formula("switch = off", plant.table()).expect("formula");
        let kept = reconfiguration
            .interpret(&mut theory, &state(&plant, &["off", "b"]), &off)
            .expect("a goal state");
        assert_eq!(kept.mode(gadget), mode(&plant, "gadget", "b"));
        assert!(!kept.is_named(gadget));
        // The gadget went on to c (b -> c is irreversible): the goal follows it.
        let moved_on = state(&plant, &["off", "c"]);
        let settled = reconfiguration.settle(&kept, &moved_on);
        assert_eq!(settled.mode(gadget), mode(&plant, "gadget", "c"));
        assert_eq!(
            reconfiguration.next_action(&moved_on, &settled),
            Action::Achieved
        );
        // Broken, the gadget can be repaired back to b: kept, and repaired.
        let broken = state(&plant, &["off", "broken"]);
        let settled = reconfiguration.settle(&kept, &broken);
        assert_eq!(settled.mode(gadget), mode(&plant, "gadget", "b"));
        assert!(matches!(
            reconfiguration.next_action(&broken, &settled),
            Action::Command(_)
        ));
        // A stuck switch has no repair: kept off, and the planner says it cannot.
        let stuck = state(&plant, &["stuck", "b"]);
        let settled = reconfiguration.settle(&kept, &stuck);
        assert_eq!(settled.mode(switch), mode(&plant, "switch", "off"));
        assert!(matches!(
            reconfiguration.next_action(&stuck, &settled),
            Action::Failure(_)
        ));
    }

    #[test]
    fn irreversible_goals_must_be_named_and_unreachable_ones_are_explained() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let mut theory = plant.theory().expect("theory");
        let current = state(&plant, &["off", "a"]);
        let c = parse_formula("gadget = c", plant.table()).expect("formula");
        let goal = reconfiguration
            .interpret(&mut theory, &current, &c)
            .expect("named, so offered");
        assert!(goal.is_named(component(&plant, "gadget")));
        let d = parse_formula("gadget = d", plant.table()).expect("formula");
        let failed = reconfiguration
            .interpret(&mut theory, &current, &d)
            .expect_err("two irreversible steps away");
        assert_eq!(
            failed.reason,
            "gadget = d is unreachable: gadget can reach only a, b, e from a; gadget = c would \
             be irreversible and the goal does not name it"
        );
        assert!(matches!(failed.cause, FailureCause::Unreachable { .. }));
    }

    /// A repair that leads only through a transient mode into an irreversible one leaves the
    /// component no mode to hold; the reason says which modes it can reach and why none is
    /// offered, instead of an empty list.
    #[test]
    fn a_repair_into_a_transient_mode_only_is_explained() {
        let plant = load(TRANSIENT_REPAIR);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let mut theory = plant.theory().expect("theory");
        let current = state(&plant, &["broken"]);
        let a = parse_formula("gadget = a", plant.table()).expect("formula");
        let failed = reconfiguration
            .interpret(&mut theory, &current, &a)
            .expect_err("a is out of reach");
        assert_eq!(
            failed.reason,
            "gadget = a is unreachable: gadget can reach from broken only the transient mode t, \
             which it leaves by itself; gadget = c would be irreversible and the goal does not \
             name it"
        );
        assert!(matches!(
            failed.cause,
            FailureCause::Unreachable { ref goals, ref components }
                if goals.is_empty() && components == &[component(&plant, "gadget")]
        ));
        // Named, the irreversible mode and the transient one are offered.
        for named in ["gadget = c", "gadget = t"] {
            let goal = parse_formula(named, plant.table()).expect("formula");
            assert!(
                reconfiguration
                    .interpret(&mut theory, &current, &goal)
                    .is_ok()
            );
        }
    }

    /// §6.1.2's camera: a goal on `taking-picture`, which the camera leaves by itself, is
    /// achieved once; the configuration kept afterwards is the idle camera it returns to, so
    /// the planner does not take another picture (nor, had it failed, repair it into one).
    #[test]
    fn a_reached_transient_goal_mode_settles_where_the_component_goes_by_itself() {
        let plant = model("engine_camera");
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let mut theory = plant.theory().expect("theory");
        let camera = component(&plant, "camera");
        let picture = parse_formula("camera = taking-picture", plant.table()).expect("formula");
        let idle = state(&plant, &["firing", "idle"]);
        let goal = reconfiguration
            .interpret(&mut theory, &idle, &picture)
            .expect("a goal state");
        // Not reached yet: kept as it is, and the planner commands the picture.
        assert_eq!(reconfiguration.settle(&goal, &idle), goal);
        assert!(matches!(
            reconfiguration.next_action(&idle, &goal),
            Action::Command(_)
        ));
        // Reached: achieved now, and from then on the camera is meant to be idle.
        let taking = state(&plant, &["firing", "taking-picture"]);
        assert_eq!(
            reconfiguration.next_action(&taking, &goal),
            Action::Achieved
        );
        let settled = reconfiguration.settle(&goal, &taking);
        assert_eq!(settled.mode(camera), mode(&plant, "camera", "idle"));
        assert!(settled.is_named(camera));
        assert_eq!(
            settled.mode(component(&plant, "engine")),
            goal.mode(component(&plant, "engine"))
        );
        assert!(matches!(
            reconfiguration.next_action(&taking, &settled),
            Action::Idle(_)
        ));
        assert_eq!(
            reconfiguration.next_action(&idle, &settled),
            Action::Achieved
        );
        // A transient mode the goal did not name (the camera merely kept where it is) stays.
        let kept = GoalState::new(&plant, taking.clone(), &[]);
        assert_eq!(reconfiguration.settle(&kept, &taking), kept);
        // Settling a settled goal changes nothing; nor does a state of the wrong shape panic.
        assert_eq!(reconfiguration.settle(&settled, &idle), settled);
        assert_eq!(reconfiguration.settle(&settled, &[]), settled);
    }

    /// A control is consistent with every state and entailed by none: such a goal is not a
    /// configuration of the plant.
    #[test]
    fn a_goal_no_state_entails_is_not_entailed() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let mut theory = plant.theory().expect("theory");
        let current = state(&plant, &["off", "a"]);
        let command = parse_formula("switch.cmd = on", plant.table()).expect("formula");
        let failed = reconfiguration
            .interpret(&mut theory, &current, &command)
            .expect_err("not a configuration");
        assert_eq!(failed.cause, FailureCause::NotEntailed);
        assert_eq!(
            failed.reason,
            "no reachable state entails `switch.cmd = on`: the states consistent with it leave \
             it undetermined"
        );
    }
}
