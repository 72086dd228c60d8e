//! Scripted plants and scenarios (DESIGN.md §11; thesis §7.2.1).
//!
//! A *scenario* runs a program against a plant model with a *scripted plant* standing in for the
//! hardware — a rule-based simulator like the one of the thesis's EDL demonstration, which
//! "eavesdrops on the issued command and state estimate streams" and "triggers one or more rules
//! that inject desired observations some specified number of execution cycles later" (§7.2.1) —
//! and says what must happen: its *expectations*. `kairos run SCENARIO` prints the mission log
//! and exits 0 when every expectation holds, 1 when one does not. Faults are injected by rules
//! (the plant misbehaves); the estimator is never told.
//!
//! Reference for users: `docs/reference/scenario.md`; how to model noise and faults:
//! `docs/modelling.md`.
//!
//! # The scenario format (RON)
//!
//! ```ron
//! Scenario(
//!     name: "propulsion: nominal",          // optional; default: the file's name
//!     description: "What it shows.",        // optional
//!     program: "fire.rmpl",                 // paths are relative to this file
//!     entry: "Fire",                        // optional; default: the file's first program
//!  // mission: "../../missions/m.ron",      // or a mission (a goal network) in place of
//!                                           // `program`: exactly one of the two
//!     plant: "../../models/propulsion.ron",
//!     cycle: 1.0,                           // cycle period, seconds; cycle i is at i · cycle
//!     end: 300.0,                           // the last cycle is at or before this time;
//!                                           // at most 10⁷ cycles (`MAX_CYCLES`), below
//!     kappa: 5,                             // optional (default 10): states tracked by estimation
//!     history: 16,                          // optional (default 16): steps estimation keeps to
//!                                           // estimate again at 8κ; 0: none
//!     rerun: Surprise,                      // optional (default Doubt): what re-runs them
//!                                           // (`TimedMeOptions::rerun`)
//!     chatter_cycles: 20,                   // optional (default 10): a command back into a mode
//!                                           // left within this many cycles is `Chatter`
//!     deadline: 0.05,                       // optional: wall-time budget per cycle, seconds
//!     believed: { "switch1": "stuck-open" },   // optional: the executive starts certain of
//!                                           // these modes (a fault known before the run,
//!                                           // as the seed's system tests 5 and 6 initialise
//!                                           // the estimate); the plant is not changed
//!     include: ["plant.ron"],               // optional: script files (below), read first
//!     hidden: { "pde": ["off", "on", "latched"] },   // the plant's own hidden state
//!     initial: { "engine.temp": "low", "pde": "off" },
//!     rules: [ /* Rule(...) */ ],
//!     expect: [ /* expectations */ ],
//! )
//! ```
//!
//! A *script file* holds the plant part alone, to be shared by several scenarios:
//! `Script(hidden: {...}, initial: {...}, rules: [...])`. Included scripts are
//! read in order, then the scenario's own `hidden`, `initial` and `rules`. Rule names are unique
//! across them; a later `initial` value overrides an earlier one.
//!
//! ## The plant's values
//!
//! The scripted plant holds a value for each observable of the model and for each `hidden`
//! variable (`name: [values]`, the first value is the initial one). It reports, every cycle,
//! every observable that has a value, holding the last one (DESIGN.md §3). `initial` gives the
//! values at the start; an observable without one is not reported until a rule sets it (the
//! executive reports it missing). Hidden variables are the plant's own state — whether the PDE
//! is powered, whether a heater works — which the executive never sees; rules test and set them.
//!
//! ## Rules
//!
//! ```ron
//! Rule(
//!     name: "PDE relays engine-standby",        // unique; expectations refer to it
//!     on: Command("PDE.cmd = engine-standby"),  // the trigger (below)
//!     when: "pde = on and engine.power = zero", // optional condition over observables and
//!                                               // hidden variables, the constraint language
//!     after: Cycles(1),                         // optional delay: Cycles(n), Seconds(s) or
//!                                               // Between(from, to) seconds (below)
//!     set: { "engine.power": "nominal" },       // values from then on
//!     drop: ["engine.temp"],                    // observables no longer reported (drop-out),
//!                                               // or garbled names no longer reported
//!     garble: { "engine.temp": "scorching" },   // reported verbatim though the model does not
//!                                               // know it (in place of that observable)
//!     once: false,                              // optional: fire at most once
//!     fault: false,                             // optional: the plant misbehaves (the log
//!                                               // highlights it)
//!     submit: Network(...),                     // optional: goals submitted to the running
//!                                               // mission (below)
//! )
//! ```
//! A rule needs at least one of `set`, `drop`, `garble`, `submit`. Triggers:
//! - `Command("PDE.cmd = on")` — a formula over the plant's controls, tested against every
//!   cycle's command μ (controls not commanded hold their idle value): fires every cycle μ
//!   satisfies it, so a re-issued command fires it again.
//! - `Estimate("engine = heating")` — a formula over component modes, tested against ŝ, the
//!   executive's most likely mode of each component: fires when it (and the condition) comes to
//!   hold.
//! - `While("temp = cold and sw1 = closed")` — a formula over the plant's own values
//!   (observables and hidden variables), tested with time rules: fires each time it (and the
//!   condition) comes to hold, and an effect of it still pending when it stops holding is
//!   dropped. A process that needs a condition to last — the device reaches 20 °C after 65 s
//!   of one heater on — is then faithful to a fault at any cycle, where a command rule's delay
//!   lands whatever happened since (`scenarios/thermostat/physics.ron`).
//! - `Time(16800.0)` — fires at the first cycle at or after that time at which the condition
//!   holds; once. In the scenario itself a time after `end` is an error; an included script's
//!   may lie beyond a short scenario's end, and never fire.
//! - `Cycle(30)` — likewise at or after that cycle (numbered from 0).
//! - `Optional(from: 16800.0, to: 17157.0, every: 10)` — open nondeterminism for `kairos
//!   explore` ([`crate::exploration`]): the rule may fire once at any cycle of the window whose
//!   number is a multiple of `every` (optional, default 1), when its condition holds — or never.
//!   An optional rule is a fault (`fault` and `once` are implied). A run fires it only where the
//!   scenario pins it: `choose: { "engine loses power": 16850.0 }` fires it at the first cycle
//!   at or after that time (a name that is not an optional rule, or a time outside its window,
//!   is a located error). `kairos explore` writes its counterexamples as the scenario with such
//!   a `choose`.
//!
//! The effect shows after the delay, counted from the cycle the rule fired: `Cycles(n)`, or
//! `Seconds(s)` (the first cycle at least s later). Without `after`, as early as possible: the
//! same cycle for time and cycle rules, the next cycle for command and estimate rules — an
//! observation at t(i+1) reflects the commands of t(i), and ŝ(i) is computed from the
//! observation of t(i), so a command or estimate rule cannot have a zero delay. Within a cycle:
//! effects due are applied in the order their rules fired, then time and cycle rules fire, then
//! the plant reports; after the executive's cycle, command rules and then estimate rules fire.
//! The condition is tested when the rule fires, on the values the plant reported in that cycle.
//!
//! A timed response whose time is uncertain takes an interval: `after: Between(30.0, 60.0)`
//! (seconds, the first more than 0, the second at least the first) lands the effect at any
//! cycle whose time is in [fired + 30 s, fired + 60 s] — or, when no cycle's is, the first
//! after fired + 30 s. A run takes the lower bound (as `Seconds(30.0)` would) unless the
//! scenario pins the delay: `choose: { "heating ends": 45.0 }` (a delay within the interval, a
//! located error otherwise) is the delay of every firing of that rule. `kairos explore` tries
//! every landing cycle, the delay chosen at the rule's first firing on a path and kept for its
//! later ones (an interval is an uncertain property of the device, not jitter). An optional
//! rule cannot have an interval (its firing time is the open choice already).
//!
//! Effects due at the same cycle are applied in the order their rules fired. Nothing can see
//! the values between two of them (conditions are tested after all are applied), so the order
//! matters only where two write the same observable, hidden variable or garbled name
//! differently; `kairos explore` then tries one order per distinct outcome. A run follows
//! `deliver: [(at: 12.0, order: ["valve opens", "surge"])]`: at the cycle at that time (a
//! multiple of the period), the effects due are applied in that order — every rule whose
//! effect is due, each as often as it is due; an order that is not exactly that is ignored
//! (the fired order). `kairos explore` writes its counterexamples with it.
//!
//! Examples, one per trigger:
//! ```ron
//! Rule(name: "PDE powers up", on: Command("PDE.cmd = on"), when: "pde = off", set: { "pde": "on" }),
//! Rule(name: "heating ends", on: Estimate("engine = heating"), after: Seconds(40.0),
//!      set: { "engine.temp": "nominal" }),
//! Rule(name: "atmospheric drag", on: Time(16800.0), set: { "entry.drag": "sensed" }),
//! Rule(name: "PDE latches up", on: Cycle(1), set: { "pde": "latched" }, fault: true),
//! ```
//!
//! ## Submitting goals to the running mission
//!
//! In a scenario that runs a mission, a rule may `submit` goals — with the time points and
//! temporal constraints that place them — to the running executive (DESIGN.md §15.4;
//! [`Executive::submit`](crate::executive::Executive::submit)), as an operator or a ground
//! station would, at a time or on any other trigger:
//! ```ron
//! Rule(
//!     name: "operator asks for a second StayWarm",
//!     on: Time(200.0),
//!     submit: Network(                       // written as a mission file's network
//!         points: ["TP_S2", "TP_E2"],        // new points
//!         constraints: [                     // over the mission's points and the new ones
//!             Constraint(from: "TP_E", to: "TP_S2", min: 0.0, max: 20.0),
//!             Constraint(from: "TP_S2", to: "TP_E2", min: 100.0, max: 100.0),
//!         ],
//!         goals: [
//!             Goal(name: "stay-warm-2", sv: "temperature", kind: Maintain,
//!                  constraint: "temperature = warm-low or temperature = warm",
//!                  start: "TP_S2", end: "TP_E2"),
//!         ],
//!     ),
//! ),
//! ```
//! The network is read by the mission loader (`goalnet::mission`): points, constraints, macros
//! and goals mean and are checked exactly as in a mission file, the goals' constraints resolved
//! against the plant. A submission names the mission's points and its own (not another
//! submission's); a goal or macro may name one of the mission's goal types (`type:
//! "StayWarm"`), and is then elaborated by its tactics when the submission is promoted (the
//! seeds' "submit StayWarm at 10 s"). `submit` in a scenario that runs an RMPL program is an
//! error. A rule may `submit` beside `set`, `drop` or `garble`, or alone. The submission is made
//! at the time of the cycle the rule's effect shows in, before the executive's cycle, so that
//! cycle schedules and dispatches it. A submission that cannot be scheduled with the running
//! network (inconsistent, unmergeable, unachievable, or a point whose window lies before that
//! time) is refused — the network runs on unchanged — and the cycle reports a
//! `SubmissionRefused` event with the reason (the log's `REFUSED` line), naming every running
//! goal it conflicts with. Expectations may name submitted points and goals
//! (`Fired(point: "TP_S2")`, `XGoalActive(goal: "stay-warm-2", ...)`).
//!
//! ## A model-driven plant
//!
//! In place of a script, a scenario can run against its plant model itself, sampled
//! ([`ModelPlant`]): every cycle each component takes a transition drawn with the model's
//! per-step probabilities (those mode estimation uses), forced faults happen at their time, and
//! the plant reports an assignment of every observable drawn among those its modes allow.
//! ```ron
//! simulator: Model(
//!     seed: 7,                                       // optional (default 0): the ChaCha8 seed
//!     faults: ["valve1 = stuck-closed @ 120 s"],     // optional: forced, `component = mode @ T`
//!     noise: 0.01,                                   // optional (default 0): the probability an
//!                                                    // observation is a random value instead
//! ),
//! ```
//! A script beside the model (`include`, `hidden`, `initial`, `rules`) plays what the model does
//! not predict — the environment's events, such as the EDL's altitude triggers
//! (`scenarios/mars_edl/descent.ron`): every cycle, a value the script reports replaces the
//! model's for that observable, and its rules fire as in a scripted run. `kairos run SCENARIO
//! --seed S` replays the run of seed `S`; `kairos campaign` runs many seeds
//! (`docs/campaigns.md`); both take `--fault "component = mode @ T s"` (repeatable, added to
//! the scenario's) and `--noise q` (in place of the scenario's). A forced fault after `end`, a
//! name that is not a component or one of its *fault* modes, and a noise outside `[0, 1]` are
//! located errors.
//!
//! ## Expectations
//!
//! Times are seconds. *Eventual* expectations take an optional window `after:`/`by:` and hold
//! when some cycle in it shows them; *never* expectations take `from:`/`to:` and hold when no
//! cycle in it shows what they exclude. Formulas use the constraint language.
//! ```ron
//! Estimated(state: "engine = firing", by: 300.0),      // ŝ satisfies it at some cycle
//! EstimatedAt(state: "engine = heating", time: 20.0),  // ŝ satisfies it at the first cycle at
//!                                                      // or after that time
//! NeverEstimated(state: "engine = off", from: 50.0, to: 17150.0),
//! Commanded(command: "PDE.cmd = engine-fire", by: 300.0),   // over controls, against μ
//! CommandsInOrder(commands: ["PDE.cmd = on", "PDE.cmd = engine-standby"], by: 60.0),
//!                                   // the commands issued in the window (non-idle cycles),
//!                                   // exactly these, in this order
//! NeverCommanded(command: "lander.cmd = fire-backup"),
//! Diagnosed(fault: "PDE = resettable", within: Cycles(3), of: "PDE latches up"),
//!                                   // the diagnosis event, at most 3 cycles after the rule
//!                                   // first fired; or with after:/by: instead
//! Achieved(goal: "engine = firing", by: 300.0),        // a goal as the program writes it
//! GoalFailed(goal: "engine = standby"),                // goal interpretation failed, for a
//!                                                      // goal containing this one (optional)
//! Completed(by: 300.0),                                // the program completed
//! AnyOf([Completed(), Reported(event: GoalFailed)]),   // one of these is shown: eventual
//!                                   // expectations that cannot fail before the end
//!                                   // (Estimated, Commanded, Diagnosed, Achieved,
//!                                   // GoalFailed, Completed, Reported)
//! Reported(event: ObservationRejected),                // any executive event, by kind
//! Reported(event: ResponseTaken, saying: "→ safing"),  // ... whose text (as the log prints
//!                                   // it) contains this: the goals a refusal names, a forced
//!                                   // point's lateness, the response taken, the tactic chosen
//! NeverReported(event: EstimatorInconsistency),        // (`saying` allowed too)
//! ```
//! Event kinds: `GoalAsserted`, `GoalAchieved`, `GoalFailed`, `Retrying`, `GoalConflict`, `Preempted`,
//! `ClockStarted`, `ModeChanged`, `Diagnosis`, `CommandIssued`, `Repair` (a command that repairs
//! a fault), `Waiting`, `PlanFailed`, `EstimatorInconsistency`, `SearchCut`,
//! `ObservationRejected`, `ObservationsMissing`, `DeadlineOverrun`, `ProgramCompleted`, and for
//! missions `TimePointFired`, `TimePointForced`, `XGoalDispatched`, `MissionGoalFailed`,
//! `TemporalInconsistency`, `SubmissionRefused`, `TacticChosen`, `TacticRejected`,
//! `ResponseTaken`, `Promoted`, `PromotionFailed`, `Safing`, `GoalRecovered`, `NetworkStalled`,
//! `SafeGoalDropped`, `XGoalWithdrawn`, and for a goal delegated to a controller
//! `ConstraintSent`, `ControllerCommand`, `ConstraintEnded`, `ConstraintWithdrawn`.
//!
//! ## Missions
//!
//! A scenario with `mission:` runs a goal network (DESIGN.md §15; the format is in
//! [`crate::goalnet::mission`]) in place of an RMPL program. The mission must bind to the
//! scenario's `plant` (the same file); its network is scheduled when the scenario is loaded, from
//! the plant's most likely initial modes, and a network that cannot be scheduled is an error at
//! `mission` with the scheduler's reason. The mission completes when every time point has fired.
//! Expectations on the network (names are checked against the mission):
//! ```ron
//! Fired(point: "TP_S", after: 71.0, by: 161.0),        // fired (on time or forced) in the window
//! NeverFired(point: "TP_bgE", to: 999.0),
//! Failed(goal: "heater1", by: 200.0),                  // the constituent goal reported failed
//! NeverFailed(goal: "stay-warm", to: 204.0),           // `goal` optional: no goal failed
//! XGoalActive(sv: "switch1", goal: "heater1", time: 200.0),  // at the first cycle at or after
//!                                   // `time`, an XGoal is active on the SV (merging `goal`)
//! NeverXGoalActive(sv: "switch1", goal: "heater1", from: 77.0), // no cycle of the window has
//!                                   // one (`goal` optional): a retired goal stays retired
//! Recovered(goal: "know-temperature", by: 110.0),      // having failed, it holds again
//! ```
//!
//! ## Invariants
//!
//! `Always(that: CONDITION, from: …, to: …)` holds when the condition holds at every cycle of
//! the window (both optional); `kairos explore` checks it on every path. Conditions
//! ([`Condition`]) speak of one cycle and combine:
//! ```ron
//! Plant("temp != cold")              // the scripted plant's TRUE values (observables, hidden)
//! Estimated("temperature = cold")    // ŝ
//! Reported(Safing)                   // an event of this kind in the cycle
//! Active("stay-warm")                // an XGoal merging this mission goal is active
//! Not(…), All([…]), Any([…]), Implies(…, …)
//! Once(…)                            // held at this cycle or an earlier one
//! ```
//! "No path safes while a working heater could keep the device warm":
//! `Always(that: Implies(Reported(Safing), Not(Plant("…a heater works…"))))`; "none loses warmth
//! while a heater works": `Always(that: Implies(All([Once(Plant("temp = warm")),
//! Active("stay-warm")]), Plant("temp != cold")))`
//! (`scenarios/thermostat/explore_a_stuck_switch.ron`).
//!
//! ## The run
//!
//! Cycle i runs at t = i · cycle from 0: the plant reports, the executive steps, the command goes
//! to the plant. The run stops after the last cycle at or before `end`, or earlier once nothing
//! more can happen: the program has completed, the plant is in its intended configuration, the
//! script has nothing pending and every eventual expectation has been shown.
//!
//! A scenario runs at most [`MAX_CYCLES`] (10⁷) cycles, `end / cycle + 1`: 58 times the nominal
//! Mars EDL (171,577 cycles), about five minutes at its pace. A longer one is refused where `end`
//! is written, with the number of cycles and a rough wall time (at the EDL's ~31 µs per cycle of
//! a release build): a mistyped period such as `cycle: 1e-8` would otherwise run for hours.
//! `kairos run` shows a progress bar on standard error while it runs, when standard error is a
//! terminal and `--quiet` is not given.
//!
//! Every problem in a scenario, script, model or program is reported with its file, line and
//! column, the text and what was expected there.

