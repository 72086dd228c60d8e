//! The mission file (DESIGN.md §15.4): a goal network in RON, bound to a plant model. Reference
//! for users: `docs/reference/mission.md`.
//!
//! ```ron
//! Mission(
//!     name: "thermostat: stay warm",          // optional; default: the file's name
//!     plant: "../models/thermostat.ron",      // relative to this file
//!     knowledge_threshold: 0.9,               // optional (default 0.9): P(ŝ value) that makes
//!                                             // a state variable "known"
//!     network: Network(
//!         // Time points; `origin` (absolute time 0) is always there and every point is at or
//!         // after it.
//!         points: ["TP_S", "TP_E"],
//!         // min ≤ t(to) − t(from) ≤ max, seconds; min defaults to 0 (order only), max to +∞.
//!         constraints: [
//!             Constraint(from: "origin", to: "TP_S", min: 10.0, max: 200.0),
//!             Constraint(from: "TP_S", to: "TP_E", min: 300.0, max: 300.0),
//!         ],
//!         // Macro goals: no state variable; they exist to be elaborated and to be
//!         // the parents of goals.
//!         macros: [Macro(name: "StayWarm", start: "TP_S", end: "TP_E")],
//!         goals: [
//!             // sv: a component (its mode variable is the state variable). kind: Maintain
//!             // (hold throughout), Transition (reach by the end point), Knowledge, or
//!             // Unconstrained. Maintain and Transition need a constraint over the SV alone.
//!             Goal(name: "heater1", sv: "switch1", kind: Maintain,
//!                  constraint: "switch1 = closed or switch1 = stuck-closed",
//!                  start: "TP_S", end: "TP_E", parent: "StayWarm", priority: 1),
//!             // Knowledge: no constraint = "known" at the threshold; or a conjunction of
//!             // least beliefs, `P(sensor = healthy) >= 0.95`.
//!             Goal(name: "know-sensor", sv: "sensor", kind: Knowledge,
//!                  start: "origin", end: "TP_E"),
//!         ],
//!     ),
//!     // Optional: the network safing promotes; default: every SV unconstrained.
//!     // Not elaborated: its goals take no `type`.
//!     safe: Network(goals: [...]),
//!     // Optional: goal types — failure responses and elaborators' tactics (module
//!     // `elaborators`, `missions/thermostat.ron`). A goal or macro of `network` takes one
//!     // with `type: "StayWarm"`.
//!     types: [GoalType(name: "StayWarm", response: ReElaborate, tactics: [...])],
//!     // Optional: controllers of state variables that are not plant components; a goal on
//!     // such a state variable is delegated to its controller (module `delegated`,
//!     // `missions/rover_traverse.ron`):
//!     controllers: [CourseOfAction(sv: "pose",
//!         device: Grid(size: 5, obstacles: [(2, 0)], rover: (x: 0, y: 0, heading: E)))],
//! )
//! ```
//! A goal's `parent` names a macro or a goal declared before it, so the goals form a tree.
//! Names of points, macros and goals are unique in their network. The network must be
//! temporally consistent: otherwise the error points at a constraint of the negative cycle and
//! lists the others.
//!
//! Every error names the file, line and column, shows the text and says what was expected.

mod delegated;
mod elaborators;
mod submission;

pub use submission::parse_submission;
pub(crate) use submission::resolve_submission;

use std::path::Path;

use serde::Deserialize;

use super::constraint_set::ConstraintSet;
use super::goal::{Goal, GoalKind};
use super::network::GoalNetwork;
use super::stn::Inconsistency;
use super::tactic::Elaborators;
use super::temporal_constraint::{Provenance, TemporalConstraint};
use super::time_point::TimePointId;
use crate::diagnostic::locate::{Locator, Step};
use crate::diagnostic::{Diagnostic, ReadError, Source, SourceErrors, did_you_mean, ron_error};
use crate::diagnostic::{LoadErrors, resolve_path};
use crate::logic::{self, Atom, CmpOp, Formula, ValueId};
use crate::plant::{ComponentId, Plant};
use crate::protocol::CoaDeclaration;

