//! A model-driven plant (DESIGN.md §11): the plant model itself, sampled, standing in
//! for the hardware. Where a scripted plant plays one story, this one plays the model's own
//! probabilities, so that a Monte Carlo campaign of seeded runs sees faults as often as the
//! model says they happen.
//!
//! Each cycle, from the state of the previous cycle under the command it sent:
//! 1. every component takes one transition, drawn from the distribution Step_TCCA (Figure 6-6)
//!    gives it — the enabled transitions' per-step probabilities of §6.2.2, timed transitions on
//!    the component clock, exactly the numbers mode estimation uses ([`step_tcca`]);
//! 2. a forced fault due by then puts its component in its mode;
//! 3. the observation is drawn among the assignments of the observables that the modes, the
//!    interconnections and the command allow: observables in random order, each given a value
//!    drawn among those keeping the partial assignment consistent with the plant's [`Theory`];
//! 4. with probability `noise`, an observation is replaced by a value drawn from its domain;
//! 5. a numeric observable (the model monitors it) whose value has a law of readings is reported
//!    as readings drawn from that law — a Gaussian around the value's nominal reading, say —
//!    so that the monitor, not the model, turns them back into a value. It is reported as twice
//!    as many readings a cycle as its monitor's persistence (a sensor sampled faster than the
//!    executive cycles): a value that holds through a cycle is confirmed in that cycle even when
//!    one of its readings strays or falls inside a hysteresis band (which reads as the old
//!    value), so the monitor adds no delay the model's timing would have to allow for — a
//!    change confirmed a cycle late can land past a timed transition's window and be diagnosed
//!    as the transition that did not happen — while a lone stray reading is still a glitch. Step 4's noise applies to each reading on its own (with probability
//!    `noise` a reading is of a value drawn among those with a law: an outlier).
//!
//! The theory's answers in steps 1 and 3 depend only on the modes and the command; they are
//! asked once per pair and kept ([`super::model_cache`]), which changes no draw.
//!
//! The generator is ChaCha8 (`chacha20::ChaCha8Rng`), a named portable algorithm: a seed replays
//! the same run on every machine.

use std::sync::Arc;

use chacha20::ChaCha8Rng;
use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_distr::{Distribution, Normal};

use super::latent::{self, Latent};
use super::model_cache::ModelCache;
use crate::executive::NamedValue;
use crate::executive::adapters::{ControlAdapter, MonitorAdapter};
use crate::logic::{ValueId, VarId};
use crate::opsat::{Consistency, Literal, Theory, TheoryError};
use crate::plant::monitor::Reading;
use crate::plant::{
    Commands, ComponentId, ModeKind, Plant, SystemState, chosen_successor, component_distributions,
};

/// How often a drawn combination of modes may contradict the plant's constraints before the
/// plant gives up the step and keeps its modes (see [`ModelPlant::step`]).
const DRAWS: usize = 100;

/// The settings of a model-driven plant.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelPlantConfig {
    /// The generator's seed.
    pub seed: u64,
    /// Faults forced at given times, whatever the model's probabilities.
    pub faults: Vec<ForcedFault>,
    /// The probability that an observation is replaced by a random value of its domain.
    pub noise: f64,
}

impl ModelPlantConfig {
    /// A plant seeded with `seed`, with no forced fault and no noise; the `with_` methods add
    /// them (the embedding API's builder).
    pub fn seeded(seed: u64) -> ModelPlantConfig {
        ModelPlantConfig {
            seed,
            faults: Vec::new(),
            noise: 0.0,
        }
    }

    /// The same with `fault` forced too (read one with [`ForcedFault::parse`]).
    pub fn with_fault(mut self, fault: ForcedFault) -> ModelPlantConfig {
        self.faults.push(fault);
        self
    }

    /// The same with sensor noise `noise`; refused unless it is a probability.
    pub fn with_noise(mut self, noise: f64) -> Result<ModelPlantConfig, String> {
        self.noise = check_noise(noise)?;
        Ok(self)
    }
}

/// `noise` when it is a probability; otherwise the error says so.
pub(super) fn check_noise(noise: f64) -> Result<f64, String> {
    if (0.0..=1.0).contains(&noise) {
        Ok(noise)
    } else {
        Err(format!("noise {noise} is not a probability"))
    }
}

