//! Mode estimation against the thesis (its acceptance): Table 6.1's timed transition,
//! §6.2.2's conditional form, §7.1.2's heating engine, Figures 6-8/6-9, and the fallback on
//! inconsistent observations (DESIGN.md §8). Each runs the exact BeliefUpdate_TCCA (Figure 6-10)
//! and TimedME (Figure 6-11).

mod support;

use kairos::estimation::{
    Belief, BeliefUpdate, EstimationEvent, Fallback, ModeEstimator, TimedMe, TimedMeOptions,
};
use kairos::opsat::Theory;
use kairos::plant::{Commands, Observation, Plant};
use support::plants::{certain, log, marginal, mode_in, model, model_text, plant_from, value};

fn estimators(kappa: usize) -> Vec<(String, Box<dyn ModeEstimator>)> {
    vec![
        ("exact".to_string(), Box::new(BeliefUpdate::new())),
        (
            format!("TimedME κ={kappa}"),
            Box::new(TimedMe::new(TimedMeOptions::kappa(kappa))),
        ),
    ]
}

fn idle_step(
    estimator: &mut dyn ModeEstimator,
    plant: &Plant,
    theory: &mut Theory,
    belief: &Belief,
    time: f64,
) -> Belief {
    estimator
        .update(
            plant,
            theory,
            belief,
            &Commands::idle(plant),
            &Observation::none(),
            time,
        )
        .expect("update")
        .belief
}

/// Table 6.1, τ6 at t_D = 0.1: one cycle spanning TurningOn's window takes the driver to On with
/// probability 0.989; commanded on from Off, two such cycles give 0.989².
#[test]
fn table_6_1_p_on_is_0_989_after_one_cycle_spanning_the_window() {
    let plant = model("driver_valve");
    let mut theory = plant.theory().expect("theory");
    for (name, mut estimator) in estimators(10) {
        let turning_on = certain(&plant, &["turning-on", "closed"], 0.0);
        let after = idle_step(estimator.as_mut(), &plant, &mut theory, &turning_on, 0.1);
        let p_on = marginal(&plant, &after, "driver", "on");
        assert!((p_on - 0.989).abs() < 1e-12, "{name}: {p_on}");

        let off = certain(&plant, &["off", "closed"], 0.0);
        let on = Commands::new(&plant, &[value(&plant, "driver.dcmd_in", "on")]).expect("command");
        let commanded = estimator
            .update(&plant, &mut theory, &off, &on, &Observation::none(), 0.1)
            .expect("update")
            .belief;
        assert!((marginal(&plant, &commanded, "driver", "turning-on") - 0.989).abs() < 1e-12);
        let after = idle_step(estimator.as_mut(), &plant, &mut theory, &commanded, 0.2);
        let p_on = marginal(&plant, &after, "driver", "on");
        assert!((p_on - 0.989 * 0.989).abs() < 1e-12, "{name}: {p_on}");
    }
}

/// §6.2.2 / DESIGN.md §6.2: with the fault transitions removed (and the nominal factor 0.989,
/// which is 1 minus the fault probabilities, back to 1), the exact update's probability of having
/// reached On by time t is F(t), the CDF of τ6's uniform density, for any cycle period — the
/// conditional form composes correctly.
#[test]
fn table_6_1_reaching_on_by_t_is_the_cdf_for_any_cycle_period() {
    let text: String = model_text("driver_valve")
        .lines()
        .filter(|l| !l.contains("to: \"resettable\"") && !l.contains("to: \"failed\""))
        .filter(|l| !l.contains("to: \"stuck-"))
        .map(|l| l.replace("probability: 0.989", "probability: 1.0") + "\n")
        .collect();
    let plant = plant_from("driver_valve without faults", &text);
    let mut theory = plant.theory().expect("theory");
    let cdf = |t: f64| (t / 0.1).min(1.0);
    let jittered = [0.013, 0.031, 0.007, 0.024, 0.002, 0.05];
    for periods in [
        vec![0.01; 12],
        vec![0.025; 5],
        vec![0.03; 5],
        vec![0.07; 3],
        vec![0.1; 2],
        vec![0.15; 2],
        jittered.to_vec(),
    ] {
        let mut estimator = BeliefUpdate::new();
        let mut belief = certain(&plant, &["turning-on", "closed"], 0.0);
        let mut t = 0.0;
        for period in &periods {
            t += period;
            belief = idle_step(&mut estimator, &plant, &mut theory, &belief, t);
            let reached = marginal(&plant, &belief, "driver", "on");
            assert!(
                (reached - cdf(t)).abs() < 1e-9,
                "periods {periods:?}: at {t} s P(on) = {reached}, F = {}",
                cdf(t)
            );
        }
    }
}

