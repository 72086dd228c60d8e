//! `kairos schedule MISSION [--at T] [--dot]`: loads a mission, schedules its goal network
//! (DESIGN.md §15.4; mds-goal-networks.md §2.2) from the plant's most likely initial modes, and
//! prints every time point's window and each state variable's XGoals — or why the network cannot
//! be scheduled (exit 1). `--at T` projects the schedule to `T` (`goalnet::project`); `--dot`
//! draws it for Graphviz: time points as ellipses (fired ones with a double border), written
//! temporal constraints as labelled edges, the scheduler's ordering constraints dashed, and each
//! state variable's XGoals as boxes in its own cluster between their start and end points (the
//! XGoal active at `T` highlighted). For a mission with goal types, `--dot` draws the network
//! as the goal controller elaborates it at time 0 from the initial modes, with the elaboration
//! tree beside it: each goal with its type and the tactic in use, an edge from parent to child.

use std::path::Path;

use kairos::dot::{Cluster, Edge, Graph, Node, Shape};
use kairos::goalnet::mission::seconds;
use kairos::goalnet::{
    EstimateView, ExecutableNetwork, GoalController, GoalId, GroundError, Projection, Provenance,
    ScheduleError, TimePointId, XGoal, display, mission, project, schedule,
};
use kairos::logic::ValueId;
use kairos::plant::Plant;
use kairos::reconfiguration::Reconfiguration;

use super::Failure;
use super::output::emit;

/// Loads, schedules, optionally projects to `at`, and prints as text or DOT.
pub fn run(path: &Path, at: Option<f64>, dot: bool) -> Result<(), Failure> {
    if let Some(at) = at.filter(|t| !(t.is_finite() && *t >= 0.0)) {
        return Err(Failure::bad_input(format!(
            "error: --at {at}: expected a finite time in seconds, at or after the mission's \
             start (0)"
        )));
    }
    let mission = mission::load(path).map_err(Failure::bad_input)?;
    let reconfiguration = Reconfiguration::compile(&mission.plant)
        .map_err(|e| Failure::bad_input(format!("error: {}: {e}", mission.plant_path)))?;
    let current = mission.plant.most_likely_initial();
    let executable = schedule(&mission.network, &reconfiguration, &current).map_err(|error| {
        Failure::failed(format!(
            "mission: {} (plant {})\n{}{}",
            mission.name,
            mission.plant_path,
            display::explain(&error, &mission.network, &mission.plant),
            located(&error, &mission)
        ))
    })?;
    let controller = (dot && !mission.elaborators.types.is_empty())
        .then(|| elaborated(&mission, &reconfiguration, &current))
        .transpose()?;
    let executable = controller
        .as_ref()
        .map_or(executable, |c| c.execution().executable().clone());
    let projection = at
        .map(|at| project(&executable, at))
        .transpose()
        .map_err(|error| {
            Failure::failed(match error {
                GroundError::Refused(refused) => {
                    format!("error: projecting the schedule: {refused}")
                }
                GroundError::Inconsistent(cycle) => display::explain(
                    &ScheduleError::Inconsistent(cycle),
                    &executable.network,
                    &mission.plant,
                ),
            })
        })?;
    let plant = &mission.plant;
    let text = match (&projection, dot) {
        (_, true) => {
            let mut graph = drawing(&mission.name, &executable, projection.as_ref(), plant);
            if let Some(controller) = &controller {
                graph.clusters.push(tree(&mission, controller));
                graph.edges.extend(tree_edges(controller));
            }
            graph.render()
        }
        (Some(projection), false) => {
            header(&mission) + &display::render_projection(projection, plant)
        }
        (None, false) => header(&mission) + &display::render(&executable, plant),
    };
    emit(&text).map(|_| ())
}

/// Where a goal the scheduler refuses, and the written constraints that force it, are in the
/// mission file (`file:line:column`), one line each.
fn located(error: &ScheduleError, mission: &mission::Mission) -> String {
    let (goal, cycle): (_, &[kairos::goalnet::ConstraintId]) = match error {
        ScheduleError::Reversed { goal, cycle } => (*goal, cycle),
        ScheduleError::EmptyInterval { goal } => (*goal, &[]),
        _ => return String::new(),
    };
    let at = |span: &kairos::diagnostic::Span| {
        let (line, column) = mission.source.line_col(span.start);
        format!("{}:{line}:{column}", mission.source.name)
    };
    let network = &mission.network;
    let goal = network.goal(goal);
    let mut text = format!("\n  --> {}: goal `{}`", at(&goal.span), goal.name);
    for id in cycle {
        let constraint = network.stn().constraint(*id);
        if let Provenance::Written(span) = &constraint.provenance {
            text += &format!(
                "\n  --> {}: {} → {}",
                at(span),
                network.point(constraint.from).name,
                network.point(constraint.to).name
            );
        }
    }
    text
}

/// The goal controller made at time 0 from the initial modes (and the initial distribution as
/// the belief): the mission elaborated and scheduled as a run starts it; an error if no
/// elaboration fits (the controller would start safed).
fn elaborated(
    mission: &mission::Mission,
    reconfiguration: &Reconfiguration,
    current: &[ValueId],
) -> Result<GoalController, Failure> {
    let beliefs: Vec<Vec<f64>> = mission
        .plant
        .components()
        .iter()
        .map(|c| c.initial().to_vec())
        .collect();
    let view = EstimateView {
        modes: current,
        beliefs: &beliefs,
    };
    let controller = GoalController::new(mission, reconfiguration, 0.0, view);
    if controller.is_safed() {
        return Err(Failure::failed(format!(
            "mission: {} (plant {})\nno elaboration of the network fits: the goal controller \
             starts safed",
            mission.name, mission.plant_path
        )));
    }
    Ok(controller)
}

