//! `kairos campaign` (issue 18): seeded Monte Carlo runs whose records do not depend on the
//! number of threads or on the shard split, `campaign merge`, and `kairos run --seed` replaying
//! a campaign's run.

#[path = "support/cli.rs"]
mod cli;

use cli::kairos;
use serde_json::Value;

const SCENARIO: &str = "tests/scenarios/campaign_noisy.ron";

/// A fresh output directory for one test.
fn out_dir(name: &str) -> String {
    let dir = std::env::temp_dir().join(format!("kairos-campaign-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir.display().to_string()
}

/// `runs.jsonl` of `dir` with the machine-dependent `timing` of every record removed.
fn records(dir: &str) -> Vec<String> {
    let text = std::fs::read_to_string(format!("{dir}/runs.jsonl")).expect("runs.jsonl written");
    text.lines()
        .map(|line| {
            let mut record: Value = serde_json::from_str(line).expect("a JSON record");
            record
                .as_object_mut()
                .expect("an object")
                .remove("timing")
                .expect("timing is there");
            record.to_string()
        })
        .collect()
}

fn campaign(name: &str, runs: &str, extra: &[&str]) -> String {
    let dir = out_dir(name);
    let mut args = vec![
        "campaign", SCENARIO, "--runs", runs, "--seed", "42", "--out", &dir,
    ];
    args.extend_from_slice(extra);
    let (code, stdout, stderr) = kairos(&args);
    assert!(code == 0 || code == 1, "{stdout}\n{stderr}");
    assert!(stdout.contains("Wilson interval"), "{stdout}");
    dir
}

/// Issue 18 acceptance: same seed ⇒ byte-identical results, across `--jobs` and shard splits.
#[test]
fn records_do_not_depend_on_jobs_or_shards() {
    let one = records(&campaign("jobs1", "8", &["--jobs", "1"]));
    assert_eq!(one.len(), 8);
    let two = records(&campaign("jobs2", "8", &["--jobs", "2"]));
    assert_eq!(one, two, "--jobs 1 and --jobs 2");
    let first = campaign("shard0", "8", &["--shard", "0/2", "--jobs", "1"]);
    let second = campaign("shard1", "8", &["--shard", "1/2", "--jobs", "2"]);
    assert_eq!(records(&first).len(), 4);
    let merged = out_dir("merged");
    let (code, stdout, stderr) = kairos(&["campaign", "merge", &first, &second, "--out", &merged]);
    assert!(code == 0 || code == 1, "{stdout}\n{stderr}");
    assert!(stdout.contains("runs: 8"), "{stdout}");
    assert_eq!(one, records(&merged), "shards 0/2 and 1/2 merged");
    let seeds: std::collections::BTreeSet<&str> = one.iter().map(String::as_str).collect();
    assert_eq!(seeds.len(), 8, "runs differ from one another");
}

/// A record's seed replays its run: `kairos run --seed` reaches the same verdict, and the forced
/// fault is in every record at its time.
#[test]
fn a_records_seed_replays_the_run() {
    let dir = campaign("replay", "2", &[]);
    let text = std::fs::read_to_string(format!("{dir}/runs.jsonl")).expect("written");
    for line in text.lines() {
        let record: Value = serde_json::from_str(line).expect("a JSON record");
        let forced = record["faults"]
            .as_array()
            .expect("faults")
            .iter()
            .any(|f| f["fault"] == "valve1 = stuck-closed" && f["time"] == 25.0);
        assert!(forced, "{record}");
        let seed = record["seed"].as_u64().expect("a seed").to_string();
        let (code, stdout, _) = kairos(&["run", "--quiet", SCENARIO, "--seed", &seed]);
        let passed = record["verdict"] == "pass";
        assert_eq!(code == 0, passed, "{record}\n{stdout}");
    }
}

/// Bad arguments are bad input: a shard outside its count, a scripted scenario, a run in two
/// shards.
#[test]
fn bad_campaigns_are_bad_input() {
    let (code, _, stderr) = kairos(&["campaign", SCENARIO, "--runs", "2", "--shard", "2/2"]);
    assert_eq!(code, 2, "{stderr}");
    let (code, _, stderr) = kairos(&[
        "campaign",
        "scenarios/propulsion/nominal.ron",
        "--runs",
        "2",
    ]);
    assert_eq!(code, 2);
    assert!(stderr.contains("needs a model-driven plant"), "{stderr}");
    let dir = campaign("twice", "2", &[]);
    let (code, _, stderr) = kairos(&["campaign", "merge", &dir, &dir]);
    assert_eq!(code, 2);
    assert!(stderr.contains("is in two shards"), "{stderr}");
}
