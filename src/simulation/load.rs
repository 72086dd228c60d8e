//! Loading a scenario: the scenario file, the scripts it includes, the plant model and the
//! program, each problem located in the file it is in (DESIGN.md §13).

use std::path::Path;
use std::time::Duration;

use super::format::{ScenarioFile, ScriptFile, ScriptParts};
use super::script::Script;
use super::{Scenario, ScenarioProgram};
use crate::diagnostic::locate::{Entries, Locator, Step};
use crate::diagnostic::{
    Diagnostic, ReadError, Source, SourceErrors, Span, did_you_mean, ron_error,
};
use crate::diagnostic::{LoadErrors, resolve_path};
use crate::estimation::{DEFAULT_HISTORY, MAX_HISTORY};
use crate::executive::{CHATTER_CYCLES, ScheduledMission};
use crate::goalnet::{display, mission};
use crate::logic::{self, Formula, ValueId, VarId, VarTable};
use crate::plant::{ComponentId, Plant};
use crate::reconfiguration::Reconfiguration;
use crate::rmpl::{self, LinkOptions};

/// κ when the scenario does not say.
pub const DEFAULT_KAPPA: usize = 10;

/// The most cycles a scenario may run (`end / cycle`): ten million, 58 times the nominal Mars
/// EDL (171,577 cycles) and about five minutes at its pace. A longer run ran silently for hours
/// (`cycle: 1e-8, end: 10` is 10⁹ cycles); it is refused at `end` with the count and
/// the time it would take.
pub const MAX_CYCLES: u64 = 10_000_000;

/// The wall time of a cycle used to say how long a refused run would take: the nominal Mars EDL's
/// (5.4 s for 171,577 cycles of a release build on the benchmark machine, BENCHMARKS.md). A
/// rough figure: it depends on the plant and the program.
const CYCLE_PACE_SECONDS: f64 = 31e-6;

/// One file being read: its text, its outline and the problems found in it.
pub(super) struct FileCtx {
    pub(super) source: Source,
    pub(super) locate: Locator,
    pub(super) errors: Vec<Diagnostic>,
}

impl FileCtx {
    fn new(source: Source) -> Self {
        FileCtx {
            locate: Locator::new(&source.text),
            source,
            errors: Vec::new(),
        }
    }

    /// Records a problem at the value at `path`.
    pub(super) fn error(&mut self, path: &[Step], message: impl Into<String>, expected: &str) {
        let span = self.locate.at(path);
        self.errors
            .push(Diagnostic::new(message, span).expected(expected));
    }

    /// Records a diagnostic built by the caller.
    pub(super) fn push(&mut self, diagnostic: Diagnostic) {
        self.errors.push(diagnostic);
    }

    /// The span of the value at `path`.
    pub(super) fn span(&self, path: &[Step]) -> Span {
        self.locate.at(path)
    }

    fn finish(self, all: &mut Vec<SourceErrors>) {
        if !self.errors.is_empty() {
            all.push(SourceErrors::new(self.source, self.errors));
        }
    }
}

/// Which variables a formula may mention.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Vars {
    /// The plant's controls (command triggers and expectations).
    Controls,
    /// Component mode variables (estimate triggers and expectations: ŝ assigns modes only).
    Modes,
    /// Observables and hidden variables (rule conditions: what the scripted plant holds).
    Held,
    /// Any plant variable (goals).
    Plant,
}

/// Reads the scenario at `path`.
pub fn load(path: &Path) -> Result<Scenario, LoadErrors> {
    let source = Source::read(path)?;
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    load_source(&source, &dir)
}

