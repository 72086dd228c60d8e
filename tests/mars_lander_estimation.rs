//! Mode estimation on the Mars lander: TimedME at κ = 10 tracks the nominal EDL of
//! §7.2.2 through commanded and timed transitions, and diagnoses the faults of §7.2.5 and §1.1
//! from the observations a scripted plant (DESIGN.md §11) would give — every observable every
//! cycle, each observation reflecting the previous cycle's commands. The runs are written in the
//! replay-log format of `kairos estimate` and replayed through it too.

mod support;

use std::process::Command;

use kairos::estimation::log::replay;
use kairos::estimation::{TimedMe, TimedMeOptions, Update};
use kairos::plant::Plant;
use support::lander_edl::{CYCLE, Faults, Timeline, edl, ms, nominal_edl};
use support::plants::{log, marginal, mode_in, model};

impl Timeline {
    /// Replays the log (to `end`, grid `grid`) through TimedME at κ = 10.
    fn estimate(&self, end: f64, grid: f64) -> Run {
        let plant = model("mars_lander");
        let records = log(&plant, &self.text(end, grid));
        let mut theory = plant.theory().expect("theory");
        let mut estimator = TimedMe::new(TimedMeOptions::kappa(10));
        let updates = replay(&plant, &mut theory, &mut estimator, &records).expect("replay");
        for (record, update) in records.iter().zip(&updates) {
            assert!(
                update.events.is_empty(),
                "t = {}: {:?}",
                record.time,
                update.events
            );
        }
        let times = records.iter().map(|r| ms(r.time)).collect();
        Run {
            plant,
            updates,
            times,
        }
    }
}

/// A replayed run.
struct Run {
    plant: Plant,
    updates: Vec<Update>,
    times: Vec<u64>,
}

impl Run {
    fn update(&self, time: f64) -> &Update {
        let i = self
            .times
            .iter()
            .position(|&t| t == ms(time))
            .unwrap_or_else(|| panic!("no cycle at {time} s"));
        &self.updates[i]
    }

    /// ŝ(component) after the cycle at `time`.
    fn mode(&self, time: f64, component: &str) -> String {
        let estimate = self.update(time).belief.most_likely_plant_state();
        mode_in(&self.plant, &estimate, component).to_string()
    }

    /// The belief in `component = mode` after the cycle at `time`.
    fn belief(&self, time: f64, component: &str, mode: &str) -> f64 {
        marginal(&self.plant, &self.update(time).belief, component, mode)
    }

    /// ŝ(component) is `mode` after the cycle at `time`.
    fn expect(&self, time: f64, component: &str, mode: &str) {
        assert_eq!(self.mode(time, component), mode, "{component} at {time} s");
    }
}

