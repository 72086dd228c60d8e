//! Which modes a component can be moved to (§6.3.1, §6.3.3; DESIGN.md §9), computed per
//! component over its *planning graph*: an edge for every nominal transition (target a nominal
//! mode, timed ones included) and every repair (source a fault mode, target a nominal mode)
//! whose guard the planner can establish ([`Requirement`](super::Requirement)).
//!
//! - A transition is **reversible** when its source can be returned to from its target by
//!   nominal transitions: both lie in one strongly connected component of the graph of nominal
//!   modes. The **reversible region** of a nominal mode is its strongly connected component.
//! - A **repair mode** is a nominal mode the plant cannot reach from its initial modes by
//!   nominal transitions (any guard): it is entered only after a fault, through a repair, and
//!   is a step of that repair (Table 6.1's `resetting-on`, between `resettable` and `on`).
//!   §6.3.3 allows repairs out of fault modes; a repair that takes several transitions is no
//!   less a repair.
//! - A nominal mode is **committing** when its strongly connected component is entered from
//!   another one, irreversibly, by a transition out of a mode that is not a repair mode:
//!   `separated` for a lander that was `connected`, and every mode reversibly reachable from
//!   there. Entering the driver's `on` from `resetting-on` commits nothing: the driver could be
//!   `on` before the fault.
//! - From a **fault** mode or a repair mode, the repair continues (§6.3.3): the region is the
//!   mode, the repair modes it leads to, and the regions of the modes they all lead to that are
//!   not committing. A repair into a committing mode — the backup pyro that separates the
//!   lander — is treated like any irreversible transition.
//! - The **irreversible frontier** of a mode is what one irreversible transition leads to from
//!   its region: such a target is allowed only when the configuration goal names it explicitly,
//!   and never as an intermediate step (paths stay in the region until their last transition).

use petgraph::algo::tarjan_scc;
use petgraph::graph::{DiGraph, NodeIndex};

use crate::logic::ValueId;
use crate::plant::{Component, ModeKind};

/// The reversible regions and irreversible frontiers of one component's modes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reachability {
    /// `region[m][v]`: `v` is reversibly reachable from `m` (`m` itself included).
    region: Vec<Vec<bool>>,
    /// `frontier[m][v]`: `v` is reachable from `m` only by one final irreversible transition.
    frontier: Vec<Vec<bool>>,
    /// Nominal modes entered irreversibly from other nominal modes.
    committing: Vec<bool>,
    /// Nominal modes reached only through a repair.
    repair_modes: Vec<bool>,
}

impl Reachability {
    /// Computes the regions from the planning graph's edges `(source, target)`.
    pub(crate) fn new(component: &Component, edges: &[(ValueId, ValueId)]) -> Reachability {
        let n = component.modes().len();
        let nominal: Vec<bool> = component
            .modes()
            .iter()
            .map(|m| m.kind == ModeKind::Nominal)
            .collect();
        let mut graph: DiGraph<(), ()> = DiGraph::with_capacity(n, edges.len());
        for _ in 0..n {
            graph.add_node(());
        }
        for &(a, b) in edges {
            if nominal[a.index()] && nominal[b.index()] {
                graph.update_edge(NodeIndex::new(a.index()), NodeIndex::new(b.index()), ());
            }
        }
        let mut scc = vec![0; n];
        for (i, members) in tarjan_scc(&graph).into_iter().enumerate() {
            for node in members {
                scc[node.index()] = i;
            }
        }
        let repair_modes = off_envelope(component, &nominal);
        // A strongly connected component entered from another one commits all its modes,
        // unless it is entered only from repair modes: the plant could be there before the fault.
        let mut entered = vec![false; n];
        for &(a, b) in edges {
            let (a, b) = (a.index(), b.index());
            if nominal[a] && !repair_modes[a] && nominal[b] && scc[a] != scc[b] {
                entered[scc[b]] = true;
            }
        }
        let committing: Vec<bool> = (0..n).map(|v| nominal[v] && entered[scc[v]]).collect();
        let mut region = vec![vec![false; n]; n];
        for (m, row) in region.iter_mut().enumerate() {
            if nominal[m] && !repair_modes[m] {
                for v in 0..n {
                    row[v] = nominal[v] && scc[v] == scc[m];
                }
                continue;
            }
            // A fault or a repair mode: follow the repair through repair modes, up to the
            // modes it restores (whole strongly connected components) unless they commit.
            row[m] = true;
            let mut stack = vec![m];
            while let Some(at) = stack.pop() {
                for &(a, b) in edges {
                    let (a, b) = (a.index(), b.index());
                    if a != at || row[b] || committing[b] {
                        continue;
                    }
                    if repair_modes[b] {
                        row[b] = true;
                        stack.push(b);
                    } else {
                        for v in 0..n {
                            row[v] |= nominal[v] && scc[v] == scc[b];
                        }
                    }
                }
            }
        }
        let frontier = region
            .iter()
            .map(|inside| {
                let mut out = vec![false; n];
                for &(a, b) in edges {
                    if inside[a.index()] && !inside[b.index()] {
                        out[b.index()] = true;
                    }
                }
                out
            })
            .collect();
        Reachability {
            region,
            frontier,
            committing,
            repair_modes,
        }
    }

