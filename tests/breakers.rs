//! The circuit-breaker tree (the Livingstone 2 benchmark shape): the shipped
//! `models/breakers_15.ron` and `tests/logs/breakers_15.jsonl` are what the generator writes,
//! and TimedME at κ = 10 follows the scripted story — every breaker on, then each trip
//! diagnosed in the cycle its LEDs go dark (a tripped breaker, not a blown one: the trip rate is
//! 100× the blow rate), the reset seen as `off`, the breaker on again after `on`.

#[path = "support/breakers.rs"]
mod breakers;

use breakers::{breaker_log, breaker_script, breaker_tree_ron, tripping};
use kairos::diagnostic::Source;
use kairos::estimation::log::{parse_log, replay};
use kairos::estimation::{TimedMe, TimedMeOptions};
use kairos::plant::Plant;

const N: usize = 15;
const TRIPS: usize = 7;

fn shipped(path: &str) -> String {
    let full = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"))
}

#[test]
fn the_shipped_tree_and_log_are_the_generators() {
    assert_eq!(shipped("models/breakers_15.ron"), breaker_tree_ron(N));
    assert_eq!(
        shipped("tests/logs/breakers_15.jsonl"),
        breaker_log(N, TRIPS)
    );
}

#[test]
fn timed_me_diagnoses_every_trip_and_follows_the_repair() {
    let plant = Plant::load(&Source::new("breakers_15.ron", breaker_tree_ron(N))).expect("loads");
    let log = Source::new("breakers_15.jsonl", breaker_log(N, TRIPS));
    let records = parse_log(&log, &plant).expect("parses");
    let mut theory = plant.theory().expect("theory");
    let mut estimator = TimedMe::new(TimedMeOptions::kappa(10));
    let updates = replay(&plant, &mut theory, &mut estimator, &records).expect("replays");
    let script = breaker_script(N, TRIPS);
    assert_eq!(updates.len(), script.len());
    let mode_of = |update: &kairos::estimation::Update, b: usize| {
        let state = update.belief.most_likely_plant_state();
        plant
            .component_named(&format!("b{b}"))
            .map(|c| plant.component(c).mode(state.modes[c.index()]).name.clone())
    };
    // Cycle 1: everything on.
    for b in 0..N {
        assert_eq!(
            mode_of(&updates[1], b).as_deref(),
            Some("on"),
            "b{b} at t = 1"
        );
    }
    for k in 0..TRIPS {
        let b = tripping(N, k);
        let at = 2 + 3 * k;
        let expected = [(at, "tripped"), (at + 1, "off"), (at + 2, "on")];
        for (cycle, mode) in expected {
            assert_eq!(
                mode_of(&updates[cycle], b).as_deref(),
                Some(mode),
                "b{b} at t = {}",
                script[cycle].time
            );
        }
        // Only the tripped breaker is blamed.
        for other in (0..N).filter(|&o| o != b) {
            assert_eq!(
                mode_of(&updates[at], other).as_deref(),
                Some("on"),
                "b{other}"
            );
        }
    }
}
