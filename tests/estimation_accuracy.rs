//! The accuracy of TimedME against the exact update on broad random plants (the history
//! window's measure; DESIGN.md §8: "the exact BeliefUpdate_TCCA is the reference the approximate
//! estimator is measured against"): per step, whether TimedME's most likely plant state is the
//! exact one (up to exact ties) and the total-variation distance between the two distributions
//! over plant states, at κ = 3, 5, 10 and 20, with TimedME's history window and without, and
//! the time TimedME took per update. The window runs under both re-run policies
//! (`Rerun::Doubt`, the default, rows `on`; `Rerun::Surprise`, rows `on, surprise`; src/
//! estimation/timed_me.rs, "When the window is re-run"). A measurement, recorded in
//! BENCHMARKS.md:
//!
//! ```text
//! KAIROS_CASES=3000 cargo test --release --test estimation_accuracy -- --ignored --nocapture
//! ```

mod support;

#[path = "support/seeded.rs"]
mod seeded;

use std::collections::HashMap;
use std::time::Instant;

use kairos::estimation::{
    Belief, BeliefUpdate, ModeEstimator, Rerun, TimedMe, TimedMeOptions, Update,
};
use kairos::logic::ValueId;
use proptest::strategy::{Strategy, ValueTree};
use support::random_plant::{
    RandomPlant, RandomRun, broad_plant, fault_to_fault_plant, runs, sparse_runs,
};

/// The estimators scored: κ, whether TimedME keeps its history window (docs/design/
/// estimation.md, "The history window"; 0 turns it off) and what re-runs it.
const ESTIMATORS: [(usize, usize, Rerun); 12] = [
    (3, 0, Rerun::Doubt),
    (3, DEFAULT_HISTORY, Rerun::Doubt),
    (3, DEFAULT_HISTORY, Rerun::Surprise),
    (5, 0, Rerun::Doubt),
    (5, DEFAULT_HISTORY, Rerun::Doubt),
    (5, DEFAULT_HISTORY, Rerun::Surprise),
    (10, 0, Rerun::Doubt),
    (10, DEFAULT_HISTORY, Rerun::Doubt),
    (10, DEFAULT_HISTORY, Rerun::Surprise),
    (20, 0, Rerun::Doubt),
    (20, DEFAULT_HISTORY, Rerun::Doubt),
    (20, DEFAULT_HISTORY, Rerun::Surprise),
];
const DEFAULT_HISTORY: usize = usize::MAX;
const COMPONENTS: usize = 5;
const STEPS: usize = 30;

/// Per κ: steps, steps whose ŝ agreed, summed total-variation distance, and the updates that
/// re-ran the history window (and how many steps they re-ran), and the time TimedME took.
#[derive(Default, Clone, Copy)]
struct Score {
    seconds: f64,
    steps: u64,
    agreed: u64,
    distance: f64,
    reruns: u64,
    rerun_steps: u64,
}

/// TimedME's ŝ is the exact ŝ, or exactly as probable under the exact belief.
fn agrees(exact: &Belief, timed: &Belief) -> bool {
    let best = exact.most_likely_plant_state();
    let chosen = timed.most_likely_plant_state();
    chosen.modes == best.modes
        || exact
            .plant_states()
            .iter()
            .find(|e| e.modes == chosen.modes)
            .is_some_and(|e| e.probability >= best.probability * (1.0 - 1e-9))
}

/// ½ Σ |p − q| over plant states.
fn total_variation(exact: &Belief, timed: &Belief) -> f64 {
    let mut difference: HashMap<std::sync::Arc<[ValueId]>, f64> = HashMap::new();
    for e in exact.plant_states() {
        *difference.entry(e.modes).or_default() += e.probability;
    }
    for t in timed.plant_states() {
        *difference.entry(t.modes).or_default() -= t.probability;
    }
    0.5 * difference.values().map(|d| d.abs()).sum::<f64>()
}