#[test]
fn the_nominal_edl_is_tracked_goal_by_goal() {
    // §7.2.2's scenario; §7.2.1's nominal requirements 6 and 7 (tracking through commanded and
    // timed transitions): every goal of Appendix B's program is estimated achieved the cycle
    // its confirmation arrives, with no inconsistency on the way.
    use edl::*;
    let run = nominal_edl(Faults::default()).estimate(END, 600.0);
    let checks: &[(f64, &str, &str)] = &[
        (0.1, "PDE", "on"),
        (0.2, "engine", "heating"),
        (STANDBY - 0.1, "engine", "heating"),
        (STANDBY, "engine", "standby"),
        (STANDBY + 0.1, "PDE", "off"),
        (NAV, "nav", "earth-relative"),
        (NAV + 0.1, "nav", "inertial"),
        (SLEW + 0.1, "att", "slew-to-entry"),
        (ENTRY_ORIENT - 0.1, "att", "slew-to-entry"),
        (ENTRY_ORIENT, "att", "entry-orient"),
        (SEPARATE, "lander", "connected"),
        (SEPARATE + 0.1, "lander", "separated"),
        (ENTRY - 0.1, "entry", "not-initiated"),
        (ENTRY, "entry", "initiated"),
        (ENTRY + 0.2, "att", "slew-to-vel-vector"),
        (ENTRY + 15.0, "att", "vel-vector-orient"),
        (MACH, "Mach_trigger", "triggered"),
        (CHUTE + 0.1, "chute", "deployed"),
        (HEATSHIELD + 0.1, "heatshield", "jettison"),
        (LEGS + 0.1, "legs", "deployed"),
        (LEGS + 0.1, "touchdown_sensor", "not-triggered"),
        (RADAR + 0.1, "radar_altim", "on"),
        (ALT_VEL, "alt_vel_trigger", "triggered"),
        (BACKSHELL + 0.1, "backshield", "jettisoned"),
        (POWERED + 0.1, "PDE", "on"),
        (POWERED + 0.2, "valve1", "open"),
        (POWERED + 0.3, "valve2", "open"),
        (POWERED + 0.4, "engine", "firing"),
        (POWERED + 0.5, "PDE", "off"),
        (POWERED + 0.5, "engine", "firing"),
        (POWERED + 0.6, "att", "slew-to-landing"),
        (POWERED + 0.7, "prop", "gravity-turn"),
        (POWERED + 20.0, "att", "landing-orient"),
        (ALT_40M, "alt_40m_trigger", "triggered"),
        (ALT_40M + 0.2, "radar_altim", "off"),
        (ALT_12M, "alt_12m_trigger", "triggered"),
        (ALT_12M + 0.2, "prop", "const-vel-descent"),
        (TOUCHDOWN, "touchdown_sensor", "triggered"),
        (TOUCHDOWN + 0.3, "engine", "standby"),
        (TOUCHDOWN + 0.4, "engine", "off"),
        (TOUCHDOWN + 0.5, "landing", "success"),
    ];
    for &(time, component, mode) in checks {
        run.expect(time, component, mode);
    }
    // The estimate is confident throughout: the leading alternative before the engine fires is
    // a valve stuck closed since the start (a fault no observation shows while it is closed:
    // about 1e-7/s x 17,000 s). A trigger that fires after seconds without a report competes
    // with its sensor's failure over that stretch (the touchdown sensor, 5 s here).
    for &(time, component, mode) in checks {
        let p = run.belief(time, component, mode);
        assert!(p > 0.98, "{component} = {mode} at {time} s: {p}");
    }
    let valve = run.belief(POWERED, "valve1", "stuck-closed");
    assert!((1e-3..3e-3).contains(&valve), "{valve}");
    assert!(run.belief(POWERED + 0.3, "valve1", "stuck-closed") < 1e-9);
}

#[test]
fn the_switch_to_inertial_navigation_is_tracked_from_its_command() {
    // §7.2.1 nominal requirement 6, §3.3 ("a command that triggers the desired change in
    // navigation mode"): commanded, then confirmed by the estimator's reported mode.
    let mut t = Timeline::default();
    t.at(10.0, &[], &[("nav.cmd", "inertial")])
        .at(10.1, &[("nav.reported", "inertial")], &[]);
    let run = t.estimate(11.0, 1.0);
    run.expect(10.0, "nav", "earth-relative");
    run.expect(10.1, "nav", "inertial");
    assert!(run.belief(10.1, "nav", "inertial") > 0.999_999);
    // Unobserved, the command alone is believed (§3.2's 99.9%).
    let mut t = Timeline::default();
    t.at(10.0, &[], &[("nav.cmd", "inertial")]);
    let text = t
        .text(10.1, 1.0)
        .replace("\"nav.reported\": \"earth-relative\", ", "");
    let plant = model("mars_lander");
    let records = log(&plant, &text);
    let mut theory = plant.theory().expect("theory");
    let updates = replay(
        &plant,
        &mut theory,
        &mut TimedMe::new(TimedMeOptions::kappa(10)),
        &records,
    )
    .expect("replay");
    let last = updates.last().expect("updates");
    // (less the 1e-6 that nav became unknown unobserved over the 10 s before).
    let p = marginal(&plant, &last.belief, "nav", "inertial");
    assert!((p - 0.999).abs() < 1e-5, "{p}");
}

#[test]
fn heating_ends_when_the_temperature_is_nominal() {
    // §3.3 and §7.2.5: "receipt of a temp = nominal observation allows the executive to
    // conclude that the engine has taken the timed transition from heating to standby" — 43 s
    // into the 30-60 s window.
    let run = nominal_edl(Faults::default()).estimate(60.0, 1.0);
    for t in [0.2, 1.0, 29.0, 30.0, 31.0, 42.0, 43.0, 43.1] {
        run.expect(t, "engine", "heating");
    }
    run.expect(43.2, "engine", "standby");
    assert!(run.belief(43.2, "engine", "standby") > 0.9999);
}

