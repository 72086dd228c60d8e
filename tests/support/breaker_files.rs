//! What the two circuit-breaker generators (`breakers.rs`, `l2_breakers.rs` beside this file)
//! share: the layout of a plant file written with component types, indexed names, and the
//! command line of their examples (`examples/breakers.rs`, `examples/l2_breakers.rs`).
//!
//! Both models declare a breaker and an LED once, as types, and instantiate them as arrays
//! (`b[0..14]`, `led[7..14]`); the connections of the tree stay explicit, one a breaker feeding
//! its two children (`"b1.out = b[3..4].in"`). Loading expands the file into the plant the
//! components written out would give; `tests/plant_types.rs` checks the shipped files against
//! their written-out forms kept in `tests/models/pre_types/`.

use std::fmt::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// `prefix[first..last]`, or `prefix{first}` for a single index.
pub fn indexed(prefix: &str, first: usize, last: usize) -> String {
    if first == last {
        format!("{prefix}{first}")
    } else {
        format!("{prefix}[{first}..{last}]")
    }
}

/// A breaker tree as the generators write it: a `breaker` and an `led` type, an array of
/// each, every breaker's `cmd` a control (idle `none`), every LED's light an observable.
pub struct BreakerTree {
    /// The comment lines above `Plant(`, each without its `// `.
    pub comment: Vec<String>,
    /// The plant's name.
    pub name: String,
    /// The `Type(name: "breaker", ...)`, written out with the indentation of a list entry.
    pub breaker: &'static str,
    /// The `Type(name: "led", ...)`, likewise.
    pub led: &'static str,
    /// The breakers' array (`indexed("b", 0, 14)`).
    pub breakers: String,
    /// The LEDs' array.
    pub leds: String,
    /// The LED's observable attribute.
    pub light: &'static str,
    /// The connections, unquoted.
    pub connections: Vec<String>,
}

impl BreakerTree {
    /// The file's text.
    pub fn ron(&self) -> String {
        let mut out = String::new();
        for line in &self.comment {
            let _ = writeln!(out, "// {line}");
        }
        let _ = writeln!(
            out,
            "Plant(\n  name: \"{}\",\n  types: [\n{}{}  ],",
            self.name, self.breaker, self.led
        );
        let (breakers, leds) = (&self.breakers, &self.leds);
        let _ = writeln!(
            out,
            "  components: [\n    Component(name: \"{breakers}\", type: \"breaker\"),\n    Component(name: \"{leds}\", type: \"led\"),\n  ],"
        );
        let _ = writeln!(
            out,
            "  controls: {{ \"{breakers}.cmd\": \"none\" }},\n  observables: [\"{leds}.{}\"],\n  connections: [",
            self.light
        );
        for connection in &self.connections {
            let _ = writeln!(out, "    \"{connection}\",");
        }
        out.push_str("  ],\n)\n");
        out
    }
}

/// One generator's command line: `cargo run --example NAME -- N [COUNT] [DIR]` writes
/// `DIR/NAME_N.ron` and `DIR/NAME_N.jsonl`.
pub struct Generator {
    /// The example's name, also the stem of the files it writes.
    pub name: &'static str,
    /// What the optional second argument counts (`TRIPS`, `CYCLES`).
    pub count: &'static str,
    /// Its default.
    pub default_count: usize,
    /// Whether `n` breakers make a tree the generator can write.
    pub valid: fn(usize) -> bool,
    /// The sizes it accepts, for the error message.
    pub sizes: &'static str,
    /// The model of `n` breakers.
    pub model: fn(usize) -> String,
    /// The replay log of `n` breakers and the count.
    pub log: fn(usize, usize) -> String,
}

impl Generator {
    /// Runs the generator on the process's arguments.
    pub fn main(&self) -> ExitCode {
        let args: Vec<String> = std::env::args().skip(1).collect();
        let n = args.first().and_then(|a| a.parse::<usize>().ok());
        let count = args
            .get(1)
            .map_or(Some(self.default_count), |a| a.parse::<usize>().ok());
        let dir = PathBuf::from(args.get(2).map_or(".", String::as_str));
        let (Some(n), Some(count)) = (n, count) else {
            eprintln!(
                "usage: cargo run --example {} -- N [{}] [DIR]",
                self.name, self.count
            );
            return ExitCode::from(2);
        };
        if !(self.valid)(n) {
            eprintln!("error: N must be {}, not {n}", self.sizes);
            return ExitCode::from(2);
        }
        let model = dir.join(format!("{}_{n}.ron", self.name));
        let log = dir.join(format!("{}_{n}.jsonl", self.name));
        let written = std::fs::write(&model, (self.model)(n))
            .and_then(|()| std::fs::write(&log, (self.log)(n, count)));
        match written {
            Ok(()) => {
                println!("wrote {} and {}", model.display(), log.display());
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        }
    }
}
