//! Goal types, elaborators and tactics (mds-goal-networks.md §2.1, §2.6; AG §1.2.5, §1.2.7 c,
//! §3.9; DESIGN.md §15.1): a named goal *type* (StayWarm, Heater) carries the failure response
//! its goals take and an ordered list of tactics; a tactic adds child goals, time points and
//! temporal constraints written relative to the parent's two points and its state variable.

use super::constraint_set::ConstraintSet;
use super::goal::{GoalId, GoalKind};
use super::network::GoalNetwork;
use crate::diagnostic::Span;
use crate::plant::ComponentId;

/// The re-elaborations a goal gets per network lifetime when its type does not say
/// (mds-goal-networks.md §2.7 step 4: "default 3", to stop oscillation).
pub const DEFAULT_REELABORATION_BUDGET: u32 = 3;

/// A goal type's index in its mission.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TypeId(pub u32);

impl TypeId {
    /// The index as a `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// What a goal of a type does when it fails: the four responses the seeds name (AG §1.2.7 c;
/// GP §3.8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Response {
    /// Stop and put the system safe: promote the safe network.
    Safing,
    /// Re-elaborate this goal with its next tactic, cyclically, within its budget.
    ReElaborate,
    /// Pass the failure to the parent goal (a root has none: safing).
    FailUp,
    /// Do nothing: let the plan run and hope for the best.
    Ignore,
}

impl Response {
    /// The word used in mission files and messages.
    pub fn name(self) -> &'static str {
        match self {
            Response::Safing => "Safing",
            Response::ReElaborate => "ReElaborate",
            Response::FailUp => "FailUp",
            Response::Ignore => "Ignore",
        }
    }
}

/// A named goal type: its failure response and its elaborator's tactics.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalType {
    /// Its name in the mission (`"StayWarm"`).
    pub name: String,
    /// What a failed goal of this type does.
    pub response: Response,
    /// How often one goal may be re-elaborated (for [`Response::ReElaborate`]).
    pub budget: u32,
    /// The elaborator's tactics, in the order they are tried; none for a terminal type.
    pub tactics: Vec<Tactic>,
    /// Where it is declared.
    pub span: Span,
}

/// One way to elaborate a goal (an *ElaborationSpec* generator, AG §3.9): never the parent
/// goal or its points themselves.
#[derive(Debug, Clone, PartialEq)]
pub struct Tactic {
    /// Its name (`"heater 1"`), for messages.
    pub name: String,
    /// The points it adds, by local name (a re-elaboration adds fresh ones:
    /// `stay-warm#2.TP_A`).
    pub points: Vec<String>,
    /// The temporal constraints it adds.
    pub constraints: Vec<TacticConstraint>,
    /// The child goals it adds, in the order they are elaborated.
    pub goals: Vec<ChildGoal>,
}

/// A point a tactic refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointRef {
    /// The parent goal's start point (`"start"` in the file).
    Start,
    /// The parent goal's end point (`"end"`).
    End,
    /// The tactic's own point of this index.
    Local(usize),
}

/// `min ≤ t(to) − t(from) ≤ max` between the parent's and the tactic's points.
#[derive(Debug, Clone, PartialEq)]
pub struct TacticConstraint {
    /// The earlier point.
    pub from: PointRef,
    /// The later point.
    pub to: PointRef,
    /// The least separation, seconds.
    pub min: f64,
    /// The greatest separation, seconds (`f64::INFINITY` for none).
    pub max: f64,
    /// Where it is written (its provenance in the network).
    pub span: Span,
}

/// The constraint of a child goal.
#[derive(Debug, Clone, PartialEq)]
pub enum ChildConstraint {
    /// The parent's (a child on its parent's state variable, as Heater's switch transition).
    Inherit,
    /// Its own, resolved against the plant, and the text as written.
    Given(ConstraintSet, String),
}

/// A goal a tactic adds.
#[derive(Debug, Clone, PartialEq)]
pub struct ChildGoal {
    /// Its name, local to its parent (`heater1`: `stay-warm.heater1`, `stay-warm#2.heater1`).
    pub name: String,
    /// Its type, if it has one (an elaborator, a failure response).
    pub goal_type: Option<TypeId>,
    /// Its state variable; `None` for the parent's.
    pub sv: Option<ComponentId>,
    /// How its constraint is judged.
    pub kind: GoalKind,
    /// Its constraint.
    pub constraint: ChildConstraint,
    /// Its start point.
    pub start: PointRef,
    /// Its end point.
    pub end: PointRef,
    /// Its priority.
    pub priority: i32,
    /// Where it is written.
    pub span: Span,
}

/// A mission's goal types and which of its initial goals have which.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Elaborators {
    /// Every goal type, in declaration order; a type's index is its id.
    pub types: Vec<GoalType>,
    /// Per goal of the mission's initial network (by id), its type.
    pub of_goal: Vec<Option<TypeId>>,
}

