//! Random plant models and runs, shared by the estimation property tests
//! (`tests/estimation_properties.rs`) and the benchmarks (`benches/estimation.rs`).
//!
//! A [`RandomPlant`] is described by plain numbers and rendered as a RON model, so every plant
//! also goes through the loader. Components `c0, c1, …` have 2–4 modes (the last sometimes a
//! fault, unconstrained or stuck low), an output `out` (observable or hidden), optionally a
//! command input `cmd` and an input `in` wired to the previous component's `out`; transitions
//! are commanded, guarded on the input, timed (uniform, fixed, exponential, Gaussian) and
//! faults (per cycle or rate), with probabilities that always keep validation happy.
//! [`RandomRun`] is a command schedule and the uniforms that drive a simulated true trajectory;
//! observations are drawn consistent with the true state (sometimes replaced by noise).
#![allow(dead_code)] // each includer uses a different part

use kairos::diagnostic::Source;
use kairos::estimation::{ModeEstimator, Update};
use kairos::logic::{ValueId, VarId};
use kairos::opsat::{Consistency, Literal, Theory};
use kairos::plant::{Commands, Observation, Plant, SystemState, step_tcca};
use proptest::prelude::*;

/// A nominal mode's behaviour.
#[derive(Debug, Clone, Copy)]
pub enum Behaviour {
    /// `out = lo`
    Low,
    /// `out = hi`
    High,
    /// `out = in` (only with an input)
    Follow,
    /// unconstrained
    Free,
    /// `in = hi and out = hi` (only with an input; else unconstrained): a mode that needs its
    /// supply, so that it and a low upstream output violate the connection together (the broad
    /// generator only).
    Powered,
}

/// When a timed transition fires.
#[derive(Debug, Clone, Copy)]
pub enum Delay {
    /// `Uniform(lower, lower + width)`
    Uniform(f64, f64),
    /// `Fixed(d)`
    Fixed(f64),
    /// `Exponential(rate)`
    Exponential(f64),
    /// `Gaussian(mean, sd)`
    Gaussian(f64, f64),
}

/// What enables a transition.
#[derive(Debug, Clone, Copy)]
pub enum Trigger {
    /// `cmd = a` (0) or `cmd = b` (1).
    Command(usize),
    /// `in = hi`.
    Input,
    /// A delay on the clock (guarded by `cmd = none` when the component has commands).
    Timed(Delay),
}

/// A nominal transition: from, to, trigger, and its share of what faults leave (0.5–1).
#[derive(Debug, Clone, Copy)]
pub struct TransitionSpec {
    /// Source mode.
    pub from: usize,
    /// Target mode.
    pub to: usize,
    /// What enables it.
    pub trigger: Trigger,
    /// Fraction of the probability the faults leave.
    pub share: f64,
}

/// How a component fails.
#[derive(Debug, Clone, Copy)]
pub enum FaultSpec {
    /// `probability: p` per cycle into the fault mode.
    PerCycle(f64),
    /// `rate: r` per second.
    Rate(f64),
}

/// One component.
#[derive(Debug, Clone)]
pub struct ComponentSpec {
    /// Nominal modes' behaviours (1–4 of them).
    pub behaviours: Vec<Behaviour>,
    /// A fault mode after the nominal ones, unconstrained (`true`) or stuck low (`false`).
    pub fault: Option<(bool, FaultSpec)>,
    /// With a fault: a second fault mode of the other kind after it, entered by the same law
    /// from every nominal mode and from the first fault, which it can also return to (fault to
    /// fault, as Livingstone 2's breakers go between tripped, blown and unknown).
    pub fault_to_fault: bool,
    /// Has a `cmd` control.
    pub commanded: bool,
    /// `out` is observable.
    pub observed: bool,
    /// `in` is wired to the previous component's `out`.
    pub coupled: bool,
    /// Nominal transitions (invalid combinations are dropped when rendering).
    pub transitions: Vec<TransitionSpec>,
    /// Initial probability of mode 0 (the rest on mode 1).
    pub initial: f64,
}

/// A random plant.
#[derive(Debug, Clone)]
pub struct RandomPlant {
    /// The components, in a chain.
    pub components: Vec<ComponentSpec>,
}

