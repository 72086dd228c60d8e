//! The scripted plant: a rule-based simulator in the manner of the one the thesis's EDL
//! demonstration used (§7.2.1: it "eavesdrops on the issued command and state estimate streams"
//! and "triggers one or more rules that inject desired observations some specified number of
//! execution cycles later").
//!
//! The plant holds a value for every observable it reports and for its own hidden state
//! variables. Every cycle it reports every observable that has a value, holding the last one
//! (DESIGN.md §3). Rules fire on the command the executive issued, on its estimate, at a time or
//! at a cycle, optionally only while a condition over the plant's values holds, and change
//! values after a delay.
//!
//! Order within cycle i at time t(i) (DESIGN.md §3: an observation at t(i+1) reflects the
//! commands of t(i)):
//! 1. [`observe`](MonitorAdapter::observe): effects due at cycle i are applied (in the order
//!    their rules fired); then time and cycle rules whose moment has come, and `While` rules
//!    whose condition has come to hold, fire, in declaration order (an effect without delay
//!    applies at once), and a `While` rule whose condition no longer holds loses the effects it
//!    has pending; the observation is reported.
//! 2. The executive runs its cycle.
//! 3. [`send`](ControlAdapter::send): command rules fire on μ(i); their effects are due at cycle
//!    i + 1 at the earliest.
//! 4. [`estimated`](ScriptedPlant::estimated): estimate rules fire on ŝ(i); effects likewise.
//!
//! What `kairos explore` leaves open beyond optional rules — where in its interval a timed
//! response lands, and the order of simultaneous deliveries — is in [`open`].

mod open;

pub use open::OpenLanding;

use std::sync::Arc;

use crate::executive::adapters::{ControlAdapter, MonitorAdapter};
use crate::executive::{NamedValue, Submission};
use crate::logic::{Formula, ValueId, VarId, VarTable};

/// Two times closer than this are the same instant (cycle times are products of the period).
pub(crate) const TIME_EPSILON: f64 = 1e-6;

/// A scripted plant's definition: its variables, initial values and rules.
#[derive(Debug, Clone, PartialEq)]
pub struct Script {
    /// The plant model's variables followed by the script's hidden variables.
    pub(crate) world: VarTable,
    /// The plant's observables, in the model's order.
    pub(crate) observables: Vec<VarId>,
    /// The plant's controls and their idle values.
    pub(crate) controls: Vec<(VarId, ValueId)>,
    /// Each component's mode variable, by component index.
    pub(crate) modes: Vec<VarId>,
    /// The hidden variables.
    pub(crate) hidden: Vec<VarId>,
    /// Values at the start.
    pub(crate) initial: Vec<(VarId, Held)>,
    /// The rules, included files' first, in declaration order.
    pub(crate) rules: Vec<Rule>,
    /// Optional rules a run fires, at the first cycle at or after the time (rule index, time):
    /// the scenario's `choose`.
    pub(crate) pinned: Vec<(usize, f64)>,
    /// Orders of simultaneous deliveries a run follows (time of the cycle, the rules whose
    /// effects are due then, in the order they are applied): the scenario's `deliver`.
    pub(crate) deliveries: Vec<(f64, Vec<usize>)>,
}

impl Script {
    /// The plant's variables and the hidden ones.
    pub fn variables(&self) -> &VarTable {
        &self.world
    }

    /// The rules.
    pub fn rules(&self) -> &[Rule] {
        &self.rules
    }

    /// The rule with this name.
    pub fn rule_named(&self, name: &str) -> Option<usize> {
        self.rules.iter().position(|r| r.name == name)
    }

    /// The initial values (observables and hidden variables).
    pub fn initial(&self) -> &[(VarId, Held)] {
        &self.initial
    }

    /// The hidden variables.
    pub fn hidden(&self) -> &[VarId] {
        &self.hidden
    }

    /// The scenario's `choose`: the optional rules a run fires and the times it fires them at,
    /// and the delays a run takes for rules with an interval ([`Rule::interval`]).
    pub fn pinned(&self) -> &[(usize, f64)] {
        &self.pinned
    }

    /// The scenario's `deliver`: the orders a run applies simultaneous effects in.
    pub fn deliveries(&self) -> &[(f64, Vec<usize>)] {
        &self.deliveries
    }
}

impl Trigger {
    /// True when the rule is open nondeterminism ([`Trigger::Optional`]).
    pub fn is_optional(&self) -> bool {
        matches!(self, Trigger::Optional { .. })
    }