/// Reads a scenario from its text; relative paths in it are relative to `dir`.
pub fn load_source(source: &Source, dir: &Path) -> Result<Scenario, LoadErrors> {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let file: ScenarioFile = options.from_str(&source.text).map_err(|e| {
        LoadErrors::Invalid(vec![SourceErrors::new(
            source.clone(),
            vec![ron_error(source, &e)],
        )])
    })?;
    let mut all = Vec::new();
    let mut ctx = FileCtx::new(source.clone());
    let settings = settings(&mut ctx, &file);
    let Some((plant, program, paths)) = model_and_program(&mut ctx, &file, dir, &mut all) else {
        ctx.finish(&mut all);
        return Err(LoadErrors::Invalid(all));
    };
    let mut includes = read_includes(&mut ctx, &file, dir, &mut all);
    let mut parts: Vec<(&mut FileCtx, ScriptParts<'_>)> = includes
        .iter_mut()
        .map(|(ctx, script)| (ctx, script.script()))
        .collect();
    parts.push((&mut ctx, file.script()));
    // Every rule the files declare, those that did not load included: an expectation that
    // names one of them is not a second error.
    let declared: Vec<String> = (parts.iter())
        .flat_map(|(_, part)| part.rules.iter().map(|rule| rule.name.clone()))
        .collect();
    let mission = program.mission().map(|m| m.mission());
    let mut script = super::load_script::script(&plant, mission, &mut parts, settings.end);
    drop(parts);
    script.pinned = super::load_script::pinned(&mut ctx, &file.choose, &script);
    script.deliveries = super::load_deliver::deliveries(
        &mut ctx,
        &file.deliver,
        &script,
        (settings.cycle, settings.end),
    );
    let model = super::load_model::model_config(&mut ctx, &file, &plant, settings.end);
    let believed = believed(&mut ctx, &file.believed, &plant);
    let expectations = super::load_expect::expectations(
        &mut ctx,
        &file.expect,
        &plant,
        &program,
        (&script, &declared),
        settings.end,
    );
    for (include, _) in includes {
        include.finish(&mut all);
    }
    ctx.finish(&mut all);
    if !all.is_empty() {
        return Err(LoadErrors::Invalid(all));
    }
    let name = file.name.clone().unwrap_or_else(|| {
        Path::new(&source.name)
            .file_stem()
            .map_or_else(|| source.name.clone(), |s| s.to_string_lossy().to_string())
    });
    Ok(Scenario {
        name,
        description: file.description.clone(),
        source: source.clone(),
        plant_path: paths.0,
        program_source: paths.1,
        entry: file.entry.clone(),
        plant,
        program,
        cycle: settings.cycle,
        end: settings.end,
        kappa: settings.kappa,
        history: settings.history,
        rerun: file.rerun.unwrap_or_default(),
        chatter_cycles: settings.chatter_cycles,
        deadline: settings.deadline,
        script,
        model,
        expectations,
        believed,
    })
}

/// The scenario's `believed`: each name a component, each value one of its modes.
fn believed(
    ctx: &mut FileCtx,
    believed: &Entries<String>,
    plant: &Plant,
) -> Vec<(ComponentId, ValueId)> {
    let mut out = Vec::new();
    for (name, mode) in &believed.0 {
        let Some(c) = plant.component_named(name) else {
            let names = plant.components().iter().map(|c| c.name());
            let mut diagnostic = Diagnostic::new(
                format!("no component `{name}`"),
                ctx.span(&[Step::Field("believed"), Step::Key(name)]),
            )
            .expected("the name of a component of the plant model");
            if let Some(close) = did_you_mean(name, names) {
                diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
            }
            ctx.push(diagnostic);
            continue;
        };
        let component = plant.component(c);
        match component.mode_named(mode) {
            Some(m) => out.push((c, m)),
            None => {
                let modes: Vec<&str> = component.modes().iter().map(|m| m.name.as_str()).collect();
                ctx.push(
                    Diagnostic::new(
                        format!("`{mode}` is not a mode of {name}"),
                        ctx.span(&[Step::Field("believed"), Step::Value(name)]),
                    )
                    .expected(format!("one of {name}'s modes: {}", modes.join(", "))),
                );
            }
        }
    }
    out
}

/// The run's numbers, checked.
struct Settings {
    cycle: f64,
    end: f64,
    kappa: usize,
    history: usize,
    chatter_cycles: u64,
    deadline: Option<Duration>,
}

fn settings(ctx: &mut FileCtx, file: &ScenarioFile) -> Settings {
    let mut cycle = file.cycle;
    if !(cycle.is_finite() && cycle > 0.0) {
        ctx.error(
            &[Step::Field("cycle")],
            format!("cycle period {cycle} is not a positive number of seconds"),
            "a period in seconds greater than 0, such as 0.1",
        );
        cycle = 1.0;
    }
    let mut end = file.end;
    if !(end.is_finite() && end >= 0.0) {
        ctx.error(
            &[Step::Field("end")],
            format!("end time {end} is not a time"),
            "the time the run stops, in seconds (0 or more)",
        );
        end = 0.0;
    } else if super::cycle_count(end, cycle) > MAX_CYCLES as f64 {
        too_many_cycles(ctx, end, cycle);
    }
    let kappa = match file.kappa {
        None => DEFAULT_KAPPA,
        Some(k) if k >= 1 => usize::try_from(k).unwrap_or(usize::MAX),
        Some(k) => {
            ctx.error(
                &[Step::Field("kappa")],
                format!("κ = {k} tracks no state"),
                "the number of system states mode estimation tracks, at least 1",
            );
            DEFAULT_KAPPA
        }
    };
    let history = match file
        .history
        .map(|n| usize::try_from(n).ok().filter(|&n| n <= MAX_HISTORY))
    {
        None => DEFAULT_HISTORY,
        Some(Some(n)) => n,
        Some(None) => {
            let n = file.history.unwrap_or_default();
            ctx.error(
                &[Step::Field("history")],
                format!("a history window of {n} steps is out of range"),
                &format!(
                    "the number of recent steps mode estimation keeps to estimate again, 0 (none) \
                     to {MAX_HISTORY}"
                ),
            );
            DEFAULT_HISTORY
        }
    };
    let chatter_cycles = match file.chatter_cycles {
        None => CHATTER_CYCLES,
        Some(n) if n >= 1 => u64::try_from(n).unwrap_or(u64::MAX),
        Some(n) => {
            ctx.error(
                &[Step::Field("chatter_cycles")],
                format!("a chatter window of {n} cycles sees no return"),
                "the number of cycles within which a command back into a mode left is chatter, \
                 at least 1",
            );
            CHATTER_CYCLES
        }
    };
    let deadline = file.deadline.and_then(|d| {
        // `try_from_secs_f64`, not `from_secs_f64`: a deadline past `Duration::MAX` (1e20 s)
        // panics in the latter.
        let duration = Duration::try_from_secs_f64(d).ok().filter(|d| !d.is_zero());
        if duration.is_none() {
            let problem = if !(d.is_finite() && d > 0.0) {
                format!("{d} is not a positive number of seconds")
            } else if d < 1.0 {
                format!("{d:e} s is shorter than a nanosecond")
            } else {
                format!("{d:e} s is longer than any duration (at most about 1.8e19 s)")
            };
            ctx.error(
                &[Step::Field("deadline")],
                format!("cycle deadline {problem}"),
                "a wall-time budget per cycle in seconds, such as 0.05",
            );
        }
        duration
    });
    Settings {
        cycle,
        end,
        kappa,
        history,
        chatter_cycles,
        deadline,
    }
}

/// The error for a run of more than [`MAX_CYCLES`] cycles, at `end`, with where `cycle` is.
fn too_many_cycles(ctx: &mut FileCtx, end: f64, cycle: f64) {
    let cycles = super::cycle_count(end, cycle);
    let (line, col) = ctx.source.line_col(ctx.span(&[Step::Field("cycle")]).start);
    let diagnostic = Diagnostic::new(
        format!(
            "{end} s at {cycle} s per cycle is {cycles:.3e} cycles, more than the {MAX_CYCLES} a \
             scenario may run: about {} at the Mars EDL's pace",
            rough_duration(cycles * CYCLE_PACE_SECONDS)
        ),
        ctx.span(&[Step::Field("end")]),
    )
    .expected(format!(
        "an end time and a cycle period giving at most {MAX_CYCLES} cycles"
    ))
    .note(format!(
        "the cycle period is set at line {line}, column {col}"
    ));
    ctx.push(diagnostic);
}

/// A duration in the largest unit that keeps it at least 1 (`8.6 hours`, `12 days`).
fn rough_duration(seconds: f64) -> String {
    const UNITS: [(f64, &str); 5] = [
        (365.25 * 86_400.0, "years"),
        (86_400.0, "days"),
        (3_600.0, "hours"),
        (60.0, "minutes"),
        (1.0, "seconds"),
    ];
    let (size, name) = UNITS
        .into_iter()
        .find(|&(size, _)| seconds >= size)
        .unwrap_or(UNITS[4]);
    let amount = seconds / size;
    if amount >= 1e6 {
        format!("{amount:.1e} {name}")
    } else {
        format!("{amount:.1} {name}")
    }
}

/// Reads a file named at `path` in the scenario; an unreadable file is an error there, one that
/// is not UTF-8 an error in that file (at its first invalid byte).
fn read_named(
    ctx: &mut FileCtx,
    path: &[Step],
    dir: &Path,
    name: &str,
    all: &mut Vec<SourceErrors>,
) -> Option<Source> {
    let resolved = resolve_path(dir, name);
    match Source::read(&resolved) {
        Ok(source) => Some(source),
        Err(ReadError::Io { error, .. }) => {
            ctx.error(
                path,
                format!("cannot read `{}`: {error}", resolved.display()),
                "a path relative to the scenario file",
            );
            None
        }
        Err(ReadError::NotUtf8(errors)) => {
            all.push(*errors);
            None
        }
    }
}

type Loaded = (Plant, ScenarioProgram, (String, Source));

/// Loads the plant model and the control program: the RMPL program linked against the plant,
/// or the mission bound to it, scheduled. Exactly one of `program` and `mission` is given.
fn model_and_program(
    ctx: &mut FileCtx,
    file: &ScenarioFile,
    dir: &Path,
    all: &mut Vec<SourceErrors>,
) -> Option<Loaded> {
    let plant_source = read_named(ctx, &[Step::Field("plant")], dir, &file.plant, all);
    let program_name = match (&file.program, &file.mission) {
        (Some(_), Some(_)) => {
            ctx.error(
                &[Step::Field("mission")],
                "a scenario runs an RMPL program or a mission, and this one names both",
                "either `program: \"file.rmpl\"` or `mission: \"file.ron\"`, not both",
            );
            None
        }
        (None, None) => {
            ctx.error(
                &[],
                "the scenario names no control program",
                "`program: \"file.rmpl\"` (RMPL) or `mission: \"file.ron\"` (a goal network)",
            );
            None
        }
        (Some(program), None) => Some(program),
        (None, Some(_)) => None,
    };
    let program_source =
        program_name.and_then(|name| read_named(ctx, &[Step::Field("program")], dir, name, all));
    let plant = match Plant::load(&plant_source?) {
        Ok(plant) => plant,
        Err(errors) => {
            all.push(errors);
            return None;
        }
    };
    let plant_path = resolve_path(dir, &file.plant).display().to_string();
    if let (None, Some(mission)) = (&file.program, &file.mission) {
        let (program, source) = load_mission(ctx, dir, mission, &plant, &plant_path, all)?;
        return Some((plant, program, (plant_path, source)));
    }
    let program_source = program_source?;
    let options = LinkOptions {
        entry: file.entry.as_deref(),
        plant: Some(plant.table()),
    };
    match rmpl::load(&program_source, &options) {
        Ok(program) => Some((
            plant,
            ScenarioProgram::Rmpl(Box::new(program)),
            (plant_path, program_source),
        )),
        Err(errors) => {
            all.push(errors);
            None
        }
    }
}

/// Loads the mission named at `mission`, checks it binds to the scenario's plant model and
/// schedules its network from the plant's most likely initial modes; every problem is located
/// (in the mission file, or at `mission` in the scenario).
fn load_mission(
    ctx: &mut FileCtx,
    dir: &Path,
    name: &str,
    plant: &Plant,
    plant_path: &str,
    all: &mut Vec<SourceErrors>,
) -> Option<(ScenarioProgram, Source)> {
    let at = [Step::Field("mission")];
    let loaded = match mission::load(&resolve_path(dir, name)) {
        Ok(loaded) => loaded,
        Err(LoadErrors::Unreadable(message)) => {
            let message = message
                .strip_prefix("error: ")
                .unwrap_or(&message)
                .to_string();
            ctx.error(
                &at,
                message,
                "a path to a mission file, relative to the scenario file",
            );
            return None;
        }
        Err(LoadErrors::Invalid(errors)) => {
            all.extend(errors);
            return None;
        }
    };
    if loaded.plant_path != plant_path {
        ctx.error(
            &at,
            format!(
                "the mission binds to the plant model `{}`, the scenario to `{plant_path}`",
                loaded.plant_path
            ),
            "a mission bound to the scenario's plant model",
        );
        return None;
    }
    let reconfiguration = match Reconfiguration::compile(plant) {
        Ok(reconfiguration) => reconfiguration,
        Err(e) => {
            ctx.error(
                &at,
                format!("the plant model cannot be encoded: {e}"),
                "a plant model",
            );
            return None;
        }
    };
    let (source, network) = (loaded.source.clone(), loaded.network.clone());
    match ScheduledMission::schedule(loaded, &reconfiguration) {
        Ok(scheduled) => Some((ScenarioProgram::Mission(Box::new(scheduled)), source)),
        Err(error) => {
            let why = display::explain(&error, &network, plant);
            ctx.push(
                Diagnostic::new(
                    "the mission's goal network cannot be scheduled",
                    ctx.span(&at),
                )
                .expected("a mission whose network schedules from the plant's initial state")
                .note(why),
            );
            None
        }
    }
}

/// Reads the included scripts (errors in them are theirs).
fn read_includes(
    ctx: &mut FileCtx,
    file: &ScenarioFile,
    dir: &Path,
    all: &mut Vec<SourceErrors>,
) -> Vec<(FileCtx, ScriptFile)> {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let mut out = Vec::new();
    for (i, name) in file.include.iter().enumerate() {
        let path = [Step::Field("include"), Step::Index(i)];
        let Some(source) = read_named(ctx, &path, dir, name, all) else {
            continue;
        };
        match options.from_str::<ScriptFile>(&source.text) {
            Ok(script) => out.push((FileCtx::new(source), script)),
            Err(e) => {
                let diagnostic = ron_error(&source, &e);
                all.push(SourceErrors::new(source, vec![diagnostic]));
            }
        }
    }
    out
}

/// Parses and resolves the formula written at `path` of `ctx`'s file and checks which
/// variables it mentions; `None` (errors recorded) when it does not fit.
pub(super) fn formula(
    ctx: &mut FileCtx,
    path: &[Step],
    text: &str,
    table: &VarTable,
    allowed: Vars,
    classes: &VarClasses,
) -> Option<Formula> {
    let offset = ctx.span(path).start;
    let resolved = logic::syntax::parse_at(text, offset)
        .map_err(|d| vec![d])
        .and_then(|expr| logic::resolve(&expr, table));
    let formula = match resolved {
        Ok(formula) => formula,
        Err(diagnostics) => {
            diagnostics.into_iter().for_each(|d| ctx.push(d));
            return None;
        }
    };
    let span = offset..offset + text.len();
    if formula.has_external_atoms() {
        ctx.push(
            Diagnostic::new(
                "a clock or a confidence `P(...)` cannot be tested here",
                span,
            )
            .expected(allowed.expected()),
        );
        return None;
    }
    let wrong: Vec<VarId> = formula
        .variables()
        .into_iter()
        .filter(|&v| !classes.allows(allowed, v))
        .collect();
    if let Some(&var) = wrong.first() {
        let name = table.variable(var).name();
        let mut diagnostic =
            Diagnostic::new(format!("`{name}` is {}", classes.describe(var)), span)
                .expected(allowed.expected());
        let known = classes.names(allowed, table);
        if let Some(close) = did_you_mean(name, known.iter().map(String::as_str)) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        ctx.push(diagnostic);
        return None;
    }
    Some(formula)
}

impl Vars {
    fn expected(self) -> &'static str {
        match self {
            Vars::Controls => "a formula over the plant's controls (the commands it accepts)",
            Vars::Modes => "a formula over component modes (`engine = firing`): ŝ assigns modes",
            Vars::Held => {
                "a formula over the plant's observables and the script's hidden variables"
            }
            Vars::Plant => "a formula over the plant's variables",
        }
    }
}