fn number(x: f64) -> String {
    format!("{x:?}")
}

impl ComponentSpec {
    fn modes(&self) -> usize {
        self.behaviours.len() + self.faults()
    }

    /// How many fault modes (0–2).
    fn faults(&self) -> usize {
        match self.fault {
            Some(_) if self.fault_to_fault => 2,
            Some(_) => 1,
            None => 0,
        }
    }

    /// The probability per cycle of leaving a mode into the faults.
    fn fault_probability(&self) -> f64 {
        match self.fault {
            Some((_, FaultSpec::PerCycle(p))) => p * self.faults() as f64,
            _ => 0.0,
        }
    }

    /// The transitions that keep the model valid: distinct triggers per source, no self-loops,
    /// inputs only when coupled, commands only when commanded.
    fn valid_transitions(&self) -> Vec<TransitionSpec> {
        let nominal = self.behaviours.len();
        let mut kept: Vec<TransitionSpec> = Vec::new();
        for t in &self.transitions {
            let (from, to) = (t.from % nominal, t.to % self.modes().max(1));
            let to = if to >= nominal {
                (from + 1) % nominal
            } else {
                to
            };
            if from == to {
                continue;
            }
            let usable = match t.trigger {
                Trigger::Command(_) => self.commanded,
                Trigger::Input => self.coupled,
                Trigger::Timed(_) => true,
            };
            let same_kind = |k: &TransitionSpec| {
                k.from == from
                    && match (k.trigger, t.trigger) {
                        (Trigger::Command(a), Trigger::Command(b)) => a == b,
                        (Trigger::Command(_), _) | (_, Trigger::Command(_)) => false,
                        _ => true,
                    }
            };
            if usable && !kept.iter().any(same_kind) {
                kept.push(TransitionSpec { from, to, ..*t });
            }
        }
        kept
    }

    fn render(&self, i: usize) -> String {
        let name = format!("c{i}");
        let mut attributes = vec![format!("\"out\": [\"lo\", \"hi\"]")];
        if self.coupled {
            attributes.push("\"in\": [\"lo\", \"hi\"]".into());
        }
        if self.commanded {
            attributes.push("\"cmd\": [\"none\", \"a\", \"b\"]".into());
        }
        let mut modes = Vec::new();
        for (m, behaviour) in self.behaviours.iter().enumerate() {
            let constraint = match behaviour {
                Behaviour::Low => format!("{name}.out = lo"),
                Behaviour::High => format!("{name}.out = hi"),
                Behaviour::Follow if self.coupled => format!("{name}.out = {name}.in"),
                Behaviour::Powered if self.coupled => {
                    format!("{name}.in = hi and {name}.out = hi")
                }
                _ => "true".into(),
            };
            modes.push(format!(
                "Mode(name: \"m{m}\", constraint: \"{constraint}\")"
            ));
        }
        let nominal = self.behaviours.len();
        if let Some((unconstrained, _)) = self.fault {
            for (k, unconstrained) in [unconstrained, !unconstrained]
                .into_iter()
                .take(self.faults())
                .enumerate()
            {
                let constraint = if unconstrained {
                    "true".to_string()
                } else {
                    format!("{name}.out = lo")
                };
                modes.push(format!(
                    "Mode(name: \"m{}\", kind: Fault, constraint: \"{constraint}\")",
                    nominal + k
                ));
            }
        }
        let left = 1.0 - self.fault_probability();
        let mut transitions = Vec::new();
        for t in self.valid_transitions() {
            // One mode's transitions never overlap: commands differ, and the input-guarded or
            // timed one (at most one per mode) waits for `cmd = none`.
            let p = number(t.share * left);
            let idle = if self.commanded {
                format!(" and {name}.cmd = none")
            } else {
                String::new()
            };
            let (guard, law) = match t.trigger {
                Trigger::Command(c) => (
                    format!("{name}.cmd = {}", ["a", "b"][c % 2]),
                    format!("probability: {p}"),
                ),
                Trigger::Input => (format!("{name}.in = hi{idle}"), format!("probability: {p}")),
                Trigger::Timed(delay) => {
                    let guard = format!("true{idle}");
                    let after = match delay {
                        Delay::Uniform(l, w) => {
                            format!("Uniform({}, {})", number(l), number(l + w))
                        }
                        Delay::Fixed(d) => format!("Fixed({})", number(d)),
                        Delay::Exponential(r) => format!("Exponential({})", number(r)),
                        Delay::Gaussian(m, sd) => {
                            format!("Gaussian({}, {})", number(m), number(sd))
                        }
                    };
                    (guard, format!("after: {after}, probability: {p}"))
                }
            };
            transitions.push(format!(
                "(from: \"m{}\", to: \"m{}\", guard: \"{guard}\", {law})",
                t.from, t.to
            ));
        }
        if let Some((_, law)) = self.fault {
            let law = match law {
                FaultSpec::PerCycle(p) => format!("probability: {}", number(p)),
                FaultSpec::Rate(r) => format!("rate: {}", number(r)),
            };
            transitions.push(format!("(from: \"*\", to: \"m{nominal}\", {law})"));
            if self.fault_to_fault {
                let (first, second) = (nominal, nominal + 1);
                for (from, to) in [("*", second), (&*format!("m{first}"), second)] {
                    transitions.push(format!("(from: \"{from}\", to: \"m{to}\", {law})"));
                }
                transitions.push(format!("(from: \"m{second}\", to: \"m{first}\", {law})"));
            }
        }
        let initial = if self.initial >= 1.0 || nominal < 2 {
            "{ \"m0\": 1.0 }".to_string()
        } else {
            format!(
                "{{ \"m0\": {}, \"m1\": {} }}",
                number(self.initial),
                number(1.0 - self.initial)
            )
        };
        format!(
            "Component(name: \"{name}\", attributes: {{ {} }}, modes: [{}], initial: {initial}, transitions: [{}])",
            attributes.join(", "),
            modes.join(", "),
            transitions.join(", ")
        )
    }
}