    /// True when an optional rule may fire at this cycle and time.
    pub fn may_fire_at(&self, cycle: u64, time: f64) -> bool {
        match *self {
            Trigger::Optional { from, to, every } => {
                time >= from - TIME_EPSILON
                    && time <= to + TIME_EPSILON
                    && cycle % every.max(1) == 0
            }
            _ => false,
        }
    }
}

/// One rule of the script.
#[derive(Debug, Clone, PartialEq)]
pub struct Rule {
    /// Its name, unique in the scenario.
    pub name: String,
    /// What makes it fire.
    pub trigger: Trigger,
    /// It fires only while this holds over the plant's values (observables and hidden).
    pub condition: Option<Formula>,
    /// How long after firing its effect shows (for a rule with an interval, its lower bound).
    pub delay: Delay,
    /// `after: Between(from, to)`: the effect lands at any cycle whose time is in
    /// [fired + from, fired + to] seconds. A run takes `from` unless `choose` pins another
    /// delay; `kairos explore` tries every such cycle.
    pub interval: Option<(f64, f64)>,
    /// What it does.
    pub effect: Effect,
    /// Fires at most once.
    pub once: bool,
    /// Makes the plant misbehave (the mission log highlights it).
    pub fault: bool,
}

/// What makes a rule fire.
#[derive(Debug, Clone, PartialEq)]
pub enum Trigger {
    /// Every cycle whose command μ (idle values for controls not commanded) satisfies the
    /// formula over control variables.
    Command(Formula),
    /// When ŝ, the most likely mode of each component, comes to satisfy the formula over mode
    /// variables (with the condition: when both come to hold).
    Estimate(Formula),
    /// When the plant's own values (observables and hidden variables) come to satisfy the
    /// formula — each time they do — and only for as long as they go on satisfying it: an effect
    /// still pending when the formula stops holding is dropped. A physical process that needs a
    /// condition to last ("the device reaches 20 °C after 65 s of one heater on") is faithful to
    /// a fault at any cycle, as a command-triggered delay is not.
    While(Formula),
    /// The first cycle at or after this time (in seconds) at which the condition holds.
    Time(f64),
    /// The first cycle at or after this one (numbered from 0) at which the condition holds.
    Cycle(u64),
    /// Open nondeterminism: the rule may fire once at any cycle of `from..=to` (seconds) whose
    /// number is a multiple of `every`, or never. `kairos explore` tries every choice; a run
    /// fires it only where the scenario's `choose` pins it ([`Script::pinned`]).
    Optional {
        /// The window's first time.
        from: f64,
        /// The window's last time.
        to: f64,
        /// Only cycles whose number is a multiple of this (a coarser search).
        every: u64,
    },
}

impl Trigger {
    /// True for triggers that fire after the executive's cycle (command, estimate): their effect
    /// shows at the next cycle at the earliest.
    pub fn after_the_step(&self) -> bool {
        matches!(self, Trigger::Command(_) | Trigger::Estimate(_))
    }
}

/// A delay, or a tolerance, in cycles or seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Delay {
    /// This many cycles.
    Cycles(u64),
    /// At the first cycle at least this many seconds later.
    Seconds(f64),
}

/// What the scripted plant holds for an observable or a hidden variable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Held {
    /// A value of its domain.
    Value(ValueId),
    /// A reading of a numeric observable (the plant model monitors it), reported as a number.
    Reading(f64),
}

impl Held {
    /// The value, unless it is a reading.
    pub fn value(self) -> Option<ValueId> {
        match self {
            Held::Value(value) => Some(value),
            Held::Reading(_) => None,
        }
    }

    /// `name = value` or `name = 28.1` for a reading.
    pub fn describe(self, world: &VarTable, var: VarId) -> String {
        match self {
            Held::Value(value) => world.assignment(var, value).to_string(),
            Held::Reading(x) => format!("{} = {x}", world.variable(var).name()),
        }
    }
}

/// What a rule does to the plant.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Effect {
    /// Values to hold from now on (observables are reported with them).
    pub set: Vec<(VarId, Held)>,
    /// Observables to stop reporting (a sensor drop-out).
    pub drop: Vec<VarId>,
    /// Garbled names (not observables) to stop reporting: the end of a garbled telemetry word.
    pub ungarble: Vec<String>,
    /// Name/value pairs to report verbatim although they do not fit the model, in place of the
    /// observable of that name if there is one (a garbled telemetry word).
    pub garble: Vec<NamedValue>,
    /// Goals, with their points and constraints, to submit to the running mission
    /// ([`Executive::submit`](crate::executive::Executive::submit)) when the effect shows.
    pub submit: Option<Submission>,
}

