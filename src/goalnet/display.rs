//! Text for people: a scheduled network (`kairos schedule`) and why scheduling failed.

use std::fmt::Write;

use super::constraint_set::ConstraintSet;
use super::mission::seconds;
use super::network::{ExecutableNetwork, GoalNetwork};
use super::projection::Projection;
use super::schedule::ScheduleError;
use super::stn::Inconsistency;
use super::temporal_constraint::{ConstraintId, Provenance};
use super::xgoal::XGoal;
use crate::logic::ValueId;
use crate::plant::{ComponentId, Plant};

/// Every point's window, then per state variable its XGoals with their merged constraint and
/// constituent goals.
pub fn render(executable: &ExecutableNetwork, plant: &Plant) -> String {
    write_network(executable, plant, None)
}

/// A projection (`kairos schedule --at T`): as [`render`], with the points fired by `T` and
/// the XGoal each state variable is under at `T` marked.
pub fn render_projection(projection: &Projection, plant: &Plant) -> String {
    let header = format!(
        "projected to {} s (every point fired as early as the network lets it):\n",
        seconds(projection.at)
    );
    header + &write_network(&projection.executable, plant, Some(projection))
}

fn write_network(
    executable: &ExecutableNetwork,
    plant: &Plant,
    projection: Option<&Projection>,
) -> String {
    let network = &executable.network;
    let mut out = String::from("time points (windows, s):\n");
    let width = network
        .points()
        .iter()
        .map(|p| p.name.len())
        .max()
        .unwrap_or(0);
    for (i, point) in network.points().iter().enumerate() {
        let id = super::TimePointId(i as u32);
        let window = network.stn().window(id);
        let fired = projection.and_then(|p| p.fired[i]);
        let shown = match (fired, window) {
            (Some(time), _) => format!("fired at {}", seconds(time)),
            (None, Some(w)) => format!("[{}, {}]", seconds(w.lb), seconds(w.ub)),
            (None, None) => "(not propagated)".to_string(),
        };
        let _ = writeln!(out, "  {:width$}  {shown}", point.name);
    }
    for timeline in &executable.timelines {
        let _ = writeln!(out, "{}:", plant.component(timeline.sv).name());
        let active = projection.and_then(|p| p.active(timeline.sv));
        for xgoal in &timeline.xgoals {
            let marker = if active == Some(xgoal) {
                "  ← active"
            } else {
                ""
            };
            let _ = writeln!(out, "  {}{marker}", xgoal_line(network, plant, xgoal));
        }
    }
    // Goals on state variables that are not components: on no timeline, their controllers'.
    let delegated = network.goals().iter().filter(|g| g.delegate.is_some());
    for (i, goal) in delegated.enumerate() {
        if i == 0 {
            out.push_str("delegated to the controllers of their state variables:\n");
        }
        let (start, end) = (
            &network.point(goal.start).name,
            &network.point(goal.end).name,
        );
        let (kind, text) = (goal.kind.name(), &goal.text);
        let _ = writeln!(out, "  [{start}, {end}] {kind} {text}: {}", goal.name);
    }
    out
}

fn xgoal_line(network: &GoalNetwork, plant: &Plant, xgoal: &XGoal) -> String {
    let names: Vec<&str> = xgoal
        .constituents
        .iter()
        .map(|g| network.goal(*g).name.as_str())
        .collect();
    let goals = if names.is_empty() {
        "(no goal)".to_string()
    } else {
        names.join(", ")
    };
    format!(
        "[{}, {}] {} {}: {goals}",
        network.point(xgoal.start).name,
        network.point(xgoal.end).name,
        xgoal.kind.name(),
        constraint_text(plant, xgoal.sv, &xgoal.constraint),
    )
}

/// `switch1 ∈ {closed, stuck-closed}, known, P(switch1 = closed) ≥ 0.9`, or `anything`.
pub fn constraint_text(plant: &Plant, sv: ComponentId, set: &ConstraintSet) -> String {
    let component = plant.component(sv);
    let mut parts = Vec::new();
    if !set.is_control_free() {
        let values: Vec<&str> = set.admitted().map(|v| mode_name(plant, sv, v)).collect();
        parts.push(format!("{} ∈ {{{}}}", component.name(), values.join(", ")));
    }
    if set.requires_known() {
        parts.push("known".to_string());
    }
    for (value, p) in set.least_beliefs() {
        let name = mode_name(plant, sv, value);
        parts.push(format!("P({} = {name}) ≥ {p}", component.name()));
    }
    if parts.is_empty() {
        "anything".to_string()
    } else {
        parts.join(", ")
    }
}

