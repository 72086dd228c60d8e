//! Reasoning fidelity of mode estimation, on random plants
//! (`tests/support/random_plant.rs`) against the exact update:
//!
//! - **Merge before truncating** (DESIGN.md §8: equal system states are merged by summing, "exact,
//!   and what makes §6.2's plant-state probabilities come out right with a small κ"): while the
//!   exact belief holds at most κ system states, TimedME at κ *is* the exact update — the same
//!   system states with the same probabilities, to 1e-9.
//! - **Consistent with the model** (DESIGN.md §8: "the targets must be consistent with o(i+1) and
//!   the model"): every system state either estimator keeps is consistent with the plant's
//!   connections and mode constraints, whether or not anything was observed.
//! - **How far from exact** (`src/estimation/timed_me.rs`): the total-variation distance between
//!   TimedME's belief and the exact one, over system states, never exceeds
//!   `Belief::distance_bound`, on every generator — the broad one with fault-to-fault
//!   transitions and steps that observe nothing included, at κ small enough to truncate.
//!
//! `KAIROS_CASES=N` changes the number of random plants; `KAIROS_PROPTEST_SEED=random` explores.

mod support;

#[path = "support/seeded.rs"]
mod seeded;

use kairos::estimation::{Belief, BeliefUpdate, ModeEstimator, TimedMe, TimedMeOptions, Update};
use kairos::opsat::Theory;
use kairos::plant::{Observation, Plant};
use proptest::prelude::*;
use support::random_plant::{
    RandomPlant, RandomRun, broad_plant, consistent_with, fault_to_fault_plant, random_plant,
    random_run, runs, sparse_runs,
};

const MAX_COMPONENTS: usize = 4;
const MAX_STEPS: usize = 12;

/// The broad generator: plants of up to this many components, 10–30 steps.
const BROAD_COMPONENTS: usize = 5;
const BROAD_STEPS: usize = 30;

/// κ for the exactness property: small enough that κ² candidates (κ sources with at most κ
/// targets each, which is all there can be while the exact belief holds ≤ κ states) stay within
/// TimedME's default cap of 4κ + 16.
const KAPPA: usize = 6;

/// The differences between two beliefs over system states beyond 1e-9 (empty when equal up to
/// that; a state lighter than that may be missing from either).
fn differences(plant: &Plant, exact: &Belief, timed: &Belief) -> Vec<String> {
    let mut out = Vec::new();
    for t in timed.states() {
        if t.probability > 1e-9 && !exact.states().iter().any(|e| e.state == t.state) {
            out.push(format!(
                "TimedME has {} {:?} (p {}), the exact update has not",
                t.state.describe(plant),
                t.state.clock_starts,
                t.probability
            ));
        }
    }
    for e in exact.states() {
        let t = timed
            .states()
            .iter()
            .find(|t| t.state == e.state)
            .map_or(0.0, |t| t.probability);
        if (t - e.probability).abs() > 1e-9 {
            out.push(format!(
                "{} {:?}: exact {} TimedME {t}",
                e.state.describe(plant),
                e.state.clock_starts,
                e.probability
            ));
        }
    }
    out
}

/// ½ Σ |p − q| over system states.
fn total_variation(exact: &Belief, timed: &Belief) -> f64 {
    let mut distance: f64 = exact
        .states()
        .iter()
        .map(|e| {
            let t =
                (timed.states().iter().find(|t| t.state == e.state)).map_or(0.0, |t| t.probability);
            (e.probability - t).abs()
        })
        .sum();
    distance += (timed.states().iter())
        .filter(|t| !exact.states().iter().any(|e| e.state == t.state))
        .map(|t| t.probability)
        .sum::<f64>();
    0.5 * distance
}

/// The states of `update` that the model alone refutes.
fn inconsistent(plant: &Plant, theory: &mut Theory, update: &Update, who: &str) -> Vec<String> {
    update
        .belief
        .states()
        .iter()
        .filter(|w| !consistent_with(plant, theory, &w.state.modes, &Observation::none()))
        .map(|w| {
            format!(
                "{who} kept {} (p {}) against the model",
                w.state.describe(plant),
                w.probability
            )
        })
        .collect()
}

/// What one run showed: exactness problems while the exact belief fits in κ, and states
/// inconsistent with the model.
#[derive(Default)]
struct Findings {
    inexact: Vec<String>,
    inconsistent: Vec<String>,
    /// Steps where TimedME was further from the exact belief than its bound said.
    beyond_bound: Vec<String>,
}

fn run_case(spec: &RandomPlant, run: &RandomRun) -> Findings {
    run_case_at(spec, run, KAPPA)
}