impl Effect {
    /// `engine.temp = nominal, pde = on, engine.power dropped, engine.colour = "blue"`.
    pub fn describe(&self, world: &VarTable) -> String {
        let mut parts: Vec<String> = self
            .set
            .iter()
            .map(|&(x, v)| v.describe(world, x))
            .collect();
        parts.extend(
            self.drop
                .iter()
                .map(|&x| format!("{} no longer reported", world.variable(x).name())),
        );
        parts.extend(
            self.ungarble
                .iter()
                .map(|name| format!("{name} no longer reported")),
        );
        parts.extend(
            self.garble
                .iter()
                .map(|g| format!("{} = \"{}\" (garbled)", g.variable, g.value)),
        );
        if let Some(submission) = &self.submit {
            let goals: Vec<&str> = submission.goals.iter().map(|g| g.name.as_str()).collect();
            parts.push(format!("submits {}", goals.join(", ")));
        }
        parts.join(", ")
    }
}

/// When a fired rule's effect is applied.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Due {
    /// At this cycle.
    Cycle(u64),
    /// At the first cycle at or after this time, and not before this cycle.
    Time { at: f64, not_before: u64 },
    /// Fired at this time with an interval whose landing `kairos explore` has yet to choose.
    Open { fired: f64, not_before: u64 },
}

#[derive(Debug, Clone, PartialEq)]
struct Pending {
    rule: usize,
    due: Due,
}

/// Something the scripted plant did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlantEventKind {
    /// The rule fired (its effect is due now or later).
    Fired,
    /// The rule's effect was applied to the plant.
    Applied,
}

/// A rule firing or taking effect.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlantEvent {
    /// The cycle.
    pub cycle: u64,
    /// Its time.
    pub time: f64,
    /// The rule, by index into [`Script::rules`].
    pub rule: usize,
    /// Fired or applied.
    pub kind: PlantEventKind,
}

/// A plant that follows a [`Script`]; see the module documentation.
#[derive(Debug, Clone)]
pub struct ScriptedPlant<'s> {
    script: &'s Script,
    values: Vec<Option<ValueId>>,
    /// The readings numeric observables hold (in place of a value), by variable.
    readings: Vec<Option<f64>>,
    garbled: Vec<NamedValue>,
    cycle: Option<u64>,
    time: f64,
    pending: Vec<Pending>,
    /// Whether each rule's trigger and condition held at its last evaluation (edge triggers).
    held: Vec<bool>,
    /// The first cycle and time each rule fired.
    first_fired: Vec<Option<(u64, f64)>>,
    /// How many times each rule fired.
    fired: Vec<u64>,
    events: Vec<PlantEvent>,
    /// Optional rules to fire at the next cycle ([`ScriptedPlant::force`]).
    forced: Vec<usize>,
    /// Rules whose effect, applied since the last [`take_submissions`](Self::take_submissions),
    /// submits goals.
    submitted: Vec<usize>,
    /// True when intervals are left open for exploration ([`ScriptedPlant::leave_open`]).
    open: bool,
    /// The delay each rule with an interval takes on this path, once chosen.
    landing: Vec<Option<f64>>,
    /// The order to apply the effects due at the next cycle in ([`ScriptedPlant::force_order`]).
    order: Option<Vec<usize>>,
    /// The last report, while it still holds: a report is a pure function of `values` and
    /// `garbled`, which only [`apply`](Self::apply) changes (and clears this), so a quiet cycle
    /// hands out the same names instead of formatting every observable again.
    report: Option<Arc<[NamedValue]>>,
    /// The command rules the idle action μ (no command) issues, in declaration order: a
    /// function of the fixed script alone, so a quiet cycle's [`send`](ControlAdapter::send)
    /// evaluates no trigger (their conditions still are, on the current values).
    idle_issues: Arc<[usize]>,
}

impl<'s> ScriptedPlant<'s> {
    /// A plant in the script's initial state, before its first cycle.
    pub fn new(script: &'s Script) -> Self {
        let mut values = vec![None; script.world.len()];
        let mut readings = vec![None; script.world.len()];
        for &(var, held) in &script.initial {
            hold(&mut values, &mut readings, var, held);
        }
        let rules = script.rules.len();
        ScriptedPlant {
            script,
            values,
            readings,
            garbled: Vec::new(),
            cycle: None,
            time: 0.0,
            pending: Vec::new(),
            held: vec![false; rules],
            first_fired: vec![None; rules],
            fired: vec![0; rules],
            events: Vec::new(),
            forced: Vec::new(),
            submitted: Vec::new(),
            open: false,
            landing: vec![None; rules],
            order: None,
            report: None,
            idle_issues: issued_by(script, &idle_values(script)).collect(),
        }
    }

