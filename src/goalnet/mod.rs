//! Goal networks: the Mission Data System's goal-based control on kairos's deductive controller
//! (DESIGN.md §15; seeds 000, 003; `mds-goal-networks.md` is the reading of the seeds).
//!
//! A goal network constrains **state variables** (a component's mode variable) over intervals
//! between **time points**, related by **temporal constraints**. The concepts have their MDS
//! names, one file each:
//! - [`TimePoint`] and [`TemporalConstraint`] (with its [`Provenance`]);
//! - [`Stn`]: the simple temporal network — distance graph, propagation (petgraph's
//!   Bellman–Ford), windows, grounding a fired point, incremental re-propagation, and the
//!   negative cycle named by its constraints;
//! - [`ConstraintSet`]: a constraint on one SV's values and its algebra (merge, subset);
//! - [`Goal`] (kind [`GoalKind`]), [`XGoal`] (the merge of goals on one SV over an interval);
//! - [`GoalNetwork`] (unscheduled) and [`ExecutableNetwork`] (scheduled, per-SV timelines);
//! - [`schedule()`]: merging and scheduling into an [`ExecutableNetwork`] or a [`ScheduleError`];
//!   [`display`] renders both for people;
//! - [`judge_delegated`]: whether the controllers of state variables that are not components
//!   can achieve the goals delegated to them (the scheduler's achievability, asked of them);
//! - [`project()`]: the nominal [`Projection`] of a scheduled network to a time (every point
//!   fired as early as it may), for `kairos schedule --at`;
//! - [`Execution`]: firing, grounding, dispatch and monitoring, one cycle at a time, and the
//!   configuration goal the active XGoals give mode reconfiguration;
//! - [`mission`]: the mission file (RON, `missions/`) and its loader, [`Mission`];
//! - [`GoalType`] ([`tactic`]): a named goal type's failure [`Response`] and its elaborator's
//!   [`Tactic`]s; [`elaborate`]: elaboration with chronological tactic backtracking;
//! - [`Proposal`]: a copy of the running network to edit and promote;
//! - [`Submission`]: goals, points and constraints submitted to a running mission;
//! - [`GoalController`]: the per-cycle mission executive — monitoring, failure responses
//!   (re-elaboration, fail up, safing), promotion, firing — reporting [`MissionEvent`]s, each
//!   failure with its [`Explanation`] chain.

mod achievable;
mod constraint_set;
mod controller;
pub mod display;
pub mod elaborate;
mod events;
mod execution;
mod goal;
pub mod mission;
mod network;
mod projection;
mod proposal;
mod schedule;
mod stn;
mod submission;
pub mod tactic;
mod temporal_constraint;
mod time_point;
mod xgoal;

pub use achievable::judge_delegated;
pub use constraint_set::ConstraintSet;
pub use controller::GoalController;
pub use elaborate::{Elaboration, ElaborationState, Rejection};
pub use events::{Explanation, MissionEvent, ResponseStep};
pub use execution::{EstimateView, Execution, FailureReason, GoalEvent, Waiting};
pub use goal::{Delegate, Goal, GoalId, GoalKind};
pub use mission::{Mission, MissionErrors};
pub use network::{ExecutableNetwork, GoalNetwork, ORIGIN_NAME, Timeline};
pub use projection::{Projection, project};
pub use proposal::Proposal;
pub use schedule::{ScheduleError, schedule};
pub use stn::{GroundError, Inconsistency, Stn, StnError, Window};
pub use submission::{Submission, SubmitError, SubmittedConstraint, SubmittedGoal};
pub use tactic::{Elaborators, GoalType, MissionNames, Response, Tactic, TypeId};
pub use temporal_constraint::{ConstraintId, Provenance, TemporalConstraint};
pub use time_point::{TimePoint, TimePointId};
pub use xgoal::XGoal;
