//! Running a scenario: the executive against the scripted plant, cycle by cycle, with the
//! expectations checked as it goes.

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::Scenario;
use super::expect::{Checker, Names};
use super::expectation::Verdict;
use super::model_plant::{FaultDrawn, ModelPlant};
use super::script::{PlantEvent, ScriptedPlant, TIME_EPSILON};
use crate::executive::adapters::{Clock, ControlAdapter, MonitorAdapter, SimulatedClock};
use crate::executive::{
    BuildError, Event, EventKind, Executive, NamedValue, Retention, Step, StepError, Timelines,
};
use crate::logic::ValueId;

/// What one cycle of a run showed: for the mission log, the trace and benchmarks.
#[derive(Debug)]
pub struct CycleRecord<'a> {
    /// The executive's cycle.
    pub step: &'a Step,
    /// The observation the plant reported for it.
    pub observation: &'a [NamedValue],
    /// What the scripted plant did in the cycle (rules fired, effects applied).
    pub plant_events: &'a [PlantEvent],
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The end time was reached.
    EndTime,
    /// The program completed, the plant is in its intended configuration, the script has
    /// nothing pending and every eventual expectation has been shown: nothing more can happen.
    Settled,
}

/// How a run went. With the [`Scenario`] (plant, program, its source) it holds everything a
/// picture of the run needs: the start and end times, every event and the state timelines.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutcome {
    /// The time of the first cycle.
    pub start: f64,
    /// Each expectation's verdict, in the scenario's order.
    pub verdicts: Vec<Verdict>,
    /// Cycles run.
    pub cycles: u64,
    /// The time of the last cycle.
    pub last_time: f64,
    /// Why it stopped.
    pub stop: StopReason,
    /// True once the program had completed.
    pub completed: bool,
    /// Wall time of the whole run.
    pub wall: Duration,
    /// Cycles that overran the scenario's deadline.
    pub overruns: u64,
    /// The longest cycle.
    pub slowest_cycle: Duration,
    /// The events the executive reported, oldest first: the last [`RunOptions::events`] of
    /// them.
    pub events: Vec<Event>,
    /// How many older events were not kept.
    pub events_dropped: usize,
    /// The executive's state timelines and command and observation histories at the end
    /// (bounded by the retention).
    pub timelines: Timelines,
    /// The faults the model-driven plant drew or was forced into, oldest first (empty for a
    /// scripted plant, whose faults are its rules).
    pub faults: Vec<FaultDrawn>,
}

impl RunOutcome {
    /// True when every expectation holds.
    pub fn passed(&self) -> bool {
        self.verdicts.iter().all(Verdict::holds)
    }
}

/// Why a run could not go on.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    /// The executive could not be built.
    #[error("the executive cannot be built: {0}")]
    Build(#[from] BuildError),
    /// The executive refused a cycle.
    #[error("the executive stopped: {0}")]
    Step(#[from] StepError),
    /// The model-driven plant cannot be built (its theory does not encode).
    #[error("the model-driven plant cannot be built: {0}")]
    Model(String),
    /// The plant refused a command.
    #[error("the plant refused the command of the cycle at {time} s: {message}")]
    Control {
        /// The cycle's time.
        time: f64,
        /// Why.
        message: String,
    },
}

/// Options of a run beyond the scenario's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOptions {
    /// How much history the executive's timelines keep (default: the executive's).
    pub retention: Option<Retention>,
    /// How many of the latest events the outcome keeps, so that a run of any length uses
    /// bounded memory (the log and the trace see every event as it happens).
    pub events: usize,
    /// The model-driven plant's seed, in place of the scenario's (`kairos run --seed`, campaign
    /// runs); a scripted plant has none.
    pub seed: Option<u64>,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            retention: None,
            events: 16384,
            seed: None,
        }
    }
}

