//! `kairos run SCENARIO [--trace FILE] [--timeline FILE.svg] [--report FILE.html] [--quiet]
//! [--hide-plant] [--only COMPONENT,…] [--from T] [--to T] [--seed S] [--fault F]... [--noise q]
//! [--history N] [--rerun doubt|surprise]`:
//! run a scenario
//! (DESIGN.md §11, §12) and print its mission log (`kairos::report::log`); exit 0 when every
//! expectation holds, 1 when one does not (the failed ones are listed on standard error), 2 when
//! the scenario or a file it names is bad input. The timeline picture is drawn whether or not
//! the expectations hold: a failed run is the one worth looking at.

use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::Path;

use kairos::diagnostic::did_you_mean;
use kairos::report::html::Recorder;
use kairos::report::log::{LogFilter, MissionLog};
use kairos::report::timeline::{self, InjectedFault, TimelineInput};
use kairos::report::trace::Trace;
use kairos::simulation::{self, RunError, RunOptions, RunOutcome, Scenario};

use super::Failure;
use super::model_args::ModelArgs;
use super::output::emit;
use super::window_args::WindowArgs;

/// What to run and how to show it.
pub struct RunArgs<'a> {
    /// The scenario file.
    pub scenario: &'a Path,
    /// Where to write the JSON-lines trace.
    pub trace: Option<&'a Path>,
    /// Every field of the trace on every line, not only what changed.
    pub trace_full: bool,
    /// Where to write the SVG timeline of the run.
    pub timeline: Option<&'a Path>,
    /// Where to write the interactive HTML report of the run.
    pub report: Option<&'a Path>,
    /// Print only the summary and the verdicts, not the log of cycles.
    pub quiet: bool,
    /// The model-driven plant's seed, in place of the scenario's.
    pub seed: Option<u64>,
    /// Which lines of the log to print.
    pub filter: LogFilter,
    /// The model-driven plant's forced faults and noise.
    pub model: &'a ModelArgs,
    /// Mode estimation's history window, in place of the scenario's.
    pub window: WindowArgs,
}

/// Loads and runs the scenario; the outcome is the exit code.
pub fn run(args: &RunArgs) -> Result<(), Failure> {
    let mut scenario = simulation::load(args.scenario).map_err(Failure::bad_input)?;
    let model_options = [
        ("--seed", args.seed.is_some()),
        ("--fault", !args.model.faults.is_empty()),
        ("--noise", args.model.noise.is_some()),
    ];
    if let Some((option, _)) = model_options.iter().find(|(_, given)| *given)
        && scenario.model.is_none()
    {
        return Err(Failure::bad_input(format!(
            "error: {}: {option} needs a model-driven plant (`simulator: Model(...)`)",
            args.scenario.display()
        )));
    }
    args.model.apply(&mut scenario)?;
    args.window.apply(&mut scenario);
    check_filter(&scenario, &args.filter)?;
    // Opened before the run, so that a bad path is reported before a long run, not after.
    let picture = args
        .timeline
        .map(|path| create(path).map(|file| (path, file)));
    let picture = picture.transpose()?;
    let report = args
        .report
        .map(|path| create(path).map(|file| (path, file)));
    let report = report.transpose()?;
    let mut recorder = report.as_ref().map(|_| Recorder::new());
    let (outcome, injected) = execute(&scenario, args, recorder.as_mut())?;
    if let Some((path, file)) = picture {
        draw(&scenario, &outcome, &injected, path, file)?;
    }
    if let (Some((path, file)), Some(recorder)) = (report, recorder) {
        let page = recorder.page(&scenario, &outcome, &injected);
        write_all(path, file, &page)?;
    }
    if outcome.passed() {
        return Ok(());
    }
    let failed: Vec<&str> = outcome
        .verdicts
        .iter()
        .filter(|v| !v.holds())
        .map(|v| v.label.as_str())
        .collect();
    Err(Failure::failed(format!(
        "error: scenario `{}`: {} expectation{} failed: {}",
        scenario.name,
        failed.len(),
        if failed.len() == 1 { "" } else { "s" },
        failed.join("; ")
    )))
}