#[test]
fn without_a_temperature_heating_is_believed_over_at_45_s() {
    // §7.1.2: with no temperature observation, the engine is believed to be heating before
    // 45 s and in standby from the first cycle at or after 45 s (the middle of the window).
    let mut t = Timeline::default();
    t.at(0.0, &[], &[("PDE.cmd", "on")])
        .at(
            0.1,
            &[("PDE.status", "nominal")],
            &[("PDE.cmd", "engine-standby")],
        )
        .at(0.2, &[("engine.power", "nominal")], &[]);
    let text = t.text(50.0, 0.1).replace("\"engine.temp\": \"low\", ", "");
    let plant = model("mars_lander");
    let records = log(&plant, &text);
    let mut theory = plant.theory().expect("theory");
    let updates = replay(
        &plant,
        &mut theory,
        &mut TimedMe::new(TimedMeOptions::kappa(10)),
        &records,
    )
    .expect("replay");
    for (record, update) in records.iter().zip(&updates).skip(2) {
        let engine =
            mode_in(&plant, &update.belief.most_likely_plant_state(), "engine").to_string();
        // Heating began at 0.2 s: the middle of its window is 45.2 s.
        let expected = if record.time < 45.2 - 1e-9 {
            "heating"
        } else {
            "standby"
        };
        assert_eq!(engine, expected, "at {} s", record.time);
    }
}

#[test]
fn a_primary_pyro_misfire_is_an_unsuccessful_attempt_and_the_backup_separates() {
    // §3.3, §7.2.5 (recovery by physical redundancy): the primary pyro fires but the lander
    // stays attached: unsuccessful-attempt, the cycle it shows; the backup pyro separates it.
    use edl::*;
    let run = nominal_edl(Faults {
        misfire: true,
        ..Faults::default()
    })
    .estimate(ENTRY + 1.0, 600.0);
    run.expect(SEPARATE, "lander", "connected");
    run.expect(SEPARATE + 0.1, "lander", "unsuccessful-attempt");
    assert!(run.belief(SEPARATE + 0.1, "lander", "unsuccessful-attempt") > 0.999);
    run.expect(SEPARATE + 0.2, "lander", "separated");
    run.expect(ENTRY, "entry", "initiated");
}

/// The engine commanded to standby at 0.1 s (heating from 0.2 s), with `sense` at `when`.
fn heating_with(when: f64, sense: &[(&'static str, &'static str)], end: f64) -> Run {
    let mut t = Timeline::default();
    t.at(0.0, &[], &[("PDE.cmd", "on")])
        .at(
            0.1,
            &[("PDE.status", "nominal")],
            &[("PDE.cmd", "engine-standby")],
        )
        .at(0.2, &[("engine.power", "nominal")], &[])
        .at(when, sense, &[]);
    t.estimate(end, CYCLE)
}

#[test]
fn an_engine_still_cold_after_60_s_of_heating_has_failed() {
    // §3.2 ("If the sensors indicate that the engine has not reached its nominal standby
    // temperature within the specified nominal time window, the executive should deduce that the
    // engine has somehow malfunctioned"), §7.2.5 (diagnosis through timed transitions). Heating
    // from 0.2 s: the window closes at 60.2 s.
    let run = heating_with(1.0, &[], 61.0);
    for t in [1.0, 30.0, 45.2, 59.0, 60.1] {
        run.expect(t, "engine", "heating");
    }
    run.expect(60.2, "engine", "failed");
    assert!(run.belief(60.2, "engine", "failed") > 0.999);
    run.expect(61.0, "engine", "failed");
    // Nothing else is blamed.
    run.expect(61.0, "PDE", "on");
}

#[test]
fn an_engine_that_loses_power_while_heating_is_in_its_unconstrained_mode() {
    // §7.2.5: "the management of completely unanticipated faults ... the case where the engine
    // component suddenly observes a loss of power while in its heating mode".
    let run = heating_with(20.0, &[("engine.power", "zero")], 21.0);
    run.expect(19.9, "engine", "heating");
    run.expect(20.0, "engine", "failed");
    let plant = &run.plant;
    let engine = plant.component(plant.component_named("engine").expect("engine"));
    let failed = engine.mode(engine.mode_named("failed").expect("failed"));
    assert!(failed.is_unconstrained_fault());
    assert!(run.belief(20.0, "engine", "failed") > 0.999);
}

