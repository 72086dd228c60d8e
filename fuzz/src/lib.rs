//! The fuzz targets' entry functions (DESIGN.md §13: no panic, no abort, no
//! hang on any input).
//!
//! One function per input format, each taking the raw bytes libFuzzer hands over. The
//! `fuzz_targets/` binaries call them, and so does `tests/fuzz_smoke.rs` (which includes this
//! file with `#[path]`) over the committed corpus and over proptest-generated inputs, so the
//! stable-toolchain CI runs exactly the code the fuzzers run. The functions return nothing:
//! a rejected input is fine, a panic (or an abort, or a hang) is the finding. Where a format
//! promises more than "no panic" the functions assert it.
//!
//! Inputs that are not UTF-8 are dropped by the text targets: every loader takes a `&str` (the
//! CLI's own decoding error is tested in `tests/cli_robustness.rs`).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use arbitrary::{Arbitrary, Unstructured};
use kairos::diagnostic::Source;
use kairos::estimation::log::{parse_log, replay};
use kairos::estimation::{TimedMe, TimedMeOptions};
use kairos::executive::{Executive, NamedValue, StepError};
use kairos::exploration::Budget as ExploreBudget;
use kairos::goalnet::{self, EstimateView, GoalController, Mission, display};
use kairos::logic::{Formula, VarTable, parse_formula};
use kairos::opsat::{Budget, SearchOptions};
use kairos::plant::Plant;
use kairos::protocol::CoaController;
use kairos::reconfiguration::Reconfiguration;
use kairos::rmpl::{self, LinkOptions};
use kairos::simulation::{self, RunOptions};

/// Cycles a fuzzed scenario or executive run may take: enough to pass the first goals and
/// faults of the shipped programs, few enough that one input takes milliseconds.
pub const MAX_CYCLES: usize = 24;

/// Records of an estimation log that are replayed (all of them are parsed).
pub const MAX_REPLAYED_RECORDS: usize = 24;

/// Configurations a fuzzed rover scenario's protocol search may store.
pub const PROTOCOL_STATES: u64 = 2_000;

/// OPSAT's node budget for a fuzzed OCSP, so that a large problem cannot stall the fuzzer.
pub const OCSP_NODE_BUDGET: u64 = 2_000;

/// The shipped plant models, in the order the targets index them.
const MODELS: [(&str, &str); 5] = [
    (
        "models/driver_valve.ron",
        include_str!("../../models/driver_valve.ron"),
    ),
    (
        "models/propulsion.ron",
        include_str!("../../models/propulsion.ron"),
    ),
    (
        "models/engine_camera.ron",
        include_str!("../../models/engine_camera.ron"),
    ),
    (
        "models/lander_separation.ron",
        include_str!("../../models/lander_separation.ron"),
    ),
    (
        "models/mars_lander.ron",
        include_str!("../../models/mars_lander.ron"),
    ),
];

/// Index of `models/driver_valve.ron` in [`MODELS`].
const DRIVER_VALVE: usize = 0;
/// Index of `models/propulsion.ron` in [`MODELS`].
const PROPULSION: usize = 1;
/// Index of `models/mars_lander.ron` in [`MODELS`].
const MARS_LANDER: usize = 4;

/// The shipped models, loaded once per process (they are valid: `tests/plant_models.rs`).
fn models() -> &'static [Plant] {
    static PLANTS: OnceLock<Vec<Plant>> = OnceLock::new();
    PLANTS.get_or_init(|| {
        MODELS
            .iter()
            .map(|(name, text)| {
                Plant::load(&Source::new(*name, *text))
                    .unwrap_or_else(|e| panic!("shipped model {name} does not load:\n{e}"))
            })
            .collect()
    })
}

/// The repository root: the directory holding `models/` (this file is compiled from the
/// repository's tests and from `fuzz/`, whose manifest directories differ by one level).
pub fn repository() -> &'static Path {
    static ROOT: OnceLock<PathBuf> = OnceLock::new();
    ROOT.get_or_init(|| {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .ancestors()
            .find(|dir| dir.join("models/driver_valve.ron").is_file())
            .expect("the repository holds models/")
            .to_path_buf()
    })
}

fn text(data: &[u8]) -> Option<&str> {
    std::str::from_utf8(data).ok()
}

