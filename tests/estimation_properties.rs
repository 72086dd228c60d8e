//! TimedME against the exact update on random plants (DESIGN.md §8: "the exact
//! BeliefUpdate_TCCA is the reference the approximate estimator is measured against").
//!
//! Random plants of up to 5 components with up to 4 modes (random guards, mode constraints,
//! timings, faults; `tests/support/random_plant.rs`) run random command schedules; a simulated
//! true trajectory supplies observations consistent with it, one cycle in ten pure noise. Per
//! step, TimedME at κ = 10 must return the exact update's most likely plant state (up to exact
//! ties) in at least 99 % of steps, and must never return a state inconsistent with the
//! observation. `KAIROS_CASES=N` changes the number of random plants.

mod support;

#[path = "support/seeded.rs"]
mod seeded;
use kairos::estimation::{
    Belief, BeliefUpdate, EstimationEvent, Fallback, ModeEstimator, TimedMe, TimedMeOptions, Update,
};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use support::random_plant::{RandomPlant, RandomRun, consistent_with, random_plant, random_run};

const MAX_COMPONENTS: usize = 5;
const MAX_STEPS: usize = 10;

/// What one random plant and run showed.
#[derive(Default)]
struct Tally {
    steps: u64,
    agreed: u64,
    problems: Vec<String>,
    /// Random models validation refused.
    refused: u64,
}

/// TimedME's ŝ is the exact ŝ, or exactly as probable under the exact belief.
fn same_estimate(exact: &Belief, timed: &Belief) -> bool {
    let best = exact.most_likely_plant_state();
    let chosen = timed.most_likely_plant_state();
    if chosen.modes == best.modes {
        return true;
    }
    let exact_of_chosen = exact
        .plant_states()
        .into_iter()
        .find(|e| e.modes == chosen.modes)
        .map_or(0.0, |e| e.probability);
    exact_of_chosen >= best.probability * (1.0 - 1e-9)
}

fn set_aside(update: &Update) -> bool {
    update
        .events
        .contains(&EstimationEvent::InconsistentObservation {
            fallback: Fallback::PreviousBelief,
        })
}

fn run_case(spec: &RandomPlant, run: &RandomRun) -> Tally {
    let Some(plant) = spec.plant() else {
        return Tally {
            refused: 1,
            ..Tally::default()
        };
    };
    let mut theory = plant.theory().expect("theory");
    let (first, cycles) = run.simulate(&plant, &mut theory);
    let mut exact = BeliefUpdate::new();
    let mut timed = TimedMe::new(TimedMeOptions::kappa(10));
    let mut e = exact
        .initial(&plant, &mut theory, 0.0, &first)
        .expect("exact initial");
    let mut t = timed
        .initial(&plant, &mut theory, 0.0, &first)
        .expect("timed initial");
    let mut tally = Tally::default();
    let check = |tally: &mut Tally, e: &Update, t: &Update, observation, theory: &mut _, step| {
        tally.steps += 1;
        if same_estimate(&e.belief, &t.belief) {
            tally.agreed += 1;
        }
        if !set_aside(t) {
            for w in t.belief.states() {
                if !consistent_with(&plant, theory, &w.state.modes, observation) {
                    tally.problems.push(format!(
                        "step {step}: TimedME kept {} against the observation",
                        w.state.describe(&plant)
                    ));
                }
            }
        }
    };
    check(&mut tally, &e, &t, &first, &mut theory, 0);
    for (step, cycle) in cycles.iter().enumerate() {
        e = cycle.update(&mut exact, &plant, &mut theory, &e);
        t = cycle.update(&mut timed, &plant, &mut theory, &t);
        check(
            &mut tally,
            &e,
            &t,
            &cycle.observation,
            &mut theory,
            step + 1,
        );
    }
    tally
}

/// The measured agreement rate over many random plants (printed; run with `--nocapture`).
#[test]
fn timed_me_at_kappa_10_agrees_with_the_exact_update_in_99_percent_of_steps() {
    let strategy = (
        random_plant(MAX_COMPONENTS),
        random_run(MAX_COMPONENTS, MAX_STEPS),
    );
    let mut runner = seeded::runner();
    let mut total = Tally::default();
    for _ in 0..seeded::cases(300) {
        let (spec, run) = strategy.new_tree(&mut runner).expect("a case").current();
        let tally = run_case(&spec, &run);
        total.steps += tally.steps;
        total.agreed += tally.agreed;
        total.refused += tally.refused;
        for problem in tally.problems {
            total
                .problems
                .push(format!("{problem}\nmodel: {}", spec.ron()));
        }
    }
    let rate = total.agreed as f64 / total.steps as f64;
    println!(
        "TimedME (κ = 10) and the exact update agree on the most likely plant state in {} of {} steps: {:.2} % ({} random models refused by validation were skipped)",
        total.agreed,
        total.steps,
        100.0 * rate,
        total.refused
    );
    assert!(total.problems.is_empty(), "{}", total.problems.join("\n\n"));
    assert!(
        rate >= 0.99,
        "agreement {:.2} % is below 99 %",
        100.0 * rate
    );
}

proptest! {
    #![proptest_config(seeded::config(48))]

    /// Never a state inconsistent with the observation, whatever the plant and the run (unless
    /// the observation was set aside, which the update says).
    #[test]
    fn timed_me_never_keeps_a_state_the_observation_refutes(
        spec in random_plant(MAX_COMPONENTS),
        run in random_run(MAX_COMPONENTS, MAX_STEPS),
    ) {
        let tally = run_case(&spec, &run);
        prop_assert!(tally.problems.is_empty(), "{}", tally.problems.join("\n"));
    }
}
