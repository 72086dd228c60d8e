//! The causal graph of components (§6.3.2; Williams & Nayak, "A reactive planner for a
//! model-based executive", IJCAI-97): an edge `u → c` when the mode of `u` helps determine
//! whether a guard of one of `c`'s transitions holds. Strongly connected components are
//! collapsed into *causal units*; the units form a DAG, which orders the reactive planner's
//! work (downstream goals first, upstream helpers last).
//!
//! Influence is computed structurally from the model, once. Every constraint is cut into
//! *pieces*: each top-level conjunct of a mode constraint `u = M => a ∧ b ∧ …` is a piece over
//! `{u} ∪ vars(a)`, `{u} ∪ vars(b)`, …, and each top-level conjunct of an interconnection is a
//! piece over its variables. Starting from a guard's variables, the search walks from an
//! attribute to every variable that shares a piece with it, and stops at
//! - a **mode variable** of another component: that component is upstream (the walk does not
//!   pass *through* a component, whose own inputs are its own upstream's business);
//! - a **control**: a command the planner can issue.
//!
//! For the propulsion model, `engine.cmd` reaches `PDE.engine_cmd` through the interconnection
//! and then `PDE` and `PDE.cmd` through the pieces of the PDE's `on` constraint; `engine.fuel`
//! reaches `valve1` and, through `valve1.inlet`, `tank1`.

use petgraph::algo::tarjan_scc;
use petgraph::graph::{DiGraph, NodeIndex};

use crate::logic::{Formula, VarId};
use crate::plant::{ComponentId, Plant};

/// The top-level conjuncts of a formula (`a ∧ (b ∧ c)` gives `a, b, c`).
pub(crate) fn conjuncts(formula: &Formula) -> Vec<&Formula> {
    match formula {
        Formula::And(parts) => parts.iter().flat_map(conjuncts).collect(),
        Formula::True => Vec::new(),
        other => vec![other],
    }
}

/// What a set of variables depends on: upstream components' modes and controls.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Dependencies {
    /// Components whose mode the variables depend on (sorted, without repeats).
    pub modes: Vec<ComponentId>,
    /// Controls the variables depend on (sorted, without repeats).
    pub controls: Vec<VarId>,
}

impl Dependencies {
    /// True when the two share an upstream component or a control.
    pub fn overlaps(&self, other: &Dependencies) -> bool {
        self.modes.iter().any(|m| other.modes.contains(m))
            || self.controls.iter().any(|k| other.controls.contains(k))
    }

    /// Adds another's dependencies.
    pub fn merge(&mut self, other: &Dependencies) {
        self.modes.extend(&other.modes);
        self.controls.extend(&other.controls);
        self.normalize();
    }

    fn normalize(&mut self) {
        self.modes.sort_unstable();
        self.modes.dedup();
        self.controls.sort_unstable();
        self.controls.dedup();
    }
}

/// The variable-level structure the causal graph is derived from (see the module doc).
#[derive(Debug, Clone)]
pub(crate) struct Influence {
    /// Each piece's variables.
    pieces: Vec<Vec<VarId>>,
    /// For each variable, the pieces that mention it.
    pieces_of: Vec<Vec<usize>>,
    /// For each variable, whether it is a control.
    is_control: Vec<bool>,
}

impl Influence {
    /// Cuts the plant's constraints into pieces.
    pub fn new(plant: &Plant) -> Influence {
        let mut pieces = Vec::new();
        for component in plant.components() {
            for mode in component.modes() {
                for part in conjuncts(&mode.constraint) {
                    let mut vars = part.variables();
                    vars.push(component.mode_var());
                    pieces.push(vars);
                }
            }
        }
        for connection in plant.connections() {
            pieces.extend(conjuncts(connection).into_iter().map(Formula::variables));
        }
        let mut pieces_of = vec![Vec::new(); plant.table().len()];
        for (p, vars) in pieces.iter().enumerate() {
            for x in vars {
                pieces_of[x.index()].push(p);
            }
        }
        let mut is_control = vec![false; plant.table().len()];
        for control in plant.controls() {
            is_control[control.var.index()] = true;
        }
        Influence {
            pieces,
            pieces_of,
            is_control,
        }
    }