impl RandomPlant {
    /// The model as RON text.
    pub fn ron(&self) -> String {
        let components: Vec<String> = self
            .components
            .iter()
            .enumerate()
            .map(|(i, c)| c.render(i))
            .collect();
        let controls: Vec<String> = self
            .components
            .iter()
            .enumerate()
            .filter(|(_, c)| c.commanded)
            .map(|(i, _)| format!("\"c{i}.cmd\": \"none\""))
            .collect();
        let mut observables: Vec<String> = self
            .components
            .iter()
            .enumerate()
            .filter(|(_, c)| c.observed)
            .map(|(i, _)| format!("\"c{i}.out\""))
            .collect();
        if observables.is_empty() {
            observables.push("\"c0.out\"".into());
        }
        let connections: Vec<String> = self
            .components
            .iter()
            .enumerate()
            .filter(|(i, c)| *i > 0 && c.coupled)
            .map(|(i, _)| format!("\"c{}.out = c{i}.in\"", i - 1))
            .collect();
        format!(
            "Plant(name: \"random\", components: [{}], controls: {{ {} }}, observables: [{}], connections: [{}])",
            components.join(",\n"),
            controls.join(", "),
            observables.join(", "),
            connections.join(", ")
        )
    }

    /// The loaded plant, or `None` when validation refuses it (the generator cannot foresee
    /// every guard that coupling makes impossible, e.g. `in = hi` below a component whose
    /// output is always `lo`).
    pub fn plant(&self) -> Option<Plant> {
        Plant::load(&Source::new("random.ron", self.ron())).ok()
    }
}

fn delay() -> impl Strategy<Value = Delay> {
    prop_oneof![
        (
            prop::sample::select(vec![0.0, 0.5, 2.0]),
            prop::sample::select(vec![0.5, 1.0, 3.0])
        )
            .prop_map(|(l, w)| Delay::Uniform(l, w)),
        prop::sample::select(vec![0.5, 1.5]).prop_map(Delay::Fixed),
        prop::sample::select(vec![0.5, 2.0]).prop_map(Delay::Exponential),
        (
            prop::sample::select(vec![1.0, 3.0]),
            prop::sample::select(vec![0.3, 1.0])
        )
            .prop_map(|(m, sd)| Delay::Gaussian(m, sd)),
    ]
}