/// The knowledge threshold when the mission does not give one.
pub const DEFAULT_KNOWLEDGE_THRESHOLD: f64 = 0.9;

/// A loaded mission: the plant it binds to and its goal networks.
#[derive(Debug, Clone)]
pub struct Mission {
    /// Its name.
    pub name: String,
    /// The mission file.
    pub source: Source,
    /// The plant model's path, as resolved from the mission's directory.
    pub plant_path: String,
    /// The plant model.
    pub plant: Plant,
    /// P(ŝ value) at or above which a state variable is known.
    pub knowledge_threshold: f64,
    /// The initial goal network, propagated.
    pub network: GoalNetwork,
    /// The safe network (safing promotes it).
    pub safe: GoalNetwork,
    /// The goal types (elaborators, tactics, failure responses) and the initial goals' types.
    pub elaborators: Elaborators,
    /// The controllers of state variables that are not plant components, which goals on them
    /// are delegated to (a [`Delegate`](super::Delegate) indexes this list).
    pub controllers: Vec<CoaDeclaration>,
}

/// Why a mission could not be loaded: the file is unreadable, or its problems grouped by file
/// (the mission, the plant model) — the same shape as a scenario's.
pub type MissionErrors = LoadErrors;

#[derive(Deserialize)]
#[serde(rename = "Mission", deny_unknown_fields)]
struct MissionFile {
    name: Option<String>,
    plant: String,
    knowledge_threshold: Option<f64>,
    network: NetworkFile,
    #[serde(default)]
    safe: NetworkFile,
    #[serde(default)]
    types: Vec<elaborators::TypeFile>,
    #[serde(default)]
    controllers: Vec<delegated::ControllerFile>,
}

/// A `Network(...)` as written: a mission's network, its safe network, or the goals a scenario's
/// rule submits ([`resolve_submission`]).
#[derive(Deserialize, Default)]
#[serde(rename = "Network", deny_unknown_fields)]
pub(crate) struct NetworkFile {
    #[serde(default)]
    points: Vec<String>,
    #[serde(default)]
    constraints: Vec<ConstraintFile>,
    #[serde(default)]
    macros: Vec<MacroFile>,
    #[serde(default)]
    goals: Vec<GoalFile>,
}

#[derive(Deserialize)]
#[serde(rename = "Constraint", deny_unknown_fields)]
struct ConstraintFile {
    from: String,
    to: String,
    min: Option<f64>,
    max: Option<f64>,
}

impl ConstraintFile {
    /// `[min, max]`, min defaulting to 0 (order only) and max to +∞.
    fn bounds(&self) -> (f64, f64) {
        (self.min.unwrap_or(0.0), self.max.unwrap_or(f64::INFINITY))
    }
}

#[derive(Deserialize)]
#[serde(rename = "Macro", deny_unknown_fields)]
struct MacroFile {
    name: String,
    start: String,
    end: String,
    parent: Option<String>,
    #[serde(default)]
    priority: i32,
    #[serde(rename = "type")]
    goal_type: Option<String>,
}

#[derive(Deserialize, Clone, Copy)]
enum KindFile {
    Maintain,
    Transition,
    Knowledge,
    Unconstrained,
}

impl KindFile {
    fn kind(self) -> GoalKind {
        match self {
            KindFile::Maintain => GoalKind::Maintain,
            KindFile::Transition => GoalKind::Transition,
            KindFile::Knowledge => GoalKind::Knowledge,
            KindFile::Unconstrained => GoalKind::Unconstrained,
        }
    }
}

#[derive(Deserialize)]
#[serde(rename = "Goal", deny_unknown_fields)]
struct GoalFile {
    name: String,
    sv: String,
    kind: KindFile,
    constraint: Option<String>,
    start: String,
    end: String,
    parent: Option<String>,
    #[serde(default)]
    priority: i32,
    #[serde(rename = "type")]
    goal_type: Option<String>,
}

