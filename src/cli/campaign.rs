//! `kairos campaign SCENARIO --runs N --seed S [--jobs J] [--shard i/n] [--out DIR] [--fault F]...
//! [--noise q] [--memory BYTES]`: a Monte
//! Carlo campaign of a scenario with a model-driven plant (`kairos::campaign`), and
//! `kairos campaign merge DIR... [--out DIR]`, which joins the shards of one.
//!
//! With `--out`, the directory receives `runs.jsonl` (one [`RunRecord`] per line, by run index),
//! `summary.txt`, `campaign.svg` and the shard's manifest (`super::shards`: a merge refuses
//! shards of different campaigns); the summary is printed in any case. Exit 0 when every run
//! passed, 1 when one did not (its seed replays it: `kairos run SCENARIO --seed SEED`), 2 on bad
//! input or a file that cannot be written.
//!
//! # Memory
//! A campaign holds its shard's records until the summary is made. A record is a few hundred
//! bytes (its histogram of cycle times, its faults, its first failure), so [`RECORD_BYTES`]
//! bounds it from above, and a shard whose runs would need more than the memory budget is
//! refused before it starts, with the shard count that fits: `--runs 1000000000` in one process
//! would otherwise run for days and then abort allocating.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use kairos::campaign::{self, RunRecord, RunVerdict, Summary, plot};
use kairos::simulation;

use super::Failure;
use super::limits::{self, parse_memory, parse_shard};
use super::model_args::ModelArgs;
use super::output::emit;
use super::shards::{self, Manifest};

/// An upper bound on the memory one run's record takes while the campaign holds it, bytes
/// (its fields, its histogram's map nodes, its strings and faults; measured records of the
/// shipped campaigns take a few hundred).
pub const RECORD_BYTES: u64 = 2048;

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
    /// How many runs in the whole campaign (all shards), at least 1.
    #[arg(long, required = true, value_parser = clap::value_parser!(u64).range(1..))]
    pub runs: Option<u64>,
    /// The campaign's seed; run i plays the plant seed derived from (seed, i).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Threads, at most the machine's cores (default, 0: one per core).
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// The most memory the shard's records may take (`4G`, `512M`); a shard that needs more is
    /// refused before it starts.
    #[arg(long, value_name = "BYTES", value_parser = parse_memory, default_value = "4G")]
    pub memory: u64,
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
        /// The campaign's name in the summary and on the picture (default: the scenario's).
        #[arg(long)]
        title: Option<String>,
    },
}

