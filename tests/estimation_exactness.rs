//! No loss of exactness from the theory's unit-propagation fast path (direction 4;
//! DESIGN.md §7: the theory answers "consistent?" and "entailed?" completely), nor from
//! replaying quiet steps (DESIGN.md §8, `src/estimation/replay.rs`).
//!
//! Propagation answers the questions it decides and leaves the rest to the SAT solver, which
//! still gives every conflict its core; skipping solver calls must change no answer and no
//! search order. So TimedME run on a theory with the fast path and on one without it
//! (`Theory::set_propagation`) must keep the same system states with bit-for-bit the same
//! probabilities, cycle after cycle: on the circuit-breaker tree, on the
//! Mars lander's EDL events (§7.2.2) and on random plants.
//!
//! A replayed step serves the last step's solutions re-costed only where it certifies that the
//! full expansion would give the same answer; so TimedME with replay on and off
//! (`TimedMeOptions::replay`) must give bit-for-bit the same beliefs too, and quiet cycles must
//! actually be replayed (`UpdateStats::replayed`). A warm TimedME must step quiet cycles as a
//! clone with empty caches does (the sources' choices kept across steps, the replay's kept
//! preparations and successors), and a replayed step must restart the clock of a candidate
//! that changes into a timed mode at the step's end, never copy an earlier step's successor.
//!
//! Conflicts learned by one source's OPSAT search are shared with the other sources' searches
//! under the same observation (`src/opsat/shared.rs`): they prune only
//! inconsistent assignments, and OPSAT returns equal-cost solutions in a canonical order
//! (`src/opsat/search.rs`, "Order"), so TimedME with sharing on and off
//! (`TimedMeOptions::share_conflicts`) must give bit-for-bit the same beliefs as well.
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
use support::lander_edl::{CYCLE, Faults, nominal_edl};
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

/// How TimedME is run: the theory's propagation fast path, replaying quiet steps, and sharing
/// conflicts between the sources' searches.
#[derive(Clone, Copy)]
struct Setting {
    propagation: bool,
    replay: bool,
    share: bool,
}

const REFERENCE: Setting = Setting {
    propagation: true,
    replay: true,
    share: true,
};
const NO_PROPAGATION: Setting = Setting {
    propagation: false,
    ..REFERENCE
};
const NO_REPLAY: Setting = Setting {
    replay: false,
    ..REFERENCE
};
const NO_SHARING: Setting = Setting {
    share: false,
    ..REFERENCE
};

/// TimedME at κ as `setting` says.
fn estimator(kappa: usize, setting: Setting) -> TimedMe {
    TimedMe::new(TimedMeOptions {
        replay: setting.replay,
        share_conflicts: setting.share,
        ..TimedMeOptions::kappa(kappa)
    })
}

/// Every belief of a TimedME replay of `records` (the initial one first), and how many steps
/// were replayed.
fn beliefs(plant: &Plant, records: &[LogRecord], setting: Setting) -> (Vec<Belief>, usize) {
    let mut theory = plant.theory().expect("theory");
    theory.set_propagation(setting.propagation);
    let mut estimator = estimator(10, setting);
    let updates = replay(plant, &mut theory, &mut estimator, records).expect("replays");
    assert!(
        setting.propagation || theory.stats().propagated == 0,
        "off means every question goes to the solver"
    );
    let replayed = updates.iter().filter(|u| u.stats.replayed).count();
    assert!(setting.replay || replayed == 0, "off means never replayed");
    (updates.into_iter().map(|u| u.belief).collect(), replayed)
}

/// The step at which the replays in the reference setting and in `other` first differ, if any.
fn first_difference(plant: &Plant, records: &[LogRecord], other: Setting) -> Option<usize> {
    let (with, _) = beliefs(plant, records, REFERENCE);
    let (without, _) = beliefs(plant, records, other);
    assert_eq!(with.len(), without.len());
    with.iter()
        .zip(&without)
        .position(|(a, b)| exactly(a) != exactly(b))
}

