//! A REPL session: the live machine, the layout typed lines compile into, the dialect, the
//! watches and the trace. No terminal here: everything is said through [`Output`], so a test
//! drives a session in-process exactly as the terminal does.

use super::complete::Vocabulary;
use super::line::{self, Parsed};
use crate::check::motionbasic::Variables;
use crate::check::typed::Program;
use crate::check::{check, check_expr, CheckEnv, Ty};
use crate::compile::{compile, compile_expr, Layout};
use crate::diag::{Diagnostics, Level, Problem, SourceFile};
use crate::load::{load_with, LoadOptions, LoadRequest};
use crate::registry::{Kind, SlotId, ValueType};
use crate::syntax::ast::{Expr, ExprKind, Name, ProgramAst, Stmt, StmtKind};
use crate::syntax::Dialect;
use crate::trace::Trace;
use crate::vm::live::{LineRun, TaskView};
use crate::vm::task::TaskState;
use crate::vm::{Machine, RunError, StopReason, REPL_PROGRAM};
use indexmap::IndexMap;
use std::path::{Path, PathBuf};

/// Where a session's messages go.
pub trait Output {
    /// One message (may hold several lines).
    fn line(&mut self, text: String);
}

impl Output for Vec<String> {
    fn line(&mut self, text: String) {
        self.push(text);
    }
}

/// MotionBASIC variables a session can add from typed lines (the registry is fixed once the
/// machine runs, so slots are set aside at load).
pub const SPARE_VARIABLES: usize = 64;

/// The name typed lines carry in diagnostics.
const TYPED: &str = "typed line";

/// One watched member or variable.
#[derive(Debug, Clone)]
struct Watch {
    name: String,
    slot: SlotId,
    ty: ValueType,
    last: f64,
}

/// What became of a typed line.
#[derive(Debug, Clone, PartialEq)]
pub enum Ran {
    /// It ran to its end (an expression's value has been printed).
    Done,
    /// It waits: the machine must run on until it ends.
    Blocked,
    /// It did not run (problems printed) or failed at run time (error printed).
    Failed,
}

/// A REPL session on one machine.
pub struct Session {
    machine: Machine,
    layout: Layout,
    dialect: Dialect,
    folder: Option<PathBuf>,
    sources: IndexMap<u32, SourceFile>,
    /// Typed lines by the chunk they compiled to.
    typed: IndexMap<usize, String>,
    watches: Vec<Watch>,
    trace_path: Option<PathBuf>,
    color: bool,
    /// The lowest subscript of the programs' arrays that do not start at 0.
    array_lower: IndexMap<String, u32>,
}

impl Session {
    /// Load `folder` (None: the empty default machine). `dialect`: of typed lines (default:
    /// MotionBASIC when every program is, else PowerTools). Ok: the session and the load's
    /// warnings, rendered; Err: the problems, rendered.
    pub fn open(
        folder: Option<PathBuf>,
        dialect: Option<Dialect>,
        color: bool,
    ) -> Result<(Session, String), String> {
        if let Some(f) = &folder {
            if !f.exists() {
                return Err(format!(
                    "error: no folder {} (give a machine folder such as programs/labeling)",
                    f.display()
                ));
            }
        }
        let req = LoadRequest {
            paths: folder.iter().cloned().collect(),
            machine: None,
            scenario: None,
        };
        let options = LoadOptions {
            allow_no_programs: true,
            spare_basic_vars: SPARE_VARIABLES,
        };
        let loaded = load_with(&req, &options).map_err(|d| d.render(color))?;
        let all_basic = !loaded.sources.is_empty()
            && loaded
                .sources
                .values()
                .all(|f| Dialect::of_path(Path::new(&f.name)) == Some(Dialect::MotionBasic));
        let dialect = dialect.unwrap_or(if all_basic {
            Dialect::MotionBasic
        } else {
            Dialect::PowerTools
        });
        let tick_ns = loaded.image.tick_ns;
        let warnings = loaded.warnings.render(color);
        let mut machine = Machine::new(loaded.image, Trace::new(None, tick_ns));
        machine.keep_printed();
        let session = Session {
            machine,
            layout: loaded.layout,
            dialect,
            folder,
            sources: loaded.sources,
            typed: IndexMap::new(),
            watches: Vec::new(),
            trace_path: None,
            color,
            array_lower: loaded.array_lower,
        };
        Ok((session, warnings))
    }