fn transition() -> impl Strategy<Value = TransitionSpec> {
    let trigger = prop_oneof![
        (0usize..2).prop_map(Trigger::Command),
        Just(Trigger::Input),
        delay().prop_map(Trigger::Timed),
    ];
    (
        0usize..4,
        0usize..4,
        trigger,
        prop::sample::select(vec![0.5, 0.8, 0.95, 1.0]),
    )
        .prop_map(|(from, to, trigger, share)| TransitionSpec {
            from,
            to,
            trigger,
            share,
        })
}

fn component() -> impl Strategy<Value = ComponentSpec> {
    let behaviour = prop_oneof![
        Just(Behaviour::Low),
        Just(Behaviour::High),
        Just(Behaviour::Follow),
        Just(Behaviour::Free),
    ];
    let fault = prop::option::weighted(
        0.8,
        (
            any::<bool>(),
            prop_oneof![
                prop::sample::select(vec![0.001, 0.005, 0.02]).prop_map(FaultSpec::PerCycle),
                prop::sample::select(vec![0.001, 0.01]).prop_map(FaultSpec::Rate),
            ],
        ),
    );
    (
        prop::collection::vec(behaviour, 1..=3),
        fault,
        prop::bool::weighted(0.6),
        prop::bool::weighted(0.7),
        any::<bool>(),
        prop::collection::vec(transition(), 0..=4),
        prop::sample::select(vec![1.0, 0.9, 0.7]),
    )
        .prop_map(
            |(behaviours, fault, commanded, observed, coupled, transitions, initial)| {
                ComponentSpec {
                    behaviours,
                    fault,
                    fault_to_fault: false,
                    commanded,
                    observed,
                    coupled,
                    transitions,
                    initial,
                }
            },
        )
}

/// A component of the broad generator: powered modes that can violate the
/// connections, more transitions (every timing kind), faults by probability and by rate up to
/// 0.05/s, fewer observables and more coupling, so that beliefs spread over many clock-distinct
/// system states.
fn broad_component() -> impl Strategy<Value = ComponentSpec> {
    let behaviour = prop_oneof![
        Just(Behaviour::Low),
        Just(Behaviour::High),
        Just(Behaviour::Follow),
        Just(Behaviour::Free),
        Just(Behaviour::Powered),
    ];
    let fault = prop::option::weighted(
        0.9,
        (
            any::<bool>(),
            prop_oneof![
                prop::sample::select(vec![0.001, 0.005, 0.02, 0.05]).prop_map(FaultSpec::PerCycle),
                prop::sample::select(vec![0.001, 0.01, 0.05]).prop_map(FaultSpec::Rate),
            ],
        ),
    );
    (
        prop::collection::vec(behaviour, 2..=3),
        fault,
        prop::bool::weighted(0.6),
        prop::bool::weighted(0.5),
        prop::bool::weighted(0.8),
        prop::collection::vec(transition(), 2..=6),
        prop::sample::select(vec![1.0, 0.9, 0.7, 0.5]),
    )
        .prop_map(
            |(behaviours, fault, commanded, observed, coupled, transitions, initial)| {
                ComponentSpec {
                    behaviours,
                    fault,
                    fault_to_fault: false,
                    commanded,
                    observed,
                    coupled,
                    transitions,
                    initial,
                }
            },
        )
}

/// Broad random plants of 2..=`max_components` components (see [`broad_component`]).
pub fn broad_plant(max_components: usize) -> impl Strategy<Value = RandomPlant> {
    prop::collection::vec(broad_component(), 2..=max_components.max(2)).prop_map(
        |mut components| {
            if let Some(first) = components.first_mut() {
                first.coupled = false;
            }
            RandomPlant { components }
        },
    )
}