    /// True when `to` is reversibly reachable from `from` (or is `from`).
    pub fn is_reversible(&self, from: ValueId, to: ValueId) -> bool {
        self.region[from.index()][to.index()]
    }

    /// True when `to` is reachable from `from` only by one final irreversible transition.
    pub fn is_irreversible(&self, from: ValueId, to: ValueId) -> bool {
        self.frontier[from.index()][to.index()]
    }

    /// The modes reversibly reachable from `from`, `from` included.
    pub fn reversible(&self, from: ValueId) -> impl Iterator<Item = ValueId> + '_ {
        members(&self.region[from.index()])
    }

    /// The modes reachable from `from` only by a final irreversible transition.
    pub fn irreversible(&self, from: ValueId) -> impl Iterator<Item = ValueId> + '_ {
        members(&self.frontier[from.index()])
    }

    /// True for a nominal mode entered irreversibly from other nominal modes.
    pub fn is_committing(&self, mode: ValueId) -> bool {
        self.committing[mode.index()]
    }

    /// True for a nominal mode the plant reaches only through a repair (a step of the repair,
    /// which the component cannot return to once repaired).
    pub fn is_repair_mode(&self, mode: ValueId) -> bool {
        self.repair_modes[mode.index()]
    }
}

/// The nominal modes outside the plant's nominal envelope: not reachable from an initial
/// nominal mode by nominal transitions. Every transition counts, whatever its guard (an
/// environment-driven one too): what matters is where the plant can be without a fault, not
/// what the planner can cause.
fn off_envelope(component: &Component, nominal: &[bool]) -> Vec<bool> {
    let mut inside: Vec<bool> = component
        .initial()
        .iter()
        .zip(nominal)
        .map(|(&p, &nominal)| nominal && p > 0.0)
        .collect();
    let mut stack: Vec<usize> = members(&inside).map(ValueId::index).collect();
    while let Some(at) = stack.pop() {
        for &t in component.outgoing(ValueId(at as u32)) {
            let target = component.transitions()[t].target.index();
            if nominal[target] && !inside[target] {
                inside[target] = true;
                stack.push(target);
            }
        }
    }
    nominal
        .iter()
        .zip(&inside)
        .map(|(&nominal, &inside)| nominal && !inside)
        .collect()
}

/// The modes whose flag is set.
pub(crate) fn members(flags: &[bool]) -> impl Iterator<Item = ValueId> + '_ {
    flags
        .iter()
        .enumerate()
        .filter(|(_, on)| **on)
        .map(|(i, _)| ValueId(i as u32))
}

#[cfg(test)]
mod tests {
    use super::super::Reconfiguration;
    use super::super::testing::{SWITCH_GADGET, component, load, mode};
    use crate::logic::ValueId;

    #[test]
    fn regions_frontiers_and_committing_modes() {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let gadget = component(&plant, "gadget");
        let reach = reconfiguration.policy(gadget).reachability();
        let m = |name| mode(&plant, "gadget", name);
        let names = |modes: Vec<ValueId>| -> Vec<String> {
            modes
                .into_iter()
                .map(|v| plant.component(gadget).mode(v).name.clone())
                .collect()
        };
        assert_eq!(names(reach.reversible(m("a")).collect()), ["a", "b", "e"]);
        assert_eq!(names(reach.irreversible(m("a")).collect()), ["c"]);
        assert_eq!(names(reach.reversible(m("c")).collect()), ["c", "d"]);
        assert_eq!(reach.irreversible(m("c")).count(), 0);
        // d is entered only from c, but its strongly connected component is entered
        // irreversibly: both commit.
        assert!(reach.is_committing(m("c")) && reach.is_committing(m("d")));
        assert!(!reach.is_committing(m("a")) && !reach.is_committing(m("e")));
        // From the fault, the repair into a is allowed (§6.3.3); the repair into c is an
        // irreversible step like any other.
        assert_eq!(
            names(reach.reversible(m("broken")).collect()),
            ["a", "b", "e", "broken"]
        );
        assert_eq!(names(reach.irreversible(m("broken")).collect()), ["c"]);
        assert!(reach.is_reversible(m("broken"), m("b")));
        assert!(reach.is_irreversible(m("b"), m("c")));
    }
}