/// The constraint language (`logic::syntax`, `logic::resolve`): parse the text as a formula,
/// resolve it against every shipped model's variables and, where it resolves, encode it in that
/// model's theory and ask whether it is consistent — the path every guard, goal and condition
/// takes.
pub fn constraint(data: &[u8]) {
    let Some(text) = text(data) else { return };
    let _ = kairos::logic::syntax::parse(text);
    // The encoding is tried on the two small models only: building the lander's theory for
    // every input would dominate the run, and the encoder does not depend on the model.
    for (index, plant) in models().iter().enumerate() {
        let Ok(formula) = parse_formula(text, plant.table()) else {
            continue;
        };
        let _ = formula.display(plant.table()).to_string();
        if index == DRIVER_VALVE || index == PROPULSION {
            encode(plant, &formula);
        }
    }
}

/// Encodes `formula` (its clock and confidence atoms grounded, as the sequencer does) in the
/// plant's theory and checks it for consistency.
fn encode(plant: &Plant, formula: &Formula) {
    let grounded = formula.ground(&mut |atom| atom.is_external().then_some(true));
    let Ok(mut theory) = plant.theory() else {
        return;
    };
    if let Ok(literal) = theory.define(&grounded) {
        let _ = theory.consistent(&[literal]);
    }
}

/// RMPL (`rmpl::load`): parse, link and compile, once without a plant (variables inferred from
/// the program) and once against the Mars lander's variables (what the shipped programs name).
pub fn rmpl(data: &[u8]) {
    let Some(text) = text(data) else { return };
    let source = Source::new("fuzz.rmpl", text);
    let _ = rmpl::load(&source, &LinkOptions::default());
    let lander = LinkOptions {
        plant: Some(models()[MARS_LANDER].table()),
        ..LinkOptions::default()
    };
    if let Err(errors) = rmpl::load(&source, &lander) {
        // Rendering locates every span in the text: a span past the end or inside a character
        // is a bug the tests of well-formed programs would not see.
        let _ = errors.to_string();
    }
}

/// Plant models (`plant::file`): load and validate; on success build the theory, as every
/// command that reads a model does.
pub fn plant(data: &[u8]) {
    let Some(text) = text(data) else { return };
    match Plant::load(&Source::new("fuzz.ron", text)) {
        Ok(plant) => {
            let _ = plant.theory();
        }
        Err(errors) => {
            let _ = errors.to_string();
        }
    }
}

/// The shipped scenario directories, with the model their scenarios run.
const SCENARIO_DIRS: [(&str, &str); 4] = [
    ("scenarios/driver_valve", "driver_valve.ron"),
    ("scenarios/propulsion", "propulsion.ron"),
    ("scenarios/engine_camera", "engine_camera.ron"),
    ("scenarios/mars_edl", "mars_lander.ron"),
];

/// Scenario files (`simulation::load_source`): load, then run at most [`MAX_CYCLES`] cycles.
///
/// Relative paths in a scenario are read from the directory of the shipped scenarios of the
/// model it names (so a seed's `include: ["plant.ron"]` finds its script). Inputs that name
/// device or process files are skipped: reading `/dev/zero` or `/dev/stdin` would hang the
/// fuzzer, and naming such a file is the user's choice, not a malformed input.
pub fn scenario(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if ["/dev", "/proc", "/sys"].iter().any(|p| text.contains(p)) {
        return;
    }
    let dir = SCENARIO_DIRS
        .iter()
        .find(|(_, model)| text.contains(model))
        .map_or(SCENARIO_DIRS[0].0, |(dir, _)| dir);
    run_scenario(text, dir);
}

/// The scenario directories of missions: scenarios that run a goal network (`mission:`).
const MISSION_SCENARIO_DIRS: [(&str, &str); 3] = [
    ("scenarios/thermostat", "thermostat.ron"),
    ("scenarios/rover", "rover.ron"),
    ("scenarios/mars_edl", "mars_lander.ron"),
];

/// Loads a mission file (`goalnet::mission::load_source`), its plant path relative to
/// `missions/`; errors are rendered.
fn load_mission(text: &str) -> Option<Mission> {
    let source = Source::new("fuzz-mission.ron", text);
    match goalnet::mission::load_source(&source, &repository().join("missions")) {
        Ok(mission) => Some(mission),
        Err(errors) => {
            let _ = errors.to_string();
            None
        }
    }
}

