//! The model-driven plant (DESIGN.md §11, §6.2): it samples the TCCA with the same
//! per-step probabilities mode estimation uses (thesis §6.1.3, §6.2.2), draws observations the
//! modes allow, replays a seed exactly and applies forced faults at their time.

use kairos::diagnostic::Source;
use kairos::executive::NamedValue;
use kairos::executive::adapters::{ControlAdapter, MonitorAdapter};
use kairos::logic::ValueId;
use kairos::opsat::{Consistency, Literal};
use kairos::plant::Plant;
use kairos::simulation::{self, ForcedFault, ModelPlant, ModelPlantConfig, RunOptions};

fn plant_from(name: &str, text: &str) -> Plant {
    Plant::load(&Source::new(name, text)).unwrap_or_else(|e| panic!("{e}"))
}

fn shipped(path: &str) -> Plant {
    let text = std::fs::read_to_string(format!("{}/{path}", env!("CARGO_MANIFEST_DIR")))
        .expect("the model is shipped");
    plant_from(path, &text)
}

fn config(seed: u64) -> ModelPlantConfig {
    ModelPlantConfig::seeded(seed)
}

/// One component cycling between three modes with per-cycle probabilities (§6.1.3): from `a`,
/// 0.2 to `b`, 0.1 to `c`, 0.7 to stay.
const CYCLER: &str = r#"Plant(name: "cycler", components: [Component(
    name: "m",
    attributes: { "light": ["dark", "dim", "bright"] },
    modes: [
        Mode(name: "a", constraint: "m.light = bright", reward: 0),
        Mode(name: "b", constraint: "m.light = dim", reward: 0),
        Mode(name: "c", kind: Fault, constraint: "true", reward: 0),
    ],
    initial: { "a": 1.0 },
    transitions: [
        (from: "a", to: "b", probability: 0.2),
        (from: "a", to: "c", probability: 0.1),
        (from: "b", to: "a", probability: 0.5),
        (from: "c", to: "a", probability: 0.5),
    ],
)], observables: ["m.light"])"#;

/// Pearson's statistic of `counts` against `probabilities` (summing to 1).
fn chi_square(counts: &[u64], probabilities: &[f64]) -> f64 {
    let n: u64 = counts.iter().sum();
    counts
        .iter()
        .zip(probabilities)
        .map(|(&k, &p)| {
            let expected = n as f64 * p;
            (k as f64 - expected).powi(2) / expected
        })
        .sum()
}

/// §6.1.3: per step, a mode's transitions fire with their probabilities and it stays with the
/// rest. 20,000 steps from a seeded run; the outcomes from `a` are tested against (0.7, 0.2,
/// 0.1) with Pearson's χ² on 2 degrees of freedom. The bound 27.6 is the 1 − 10⁻⁶ quantile: a
/// correct sampler exceeds it for one seed in a million, a sampler off by a few points of
/// probability exceeds it at once (with ≈ 12,500 steps from `a`, 0.2 read as 0.22 gives χ² ≈ 25
/// on that cell alone, plus the others'). The seed is fixed, so the test is deterministic.
#[test]
fn sampled_transition_frequencies_match_the_models_probabilities() {
    let plant = plant_from("cycler.ron", CYCLER);
    let mut model = ModelPlant::new(&plant, &config(18)).expect("encodes");
    let mut counts = [0u64; 3];
    model.observe(0.0);
    let mut before = model.modes().expect("started")[0];
    for i in 1..=20_000 {
        model.send(f64::from(i - 1), &[]).expect("idle");
        model.observe(f64::from(i));
        let after = model.modes().expect("started")[0];
        if before == ValueId(0) {
            counts[after.index()] += 1;
        }
        before = after;
    }
    let statistic = chi_square(&counts, &[0.7, 0.2, 0.1]);
    assert!(statistic < 27.6, "χ² = {statistic} for {counts:?}");
}

