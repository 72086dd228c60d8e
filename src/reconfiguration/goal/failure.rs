//! Why goal interpretation found no goal state (§6.3.1; DESIGN.md §9's **goal failed**).
//!
//! When no candidate is consistent, the goal's assignments and each component's restriction to
//! the modes it may take are assumed together, and the theory's *minimal* conflict among them
//! names exactly the goals and components responsible: the reason a person reads ("engine =
//! standby is unreachable: engine is failed"; "conflicting goals: … cannot hold together").
//! Each component in the conflict is described by where it is, what it can reach and, for a
//! move its policy blocks, every alternative way of making that move with what each lacks.

use std::fmt;

use super::super::Reconfiguration;
use super::super::feasible::{BlockedMove, Feasible};
use super::super::reachability::members;
use crate::logic::{Formula, ValueId};
use crate::opsat::{Consistency, Literal, Theory};
use crate::plant::{ComponentId, ModeKind, Plant};

/// Why goal interpretation found no goal state.
#[derive(Debug, Clone, PartialEq)]
pub enum FailureCause {
    /// These parts of the goal hold in no state the components can reach; these components'
    /// limited reach is responsible.
    Unreachable {
        /// The parts of the goal in the conflict.
        goals: Vec<Formula>,
        /// The components whose reachable modes are in the conflict.
        components: Vec<ComponentId>,
    },
    /// These parts of the goal cannot hold together in any state of the model.
    Contradictory {
        /// The parts of the goal in the conflict.
        goals: Vec<Formula>,
    },
    /// Reachable states are consistent with the goal but none entails it.
    NotEntailed,
    /// The state or the goal cannot be interpreted (wrong shape, clock or confidence atoms, a
    /// theory of another plant).
    BadInput,
}

/// Goal interpretation's failure: DESIGN.md §9's **goal failed**, with a human reason.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalFailed {
    /// A sentence naming the goals, components and modes responsible.
    pub reason: String,
    /// The same, structured.
    pub cause: FailureCause,
}

impl GoalFailed {
    pub(super) fn bad_input(reason: impl Into<String>) -> GoalFailed {
        GoalFailed {
            reason: reason.into(),
            cause: FailureCause::BadInput,
        }
    }
}

impl fmt::Display for GoalFailed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.reason)
    }
}

impl std::error::Error for GoalFailed {}

/// What GI knew when it found no candidate.
pub(super) struct Explanation<'a> {
    pub(super) feasible: &'a Feasible,
    pub(super) domains: &'a [Vec<ValueId>],
    pub(super) named: &'a [Vec<ValueId>],
    pub(super) parts: &'a [(Literal, Formula)],
}

/// Where an assumption of the explanation came from.
enum Origin {
    Goal(usize),
    Component(ComponentId),
}

/// Turns the minimal conflict between the goal and the components' allowed modes into a reason.
pub(super) fn explain(
    reconfiguration: &Reconfiguration,
    theory: &mut Theory,
    current: &[ValueId],
    why: &Explanation<'_>,
) -> GoalFailed {
    let plant = reconfiguration.plant();
    let table = plant.table();
    let mut assumptions = Vec::new();
    let mut origins = Vec::new();
    for (i, (literal, _)) in why.parts.iter().enumerate() {
        assumptions.push(*literal);
        origins.push(Origin::Goal(i));
    }
    for (id, component) in plant.component_ids() {
        let domain = &why.domains[id.index()];
        if domain.len() == component.modes().len() {
            continue;
        }
        let restriction = Formula::Or(
            domain
                .iter()
                .map(|&v| Formula::is(component.mode_var(), v))
                .collect(),
        );
        let literal = match domain.as_slice() {
            [only] => Literal::Is(component.mode_var(), *only),
            _ => match theory.define(&restriction) {
                Ok(literal) => literal,
                Err(_) => continue,
            },
        };
        assumptions.push(literal);
        origins.push(Origin::Component(id));
    }
    let Consistency::Conflict(conflict) = theory.minimal_conflict(&assumptions) else {
        return GoalFailed {
            reason: "no reachable state achieves the goal".to_string(),
            cause: FailureCause::NotEntailed,
        };
    };
    let mut goals = Vec::new();
    let mut components = Vec::new();
    for literal in conflict {
        match assumptions
            .iter()
            .position(|a| *a == literal)
            .map(|i| &origins[i])
        {
            Some(Origin::Goal(i)) => goals.push(why.parts[*i].1.clone()),
            Some(Origin::Component(c)) => components.push(*c),
            None => {}
        }
    }
    // A component with no mode to choose blocks every goal: the conflict is that component
    // alone, and the whole goal is what it makes unreachable.
    let stranded = components.iter().any(|c| why.domains[c.index()].is_empty());
    let goal_text = if goals.is_empty() && stranded {
        why.parts
            .iter()
            .map(|(_, g)| g.display(table).to_string())
            .collect::<Vec<_>>()
    } else {
        goals.iter().map(|g| g.display(table).to_string()).collect()
    };
    let goal_text = if goal_text.is_empty() {
        "the goal".to_string()
    } else {
        goal_text.join(" and ")
    };
    let reach = components
        .iter()
        .map(|&c| describe_reach(plant, current, why, c))
        .collect::<Vec<_>>()
        .join("; ");
    match (goals.len(), components.is_empty()) {
        (0, _) if stranded => GoalFailed {
            reason: format!("{goal_text} is unreachable: {reach}"),
            cause: FailureCause::Unreachable { goals, components },
        },
        (0, _) => GoalFailed {
            reason: format!("the current state contradicts the model: {reach}"),
            cause: FailureCause::Unreachable { goals, components },
        },
        (_, false) => GoalFailed {
            reason: format!("{goal_text} is unreachable: {reach}"),
            cause: FailureCause::Unreachable { goals, components },
        },
        (1, true) => GoalFailed {
            reason: format!("the goal {goal_text} contradicts the model"),
            cause: FailureCause::Contradictory { goals },
        },
        (_, true) => GoalFailed {
            reason: format!("conflicting goals: {goal_text} cannot hold together"),
            cause: FailureCause::Contradictory { goals },
        },
    }
}

