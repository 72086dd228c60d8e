//! Conflict-directed A* over one independent sub-problem (Williams & Ragno; thesis §6.2.3).
//!
//! # The search space
//! A *node* is a set of full assignments described per decision variable by a slot:
//! `Fixed(i)` (the variable takes its `i`-th cheapest choice) or `From(i)` (it takes its `i`-th
//! cheapest choice or a dearer one). Costs are additive and independent per variable, so the
//! cheapest assignment of a node — its *best completion* — takes choice `i` in every slot, and
//! its cost is exactly the node's least cost. The frontier pops nodes by that cost.
//!
//! # Expansion
//! A popped node's best completion `c` is either
//! - *known bad*: it contains a learned conflict `K`;
//! - *tested bad*: the theory refutes it and returns a conflict `K ⊆ c`, which is learned;
//! - *good*: it is the next solution; then `K = c`.
//!
//! In each case the node is replaced by children that together hold exactly its assignments that
//! do not contain `K`. For the free variables `y1..yr` of `K` (those in `From` slots), child `j`
//! fixes `y1..y(j-1)` to their values in `K` and excludes `yj`'s value (`From(i+1)`): every
//! assignment avoiding `K` differs from it first at exactly one `yj`, so the children are
//! disjoint and cover the rest. These are the constituent kernels of `K` expanded systematically,
//! so every assignment is reached at most once and none is lost. Excluded values are always the
//! cheapest remaining ones, which is why `From(i)` (a prefix excluded) suffices.
//!
//! Each node is popped at its exact least cost, so solutions come out cheapest first; a conflict
//! prunes every assignment containing it without testing them one by one. A conflict of a
//! single pair refutes that choice on its own: it is skipped in every node at once (a `From`
//! slot moves past it) instead of being split off one node at a time.
//!
//! # Order
//! Assignments are ordered by cost, then by their choice indices compared colexicographically
//! (the last member first), and the frontier pops the node whose best completion is first in
//! that order. That best completion is the node's first assignment: every other one takes, in
//! each slot, a choice at or after the slot's index, so it costs at least as much (choices are
//! sorted by cost, and a floating-point sum in a fixed order is monotone in each term) and, at
//! equal cost, comes later in any order that compares indices position by position. The
//! frontier's nodes partition the assignments not yet returned or refuted, so each pop is at
//! the first of those, and the feasible ones come out in exactly this order: the sequence of
//! solutions is a function of the OCSP alone — not of which conflicts are known, which core the
//! SAT solver returned or what it had learned before. Conflicts shared between searches
//! (`shared.rs`), conflicts read off unit propagation (`Theory::search_conflict`) and choices
//! refuted on their own (skipped, which only removes infeasible assignments and re-queues a
//! node at a cost no lower than it was popped at) rely on this.
//!
//! When every cost is non-negative (estimation's −ln p), a child enters the frontier at a lower
//! bound: its own partial sum through the member it raises (the rest only adds non-negative
//! terms, and a floating-point sum never decreases by adding one). Its cost is summed when it
//! reaches the front, and it re-enters at that cost; a node popped at its exact cost is still
//! first, since every other node's exact place is at or after its queued one. Most children of
//! a solution's split raise a member to a fault far dearer than the front and are never summed.
//!
//! Ties used to follow node creation order, which depends on the conflict tree. Colexicographic
//! is the order a split creates its children in (child `j` raises the `j`-th free member of the
//! conflict, leaving the later ones at their indices), so it is the order ties came out in on
//! the Mars EDL: its beliefs and traces are byte-identical to those of the creation order
//! (docs/design/opsat.md, "The search"). Where a cut falls inside a group of ties, another
//! member of the group may now be returned (`kairos solve` on the full adder with `-k 5`,
//! docs/design/opsat.md).

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;
use std::hash::BuildHasherDefault;
use std::rc::Rc;

use rustc_hash::{FxHashMap, FxHasher};

use super::ocsp::{Choice, Cut, Meter, Ocsp};
use super::shared::ConflictStore;
use super::theory::{Consistency, Literal, Theory};
use crate::logic::VarId;

/// A cost ordered totally (costs are never NaN; [`Ocsp::decide`] refuses them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cost(pub(crate) f64);

impl Eq for Cost {}