/// Reads the mission at `path`.
pub fn load(path: &Path) -> Result<Mission, MissionErrors> {
    let source = Source::read(path)?;
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    load_source(&source, &dir)
}

/// Reads a mission from its text; its plant path is relative to `dir`.
pub fn load_source(source: &Source, dir: &Path) -> Result<Mission, MissionErrors> {
    let invalid =
        |diagnostics| LoadErrors::Invalid(vec![SourceErrors::new(source.clone(), diagnostics)]);
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let file: MissionFile = options
        .from_str(&source.text)
        .map_err(|e| invalid(vec![ron_error(source, &e)]))?;
    let mut loader = Loader {
        locate: Locator::new(&source.text),
        source,
        errors: Vec::new(),
        controllers: Vec::new(),
    };
    let plant_path = resolve_path(dir, &file.plant).display().to_string();
    let plant_source = match Source::read(Path::new(&plant_path)) {
        Ok(source) => source,
        Err(ReadError::NotUtf8(errors)) => return Err(LoadErrors::Invalid(vec![*errors])),
        Err(ReadError::Io { error: e, .. }) => {
            loader.error(
                &[Step::Field("plant")],
                format!("cannot read `{plant_path}`: {e}"),
                "a path to a plant model, relative to the mission file",
            );
            return Err(invalid(loader.errors));
        }
    };
    let plant = Plant::load(&plant_source).map_err(|e| LoadErrors::Invalid(vec![e]))?;
    let knowledge_threshold = loader.threshold(file.knowledge_threshold);
    loader.controllers = loader.controllers(&plant, &file.controllers);
    let network = loader.network(&plant, &file.network, "network");
    let safe = loader.network(&plant, &file.safe, "safe");
    let elaborators = loader.elaborators(&plant, &file, &network);
    if !loader.errors.is_empty() {
        return Err(invalid(loader.errors));
    }
    let name = file.name.clone().unwrap_or_else(|| {
        Path::new(&source.name)
            .file_stem()
            .map_or_else(|| source.name.clone(), |s| s.to_string_lossy().to_string())
    });
    Ok(Mission {
        name,
        source: source.clone(),
        plant_path,
        plant,
        knowledge_threshold,
        network,
        safe,
        elaborators,
        controllers: loader.controllers,
    })
}

struct Loader<'a> {
    source: &'a Source,
    locate: Locator,
    errors: Vec<Diagnostic>,
    /// The mission's controllers of state variables that are not components.
    controllers: Vec<CoaDeclaration>,
}

/// Where a goal's or macro's fields are: `network.goals[i]`, `network.macros[i]`, or a
/// tactic's child `types[i].tactics[j].goals[k]`.
#[derive(Clone)]
struct Item<'p> {
    prefix: Vec<Step<'p>>,
}

impl<'p> Item<'p> {
    /// `network.list[index]`.
    fn listed(network: &'p str, list: &'p str, index: usize) -> Self {
        Item {
            prefix: vec![Step::Field(network), Step::Field(list), Step::Index(index)],
        }
    }

    fn path(&self, field: &'p str) -> Vec<Step<'p>> {
        let mut path = self.prefix.clone();
        path.push(Step::Field(field));
        path
    }
}

impl Loader<'_> {
    fn error(&mut self, path: &[Step], message: String, expected: &str) {
        let span = self.locate.at(path);
        self.errors
            .push(Diagnostic::new(message, span).expected(expected));
    }

    fn threshold(&mut self, given: Option<f64>) -> f64 {
        match given {
            None => DEFAULT_KNOWLEDGE_THRESHOLD,
            Some(p) if p > 0.0 && p <= 1.0 => p,
            Some(p) => {
                self.error(
                    &[Step::Field("knowledge_threshold")],
                    format!("knowledge threshold {p} is not a probability above 0"),
                    "a probability in (0, 1], such as 0.9",
                );
                DEFAULT_KNOWLEDGE_THRESHOLD
            }
        }
    }

