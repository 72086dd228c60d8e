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
//! Semantics (thesis §6.1, DESIGN.md §6.2): a transition is enabled when the constraint store
//! (the current modes' constraints, the interconnections and the commands) entails its guard;
//! a mode stays with the probability its enabled transitions leave (no explicit self-loops); a
//! component takes at most one transition per cycle and its clock restarts when it changes mode.
//! See [`TransitionLaw`] for how per-cycle, rate and timed laws combine.
//!
//! Every error names the file, line and column, shows the text, says what was expected and which
//! component and mode it concerns. Formulas are the constraint language of DESIGN.md §4.

use std::collections::HashSet;

use serde::Deserialize;

use super::{
    Component, ComponentId, Control, Mode, ModeKind, Plant, Timing, Transition, TransitionLaw,
    TransitionSource, validate,
};
use crate::diagnostic::locate::{Entries, Locator, Step};
use crate::diagnostic::{Diagnostic, Source, SourceErrors, did_you_mean, ron_error};
use crate::logic::{self, DeclarationError, Formula, ValueId, VarId, VarTable, is_value_name};

/// Initial probabilities and outgoing sums are compared with this tolerance.
pub(crate) const TOLERANCE: f64 = 1e-9;

#[derive(Deserialize)]
#[serde(rename = "Plant", deny_unknown_fields)]
struct PlantFile {
    name: String,
    components: Vec<ComponentFile>,
    #[serde(default)]
    controls: Entries<String>,
    #[serde(default)]
    observables: Vec<String>,
    #[serde(default)]
    connections: Vec<String>,
}

#[derive(Deserialize)]
#[serde(rename = "Component", deny_unknown_fields)]
struct ComponentFile {
    name: String,
    #[serde(default)]
    attributes: Entries<Vec<String>>,
    modes: Vec<ModeFile>,
    initial: Entries<f64>,
    #[serde(default)]
    transitions: Vec<TransitionFile>,
}

fn always() -> String {
    "true".to_string()
}

#[derive(Deserialize)]
#[serde(rename = "Mode", deny_unknown_fields)]
struct ModeFile {
    name: String,
    #[serde(default)]
    kind: KindFile,
    #[serde(default = "always")]
    constraint: String,
    #[serde(default)]
    reward: f64,
}

#[derive(Deserialize, Default, Clone, Copy)]
enum KindFile {
    #[default]
    Nominal,
    Fault,
}

#[derive(Deserialize)]
#[serde(rename = "Transition", deny_unknown_fields)]
struct TransitionFile {
    from: String,
    to: String,
    #[serde(default = "always")]
    guard: String,
    probability: Option<f64>,
    rate: Option<f64>,
    after: Option<TimingFile>,
}

#[derive(Deserialize, Clone, Copy)]
enum TimingFile {
    Uniform(f64, f64),
    Gaussian(f64, f64),
    Exponential(f64),
    Fixed(f64),
}

/// Path to component `c`, then `rest`.
pub(crate) fn component_path<'a>(c: usize, rest: &[Step<'a>]) -> Vec<Step<'a>> {
    let mut path = vec![Step::Field("components"), Step::Index(c)];
    path.extend_from_slice(rest);
    path
}

/// Path to mode `m` of component `c`, then `field`.
pub(crate) fn mode_path(c: usize, m: usize, field: &str) -> Vec<Step<'_>> {
    component_path(
        c,
        &[Step::Field("modes"), Step::Index(m), Step::Field(field)],
    )
}

/// Path to transition `t` of component `c`, then `rest`.
pub(crate) fn transition_path<'a>(c: usize, t: usize, rest: &[Step<'a>]) -> Vec<Step<'a>> {
    let mut path = component_path(c, &[Step::Field("transitions"), Step::Index(t)]);
    path.extend_from_slice(rest);
    path
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
        locate: Locator::new(&source.text),
        errors: Vec::new(),
        table: VarTable::new(),
    };
    let plant = loader.plant(&file);
    if !loader.errors.is_empty() {
        return Err(fail(loader.errors));
    }
    let errors = validate::check(&plant, &loader.locate);
    if errors.is_empty() {
        Ok(plant)
    } else {
        Err(fail(errors))
    }
}

struct Loader {
    locate: Locator,
    errors: Vec<Diagnostic>,
    table: VarTable,
}

impl Loader {
    fn error(&mut self, path: &[Step], message: String, expected: impl Into<String>) {
        let span = self.locate.at(path);
        self.errors
            .push(Diagnostic::new(message, span).expected(expected));
    }

