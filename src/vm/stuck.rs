//! What each task still waits on, at which line: said when a run is cut while programs wait
//! (the one-hour cap, a duration, Ctrl-C), so a program stuck on a condition that never comes
//! true is found without a debugger.

use super::task::TaskState;
use super::{Machine, REPL_PROGRAM};
use crate::trace::{Event, Origin};

/// A task blocked at a statement.
#[derive(Debug, Clone, PartialEq)]
pub struct Waiting {
    /// The task.
    pub task: usize,
    /// The program's number (None for a line typed at the REPL).
    pub program: Option<u32>,
    /// The program's file.
    pub file: String,
    /// 1-based line and column of the statement it waits at.
    pub line: u32,
    /// Column, in characters.
    pub column: u32,
    /// The statement's source line, trimmed.
    pub statement: String,
    /// What it waits for, in words.
    pub what: String,
}

impl std::fmt::Display for Waiting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "task {} waits at {}:{}:{} `{}`: {}",
            self.task, self.file, self.line, self.column, self.statement, self.what
        )
    }
}

impl Machine {
    /// Every task blocked on a wait, a motion profile or a time, with its place.
    pub fn waiting(&self) -> Vec<Waiting> {
        let tick_s = self.image.tick_ns as f64 / 1e9;
        let mut out = Vec::new();
        for (ti, task) in self.tasks.iter().enumerate() {
            let Some(frame) = task.frames.last() else {
                continue;
            };
            let (pc, what) = match task.state {
                TaskState::Waiting { resume, .. } => (
                    resume.saturating_sub(1),
                    "its condition never came true".to_string(),
                ),
                TaskState::Sleeping { until } => (
                    frame.pc.saturating_sub(1),
                    format!("it sleeps until t = {} s", until as f64 * tick_s),
                ),
                TaskState::MotionWait { profile } => {
                    let moving: Vec<String> = self.moving().into_iter().map(|m| m.name).collect();
                    let held = if moving.is_empty() {
                        String::new()
                    } else {
                        format!(" (moving: {})", moving.join(", "))
                    };
                    (
                        frame.pc,
                        format!("motion profile {profile} never became free{held}"),
                    )
                }
                TaskState::Free | TaskState::Ready => continue,
            };
            let Some(chunk) = self.image.chunks.get(frame.chunk) else {
                continue;
            };
            let (line, column, statement) = match chunk.spans.get(pc as usize) {
                Some(span) => {
                    let (l, c) = chunk.source.line_col(*span);
                    let text = chunk
                        .source
                        .text
                        .lines()
                        .nth(l.saturating_sub(1))
                        .unwrap_or("")
                        .trim()
                        .to_string();
                    (l as u32, c as u32, text)
                }
                None => (
                    chunk.lines.get(pc as usize).copied().unwrap_or(0),
                    0,
                    String::new(),
                ),
            };
            out.push(Waiting {
                task: ti,
                program: (chunk.program != REPL_PROGRAM).then_some(chunk.program),
                file: chunk.file.clone(),
                line,
                column,
                statement,
                what,
            });
        }
        out
    }

    /// Trace a warning at each waiting task's statement: the run was cut while it waited.
    pub(super) fn trace_waiting(&mut self, waiting: &[Waiting], why: &str) {
        for w in waiting {
            let message = format!("{why}, the task still waits: {}", w.what);
            self.trace.emit(
                self.tick,
                &Event::Warning {
                    origin: Origin::At {
                        task: w.task,
                        program: w.program,
                        file: w.file.as_str().into(),
                        line: w.line,
                        column: w.column,
                    },
                    message: message.as_str().into(),
                },
            );
        }
    }
}
