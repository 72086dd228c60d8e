//! Large plants load and validate (a 10,000-component plant ran for minutes;
//! validation asked one SAT question per mode and guard, each assigning every variable). The
//! timings are in BENCHMARKS.md, "Loading large plants"; here, what the batched validation
//! decides must not change: modes that exclude each other across an interconnection are each
//! still possible (DESIGN.md §6.1: a mode that can never hold is an error, one that cannot hold
//! *together with another* is not).

#[path = "support/large_plant.rs"]
mod large_plant;

use kairos::diagnostic::Source;
use kairos::plant::Plant;

fn load(text: String) -> Plant {
    Plant::load(&Source::new("large.ron", text)).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_thousand_component_chain_loads() {
    let plant = load(large_plant::chain(1000));
    assert_eq!(plant.components().len(), 1000);
}

#[test]
fn a_component_with_a_thousand_modes_loads() {
    let plant = load(large_plant::many_modes(1000));
    assert_eq!(plant.components()[0].modes().len(), 1000);
}

/// `a = on` needs the link high and `b = on` needs it low: each can hold, not both. The batched
/// check asks them together first, meets the conflict, and must then ask each alone.
#[test]
fn modes_exclusive_across_a_connection_are_each_possible() {
    let text = r#"Plant(
    name: "exclusive",
    components: [
        Component(name: "a", attributes: { "x": ["low", "high"] },
            modes: [Mode(name: "on", constraint: "a.x = high"), Mode(name: "off", constraint: "true")],
            initial: { "off": 1.0 }, transitions: []),
        Component(name: "b", attributes: { "x": ["low", "high"] },
            modes: [Mode(name: "on", constraint: "b.x = low"), Mode(name: "off", constraint: "true")],
            initial: { "off": 1.0 }, transitions: []),
    ],
    connections: ["a.x = b.x"],
)"#;
    load(text.to_string());
    let broken = text.replace(r#""b.x = low""#, r#""b.x = low and a.x = high""#);
    let error = Plant::load(&Source::new("broken.ron", broken)).expect_err("b = on never holds");
    assert!(
        error.to_string().contains("mode `on` can never hold"),
        "{error}"
    );
}