/// Runs the subcommand.
pub fn run(args: &CampaignArgs) -> Result<(), Failure> {
    if let Some(MergeCommand::Merge { dirs, out, title }) = &args.merge {
        return merge(dirs, title.as_deref(), out.as_deref());
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
    let jobs = limits::threads(args.jobs)?;
    let memory = limits::memory_budget(args.memory)?;
    let (shard, shards) = args.shard.unwrap_or((0, 1));
    // The runs whose index is `shard` modulo `shards`.
    let count = runs.saturating_sub(shard).div_ceil(shards);
    fits(count, shards, memory)?;
    if let Some(out) = &args.out {
        create_dir(out)?;
        let options = [
            ("seed", serde_json::json!(args.seed)),
            ("runs", serde_json::json!(runs)),
            ("fault", serde_json::json!(args.model.faults)),
            ("noise", serde_json::json!(args.model.noise)),
        ];
        let options = options.map(|(k, v)| (k.to_string(), v)).into();
        Manifest::new("campaign", path, &scenario.name, options, (shard, shards))?.write(out)?;
    }
    let indices: Vec<u64> = (0..count).map(|k| shard + k * shards).collect();
    let progress = progress_bar(indices.len() as u64);
    let started = Instant::now();
    let records = campaign::run_campaign(&scenario, args.seed, &indices, jobs, &|| {
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

/// Refuses, before it starts, a shard of `count` runs whose records would take more than
/// `memory` bytes, saying how many shards would fit.
fn fits(count: u64, shards: u64, memory: u64) -> Result<(), Failure> {
    let most = memory / RECORD_BYTES;
    if count <= most {
        return Ok(());
    }
    let total = count.saturating_mul(shards);
    let needed = total.div_ceil(most.max(1));
    Err(Failure::bad_input(format!(
        "error: --runs: this shard has {count} runs, whose records take up to {} (at most {} \
         a run), more than the memory budget of {}\n  expected: at most {most} runs a shard: \
         split the campaign into at least {needed} shards (--shard i/{needed}), or raise \
         --memory",
        kairos::exploration::memory::format_bytes(count.saturating_mul(RECORD_BYTES)),
        kairos::exploration::memory::format_bytes(RECORD_BYTES),
        kairos::exploration::memory::format_bytes(memory),
    )))
}

/// Creates an output directory.
fn create_dir(dir: &Path) -> Result<(), Failure> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Failure::io(format!("error: cannot create {}: {e}", dir.display())))
}

/// Checks that the merged records are the campaign's runs 0 to `runs − 1`, each with its seed.
fn check_records(records: &[RunRecord], runs: u64, seed: u64) -> Result<(), Failure> {
    if let Some(odd) = records
        .iter()
        .find(|r| r.index >= runs || r.seed != campaign::run_seed(seed, r.index))
    {
        return Err(Failure::bad_input(format!(
            "error: run {} (seed {}) is not a run of the campaign of seed {seed} and {runs} runs",
            odd.index, odd.seed
        )));
    }
    if records.len() as u64 != runs {
        return Err(Failure::bad_input(format!(
            "error: the shards hold {} of the campaign's {runs} runs (a shard's runs.jsonl is \
             incomplete)",
            records.len()
        )));
    }
    Ok(())
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
        write_records(&dir.join("runs.jsonl"), records)?;
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

/// Writes the records as JSON lines, one at a time.
fn write_records(path: &Path, records: &[RunRecord]) -> Result<(), Failure> {
    use std::io::Write;
    let cannot =
        |e: std::io::Error| Failure::io(format!("error: cannot write {}: {e}", path.display()));
    let mut file = std::io::BufWriter::new(std::fs::File::create(path).map_err(cannot)?);
    for record in records {
        serde_json::to_writer(&mut file, record)
            .map_err(|e| Failure::io(format!("error: cannot write {}: {e}", path.display())))?;
        file.write_all(b"\n").map_err(cannot)?;
    }
    file.flush().map_err(cannot)
}

fn write(path: &Path, text: &str) -> Result<(), Failure> {
    std::fs::write(path, text)
        .map_err(|e| Failure::io(format!("error: cannot write {}: {e}", path.display())))
}

/// `kairos campaign merge`: the shards' records, by run index, once their manifests show them
/// the shards of one campaign, each once; a run in two shards, or a shard whose records are
/// not its runs, is an error.
fn merge(dirs: &[PathBuf], title: Option<&str>, out: Option<&Path>) -> Result<(), Failure> {
    let manifests = shards::read_all("campaign", dirs)?;
    let first = &manifests[0];
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
    let runs = first
        .options
        .get("runs")
        .and_then(serde_json::Value::as_u64);
    let seed = first
        .options
        .get("seed")
        .and_then(serde_json::Value::as_u64);
    if let (Some(runs), Some(seed)) = (runs, seed) {
        check_records(&records, runs, seed)?;
    }
    if let Some(dir) = out {
        create_dir(dir)?;
    }
    let title = title.unwrap_or(&first.scenario);
    let header = format!(
        "campaign `{title}` merged from {} shards (seed {}, {} runs)\n",
        dirs.len(),
        seed.map_or_else(|| "?".to_string(), |s| s.to_string()),
        records.len()
    );
    report(&records, title, &header, out)
}