/// §7.1.2 (and DESIGN.md §6.2): the engine commanded to standby, no temperature observations:
/// ŝ(engine) is heating before 45 s of heating and standby from the first cycle at or after
/// 45 s — with κ = 5 TimedME and with the exact update, for several cycle periods.
#[test]
fn section_7_1_2_heating_until_45_s_then_standby() {
    let plant = model("engine_camera");
    let mut theory = plant.theory().expect("theory");
    let standby = Commands::new(&plant, &[value(&plant, "engine.cmd", "standby")]).expect("cmd");
    for period in [1.0, 0.7, 2.5] {
        for (name, mut estimator) in estimators(5) {
            let start = estimator
                .initial(&plant, &mut theory, 0.0, &Observation::none())
                .expect("initial")
                .belief;
            let mut belief = estimator
                .update(
                    &plant,
                    &mut theory,
                    &start,
                    &standby,
                    &Observation::none(),
                    period,
                )
                .expect("update")
                .belief;
            let heating_since = period;
            let mut t = period;
            while t - heating_since < 52.0 {
                let clock = t - heating_since;
                let expected = if clock < 45.0 - 1e-9 {
                    "heating"
                } else {
                    "standby"
                };
                let estimate = belief.most_likely_plant_state();
                assert_eq!(
                    mode_in(&plant, &estimate, "engine"),
                    expected,
                    "{name}, period {period}: heating clock {clock}"
                );
                t += period;
                belief = idle_step(estimator.as_mut(), &plant, &mut theory, &belief, t);
            }
            assert!(belief.states().len() <= 5 || name == "exact");
        }
    }
}

/// Figures 6-8 and 6-9: commanding the engine off during heating returns it to off, whether or
/// not the timed transition to standby has been taken by then; without a command, heating cannot
/// outlast its window.
#[test]
fn figures_6_8_and_6_9_off_during_heating_returns_to_off_either_way() {
    let plant = model("engine_camera");
    let mut theory = plant.theory().expect("theory");
    let off = Commands::new(&plant, &[value(&plant, "engine.cmd", "off")]).expect("cmd");
    for (name, mut estimator) in estimators(10) {
        let mut belief = certain(&plant, &["heating", "off"], 0.0);
        for t in 1..=33 {
            belief = idle_step(
                estimator.as_mut(),
                &plant,
                &mut theory,
                &belief,
                f64::from(t),
            );
        }
        // Figure 6-9 at t1 + 30 + 3dt: both branches of the trellis are alive.
        let heating = marginal(&plant, &belief, "engine", "heating");
        let standby = marginal(&plant, &belief, "engine", "standby");
        assert!(
            heating > 0.8 && standby > 0.05,
            "{name}: {heating} {standby}"
        );
        let after = estimator
            .update(
                &plant,
                &mut theory,
                &belief,
                &off,
                &Observation::none(),
                34.0,
            )
            .expect("update")
            .belief;
        // Everything not failed (10⁻⁵/s over 34 s) is off: from heating and from standby alike.
        let p_off = marginal(&plant, &after, "engine", "off");
        let p_failed = marginal(&plant, &after, "engine", "failed");
        assert!(
            (p_off + p_failed - 1.0).abs() < 1e-12,
            "{name}: P(off) = {p_off}"
        );
        assert!(p_failed < 35e-5, "{name}: P(failed) = {p_failed}");

        // Figure 6-8: past the window, heating is gone.
        for t in 34..=61 {
            belief = idle_step(
                estimator.as_mut(),
                &plant,
                &mut theory,
                &belief,
                f64::from(t),
            );
        }
        assert_eq!(
            marginal(&plant, &belief, "engine", "heating"),
            0.0,
            "{name}"
        );
    }
}