impl PartialOrd for Cost {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Cost {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// The merge frontier's priority: cheapest first, then first created (deterministic ties).
pub(crate) type Priority = Reverse<(Cost, u64)>;

/// The merge frontier's hasher: entries are hashed on every push and pop, and SipHash was a
/// tenth of a busy estimation step on a breaker tree (the order of pops does not depend on it).
pub(crate) type FxBuildHasher = BuildHasherDefault<FxHasher>;

/// A decision variable's slot in a node: `Fixed(i)` (it takes its `i`-th cheapest choice) or
/// `From(i)` (that choice or a dearer one), packed in 32 bits — the flag in the top bit, the
/// choice below (a variable never has 2³¹ choices) — because a node holds one per member and
/// is copied per child: on a breaker tree of 1,535 components the frontier's nodes were most of
/// the search's memory and copying them a third of its time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Slot(u32);

/// The top bit of a [`Slot`]: set when it is `Fixed`.
const FIXED: u32 = 1 << 31;

impl Slot {
    /// `Fixed(choice)`.
    fn exactly(choice: u32) -> Slot {
        Slot(choice | FIXED)
    }

    /// `From(choice)`.
    fn at_least(choice: u32) -> Slot {
        Slot(choice)
    }

    fn is_fixed(self) -> bool {
        self.0 & FIXED != 0
    }

    fn choice(self) -> u32 {
        self.0 & !FIXED
    }
}

/// A set of assignments (see the module documentation).
#[derive(Debug, Clone)]
struct Node(Box<[Slot]>);

/// What the children of one split share: the popped node and its best completion. A child
/// is this node with the conflict's free members before its own fixed to their choices in
/// the completion and its own raised; it is written out in full only when it is popped. A
/// split of a solution queues up to one child per member, most never popped: written out,
/// they were a member-long slot vector each — on a 1,023-breaker tree a third of a busy step
/// (allocation and page faults) and nearly all of its 1.9 GB.
#[derive(Debug)]
struct Split {
    node: Node,
    candidate: Box<[u32]>,
    /// The conflict's members free in `node` (`From` slots), ascending.
    free: Box<[u32]>,
}

/// A frontier node: whole, or a child of a split not written out yet.
#[derive(Debug)]
enum Pending {
    Whole(Node),
    Child {
        split: Rc<Split>,
        /// The member the child raises…
        member: u32,
        /// …to this choice (`From`).
        raised: u32,
    },
}

impl Pending {
    /// Member `p`'s choice in the node's best completion.
    fn choice(&self, p: usize) -> u32 {
        match self {
            Pending::Whole(node) => node.0[p].choice(),
            Pending::Child {
                split,
                member,
                raised,
            } => {
                if p == *member as usize {
                    *raised
                } else {
                    split.candidate[p]
                }
            }
        }
    }

    /// The node written out.
    fn into_node(self) -> Node {
        match self {
            Pending::Whole(node) => node,
            Pending::Child {
                split,
                member,
                raised,
            } => {
                let mut slots = split.node.0.clone();
                for &p in split.free.iter().take_while(|&&p| p < member) {
                    slots[p as usize] = Slot::exactly(split.candidate[p as usize]);
                }
                slots[member as usize] = Slot::at_least(raised);
                Node(slots)
            }
        }
    }
}

/// A node in the frontier with the cost of its best completion, ordered so that the heap's
/// greatest is the first in the search's order (see "Order" in the module documentation).
#[derive(Debug)]
struct Queued {
    /// The cost of the node's best completion when `exact`; otherwise a lower bound on it
    /// (see "Order").
    cost: Cost,
    exact: bool,
    /// One past the last member whose best-completion choice is not its cheapest (0 if none):
    /// most ties between nodes are told apart by it alone, without scanning both completions.
    last: usize,
    node: Pending,
}

impl Queued {
    /// Colexicographic comparison of the two nodes' best completions. Past `last` a completion
    /// is all zeros, so the one whose `last` is greater is the later; at equal `last` the
    /// choices below it decide, compared from the back.
    fn colex(&self, other: &Self) -> Ordering {
        self.last
            .cmp(&other.last)
            .then_with(|| self.colex_below_last(other))
    }