/// Scores one plant and run into `scores`; returns the largest exact belief (system states),
/// or `None` when validation refused the plant.
fn measure(spec: &RandomPlant, run: &RandomRun, scores: &mut [Score]) -> Option<usize> {
    let plant = spec.plant()?;
    let mut theory = plant.theory().expect("theory");
    let (first, cycles) = run.simulate(&plant, &mut theory);
    let mut exact = BeliefUpdate::new();
    let mut e = exact
        .initial(&plant, &mut theory, 0.0, &first)
        .expect("exact initial");
    let mut timed: Vec<(TimedMe, Update)> = ESTIMATORS
        .iter()
        .map(|&(kappa, history, rerun)| {
            let mut options = TimedMeOptions {
                rerun,
                ..TimedMeOptions::kappa(kappa)
            };
            if history != DEFAULT_HISTORY {
                options.history = history;
            }
            let mut estimator = TimedMe::new(options);
            let update = estimator
                .initial(&plant, &mut theory, 0.0, &first)
                .expect("timed initial");
            (estimator, update)
        })
        .collect();
    let mut largest = e.belief.states().len();
    for cycle in &cycles {
        e = cycle.update(&mut exact, &plant, &mut theory, &e);
        largest = largest.max(e.belief.states().len());
        for ((estimator, t), score) in timed.iter_mut().zip(scores.iter_mut()) {
            let started = Instant::now();
            *t = cycle.update(estimator, &plant, &mut theory, t);
            score.seconds += started.elapsed().as_secs_f64();
            score.steps += 1;
            score.agreed += u64::from(agrees(&e.belief, &t.belief));
            score.distance += total_variation(&e.belief, &t.belief);
            score.reruns += u64::from(t.stats.rerun > 0);
            score.rerun_steps += u64::from(t.stats.rerun);
        }
    }
    Some(largest)
}

#[test]
#[ignore = "a measurement (BENCHMARKS.md): run in release with --ignored --nocapture"]
fn accuracy_of_timed_me_on_broad_random_plants() {
    report(
        "broad random plants",
        (broad_plant(COMPONENTS), runs(COMPONENTS, 10, STEPS)),
    );
}

/// As Livingstone 2's benchmark has them: components that go from fault to fault, and runs whose
/// steps observe nothing half of the time (the others some observables each).
#[test]
#[ignore = "a measurement (BENCHMARKS.md): run in release with --ignored --nocapture"]
fn accuracy_of_timed_me_on_partially_observed_fault_to_fault_plants() {
    report(
        "fault-to-fault random plants, half the steps blind",
        (
            fault_to_fault_plant(COMPONENTS),
            sparse_runs(COMPONENTS, 10, STEPS, 0.5),
        ),
    );
}

/// Measures `seeded::cases(300)` plants and runs from `strategy` and prints the tables.
fn report(name: &str, strategy: impl Strategy<Value = (RandomPlant, RandomRun)>) {
    let mut runner = seeded::runner();
    // Scored apart: plants whose exact belief stays within 80 system states (the issue's
    // "30–80 clock-distinct states" and smaller) and the wider ones (up to thousands).
    let mut narrow = [Score::default(); ESTIMATORS.len()];
    let mut broad = [Score::default(); ESTIMATORS.len()];
    let (mut plants, mut refused, mut wide, mut widest) = (0u32, 0u32, 0u32, 0usize);
    for _ in 0..seeded::cases(300) {
        let (spec, run) = strategy.new_tree(&mut runner).expect("a case").current();
        let mut scores = [Score::default(); ESTIMATORS.len()];
        match measure(&spec, &run, &mut scores) {
            Some(largest) => {
                plants += 1;
                widest = widest.max(largest);
                wide += u32::from(largest > 80);
                let into = if largest > 80 {
                    &mut broad
                } else {
                    &mut narrow
                };
                for (total, score) in into.iter_mut().zip(&scores) {
                    total.steps += score.steps;
                    total.agreed += score.agreed;
                    total.distance += score.distance;
                    total.seconds += score.seconds;
                    total.reruns += score.reruns;
                    total.rerun_steps += score.rerun_steps;
                }
            }
            None => refused += 1,
        }
    }
    println!(
        "{plants} {name} ({refused} refused by validation); exact beliefs stayed \
         within 80 system states on {}, reached more on {wide} (at most {widest})",
        plants - wide
    );
    for (title, scores) in [("≤ 80 states", &narrow), ("> 80 states", &broad)] {
        println!("\nExact belief {title}:\n");
        println!(
            "| κ | history | steps | top-1 agreement | mean total-variation distance | updates \
             re-run | steps re-run per update | TimedME µs per update |"
        );
        println!("|---|---|---|---|---|---|---|---|");
        for (&(kappa, history, rerun), score) in ESTIMATORS.iter().zip(scores) {
            let steps = score.steps.max(1) as f64;
            println!(
                "| {kappa} | {} | {} | {:.2} % | {:.4} | {:.2} % | {:.2} | {:.1} |",
                match (history, rerun) {
                    (0, _) => "off",
                    (_, Rerun::Doubt) => "on",
                    (_, Rerun::Surprise) => "on, surprise",
                },
                score.steps,
                100.0 * score.agreed as f64 / steps,
                score.distance / steps,
                100.0 * score.reruns as f64 / steps,
                score.rerun_steps as f64 / steps,
                1e6 * score.seconds / steps
            );
        }
    }
    assert!(plants > 0);
}