    /// Fires these optional rules at the next cycle (in [`observe`](MonitorAdapter::observe),
    /// with the time rules, in declaration order), each if its condition holds and it has not
    /// fired yet: the choice `kairos explore` makes for a path.
    pub fn force(&mut self, rules: &[usize]) {
        self.forced.clear();
        self.forced.extend_from_slice(rules);
    }

    /// Feeds the plant's state — values, garbled words, pending effects, edge-trigger memory,
    /// which rules fired and when first (expectations read it) — to `state`, for
    /// exploration's deduplication. How often a rule fired beyond the first is left out: only
    /// `once` and quiescence read it, as "fired at all".
    pub fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        use std::hash::Hash;
        self.values.hash(state);
        for reading in &self.readings {
            reading.map(f64::to_bits).hash(state);
        }
        self.garbled.hash(state);
        self.cycle.hash(state);
        for pending in &self.pending {
            pending.rule.hash(state);
            match pending.due {
                Due::Cycle(n) => (0u8, n).hash(state),
                Due::Time { at, not_before } => (1u8, at.to_bits(), not_before).hash(state),
                Due::Open { fired, not_before } => (2u8, fired.to_bits(), not_before).hash(state),
            }
        }
        for landing in &self.landing {
            landing.map(f64::to_bits).hash(state);
        }
        self.held.hash(state);
        for (count, first) in self.fired.iter().zip(&self.first_fired) {
            (*count > 0).hash(state);
            first.map(|(cycle, _)| cycle).hash(state);
        }
    }

    /// The script it follows.
    pub fn script(&self) -> &'s Script {
        self.script
    }

    /// The current value of an observable or hidden variable (`None`: not reported, or a
    /// reading).
    pub fn value(&self, var: VarId) -> Option<ValueId> {
        self.values.get(var.index()).copied().flatten()
    }

    /// When a rule first fired: (cycle, time).
    pub fn first_fired(&self, rule: usize) -> Option<(u64, f64)> {
        self.first_fired.get(rule).copied().flatten()
    }

    /// How many times a rule fired.
    pub fn times_fired(&self, rule: usize) -> u64 {
        self.fired.get(rule).copied().unwrap_or(0)
    }

    /// The submissions of the effects applied since the last call, in the order they were
    /// applied (rule index, submission): the run submits them to the executive before its cycle.
    pub fn take_submissions(&mut self) -> Vec<(usize, &'s Submission)> {
        let script = self.script;
        std::mem::take(&mut self.submitted)
            .into_iter()
            .filter_map(|i| Some((i, script.rules[i].effect.submit.as_ref()?)))
            .collect()
    }

    /// What the plant did since the last call (rule firings and effects), oldest first.
    pub fn take_events(&mut self) -> Vec<PlantEvent> {
        std::mem::take(&mut self.events)
    }

    /// True when nothing is pending and no time or cycle rule is still to fire before `end`:
    /// the plant changes only if the executive commands something or changes its estimate.
    pub fn is_quiet(&self, end: f64) -> bool {
        self.pending.is_empty()
            && self.script.rules.iter().enumerate().all(|(i, rule)| {
                let spent = self.fired[i] > 0;
                match rule.trigger {
                    Trigger::Time(at) => spent || at > end + TIME_EPSILON,
                    Trigger::Cycle(_) => spent,
                    // Values change only by effects: with none pending they keep their edge.
                    Trigger::Command(_) | Trigger::Estimate(_) | Trigger::While(_) => true,
                    Trigger::Optional { .. } => spent || self.pin(i).is_none_or(|at| at > end),
                }
            })
    }

    /// Notes the executive's estimate ŝ(i) (a mode per component, by component index) for
    /// estimate rules. Call it after [`send`](ControlAdapter::send) in each cycle.
    pub fn estimated(&mut self, modes: &[ValueId]) {
        let script = self.script;
        let mode_of = |var: VarId| {
            let component = script.modes.iter().position(|&m| m == var)?;
            modes.get(component).copied()
        };
        for (i, rule) in script.rules.iter().enumerate() {
            if let Trigger::Estimate(formula) = &rule.trigger {
                let now = formula.eval_assignment(&script.world, &mode_of) == Some(true)
                    && self.condition_holds(rule);
                let rising = now && !self.held[i];
                self.held[i] = now;
                if rising {
                    self.fire(i);
                }
            }
        }
    }

    fn condition_holds(&self, rule: &Rule) -> bool {
        rule.condition.as_ref().is_none_or(|condition| {
            condition.eval_assignment(&self.script.world, &|var| self.value(var)) == Some(true)
        })
    }

    fn current_cycle(&self) -> u64 {
        self.cycle.unwrap_or(0)
    }

    /// Fires rule `i` now, unless it is a spent `once` rule.
    fn fire(&mut self, i: usize) {
        let script = self.script;
        let rule = &script.rules[i];
        if rule.once && self.fired[i] > 0 {
            return;
        }
        let cycle = self.current_cycle();
        let earliest = cycle + u64::from(rule.trigger.after_the_step());
        self.fired[i] += 1;
        self.first_fired[i].get_or_insert((cycle, self.time));
        self.push_event(i, PlantEventKind::Fired);
        let due = self.due(i, cycle, earliest);
        if self.is_due(due) {
            self.apply(i);
        } else {
            self.pending.push(Pending { rule: i, due });
        }
    }

    fn is_due(&self, due: Due) -> bool {
        self.cycle
            .is_some_and(|cycle| due_at(due, cycle, self.time))
    }

    fn apply(&mut self, i: usize) {
        let script = self.script;
        let effect = &script.rules[i].effect;
        self.report = None;
        for &(var, held) in &effect.set {
            hold(&mut self.values, &mut self.readings, var, held);
            let name = script.world.variable(var).name();
            self.garbled.retain(|g| g.variable != name);
        }
        for &var in &effect.drop {
            self.values[var.index()] = None;
            self.readings[var.index()] = None;
            let name = script.world.variable(var).name();
            self.garbled.retain(|g| g.variable != name);
        }
        for name in &effect.ungarble {
            self.garbled.retain(|g| &g.variable != name);
        }
        for garbled in &effect.garble {
            self.garbled.retain(|g| g.variable != garbled.variable);
            self.garbled.push(garbled.clone());
        }
        if effect.submit.is_some() {
            self.submitted.push(i);
        }
        self.push_event(i, PlantEventKind::Applied);
    }

    fn push_event(&mut self, rule: usize, kind: PlantEventKind) {
        self.events.push(PlantEvent {
            cycle: self.current_cycle(),
            time: self.time,
            rule,
            kind,
        });
    }

    /// Applies the effects due now, in the order their rules fired unless an order is forced
    /// or pinned for this cycle ([`open`]).
    fn apply_due(&mut self) {
        let (due, waiting): (Vec<Pending>, Vec<Pending>) = std::mem::take(&mut self.pending)
            .into_iter()
            .partition(|p| self.is_due(p.due));
        self.pending = waiting;
        let fired: Vec<usize> = due.iter().map(|p| p.rule).collect();
        for rule in self.delivery_order(fired) {
            self.apply(rule);
        }
    }

    /// Fires time and cycle rules whose moment has come and whose condition holds.
    fn fire_timed(&mut self) {
        let cycle = self.current_cycle();
        let script = self.script;
        for (i, rule) in script.rules.iter().enumerate() {
            let reached = match &rule.trigger {
                Trigger::Time(at) => self.time >= at - TIME_EPSILON,
                Trigger::Cycle(n) => cycle >= *n,
                Trigger::Command(_) | Trigger::Estimate(_) => continue,
                Trigger::While(formula) => {
                    self.sustain(i, formula, rule);
                    continue;
                }
                Trigger::Optional { .. } => {
                    let pinned = self.pin(i).is_some_and(|at| self.time >= at - TIME_EPSILON);
                    let chosen = pinned || self.forced.contains(&i);
                    if chosen && self.fired[i] == 0 && self.condition_holds(rule) {
                        self.fire(i);
                    }
                    continue;
                }
            };
            let now = reached && self.condition_holds(rule);
            let rising = now && !self.held[i];
            self.held[i] = now;
            if rising && self.fired[i] == 0 {
                self.fire(i);
            }
        }
    }

    /// A `While` rule at this cycle: it fires when its formula (and condition) comes to hold,
    /// and its pending effects are dropped when they stop holding.
    fn sustain(&mut self, i: usize, formula: &Formula, rule: &Rule) {
        let script = self.script;
        let now = formula.eval_assignment(&script.world, &|var| self.value(var)) == Some(true)
            && self.condition_holds(rule);
        let was = std::mem::replace(&mut self.held[i], now);
        if now && !was {
            self.fire(i);
        } else if was && !now {
            self.pending.retain(|p| p.rule != i);
        }
    }

    /// The time the scenario pins optional rule `i` at, if it does.
    fn pin(&self, i: usize) -> Option<f64> {
        let pinned = self.script.pinned.iter().find(|(rule, _)| *rule == i);
        pinned.map(|&(_, at)| at)
    }

    /// [`observe`](MonitorAdapter::observe) without copying the report: the same shared
    /// report every cycle until an effect changes a value, so that a run's quiet cycle neither
    /// formats nor frees names.
    pub fn observe_shared(&mut self, time: f64) -> Arc<[NamedValue]> {
        let cycle = self.cycle.map_or(0, |c| c + 1);
        self.cycle = Some(cycle);
        self.time = time;
        self.apply_due();
        self.order = None;
        self.fire_timed();
        self.forced.clear();
        if let Some(report) = &self.report {
            return Arc::clone(report);
        }
        let report: Arc<[NamedValue]> = self.report().into();
        self.report = Some(Arc::clone(&report));
        report
    }

    /// The observation: every observable with a value, garbled pairs in place of or beside them.
    fn report(&self) -> Vec<NamedValue> {
        let world = &self.script.world;
        let mut observed: Vec<NamedValue> = Vec::with_capacity(self.script.observables.len());
        for &var in &self.script.observables {
            let variable = world.variable(var);
            if let Some(garbled) = self.garbled.iter().find(|g| g.variable == variable.name()) {
                observed.push(garbled.clone());
            } else if let Some(reading) = self.readings[var.index()] {
                observed.push(NamedValue::new(variable.name(), reading));
            } else if let Some(value) = self.value(var) {
                observed.push(NamedValue::new(variable.name(), variable.value_name(value)));
            }
        }
        let extra: Vec<NamedValue> = self
            .garbled
            .iter()
            .filter(|g| !observed.iter().any(|o| o.variable == g.variable))
            .cloned()
            .collect();
        observed.extend(extra);
        observed
    }

    /// The full control action μ named by `command` (idle values elsewhere); unknown names and
    /// values are refused.
    fn control_values(&self, command: &[NamedValue]) -> Result<Vec<Option<ValueId>>, String> {
        let world = &self.script.world;
        let mut values = idle_values(self.script);
        for assignment in command {
            let var = world
                .variable_id(&assignment.variable)
                .filter(|v| self.script.controls.iter().any(|(c, _)| c == v))
                .ok_or_else(|| format!("no actuator for {assignment}: not a control"))?;
            let value = (assignment.value.symbol())
                .and_then(|name| world.variable(var).value(name))
                .ok_or_else(|| format!("no actuator for {assignment}: not a value"))?;
            values[var.index()] = Some(value);
        }
        Ok(values)
    }
}

