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

// Parsed once per process: the size of the largest variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// Run programs on the simulated machine
    Run {
        #[command(flatten)]
        project: Project,
        /// Scenario file (default: scenario.toml beside the programs)
        #[arg(long)]
        scenario: Option<PathBuf>,
        /// Set a scenario, machine-file or member value for this run (repeatable):
        /// master.speed=40, products.0.pitch=0.8, run.seed=7, machine.update=2ms,
        /// Queue.0.QueueOffset=9.5 (the names of `pacer sweep --vary`)
        #[arg(long, value_name = "NAME=VALUE", value_parser = pacer::sweep::set::parse_assignment)]
        set: Vec<(pacer::sweep::set::Name, toml::Value)>,
        /// Simulated time to run: seconds, or with a unit (`90`, `1.5s`, `250ms`); default: the
        /// scenario's duration, else until every program has ended and motion is at rest
        #[arg(long = "for", value_name = "SECONDS", value_parser = pacer::config::values::parse_duration)]
        duration: Option<u64>,
        /// Write the JSON-lines trace here
        #[arg(long, value_name = "FILE.jsonl")]
        trace: Option<PathBuf>,
        /// Also trace a program's writes that leave a value as it was (default: changes only)
        #[arg(long)]
        trace_writes: bool,
        /// The most the trace file may hold: bytes, or with K, M or G (default 1G; 0: no
        /// limit). The run ends with an error when the trace would pass it
        #[arg(long, value_name = "SIZE", value_parser = parse_size)]
        trace_limit: Option<u64>,
        /// Print nothing but errors
        #[arg(long, short)]
        quiet: bool,
        /// Where inputs come from and outputs go: `sim` (the simulated machine), `modbus` (the
        /// coupler of machine.toml's [modbus]) or `modbus://HOST[:PORT][/UNIT]`; real I/O runs
        /// in real time. Default: sim, or modbus when [modbus] says `enabled = true`
        #[arg(long, value_name = "IO", value_parser = pacer::io::target::IoTarget::parse)]
        io: Option<pacer::io::target::IoTarget>,
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
    /// Run the machine over many variants of its scenario and settings, and summarise
    Sweep(pacer::sweep::SweepCommand),
    /// Poke at the simulated machine: type statements, step, watch, set inputs
    Repl {
        /// A machine folder (default: an empty machine with the default machine.toml)
        folder: Option<PathBuf>,
        /// Language of typed lines: pt (PowerTools) or mb (MotionBASIC); default: the programs'
        #[arg(long, value_parser = ["pt", "mb"])]
        dialect: Option<String>,
    },
}

