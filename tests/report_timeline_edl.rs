//! The SVG timeline of the Mars EDL (thesis §7.2.2; issue 7 item 4): the example's lander with
//! its three injected faults, drawn and read back — the 22 state variables of Table 7.1 as
//! lanes, the faults highlighted where they were estimated, the 4.5-hour cruise compressed.

#[path = "../examples/edl_timeline/lander.rs"]
mod lander;

use kairos::executive::EventKind;
use kairos::report::timeline::{TimelineInput, render};
use roxmltree::Document;

/// §12 and issue 7 item 4 on the headline run: one lane per state variable, fault modes
/// highlighted, a mark per command and diagnosis, the cruise compressed into a marked break.
#[test]
fn the_edl_run_draws_its_lanes_faults_and_the_compressed_cruise() {
    let run = lander::run_edl(lander::Faults::all());
    let plant = run.executive.plant();
    let svg = render(&TimelineInput {
        plant,
        program: Some(run.executive.program()),
        timelines: run.executive.timelines(),
        events: &run.events,
        start: 0.0,
        end: run.end,
        title: "Mars EDL",
    });
    let document = Document::parse(&svg).expect("the timeline is well-formed XML");
    let class_is = |node: &roxmltree::Node, class: &str| {
        node.attribute("class")
            .is_some_and(|c| c.split(' ').any(|word| word == class))
    };

    let lanes: Vec<_> = document
        .descendants()
        .filter(|n| n.has_tag_name("g") && class_is(n, "lane"))
        .collect();
    let names: Vec<&str> = plant.components().iter().map(|c| c.name()).collect();
    let drawn: Vec<&str> = lanes
        .iter()
        .filter_map(|g| g.attribute("data-component"))
        .collect();
    assert_eq!(names.len(), 22);
    assert_eq!(
        drawn, names,
        "one lane per state variable, in the model's order"
    );

    // The misfire and the PDE fault show as fault segments in their lanes.
    let faults = |component: &str| -> Vec<String> {
        lanes
            .iter()
            .filter(|g| g.attribute("data-component") == Some(component))
            .flat_map(|g| g.descendants())
            .filter(|n| n.has_tag_name("rect") && class_is(n, "fault"))
            .filter_map(|n| n.attribute("data-mode").map(str::to_string))
            .collect()
    };
    assert_eq!(faults("lander"), ["unsuccessful-attempt"]);
    assert_eq!(faults("PDE"), ["resettable"]);

    let marks = |class: &str| {
        document
            .descendants()
            .filter(|n| n.has_tag_name("g") && class_is(n, "event") && class_is(n, class))
            .count()
    };
    let count =
        |matches: fn(&EventKind) -> bool| run.events.iter().filter(|e| matches(&e.kind)).count();
    assert_eq!(
        marks("command"),
        count(|k| matches!(k, EventKind::CommandIssued { .. }))
    );
    assert_eq!(
        marks("diagnosis"),
        count(|k| matches!(k, EventKind::Diagnosis { .. }))
    );
    assert!(marks("repair") >= 2, "the backup pyro and the PDE reset");
    assert_eq!(marks("completed"), 1);

    // The cruise — 4 h 30 min with nothing happening — is one break, not 16,000 s of axis.
    let cruise = document
        .descendants()
        .filter(|n| n.has_tag_name("g") && class_is(n, "idle-break"))
        .find(|n| {
            n.descendants()
                .any(|t| t.text().map(str::trim) == Some("≈ 4 h 30 min idle"))
        });
    assert!(cruise.is_some(), "the cruise is compressed and marked");
}
