//! `pacer repl`: poke at the simulated machine as at a real one. Typed statements run at once
//! on a task of their own, expressions print their value, `:` commands step or run the
//! machine, set inputs, watch members and write the trace.
//!
//! The machine is the batch run's own deterministic kernel ([`crate::vm::Machine`]), driven
//! update by update from the main thread; the line editor runs on a thread of its own so the
//! machine can `:run` in real time while the prompt waits. `:step` and typed lines are exact
//! and repeatable; only where a `:run` stops depends on the wall clock, which paces it.

pub mod commands;
pub mod complete;
pub mod editor;
pub mod line;
pub mod session;
pub mod validate;

use commands::{Command, Speed, StepBy, TraceArg};
use complete::Vocabulary;
use editor::{EditorThread, FromEditor, Printer};
use session::{dialect_name, Output, Ran, Session};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use crate::syntax::Dialect;
use crate::vm::StopReason;

/// How to start the REPL.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// A machine folder; None: the empty default machine.
    pub folder: Option<PathBuf>,
    /// The language of typed lines (default: that of the programs).
    pub dialect: Option<Dialect>,
}

/// How long a typed line may wait, or `:run` go on at full speed, in simulated seconds, before
/// the REPL gives up on it (a `Wait For` that nothing will ever make true).
const WAIT_LIMIT_SECONDS: f64 = crate::vm::DEFAULT_MAX_SECONDS as f64;

/// Updates computed between two looks at the prompt while `:run` goes at full speed.
const MAX_SLICE: u64 = 20_000;

/// How often a paced `:run` computes the updates that are due.
const PACE: Duration = Duration::from_millis(10);
/// The most wall time one slice of updates takes before the REPL looks at its keyboard again.
const SLICE_WALL: Duration = Duration::from_millis(20);

/// Messages to the terminal, in order, above the prompt when one is showing. They go through
/// a thread of their own: the editor's printer may wait for the editor, and the editor for
/// the main thread, which must never wait for it.
struct Console {
    to: Option<std::sync::mpsc::Sender<Printed>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

enum Printed {
    Text(String),
    /// Answer once everything before has been printed.
    Mark(std::sync::mpsc::Sender<()>),
}

/// How long the prompt waits for earlier messages to be printed, so it comes after them. The
/// printer can be held up by a prompt that just closed; the messages then come above the next.
const PRINT_WAIT: Duration = Duration::from_millis(200);

impl Console {
    fn new(mut printer: Option<Printer>) -> Console {
        let (to, from) = std::sync::mpsc::channel::<Printed>();
        let thread = std::thread::Builder::new()
            .name("pacer-repl-output".into())
            .spawn(move || {
                use std::io::Write as _;
                for m in from {
                    let text = match m {
                        Printed::Text(t) => t,
                        Printed::Mark(done) => {
                            let _ = done.send(());
                            continue;
                        }
                    };
                    if let Some(p) = printer.as_mut() {
                        if p.print(format!("{text}\n")).is_ok() {
                            continue;
                        }
                    }
                    // A closed output (a pipe whose reader left) is no reason to stop.
                    let _ = writeln!(std::io::stdout().lock(), "{text}");
                }
            })
            .ok();
        Console {
            to: thread.is_some().then_some(to),
            thread,
        }
    }

    /// Wait (a little) until the messages so far are out: a prompt drawn after them.
    fn flush(&self) {
        if let Some(to) = &self.to {
            let (done, wait) = std::sync::mpsc::channel();
            if to.send(Printed::Mark(done)).is_ok() {
                let _ = wait.recv_timeout(PRINT_WAIT);
            }
        }
    }

