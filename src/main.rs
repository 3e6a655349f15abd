//! The `pacer` command.

use clap::{Parser, Subcommand};
use pacer::load::{load, LoadRequest};
use pacer::trace::Trace;
use pacer::vm::Machine;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

// A reader that goes away (`pacer run … | head`) is not an error of the run: output to a closed
// pipe is dropped instead of panicking.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}
macro_rules! say_raw {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout().lock(), $($arg)*);
    }};
}
macro_rules! warn {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr().lock(), $($arg)*);
    }};
}
macro_rules! warn_raw {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stderr().lock(), $($arg)*);
    }};
}

#[derive(Parser)]
#[command(
    name = "pacer",
    version,
    about = "Run motion-controller programs on an exact, repeatable simulated machine"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args)]
struct Project {
    /// A machine folder, or program files (.pt PowerTools, .mb MotionBASIC)
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// Machine file (default: machine.toml beside the programs)
    #[arg(long)]
    machine: Option<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Run programs on the simulated machine
    Run {
        #[command(flatten)]
        project: Project,
        /// Scenario file (default: scenario.toml beside the programs)
        #[arg(long)]
        scenario: Option<PathBuf>,
        /// Simulated seconds to run (default: the scenario's duration, else until all programs end)
        #[arg(long = "for", value_name = "SECONDS")]
        duration: Option<f64>,
        /// Write the JSON-lines trace here
        #[arg(long, value_name = "FILE.jsonl")]
        trace: Option<PathBuf>,
        /// Print nothing but errors
        #[arg(long, short)]
        quiet: bool,
        #[command(flatten)]
        export: pacer::export::ExportArgs,
    },
    /// Parse and check programs (and the machine and scenario files) without running
    Check {
        #[command(flatten)]
        project: Project,
        /// Scenario file to check too
        #[arg(long)]
        scenario: Option<PathBuf>,
    },
    /// Print the compiled bytecode of programs
    Disasm {
        #[command(flatten)]
        project: Project,
    },
    /// Draw plots (SVG) from a recorded trace, without running again
    Plot(pacer::export::PlotArgs),
    /// Poke at the simulated machine: type statements, step, watch, set inputs
    Repl {
        /// A machine folder (default: an empty machine with the default machine.toml)
        folder: Option<PathBuf>,
        /// Language of typed lines: pt (PowerTools) or mb (MotionBASIC); default: the programs'
        #[arg(long, value_parser = ["pt", "mb"])]
        dialect: Option<String>,
    },
}

const EXIT_PROBLEMS: u8 = 1;
const EXIT_RUNTIME: u8 = 2;
const EXIT_IO: u8 = 3;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let color = std::io::stderr().is_terminal();
    match cli.command {
        Command::Run {
            project,
            scenario,
            duration,
            trace,
            quiet,
            export,
        } => run(project, scenario, duration, trace, quiet, export, color),
        Command::Plot(args) => match pacer::export::plot_command(&args) {
            Ok(path) => {
                say!("plot: {}", path.display());
                ExitCode::SUCCESS
            }
            Err(e) => {
                warn!("error: {e}");
                ExitCode::from(e.exit_code())
            }
        },
        Command::Check { project, scenario } => {
            let req = LoadRequest {
                paths: project.paths,
                machine: project.machine,
                scenario,
            };
            match load(&req) {
                Ok(loaded) => {
                    warn_raw!("{}", loaded.warnings.render(color));
                    say!("ok: {} program(s) checked", loaded.sources.len());
                    ExitCode::SUCCESS
                }
                Err(d) => problems(&d, color),
            }
        }
        Command::Repl { folder, dialect } => {
            let dialect = dialect.map(|d| match d.as_str() {
                "mb" => pacer::syntax::Dialect::MotionBasic,
                _ => pacer::syntax::Dialect::PowerTools,
            });
            ExitCode::from(pacer::repl::run(pacer::repl::Options { folder, dialect }))
        }
        Command::Disasm { project } => {
            let req = LoadRequest {
                paths: project.paths,
                machine: project.machine,
                scenario: None,
            };
            match load(&req) {
                Ok(loaded) => {
                    for chunk in &loaded.image.chunks {
                        say_raw!(
                            "{}",
                            pacer::compile::disasm::disassemble(
                                chunk,
                                &loaded.layout,
                                &loaded.image.registry
                            )
                        );
                    }
                    ExitCode::SUCCESS
                }
                Err(d) => problems(&d, color),
            }
        }
    }
}

