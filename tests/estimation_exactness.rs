//! No loss of exactness from the theory's unit-propagation fast path (issue 15, direction 4;
//! DESIGN.md §7: the theory answers "consistent?" and "entailed?" completely).
//!
//! Propagation answers the questions it decides and leaves the rest to the SAT solver, which
//! still gives every conflict its core; skipping solver calls must change no answer and no
//! search order. So TimedME run on a theory with the fast path and on one without it
//! (`Theory::set_propagation`) must keep the same system states with bit-for-bit the same
//! probabilities, cycle after cycle: on the circuit-breaker tree (issue 15 item 6), on the
//! Mars lander's EDL events (§7.2.2) and on random plants.
//!
//! `KAIROS_CASES=N` changes the number of random plants; `KAIROS_PROPTEST_SEED=random` explores.

mod support;

#[path = "support/seeded.rs"]
mod seeded;

#[path = "support/breakers.rs"]
mod breakers;

use kairos::diagnostic::Source;
use kairos::estimation::log::{LogRecord, parse_log, replay};
use kairos::estimation::{Belief, ModeEstimator, TimedMe, TimedMeOptions};
use kairos::plant::Plant;
use proptest::prelude::*;
use support::lander_edl::{Faults, nominal_edl};
use support::plants::model;
use support::random_plant::{random_plant, random_run};

/// A belief exactly: per system state its probability's bits, modes and clock starts' bits.
fn exactly(belief: &Belief) -> Vec<(u64, Vec<u32>, Vec<Option<u64>>)> {
    belief
        .states()
        .iter()
        .map(|w| {
            (
                w.probability.to_bits(),
                w.state.modes.iter().map(|m| m.0).collect(),
                w.state
                    .clock_starts
                    .iter()
                    .map(|c| c.map(f64::to_bits))
                    .collect(),
            )
        })
        .collect()
}

/// Every belief of a TimedME replay of `records` (the initial one first).
fn beliefs(plant: &Plant, records: &[LogRecord], propagation: bool) -> Vec<Belief> {
    let mut theory = plant.theory().expect("theory");
    theory.set_propagation(propagation);
    let mut estimator = TimedMe::new(TimedMeOptions::kappa(10));
    let updates = replay(plant, &mut theory, &mut estimator, records).expect("replays");
    assert!(
        propagation || theory.stats().propagated == 0,
        "off means every question goes to the solver"
    );
    updates.into_iter().map(|u| u.belief).collect()
}

/// The step at which the two replays first differ, if any.
fn first_difference(plant: &Plant, records: &[LogRecord]) -> Option<usize> {
    let with = beliefs(plant, records, true);
    let without = beliefs(plant, records, false);
    assert_eq!(with.len(), without.len());
    with.iter()
        .zip(&without)
        .position(|(a, b)| exactly(a) != exactly(b))
}

#[test]
fn the_breaker_tree_is_estimated_identically_with_and_without_propagation() {
    let plant = Plant::load(&Source::new(
        "breakers_15.ron",
        breakers::breaker_tree_ron(15),
    ))
    .expect("loads");
    let log = Source::new("breakers_15.jsonl", breakers::breaker_log(15, 7));
    let records = parse_log(&log, &plant).expect("parses");
    assert_eq!(first_difference(&plant, &records), None);
}

#[test]
fn the_mars_edl_events_are_estimated_identically_with_and_without_propagation() {
    // The nominal EDL on a 600 s grid, with every command and observation change (the
    // `events` case of `examples/me_profile.rs`, where the busy cycles are), up to the entry.
    let plant = model("mars_lander");
    let timeline = nominal_edl(Faults::default());
    let times = timeline.times(support::lander_edl::edl::ENTRY + 60.0, 600.0);
    let records = timeline.records(&plant, &times);
    assert!(records.len() > 30, "{} records", records.len());
    assert_eq!(first_difference(&plant, &records), None);
}

proptest! {
    #![proptest_config(seeded::config(48))]

    /// Random plants and runs (`tests/support/random_plant.rs`): the same beliefs, bit for bit.
    #[test]
    fn random_plants_are_estimated_identically_with_and_without_propagation(
        spec in random_plant(4),
        run in random_run(4, 12),
    ) {
        let Some(plant) = spec.plant() else {
            return Ok(());
        };
        let mut reference = plant.theory().expect("theory");
        reference.set_propagation(false);
        let (first, cycles) = run.simulate(&plant, &mut reference);
        let mut beliefs: Vec<Vec<Belief>> = Vec::new();
        for propagation in [true, false] {
            let mut theory = plant.theory().expect("theory");
            theory.set_propagation(propagation);
            let mut estimator = TimedMe::new(TimedMeOptions::kappa(4));
            let mut update = estimator
                .initial(&plant, &mut theory, 0.0, &first)
                .expect("initial");
            let mut these = vec![update.belief.clone()];
            for cycle in &cycles {
                update = cycle.update(&mut estimator, &plant, &mut theory, &update);
                these.push(update.belief.clone());
            }
            beliefs.push(these);
        }
        for (step, (a, b)) in beliefs[0].iter().zip(&beliefs[1]).enumerate() {
            prop_assert_eq!(exactly(a), exactly(b), "step {}\nmodel: {}", step, spec.ron());
        }
    }
}