    /// Print everything still queued, then stop.
    fn close(&mut self) {
        self.to = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Output for Console {
    fn line(&mut self, text: String) {
        use std::io::Write as _;
        match &self.to {
            Some(to) => {
                if let Err(std::sync::mpsc::SendError(Printed::Text(t))) =
                    to.send(Printed::Text(text))
                {
                    let _ = writeln!(std::io::stdout().lock(), "{t}");
                }
            }
            None => {
                let _ = writeln!(std::io::stdout().lock(), "{text}");
            }
        }
    }
}

/// Where the machine is going.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    /// Stopped; it moves only by `:step` or typed lines that wait.
    Paused,
    /// `:run`: paced from `clock`, when `base` updates had been computed; ends after update
    /// `until` (a count of updates) if set.
    Running {
        clock: Instant,
        base: u64,
        until: Option<u64>,
    },
}

struct Repl {
    session: Session,
    mode: Mode,
    speed: Speed,
    /// A typed line waits on the REPL task: the prompt waits for it.
    waiting: Option<WaitingLine>,
    console: Console,
    interrupt: Arc<AtomicBool>,
    vocabulary: Arc<Mutex<Vocabulary>>,
    color: bool,
    quit: bool,
}

#[derive(Debug, Clone, Copy)]
struct WaitingLine {
    /// Updates computed when it started.
    from: u64,
}

/// Run the REPL; the process's exit code.
pub fn run(options: Options) -> u8 {
    use std::io::IsTerminal;
    // Colour on a terminal, unless the user asked for none (https://no-color.org).
    let color = std::io::stdout().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    let interrupt = Arc::new(AtomicBool::new(false));
    // Ctrl-C outside the prompt (while the machine steps) sets the flag instead of ending the
    // process: nothing typed can end the REPL but :quit and Ctrl-D.
    if let Err(e) = signal_hook::flag::register(signal_hook::consts::SIGINT, interrupt.clone()) {
        eprintln!("warning: Ctrl-C cannot be caught ({e}); it will end the REPL");
    }
    let (session, warnings) = match Session::open(options.folder, options.dialect, color) {
        Ok(s) => s,
        Err(problems) => {
            eprint!("{problems}");
            return 1;
        }
    };
    let vocabulary = Arc::new(Mutex::new(session.vocabulary()));
    let (editor, printer) = match EditorThread::start(vocabulary.clone(), history_file()) {
        Ok(e) => e,
        Err(message) => {
            eprintln!("error: {message}");
            return 1;
        }
    };
    let mut repl = Repl {
        session,
        mode: Mode::Paused,
        speed: Speed::Factor(1.0),
        waiting: None,
        console: Console::new(printer),
        interrupt,
        vocabulary,
        color,
        quit: false,
    };
    if !warnings.trim().is_empty() {
        repl.console.line(warnings.trim_end().to_string());
    }
    let intro = format!(
        "pacer repl: {}. :help for help, :quit to leave.",
        repl.session.describe()
    );
    repl.console.line(intro);
    repl.console.flush();
    editor.prompt(&repl.prompt());
    while !repl.quit {
        if repl.waiting.is_some() {
            repl.wait_step();
            if repl.waiting.is_none() {
                repl.console.flush();
                editor.prompt(&repl.prompt());
            }
            continue;
        }
        let wait = match (repl.mode, repl.speed) {
            (Mode::Paused, _) => None,
            // At full speed only a look at the keyboard between slices.
            (Mode::Running { .. }, Speed::Max) => Some(Duration::ZERO),
            (Mode::Running { .. }, Speed::Factor(_)) => Some(PACE),
        };
        match editor.receive(wait) {
            None => repl.run_step(),
            Some(FromEditor::Line(text)) => {
                repl.interrupt.store(false, Ordering::SeqCst);
                repl.handle(&text);
                if !repl.quit && repl.waiting.is_none() {
                    repl.console.flush();
                    editor.prompt(&repl.prompt());
                }
            }
            Some(FromEditor::Interrupted) => {
                if matches!(repl.mode, Mode::Running { .. }) {
                    repl.pause("interrupted");
                }
                repl.console.flush();
                editor.prompt(&repl.prompt());
            }
            Some(FromEditor::Eof) => repl.quit = true,
        }
    }
    repl.session
        .trace_off(StopReason::ReplEnded, &mut repl.console);
    repl.console.close();
    editor.close();
    0
}

/// The history file in the user's data directory (`$XDG_DATA_HOME/pacer/history`).
fn history_file() -> Option<PathBuf> {
    dirs::data_dir().map(|d| d.join("pacer").join("history"))
}

impl Repl {
    fn prompt(&self) -> String {
        match self.session.dialect() {
            Dialect::PowerTools => "pt> ".to_string(),
            Dialect::MotionBasic => "mb> ".to_string(),
        }
    }

    fn refresh_vocabulary(&self) {
        let v = self.session.vocabulary();
        *self
            .vocabulary
            .lock()
            .unwrap_or_else(PoisonError::into_inner) = v;
    }

    fn interrupted(&self) -> bool {
        self.interrupt.swap(false, Ordering::SeqCst)
    }

    fn handle(&mut self, text: &str) {
        let trimmed = text.trim();
        if trimmed.is_empty() {
            return;
        }
        if trimmed.starts_with(commands::PREFIX) {
            match commands::parse(trimmed) {
                Ok(c) => self.command(c),
                Err(message) => self.console.line(format!("error: {message}")),
            }
            return;
        }
        match self.session.enter(text, &mut self.console) {
            Ran::Done | Ran::Failed => {}
            Ran::Blocked => {
                self.console.line(format!(
                    "waiting from t={} s as the machine runs (Ctrl-C cancels)",
                    self.session.time()
                ));
                self.waiting = Some(WaitingLine {
                    from: self.session.updates(),
                });
            }
        }
        // A MotionBASIC line may have added variables.
        self.refresh_vocabulary();
    }

