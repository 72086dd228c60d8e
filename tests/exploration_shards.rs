//! A search split into shards (`kairos explore --shard i/n`, `exploration::Shard`) and merged
//! (`exploration::merge`) finds what one process finds — states, paths, failing paths,
//! coverage and the shortest counterexample of each finding — on every shipped exploration
//! scenario (DESIGN.md §16; the module documentation of `exploration`, "Parallel and
//! deterministic"). Each shard's result goes through JSON, as `--out` writes it and
//! `explore merge` reads it.

use std::path::Path;

use kairos::exploration::{Exploration, ExploreOptions, Shard, explore, merge};
use kairos::simulation::{self, Scenario};

fn scenario(path: &str) -> Scenario {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    simulation::load(&root.join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The shipped scenarios that `kairos explore` is for, with the faults a path they are run at.
const SCENARIOS: [(&str, usize); 6] = [
    ("tests/scenarios/explore_flameout.ron", 2),
    ("tests/scenarios/explore_heat_window.ron", 1),
    ("tests/scenarios/explore_power_on_race.ron", 1),
    ("tests/scenarios/explore_edl_small.ron", 1),
    ("scenarios/mars_edl/explore_faults.ron", 1),
    ("tests/scenarios/explore_flameout.ron", 0),
];

/// Everything but the wall time.
fn verdict(e: &Exploration) -> impl PartialEq + std::fmt::Debug + '_ {
    (
        e.states,
        e.paths,
        e.longest,
        &e.counterexamples,
        &e.failing_paths,
        e.cut_at,
        e.limit,
    )
}

fn explored(scenario: &Scenario, faults: usize, shard: Shard, jobs: usize) -> Exploration {
    let options = ExploreOptions {
        faults,
        jobs,
        shard,
        ..ExploreOptions::default()
    };
    explore(scenario, &options, &|_| {}).expect("explores")
}

#[test]
fn merged_shards_are_the_single_search_on_every_shipped_scenario() {
    for (path, faults) in SCENARIOS {
        let scenario = scenario(path);
        let whole = explored(&scenario, faults, Shard::WHOLE, 1);
        for count in [2, 3] {
            // The shards use one worker each, or two: the split does not depend on it.
            let jobs = if count == 2 { 2 } else { 1 };
            let shards: Vec<Exploration> = (0..count)
                .map(|index| {
                    let part = explored(&scenario, faults, Shard { index, count }, jobs);
                    let json = serde_json::to_string(&part).expect("encodes");
                    serde_json::from_str(&json).expect("decodes")
                })
                .collect();
            let merged = merge(shards);
            assert_eq!(
                verdict(&merged),
                verdict(&whole),
                "{path}, {faults} faults, {count} shards"
            );
        }
        assert!(
            whole.cut_at.is_none(),
            "{path}: the whole search covers every path"
        );
    }
}

/// A shard that does not exist is refused, not explored as some other part.
#[test]
fn a_shard_outside_its_count_is_refused() {
    let scenario = scenario("tests/scenarios/explore_flameout.ron");
    let options = ExploreOptions {
        shard: Shard { index: 2, count: 2 },
        ..ExploreOptions::default()
    };
    let error = explore(&scenario, &options, &|_| {}).expect_err("no shard 2/2");
    assert!(
        error.to_string().contains("shard 2/2 does not exist"),
        "{error}"
    );
}
