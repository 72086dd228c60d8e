//! The RON format of plant models (DESIGN.md §6.1) and its loader. Reference for users:
//! `docs/reference/plant.md`.
//!
//! ```ron
//! Plant(
//!     name: "driver_valve",
//!     components: [
//!         Component(
//!             name: "driver",
//!             // Attribute variables `driver.dcmd_in`, ... and their finite domains, in order.
//!             attributes: { "dcmd_in": ["no-command", "on", "off"], "dcmd_out": ["no-command", "on", "off"] },
//!             modes: [
//!                 // kind: Nominal (default) or Fault; constraint: default "true"; reward: default 0.
//!                 Mode(name: "off", constraint: "driver.dcmd_out = no-command"),
//!                 Mode(name: "turning-on"),
//!                 Mode(name: "on", constraint: "driver.dcmd_out = driver.dcmd_in"),
//!                 Mode(name: "failed", kind: Fault, reward: -20),
//!             ],
//!             // P_Θ: must sum to 1; modes not listed start with probability 0.
//!             initial: { "off": 0.9, "on": 0.1 },
//!             transitions: [
//!                 // Per cycle: `probability`, fired with that probability in every step.
//!                 (from: "off", to: "turning-on", guard: "driver.dcmd_in = on", probability: 0.989),
//!                 // Timed: `after` a distribution on the component clock (Uniform(l, u),
//!                 // Gaussian(mean, sd), Exponential(rate), Fixed(d); seconds); `probability` is
//!                 // the nominal factor (default 1).
//!                 (from: "turning-on", to: "on", after: Uniform(0.0, 0.1), probability: 0.989),
//!                 // A hazard: `rate` per second, independent of the cycle period.
//!                 // "*" is every nominal mode other than the target.
//!                 (from: "*", to: "failed", rate: 0.0001),
//!             ],
//!         ),
//!     ],
//!     // Control variables and the value each holds in a cycle without a command to it.
//!     controls: { "driver.dcmd_in": "no-command" },
//!     observables: ["driver.dcmd_out"],
//!     // Interconnections (Q): constraints between components' attributes.
//!     connections: [],
//! )
//! ```
//! A component that repeats is written once as a **type** and instantiated by name
//! (`src/plant/file/types.rs` has the rules): in a type, `self` is the instance and a number may be the name of
//! one of the type's parameters; an instance gives parameter values or takes the defaults; an
//! indexed name (`b[0..14]`) writes several instances, controls, observables or connections at
//! once. Loading expands them: the plant is the one the components written out would give.
//! ```ron
//! Plant(
//!     name: "two_switches",
//!     types: [
//!         Type(
//!             name: "switch",
//!             parameters: { "stuck": 0.00001 },      // name: default value
//!             attributes: { "cmd": ["none", "open", "close"], "heat": ["off", "on"] },
//!             modes: [
//!                 Mode(name: "open", constraint: "self.heat = off"),
//!                 Mode(name: "closed", constraint: "self.heat = on"),
//!                 Mode(name: "stuck-open", kind: Fault, constraint: "self.heat = off", reward: -20),
//!             ],
//!             initial: { "open": 1.0 },
//!             transitions: [
//!                 (from: "open", to: "closed", guard: "self.cmd = close", probability: 1.0),
//!                 (from: "closed", to: "open", guard: "self.cmd = open", probability: 1.0),
//!                 (from: "*", to: "stuck-open", rate: "stuck"),   // the parameter
//!             ],
//!         ),
//!     ],
//!     components: [
//!         Component(name: "switch1", type: "switch"),
//!         Component(name: "switch2", type: "switch", parameters: { "stuck": 0.00002 }),
//!     ],
//!     controls: { "switch[1..2].cmd": "none" },
//!     observables: ["switch[1..2].heat"],
//! )
//! ```
//! An error in a type's body points at the type's text and at the instance it was expanded for.
//!
//! An observable may be **numeric**: `monitors: { "bus.voltage": Monitor(...) }` says how its
//! readings become qualitative values (`src/plant/file/monitors.rs` has the
//! format, [`monitor`](super::monitor) the semantics).
//!
//! A control may name the observable that reports flight software's answer to its last command:
//! `acknowledgements: { "PDE.cmd": "PDE.ack" }` (`src/plant/file/acknowledgements.rs` has the
//! rules, [`acknowledgement`](super::acknowledgement) the semantics).
//!
//! Semantics (thesis §6.1, DESIGN.md §6.2): a transition is enabled when the constraint store
//! (the current modes' constraints, the interconnections and the commands) entails its guard;
//! a mode stays with the probability its enabled transitions leave (no explicit self-loops); a
//! component takes at most one transition per cycle and its clock restarts when it changes mode.
//! See [`TransitionLaw`](super::TransitionLaw) for how per-cycle, rate and timed laws combine.
//!
//! Every error names the file, line and column, shows the text, says what was expected and which
//! component and mode it concerns. Formulas are the constraint language of DESIGN.md §4.