/// `component = mode @ T s`: the component is put in the mode at the first cycle at or after
/// `T`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForcedFault {
    /// The component.
    pub component: ComponentId,
    /// Its mode from then on.
    pub mode: ValueId,
    /// When, seconds.
    pub time: f64,
}

impl ForcedFault {
    /// Reads `component = mode @ T` (`T` in seconds, an optional trailing `s`; the mode one of
    /// the component's fault modes) against `plant`; the error says what is wrong, for the
    /// caller to locate.
    pub fn parse(plant: &Plant, text: &str) -> Result<ForcedFault, String> {
        let shape = || format!("`{text}` is not `component = mode @ time`");
        let (assignment, time) = text.split_once('@').ok_or_else(shape)?;
        let (component, mode) = assignment.split_once('=').ok_or_else(shape)?;
        let (component, mode) = (component.trim(), mode.trim());
        let time = time.trim();
        let time = time.strip_suffix('s').unwrap_or(time).trim();
        let time: f64 = time
            .parse()
            .ok()
            .filter(|t: &f64| t.is_finite() && *t >= 0.0)
            .ok_or_else(|| format!("`{time}` is not a time in seconds"))?;
        let id = plant.component_named(component).ok_or_else(|| {
            let names = plant.components().iter().map(|c| c.name());
            let hint = crate::diagnostic::did_you_mean(component, names)
                .map_or_else(String::new, |n| format!(" (did you mean `{n}`?)"));
            format!("`{component}` is not a component of the plant{hint}")
        })?;
        let value = plant.component(id).mode_named(mode).ok_or_else(|| {
            let names = plant.component(id).modes().iter().map(|m| m.name.as_str());
            let hint = crate::diagnostic::did_you_mean(mode, names)
                .map_or_else(String::new, |n| format!(" (did you mean `{n}`?)"));
            format!("`{mode}` is not a mode of `{component}`{hint}")
        })?;
        // A forced mode is recorded, and its diagnosis timed, as a fault: a nominal one would
        // be neither, so it is refused rather than silently left out of the records.
        let modes = plant.component(id).modes();
        if modes[value.index()].kind != ModeKind::Fault {
            let faults: Vec<String> = modes
                .iter()
                .filter(|m| m.kind == ModeKind::Fault)
                .map(|m| format!("`{}`", m.name))
                .collect();
            return Err(format!(
                "`{mode}` is not a fault mode of `{component}` (its fault modes: {})",
                faults.join(", ")
            ));
        }
        Ok(ForcedFault {
            component: id,
            mode: value,
            time,
        })
    }

    /// The fault when it happens by `end` (a run's last time); otherwise the error says when it
    /// would.
    pub fn by(self, end: f64) -> Result<ForcedFault, String> {
        if self.time > end {
            Err(format!(
                "the fault is forced at {} s, after the end ({end} s)",
                self.time
            ))
        } else {
            Ok(self)
        }
    }
}

/// A component entering a fault mode during a run.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultDrawn {
    /// The component.
    pub component: ComponentId,
    /// The fault mode.
    pub mode: ValueId,
    /// The first cycle at which the plant was in it, seconds.
    pub time: f64,
    /// True when it was forced rather than drawn.
    pub forced: bool,
    /// The first time the plant's observation (before noise) could not have come from the
    /// component in the mode it left — from then on the fault was observable; `None` while it
    /// stayed *latent* (a valve stuck closed while it is closed, a fault of a component that is
    /// off) to the end of the run or until the component left the fault mode. A fault the
    /// plant started in has no mode it left and counts as observable from its first cycle.
    pub revealed: Option<f64>,
}

/// The model-driven plant: a [`MonitorAdapter`] and a [`ControlAdapter`] over a [`Plant`].
pub struct ModelPlant<'p> {
    plant: &'p Plant,
    theory: Theory,
    cache: ModelCache,
    rng: ChaCha8Rng,
    noise: f64,
    /// Forced faults, by time; those before `next_forced` have been applied.
    forced: Vec<ForcedFault>,
    next_forced: usize,
    state: Option<SystemState>,
    last_time: f64,
    commands: Commands,
    faults: Vec<FaultDrawn>,
    /// The faults that nothing observed has shown yet.
    latent: Vec<Latent>,
    /// Why the last step could not be taken, reported by the next [`ControlAdapter::send`].
    failure: Option<String>,
}

