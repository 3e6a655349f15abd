//! `pacer sweep`: one job — run a machine over many scenario and machine variants (a grid or a
//! seeded random sample of values), measure and judge each run, and summarise where the
//! machine works; in slices (shards) on batch engines, merged afterwards into the results of
//! one run. See docs/sweep.md.
//!
//! [`spec`] reads the sweep, [`set`] applies a variant's values to the machine's files (shared
//! with `pacer run --set`), [`run`] runs variants, [`results`] writes, reads and merges the
//! result files, [`summary`] and [`plot`] report.

pub mod expr;
pub mod plot;
pub mod results;
pub mod run;
pub mod set;
pub mod spec;
pub mod summary;

use results::{Meta, Shard};
use set::Base;
use spec::{ArgSpec, SpecError};
use std::io::{IsTerminal, Write};
use std::path::PathBuf;

/// Exit code: every variant passed (or a merge succeeded).
pub const EXIT_OK: u8 = 0;
/// Exit code: a problem in the inputs (sweep.toml, a machine that does not load, shards that do
/// not merge).
pub const EXIT_PROBLEMS: u8 = 1;
/// Exit code: a variant failed (an assertion, a run-time error, a value the machine refuses).
pub const EXIT_FAILED: u8 = 2;
/// Exit code: the results cannot be written.
pub const EXIT_IO: u8 = 3;
/// Exit code: the command line is wrong (`--vary`, `--shard`, `--jobs`).
pub const EXIT_USAGE: u8 = 64;

/// `pacer sweep`: its options, or `pacer sweep merge`.
#[derive(clap::Args, Debug, Clone)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepCommand {
    /// `merge`.
    #[command(subcommand)]
    pub merge: Option<SweepSub>,
    /// The sweep's options.
    #[command(flatten)]
    pub args: SweepArgs,
}

/// The subcommands of `pacer sweep`.
#[derive(clap::Subcommand, Debug, Clone)]
pub enum SweepSub {
    /// Join the results folders of a sharded sweep into the results of one run
    Merge(MergeArgs),
}

/// `pacer sweep merge`.
#[derive(clap::Args, Debug, Clone)]
pub struct MergeArgs {
    /// The shards' results folders (each written by `pacer sweep --shard I/N --out DIR`)
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Write the merged sweep.json, results.jsonl and results.csv here
    #[arg(long, value_name = "DIR", required = true)]
    pub out: PathBuf,
    /// Draw the sweep's plot to an SVG file
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
}

/// `pacer sweep FOLDER …`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SweepArgs {
    /// A machine folder (its sweep.toml, machine.toml and scenario.toml are read)
    #[arg(required = true)]
    pub folder: Option<PathBuf>,
    /// Machine file (default: machine.toml in the folder)
    #[arg(long)]
    pub machine: Option<PathBuf>,
    /// Scenario file (default: scenario.toml in the folder)
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    /// Sweep file (default: sweep.toml in the folder, if there is one)
    #[arg(long, value_name = "FILE")]
    pub sweep: Option<PathBuf>,
    /// Vary a value: NAME=FROM..TO:COUNT, NAME=A,B,C or NAME=VALUE (repeatable), e.g.
    /// master.speed=10..60:26, products.0.pitch=0.7,0.8, Queue.0.QueueOffset=9.5..10.5:3
    #[arg(long, value_name = "NAME=VALUES")]
    pub vary: Vec<String>,
    /// Also vary run.seed over 1..N
    #[arg(long, value_name = "N")]
    pub seeds: Option<u64>,
    /// Run a seeded random sample of N variants instead of the whole grid
    #[arg(long, value_name = "N")]
    pub sample: Option<u64>,
    /// Seed of --sample (default 1)
    #[arg(long, value_name = "SEED")]
    pub sample_seed: Option<u64>,
    /// Simulated time of each run: seconds or with a unit (default: sweep.toml's, else the
    /// scenario's)
    #[arg(long = "for", value_name = "SECONDS", value_parser = crate::config::values::parse_duration)]
    pub duration: Option<u64>,
    /// An assertion every variant must meet (repeatable), e.g. "Queue.0.QueueOverflow == OFF"
    #[arg(long, value_name = "ASSERTION")]
    pub expect: Vec<String>,
    /// Runs at once (default: the machine's cores); the results do not depend on it
    #[arg(long, short, value_name = "N")]
    pub jobs: Option<usize>,
    /// Write sweep.json, results.jsonl and results.csv here
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Run only slice I of N (from 0): the variants whose number modulo N is I; `env/N` reads I
    /// from JOB_COMPLETION_INDEX or SLURM_ARRAY_TASK_ID. Needs --out
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Draw the sweep's plot to an SVG file
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Print only the summary (no progress, no timing)
    #[arg(long, short)]
    pub quiet: bool,
}

