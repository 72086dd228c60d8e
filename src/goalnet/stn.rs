//! The Simple Temporal Network of a goal network (mds-goal-networks.md §1.5, DESIGN.md §15.1).
//!
//! Each constraint `min ≤ t(to) − t(from) ≤ max` becomes two edges of the *distance graph*:
//! `from → to` weighted `max` and `to → from` weighted `−min` (an infinite bound gives no edge).
//! The origin `Z` stands for absolute time 0 and every point is at or after it. The network is
//! consistent iff the distance graph has no negative cycle, and the window of a point `p` is
//! `[−d(p, Z), d(Z, p)]`, where `d` is the shortest-path distance.
//!
//! Propagation keeps the two single-source distance vectors `d(Z, ·)` (on the distance graph) and
//! `d(·, Z)` (on the reversed graph, where every point is reachable from `Z` through its
//! `[0, +∞)` constraint to the origin, so every negative cycle is found from there).
//! - The earliest times `−d(·, Z)`: a full propagation runs petgraph's Bellman–Ford on the
//!   reversed graph; adding constraints to a propagated network (grounding a fired point, a
//!   scheduler's serialisation) relaxes from the new edges only (FIFO label correcting), touching
//!   only the points whose earliest time changes. A point queued more often than there are
//!   points signals a negative cycle, and relaxation past a work budget (twice the graph's size)
//!   would cost more than starting over: in both cases the full Bellman–Ford decides.
//! - The latest times `d(Z, ·)`: petgraph's Dijkstra on weights reduced by the earliest times
//!   (Johnson's reweighting; the earliest times are a solution, so reduced weights are ≥ 0).
//!   Bellman–Ford needed a pass per point of a chain of negative edges there: grounding one point
//!   of a 10,000-point chain took 1 s.
//! - On a negative cycle, the cycle is extracted (Bellman–Ford with predecessor edges, walked
//!   back into the cycle) and named by its constraints.
//! - **The scheduler's trials** ([`Stn::try_constraint`], [`Stn::undo`]): a constraint is added
//!   to the network itself and relaxed from, with what the relaxation changed kept to undo it;
//!   the latest times (a Dijkstra over the whole graph) wait for the next [`Stn::propagate`].
//!   For a constraint with one edge `u → v` the test for a negative cycle is exact — the cycle
//!   must pass through the new edge, so it exists iff the relaxation improves `u` again — and
//!   costs no more than the relaxation. A trial thus costs the points whose earliest time it
//!   moves, not a copy of the network and a full propagation; a refused one leaves the network
//!   as it was, edge lists included (petgraph removes the last edges in place).
//! - **Rigid components** ([`Stn::rigid_components`]): the points the network fixes relative
//!   to each other are the strongly connected components of the edges the earliest times make
//!   tight, found in one pass; the scheduler asks whether two consecutive points coincide with
//!   it instead of a Bellman–Ford per pair.

use std::collections::VecDeque;

use petgraph::algo::{bellman_ford, dijkstra, tarjan_scc};
use petgraph::graph::{DiGraph, EdgeIndex, NodeIndex};
use petgraph::visit::{EdgeFiltered, EdgeRef, Reversed};
use rustc_hash::FxHashMap;

use super::temporal_constraint::{ConstraintId, Provenance, TemporalConstraint};
use super::time_point::TimePointId;

/// The earliest and latest time a point may fire (`lb ≤ t(p) ≤ ub`; `ub` may be `+∞`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    /// The earliest time, seconds.
    pub lb: f64,
    /// The latest time, seconds (`f64::INFINITY` when unbounded).
    pub ub: f64,
}

/// The network has no solution: the constraints of a negative cycle of the distance graph, in
/// cycle order (each at most once).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "the temporal constraints are inconsistent: {} of them form a negative cycle",
    cycle.len()
)]
pub struct Inconsistency {
    /// The constraints whose bounds add up to a negative cycle.
    pub cycle: Vec<ConstraintId>,
}