    /// One line describing the machine loaded.
    pub fn describe(&self) -> String {
        let programs = self.machine.program_numbers();
        let what = match &self.folder {
            Some(f) => format!("{} ({})", self.machine.name(), f.display()),
            None => "the empty default machine".to_string(),
        };
        format!(
            "{what}: {} program(s), update {} ms, typed lines in {}",
            programs.len(),
            self.machine.tick_ns() as f64 / 1e6,
            dialect_name(self.dialect)
        )
    }

    /// The folder loaded, if any.
    pub fn folder(&self) -> Option<&Path> {
        self.folder.as_deref()
    }

    /// The machine.
    pub fn machine(&self) -> &Machine {
        &self.machine
    }

    /// The language of typed lines.
    pub fn dialect(&self) -> Dialect {
        self.dialect
    }

    /// Set the language of typed lines.
    pub fn set_dialect(&mut self, dialect: Dialect) {
        self.dialect = dialect;
    }

    /// What completion offers now.
    pub fn vocabulary(&self) -> Vocabulary {
        Vocabulary::new(self.machine.registry(), self.dialect)
    }

    /// Simulated time of the last update, seconds.
    pub fn time(&self) -> f64 {
        self.machine.time()
    }

    /// The update period, seconds.
    pub fn update_seconds(&self) -> f64 {
        self.machine.tick_ns() as f64 / 1e9
    }

    /// Updates computed so far.
    pub fn updates(&self) -> u64 {
        if self.machine.has_stepped() {
            self.machine.tick() + 1
        } else {
            0
        }
    }

    /// Compute one update and report the watched changes. A run-time error (a program's, or
    /// the typed line's: then its `program` is [`REPL_PROGRAM`]) is returned, not printed.
    pub fn advance(&mut self, out: &mut dyn Output) -> Option<RunError> {
        self.machine.advance();
        self.report_printed(out);
        self.report_watches(out);
        self.machine.take_error()
    }

    /// Show what the programs and typed lines printed, as they printed it.
    fn report_printed(&mut self, out: &mut dyn Output) {
        for line in self.machine.take_printed() {
            out.line(line);
        }
    }

    /// Where the line on the REPL task is: Done once it has ended.
    pub fn line_state(&mut self) -> LineRun {
        self.machine.line_outcome()
    }

    /// Drop the line still waiting on the REPL task.
    pub fn cancel_line(&mut self) {
        self.machine.cancel_line();
    }

    /// A run-time error as the REPL says it: shown in its line, the failing expression
    /// underlined (in the typed line, or in the program's file).
    pub fn error_text(&self, e: &RunError) -> String {
        e.render(self.color).trim_end().to_string()
    }

