//! The thermostat's numeric telemetry in a campaign (DESIGN.md §17; `plant::monitor`): the
//! StayWarm mission against the sampled model, the sensor read in °C through the model's
//! monitor — readings Gaussian around each band's middle, sd 1.2 °C; band edges 20, 27, 33,
//! 40 °C with 0.5 °C of hysteresis; persistence 3 (`models/thermostat.ron`). No run fails
//! silently and no fault is diagnosed that the plant did not have — the noise alone never
//! makes one — and the same campaign with a bare threshold (no hysteresis, persistence 1) does
//! diagnose faults from the noise, so the check can fail.

use kairos::campaign::run_seed;
use kairos::diagnostic::Source;
use kairos::executive::EventKind;
use kairos::plant::Plant;
use kairos::simulation::{self, RunOptions, Scenario};

const RUNS: u64 = 300;

fn campaign() -> Scenario {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/thermostat/campaign.ron"
    );
    simulation::load(std::path::Path::new(path)).expect("the campaign loads")
}

/// What the runs of a campaign showed: runs that failed without the executive reporting a
/// failure, and diagnoses of a fault the plant was not in (component = mode, the run's seed).
#[derive(Debug, Default)]
struct Findings {
    silent: Vec<u64>,
    spurious: Vec<(String, u64)>,
}

fn findings(scenario: &Scenario, noise: f64) -> Findings {
    let mut scenario = scenario.clone();
    if let Some(model) = &mut scenario.model {
        model.noise = noise;
    }
    let plant = &scenario.plant;
    let mut found = Findings::default();
    for i in 0..RUNS {
        let seed = run_seed(1, i);
        let options = RunOptions {
            seed: Some(seed),
            ..RunOptions::default()
        };
        let outcome = simulation::run(&scenario, options, &mut |_| {}).expect("the run goes");
        let mut reported = false;
        for event in &outcome.events {
            match &event.kind {
                EventKind::Diagnosis {
                    component, mode, ..
                } => {
                    let had = outcome.faults.iter().any(|f| {
                        f.component == *component
                            && plant.component(f.component).mode(f.mode).name == *mode
                            && f.time <= event.time
                    });
                    if !had {
                        let name = plant.component(*component).name();
                        found.spurious.push((format!("{name} = {mode}"), seed));
                    }
                }
                EventKind::GoalFailed { .. }
                | EventKind::PlanFailed { .. }
                | EventKind::MissionGoalFailed { .. }
                | EventKind::Safing { .. } => reported = true,
                _ => {}
            }
        }
        if !outcome.passed() && !reported {
            found.silent.push(seed);
        }
    }
    found
}

/// Gaussian noise alone: every run passes or says why, and every diagnosis is of a fault the
/// plant drew.
#[test]
fn gaussian_noise_alone_diagnoses_nothing() {
    let found = findings(&campaign(), 0.0);
    assert!(found.silent.is_empty(), "{found:?}");
    assert!(found.spurious.is_empty(), "{found:?}");
}

/// With outliers too (`--noise 0.01`: one reading in a hundred is of a random band, the case
/// that once diagnosed a permanent fault from one reading): no silent failure, no diagnosis
/// from the noise in these runs.
#[test]
fn outliers_are_glitches_not_faults() {
    let found = findings(&campaign(), 0.01);
    assert!(found.silent.is_empty(), "{found:?}");
    assert!(found.spurious.is_empty(), "{found:?}");
}

/// The same campaign with a bare threshold — no hysteresis, persistence 1 — diagnoses faults
/// the plant never had: the monitor's hysteresis and persistence are what keep the noise out.
#[test]
fn a_bare_threshold_diagnoses_faults_from_the_noise() {
    let mut scenario = campaign();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/models/thermostat.ron");
    let text = std::fs::read_to_string(path)
        .expect("the model")
        .replace("persistence: 3,", "persistence: 1,")
        .replace("hysteresis: 0.5", "hysteresis: 0.0");
    scenario.plant = Plant::load(&Source::new("bare.ron", text)).expect("the variant loads");
    let found = findings(&scenario, 0.0);
    assert!(found.spurious.len() > 10, "{found:?}");
}
