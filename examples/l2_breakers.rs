//! Writes Livingstone 2's circuit-breaker benchmark at any size (its `cb` model and its
//! `cycle-7-8` script, generalised; `tests/support/l2_breakers.rs` describes both):
//! `cargo run --example l2_breakers -- N [CYCLES] [DIR]` writes `DIR/l2_breakers_N.ron` and
//! `DIR/l2_breakers_N.jsonl` (N = 2^d − 1 ≥ 7 breakers; default 100 cycles; default DIR `.`).
//! The shipped `models/l2_breakers_{15,63}.ron` and `tests/logs/l2_breakers_{15,63}.jsonl` are
//! `-- 15 100` and `-- 63 25` (checked by `tests/l2_breakers.rs`). Measure with
//! `kairos bench --plant DIR/l2_breakers_N.ron --log DIR/l2_breakers_N.jsonl --kappa 5 --kappa 10`.

#[path = "../tests/support/l2_breakers.rs"]
mod l2_breakers;

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n = args.first().and_then(|a| a.parse::<usize>().ok());
    let cycles = args.get(1).map_or(Some(100), |a| a.parse::<usize>().ok());
    let dir = PathBuf::from(args.get(2).map_or(".", String::as_str));
    let (Some(n), Some(cycles)) = (n, cycles) else {
        eprintln!("usage: cargo run --example l2_breakers -- N [CYCLES] [DIR]");
        return ExitCode::from(2);
    };
    if l2_breakers::depth(n).is_none() {
        eprintln!("error: N must be 2^d − 1 with d ≥ 3 (7, 15, 31, 63, 255, 1023, ...), not {n}");
        return ExitCode::from(2);
    }
    let model = dir.join(format!("l2_breakers_{n}.ron"));
    let log = dir.join(format!("l2_breakers_{n}.jsonl"));
    let written = std::fs::write(&model, l2_breakers::model_ron(n))
        .and_then(|()| std::fs::write(&log, l2_breakers::log(n, cycles)));
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