/// §6.2.2: a timed transition fires on the component clock with the distribution's mass per
/// step: `after: Uniform(0, 10)` with p = 1 at a 1 s cycle fires in each of the first ten steps
/// with probability 0.1. 2,000 seeded runs; χ² on 9 degrees of freedom against the 1 − 10⁻⁶
/// quantile, 45.3 (same reasoning as above).
#[test]
fn timed_transitions_fire_with_their_distribution_on_the_clock() {
    let plant = plant_from(
        "warmer.ron",
        r#"Plant(name: "warmer", components: [Component(
            name: "w",
            attributes: { "temp": ["cold", "warm"] },
            modes: [
                Mode(name: "warming", constraint: "w.temp = cold", reward: 0),
                Mode(name: "warm", constraint: "w.temp = warm", reward: 0),
            ],
            initial: { "warming": 1.0 },
            transitions: [(from: "warming", to: "warm", after: Uniform(0.0, 10.0), probability: 1.0)],
        )], observables: ["w.temp"])"#,
    );
    let mut counts = [0u64; 10];
    for seed in 0..2_000 {
        let mut model = ModelPlant::new(&plant, &config(seed)).expect("encodes");
        model.observe(0.0);
        let step = (1..=10)
            .find(|&i| {
                model.send(f64::from(i - 1), &[]).expect("idle");
                model.observe(f64::from(i));
                model.modes().expect("started")[0] == ValueId(1)
            })
            .expect("fires by the end of the window");
        counts[step as usize - 1] += 1;
    }
    let statistic = chi_square(&counts, &[0.1; 10]);
    assert!(statistic < 45.3, "χ² = {statistic} for {counts:?}");
}

/// The observation is an assignment of the observables the modes, the
/// interconnections and the command allow. On the driver and valve of §6.1 (interconnected),
/// commanded on, open, close and off, every cycle's observation is consistent with the plant's
/// modes in the theory.
#[test]
fn observations_are_consistent_with_the_sampled_modes() {
    let plant = shipped("models/driver_valve.ron");
    let mut theory = plant.theory().expect("encodes");
    let mut model = ModelPlant::new(&plant, &config(3)).expect("encodes");
    let script = ["on", "open", "no-command", "close", "off", "reset"];
    for i in 0..600u32 {
        let observation = model.observe(f64::from(i) * 0.1);
        let modes = model.modes().expect("started");
        let mut literals: Vec<Literal> = plant
            .components()
            .iter()
            .zip(modes)
            .map(|(c, &m)| Literal::Is(c.mode_var(), m))
            .collect();
        assert_eq!(observation.len(), plant.observables().len(), "all reported");
        for value in &observation {
            let var = plant.table().variable_id(&value.variable).expect("known");
            let v = plant
                .table()
                .variable(var)
                .value(value.value.symbol().unwrap_or_default())
                .expect("known");
            literals.push(Literal::Is(var, v));
        }
        assert_eq!(theory.consistent(&literals), Consistency::Consistent);
        let command = NamedValue::new("driver.dcmd_in", script[(i / 7) as usize % script.len()]);
        model
            .send(f64::from(i) * 0.1, &[command])
            .expect("a control");
    }
}

/// A forced fault `valve1 = stuck-closed @ 20 s` puts the valve in that mode at the
/// first cycle at or after 20 s, and the run records it as forced, at that time.
#[test]
fn a_forced_fault_happens_at_its_time() {
    let plant = shipped("models/propulsion.ron");
    let fault = ForcedFault::parse(&plant, "valve1 = stuck-closed @ 20 s").expect("reads");
    let config = config(5).with_fault(fault);
    let mut model = ModelPlant::new(&plant, &config).expect("encodes");
    let valve1 = plant.component_named("valve1").expect("a component");
    for i in 0..=25 {
        model.observe(f64::from(i));
        let stuck = model.modes().expect("started")[valve1.index()] == fault.mode;
        assert_eq!(stuck, i >= 20, "at {i} s");
        model.send(f64::from(i), &[]).expect("idle");
    }
    let forced: Vec<_> = model.faults().iter().filter(|f| f.forced).collect();
    assert_eq!(forced.len(), 1);
    assert_eq!((forced[0].component, forced[0].time), (valve1, 20.0));
}

