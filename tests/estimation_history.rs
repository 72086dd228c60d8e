//! TimedME's history (beyond the thesis; docs/design/estimation.md, "The
//! history window"): when an observation contradicts every tracked state, the last steps are
//! estimated again tracking more states before DESIGN.md §8's fault-jump fallback — so a state
//! truncated away a few steps ago is found again, with its weight.

mod support;

use kairos::estimation::{
    EstimationEvent, Fallback, ModeEstimator, Rerun, TimedMe, TimedMeOptions, Update,
};
use kairos::plant::{Commands, Observation, Plant};
use support::plants::{mode_in, plant_from, value};

/// A switch that may start moving up unseen (`p` a cycle) and is up the cycle after, never
/// back; a lamp lit only when it is up; a fault no transition enters, which explains any lamp
/// (DESIGN.md §8's fault jumps).
fn switch(p: f64) -> Plant {
    let text = r#"Plant(
            name: "switch",
            components: [Component(
                name: "switch",
                attributes: { "lamp": ["dark", "lit"] },
                modes: [
                    Mode(name: "down", constraint: "switch.lamp = dark"),
                    Mode(name: "moving", constraint: "switch.lamp = dark"),
                    Mode(name: "up", constraint: "switch.lamp = lit"),
                    Mode(name: "broken", kind: Fault),
                ],
                initial: { "down": 1.0 },
                transitions: [
                    (from: "down", to: "moving", probability: MOVE),
                    (from: "moving", to: "up", probability: 1.0),
                ],
            )],
            observables: ["switch.lamp"],
        )"#;
    plant_from("switch", &text.replace("MOVE", &p.to_string()))
}

/// `estimator` from its own initial belief through two unseen cycles (κ = 1 truncates the move
/// away, being the less likely), then the lamp lit. Returns every update.
fn run(plant: &Plant, estimator: &mut TimedMe) -> Vec<Update> {
    let mut theory = plant.theory().expect("theory");
    let idle = Commands::idle(plant);
    let lit = Observation::new(plant, &[value(plant, "switch.lamp", "lit")]).expect("obs");
    let mut updates = vec![
        estimator
            .initial(plant, &mut theory, 0.0, &Observation::none())
            .expect("initial"),
    ];
    for (time, observation) in [
        (1.0, Observation::none()),
        (2.0, Observation::none()),
        (3.0, lit),
    ] {
        let last = &updates[updates.len() - 1].belief;
        let next = estimator
            .update(plant, &mut theory, last, &idle, &observation, time)
            .expect("update");
        updates.push(next);
    }
    updates
}

/// ŝ's mode of the switch after `update`.
fn estimate<'a>(plant: &'a Plant, update: &Update) -> &'a str {
    mode_in(plant, &update.belief.most_likely_plant_state(), "switch")
}

/// `update` explained its observation by re-running `steps` steps of the history, and ŝ is
/// `mode`.
fn assert_reestimated(plant: &Plant, update: &Update, steps: usize, mode: &str) {
    assert_eq!(
        update.events,
        vec![EstimationEvent::InconsistentObservation {
            fallback: Fallback::Reestimated { steps }
        }]
    );
    assert_eq!(estimate(plant, update), mode);
}

fn kappa_one(history: usize) -> TimedMe {
    TimedMe::new(TimedMeOptions {
        history,
        ..TimedMeOptions::kappa(1)
    })
}

#[test]
fn a_state_truncated_within_the_window_is_found_again() {
    let plant = switch(0.02);
    let updates = run(&plant, &mut kappa_one(16));
    // Unseen, κ = 1 keeps `down` (0.98 a cycle against 0.02; 0.04 truncated in all, too little
    // to put ŝ in doubt).
    for update in &updates[1..3] {
        assert_eq!(estimate(&plant, update), "down");
        assert!(update.events.is_empty());
    }
    // The lamp lit: `down` cannot show it; the three steps estimated again at 8κ = 8 hold `up`.
    let last = &updates[3];
    assert_reestimated(&plant, last, 3, "up");
}