// The exit codes, one table in docs/cli.md ("Exit codes"); tests/exit_codes.rs runs each.
const EXIT_PROBLEMS: u8 = 1;
const EXIT_RUNTIME: u8 = 2;
const EXIT_IO: u8 = 3;
/// The command line itself is wrong (an unknown flag, a value that is not a duration): the
/// BSD `EX_USAGE`, apart from the run-time error's 2 that clap would give.
const EXIT_USAGE: u8 = 64;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // `--help` and `--version` come this way too, and are not errors.
            let code = if e.use_stderr() { EXIT_USAGE } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let color = std::io::stderr().is_terminal();
    match cli.command {
        Command::Run {
            project,
            scenario,
            set,
            duration,
            trace,
            trace_writes,
            trace_limit,
            quiet,
            io,
            export,
        } => run(
            project,
            scenario,
            &set,
            RunOptions {
                duration,
                trace,
                trace_writes,
                trace_limit,
                quiet,
                io,
                color,
            },
            export,
        ),
        Command::Sweep(cmd) => ExitCode::from(pacer::sweep::command(&cmd, color)),
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

/// What `pacer run` was asked for, beside the project and the exports.
struct RunOptions {
    duration: Option<u64>,
    trace: Option<PathBuf>,
    trace_writes: bool,
    trace_limit: Option<u64>,
    quiet: bool,
    io: Option<pacer::io::target::IoTarget>,
    color: bool,
}

/// The real I/O a run is wired to, resolved from `--io` and the machine file.
struct RealIo {
    map: pacer::io::map::IoMap,
    host: String,
    port: u16,
    unit: u8,
}

/// `--io` against the machine file: None for the simulator, the coupler for real I/O, or the
/// message of a setting that cannot work.
/// `--io`'s own syntax is parsed with the command line (a value that is no I/O is a usage
/// error, exit 64, like any other flag's); here it meets the machine file.
fn resolve_io(
    io: Option<&pacer::io::target::IoTarget>,
    loaded: &pacer::load::Loaded,
) -> Result<Option<RealIo>, String> {
    use pacer::io::target::IoTarget;
    let target = match io {
        Some(target) => target.clone(),
        None if loaded.io_map.as_ref().is_some_and(|m| m.enabled) => IoTarget::Modbus {
            host: None,
            port: None,
            unit: None,
        },
        None => IoTarget::Simulator,
    };
    let IoTarget::Modbus { host, port, unit } = target else {
        return Ok(None);
    };
    let Some(map) = loaded.io_map.clone() else {
        return Err(
            "--io modbus: machine.toml has no [modbus] section: map the coupler's points to pacer's members first (see docs/real-io.md)"
                .into(),
        );
    };
    let Some(host) = host.or_else(|| map.host.clone()) else {
        return Err(
            "--io modbus: no host: give one (--io modbus://HOST:PORT) or set [modbus] host in machine.toml"
                .into(),
        );
    };
    if let Some(d) = loaded.image.devices.iter().find(|d| !d.safe_state()) {
        return Err(format!(
            "--io modbus: this machine has {}, which pacer cannot bring to a stop on an I/O fault",
            d.describe()
        ));
    }
    Ok(Some(RealIo {
        port: port.unwrap_or(map.port),
        unit: unit.unwrap_or(map.unit),
        host,
        map,
    }))
}

fn run(
    project: Project,
    scenario: Option<PathBuf>,
    set: &[(pacer::sweep::set::Name, toml::Value)],
    options: RunOptions,
    export: pacer::export::ExportArgs,
) -> ExitCode {
    let color = options.color;
    let duration_ns = options.duration;
    let req = LoadRequest {
        paths: project.paths,
        machine: project.machine,
        scenario,
    };
    // Values set are applied to the files as read, so the loader checks them as if written there.
    let loaded = if set.is_empty() {
        match load(&req) {
            Ok(l) => l,
            Err(d) => return problems(&d, color),
        }
    } else {
        match pacer::sweep::set::Base::open(req).load(set) {
            Ok(l) => l,
            Err(pacer::sweep::set::SetError::Load(d)) => return problems(&d, color),
            Err(e) => {
                warn_raw!("{}", e.render(color));
                return ExitCode::from(EXIT_PROBLEMS);
            }
        }
    };
    warn_raw!("{}", loaded.warnings.render(color));
    if let Some(d) = duration_ns {
        let updates = d / loaded.image.tick_ns.max(1);
        if updates > pacer::config::limits::MAX_UPDATES {
            warn!(
                "error: --for: a run of {} updates is too long: at most {} (every update takes time even when nothing moves)",
                pacer::config::limits::thousands(updates),
                pacer::config::limits::thousands(pacer::config::limits::MAX_UPDATES)
            );
            return ExitCode::from(EXIT_USAGE);
        }
    }
    let real_io = match resolve_io(options.io.as_ref(), &loaded) {
        Ok(r) => r,
        Err(e) => {
            warn!("error: {e}");
            return ExitCode::from(EXIT_PROBLEMS);
        }
    };
    match real_io {
        None => execute(loaded, duration_ns, options, export, None),
        // The updates get a thread of their own (its priority is raised), which owns the
        // connection from the start.
        Some(real) => {
            let worker = std::thread::Builder::new()
                .name("pacer-update".into())
                .spawn(move || execute(loaded, duration_ns, options, export, Some(real)));
            match worker.map(|w| w.join()) {
                Ok(Ok(code)) => code,
                Ok(Err(_)) => {
                    warn!("error: the update thread stopped unexpectedly");
                    ExitCode::from(EXIT_RUNTIME)
                }
                Err(e) => {
                    warn!("error: cannot start the update thread: {e}");
                    ExitCode::from(EXIT_RUNTIME)
                }
            }
        }
    }
}

/// Ctrl-C and SIGTERM end a real-time run after the current update (outputs safe, trace
/// closed); a second Ctrl-C while that is under way ends pacer at once.
fn catch_stop_signals(flag: &std::sync::Arc<std::sync::atomic::AtomicBool>) -> std::io::Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    // Registered first, so it sees the flag as the first signal left it.
    signal_hook::flag::register_conditional_shutdown(SIGINT, 130, flag.clone())?;
    signal_hook::flag::register(SIGINT, flag.clone())?;
    signal_hook::flag::register(SIGTERM, flag.clone())?;
    Ok(())
}

