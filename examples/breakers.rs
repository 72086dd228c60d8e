//! Writes a circuit-breaker tree model and its scripted replay log:
//! `cargo run --example breakers -- N [TRIPS] [DIR]` writes `DIR/breakers_N.ron` and
//! `DIR/breakers_N.jsonl` (N = 2^d − 1 breakers; default 7 trips; default DIR `.`). The shipped
//! `models/breakers_15.ron` and `tests/logs/breakers_15.jsonl` are `-- 15 7` (checked by
//! `tests/breakers.rs`). Measure with `kairos bench --plant DIR/breakers_N.ron --log
//! DIR/breakers_N.jsonl --kappa 10`.

#[path = "../tests/support/breakers.rs"]
mod breakers;

use std::process::ExitCode;

fn main() -> ExitCode {
    breakers::files::Generator {
        name: "breakers",
        count: "TRIPS",
        default_count: 7,
        valid: |n| n > 0 && (n + 1).is_power_of_two(),
        sizes: "2^d − 1 (1, 3, 7, 15, 63, 255, 1023, ...)",
        model: breakers::breaker_tree_ron,
        log: breakers::breaker_log,
    }
    .main()
}
