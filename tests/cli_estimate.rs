//! `kairos estimate`: replays a log and prints the top estimates per cycle,
//! with TimedME or the exact update, as text or JSON lines; a bad log exits 2 with located errors.

#[path = "support/cli.rs"]
mod cli;

use cli::kairos;

#[path = "support/l2_breakers.rs"]
mod l2_breakers;

const PLANT: &str = "models/driver_valve.ron";
const LOG: &str = "tests/logs/driver_valve_stuck.jsonl";

/// The driver is turned on and the valve commanded open, but no flow comes out: the valve is
/// stuck closed (most likely) or the driver stopped relaying (Table 6.1's resettable).
#[test]
fn timed_me_diagnoses_the_valve_and_keeps_the_driver_in_view() {
    let (code, stdout, stderr) = kairos(&["estimate", "--plant", PLANT, "--log", LOG]);
    assert_eq!(code, 0, "{stderr}");
    let last_cycle = stdout.rsplit("t = ").next().unwrap_or_default();
    let mut estimates = last_cycle.lines().skip(1);
    assert!(
        estimates
            .next()
            .unwrap_or_default()
            .ends_with("driver = on, valve = stuck-closed"),
        "{stdout}"
    );
    assert!(
        estimates
            .next()
            .unwrap_or_default()
            .ends_with("driver = resettable, valve = closed"),
        "{stdout}"
    );
    insta::assert_snapshot!(stdout);
}

#[test]
fn the_exact_update_agrees_on_the_top_estimates() {
    let (code, exact, _) = kairos(&[
        "estimate", "--plant", PLANT, "--log", LOG, "--exact", "--top", "2",
    ]);
    assert_eq!(code, 0);
    let (_, timed, _) = kairos(&["estimate", "--plant", PLANT, "--log", LOG, "--top", "2"]);
    let modes = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| l.starts_with("    "))
            .map(|l| l.split("  ").last().unwrap_or_default().to_string())
            .collect()
    };
    assert_eq!(modes(&exact), modes(&timed));
    insta::assert_snapshot!(exact);
}

#[test]
fn json_lines_carry_estimates_events_and_commands() {
    let (code, stdout, _) = kairos(&[
        "estimate", "--plant", PLANT, "--log", LOG, "--json", "--kappa", "5",
    ]);
    assert_eq!(code, 0);
    let cycles: Vec<serde_json::Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect();
    assert_eq!(cycles.len(), 5);
    assert_eq!(cycles[0]["commands"]["driver.dcmd_in"], "on");
    assert_eq!(cycles[0]["estimates"][0]["modes"]["driver"], "off");
    assert_eq!(cycles[4]["estimates"][0]["modes"]["valve"], "stuck-closed");
    assert!(
        cycles
            .iter()
            .all(|c| c["system_states"].as_u64().unwrap_or(99) <= 5)
    );
}

#[test]
fn a_bad_log_exits_2_with_every_error_located() {
    let (code, stdout, stderr) = kairos(&[
        "estimate",
        "--plant",
        PLANT,
        "--log",
        "tests/logs/bad_log.jsonl",
    ]);
    assert_eq!(code, 2, "{stdout}");
    for expected in [
        "bad_log.jsonl:3:33",
        "`valve.flow` is not an observable of the plant",
        "did you mean `valve.flow_in`?",
        "`full` is not a value of `valve.flow_out`",
        "`valve.vcmd_in` is not a control of the plant",
        "malformed log line",
        "time 1.5 s comes after 2 s on line 5",
    ] {
        assert!(
            stderr.contains(expected),
            "missing `{expected}` in\n{stderr}"
        );
    }
    insta::assert_snapshot!(stderr);
}

/// The history window is the user's to set (src/estimation/timed_me.rs, "When the window is
/// re-run"): `--history N` and `--rerun doubt|surprise` are named in the title when they differ
/// from the defaults; a policy that does not exist, a window past the most allowed, or either
/// with the exact update (which has no window) is refused with what was expected.
#[test]
fn the_history_window_is_a_choice_and_bad_choices_are_refused() {
    let base = ["estimate", "--plant", PLANT, "--log", LOG];
    let (code, stdout, stderr) = kairos(&[&base[..], &["--rerun", "surprise"]].concat());
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("TimedME, κ = 10, re-run on surprise"),
        "{stdout}"
    );
    let (code, stdout, stderr) = kairos(&[&base[..], &["--history", "0"]].concat());
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("TimedME, κ = 10, history 0,"), "{stdout}");
    let mut refusals = Vec::new();
    for bad in [
        &["--rerun", "never"][..],
        &["--history=-1"],
        &["--history", "10001"],
        &["--exact", "--rerun", "surprise"],
    ] {
        let (code, stdout, stderr) = kairos(&[&base[..], bad].concat());
        assert_eq!(code, 2, "{bad:?}: {stdout}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        refusals.push(format!("$ {}\n{stderr}", bad.join(" ")));
    }
    insta::assert_snapshot!(refusals.join("\n"));
}