impl<'p> ModelPlant<'p> {
    /// A plant playing `plant`'s model with `config`.
    pub fn new(plant: &'p Plant, config: &ModelPlantConfig) -> Result<Self, TheoryError> {
        let mut forced = config.faults.clone();
        forced.sort_by(|a, b| a.time.total_cmp(&b.time));
        Ok(ModelPlant {
            theory: plant.theory()?,
            cache: ModelCache::default(),
            rng: ChaCha8Rng::seed_from_u64(config.seed),
            noise: config.noise,
            forced,
            next_forced: 0,
            state: None,
            last_time: 0.0,
            commands: Commands::idle(plant),
            faults: Vec::new(),
            latent: Vec::new(),
            failure: None,
            plant,
        })
    }

    /// Every component's mode now (`None` before the first observation).
    pub fn modes(&self) -> Option<&[ValueId]> {
        self.state.as_ref().map(|s| &*s.modes)
    }

    /// The faults so far, oldest first.
    pub fn faults(&self) -> &[FaultDrawn] {
        &self.faults
    }

    /// True when no forced fault is still to come before `end`: what the plant does from then
    /// on is the model's alone.
    pub fn is_quiet(&self, end: f64) -> bool {
        self.forced[self.next_forced..]
            .iter()
            .all(|f| f.time > end + super::script::TIME_EPSILON)
    }

    /// The state at `time`: drawn from the initial distributions at the first cycle, then by one
    /// step of the TCCA from the previous cycle's.
    fn advance(&mut self, time: f64) -> SystemState {
        let Some(state) = self.state.take() else {
            let modes = self.draw_consistent(|plant, rng| {
                plant
                    .components()
                    .iter()
                    .map(|c| initial_mode(c.initial(), rng))
                    .collect()
            });
            return SystemState::entered_at(self.plant, modes.unwrap_or_default(), time);
        };
        match self.step(&state, time) {
            Ok(Some(next)) => next,
            Ok(None) => state,
            Err(message) => {
                self.failure = Some(message);
                state
            }
        }
    }

    /// One step of the TCCA (Figure 6-6) from the previous cycle to `time`, each component's
    /// transition drawn from its distribution. Figure 6-7 allows only next states whose modes
    /// are consistent together; a draw that is not is drawn again (rejection sampling, which
    /// conditions the step's distribution on consistency), and after [`DRAWS`] failures the
    /// plant keeps its modes (`None`).
    fn step(&mut self, state: &SystemState, time: f64) -> Result<Option<SystemState>, String> {
        let enabled =
            self.cache
                .enabled(self.plant, &mut self.theory, &state.modes, &self.commands)?;
        let choices = component_distributions(self.plant, state, enabled, self.last_time, time);
        for _ in 0..DRAWS {
            let rng = &mut self.rng;
            let next = chosen_successor(state, &choices, time, |_, distribution| {
                draw(distribution.iter().map(|&(_, p)| p), rng)
            });
            if self.consistent_modes(&next.modes) {
                return Ok(Some(next));
            }
        }
        Ok(None)
    }

    /// Modes drawn by `draw_modes` until they are consistent, at most [`DRAWS`] times.
    fn draw_consistent(
        &mut self,
        draw_modes: impl Fn(&Plant, &mut ChaCha8Rng) -> Vec<ValueId>,
    ) -> Option<Vec<ValueId>> {
        let mut last = None;
        for _ in 0..DRAWS {
            let modes = draw_modes(self.plant, &mut self.rng);
            if self.consistent_modes(&modes) {
                return Some(modes);
            }
            last = Some(modes);
        }
        last
    }

    fn consistent_modes(&mut self, modes: &[ValueId]) -> bool {
        self.cache
            .modes_consistent(self.plant, &mut self.theory, modes)
    }

    /// Puts the components of the forced faults due at `time` in their modes; their clocks
    /// start now.
    fn force(&mut self, state: &mut SystemState, time: f64) {
        while let Some(fault) = self.forced.get(self.next_forced) {
            if fault.time > time + super::script::TIME_EPSILON {
                break;
            }
            let c = fault.component.index();
            if state.modes[c] != fault.mode {
                Arc::make_mut(&mut state.modes)[c] = fault.mode;
                Arc::make_mut(&mut state.clock_starts)[c] = Some(time);
            }
            self.next_forced += 1;
        }
    }

