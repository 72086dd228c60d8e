//! Prints a generated goal-network workload on standard output, for measuring how `kairos
//! schedule` and submissions to a running mission scale with the number of goals
//! (tests/support/goal_workload.rs describes them):
//!
//! ```text
//! cargo run --release --example goal_workload -- mission knowledge 1000 > /tmp/m.ron
//! kairos schedule /tmp/m.ron
//! cargo run --release --example goal_workload -- scenario knowledge 300 > /tmp/s.ron
//! kairos run /tmp/s.ron
//! ```
//!
//! Kinds: `knowledge`, `maintain`, `transition`. The files name the crate's models by absolute
//! path, so they may be written anywhere.

#[path = "../tests/support/goal_workload.rs"]
mod goal_workload;

use goal_workload::Kind;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let kind = args.get(1).and_then(|k| Kind::named(k));
    let size = args.get(2).and_then(|n| n.parse::<usize>().ok());
    let text = match (args.first().map(String::as_str), kind, size) {
        (Some("mission"), Some(kind), Some(n)) => goal_workload::mission(n, kind),
        (Some("scenario"), Some(kind), Some(n)) => goal_workload::scenario(n, kind),
        _ => {
            eprintln!("usage: goal_workload mission|scenario knowledge|maintain|transition GOALS");
            std::process::exit(2);
        }
    };
    print!("{text}");
}