#[test]
fn the_breaker_tree_is_estimated_identically_with_and_without_propagation_replay_and_sharing() {
    let plant = Plant::load(&Source::new(
        "breakers_15.ron",
        breakers::breaker_tree_ron(15),
    ))
    .expect("loads");
    let log = Source::new("breakers_15.jsonl", breakers::breaker_log(15, 7));
    let records = parse_log(&log, &plant).expect("parses");
    assert_eq!(first_difference(&plant, &records, NO_PROPAGATION), None);
    assert_eq!(first_difference(&plant, &records, NO_REPLAY), None);
    assert_eq!(first_difference(&plant, &records, NO_SHARING), None);
}

#[test]
fn the_mars_edl_events_are_estimated_identically_with_and_without_propagation_replay_and_sharing() {
    // The nominal EDL on a 600 s grid, with every command and observation change (the
    // `events` case of `examples/me_profile.rs`, where the busy cycles are), up to the entry.
    let plant = model("mars_lander");
    let timeline = nominal_edl(Faults::default());
    let times = timeline.times(support::lander_edl::edl::ENTRY + 60.0, 600.0);
    let records = timeline.records(&plant, &times);
    assert!(records.len() > 30, "{} records", records.len());
    assert_eq!(first_difference(&plant, &records, NO_PROPAGATION), None);
    assert_eq!(first_difference(&plant, &records, NO_REPLAY), None);
    assert_eq!(first_difference(&plant, &records, NO_SHARING), None);
}

/// The EDL replayed on a 600 s grid up to `from` s, then `steps` cycles of 0.1 s.
fn quiet_window(plant: &Plant, from: f64, steps: u64) -> Vec<LogRecord> {
    let timeline = nominal_edl(Faults::default());
    let start = support::lander_edl::ms(from);
    let mut times: Vec<u64> = timeline
        .times(support::lander_edl::edl::END, 600.0)
        .into_iter()
        .filter(|&t| t < start)
        .chain((0..steps).map(|k| start + k * support::lander_edl::ms(CYCLE)))
        .collect();
    times.sort_unstable();
    times.dedup();
    timeline.records(plant, &times)
}

#[test]
fn quiet_mars_edl_cycles_are_replayed_with_the_full_steps_beliefs() {
    // The cruise (the entry clock running), the engine's heating window with its end (engine
    // heating → standby at 43.2 s: a new observation) and the entry window (the per-step
    // probability moving every cycle): §7.2.2's EDL at the executive's 0.1 s cycle.
    let plant = model("mars_lander");
    for (from, steps) in [(1000.0, 300), (25.0, 300), (15700.0, 300)] {
        let records = quiet_window(&plant, from, steps);
        let (replayed, count) = beliefs(&plant, &records, REFERENCE);
        let (full, _) = beliefs(&plant, &records, NO_REPLAY);
        let first = replayed
            .iter()
            .zip(&full)
            .position(|(a, b)| exactly(a) != exactly(b));
        assert_eq!(first, None, "window from {from} s");
        // Every cycle of the window but the first few (where the solution cache and the
        // record are still being filled) and the few after the heating window's end.
        assert!(
            count + 20 >= steps as usize,
            "window from {from} s: {count} of {steps} quiet cycles replayed"
        );
    }
}