/// Broad random plants (see [`broad_plant`]) whose faulty components have, with probability
/// 0.6, a second fault mode with fault-to-fault transitions ([`ComponentSpec::fault_to_fault`]).
pub fn fault_to_fault_plant(max_components: usize) -> impl Strategy<Value = RandomPlant> {
    prop::collection::vec(
        (broad_component(), prop::bool::weighted(0.6)),
        2..=max_components.max(2),
    )
    .prop_map(|components| {
        let mut components: Vec<ComponentSpec> = components
            .into_iter()
            .map(|(mut c, second)| {
                c.fault_to_fault = second && c.fault.is_some();
                c
            })
            .collect();
        if let Some(first) = components.first_mut() {
            first.coupled = false;
        }
        RandomPlant { components }
    })
}

/// Random plants of 1..=`max_components` components (2–4 modes each).
pub fn random_plant(max_components: usize) -> impl Strategy<Value = RandomPlant> {
    prop::collection::vec(component(), 1..=max_components).prop_map(|mut components| {
        if let Some(first) = components.first_mut() {
            first.coupled = false;
        }
        RandomPlant { components }
    })
}

/// A run: per step, a period, a command choice per component (0 none, 1 a, 2 b) and uniforms
/// that drive the simulation and the observation.
#[derive(Debug, Clone)]
pub struct RandomRun {
    /// Per step: (period, commands, uniforms, noisy observation?).
    pub steps: Vec<(f64, Vec<usize>, Vec<f64>, bool)>,
    /// Uniforms for the initial state.
    pub start: Vec<f64>,
    /// Per step, whether nothing at all is observed after it (missing: every step observes
    /// something, each observable with probability 0.8).
    pub blind: Vec<bool>,
}

/// Runs of up to `max_steps` steps for plants of up to `max_components` components.
pub fn random_run(max_components: usize, max_steps: usize) -> impl Strategy<Value = RandomRun> {
    runs(max_components, 2, max_steps)
}

/// Runs of `min_steps..=max_steps` steps for plants of up to `max_components` components.
pub fn runs(
    max_components: usize,
    min_steps: usize,
    max_steps: usize,
) -> impl Strategy<Value = RandomRun> {
    let uniforms = prop::collection::vec(0.0..1.0f64, 3 * max_components);
    let step = (
        prop::sample::select(vec![0.1, 0.4, 1.0, 2.5]),
        prop::collection::vec(
            prop::sample::select(vec![0usize, 0, 0, 1, 2]),
            max_components,
        ),
        uniforms.clone(),
        prop::bool::weighted(0.1),
    );
    (prop::collection::vec(step, min_steps..=max_steps), uniforms).prop_map(|(steps, start)| {
        RandomRun {
            steps,
            start,
            blind: Vec::new(),
        }
    })
}

/// Runs as [`runs`] gives them whose steps observe nothing with probability `blind`: partial
/// observation as Livingstone 2's scripts have it, a few observables on some steps only.
pub fn sparse_runs(
    max_components: usize,
    min_steps: usize,
    max_steps: usize,
    blind: f64,
) -> impl Strategy<Value = RandomRun> {
    (
        runs(max_components, min_steps, max_steps),
        prop::collection::vec(prop::bool::weighted(blind), max_steps),
    )
        .prop_map(|(run, blind)| RandomRun { blind, ..run })
}

/// One simulated cycle of a run: the control action before it, the time and the observation.
pub struct Cycle {
    /// μ(i), issued before this cycle.
    pub commands: Commands,
    /// t(i+1).
    pub time: f64,
    /// o(i+1).
    pub observation: Observation,
}

impl Cycle {
    /// `estimator`'s update from `last` through this cycle (the runs are valid input: a refusal
    /// is a test failure).
    pub fn update(
        &self,
        estimator: &mut dyn ModeEstimator,
        plant: &Plant,
        theory: &mut Theory,
        last: &Update,
    ) -> Update {
        estimator
            .update(
                plant,
                theory,
                &last.belief,
                &self.commands,
                &self.observation,
                self.time,
            )
            .expect("an estimation update")
    }
}

fn sample(distribution: &[(ValueId, f64)], u: f64) -> usize {
    let total: f64 = distribution.iter().map(|(_, p)| p).sum();
    let mut acc = 0.0;
    for (i, (_, p)) in distribution.iter().enumerate() {
        acc += p / total;
        if u < acc {
            return i;
        }
    }
    distribution.len().saturating_sub(1)
}