/// The reconfiguration compiled for the mission's plant and the plant's most likely initial
/// modes, as `kairos run` and `kairos schedule` start from them.
fn start(mission: &Mission) -> Option<(Reconfiguration, Vec<kairos::logic::ValueId>)> {
    let reconfiguration = Reconfiguration::compile(&mission.plant).ok()?;
    let current = mission.plant.most_likely_initial();
    Some((reconfiguration, current))
}

/// Mission files (`goalnet::mission`): load (every check `kairos check` makes), then build the
/// goal controller at time 0 from the initial modes — the elaboration of every goal type
/// (tactics that create goals of their own types included) and the first schedule.
pub fn mission(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if ["/dev", "/proc", "/sys"].iter().any(|p| text.contains(p)) {
        return;
    }
    let Some(mission) = load_mission(text) else {
        return;
    };
    let Some((reconfiguration, current)) = start(&mission) else {
        return;
    };
    let beliefs: Vec<Vec<f64>> = (mission.plant.components().iter())
        .map(|c| c.initial().to_vec())
        .collect();
    let view = EstimateView {
        modes: &current,
        beliefs: &beliefs,
    };
    let controller = GoalController::new(&mission, &reconfiguration, 0.0, view);
    let _ = controller.is_safed();
}

/// `kairos schedule`: a mission's network scheduled from the initial modes, rendered, and
/// projected to a time the input's length picks (0 to 999 s).
pub fn schedule(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if ["/dev", "/proc", "/sys"].iter().any(|p| text.contains(p)) {
        return;
    }
    let Some(mission) = load_mission(text) else {
        return;
    };
    let Some((reconfiguration, current)) = start(&mission) else {
        return;
    };
    match goalnet::schedule(&mission.network, &reconfiguration, &current) {
        Ok(executable) => {
            let _ = display::render(&executable, &mission.plant);
            let at = (text.len() % 1000) as f64;
            if let Ok(projection) = goalnet::project(&executable, at) {
                let _ = display::render_projection(&projection, &mission.plant);
            }
        }
        Err(error) => {
            let _ = display::explain(&error, &mission.network, &mission.plant);
        }
    }
}

/// Scenarios that run a mission (a goal network against a scripted plant): load, then run at
/// most [`MAX_CYCLES`] cycles, relative paths read from the shipped mission scenarios'
/// directory of the model the text names.
pub fn mission_scenario(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if ["/dev", "/proc", "/sys"].iter().any(|p| text.contains(p)) {
        return;
    }
    let dir = MISSION_SCENARIO_DIRS
        .iter()
        .find(|(_, model)| text.contains(model))
        .map_or(MISSION_SCENARIO_DIRS[0].0, |(dir, _)| dir);
    run_scenario(text, dir);
}

/// Loads the scenario `text` with relative paths from `dir` and runs at most [`MAX_CYCLES`]
/// cycles; errors are rendered.
fn run_scenario(text: &str, dir: &str) {
    let source = Source::new("fuzz-scenario.ron", text);
    let mut scenario = match simulation::load_source(&source, &repository().join(dir)) {
        Ok(scenario) => scenario,
        Err(errors) => {
            let _ = errors.to_string();
            return;
        }
    };
    scenario.end = scenario.end.min(scenario.cycle * MAX_CYCLES as f64);
    let _ = simulation::run(&scenario, RunOptions::default(), &mut |_| {});
}

/// Rover scenarios (`protocol::scenario`): load, then explore the controller protocol's
/// interleavings within [`PROTOCOL_STATES`] configurations.
pub fn protocol(data: &[u8]) {
    let Some(text) = text(data) else { return };
    let source = Source::new("fuzz-rover.ron", text);
    let scenario = match kairos::protocol::scenario::load_source(&source) {
        Ok(scenario) => scenario,
        Err(errors) => {
            let _ = errors.to_string();
            return;
        }
    };
    let controller = CoaController::new(scenario.initial_value());
    let explored = kairos::exploration::protocol::explore(
        &scenario,
        controller,
        ExploreBudget::States(PROTOCOL_STATES),
        u64::MAX,
    );
    let _ = explored.holds();
}

