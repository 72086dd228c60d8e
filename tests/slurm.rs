//! Campaigns and explorations on a real Slurm cluster (docs/campaigns.md, "On a cluster";
//! `scripts/slurm/`): a single-node cluster (munged, slurmctld, slurmd) started by
//! `scripts/slurm/local-cluster.sh`, a 4-task job array of a shipped campaign and of a search,
//! each with its dependent merge job submitted by `scripts/slurm/submit.sh`, and the merged
//! results compared with one process's on the same seed and runs (DESIGN.md §17: a campaign's
//! records do not depend on how it is split; §16: nor does a search's verdict).
//!
//! Opt-in: it needs Debian's `slurm-wlm` and `munge` and root, which `.ci/run` installs and has;
//! it runs when `KAIROS_SLURM=1` (as `.ci/run` sets it) and otherwise prints a notice and
//! passes, so that `cargo test` on a developer's machine needs only Rust.

#[path = "support/cli.rs"]
mod cli;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use serde_json::Value;

/// The campaign: a shipped one, small enough for a test.
const CAMPAIGN: [&str; 5] = [
    "scenarios/propulsion/campaign.ron",
    "--runs",
    "24",
    "--seed",
    "2026",
];

/// The search: a shipped exploration scenario with two faults a path (5,081 states).
const SEARCH: [&str; 3] = ["tests/scenarios/explore_flameout.ron", "--faults", "2"];

/// How long the jobs may take, from submission to both merges written.
const DEADLINE: Duration = Duration::from_secs(300);

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The cluster, stopped (and its daemons ended) when dropped, whatever the test's outcome.
struct Cluster {
    dir: PathBuf,
}