/// Runs `scenario` from time 0 to its end (or until nothing more can happen), calling `observe`
/// after every cycle.
pub fn run(
    scenario: &Scenario,
    options: RunOptions,
    observe: &mut dyn FnMut(&CycleRecord<'_>),
) -> Result<RunOutcome, RunError> {
    let started = Instant::now();
    let mut executive = build(scenario, options)?;
    let mut plant = Simulator::new(scenario, options)?;
    let mut checker = Checker::new(
        &scenario.expectations,
        Names {
            plant: &scenario.plant,
            world: &scenario.script.world,
            controls: &scenario.script.controls,
            program: &scenario.program_source,
        },
    );
    let mut clock = SimulatedClock::new(0.0, scenario.cycle);
    let start = clock.start();
    let mut time = start;
    let mut events: VecDeque<Event> = VecDeque::new();
    let mut events_dropped = 0;
    let (mut cycles, mut overruns, mut slowest) = (0, 0, Duration::ZERO);
    let mut completed = false;
    let mut last_time;
    let stop = loop {
        let observation = plant.observe(time);
        let refused = submit_due(plant.rules_mut(), &mut executive, time);
        let mut step = executive.step_shared(time, &observation)?;
        report_refusals(&mut step, refused);
        let command: Vec<NamedValue> = step
            .command
            .iter()
            .map(|&(x, v)| NamedValue::of(executive.plant(), x, v))
            .collect();
        plant
            .send(time, &command)
            .map_err(|message| RunError::Control { time, message })?;
        plant.estimated(&step.most_likely);
        let plant_events = plant.take_events();
        checker.observe(&step, plant.rules());
        observe(&CycleRecord {
            step: &step,
            observation: &observation,
            plant_events: &plant_events,
        });
        cycles += 1;
        last_time = step.time;
        completed |= step.completed;
        slowest = slowest.max(step.times.total);
        overruns += step
            .events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::DeadlineOverrun { .. }))
            .count() as u64;
        events.extend(step.events.iter().cloned());
        while events.len() > options.events {
            events.pop_front();
            events_dropped += 1;
        }
        if time >= scenario.end - TIME_EPSILON {
            break StopReason::EndTime;
        }
        if step.is_settled() && plant.is_quiet(scenario.end) && !checker.awaits_something() {
            break StopReason::Settled;
        }
        time = clock.next_cycle();
        if time > scenario.end + TIME_EPSILON {
            break StopReason::EndTime;
        }
    };
    Ok(RunOutcome {
        start,
        verdicts: checker.finish(plant.rules()),
        cycles,
        last_time,
        stop,
        completed,
        wall: started.elapsed(),
        overruns,
        slowest_cycle: slowest,
        events: events.into(),
        events_dropped,
        timelines: executive.timelines().clone(),
        faults: plant.faults().to_vec(),
    })
}

/// The plant a run drives: the scenario's script, or its model sampled with the script beside
/// it playing what the model does not predict (the environment's events): each cycle a value
/// the script reports replaces the model's for that observable.
enum Simulator<'s> {
    Script(ScriptedPlant<'s>),
    Model {
        // Boxed: the sampler (theory, generator) is much larger than a script's state.
        plant: Box<ModelPlant<'s>>,
        rules: ScriptedPlant<'s>,
    },
}

impl<'s> Simulator<'s> {
    fn new(scenario: &'s Scenario, options: RunOptions) -> Result<Self, RunError> {
        let rules = ScriptedPlant::new(&scenario.script);
        let Some(config) = &scenario.model else {
            return Ok(Simulator::Script(rules));
        };
        let mut config = config.clone();
        config.seed = options.seed.unwrap_or(config.seed);
        let plant = ModelPlant::new(&scenario.plant, &config)
            .map_err(|e| RunError::Model(e.to_string()))?;
        Ok(Simulator::Model {
            plant: Box::new(plant),
            rules,
        })
    }

    fn observe(&mut self, time: f64) -> Arc<[NamedValue]> {
        match self {
            Simulator::Script(plant) => plant.observe_shared(time),
            Simulator::Model { plant, rules } => {
                let mut observation = plant.observe(time);
                for scripted in rules.observe(time) {
                    match observation
                        .iter_mut()
                        .find(|o| o.variable == scripted.variable)
                    {
                        Some(value) => *value = scripted,
                        None => observation.push(scripted),
                    }
                }
                observation.into()
            }
        }
    }

    fn send(&mut self, time: f64, command: &[NamedValue]) -> Result<(), String> {
        match self {
            Simulator::Script(plant) => plant.send(time, command),
            Simulator::Model { plant, rules } => {
                rules.send(time, command)?;
                plant.send(time, command)
            }
        }
    }

    fn estimated(&mut self, modes: &[ValueId]) {
        match self {
            Simulator::Script(rules) | Simulator::Model { rules, .. } => rules.estimated(modes),
        }
    }

    fn take_events(&mut self) -> Vec<PlantEvent> {
        match self {
            Simulator::Script(rules) | Simulator::Model { rules, .. } => rules.take_events(),
        }
    }

    fn is_quiet(&self, end: f64) -> bool {
        match self {
            Simulator::Script(rules) => rules.is_quiet(end),
            Simulator::Model { plant, rules } => plant.is_quiet(end) && rules.is_quiet(end),
        }
    }

