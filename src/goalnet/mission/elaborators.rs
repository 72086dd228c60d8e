//! The mission file's goal types (mds-goal-networks.md §2.1, §2.6): each with
//! its failure response and its elaborator's tactics. Reference for users:
//! `docs/reference/mission.md`.
//!
//! ```ron
//! types: [
//!     // response: Safing, ReElaborate (the next tactic, cyclically; `budget` times per goal,
//!     // default 3), FailUp (the default: to the parent; a root goes to safing) or Ignore.
//!     GoalType(name: "StayWarm", response: ReElaborate, budget: 3, tactics: [
//!         Tactic(
//!             name: "heater 1",                 // optional; default "tactic N"
//!             // New points, fresh at every elaboration (`TP_A`, then `TP_A′`).
//!             points: ["TP_A"],
//!             // Between `start`/`end` (the parent's points) and the tactic's own points.
//!             constraints: [Constraint(from: "TP_A", to: "start", min: 60.0, max: 150.0)],
//!             goals: [
//!                 // Without `sv`: on the parent's state variable, with its constraint
//!                 // (a Knowledge child: known).
//!                 Child(name: "get-warm", type: "GetWarm", kind: Transition,
//!                       start: "TP_A", end: "start"),
//!                 Child(name: "heater1", type: "Heater", sv: "switch1", kind: Maintain,
//!                       constraint: "switch1 = closed", start: "TP_A", end: "end"),
//!             ],
//!         ),
//!     ]),
//!     GoalType(name: "Heater", tactics: [...]),   // response FailUp
//! ],
//! ```
//! A goal or macro of the initial network takes a type with `type: "StayWarm"`; the safe
//! network is not elaborated and its goals take none.
//!
//! A type may not elaborate into itself, directly or through other types (elaboration would
//! never end), and one goal's elaboration may create at most [`MAX_ELABORATED_GOALS`] goals
//! (types whose tactics each create several typed children multiply: ten levels of two make a
//! thousand); both are load errors, so `kairos check` reports them too.

use serde::Deserialize;

use super::{ConstraintFile, GoalNetwork, Item, KindFile, Loader, MissionFile};
use crate::diagnostic::locate::Step;
use crate::diagnostic::{Diagnostic, did_you_mean};
use crate::goalnet::tactic::{
    ChildConstraint, ChildGoal, DEFAULT_REELABORATION_BUDGET, Elaborators, GoalType, PointRef,
    Response, Tactic, TacticConstraint, TypeId,
};
use crate::logic;
use crate::plant::Plant;

#[derive(Deserialize)]
#[serde(rename = "GoalType", deny_unknown_fields)]
pub(super) struct TypeFile {
    name: String,
    #[serde(default)]
    response: ResponseFile,
    budget: Option<u32>,
    #[serde(default)]
    tactics: Vec<TacticFile>,
}

#[derive(Deserialize, Default, Clone, Copy)]
#[serde(rename = "Response")]
pub(super) enum ResponseFile {
    Safing,
    ReElaborate,
    #[default]
    FailUp,
    Ignore,
}

#[derive(Deserialize)]
#[serde(rename = "Tactic", deny_unknown_fields)]
struct TacticFile {
    name: Option<String>,
    #[serde(default)]
    points: Vec<String>,
    #[serde(default)]
    constraints: Vec<ConstraintFile>,
    #[serde(default)]
    goals: Vec<ChildFile>,
}

#[derive(Deserialize)]
#[serde(rename = "Child", deny_unknown_fields)]
struct ChildFile {
    name: String,
    #[serde(rename = "type")]
    goal_type: Option<String>,
    sv: Option<String>,
    kind: KindFile,
    constraint: Option<String>,
    start: String,
    end: String,
    #[serde(default)]
    priority: i32,
}

/// A macro or goal of a network file, with where it is and the type it names.
struct Listed<'a> {
    list: &'static str,
    index: usize,
    name: &'a str,
    goal_type: Option<&'a str>,
}

/// A network's macros, then its goals.
fn listed(net: &super::NetworkFile) -> Vec<Listed<'_>> {
    let macros = net.macros.iter().enumerate().map(|(index, m)| Listed {
        list: "macros",
        index,
        name: &m.name,
        goal_type: m.goal_type.as_deref(),
    });
    let goals = net.goals.iter().enumerate().map(|(index, g)| Listed {
        list: "goals",
        index,
        name: &g.name,
        goal_type: g.goal_type.as_deref(),
    });
    macros.chain(goals).collect()
}

