//! Property tests of the goal network's core (DESIGN.md §15.1–15.2;
//! mds-goal-networks.md §1.4–1.5, §3.3 "unit tests of every constraint's merge and subset").
//!
//! - STN propagation (petgraph's Bellman–Ford, full and incremental) against a brute-force
//!   Floyd–Warshall on the same distance graph: the consistency verdict and every window; a
//!   reported negative cycle is inconsistent on its own.
//! - The constraint-set algebra: merge commutative, associative, idempotent, `merge(a, b) ⊆ a`,
//!   `Unconstrained` the identity, `a ⊆ b ⇔ merge(a, b) = a`.

#[path = "support/seeded.rs"]
mod seeded;

use kairos::goalnet::{ConstraintSet, Provenance, Stn, TemporalConstraint, TimePointId, Window};
use kairos::logic::ValueId;
use proptest::prelude::*;

/// A constraint drawn over points `0..=points` (0 is the origin), integer bounds so that sums
/// are exact; `None` is an open side.
#[derive(Debug, Clone)]
struct Drawn {
    from: u32,
    to: u32,
    min: Option<i32>,
    max: Option<i32>,
}

fn drawn(points: u32) -> impl Strategy<Value = Drawn> {
    (
        0..=points,
        0..=points,
        proptest::option::weighted(0.8, -20..30i32),
        proptest::option::weighted(0.7, 0..40i32),
    )
        .prop_map(|(from, to, min, width)| {
            // max = min + width keeps most draws well-formed; an open min takes width as max.
            let max = width.map(|w| min.map_or(w, |m| m + w));
            Drawn { from, to, min, max }
        })
}

/// A network of 1–7 points with fewer than `constraints` drawn constraints.
fn network(constraints: usize) -> impl Strategy<Value = (u32, Vec<Drawn>)> {
    (1..8u32).prop_flat_map(move |n| (Just(n), proptest::collection::vec(drawn(n), 0..constraints)))
}

fn constraint(d: &Drawn) -> TemporalConstraint {
    TemporalConstraint::new(
        TimePointId(d.from),
        TimePointId(d.to),
        d.min.map_or(f64::NEG_INFINITY, f64::from),
        d.max.map_or(f64::INFINITY, f64::from),
        Provenance::Written(0..0),
    )
}

fn stn(points: u32, constraints: &[Drawn]) -> Stn {
    let mut stn = Stn::new();
    for _ in 0..points {
        stn.add_point();
    }
    for d in constraints {
        stn.add_constraint(constraint(d))
            .expect("well-formed bounds");
    }
    stn
}

/// Floyd–Warshall on the distance graph, written out: `None` on a negative cycle, else every
/// point's window `[−D(p, Z), D(Z, p)]`.
fn brute_force(points: u32, constraints: &[Drawn]) -> Option<Vec<Window>> {
    let n = points as usize + 1;
    let mut d = vec![vec![f64::INFINITY; n]; n];
    for (i, row) in d.iter_mut().enumerate() {
        row[i] = 0.0;
    }
    let mut edge = |a: usize, b: usize, w: f64| d[a][b] = d[a][b].min(w);
    for p in 1..n {
        edge(p, 0, 0.0); // every point at or after the origin
    }
    for c in constraints {
        let (a, b) = (c.from as usize, c.to as usize);
        if let Some(max) = c.max {
            edge(a, b, f64::from(max));
        }
        if let Some(min) = c.min {
            edge(b, a, -f64::from(min));
        }
    }
    for k in 0..n {
        for i in 0..n {
            for j in 0..n {
                let through = d[i][k] + d[k][j];
                if through < d[i][j] {
                    d[i][j] = through;
                }
            }
        }
    }
    if (0..n).any(|i| d[i][i] < 0.0) {
        return None;
    }
    Some(
        (0..n)
            .map(|p| Window {
                lb: -d[p][0],
                ub: d[0][p],
            })
            .collect(),
    )
}

fn windows(stn: &Stn) -> Vec<Window> {
    (0..stn.point_count() as u32)
        .map(|p| stn.window(TimePointId(p)).expect("propagated"))
        .collect()
}