/// By default `kairos estimate` prints the cycles where something changed and
/// says how many it left out; `--full` prints every cycle.
#[test]
fn estimate_prints_changes_unless_full() {
    let args = [
        "estimate",
        "--plant",
        "models/mars_lander.ron",
        "--log",
        "tests/logs/mars_lander_first_minutes.jsonl",
    ];
    let (code, changes, stderr) = kairos(&args);
    assert_eq!(code, 0, "{stderr}");
    let (code, full, stderr) = kairos(&[&args[..], &["--full"]].concat());
    assert_eq!(code, 0, "{stderr}");
    let cycles = |text: &str| text.lines().filter(|l| l.starts_with("t = ")).count();
    let left_out: usize = changes
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("... "))
        .filter_map(|l| l.split(' ').next()?.parse::<usize>().ok())
        .sum();
    assert_eq!(cycles(&full), 16, "{full}");
    assert!(cycles(&changes) < 16 && left_out > 0, "{changes}");
    assert_eq!(cycles(&changes) + left_out, 16, "{changes}");
}

/// Item 1 (DESIGN.md §6.2 "Expected behaviour", §8 "merge ... summing their
/// probabilities"): the engine alone heating in Uniform(30, 60) s, nothing observed. The exact
/// update never holds more than 3 system states (heating, standby, failed), so TimedME at κ = 3
/// must be the exact update — and flip to standby in the second half of the window (§7.1.2).
/// It once kept heating (0.856) at 46 s: the trickle from heating into standby, each cycle
/// lighter than the `failed` state, was dropped instead of merged into standby.
#[test]
fn timed_me_at_kappa_3_is_the_exact_update_of_the_heating_engine() {
    let run = |extra: &[&str]| -> Vec<serde_json::Value> {
        let mut args = vec![
            "estimate",
            "--plant",
            "tests/models/engine_heating.ron",
            "--log",
            "tests/logs/engine_heating.jsonl",
            "--json",
            "--full",
        ];
        args.extend_from_slice(extra);
        let (code, stdout, stderr) = kairos(&args);
        assert_eq!(code, 0, "{stderr}");
        stdout
            .lines()
            .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
            .collect()
    };
    let timed = run(&["--kappa", "3"]);
    let exact = run(&["--exact"]);
    assert_eq!(timed.len(), exact.len());
    for (t, e) in timed.iter().zip(&exact) {
        assert!(e["system_states"].as_u64().unwrap_or(99) <= 3, "{e}");
        let estimates = |c: &serde_json::Value| -> Vec<(String, f64)> {
            c["estimates"]
                .as_array()
                .into_iter()
                .flatten()
                .map(|x| {
                    (
                        x["modes"]["engine"].as_str().unwrap_or("?").to_string(),
                        x["probability"].as_f64().unwrap_or(f64::NAN),
                    )
                })
                .collect()
        };
        let (t, e) = (estimates(t), estimates(e));
        assert_eq!(t.len(), e.len(), "{t:?} vs {e:?}");
        for ((tm, tp), (em, ep)) in t.iter().zip(&e) {
            assert_eq!(tm, em, "{t:?} vs {e:?}");
            assert!((tp - ep).abs() < 1e-9, "{t:?} vs {e:?}");
        }
    }
    let last = &timed[timed.len() - 1];
    assert_eq!(last["time"], 46.0);
    assert_eq!(last["estimates"][0]["modes"]["engine"], "standby");
}

/// `--json` says per cycle how much truncation discarded and how far the belief may be from the
/// exact update's (`docs/reference/estimation-log.md`; the bound is derived in
/// `src/estimation/timed_me.rs`), on Livingstone 2's reference script at κ = 10: nothing is
/// discarded until the breakers can fail, the bound only grows, and it jumps where led8 off
/// refutes almost every state kept.
#[test]
fn json_lines_say_what_truncation_discarded_and_how_far_from_exact() {
    let dir = std::env::temp_dir().join(format!("kairos-estimate-bound-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    let (model, log) = (dir.join("cb15.ron"), dir.join("cb.jsonl"));
    std::fs::write(&model, l2_breakers::model_ron(15)).expect("model written");
    std::fs::write(&log, l2_breakers::reference_log()).expect("log written");
    let (model, log) = (model.display().to_string(), log.display().to_string());
    let (code, stdout, stderr) = kairos(&[
        "estimate", "--plant", &model, "--log", &log, "--json", "--full", "--top", "3", "--kappa",
        "10",
    ]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 0, "{stderr}");
    let cycles: Vec<serde_json::Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect();
    let field = |c: &serde_json::Value, name: &str| c[name].as_f64().expect("a number");
    assert_eq!(field(&cycles[0], "discarded"), 0.0);
    assert_eq!(field(&cycles[0], "distance_bound"), 0.0);
    for pair in cycles.windows(2) {
        let discarded = field(&pair[1], "discarded");
        assert!((0.0..=1.0).contains(&discarded), "{}", pair[1]);
        assert!(
            field(&pair[1], "distance_bound") >= field(&pair[0], "distance_bound"),
            "{pair:?}"
        );
    }
    assert!(field(&cycles[4], "distance_bound") > 10.0 * field(&cycles[3], "distance_bound"));
    let shown: Vec<String> = (stdout.lines())
        .map(|l| l.replace(&model, "MODEL").replace(&log, "LOG"))
        .collect();
    insta::assert_snapshot!(shown.join("\n"));
}
