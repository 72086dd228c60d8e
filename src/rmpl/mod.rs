//! RMPL, the Reactive Model-based Programming Language (thesis §5.1; DESIGN.md §5.1–§5.2): its
//! syntax tree and parser, linking against a plant's variables, and compilation to a THCA for
//! the [`sequencer`](crate::sequencer). Reference for users: `docs/reference/rmpl.md`.
//!
//! ```text
//! text ──syntax::parse──► ProgramFile ──link──► LinkedProgram ──compile──► Thca
//! ```
//! [`load`] runs the three stages and renders every error against the source.

pub mod compile;
mod expand;
pub mod link;
pub mod program;
pub mod syntax;

pub use compile::compile;
pub use expand::{MAX_INLINED_DEPTH, MAX_INLINED_SIZE};
pub use link::{LinkOptions, link};
pub use program::LinkedProgram;
pub use syntax::{ProgramFile, parse};

use crate::diagnostic::{Diagnostic, Source, SourceErrors};
use crate::sequencer::Thca;

/// Parses, links and compiles the program in `source`. Every error found is reported: all the
/// syntax errors (one per broken definition) or, if the syntax is sound, all the linking errors.
pub fn load(source: &Source, options: &LinkOptions<'_>) -> Result<Thca, SourceErrors> {
    let fail = |diagnostics| SourceErrors::new(source.clone(), diagnostics);
    let file = parse(&source.text).map_err(fail)?;
    let linked = link(source, &file, options).map_err(fail)?;
    compile(&linked, source).map_err(|error| {
        fail(vec![
            Diagnostic::new(format!("internal error: {error}"), linked.span.clone())
                .expected("a program the compiler can build an automaton for"),
        ])
    })
}