    /// Run a typed line (statements or an expression) now, at the time of the last update.
    pub fn enter(&mut self, text: &str, out: &mut dyn Output) -> Ran {
        let file = SourceFile::new(TYPED, text);
        let parsed = match line::parse(text, self.dialect, self.machine.registry()) {
            Ok(p) => p,
            Err(problems) => {
                self.report(&file, problems, out);
                return Ran::Failed;
            }
        };
        if self.dialect == Dialect::MotionBasic {
            if let Err(p) = self.declare_variables(&parsed) {
                self.report(&file, vec![p], out);
                return Ran::Failed;
            }
        }
        let (checked, problems) = self.check(&parsed);
        let failed = problems.iter().any(|p| p.level == Level::Error);
        self.report(&file, problems, out);
        if failed {
            return Ran::Failed;
        }
        let registry = self.machine.registry();
        let (chunk, result) = match &parsed {
            Parsed::Expression(Expr {
                kind: ExprKind::Name(n),
                ..
            }) => {
                // A name is read, not run: no task needed.
                match line::resolve(registry, n, self.dialect) {
                    Ok(r) => {
                        let v = self.machine.values()[r.slot as usize];
                        out.line(self.show(r.ty, v, &r.name));
                        return Ran::Done;
                    }
                    Err(p) => {
                        self.report(&file, vec![p], out);
                        return Ran::Failed;
                    }
                }
            }
            _ => {
                let compiled = match &checked {
                    Some(Checked::Expression(e)) => {
                        compile_expr(e, text, TYPED, REPL_PROGRAM, &mut self.layout)
                            .map(|(chunk, reg)| (chunk, Some((reg, e.ty))))
                    }
                    Some(Checked::Statements(program)) => {
                        compile(program, text, TYPED, REPL_PROGRAM, &mut self.layout)
                            .map(|chunk| (chunk, None))
                    }
                    None => return Ran::Failed,
                };
                match compiled {
                    Ok(c) => c,
                    Err(problems) => {
                        self.report(&file, problems, out);
                        return Ran::Failed;
                    }
                }
            }
        };
        let index = self.machine.add_chunk(chunk, &self.layout);
        self.typed.insert(index, text.to_string());
        let ran = self.machine.run_line(index);
        self.report_printed(out);
        let ran = match ran {
            Err(message) => {
                out.line(format!("error: {message}"));
                Ran::Failed
            }
            Ok(LineRun::Failed(e)) => {
                out.line(self.error_text(&e));
                Ran::Failed
            }
            Ok(LineRun::Blocked) => Ran::Blocked,
            Ok(LineRun::Done) => {
                if let Some((reg, ty)) = result {
                    let v = self.machine.values()[reg as usize];
                    out.line(self.show_value(v, ty));
                }
                Ran::Done
            }
        };
        self.report_watches(out);
        ran
    }

    /// Give every MotionBASIC variable the line uses, and no program declared, a spare slot.
    fn declare_variables(&mut self, parsed: &Parsed) -> Result<(), Problem> {
        let mut vars = Variables::default();
        match parsed {
            Parsed::Statements(ast) => vars.collect(ast),
            Parsed::Expression(e) => vars.collect(&wait_for(e)),
        }
        for (spelling, ty) in vars.all.values() {
            let known = self
                .machine
                .registry()
                .of(Kind::BasicVar)
                .names
                .contains_key(&spelling.to_ascii_lowercase());
            if known {
                continue;
            }
            let Some(slot) = self.machine.declare_basic_var(spelling, *ty) else {
                return Err(Problem::error(
                    "pacer::repl::variables",
                    crate::span::Span::new(0, 0),
                    format!("no room for the new variable {spelling}: a session can add {SPARE_VARIABLES}"),
                    "here",
                )
                .with_help("use a variable the programs already have, or :reset"));
            };
            // A string variable holds its own cell of the string table.
            if crate::compile::is_text_name(spelling) {
                let cell = self.layout.cell();
                self.machine.bind_text_cell(slot, cell, &self.layout);
            }
        }
        Ok(())
    }

    /// Check a typed line: its checked form (a name read needs none) and its problems.
    fn check(&self, parsed: &Parsed) -> (Option<Checked>, Vec<Problem>) {
        let registry = self.machine.registry();
        let programs = self.machine.program_numbers();
        let env = CheckEnv {
            registry,
            loaded_programs: &programs,
            all_programs: true,
        };
        match (self.dialect, parsed) {
            // A name is read as it is, whatever its type (strings, axis sets too).
            (
                _,
                Parsed::Expression(Expr {
                    kind: ExprKind::Name(n),
                    ..
                }),
            ) => match line::resolve(registry, n, self.dialect) {
                Ok(r) if line::readable(&r) => (None, Vec::new()),
                Ok(r) => (
                    None,
                    vec![Problem::error(
                        "pacer::repl::not_readable",
                        n.span,
                        format!("{} cannot be read", r.name),
                        "an action or a write-only input",
                    )],
                ),
                Err(p) => (None, vec![p]),
            },
            (dialect, Parsed::Statements(ast)) => {
                let (program, problems) = check(ast, dialect, &env, &self.known_variables());
                (Some(Checked::Statements(program)), problems)
            }
            (dialect, Parsed::Expression(e)) => {
                let (e, problems) = check_expr(e, dialect, &env, &self.known_variables());
                (e.map(Checked::Expression), problems)
            }
        }
    }

