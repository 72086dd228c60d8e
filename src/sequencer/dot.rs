//! Drawing a THCA with Graphviz, in the manner of the thesis's Figures 3-4 and 5-4..5-12:
//! composites are clusters (dashed when they carry a maintenance constraint), primitive locations
//! are boxes listing their goal, clock initialisations and maintenance, transitions are edges
//! labelled with their guards (`⊨ c` entailed, `⊭ c` not entailed; no label is **True**).
//!
//! Graphviz edges join nodes, not clusters, so each composite holds a small point node standing
//! for the composite itself: transitions into or out of the composite start or end there, and
//! dashed `start` edges lead from it to the composite's start locations.

use super::thca::{Location, LocationId, LocationKind, Thca};
use crate::dot::{Cluster, Edge, Graph, Node, Shape};

/// The drawing of `thca`, with the locations in `marked` highlighted (a marking from a trace).
pub fn graph(thca: &Thca, marked: &[LocationId]) -> Graph {
    let mut graph = Graph::new(thca.name());
    graph.nodes.push(Node {
        shape: Shape::Point,
        ..Node::new("start", "")
    });
    for &start in thca.starts() {
        graph.edges.push(start_edge("start", start));
    }
    let drawing = Drawing { thca, marked };
    for location in thca.locations().iter().filter(|l| l.parent.is_none()) {
        drawing.place(location, &mut graph.nodes, &mut graph.clusters);
    }
    for location in thca.locations() {
        drawing.edges_of(location, &mut graph.edges);
    }
    graph
}

fn node_id(location: LocationId) -> String {
    format!("L{location}")
}

fn start_edge(from: &str, to: LocationId) -> Edge {
    Edge {
        from: from.to_string(),
        to: node_id(to),
        label: "start".to_string(),
        dashed: true,
    }
}

struct Drawing<'a> {
    thca: &'a Thca,
    marked: &'a [LocationId],
}

impl Drawing<'_> {
    /// Adds a primitive location as a node, or a composite as a cluster holding its contents.
    fn place(&self, location: &Location, nodes: &mut Vec<Node>, clusters: &mut Vec<Cluster>) {
        let title = self.title(location);
        let highlight = self.marked.contains(&location.id);
        let LocationKind::Composite { children, .. } = &location.kind else {
            let mut lines = vec![title];
            lines.extend(self.thca.labels(location));
            nodes.push(Node {
                highlight,
                peripheral: self.is_start(location.id),
                ..Node::new(node_id(location.id), lines.join("\n"))
            });
            return;
        };
        let mut label = vec![title];
        label.extend(self.thca.labels(location));
        let mut cluster = Cluster {
            id: node_id(location.id),
            label: label.join("\n"),
            dashed: location.maintenance.is_some(),
            ..Cluster::default()
        };
        cluster.nodes.push(Node {
            shape: Shape::Point,
            highlight,
            ..Node::new(node_id(location.id), "")
        });
        for &child in children {
            self.place(
                self.thca.location(child),
                &mut cluster.nodes,
                &mut cluster.clusters,
            );
        }
        clusters.push(cluster);
    }

    fn title(&self, location: &Location) -> String {
        let (line, _) = self.thca.position(location.id);
        format!(
            "{}: {} (line {line})",
            location.id, location.origin.construct
        )
    }

    fn is_start(&self, id: LocationId) -> bool {
        self.thca.starts().contains(&id)
            || self
                .thca
                .location(id)
                .parent
                .is_some_and(|p| self.thca.location(p).starts().contains(&id))
    }

    fn edges_of(&self, location: &Location, edges: &mut Vec<Edge>) {
        let from = node_id(location.id);
        for &start in location.starts() {
            edges.push(start_edge(&from, start));
        }
        for transition in &location.transitions {
            let label = transition
                .guard
                .as_ref()
                .map_or(String::new(), |g| self.thca.condition_text(g));
            for &target in &transition.targets {
                edges.push(Edge {
                    from: from.clone(),
                    to: node_id(target),
                    label: label.clone(),
                    dashed: false,
                });
            }
        }
    }
}