#[test]
fn a_pde_fault_is_resettable_and_a_reset_repairs_it() {
    // §7.2.4 ("A resettable fault mode is specified, which can be repaired by issuing a reset
    // or off command to the PDE"), §7.2.5 (recovery by repair).
    // The PDE reports a fault as it is turned on; reset; then the engine is commanded.
    let mut t = Timeline::default();
    t.at(0.0, &[], &[("PDE.cmd", "on")])
        .at(0.1, &[("PDE.status", "fault")], &[("PDE.cmd", "reset")])
        .at(
            0.2,
            &[("PDE.status", "nominal")],
            &[("PDE.cmd", "engine-standby")],
        )
        .at(0.3, &[("engine.power", "nominal")], &[]);
    let run = t.estimate(1.0, 1.0);
    run.expect(0.1, "PDE", "resettable");
    assert!(run.belief(0.1, "PDE", "resettable") > 0.999);
    run.expect(0.2, "PDE", "on");
    run.expect(0.3, "engine", "heating");
    // The PDE swallows the engine command and reports a fault: the command is read as not
    // taken (the engine is not blamed), the PDE as resettable; reset, the command again.
    let mut t = Timeline::default();
    t.at(0.0, &[], &[("PDE.cmd", "on")])
        .at(
            0.1,
            &[("PDE.status", "nominal")],
            &[("PDE.cmd", "engine-standby")],
        )
        .at(0.2, &[("PDE.status", "fault")], &[("PDE.cmd", "reset")])
        .at(
            0.3,
            &[("PDE.status", "nominal")],
            &[("PDE.cmd", "engine-standby")],
        )
        .at(0.4, &[("engine.power", "nominal")], &[]);
    let run = t.estimate(1.0, 1.0);
    run.expect(0.2, "PDE", "resettable");
    run.expect(0.2, "engine", "off");
    assert!(run.belief(0.2, "engine", "failed") < 1e-3);
    run.expect(0.3, "PDE", "on");
    run.expect(0.4, "engine", "heating");
    // An off command repairs it too.
    let mut t = Timeline::default();
    t.at(0.0, &[], &[("PDE.cmd", "on")])
        .at(0.1, &[("PDE.status", "fault")], &[("PDE.cmd", "off")])
        .at(0.2, &[("PDE.status", "off")], &[]);
    let run = t.estimate(1.0, 1.0);
    run.expect(0.1, "PDE", "resettable");
    run.expect(0.2, "PDE", "off");
}

#[test]
fn a_touchdown_spike_at_leg_deployment_reads_triggered_before_the_12_m_trigger() {
    // The Mars Polar Lander case (§1.1; §7.2.3's fifth thread; DESIGN.md §11): the leg
    // deployment latches a spike on the touchdown sensor. The estimate says what the sensor
    // says — triggered — while the 12 m trigger has not fired, which is the state the program's
    // `whenever` answers with a reset; after the reset the sensor reads not-triggered until the
    // real touchdown, after the 12 m trigger.
    use edl::*;
    let run = nominal_edl(Faults {
        spike: true,
        ..Faults::default()
    })
    .estimate(END, 600.0);
    run.expect(LEGS, "touchdown_sensor", "not-triggered");
    for t in [LEGS + 0.1, RADAR, ALT_VEL, POWERED + 0.6] {
        run.expect(t, "touchdown_sensor", "triggered");
        run.expect(t, "alt_12m_trigger", "not-triggered");
        assert!(run.belief(t, "touchdown_sensor", "triggered") > 0.9);
    }
    run.expect(LEGS + 0.1, "legs", "deployed");
    run.expect(POWERED + 0.8, "touchdown_sensor", "not-triggered");
    run.expect(POWERED + 0.8, "engine", "firing");
    run.expect(ALT_12M, "touchdown_sensor", "not-triggered");
    run.expect(ALT_12M, "alt_12m_trigger", "triggered");
    run.expect(TOUCHDOWN, "touchdown_sensor", "triggered");
    run.expect(TOUCHDOWN + 0.5, "landing", "success");
}

#[test]
fn a_valve_that_does_not_open_for_powered_descent_is_stuck_closed() {
    // §6.3.3, §7.2.5 ("pressure = high measurements ... confirm ... a valve has successfully
    // opened"): after 4.7 hours closed, a valve that stays at low pressure when opened is
    // stuck closed — a fault no observation could show while it was closed — rather than its
    // tank empty (ten times rarer) or the command not taken (0.1%).
    use edl::*;
    let mut t = nominal_edl(Faults::default());
    // Valve 1 never opens: its outlet stays low.
    t.events.retain(|&time, _| time <= ms(POWERED + 0.1));
    let run = t.estimate(POWERED + 0.2, 600.0);
    run.expect(POWERED + 0.2, "valve1", "stuck-closed");
    run.expect(POWERED + 0.2, "tank1", "full");
    run.expect(POWERED + 0.2, "PDE", "on");
    let stuck = run.belief(POWERED + 0.2, "valve1", "stuck-closed");
    let empty = run.belief(POWERED + 0.2, "tank1", "empty");
    assert!(
        stuck > 0.5 && empty > 0.01 && stuck > 5.0 * empty,
        "{stuck} {empty}"
    );
}