/// The most goals one goal's elaboration may create, counted down every level of typed
/// children with the tactic that creates the most at each: beyond this a mission is refused at
/// load rather than left to exhaust memory at its first cycle.
pub const MAX_ELABORATED_GOALS: u64 = 10_000;

/// Names a tactic's points may not take: the parent's points and the origin.
const RESERVED_POINTS: [&str; 3] = ["start", "end", "origin"];

impl Loader<'_> {
    /// The goal types, and the types of the initial network's goals (`network` as loaded).
    pub(super) fn elaborators(
        &mut self,
        plant: &Plant,
        file: &MissionFile,
        network: &GoalNetwork,
    ) -> Elaborators {
        let mut types = Vec::new();
        for (i, spec) in file.types.iter().enumerate() {
            let path = [Step::Field("types"), Step::Index(i), Step::Field("name")];
            if !logic::is_value_name(&spec.name) {
                self.error(
                    &path,
                    format!("`{}` is not a valid goal type name", spec.name),
                    "an identifier (letters, digits, `_`, `-`)",
                );
            } else if types.iter().any(|t: &GoalType| t.name == spec.name) {
                self.error(
                    &path,
                    format!("goal type `{}` is declared twice", spec.name),
                    "a type name not used before",
                );
            }
            types.push(GoalType {
                name: spec.name.clone(),
                response: match spec.response {
                    ResponseFile::Safing => Response::Safing,
                    ResponseFile::ReElaborate => Response::ReElaborate,
                    ResponseFile::FailUp => Response::FailUp,
                    ResponseFile::Ignore => Response::Ignore,
                },
                budget: spec.budget.unwrap_or(DEFAULT_REELABORATION_BUDGET),
                tactics: Vec::new(),
                span: self.locate.at(&path),
            });
        }
        let mut elaborators = Elaborators {
            types,
            of_goal: vec![None; network.goals().len()],
        };
        for (i, spec) in file.types.iter().enumerate() {
            for (j, tactic) in spec.tactics.iter().enumerate() {
                let tactic = self.tactic(plant, &elaborators, i, j, tactic);
                elaborators.types[i].tactics.push(tactic);
            }
        }
        self.recursive_types(file, &elaborators);
        self.typed_goals(file, network, &mut elaborators);
        elaborators
    }

    /// Refuses goal types that elaborate into themselves: a tactic's child whose type is the
    /// tactic's own type, or leads back to it through other types. Elaboration expands every
    /// typed child at once (elaborate.rs), so such a type would expand without end — memory
    /// exhausted within seconds. Each cycle is reported once, at the child's `type` that
    /// closes it (the back edge of a depth-first walk over "type → child's type"), naming the
    /// types around it.
    fn recursive_types(&mut self, file: &MissionFile, elaborators: &Elaborators) {
        // edges[t]: (child's type, tactic index, child index) for every typed child of t.
        let edges: Vec<Vec<(usize, usize, usize)>> = (file.types.iter())
            .map(|spec| {
                let children = spec.tactics.iter().enumerate().flat_map(|(j, tactic)| {
                    tactic.goals.iter().enumerate().map(move |(k, c)| (j, k, c))
                });
                children
                    .filter_map(|(j, k, child)| {
                        let to = elaborators.named(child.goal_type.as_deref()?)?;
                        Some((to.index(), j, k))
                    })
                    .collect()
            })
            .collect();
        // 0: not visited, 1: on the walk's stack, 2: done.
        let mut state = vec![0u8; edges.len()];
        // Finished types in the order the walk finished them: children first.
        let mut finished: Vec<usize> = Vec::new();
        let mut recursive = false;
        for root in 0..edges.len() {
            if state[root] != 0 {
                continue;
            }
            // An explicit stack (type, next edge): a long chain of types cannot overflow it.
            let mut stack: Vec<(usize, usize)> = vec![(root, 0)];
            state[root] = 1;
            while let Some(&mut (t, ref mut next)) = stack.last_mut() {
                let Some(&(to, j, k)) = edges[t].get(*next) else {
                    state[t] = 2;
                    finished.push(t);
                    stack.pop();
                    continue;
                };
                *next += 1;
                match state[to] {
                    0 => {
                        state[to] = 1;
                        stack.push((to, 0));
                    }
                    1 => {
                        recursive = true;
                        let from = stack.iter().position(|&(s, _)| s == to).unwrap_or(0);
                        let mut cycle: Vec<&str> = (stack[from..].iter())
                            .map(|&(s, _)| file.types[s].name.as_str())
                            .collect();
                        cycle.push(file.types[to].name.as_str());
                        let path = [
                            Step::Field("types"),
                            Step::Index(t),
                            Step::Field("tactics"),
                            Step::Index(j),
                            Step::Field("goals"),
                            Step::Index(k),
                            Step::Field("type"),
                        ];
                        self.error(
                            &path,
                            format!(
                                "goal type `{}` elaborates into itself: {}",
                                file.types[to].name,
                                cycle.join(" → ")
                            ),
                            "child goals whose types do not lead back to their parent's type \
                             (elaboration would never end)",
                        );
                    }
                    _ => {}
                }
            }
        }
        if !recursive {
            self.expansion_sizes(file, &finished);
        }
    }

    /// Refuses a type one goal of which elaborates into more than [`MAX_ELABORATED_GOALS`]
    /// goals; `order` lists the types children first (the types form no cycle).
    fn expansion_sizes(&mut self, file: &MissionFile, order: &[usize]) {
        let named = |name: &str| file.types.iter().position(|t| t.name == name);
        let mut size = vec![0u64; file.types.len()];
        for &t in order {
            // Each goal elaborates with one tactic; the largest bounds them all.
            size[t] = (file.types[t].tactics.iter())
                .map(|tactic| {
                    (tactic.goals.iter())
                        .map(|child| {
                            let below = child.goal_type.as_deref().and_then(named);
                            1u64.saturating_add(below.map_or(0, |c| size[c]))
                        })
                        .fold(0u64, u64::saturating_add)
                })
                .max()
                .unwrap_or(0);
            if size[t] > MAX_ELABORATED_GOALS {
                self.error(
                    &[Step::Field("types"), Step::Index(t), Step::Field("name")],
                    format!(
                        "a goal of type `{}` elaborates into {} goals",
                        file.types[t].name,
                        if size[t] == u64::MAX {
                            "more than 10¹⁹".to_string()
                        } else {
                            size[t].to_string()
                        }
                    ),
                    &format!(
                        "at most {MAX_ELABORATED_GOALS} goals from one goal's elaboration \
                         (typed children multiply down every level)"
                    ),
                );
                // Its parents would repeat the error: they are bounded by this one's report.
                size[t] = 0;
            }
        }
    }

    /// Resolves the `type` of the initial network's macros and goals; refuses one in `safe`.
    fn typed_goals(
        &mut self,
        file: &MissionFile,
        network: &GoalNetwork,
        elaborators: &mut Elaborators,
    ) {
        for item in listed(&file.network) {
            let Some(type_name) = item.goal_type else {
                continue;
            };
            let path = Item::listed("network", item.list, item.index).path("type");
            let found = self.goal_type(elaborators, &path, type_name);
            if let (Some(found), Some(goal)) = (found, network.goal_named(item.name)) {
                elaborators.of_goal[goal.index()] = Some(found);
            }
        }
        for item in listed(&file.safe) {
            if item.goal_type.is_some() {
                self.error(
                    &Item::listed("safe", item.list, item.index).path("type"),
                    "the safe network is not elaborated: its goals take no type".into(),
                    "no `type:` in the safe network (it must be promotable as written)",
                );
            }
        }
    }

    fn goal_type(
        &mut self,
        elaborators: &Elaborators,
        path: &[Step],
        name: &str,
    ) -> Option<TypeId> {
        let found = elaborators.named(name);
        if found.is_none() {
            let span = self.locate.at(path);
            let known = elaborators.types.iter().map(|t| t.name.as_str());
            let mut diagnostic = Diagnostic::new(format!("unknown goal type `{name}`"), span)
                .expected("a type declared in `types`");
            if let Some(close) = did_you_mean(name, known) {
                diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
            }
            self.errors.push(diagnostic);
        }
        found
    }

    fn tactic(
        &mut self,
        plant: &Plant,
        elaborators: &Elaborators,
        type_index: usize,
        index: usize,
        spec: &TacticFile,
    ) -> Tactic {
        let prefix = vec![
            Step::Field("types"),
            Step::Index(type_index),
            Step::Field("tactics"),
            Step::Index(index),
        ];
        let at = |rest: &[Step<'static>]| {
            let mut path = prefix.clone();
            path.extend_from_slice(rest);
            path
        };
        let mut points: Vec<String> = Vec::new();
        for (i, name) in spec.points.iter().enumerate() {
            let path = at(&[Step::Field("points"), Step::Index(i)]);
            if !logic::is_value_name(name) || RESERVED_POINTS.contains(&name.as_str()) {
                self.error(
                    &path,
                    format!("`{name}` cannot name a tactic's point"),
                    "an identifier other than `start`, `end` and `origin`",
                );
            } else if points.contains(name) {
                self.error(
                    &path,
                    format!("time point `{name}` is declared twice"),
                    "a point name not used before in this tactic",
                );
            }
            points.push(name.clone());
        }
        let mut constraints = Vec::new();
        for (i, c) in spec.constraints.iter().enumerate() {
            let field = |f| at(&[Step::Field("constraints"), Step::Index(i), Step::Field(f)]);
            let from = self.point_ref(&points, &field("from"), &c.from);
            let to = self.point_ref(&points, &field("to"), &c.to);
            let (min, max) = (c.min.unwrap_or(0.0), c.max.unwrap_or(f64::INFINITY));
            let valid = min <= max && min != f64::INFINITY && max != f64::NEG_INFINITY;
            if !valid {
                self.error(
                    &field(if min.is_nan() || min == f64::INFINITY {
                        "min"
                    } else {
                        "max"
                    }),
                    format!("bounds [{min}, {max}] describe no interval of time"),
                    "min ≤ max, both numbers (max may be left out for +∞)",
                );
            }
            let span = self
                .locate
                .at(&at(&[Step::Field("constraints"), Step::Index(i)]));
            if let (Some(from), Some(to), true) = (from, to, valid) {
                constraints.push(TacticConstraint {
                    from,
                    to,
                    min,
                    max,
                    span,
                });
            }
        }
        let mut goals = Vec::new();
        for (i, child) in spec.goals.iter().enumerate() {
            let mut path = prefix.clone();
            path.extend([Step::Field("goals"), Step::Index(i)]);
            let item = Item { prefix: path };
            if let Some(goal) = self.child(plant, elaborators, &points, &item, child) {
                goals.push(goal);
            }
        }
        Tactic {
            name: spec
                .name
                .clone()
                .unwrap_or_else(|| format!("tactic {}", index + 1)),
            points,
            constraints,
            goals,
        }
    }

    fn point_ref(&mut self, points: &[String], path: &[Step], name: &str) -> Option<PointRef> {
        match name {
            "start" => return Some(PointRef::Start),
            "end" => return Some(PointRef::End),
            _ => {}
        }
        if let Some(i) = points.iter().position(|p| p == name) {
            return Some(PointRef::Local(i));
        }
        let span = self.locate.at(path);
        let known = points.iter().map(String::as_str).chain(["start", "end"]);
        let mut diagnostic = Diagnostic::new(format!("unknown time point `{name}`"), span)
            .expected("`start` or `end` (the parent goal's points), or a point of this tactic");
        if let Some(close) = did_you_mean(name, known) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        self.errors.push(diagnostic);
        None
    }

    fn child(
        &mut self,
        plant: &Plant,
        elaborators: &Elaborators,
        points: &[String],
        item: &Item,
        spec: &ChildFile,
    ) -> Option<ChildGoal> {
        if !logic::is_value_name(&spec.name) {
            self.error(
                &item.path("name"),
                format!("`{}` is not a valid goal name", spec.name),
                "an identifier (letters, digits, `_`, `-`)",
            );
        }
        let goal_type = match &spec.goal_type {
            Some(name) => Some(self.goal_type(elaborators, &item.path("type"), name)?),
            None => None,
        };
        let start = self.point_ref(points, &item.path("start"), &spec.start);
        let end = self.point_ref(points, &item.path("end"), &spec.end);
        let kind = spec.kind.kind();
        let (sv, constraint) = match &spec.sv {
            None => {
                if spec.constraint.is_some() {
                    self.error(
                        &item.path("constraint"),
                        "a child on its parent's state variable takes its parent's constraint"
                            .into(),
                        "no `constraint:`, or an `sv:` naming the state variable it constrains",
                    );
                    return None;
                }
                (None, ChildConstraint::Inherit)
            }
            Some(name) => {
                let sv = self.state_variable(plant, &item.path("sv"), name)?;
                let text = spec.constraint.as_deref();
                let set = self.constraint_set(plant, sv, kind, item, text)?;
                let text = text.unwrap_or_default().to_string();
                (Some(sv), ChildConstraint::Given(set, text))
            }
        };
        Some(ChildGoal {
            name: spec.name.clone(),
            goal_type,
            sv,
            kind,
            constraint,
            start: start?,
            end: end?,
            priority: spec.priority,
            span: self.locate.at(&item.path("name")),
        })
    }
}