/// A constraint the network refuses outright.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StnError {
    /// A point not in this network.
    #[error("time point {0} is not in the network")]
    UnknownPoint(u32),
    /// NaN bounds, `min > max`, or a bound infinite on the wrong side.
    #[error("bounds [{min}, {max}] describe no interval")]
    BadBounds {
        /// The lower bound given.
        min: f64,
        /// The upper bound given.
        max: f64,
    },
}

/// Distances from and to the origin after a successful propagation.
#[derive(Debug, Clone)]
struct Distances {
    /// `d(Z, p)`: the latest time of `p`; `None` while only the earliest times are up to date
    /// (a scheduler's trials, [`Stn::try_constraint`]).
    from_origin: Option<Vec<f64>>,
    /// `d(p, Z)`: minus the earliest time of `p`.
    to_origin: Vec<f64>,
}

/// A simple temporal network over time points, with its distance graph and (once propagated)
/// every point's window.
#[derive(Debug, Clone)]
pub struct Stn {
    constraints: Vec<TemporalConstraint>,
    graph: DiGraph<(), f64>,
    /// The constraint each edge of `graph` comes from, by edge index.
    edge_constraint: Vec<ConstraintId>,
    /// `None` until propagated, and after an inconsistency.
    distances: Option<Distances>,
    /// Edges added since the last propagation (relaxed incrementally).
    pending: Vec<EdgeIndex>,
}

impl Default for Stn {
    fn default() -> Self {
        Self::new()
    }
}

impl Stn {
    /// A network holding only the origin.
    pub fn new() -> Self {
        let mut graph = DiGraph::new();
        graph.add_node(());
        Stn {
            constraints: Vec::new(),
            graph,
            edge_constraint: Vec::new(),
            // The first propagation is a full one (petgraph's Bellman–Ford).
            distances: None,
            pending: Vec::new(),
        }
    }

    /// Number of points, the origin included.
    pub fn point_count(&self) -> usize {
        self.graph.node_count()
    }

    /// Every constraint, in the order added (the `[0, +∞)` constraint of each point included).
    pub fn constraints(&self) -> &[TemporalConstraint] {
        &self.constraints
    }

    /// One constraint.
    pub fn constraint(&self, id: ConstraintId) -> &TemporalConstraint {
        &self.constraints[id.index()]
    }

    /// Adds a point, at or after the origin.
    pub fn add_point(&mut self) -> TimePointId {
        let node = self.graph.add_node(());
        let point = TimePointId(node.index() as u32);
        if let Some(distances) = &mut self.distances {
            // Unconstrained but for [0, +∞) from the origin: the window is [0, +∞).
            if let Some(from_origin) = &mut distances.from_origin {
                from_origin.push(f64::INFINITY);
            }
            distances.to_origin.push(0.0);
        }
        let after = TemporalConstraint::before(TimePointId::ORIGIN, point, Provenance::AfterOrigin);
        self.insert(after);
        point
    }

    /// Adds a constraint; the windows are brought up to date by the next [`Stn::propagate`].
    pub fn add_constraint(
        &mut self,
        constraint: TemporalConstraint,
    ) -> Result<ConstraintId, StnError> {
        for point in [constraint.from, constraint.to] {
            if point.index() >= self.point_count() {
                return Err(StnError::UnknownPoint(point.0));
            }
        }
        if !constraint.bounds_are_valid() {
            return Err(StnError::BadBounds {
                min: constraint.min,
                max: constraint.max,
            });
        }
        Ok(self.insert(constraint))
    }

    fn insert(&mut self, constraint: TemporalConstraint) -> ConstraintId {
        let id = ConstraintId(self.constraints.len() as u32);
        let from = NodeIndex::new(constraint.from.index());
        let to = NodeIndex::new(constraint.to.index());
        if constraint.max.is_finite() {
            self.add_edge(from, to, constraint.max, id);
        }
        if constraint.min.is_finite() {
            self.add_edge(to, from, -constraint.min, id);
        }
        self.constraints.push(constraint);
        id
    }