/// DESIGN.md §8: when nothing tracked explains an observation, the estimator says so, tries the
/// unconstrained fault modes, then keeps the previous belief — and never panics.
#[test]
fn inconsistent_observations_fall_back_and_say_so() {
    // Flow out of a valve with no flow in: no valve mode allows it, and the valve has no
    // unconstrained fault mode to fall back on.
    let plant = model("driver_valve");
    let mut theory = plant.theory().expect("theory");
    let impossible = Observation::new(
        &plant,
        &[
            value(&plant, "valve.flow_in", "zero"),
            value(&plant, "valve.flow_out", "nominal"),
        ],
    )
    .expect("observation");
    for (name, mut estimator) in estimators(10) {
        let belief = certain(&plant, &["on", "closed"], 0.0);
        let update = estimator
            .update(
                &plant,
                &mut theory,
                &belief,
                &Commands::idle(&plant),
                &impossible,
                1.0,
            )
            .expect("update");
        assert_eq!(
            update.events,
            vec![EstimationEvent::InconsistentObservation {
                fallback: Fallback::PreviousBelief
            }],
            "{name}"
        );
        assert_eq!(update.belief.time(), 1.0);
        assert_eq!(update.belief.states(), belief.states());
    }

    // A sensor nothing reachable explains, but an unconstrained fault does: a component that
    // cannot fail by any transition is caught jumping into `broken`.
    let sensor = plant_from(
        "sensor",
        r#"Plant(
            name: "sensor",
            components: [Component(
                name: "sensor",
                attributes: { "reading": ["low", "high"] },
                modes: [
                    Mode(name: "ok", constraint: "sensor.reading = low"),
                    Mode(name: "broken", kind: Fault),
                ],
                initial: { "ok": 1.0 },
            )],
            observables: ["sensor.reading"],
        )"#,
    );
    let mut theory = sensor.theory().expect("theory");
    let high = Observation::new(&sensor, &[value(&sensor, "sensor.reading", "high")]).expect("obs");
    for (name, mut estimator) in estimators(10) {
        let update = estimator
            .initial(&sensor, &mut theory, 0.0, &high)
            .expect("initial");
        assert_eq!(
            update.events,
            vec![EstimationEvent::InconsistentObservation {
                fallback: Fallback::UnconstrainedFaults
            }],
            "{name}"
        );
        let estimate = update.belief.most_likely_plant_state();
        assert_eq!(mode_in(&sensor, &estimate, "sensor"), "broken", "{name}");
    }
}

/// The replay log drives both estimators: a driver commanded on whose valve
/// shows flow once opened.
#[test]
fn a_logged_run_replays_through_both_estimators() {
    let plant = model("driver_valve");
    let records = log(
        &plant,
        r#"# driver_valve: on, then open; the valve passes flow
{"time": 0.0, "observations": {"valve.flow_in": "nominal", "valve.flow_out": "zero"}, "commands": {"driver.dcmd_in": "on"}}
{"time": 1.0, "observations": {"valve.flow_in": "nominal", "valve.flow_out": "zero"}}
{"time": 2.0, "observations": {"valve.flow_in": "nominal", "valve.flow_out": "zero"}, "commands": {"driver.dcmd_in": "open"}}
{"time": 3.0, "observations": {"valve.flow_in": "nominal", "valve.flow_out": "nominal"}}
"#,
    );
    let mut theory = plant.theory().expect("theory");
    for (name, mut estimator) in estimators(10) {
        let updates =
            kairos::estimation::log::replay(&plant, &mut theory, estimator.as_mut(), &records)
                .expect("replay");
        let last = updates
            .last()
            .expect("updates")
            .belief
            .most_likely_plant_state();
        assert_eq!(mode_in(&plant, &last, "driver"), "on", "{name}");
        assert_eq!(mode_in(&plant, &last, "valve"), "open", "{name}");
        assert!(updates.iter().all(|u| u.events.is_empty()), "{name}");
    }
}