/// Connect to the coupler, writing the safe values first, and start its process image: the
/// backend the run talks to.
fn connect(real: RealIo) -> Result<Box<dyn pacer::io::IoBackend>, String> {
    use pacer::io::exchange::{Exchange, ExchangeOptions};
    use pacer::io::memory::PlanBackend;
    use pacer::io::supervisor::{Backoff, Supervisor};
    let device =
        pacer::io::modbus::ModbusTcp::new(&real.host, real.port, real.unit, real.map.timeout_ns);
    let options = ExchangeOptions {
        period_ns: real.map.period_ns,
        max_age_ns: real.map.max_age_ns,
    };
    let mut supervisor = Supervisor::new(PlanBackend::new(real.map, device), Backoff::default());
    supervisor.open().map_err(|e| e.to_string())?;
    let exchange = Exchange::start(supervisor, options)
        .map_err(|e| format!("cannot start the exchange thread: {e}"))?;
    Ok(Box::new(exchange))
}

/// Run the loaded machine (on the simulator, or in real time on `real`) and report.
fn execute(
    loaded: pacer::load::Loaded,
    duration_ns: Option<u64>,
    options: RunOptions,
    export: pacer::export::ExportArgs,
    real: Option<RealIo>,
) -> ExitCode {
    let RunOptions {
        trace,
        trace_writes,
        trace_limit,
        quiet,
        color,
        ..
    } = options;
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
    let tick_ns = loaded.image.tick_ns;
    let name = loaded.image.name.clone();
    let mut writer = Trace::new(sink, tick_ns);
    writer.record_writes(trace_writes);
    writer.limit(match trace_limit {
        None => Some(pacer::trace::DEFAULT_LIMIT),
        Some(0) => None,
        Some(bytes) => Some(bytes),
    });
    if let Some(observer) = export.trace_observer() {
        writer.observe(observer);
    }
    let mut machine = Machine::new(loaded.image, writer);
    machine.set_output(Box::new(std::io::stdout()));
    let mut realtime = None;
    if let Some(real) = real {
        let overrun_limit = real.map.overrun_limit;
        // Caught before the connection: the exchange starts with it, and a Ctrl-C from then on
        // must end the run with the outputs safe.
        let interrupt = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        if let Err(e) = catch_stop_signals(&interrupt) {
            warn!("warning: Ctrl-C cannot be caught ({e}): it will end pacer without driving the outputs safe");
        }
        let supervisor = match connect(real) {
            Ok(s) => s,
            Err(e) => {
                warn!("error: {e}");
                return ExitCode::from(EXIT_IO);
            }
        };
        let dropped = machine.attach_io(supervisor);
        if dropped > 0 && !quiet {
            warn!("note: {dropped} scenario input edge(s) dropped: the device drives those inputs");
        }
        if !quiet {
            warn!(
                "pacer: {}: real time on {}; Ctrl-C stops",
                name,
                machine.io_device()
            );
        }
        let options = pacer::vm::realtime::RealTimeOptions {
            overrun_limit,
            interrupt: &interrupt,
        };
        realtime = Some(if export.is_active() {
            export.start(&machine);
            pacer::vm::realtime::run_real_time(&mut machine, duration_ns, options, &mut |m| {
                export.observe(m)
            })
        } else {
            pacer::vm::realtime::run_real_time(&mut machine, duration_ns, options, &mut |_| {})
        });
    }
    // Observed only when something is exported: otherwise the run is exactly what it was.
    let summary = if let Some(r) = &realtime {
        r.summary.clone()
    } else if export.is_active() {
        export.start(&machine);
        machine.run_observed(duration_ns, &mut |m| export.observe(m))
    } else {
        machine.run(duration_ns)
    };
    if let Err(e) = machine.finish() {
        let path = trace
            .as_ref()
            .map_or_else(String::new, |p| p.display().to_string());
        warn!(
            "error: cannot write the trace to {path}: {e}; the run stopped at t = {:.3} s",
            summary.seconds
        );
        return ExitCode::from(EXIT_IO);
    }
    let exported = match export.finish(machine.registry()) {
        Ok(w) => w,
        Err(e) => {
            warn!("error: {e}");
            return ExitCode::from(e.exit_code());
        }
    };
    // Standard output carries what the programs print; the run's own account goes to stderr.
    if !quiet {
        let events: Vec<String> = summary
            .events
            .iter()
            .map(|(k, n)| format!("{n} {k}"))
            .collect();
        warn!(
            "pacer: {name}: {:.3} s simulated in {} updates of {} ms, {} instructions; {}; stopped: {}",
            summary.seconds,
            summary.ticks,
            tick_ns as f64 / 1e6,
            summary.instructions,
            if events.is_empty() { "no events".to_string() } else { events.join(", ") },
            summary.stop_reason
        );
        if !summary.moving.is_empty() {
            warn!("still moving: {}", summary.moving.join(", "));
        }
        if matches!(
            summary.stop_reason,
            pacer::vm::StopReason::Cap { .. } | pacer::vm::StopReason::Interrupted
        ) {
            for w in &summary.waiting {
                warn!("{w}");
            }
        }
        if let Some(p) = &trace {
            warn!("trace: {}", p.display());
        }
        for (kind, p) in &exported {
            warn!("{kind}: {}", p.display());
        }
    }
    if let Some(r) = &realtime {
        report_real_time(r, &machine.io_device(), quiet);
    }
    if let pacer::vm::StopReason::TraceLimit { .. } = summary.stop_reason {
        warn!(
            "error: {} at t = {:.3} s: the run stopped there; raise the limit (--trace-limit 4G, 0 for none) or trace less",
            summary.stop_reason, summary.seconds
        );
        return ExitCode::from(EXIT_IO);
    }
    match summary.error {
        Some(e) => {
            warn_raw!("{}", e.render(color));
            ExitCode::from(EXIT_RUNTIME)
        }
        None => match realtime.and_then(|r| r.overrun_fault) {
            Some(fault) => {
                warn!("error: {fault}");
                ExitCode::from(EXIT_RUNTIME)
            }
            None => ExitCode::SUCCESS,
        },
    }
}