    fn add_edge(&mut self, from: NodeIndex, to: NodeIndex, weight: f64, id: ConstraintId) {
        let edge = self.graph.add_edge(from, to, weight);
        self.edge_constraint.push(id);
        self.pending.push(edge);
    }

    /// Fixes a fired point at `time` (`Z → p ∈ [τ, τ]`, AG §1.2.7 d) and re-propagates
    /// incrementally.
    pub fn ground(&mut self, point: TimePointId, time: f64) -> Result<(), GroundError> {
        let constraint =
            TemporalConstraint::new(TimePointId::ORIGIN, point, time, time, Provenance::Fired);
        self.add_constraint(constraint)
            .map_err(GroundError::Refused)?;
        self.propagate().map_err(GroundError::Inconsistent)
    }

    /// Brings every window up to date: in full the first time and after an inconsistency,
    /// incrementally from the constraints added since the last successful propagation.
    pub fn propagate(&mut self) -> Result<(), Inconsistency> {
        self.propagate_earliest()?;
        if let Some(distances) = &mut self.distances
            && distances.from_origin.is_none()
        {
            distances.from_origin = Some(latest_times(&self.graph, &distances.to_origin));
        }
        Ok(())
    }

    /// Brings the earliest times up to date (as [`Stn::propagate`]), leaving the latest times
    /// to the next [`Stn::propagate`].
    fn propagate_earliest(&mut self) -> Result<(), Inconsistency> {
        let pending = std::mem::take(&mut self.pending);
        // The relaxation's cycle test is a bound on work; Bellman–Ford has the last word.
        let incremental = self
            .distances
            .take()
            .and_then(|mut distances| {
                if pending.is_empty() {
                    return Some(distances);
                }
                let seeds = self.backward(&pending);
                let relaxed = relax_from(
                    Reversed(&self.graph),
                    &mut distances.to_origin,
                    &seeds,
                    self.limits(None),
                );
                distances.from_origin = None;
                matches!(relaxed, Relaxed::Done(_)).then_some(distances)
            })
            .or_else(|| self.full());
        match incremental {
            Some(distances) => {
                self.distances = Some(distances);
                Ok(())
            }
            None => Err(Inconsistency {
                cycle: self.negative_cycle(),
            }),
        }
    }

    /// Full propagation of the earliest times: Bellman–Ford on the reversed graph; `None` when
    /// the distance graph has a negative cycle.
    fn full(&self) -> Option<Distances> {
        // The reversed graph reaches every point, so any negative cycle shows here.
        let to_origin = bellman_ford(Reversed(&self.graph), NodeIndex::new(0))
            .ok()?
            .distances;
        Some(Distances {
            from_origin: None,
            to_origin,
        })
    }

    /// The new edges as relaxation seeds on the reversed graph: `(tail, head, weight)`.
    fn backward(&self, new_edges: &[EdgeIndex]) -> Vec<(NodeIndex, NodeIndex, f64)> {
        new_edges
            .iter()
            .filter_map(|&edge| {
                let (from, to) = self.graph.edge_endpoints(edge)?;
                Some((to, from, self.graph[edge]))
            })
            .collect()
    }

    /// The relaxation's bounds: a point queued more often than there are points is a (possible)
    /// negative cycle; past twice the graph's size in improvements a full propagation is
    /// cheaper than relaxing on. `exact`: the tail of the only new edge, whose improvement is a
    /// negative cycle through that edge.
    fn limits(&self, exact: Option<NodeIndex>) -> Limits {
        Limits {
            enqueued: self.point_count() + 1,
            budget: 2 * (self.graph.edge_count() + self.point_count()),
            exact,
        }
    }