fn well_formed(constraints: &[Drawn]) -> Vec<Drawn> {
    constraints
        .iter()
        .filter(|d| constraint(d).bounds_are_valid())
        .cloned()
        .collect()
}

proptest! {
    #![proptest_config(seeded::config(512))]

    /// Full propagation agrees with Floyd–Warshall: same verdict, same windows (§1.5).
    #[test]
    fn propagation_matches_floyd_warshall((points, drawn) in network(14)) {
        let drawn = well_formed(&drawn);
        let mut stn = stn(points, &drawn);
        let result = stn.propagate();
        match brute_force(points, &drawn) {
            Some(expected) => {
                prop_assert!(result.is_ok(), "consistent network reported {result:?}");
                prop_assert_eq!(windows(&stn), expected);
            }
            None => {
                let cycle = result.expect_err("inconsistent network accepted").cycle;
                prop_assert!(!cycle.is_empty());
                // The named constraints are inconsistent on their own.
                let named: Vec<Drawn> = cycle
                    .iter()
                    .filter_map(|id| {
                        let c = stn.constraint(*id);
                        let written = matches!(c.provenance, Provenance::Written(_));
                        written.then(|| {
                            drawn[id.index() - points as usize].clone()
                        })
                    })
                    .collect();
                prop_assert!(brute_force(points, &named).is_none(), "cycle {cycle:?} is consistent");
            }
        }
    }

    /// Adding constraints one at a time and re-propagating incrementally gives the windows of a
    /// full propagation, and fails at the first constraint that makes the network inconsistent.
    #[test]
    fn incremental_propagation_matches_full((points, drawn) in network(14)) {
        let drawn = well_formed(&drawn);
        let mut incremental = stn(points, &[]);
        prop_assert!(incremental.propagate().is_ok());
        for (i, d) in drawn.iter().enumerate() {
            incremental.add_constraint(constraint(d)).expect("well-formed");
            let result = incremental.propagate();
            match brute_force(points, &drawn[..=i]) {
                Some(expected) => {
                    prop_assert!(result.is_ok());
                    prop_assert_eq!(windows(&incremental), expected);
                }
                None => {
                    prop_assert!(result.is_err());
                    break;
                }
            }
        }
    }

    /// Grounding a point anywhere in its window keeps the network consistent, fixes the point's
    /// window to that time, and gives the windows of a full propagation (AG §1.2.7 d).
    #[test]
    fn grounding_in_the_window_is_consistent(
        (points, drawn) in network(6),
        pick in 0..8u32,
        fraction in 0.0..=1.0f64,
    ) {
        let drawn = well_formed(&drawn);
        let mut stn = stn(points, &drawn);
        if stn.propagate().is_err() {
            return Ok(()); // the other properties cover inconsistent networks
        }
        let point = TimePointId(1 + pick % points);
        let window = stn.window(point).expect("propagated");
        let time = (window.lb + fraction * (window.ub.min(window.lb + 100.0) - window.lb)).round();
        prop_assume!(time >= window.lb && time <= window.ub);
        prop_assert!(stn.ground(point, time).is_ok());
        prop_assert_eq!(stn.window(point), Some(Window { lb: time, ub: time }));
        let mut grounded = drawn.clone();
        grounded.push(Drawn { from: 0, to: point.0, min: Some(time as i32), max: Some(time as i32) });
        prop_assert_eq!(Some(windows(&stn)), brute_force(points, &grounded));
    }
}

/// A constraint set over a domain of `domain` values.
fn constraint_set(domain: usize) -> impl Strategy<Value = ConstraintSet> {
    (
        proptest::collection::vec(any::<bool>(), domain),
        any::<bool>(),
        proptest::collection::vec(
            prop_oneof![Just(0.0), Just(0.3), Just(0.5), Just(0.9)],
            domain,
        ),
        any::<bool>(),
    )
        .prop_map(move |(admitted, known, beliefs, unconstrained)| {
            if unconstrained {
                return ConstraintSet::unconstrained(domain);
            }
            let mut set = ConstraintSet::control(domain, |v| admitted[v.index()]);
            if known {
                set = set.with_known();
            }
            for (i, p) in beliefs.into_iter().enumerate() {
                set = set.with_belief(ValueId(i as u32), p);
            }
            set
        })
}