    /// [`Queued::colex`] at equal `last`. Two children (most of the frontier) are compared as
    /// their splits' completions, each with one member changed, slice by slice — siblings
    /// at the changed members alone — rather than member by member through [`Pending`].
    fn colex_below_last(&self, other: &Self) -> Ordering {
        let (
            Pending::Child {
                split: a,
                member: ma,
                raised: ra,
            },
            Pending::Child {
                split: b,
                member: mb,
                raised: rb,
            },
        ) = (&self.node, &other.node)
        else {
            return self.below_last().cmp(other.below_last());
        };
        let last = self.last;
        let (a, b) = (&a.candidate[..last], &b.candidate[..last]);
        let siblings = std::ptr::eq(a, b);
        let (ma, mb) = (*ma as usize, *mb as usize);
        let choice_a = |p: usize| if p == ma { *ra } else { a[p] };
        let choice_b = |p: usize| if p == mb { *rb } else { b[p] };
        // From the back: the bases above the higher changed member, that member, the bases
        // between, the lower one, the bases below (equal bases need no scan).
        let bases = |range: std::ops::Range<usize>| {
            if siblings {
                Ordering::Equal
            } else {
                a[range.clone()].iter().rev().cmp(b[range].iter().rev())
            }
        };
        let (low, high) = (ma.min(mb), ma.max(mb));
        bases(high + 1..last)
            .then_with(|| choice_a(high).cmp(&choice_b(high)))
            .then_with(|| {
                if low == high {
                    return Ordering::Equal;
                }
                bases(low + 1..high).then_with(|| choice_a(low).cmp(&choice_b(low)))
            })
            .then_with(|| bases(0..low))
    }

    /// The best completion's choices below `last`, from the back.
    fn below_last(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.last).rev().map(|p| self.node.choice(p))
    }
}

impl Ord for Queued {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: the cheapest, then colexicographically first, is the greatest.
        other.cost.cmp(&self.cost).then_with(|| other.colex(self))
    }
}

impl PartialOrd for Queued {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Queued {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Queued {}

/// A conflict over this sub-problem: (member position, choice index) pairs, sorted.
type Conflict = Vec<(usize, u32)>;

/// A solution of one sub-problem: a choice index per member, and its cost.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PartialSolution {
    pub(crate) choices: Vec<u32>,
    pub(crate) cost: f64,
}

/// Best-first enumeration of the solutions of one sub-problem.
pub(crate) struct ComponentSearch {
    /// Indices into the OCSP's decisions.
    members: Vec<usize>,
    /// Per member, where its choices lie in the OCSP's list of all choices (first, count):
    /// summing a node's cost reads a member's choice there directly, the innermost loop of
    /// the search (`Ocsp`, "All choices in one list").
    stretches: Vec<(u32, u32)>,
    position: FxHashMap<VarId, usize>,
    frontier: BinaryHeap<Queued>,
    /// Conflicts of two or more pairs.
    conflicts: Vec<Conflict>,
    /// Per member, per choice: refuted on its own (a conflict of one pair). Such choices are
    /// skipped outright ([`ComponentSearch::skip_refuted`]) rather than split off one pop at a
    /// time: most conflicts a breaker tree's observation gives are of this kind.
    refuted: Vec<Vec<bool>>,
    /// How many of the shared store's conflicts this search has read (see [`ConflictStore`]).
    read: usize,
    /// Every choice of every member costs at least zero (true of estimation's −ln p), so a
    /// partial sum bounds every completion of it from below (see "Order").
    nonnegative: bool,
}

impl ComponentSearch {
    /// A search over the decisions `members` of `ocsp`, starting from the node of all
    /// assignments.
    pub(crate) fn new(ocsp: &Ocsp, members: Vec<usize>) -> Self {
        let refuted = vec![Vec::new(); members.len()];
        let nonnegative = members
            .iter()
            .all(|&d| ocsp.choices(d).iter().all(|c| c.cost >= 0.0));
        let position = members
            .iter()
            .enumerate()
            .map(|(p, &d)| (ocsp.decisions()[d].var, p))
            .collect();
        let stretches = members.iter().map(|&d| ocsp.stretch(d)).collect();
        let mut search = ComponentSearch {
            members,
            stretches,
            position,
            frontier: BinaryHeap::new(),
            conflicts: Vec::new(),
            refuted,
            read: 0,
            nonnegative,
        };
        let root = Node(vec![Slot::at_least(0); search.members.len()].into_boxed_slice());
        let cheapest = std::iter::repeat(0);
        if let Some(cost) = search.sum_from(ocsp, 0, 0.0, cheapest) {
            search.frontier.push(Queued {
                cost: Cost(cost),
                exact: true,
                last: 0,
                node: Pending::Whole(root),
            });
        }
        search
    }