fn goal_id(goal: GoalId) -> String {
    format!("goal/{}", goal.0)
}

/// The elaboration tree as a cluster: one node per goal of the running network (retired ones
/// left out), with its type and the tactic its elaboration uses.
fn tree(mission: &mission::Mission, controller: &GoalController) -> Cluster {
    let state = controller.elaboration();
    let mut cluster = Cluster {
        id: "elaboration".to_string(),
        label: "elaboration".to_string(),
        ..Cluster::default()
    };
    for (i, goal) in controller.network().goals().iter().enumerate() {
        let id = GoalId(i as u32);
        if state.retired.get(i).copied().unwrap_or(false) {
            continue;
        }
        let mut label = goal.name.clone();
        if let Some(t) = state.types.get(i).copied().flatten() {
            let goal_type = mission.elaborators.get(t);
            label += &format!("\ntype {}", goal_type.name);
            if let Some(e) = state.elaborations.get(&id) {
                let tactic = &goal_type.tactics[e.tactic];
                label += &format!("\ntactic {}: {}", e.tactic + 1, tactic.name);
            }
        }
        cluster.nodes.push(Node::new(goal_id(id), label));
    }
    cluster
}

/// Parent → child, for every goal of the running network that has a parent.
fn tree_edges(controller: &GoalController) -> Vec<Edge> {
    let state = controller.elaboration();
    let live = |g: GoalId| !state.retired.get(g.index()).copied().unwrap_or(false);
    controller
        .network()
        .goals()
        .iter()
        .enumerate()
        .filter_map(|(i, goal)| Some((GoalId(i as u32), goal.parent?)))
        .filter(|&(child, parent)| live(child) && live(parent))
        .map(|(child, parent)| Edge {
            from: goal_id(parent),
            to: goal_id(child),
            label: String::new(),
            dashed: false,
        })
        .collect()
}

fn header(mission: &mission::Mission) -> String {
    format!("mission: {} (plant {})\n", mission.name, mission.plant_path)
}

fn point_id(point: TimePointId) -> String {
    format!("point/{}", point.0)
}

/// The Graphviz drawing of a scheduled (and possibly projected) network.
fn drawing(
    name: &str,
    executable: &ExecutableNetwork,
    projection: Option<&Projection>,
    plant: &Plant,
) -> Graph {
    // A projection's network has its fired points grounded; draw its windows.
    let network = projection.map_or(&executable.network, |p| &p.executable.network);
    let mut graph = Graph::new(name);
    graph.left_to_right = true;
    for (i, point) in network.points().iter().enumerate() {
        let id = TimePointId(i as u32);
        let fired = projection.and_then(|p| p.fired[i]);
        let when = match (fired, network.stn().window(id)) {
            (Some(time), _) => format!("fired at {} s", seconds(time)),
            (None, Some(w)) => format!("[{}, {}] s", seconds(w.lb), seconds(w.ub)),
            (None, None) => "(not propagated)".to_string(),
        };
        graph.nodes.push(Node {
            shape: Shape::Ellipse,
            peripheral: fired.is_some(),
            ..Node::new(point_id(id), format!("{}\n{when}", point.name))
        });
    }
    for c in network.stn().constraints() {
        let (label, dashed) = match &c.provenance {
            Provenance::Written(_) | Provenance::Submitted => {
                (format!("[{}, {}] s", seconds(c.min), seconds(c.max)), false)
            }
            // An ordering the XGoal boxes already show is not drawn twice.
            Provenance::Scheduled { .. } if joined_by_xgoal(executable, c.from, c.to) => continue,
            Provenance::Scheduled { reason } => (reason.clone(), true),
            Provenance::AfterOrigin | Provenance::Fired | Provenance::GoalInterval => continue,
        };
        graph.edges.push(Edge {
            from: point_id(c.from),
            to: point_id(c.to),
            label,
            dashed,
        });
    }
    for timeline in &executable.timelines {
        let sv = plant.component(timeline.sv).name();
        let active = projection.and_then(|p| p.active(timeline.sv));
        let mut cluster = Cluster {
            id: format!("sv/{sv}"),
            label: sv.to_string(),
            ..Cluster::default()
        };
        for (index, xgoal) in timeline.xgoals.iter().enumerate() {
            let id = format!("xgoal/{sv}/{index}");
            cluster.nodes.push(Node {
                highlight: active == Some(xgoal),
                ..Node::new(&id, xgoal_label(executable, plant, xgoal))
            });
            for (from, to) in [
                (point_id(xgoal.start), id.clone()),
                (id, point_id(xgoal.end)),
            ] {
                graph.edges.push(Edge {
                    from,
                    to,
                    label: String::new(),
                    dashed: false,
                });
            }
        }
        graph.clusters.push(cluster);
    }
    graph
}

fn joined_by_xgoal(executable: &ExecutableNetwork, from: TimePointId, to: TimePointId) -> bool {
    let xgoals = executable.timelines.iter().flat_map(|t| &t.xgoals);
    xgoals.clone().any(|x| x.start == from && x.end == to)
}

fn xgoal_label(executable: &ExecutableNetwork, plant: &Plant, xgoal: &XGoal) -> String {
    let goals: Vec<&str> = xgoal
        .constituents
        .iter()
        .map(|g| executable.network.goal(*g).name.as_str())
        .collect();
    format!(
        "{}\n{}\ngoals: {}",
        xgoal.kind.name(),
        display::constraint_text(plant, xgoal.sv, &xgoal.constraint),
        if goals.is_empty() {
            "none".to_string()
        } else {
            goals.join(", ")
        }
    )
}
