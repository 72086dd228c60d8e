//! Component types (`src/plant/file/types.rs`; DESIGN.md §6.1's format): a typed model
//! expands to exactly the plant its hand-written twin gives — the shipped models against the
//! files they were before the rewrite (`tests/models/pre_types/`: the lander, the thermostat, the
//! breaker trees), and random types with random
//! instance counts, parameters and indexed names against a renderer that writes every
//! component out.

#[path = "support/seeded.rs"]
mod seeded;

use kairos::diagnostic::Source;
use kairos::plant::Plant;
use proptest::prelude::*;

fn load(name: &str, text: &str) -> Plant {
    Plant::load(&Source::new(name, text)).unwrap_or_else(|e| panic!("{name}:\n{e}\n{text}"))
}

fn read(path: &str) -> String {
    let full = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"))
}

/// The shipped models rewritten with types are the plants they were written out. The breaker
/// models are generated (`examples/breakers.rs`, `examples/l2_breakers.rs`; `tests/breakers.rs`
/// and `tests/l2_breakers.rs` check the files are the generators' output): their written-out
/// forms are the files as generated before the generators wrote types, kept as they were, so
/// the comparison does not rest on the generators' code.
#[test]
fn shipped_typed_models_expand_to_their_written_out_twins() {
    for model in [
        "mars_lander.ron",
        "thermostat.ron",
        "breakers_15.ron",
        "l2_breakers_15.ron",
        "l2_breakers_63.ron",
    ] {
        let typed = load(model, &read(&format!("models/{model}")));
        let written = load(model, &read(&format!("tests/models/pre_types/{model}")));
        assert!(typed == written, "{model}: the typed model differs");
    }
}

/// One random type: attribute domain sizes, its modes (constraint on the last attribute, a
/// fault flag), per-cycle transitions guarded on the first attribute, fault rates (some
/// through parameters) and its parameters' defaults.
#[derive(Debug, Clone)]
struct TypeSpec {
    domains: Vec<usize>,
    modes: Vec<(Option<usize>, bool)>,
    moves: Vec<(usize, usize, usize, f64)>,
    faults: Vec<(usize, Rate)>,
    parameters: Vec<f64>,
}

#[derive(Debug, Clone)]
enum Rate {
    Number(f64),
    Parameter(usize),
}

/// An entry of `components`: a component written out (of a type's shape, but not an
/// instance), one instance, or an indexed run of instances; with parameter overrides.
#[derive(Debug, Clone)]
struct Entry {
    ty: usize,
    count: usize,
    indexed: bool,
    instance: bool,
    overrides: Vec<(usize, f64)>,
}

fn type_spec() -> impl Strategy<Value = TypeSpec> {
    (
        prop::collection::vec(2..4usize, 1..4),
        prop::collection::vec((prop::option::of(0..3usize), any::<bool>()), 2..5),
        prop::collection::vec(0.001..1.0f64, 0..3),
    )
        .prop_flat_map(|(domains, mut modes, parameters)| {
            modes[0].1 = false; // a nominal mode, so `*` stands for one
            let n_modes = modes.len();
            let first = domains[0];
            let n_params = parameters.len();
            let moves =
                prop::collection::vec((0..n_modes, 0..n_modes, 0..first, 0.01..0.45f64), 0..3)
                    .prop_map(|moves| {
                        // No self-loop, at most one move per source mode (probabilities stay <= 1).
                        let mut kept: Vec<(usize, usize, usize, f64)> = Vec::new();
                        for m in moves {
                            if m.0 != m.1 && !kept.iter().any(|k| k.0 == m.0) {
                                kept.push(m);
                            }
                        }
                        kept
                    });
            let rate = if n_params == 0 {
                (1e-6..1e-2f64).prop_map(Rate::Number).boxed()
            } else {
                prop_oneof![
                    (1e-6..1e-2f64).prop_map(Rate::Number),
                    (0..n_params).prop_map(Rate::Parameter),
                ]
                .boxed()
            };
            let faults = prop::collection::vec((1..n_modes, rate), 0..3).prop_map(|faults| {
                let mut kept: Vec<(usize, Rate)> = Vec::new();
                for f in faults {
                    if !kept.iter().any(|k| k.0 == f.0) {
                        kept.push(f);
                    }
                }
                kept
            });
            (Just(domains), Just(modes), moves, faults, Just(parameters))
        })
        .prop_map(|(domains, modes, moves, faults, parameters)| TypeSpec {
            domains,
            modes,
            moves,
            faults,
            parameters,
        })
}

