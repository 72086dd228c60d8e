//! The SVG timeline of the Mars EDL (thesis §7.2.2, §7.2.5): the primary
//! pyro misfire scenario run through the scenario runner, drawn and read back — the 22 state
//! variables of Table 7.1 as lanes, the fault highlighted where it was estimated, a mark per
//! command and diagnosis, the 4.5-hour cruise compressed.

use std::path::Path;

use kairos::executive::EventKind;
use kairos::report::timeline::{TimelineInput, render};
use kairos::simulation::{self, RunOptions};
use roxmltree::Document;

/// §12, the timeline, on a headline run: one lane per state variable, fault modes
/// highlighted, a mark per command and diagnosis, the cruise compressed into a marked break.
#[test]
fn the_edl_run_draws_its_lanes_faults_and_the_compressed_cruise() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/mars_edl/lander_pyro_misfire.ron");
    let scenario = simulation::load(&path).expect("the scenario loads");
    let run = simulation::run(&scenario, RunOptions::default(), &mut |_| {}).expect("it runs");
    assert!(run.passed(), "the scenario's own expectations hold");
    let plant = &scenario.plant;
    let svg = render(&TimelineInput::of_run(&scenario, &run, &[]));
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

    // The misfire shows as a fault segment in the lander's lane, and only there.
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
    for other in names.iter().filter(|&&n| n != "lander") {
        assert!(faults(other).is_empty(), "{other}: {:?}", faults(other));
    }

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
    assert_eq!(marks("repair"), 1, "the backup pyro");
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