mod condition;
mod expect;
mod expectation;
mod format;
mod latent;
mod load;
mod load_deliver;
mod load_expect;
mod load_model;
mod load_script;
mod model_cache;
mod model_plant;
mod run;
mod script;

use std::time::Duration;

pub use condition::Condition;
pub(crate) use expect::{Checker, Names};
pub use expectation::{Expectation, ExpectationKind, Outcome, Verdict, Window};
pub use format::EventName;
pub use load::{DEFAULT_KAPPA, MAX_CYCLES, load, load_source};
pub use model_plant::{FaultDrawn, ForcedFault, ModelPlant, ModelPlantConfig};
pub(crate) use run::build as build_executive;
pub use run::{CycleRecord, RunError, RunOptions, RunOutcome, StopReason, run};
pub(crate) use run::{report_refusals, submit_due};
pub use script::{
    Delay, Effect, Held, OpenLanding, PlantEvent, PlantEventKind, Rule, Script, ScriptedPlant,
    Trigger,
};

use crate::diagnostic::Source;
use crate::estimation::{Rerun, TimedMeOptions};
use crate::executive::{ControlProgram, ScheduledMission};
use crate::logic::ValueId;
use crate::plant::{ComponentId, Plant};
use crate::sequencer::Thca;

/// What a scenario runs: an RMPL program or a mission (a goal network).
#[derive(Debug, Clone)]
pub enum ScenarioProgram {
    /// An RMPL program, linked against the plant (boxed, as the mission: they differ in size).
    Rmpl(Box<Thca>),
    /// A mission bound to the scenario's plant, its network scheduled.
    Mission(Box<ScheduledMission>),
}

