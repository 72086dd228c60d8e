//! Loading the scripted plant: hidden variables, initial values and rules, from the included
//! script files and the scenario itself, each problem located in its file.

use super::format::{DelayFile, RuleFile, ScriptParts, TriggerFile};
use super::load::{FileCtx, VarClasses, Vars, empty_script, formula};
use super::script::{Delay, Effect, Held, Rule, Script, TIME_EPSILON, Trigger};
use crate::diagnostic::locate::{Entries, NumberOrName, Step};
use crate::diagnostic::{Diagnostic, did_you_mean};
use crate::executive::{NamedValue, Submission};
use crate::goalnet::Mission;
use crate::goalnet::mission::{NetworkFile, resolve_submission};
use crate::logic::{ValueId, VarId, VarTable};
use crate::plant::Plant;

/// The script of a scenario: `parts` are the included files' then the scenario's own; `mission`
/// is the scenario's mission, if it runs one (rules may submit goals to its network, of its
/// goal types).
pub(super) fn script(
    plant: &Plant,
    mission: Option<&Mission>,
    parts: &mut [(&mut FileCtx, ScriptParts<'_>)],
    end: f64,
) -> Script {
    let mut script = empty_script(plant);
    for (ctx, part) in parts.iter_mut() {
        declare_hidden(ctx, part, &mut script);
    }
    let classes = VarClasses::new(plant, script.hidden.clone());
    script.initial = (script.hidden.iter())
        .map(|&v| (v, Held::Value(ValueId(0))))
        .collect();
    for (ctx, part) in parts.iter_mut() {
        initial_values(ctx, part, &classes, &mut script);
    }
    let mut loader = RuleLoader {
        mission,
        world: &script.world,
        classes: &classes,
        end,
        own: false,
        garbled: parts
            .iter()
            .flat_map(|(_, part)| part.rules.iter())
            .flat_map(|rule| rule.garble.0.iter().map(|(name, _)| name.clone()))
            .collect(),
        names: Vec::new(),
    };
    let mut rules = Vec::new();
    let own = parts.len().saturating_sub(1);
    for (k, (ctx, part)) in parts.iter_mut().enumerate() {
        loader.own = k == own;
        for (i, rule) in part.rules.iter().enumerate() {
            if let Some(rule) = loader.rule(ctx, i, rule) {
                rules.push(rule);
            }
        }
    }
    script.rules = rules;
    script
}

fn declare_hidden(ctx: &mut FileCtx, part: &ScriptParts<'_>, script: &mut Script) {
    for (name, values) in &part.hidden.0 {
        match script
            .world
            .add_variable(name.as_str(), values.iter().cloned())
        {
            Ok(var) => script.hidden.push(var),
            Err(e) => ctx.error(
                &[Step::Field("hidden"), Step::Key(name)],
                format!("hidden variable `{name}`: {e}"),
                "a new name (not one of the plant model's variables) with at least one value",
            ),
        }
    }
}

/// Reads `initial`: later files override earlier ones; a name given twice in one file is an
/// error.
fn initial_values(
    ctx: &mut FileCtx,
    part: &ScriptParts<'_>,
    classes: &VarClasses,
    script: &mut Script,
) {
    let mut seen: Vec<&str> = Vec::new();
    for (name, value) in &part.initial.0 {
        let key = [Step::Field("initial"), Step::Key(name)];
        if seen.contains(&name.as_str()) {
            ctx.error(
                &key,
                format!("`{name}` is given twice"),
                "each observable or hidden variable once",
            );
            continue;
        }
        seen.push(name);
        let path = [Step::Field("initial"), Step::Value(name)];
        let Some((var, value)) = held_value(ctx, &key, &path, &script.world, classes, name, value)
        else {
            continue;
        };
        script.initial.retain(|(x, _)| *x != var);
        script.initial.push((var, value));
    }
}

/// Resolves `name: value` where `name` must be an observable or a hidden variable, and a
/// number (a reading) only for an observable the plant model monitors.
fn held_value(
    ctx: &mut FileCtx,
    key: &[Step],
    value_path: &[Step],
    world: &VarTable,
    classes: &VarClasses,
    name: &str,
    value: &NumberOrName,
) -> Option<(VarId, Held)> {
    let Some(var) = world
        .variable_id(name)
        .filter(|&v| classes.is_observable(v) || classes.is_hidden(v))
    else {
        let known: Vec<&str> = world
            .variables()
            .filter(|(v, _)| classes.is_observable(*v) || classes.is_hidden(*v))
            .map(|(_, v)| v.name())
            .collect();
        let problem = if world.variable_id(name).is_some() {
            format!("`{name}` is not an observable of the plant model")
        } else {
            format!("no observable or hidden variable `{name}`")
        };
        let mut diagnostic = Diagnostic::new(problem, ctx.span(key))
            .expected("an observable of the plant model or a hidden variable of the script")
            .note(format!("known: {}", known.join(", ")));
        if let Some(close) = did_you_mean(name, known.iter().copied()) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        ctx.push(diagnostic);
        return None;
    };
    let variable = world.variable(var);
    let value = match value {
        NumberOrName::Number(x) if classes.is_numeric(var) => {
            return Some((var, Held::Reading(*x)));
        }
        NumberOrName::Number(x) => {
            ctx.push(
                Diagnostic::new(
                    format!("`{name}` is not numeric: the plant model has no monitor for it"),
                    ctx.span(value_path),
                )
                .expected(format!("one of: {}", variable.values().join(", ")))
                .note(format!(
                    "{x} is a reading; a model's `monitors` make an observable numeric"
                )),
            );
            return None;
        }
        NumberOrName::Name(value) => value,
    };
    let Some(id) = variable.value(value) else {
        let mut diagnostic = Diagnostic::new(
            format!("`{value}` is not a value of `{name}`"),
            ctx.span(value_path),
        )
        .expected(format!("one of: {}", variable.values().join(", ")));
        if let Some(close) = did_you_mean(value, variable.values().iter().map(String::as_str)) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        ctx.push(diagnostic);
        return None;
    };
    Some((var, Held::Value(id)))
}

struct RuleLoader<'a> {
    /// The mission, as loaded (`None`: the scenario runs RMPL).
    mission: Option<&'a Mission>,
    world: &'a VarTable,
    classes: &'a VarClasses,
    end: f64,
    /// True while reading the scenario's own rules: a time rule after the end is a mistake
    /// there, while an included script may go on past a short scenario's end.
    own: bool,
    /// The names some rule garbles (a `drop` may name them).
    garbled: Vec<String>,
    /// Names declared so far, across files.
    names: Vec<String>,
}

impl RuleLoader<'_> {
    fn rule(&mut self, ctx: &mut FileCtx, i: usize, file: &RuleFile) -> Option<Rule> {
        let at = |rest: &[Step<'static>]| {
            let mut path = vec![Step::Field("rules"), Step::Index(i)];
            path.extend_from_slice(rest);
            path
        };
        if self.names.contains(&file.name) {
            ctx.error(
                &at(&[Step::Field("name")]),
                format!("a rule named `{}` is already declared", file.name),
                "a name no other rule of the scenario or its includes has",
            );
        }
        self.names.push(file.name.clone());
        let trigger = self.trigger(ctx, &at(&[Step::Field("on")]), &file.on);
        let condition = match &file.when {
            Some(text) => Some(formula(
                ctx,
                &at(&[Step::Field("when")]),
                text,
                self.world,
                Vars::Held,
                self.classes,
            )?),
            None => None,
        };
        let trigger = trigger?;
        let delay = delay(ctx, &at(&[Step::Field("after")]), file.after, &trigger);
        let effect = self.effect(ctx, &at, file);
        let optional = trigger.is_optional();
        Some(Rule {
            name: file.name.clone(),
            trigger,
            condition,
            delay: delay?,
            interval: match file.after {
                Some(DelayFile::Between(from, to)) => Some((from, to)),
                _ => None,
            },
            effect: effect?,
            // An optional rule is a fault the plant may have: the log highlights it as one.
            once: file.once || optional,
            fault: file.fault || optional,
        })
    }

    fn trigger(&self, ctx: &mut FileCtx, path: &[Step], on: &TriggerFile) -> Option<Trigger> {
        let mut inner = path.to_vec();
        inner.push(Step::Index(0));
        match on {
            TriggerFile::Command(text) => {
                formula(ctx, &inner, text, self.world, Vars::Controls, self.classes)
                    .map(Trigger::Command)
            }
            TriggerFile::Estimate(text) => {
                formula(ctx, &inner, text, self.world, Vars::Modes, self.classes)
                    .map(Trigger::Estimate)
            }
            TriggerFile::While(text) => {
                formula(ctx, &inner, text, self.world, Vars::Held, self.classes).map(Trigger::While)
            }
            &TriggerFile::Time(at) => {
                if !(at.is_finite() && at >= 0.0) {
                    ctx.error(
                        &inner,
                        format!("time {at} is not a time"),
                        "seconds, 0 or more",
                    );
                    return None;
                }
                if at > self.end && self.own {
                    ctx.error(
                        &inner,
                        format!(
                            "the rule would fire at {at} s, after the run ends at {} s",
                            self.end
                        ),
                        "a time within the run",
                    );
                    return None;
                }
                Some(Trigger::Time(at))
            }
            &TriggerFile::Optional { from, to, every } => self.window(ctx, path, from, to, every),
            &TriggerFile::Cycle(n) => match u64::try_from(n) {
                Ok(n) => Some(Trigger::Cycle(n)),
                Err(_) => {
                    ctx.error(
                        &inner,
                        format!("cycle {n} is not a cycle"),
                        "a cycle number, from 0",
                    );
                    None
                }
            },
        }
    }

    /// `Optional(from:, to:, every:)`: a window within the run, `every` at least 1.
    fn window(
        &self,
        ctx: &mut FileCtx,
        path: &[Step],
        from: f64,
        to: f64,
        every: Option<i64>,
    ) -> Option<Trigger> {
        let field = |name: &'static str| with(path.to_vec(), Step::Field(name));
        let before = ctx.errors.len();
        if !(from.is_finite() && from >= 0.0) {
            ctx.error(
                &field("from"),
                format!("time {from} is not a time"),
                "seconds, 0 or more",
            );
        } else if from > self.end && self.own {
            ctx.error(
                &field("from"),
                format!(
                    "the window opens at {from} s, after the run ends at {} s",
                    self.end
                ),
                "a time within the run",
            );
        }
        if !(to.is_finite() && to >= from) {
            ctx.error(
                &field("to"),
                format!("the window closes at {to} s, before it opens at {from} s"),
                "a time at or after `from`",
            );
        }
        let every = match every.map(u64::try_from) {
            None => 1,
            Some(Ok(n)) if n > 0 => n,
            Some(_) => {
                let n = every.unwrap_or_default();
                ctx.error(
                    &field("every"),
                    format!("every {n} cycles is not a stride"),
                    "1 or more cycles",
                );
                return None;
            }
        };
        (ctx.errors.len() == before).then_some(Trigger::Optional { from, to, every })
    }

    fn effect(
        &self,
        ctx: &mut FileCtx,
        at: &dyn Fn(&[Step<'static>]) -> Vec<Step<'static>>,
        file: &RuleFile,
    ) -> Option<Effect> {
        let mut effect = Effect::default();
        let before = ctx.errors.len();
        for (name, value) in &file.set.0 {
            let key = with(at(&[Step::Field("set")]), Step::Key(name));
            let value_path = with(at(&[Step::Field("set")]), Step::Value(name));
            if let Some(pair) = held_value(
                ctx,
                &key,
                &value_path,
                self.world,
                self.classes,
                name,
                value,
            ) {
                effect.set.push(pair);
            }
        }
        for (k, name) in file.drop.iter().enumerate() {
            let path = at(&[Step::Field("drop"), Step::Index(k)]);
            match self
                .world
                .variable_id(name)
                .filter(|&v| self.classes.is_observable(v))
            {
                Some(var) => effect.drop.push(var),
                None if self.garbled.contains(name) => effect.ungarble.push(name.clone()),
                None => ctx.error(
                    &path,
                    format!(
                        "`{name}` is not an observable of the plant model, nor garbled by a rule"
                    ),
                    "an observable the plant stops reporting, or a name a rule's `garble` reports",
                ),
            }
        }
        for (name, value) in &file.garble.0 {
            if let Some(var) = self.world.variable_id(name) {
                let valid = self.classes.is_observable(var)
                    && self.world.variable(var).value(value).is_some();
                if valid {
                    let path = with(at(&[Step::Field("garble")]), Step::Value(name));
                    ctx.error(
                        &path,
                        format!("`{name} = {value}` is a valid observation, not a garbled one"),
                        "a name or value the plant model does not know (use `set` for valid ones)",
                    );
                    continue;
                }
            }
            effect
                .garble
                .push(NamedValue::new(name.as_str(), value.as_str()));
        }
        if let Some(network) = &file.submit {
            effect.submit = self.submission(ctx, &at(&[Step::Field("submit")]), network);
        }
        if effect.set.is_empty()
            && effect.drop.is_empty()
            && effect.ungarble.is_empty()
            && effect.garble.is_empty()
            && effect.submit.is_none()
        {
            if ctx.errors.len() == before {
                ctx.error(
                    &at(&[]),
                    format!("rule `{}` does nothing", file.name),
                    "at least one of `set`, `drop`, `garble` or `submit`",
                );
            }
            return None;
        }
        (ctx.errors.len() == before).then_some(effect)
    }
}

impl RuleLoader<'_> {
    /// A rule's `submit: Network(...)`, resolved against the plant as a mission's goals are
    /// (`goalnet::mission`); an error when the scenario runs RMPL, which has no network.
    fn submission(
        &self,
        ctx: &mut FileCtx,
        path: &[Step],
        network: &NetworkFile,
    ) -> Option<Submission> {
        let Some(mission) = self.mission else {
            ctx.error(
                path,
                "this rule submits goals, and the scenario runs an RMPL program",
                "a scenario with `mission: \"...\"` (goals are submitted to a goal network)",
            );
            return None;
        };
        match resolve_submission(&ctx.source, path, mission, network) {
            Ok(submission) => Some(submission),
            Err(diagnostics) => {
                for diagnostic in diagnostics {
                    ctx.push(diagnostic);
                }
                None
            }
        }
    }
}

fn with<'a>(mut path: Vec<Step<'a>>, step: Step<'a>) -> Vec<Step<'a>> {
    path.push(step);
    path
}

/// The rule's delay: as written, or the earliest possible (the next cycle for command and
/// estimate triggers, the same cycle for time and cycle triggers).
fn delay(
    ctx: &mut FileCtx,
    path: &[Step],
    after: Option<DelayFile>,
    trigger: &Trigger,
) -> Option<Delay> {
    let earliest = u64::from(trigger.after_the_step());
    let mut inner = path.to_vec();
    inner.push(Step::Index(0));
    let delay = match after {
        None => return Some(Delay::Cycles(earliest)),
        Some(DelayFile::Cycles(n)) => match u64::try_from(n) {
            Ok(n) => Delay::Cycles(n),
            Err(_) => {
                ctx.error(
                    &inner,
                    format!("{n} cycles is not a delay"),
                    "0 or more cycles",
                );
                return None;
            }
        },
        Some(DelayFile::Seconds(s)) if s.is_finite() && s >= 0.0 => Delay::Seconds(s),
        Some(DelayFile::Seconds(s)) => {
            ctx.error(&inner, format!("{s} s is not a delay"), "0 or more seconds");
            return None;
        }
        Some(DelayFile::Between(from, to)) => interval(ctx, path, from, to, trigger)?,
    };
    let immediate = matches!(delay, Delay::Cycles(0)) || delay == Delay::Seconds(0.0);
    if trigger.after_the_step() && immediate {
        ctx.error(
            &inner,
            "a command or an estimate cannot change the observation already made in its cycle",
            "Cycles(1) or more, or a positive number of seconds (DESIGN.md §3: an observation at t(i+1) reflects the commands of t(i))",
        );
        return None;
    }
    Some(delay)
}

/// `Between(from, to)`: seconds, `from` more than 0 and `to` at least `from`, not on an optional
/// rule (its firing time is the open choice already, and `choose` pins one number per rule).
/// The run's delay is `from`.
fn interval(
    ctx: &mut FileCtx,
    path: &[Step],
    from: f64,
    to: f64,
    trigger: &Trigger,
) -> Option<Delay> {
    let bound = |k: usize| with(path.to_vec(), Step::Index(k));
    let before = ctx.errors.len();
    if trigger.is_optional() {
        ctx.error(
            path,
            "an optional rule's effect cannot land in an interval",
            "Cycles(n) or Seconds(s): the optional rule's firing time is already open",
        );
    }
    if !(from.is_finite() && from > 0.0) {
        // A lower bound of 0 would let a time rule's response land in its own cycle, which
        // exploration (choosing the landing after the cycle) could not offer.
        ctx.error(
            &bound(0),
            format!("{from} s is not the start of an interval"),
            "more than 0 seconds (Seconds(0.0) or no `after` for an immediate response)",
        );
    } else if !(to.is_finite() && to >= from) {
        ctx.error(
            &bound(1),
            format!("the interval closes at {to} s, before it opens at {from} s"),
            "a delay in seconds at or after the interval's first",
        );
    }
    (ctx.errors.len() == before).then_some(Delay::Seconds(from))
}

/// The scenario's `choose`: each name an optional rule, each time within its window; or a rule
/// with an interval, each delay within it.
pub(super) fn pinned(
    ctx: &mut FileCtx,
    choose: &Entries<f64>,
    script: &Script,
) -> Vec<(usize, f64)> {
    let mut pinned = Vec::new();
    for &(ref name, at) in &choose.0 {
        let key = [Step::Field("choose"), Step::Key(name)];
        let optional: Vec<&str> = script
            .rules
            .iter()
            .filter(|r| r.trigger.is_optional())
            .map(|r| r.name.as_str())
            .collect();
        let Some(i) = script.rule_named(name).filter(|&i| {
            script.rules[i].trigger.is_optional() || script.rules[i].interval.is_some()
        }) else {
            let mut diagnostic = Diagnostic::new(
                format!("no optional rule `{name}`"),
                ctx.span(&key),
            )
            .expected(
                "the name of a rule with an `Optional(...)` trigger or a `Between(...)` delay",
            )
            .note(format!("optional rules: {}", optional.join(", ")));
            if let Some(close) = did_you_mean(name, optional.iter().copied()) {
                diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
            }
            ctx.push(diagnostic);
            continue;
        };
        if let Trigger::Optional { from, to, .. } = script.rules[i].trigger {
            if !(at >= from - TIME_EPSILON && at <= to + TIME_EPSILON) {
                ctx.error(
                    &[Step::Field("choose"), Step::Value(name)],
                    format!("{at} s is outside the rule's window, {from} s to {to} s"),
                    "a time within the rule's `Optional` window",
                );
                continue;
            }
        }
        if let Some((from, to)) = script.rules[i].interval {
            if !(at >= from - TIME_EPSILON && at <= to + TIME_EPSILON) {
                ctx.error(
                    &[Step::Field("choose"), Step::Value(name)],
                    format!("a delay of {at} s is outside the rule's interval, {from} s to {to} s"),
                    "a delay within the rule's `Between` interval",
                );
                continue;
            }
        }
        pinned.push((i, at));
    }
    pinned
}
