//! `kairos campaign SCENARIO --runs N --seed S [--jobs J] [--shard i/n] [--out DIR] [--fault F]...
//! [--noise q]`: a Monte
//! Carlo campaign of a scenario with a model-driven plant (`kairos::campaign`), and
//! `kairos campaign merge DIR... [--out DIR]`, which joins the shards of one.
//!
//! With `--out`, the directory receives `runs.jsonl` (one [`RunRecord`] per line, by run index),
//! `summary.txt` and `campaign.svg`; the summary is printed in any case. Exit 0 when every run
//! passed, 1 when one did not (its seed replays it: `kairos run SCENARIO --seed SEED`), 2 on bad
//! input.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use kairos::campaign::{self, RunRecord, RunVerdict, Summary, plot};
use kairos::simulation;

use super::Failure;
use super::model_args::ModelArgs;
use super::output::emit;

/// `kairos campaign`'s arguments.
#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct CampaignArgs {
    /// Join shards instead of running.
    #[command(subcommand)]
    pub merge: Option<MergeCommand>,
    /// The scenario (it needs `simulator: Model(...)`).
    #[arg(required = true)]
    pub scenario: Option<PathBuf>,
    /// How many runs in the whole campaign (all shards).
    #[arg(long, required = true)]
    pub runs: Option<u64>,
    /// The campaign's seed; run i plays the plant seed derived from (seed, i).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Threads (default: one per core).
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Run only shard i of n (the runs whose index is i modulo n), such as `--shard 3/100`.
    #[arg(long, value_name = "i/n", value_parser = parse_shard)]
    pub shard: Option<(u64, u64)>,
    /// Write runs.jsonl, summary.txt and campaign.svg in this directory.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Every run's forced faults and noise.
    #[command(flatten)]
    pub model: ModelArgs,
}

/// `kairos campaign merge`.
#[derive(clap::Subcommand)]
pub enum MergeCommand {
    /// Join the `runs.jsonl` of shard directories and summarise the whole campaign.
    Merge {
        /// The shards' output directories.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Write the merged runs.jsonl, summary.txt and campaign.svg here.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// The campaign's name in the summary and on the picture (the records do not carry
        /// the scenario's).
        #[arg(long, default_value = "campaign")]
        title: String,
    },
}

/// `i/n` with `i < n`.
fn parse_shard(text: &str) -> Result<(u64, u64), String> {
    let bad = || format!("`{text}` is not a shard `i/n` with 0 ≤ i < n, such as 0/4");
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (u64, u64) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if i < n { Ok((i, n)) } else { Err(bad()) }
}

/// Runs the subcommand.
pub fn run(args: &CampaignArgs) -> Result<(), Failure> {
    if let Some(MergeCommand::Merge { dirs, out, title }) = &args.merge {
        return merge(dirs, title, out.as_deref());
    }
    let (Some(path), Some(runs)) = (&args.scenario, args.runs) else {
        return Err(Failure::bad_input(
            "error: kairos campaign needs SCENARIO and --runs",
        ));
    };
    let mut scenario = simulation::load(path).map_err(Failure::bad_input)?;
    if scenario.model.is_none() {
        return Err(Failure::bad_input(format!(
            "error: {}: a campaign needs a model-driven plant (`simulator: Model(...)`)",
            path.display()
        )));
    }
    args.model.apply(&mut scenario)?;
    if let Some(out) = &args.out {
        std::fs::create_dir_all(out).map_err(|e| {
            Failure::bad_input(format!("error: cannot create {}: {e}", out.display()))
        })?;
    }
    let (shard, shards) = args.shard.unwrap_or((0, 1));
    let indices: Vec<u64> = (0..runs).filter(|i| i % shards == shard).collect();
    let progress = progress_bar(indices.len() as u64);
    let started = Instant::now();
    let records = campaign::run_campaign(&scenario, args.seed, &indices, args.jobs, &|| {
        progress.inc(1);
    })
    .map_err(|e| Failure::failed(format!("error: cannot start the threads: {e}")))?;
    progress.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    let header = format!(
        "campaign `{}`: {} runs (seed {}, shard {shard}/{shards}) in {wall:.1} s, {:.2} runs/s\n\
         replay a run: kairos run {}{} --seed SEED\n",
        scenario.name,
        records.len(),
        args.seed,
        records.len() as f64 / wall.max(1e-9),
        path.display(),
        args.model.command_line(),
    );
    report(&records, &scenario.name, &header, args.out.as_deref())
}

/// A progress bar with rate and ETA on standard error, drawn only when it is a terminal.
fn progress_bar(len: u64) -> ProgressBar {
    let target = if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let bar = ProgressBar::with_draw_target(Some(len), target);
    if let Ok(style) =
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs  {per_sec}  ETA {eta}")
    {
        bar.set_style(style);
    }
    bar
}

/// Prints the summary; writes the records, the summary and the plot under `out`. Exit 1 when a
/// run did not pass.
fn report(
    records: &[RunRecord],
    title: &str,
    header: &str,
    out: Option<&Path>,
) -> Result<(), Failure> {
    let summary = Summary::of(records);
    let text = format!("{header}{summary}");
    if let Some(dir) = out {
        let mut lines = String::new();
        for record in records {
            let line = serde_json::to_string(record)
                .map_err(|e| Failure::failed(format!("error: cannot encode a run: {e}")))?;
            lines.push_str(&line);
            lines.push('\n');
        }
        write(&dir.join("runs.jsonl"), &lines)?;
        write(&dir.join("summary.txt"), &text)?;
        write(&dir.join("campaign.svg"), &plot::render(&summary, title))?;
    }
    emit(&text)?;
    if records.iter().all(|r| r.verdict == RunVerdict::Pass) {
        Ok(())
    } else {
        Err(Failure::failed(format!(
            "error: {} of {} runs did not pass",
            summary.runs - summary.passed,
            summary.runs
        )))
    }
}

fn write(path: &Path, text: &str) -> Result<(), Failure> {
    std::fs::write(path, text)
        .map_err(|e| Failure::failed(format!("error: cannot write {}: {e}", path.display())))
}

/// `kairos campaign merge`: the shards' records, by run index; a run in two shards is an error.
fn merge(dirs: &[PathBuf], title: &str, out: Option<&Path>) -> Result<(), Failure> {
    let mut records = Vec::new();
    for dir in dirs {
        let path = dir.join("runs.jsonl");
        let text = std::fs::read_to_string(&path).map_err(|e| {
            Failure::bad_input(format!("error: cannot read {}: {e}", path.display()))
        })?;
        for (n, line) in text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty())
        {
            let record: RunRecord = serde_json::from_str(line).map_err(|e| {
                Failure::bad_input(format!(
                    "error: {}:{}:{}: not a run record: {e}",
                    path.display(),
                    n + 1,
                    e.column()
                ))
            })?;
            records.push(record);
        }
    }
    records.sort_by_key(|r| r.index);
    if let Some(pair) = records.windows(2).find(|w| w[0].index == w[1].index) {
        return Err(Failure::bad_input(format!(
            "error: run {} is in two shards",
            pair[0].index
        )));
    }
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).map_err(|e| {
            Failure::bad_input(format!("error: cannot create {}: {e}", dir.display()))
        })?;
    }
    let header = format!("campaign `{title}` merged from {} shards\n", dirs.len());
    report(&records, title, &header, out)
}