    fn rules(&self) -> &ScriptedPlant<'s> {
        match self {
            Simulator::Script(rules) | Simulator::Model { rules, .. } => rules,
        }
    }

    fn rules_mut(&mut self) -> &mut ScriptedPlant<'s> {
        match self {
            Simulator::Script(rules) | Simulator::Model { rules, .. } => rules,
        }
    }

    fn faults(&self) -> &[FaultDrawn] {
        match self {
            Simulator::Script(_) => &[],
            Simulator::Model { plant, .. } => plant.faults(),
        }
    }
}

/// The scenario's executive (κ, the history window and its re-runs, deadline, and the options'
/// retention).
pub(crate) fn build(scenario: &Scenario, options: RunOptions) -> Result<Executive, BuildError> {
    let mut plant = scenario.plant.clone();
    for &(component, mode) in &scenario.believed {
        plant = plant.believing(component, mode);
    }
    let mut builder = Executive::builder(plant, scenario.program.clone())
        .kappa(scenario.kappa)
        .history(scenario.history)
        .rerun(scenario.rerun)
        .chatter_cycles(scenario.chatter_cycles);
    if let Some(deadline) = scenario.deadline {
        builder = builder.cycle_deadline(deadline);
    }
    if let Some(retention) = options.retention {
        builder = builder.retention(retention);
    }
    builder.build()
}

/// Submits to the executive, at `time` (the cycle's), the goals of the rules whose effect
/// showed in this cycle's observation (`submit:`), before its cycle runs — so that the cycle
/// schedules and dispatches them; the refusals, as events (what the rule submitted, why it was
/// refused, the running goals it conflicts with).
pub(crate) fn submit_due(
    plant: &mut ScriptedPlant<'_>,
    executive: &mut Executive,
    time: f64,
) -> Vec<EventKind> {
    let script = plant.script();
    plant
        .take_submissions()
        .into_iter()
        .filter_map(|(rule, submission)| {
            let error = executive.submit(submission, time).err()?;
            Some(EventKind::SubmissionRefused {
                by: script.rules()[rule].name.clone(),
                goals: submission.goals.iter().map(|g| g.name.clone()).collect(),
                reason: error.to_string(),
                conflicts: error.conflicts().to_vec(),
            })
        })
        .collect()
}

/// Puts the refusals of the submissions made before `step`'s cycle first among its events.
pub(crate) fn report_refusals(step: &mut Step, refused: Vec<EventKind>) {
    let (cycle, time) = (step.cycle, step.time);
    let refusals = refused.into_iter().map(|kind| Event { cycle, time, kind });
    step.events.splice(0..0, refusals);
}

#[cfg(test)]
mod tests {
    //! Runs of the engine/camera scenario with expectations that hold and that do not.

    use super::*;
    use crate::simulation::testing::engine_camera;
    use crate::simulation::{Outcome, Window};

    fn outcome(rest: &str) -> RunOutcome {
        let scenario = engine_camera(&format!(
            r#"include: ["scenarios/engine_camera/plant.ron"], {rest}"#
        ));
        run(&scenario, RunOptions::default(), &mut |_| {}).expect("the run goes")
    }

    /// `expect.rs`, `ExpectationKind::opens_at`: the checker's agenda — an open expectation not
    /// asked before its window opens — changes no verdict, no cycle count and no stop, over
    /// shipped scenarios that use every kind of expectation between them (met, failed and
    /// never shown; `Always` invariants; `AnyOf`; missions' XGoals and time points).
    #[test]
    fn the_checkers_agenda_changes_no_verdict() {
        const SCENARIOS: &[&str] = &[
            "scenarios/driver_valve/valve_stuck.ron",
            "scenarios/driver_valve/nominal.ron",
            "scenarios/power/nominal.ron",
            "scenarios/power/both_regulators_fail.ron",
            "scenarios/power/mission_regulator_a_fails.ron",
            "scenarios/power/campaign.ron",
            "scenarios/propulsion/nominal.ron",
            "scenarios/engine_camera/nominal.ron",
            "scenarios/rover/mission_blocked.ron",
            "scenarios/rover/mission_traverse.ron",
            "scenarios/thermostat/switch1_stuck_open_mission.ron",
            "scenarios/thermostat/know_all.ron",
            "scenarios/thermostat/sensor_dropouts.ron",
            "scenarios/thermostat/backup_heater_after_a_stuck_switch.ron",
            "scenarios/thermostat/explore_a_stuck_switch.ron",
            "tests/scenarios/failing_expectation.ron",
            "tests/scenarios/invariant_safes_with_a_working_heater.ron",
        ];
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        for name in SCENARIOS {
            let scenario = crate::simulation::load(&root.join(name)).expect("the scenario loads");
            let mut runs = [false, true].map(|without| {
                super::super::expect::WITHOUT_AGENDA.set(without);
                run(&scenario, RunOptions::default(), &mut |_| {}).expect("the run goes")
            });
            super::super::expect::WITHOUT_AGENDA.set(false);
            let [with, without] = &mut runs;
            assert!(!with.verdicts.is_empty(), "{name}: expectations to check");
            assert_eq!(with.verdicts, without.verdicts, "{name}");
            assert_eq!(
                (with.cycles, with.last_time.to_bits(), with.stop),
                (without.cycles, without.last_time.to_bits(), without.stop),
                "{name}"
            );
        }
    }

