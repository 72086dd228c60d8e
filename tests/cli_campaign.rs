//! `kairos campaign`: seeded Monte Carlo runs whose records do not depend on the
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

/// The campaign's acceptance: same seed ⇒ byte-identical results, across `--jobs` and shard splits.
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

/// Bad arguments are bad input: a shard outside its count, a scripted scenario, a shard given
/// twice to a merge.
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
    assert!(stderr.contains("shard 0/1 is given twice"), "{stderr}");
}

/// The records of `dir`'s `runs.jsonl`, or of a recorded file, as JSON values without the
/// machine-dependent `timing`, and without each fault's `revealed_after`, which records made
/// before it existed lack (it is a judgement of the draws, not a draw).
fn values(path: &str) -> Vec<Value> {
    let text = std::fs::read_to_string(path).expect("the records are there");
    text.lines()
        .map(|line| {
            let mut record: Value = serde_json::from_str(line).expect("a JSON record");
            let object = record.as_object_mut().expect("an object");
            object.remove("timing");
            if let Some(Value::Array(faults)) = object.get_mut("faults") {
                for fault in faults {
                    if let Some(fault) = fault.as_object_mut() {
                        fault.remove("revealed_after");
                    }
                }
            }
            record
        })
        .collect()
}

/// The model plant's cache (docs/design/campaigns.md; BENCHMARKS.md "Campaigns"): the model-driven
/// plant asks its theory once per (modes, command) and keeps the answers, which must change no
/// draw. The records of two campaigns made before the cache existed (`tests/records/`, commit
/// 57d509f) are reproduced exactly: the propulsion campaign (three runs with a drawn fault — a
/// stuck valve, a resettable PDE — whose fault modes leave observables open) and the noisy one with
/// a forced fault. One line of the propulsion record was remade when the executive learned to act
/// under diagnostic ambiguity: run 69 draws the same resettable PDE at 10 s, and now recovers (a
/// retried reset and `open1`) instead of failing; its draws are unchanged.
#[test]
fn records_are_those_of_the_plant_before_its_cache() {
    let propulsion = out_dir("recorded-propulsion");
    let (code, stdout, stderr) = kairos(&[
        "campaign",
        "scenarios/propulsion/campaign.ron",
        "--runs",
        "100",
        "--seed",
        "7",
        "--out",
        &propulsion,
    ]);
    assert_eq!(code, 1, "two runs fail\n{stdout}\n{stderr}");
    assert_eq!(
        values(&format!("{propulsion}/runs.jsonl")),
        values("tests/records/propulsion_campaign_seed7.jsonl")
    );
    let noisy = campaign("recorded-noisy", "8", &[]);
    assert_eq!(
        values(&format!("{noisy}/runs.jsonl")),
        values("tests/records/campaign_noisy_seed42.jsonl")
    );
}

/// `--fault` forces a fault in every run of a campaign (a drawn-fault record marked
/// forced, at the first cycle at or after its time), `--noise` sets the sensor noise, the
/// summary says how to replay a run with them, and `kairos run --seed` with the same options
/// replays it: the same verdict, and the same fault in the run's log.
#[test]
fn forced_faults_and_noise_from_the_command_line() {
    let options = [
        "--fault",
        "valve2 = stuck-closed @ 19.5 s",
        "--fault",
        "PDE = resettable @ 40",
        "--noise",
        "0.05",
    ];
    let dir = out_dir("options");
    let mut args = vec![
        "campaign",
        "scenarios/propulsion/campaign.ron",
        "--runs",
        "3",
        "--seed",
        "5",
        "--out",
        &dir,
    ];
    args.extend_from_slice(&options);
    let (code, stdout, stderr) = kairos(&args);
    assert!(code == 0 || code == 1, "{stdout}\n{stderr}");
    assert!(
        stdout.contains(
            "replay a run: kairos run scenarios/propulsion/campaign.ron --fault \
             \"valve2 = stuck-closed @ 19.5 s\" --fault \"PDE = resettable @ 40\" --noise 0.05 \
             --seed SEED"
        ),
        "{stdout}"
    );
    for record in values(&format!("{dir}/runs.jsonl")) {
        let faults = record["faults"].as_array().expect("faults");
        let forced = |name: &str, time: f64| {
            faults
                .iter()
                .any(|f| f["fault"] == name && f["time"] == time && f["forced"] == true)
        };
        assert!(forced("valve2 = stuck-closed", 20.0), "{record}");
        assert!(forced("PDE = resettable", 40.0), "{record}");
        let seed = record["seed"].as_u64().expect("a seed").to_string();
        let mut replay = vec![
            "run",
            "--quiet",
            "scenarios/propulsion/campaign.ron",
            "--seed",
            &seed,
        ];
        replay.extend_from_slice(&options);
        let (code, stdout, _) = kairos(&replay);
        assert_eq!(code == 0, record["verdict"] == "pass", "{record}\n{stdout}");
    }
}

/// Bad `--fault` and `--noise` options are bad input (exit 2) that name the option, its text,
/// what is wrong and what was expected: an unknown component or mode (with the closest name),
/// a nominal mode, a time that is not one, a time after the scenario's end, a noise that is not a probability,
/// and a scripted scenario, which has no model to force.
#[test]
fn bad_fault_and_noise_options_are_clear_errors() {
    let mut report = String::new();
    for option in [
        ["--fault", "valve9 = stuck-closed @ 17 s"],
        ["--fault", "valve1 = stuck-clsoed @ 17 s"],
        ["--fault", "valve1 = open @ 17 s"],
        ["--fault", "valve1 = stuck-closed @ soon"],
        ["--fault", "valve1 = stuck-closed"],
        ["--fault", "valve1 = stuck-closed @ 17103 s"],
        ["--noise", "1.5"],
    ] {
        for command in ["run", "campaign"] {
            let mut args = vec![command, "scenarios/propulsion/campaign.ron"];
            if command == "campaign" {
                args.extend(["--runs", "1"]);
            }
            args.extend(option);
            let (code, _, stderr) = kairos(&args);
            assert_eq!(code, 2, "{args:?}: {stderr}");
            if command == "run" {
                let [name, value] = option;
                report.push_str(&format!(
                    "$ kairos run scenarios/propulsion/campaign.ron {name} \"{value}\"\n{stderr}\n"
                ));
            }
        }
    }
    let (code, _, stderr) = kairos(&[
        "run",
        "scenarios/propulsion/nominal.ron",
        "--fault",
        "valve1 = stuck-closed @ 17 s",
    ]);
    assert_eq!(code, 2);
    report.push_str(&stderr);
    insta::assert_snapshot!(report);
}
