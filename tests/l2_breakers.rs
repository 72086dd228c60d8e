//! Livingstone 2's circuit-breaker benchmark (`tests/support/l2_breakers.rs`): the shipped
//! models and logs are what the generator writes, and the script is L2's `cycle-7-8` at 15
//! breakers.

#[path = "support/l2_breakers.rs"]
mod l2_breakers;

fn shipped(path: &str) -> String {
    let full = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"))
}

#[test]
fn the_shipped_models_and_logs_are_the_generators() {
    for (n, cycles) in [(15, 100), (63, 25)] {
        assert_eq!(
            shipped(&format!("models/l2_breakers_{n}.ron")),
            l2_breakers::model_ron(n)
        );
        assert_eq!(
            shipped(&format!("tests/logs/l2_breakers_{n}.jsonl")),
            l2_breakers::log(n, cycles)
        );
    }
}

/// L2's `mba/cpp/tests/cb/cycle-7-8.scr`, command by command and observation by observation.
#[test]
fn at_15_breakers_the_script_is_l2s_cycle_7_8() {
    let script: Vec<String> = l2_breakers::cycle(15)
        .iter()
        .map(|step| {
            let (k, command) = step.command;
            let observed: Vec<String> = step
                .observed
                .iter()
                .map(|(led, state)| format!(" led{led}={state}"))
                .collect();
            format!("cb{k}={command}{}", observed.concat())
        })
        .collect();
    let l2 = [
        "cb15=on",
        "cb14=on",
        "cb12=on",
        "cb11=on",
        "cb5=on led5=on",
        "cb8=on led8=off",
        "cb7=on led7=on",
        "cb8=reset",
        "cb8=on led8=on",
        "cb15=off led8=off led5=off led7=off",
        "cb14=off",
        "cb12=off",
        "cb11=off",
        "cb5=off",
        "cb7=off",
        "cb8=off",
    ];
    assert_eq!(script, l2);
}

/// The tree is L2's: cb15 feeds cb13 and cb14, cb14 feeds cb11 and cb12, cb12 feeds cb7 and
/// cb8 (`l2-regress/tests/cb/README`).
#[test]
fn breakers_are_numbered_as_l2_numbers_them() {
    let d = l2_breakers::depth(15).expect("15 breakers");
    let numbers: Vec<usize> = (0..15).map(|h| l2_breakers::number(d, h)).collect();
    assert_eq!(numbers, [15, 13, 14, 9, 10, 11, 12, 1, 2, 3, 4, 5, 6, 7, 8]);
    assert_eq!(l2_breakers::depth(14), None);
    assert_eq!(l2_breakers::depth(3), None);
}