    fn command(&mut self, c: Command) {
        match c {
            Command::Help(c) => self.console.line(commands::help(c.as_deref())),
            Command::Quit => self.quit = true,
            Command::Pause => match self.mode {
                Mode::Running { .. } => self.pause("paused"),
                Mode::Paused => self.console.line(format!(
                    "not running (t={} s); :run runs the machine",
                    self.session.time()
                )),
            },
            Command::Run(duration) => {
                let until = duration.map(|ns| {
                    let n = (ns as f64 / 1e9 / self.session.update_seconds()).round() as u64;
                    self.target_updates(n)
                });
                self.mode = Mode::Running {
                    clock: Instant::now(),
                    base: self.session.updates(),
                    until,
                };
                let speed = match self.speed {
                    Speed::Max => "at full speed".to_string(),
                    Speed::Factor(1.0) => "in real time".to_string(),
                    Speed::Factor(f) => format!("at {f}x real time"),
                };
                self.console.line(format!(
                    "running from t={} s {speed}; :pause or Ctrl-C stops it",
                    self.session.time()
                ));
            }
            Command::Speed(None) => self.console.line(match self.speed {
                Speed::Max => ":run goes at full speed".into(),
                Speed::Factor(f) => format!(":run goes at {f}x real time"),
            }),
            Command::Speed(Some(s)) => {
                self.speed = s;
                if let Mode::Running { until, .. } = self.mode {
                    // Pace from now at the new speed.
                    self.mode = Mode::Running {
                        clock: Instant::now(),
                        base: self.session.updates(),
                        until,
                    };
                }
                self.command(Command::Speed(None));
            }
            Command::Step(by) => {
                if matches!(self.mode, Mode::Running { .. }) {
                    self.pause("paused");
                }
                let n = match by {
                    StepBy::Updates(n) => n,
                    StepBy::Time(ns) => {
                        let n = (ns as f64 / 1e9 / self.session.update_seconds()).round() as u64;
                        self.target_updates(n) - self.session.updates()
                    }
                };
                self.step(n);
            }
            Command::Set { name, on } => self.session.set_input(&name, on, &mut self.console),
            Command::Watch(names) => self.session.watch(&names, &mut self.console),
            Command::Unwatch(names) => self.session.unwatch(&names, &mut self.console),
            Command::Tasks => {
                for l in self.session.tasks() {
                    self.console.line(l);
                }
            }
            Command::Trace(TraceArg::Show) => self.console.line(match self.session.trace_path() {
                Some(p) => format!("trace: {}", p.display()),
                None => "no trace is written (:trace FILE)".to_string(),
            }),
            Command::Trace(TraceArg::Off) => {
                if self.session.trace_path().is_none() {
                    self.console.line("no trace is written".into());
                }
                self.session
                    .trace_off(StopReason::TraceOff, &mut self.console);
            }
            Command::Trace(TraceArg::To(path)) => self.session.trace_to(&path, &mut self.console),
            Command::Dialect(None) => self.console.line(format!(
                "typed lines are {}",
                dialect_name(self.session.dialect())
            )),
            Command::Dialect(Some(d)) => {
                self.session.set_dialect(d);
                self.refresh_vocabulary();
                self.console
                    .line(format!("typed lines are {}", dialect_name(d)));
            }
            Command::Load(folder) => self.load(Some(folder), None),
            Command::Reset => {
                let folder = self.session.folder().map(|p| p.to_path_buf());
                let dialect = self.session.dialect();
                self.load(folder, Some(dialect));
            }
        }
    }

    /// The update count that puts the clock `n` updates after now (after update 0 first: a
    /// batch run `--for T` computes updates 0 to T/update, so `:step T` from the start does).
    fn target_updates(&self, n: u64) -> u64 {
        let done = self.session.updates();
        if done == 0 {
            n.saturating_add(1)
        } else {
            done.saturating_add(n)
        }
    }

    fn load(&mut self, folder: Option<PathBuf>, dialect: Option<Dialect>) {
        match Session::open(folder, dialect, self.color) {
            Err(problems) => {
                self.console.line(problems.trim_end().to_string());
                self.console
                    .line("(not loaded: the machine is as it was)".to_string());
            }
            Ok((mut session, warnings)) => {
                if !warnings.trim().is_empty() {
                    self.console.line(warnings.trim_end().to_string());
                }
                self.session
                    .trace_off(StopReason::Reloaded, &mut self.console);
                session.adopt_watches(&self.session, &mut self.console);
                self.session = session;
                self.mode = Mode::Paused;
                self.refresh_vocabulary();
                let d = self.session.describe();
                self.console.line(format!("loaded {d}"));
            }
        }
    }