    fn plant(&mut self, file: &PlantFile) -> Plant {
        // Variables first, so that formulas anywhere may mention any component.
        let declared: Vec<bool> = (0..file.components.len())
            .map(|c| self.declare_component(file, c))
            .collect();
        let mut components = Vec::new();
        for (c, spec) in file.components.iter().enumerate() {
            if declared[c] {
                components.push(self.component(c, spec));
            }
        }
        let controls = self.controls(file);
        let observables = self.observables(file, &controls);
        let connections = file
            .connections
            .iter()
            .enumerate()
            .filter_map(|(i, text)| {
                let path = [Step::Field("connections"), Step::Index(i)];
                let formula = self.formula(&path, text, "connection")?;
                self.refuse_mode_variables(&path, &formula);
                Some(formula)
            })
            .collect();
        let mut component_of = vec![None; self.table.len()];
        for (i, component) in components.iter().enumerate() {
            component_of[component.mode_var.index()] = Some(ComponentId(i as u32));
        }
        Plant {
            name: file.name.clone(),
            table: std::mem::take(&mut self.table),
            components,
            controls,
            observables,
            connections,
            component_of,
        }
    }

    /// Declares a component's mode variable and attributes; false when its name is unusable
    /// (then it is left out, so that one bad name does not cascade into many errors).
    fn declare_component(&mut self, file: &PlantFile, c: usize) -> bool {
        let spec = &file.components[c];
        let name_path = component_path(c, &[Step::Field("name")]);
        if !is_value_name(&spec.name) {
            self.error(
                &name_path,
                format!("`{}` is not a valid component name", spec.name),
                "an identifier (letters, digits, `_`, `-`; no dots)",
            );
            return false;
        }
        if file.components[..c].iter().any(|o| o.name == spec.name) {
            self.error(
                &name_path,
                format!("component `{}` is declared twice", spec.name),
                "a component name not used before",
            );
            return false;
        }
        let modes: Vec<&str> = spec.modes.iter().map(|m| m.name.as_str()).collect();
        let mut usable = self.names_are_fresh(c, &modes, |m| mode_path(c, m, "name"), "mode");
        if usable {
            if let Err(e) = self.table.add_variable(spec.name.clone(), modes) {
                let message = format!("component `{}`: {e}", spec.name);
                self.error(&name_path, message, "a name not used before");
                usable = false;
            }
        }
        for (a, (attribute, values)) in spec.attributes.0.iter().enumerate() {
            self.declare_attribute(file, c, a, attribute, values);
        }
        usable
    }

