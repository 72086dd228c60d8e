//! Plant models written as RON text for the mode reconfiguration tests and benchmarks: random
//! small plants with acyclic causal graphs (`tests/reconfiguration_properties.rs`) and a
//! synthetic plant of drivers relaying commands to devices, of any size
//! (`benches/reconfiguration.rs`). Included with `#[path]`.
#![allow(dead_code)] // each includer uses a different part

use std::fmt::Write;

/// A random transition `(from, to, timed, condition, back)`; see [`RandomComponent::edges`].
pub type RandomEdge = (usize, usize, bool, Option<(usize, usize)>, bool);

/// One random component, as plain numbers read modulo the sizes they index.
#[derive(Debug, Clone)]
pub struct RandomComponent {
    /// Nominal modes `m0..`, 2 to 4.
    pub modes: usize,
    /// Reward of each nominal mode (the first `modes` are used).
    pub rewards: Vec<i32>,
    /// Transitions `(from, to, timed, condition, back)`: a commanded transition (`cmd =
    /// go-mTO`), or a timed one that happens by itself (`cmd = none`, after Uniform(1, 2)); the
    /// condition `(upstream pick, mode)` adds "that upstream component is in that mode" to the
    /// guard; `back` adds the commanded transition back, under the same condition.
    pub edges: Vec<RandomEdge>,
    /// 0: no fault mode; 1: a permanent fault `broken`; 2: `broken` repaired by `cmd = repair`.
    pub fault: usize,
    /// `links[j]`: component `j` (earlier) is upstream of this one.
    pub links: Vec<bool>,
}

/// A random plant: components, each driven only by earlier ones, so the causal graph is
/// acyclic. Component `ci` has a control `ci.cmd` (`none`, `go-m0`.., `repair`), a status
/// attribute `ci.status` that names its nominal mode (`down` when broken), and an input
/// `ci.in_j` wired to each upstream component's status.
#[derive(Debug, Clone)]
pub struct RandomPlant {
    /// The components, upstream ones first.
    pub components: Vec<RandomComponent>,
}

impl RandomComponent {
    fn has_fault(&self) -> bool {
        self.fault > 0
    }

    /// Every mode name, nominal first.
    pub fn mode_names(&self) -> Vec<String> {
        let mut names: Vec<String> = (0..self.modes).map(|m| format!("m{m}")).collect();
        if self.has_fault() {
            names.push("broken".to_string());
        }
        names
    }
}

impl RandomPlant {
    /// The upstream components of component `i`.
    pub fn upstream(&self, i: usize) -> Vec<usize> {
        (0..i)
            .filter(|&j| self.components[i].links.get(j).copied().unwrap_or(false))
            .collect()
    }

    /// Status values: every component's status domain is `m0..m3, down` so that wires can
    /// connect any two (an interconnection holds values with the same name).
    fn statuses() -> String {
        "[\"m0\", \"m1\", \"m2\", \"m3\", \"down\"]".to_string()
    }

    /// The model as RON.
    pub fn to_ron(&self) -> String {
        let mut out = String::from("Plant(\n  name: \"random\",\n  components: [\n");
        let mut controls = Vec::new();
        let mut connections = Vec::new();
        for (i, component) in self.components.iter().enumerate() {
            let upstream = self.upstream(i);
            self.component_ron(&mut out, i, component, &upstream);
            controls.push(format!("\"c{i}.cmd\": \"none\""));
            for j in upstream {
                connections.push(format!("\"c{j}.status = c{i}.in{j}\""));
            }
        }
        writeln!(
            out,
            "  ],\n  controls: {{ {} }},\n  connections: [{}],\n)",
            controls.join(", "),
            connections.join(", ")
        )
        .ok();
        out
    }