    fn pause(&mut self, why: &str) {
        self.mode = Mode::Paused;
        self.console.line(format!(
            "{why} at t={} s ({} updates)",
            self.session.time(),
            self.session.updates()
        ));
    }

    /// One update; false when a run-time error stopped the machine (reported).
    fn advance(&mut self) -> bool {
        match self.session.advance(&mut self.console) {
            None => true,
            Some(e) => {
                let text = self.session.error_text(&e);
                self.console.line(text);
                if e.program == crate::vm::REPL_PROGRAM {
                    // The typed line failed (and has ended): the machine goes on.
                    self.waiting = None;
                    true
                } else {
                    // A batch run ends at a program's error; here the machine stops there and
                    // may be stepped on (the task in error has ended).
                    if self.waiting.take().is_some() {
                        self.session.cancel_line();
                        self.console.line("the typed line was cancelled".into());
                    }
                    if matches!(self.mode, Mode::Running { .. }) {
                        self.pause("stopped by the error");
                    }
                    false
                }
            }
        }
    }

    /// `:step`: `n` updates at full speed, or until Ctrl-C or a run-time error.
    fn step(&mut self, n: u64) {
        self.interrupt.store(false, Ordering::SeqCst);
        let start = self.session.updates();
        for _ in 0..n {
            if self.interrupted() {
                self.console.line("interrupted".into());
                break;
            }
            if !self.advance() {
                break;
            }
        }
        self.console.line(format!(
            "t={} s ({} updates, {} computed now)",
            self.session.time(),
            self.session.updates(),
            self.session.updates() - start
        ));
    }

    /// `:run` in the background: compute the updates due by now.
    fn run_step(&mut self) {
        let Mode::Running { clock, base, until } = self.mode else {
            return;
        };
        let done = self.session.updates();
        let due = match self.speed {
            Speed::Max => done + MAX_SLICE,
            Speed::Factor(f) => {
                let simulated = clock.elapsed().as_secs_f64() * f;
                let due = base + (simulated / self.session.update_seconds()) as u64;
                due.min(done + MAX_SLICE)
            }
        };
        let due = until.map_or(due, |u| due.min(u));
        // A slice ends after SLICE_WALL of wall time too, so the keyboard (Ctrl-C) is read
        // soon on a heavy machine; where a slice ends does not change what is computed.
        let started = std::time::Instant::now();
        while self.session.updates() < due {
            if !self.advance() {
                return;
            }
            if self.session.updates().is_multiple_of(64) && started.elapsed() > SLICE_WALL {
                break;
            }
        }
        if until.is_some_and(|u| self.session.updates() >= u) {
            self.pause("run ended");
        }
    }

    /// A typed line waits: let the machine run (paced while `:run` is on) until it ends.
    fn wait_step(&mut self) {
        let Some(w) = self.waiting else { return };
        let limit = (WAIT_LIMIT_SECONDS / self.session.update_seconds()) as u64;
        match self.mode {
            Mode::Running { .. } => {
                std::thread::sleep(PACE);
                self.run_step();
            }
            Mode::Paused => {
                // Ctrl-C is looked at every update: a slice must not delay it.
                let started = std::time::Instant::now();
                for _ in 0..MAX_SLICE {
                    if self.interrupt.load(Ordering::SeqCst)
                        || started.elapsed() > SLICE_WALL
                        || !self.advance()
                        || self.waiting.is_none()
                        || self.session.line_state() != crate::vm::live::LineRun::Blocked
                    {
                        break;
                    }
                }
            }
        }
        if self.waiting.is_none() {
            // Ended by an error, already reported.
            return;
        }
        match self.session.line_state() {
            crate::vm::live::LineRun::Blocked => {}
            _ => {
                self.waiting = None;
                let t = self.session.time();
                self.console.line(format!(
                    "done at t={t} s ({} updates later)",
                    self.session.updates() - w.from
                ));
                return;
            }
        }
        if self.interrupted() {
            self.session.cancel_line();
            self.waiting = None;
            if matches!(self.mode, Mode::Running { .. }) {
                self.mode = Mode::Paused;
            }
            self.console.line(format!(
                "interrupted at t={} s: the typed line was cancelled",
                self.session.time()
            ));
        } else if self.session.updates() - w.from >= limit {
            self.session.cancel_line();
            self.waiting = None;
            self.console.line(format!(
                "gave up after {WAIT_LIMIT_SECONDS} s simulated: the typed line was cancelled (t={} s)",
                self.session.time()
            ));
        }
    }
}
