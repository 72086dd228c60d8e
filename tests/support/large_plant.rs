//! Large plant models written as RON, for measuring how loading and validation scale
//! (BENCHMARKS.md "Loading large plants"): `examples/large_plant.rs` prints them, and
//! `tests/plant_large.rs` checks that they load.
#![allow(dead_code)] // each includer uses a different part

use std::fmt::Write;

/// `components` components in a chain, each a switch relaying its input when on: modes `off`
/// (output zero), `on` (output = input) and the fault `failed`; a control `cmd` (`on`, `off`,
/// idle `none`) with guarded transitions between off and on, a per-cycle fault from any nominal
/// mode; component i's input is connected to component i − 1's output, every output observed.
pub fn chain(components: usize) -> String {
    let mut text = String::from("Plant(\n    name: \"large_chain\",\n    components: [\n");
    for i in 0..components {
        let _ = write!(
            text,
            r#"        Component(
            name: "c{i}",
            attributes: {{ "cmd": ["on", "off", "none"], "in": ["zero", "nominal"], "out": ["zero", "nominal"] }},
            modes: [
                Mode(name: "off", constraint: "c{i}.out = zero", reward: 0),
                Mode(name: "on", constraint: "c{i}.out = c{i}.in", reward: -1),
                Mode(name: "failed", kind: Fault, constraint: "true", reward: -10),
            ],
            initial: {{ "off": 1.0 }},
            transitions: [
                (from: "off", to: "on", guard: "c{i}.cmd = on", probability: 0.99),
                (from: "on", to: "off", guard: "c{i}.cmd = off", probability: 0.99),
                (from: "*", to: "failed", probability: 0.001),
            ],
        ),
"#
        );
    }
    text.push_str("    ],\n    controls: {");
    let controls: Vec<String> = (0..components)
        .map(|i| format!("\"c{i}.cmd\": \"none\""))
        .collect();
    text.push_str(&controls.join(", "));
    text.push_str("},\n    observables: [");
    let observables: Vec<String> = (0..components).map(|i| format!("\"c{i}.out\"")).collect();
    text.push_str(&observables.join(", "));
    text.push_str("],\n    connections: [");
    let connections: Vec<String> = (1..components)
        .map(|i| format!("\"c{i}.in = c{}.out\"", i - 1))
        .collect();
    text.push_str(&connections.join(", "));
    text.push_str("],\n)\n");
    text
}

/// One component with `modes` modes `m0`, `m1`, ... in a ring: the control `cmd` holds `go-mK`
/// to move from the mode before K to mode K; the output tells even modes from odd ones.
pub fn many_modes(modes: usize) -> String {
    let mut text = String::from("Plant(\n    name: \"many_modes\",\n    components: [\n");
    let values: Vec<String> = (0..modes).map(|k| format!("\"go-m{k}\"")).collect();
    let _ = writeln!(
        text,
        "        Component(\n            name: \"c\",\n            attributes: {{ \"cmd\": [{}, \"none\"], \"out\": [\"even\", \"odd\"] }},\n            modes: [",
        values.join(", ")
    );
    for k in 0..modes {
        let parity = if k % 2 == 0 { "even" } else { "odd" };
        let _ = writeln!(
            text,
            "                Mode(name: \"m{k}\", constraint: \"c.out = {parity}\", reward: 0),"
        );
    }
    text.push_str(
        "            ],\n            initial: { \"m0\": 1.0 },\n            transitions: [\n",
    );
    for k in 0..modes {
        let next = (k + 1) % modes;
        let _ = writeln!(
            text,
            "                (from: \"m{k}\", to: \"m{next}\", guard: \"c.cmd = go-m{next}\", probability: 0.99),"
        );
    }
    text.push_str(
        "            ],\n        ),\n    ],\n    controls: { \"c.cmd\": \"none\" },\n    observables: [\"c.out\"],\n)\n",
    );
    text
}
