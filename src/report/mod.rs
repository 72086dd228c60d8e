//! Output for people and tools (DESIGN.md §2, §12): Graphviz DOT drawings, the mission log and
//! the JSON-lines trace of `kairos run`, and the SVG timeline of a run, and the interactive HTML report of a run.

pub mod dot;
pub mod html;
pub mod log;
pub mod timeline;
pub mod trace;
