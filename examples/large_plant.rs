//! Prints a large generated plant model (RON) on standard output, for measuring how `kairos
//! check`, `graph`, `plan` and `estimate` scale (BENCHMARKS.md, "Loading large plants"):
//!
//! ```text
//! cargo run --release --example large_plant -- chain 10000 > /tmp/chain.ron
//! cargo run --release --example large_plant -- modes 5000 > /tmp/modes.ron
//! ```

#[path = "../tests/support/large_plant.rs"]
mod large_plant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size = args.get(1).and_then(|n| n.parse::<usize>().ok());
    let text = match (args.first().map(String::as_str), size) {
        (Some("chain"), Some(n)) => large_plant::chain(n),
        (Some("modes"), Some(n)) => large_plant::many_modes(n),
        _ => {
            eprintln!("usage: large_plant chain COMPONENTS | modes MODES");
            std::process::exit(2);
        }
    };
    print!("{text}");
}
