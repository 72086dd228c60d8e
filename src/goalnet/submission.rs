//! Goals submitted to a running mission (DESIGN.md §15.4; mds-goal-networks.md §2.1–2.2): what
//! a submission adds — new time points, the temporal constraints that place them, goals over
//! them, each of which may have one of the mission's goal types (elaborated at promotion: the
//! seeds' "submit StayWarm at 10 s") — and how it is added to a [`Proposal`] of the running
//! network. Scheduling the proposal,
//! and refusing it with the running network left as it was, is the executive's
//! (`Executive::submit`).

use super::{
    ConstraintSet, Goal, GoalKind, GoalNetwork, Proposal, Provenance, ScheduleError,
    TemporalConstraint, TimePointId, TypeId,
};
use crate::logic;
use crate::plant::ComponentId;

/// What a submission adds to the running network; points are named, and a name may be one the
/// network already has.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Submission {
    /// New time points (names not in the network yet).
    pub points: Vec<String>,
    /// Temporal constraints over new and existing points.
    pub constraints: Vec<SubmittedConstraint>,
    /// Goals over new and existing points.
    pub goals: Vec<SubmittedGoal>,
}

/// `min ≤ t(to) − t(from) ≤ max`, seconds (as a mission file's `Constraint`).
#[derive(Debug, Clone, PartialEq)]
pub struct SubmittedConstraint {
    /// The earlier point's name.
    pub from: String,
    /// The later point's name.
    pub to: String,
    /// The least distance.
    pub min: f64,
    /// The greatest distance (`f64::INFINITY` for none).
    pub max: f64,
}

/// A goal to add (as a mission file's `Goal` or `Macro`, its constraint already a
/// [`ConstraintSet`] over the state variable's modes).
#[derive(Debug, Clone, PartialEq)]
pub struct SubmittedGoal {
    /// Its name, unique in the network.
    pub name: String,
    /// The state variable; `None` for a macro goal.
    pub sv: Option<ComponentId>,
    /// How the constraint is judged.
    pub kind: GoalKind,
    /// The constraint on the SV's modes.
    pub constraint: ConstraintSet,
    /// The constraint as written, for messages.
    pub text: String,
    /// The start point's name.
    pub start: String,
    /// The end point's name.
    pub end: String,
    /// The parent goal's name, if any.
    pub parent: Option<String>,
    /// Its priority.
    pub priority: i32,
    /// Its goal type (one of the mission's): the goal is elaborated by the type's tactics when
    /// the submission is promoted, and fails with the type's response.
    pub goal_type: Option<TypeId>,
}

/// Why a submission was refused (the running network is unchanged).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SubmitError {
    /// The executive runs an RMPL program, which has no goal network.
    #[error("the executive runs an RMPL program: goals are submitted to a mission")]
    NotAMission,
    /// A point or goal name is not an identifier, or is taken.
    #[error("`{0}` is not a new name (an identifier not used in the network)")]
    Name(String),
    /// A goal's constraint set is not over its state variable's modes.
    #[error("goal `{0}`'s constraint is not over the modes of its state variable")]
    Domain(String),
    /// A name that should be in the network is not.
    #[error("the network has no {what} `{name}`")]
    Unknown {
        /// `time point` or `goal`.
        what: &'static str,
        /// The name.
        name: String,
    },
    /// Bounds that describe no interval.
    #[error("bounds [{min}, {max}] between `{from}` and `{to}` describe no interval of time")]
    Bounds {
        /// The earlier point.
        from: String,
        /// The later point.
        to: String,
        /// The least distance.
        min: f64,
        /// The greatest distance.
        max: f64,
    },
    /// The proposal could not be elaborated (the controller's reason).
    #[error("the submission cannot be elaborated: {0}")]
    NotElaborated(String),
    /// The network with the submission cannot be scheduled (inconsistent, unmergeable,
    /// unachievable, or a point it would have fire in the past).
    #[error("the submission cannot be scheduled: {explanation}")]
    Refused {
        /// The scheduler's error.
        error: ScheduleError,
        /// It in words, with the evidence (`goalnet::display::explain`).
        explanation: String,
        /// Every goal a submitted goal conflicts with, by name (empty unless unmergeable).
        conflicts: Vec<String>,
    },
    /// A submission at a time before the last cycle's.
    #[error("submitted at {now} s, before the last cycle ({last} s)")]
    Late {
        /// The time given.
        now: f64,
        /// The last cycle's time.
        last: f64,
    },
}

impl SubmitError {
    /// The goals of the running network a refused submission conflicts with, by name.
    pub fn conflicts(&self) -> &[String] {
        match self {
            SubmitError::Refused { conflicts, .. } => conflicts,
            _ => &[],
        }
    }
}

impl Submission {
    /// Adds the submission to `proposal`, resolving names; the first problem refuses it.
    pub(crate) fn add_to(&self, proposal: &mut Proposal) -> Result<(), SubmitError> {
        for name in &self.points {
            if !logic::is_value_name(name) || proposal.network().point_named(name).is_some() {
                return Err(SubmitError::Name(name.clone()));
            }
            proposal.add_point(name, 0..0);
        }
        for c in &self.constraints {
            let network = proposal.network();
            let (from, to) = (point(network, &c.from)?, point(network, &c.to)?);
            let constraint = TemporalConstraint::new(from, to, c.min, c.max, Provenance::Submitted);
            let bounds = || SubmitError::Bounds {
                from: c.from.clone(),
                to: c.to.clone(),
                min: c.min,
                max: c.max,
            };
            if !constraint.bounds_are_valid() {
                return Err(bounds());
            }
            proposal.add_constraint(constraint).map_err(|_| bounds())?;
        }
        for g in &self.goals {
            let network = proposal.network();
            if !logic::is_value_name(&g.name) || network.goal_named(&g.name).is_some() {
                return Err(SubmitError::Name(g.name.clone()));
            }
            let parent = match &g.parent {
                None => None,
                Some(name) => {
                    Some(
                        network
                            .goal_named(name)
                            .ok_or_else(|| SubmitError::Unknown {
                                what: "goal",
                                name: name.clone(),
                            })?,
                    )
                }
            };
            let goal = Goal {
                name: g.name.clone(),
                sv: g.sv,
                kind: g.kind,
                constraint: g.constraint.clone(),
                delegate: None,
                text: g.text.clone(),
                start: point(network, &g.start)?,
                end: point(network, &g.end)?,
                parent,
                priority: g.priority,
                span: 0..0,
            };
            proposal.add_goal(goal, g.goal_type);
        }
        Ok(())
    }
}

fn point(network: &GoalNetwork, name: &str) -> Result<TimePointId, SubmitError> {
    network
        .point_named(name)
        .ok_or_else(|| SubmitError::Unknown {
            what: "time point",
            name: name.to_string(),
        })
}