/// Runs the scenario, writing the log and the trace as it goes. The returned outcome holds the
/// timelines and events a drawing of the run needs (the seam for `--timeline`), beside the
/// faults the script injected.
fn execute(
    scenario: &Scenario,
    args: &RunArgs,
    mut recorder: Option<&mut Recorder>,
) -> Result<(RunOutcome, Vec<InjectedFault>), Failure> {
    let mut injected = Vec::new();
    let mut trace = args.trace.map(create).transpose()?;
    let mut tracer = if args.trace_full {
        Trace::full()
    } else {
        Trace::changes()
    };
    let mut log = MissionLog::filtered(scenario, args.filter.clone());
    let mut printing = !args.quiet && emit(&log.header())?;
    let progress = progress_bar(scenario, args.quiet);
    let shared_terminal = !progress.is_hidden() && std::io::stdout().is_terminal();
    // The callback cannot return an error; the first one is kept and reported after the run.
    let mut problem: Option<Failure> = None;
    let options = RunOptions {
        seed: args.seed,
        ..RunOptions::default()
    };
    // A hidden bar still takes the time on every count: a quiet run does not count.
    let counting = !progress.is_hidden();
    let outcome = simulation::run(scenario, options, &mut |record| {
        if counting {
            progress.inc(1);
        }
        injected.extend(InjectedFault::of_cycle(scenario, record));
        if let Some(recorder) = recorder.as_mut() {
            recorder.cycle(scenario, record);
        }
        if printing && let Some(block) = log.cycle(record) {
            // On one terminal the bar is taken off while the log is written above it; a log
            // going elsewhere needs no redraw of the bar per block.
            let written = if shared_terminal {
                progress.suspend(|| emit(&block))
            } else {
                emit(&block)
            };
            match written {
                Ok(more) => printing = more,
                Err(e) => {
                    printing = false;
                    problem.get_or_insert(e);
                }
            }
        }
        if let Some(writer) = trace.as_mut()
            && let Err(e) = writeln!(writer, "{}", tracer.line(scenario, record))
        {
            problem.get_or_insert(Failure::io(format!("error: cannot write the trace: {e}")));
            trace = None;
        }
    })
    .map_err(|e| match e {
        RunError::Build(_) => Failure::bad_input(format!("error: {e}")),
        _ => Failure::failed(format!("error: {e}")),
    });
    progress.finish_and_clear();
    let outcome = outcome?;
    if let Some(mut writer) = trace
        && let Err(e) = writer.flush()
    {
        problem.get_or_insert(Failure::io(format!("error: cannot write the trace: {e}")));
    }
    if let Some(problem) = problem {
        return Err(problem);
    }
    emit(&log.summary(&outcome))?;
    // A model-driven plant's faults are not rules: the outcome lists them.
    injected.extend(
        outcome
            .faults
            .iter()
            .map(|f| InjectedFault::drawn(&scenario.plant, f)),
    );
    Ok((outcome, injected))
}

/// `--only` names components of the plant; `--from` is not after `--to`.
fn check_filter(scenario: &Scenario, filter: &LogFilter) -> Result<(), Failure> {
    let plant = &scenario.plant;
    let names = || plant.components().iter().map(|c| c.name());
    for name in &filter.only {
        if plant.component_named(name).is_none() {
            let hint = did_you_mean(name, names())
                .map_or_else(String::new, |known| format!(" (did you mean `{known}`?)"));
            return Err(Failure::bad_input(format!(
                "error: --only {name}: no such component in {}{hint}; expected one of: {}",
                scenario.plant_path,
                names().collect::<Vec<_>>().join(", ")
            )));
        }
    }
    if filter.from.is_nan() || filter.to.is_nan() {
        return Err(Failure::bad_input(
            "error: --from and --to expect a time in seconds, not NaN",
        ));
    }
    if filter.from > filter.to {
        return Err(Failure::bad_input(format!(
            "error: --from {} is after --to {}: no cycle would be logged",
            filter.from, filter.to
        )));
    }
    Ok(())
}

/// The progress of a run, in cycles, on standard error: hidden when standard error is not a
/// terminal (a log, a pipe, a test) or with `--quiet`, so that only a person watching sees it
/// (a long run showed nothing for minutes). indicatif redraws at most 20 times a
/// second, so counting every cycle costs nothing measurable.
fn progress_bar(scenario: &Scenario, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(scenario.cycles()), ProgressDrawTarget::stderr());
    // The template is a constant; were it refused, the default style still shows the count.
    if let Ok(style) = ProgressStyle::with_template(
        "{spinner} [{elapsed_precise}] {wide_bar} {human_pos}/{human_len} cycles (eta {eta})",
    ) {
        bar.set_style(style);
    }
    bar
}

/// Creates an output file, buffered; a path that cannot be written is bad input.
fn create(path: &Path) -> Result<BufWriter<File>, Failure> {
    File::create(path)
        .map(BufWriter::new)
        .map_err(|e| Failure::io(format!("error: cannot write {}: {e}", path.display())))
}

/// Draws the run's timeline (`kairos::report::timeline`) from the first to the last cycle.
fn draw(
    scenario: &Scenario,
    outcome: &RunOutcome,
    injected: &[InjectedFault],
    path: &Path,
    file: BufWriter<File>,
) -> Result<(), Failure> {
    let svg = timeline::render(&TimelineInput::of_run(scenario, outcome, injected));
    write_all(path, file, &svg)
}

/// Writes a whole document to its (already created) file.
fn write_all(path: &Path, mut file: BufWriter<File>, text: &str) -> Result<(), Failure> {
    file.write_all(text.as_bytes())
        .and_then(|()| file.flush())
        .map_err(|e| Failure::io(format!("error: cannot write {}: {e}", path.display())))
}