    fn network(&mut self, plant: &Plant, file: &NetworkFile, field: &str) -> GoalNetwork {
        let mut network = GoalNetwork::new();
        self.points(&mut network, file, &[Step::Field(field)]);
        self.constraints(&mut network, file, &[Step::Field(field)]);
        for (index, spec) in file.macros.iter().enumerate() {
            let item = Item::listed(field, "macros", index);
            let header = Header {
                name: &spec.name,
                start: &spec.start,
                end: &spec.end,
                parent: spec.parent.as_deref(),
                priority: spec.priority,
            };
            if let Some(goal) = self.header(&network, &item, &header) {
                network.add_goal(goal(
                    None,
                    GoalKind::Unconstrained,
                    ConstraintSet::unconstrained(0),
                    String::new(),
                ));
            }
        }
        for (index, spec) in file.goals.iter().enumerate() {
            let item = Item::listed(field, "goals", index);
            self.goal(plant, &mut network, item, spec);
        }
        if let Err(inconsistency) = network.propagate() {
            self.inconsistent(&network, field, &inconsistency);
        }
        network
    }

    /// The network's points, the network being at `at` in the file.
    fn points(&mut self, network: &mut GoalNetwork, file: &NetworkFile, at: &[Step]) {
        for (i, name) in file.points.iter().enumerate() {
            let path = [at, &[Step::Field("points"), Step::Index(i)]].concat();
            if !logic::is_value_name(name) {
                self.error(
                    &path,
                    format!("`{name}` is not a valid time point name"),
                    "an identifier (letters, digits, `_`, `-`)",
                );
            } else if network.point_named(name).is_some() {
                self.error(
                    &path,
                    format!("time point `{name}` is declared twice"),
                    "a point name not used before (`origin` is always declared)",
                );
            } else {
                let span = self.locate.at(&path);
                network.add_point(name.clone(), span);
            }
        }
    }

    fn point(&mut self, network: &GoalNetwork, path: &[Step], name: &str) -> Option<TimePointId> {
        let found = network.point_named(name);
        if found.is_none() {
            let span = self.locate.at(path);
            let known = network.points().iter().map(|p| p.name.as_str());
            let mut diagnostic = Diagnostic::new(format!("unknown time point `{name}`"), span)
                .expected("a point listed in `points`, or `origin`");
            if let Some(close) = did_you_mean(name, known) {
                diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
            }
            self.errors.push(diagnostic);
        }
        found
    }

    /// The network's temporal constraints, the network being at `network_at` in the file.
    fn constraints(&mut self, network: &mut GoalNetwork, file: &NetworkFile, network_at: &[Step]) {
        for (i, spec) in file.constraints.iter().enumerate() {
            let whole = [network_at, &[Step::Field("constraints"), Step::Index(i)]].concat();
            let at = |f| [&whole[..], &[Step::Field(f)]].concat();
            let from = self.point(network, &at("from"), &spec.from);
            let to = self.point(network, &at("to"), &spec.to);
            let (min, max) = spec.bounds();
            let span = self.locate.at(&whole);
            let constraint = TemporalConstraint::new(
                from.unwrap_or(TimePointId::ORIGIN),
                to.unwrap_or(TimePointId::ORIGIN),
                min,
                max,
                Provenance::Written(span),
            );
            if !constraint.bounds_are_valid() {
                let culprit = if min.is_nan() || min == f64::INFINITY {
                    "min"
                } else {
                    "max"
                };
                self.error(
                    &at(culprit),
                    format!("bounds [{min}, {max}] describe no interval of time"),
                    "min ≤ max, both numbers (max may be left out for +∞)",
                );
            } else if from.is_some() && to.is_some() {
                // Points and bounds were checked: the network accepts it.
                let _ = network.add_constraint(constraint);
            }
        }
    }

