//! The shipped programs ("the three programs parse, link and compile"), their
//! THCA drawings, and end-to-end runs against an ideal plant that show the seed's intent: the EDL
//! lands (Appendix B), the Mars Polar Lander's touchdown-sensor spike is ignored (§1.1, DESIGN.md
//! §11), and the deployment sequence of Figure 5-1 reaches success either way round (§5.1.2).

#[path = "support/rmpl.rs"]
mod rmpl_support;

use kairos::sequencer::{Construct, dot};
use rmpl_support::{
    IdealPlant, MARS_LANDER_INITIAL, SPACECRAFT_INITIAL, load_program, mars_lander_plant,
    spacecraft_plant,
};

const PROGRAMS: [(&str, &str, usize); 3] = [
    ("programs/mars_entry.rmpl", "EntrySequence", 12),
    ("programs/mars_edl.rmpl", "MarsEDL", 52),
    (
        "programs/spacecraft_deployment.rmpl",
        "SpacecraftDeployment",
        65,
    ),
];

#[test]
fn the_three_programs_parse_link_and_compile() {
    for (path, entry, locations) in PROGRAMS {
        // Linked against the names they use (no plant)...
        let thca = load_program(path, None);
        assert_eq!(thca.name(), entry, "{path}");
        assert_eq!(thca.locations().len(), locations, "{path}");
        assert_eq!(
            thca.starts().len(),
            1,
            "{path}: the program is one composite"
        );
    }
    // ...and the Mars programs against the lander's variables.
    for path in ["programs/mars_entry.rmpl", "programs/mars_edl.rmpl"] {
        let thca = load_program(path, Some(&mars_lander_plant()));
        assert_eq!(thca.table().len(), mars_lander_plant().len(), "{path}");
    }
}

#[test]
fn inlined_locations_remember_their_invocation() {
    // Invocations are inlined (DESIGN.md §5.1); each location still maps back to its source:
    // its own text in the invoked program and the invocation it came through.
    let thca = load_program("programs/spacecraft_deployment.rmpl", None);
    let source = thca.source();
    let lga_goals: Vec<_> = thca
        .locations()
        .iter()
        .filter(|l| &source.text[l.origin.span.clone()] == "LGA = deployed")
        .collect();
    assert_eq!(lga_goals.len(), 1);
    let call = &lga_goals[0].origin.call_stack;
    assert_eq!(call.len(), 1);
    assert_eq!(&source.text[call[0].clone()], "DeployLGA()");
    // DeploySolarArrays is invoked twice (lines 12 and 14 of Figure 5-1): two copies.
    let copies = thca
        .locations()
        .iter()
        .filter(|l| &source.text[l.origin.span.clone()] == "downlink = nominal")
        .count();
    assert_eq!(copies, 2);
    // The `;` after the parallel warm-up (lines 4-8) needs a composite to know both are done.
    assert!(
        thca.locations()
            .iter()
            .any(|l| l.origin.construct == Construct::Group)
    );
}

#[test]
fn mars_entry_listing_and_drawing() {
    // Figure 3-4 as text and as Graphviz (composites as clusters, guards on edges).
    let thca = load_program("programs/mars_entry.rmpl", None);
    insta::assert_snapshot!("mars_entry_listing", thca.to_string());
    insta::assert_snapshot!("mars_entry_dot", dot::graph(&thca, &[]).render());
}

/// Scripted EDL happenings (DESIGN.md §6.3's triggers), one cycle per second.
const EDL_SCRIPT: &[(f64, &[(&str, &str)])] = &[
    (17000.0, &[("entry", "initiated")]),
    (17100.0, &[("Mach_trigger", "triggered")]),
    (17200.0, &[("alt_vel_trigger", "triggered")]),
    (17240.0, &[("alt_40m_trigger", "triggered")]),
    (17260.0, &[("alt_12m_trigger", "triggered")]),
    (17270.0, &[("touchdown_sensor", "triggered")]),
];

#[test]
fn mars_edl_lands_against_an_ideal_plant() {
    let thca = load_program("programs/mars_edl.rmpl", Some(&mars_lander_plant()));
    let mut run = IdealPlant::new(thca, MARS_LANDER_INITIAL, 1.0);
    run.run_until(20000.0, EDL_SCRIPT);
    run.assert_in_order(&[
        "t=0.0 goal engine = standby",
        "clock t1 started at 1",
        "goal nav = inertial",
        "clock t2 started",
        "goal att = entry-orient",
        "goal att = entry-orient and lander = separated",
        "t=17001.0 location 9 preempted",
        "goal chute = deployed",
        "goal heatshield = jettison",
        "legs = deployed",
        "radar_altim = on",
        "goal backshield = jettisoned",
        "goal engine = firing",
        "goal att = landing-orient and prop = gravity-turn",
        "radar_altim = off",
        "prop = const-vel-descent",
        "location 41 preempted",
        "engine = off",
        "landing = success",
        "location 2 preempted",
        "completed",
    ]);
    assert!(run.sequencer.is_complete());
}