    /// Adds `constraint` if the network stays consistent with it, and brings the earliest times
    /// up to date; the latest times wait for the next [`Stn::propagate`]. The scheduler's trial
    /// (an order or a serialisation that may not fit): instead of a copy of the network
    /// propagated in full, the new edge is relaxed from, touching only the points whose earliest
    /// time it moves, and a refusal leaves the network exactly as it was. Propagates first if
    /// the network is not (its constraints as given may be inconsistent: `Err`).
    ///
    /// A constraint with one edge `u → v` (an order, `[0, +∞)`) closes a negative cycle iff
    /// relaxing from it improves `u` again — the improvement went round the cycle — so the test
    /// is exact and as cheap as the relaxation; a constraint with two edges falls back on the
    /// propagation's bounds and Bellman–Ford.
    pub(crate) fn try_constraint(
        &mut self,
        constraint: TemporalConstraint,
    ) -> Result<Trial, Refusal> {
        if !self.pending.is_empty() || self.distances.is_none() {
            self.propagate_earliest().map_err(|_| Refusal)?;
        }
        let (constraints, edges) = (self.constraints.len(), self.graph.edge_count());
        self.add_constraint(constraint).map_err(|_| Refusal)?;
        let pending = std::mem::take(&mut self.pending);
        let seeds = self.backward(&pending);
        let exact = match seeds[..] {
            [(tail, _, _)] => Some(tail),
            _ => None,
        };
        let limits = self.limits(exact);
        let Some(mut distances) = self.distances.take() else {
            self.remove_since(constraints, edges);
            return Err(Refusal);
        };
        let latest = distances.from_origin.take();
        let relaxed = relax_from(
            Reversed(&self.graph),
            &mut distances.to_origin,
            &seeds,
            limits,
        );
        let earliest = match relaxed {
            Relaxed::Done(changed) => Some(Earliest::Changed(changed)),
            Relaxed::Cycle(changed) => {
                restore(&mut distances.to_origin, &changed);
                None
            }
            Relaxed::GaveUp(changed) => {
                // Bellman–Ford decides; the values before are kept to undo the trial.
                restore(&mut distances.to_origin, &changed);
                self.full().map(|full| {
                    Earliest::All(std::mem::replace(&mut distances.to_origin, full.to_origin))
                })
            }
        };
        match earliest {
            Some(earliest) => {
                self.distances = Some(distances);
                Ok(Trial {
                    constraints,
                    edges,
                    earliest,
                    latest,
                })
            }
            None => {
                distances.from_origin = latest;
                self.distances = Some(distances);
                self.remove_since(constraints, edges);
                Err(Refusal)
            }
        }
    }

    /// Takes back a constraint [`Stn::try_constraint`] added: the network is as it was before.
    pub(crate) fn undo(&mut self, trial: Trial) {
        self.remove_since(trial.constraints, trial.edges);
        if let Some(distances) = &mut self.distances {
            match trial.earliest {
                Earliest::Changed(changed) => restore(&mut distances.to_origin, &changed),
                Earliest::All(before) => distances.to_origin = before,
            }
            distances.from_origin = trial.latest;
        }
    }

    /// Removes the constraints and edges added after the first `constraints` and `edges`.
    fn remove_since(&mut self, constraints: usize, edges: usize) {
        while self.graph.edge_count() > edges {
            let last = EdgeIndex::new(self.graph.edge_count() - 1);
            self.graph.remove_edge(last);
        }
        self.edge_constraint.truncate(edges);
        self.constraints.truncate(constraints);
        self.pending.clear();
    }

    /// The earliest time of a point as of the last successful propagation, or of the last trial
    /// ([`Stn::try_constraint`]); `None` before one, after an inconsistency, or for a point added
    /// since.
    pub(crate) fn earliest(&self, point: TimePointId) -> Option<f64> {
        let distances = self.distances.as_ref()?;
        distances.to_origin.get(point.index()).map(|d| -d)
    }

    /// The constraints of a negative cycle (empty if there is none).
    fn negative_cycle(&self) -> Vec<ConstraintId> {
        let Some(edges) = self.cycle_edges() else {
            return Vec::new();
        };
        let mut cycle = Vec::new();
        for edge in edges {
            let id = self.edge_constraint[edge.index()];
            if !cycle.contains(&id) {
                cycle.push(id);
            }
        }
        cycle
    }