    proptest::proptest! {
        #![proptest_config(crate::seeded::config(48))]

        /// `expect.rs`, `ExpectationKind::closes_at`: the agenda's closing — an expectation
        /// not asked after its window closed — changes no verdict, no cycle count and no stop
        /// either. The windows of shipped scenarios' expectations (every kind with a window,
        /// `AnyOf` members, `Always`, `CommandsInOrder`) are moved to start and end at the
        /// times of cycles where something happened, a fraction of ε = `TIME_EPSILON` either
        /// side or exactly, and
        /// the run with the agenda is compared with the run that asks every open expectation
        /// at every cycle.
        #[test]
        fn closing_windows_change_no_verdict(
            which in 0usize..4,
            ends in proptest::collection::vec((0usize..400, 0usize..400, 0usize..7, 0usize..7), 32),
        ) {
            const SCENARIOS: &[&str] = &[
                "scenarios/thermostat/sensor_dropouts.ron",
                "scenarios/power/mission_regulator_a_fails.ron",
                "scenarios/driver_valve/valve_stuck.ron",
                "tests/scenarios/invariant_safes_with_a_working_heater.ron",
            ];
            const SHIFTS: [f64; 7] = [-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0];
            let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
            let mut scenario =
                crate::simulation::load(&root.join(SCENARIOS[which])).expect("the scenario loads");
            // The cycles where something happened (events, a command, ŝ moved): where a
            // window's end decides a verdict.
            let mut times = Vec::new();
            let mut last: Option<Arc<[ValueId]>> = None;
            run(&scenario, RunOptions::default(), &mut |c| {
                let moved = last.as_ref() != Some(&c.step.most_likely);
                if moved || !c.step.events.is_empty() || !c.step.command.is_empty() {
                    times.push(c.step.time);
                }
                last = Some(Arc::clone(&c.step.most_likely));
            })
            .expect("the run goes");
            let at = |k: usize, shift: usize| {
                times[k % times.len()] + SHIFTS[shift] * TIME_EPSILON
            };
            let windows = (scenario.expectations.iter_mut())
                .flat_map(|e| e.kind.windows_mut());
            for (window, &(a, b, sa, sb)) in windows.zip(ends.iter().cycle()) {
                let (from, to) = (at(a, sa), at(b, sb));
                *window = Window { from: from.min(to), to: from.max(to) };
            }
            let mut runs = [false, true].map(|without| {
                super::super::expect::WITHOUT_AGENDA.set(without);
                let outcome = run(&scenario, RunOptions::default(), &mut |_| {});
                super::super::expect::WITHOUT_AGENDA.set(false);
                outcome.expect("the run goes")
            });
            let [with, without] = &mut runs;
            proptest::prop_assert_eq!(&with.verdicts, &without.verdicts);
            proptest::prop_assert_eq!(
                (with.cycles, with.last_time.to_bits(), with.stop),
                (without.cycles, without.last_time.to_bits(), without.stop)
            );
        }
    }

    /// `executive/reconfigure.rs`: the intended configuration, settled only when ŝ changed
    /// (settling is idempotent), is settled on every cycle's ŝ — which the executive checks
    /// each cycle in the crate's tests, with settling's own code — over shipped scenarios
    /// whose goals name transient modes (the camera's picture) or keep modes the plant leaves
    /// for good (the spacecraft's deployment).
    #[test]
    fn the_intended_configuration_is_settled_on_every_cycles_estimate() {
        const SCENARIOS: &[&str] = &[
            "scenarios/engine_camera/nominal.ron",
            "scenarios/engine_camera/flameout.ron",
            "scenarios/spacecraft_deployment/arrays_first.ron",
            "scenarios/thermostat/backup_heater_after_a_stuck_switch.ron",
        ];
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        for name in SCENARIOS {
            let scenario = crate::simulation::load(&root.join(name)).expect("the scenario loads");
            let outcome = run(&scenario, RunOptions::default(), &mut |_| {}).expect("the run goes");
            assert!(outcome.cycles > 0, "{name}");
        }
    }

