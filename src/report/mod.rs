//! Output for people and tools: Graphviz DOT today; the console mission log, the JSON-lines
//! trace and the SVG timeline join it with the executive (DESIGN.md §2, §12).

pub mod dot;
pub mod log;
pub mod trace;
