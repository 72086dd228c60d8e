//! Writes a circuit-breaker tree model and its scripted replay log:
//! `cargo run --example breakers -- N [TRIPS] [DIR]` writes `DIR/breakers_N.ron` and
//! `DIR/breakers_N.jsonl` (N = 2^d − 1 breakers; default 7 trips; default DIR `.`). The shipped
//! `models/breakers_15.ron` and `tests/logs/breakers_15.jsonl` are `-- 15 7` (checked by
//! `tests/breakers.rs`). Measure with `kairos bench --plant DIR/breakers_N.ron --log
//! DIR/breakers_N.jsonl --kappa 10`.

#[path = "../tests/support/breakers.rs"]
mod breakers;

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n = args.first().and_then(|a| a.parse::<usize>().ok());
    let trips = args.get(1).map_or(Some(7), |a| a.parse::<usize>().ok());
    let dir = PathBuf::from(args.get(2).map_or(".", String::as_str));
    let (Some(n), Some(trips)) = (n, trips) else {
        eprintln!("usage: cargo run --example breakers -- N [TRIPS] [DIR]");
        return ExitCode::from(2);
    };
    if n == 0 || !(n + 1).is_power_of_two() {
        eprintln!("error: N must be 2^d − 1 (1, 3, 7, 15, 63, 255, 1023, ...), not {n}");
        return ExitCode::from(2);
    }
    let model = dir.join(format!("breakers_{n}.ron"));
    let log = dir.join(format!("breakers_{n}.jsonl"));
    let written = std::fs::write(&model, breakers::breaker_tree_ron(n))
        .and_then(|()| std::fs::write(&log, breakers::breaker_log(n, trips)));
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