    /// The decisions this search assigns.
    pub(crate) fn members(&self) -> &[usize] {
        &self.members
    }

    /// The next solution, cheapest first; `Ok(None)` when there are no more; `Err` when the
    /// budget ran out (the search can be resumed with a new meter). With `shared` (a store for
    /// the OCSP's own assumptions, used only with `use_conflicts`), the search reads the
    /// conflicts other searches learned there and adds its own.
    pub(crate) fn next(
        &mut self,
        ocsp: &Ocsp,
        theory: &mut Theory,
        use_conflicts: bool,
        mut shared: Option<&mut ConflictStore>,
        meter: &mut Meter,
    ) -> Result<Option<PartialSolution>, Cut> {
        loop {
            let Some(front) = self.frontier.peek() else {
                return Ok(None);
            };
            if !front.exact {
                self.cost_front(ocsp);
                continue;
            }
            meter.charge_node()?;
            if let Some(store) = shared.as_deref_mut() {
                self.read_shared(ocsp, store);
            }
            let Some(Queued {
                cost, last, node, ..
            }) = self.frontier.pop()
            else {
                return Ok(None);
            };
            let node = node.into_node();
            let candidate: Vec<u32> = node.0.iter().map(|s| s.choice()).collect();
            if self.takes_refuted(&candidate) {
                self.skip_refuted(ocsp, &node);
                continue;
            }
            if let Some(known) = self.known_conflict(&candidate) {
                let known = known.clone();
                self.split(ocsp, (node, last), &candidate, &known);
                continue;
            }
            meter.stats.consistency_checks += 1;
            let mut assumptions = ocsp.assumptions().to_vec();
            let pairs = candidate.iter().copied().enumerate();
            assumptions.extend(pairs.map(|pair| self.literal(ocsp, pair)));
            match theory.search_conflict(&assumptions) {
                Consistency::Consistent => {
                    let whole: Conflict = candidate.iter().copied().enumerate().collect();
                    self.split(ocsp, (node, last), &candidate, &whole);
                    return Ok(Some(PartialSolution {
                        choices: candidate,
                        cost: cost.0,
                    }));
                }
                Consistency::Conflict(literals) => {
                    let conflict = if use_conflicts {
                        self.conflict_over_members(ocsp, &literals, &candidate)
                    } else {
                        candidate.iter().copied().enumerate().collect()
                    };
                    if conflict.is_empty() {
                        // The per-problem assumptions alone are inconsistent: nothing is feasible.
                        self.frontier.clear();
                        return Ok(None);
                    }
                    self.split(ocsp, (node, last), &candidate, &conflict);
                    if use_conflicts {
                        meter.stats.conflicts += 1;
                        if let Some(store) = shared.as_deref_mut() {
                            // Read up to here at the top of this pass: only this one is new.
                            store.learn(conflict.iter().map(|&pair| self.literal(ocsp, pair)));
                            self.read = store.len();
                        }
                        self.learn(ocsp, conflict);
                    }
                }
            }
        }
    }

    fn known_conflict(&self, candidate: &[u32]) -> Option<&Conflict> {
        self.conflicts
            .iter()
            .find(|k| k.iter().all(|&(p, c)| candidate[p] == c))
    }

    /// Takes in the conflicts the store gained since the last call, each translated into this
    /// search's (member position, choice) pairs; one naming a variable that is not a member, or
    /// a value that is not among its choices, cannot be contained in any candidate here and is
    /// left out.
    fn read_shared(&mut self, ocsp: &Ocsp, store: &ConflictStore) {
        for literals in store.since(self.read) {
            let translated: Option<Conflict> = literals
                .iter()
                .map(|literal| self.pair_of(ocsp, *literal))
                .collect();
            if let Some(mut conflict) = translated {
                conflict.sort_unstable();
                conflict.dedup();
                self.learn(ocsp, conflict);
            }
        }
        self.read = store.len();
    }