    fn component_ron(&self, out: &mut String, i: usize, c: &RandomComponent, upstream: &[usize]) {
        let commands: Vec<String> = std::iter::once("\"none\"".to_string())
            .chain((0..c.modes).map(|m| format!("\"go-m{m}\"")))
            .chain(std::iter::once("\"repair\"".to_string()))
            .collect();
        writeln!(
            out,
            "    Component(\n      name: \"c{i}\",\n      attributes: {{"
        )
        .ok();
        writeln!(out, "        \"cmd\": [{}],", commands.join(", ")).ok();
        writeln!(out, "        \"status\": {},", Self::statuses()).ok();
        for j in upstream {
            writeln!(out, "        \"in{j}\": {},", Self::statuses()).ok();
        }
        writeln!(out, "      }},\n      modes: [").ok();
        for m in 0..c.modes {
            let reward = c.rewards.get(m).copied().unwrap_or(0);
            writeln!(
                out,
                "        Mode(name: \"m{m}\", constraint: \"c{i}.status = m{m}\", reward: {reward}),"
            )
            .ok();
        }
        if c.has_fault() {
            writeln!(
                out,
                "        Mode(name: \"broken\", kind: Fault, constraint: \"c{i}.status = down\", reward: -20),"
            )
            .ok();
        }
        writeln!(
            out,
            "      ],\n      initial: {{ \"m0\": 1.0 }},\n      transitions: ["
        )
        .ok();
        for line in self.transitions(i, c, upstream) {
            writeln!(out, "        {line},").ok();
        }
        if c.has_fault() {
            writeln!(out, "        (from: \"*\", to: \"broken\", rate: 0.001),").ok();
        }
        if c.fault == 2 {
            writeln!(
                out,
                "        (from: \"broken\", to: \"m0\", guard: \"c{i}.cmd = repair\", probability: 1.0),"
            )
            .ok();
        }
        writeln!(out, "      ],\n    ),").ok();
    }

    /// The nominal transitions: one per (from, to) pair, at most one timed per source mode (two
    /// would together exceed probability 1).
    fn transitions(&self, i: usize, c: &RandomComponent, upstream: &[usize]) -> Vec<String> {
        let mut seen = Vec::new();
        let mut timed_from = Vec::new();
        let mut lines = Vec::new();
        for &(from, to, timed, condition, back) in &c.edges {
            let (from, to) = (from % c.modes, to % c.modes);
            let condition = match (condition, upstream.is_empty()) {
                (Some((pick, mode)), false) => {
                    let j = upstream[pick % upstream.len()];
                    format!(" and c{i}.in{j} = m{}", mode % self.components[j].modes)
                }
                _ => String::new(),
            };
            let mut add = |from: usize, to: usize, timed: bool| {
                if from == to || seen.contains(&(from, to)) || (timed && timed_from.contains(&from))
                {
                    return;
                }
                seen.push((from, to));
                let (guard, law) = if timed {
                    timed_from.push(from);
                    (format!("c{i}.cmd = none"), "after: Uniform(1.0, 2.0)")
                } else {
                    (format!("c{i}.cmd = go-m{to}"), "probability: 1.0")
                };
                lines.push(format!(
                    "(from: \"m{from}\", to: \"m{to}\", guard: \"{guard}{condition}\", {law})"
                ));
            };
            add(from, to, timed);
            if back {
                add(to, from, false);
            }
        }
        lines
    }
}

/// A synthetic plant of `1 + drivers + drivers·devices` components, like the propulsion
/// subsystem scaled up: a power `bus` (off/on), `drivers` drivers that can be switched on only
/// while the bus is on, each relaying open/close commands to its `devices` devices when on.
/// Every driver has its own control. The causal graph is bus → drivers → devices (depth 2).
pub fn synthetic_plant_ron(drivers: usize, devices: usize) -> String {
    let mut out = String::from("Plant(\n  name: \"synthetic\",\n  components: [\n");
    out.push_str(
        "    Component(\n      name: \"bus\",\n      attributes: { \"cmd\": [\"none\", \"on\", \"off\"], \"power\": [\"off\", \"on\"] },\n      modes: [\n        Mode(name: \"off\", constraint: \"bus.power = off\", reward: 0),\n        Mode(name: \"on\", constraint: \"bus.power = on\", reward: -1),\n        Mode(name: \"failed\", kind: Fault, reward: -20),\n      ],\n      initial: { \"off\": 1.0 },\n      transitions: [\n        (from: \"off\", to: \"on\", guard: \"bus.cmd = on\", probability: 1.0),\n        (from: \"on\", to: \"off\", guard: \"bus.cmd = off\", probability: 1.0),\n        (from: \"*\", to: \"failed\", rate: 0.00001),\n      ],\n    ),\n",
    );
    let mut controls = vec!["\"bus.cmd\": \"none\"".to_string()];
    let mut connections = Vec::new();
    for d in 0..drivers {
        driver_ron(&mut out, d, devices);
        controls.push(format!("\"d{d}.cmd\": \"none\""));
        connections.push(format!("\"bus.power = d{d}.power\""));
        for v in 0..devices {
            device_ron(&mut out, d, v);
            connections.push(format!("\"d{d}.out{v} = d{d}v{v}.cmd\""));
        }
    }
    writeln!(
        out,
        "  ],\n  controls: {{ {} }},\n  connections: [{}],\n)",
        controls.join(", "),
        connections.join(", ")
    )
    .ok();
    out
}