/// OCSP files (`opsat::file`): load, then find the three best solutions within
/// [`OCSP_NODE_BUDGET`] nodes, which must come in non-decreasing cost (DESIGN.md §4).
pub fn ocsp(data: &[u8]) {
    let Some(text) = text(data) else { return };
    let Ok(mut instance) = kairos::opsat::file::load(&Source::new("fuzz-ocsp.ron", text)) else {
        return;
    };
    let options = SearchOptions {
        budget: Budget {
            max_nodes: Some(OCSP_NODE_BUDGET),
            ..Budget::default()
        },
        ..SearchOptions::default()
    };
    let solutions = instance.ocsp.best_with(&mut instance.theory, 3, options);
    let costs: Vec<f64> = solutions.solutions.iter().map(|s| s.cost).collect();
    assert!(
        costs.windows(2).all(|pair| pair[0] <= pair[1]),
        "OPSAT returned solutions out of cost order: {costs:?}"
    );
}

/// Estimation replay logs (`estimation::log`): parse against the driver/valve model (the model of
/// `tests/logs/driver_valve_stuck.jsonl`) and the Mars lander, and replay the first
/// [`MAX_REPLAYED_RECORDS`] records of a driver/valve log through TimedME, κ = 3.
pub fn estimation_log(data: &[u8]) {
    let Some(text) = text(data) else { return };
    let source = Source::new("fuzz.jsonl", text);
    let _ = parse_log(&source, &models()[MARS_LANDER]);
    let plant = &models()[DRIVER_VALVE];
    let Ok(records) = parse_log(&source, plant) else {
        return;
    };
    let Ok(mut theory) = plant.theory() else {
        return;
    };
    let mut estimator = TimedMe::new(TimedMeOptions::kappa(3));
    let replayed = &records[..records.len().min(MAX_REPLAYED_RECORDS)];
    // A parsed log has increasing times and names only what the plant has: replay must accept it.
    if let Err(error) = replay(plant, &mut theory, &mut estimator, replayed) {
        panic!("a log that parsed was refused by replay: {error}");
    }
}

/// The executive target's input: a system (model + program) and a stream of cycles, each an
/// arbitrary time step and arbitrary observations, biased towards names the plant knows so that
/// most cycles reach the sequencer and reconfiguration.
#[derive(Debug, Clone, Arbitrary)]
pub struct ExecutiveRun {
    /// Which shipped model and program run.
    pub system: System,
    /// κ, taken as `1 + kappa % 8`.
    pub kappa: u8,
    /// The cycles, at most [`MAX_CYCLES`] of them run.
    pub cycles: Vec<Cycle>,
}

/// A shipped model and its program.
#[derive(Debug, Clone, Copy, Arbitrary)]
pub enum System {
    /// `models/driver_valve.ron` running `programs/valve_open.rmpl`.
    DriverValve,
    /// `models/propulsion.ron` running `programs/propulsion_fire.rmpl`.
    Propulsion,
}

/// One cycle's input.
#[derive(Debug, Clone, Arbitrary)]
pub struct Cycle {
    /// How the cycle's time is chosen.
    pub time: Time,
    /// What the monitors report.
    pub observations: Vec<Reading>,
}

/// A cycle's time.
#[derive(Debug, Clone, Copy, Arbitrary)]
pub enum Time {
    /// The previous time plus this many milliseconds (0 repeats the time: an error).
    AfterMillis(u16),
    /// The previous time plus this many seconds.
    AfterSeconds(u8),
    /// Exactly this time: NaN, infinities, the past, huge values.
    Exactly(f64),
}

/// One reported `variable = value`.
#[derive(Debug, Clone, Arbitrary)]
pub struct Reading {
    /// The variable.
    pub variable: Name,
    /// Its value.
    pub value: Name,
}

/// A name: one the plant knows (an index, wrapped) or any text.
#[derive(Debug, Clone, Arbitrary)]
pub enum Name {
    /// The n-th variable of the plant, or the n-th value of the reading's variable.
    Known(u8),
    /// Any text.
    Text(String),
}

/// The programs the executive target runs, each linked against its model (index in
/// [`MODELS`]).
fn systems() -> &'static [(usize, kairos::sequencer::Thca); 2] {
    static SYSTEMS: OnceLock<[(usize, kairos::sequencer::Thca); 2]> = OnceLock::new();
    SYSTEMS.get_or_init(|| {
        let link = |model: usize, name: &str, text: &str| {
            let options = LinkOptions {
                plant: Some(models()[model].table()),
                ..LinkOptions::default()
            };
            let thca = rmpl::load(&Source::new(name, text), &options)
                .unwrap_or_else(|e| panic!("shipped program {name} does not link:\n{e}"));
            (model, thca)
        };
        [
            link(
                DRIVER_VALVE,
                "programs/valve_open.rmpl",
                include_str!("../../programs/valve_open.rmpl"),
            ),
            link(
                PROPULSION,
                "programs/propulsion_fire.rmpl",
                include_str!("../../programs/propulsion_fire.rmpl"),
            ),
        ]
    })
}