    /// Every MotionBASIC variable, all taken as assigned: at the prompt, reading a variable
    /// is asking for its value, not a slip.
    fn known_variables(&self) -> Variables {
        let registry = self.machine.registry();
        let t = registry.of(Kind::BasicVar);
        Variables::known(
            t.display.iter().enumerate().map(|(i, name)| {
                let slot = t.slot(i as u32, 0, false) as usize;
                (name, registry.slots[slot].ty)
            }),
            &self.array_lower,
        )
    }

    fn report(&self, file: &SourceFile, problems: Vec<Problem>, out: &mut dyn Output) {
        if problems.is_empty() {
            return;
        }
        let mut d = Diagnostics::new();
        // The parser speaks of files; here it is one typed line.
        let problems = problems
            .into_iter()
            .map(|mut p| {
                p.message = p.message.replace("the file ends", "the line ends");
                p
            })
            .collect();
        d.extend_file(file, problems);
        out.line(d.render(self.color).trim_end().to_string());
    }

    /// A member's value as the REPL prints it.
    fn show(&self, ty: ValueType, v: f64, name: &str) -> String {
        match ty {
            ValueType::Bit => on_off(v).to_string(),
            _ if crate::compile::is_text_name(name) => match self.machine.strings().get(v as usize)
            {
                Some(s) if v >= 0.0 && v.fract() == 0.0 => format!("\"{s}\""),
                _ => "\"\"".to_string(),
            },
            // An axis set is a mask: bit N-1 for axis N.
            _ if name.ends_with('~') && v.fract() == 0.0 && (0.0..65536.0).contains(&v) => {
                let bits = v as u32;
                let axes: Vec<String> = (1..=16u32)
                    .filter(|n| bits & (1 << (n - 1)) != 0)
                    .map(|n| n.to_string())
                    .collect();
                format!("{{{}}}", axes.join(", "))
            }
            _ => number(v),
        }
    }

    fn show_value(&self, v: f64, ty: Ty) -> String {
        match ty {
            Ty::Bool => on_off(v).to_string(),
            Ty::Str => match self.machine.strings().get(v as usize) {
                Some(s) if v >= 0.0 && v.fract() == 0.0 => format!("\"{s}\""),
                _ => "\"\"".to_string(),
            },
            _ => number(v),
        }
    }

    /// Watch `names` (print each change from now on). Err: the first name that cannot be.
    pub fn watch(&mut self, names: &[String], out: &mut dyn Output) {
        if names.is_empty() {
            if self.watches.is_empty() {
                out.line("nothing watched (:watch NAME…)".into());
            }
            for w in &self.watches {
                let v = self.machine.values()[w.slot as usize];
                out.line(format!(
                    "watching {} = {}",
                    w.name,
                    self.show(w.ty, v, &w.name)
                ));
            }
            return;
        }
        for n in names {
            match self.resolve_text(n) {
                Err(message) => out.line(message),
                Ok(r) if !line::readable(&r) => out.line(format!(
                    "{} cannot be watched: it is {}",
                    r.name,
                    if r.access == crate::registry::Access::Action {
                        "an action"
                    } else {
                        "a write-only input"
                    }
                )),
                Ok(r) => {
                    let v = self.machine.values()[r.slot as usize];
                    out.line(format!(
                        "watching {} = {}",
                        r.name,
                        self.show(r.ty, v, &r.name)
                    ));
                    if !self.watches.iter().any(|w| w.slot == r.slot) {
                        self.watches.push(Watch {
                            name: r.name,
                            slot: r.slot,
                            ty: r.ty,
                            last: v,
                        });
                    }
                }
            }
        }
    }