    /// Records the components that entered a fault mode between `before` and `after`.
    fn record_faults(&mut self, before: Option<&SystemState>, after: &[ValueId], time: f64) {
        for (id, component) in self.plant.component_ids() {
            let mode = after[id.index()];
            let entered = before.is_none_or(|b| b.modes[id.index()] != mode);
            if entered && component.mode(mode).kind == ModeKind::Fault {
                let forced = self.forced[..self.next_forced]
                    .iter()
                    .any(|f| f.component == id && f.mode == mode && f.time <= time);
                if let Some(before) = before {
                    self.latent.push(Latent::new(self.faults.len(), id, before));
                }
                self.faults.push(FaultDrawn {
                    component: id,
                    mode,
                    time,
                    forced,
                    revealed: before.is_none().then_some(time),
                });
            }
        }
    }

    /// Step 3 of the module documentation: a consistent assignment of every observable, drawn.
    /// The command of the previous cycle is assumed too when it fits the modes (a mode may say
    /// nothing about it, or contradict it, as a stuck valve does). From the cached assignments
    /// when the modes leave few open; otherwise each value is checked with the theory.
    fn draw_observation(&mut self, modes: &[ValueId]) -> Vec<(VarId, ValueId)> {
        let observations =
            self.cache
                .observations(self.plant, &mut self.theory, modes, &self.commands);
        if let Some(assignments) = &observations.assignments {
            let mut candidates: Vec<&[ValueId]> = assignments.iter().map(Vec::as_slice).collect();
            return draw_in_order(self.plant, &mut self.rng, |position, _, value| {
                let agrees = candidates.iter().any(|a| a[position] == value);
                if agrees {
                    candidates.retain(|a| a[position] == value);
                }
                agrees
            });
        }
        let mut assumed = observations.assumed.clone();
        let theory = &mut self.theory;
        draw_in_order(self.plant, &mut self.rng, |_, var, value| {
            assumed.push(Literal::Is(var, value));
            let consistent = theory.consistent(&assumed) == Consistency::Consistent;
            if !consistent {
                assumed.pop();
            }
            consistent
        })
    }

    /// Steps every latent fault's nominal counterfactual from `before` to `now` and marks the
    /// faults `observation` (drawn before noise) reveals ([`super::latent`]).
    fn reveal(
        &mut self,
        before: &SystemState,
        now: &SystemState,
        observation: &[(VarId, ValueId)],
        time: f64,
    ) {
        let mut latent = std::mem::take(&mut self.latent);
        let mut world = latent::World {
            plant: self.plant,
            theory: &mut self.theory,
            cache: &mut self.cache,
            commands: &self.commands,
        };
        latent.retain_mut(|entry| {
            let fault = &self.faults[entry.fault];
            match entry.step(
                &mut world,
                fault,
                (before, now),
                observation,
                (self.last_time, time),
            ) {
                latent::Verdict::Latent => true,
                latent::Verdict::Revealed => {
                    self.faults[entry.fault].revealed = Some(time);
                    false
                }
                latent::Verdict::Over => false,
            }
        });
        self.latent = latent;
    }

    /// Step 4: each observation replaced, with probability `noise`, by a value of its domain.
    fn add_noise(&mut self, observation: &mut [(VarId, ValueId)]) {
        if self.noise <= 0.0 {
            return;
        }
        for (var, value) in observation {
            if self.is_read(*var) {
                continue; // noise per reading (step 5)
            }
            if self.rng.random_bool(self.noise.min(1.0)) {
                let size = self.plant.table().variable(*var).domain_size() as u32;
                *value = ValueId(self.rng.random_range(0..size));
            }
        }
    }
}

/// The observables in random order, each given the first of its values, in random order, that
/// `accept(position, variable, value)` takes — it takes a value that keeps the partial
/// assignment consistent, and keeps it — or none when no value is taken. The generator is used
/// the same way whatever `accept` answers: the shuffles depend only on the lengths.
fn draw_in_order(
    plant: &Plant,
    rng: &mut ChaCha8Rng,
    mut accept: impl FnMut(usize, VarId, ValueId) -> bool,
) -> Vec<(VarId, ValueId)> {
    let observables = plant.observables();
    let mut order: Vec<usize> = (0..observables.len()).collect();
    order.shuffle(rng);
    let mut drawn = Vec::with_capacity(order.len());
    for position in order {
        let var = observables[position];
        let size = plant.table().variable(var).domain_size() as u32;
        let mut values: Vec<ValueId> = (0..size).map(ValueId).collect();
        values.shuffle(rng);
        if let Some(value) = values
            .into_iter()
            .find(|&value| accept(position, var, value))
        {
            drawn.push((var, value));
        }
    }
    drawn
}