    /// The edges of a negative cycle, in cycle order: Bellman–Ford on the reversed graph from
    /// the origin (which reaches every point) with predecessor edges; a point still improved in
    /// the n-th pass leads back, through n predecessor steps, into a cycle.
    fn cycle_edges(&self) -> Option<Vec<EdgeIndex>> {
        let n = self.point_count();
        let mut dist = vec![f64::INFINITY; n];
        let mut pred: Vec<Option<EdgeIndex>> = vec![None; n];
        dist[0] = 0.0;
        let mut last = None;
        for _ in 0..n {
            last = None;
            for edge in self.graph.edge_references() {
                // Reversed: the edge from → to is walked to → from.
                let (from, to) = (edge.target().index(), edge.source().index());
                if dist[from] + edge.weight() < dist[to] {
                    dist[to] = dist[from] + edge.weight();
                    pred[to] = Some(edge.id());
                    last = Some(to);
                }
            }
            last?;
        }
        let mut node = last?;
        for _ in 0..n {
            node = self.graph.edge_endpoints(pred[node]?)?.1.index();
        }
        let start = node;
        let mut edges = Vec::new();
        loop {
            let edge = pred[node]?;
            edges.push(edge);
            node = self.graph.edge_endpoints(edge)?.1.index();
            if node == start || edges.len() > n {
                break;
            }
        }
        edges.reverse();
        Some(edges)
    }

    /// Whether the last propagation succeeded and nothing was added since.
    pub fn is_propagated(&self) -> bool {
        self.distances
            .as_ref()
            .is_some_and(|d| d.from_origin.is_some())
            && self.pending.is_empty()
    }

    /// The window of a point as of the last successful propagation (`None` before one, after an
    /// inconsistency, or for a point added since).
    pub fn window(&self, point: TimePointId) -> Option<Window> {
        let distances = self.distances.as_ref()?;
        let ub = *distances.from_origin.as_ref()?.get(point.index())?;
        let to_origin = *distances.to_origin.get(point.index())?;
        Some(Window { lb: -to_origin, ub })
    }

    /// Per point, the points that must fire before it: the sources of the constraints into it
    /// with a minimum ≥ 0 (the firing rule of mds-goal-networks.md §2.4: "predecessors fired").
    pub fn predecessors(&self) -> Vec<Vec<TimePointId>> {
        let mut predecessors = vec![Vec::new(); self.point_count()];
        for c in &self.constraints {
            if c.min >= 0.0 && c.from != c.to && !predecessors[c.to.index()].contains(&c.from) {
                predecessors[c.to.index()].push(c.from);
            }
        }
        predecessors
    }

    /// Per point, its *rigid component* (as of the earliest times of the last propagation or
    /// trial): two points are in one component iff the network fixes the time between them,
    /// `d(a, b) + d(b, a) = 0`. With the earliest times `e` (a solution), every edge `u → v`
    /// has slack `w − (e(v) − e(u)) ≥ 0`; a shortest path `a → b` followed by one `b → a` is a
    /// closed walk of length `d(a, b) + d(b, a) ≥ 0` whose slack is the same sum, so the sum is 0
    /// iff the walk uses only tight edges (slack 0), iff `a` and `b` are in one strongly
    /// connected component of the tight edges. Then `t(b) − t(a) = e(b) − e(a)` in every
    /// solution. One pass over the graph (Tarjan's algorithm, petgraph).
    pub(crate) fn rigid_components(&self) -> Option<Vec<usize>> {
        let to_origin = &self.distances.as_ref()?.to_origin;
        let earliest = |n: NodeIndex| -to_origin[n.index()];
        let tight = EdgeFiltered::from_fn(&self.graph, |edge| {
            edge.weight() + earliest(edge.source()) - earliest(edge.target()) <= 0.0
        });
        let mut component = vec![0; self.point_count()];
        for (c, nodes) in tarjan_scc(&tight).into_iter().enumerate() {
            for node in nodes {
                component[node.index()] = c;
            }
        }
        Some(component)
    }