#[test]
fn a_touchdown_spike_before_12_m_does_not_stop_the_engine() {
    // The Mars Polar Lander case (§1.1; DESIGN.md §11): the touchdown sensor reads "triggered"
    // when the legs deploy. `whenever (alt_12m_trigger = not-triggered ∧ touchdown_sensor =
    // triggered) donext touchdown_sensor = not-triggered` resets it; the engine is shut down only
    // after the 12 m trigger.
    let thca = load_program("programs/mars_edl.rmpl", Some(&mars_lander_plant()));
    let mut run = IdealPlant::new(thca, MARS_LANDER_INITIAL, 1.0);
    let mut script = EDL_SCRIPT.to_vec();
    script.insert(4, (17245.0, &[("touchdown_sensor", "triggered")]));
    run.run_until(20000.0, &script);
    let engine_off = run
        .log
        .iter()
        .position(|l| l.contains("engine = off"))
        .unwrap_or_else(|| panic!("the engine is shut down in the end: {:#?}", run.log));
    let reset = run
        .log
        .iter()
        .position(|l| l.contains("touchdown_sensor = not-triggered"))
        .expect("the spike is reset");
    assert!(reset < engine_off, "{:#?}", run.log);
    assert!(
        run.log[engine_off].starts_with("t=1727"),
        "{}",
        run.log[engine_off]
    );
}

#[test]
fn spacecraft_deployment_reaches_success_lga_first() {
    // §5.1.2, nominal: shuttle separation, warm-up, LGA flag first (DeployLGA), then the SA flag
    // (DeploySolarArrays); success preempts the whole sequence (line 17).
    let plant = spacecraft_plant();
    let thca = load_program("programs/spacecraft_deployment.rmpl", Some(&plant));
    let mut run = IdealPlant::new(thca, SPACECRAFT_INITIAL, 1.0);
    run.run_until(
        3000.0,
        &[
            (5.0, &[("shuttle", "separated")]),
            (20.0, &[("LGA_deploy_flag", "set")]),
            (60.0, &[("SA_deploy_flag", "set")]),
            (1500.0, &[("IUS", "separated")]),
        ],
    );
    run.assert_in_order(&[
        "goal IMU_1 = warmed and IMU_2 = warmed and RCS = warmed",
        "goal SSR_A = on and SSR_B = on",
        "goal downlink = beacon",
        "goal IMU_1 = on",
        "goal LGA = deployed",
        "clock t1 started",
        "goal downlink = nominal",
        "goal SA_1 = deployed and SA_2 = deployed",
        "goal ACS = active",
        "goal power_switch = engage-onboard-batts",
        "goal spacecraft_deployment = success",
        "location 2 preempted",
        "completed",
    ]);
    // Line 51: the ACS waits for 19 minutes after the SA flag.
    let acs = run
        .log
        .iter()
        .find(|l| l.contains("goal ACS = active"))
        .unwrap();
    assert!(
        acs.starts_with("t=1202.0") || acs.starts_with("t=1201.0"),
        "{acs}"
    );
}

#[test]
fn an_imu_failure_still_deploys_the_lga() {
    // DESIGN.md §5.2: `if (IMU_1 = failed) thennext (IMU_2 = on); LGA = deployed` deploys the LGA
    // either way; `do (IMU_1 = on) watching (IMU_1 = failed)` is preempted by the failure.
    let plant = spacecraft_plant();
    let thca = load_program("programs/spacecraft_deployment.rmpl", Some(&plant));
    let mut run = IdealPlant::new(thca, SPACECRAFT_INITIAL, 1.0);
    let flags: &[(f64, &[(&str, &str)])] = &[
        (5.0, &[("shuttle", "separated")]),
        (20.0, &[("LGA_deploy_flag", "set")]),
    ];
    run.run_until(23.0, flags);
    // IMU_1 fails while being turned on (line 26 asserts `IMU_1 = on` at 23 s).
    run.break_variable("IMU_1");
    run.run_until(200.0, &[(23.0, &[("IMU_1", "failed")])]);
    run.assert_in_order(&[
        "goal IMU_1 = on",
        "preempted (`do (IMU_1 = on) watching (IMU_1 = failed)`)",
        "goal IMU_2 = on",
        "goal LGA = deployed",
    ]);
}
