//! Output for people and tools (DESIGN.md §2, §12): the mission log and the JSON-lines trace of
//! `kairos run`, the SVG timeline of a run, and the interactive HTML report of a run. (Graphviz
//! drawings go through [`crate::dot`], below every layer that draws.)

pub mod html;
pub mod log;
pub mod timeline;
pub mod trace;