impl ScenarioProgram {
    /// The RMPL program's automaton, if the scenario runs one.
    pub fn thca(&self) -> Option<&Thca> {
        match self {
            ScenarioProgram::Rmpl(thca) => Some(thca),
            ScenarioProgram::Mission(_) => None,
        }
    }

    /// The scheduled mission, if the scenario runs one.
    pub fn mission(&self) -> Option<&ScheduledMission> {
        match self {
            ScenarioProgram::Rmpl(_) => None,
            ScenarioProgram::Mission(mission) => Some(mission),
        }
    }
}

impl From<ScenarioProgram> for ControlProgram {
    fn from(program: ScenarioProgram) -> Self {
        match program {
            ScenarioProgram::Rmpl(thca) => (*thca).into(),
            ScenarioProgram::Mission(mission) => (*mission).into(),
        }
    }
}

/// A loaded, validated scenario.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// Its name.
    pub name: String,
    /// What it shows.
    pub description: String,
    /// The scenario file.
    pub source: Source,
    /// The plant model's path.
    pub plant_path: String,
    /// The program or mission file (its path is its name); events' spans point into it.
    pub program_source: Source,
    /// The entry program, when the scenario names one.
    pub entry: Option<String>,
    /// The plant model.
    pub plant: Plant,
    /// The program, linked against the plant, or the mission, scheduled.
    pub program: ScenarioProgram,
    /// The cycle period, in seconds.
    pub cycle: f64,
    /// The end time, in seconds.
    pub end: f64,
    /// κ for mode estimation.
    pub kappa: usize,
    /// Mode estimation's history window, in steps (0: none; `TimedMeOptions::history`).
    pub history: usize,
    /// Which occasions re-run mode estimation's history window (`TimedMeOptions::rerun`).
    pub rerun: Rerun,
    /// The executive's chatter window, in cycles (DESIGN.md §9; `chatter_cycles`).
    pub chatter_cycles: u64,
    /// The wall-time deadline of a cycle.
    pub deadline: Option<Duration>,
    /// The scripted plant.
    pub script: Script,
    /// The model-driven plant's settings, when the scenario runs against its model sampled
    /// (`simulator: Model(...)`) rather than its script.
    pub model: Option<ModelPlantConfig>,
    /// What must happen.
    pub expectations: Vec<Expectation>,
    /// Components the executive starts certain of (`believed`): its model's initial
    /// distribution is replaced by certainty on the mode (the plant played is not changed).
    pub believed: Vec<(ComponentId, ValueId)>,
}