fn run_case_at(spec: &RandomPlant, run: &RandomRun, kappa: usize) -> Findings {
    let mut findings = Findings::default();
    let Some(plant) = spec.plant() else {
        return findings;
    };
    let mut theory = plant.theory().expect("theory");
    let (first, cycles) = run.simulate(&plant, &mut theory);
    let mut exact = BeliefUpdate::new();
    let mut timed = TimedMe::new(TimedMeOptions::kappa(kappa));
    let mut e = exact
        .initial(&plant, &mut theory, 0.0, &first)
        .expect("exact initial");
    let mut t = timed
        .initial(&plant, &mut theory, 0.0, &first)
        .expect("timed initial");
    let mut within = true;
    for step in 0..=cycles.len() {
        let distance = total_variation(&e.belief, &t.belief);
        if distance > t.belief.distance_bound() + 1e-9 {
            findings.beyond_bound.push(format!(
                "step {step}: distance {distance} beyond the bound {} (events: exact {:?}, \
                 TimedME {:?})",
                t.belief.distance_bound(),
                e.events,
                t.events
            ));
        }
        within &= e.belief.states().len() <= kappa;
        if within {
            for difference in differences(&plant, &e.belief, &t.belief) {
                findings.inexact.push(format!(
                    "step {step}: {difference} (events: exact {:?}, TimedME {:?})",
                    e.events, t.events
                ));
            }
        }
        for (update, who) in [(&e, "the exact update"), (&t, "TimedME")] {
            for problem in inconsistent(&plant, &mut theory, update, who) {
                findings
                    .inconsistent
                    .push(format!("step {step}: {problem}"));
            }
        }
        let Some(cycle) = cycles.get(step) else {
            break;
        };
        e = cycle.update(&mut exact, &plant, &mut theory, &e);
        t = cycle.update(&mut timed, &plant, &mut theory, &t);
    }
    findings
}

proptest! {
    #![proptest_config(seeded::config(64))]

    /// TimedME equals the exact update while the exact belief fits in κ.
    #[test]
    fn timed_me_is_the_exact_update_while_kappa_states_suffice(
        spec in random_plant(MAX_COMPONENTS),
        run in random_run(MAX_COMPONENTS, MAX_STEPS),
    ) {
        let findings = run_case(&spec, &run);
        prop_assert!(
            findings.inexact.is_empty() && findings.beyond_bound.is_empty(),
            "{}\n{}\nmodel: {}",
            findings.inexact.join("\n"),
            findings.beyond_bound.join("\n"),
            spec.ron()
        );
    }

    /// No kept system state violates the model, observed or not.
    #[test]
    fn every_kept_state_is_consistent_with_the_model(
        spec in random_plant(MAX_COMPONENTS),
        run in random_run(MAX_COMPONENTS, MAX_STEPS),
    ) {
        let findings = run_case(&spec, &run);
        prop_assert!(
            findings.inconsistent.is_empty(),
            "{}\nmodel: {}",
            findings.inconsistent.join("\n"),
            spec.ron()
        );
    }
}

proptest! {
    // The broad plants are slower (up to 80 system states, 30 steps): a few cases by default.
    #![proptest_config(seeded::config(12))]

    /// Merging before truncating, and every kept state consistent, on the broad generator, whose
    /// powered modes can violate the connections when a step observes too little to rule them out.
    #[test]
    fn on_broad_plants_timed_me_is_exact_within_kappa_and_every_kept_state_is_consistent(
        spec in broad_plant(BROAD_COMPONENTS),
        run in runs(BROAD_COMPONENTS, 10, BROAD_STEPS),
    ) {
        let findings = run_case(&spec, &run);
        prop_assert!(
            findings.inexact.is_empty()
                && findings.inconsistent.is_empty()
                && findings.beyond_bound.is_empty(),
            "{}\n{}\n{}\nmodel: {}",
            findings.inexact.join("\n"),
            findings.inconsistent.join("\n"),
            findings.beyond_bound.join("\n"),
            spec.ron()
        );
    }

    /// The distance bound holds where truncation is heavy: κ = 3 on plants whose components
    /// go from fault to fault, half the steps observing nothing (Livingstone 2's benchmark in
    /// miniature).
    #[test]
    fn the_distance_bound_holds_on_partially_observed_fault_to_fault_plants(
        spec in fault_to_fault_plant(BROAD_COMPONENTS),
        run in sparse_runs(BROAD_COMPONENTS, 10, BROAD_STEPS, 0.5),
    ) {
        let findings = run_case_at(&spec, &run, 3);
        prop_assert!(
            findings.inconsistent.is_empty() && findings.beyond_bound.is_empty(),
            "{}\n{}\nmodel: {}",
            findings.inconsistent.join("\n"),
            findings.beyond_bound.join("\n"),
            spec.ron()
        );
    }
}