    /// Checks the fields a goal and a macro share; returns a builder for the goal.
    fn header(
        &mut self,
        network: &GoalNetwork,
        item: &Item,
        header: &Header,
    ) -> Option<impl FnOnce(Option<ComponentId>, GoalKind, ConstraintSet, String) -> Goal + use<>>
    {
        let name_path = item.path("name");
        let mut ok = true;
        if !logic::is_value_name(header.name) {
            self.error(
                &name_path,
                format!("`{}` is not a valid goal name", header.name),
                "an identifier (letters, digits, `_`, `-`)",
            );
            ok = false;
        } else if network.goal_named(header.name).is_some() {
            self.error(
                &name_path,
                format!("goal `{}` is declared twice", header.name),
                "a goal or macro name not used before",
            );
            ok = false;
        }
        let start = self.point(network, &item.path("start"), header.start);
        let end = self.point(network, &item.path("end"), header.end);
        let parent = match header.parent {
            None => None,
            Some(name) => {
                let found = network.goal_named(name);
                if found.is_none() {
                    self.error(
                        &item.path("parent"),
                        format!("unknown parent goal `{name}`"),
                        "a macro, or a goal declared before this one",
                    );
                    ok = false;
                }
                found
            }
        };
        let (start, end) = (start?, end?);
        let span = self.locate.at(&name_path);
        let name = header.name.to_string();
        let priority = header.priority;
        ok.then_some(move |sv, kind, constraint, text| Goal {
            name,
            sv,
            kind,
            constraint,
            delegate: None,
            text,
            start,
            end,
            parent,
            priority,
            span,
        })
    }

    fn goal(&mut self, plant: &Plant, network: &mut GoalNetwork, item: Item, spec: &GoalFile) {
        let header = Header {
            name: &spec.name,
            start: &spec.start,
            end: &spec.end,
            parent: spec.parent.as_deref(),
            priority: spec.priority,
        };
        let build = self.header(network, &item, &header);
        if let Some(controller) = self.controllers.iter().position(|c| c.sv == spec.sv) {
            let delegate = self.delegate(&item, spec, controller);
            if let (Some(build), Some(delegate)) = (build, delegate) {
                let text = spec.constraint.clone().unwrap_or_default();
                let unconstrained = ConstraintSet::unconstrained(0);
                let mut goal = build(None, GoalKind::Transition, unconstrained, text);
                goal.delegate = Some(delegate);
                network.add_goal(goal);
            }
            return;
        }
        let Some(sv) = self.state_variable(plant, &item.path("sv"), &spec.sv) else {
            return;
        };
        let kind = spec.kind.kind();
        let constraint = self.constraint_set(plant, sv, kind, &item, spec.constraint.as_deref());
        if let (Some(build), Some(constraint)) = (build, constraint) {
            let text = spec.constraint.clone().unwrap_or_default();
            network.add_goal(build(Some(sv), kind, constraint, text));
        }
    }

    /// The component `name` names (its mode variable is the state variable), or an error.
    fn state_variable(&mut self, plant: &Plant, path: &[Step], name: &str) -> Option<ComponentId> {
        let found = plant.component_named(name);
        if found.is_none() {
            let span = self.locate.at(path);
            let known = plant.components().iter().map(|c| c.name());
            let mut diagnostic = Diagnostic::new(format!("unknown state variable `{name}`"), span)
                .expected("a component of the plant (its mode variable is the state variable)");
            if let Some(close) = did_you_mean(name, known) {
                diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
            }
            self.errors.push(diagnostic);
        }
        found
    }