/// An observation of the true `modes`: each observable read with probability 0.8, its value
/// drawn at random among those consistent with the state and the values drawn so far; `noisy`
/// draws values with no regard for the state (possibly inconsistent with every state).
fn observe(
    plant: &Plant,
    theory: &mut Theory,
    modes: &[ValueId],
    uniforms: &[f64],
    noisy: bool,
) -> Observation {
    let mut assumptions: Vec<Literal> = plant
        .components()
        .iter()
        .zip(modes)
        .map(|(c, &m)| Literal::Is(c.mode_var(), m))
        .collect();
    let mut observed: Vec<(VarId, ValueId)> = Vec::new();
    for (i, &x) in plant.observables().iter().enumerate() {
        let u = uniforms.get(2 * i).copied().unwrap_or(0.5);
        if u > 0.8 {
            continue;
        }
        let v = uniforms.get(2 * i + 1).copied().unwrap_or(0.5);
        let size = plant.table().variable(x).domain_size();
        let first = ValueId(((v * size as f64) as usize).min(size - 1) as u32);
        let value = if noisy {
            first
        } else {
            let mut chosen = first;
            for k in 0..size {
                let candidate = ValueId(((first.index() + k) % size) as u32);
                let mut trial = assumptions.clone();
                trial.push(Literal::Is(x, candidate));
                if theory.consistent(&trial) == Consistency::Consistent {
                    chosen = candidate;
                    break;
                }
            }
            chosen
        };
        assumptions.push(Literal::Is(x, value));
        observed.push((x, value));
    }
    Observation::new(plant, &observed).unwrap_or_default()
}

impl RandomRun {
    /// Simulates the run on `plant` from a true initial state, returning the initial
    /// observation and the cycles.
    pub fn simulate(&self, plant: &Plant, theory: &mut Theory) -> (Observation, Vec<Cycle>) {
        let initial: Vec<ValueId> = plant
            .components()
            .iter()
            .enumerate()
            .map(|(c, component)| {
                let distribution: Vec<(ValueId, f64)> = component
                    .initial()
                    .iter()
                    .enumerate()
                    .map(|(m, &p)| (ValueId(m as u32), p))
                    .collect();
                distribution[sample(&distribution, self.start.get(c).copied().unwrap_or(0.5))].0
            })
            .collect();
        let mut state = SystemState::entered_at(plant, initial, 0.0);
        let first = observe(plant, theory, &state.modes, &self.start, false);
        let controls: Vec<VarId> = plant.controls().iter().map(|c| c.var).collect();
        let mut time = 0.0;
        let mut cycles = Vec::new();
        for (i, (period, commands, uniforms, noisy)) in self.steps.iter().enumerate() {
            let issued: Vec<(VarId, ValueId)> = controls
                .iter()
                .zip(commands)
                .map(|(&x, &v)| (x, ValueId(v as u32)))
                .collect();
            let commands = Commands::new(plant, &issued).unwrap_or_else(|_| Commands::idle(plant));
            let next = step_tcca(
                plant,
                theory,
                &state,
                &commands,
                time,
                time + period,
                |c, d| sample(d, uniforms.get(c.index()).copied().unwrap_or(0.5)),
            )
            .expect("step");
            time += period;
            let observation = if self.blind.get(i).copied().unwrap_or(false) {
                Observation::none()
            } else {
                observe(
                    plant,
                    theory,
                    &next.modes,
                    &uniforms[plant.components().len().min(uniforms.len())..],
                    *noisy,
                )
            };
            state = next;
            cycles.push(Cycle {
                commands,
                time,
                observation,
            });
        }
        (first, cycles)
    }
}

/// Does `theory` find `modes` consistent with `observation`?
pub fn consistent_with(
    plant: &Plant,
    theory: &mut Theory,
    modes: &[ValueId],
    observation: &Observation,
) -> bool {
    let mut assumptions: Vec<Literal> = plant
        .components()
        .iter()
        .zip(modes)
        .map(|(c, &m)| Literal::Is(c.mode_var(), m))
        .collect();
    assumptions.extend(observation.values().iter().map(|&(x, v)| Literal::Is(x, v)));
    theory.consistent(&assumptions) == Consistency::Consistent
}