/// `Executive::step` on an arbitrary observation stream: the bytes are read as an
/// [`ExecutiveRun`] (`arbitrary`); see [`executive_run`].
pub fn executive(data: &[u8]) {
    if let Ok(run) = ExecutiveRun::arbitrary_take_rest(Unstructured::new(data)) {
        executive_run(&run);
    }
}

/// Runs the executive over `run`'s cycles and checks its contract (DESIGN.md §3, §13): a cycle is
/// refused exactly when its time is not finite or not after the previous cycle's; observations
/// that do not fit the plant are events, never errors; the belief stays a distribution.
pub fn executive_run(run: &ExecutiveRun) {
    let (model, thca) = &systems()[run.system as usize];
    let plant = &models()[*model];
    let mut executive = Executive::builder(plant.clone(), thca.clone())
        .kappa(1 + usize::from(run.kappa % 8))
        .build()
        .expect("a shipped program builds against its model");
    let mut previous: Option<f64> = None;
    for cycle in run.cycles.iter().take(MAX_CYCLES) {
        let now = match cycle.time {
            Time::AfterMillis(ms) => previous.unwrap_or(0.0) + f64::from(ms) / 1000.0,
            Time::AfterSeconds(s) => previous.unwrap_or(0.0) + f64::from(s),
            Time::Exactly(t) => t,
        };
        let observed: Vec<NamedValue> = cycle
            .observations
            .iter()
            .map(|reading| named_value(plant.table(), reading))
            .collect();
        let in_order = now.is_finite() && previous.is_none_or(|p| now > p);
        match executive.step(now, &observed) {
            Ok(step) => {
                assert!(in_order, "cycle at {now} s accepted after {previous:?}");
                assert_eq!(step.time, now);
                previous = Some(now);
                if let Some(belief) = executive.belief() {
                    let total: f64 = belief.states().iter().map(|s| s.probability).sum();
                    assert!((total - 1.0).abs() < 1e-6, "belief sums to {total}");
                }
            }
            Err(StepError::TimeNotAfter { .. }) => {
                assert!(!in_order, "cycle at {now} s refused after {previous:?}")
            }
            Err(error) => panic!("cycle at {now} s failed: {error}"),
        }
    }
}

/// The reading as the monitors would report it: known names by index (into every variable of
/// the plant's table; values into the chosen variable's domain), or the text as given.
fn named_value(table: &VarTable, reading: &Reading) -> NamedValue {
    let variables: Vec<_> = table.variables().map(|(_, v)| v).collect();
    let (variable, known) = match &reading.variable {
        Name::Known(i) if !variables.is_empty() => {
            let var = variables[usize::from(*i) % variables.len()];
            (var.name().to_string(), Some(var))
        }
        Name::Known(i) => (i.to_string(), None),
        Name::Text(text) => (
            text.clone(),
            table.variable_id(text).map(|id| table.variable(id)),
        ),
    };
    let value = match (&reading.value, known) {
        (Name::Known(j), Some(var)) if var.domain_size() > 0 => {
            var.values()[usize::from(*j) % var.domain_size()].clone()
        }
        (Name::Known(j), _) => j.to_string(),
        (Name::Text(text), _) => text.clone(),
    };
    NamedValue::new(variable, value)
}

/// A target's entry function: the bytes libFuzzer hands over.
pub type Entry = fn(&[u8]);

/// Every target by name, as `cargo fuzz` knows them (`fuzz/fuzz_targets/<name>.rs`) and as the
/// corpus directories are named.
pub const TARGETS: [(&str, Entry); 11] = [
    ("constraint", constraint),
    ("rmpl", rmpl),
    ("plant", plant),
    ("scenario", scenario),
    ("ocsp", ocsp),
    ("estimation_log", estimation_log),
    ("executive", executive),
    ("mission", mission),
    ("schedule", schedule),
    ("mission_scenario", mission_scenario),
    ("protocol", protocol),
];
