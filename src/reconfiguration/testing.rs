//! Small plants for the unit tests of mode reconfiguration.

use crate::diagnostic::Source;
use crate::logic::ValueId;
use crate::plant::{ComponentId, Plant};

/// A `switch` that powers a `gadget`. The gadget's nominal modes are `a ↔ b → c ↔ d` plus `e`,
/// which `a` reaches by a timed transition (so `a` is transient) and which returns to `a` on
/// command; `a → b` needs the switch on (power); `b → c` is irreversible. The gadget's fault
/// `broken` is repaired into `a` or, irreversibly, into `c`; the switch's fault `stuck` has no
/// repair.
pub const SWITCH_GADGET: &str = r#"Plant(
    name: "switch_gadget",
    components: [
        Component(
            name: "switch",
            attributes: { "cmd": ["none", "on", "off"], "power": ["off", "on"] },
            modes: [
                Mode(name: "off", constraint: "switch.power = off"),
                Mode(name: "on", constraint: "switch.power = on", reward: -1),
                Mode(name: "stuck", kind: Fault, reward: -10),
            ],
            initial: { "off": 1.0 },
            transitions: [
                (from: "off", to: "on", guard: "switch.cmd = on", probability: 1.0),
                (from: "on", to: "off", guard: "switch.cmd = off", probability: 1.0),
                (from: "*", to: "stuck", rate: 0.001),
            ],
        ),
        Component(
            name: "gadget",
            attributes: {
                "cmd": ["none", "go-a", "go-b", "go-c", "go-d", "fix-a", "fix-c"],
                "power": ["off", "on"],
            },
            modes: [
                Mode(name: "a"),
                Mode(name: "b", reward: -1),
                Mode(name: "c"),
                Mode(name: "d"),
                Mode(name: "e"),
                Mode(name: "broken", kind: Fault, reward: -10),
            ],
            initial: { "a": 1.0 },
            transitions: [
                (from: "a", to: "b", guard: "gadget.cmd = go-b and gadget.power = on", probability: 1.0),
                (from: "b", to: "a", guard: "gadget.cmd = go-a", probability: 1.0),
                (from: "b", to: "c", guard: "gadget.cmd = go-c", probability: 1.0),
                (from: "c", to: "d", guard: "gadget.cmd = go-d", probability: 1.0),
                (from: "d", to: "c", guard: "gadget.cmd = go-c", probability: 1.0),
                (from: "a", to: "e", guard: "gadget.cmd = none", after: Uniform(1.0, 2.0)),
                (from: "e", to: "a", guard: "gadget.cmd = go-a", probability: 1.0),
                (from: "broken", to: "a", guard: "gadget.cmd = fix-a", probability: 1.0),
                (from: "broken", to: "c", guard: "gadget.cmd = fix-c", probability: 1.0),
                (from: "*", to: "broken", rate: 0.001),
            ],
        ),
    ],
    controls: { "switch.cmd": "none", "gadget.cmd": "none" },
    connections: ["switch.power = gadget.power"],
)"#;

/// Two components that each need the other moved first: `p`'s `x → y` needs `q = y` and `q`'s
/// needs `p = y` (a cycle of influence, one causal unit); `y → x` needs only a command.
pub const DEADLOCK: &str = r#"Plant(
    name: "deadlock",
    components: [
        Component(
            name: "p",
            attributes: { "cmd": ["none", "go", "back"], "status": ["x", "y"], "peer": ["x", "y"] },
            modes: [
                Mode(name: "x", constraint: "p.status = x"),
                Mode(name: "y", constraint: "p.status = y", reward: 1),
            ],
            initial: { "x": 1.0 },
            transitions: [
                (from: "x", to: "y", guard: "p.cmd = go and p.peer = y", probability: 1.0),
                (from: "y", to: "x", guard: "p.cmd = back", probability: 1.0),
            ],
        ),
        Component(
            name: "q",
            attributes: { "cmd": ["none", "go", "back"], "status": ["x", "y"], "peer": ["x", "y"] },
            modes: [
                Mode(name: "x", constraint: "q.status = x"),
                Mode(name: "y", constraint: "q.status = y", reward: 1),
            ],
            initial: { "x": 1.0 },
            transitions: [
                (from: "x", to: "y", guard: "q.cmd = go and q.peer = y", probability: 1.0),
                (from: "y", to: "x", guard: "q.cmd = back", probability: 1.0),
            ],
        ),
    ],
    controls: { "p.cmd": "none", "q.cmd": "none" },
    connections: ["q.status = p.peer", "p.status = q.peer"],
)"#;

