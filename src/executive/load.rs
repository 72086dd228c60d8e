//! Loading an executive from files in one call: the plant model and the
//! control program, each read, validated and linked, with every error located as the CLI shows
//! it. An embedder writes `Executive::load(plant, program)?.kappa(10).build()?` and is done.

use std::fmt;
use std::path::Path;

use super::{Executive, ExecutiveBuilder};
use crate::diagnostic::{ReadError, Source, SourceErrors};
use crate::plant::Plant;
use crate::rmpl::{self, LinkOptions};

/// Why [`Executive::load`] could not produce a builder.
#[derive(Debug)]
pub enum LoadError {
    /// A file could not be read, or is not UTF-8 (located).
    Read(ReadError),
    /// The plant model or the program is invalid: every problem, located.
    Invalid(Box<SourceErrors>),
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadError::Read(error) => write!(f, "{error}"),
            LoadError::Invalid(errors) => write!(f, "{errors}"),
        }
    }
}

impl std::error::Error for LoadError {}

impl From<ReadError> for LoadError {
    fn from(error: ReadError) -> Self {
        LoadError::Read(error)
    }
}

impl From<SourceErrors> for LoadError {
    fn from(errors: SourceErrors) -> Self {
        LoadError::Invalid(Box::new(errors))
    }
}

impl Executive {
    /// Reads the plant model at `plant` and the RMPL program at `program` (its first program is
    /// the entry), links the program against the plant, and returns the builder to set options
    /// on. See [`Executive`] for the whole loop.
    pub fn load(plant: &Path, program: &Path) -> Result<ExecutiveBuilder, LoadError> {
        let plant = Plant::load(&Source::read(plant)?)?;
        let options = LinkOptions {
            plant: Some(plant.table()),
            ..LinkOptions::default()
        };
        let program = rmpl::load(&Source::read(program)?, &options)?;
        Ok(Executive::builder(plant, program))
    }
}