    /// The upstream components and controls that `vars` (read by a guard of `of`) depend on.
    pub fn dependencies(&self, plant: &Plant, of: ComponentId, vars: &[VarId]) -> Dependencies {
        let own_mode = plant.component(of).mode_var();
        let mut seen = vec![false; self.is_control.len()];
        let mut stack: Vec<VarId> = vars.to_vec();
        let mut found = Dependencies::default();
        while let Some(x) = stack.pop() {
            if std::mem::replace(&mut seen[x.index()], true) || x == own_mode {
                continue;
            }
            if let Some(upstream) = plant.component_of(x) {
                found.modes.push(upstream);
            } else if self.is_control[x.index()] {
                found.controls.push(x);
            } else {
                for &p in &self.pieces_of[x.index()] {
                    stack.extend(self.pieces[p].iter().filter(|y| !seen[y.index()]));
                }
            }
        }
        found.normalize();
        found
    }
}

/// The strongly connected components of `graph` as units ordered upstream first (by depth, then
/// by their first component), each component's unit, and each component's depth.
fn collapse(graph: &DiGraph<ComponentId, ()>) -> (Vec<Vec<ComponentId>>, Vec<usize>, Vec<usize>) {
    let n = graph.node_count();
    // Tarjan's algorithm yields the strongly connected components downstream first.
    let mut sccs: Vec<Vec<ComponentId>> = tarjan_scc(graph)
        .into_iter()
        .rev()
        .map(|scc| {
            let mut unit: Vec<ComponentId> = scc.into_iter().map(|node| graph[node]).collect();
            unit.sort_unstable();
            unit
        })
        .collect();
    let mut scc_of = vec![0; n];
    for (i, unit) in sccs.iter().enumerate() {
        for c in unit {
            scc_of[c.index()] = i;
        }
    }
    // In Tarjan's reversed order every edge between units goes forward, so one pass suffices.
    let mut scc_depth = vec![0usize; sccs.len()];
    for (i, unit) in sccs.iter().enumerate() {
        for c in unit {
            for u in graph.neighbors_directed(NodeIndex::new(c.index()), petgraph::Incoming) {
                let from = scc_of[u.index()];
                if from != i {
                    scc_depth[i] = scc_depth[i].max(scc_depth[from] + 1);
                }
            }
        }
    }
    let depth: Vec<usize> = scc_of.iter().map(|&s| scc_depth[s]).collect();
    sccs.sort_by_key(|unit| (depth[unit[0].index()], unit[0]));
    let mut unit_of = vec![0; n];
    for (i, unit) in sccs.iter().enumerate() {
        for c in unit {
            unit_of[c.index()] = i;
        }
    }
    (sccs, unit_of, depth)
}

/// The causal graph of a plant's components, with its strongly connected components collapsed
/// into causal units (§6.3.2: "strongly connected components are treated as one").
#[derive(Debug, Clone)]
pub struct CausalGraph {
    /// Node `i` is component `i`; an edge `u → c` says `u` is upstream of `c`.
    graph: DiGraph<ComponentId, ()>,
    /// The causal units, upstream first (a topological order of the collapsed graph).
    units: Vec<Vec<ComponentId>>,
    /// Each component's unit, by position in `units`.
    unit_of: Vec<usize>,
    /// Each component's depth: the longest chain of units upstream of its unit.
    depth: Vec<usize>,
    /// Components by decreasing depth, then declaration order: the reactive planner's order.
    downstream_first: Vec<ComponentId>,
}

impl CausalGraph {
    /// Builds the graph from the edges `upstream[c]` (the components upstream of `c`).
    pub(crate) fn new(upstream: &[Vec<ComponentId>]) -> CausalGraph {
        let mut graph = DiGraph::with_capacity(upstream.len(), 0);
        for c in 0..upstream.len() {
            graph.add_node(ComponentId(c as u32));
        }
        for (c, ups) in upstream.iter().enumerate() {
            for u in ups.iter().filter(|u| u.index() != c) {
                graph.update_edge(NodeIndex::new(u.index()), NodeIndex::new(c), ());
            }
        }
        let (units, unit_of, depth) = collapse(&graph);
        let mut downstream_first: Vec<ComponentId> =
            (0..upstream.len()).map(|c| ComponentId(c as u32)).collect();
        downstream_first.sort_by_key(|c| (std::cmp::Reverse(depth[c.index()]), *c));
        CausalGraph {
            graph,
            units,
            unit_of,
            depth,
            downstream_first,
        }
    }

