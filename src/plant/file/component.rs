//! Building one component of the expanded plant: its modes, initial distribution and
//! transitions with their laws, every number read through the instance's parameters when the
//! component is an instance of a type.

use super::{KindFile, Loader, Spec, TOLERANCE, TimingFile, TransitionFile};
use crate::diagnostic::locate::NumberOrName as Number;
use crate::diagnostic::locate::Step;
use crate::logic::{Formula, ValueId, VarId};
use crate::plant::{
    Component, Mode, ModeKind, Timing, Transition, TransitionLaw, TransitionSource,
};

impl Loader {
    pub(super) fn component(&mut self, c: usize, spec: &Spec) -> Component {
        let mode_var = self.table.variable_id(&spec.name).unwrap_or(VarId(0));
        let attributes = spec
            .body
            .attributes
            .0
            .iter()
            .filter_map(|(a, _)| self.table.variable_id(&format!("{}.{a}", spec.name)))
            .collect();
        let this = spec.parameters.as_ref().map(|_| (c, spec.name.as_str()));
        let modes: Vec<Mode> = spec
            .body
            .modes
            .iter()
            .enumerate()
            .map(|(m, mode)| {
                let path = self.places.mode(c, m, "constraint");
                let what = format!("constraint of `{}`", spec.name);
                let constraint = self
                    .formula(&path, &mode.constraint, &what, this)
                    .unwrap_or(Formula::True);
                let reward_path = [Step::Field("modes"), Step::Index(m), Step::Field("reward")];
                let reward = self.number(c, spec, &reward_path, &mode.reward);
                let reward = match reward {
                    Some(r) if !r.is_finite() => {
                        let message = format!(
                            "component `{}`, mode `{}`: reward {r} is not finite",
                            spec.name, mode.name
                        );
                        self.error_in(c, &reward_path, message, "a finite reward");
                        0.0
                    }
                    r => r.unwrap_or(0.0),
                };
                Mode {
                    name: mode.name.clone(),
                    kind: match mode.kind {
                        KindFile::Nominal => ModeKind::Nominal,
                        KindFile::Fault => ModeKind::Fault,
                    },
                    constraint,
                    reward,
                }
            })
            .collect();
        let initial = self.initial(c, spec);
        let transitions: Vec<Transition> = spec
            .body
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

    /// A number of component `c`'s body at `rest`: as written, or the value of the parameter
    /// it names (an instance's); `None` with an error for a name that is no parameter.
    fn number(&mut self, c: usize, spec: &Spec, rest: &[Step], number: &Number) -> Option<f64> {
        let name = match number {
            Number::Number(value) => return Some(*value),
            Number::Name(name) => name,
        };
        let Some(parameters) = &spec.parameters else {
            let message = format!(
                "component `{}`: `{name}` is not a number (parameter names are for types)",
                spec.name
            );
            self.error_in(c, rest, message, "a number");
            return None;
        };
        if let Some(&(_, value)) = parameters.iter().find(|(n, _)| n == name) {
            return Some(value);
        }
        let names: Vec<&str> = parameters.iter().map(|(n, _)| *n).collect();
        let mut diagnostic = self
            .places
            .diagnostic(c, rest, format!("no parameter `{name}`"))
            .expected("a number, or the name of a parameter of the type")
            .note(if names.is_empty() {
                "the type declares no parameter (`parameters: { \"name\": default }`)".to_string()
            } else {
                format!("the type's parameters: {}", names.join(", "))
            });
        if let Some(close) = crate::diagnostic::did_you_mean(name, names.iter().copied()) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        self.errors.push(diagnostic);
        None
    }

    /// A mode of `spec` named `name`, or an error at `rest` naming the component's modes.
    fn mode_named(&mut self, c: usize, spec: &Spec, rest: &[Step], name: &str) -> Option<ValueId> {
        if let Some(m) = spec.body.modes.iter().position(|m| m.name == name) {
            return Some(ValueId(m as u32));
        }
        let modes: Vec<&str> = spec.body.modes.iter().map(|m| m.name.as_str()).collect();
        let mut diagnostic = self
            .places
            .diagnostic(
                c,
                rest,
                format!("component `{}` has no mode `{name}`", spec.name),
            )
            .expected(format!("a mode of `{}`", spec.name))
            .note(format!("`{}` has modes: {}", spec.name, modes.join(", ")));
        if let Some(close) = crate::diagnostic::did_you_mean(name, modes.iter().copied()) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        self.errors.push(diagnostic);
        None
    }

    fn initial(&mut self, c: usize, spec: &Spec) -> Vec<f64> {
        let mut initial = vec![0.0; spec.body.modes.len()];
        let mut seen: Vec<&str> = Vec::new();
        let mut total = 0.0;
        for (name, p) in &spec.body.initial.0 {
            let key = [Step::Field("initial"), Step::Key(name)];
            let value = [Step::Field("initial"), Step::Value(name)];
            let Some(mode) = self.mode_named(c, spec, &key, name) else {
                continue;
            };
            let Some(p) = self.number(c, spec, &value, p) else {
                continue;
            };
            total += p;
            if seen.contains(&name.as_str()) {
                let message = format!(
                    "component `{}`: mode `{name}` has two initial probabilities",
                    spec.name
                );
                self.error_in(c, &[Step::Field("initial")], message, "each mode once");
            }
            seen.push(name);
            if !(0.0..=1.0).contains(&p) {
                let message = format!(
                    "component `{}`, mode `{name}`: initial probability {p} is outside [0, 1]",
                    spec.name
                );
                self.error_in(c, &value, message, "a probability between 0 and 1");
            }
            initial[mode.index()] = p;
        }
        if (total - 1.0).abs() > TOLERANCE && total.is_finite() {
            let message = format!(
                "component `{}`: initial probabilities sum to {total}, not 1",
                spec.name
            );
            self.error_in(
                c,
                &[Step::Field("initial")],
                message,
                "probabilities that sum to 1",
            );
        }
        initial
    }

    fn transition(
        &mut self,
        c: usize,
        t: usize,
        spec: &Spec,
        file: &TransitionFile,
    ) -> Option<Transition> {
        let at = |field| {
            [
                Step::Field("transitions"),
                Step::Index(t),
                Step::Field(field),
            ]
        };
        let source = if file.from == "*" {
            Some(TransitionSource::AnyNominal)
        } else {
            self.mode_named(c, spec, &at("from"), &file.from)
                .map(TransitionSource::Mode)
        };
        let target = self.mode_named(c, spec, &at("to"), &file.to);
        let guard_path = self.places.transition(c, t, &[Step::Field("guard")]);
        let this = spec.parameters.as_ref().map(|_| (c, spec.name.as_str()));
        let what = format!("guard of `{}`", spec.name);
        let guard = self.formula(&guard_path, &file.guard, &what, this);
        let law = self.law(c, t, spec, file);
        let (source, target, guard, law) = (source?, target?, guard?, law?);
        let describe = format!(
            "component `{}`, transition `{}` -> `{}`",
            spec.name, file.from, file.to
        );
        match source {
            TransitionSource::Mode(m) if m == target => {
                self.error_in(
                    c,
                    &at("to"),
                    format!("{describe}: a transition to its own source"),
                    "another mode: a mode stays with the probability its transitions leave",
                );
                return None;
            }
            TransitionSource::AnyNominal
                if !spec.body.modes.iter().enumerate().any(|(m, mode)| {
                    matches!(mode.kind, KindFile::Nominal) && m != target.index()
                }) =>
            {
                self.error_in(
                    c,
                    &at("from"),
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
        spec: &Spec,
        file: &TransitionFile,
    ) -> Option<TransitionLaw> {
        let describe = format!(
            "component `{}`, transition `{}` -> `{}`",
            spec.name, file.from, file.to
        );
        let at = |field| {
            [
                Step::Field("transitions"),
                Step::Index(t),
                Step::Field(field),
            ]
        };
        let probability = match &file.probability {
            Some(p) => Some(self.number(c, spec, &at("probability"), p)?),
            None => None,
        };
        let rate = match &file.rate {
            Some(r) => Some(self.number(c, spec, &at("rate"), r)?),
            None => None,
        };
        let probability_ok = |loader: &mut Self, p: f64| {
            let ok = (0.0..=1.0).contains(&p);
            if !ok {
                let message = format!("{describe}: probability {p} is outside [0, 1]");
                loader.error_in(
                    c,
                    &at("probability"),
                    message,
                    "a probability between 0 and 1",
                );
            }
            ok
        };
        match (probability, rate, &file.after) {
            (Some(_), Some(_), _) => {
                let message = format!("{describe}: both a probability and a rate");
                self.error_in(
                    c,
                    &at("rate"),
                    message,
                    "either `probability` (per cycle) or `rate` (per second)",
                );
                None
            }
            (_, Some(_), Some(_)) => {
                let message = format!("{describe}: a timed transition has no rate");
                self.error_in(
                    c,
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
                    self.error_in(c, &at("rate"), message, "a rate per second, 0 or more");
                    None
                }
            }
            (p, None, Some(after)) => {
                let probability = p.unwrap_or(1.0);
                let p_ok = probability_ok(self, probability);
                let timing = self.timing(c, t, spec, &describe, after)?;
                p_ok.then_some(TransitionLaw::Timed {
                    probability,
                    timing,
                })
            }
            (None, None, None) => {
                let message = format!("{describe}: no probability");
                self.error_in(
                    c,
                    &[Step::Field("transitions"), Step::Index(t)],
                    message,
                    "`probability: p`, `rate: r` or `after: Uniform(l, u)`",
                );
                None
            }
        }
    }

    fn timing(
        &mut self,
        c: usize,
        t: usize,
        spec: &Spec,
        describe: &str,
        after: &TimingFile,
    ) -> Option<Timing> {
        let arg = |i| {
            [
                Step::Field("transitions"),
                Step::Index(t),
                Step::Field("after"),
                Step::Index(i),
            ]
        };
        let numbers: Vec<&Number> = match after {
            TimingFile::Uniform(a, b) | TimingFile::Gaussian(a, b) => vec![a, b],
            TimingFile::Exponential(a) | TimingFile::Fixed(a) => vec![a],
        };
        let mut values = Vec::with_capacity(2);
        for (i, number) in numbers.into_iter().enumerate() {
            values.push(self.number(c, spec, &arg(i), number));
        }
        let values: Vec<f64> = values.into_iter().collect::<Option<_>>()?;
        let finite = |xs: &[f64]| xs.iter().all(|x| x.is_finite());
        let timing = match (after, values.as_slice()) {
            (TimingFile::Uniform(..), &[lower, upper]) => Timing::Uniform { lower, upper },
            (TimingFile::Gaussian(..), &[mean, sd]) => Timing::Gaussian { mean, sd },
            (TimingFile::Exponential(_), &[rate]) => Timing::Exponential { rate },
            (_, &[delay]) => Timing::Fixed { delay },
            _ => return None,
        };
        let problem: Option<(usize, String, &str)> = match timing {
            Timing::Uniform { lower: l, upper: u } if !finite(&[l, u]) => Some((
                0,
                format!("window [{l}, {u}] is not finite"),
                "finite bounds, seconds",
            )),
            Timing::Uniform { lower: l, .. } if l < 0.0 => Some((
                0,
                format!("window starts at {l} s, before the mode is entered"),
                "a lower bound of 0 or more",
            )),
            Timing::Uniform { lower: l, upper: u } if l > u => Some((
                1,
                format!("window [{l}, {u}] is inverted"),
                "an upper bound above the lower bound",
            )),
            Timing::Uniform { lower: l, upper: u } if l == u => Some((
                1,
                format!("window [{l}, {u}] is empty"),
                "an upper bound above the lower bound (or `Fixed(d)`)",
            )),
            Timing::Gaussian { mean: m, sd } if !finite(&[m, sd]) || sd <= 0.0 => Some((
                1,
                format!("Gaussian({m}, {sd}) has no spread"),
                "a finite mean and a standard deviation above 0",
            )),
            Timing::Exponential { rate: r } if !r.is_finite() || r <= 0.0 => Some((
                0,
                format!("Exponential({r}) never fires"),
                "a rate above 0, per second",
            )),
            Timing::Fixed { delay: d } if !d.is_finite() || d < 0.0 => Some((
                0,
                format!("Fixed({d}) is not a delay"),
                "a delay of 0 or more, seconds",
            )),
            _ => None,
        };
        if let Some((i, message, expected)) = problem {
            self.error_in(c, &arg(i), format!("{describe}: {message}"), expected);
            return None;
        }
        Some(timing)
    }
}