    fn reason(verdict: &Verdict) -> &str {
        match &verdict.outcome {
            Outcome::Failed { reason } => reason,
            Outcome::Met { .. } => panic!("{} holds", verdict.label),
        }
    }

    /// DESIGN.md §11: the run stops once nothing more can happen, and its expectations are
    /// judged; eventual ones with the time that showed them.
    #[test]
    fn a_nominal_run_settles_and_its_expectations_hold() {
        let outcome = outcome(
            r#"expect: [Completed(by: 100.0), EstimatedAt(state: "engine = heating", time: 10.0),
                        NeverCommanded(command: "engine.cmd = off")]"#,
        );
        assert!(outcome.passed(), "{:?}", outcome.verdicts);
        assert_eq!(outcome.stop, StopReason::Settled);
        assert!(outcome.completed);
        assert!(
            matches!(outcome.verdicts[1].outcome, Outcome::Met { at: Some(t) } if (t - 10.0).abs() < 1e-6)
        );
        assert_eq!(
            outcome.cycles,
            (outcome.last_time / 0.05).round() as u64 + 1
        );
        assert!(
            outcome
                .events
                .iter()
                .any(|e| matches!(e.kind, EventKind::ProgramCompleted))
        );
        assert_eq!(
            outcome.timelines.commands().len(),
            4,
            "the commands are kept"
        );
    }

    /// Failed expectations say why, with times and the estimate.
    #[test]
    fn failed_expectations_say_why() {
        let outcome = outcome(
            r#"expect: [
                EstimatedAt(state: "engine = firing", time: 10.0),
                CommandsInOrder(commands: ["camera.cmd = on", "engine.cmd = standby"]),
                Estimated(state: "camera = failed"),
                NeverEstimated(state: "engine = heating", from: 5.0),
            ]"#,
        );
        assert!(!outcome.passed());
        // The four written ones; the invariants every scenario checks (DESIGN.md §9) follow
        // and hold.
        let reasons: Vec<&str> = outcome.verdicts[..4].iter().map(reason).collect();
        assert_eq!(reasons[0], "at 10.000 s ŝ had engine = heating");
        assert_eq!(
            reasons[1],
            "command 1 of the sequence, at 0.000 s, was engine.cmd = standby"
        );
        assert!(
            reasons[2].starts_with("not shown; at the end"),
            "{}",
            reasons[2]
        );
        assert_eq!(reasons[3], "at 5.000 s ŝ had engine = heating");
    }

    /// The run ends at the end time when the program has not completed.
    #[test]
    fn a_run_stops_at_its_end_time() {
        let scenario = engine_camera(r#"include: ["scenarios/engine_camera/plant.ron"]"#);
        let short = Scenario {
            end: 20.5,
            ..scenario
        };
        let mut seen = 0;
        let outcome = run(&short, RunOptions::default(), &mut |_| seen += 1).expect("runs");
        assert_eq!(outcome.stop, StopReason::EndTime);
        assert_eq!((outcome.cycles, seen), (411, 411));
        assert!((outcome.last_time - 20.5).abs() < 1e-6);
        assert!(!outcome.completed);
    }

    /// A run of any length keeps bounded memory — the outcome keeps the latest events.
    #[test]
    fn the_outcome_keeps_the_latest_events() {
        let scenario = engine_camera(r#"include: ["scenarios/engine_camera/plant.ron"]"#);
        let options = RunOptions {
            events: 3,
            ..RunOptions::default()
        };
        let outcome = run(&scenario, options, &mut |_| {}).expect("runs");
        assert_eq!(outcome.events.len(), 3);
        assert!(outcome.events_dropped > 0);
        // The program completes on the picture; the camera's return to idle comes after.
        assert!(
            outcome
                .events
                .iter()
                .any(|e| matches!(e.kind, EventKind::ProgramCompleted))
        );
    }

    /// A deadline no cycle can meet is reported, every cycle, and the run goes on.
    #[test]
    fn deadline_overruns_are_counted() {
        let scenario = engine_camera(r#"include: ["scenarios/engine_camera/plant.ron"]"#);
        let strict = Scenario {
            deadline: Some(Duration::from_nanos(1)),
            end: 5.0,
            ..scenario
        };
        let outcome = run(&strict, RunOptions::default(), &mut |_| {}).expect("runs");
        assert_eq!(outcome.overruns, outcome.cycles);
    }
}