    /// Remembers a conflict: a single pair as a refuted choice, a longer one in the list.
    fn learn(&mut self, ocsp: &Ocsp, conflict: Conflict) {
        if let [(p, c)] = conflict[..] {
            let refuted = &mut self.refuted[p];
            if refuted.is_empty() {
                refuted.resize(ocsp.choices(self.members[p]).len(), false);
            }
            refuted[c as usize] = true;
        } else {
            self.conflicts.push(conflict);
        }
    }

    /// Whether an assignment takes a choice refuted on its own.
    fn takes_refuted(&self, choices: &[u32]) -> bool {
        choices
            .iter()
            .zip(&self.refuted)
            .any(|(&c, refuted)| refuted.get(c as usize) == Some(&true))
    }

    /// The first choice of member `p` at or after `i` not refuted on its own (past the last
    /// choice if none is left).
    fn unrefuted_from(&self, p: usize, i: u32) -> u32 {
        let refuted = &self.refuted[p];
        (i..)
            .find(|&j| refuted.get(j as usize) != Some(&true))
            .unwrap_or(i)
    }

    /// Puts `node` back without the choices refuted on its own: each `From` slot moved past
    /// them — the same assignments less infeasible ones, at its new best completion's cost
    /// (never below the old: choices only move to dearer ones). A `Fixed` slot on a refuted
    /// choice, or a slot with no choice left, leaves nothing.
    fn skip_refuted(&mut self, ocsp: &Ocsp, node: &Node) {
        let mut slots = node.0.clone();
        for (p, slot) in slots.iter_mut().enumerate() {
            let choice = slot.choice();
            if !slot.is_fixed() {
                *slot = Slot::at_least(self.unrefuted_from(p, choice));
            } else if self.refuted[p].get(choice as usize) == Some(&true) {
                return;
            }
        }
        let completion = slots.iter().map(|s| s.choice());
        let Some(cost) = self.sum_from(ocsp, 0, 0.0, completion) else {
            return;
        };
        let last = slots
            .iter()
            .rposition(|s| s.choice() > 0)
            .map_or(0, |p| p + 1);
        self.frontier.push(Queued {
            cost: Cost(cost),
            exact: true,
            last,
            node: Pending::Whole(Node(slots)),
        });
    }

    /// The (member position, choice) pair stating `literal`, if it is one of this search's.
    fn pair_of(&self, ocsp: &Ocsp, literal: Literal) -> Option<(usize, u32)> {
        let Literal::Is(var, value) = literal else {
            return None;
        };
        let &p = self.position.get(&var)?;
        let choices = ocsp.choices(self.members[p]);
        let c = choices.iter().position(|c| c.value == value)?;
        Some((p, c as u32))
    }

    /// The literal stating that member `p` takes its choice `c`.
    fn literal(&self, ocsp: &Ocsp, (p, c): (usize, u32)) -> Literal {
        let d = self.members[p];
        Literal::Is(ocsp.decisions()[d].var, ocsp.choices(d)[c as usize].value)
    }

    /// The theory's conflict restricted to the candidate's own assignments. The per-problem
    /// assumptions hold in every candidate, so they can be dropped — including an assumption
    /// about a decision variable, which must not be read as a choice of the candidate.
    fn conflict_over_members(
        &self,
        ocsp: &Ocsp,
        literals: &[Literal],
        candidate: &[u32],
    ) -> Conflict {
        let mut conflict: Conflict = literals
            .iter()
            .filter_map(|literal| {
                let (p, c) = self.pair_of(ocsp, *literal)?;
                (candidate[p] == c).then_some((p, c))
            })
            .collect();
        conflict.sort_unstable();
        conflict.dedup();
        conflict
    }