fn three_sets() -> impl Strategy<Value = (ConstraintSet, ConstraintSet, ConstraintSet)> {
    (1..6usize).prop_flat_map(|n| (constraint_set(n), constraint_set(n), constraint_set(n)))
}

proptest! {
    #![proptest_config(seeded::config(512))]

    /// Merge is commutative, associative and idempotent (AG §3.4 `mergeWith`).
    #[test]
    fn merge_is_a_semilattice((a, b, c) in three_sets()) {
        prop_assert_eq!(a.merge(&b), b.merge(&a));
        prop_assert_eq!(a.merge(&b).merge(&c), a.merge(&b.merge(&c)));
        prop_assert_eq!(a.merge(&a), a.clone());
    }

    /// `merge(a, b) ⊆ a` and `⊆ b`; `Unconstrained` is the identity and the top.
    #[test]
    fn merge_narrows_and_unconstrained_is_identity((a, b, _c) in three_sets()) {
        let merged = a.merge(&b);
        prop_assert!(merged.is_subset(&a));
        prop_assert!(merged.is_subset(&b));
        let all = ConstraintSet::unconstrained(a.domain());
        prop_assert_eq!(a.merge(&all), a.clone());
        prop_assert_eq!(all.merge(&a), a.clone());
        prop_assert!(a.is_subset(&all));
    }

    /// Subset is the order of merge: `a ⊆ b ⇔ merge(a, b) = a`; and a partial order.
    #[test]
    fn subset_is_the_order_of_merge((a, b, c) in three_sets()) {
        prop_assert_eq!(a.is_subset(&b), a.merge(&b) == a);
        prop_assert!(a.is_subset(&a));
        if a.is_subset(&b) && b.is_subset(&a) {
            prop_assert_eq!(&a, &b);
        }
        if a.is_subset(&b) && b.is_subset(&c) {
            prop_assert!(a.is_subset(&c));
        }
    }
}

/// A negative cycle is reported with the constraints that make it (DESIGN.md §15.1): here
/// `a → b ∈ [10, 20]` and `b → a ∈ [0, +∞)` (so `b − a ≤ 0`).
#[test]
fn a_negative_cycle_names_its_constraints() {
    let mut stn = Stn::new();
    let a = stn.add_point();
    let b = stn.add_point();
    let first = stn
        .add_constraint(TemporalConstraint::new(
            a,
            b,
            10.0,
            20.0,
            Provenance::Written(5..9),
        ))
        .unwrap();
    let second = stn
        .add_constraint(TemporalConstraint::before(
            b,
            a,
            Provenance::Written(12..17),
        ))
        .unwrap();
    let cycle = stn.propagate().unwrap_err().cycle;
    let mut sorted = cycle.clone();
    sorted.sort();
    assert_eq!(sorted, vec![first, second], "{cycle:?}");
    // After an inconsistency the windows are gone until the network is fixed.
    assert_eq!(stn.window(a), None);
}

/// Grounding a point outside its window is a temporal inconsistency naming the grounding.
#[test]
fn grounding_outside_the_window_is_inconsistent() {
    let mut stn = Stn::new();
    let a = stn.add_point();
    stn.add_constraint(TemporalConstraint::new(
        TimePointId::ORIGIN,
        a,
        5.0,
        8.0,
        Provenance::Written(0..1),
    ))
    .unwrap();
    stn.propagate().unwrap();
    assert_eq!(stn.window(a), Some(Window { lb: 5.0, ub: 8.0 }));
    let error = stn.ground(a, 9.0).unwrap_err();
    let kairos::goalnet::GroundError::Inconsistent(inconsistency) = error else {
        panic!("{error:?}");
    };
    let provenances: Vec<_> = inconsistency
        .cycle
        .iter()
        .map(|c| stn.constraint(*c).provenance.clone())
        .collect();
    assert!(provenances.contains(&Provenance::Fired), "{provenances:?}");
}
