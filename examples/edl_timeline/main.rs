//! Draws the timeline of a Mars EDL run (thesis §7.2.2) with three injected faults — a primary
//! pyro misfire at separation, a resettable PDE fault at powered descent, a touchdown-sensor
//! spike at leg deployment — driven by the hand-written lander of `lander.rs`:
//!
//! ```sh
//! cargo run --release --example edl_timeline [OUTPUT.svg]   # default: docs/timeline.svg
//! ```
//!
//! The hardware is scripted by hand and the cycles are spaced adaptively (0.1 s near activity,
//! 10 s through the cruise; about 7,900 cycles), so this is a picture of a real executive run,
//! not of the scenario runner: `kairos run SCENARIO --timeline FILE.svg` draws those with the
//! same `render`.

mod lander;

use kairos::report::timeline::{TimelineInput, render};

fn main() {
    let output = std::env::args()
        .nth(1)
        .unwrap_or_else(|| format!("{}/docs/timeline.svg", env!("CARGO_MANIFEST_DIR")));
    let run = lander::run_edl(lander::Faults::all());
    let svg = render(&TimelineInput {
        plant: run.executive.plant(),
        program: Some(run.executive.program()),
        timelines: run.executive.timelines(),
        events: &run.events,
        start: 0.0,
        end: run.end,
        title: "Mars EDL: a pyro misfire, a PDE fault and a touchdown-sensor spike",
    });
    if let Err(error) = std::fs::write(&output, svg) {
        eprintln!("cannot write {output}: {error}");
        std::process::exit(1);
    }
    println!(
        "{output}: {} cycles, {} events, {:.1} s",
        run.executive.cycles(),
        run.events.len(),
        run.end
    );
}
