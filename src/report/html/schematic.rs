//! The plant schematic of the run report (thesis §8.1, Helios's live picture of the plant): a
//! box per component, in the plant's order on a grid, and a line between two components that
//! one of the plant's connections relates. The page colours each box by its estimated mode.

use std::collections::BTreeSet;

use serde_json::{Value, json};
use svg::Document;
use svg::node::element::{Group, Line, Rectangle, Text};

use crate::plant::{ModeKind, Plant};

use super::super::timeline::mode_colours;

/// Box size and spacing, in pixels.
const WIDTH: f64 = 150.0;
const HEIGHT: f64 = 38.0;
const GAP_X: f64 = 22.0;
const GAP_Y: f64 = 18.0;

/// Each component's name and modes (name, fill colour, fault or not), for the page's script.
pub(super) fn components(plant: &Plant) -> Vec<Value> {
    plant
        .components()
        .iter()
        .map(|component| {
            let colours = mode_colours(component);
            let modes: Vec<Value> = component
                .modes()
                .iter()
                .zip(colours)
                .map(|(mode, colour)| {
                    json!({
                        "name": mode.name,
                        "colour": colour,
                        "fault": mode.kind == ModeKind::Fault,
                    })
                })
                .collect();
            json!({ "name": component.name(), "modes": modes })
        })
        .collect()
}

/// The pairs of components some connection relates, each once, by index.
pub(super) fn links(plant: &Plant) -> BTreeSet<(usize, usize)> {
    let mut links = BTreeSet::new();
    for connection in plant.connections() {
        let mut ends: Vec<usize> = connection
            .variables()
            .into_iter()
            .filter_map(|var| plant.component_of(var))
            .map(|c| c.index())
            .collect();
        ends.sort_unstable();
        ends.dedup();
        for (k, &a) in ends.iter().enumerate() {
            for &b in &ends[k + 1..] {
                links.insert((a, b));
            }
        }
    }
    links
}

/// The schematic as inline SVG: boxes `g.node#schematic-node-K` holding `text.s-mode#schematic-mode-K`, which the
/// script fills in.
pub(super) fn svg(plant: &Plant) -> String {
    let n = plant.components().len();
    let columns = (n as f64).sqrt().ceil().max(1.0) as usize;
    let rows = n.div_ceil(columns).max(1);
    let centre = |k: usize| {
        let (row, column) = (k / columns, k % columns);
        (
            GAP_X + column as f64 * (WIDTH + GAP_X) + WIDTH / 2.0,
            GAP_Y + row as f64 * (HEIGHT + GAP_Y) + HEIGHT / 2.0,
        )
    };
    let width = GAP_X + columns as f64 * (WIDTH + GAP_X);
    let height = GAP_Y + rows as f64 * (HEIGHT + GAP_Y);
    let mut wires = Group::new().set("class", "wires");
    for (a, b) in links(plant) {
        let ((x1, y1), (x2, y2)) = (centre(a), centre(b));
        wires = wires.add(
            Line::new()
                .set("x1", x1)
                .set("y1", y1)
                .set("x2", x2)
                .set("y2", y2)
                .set("data-ends", format!("{a} {b}")),
        );
    }
    let mut nodes = Group::new().set("class", "nodes");
    for (k, component) in plant.components().iter().enumerate() {
        let (x, y) = centre(k);
        nodes = nodes.add(
            Group::new()
                .set("class", "node")
                .set("id", format!("schematic-node-{k}"))
                .set("data-node", component.name())
                .add(
                    Rectangle::new()
                        .set("x", x - WIDTH / 2.0)
                        .set("y", y - HEIGHT / 2.0)
                        .set("width", WIDTH)
                        .set("height", HEIGHT)
                        .set("rx", 5),
                )
                .add(
                    Text::new(component.name())
                        .set("class", "s-name")
                        .set("x", x)
                        .set("y", y - 4.0),
                )
                .add(
                    Text::new("")
                        .set("class", "s-mode")
                        .set("id", format!("schematic-mode-{k}"))
                        .set("x", x)
                        .set("y", y + 11.0),
                ),
        );
    }
    Document::new()
        .set("viewBox", (0, 0, width, height))
        .set("width", width)
        .set("height", height)
        .add(wires)
        .add(nodes)
        .to_string()
}