/// A seed replays a run exactly — the same observations every cycle, the same faults,
/// the same verdicts — and another seed plays another run. The propulsion scenario driven by
/// its model, with noise so that the generator is used every cycle.
#[test]
fn the_same_seed_replays_the_same_run() {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
    let scenario = simulation::load_source(
        &Source::new(
            "model.ron",
            r#"Scenario(program: "programs/propulsion_fire.rmpl", plant: "models/propulsion.ron",
                cycle: 1.0, end: 60.0, kappa: 5,
                simulator: Model(seed: 1, faults: ["valve2 = stuck-closed @ 30 s"], noise: 0.05),
                expect: [Completed(by: 60.0)])"#,
        ),
        std::path::Path::new("."),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let play = |seed: Option<u64>| {
        let mut observations = Vec::new();
        let options = RunOptions {
            seed,
            ..RunOptions::default()
        };
        let outcome = simulation::run(&scenario, options, &mut |record| {
            observations.push(record.observation.to_vec());
        })
        .expect("runs");
        (observations, outcome.faults, outcome.verdicts)
    };
    let first = play(None);
    assert_eq!(first, play(Some(1)), "the scenario's seed is 1");
    assert_ne!(first.0, play(Some(2)).0, "another seed, another run");
    assert!(first.1.iter().any(|f| f.forced && f.time == 30.0));
}

/// With noise q an observation is replaced by a value drawn from its domain, so on the
/// cycler held in `a` (which shows `bright`) a 3-value observable reads something else with
/// probability q · 2/3. q = 0.3 over 20,000 cycles: 0.2 expected; the bound ±0.0142 is 5
/// standard deviations of the binomial proportion (√(0.2 · 0.8 / 20,000) = 0.00283), exceeded by
/// a correct sampler with probability below 10⁻⁶.
#[test]
fn noise_replaces_observations_at_its_rate() {
    let held = CYCLER
        .replace("probability: 0.2", "probability: 0.0")
        .replace(
            "(from: \"a\", to: \"c\", probability: 0.1)",
            "(from: \"a\", to: \"c\", probability: 0.0)",
        );
    let plant = plant_from("held.ron", &held);
    let config = config(9).with_noise(0.3).expect("a probability");
    let mut model = ModelPlant::new(&plant, &config).expect("encodes");
    let mut wrong = 0u32;
    for i in 0..20_000u32 {
        let observation = model.observe(f64::from(i));
        assert_eq!(model.modes().expect("started")[0], ValueId(0), "held in a");
        if observation[0].value != "bright" {
            wrong += 1;
        }
        model.send(f64::from(i), &[]).expect("idle");
    }
    let rate = f64::from(wrong) / 20_000.0;
    assert!((rate - 0.2).abs() < 0.0142, "{rate}");
}

/// A script beside the model plays what the model does not predict: from the cycle its rule
/// fires, the value it sets replaces the model's (here the engine's temperature, which the
/// sampled plant would report `low` while the engine is off).
#[test]
fn a_script_beside_the_model_overrides_its_observables() {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
    let scenario = simulation::load_source(
        &Source::new(
            "hybrid.ron",
            r#"Scenario(program: "programs/propulsion_fire.rmpl", plant: "models/propulsion.ron",
                cycle: 1.0, end: 20.0, kappa: 5,
                rules: [Rule(name: "sensor", on: Time(10.0), set: { "engine.temp": "nominal" })],
                simulator: Model(seed: 4))"#,
        ),
        std::path::Path::new("."),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mut temps = Vec::new();
    simulation::run(&scenario, RunOptions::default(), &mut |record| {
        let temp = record
            .observation
            .iter()
            .find(|o| o.variable == "engine.temp")
            .map(|o| o.value.to_string());
        temps.push((record.step.time, temp));
    })
    .expect("runs");
    for (time, temp) in temps {
        let temp = temp.expect("the model reports every observable");
        let expected = if time >= 10.0 { "nominal" } else { "low" };
        assert_eq!(temp, expected, "at {time} s");
    }
}

