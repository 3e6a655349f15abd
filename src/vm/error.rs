//! Run-time errors: what went wrong, when, and where — in a program, the exact expression or
//! statement whose instruction failed (shown underlined in its line, as compile-time problems
//! are), or the device or assignment of the machine that failed.

use crate::diag::{render_located, Problem, SourceFile};
use crate::span::Span;

/// A run-time error.
#[derive(Debug, Clone, PartialEq)]
pub struct RunError {
    /// Task number.
    pub task: usize,
    /// Program number.
    pub program: u32,
    /// Program file (or the machine's part that failed: `machine.toml`, `DSP axes`).
    pub file: String,
    /// Source line (0: not in a program).
    pub line: u32,
    /// Source column, in characters (0: not in a program).
    pub column: u32,
    /// The failing expression or statement in the program's text.
    pub place: Option<(SourceFile, Span)>,
    /// What went wrong.
    pub message: String,
    /// Time of the error, seconds.
    pub time: f64,
}

impl RunError {
    /// An error of the machine itself (a device, an assignment, a program that cannot start),
    /// reported at `file`.
    pub fn machine(file: impl Into<String>, message: String, time: f64) -> RunError {
        RunError {
            task: 0,
            program: 0,
            file: file.into(),
            line: 0,
            column: 0,
            place: None,
            message,
            time,
        }
    }

    /// The error as a diagnostic: its heading, then the program's line with the failing
    /// expression underlined; the heading alone when it is not in a program.
    pub fn render(&self, color: bool) -> String {
        match &self.place {
            Some((source, span)) => {
                // The label under the expression: the message's first clause ("Overflow").
                let label = self.message.split(':').next().unwrap_or(&self.message);
                let problem = Problem::error("pacer::run", *span, &self.message, label);
                let heading = format!(
                    "run-time error at t={} s in {} (task {})",
                    self.time,
                    self.who(),
                    self.task
                );
                render_located(source, &problem, &heading, color)
            }
            None => format!("{self}\n"),
        }
    }

    /// The program, as the messages name it.
    fn who(&self) -> String {
        if self.program == super::REPL_PROGRAM {
            "the typed line".into()
        } else {
            format!("Program.{}", self.program)
        }
    }
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.column > 0 {
            write!(
                f,
                "run-time error at t={} s: task {}, {} ({}) line {}, column {}: {}",
                self.time,
                self.task,
                self.who(),
                self.file,
                self.line,
                self.column,
                self.message
            )
        } else {
            write!(
                f,
                "run-time error at t={} s: task {}, {} ({}) line {}: {}",
                self.time,
                self.task,
                self.who(),
                self.file,
                self.line,
                self.message
            )
        }
    }
}