    /// The components directly upstream of `c` (whose modes its guards depend on), in
    /// declaration order.
    pub fn upstream(&self, c: ComponentId) -> Vec<ComponentId> {
        let mut ups: Vec<ComponentId> = self
            .graph
            .neighbors_directed(NodeIndex::new(c.index()), petgraph::Incoming)
            .map(|n| self.graph[n])
            .collect();
        ups.sort_unstable();
        ups
    }

    /// The causal units (strongly connected components), upstream first. A unit with more than
    /// one component is a cycle of influence.
    pub fn units(&self) -> &[Vec<ComponentId>] {
        &self.units
    }

    /// The unit `c` belongs to, by position in [`CausalGraph::units`].
    pub fn unit_of(&self, c: ComponentId) -> usize {
        self.unit_of[c.index()]
    }

    /// True when no unit has more than one component (Burton's acyclic case).
    pub fn is_acyclic(&self) -> bool {
        self.units.iter().all(|u| u.len() == 1)
    }

    /// The longest chain of units upstream of `c`'s unit (0 for a component nothing drives).
    pub fn depth(&self, c: ComponentId) -> usize {
        self.depth[c.index()]
    }

    /// Every component, most downstream first (ties in declaration order): the order in which
    /// the reactive planner achieves goals and sub-goals.
    pub fn downstream_first(&self) -> &[ComponentId] {
        &self.downstream_first
    }

    /// Every edge `(upstream, downstream)`, sorted.
    pub fn edges(&self) -> Vec<(ComponentId, ComponentId)> {
        let mut edges: Vec<(ComponentId, ComponentId)> = self
            .graph
            .edge_indices()
            .filter_map(|e| self.graph.edge_endpoints(e))
            .map(|(a, b)| (self.graph[a], self.graph[b]))
            .collect();
        edges.sort_unstable();
        edges
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ids(list: &[u32]) -> Vec<ComponentId> {
        list.iter().map(|&i| ComponentId(i)).collect()
    }

    #[test]
    fn depth_orders_downstream_first_and_cycles_collapse() {
        // 0 → 1 → 2, 0 → 2; 3 ↔ 4 downstream of 2.
        let upstream = vec![ids(&[]), ids(&[0]), ids(&[0, 1]), ids(&[2, 4]), ids(&[3])];
        let graph = CausalGraph::new(&upstream);
        assert_eq!(graph.depth(ComponentId(2)), 2);
        assert_eq!(graph.depth(ComponentId(3)), 3);
        assert_eq!(graph.depth(ComponentId(4)), 3);
        assert_eq!(graph.unit_of(ComponentId(3)), graph.unit_of(ComponentId(4)));
        assert!(!graph.is_acyclic());
        assert_eq!(graph.downstream_first(), ids(&[3, 4, 2, 1, 0]).as_slice());
        assert_eq!(graph.upstream(ComponentId(2)), ids(&[0, 1]));
        let positions: Vec<usize> = (0..5).map(|c| graph.unit_of(ComponentId(c))).collect();
        assert!(positions[0] < positions[1] && positions[1] < positions[2]);
        assert!(positions[2] < positions[3]);
    }

    #[test]
    fn self_influence_is_no_edge() {
        let graph = CausalGraph::new(&[ids(&[0])]);
        assert!(graph.edges().is_empty());
        assert!(graph.is_acyclic());
    }
}

#[cfg(test)]
mod influence_tests {
    use super::super::testing::{component, model};
    use super::Influence;

    #[test]
    fn guard_inputs_are_traced_to_upstream_modes_and_controls() {
        let plant = model("propulsion");
        let influence = Influence::new(&plant);
        let engine = component(&plant, "engine");
        let var = |name: &str| plant.table().variable_id(name).expect(name);
        let command = influence.dependencies(&plant, engine, &[var("engine.cmd")]);
        assert_eq!(command.modes, [component(&plant, "PDE")]);
        assert_eq!(command.controls, [var("PDE.cmd")]);
        let fuel = influence.dependencies(&plant, engine, &[var("engine.fuel")]);
        assert_eq!(
            fuel.modes,
            [component(&plant, "tank1"), component(&plant, "valve1")]
        );
        assert!(fuel.controls.is_empty());
        assert!(!fuel.overlaps(&command));
    }
}
