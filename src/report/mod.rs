//! Output for people and tools: Graphviz DOT and the SVG timeline of a run today; the console
//! mission log and the JSON-lines trace join them with the executive (DESIGN.md §2, §12).

pub mod dot;
pub mod timeline;
