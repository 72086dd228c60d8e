//! Writes Livingstone 2's circuit-breaker benchmark at any size (its `cb` model and its
//! `cycle-7-8` script, generalised; `tests/support/l2_breakers.rs` describes both):
//! `cargo run --example l2_breakers -- N [CYCLES] [DIR]` writes `DIR/l2_breakers_N.ron` and
//! `DIR/l2_breakers_N.jsonl` (N = 2^d − 1 ≥ 7 breakers; default 100 cycles; default DIR `.`).
//! The shipped `models/l2_breakers_{15,63}.ron` and `tests/logs/l2_breakers_{15,63}.jsonl` are
//! `-- 15 100` and `-- 63 25` (checked by `tests/l2_breakers.rs`). Measure with
//! `kairos bench --plant DIR/l2_breakers_N.ron --log DIR/l2_breakers_N.jsonl --kappa 5 --kappa 10`.

#[path = "../tests/support/l2_breakers.rs"]
mod l2_breakers;

use std::process::ExitCode;

fn main() -> ExitCode {
    l2_breakers::files::Generator {
        name: "l2_breakers",
        count: "CYCLES",
        default_count: 100,
        valid: |n| l2_breakers::depth(n).is_some(),
        sizes: "2^d − 1 with d ≥ 3 (7, 15, 31, 63, 255, 1023, ...)",
        model: l2_breakers::model_ron,
        log: l2_breakers::log,
    }
    .main()
}