    /// Checks a component's list of mode names: valid, non-empty, no repeats.
    fn names_are_fresh<'p>(
        &mut self,
        c: usize,
        names: &[&str],
        path: impl Fn(usize) -> Vec<Step<'p>>,
        what: &str,
    ) -> bool {
        let mut ok = true;
        if names.is_empty() {
            self.error(
                &component_path(c, &[Step::Field("modes")]),
                "a component needs at least one mode".into(),
                "at least one `Mode(...)`",
            );
            return false;
        }
        for (i, name) in names.iter().enumerate() {
            if !is_value_name(name) {
                self.error(
                    &path(i),
                    format!("`{name}` is not a valid {what} name"),
                    "an identifier (letters, digits, `_`, `-`)",
                );
                ok = false;
            } else if names[..i].contains(name) {
                self.error(
                    &path(i),
                    format!("{what} `{name}` is declared twice"),
                    format!("a {what} name not used before"),
                );
                ok = false;
            }
        }
        ok
    }

    fn declare_attribute(
        &mut self,
        file: &PlantFile,
        c: usize,
        a: usize,
        attribute: &str,
        values: &[String],
    ) {
        let component = &file.components[c].name;
        let attributes = &file.components[c].attributes.0;
        let key_path = component_path(c, &[Step::Field("attributes"), Step::Key(attribute)]);
        if !is_value_name(attribute) {
            let message =
                format!("component `{component}`: `{attribute}` is not a valid attribute name");
            self.error(
                &key_path,
                message,
                "an identifier (letters, digits, `_`, `-`; no dots)",
            );
            return;
        }
        if attributes[..a].iter().any(|(other, _)| other == attribute) {
            // The second occurrence is the offending one; the outline finds the first, so point
            // at the attribute map as a whole.
            let path = component_path(c, &[Step::Field("attributes")]);
            let message =
                format!("component `{component}`: attribute `{attribute}` is declared twice");
            self.error(&path, message, "each attribute once");
            return;
        }
        let name = format!("{component}.{attribute}");
        if let Err(e) = self.table.add_variable(name, values.iter().cloned()) {
            let mut path = component_path(c, &[Step::Field("attributes"), Step::Value(attribute)]);
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
            self.error(&path, format!("component `{component}`: {e}"), expected);
        }
    }

    /// Parses and resolves a formula found at `path`; `None` (with errors recorded) on failure.
    fn formula(&mut self, path: &[Step], text: &str, what: &str) -> Option<Formula> {
        let offset = self.locate.at(path).start;
        let resolved = logic::syntax::parse_at(text, offset)
            .map_err(|d| vec![d])
            .and_then(|expr| logic::resolve(&expr, &self.table));
        match resolved {
            Ok(formula) => {
                if formula.has_external_atoms() {
                    let span = offset..offset + text.len();
                    self.errors.push(
                        Diagnostic::new(
                            format!("a {what} cannot mention a confidence `P(...)` or a clock"),
                            span,
                        )
                        .expected("a constraint over the plant's modes and attributes")
                        .note("timing belongs in a transition's `after:`"),
                    );
                    return None;
                }
                Some(formula)
            }
            Err(diagnostics) => {
                self.errors.extend(diagnostics);
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

    fn component(&mut self, c: usize, spec: &ComponentFile) -> Component {
        let mode_var = self.table.variable_id(&spec.name).unwrap_or(VarId(0));
        let attributes = spec
            .attributes
            .0
            .iter()
            .filter_map(|(a, _)| self.table.variable_id(&format!("{}.{a}", spec.name)))
            .collect();
        let modes: Vec<Mode> = spec
            .modes
            .iter()
            .enumerate()
            .map(|(m, mode)| {
                let path = mode_path(c, m, "constraint");
                let constraint = self
                    .formula(
                        &path,
                        &mode.constraint,
                        &format!("constraint of `{}`", spec.name),
                    )
                    .unwrap_or(Formula::True);
                Mode {
                    name: mode.name.clone(),
                    kind: match mode.kind {
                        KindFile::Nominal => ModeKind::Nominal,
                        KindFile::Fault => ModeKind::Fault,
                    },
                    constraint,
                    reward: mode.reward,
                }
            })
            .collect();
        let initial = self.initial(c, spec);
        let transitions: Vec<Transition> = spec
            .transitions
            .iter()
            .enumerate()
            .filter_map(|(t, transition)| self.transition(c, t, spec, transition))
            .collect();
        let outgoing: Vec<Vec<usize>> = (0..modes.len())
            .map(|m| {
                let m = ValueId(m as u32);
                transitions
                    .iter()
                    .enumerate()
                    .filter(|(_, t)| match t.source {
                        TransitionSource::Mode(source) => source == m,
                        TransitionSource::AnyNominal => {
                            t.target != m && modes[m.index()].kind == ModeKind::Nominal
                        }
                    })
                    .map(|(i, _)| i)
                    .collect()
            })
            .collect();
        let timed = outgoing
            .iter()
            .map(|leaving| {
                leaving
                    .iter()
                    .any(|&t| transitions[t].law.timing().is_some_and(Timing::needs_clock))
            })
            .collect();
        Component {
            name: spec.name.clone(),
            mode_var,
            attributes,
            modes,
            initial,
            transitions,
            outgoing,
            timed,
        }
    }

    /// A mode of `spec` named `name`, or an error at `path` naming the component's modes.
    fn mode_named(&mut self, spec: &ComponentFile, path: &[Step], name: &str) -> Option<ValueId> {
        if let Some(m) = spec.modes.iter().position(|m| m.name == name) {
            return Some(ValueId(m as u32));
        }
        let modes: Vec<&str> = spec.modes.iter().map(|m| m.name.as_str()).collect();
        let mut diagnostic = Diagnostic::new(
            format!("component `{}` has no mode `{name}`", spec.name),
            self.locate.at(path),
        )
        .expected(format!("a mode of `{}`", spec.name))
        .note(format!("`{}` has modes: {}", spec.name, modes.join(", ")));
        if let Some(close) = did_you_mean(name, modes.iter().copied()) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        self.errors.push(diagnostic);
        None
    }

    fn initial(&mut self, c: usize, spec: &ComponentFile) -> Vec<f64> {
        let mut initial = vec![0.0; spec.modes.len()];
        let mut seen: Vec<&str> = Vec::new();
        for (name, p) in &spec.initial.0 {
            let key = component_path(c, &[Step::Field("initial"), Step::Key(name)]);
            let Some(mode) = self.mode_named(spec, &key, name) else {
                continue;
            };
            if seen.contains(&name.as_str()) {
                let path = component_path(c, &[Step::Field("initial")]);
                let message = format!(
                    "component `{}`: mode `{name}` has two initial probabilities",
                    spec.name
                );
                self.error(&path, message, "each mode once");
            }
            seen.push(name);
            if !(0.0..=1.0).contains(p) {
                let path = component_path(c, &[Step::Field("initial"), Step::Value(name)]);
                let message = format!(
                    "component `{}`, mode `{name}`: initial probability {p} is outside [0, 1]",
                    spec.name
                );
                self.error(&path, message, "a probability between 0 and 1");
            }
            initial[mode.index()] = *p;
        }
        let total: f64 = spec.initial.0.iter().map(|(_, p)| p).sum();
        if (total - 1.0).abs() > TOLERANCE && total.is_finite() {
            let path = component_path(c, &[Step::Field("initial")]);
            let message = format!(
                "component `{}`: initial probabilities sum to {total}, not 1",
                spec.name
            );
            self.error(&path, message, "probabilities that sum to 1");
        }
        initial
    }

    fn transition(
        &mut self,
        c: usize,
        t: usize,
        spec: &ComponentFile,
        file: &TransitionFile,
    ) -> Option<Transition> {
        let from_path = transition_path(c, t, &[Step::Field("from")]);
        let to_path = transition_path(c, t, &[Step::Field("to")]);
        let source = if file.from == "*" {
            Some(TransitionSource::AnyNominal)
        } else {
            self.mode_named(spec, &from_path, &file.from)
                .map(TransitionSource::Mode)
        };
        let target = self.mode_named(spec, &to_path, &file.to);
        let guard_path = transition_path(c, t, &[Step::Field("guard")]);
        let guard = self.formula(
            &guard_path,
            &file.guard,
            &format!("guard of `{}`", spec.name),
        );
        let law = self.law(c, t, spec, file);
        let (source, target, guard, law) = (source?, target?, guard?, law?);
        let describe = format!(
            "component `{}`, transition `{}` -> `{}`",
            spec.name, file.from, file.to
        );
        match source {
            TransitionSource::Mode(m) if m == target => {
                self.error(
                    &to_path,
                    format!("{describe}: a transition to its own source"),
                    "another mode: a mode stays with the probability its transitions leave",
                );
                return None;
            }
            TransitionSource::AnyNominal
                if !spec.modes.iter().enumerate().any(|(m, mode)| {
                    matches!(mode.kind, KindFile::Nominal) && m != target.index()
                }) =>
            {
                self.error(
                    &from_path,
                    format!("{describe}: `*` stands for no mode here"),
                    "a nominal mode other than the target",
                );
                return None;
            }
            _ => {}
        }
        Some(Transition {
            source,
            target,
            guard,
            law,
        })
    }

    fn law(
        &mut self,
        c: usize,
        t: usize,
        spec: &ComponentFile,
        file: &TransitionFile,
    ) -> Option<TransitionLaw> {
        let describe = format!(
            "component `{}`, transition `{}` -> `{}`",
            spec.name, file.from, file.to
        );
        let at = |field| transition_path(c, t, &[Step::Field(field)]);
        let probability_ok = |loader: &mut Self, p: f64| {
            let ok = (0.0..=1.0).contains(&p);
            if !ok {
                let message = format!("{describe}: probability {p} is outside [0, 1]");
                loader.error(&at("probability"), message, "a probability between 0 and 1");
            }
            ok
        };
        match (file.probability, file.rate, file.after) {
            (Some(_), Some(_), _) => {
                let message = format!("{describe}: both a probability and a rate");
                self.error(
                    &at("rate"),
                    message,
                    "either `probability` (per cycle) or `rate` (per second)",
                );
                None
            }
            (_, Some(_), Some(_)) => {
                let message = format!("{describe}: a timed transition has no rate");
                self.error(
                    &at("rate"),
                    message,
                    "a nominal factor `probability` (default 1) with `after`",
                );
                None
            }
            (Some(p), None, None) => {
                probability_ok(self, p).then_some(TransitionLaw::PerCycle { probability: p })
            }
            (None, Some(r), None) => {
                if r.is_finite() && r >= 0.0 {
                    Some(TransitionLaw::Rate { per_second: r })
                } else {
                    let message = format!("{describe}: rate {r} is not a finite rate");
                    self.error(&at("rate"), message, "a rate per second, 0 or more");
                    None
                }
            }
            (p, None, Some(after)) => {
                let probability = p.unwrap_or(1.0);
                let p_ok = probability_ok(self, probability);
                let timing = self.timing(c, t, &describe, after)?;
                p_ok.then_some(TransitionLaw::Timed {
                    probability,
                    timing,
                })
            }
            (None, None, None) => {
                let path = transition_path(c, t, &[]);
                let message = format!("{describe}: no probability");
                self.error(
                    &path,
                    message,
                    "`probability: p`, `rate: r` or `after: Uniform(l, u)`",
                );
                None
            }
        }
    }

    fn timing(&mut self, c: usize, t: usize, describe: &str, after: TimingFile) -> Option<Timing> {
        let arg = |i| transition_path(c, t, &[Step::Field("after"), Step::Index(i)]);
        let finite = |xs: &[f64]| xs.iter().all(|x| x.is_finite());
        let problem: Option<(usize, String, &str)> = match after {
            TimingFile::Uniform(l, u) if !finite(&[l, u]) => Some((
                0,
                format!("window [{l}, {u}] is not finite"),
                "finite bounds, seconds",
            )),
            TimingFile::Uniform(l, _) if l < 0.0 => Some((
                0,
                format!("window starts at {l} s, before the mode is entered"),
                "a lower bound of 0 or more",
            )),
            TimingFile::Uniform(l, u) if l > u => Some((
                1,
                format!("window [{l}, {u}] is inverted"),
                "an upper bound above the lower bound",
            )),
            TimingFile::Uniform(l, u) if l == u => Some((
                1,
                format!("window [{l}, {u}] is empty"),
                "an upper bound above the lower bound (or `Fixed(d)`)",
            )),
            TimingFile::Gaussian(m, sd) if !finite(&[m, sd]) || sd <= 0.0 => Some((
                1,
                format!("Gaussian({m}, {sd}) has no spread"),
                "a finite mean and a standard deviation above 0",
            )),
            TimingFile::Exponential(r) if !r.is_finite() || r <= 0.0 => Some((
                0,
                format!("Exponential({r}) never fires"),
                "a rate above 0, per second",
            )),
            TimingFile::Fixed(d) if !d.is_finite() || d < 0.0 => Some((
                0,
                format!("Fixed({d}) is not a delay"),
                "a delay of 0 or more, seconds",
            )),
            _ => None,
        };
        if let Some((i, message, expected)) = problem {
            self.error(&arg(i), format!("{describe}: {message}"), expected);
            return None;
        }
        Some(match after {
            TimingFile::Uniform(lower, upper) => Timing::Uniform { lower, upper },
            TimingFile::Gaussian(mean, sd) => Timing::Gaussian { mean, sd },
            TimingFile::Exponential(rate) => Timing::Exponential { rate },
            TimingFile::Fixed(delay) => Timing::Fixed { delay },
        })
    }

    /// An attribute variable named at `path` (a control or an observable), or an error.
    fn attribute(&mut self, path: &[Step], name: &str, role: &str) -> Option<VarId> {
        let problem = match self.table.variable_id(name) {
            Some(var) if name.contains('.') => return Some(var),
            Some(_) => format!("`{name}` is a component's mode variable; {role} is an attribute"),
            None => format!("`{name}` is not an attribute, so it cannot be {role}"),
        };
        let mut diagnostic = Diagnostic::new(problem, self.locate.at(path))
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
        for (name, idle) in &file.controls.0 {
            let key = [Step::Field("controls"), Step::Key(name)];
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
                    let note = format!("`{name}` takes one of: {}", variable.values().join(", "));
                    let span = self
                        .locate
                        .at(&[Step::Field("controls"), Step::Value(name)]);
                    self.errors.push(
                        Diagnostic::new(format!("`{idle}` is not a value of `{name}`"), span)
                            .expected(format!("the value `{name}` holds when not commanded"))
                            .note(note),
                    );
                }
            }
        }
        controls
    }

    fn observables(&mut self, file: &PlantFile, controls: &[Control]) -> Vec<VarId> {
        let mut observables = Vec::new();
        let mut listed = HashSet::new();
        let controlled: HashSet<VarId> = controls.iter().map(|c| c.var).collect();
        for (i, name) in file.observables.iter().enumerate() {
            let path = [Step::Field("observables"), Step::Index(i)];
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
            ],
        );
    }
}