impl Scenario {
    /// Mode estimation's options as the scenario sets them: κ and the history window.
    pub fn estimation(&self) -> TimedMeOptions {
        TimedMeOptions {
            history: self.history,
            rerun: self.rerun,
            ..TimedMeOptions::kappa(self.kappa)
        }
    }

    /// How many cycles the run has if it goes to its end (it may settle earlier).
    pub fn cycles(&self) -> u64 {
        // At most `MAX_CYCLES`, checked when the scenario was loaded: the cast does not saturate.
        cycle_count(self.end, self.cycle) as u64
    }
}

impl Scenario {
    /// Forces `text` (`component = mode @ T s`, at or before the end) in the model-driven plant,
    /// besides the scenario's own forced faults (`kairos run/campaign --fault`).
    pub fn force_fault(&mut self, text: &str) -> Result<(), String> {
        let fault = ForcedFault::parse(&self.plant, text)?.by(self.end)?;
        let model = self.model.as_mut().ok_or_else(needs_model)?;
        model.faults.push(fault);
        Ok(())
    }

    /// Sets the model-driven plant's sensor noise, in place of the scenario's (`--noise`).
    pub fn set_noise(&mut self, noise: f64) -> Result<(), String> {
        let noise = model_plant::check_noise(noise)?;
        self.model.as_mut().ok_or_else(needs_model)?.noise = noise;
        Ok(())
    }
}

fn needs_model() -> String {
    "the scenario has no model-driven plant (`simulator: Model(...)`)".to_string()
}

/// The number of cycles from time 0 to `end` at `cycle` seconds each, both ends included.
fn cycle_count(end: f64, cycle: f64) -> f64 {
    ((end + script::TIME_EPSILON) / cycle).floor() + 1.0
}

#[cfg(test)]
pub(crate) mod testing {
    //! Scenarios written inline for unit tests, against the shipped models and programs.

    use std::path::Path;

    use super::{Scenario, load_source};
    use crate::diagnostic::Source;

    /// A scenario on the engine/camera model running `programs/engine_burn.rmpl` at a 0.05 s
    /// cycle (the camera's picture lasts 0.1 to 0.2 s), with `rest` (fields after `end`) added.
    pub(crate) fn engine_camera(rest: &str) -> Scenario {
        let text = format!(
            "Scenario(program: \"programs/engine_burn.rmpl\", plant: \"models/engine_camera.ron\", \
             cycle: 0.05, end: 100.0, {rest})"
        );
        load_source(
            &Source::new("test.ron", text),
            Path::new(env!("CARGO_MANIFEST_DIR")),
        )
        .unwrap_or_else(|e| panic!("{e}"))
    }
}