proptest! {
    #![proptest_config(seeded::config(48))]

    /// Random plants and runs (`tests/support/random_plant.rs`): the same beliefs, bit for bit.
    #[test]
    fn random_plants_are_estimated_identically_with_and_without_propagation_replay_and_sharing(
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
        for setting in [REFERENCE, NO_PROPAGATION, NO_REPLAY, NO_SHARING] {
            let mut theory = plant.theory().expect("theory");
            theory.set_propagation(setting.propagation);
            let mut estimator = estimator(4, setting);
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
        for other in &beliefs[1..] {
            for (step, (a, b)) in beliefs[0].iter().zip(other).enumerate() {
                prop_assert_eq!(exactly(a), exactly(b), "step {}\nmodel: {}", step, spec.ron());
            }
        }
    }
}

/// A warm TimedME and a clone of it (`TimedMe::clone`: the history copied, every cache
/// empty) take each step of `records` from `from` s on from the same belief: the warm one's
/// caches — the sources' choices kept from recent steps (`expand.rs`, `Recents`), the replay's
/// preparations and successors (`replay.rs`, conditions 1–7) — must change no bit of any
/// belief. (Before `from`, on the EDL's 600 s grid, a cold clone does not always agree with
/// the warm estimator bit for bit, on main as well; the quiet cycles are what this checks.)
fn warm_steps_as_cold(plant: &Plant, records: &[LogRecord], from: f64) -> Option<usize> {
    let mut theory = plant.theory().expect("theory");
    let mut warm = estimator(10, REFERENCE);
    let first = records.first().expect("a record");
    let mut belief = warm
        .initial(plant, &mut theory, first.time, &first.observation)
        .expect("initial")
        .belief;
    records.windows(2).position(|pair| {
        let (before, now) = (&pair[0], &pair[1]);
        let mut step = |estimator: &mut TimedMe| {
            let update = estimator.update(
                plant,
                &mut theory,
                &belief,
                &before.commands,
                &now.observation,
                now.time,
            );
            update.expect("update").belief
        };
        let fresh = (now.time >= from).then(|| step(&mut warm.clone()));
        let hot = step(&mut warm);
        let differ = fresh.is_some_and(|fresh| exactly(&hot) != exactly(&fresh));
        belief = hot;
        differ
    })
}

#[test]
fn a_warm_estimator_steps_quiet_mars_edl_cycles_as_a_cold_one() {
    // A quiet step replayed and its sources' choices kept across steps: the cruise
    // with the entry clock running and the cycle's length jittering in its last bits, and the
    // heating window with its end (§7.2.2's EDL at the executive's 0.1 s cycle).
    let plant = model("mars_lander");
    for (from, steps) in [(1000.0, 120), (40.0, 60)] {
        let records = quiet_window(&plant, from, steps);
        assert_eq!(
            warm_steps_as_cold(&plant, &records, from),
            None,
            "window from {from} s"
        );
    }
}

/// A heater that degrades (1 % per cycle) into a mode whose clock matters (it burns out within
/// 5 s), observed hot throughout: every quiet step's candidate "starts degrading now" restarts
/// a clock at the step's end, so its successor must never be copied from an earlier step
/// (`replay.rs`, condition 7).
const DEGRADING_HEATER: &str = r#"Plant(
    name: "degrading_heater",
    components: [
        Component(
            name: "heater",
            attributes: { "temp": ["low", "high"] },
            modes: [
                Mode(name: "ok", constraint: "heater.temp = high", reward: 0),
                Mode(name: "degrading", kind: Fault, constraint: "true", reward: -5),
                Mode(name: "burnt", kind: Fault, constraint: "heater.temp = low", reward: -10),
            ],
            initial: { "ok": 1.0 },
            transitions: [
                (from: "ok", to: "degrading", probability: 0.01),
                (from: "degrading", to: "burnt", after: Uniform(0.0, 5.0), probability: 1.0),
            ],
        ),
    ],
    controls: {},
    observables: ["heater.temp"],
    connections: [],
)"#;

#[test]
fn a_replayed_step_restarts_the_clocks_of_its_candidates_successors() {
    // Figure 6-11 step 5: a component that changes mode restarts its clock at t(i+1).
    let plant = Plant::load(&Source::new("degrading_heater.ron", DEGRADING_HEATER)).expect("loads");
    let log: String = (0..200)
        .map(|k| {
            format!(
                "{{\"time\": {}, \"observations\": {{\"heater.temp\": \"high\"}}}}\n",
                1000.0 + k as f64 * 0.1
            )
        })
        .collect();
    let records = parse_log(&Source::new("heater.jsonl", log), &plant).expect("parses");
    let (_, replayed) = beliefs(&plant, &records, REFERENCE);
    assert!(replayed > 100, "{replayed} of 199 steps replayed");
    assert_eq!(first_difference(&plant, &records, NO_REPLAY), None);
}