#[test]
fn without_the_history_the_fault_explains_it() {
    let plant = switch(0.02);
    let last = &run(&plant, &mut kappa_one(0))[3];
    assert_eq!(
        last.events,
        vec![EstimationEvent::InconsistentObservation {
            fallback: Fallback::UnconstrainedFaults
        }]
    );
    assert_eq!(estimate(&plant, last), "broken");
}

#[test]
fn an_update_from_another_belief_starts_the_window_afresh() {
    // The caller goes on, at the second cycle, from a belief this estimator did not return (a
    // κ = 2 estimator's, which holds the move): the window starts there, so the lamp's step
    // re-runs two steps, not three.
    let plant = switch(0.1);
    let mut theory = plant.theory().expect("theory");
    let idle = Commands::idle(&plant);
    let foreign = &run(&plant, &mut TimedMe::new(TimedMeOptions::kappa(2)))[1].belief;
    let mut estimator = kappa_one(16);
    let own = &run(&plant, &mut estimator)[1].belief;
    assert_ne!(foreign, own);
    let second = estimator
        .update(
            &plant,
            &mut theory,
            foreign,
            &idle,
            &Observation::none(),
            2.0,
        )
        .expect("update");
    assert_eq!(estimate(&plant, &second), "down");
    let lit = Observation::new(&plant, &[value(&plant, "switch.lamp", "lit")]).expect("obs");
    let third = estimator
        .update(&plant, &mut theory, &second.belief, &idle, &lit, 3.0)
        .expect("update");
    assert_reestimated(&plant, &third, 2, "up");
}

#[test]
fn a_truncation_that_could_decide_the_estimate_is_rerun_wider() {
    // With the move at 0.4 a cycle, two unseen cycles leave the exact belief at up 0.4, down
    // 0.36, moving 0.24: ŝ = up. κ = 1 alone keeps `down` both cycles (0.6 against 0.4); the
    // weight it truncated (0.4, then 0.64) could reverse its single plant state, so the window
    // is run again at 8κ = 8 and gives the exact ŝ, silently (no event: nothing was wrong with
    // the observations). The lamp's step is in doubt too (the window's loss stays): the wide
    // belief the re-run kept is stepped once instead of the window re-run.
    let plant = switch(0.4);
    let narrow = run(&plant, &mut kappa_one(0));
    let wide = run(&plant, &mut kappa_one(16));
    assert_eq!(estimate(&plant, &narrow[2]), "down");
    assert_eq!(narrow[2].stats.rerun, 0);
    assert_eq!(estimate(&plant, &wide[2]), "up");
    assert_eq!(wide[2].stats.rerun, 2);
    assert!(wide[2].events.is_empty());
    assert_eq!(estimate(&plant, &wide[3]), "up");
    assert_eq!(wide[3].stats.rerun, 1);
}

#[test]
fn on_surprise_alone_doubt_does_not_rerun_but_a_contradiction_does() {
    // The case above, re-running only on contradiction and surprise (`Rerun::Surprise`,
    // src/estimation/timed_me.rs "When the window is re-run"): the two unseen cycles put ŝ in
    // doubt, which re-ran the window above; here they do not, and ŝ stays κ = 1's `down`, as
    // without a history. The lamp lit contradicts `down`: the window is re-run from its start
    // (three steps) and finds `up`, where no history would have blamed the fault.
    let plant = switch(0.4);
    let mut estimator = TimedMe::new(TimedMeOptions {
        rerun: Rerun::Surprise,
        ..TimedMeOptions::kappa(1)
    });
    let updates = run(&plant, &mut estimator);
    for update in &updates[1..3] {
        assert_eq!(update.stats.rerun, 0);
        assert_eq!(estimate(&plant, update), "down");
        assert!(update.events.is_empty());
    }
    assert_reestimated(&plant, &updates[3], 3, "up");
    assert_eq!(updates[3].stats.rerun, 3);
}

#[test]
fn the_default_reruns_on_doubt() {
    assert_eq!(TimedMeOptions::kappa(1).rerun, Rerun::Doubt);
    assert_eq!(Rerun::default(), Rerun::Doubt);
}