    /// Stop watching `names` (all when empty).
    pub fn unwatch(&mut self, names: &[String], out: &mut dyn Output) {
        if names.is_empty() {
            out.line(format!("stopped watching {} name(s)", self.watches.len()));
            self.watches.clear();
            return;
        }
        for n in names {
            match self.resolve_text(n) {
                Err(message) => out.line(message),
                Ok(r) => {
                    let before = self.watches.len();
                    self.watches.retain(|w| w.slot != r.slot);
                    if self.watches.len() == before {
                        out.line(format!("{} was not watched", r.name));
                    } else {
                        out.line(format!("stopped watching {}", r.name));
                    }
                }
            }
        }
    }

    /// The names watched.
    pub fn watched(&self) -> Vec<String> {
        self.watches.iter().map(|w| w.name.clone()).collect()
    }

    fn report_watches(&mut self, out: &mut dyn Output) {
        let values = self.machine.values();
        let t = self.machine.time();
        for i in 0..self.watches.len() {
            let v = values[self.watches[i].slot as usize];
            if v.to_bits() != self.watches[i].last.to_bits() {
                self.watches[i].last = v;
                let w = &self.watches[i];
                out.line(format!(
                    "t={t} s  {} = {}",
                    w.name,
                    self.show(w.ty, v, &w.name)
                ));
            }
        }
    }