impl Elaborators {
    /// One type.
    pub fn get(&self, id: TypeId) -> &GoalType {
        &self.types[id.index()]
    }

    /// The type with this name.
    pub fn named(&self, name: &str) -> Option<TypeId> {
        self.types
            .iter()
            .position(|t| t.name == name)
            .map(|i| TypeId(i as u32))
    }

    /// The type of an initial goal.
    pub fn of(&self, goal: GoalId) -> Option<TypeId> {
        self.of_goal.get(goal.index()).copied().flatten()
    }
}

/// Every name a point or goal of a running mission can have (the mission's own, those its
/// elaborations give — `stay-warm.TP_A`, `stay-warm.get-warm.heater1` — and the safe
/// network's), without the elaboration counts a re-elaboration adds (`stay-warm#2.TP_A`) or the
/// primes a name taken already gets: what a scenario's expectations may name before the run has
/// made them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MissionNames {
    /// Time points.
    pub points: Vec<String>,
    /// Goals (macro goals included).
    pub goals: Vec<String>,
}

impl MissionNames {
    /// Whether `name`, elaboration counts (`#2`) and primes aside, is one of `names`.
    fn has(names: &[String], name: &str) -> bool {
        let plain: Vec<&str> = name
            .trim_end_matches('′')
            .split('.')
            .map(|segment| match segment.rsplit_once('#') {
                Some((base, n)) if !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) => base,
                _ => segment,
            })
            .collect();
        let plain = plain.join(".");
        names.contains(&plain)
    }

    /// Whether a point can have this name.
    pub fn has_point(&self, name: &str) -> bool {
        Self::has(&self.points, name)
    }

    /// Whether a goal can have this name.
    pub fn has_goal(&self, name: &str) -> bool {
        Self::has(&self.goals, name)
    }
}

impl Elaborators {
    /// The names of `network`'s points and goals, of everything its typed goals' tactics can
    /// add (recursively, a type not re-entered below itself), and of `safe`'s, with `safing`,
    /// the point safing promotes from (`GoalController`'s naming, elaborate.rs and proposal.rs).
    pub fn names(&self, network: &GoalNetwork, safe: &GoalNetwork) -> MissionNames {
        let mut names = MissionNames::default();
        // The safe network's origin becomes the point `safing`.
        names
            .points
            .extend(network.points().iter().map(|p| p.name.clone()));
        names.points.push("safing".to_string());
        names
            .points
            .extend(safe.points()[1..].iter().map(|p| p.name.clone()));
        for graph in [network, safe] {
            let goals = graph.goals().iter().filter(|g| !g.is_macro());
            names.goals.extend(goals.map(|g| g.name.clone()));
        }
        for (i, goal) in network.goals().iter().enumerate() {
            if let Some(t) = self.of(GoalId(i as u32)) {
                self.elaborated_names(&goal.name, t, &mut Vec::new(), &mut names);
            }
        }
        names
    }

    /// Adds the names the tactics of type `t` give a goal named `goal` (a typed goal submitted
    /// to the running mission), and their typed children's.
    pub fn add_elaborated(&self, goal: &str, t: TypeId, names: &mut MissionNames) {
        self.elaborated_names(goal, t, &mut Vec::new(), names);
    }

    /// The names `goal`'s tactics (of type `t`) give, and their typed children's, depth first.
    fn elaborated_names(
        &self,
        goal: &str,
        t: TypeId,
        path: &mut Vec<TypeId>,
        names: &mut MissionNames,
    ) {
        if path.contains(&t) {
            return;
        }
        path.push(t);
        for tactic in &self.get(t).tactics {
            names
                .points
                .extend(tactic.points.iter().map(|p| format!("{goal}.{p}")));
            for child in &tactic.goals {
                let name = format!("{goal}.{}", child.name);
                if let Some(child_type) = child.goal_type {
                    self.elaborated_names(&name, child_type, path, names);
                }
                names.goals.push(name);
            }
        }
        path.pop();
    }
}

#[cfg(test)]
mod tests {
    //! The names a scenario's expectations may use (docs/design/goal-networks.md, "Names").

    use super::MissionNames;

    /// An elaboration count on any segment, and primes, are set aside: `stay-warm#2.TP_A` is a
    /// name `stay-warm.TP_A` stands for; a `#` not followed by digits is not a count.
    #[test]
    fn elaboration_counts_and_primes_are_set_aside() {
        let names = MissionNames {
            points: vec!["stay-warm.TP_A".into(), "stay-warm.heater1.TP_H".into()],
            goals: vec!["stay-warm.heater1".into()],
        };
        assert!(names.has_point("stay-warm#2.TP_A"));
        assert!(names.has_point("stay-warm#3.heater1#2.TP_H"));
        assert!(names.has_point("stay-warm.TP_A′"));
        assert!(names.has_goal("stay-warm#12.heater1"));
        assert!(!names.has_goal("stay-warm#x.heater1"));
        assert!(!names.has_point("stay-warm#2.TP_B"));
    }
}