/// A gadget whose fault `broken` is repaired only into `t`, a transient mode it leaves by itself
/// for `c`, which is irreversible: `c` is also entered from `a`, and nothing leads back. From
/// `broken` there is no mode the gadget stays in unless the goal names `t` or `c`.
pub const TRANSIENT_REPAIR: &str = r#"Plant(
    name: "transient_repair",
    components: [
        Component(
            name: "gadget",
            attributes: { "cmd": ["none", "go-c", "fix"] },
            modes: [
                Mode(name: "a"),
                Mode(name: "t"),
                Mode(name: "c"),
                Mode(name: "broken", kind: Fault, reward: -10),
            ],
            initial: { "a": 1.0 },
            transitions: [
                (from: "a", to: "c", guard: "gadget.cmd = go-c", probability: 1.0),
                (from: "broken", to: "t", guard: "gadget.cmd = fix", probability: 1.0),
                (from: "t", to: "c", after: Uniform(1.0, 2.0)),
                (from: "*", to: "broken", rate: 0.001),
            ],
        ),
    ],
    controls: { "gadget.cmd": "none" },
)"#;

/// Transient modes in a chain (`t1` leaves by itself for `t2`, `t2` for `c`) and a mode left
/// for good (`c`, which nothing brings back to `a` or `t1`), next to a switch: what settling a
/// goal state follows in one step and must not follow further in a second.
pub const TRANSIENT_CHAIN: &str = r#"Plant(
    name: "transient_chain",
    components: [
        Component(
            name: "gadget",
            attributes: { "cmd": ["none", "go", "fix"] },
            modes: [
                Mode(name: "a"),
                Mode(name: "t1"),
                Mode(name: "t2"),
                Mode(name: "c"),
                Mode(name: "broken", kind: Fault, reward: -10),
            ],
            initial: { "a": 1.0 },
            transitions: [
                (from: "a", to: "t1", guard: "gadget.cmd = go", probability: 1.0),
                (from: "t1", to: "t2", after: Uniform(1.0, 2.0)),
                (from: "t2", to: "c", after: Uniform(1.0, 2.0)),
                (from: "broken", to: "a", guard: "gadget.cmd = fix", probability: 1.0),
                (from: "*", to: "broken", rate: 0.001),
            ],
        ),
        Component(
            name: "switch",
            attributes: { "cmd": ["none", "on", "off"] },
            modes: [Mode(name: "off"), Mode(name: "on")],
            initial: { "off": 1.0 },
            transitions: [
                (from: "off", to: "on", guard: "switch.cmd = on", probability: 1.0),
                (from: "on", to: "off", guard: "switch.cmd = off", probability: 1.0),
            ],
        ),
    ],
    controls: { "gadget.cmd": "none", "switch.cmd": "none" },
)"#;

/// A plant from RON text (the texts above are valid).
pub fn load(text: &str) -> Plant {
    Plant::load(&Source::new("test.ron", text)).unwrap_or_else(|e| panic!("{e}"))
}

/// The shipped `models/NAME.ron`.
pub fn model(name: &str) -> Plant {
    let path = format!("{}/models/{name}.ron", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    Plant::load(&Source::new(path, text)).unwrap_or_else(|e| panic!("{e}"))
}

/// A component by name.
pub fn component(plant: &Plant, name: &str) -> ComponentId {
    plant
        .component_named(name)
        .unwrap_or_else(|| panic!("no `{name}`"))
}

/// A mode by component and mode names.
pub fn mode(plant: &Plant, component_name: &str, mode: &str) -> ValueId {
    plant
        .component(component(plant, component_name))
        .mode_named(mode)
        .unwrap_or_else(|| panic!("no mode `{mode}`"))
}

/// A state from one mode name per component, in order.
pub fn state(plant: &Plant, names: &[&str]) -> Vec<ValueId> {
    plant
        .components()
        .iter()
        .zip(names)
        .map(|(c, n)| c.mode_named(n).unwrap_or_else(|| panic!("no mode `{n}`")))
        .collect()
}