fn model() -> impl Strategy<Value = (Vec<TypeSpec>, Vec<Entry>)> {
    prop::collection::vec(type_spec(), 1..4).prop_flat_map(|types| {
        let n = types.len();
        let params: Vec<usize> = types.iter().map(|t| t.parameters.len()).collect();
        let entry = (0..n, 1..5usize, any::<bool>(), prop::bool::weighted(0.8)).prop_flat_map(
            move |(ty, count, indexed, instance)| {
                let overrides = if params[ty] == 0 {
                    Just(Vec::new()).boxed()
                } else {
                    prop::collection::vec((0..params[ty], 0.001..1.0f64), 0..2).boxed()
                };
                overrides.prop_map(move |overrides| Entry {
                    ty,
                    count,
                    indexed,
                    instance,
                    overrides,
                })
            },
        );
        (Just(types), prop::collection::vec(entry, 1..5))
    })
}

/// The names of an entry's components: `e{k}_{i}`.
fn names(k: usize, entry: &Entry) -> Vec<String> {
    let count = if entry.instance { entry.count } else { 1 };
    (0..count).map(|i| format!("e{k}_{i}")).collect()
}

/// A value of each parameter for an entry: its overrides, else the type's defaults.
fn parameter_values(ty: &TypeSpec, entry: &Entry) -> Vec<f64> {
    let mut values = ty.parameters.clone();
    for &(p, v) in &entry.overrides {
        values[p] = v;
    }
    values
}

/// The body of a type, or of a component written out (`me` in place of `self`, numbers in
/// place of parameter names).
fn body(ty: &TypeSpec, me: &str, values: Option<&[f64]>) -> String {
    let attributes: Vec<String> = ty
        .domains
        .iter()
        .enumerate()
        .map(|(a, &size)| {
            let domain: Vec<String> = (0..size).map(|v| format!("\"v{v}\"")).collect();
            format!("\"a{a}\": [{}]", domain.join(", "))
        })
        .collect();
    let last = ty.domains.len() - 1;
    let modes: Vec<String> = ty
        .modes
        .iter()
        .enumerate()
        .map(|(m, (constraint, fault))| {
            let constraint = match constraint {
                Some(v) => format!("{me}.a{last} = v{}", v % ty.domains[last]),
                None => "true".to_string(),
            };
            let kind = if *fault { "Fault" } else { "Nominal" };
            format!(
                "Mode(name: \"m{m}\", kind: {kind}, constraint: \"{constraint}\", reward: -{m})"
            )
        })
        .collect();
    let mut transitions: Vec<String> = ty
        .moves
        .iter()
        .map(|&(from, to, v, p)| {
            // With one attribute the guard would fight the mode constraints: none then.
            let guard = if last > 0 {
                format!("{me}.a0 = v{v}")
            } else {
                "true".into()
            };
            format!("(from: \"m{from}\", to: \"m{to}\", guard: \"{guard}\", probability: {p:?})")
        })
        .collect();
    transitions.extend(ty.faults.iter().map(|(to, rate)| {
        let rate = match (rate, values) {
            (Rate::Number(r), _) => format!("{r:?}"),
            (Rate::Parameter(p), Some(values)) => format!("{:?}", values[*p]),
            (Rate::Parameter(p), None) => format!("\"p{p}\""),
        };
        format!("(from: \"*\", to: \"m{to}\", rate: {rate})")
    }));
    format!(
        "attributes: {{ {} }}, modes: [{}], initial: {{ \"m0\": 1.0 }}, transitions: [{}]",
        attributes.join(", "),
        modes.join(", "),
        transitions.join(", ")
    )
}

/// Controls (the first attribute), observables (the last), as the typed file writes them: one
/// indexed entry per indexed run of instances.
fn interface(types: &[TypeSpec], entries: &[Entry], indexed: bool) -> (Vec<String>, Vec<String>) {
    let (mut controls, mut observables) = (Vec::new(), Vec::new());
    for (k, entry) in entries.iter().enumerate() {
        let ty = &types[entry.ty];
        let last = ty.domains.len() - 1;
        let run: Vec<String> = if indexed && entry.instance && entry.indexed {
            vec![format!("e{k}_[0..{}]", entry.count - 1)]
        } else {
            names(k, entry)
        };
        for name in run {
            if last > 0 {
                controls.push(format!("\"{name}.a0\": \"v0\""));
            }
            observables.push(format!("\"{name}.a{last}\""));
        }
    }
    (controls, observables)
}