    /// The shortest-path distance `d(a, b)`: the latest `t(b) − t(a)` the network allows
    /// (`+∞` when unbounded; `None` when the network is inconsistent). Bellman–Ford from `a`:
    /// the scheduler asks this for a handful of pairs, not for every pair.
    pub fn distance(&self, a: TimePointId, b: TimePointId) -> Option<f64> {
        if a.index() >= self.point_count() || b.index() >= self.point_count() {
            return None;
        }
        let paths = bellman_ford(&self.graph, NodeIndex::new(a.index())).ok()?;
        paths.distances.get(b.index()).copied()
    }
}

/// `d(Z, ·)` by petgraph's Dijkstra on reduced weights (Johnson): the earliest times
/// `t = −d(·, Z)` are a solution of the network, so `w(u → v) + t(u) − t(v) ≥ 0` on every
/// edge, and `d(Z, v)` is the reduced distance plus `t(v)`. Bellman–Ford would need as many
/// passes as the longest chain of negative edges (a grounded point bounds every point before
/// it, one pass each).
fn latest_times(graph: &DiGraph<(), f64>, to_origin: &[f64]) -> Vec<f64> {
    let earliest = |n: NodeIndex| -to_origin[n.index()];
    let reduced = dijkstra(graph, NodeIndex::new(0), None, |edge| {
        (edge.weight() + earliest(edge.source()) - earliest(edge.target())).max(0.0)
    });
    let mut from_origin = vec![f64::INFINITY; graph.node_count()];
    for (node, distance) in reduced {
        from_origin[node.index()] = distance + earliest(node);
    }
    from_origin
}

/// Why grounding a point failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GroundError {
    /// The point or the time is not acceptable (unknown point, NaN time).
    #[error("the firing is refused: {0}")]
    Refused(StnError),
    /// Firing then contradicts the network (possible only for a forced firing, §2.4).
    #[error("the firing contradicts the network: {0}")]
    Inconsistent(Inconsistency),
}

/// What a trial changed in the earliest times, to undo it.
#[derive(Debug)]
enum Earliest {
    /// The points relaxed, each with its `d(·, Z)` before.
    Changed(Vec<(usize, f64)>),
    /// Every `d(·, Z)` before (the trial ended in a full propagation).
    All(Vec<f64>),
}

/// A constraint [`Stn::try_constraint`] added, with what [`Stn::undo`] needs to take it back.
#[derive(Debug)]
pub(crate) struct Trial {
    /// The number of constraints and edges before it.
    constraints: usize,
    edges: usize,
    earliest: Earliest,
    /// The latest times before it (`None` if they were not up to date).
    latest: Option<Vec<f64>>,
}

impl Trial {
    /// The points whose earliest time the trial moved, each with its earliest time before.
    pub(crate) fn moved(&self, stn: &Stn) -> Vec<(TimePointId, f64)> {
        match &self.earliest {
            Earliest::Changed(changed) => (changed.iter())
                .map(|&(i, before)| (TimePointId(i as u32), -before))
                .collect(),
            Earliest::All(before) => (before.iter().enumerate())
                .map(|(i, &before)| (TimePointId(i as u32), -before))
                .filter(|&(p, before)| stn.earliest(p).map(f64::to_bits) != Some(before.to_bits()))
                .collect(),
        }
    }
}

/// A constraint [`Stn::try_constraint`] refused: the network would have no solution with it
/// (or it is malformed); the network is unchanged.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Refusal;

/// Puts back the values a relaxation changed.
fn restore(dist: &mut [f64], changed: &[(usize, f64)]) {
    for &(i, before) in changed {
        dist[i] = before;
    }
}

/// The bounds of one relaxation ([`Stn::limits`]).
#[derive(Debug, Clone, Copy)]
struct Limits {
    /// Times a point may be queued before a negative cycle is suspected.
    enqueued: usize,
    /// Improvements before handing over to a full propagation.
    budget: usize,
    /// The tail of the only new edge: its improvement is a negative cycle.
    exact: Option<NodeIndex>,
}