/// What each variable of the scenario's world is.
pub(super) struct VarClasses {
    controls: Vec<VarId>,
    modes: Vec<VarId>,
    observables: Vec<VarId>,
    /// The observables the plant model monitors (they may hold readings).
    numeric: Vec<VarId>,
    hidden: Vec<VarId>,
    plant_vars: usize,
}

impl VarClasses {
    pub(super) fn new(plant: &Plant, hidden: Vec<VarId>) -> Self {
        VarClasses {
            controls: plant.controls().iter().map(|c| c.var).collect(),
            modes: plant.components().iter().map(|c| c.mode_var()).collect(),
            observables: reported(plant),
            numeric: plant.monitors().iter().map(|m| m.observable).collect(),
            hidden,
            plant_vars: plant.table().len(),
        }
    }

    fn allows(&self, allowed: Vars, var: VarId) -> bool {
        match allowed {
            Vars::Controls => self.controls.contains(&var),
            Vars::Modes => self.modes.contains(&var),
            Vars::Held => self.observables.contains(&var) || self.hidden.contains(&var),
            Vars::Plant => var.index() < self.plant_vars,
        }
    }

    fn describe(&self, var: VarId) -> &'static str {
        if self.controls.contains(&var) {
            "a control (a command the executive sends)"
        } else if self.modes.contains(&var) {
            "a component's mode, which the plant does not report (its observables show it)"
        } else if self.observables.contains(&var) {
            "an observable (test it in a rule's `when`)"
        } else if self.hidden.contains(&var) {
            "a hidden variable of the script"
        } else {
            "an attribute the plant does not report (not an observable)"
        }
    }

    fn names(&self, allowed: Vars, table: &VarTable) -> Vec<String> {
        table
            .variables()
            .filter(|(id, _)| self.allows(allowed, *id))
            .map(|(_, v)| v.name().to_string())
            .collect()
    }

    /// True for observables.
    pub(super) fn is_observable(&self, var: VarId) -> bool {
        self.observables.contains(&var)
    }

    /// True for the observables the plant model monitors.
    pub(super) fn is_numeric(&self, var: VarId) -> bool {
        self.numeric.contains(&var)
    }

    /// True for hidden variables.
    pub(super) fn is_hidden(&self, var: VarId) -> bool {
        self.hidden.contains(&var)
    }
}