    /// Replaces `node` (whose best completion is `candidate`, and [`Queued::last`] `last`) by
    /// the children that hold its assignments not containing `conflict` (systematic expansion
    /// over the constituent kernels; see the module documentation), less choices refuted on
    /// their own. Child `j`'s best completion is `candidate` with the `j`-th free member of the
    /// conflict raised (to its next choice not refuted on its own), so its cost is
    /// the candidate's members before that one, summed once for all children, then the rest:
    /// the same additions in the same order as a sum over all members, so the same bits. With
    /// non-negative costs only the part through the raised member is summed here, a lower
    /// bound ([`ComponentSearch::cost_front`] finishes it if the child reaches the front).
    fn split(
        &mut self,
        ocsp: &Ocsp,
        (node, last): (Node, usize),
        candidate: &[u32],
        conflict: &Conflict,
    ) {
        let free = conflict
            .iter()
            .filter(|&&(p, _)| !node.0[p].is_fixed())
            .map(|&(p, _)| p as u32)
            .collect();
        let split = Rc::new(Split {
            node,
            candidate: candidate.into(),
            free,
        });
        let (mut at, mut before) = (0, 0.0);
        for &member in split.free.iter() {
            let p = member as usize;
            // Every choice of the candidate exists: it was a node's best completion.
            before = self
                .sum_from(ocsp, at, before, candidate[at..p].iter().copied())
                .unwrap_or(f64::INFINITY);
            at = p;
            let raised = self.unrefuted_from(p, candidate[p] + 1);
            // A member with no choice left makes the child empty: it is not queued.
            let Some(choice) = self.choice(ocsp, p, raised) else {
                continue;
            };
            let (cost, exact) = if self.nonnegative {
                // The child's own partial sum through its raised member: the rest only
                // adds non-negative terms, which never lowers a floating-point sum.
                (before + choice.cost, false)
            } else {
                let rest = std::iter::once(raised).chain(candidate[p + 1..].iter().copied());
                let cost = self.sum_from(ocsp, p, before, rest);
                (cost.unwrap_or(f64::INFINITY), true)
            };
            self.frontier.push(Queued {
                cost: Cost(cost),
                exact,
                last: last.max(p + 1),
                node: Pending::Child {
                    split: Rc::clone(&split),
                    member,
                    raised,
                },
            });
        }
    }

    /// Replaces the front node, queued at a lower bound, by itself at its exact cost: its best
    /// completion's costs summed in member order from 0.0, the sum every node's cost is. Only
    /// a split's children are queued at a lower bound (the root and re-queued nodes are
    /// exact).
    fn cost_front(&mut self, ocsp: &Ocsp) {
        // Costed in place: the exact cost is at or above the bound it was queued at, so the
        // node only sinks, which `PeekMut` does on drop with one sift down instead of a pop
        // and a push. Frontier nodes are disjoint, so their best completions differ and the
        // order is total: the same nodes come out in the same order whatever the heap's shape.
        let mut frontier = std::mem::take(&mut self.frontier);
        if let Some(mut front) = frontier.peek_mut() {
            // Every slot has its choice: empty children are never queued.
            let cost = match &front.node {
                // Queued at its partial sum through the member it raises (`split`): the rest
                // continues that sum — the same additions in the same order as from 0.0.
                Pending::Child { split, member, .. } => {
                    let rest = &split.candidate[*member as usize + 1..];
                    self.sum_from(
                        ocsp,
                        *member as usize + 1,
                        front.cost.0,
                        rest.iter().copied(),
                    )
                }
                Pending::Whole(node) => {
                    self.sum_from(ocsp, 0, 0.0, node.0.iter().map(|s| s.choice()))
                }
            };
            front.cost = Cost(cost.unwrap_or(f64::INFINITY));
            front.exact = true;
        }
        self.frontier = frontier;
    }

    /// `start` plus the costs of `choices` (indices) of the members from `from` on, added in
    /// member order; `None` if a member has no such choice.
    fn sum_from(
        &self,
        ocsp: &Ocsp,
        from: usize,
        start: f64,
        choices: impl Iterator<Item = u32>,
    ) -> Option<f64> {
        let mut cost = start;
        for (&(first, count), c) in self.stretches[from..].iter().zip(choices) {
            if c >= count {
                return None;
            }
            cost += ocsp.all_choices().get((first + c) as usize)?.cost;
        }
        Some(cost)
    }

    /// Member `p`'s `c`-th cheapest choice, if it has one.
    fn choice<'o>(&self, ocsp: &'o Ocsp, p: usize, c: u32) -> Option<&'o Choice> {
        let (first, count) = self.stretches[p];
        if c < count {
            ocsp.all_choices().get((first + c) as usize)
        } else {
            None
        }
    }
}