/// The embedding API's builder refuses what the scenario loader and the command line refuse: a
/// noise that is not a probability, a fault after the run's end (`ForcedFault::by`), a name that
/// is not a component or one of its modes (with the closest name).
#[test]
fn the_builder_refuses_bad_faults_and_noise() {
    let plant = shipped("models/propulsion.ron");
    assert_eq!(
        config(1).with_noise(1.5).unwrap_err(),
        "noise 1.5 is not a probability"
    );
    let late = ForcedFault::parse(&plant, "valve1 = stuck-closed @ 400 s").expect("reads");
    assert_eq!(
        late.by(300.0).unwrap_err(),
        "the fault is forced at 400 s, after the end (300 s)"
    );
    assert_eq!(late.by(400.0), Ok(late));
    assert_eq!(
        ForcedFault::parse(&plant, "valve9 = stuck-closed @ 4 s").unwrap_err(),
        "`valve9` is not a component of the plant (did you mean `valve2`?)"
    );
    assert_eq!(
        ForcedFault::parse(&plant, "valve1 = stuck-clsoed @ 4 s").unwrap_err(),
        "`stuck-clsoed` is not a mode of `valve1` (did you mean `stuck-closed`?)"
    );
}

/// A valve behind its own command: open shows flow, closed and stuck closed show none. The
/// fault has no probability of its own; tests force it.
const VALVE: &str = r#"Plant(name: "valve", components: [Component(
    name: "valve",
    attributes: { "cmd": ["none", "open", "close"], "flow": ["none", "some"] },
    modes: [
        Mode(name: "closed", constraint: "valve.flow = none", reward: 0),
        Mode(name: "open", constraint: "valve.flow = some", reward: 0),
        Mode(name: "stuck-closed", kind: Fault, constraint: "valve.flow = none", reward: -10),
    ],
    initial: { "closed": 1.0 },
    transitions: [
        (from: "closed", to: "open", guard: "valve.cmd = open", probability: 0.99),
        (from: "open", to: "closed", guard: "valve.cmd = close", probability: 0.99),
    ],
)], controls: { "valve.cmd": "none" }, observables: ["valve.flow"])"#;

/// The valve stuck closed at 2 s; `open` commanded at `open_at` (if any); the time the fault
/// was revealed, after a run to 10 s.
fn revealed(open_at: Option<f64>) -> Option<f64> {
    let plant = plant_from("valve.ron", VALVE);
    let fault = ForcedFault::parse(&plant, "valve = stuck-closed @ 2 s").expect("reads");
    let mut model = ModelPlant::new(&plant, &config(3).with_fault(fault)).expect("encodes");
    for i in 0..=10 {
        let now = f64::from(i);
        model.observe(now);
        let command = match open_at {
            Some(at) if at == now => vec![NamedValue::new("valve.cmd", "open")],
            _ => Vec::new(),
        };
        model.send(now, &command).expect("a control");
    }
    let faults = model.faults();
    assert_eq!(faults.len(), 1, "{faults:?}");
    faults[0].revealed
}

/// A fault that no observation can show yet is latent (DESIGN.md §17, campaigns: a fault never
/// diagnosed is a miss only if it could have been seen): a valve stuck closed while it is
/// closed shows what the closed valve would show, until `open` is commanded and the flow the
/// nominal valve would have does not come.
#[test]
fn a_fault_is_revealed_only_when_its_nominal_shadow_would_show_otherwise() {
    assert_eq!(
        revealed(None),
        None,
        "never commanded open: latent to the end"
    );
    assert_eq!(
        revealed(Some(5.0)),
        Some(6.0),
        "opened at 5 s: no flow at 6 s"
    );
    assert_eq!(
        revealed(Some(1.0)),
        Some(2.0),
        "stuck while open: the flow stops at once"
    );
}