fn typed(types: &[TypeSpec], entries: &[Entry]) -> String {
    let declared: Vec<String> = types
        .iter()
        .enumerate()
        .map(|(t, ty)| {
            let parameters: Vec<String> = ty
                .parameters
                .iter()
                .enumerate()
                .map(|(p, v)| format!("\"p{p}\": {v:?}"))
                .collect();
            format!(
                "Type(name: \"t{t}\", parameters: {{ {} }}, {})",
                parameters.join(", "),
                body(ty, "self", None)
            )
        })
        .collect();
    let mut components = Vec::new();
    for (k, entry) in entries.iter().enumerate() {
        let ty = &types[entry.ty];
        if !entry.instance {
            let values = parameter_values(ty, entry);
            let name = &names(k, entry)[0];
            components.push(format!(
                "Component(name: \"{name}\", {})",
                body(ty, name, Some(&values))
            ));
            continue;
        }
        let overrides: Vec<String> = entry
            .overrides
            .iter()
            .map(|(p, v)| format!("\"p{p}\": {v:?}"))
            .collect();
        let parameters = format!("parameters: {{ {} }}", overrides.join(", "));
        let instance = |name: &str| {
            format!(
                "Component(name: \"{name}\", type: \"t{}\", {parameters})",
                entry.ty
            )
        };
        if entry.indexed {
            components.push(instance(&format!("e{k}_[0..{}]", entry.count - 1)));
        } else {
            components.extend(names(k, entry).iter().map(|n| instance(n)));
        }
    }
    let (controls, observables) = interface(types, entries, true);
    format!(
        "Plant(name: \"random\", types: [{}], components: [{}], controls: {{ {} }}, observables: [{}])",
        declared.join(", "),
        components.join(", "),
        controls.join(", "),
        observables.join(", ")
    )
}

fn written_out(types: &[TypeSpec], entries: &[Entry]) -> String {
    let mut components = Vec::new();
    for (k, entry) in entries.iter().enumerate() {
        let ty = &types[entry.ty];
        let values = parameter_values(ty, entry);
        for name in names(k, entry) {
            components.push(format!(
                "Component(name: \"{name}\", {})",
                body(ty, &name, Some(&values))
            ));
        }
    }
    let (controls, observables) = interface(types, entries, false);
    format!(
        "Plant(name: \"random\", components: [{}], controls: {{ {} }}, observables: [{}])",
        components.join(", "),
        controls.join(", "),
        observables.join(", ")
    )
}

proptest! {
    #![proptest_config(seeded::config(128))]

    /// A typed model — instances one by one or indexed, parameter defaults and overrides,
    /// components written out between them, indexed controls and observables — loads to the
    /// very plant of its written-out twin.
    #[test]
    fn a_typed_model_expands_to_its_written_out_twin((types, entries) in model()) {
        let typed_text = typed(&types, &entries);
        let written_text = written_out(&types, &entries);
        let typed = load("typed.ron", &typed_text);
        let written = load("written.ron", &written_text);
        prop_assert!(typed == written, "typed:\n{typed_text}\nwritten:\n{written_text}");
    }
}

/// An indexed connection is the connections it stands for, in order.
#[test]
fn an_indexed_connection_is_its_connections_in_order() {
    let component = |name: &str| {
        format!(
            "Component(name: \"{name}\", attributes: {{ \"x\": [\"a\", \"b\"] }}, modes: [Mode(name: \"m\")], initial: {{ \"m\": 1.0 }})"
        )
    };
    let names = ["p0", "p1", "p2", "q5", "q6", "q7"];
    let components: Vec<String> = names.iter().map(|n| component(n)).collect();
    let plant = |connections: &str| {
        load(
            "c.ron",
            &format!(
                "Plant(name: \"c\", components: [{}], connections: [{connections}])",
                components.join(", ")
            ),
        )
    };
    assert!(
        plant("\"p[0..2].x = q[5..7].x\"")
            == plant("\"p0.x = q5.x\", \"p1.x = q6.x\", \"p2.x = q7.x\"")
    );
}