    /// The constraint set a goal's kind and constraint text describe.
    fn constraint_set(
        &mut self,
        plant: &Plant,
        sv: ComponentId,
        kind: GoalKind,
        item: &Item,
        text: Option<&str>,
    ) -> Option<ConstraintSet> {
        let var = plant.component(sv).mode_var();
        let domain = plant.table().variable(var).domain_size();
        let path = item.path("constraint");
        let Some(text) = text else {
            return match kind {
                GoalKind::Maintain | GoalKind::Transition => {
                    self.error(
                        &item.path("kind"),
                        format!("a {} goal needs a constraint", kind.name()),
                        "`constraint: \"...\"` over the state variable's values",
                    );
                    None
                }
                GoalKind::Knowledge => Some(ConstraintSet::unconstrained(domain).with_known()),
                GoalKind::Unconstrained => Some(ConstraintSet::unconstrained(domain)),
            };
        };
        let offset = self.locate.at(&path).start;
        let formula = match logic::syntax::parse_at(text, offset)
            .map_err(|d| vec![d])
            .and_then(|expr| logic::resolve(&expr, plant.table()))
        {
            Ok(formula) => formula,
            Err(diagnostics) => {
                self.errors.extend(diagnostics);
                return None;
            }
        };
        let span = offset..offset + text.len();
        let sv_name = plant.component(sv).name().to_string();
        let fail = |message: String, expected: &str| {
            Diagnostic::new(message, span.clone()).expected(expected)
        };
        match kind {
            GoalKind::Unconstrained => {
                self.errors.push(fail(
                    "an Unconstrained goal takes no constraint".into(),
                    "no `constraint:`",
                ));
                None
            }
            GoalKind::Knowledge => {
                let beliefs = least_beliefs(&formula, var);
                if beliefs.is_none() {
                    self.errors.push(fail(
                        format!("a Knowledge goal's constraint must be least beliefs in values of `{sv_name}`"),
                        &format!("`P({sv_name} = value) >= p`, joined by `and`"),
                    ));
                }
                let set = ConstraintSet::unconstrained(domain);
                beliefs.map(|b| b.into_iter().fold(set, |s, (v, p)| s.with_belief(v, p)))
            }
            GoalKind::Maintain | GoalKind::Transition => {
                let admits = |value: ValueId| {
                    formula.eval(&|atom| match atom {
                        Atom::Is(x, v) if *x == var => Some(*v == value),
                        _ => None,
                    })
                };
                let decided = (0..domain as u32)
                    .map(|v| admits(ValueId(v)))
                    .collect::<Option<Vec<bool>>>();
                let Some(admitted) = decided else {
                    self.errors.push(fail(
                        format!("a goal on `{sv_name}` may only constrain `{sv_name}`"),
                        &format!("a formula over `{sv_name} = value` atoms"),
                    ));
                    return None;
                };
                let set = ConstraintSet::control(domain, |v| admitted[v.index()]);
                if set.is_empty() {
                    self.errors.push(fail(
                        format!("the constraint admits no value of `{sv_name}`"),
                        "a constraint some mode satisfies",
                    ));
                    return None;
                }
                Some(set)
            }
        }
    }

    /// Reports a negative cycle at its first written constraint, listing the others.
    fn inconsistent(&mut self, network: &GoalNetwork, field: &str, inconsistency: &Inconsistency) {
        let stn = network.stn();
        let mut span = None;
        let mut notes = Vec::new();
        for id in &inconsistency.cycle {
            let c = stn.constraint(*id);
            let (from, to) = (&network.point(c.from).name, &network.point(c.to).name);
            let bounds = format!("{from} → {to} ∈ [{}, {}]", seconds(c.min), seconds(c.max));
            match &c.provenance {
                Provenance::Written(s) => {
                    let (line, col) = self.source.line_col(s.start);
                    notes.push(format!("{bounds} ({}:{line}:{col})", self.source.name));
                    span.get_or_insert(s.clone());
                }
                Provenance::AfterOrigin => {
                    notes.push(format!("{bounds} (every point is at or after the origin)"))
                }
                other => notes.push(format!("{bounds} ({other:?})")),
            }
        }
        let span = span.unwrap_or_else(|| self.locate.at(&[Step::Field(field)]));
        let mut diagnostic = Diagnostic::new(
            "the temporal constraints cannot all hold (a negative cycle)",
            span,
        )
        .expected("constraints with a common solution");
        diagnostic.notes.push("the cycle:".into());
        diagnostic.notes.extend(notes);
        self.errors.push(diagnostic);
    }
}