/// Makes `var` hold `held`: a value, or a reading in place of one.
fn hold(values: &mut [Option<ValueId>], readings: &mut [Option<f64>], var: VarId, held: Held) {
    let (value, reading) = match held {
        Held::Value(value) => (Some(value), None),
        Held::Reading(x) => (None, Some(x)),
    };
    values[var.index()] = value;
    readings[var.index()] = reading;
}

/// True when an effect due `due` applies at this cycle and time.
fn due_at(due: Due, cycle: u64, time: f64) -> bool {
    match due {
        Due::Cycle(n) => n <= cycle,
        Due::Time { at, not_before } => cycle >= not_before && time >= at - TIME_EPSILON,
        Due::Open { .. } => false,
    }
}

impl MonitorAdapter for ScriptedPlant<'_> {
    fn observe(&mut self, time: f64) -> Vec<NamedValue> {
        self.observe_shared(time).to_vec()
    }
}

impl ControlAdapter for ScriptedPlant<'_> {
    fn send(&mut self, _time: f64, command: &[NamedValue]) -> Result<(), String> {
        let issued: Arc<[usize]> = if command.is_empty() {
            Arc::clone(&self.idle_issues)
        } else {
            issued_by(self.script, &self.control_values(command)?).collect()
        };
        for &i in issued.iter() {
            if self.condition_holds(&self.script.rules[i]) {
                self.fire(i);
            }
        }
        Ok(())
    }
}