/// "engine is failed", "valve1 can reach only closed from closed (PDE is failed)", or "gadget
/// can reach from broken only the transient mode t, which it leaves by itself",
/// with the irreversible modes the goal did not name.
fn describe_reach(
    plant: &Plant,
    current: &[ValueId],
    why: &Explanation<'_>,
    c: ComponentId,
) -> String {
    let component = plant.component(c);
    let here = current[c.index()];
    let name = |v: ValueId| component.mode(v).name.as_str();
    let domain = &why.domains[c.index()];
    let mut text = if domain.as_slice() == [here] && component.mode(here).kind == ModeKind::Fault {
        format!("{} is {}", component.name(), name(here))
    } else if domain.is_empty() {
        // Only a repaired fault leaves its component nothing to choose (otherwise the current
        // mode stays a helper mode): every mode the repair reaches is transient, which goal
        // interpretation offers only when named, and the modes they lead to are irreversible.
        let passing: Vec<&str> = members(&why.feasible.helpers[c.index()])
            .map(name)
            .collect();
        let modes = if passing.len() == 1 { "mode" } else { "modes" };
        format!(
            "{} can reach from {} only the transient {modes} {}, which it leaves by itself",
            component.name(),
            name(here),
            passing.join(", ")
        )
    } else {
        let modes: Vec<&str> = domain.iter().map(|&v| name(v)).collect();
        format!(
            "{} can reach only {} from {}",
            component.name(),
            modes.join(", "),
            name(here)
        )
    };
    let moves = &why.feasible.blocked_moves[c.index()];
    if !moves.is_empty() {
        let sentences: Vec<String> = moves
            .iter()
            .map(|m| describe_blocked_move(plant, current, c, m))
            .collect();
        text.push_str(&format!(" ({})", sentences.join("; ")));
    }
    let unnamed: Vec<&str> = (0..component.modes().len())
        .map(|v| ValueId(v as u32))
        .filter(|v| why.feasible.finals[c.index()][v.index()] && !why.named[c.index()].contains(v))
        .map(name)
        .collect();
    if !unnamed.is_empty() {
        text.push_str(&format!(
            "; {} would be irreversible and the goal does not name it",
            unnamed
                .iter()
                .map(|m| format!("{} = {m}", component.name()))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    text
}

/// "powered needs reg_a = on (reg_a is failed) or reg_b = on (reg_b is failed)": every
/// alternative way of making a blocked move, each with the sub-goals it cannot have and where
/// their components are (DESIGN.md §9: an unreachable goal names each alternative and why).
fn describe_blocked_move(
    plant: &Plant,
    current: &[ValueId],
    c: ComponentId,
    blocked: &BlockedMove,
) -> String {
    let component = plant.component(c);
    let ways: Vec<String> = blocked
        .alternatives
        .iter()
        .map(|missing| {
            missing
                .iter()
                .map(|&(u, v)| {
                    let upstream = plant.component(u);
                    let (name, wanted) = (upstream.name(), &upstream.mode(v).name);
                    let here = current[u.index()];
                    if here == v {
                        // Where it is, but not where it can stay (a repair mode it moves on from).
                        format!("{name} = {wanted} ({name} cannot stay in {wanted})")
                    } else {
                        format!("{name} = {wanted} ({name} is {})", upstream.mode(here).name)
                    }
                })
                .collect::<Vec<_>>()
                .join(" and ")
        })
        .collect();
    format!(
        "{} -> {} needs {}",
        component.mode(blocked.source).name,
        component.mode(blocked.target).name,
        ways.join(" or ")
    )
}