/// The fields a goal and a macro share.
struct Header<'a> {
    name: &'a str,
    start: &'a str,
    end: &'a str,
    parent: Option<&'a str>,
    priority: i32,
}

/// `P(x = v) >= p and ...` over `var` as `(v, p)` pairs; `None` for any other shape.
fn least_beliefs(formula: &Formula, var: logic::VarId) -> Option<Vec<(ValueId, f64)>> {
    match formula {
        Formula::Atom(Atom::Confidence {
            var: x,
            value,
            op: CmpOp::Ge | CmpOp::Gt,
            probability,
        }) if *x == var => Some(vec![(*value, probability.0)]),
        Formula::And(parts) => {
            parts
                .iter()
                .map(|p| least_beliefs(p, var))
                .try_fold(Vec::new(), |mut all, part| {
                    all.extend(part?);
                    Some(all)
                })
        }
        _ => None,
    }
}

/// A bound as written in messages: `+∞`/`−∞` for open sides.
pub fn seconds(bound: f64) -> String {
    match bound {
        f64::INFINITY => "+∞".to_string(),
        f64::NEG_INFINITY => "−∞".to_string(),
        // `+ 0.0` turns −0 (the origin's lower bound, −d(Z, Z)) into 0.
        b => (b + 0.0).to_string(),
    }
}

/// Traces the enums a `Network(...)` holds, for the reference checks of the formats that embed
/// one (a scenario rule's `submit:`).
#[cfg(test)]
pub(crate) fn trace_network(tracer: &mut serde_reflection::Tracer) {
    crate::diagnostic::reference::add::<KindFile>(tracer);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::reference;

    /// `docs/reference/mission.md` lists every field and variant this loader accepts, and no
    /// other (poses, headings and estimates are the rover scenario's, documented on its page).
    #[test]
    fn the_reference_documents_every_field() {
        let mut tracer = reference::tracer();
        trace_network(&mut tracer);
        reference::add::<elaborators::ResponseFile>(&mut tracer);
        reference::add::<delegated::ControllerFile>(&mut tracer);
        reference::add::<delegated::DeviceFile>(&mut tracer);
        reference::add::<crate::protocol::scenario::Estimate>(&mut tracer);
        reference::add::<crate::protocol::posandhead::Heading>(&mut tracer);
        reference::add::<MissionFile>(&mut tracer);
        reference::assert_documented(&reference::registry(tracer), ASSIGNMENTS);
    }

    /// Where each container of a mission file is documented.
    const ASSIGNMENTS: &[reference::Assignment] = &[
        ("Mission", "mission.md", "`Mission(...)`"),
        ("Network", "mission.md", "`Network(...)`"),
        ("Constraint", "mission.md", "`Constraint(...)`"),
        ("Macro", "mission.md", "`Macro(...)`"),
        ("Goal", "mission.md", "`Goal(...)`"),
        ("KindFile", "mission.md", "Goal kinds"),
        ("GoalType", "mission.md", "`GoalType(...)`"),
        ("Response", "mission.md", "Responses"),
        ("Tactic", "mission.md", "`Tactic(...)`"),
        ("Child", "mission.md", "`Child(...)`"),
        ("ControllerFile", "mission.md", "Controllers"),
        ("DeviceFile", "mission.md", "Devices"),
        ("PoseFile", "rover-scenario.md", "Poses"),
        ("Heading", "rover-scenario.md", "Headings"),
        ("Estimate", "rover-scenario.md", "Estimate"),
    ];
}
