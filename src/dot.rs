//! A small Graphviz DOT writer: nested clusters, nodes with record-like labels, labelled edges.
//! `kairos compile --dot` (THCA: composites as clusters) and `kairos graph --dot` (one cluster per
//! component automaton) both draw through it, so quoting and layout conventions live in one place.
//! It knows nothing of kairos's models, so it sits below every layer that draws (the sequencer's
//! THCA drawing, the plant graph, the goal network).

use std::fmt::Write;

/// Node shapes used by kairos drawings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// A rounded box (locations, modes).
    Box,
    /// An ellipse.
    Ellipse,
    /// A point (start markers).
    Point,
}

/// A node: an id unique in the graph and a label (lines separated by `\n`).
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Identifier, unique in the whole graph.
    pub id: String,
    /// Text shown; each line left-aligned.
    pub label: String,
    /// Shape.
    pub shape: Shape,
    /// Highlight (fault modes, marked locations): drawn bold and red.
    pub highlight: bool,
    /// Drawn with a double border (start locations, initial modes).
    pub peripheral: bool,
}

impl Node {
    /// A plain rounded box.
    pub fn new(id: impl Into<String>, label: impl Into<String>) -> Self {
        Node {
            id: id.into(),
            label: label.into(),
            shape: Shape::Box,
            highlight: false,
            peripheral: false,
        }
    }
}

/// A cluster (a subgraph drawn as a box around its contents).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cluster {
    /// Identifier, unique in the graph.
    pub id: String,
    /// Title shown at the top of the box.
    pub label: String,
    /// Nodes directly inside.
    pub nodes: Vec<Node>,
    /// Nested clusters.
    pub clusters: Vec<Cluster>,
    /// Draw the box dashed (e.g. composites with a maintenance condition).
    pub dashed: bool,
}

/// A directed edge with an optional label.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// Source node id.
    pub from: String,
    /// Target node id.
    pub to: String,
    /// Text on the edge (a guard, a timing window).
    pub label: String,
    /// Draw dashed (timed or fault transitions).
    pub dashed: bool,
}

/// A whole drawing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Graph {
    /// Graph name.
    pub name: String,
    /// Top-level nodes.
    pub nodes: Vec<Node>,
    /// Top-level clusters.
    pub clusters: Vec<Cluster>,
    /// All edges.
    pub edges: Vec<Edge>,
    /// Lay out left to right (time flowing rightwards) instead of top to bottom.
    pub left_to_right: bool,
}

/// Quotes a string for DOT, escaping quotes and backslashes and turning line breaks into
/// left-aligned breaks.
pub fn quote(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\l"),
            c => out.push(c),
        }
    }
    if text.contains('\n') {
        out.push_str("\\l");
    }
    out.push('"');
    out
}

impl Graph {
    /// An empty graph with a name.
    pub fn new(name: impl Into<String>) -> Self {
        Graph {
            name: name.into(),
            ..Graph::default()
        }
    }

    /// The DOT text.
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "digraph {} {{", quote(&self.name));
        let direction = if self.left_to_right { "LR" } else { "TB" };
        let _ = writeln!(out, "  compound=true;\n  rankdir={direction};");
        out.push_str("  node [fontname=\"Helvetica\", fontsize=11];\n  edge [fontname=\"Helvetica\", fontsize=10];\n");
        for node in &self.nodes {
            write_node(&mut out, node, 1);
        }
        for cluster in &self.clusters {
            write_cluster(&mut out, cluster, 1);
        }
        for edge in &self.edges {
            let style = if edge.dashed { ", style=dashed" } else { "" };
            let _ = writeln!(
                out,
                "  {} -> {} [label={}{style}];",
                quote(&edge.from),
                quote(&edge.to),
                quote(&edge.label)
            );
        }
        out.push_str("}\n");
        out
    }
}

fn write_node(out: &mut String, node: &Node, depth: usize) {
    let indent = "  ".repeat(depth);
    let shape = match node.shape {
        Shape::Box => "box, style=rounded",
        Shape::Ellipse => "ellipse",
        Shape::Point => "point",
    };
    let highlight = if node.highlight {
        ", color=red, fontcolor=red, penwidth=2"
    } else {
        ""
    };
    let peripheral = if node.peripheral {
        ", peripheries=2"
    } else {
        ""
    };
    let _ = writeln!(
        out,
        "{indent}{} [label={}, shape={shape}{highlight}{peripheral}];",
        quote(&node.id),
        quote(&node.label)
    );
}

fn write_cluster(out: &mut String, cluster: &Cluster, depth: usize) {
    let indent = "  ".repeat(depth);
    let _ = writeln!(
        out,
        "{indent}subgraph {} {{",
        quote(&format!("cluster_{}", cluster.id))
    );
    let _ = writeln!(out, "{indent}  label={};", quote(&cluster.label));
    if cluster.dashed {
        let _ = writeln!(out, "{indent}  style=dashed;");
    }
    for node in &cluster.nodes {
        write_node(out, node, depth + 1);
    }
    for inner in &cluster.clusters {
        write_cluster(out, inner, depth + 1);
    }
    let _ = writeln!(out, "{indent}}}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clusters_nest_and_labels_are_quoted() {
        let mut graph = Graph::new("g");
        let mut inner = Cluster {
            id: "inner".into(),
            label: "do … watching \"x\"".into(),
            ..Cluster::default()
        };
        inner
            .nodes
            .push(Node::new("a", "goal: x = on\nmaintain: y"));
        graph.clusters.push(Cluster {
            id: "outer".into(),
            clusters: vec![inner],
            ..Cluster::default()
        });
        graph.edges.push(Edge {
            from: "a".into(),
            to: "a".into(),
            label: "t >= 3 s".into(),
            dashed: true,
        });
        let text = graph.render();
        assert!(
            text.contains(
                "subgraph \"cluster_outer\" {\n    label=\"\";\n    subgraph \"cluster_inner\""
            ),
            "{text}"
        );
        assert!(text.contains("label=\"do … watching \\\"x\\\"\""), "{text}");
        assert!(text.contains("\"goal: x = on\\lmaintain: y\\l\""), "{text}");
        assert!(
            text.contains("\"a\" -> \"a\" [label=\"t >= 3 s\", style=dashed];"),
            "{text}"
        );
    }
}