mod acknowledgements;
mod component;
mod monitors;
mod schema;
pub(crate) mod types;

use std::collections::{HashMap, HashSet};

use super::{ComponentIndex, Control, Plant, validate};
use crate::diagnostic::locate::NumberOrName as Number;
use crate::diagnostic::locate::{Entries, Locator, Step};
use crate::diagnostic::{Diagnostic, Source, SourceErrors, Span, did_you_mean, ron_error};
use crate::logic::{self, DeclarationError, Formula, VarId, VarTable, is_value_name};
use schema::{ComponentFile, KindFile, ModeFile, PlantFile, TimingFile, TransitionFile};
use types::{expand_indexed, rename_self};

/// Initial probabilities and outgoing sums are compared with this tolerance.
pub(crate) const TOLERANCE: f64 = 1e-9;

/// What a component is made of: the body of a component written out, or of its type.
#[derive(Clone, Copy)]
struct Body<'f> {
    attributes: &'f Entries<Vec<String>>,
    modes: &'f [ModeFile],
    initial: &'f Entries<Number>,
    transitions: &'f [TransitionFile],
}

/// One component of the plant, after types and indexed names are expanded.
struct Spec<'f> {
    name: String,
    body: Body<'f>,
    /// For an instance of a type: each parameter's value (the instance's, else the type's).
    parameters: Option<Vec<(&'f str, f64)>>,
}

/// Where a component of the expanded plant is written: its entry in `components` (its name)
/// and, for an instance, the type that holds its body.
#[derive(Debug, Clone)]
struct Place {
    entry: usize,
    of_type: Option<usize>,
    /// For an instance: the instance's name span and how to name it beside an error in its type.
    instance: Option<(Span, String)>,
}

/// Locates what belongs to each component of the expanded plant in the file: its body in the
/// component's own entry or in its type, its name in its entry. An error in a type's body is
/// also labelled with the instance it was expanded for.
pub(crate) struct Places {
    locate: Locator,
    places: Vec<Place>,
}

impl Places {
    /// The path to `rest` inside component `c`'s body.
    fn path<'a>(&self, c: usize, rest: &[Step<'a>]) -> Vec<Step<'a>> {
        let mut path = match self.places.get(c) {
            Some(Place {
                of_type: Some(t), ..
            }) => vec![Step::Field("types"), Step::Index(*t)],
            Some(place) => vec![Step::Field("components"), Step::Index(place.entry)],
            None => vec![Step::Field("components")],
        };
        path.extend_from_slice(rest);
        path
    }

    /// A problem at `rest` in component `c`'s body, labelled with its instance if it has one.
    pub(crate) fn diagnostic(&self, c: usize, rest: &[Step], message: String) -> Diagnostic {
        let span = self.locate.at(&self.path(c, rest));
        self.label(c, Diagnostic::new(message, span))
    }

    /// Labels a diagnostic in component `c`'s body with its instance, if it has one.
    fn label(&self, c: usize, diagnostic: Diagnostic) -> Diagnostic {
        match self.places.get(c).and_then(|p| p.instance.clone()) {
            Some((span, label)) => diagnostic.related(span, label),
            None => diagnostic,
        }
    }

    /// The path to component `c`'s name (its entry's, for an instance).
    fn name_path(&self, c: usize) -> Vec<Step<'static>> {
        let entry = self.places.get(c).map_or(0, |p| p.entry);
        vec![
            Step::Field("components"),
            Step::Index(entry),
            Step::Field("name"),
        ]
    }

    /// Path to mode `m` of component `c`, then `field`.
    pub(crate) fn mode<'a>(&self, c: usize, m: usize, field: &'a str) -> Vec<Step<'a>> {
        self.path(
            c,
            &[Step::Field("modes"), Step::Index(m), Step::Field(field)],
        )
    }

    /// Path to transition `t` of component `c`, then `rest`.
    pub(crate) fn transition<'a>(&self, c: usize, t: usize, rest: &[Step<'a>]) -> Vec<Step<'a>> {
        let mut path = self.path(c, &[Step::Field("transitions"), Step::Index(t)]);
        path.extend_from_slice(rest);
        path
    }

    /// The span of a path.
    pub(crate) fn at(&self, path: &[Step]) -> Span {
        self.locate.at(path)
    }
}