/// A mode drawn from a component's initial distribution (one probability per mode).
fn initial_mode(initial: &[f64], rng: &mut ChaCha8Rng) -> ValueId {
    ValueId(draw(initial.iter().copied(), rng) as u32)
}

/// An index drawn with probability proportional to its weight (the last one should rounding
/// leave the draw past the total).
fn draw(weights: impl Iterator<Item = f64> + Clone, rng: &mut ChaCha8Rng) -> usize {
    let total: f64 = weights.clone().sum();
    let mut u = rng.random::<f64>() * total;
    let mut last = 0;
    for (i, w) in weights.enumerate() {
        if u < w {
            return i;
        }
        u -= w;
        last = i;
    }
    last
}

impl MonitorAdapter for ModelPlant<'_> {
    fn observe(&mut self, time: f64) -> Vec<NamedValue> {
        let before = self.state.clone();
        let mut state = self.advance(time);
        self.force(&mut state, time);
        self.record_faults(before.as_ref(), &state.modes, time);
        let mut observation = self.draw_observation(&state.modes);
        if let Some(before) = &before {
            self.reveal(before, &state, &observation, time);
        }
        self.add_noise(&mut observation);
        self.state = Some(state);
        self.last_time = time;
        observation.sort_unstable();
        let mut report = Vec::with_capacity(observation.len());
        for (x, v) in observation {
            self.report(x, v, &mut report);
        }
        report
    }
}

impl ModelPlant<'_> {
    /// True when `x` is reported as readings (its monitor gives laws of readings).
    fn is_read(&self, x: VarId) -> bool {
        (self.plant.monitor_of(x)).is_some_and(|m| !self.plant.monitors()[m].readings.is_empty())
    }

    /// Step 5: `x = v` as reported — as readings when `x` is read: twice as many as its
    /// monitor's persistence, each of `v` or, with probability `noise`, of a value drawn among those
    /// with a law of readings (a noisy sensor reads wrong numbers, not a validity flag), and
    /// drawn from that value's law (`v` without one is reported as itself).
    fn report(&mut self, x: VarId, v: ValueId, report: &mut Vec<NamedValue>) {
        let monitor = match self.plant.monitor_of(x) {
            Some(m) if self.is_read(x) => &self.plant.monitors()[m],
            _ => {
                report.push(NamedValue::of(self.plant, x, v));
                return;
            }
        };
        let read = monitor.readings.len();
        for _ in 0..monitor.persistence.saturating_mul(2) {
            let value = if self.noise > 0.0 && self.rng.random_bool(self.noise.min(1.0)) {
                monitor.readings[self.rng.random_range(0..read)].0
            } else {
                v
            };
            let number = match monitor.reading_of(value) {
                Some(Reading::Gaussian { mean, sd }) => match Normal::new(mean, sd) {
                    Ok(normal) => normal.sample(&mut self.rng),
                    // The loader refuses a spread that is not finite and positive.
                    Err(_) => mean,
                },
                Some(Reading::Uniform { lower, upper }) => self.rng.random_range(lower..upper),
                None => {
                    report.push(NamedValue::of(self.plant, x, value));
                    continue;
                }
            };
            report.push(NamedValue::new(
                self.plant.table().variable(x).name(),
                number,
            ));
        }
    }
}

impl ControlAdapter for ModelPlant<'_> {
    fn send(&mut self, _time: f64, command: &[NamedValue]) -> Result<(), String> {
        if let Some(failure) = self.failure.take() {
            return Err(failure);
        }
        let table = self.plant.table();
        let issued = command
            .iter()
            .map(|c| {
                let var = table
                    .variable_id(&c.variable)
                    .ok_or_else(|| format!("`{}` is not a variable of the plant", c.variable))?;
                let value = (c.value.symbol())
                    .and_then(|name| table.variable(var).value(name))
                    .ok_or_else(|| format!("`{c}`: no such value"))?;
                Ok((var, value))
            })
            .collect::<Result<Vec<_>, String>>()?;
        self.commands = Commands::new(self.plant, &issued).map_err(|e| e.to_string())?;
        Ok(())
    }
}