    /// Resolve a name typed as a command argument, in the session's dialect.
    fn resolve_text(&self, text: &str) -> Result<crate::registry::Resolved, String> {
        let ok = !text.is_empty()
            && text
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "_.&~@%!#$[](),".contains(c))
            && !text.split('.').any(str::is_empty);
        if !ok {
            return Err(format!("`{text}` is not a name"));
        }
        let name = Name::from_token(text, 0);
        line::resolve(self.machine.registry(), &name, self.dialect).map_err(|p| match p.help {
            Some(h) => format!("{}: {h}", p.message),
            None => p.message,
        })
    }

    /// Set an input from the next update on.
    pub fn set_input(&mut self, name: &str, on: bool, out: &mut dyn Output) {
        let r = match self.resolve_text(name) {
            Ok(r) => r,
            Err(message) => {
                out.line(message);
                return;
            }
        };
        let input = matches!(r.kind, Kind::DriveInput | Kind::ModuleInput)
            || (r.kind == Kind::DriveIO && r.name.ends_with(".In"));
        if !input {
            out.line(format!(
                "{} is not an input (DriveInput.N, ModuleInput.N, DriveIO.N.In); to change it, assign it: {} = …",
                r.name, r.name
            ));
            return;
        }
        self.machine.set_input(r.slot, on);
        let next = if self.machine.has_stepped() {
            self.machine.tick() + 1
        } else {
            0
        };
        out.line(format!(
            "{} {} from the next update (t={} s)",
            r.name,
            on_off(f64::from(on)),
            next as f64 * self.machine.tick_ns() as f64 / 1e9
        ));
    }

    /// Every task: program, line, state, what it waits for.
    pub fn tasks(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if !self.machine.has_stepped() && self.typed.is_empty() {
            lines.push(
                "(the machine has not started: its programs start at the first update)".into(),
            );
        }
        for v in self.machine.task_views() {
            lines.push(self.task_line(&v));
        }
        lines
    }

    fn task_line(&self, v: &TaskView) -> String {
        let who = if v.repl {
            "REPL".to_string()
        } else {
            format!("task {}", v.task)
        };
        if v.state == TaskState::Free {
            return format!("{who:<7} free");
        }
        let program = if v.repl && v.in_program == REPL_PROGRAM {
            "typed line".to_string()
        } else if v.in_program != v.program && v.program != REPL_PROGRAM {
            format!("Program.{} (in Program.{})", v.program, v.in_program)
        } else {
            format!("Program.{}", v.in_program)
        };
        let text = self.source_line(v).unwrap_or_default();
        let state = match v.state {
            TaskState::Free => String::new(),
            TaskState::Ready => "ready".to_string(),
            TaskState::Waiting { .. } => format!("waiting for: {text}"),
            TaskState::Sleeping { until } => format!(
                "waiting until t={} s: {text}",
                until as f64 * self.machine.tick_ns() as f64 / 1e9
            ),
            TaskState::MotionWait { profile } => {
                format!("waiting for Profile.{profile} to be free: {text}")
            }
        };
        format!("{who:<7} {program:<12} line {:<4} {state}", v.line)
    }

    /// The text of the line a task is at.
    fn source_line(&self, v: &TaskView) -> Option<String> {
        let text: &str = if v.in_program == REPL_PROGRAM {
            self.typed.get(&v.chunk?)?
        } else {
            &self.sources.get(&v.in_program)?.text
        };
        let line = text.lines().nth((v.line as usize).checked_sub(1)?)?;
        Some(line.trim().to_string())
    }

    /// Where the trace goes.
    pub fn trace_path(&self) -> Option<&Path> {
        self.trace_path.as_deref()
    }

    /// Write the trace to `path` from now on (closing the one being written).
    pub fn trace_to(&mut self, path: &Path, out: &mut dyn Output) {
        let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => a == b,
        };
        if self.trace_path.as_deref().is_some_and(|p| same(p, path)) {
            out.line(format!(
                "the trace is already written to {}",
                path.display()
            ));
            return;
        }
        let file = match std::fs::File::create(path) {
            Ok(f) => f,
            Err(e) => {
                out.line(format!(
                    "error: cannot create trace file {}: {e}",
                    path.display()
                ));
                return;
            }
        };
        self.trace_off(StopReason::TraceMoved, out);
        let sink: Box<dyn std::io::Write> =
            Box::new(std::io::BufWriter::with_capacity(1 << 16, file));
        let tick_ns = self.machine.tick_ns();
        self.machine.set_trace(Trace::new(Some(sink), tick_ns));
        self.trace_path = Some(path.to_path_buf());
        out.line(format!(
            "trace: {} (from t={} s)",
            path.display(),
            self.time()
        ));
    }

    /// Close the trace being written, if any, with an `end` event giving `reason`.
    pub fn trace_off(&mut self, reason: StopReason, out: &mut dyn Output) {
        let Some(path) = self.trace_path.take() else {
            return;
        };
        let result = self.machine.end_trace(&reason);
        let tick_ns = self.machine.tick_ns();
        self.machine.set_trace(Trace::new(None, tick_ns));
        match result {
            Ok(()) => out.line(format!("trace closed: {}", path.display())),
            Err(e) => out.line(format!("error: writing the trace {}: {e}", path.display())),
        }
    }

    /// Carry the watches of `old` over to this session, where their names still resolve.
    pub fn adopt_watches(&mut self, old: &Session, out: &mut dyn Output) {
        let names = old.watched();
        if !names.is_empty() {
            self.watch(&names, out);
        }
    }
}

/// A statement that checks `e` as a number: how a MotionBASIC expression is checked.
/// A typed line, checked.
enum Checked {
    /// Statements.
    Statements(Program),
    /// An expression whose value is printed.
    Expression(crate::check::typed::Expr),
}

fn wait_for(e: &Expr) -> ProgramAst {
    ProgramAst {
        body: vec![Stmt {
            kind: StmtKind::WaitFor(e.clone()),
            span: e.span,
        }],
    }
}

fn on_off(v: f64) -> &'static str {
    if v != 0.0 {
        "ON"
    } else {
        "OFF"
    }
}

/// A number as the REPL prints it: integers without a fraction, others in the fewest digits
/// that read back the same.
pub fn number(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

/// The dialect's name for people.
pub fn dialect_name(d: Dialect) -> &'static str {
    match d {
        Dialect::PowerTools => "PowerTools",
        Dialect::MotionBasic => "MotionBASIC",
    }
}
