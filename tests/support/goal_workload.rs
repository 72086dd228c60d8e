//! Goal-network workloads of a chosen size on the thermostat (models/thermostat.ron), to measure
//! what scheduling and submissions cost as the number of goals grows (DESIGN.md §15.2, §15.4):
//! `benches/goalnet.rs` times them, `examples/goal_workload.rs` writes them as files for
//! `kairos schedule` and `kairos run` under `/usr/bin/time -v`, and the scheduler's property
//! test schedules small ones.
//!
//! - [`mission`]: `n` goals over a chain of points `T(i−1) → T(i) ∈ [1, 10]`, goal `i` on state
//!   variable `i mod 4` (Knowledge, Maintain) or on switch `i mod 2` (Transition). Knowledge and
//!   Maintain goals span `[T(i), T(i+8)]`, so each overlaps the next one on its SV and the
//!   XGoals merge two constituents; Transition goals alternate `closed` and `open` over
//!   `[T(i), T(i+2)]`, so consecutive goals on one switch do not merge and are serialised.
//! - [`scenario`]: the thermostat's KnowAll mission with `n` submissions, one a cycle from 1 s
//!   on, each a goal (of the kind) over two new points 5 s apart.
#![allow(dead_code)] // each includer uses a different part

use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The kind of goal a workload is made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `Knowledge` (the SV's estimate is known), on every SV.
    Knowledge,
    /// `Maintain` of the thermostat's initial mode, on every SV.
    Maintain,
    /// `Transition` of a switch, alternately closed and open.
    Transition,
}

impl Kind {
    /// The kind named on a command line (`knowledge`, `maintain`, `transition`).
    pub fn named(name: &str) -> Option<Kind> {
        match name {
            "knowledge" => Some(Kind::Knowledge),
            "maintain" => Some(Kind::Maintain),
            "transition" => Some(Kind::Transition),
            _ => None,
        }
    }

    /// The SV and the goal's kind and constraint as a mission writes them.
    fn goal(self, i: usize) -> (&'static str, &'static str, Option<&'static str>) {
        const SVS: [(&str, &str); 4] = [
            ("temperature", "temperature = cold"),
            ("switch1", "switch1 = open"),
            ("switch2", "switch2 = open"),
            ("sensor", "sensor = healthy"),
        ];
        match self {
            Kind::Knowledge => (SVS[i % 4].0, "Knowledge", None),
            Kind::Maintain => (SVS[i % 4].0, "Maintain", Some(SVS[i % 4].1)),
            Kind::Transition => {
                let sv = ["switch1", "switch2"][i % 2];
                let constraint = match (i / 2 % 2, i % 2) {
                    (0, 0) => "switch1 = closed",
                    (1, 0) => "switch1 = open",
                    (0, _) => "switch2 = closed",
                    _ => "switch2 = open",
                };
                (sv, "Transition", Some(constraint))
            }
        }
    }

    /// How many links of the chain a goal spans.
    fn span(self) -> usize {
        match self {
            Kind::Transition => 2,
            _ => 8,
        }
    }
}

/// The crate's root (where `models/` and `missions/` are).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The thermostat plant's path.
pub fn plant() -> PathBuf {
    root().join("models/thermostat.ron")
}

/// A mission of `n` goals of `kind` (see the module doc), its plant named by absolute path.
pub fn mission(n: usize, kind: Kind) -> String {
    let span = kind.span();
    let links = n + span;
    let mut text = String::new();
    let _ = writeln!(text, "Mission(");
    let _ = writeln!(text, "    name: \"{n} {kind:?} goals\",");
    let _ = writeln!(text, "    plant: {:?},", plant().display().to_string());
    let _ = writeln!(text, "    network: Network(");
    let points: Vec<String> = (1..=links).map(|i| format!("\"T{i}\"")).collect();
    let _ = writeln!(text, "        points: [{}],", points.join(", "));
    let _ = writeln!(text, "        constraints: [");
    for i in 1..=links {
        let _ = writeln!(
            text,
            "            Constraint(from: \"{}\", to: \"T{i}\", min: 1.0, max: 10.0),",
            point(i - 1)
        );
    }
    let _ = writeln!(text, "        ],");
    let _ = writeln!(text, "        goals: [");
    for i in 0..n {
        let (sv, kind_name, constraint) = kind.goal(i);
        let constraint = constraint.map_or(String::new(), |c| format!(" constraint: \"{c}\","));
        let _ = writeln!(
            text,
            "            Goal(name: \"g{i}\", sv: \"{sv}\", kind: {kind_name},{constraint} start: \"{}\", end: \"T{}\"),",
            point(i),
            i + span
        );
    }
    let _ = writeln!(text, "        ],");
    let _ = writeln!(text, "    ),");
    let _ = writeln!(text, ")");
    text
}

fn point(i: usize) -> String {
    if i == 0 {
        "origin".to_string()
    } else {
        format!("T{i}")
    }
}

/// A scenario running the thermostat's KnowAll mission (1,000 s) with `n` submissions, one a
/// cycle from 1 s on, each a goal of `kind` over two new points 5 s apart; it ends 20 s after
/// the last.
pub fn scenario(n: usize, kind: Kind) -> String {
    let root = root();
    let path = |p: &str| root.join(p).display().to_string();
    let mut text = String::new();
    let _ = writeln!(text, "Scenario(");
    let _ = writeln!(text, "    name: \"{n} submissions of {kind:?} goals\",");
    let _ = writeln!(
        text,
        "    mission: {:?},",
        path("missions/thermostat_know_all.ron")
    );
    let _ = writeln!(text, "    plant: {:?},", path("models/thermostat.ron"));
    let _ = writeln!(text, "    cycle: 1.0,");
    let _ = writeln!(text, "    end: {}.0,", n + 20);
    let _ = writeln!(
        text,
        "    include: [{:?}],",
        path("scenarios/thermostat/plant.ron")
    );
    let _ = writeln!(text, "    rules: [");
    for i in 0..n {
        let (sv, kind_name, constraint) = kind.goal(i);
        let constraint = constraint.map_or(String::new(), |c| format!(" constraint: \"{c}\","));
        let _ = writeln!(
            text,
            "        Rule(name: \"submit {i}\", on: Time({}.0), submit: Network(\
             points: [\"S{i}\", \"E{i}\"], \
             constraints: [Constraint(from: \"S{i}\", to: \"E{i}\", min: 5.0, max: 5.0)], \
             goals: [Goal(name: \"s{i}\", sv: \"{sv}\", kind: {kind_name},{constraint} start: \"S{i}\", end: \"E{i}\")])),",
            i + 1
        );
    }
    let _ = writeln!(text, "    ],");
    let _ = writeln!(
        text,
        "    expect: [NeverReported(event: SubmissionRefused)],"
    );
    let _ = writeln!(text, ")");
    text
}

/// The directory generated files' relative paths would resolve against (their paths are
/// absolute, so any).
pub fn dir() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}