/// Reads a plant model, reporting every problem found with its location.
pub fn load(source: &Source) -> Result<Plant, SourceErrors> {
    let fail = |diagnostics| SourceErrors::new(source.clone(), diagnostics);
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let file: PlantFile = options
        .from_str(&source.text)
        .map_err(|e| fail(vec![ron_error(source, &e)]))?;
    let mut loader = Loader {
        places: Places {
            locate: Locator::new(&source.text),
            places: Vec::new(),
        },
        errors: Vec::new(),
        table: VarTable::new(),
    };
    let plant = loader.plant(&file);
    if !loader.errors.is_empty() {
        return Err(fail(once_per_type(loader.errors)));
    }
    let errors = validate::check(&plant, &loader.places);
    if errors.is_empty() {
        Ok(plant)
    } else {
        Err(fail(once_per_type(errors)))
    }
}

/// An error in a type's body is found once per instance, at the same place: it is reported
/// for the first instance, with a note counting the others (fifteen breakers, one mistake).
fn once_per_type(errors: Vec<Diagnostic>) -> Vec<Diagnostic> {
    let mut kept: Vec<Diagnostic> = Vec::with_capacity(errors.len());
    let mut repeats: Vec<usize> = Vec::new();
    let mut first_at: HashMap<(usize, usize), usize> = HashMap::new();
    for diagnostic in errors {
        if !diagnostic.related.is_empty() {
            let key = (diagnostic.span.start, diagnostic.span.end);
            if let Some(&k) = first_at.get(&key) {
                repeats[k] += 1;
                continue;
            }
            first_at.insert(key, kept.len());
        }
        kept.push(diagnostic);
        repeats.push(0);
    }
    kept.into_iter()
        .zip(repeats)
        .map(|(d, n)| match n {
            0 => d,
            1 => d.note("the same in 1 other instance"),
            n => d.note(format!("the same in {n} other instances")),
        })
        .collect()
}

struct Loader {
    places: Places,
    errors: Vec<Diagnostic>,
    table: VarTable,
}

impl Loader {
    fn error(&mut self, path: &[Step], message: String, expected: impl Into<String>) {
        let span = self.places.at(path);
        self.errors
            .push(Diagnostic::new(message, span).expected(expected));
    }

    /// A problem at `rest` in component `c`'s body (in its type, for an instance).
    fn error_in(&mut self, c: usize, rest: &[Step], message: String, expected: impl Into<String>) {
        let diagnostic = self.places.diagnostic(c, rest, message).expected(expected);
        self.errors.push(diagnostic);
    }

    fn plant(&mut self, file: &PlantFile) -> Plant {
        let specs = self.expand(file);
        // Variables first, so that formulas anywhere may mention any component.
        let mut seen = HashSet::new();
        let declared: Vec<bool> = (0..specs.len())
            .map(|c| self.declare_component(&specs, c, &mut seen))
            .collect();
        let mut components = Vec::new();
        for (c, spec) in specs.iter().enumerate() {
            if declared[c] {
                components.push(self.component(c, spec));
            }
        }
        let controls = self.controls(file);
        let observables = self.observables(file, &controls);
        let connections = self.connections(file);
        let monitors = self.monitors(&file.monitors, &observables);
        let acknowledgements =
            self.acknowledgements(&file.acknowledgements, &controls, &observables);
        self.refuse_acknowledgements_in_constraints(&acknowledgements, &components, &connections);
        let index = ComponentIndex::new(&components, self.table.len());
        Plant {
            name: file.name.clone(),
            table: std::mem::take(&mut self.table),
            components,
            controls,
            observables,
            connections,
            monitors,
            acknowledgements,
            index,
        }
    }