fn mode_name(plant: &Plant, sv: ComponentId, value: ValueId) -> &str {
    let var = plant.component(sv).mode_var();
    plant.table().variable(var).value_name(value)
}

fn modes(plant: &Plant, sv: ComponentId, values: &[ValueId]) -> String {
    let names: Vec<&str> = values.iter().map(|v| mode_name(plant, sv, *v)).collect();
    format!("{{{}}}", names.join(", "))
}

/// Why scheduling failed, in words, with the evidence.
pub fn explain(error: &ScheduleError, network: &GoalNetwork, plant: &Plant) -> String {
    match error {
        ScheduleError::Inconsistent(inconsistency) => inconsistent(inconsistency, network),
        ScheduleError::Unmergeable { sv, goals } => {
            let [a, b] = goals.map(|g| network.goal(g));
            format!(
                "unmergeable: on {}, goals `{}` ({}) and `{}` ({}) cannot hold together and \
                 cannot be serialised either way",
                plant.component(*sv).name(),
                a.name,
                a.text,
                b.name,
                b.text
            )
        }
        ScheduleError::Unachievable { xgoal, from } => format!(
            "unachievable: {} — from {} {} cannot be reached by mode reconfiguration",
            xgoal_line(network, plant, xgoal),
            plant.component(xgoal.sv).name(),
            modes(plant, xgoal.sv, from),
        ),
        ScheduleError::TransitionUnachievable {
            previous,
            from,
            next,
        } => format!(
            "transition unachievable: on {}, from {} (projected by {}) into {}",
            plant.component(next.sv).name(),
            modes(plant, next.sv, from),
            xgoal_line(network, plant, previous),
            xgoal_line(network, plant, next),
        ),
        ScheduleError::Reversed { goal, cycle } => {
            let g = network.goal(*goal);
            let mut out = format!(
                "reversed goal: `{}` ({}) — the constraints force its end `{}` before its start \
                 `{}`; a goal holds from its start to its end:",
                g.name,
                g.text,
                network.point(g.end).name,
                network.point(g.start).name
            );
            for id in cycle {
                if let Some(line) = constraint_line(network, *id) {
                    out.push_str(&line);
                }
            }
            out
        }
        ScheduleError::EmptyInterval { goal } => {
            let goal = network.goal(*goal);
            format!(
                "empty goal: `{}` ({}) holds over no time — the constraints force its start `{}` \
                 and its end `{}` to the same instant",
                goal.name,
                goal.text,
                network.point(goal.start).name,
                network.point(goal.end).name
            )
        }
        ScheduleError::DelegatedUnachievable { goal, sv, value } => {
            let goal = network.goal(*goal);
            format!(
                "unachievable: goal `{}` ({}) on {sv} — from {sv} = {value} its controller has \
                 no course of action that reaches it",
                goal.name, goal.text
            )
        }
    }
}

fn inconsistent(inconsistency: &Inconsistency, network: &GoalNetwork) -> String {
    let mut out =
        String::from("inconsistent: the temporal constraints of this cycle cannot all hold");
    for id in &inconsistency.cycle {
        match constraint_line(network, *id) {
            Some(line) => out.push_str(&line),
            None => out.push_str("\n  (an order the scheduler added)"),
        }
    }
    out
}

/// `\n  from → to ∈ [min, max] (why)` for a constraint of `network`; `None` for one it does
/// not hold (the scheduler's, added to a copy).
fn constraint_line(network: &GoalNetwork, id: ConstraintId) -> Option<String> {
    let c = network.stn().constraints().get(id.index())?;
    {
        let why = match &c.provenance {
            Provenance::Written(_) => "written".to_string(),
            Provenance::AfterOrigin => "every point is at or after the origin".to_string(),
            Provenance::Fired => "the point fired".to_string(),
            Provenance::Scheduled { reason } => format!("scheduler: {reason}"),
            Provenance::Submitted => "submitted".to_string(),
            Provenance::GoalInterval => "a goal starts no later than it ends".to_string(),
        };
        Some(format!(
            "\n  {} → {} ∈ [{}, {}] ({why})",
            network.point(c.from).name,
            network.point(c.to).name,
            seconds(c.min),
            seconds(c.max)
        ))
    }
}