/// Print to stdout, ignoring a closed pipe.
fn say(text: &str) {
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// Print to stderr.
fn warn(text: &str) {
    let _ = std::io::stderr().lock().write_all(text.as_bytes());
}

/// Run `pacer sweep`; the exit code.
pub fn command(cmd: &SweepCommand, color: bool) -> u8 {
    match &cmd.merge {
        Some(SweepSub::Merge(m)) => merge(m),
        None => sweep(&cmd.args, color),
    }
}

fn spec_error(e: SpecError, color: bool) -> u8 {
    match e {
        SpecError::File(d) => {
            warn(&d.render(color));
            warn(&format!("{} error(s)\n", d.error_count()));
            EXIT_PROBLEMS
        }
        SpecError::Arg(m) => {
            warn(&format!("error: {m}\n"));
            EXIT_USAGE
        }
    }
}

fn sweep(args: &SweepArgs, color: bool) -> u8 {
    let Some(folder) = args.folder.clone() else {
        warn("error: give a machine folder\n");
        return EXIT_USAGE;
    };
    if !folder.is_dir() {
        warn(&format!(
            "error: {}: not a machine folder\n",
            folder.display()
        ));
        return EXIT_PROBLEMS;
    }
    let shard = match &args.shard {
        None => None,
        Some(text) => match Shard::parse(text, &|v| std::env::var(v).ok()) {
            Ok(s) => Some(s),
            Err(m) => {
                warn(&format!("error: {m}\n"));
                return EXIT_USAGE;
            }
        },
    };
    if shard.is_some() && args.out.is_none() {
        warn(
            "error: --shard: give --out DIR, for `pacer sweep merge` to join the shards' results\n",
        );
        return EXIT_USAGE;
    }
    if args.jobs == Some(0) {
        warn("error: --jobs 0: give 1 or more\n");
        return EXIT_USAGE;
    }
    let sweep_path = args
        .sweep
        .clone()
        .or_else(|| Some(folder.join("sweep.toml")).filter(|p| p.exists()));
    let file = match &sweep_path {
        None => None,
        Some(p) => match std::fs::read_to_string(p) {
            Ok(t) => Some(crate::diag::SourceFile::new(p.display().to_string(), t)),
            Err(e) => {
                warn(&format!("error: cannot read {}: {e}\n", p.display()));
                return EXIT_PROBLEMS;
            }
        },
    };
    let arg_spec = ArgSpec {
        vary: args.vary.clone(),
        seeds: args.seeds,
        sample: args.sample,
        sample_seed: args.sample_seed,
        duration_ns: args.duration,
        expects: args.expect.clone(),
    };
    let spec = match spec::parse(file, &arg_spec) {
        Ok(s) => s,
        Err(e) => return spec_error(e, color),
    };
    let req = crate::load::LoadRequest {
        paths: vec![folder.clone()],
        machine: args.machine.clone(),
        scenario: args.scenario.clone(),
    };
    let base = Base::open(req);
    let loaded = match run::check(&spec, &base) {
        Ok(l) => l,
        Err(run::CheckError::Machine(e)) => {
            warn(&e.render(color));
            warn(&format!("{} error(s)\n", e.error_count()));
            return EXIT_PROBLEMS;
        }
        Err(run::CheckError::Spec(e)) => return spec_error(e, color),
    };
    let meta = meta_of(&spec, &base, &loaded, args, shard);
    let total = spec.len();
    let indices: Vec<usize> = match shard {
        Some(s) => s.indices(total),
        None => (0..total).collect(),
    };
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let show_progress = !args.quiet && std::io::stderr().is_terminal();
    let started = std::time::Instant::now();
    let mut shown = usize::MAX;
    let results = run::run_all(&spec, &base, &indices, jobs, &mut |done, all| {
        if !show_progress {
            return;
        }
        // Redrawn at each whole percent, not at each variant.
        let pct = done * 100 / all.max(1);
        if pct != shown {
            shown = pct;
            let width = 30;
            let filled = done * width / all.max(1);
            warn(&format!(
                "\r[{}{}] {done}/{all} variants",
                "#".repeat(filled),
                " ".repeat(width - filled)
            ));
        }
    });
    if show_progress {
        warn("\n");
    }
    let seconds = started.elapsed().as_secs_f64();
    let used = jobs.min(run::MAX_JOBS).min(results.len().max(1));
    if !args.quiet {
        warn(&format!(
            "sweep: {} variant{} in {seconds:.2} s on {} job{}{}\n",
            results.len(),
            if results.len() == 1 { "" } else { "s" },
            used,
            if used == 1 { "" } else { "s" },
            shard
                .map(|s| format!(" (shard {}/{})", s.index, s.count))
                .unwrap_or_default()
        ));
    }
    say(&summary::summary(&meta, &results));
    if let Some(out) = &args.out {
        if let Err(e) = results::write(out, &meta, &results) {
            warn(&format!("error: {e}\n"));
            return EXIT_IO;
        }
        if !args.quiet {
            warn(&format!("results: {}\n", out.display()));
        }
    }
    if let Some(p) = &args.plot {
        if let Err(code) = write_plot(p, &meta, &results, args.quiet) {
            return code;
        }
    }
    if results.iter().all(run::VariantResult::pass) {
        EXIT_OK
    } else {
        EXIT_FAILED
    }
}

fn write_plot(
    path: &std::path::Path,
    meta: &Meta,
    results: &[run::VariantResult],
    quiet: bool,
) -> Result<(), u8> {
    let svg = plot::svg(meta, results).map_err(|e| {
        warn(&format!("error: {e}\n"));
        EXIT_IO
    })?;
    std::fs::write(path, svg).map_err(|e| {
        warn(&format!("error: cannot write {}: {e}\n", path.display()));
        EXIT_IO
    })?;
    if !quiet {
        warn(&format!("plot: {}\n", path.display()));
    }
    Ok(())
}

/// `sweep.json` of this sweep.
fn meta_of(
    spec: &spec::Spec,
    base: &Base,
    loaded: &crate::load::Loaded,
    args: &SweepArgs,
    shard: Option<Shard>,
) -> Meta {
    let describe = spec.describe();
    let mut parts: Vec<&str> = vec![
        &describe,
        base.machine_text.as_deref().unwrap_or_default(),
        base.scenario_text.as_deref().unwrap_or_default(),
    ];
    parts.extend(loaded.sources.values().map(|s| &*s.text));
    let mut rerun = vec![args
        .folder
        .as_ref()
        .map(|f| f.display().to_string())
        .unwrap_or_default()];
    for (flag, v) in [("--machine", &args.machine), ("--scenario", &args.scenario)] {
        if let Some(p) = v {
            rerun.push(flag.into());
            rerun.push(p.display().to_string());
        }
    }
    if let Some(ns) = spec.duration_ns {
        rerun.push("--for".into());
        rerun.push(format!("{}", ns as f64 / 1e9));
    }
    Meta {
        format: results::FORMAT,
        fingerprint: results::fingerprint(&parts),
        machine: loaded.image.name.clone(),
        variants: spec.len(),
        axes: spec.axes.iter().map(|a| a.name.text.clone()).collect(),
        measures: spec.measures.iter().map(|m| m.name.clone()).collect(),
        expects: spec.expects.iter().map(|e| e.text.clone()).collect(),
        rerun,
        plot: vec![
            spec.plot.measure.clone().unwrap_or_default(),
            spec.plot.x.clone().unwrap_or_default(),
            spec.plot.y.clone().unwrap_or_default(),
        ],
        sampled: spec.sample.is_some(),
        shard,
    }
}

fn merge(m: &MergeArgs) -> u8 {
    let (meta, results) = match results::merge(&m.dirs) {
        Ok(x) => x,
        Err(e) => {
            warn(&format!("error: {e}\n"));
            return EXIT_PROBLEMS;
        }
    };
    say(&summary::summary(&meta, &results));
    if let Err(e) = results::write(&m.out, &meta, &results) {
        warn(&format!("error: {e}\n"));
        return EXIT_IO;
    }
    if let Some(p) = &m.plot {
        if let Err(code) = write_plot(p, &meta, &results, false) {
            return code;
        }
    }
    if results.iter().all(run::VariantResult::pass) {
        EXIT_OK
    } else {
        EXIT_FAILED
    }
}
