//! `kairos graph MODEL [--dot]`: the component automata of a plant model, as text or as a
//! Graphviz drawing (one cluster per component; fault modes highlighted, initial modes drawn
//! with a double border, failure transitions dashed, timed transitions labelled with their
//! distribution on the component clock).

use std::path::Path;

use kairos::dot::{Cluster, Edge, Graph, Node, Shape};
use kairos::logic::Formula;
use kairos::plant::{Component, ModeKind, Plant, Transition, TransitionSource};

use super::Failure;
use super::load_plant;
use super::output::emit;

/// Prints the automata of the model at `path`.
pub fn run(path: &Path, dot: bool) -> Result<(), Failure> {
    let plant = load_plant(path)?;
    let text = if dot {
        drawing(&plant).render()
    } else {
        listing(&plant)
    };
    emit(&text).map(|_| ())
}

/// `guard; law` on one line (the guard left out when it is `true`).
fn transition_label(plant: &Plant, transition: &Transition) -> String {
    match &transition.guard {
        Formula::True => transition.law.to_string(),
        guard => format!("{}\n{}", guard.display(plant.table()), transition.law),
    }
}

fn source_name(component: &Component, transition: &Transition) -> String {
    match transition.source {
        TransitionSource::Mode(m) => component.mode(m).name.clone(),
        TransitionSource::AnyNominal => "*".to_string(),
    }
}

fn node_id(component: &Component, mode: &str) -> String {
    format!("{}/{mode}", component.name())
}

/// The Graphviz drawing.
fn drawing(plant: &Plant) -> Graph {
    let mut graph = Graph::new(plant.name());
    for component in plant.components() {
        let mut cluster = Cluster {
            id: component.name().to_string(),
            label: component.name().to_string(),
            ..Cluster::default()
        };
        for (m, mode) in component.modes().iter().enumerate() {
            let mut label = mode.name.clone();
            if mode.constraint != Formula::True {
                label = format!("{label}\n{}", mode.constraint.display(plant.table()));
            }
            cluster.nodes.push(Node {
                highlight: mode.kind == ModeKind::Fault,
                peripheral: component.initial()[m] > 0.0,
                ..Node::new(node_id(component, &mode.name), label)
            });
        }
        if component
            .transitions()
            .iter()
            .any(|t| t.source == TransitionSource::AnyNominal)
        {
            cluster.nodes.push(Node {
                shape: Shape::Ellipse,
                ..Node::new(node_id(component, "*"), "* (any nominal mode)")
            });
        }
        for transition in component.transitions() {
            graph.edges.push(Edge {
                from: node_id(component, &source_name(component, transition)),
                to: node_id(component, &component.mode(transition.target).name),
                label: transition_label(plant, transition),
                dashed: component.mode(transition.target).kind == ModeKind::Fault,
            });
        }
        graph.clusters.push(cluster);
    }
    graph.nodes.push(Node::new("interface", interface(plant)));
    graph
}

/// Controls, observables and interconnections, one per line.
fn interface(plant: &Plant) -> String {
    let table = plant.table();
    let mut lines = Vec::new();
    for control in plant.controls() {
        let variable = table.variable(control.var);
        lines.push(format!(
            "control {} (idle {})",
            variable.name(),
            variable.value_name(control.idle)
        ));
    }
    for &var in plant.observables() {
        lines.push(format!("observable {}", table.variable(var).name()));
    }
    for connection in plant.connections() {
        lines.push(format!("connection {}", connection.display(table)));
    }
    lines.join("\n")
}

/// The plain-text listing.
fn listing(plant: &Plant) -> String {
    let mut out = format!("plant {}\n", plant.name());
    for component in plant.components() {
        out.push_str(&format!("\ncomponent {}\n", component.name()));
        for (m, mode) in component.modes().iter().enumerate() {
            let kind = match mode.kind {
                ModeKind::Nominal => "",
                ModeKind::Fault => " (fault)",
            };
            let initial = component.initial()[m];
            let initial = if initial > 0.0 {
                format!(", initially {initial}")
            } else {
                String::new()
            };
            out.push_str(&format!(
                "  mode {}{kind}: {} [reward {}{initial}]\n",
                mode.name,
                mode.constraint.display(plant.table()),
                mode.reward
            ));
        }
        for transition in component.transitions() {
            let target = &component.mode(transition.target).name;
            let label = transition_label(plant, transition).replace('\n', "; ");
            out.push_str(&format!(
                "  {} -> {target}: {label}\n",
                source_name(component, transition)
            ));
        }
    }
    out.push_str(&format!("\n{}\n", interface(plant)));
    out
}
