//! Command acknowledgements as evidence (`src/plant/acknowledgement.rs`; DESIGN.md §8, §9):
//! a switch that does not answer `on` is either stuck or did not take the command; the
//! acknowledgement settles which, in TimedME and in the exact belief update alike, and the
//! loader refuses acknowledgements that are not answers.

use kairos::diagnostic::Source;
use kairos::estimation::{BeliefUpdate, ModeEstimator, TimedMe, TimedMeOptions};
use kairos::logic::ValueId;
use kairos::plant::{Commands, Observation, Plant};

/// A switch: `on` by command with probability 0.999 a cycle, stuck off at 5e-4/s; its output
/// shows whether it is on; `switch.ack` answers for its command.
const SWITCH: &str = r#"Plant(
    name: "acknowledged_switch",
    components: [
        Component(
            name: "switch",
            attributes: {
                "cmd": ["none", "on"],
                "out": ["off", "on"],
                "ack": ["none", "accepted", "rejected", "completed", "failed"],
            },
            modes: [
                Mode(name: "off", constraint: "switch.out = off"),
                Mode(name: "on", constraint: "switch.out = on"),
                Mode(name: "stuck-off", kind: Fault, constraint: "switch.out = off", reward: -10),
            ],
            initial: { "off": 1.0 },
            transitions: [
                (from: "off", to: "on", guard: "switch.cmd = on", probability: 0.999),
                (from: "*", to: "stuck-off", rate: 0.0005),
            ],
        ),
    ],
    controls: { "switch.cmd": "none" },
    observables: ["switch.out"],
    acknowledgements: { "switch.cmd": "switch.ack" },
)"#;

fn plant() -> Plant {
    Plant::load(&Source::new("switch.ron", SWITCH)).expect("the switch loads")
}

fn assignment(plant: &Plant, name: &str, value: &str) -> (kairos::logic::VarId, ValueId) {
    let var = plant.table().variable_id(name).expect("variable");
    let value = plant.table().variable(var).value(value).expect("value");
    (var, value)
}

/// P(switch = stuck-off) after `on` is commanded, the output stays off and the switch
/// acknowledges with `answer` (none: no acknowledgement reported), by `estimator`.
fn stuck_after(estimator: &mut dyn ModeEstimator, answer: Option<&str>) -> f64 {
    let plant = plant();
    let mut theory = plant.theory().expect("theory");
    let off = assignment(&plant, "switch.out", "off");
    let first = Observation::new(&plant, &[off]).expect("observation");
    let initial = estimator
        .initial(&plant, &mut theory, 0.0, &first)
        .expect("initial");
    let on = assignment(&plant, "switch.cmd", "on");
    let commands = Commands::new(&plant, &[on]).expect("command");
    let mut observed = vec![off];
    observed.extend(answer.map(|a| assignment(&plant, "switch.ack", a)));
    let observation = Observation::new(&plant, &observed).expect("observation");
    let update = estimator
        .update(
            &plant,
            &mut theory,
            &initial.belief,
            &commands,
            &observation,
            1.0,
        )
        .expect("update");
    let stuck = plant
        .component(kairos::plant::ComponentId(0))
        .mode_named("stuck-off");
    update
        .belief
        .component_marginal(0, stuck.expect("mode"))
        .unwrap_or(0.0)
}

fn both(answer: Option<&str>) -> [f64; 2] {
    let mut timed = TimedMe::new(TimedMeOptions::kappa(10));
    let mut exact = BeliefUpdate::new();
    [
        stuck_after(&mut timed, answer),
        stuck_after(&mut exact, answer),
    ]
}

#[test]
fn without_an_acknowledgement_stuck_and_not_taken_stay_ambiguous() {
    // Prior odds: stuck 1 − e^(−0.0005) ≈ 5.0e-4 against not taken 0.001 · e^(−0.0005).
    let expected = 0.000_499_875 / (0.000_499_875 + 0.001 * (-0.0005f64).exp());
    for p in both(None).into_iter().chain(both(Some("none"))) {
        assert!((p - expected).abs() < 1e-6, "{p} against {expected}");
    }
}

#[test]
fn a_rejected_or_failed_command_did_not_happen() {
    for answer in ["rejected", "failed"] {
        for p in both(Some(answer)) {
            // Only the hazard of the one second is left: stuck 5.0e-4, off the rest.
            assert!((p - 0.000_499_875).abs() < 1e-6, "{answer}: {p}");
        }
    }
}

#[test]
fn an_accepted_or_completed_command_that_shows_no_effect_is_a_fault_for_certain() {
    for answer in ["accepted", "completed"] {
        for p in both(Some(answer)) {
            assert!((p - 1.0).abs() < 1e-12, "{answer}: {p}");
        }
    }
}

#[test]
fn an_acknowledgement_of_a_control_not_commanded_says_nothing() {
    let plant = plant();
    let ack = assignment(&plant, "switch.ack", "rejected");
    let observation = Observation::new(&plant, &[ack]).expect("observation");
    let idle = Commands::idle(&plant);
    let acknowledged = idle.acknowledged(&plant, &observation);
    assert_eq!(*acknowledged, idle);
    // Held answers are reported every cycle: one that says nothing costs no copy.
    assert!(matches!(acknowledged, std::borrow::Cow::Borrowed(_)));
    assert!(
        observation.values().is_empty(),
        "kept out of the observed values"
    );
}

fn load_error(text: &str) -> String {
    match Plant::load(&Source::new("bad.ron", text)) {
        Ok(_) => panic!("loaded"),
        Err(errors) => errors.to_string(),
    }
}

#[test]
fn the_loader_refuses_acknowledgements_that_are_not_answers() {
    let foreign = SWITCH.replace(r#""completed", "failed"]"#, r#""maybe"]"#);
    let error = load_error(&foreign);
    assert!(
        error.contains("`switch.ack` has values that are not answers: maybe"),
        "{error}"
    );
    let missing = SWITCH.replace(r#""rejected", "#, "");
    assert!(load_error(&missing).contains("`switch.ack` lacks the answers rejected"));
    let observed = SWITCH.replace(r#"["switch.out"]"#, r#"["switch.out", "switch.ack"]"#);
    assert!(load_error(&observed).contains("cannot also be a control or an observable"));
    let constrained = SWITCH.replace(
        r#"constraint: "switch.out = on""#,
        r#"constraint: "switch.out = on and switch.ack != rejected""#,
    );
    assert!(load_error(&constrained).contains("a constraint mentions it"));
    let not_control = SWITCH.replace(
        r#"{ "switch.cmd": "switch.ack" }"#,
        r#"{ "switch.out": "switch.ack" }"#,
    );
    assert!(load_error(&not_control).contains("is acknowledged but not a control"));
}