fn driver_ron(out: &mut String, d: usize, devices: usize) {
    let mut commands = vec!["\"none\"".to_string(), "\"on\"".into(), "\"off\"".into()];
    let mut relay = Vec::new();
    let mut silent = Vec::new();
    for v in 0..devices {
        commands.push(format!("\"open{v}\""));
        commands.push(format!("\"close{v}\""));
        relay.push(format!(
            "(d{d}.cmd = open{v} => d{d}.out{v} = open) and (d{d}.cmd = close{v} => d{d}.out{v} = close) and (d{d}.cmd != open{v} and d{d}.cmd != close{v} => d{d}.out{v} = none)"
        ));
        silent.push(format!("d{d}.out{v} = none"));
    }
    writeln!(
        out,
        "    Component(\n      name: \"d{d}\",\n      attributes: {{"
    )
    .ok();
    writeln!(out, "        \"cmd\": [{}],", commands.join(", ")).ok();
    writeln!(out, "        \"power\": [\"off\", \"on\"],").ok();
    for v in 0..devices {
        writeln!(out, "        \"out{v}\": [\"none\", \"open\", \"close\"],").ok();
    }
    writeln!(out, "      }},\n      modes: [").ok();
    writeln!(
        out,
        "        Mode(name: \"off\", constraint: \"{}\", reward: 0),",
        silent.join(" and ")
    )
    .ok();
    writeln!(
        out,
        "        Mode(name: \"on\", constraint: \"{}\", reward: -1),",
        relay.join(" and ")
    )
    .ok();
    writeln!(
        out,
        "        Mode(name: \"resettable\", kind: Fault, constraint: \"{}\", reward: -10),",
        silent.join(" and ")
    )
    .ok();
    writeln!(
        out,
        "      ],\n      initial: {{ \"off\": 1.0 }},\n      transitions: [\n        (from: \"off\", to: \"on\", guard: \"d{d}.cmd = on and d{d}.power = on\", probability: 1.0),\n        (from: \"on\", to: \"off\", guard: \"d{d}.cmd = off\", probability: 1.0),\n        (from: \"resettable\", to: \"off\", guard: \"d{d}.cmd = off\", probability: 1.0),\n        (from: \"*\", to: \"resettable\", rate: 0.00001),\n      ],\n    ),"
    )
    .ok();
}

fn device_ron(out: &mut String, d: usize, v: usize) {
    writeln!(
        out,
        "    Component(\n      name: \"d{d}v{v}\",\n      attributes: {{ \"cmd\": [\"none\", \"open\", \"close\"], \"flow\": [\"zero\", \"nominal\"] }},\n      modes: [\n        Mode(name: \"closed\", constraint: \"d{d}v{v}.flow = zero\", reward: 0),\n        Mode(name: \"open\", constraint: \"d{d}v{v}.flow = nominal\", reward: -1),\n        Mode(name: \"stuck\", kind: Fault, reward: -10),\n      ],\n      initial: {{ \"closed\": 1.0 }},\n      transitions: [\n        (from: \"closed\", to: \"open\", guard: \"d{d}v{v}.cmd = open\", probability: 1.0),\n        (from: \"open\", to: \"closed\", guard: \"d{d}v{v}.cmd = close\", probability: 1.0),\n        (from: \"*\", to: \"stuck\", rate: 0.00001),\n      ],\n    ),"
    )
    .ok();
}