fn problems(d: &pacer::diag::Diagnostics, color: bool) -> ExitCode {
    warn_raw!("{}", d.render(color));
    warn!("{} error(s)", d.error_count());
    ExitCode::from(EXIT_PROBLEMS)
}

fn run(
    project: Project,
    scenario: Option<PathBuf>,
    duration: Option<f64>,
    trace: Option<PathBuf>,
    quiet: bool,
    export: pacer::export::ExportArgs,
    color: bool,
) -> ExitCode {
    let duration_ns = match duration.map(pacer::config::values::seconds_to_ns) {
        None => None,
        Some(Ok(ns)) => Some(ns),
        Some(Err(e)) => {
            warn!("error: --for: {e}");
            return ExitCode::from(EXIT_PROBLEMS);
        }
    };
    let req = LoadRequest {
        paths: project.paths,
        machine: project.machine,
        scenario,
    };
    let loaded = match load(&req) {
        Ok(l) => l,
        Err(d) => return problems(&d, color),
    };
    warn_raw!("{}", loaded.warnings.render(color));
    let sink: Option<Box<dyn std::io::Write>> = match &trace {
        None => None,
        Some(p) => match std::fs::File::create(p) {
            Ok(f) => Some(Box::new(std::io::BufWriter::with_capacity(1 << 16, f))),
            Err(e) => {
                warn!("error: cannot create trace file {}: {e}", p.display());
                return ExitCode::from(EXIT_IO);
            }
        },
    };
    let mut export = match pacer::export::Export::open(&export, &loaded.image) {
        Ok(e) => e,
        Err(e) => {
            warn!("error: {e}");
            return ExitCode::from(e.exit_code());
        }
    };
    let sink = export.trace_sink(sink);
    let tick_ns = loaded.image.tick_ns;
    let name = loaded.image.name.clone();
    let mut machine = Machine::new(loaded.image, Trace::new(sink, tick_ns));
    // Observed only when something is exported: otherwise the run is exactly what it was.
    let summary = if export.is_active() {
        export.start(&machine);
        machine.run_observed(duration_ns, &mut |m| export.observe(m))
    } else {
        machine.run(duration_ns)
    };
    if let Err(e) = machine.finish() {
        warn!("error: writing the trace: {e}");
        return ExitCode::from(EXIT_IO);
    }
    let exported = match export.finish(machine.registry()) {
        Ok(w) => w,
        Err(e) => {
            warn!("error: {e}");
            return ExitCode::from(e.exit_code());
        }
    };
    if !quiet {
        let events: Vec<String> = summary
            .events
            .iter()
            .map(|(k, n)| format!("{n} {k}"))
            .collect();
        say!(
            "pacer: {name}: {:.3} s simulated in {} updates of {} ms, {} instructions; {}; stopped: {}",
            summary.seconds,
            summary.ticks,
            tick_ns as f64 / 1e6,
            summary.instructions,
            if events.is_empty() { "no events".to_string() } else { events.join(", ") },
            summary.stop_reason
        );
        if let Some(p) = &trace {
            say!("trace: {}", p.display());
        }
        for (kind, p) in &exported {
            say!("{kind}: {}", p.display());
        }
    }
    match summary.error {
        Some(e) => {
            warn!("error: {e}");
            ExitCode::from(EXIT_RUNTIME)
        }
        None => ExitCode::SUCCESS,
    }
}