#[test]
fn a_slew_that_has_not_ended_after_300_s_has_failed() {
    // §7.2.4's slew window, 0 to 300 s, diagnosed like the engine's heating (§7.2.5): the ACS
    // switches to the entry set-point but the attitude never gets there.
    let mut t = Timeline::default();
    t.at(10.0, &[], &[("att.cmd", "to-entry")]).at(
        10.1,
        &[("att.ACS", "entry"), ("att.att_obs", "off-set-point")],
        &[],
    );
    let run = t.estimate(312.0, 1.0);
    for time in [10.1, 160.0, 310.0] {
        run.expect(time, "att", "slew-to-entry");
    }
    run.expect(311.0, "att", "failed");
    assert!(run.belief(311.0, "att", "failed") > 0.999);
}

#[test]
fn an_entry_minutes_before_the_predicted_time_is_still_explained() {
    // The entry trigger's Gaussian is unbounded (§7.2.4, DESIGN.md §6.2): drag sensed 400 s
    // (13 standard deviations) early, even before separation, is an early entry — the case for
    // which DescentLandingSequence re-asserts `lander = separated` (§7.2.3) — not an
    // inconsistency.
    let mut t = Timeline::default();
    t.at(16400.0, &[("entry.drag", "sensed")], &[]);
    let run = t.estimate(16401.0, 600.0);
    run.expect(16399.9, "entry", "not-initiated");
    run.expect(16400.0, "entry", "initiated");
    run.expect(16400.0, "lander", "connected");
}

#[test]
fn a_pyro_that_does_not_fire_has_failed_the_cycle_it_shows() {
    // Every pyro subsystem (§7.2.2): a firing that leaves its switch where it was is a misfire.
    for (component, command) in [
        ("chute", "chute.cmd"),
        ("heatshield", "heatshield.cmd"),
        ("legs", "legs.cmd"),
        ("backshield", "backshield.cmd"),
    ] {
        let mut t = Timeline::default();
        t.at(5.0, &[], &[(command, "fire")]);
        let run = t.estimate(5.1, 1.0);
        run.expect(5.0, component, run.mode(0.0, component).as_str());
        run.expect(5.1, component, "failed");
    }
}

#[test]
fn a_command_that_keeps_going_unanswered_is_a_fault() {
    // §7.2.5 (diagnosis through commanded transitions), with §3.2's 99.9%: one unanswered
    // command is read as not yet taken — the planner re-issues it — and a few more as a fault
    // of the component.
    for (component, command, fault, within) in [
        ("nav", ("nav.cmd", "inertial"), "unknown", 3),
        ("prop", ("prop.cmd", "gravity-turn"), "unknown", 3),
        ("radar_altim", ("radar_altim.cmd", "on"), "failed", 3),
        ("att", ("att.cmd", "to-entry"), "failed", 6),
    ] {
        let mut t = Timeline::default();
        for k in 0..8 {
            t.at(5.0 + 0.1 * f64::from(k), &[], &[command]);
        }
        let run = t.estimate(5.8, 1.0);
        let initial = run.mode(0.0, component);
        run.expect(5.1, component, &initial);
        let diagnosed = (1..=8)
            .find(|&k| run.mode(5.0 + 0.1 * f64::from(k), component) == fault)
            .unwrap_or_else(|| panic!("{component} never diagnosed {fault}"));
        assert!(
            diagnosed <= within,
            "{component}: {fault} after {diagnosed} cycles"
        );
    }
}

#[test]
fn kairos_estimate_replays_the_first_minutes_of_the_edl() {
    // `kairos estimate` on the committed log: the engine to standby through the PDE, the PDE
    // off, the cruise, as the executive's first three minutes would run (§3.3, §7.2.2).
    let output = Command::new(env!("CARGO_BIN_EXE_kairos"))
        .args([
            "estimate",
            "--plant",
            "models/mars_lander.ron",
            "--log",
            "tests/logs/mars_lander_first_minutes.jsonl",
            "--top",
            "2",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the kairos binary runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(!stdout.contains(" ! "), "no estimation event: {stdout}");
    let last = stdout.rsplit("\nt = ").next().unwrap_or_default();
    assert!(last.contains("engine = standby, PDE = off"), "{last}");
    insta::assert_snapshot!(stdout);
}