/// How a relaxation ended, each with the points it changed and their values before (first
/// change only).
#[derive(Debug)]
enum Relaxed {
    /// Every distance is up to date.
    Done(Vec<(usize, f64)>),
    /// A negative cycle, certainly: the origin or the exact tail improved.
    Cycle(Vec<(usize, f64)>),
    /// A possible negative cycle or the work budget spent: Bellman–Ford decides.
    GaveUp(Vec<(usize, f64)>),
}

/// Label-correcting relaxation (a FIFO queue, Bellman–Ford's queue form) of single-source
/// distances `dist` from the origin over `graph`, starting from the given new edges
/// `(from, to, weight)`. Stops on a certain negative cycle — the origin's own distance drops
/// below 0, or the tail of the only new edge improves — and gives up on a possible one (a point
/// queued more than `limits.enqueued` times) or when the work exceeds `limits.budget`
/// improvements; the caller then propagates in full. Bookkeeping is per point touched, so the
/// cost is that of the points whose distance changes, not of the network.
fn relax_from<G>(
    graph: G,
    dist: &mut [f64],
    new_edges: &[(NodeIndex, NodeIndex, f64)],
    limits: Limits,
) -> Relaxed
where
    G: petgraph::visit::IntoEdges<NodeId = NodeIndex, EdgeWeight = f64>,
{
    let mut relaxation = Relaxation {
        queue: VecDeque::new(),
        touched: FxHashMap::default(),
        changed: Vec::new(),
        limits,
        dist,
    };
    let mut outcome = Ok(());
    for &(from, to, weight) in new_edges {
        let value = relaxation.dist[from.index()] + weight;
        outcome = outcome.and_then(|()| relaxation.improve(to, value));
    }
    while let (Ok(()), Some(node)) = (outcome, relaxation.queue.pop_front()) {
        relaxation.touched.entry(node.index()).or_default().queued = false;
        let base = relaxation.dist[node.index()];
        for edge in graph.edges(node) {
            outcome = relaxation.improve(edge.target(), base + *edge.weight());
            if outcome.is_err() {
                break;
            }
        }
    }
    match outcome {
        Ok(()) => Relaxed::Done(relaxation.changed),
        Err(Stop::Cycle) => Relaxed::Cycle(relaxation.changed),
        Err(Stop::GaveUp) => Relaxed::GaveUp(relaxation.changed),
    }
}

/// Why a relaxation stopped early.
#[derive(Debug, Clone, Copy)]
enum Stop {
    Cycle,
    GaveUp,
}

/// Per point touched by a relaxation.
#[derive(Debug, Default)]
struct Touched {
    queued: bool,
    enqueued: usize,
}

/// The state of one incremental relaxation.
struct Relaxation<'a> {
    dist: &'a mut [f64],
    queue: VecDeque<NodeIndex>,
    touched: FxHashMap<usize, Touched>,
    /// The points changed, with their distance before.
    changed: Vec<(usize, f64)>,
    limits: Limits,
}

impl Relaxation<'_> {
    /// Lowers `node`'s distance to `value` if that improves it.
    fn improve(&mut self, node: NodeIndex, value: f64) -> Result<(), Stop> {
        let i = node.index();
        if value >= self.dist[i] {
            return Ok(());
        }
        if i == 0 || Some(node) == self.limits.exact {
            // d(Z, Z) < 0, or the only new edge's tail improved through it: a negative cycle.
            return Err(Stop::Cycle);
        }
        let touched = self.touched.entry(i).or_default();
        if touched.enqueued == 0 && !touched.queued {
            self.changed.push((i, self.dist[i]));
        }
        self.dist[i] = value;
        self.limits.budget = self.limits.budget.checked_sub(1).ok_or(Stop::GaveUp)?;
        if !touched.queued {
            // FIFO order: a point is queued at most once per pass, and passes past the number of
            // points only happen around a negative cycle.
            touched.enqueued += 1;
            if touched.enqueued > self.limits.enqueued {
                return Err(Stop::GaveUp);
            }
            touched.queued = true;
            self.queue.push_back(node);
        }
        Ok(())
    }
}