/// The idle control action: every control at its idle value, every other variable unset.
fn idle_values(script: &Script) -> Vec<Option<ValueId>> {
    let mut values = vec![None; script.world.len()];
    for &(var, idle) in &script.controls {
        values[var.index()] = Some(idle);
    }
    values
}

/// The command rules whose trigger the control action `values` satisfies, in declaration order.
fn issued_by<'a>(
    script: &'a Script,
    values: &'a [Option<ValueId>],
) -> impl Iterator<Item = usize> + 'a {
    script
        .rules
        .iter()
        .enumerate()
        .filter_map(move |(i, rule)| match &rule.trigger {
            Trigger::Command(formula) => {
                (formula.eval_assignment(&script.world, &|var| values[var.index()]) == Some(true))
                    .then_some(i)
            }
            _ => None,
        })
}

#[cfg(test)]
mod tests {
    //! The rule semantics of DESIGN.md §11 and thesis §7.2.1, on the engine/camera model.

    use super::*;
    use crate::simulation::testing::engine_camera;

    const INITIAL: &str = r#"initial: { "engine.temp": "low", "engine.thrust": "zero", "camera.shutter": "closed" },"#;

    fn observed<'a>(report: &'a [NamedValue], name: &str) -> Option<&'a str> {
        report
            .iter()
            .find(|o| o.variable == name)
            .map(|o| o.value.symbol().unwrap_or_default())
    }

    fn fire(plant: &mut ScriptedPlant<'_>) {
        plant
            .send(0.0, &[NamedValue::new("engine.cmd", "fire")])
            .expect("a control");
    }

    /// §3: an observation at t(i+1) reflects the commands of t(i); a command rule's effect
    /// shows at the next cycle at the earliest.
    #[test]
    fn a_command_rule_shows_at_the_next_cycle() {
        let scenario = engine_camera(&format!(
            r#"{INITIAL} rules: [Rule(name: "fires", on: Command("engine.cmd = fire"),
                set: {{ "engine.thrust": "nominal" }})]"#
        ));
        let mut plant = ScriptedPlant::new(&scenario.script);
        assert_eq!(observed(&plant.observe(0.0), "engine.thrust"), Some("zero"));
        fire(&mut plant);
        assert_eq!(plant.first_fired(0), Some((0, 0.0)));
        assert_eq!(
            observed(&plant.observe(1.0), "engine.thrust"),
            Some("nominal")
        );
        let kinds: Vec<PlantEventKind> = plant.take_events().iter().map(|e| e.kind).collect();
        assert_eq!(kinds, [PlantEventKind::Fired, PlantEventKind::Applied]);
    }

    /// §7.2.1 (the plant holds its values, DESIGN.md §3): while no effect applies, every cycle
    /// reports the very same observation — shared, not formatted again — and an
    /// effect shows in the next report.
    #[test]
    fn the_report_is_shared_until_an_effect_applies() {
        let scenario = engine_camera(&format!(
            r#"{INITIAL} rules: [Rule(name: "fires", on: Command("engine.cmd = fire"),
                set: {{ "engine.thrust": "nominal" }})]"#
        ));
        let mut plant = ScriptedPlant::new(&scenario.script);
        let first = plant.observe_shared(0.0);
        let quiet = plant.observe_shared(1.0);
        assert!(
            Arc::ptr_eq(&first, &quiet),
            "nothing applied: the same report"
        );
        assert_eq!(&*quiet, plant.observe(2.0).as_slice());
        fire(&mut plant);
        let after = plant.observe_shared(3.0);
        assert_eq!(observed(&after, "engine.thrust"), Some("nominal"));
        assert_eq!(observed(&first, "engine.thrust"), Some("zero"));
    }

    /// A command rule on the idle action (no command: every control at its idle value) fires
    /// on a quiet cycle as on any other whose action satisfies it, each time its condition
    /// holds; a command that changes the control does not fire it.
    #[test]
    fn a_command_rule_on_the_idle_action_fires_without_a_command() {
        let scenario = engine_camera(&format!(
            r#"{INITIAL} rules: [Rule(name: "idle", on: Command("engine.cmd = none"),
                when: "engine.thrust = zero", set: {{ "engine.temp": "nominal" }})]"#
        ));
        let mut plant = ScriptedPlant::new(&scenario.script);
        plant.observe(0.0);
        fire(&mut plant);
        assert_eq!(plant.times_fired(0), 0, "engine.cmd = fire is not idle");
        plant.send(0.0, &[]).expect("the idle action");
        plant
            .send(0.0, &[NamedValue::new("camera.cmd", "on")])
            .expect("a control");
        assert_eq!(
            plant.times_fired(0),
            2,
            "idle engine.cmd, with and without a command"
        );
        assert_eq!(
            observed(&plant.observe(1.0), "engine.temp"),
            Some("nominal")
        );
    }

    /// `Seconds(s)`: the first cycle at least s after the firing; `once`: one firing only.
    #[test]
    fn a_delay_in_seconds_and_a_once_rule() {
        let scenario = engine_camera(&format!(
            r#"{INITIAL} rules: [Rule(name: "fires late", on: Command("engine.cmd = fire"),
                after: Seconds(2.5), set: {{ "engine.thrust": "nominal" }}, once: true)]"#
        ));
        let mut plant = ScriptedPlant::new(&scenario.script);
        let mut seen = Vec::new();
        for i in 0..5 {
            let report = plant.observe(f64::from(i));
            seen.push(observed(&report, "engine.thrust").map(str::to_string));
            fire(&mut plant);
        }
        let nominal = Some("nominal".to_string());
        assert_eq!(seen[2], Some("zero".to_string()));
        assert_eq!(seen[3], nominal, "due at 2.5 s: shown at 3 s");
        assert_eq!(plant.times_fired(0), 1, "a once rule fires once");
    }

    /// Estimate rules fire when ŝ comes to satisfy the formula, not on every cycle it does.
    #[test]
    fn an_estimate_rule_fires_on_the_rising_edge() {
        let scenario = engine_camera(&format!(
            r#"{INITIAL} rules: [Rule(name: "hot", on: Estimate("engine = heating"),
                set: {{ "engine.temp": "nominal" }})]"#
        ));
        let plant_model = &scenario.plant;
        let mode = |component: &str, name: &str| {
            let c = plant_model.component_named(component).expect("a component");
            plant_model.component(c).mode_named(name).expect("a mode")
        };
        let heating = [mode("engine", "heating"), mode("camera", "off")];
        let off = [mode("engine", "off"), mode("camera", "off")];
        let mut plant = ScriptedPlant::new(&scenario.script);
        for modes in [&off, &heating, &heating, &off, &heating] {
            plant.observe(plant.time + 1.0);
            plant.estimated(modes);
        }
        assert_eq!(plant.times_fired(0), 2);
    }

    /// Time rules wait for their condition; garbled words replace an observable's value until
    /// it is set again, and extra garbled names last until dropped.
    #[test]
    fn time_rules_conditions_and_garbled_words() {
        let scenario = engine_camera(&format!(
            r#"{INITIAL} hidden: {{ "weather": ["calm", "storm"] }},
            rules: [
                Rule(name: "storm", on: Cycle(3), set: {{ "weather": "storm" }}),
                Rule(name: "noise", on: Time(1.0), when: "weather = storm",
                     garble: {{ "engine.temp": "sizzling", "engine.colour": "blue" }}),
                Rule(name: "calm", on: Cycle(5), set: {{ "engine.temp": "low" }},
                     drop: ["engine.colour"]),
            ]"#
        ));
        let mut plant = ScriptedPlant::new(&scenario.script);
        let reports: Vec<Vec<NamedValue>> = (0..6).map(|i| plant.observe(f64::from(i))).collect();
        assert_eq!(observed(&reports[2], "engine.temp"), Some("low"));
        assert_eq!(
            observed(&reports[3], "engine.temp"),
            Some("sizzling"),
            "the condition comes to hold at cycle 3 (rules fire in order)"
        );
        assert_eq!(observed(&reports[4], "engine.colour"), Some("blue"));
        assert_eq!(observed(&reports[5], "engine.temp"), Some("low"));
        assert_eq!(observed(&reports[5], "engine.colour"), None);
        assert!(plant.is_quiet(100.0));
    }

    /// A `While` rule fires when its condition comes to hold and drops its pending effect when
    /// it stops: the engine's heat lasting 3 cycles makes it nominal, an interruption at the
    /// second cycle cancels that, and the condition back fires it again.
    #[test]
    fn a_while_rule_lands_only_if_its_condition_lasts() {
        let scenario = engine_camera(&format!(
            r#"{INITIAL} hidden: {{ "heat": ["off", "on"] }},
            rules: [
                Rule(name: "on", on: Cycle(1), set: {{ "heat": "on" }}),
                Rule(name: "off", on: Cycle(2), set: {{ "heat": "off" }}),
                Rule(name: "on again", on: Cycle(3), set: {{ "heat": "on" }}),
                Rule(name: "warms", on: While("heat = on"), after: Cycles(3),
                     set: {{ "engine.temp": "nominal" }}),
            ]"#
        ));
        let mut plant = ScriptedPlant::new(&scenario.script);
        let temps: Vec<Option<String>> = (0..8)
            .map(|i| {
                let report = plant.observe(f64::from(i));
                observed(&report, "engine.temp").map(str::to_string)
            })
            .collect();
        let low = Some("low".to_string());
        let nominal = Some("nominal".to_string());
        assert_eq!(
            temps[..6],
            vec![low; 6],
            "the first heating was cut at cycle 2"
        );
        assert_eq!(temps[6], nominal, "3 cycles after it came back at cycle 3");
        assert_eq!(plant.times_fired(3), 2);
    }

    #[test]
    fn a_command_for_no_control_is_refused() {
        let scenario = engine_camera(INITIAL);
        let mut plant = ScriptedPlant::new(&scenario.script);
        plant.observe(0.0);
        assert!(
            plant
                .send(0.0, &[NamedValue::new("engine.temp", "low")])
                .is_err()
        );
        assert!(
            plant
                .send(0.0, &[NamedValue::new("engine.cmd", "warp")])
                .is_err()
        );
    }
}
