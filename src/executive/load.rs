//! Loading an executive from files in one call: the plant model and the control program — an
//! RMPL program, or a mission (which names its plant model) — each read, validated, linked or
//! scheduled, with every error located as the CLI shows it. An embedder writes
//! `Executive::load(plant, program)?.kappa(10).build()?` or
//! `Executive::load_mission(mission)?.build()?` and is done; the builder keeps the program's
//! text, so the executive's events name their source lines ([`Event::named`]).
//!
//! [`Event::named`]: super::Event::named

use std::fmt;
use std::path::Path;

use super::{Executive, ExecutiveBuilder, ScheduledMission};
use crate::diagnostic::{LoadErrors, ReadError, Source, SourceErrors};
use crate::goalnet::{display, mission};
use crate::opsat::TheoryError;
use crate::plant::Plant;
use crate::reconfiguration::Reconfiguration;
use crate::rmpl::{self, LinkOptions};

/// Why [`Executive::load`] or [`Executive::load_mission`] could not produce a builder.
#[derive(Debug)]
pub enum LoadError {
    /// A file could not be read, or is not UTF-8 (located).
    Read(ReadError),
    /// A file named by another (the plant model a mission names) could not be read: the
    /// message names it.
    Unreadable(String),
    /// The files are invalid: every problem, located, grouped by file (the plant model, the
    /// program or mission).
    Invalid(Vec<SourceErrors>),
    /// The plant model cannot be encoded for reasoning (too large a constraint).
    Encoding(TheoryError),
    /// The mission's goal network cannot be scheduled from the plant's most likely initial
    /// state: why, with the evidence.
    NotScheduled(String),
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadError::Read(error) => write!(f, "{error}"),
            LoadError::Unreadable(message) => f.write_str(message),
            LoadError::Invalid(files) => {
                for (i, errors) in files.iter().enumerate() {
                    if i > 0 {
                        writeln!(f)?;
                    }
                    write!(f, "{errors}")?;
                }
                Ok(())
            }
            LoadError::Encoding(error) => {
                write!(f, "error: the plant model cannot be encoded: {error}")
            }
            LoadError::NotScheduled(why) => {
                write!(
                    f,
                    "error: the mission's goal network cannot be scheduled: {why}"
                )
            }
        }
    }
}

impl std::error::Error for LoadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            LoadError::Read(error) => Some(error),
            LoadError::Encoding(error) => Some(error),
            LoadError::Unreadable(_) | LoadError::Invalid(_) | LoadError::NotScheduled(_) => None,
        }
    }
}

impl From<ReadError> for LoadError {
    fn from(error: ReadError) -> Self {
        LoadError::Read(error)
    }
}

impl From<SourceErrors> for LoadError {
    fn from(errors: SourceErrors) -> Self {
        LoadError::Invalid(vec![errors])
    }
}

impl From<LoadErrors> for LoadError {
    fn from(errors: LoadErrors) -> Self {
        match errors {
            LoadErrors::Unreadable(message) => LoadError::Unreadable(message),
            LoadErrors::Invalid(files) => LoadError::Invalid(files),
        }
    }
}

impl Executive {
    /// Reads the plant model at `plant` and the RMPL program at `program` (its first program is
    /// the entry), links the program against the plant, and returns the builder to set options
    /// on. See [`Executive`] for the whole loop.
    pub fn load(plant: &Path, program: &Path) -> Result<ExecutiveBuilder, LoadError> {
        Executive::load_source(Source::read(plant)?, Source::read(program)?)
    }

    /// [`Executive::load`] from texts already in memory (an embedder that keeps its model in
    /// flash, or receives it over a link): each [`Source`]'s name is what errors point at.
    pub fn load_source(plant: Source, program: Source) -> Result<ExecutiveBuilder, LoadError> {
        let plant = Plant::load(&plant)?;
        let options = LinkOptions {
            plant: Some(plant.table()),
            ..LinkOptions::default()
        };
        let program_thca = rmpl::load(&program, &options)?;
        Ok(Executive::builder(plant, program_thca).source(program))
    }

    /// Reads the mission at `mission` and the plant model it names (relative to the mission's
    /// directory), checks both, schedules the mission's goal network from the plant's most
    /// likely initial state (DESIGN.md §15.2), and returns the builder to set options on.
    pub fn load_mission(mission: &Path) -> Result<ExecutiveBuilder, LoadError> {
        let dir = mission.parent().unwrap_or(Path::new(""));
        Executive::load_mission_source(&Source::read(mission)?, dir)
    }

    /// [`Executive::load_mission`] from the mission's text in memory; the plant model it names
    /// is read from disk, relative to `dir`.
    pub fn load_mission_source(
        mission: &Source,
        dir: &Path,
    ) -> Result<ExecutiveBuilder, LoadError> {
        let mission = mission::load_source(mission, dir)?;
        let reconfiguration =
            Reconfiguration::compile(&mission.plant).map_err(LoadError::Encoding)?;
        let (plant, source, network) = (
            mission.plant.clone(),
            mission.source.clone(),
            mission.network.clone(),
        );
        let scheduled = ScheduledMission::schedule(mission, &reconfiguration)
            .map_err(|error| LoadError::NotScheduled(display::explain(&error, &network, &plant)))?;
        Ok(Executive::builder(plant, scheduled).source(source))
    }
}