/// A size: bytes, or a number with K, M or G (powers of 1024): `1G`, `500M`, `0`.
fn parse_size(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let (digits, unit) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => (&t[..i], c.to_ascii_uppercase()),
        _ => (t, 'B'),
    };
    let shift = match unit {
        'B' => 0,
        'K' => 10,
        'M' => 20,
        'G' => 30,
        other => return Err(format!("unknown unit `{other}`: write bytes, or K, M or G")),
    };
    let n: u64 = digits
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a size: write bytes, or a number with K, M or G"))?;
    n.checked_mul(1u64 << shift)
        .ok_or_else(|| format!("`{text}` is too large"))
}

/// The real-time part of the end-of-run summary: the I/O link, the timing, and what the
/// system refused.
fn report_real_time(r: &pacer::vm::realtime::RealTimeReport, device: &str, quiet: bool) {
    for w in &r.realtime.warnings {
        warn!("warning: {w}");
    }
    if let Some(e) = &r.close_error {
        warn!("warning: the outputs could not be driven to their safe values at the end: {e}");
    }
    if quiet {
        return;
    }
    let io = r.io;
    warn!(
        "io: {device}: {} requests per exchange; {} requests in {} exchanges; {} fault(s), {} reconnection(s)",
        io.per_update,
        io.requests,
        io.updates,
        io.faults,
        io.reconnections
    );
    if let Some(x) = &io.exchange {
        warn!("exchange: {x}");
    }
    if let Some(t) = &r.timing {
        warn!(
            "timing: {t}; {}, memory {}",
            if r.realtime.fifo {
                format!("SCHED_FIFO {}", pacer::vm::realtime::PRIORITY)
            } else {
                "normal scheduling".into()
            },
            if r.realtime.locked {
                "locked"
            } else {
                "not locked"
            }
        );
    }
}