    /// The plant's components with every instance of a type expanded, in file order; records
    /// where each is written ([`Places`]).
    fn expand<'f>(&mut self, file: &'f PlantFile) -> Vec<Spec<'f>> {
        let types = self.types(file);
        let mut specs = Vec::with_capacity(file.components.len());
        for (entry, component) in file.components.iter().enumerate() {
            let name_path = [
                Step::Field("components"),
                Step::Index(entry),
                Step::Field("name"),
            ];
            let Some(type_name) = &component.type_name else {
                self.written(entry, component, &mut specs);
                continue;
            };
            let Some(t) = self.type_named(&types, file, entry, type_name) else {
                continue;
            };
            let ty = &file.types[t];
            let parameters = self.instance_parameters(file, entry, t);
            self.refuse_own_body(entry, component);
            let names = match expand_indexed(&component.name) {
                Ok(names) => names,
                Err(e) => {
                    self.error(&name_path, e.message, e.expected);
                    continue;
                }
            };
            let name_span = self.places.at(&name_path);
            for name in names {
                self.places.places.push(Place {
                    entry,
                    of_type: Some(t),
                    instance: Some((
                        name_span.clone(),
                        format!("in `{name}`, an instance of type `{}`", ty.name),
                    )),
                });
                specs.push(Spec {
                    name,
                    body: Body {
                        attributes: &ty.attributes,
                        modes: &ty.modes,
                        initial: &ty.initial,
                        transitions: &ty.transitions,
                    },
                    parameters: Some(parameters.clone()),
                });
            }
        }
        specs
    }

    /// A component written out in full.
    fn written<'f>(
        &mut self,
        entry: usize,
        component: &'f ComponentFile,
        specs: &mut Vec<Spec<'f>>,
    ) {
        let at = |field| {
            [
                Step::Field("components"),
                Step::Index(entry),
                Step::Field(field),
            ]
        };
        if component.name.contains('[') {
            let message = format!(
                "`{}`: only instances of a type have indexed names",
                component.name
            );
            self.error(
                &at("name"),
                message,
                "a `type: \"...\"` to instantiate, or one name",
            );
            return;
        }
        if !component.parameters.0.is_empty() {
            let message = format!("component `{}` has parameters but no type", component.name);
            self.error(
                &at("parameters"),
                message,
                "`type: \"...\"`: parameters are a type's",
            );
        }
        self.places.places.push(Place {
            entry,
            of_type: None,
            instance: None,
        });
        specs.push(Spec {
            name: component.name.clone(),
            body: Body {
                attributes: &component.attributes,
                modes: &component.modes,
                initial: &component.initial,
                transitions: &component.transitions,
            },
            parameters: None,
        });
    }

    /// The types by name, checked: valid, unique names; parameters with valid names and finite
    /// defaults.
    fn types<'f>(&mut self, file: &'f PlantFile) -> HashMap<&'f str, usize> {
        let mut types = HashMap::new();
        for (t, ty) in file.types.iter().enumerate() {
            let at = |field| [Step::Field("types"), Step::Index(t), Step::Field(field)];
            if !is_value_name(&ty.name) {
                let message = format!("`{}` is not a valid type name", ty.name);
                self.error(
                    &at("name"),
                    message,
                    "an identifier (letters, digits, `_`, `-`)",
                );
            } else if types.insert(ty.name.as_str(), t).is_some() {
                let message = format!("type `{}` is declared twice", ty.name);
                self.error(&at("name"), message, "a type name not used before");
            }
            for (i, (name, value)) in ty.parameters.0.iter().enumerate() {
                let path = [
                    Step::Field("types"),
                    Step::Index(t),
                    Step::Field("parameters"),
                    Step::Key(name),
                ];
                if !is_value_name(name) {
                    let message =
                        format!("type `{}`: `{name}` is not a valid parameter name", ty.name);
                    self.error(&path, message, "an identifier (letters, digits, `_`, `-`)");
                } else if ty.parameters.0[..i].iter().any(|(other, _)| other == name) {
                    let message =
                        format!("type `{}`: parameter `{name}` is declared twice", ty.name);
                    self.error(&at("parameters"), message, "each parameter once");
                } else if !value.is_finite() {
                    let message = format!("type `{}`: parameter `{name}` is {value}", ty.name);
                    self.error(&path, message, "a finite number");
                }
            }
        }
        types
    }

    /// The type an instance names, or an error naming the types there are.
    fn type_named(
        &mut self,
        types: &HashMap<&str, usize>,
        file: &PlantFile,
        entry: usize,
        name: &str,
    ) -> Option<usize> {
        if let Some(&t) = types.get(name) {
            return Some(t);
        }
        let path = [
            Step::Field("components"),
            Step::Index(entry),
            Step::Field("type"),
        ];
        let names: Vec<&str> = file.types.iter().map(|t| t.name.as_str()).collect();
        let mut diagnostic = Diagnostic::new(format!("no type `{name}`"), self.places.at(&path))
            .expected("the name of a `Type(...)` of this file")
            .note(if names.is_empty() {
                "the file declares no type (`types: [Type(...)]`)".to_string()
            } else {
                format!("the types: {}", names.join(", "))
            });
        if let Some(close) = did_you_mean(name, names.iter().copied()) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        self.errors.push(diagnostic);
        None
    }

    /// An instance's parameter values: the type's defaults, overridden by the instance's own;
    /// a parameter the type does not declare is an error.
    fn instance_parameters<'f>(
        &mut self,
        file: &'f PlantFile,
        entry: usize,
        t: usize,
    ) -> Vec<(&'f str, f64)> {
        let ty = &file.types[t];
        let mut values: Vec<(&str, f64)> = ty
            .parameters
            .0
            .iter()
            .map(|(n, v)| (n.as_str(), *v))
            .collect();
        for (name, value) in &file.components[entry].parameters.0 {
            let path = [
                Step::Field("components"),
                Step::Index(entry),
                Step::Field("parameters"),
                Step::Key(name),
            ];
            match values.iter_mut().find(|(n, _)| n == name) {
                Some(slot) if value.is_finite() => slot.1 = *value,
                Some(_) => {
                    let message = format!("parameter `{name}` is {value}");
                    self.error(&path, message, "a finite number");
                }
                None => {
                    let declared: Vec<&str> =
                        ty.parameters.0.iter().map(|(n, _)| n.as_str()).collect();
                    let mut diagnostic = Diagnostic::new(
                        format!("type `{}` has no parameter `{name}`", ty.name),
                        self.places.at(&path),
                    )
                    .expected(format!("a parameter of `{}`", ty.name))
                    .note(if declared.is_empty() {
                        format!("`{}` declares no parameter", ty.name)
                    } else {
                        format!("`{}` has parameters: {}", ty.name, declared.join(", "))
                    });
                    if let Some(close) = did_you_mean(name, declared.iter().copied()) {
                        diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
                    }
                    self.errors.push(diagnostic);
                }
            }
        }
        values
    }

    /// An instance takes its body from its type: a body of its own is an error.
    fn refuse_own_body(&mut self, entry: usize, component: &ComponentFile) {
        let own = [
            ("attributes", !component.attributes.0.is_empty()),
            ("modes", !component.modes.is_empty()),
            ("initial", !component.initial.0.is_empty()),
            ("transitions", !component.transitions.is_empty()),
        ];
        for (field, written) in own {
            if written {
                let path = [
                    Step::Field("components"),
                    Step::Index(entry),
                    Step::Field(field),
                ];
                let message = format!(
                    "`{}` is an instance of a type and has `{field}` of its own",
                    component.name
                );
                self.error(&path, message, "no body: an instance has its type's (change the type, or write the component out)");
            }
        }
    }

    /// Declares a component's mode variable and attributes; false when its name is unusable
    /// (then it is left out, so that one bad name does not cascade into many errors).
    fn declare_component<'s>(
        &mut self,
        specs: &'s [Spec],
        c: usize,
        seen: &mut HashSet<&'s str>,
    ) -> bool {
        let spec = &specs[c];
        let name_path = self.places.name_path(c);
        if !is_value_name(&spec.name) {
            self.error(
                &name_path,
                format!("`{}` is not a valid component name", spec.name),
                "an identifier (letters, digits, `_`, `-`; no dots)",
            );
            return false;
        }
        if !seen.insert(spec.name.as_str()) {
            self.error(
                &name_path,
                format!("component `{}` is declared twice", spec.name),
                "a component name not used before",
            );
            return false;
        }
        let modes: Vec<&str> = spec.body.modes.iter().map(|m| m.name.as_str()).collect();
        let mut usable = self.names_are_fresh(c, &modes);
        if usable {
            if let Err(e) = self.table.add_variable(spec.name.clone(), modes) {
                let message = format!("component `{}`: {e}", spec.name);
                self.error(&name_path, message, "a name not used before");
                usable = false;
            }
        }
        for (a, (attribute, values)) in spec.body.attributes.0.iter().enumerate() {
            self.declare_attribute(spec, c, a, attribute, values);
        }
        usable
    }

    /// Checks a component's list of mode names: valid, non-empty, no repeats.
    fn names_are_fresh(&mut self, c: usize, names: &[&str]) -> bool {
        let mut ok = true;
        if names.is_empty() {
            self.error_in(
                c,
                &[Step::Field("modes")],
                "a component needs at least one mode".into(),
                "at least one `Mode(...)`",
            );
            return false;
        }
        for (i, name) in names.iter().enumerate() {
            let path = [Step::Field("modes"), Step::Index(i), Step::Field("name")];
            if !is_value_name(name) {
                self.error_in(
                    c,
                    &path,
                    format!("`{name}` is not a valid mode name"),
                    "an identifier (letters, digits, `_`, `-`)",
                );
                ok = false;
            } else if names[..i].contains(name) {
                self.error_in(
                    c,
                    &path,
                    format!("mode `{name}` is declared twice"),
                    "a mode name not used before",
                );
                ok = false;
            }
        }
        ok
    }

    fn declare_attribute(
        &mut self,
        spec: &Spec,
        c: usize,
        a: usize,
        attribute: &str,
        values: &[String],
    ) {
        let component = &spec.name;
        let attributes = &spec.body.attributes.0;
        let key_path = [Step::Field("attributes"), Step::Key(attribute)];
        if !is_value_name(attribute) {
            let message =
                format!("component `{component}`: `{attribute}` is not a valid attribute name");
            self.error_in(
                c,
                &key_path,
                message,
                "an identifier (letters, digits, `_`, `-`; no dots)",
            );
            return;
        }
        if attributes[..a].iter().any(|(other, _)| other == attribute) {
            // The second occurrence is the offending one; the outline finds the first, so point
            // at the attribute map as a whole.
            let message =
                format!("component `{component}`: attribute `{attribute}` is declared twice");
            self.error_in(
                c,
                &[Step::Field("attributes")],
                message,
                "each attribute once",
            );
            return;
        }
        let name = format!("{component}.{attribute}");
        if let Err(e) = self.table.add_variable(name, values.iter().cloned()) {
            let mut path = vec![Step::Field("attributes"), Step::Value(attribute)];
            let expected = match &e {
                DeclarationError::DuplicateValue { value, .. }
                | DeclarationError::BadName(value) => {
                    let later = values.iter().rposition(|v| v == value).unwrap_or(0);
                    path.push(Step::Index(later));
                    "distinct identifiers (letters, digits, `_`, `-`)"
                }
                DeclarationError::EmptyDomain(_) => "at least one value",
                DeclarationError::Duplicate(_) => "a name not used before",
            };
            self.error_in(c, &path, format!("component `{component}`: {e}"), expected);
        }
    }

    /// Parses and resolves a formula found at `path`, reading `self` as the component `this`
    /// names (a type's formula); `None` (with errors recorded) on failure. `c` labels the
    /// errors with the instance.
    fn formula(
        &mut self,
        path: &[Step],
        text: &str,
        what: &str,
        this: Option<(usize, &str)>,
    ) -> Option<Formula> {
        let offset = self.places.at(path).start;
        let resolved = logic::syntax::parse_at(text, offset)
            .map_err(|d| vec![d])
            .and_then(|mut expr| {
                if let Some((_, name)) = this {
                    rename_self(&mut expr, name);
                }
                logic::resolve(&expr, &self.table)
            });
        let label = |places: &Places, d: Diagnostic| match this {
            Some((c, _)) => places.label(c, d),
            None => d,
        };
        match resolved {
            Ok(formula) => {
                if formula.has_external_atoms() {
                    let span = offset..offset + text.len();
                    let diagnostic = Diagnostic::new(
                        format!("a {what} cannot mention a confidence `P(...)` or a clock"),
                        span,
                    )
                    .expected("a constraint over the plant's modes and attributes")
                    .note("timing belongs in a transition's `after:`");
                    self.errors.push(label(&self.places, diagnostic));
                    return None;
                }
                Some(formula)
            }
            Err(diagnostics) => {
                let labelled: Vec<Diagnostic> = diagnostics
                    .into_iter()
                    .map(|d| label(&self.places, d))
                    .collect();
                self.errors.extend(labelled);
                None
            }
        }
    }

    fn refuse_mode_variables(&mut self, path: &[Step], formula: &Formula) {
        for var in formula.variables() {
            // A mode variable is named by its component; attributes are `component.attribute`
            // (a name test, not a scan of the components per connection).
            let name = self.table.variable(var).name();
            if !name.contains('.') {
                let message = format!(
                    "a connection links attributes; `{name}` is a component's mode variable"
                );
                self.error(
                    path,
                    message,
                    "a constraint between attributes (`a.x = b.y`)",
                );
            }
        }
    }

    /// The interconnections, indexed ones expanded.
    fn connections(&mut self, file: &PlantFile) -> Vec<Formula> {
        let mut connections = Vec::new();
        for (i, text) in file.connections.iter().enumerate() {
            let path = [Step::Field("connections"), Step::Index(i)];
            let Some(texts) = self.indexed(&path, text) else {
                continue;
            };
            let indexed = texts.len() > 1 || texts[0] != *text;
            for expanded in texts {
                let formula = if indexed {
                    // Spans inside an expanded text are not the file's: report at the whole.
                    self.expanded_formula(&path, text, &expanded)
                } else {
                    self.formula(&path, text, "connection", None)
                };
                if let Some(formula) = formula {
                    self.refuse_mode_variables(&path, &formula);
                    connections.push(formula);
                }
            }
        }
        connections
    }

    /// A formula expanded from the indexed text at `path`, its errors reported at that text.
    fn expanded_formula(&mut self, path: &[Step], written: &str, text: &str) -> Option<Formula> {
        match logic::parse_formula(text, &self.table) {
            Ok(formula) if !formula.has_external_atoms() => Some(formula),
            Ok(_) => {
                let message = "a connection cannot mention a confidence `P(...)` or a clock";
                self.error(path, message.into(), "a constraint between attributes");
                None
            }
            Err(diagnostics) => {
                let span = self.places.at(path);
                for d in diagnostics {
                    let problem = text.get(d.span.clone()).unwrap_or(text);
                    self.errors.push(
                        Diagnostic::new(
                            format!("`{text}` (from `{written}`): {}", d.message),
                            span.clone(),
                        )
                        .expected(d.expected)
                        .note(format!("at `{problem}` in the expansion")),
                    );
                }
                None
            }
        }
    }

    /// The texts an indexed text at `path` expands to, or an error.
    fn indexed(&mut self, path: &[Step], text: &str) -> Option<Vec<String>> {
        match expand_indexed(text) {
            Ok(texts) => Some(texts),
            Err(e) => {
                self.error(path, e.message, e.expected);
                None
            }
        }
    }

    /// An attribute variable named at `path` (a control or an observable), or an error.
    fn attribute(&mut self, path: &[Step], name: &str, role: &str) -> Option<VarId> {
        let problem = match self.table.variable_id(name) {
            Some(var) if name.contains('.') => return Some(var),
            Some(_) => format!("`{name}` is a component's mode variable; {role} is an attribute"),
            None => format!("`{name}` is not an attribute, so it cannot be {role}"),
        };
        let mut diagnostic = Diagnostic::new(problem, self.places.at(path))
            .expected("`component.attribute`, an attribute declared by a component");
        // Listed only on an error: per name, it made a plant of 10,000 attributes quadratic.
        let attributes = self
            .table
            .variables()
            .filter(|(_, v)| v.name().contains('.'))
            .map(|(_, v)| v.name());
        if let Some(close) = did_you_mean(name, attributes) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        self.errors.push(diagnostic);
        None
    }

    fn controls(&mut self, file: &PlantFile) -> Vec<Control> {
        let mut controls: Vec<Control> = Vec::new();
        let mut listed = HashSet::new();
        for (written, idle) in &file.controls.0 {
            let key = [Step::Field("controls"), Step::Key(written)];
            let Some(names) = self.indexed(&key, written) else {
                continue;
            };
            for name in &names {
                let Some(var) = self.attribute(&key, name, "a control") else {
                    continue;
                };
                if !listed.insert(var) {
                    self.error(
                        &[Step::Field("controls")],
                        format!("control `{name}` is listed twice"),
                        "each control once",
                    );
                    continue;
                }
                let variable = self.table.variable(var);
                match variable.value(idle) {
                    Some(idle) => controls.push(Control { var, idle }),
                    None => {
                        let note =
                            format!("`{name}` takes one of: {}", variable.values().join(", "));
                        let span = self
                            .places
                            .at(&[Step::Field("controls"), Step::Value(written)]);
                        self.errors.push(
                            Diagnostic::new(format!("`{idle}` is not a value of `{name}`"), span)
                                .expected(format!("the value `{name}` holds when not commanded"))
                                .note(note),
                        );
                    }
                }
            }
        }
        controls
    }

    fn observables(&mut self, file: &PlantFile, controls: &[Control]) -> Vec<VarId> {
        let mut observables = Vec::new();
        let mut listed = HashSet::new();
        let controlled: HashSet<VarId> = controls.iter().map(|c| c.var).collect();
        for (i, written) in file.observables.iter().enumerate() {
            let path = [Step::Field("observables"), Step::Index(i)];
            let Some(names) = self.indexed(&path, written) else {
                continue;
            };
            for name in &names {
                let Some(var) = self.attribute(&path, name, "an observable") else {
                    continue;
                };
                if !listed.insert(var) {
                    self.error(
                        &path,
                        format!("observable `{name}` is listed twice"),
                        "each observable once",
                    );
                } else if controlled.contains(&var) {
                    self.error(
                        &path,
                        format!("`{name}` is both a control and an observable"),
                        "a sensed attribute that is not commanded",
                    );
                } else {
                    observables.push(var);
                }
            }
        }
        observables
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::reference;

    /// `docs/reference/plant.md` lists every field and variant this loader accepts, and no
    /// other (the convention is in `diagnostic::reference`).
    #[test]
    fn the_reference_documents_every_field() {
        let mut tracer = reference::tracer();
        reference::add::<KindFile>(&mut tracer);
        reference::add::<TimingFile>(&mut tracer);
        monitors::trace_reading(&mut tracer);
        reference::add::<PlantFile>(&mut tracer);
        reference::assert_documented(
            &reference::registry(tracer),
            &[
                ("Plant", "plant.md", "`Plant(...)`"),
                ("Component", "plant.md", "`Component(...)`"),
                ("Mode", "plant.md", "`Mode(...)`"),
                ("KindFile", "plant.md", "Mode kinds"),
                ("Transition", "plant.md", "Transitions:"),
                ("TimingFile", "plant.md", "Timing laws"),
                ("Type", "plant.md", "`Type(...)`"),
                ("Monitor", "plant.md", "`Monitor(...)`"),
                ("Threshold", "plant.md", "Thresholds:"),
                ("ReadingFile", "plant.md", "Laws of readings"),
            ],
        );
    }
}