/// What a scripted plant may report: the observables, then the acknowledgement observables.
fn reported(plant: &Plant) -> Vec<VarId> {
    (plant.observables().iter().copied())
        .chain(plant.acknowledgements().iter().map(|a| a.observable))
        .collect()
}

/// Makes an empty script for a plant (used before anything is declared).
pub(super) fn empty_script(plant: &Plant) -> Script {
    Script {
        world: plant.table().clone(),
        observables: reported(plant),
        controls: plant.controls().iter().map(|c| (c.var, c.idle)).collect(),
        modes: plant.components().iter().map(|c| c.mode_var()).collect(),
        hidden: Vec::new(),
        initial: Vec::new(),
        rules: Vec::new(),
        pinned: Vec::new(),
        deliveries: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimation::Rerun;
    use crate::logic::ValueId;
    use crate::simulation::Held;
    use crate::simulation::testing::engine_camera;

    #[test]
    fn paths_read_as_a_person_writes_them() {
        let dir = Path::new("scenarios/propulsion");
        assert_eq!(
            resolve_path(dir, "../../models/propulsion.ron"),
            Path::new("models/propulsion.ron")
        );
        assert_eq!(
            resolve_path(dir, "./plant.ron"),
            Path::new("scenarios/propulsion/plant.ron")
        );
        assert_eq!(
            resolve_path(Path::new(""), "../x.ron"),
            Path::new("../x.ron")
        );
    }

    /// Mode estimation's history window and its re-runs are the scenario's to choose, and reach
    /// the executive.
    #[test]
    fn the_history_window_is_a_setting() {
        let scenario = engine_camera("history: 0, rerun: Surprise");
        assert_eq!((scenario.history, scenario.rerun), (0, Rerun::Surprise));
        let executive =
            crate::simulation::run::build(&scenario, Default::default()).expect("builds");
        let options = executive.options();
        assert_eq!((options.history, options.rerun), (0, Rerun::Surprise));
    }

    /// A scenario without `name` is named after its file; κ and the chatter window default;
    /// hidden variables start at their first value.
    #[test]
    fn defaults() {
        let scenario = engine_camera(r#"hidden: { "weather": ["calm", "storm"] }"#);
        assert_eq!(scenario.name, "test");
        assert_eq!(scenario.kappa, DEFAULT_KAPPA);
        assert_eq!(scenario.history, DEFAULT_HISTORY);
        assert_eq!(scenario.rerun, Rerun::Doubt);
        assert_eq!(scenario.chatter_cycles, CHATTER_CYCLES);
        assert_eq!(scenario.deadline, None);
        let weather = scenario.script.hidden()[0];
        assert_eq!(
            scenario.script.initial(),
            [(weather, Held::Value(ValueId(0)))]
        );
    }

    /// Numbers out of range are located errors, all of them reported together.
    #[test]
    fn bad_numbers_are_reported_together() {
        let text = "Scenario(program: \"programs/engine_burn.rmpl\", \
                    plant: \"models/engine_camera.ron\", cycle: 0.0, end: -1.0, kappa: 0, \
                    history: -1, chatter_cycles: 0, deadline: -0.5)";
        let errors = load_source(
            &Source::new("bad.ron", text),
            Path::new(env!("CARGO_MANIFEST_DIR")),
        )
        .expect_err("invalid")
        .to_string();
        for expected in [
            "cycle period 0 is not a positive number of seconds",
            "end time -1 is not a time",
            "κ = 0 tracks no state",
            "a history window of -1 steps",
            "a chatter window of 0 cycles sees no return",
            "cycle deadline -0.5 is not a positive number of seconds",
        ] {
            assert!(
                errors.contains(expected),
                "missing `{expected}` in {errors}"
            );
        }
    }
}