impl Cluster {
    fn start(dir: &Path) -> Cluster {
        let cluster = Cluster {
            dir: dir.to_path_buf(),
        };
        let output = script("local-cluster.sh")
            .args(["start", &dir.display().to_string()])
            .output()
            .expect("local-cluster.sh runs");
        assert!(
            output.status.success(),
            "the cluster did not start:\n{}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
        cluster
    }

    fn conf(&self) -> PathBuf {
        self.dir.join("slurm.conf")
    }

    /// The end of the controller's and the node's logs, and the queue, for a failure message.
    fn diagnose(&self) -> String {
        let queue = Command::new("squeue")
            .env("SLURM_CONF", self.conf())
            .output()
            .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
            .unwrap_or_default();
        let tail = |name: &str| {
            let text = std::fs::read_to_string(self.dir.join(name)).unwrap_or_default();
            let lines: Vec<&str> = text.lines().collect();
            lines[lines.len().saturating_sub(15)..].join("\n")
        };
        format!(
            "squeue:\n{queue}\nslurmctld.log:\n{}\nslurmd.log:\n{}",
            tail("slurmctld.log"),
            tail("slurmd.log")
        )
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = script("local-cluster.sh")
            .args(["stop", &self.dir.display().to_string()])
            .status();
    }
}

fn script(name: &str) -> Command {
    let mut command = Command::new("bash");
    command
        .arg(root().join("scripts/slurm").join(name))
        .current_dir(root());
    command
}

/// Submits `kind args` as 4 shards and a merge into `out`.
fn submit(cluster: &Cluster, out: &Path, kind: &str, args: &[&str]) {
    let output = script("submit.sh")
        .env("SLURM_CONF", cluster.conf())
        .env("KAIROS", env!("CARGO_BIN_EXE_kairos"))
        .args(["--tasks", "4", "--time", "00:10:00"])
        .arg(out)
        .arg("--")
        .arg(kind)
        .args(args)
        .output()
        .expect("submit.sh runs");
    assert!(
        output.status.success(),
        "submit.sh {kind}: {}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// Waits for the merge job's exit status in `out/merged.status`.
fn merged_status(cluster: &Cluster, out: &Path, started: Instant) -> i32 {
    let path = out.join("merged.status");
    loop {
        if let Ok(text) = std::fs::read_to_string(&path)
            && let Ok(status) = text.trim().parse()
        {
            return status;
        }
        assert!(
            started.elapsed() < DEADLINE,
            "no merge in {} s for {}\n{}",
            DEADLINE.as_secs(),
            out.display(),
            cluster.diagnose()
        );
        std::thread::sleep(Duration::from_millis(250));
    }
}

/// `runs.jsonl` of `dir` without the machine-dependent `timing` of each record.
fn records(dir: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(dir.join("runs.jsonl")).expect("runs.jsonl written");
    text.lines()
        .map(|line| {
            let mut record: Value = serde_json::from_str(line).expect("a JSON record");
            record.as_object_mut().expect("an object").remove("timing");
            record
        })
        .collect()
}

/// A summary's lines that depend on the runs only: not the header (which says how it was run)
/// and not the cycle times (measured on the machine).
fn summary_body(text: &str) -> Vec<&str> {
    text.lines()
        .filter(|l| !l.starts_with("campaign `") && !l.starts_with("replay a run:"))
        .filter(|l| !l.starts_with("cycle time"))
        .collect()
}

/// An exploration's report without what says how it was run: the heading, the worker count,
/// the wall time.
fn exploration_body(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| !l.starts_with("merged from") && !l.starts_with("explore `"))
        .map(|l| match l.split_once(" states; ") {
            Some(_) => l
                .rsplit_once("; ")
                .map_or(l, |(counts, _time)| counts)
                .to_string(),
            None => l.to_string(),
        })
        .collect()
}

/// Slurm runs the shards of a campaign and of a search as array tasks and merges them in a
/// dependent job; the merged campaign's records and summary are one process's, and so are the
/// merged search's verdicts, counts and counterexamples.
#[test]
fn shards_on_a_slurm_cluster_merge_into_the_one_machine_result() {
    if std::env::var_os("KAIROS_SLURM").is_none() {
        eprintln!(
            "notice: the Slurm test is skipped: set KAIROS_SLURM=1 on a machine with Debian's \
             slurm-wlm and munge, as root (.ci/run does)"
        );
        return;
    }
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("slurm-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).expect("a work directory");
    let started = Instant::now();
    let cluster = Cluster::start(&work.join("cluster"));
    let up = started.elapsed();
    submit(&cluster, &work.join("campaign"), "campaign", &CAMPAIGN);
    submit(&cluster, &work.join("explore"), "explore", &SEARCH);

    // One machine, the same seed and runs; the same search.
    let local = work.join("local");
    let mut args = vec!["campaign"];
    args.extend_from_slice(&CAMPAIGN);
    let local_out = local.display().to_string();
    args.extend_from_slice(&["--out", &local_out, "--jobs", "1"]);
    let (local_code, _, stderr) = cli::kairos(&args);
    assert!(local_code <= 1, "{stderr}");
    let mut args = vec!["explore"];
    args.extend_from_slice(&SEARCH);
    args.extend_from_slice(&["--quiet", "--no-replay", "--jobs", "1"]);
    let (explore_code, explore_local, stderr) = cli::kairos(&args);
    assert!(explore_code <= 1, "{stderr}");

    let campaign_status = merged_status(&cluster, &work.join("campaign"), started);
    let explore_status = merged_status(&cluster, &work.join("explore"), started);
    let finished = started.elapsed();
    drop(cluster);
    eprintln!(
        "Slurm: cluster up in {:.1} s, both merges written {:.1} s after the start",
        up.as_secs_f64(),
        finished.as_secs_f64()
    );

    let merged = work.join("campaign/merged");
    assert_eq!(campaign_status, local_code, "the merged campaign's verdict");
    assert_eq!(records(&merged), records(&local), "the merged records");
    let summary = |dir: &Path| std::fs::read_to_string(dir.join("summary.txt")).expect("summary");
    let (merged_summary, local_summary) = (summary(&merged), summary(&local));
    assert_eq!(
        summary_body(&merged_summary),
        summary_body(&local_summary),
        "the merged summary\n{merged_summary}\nthe one-machine summary\n{local_summary}"
    );
    assert!(merged_summary.contains("runs: 24 "), "{merged_summary}");
    for i in 0..4 {
        let shard = std::fs::read_to_string(work.join(format!("campaign/shard-{i}/shard.json")))
            .expect("each task wrote its shard");
        assert!(shard.contains(&format!("\"shard\": {i}")), "{shard}");
    }

    let merged_report =
        std::fs::read_to_string(work.join("explore/merged.txt")).expect("the merged report");
    assert_eq!(explore_status, explore_code, "the merged search's verdict");
    assert_eq!(
        exploration_body(&merged_report),
        exploration_body(&explore_local),
        "the merged search\n{merged_report}\nthe one-process search\n{explore_local}"
    );
    assert!(merged_report.contains("5081 states"), "{merged_report}");
    let _ = std::fs::remove_dir_all(&work);
}
