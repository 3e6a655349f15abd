//! Driving a live machine from a tool (the REPL): one update at a time, typed lines run on a
//! task of their own, inputs set by hand, the trace switched on and off.
//!
//! None of this is on the per-update path: a batch run never calls it.

use super::task::{Task, TaskState};
use super::{Machine, RunError, REPL_PROGRAM};
use crate::compile::{Chunk, Layout};
use crate::registry::{Kind, SlotId, SlotName, ValueType};
use crate::trace::Trace;
use crate::world::Edge;

/// Names of the spare MotionBASIC variable slots a REPL machine is loaded with: a typed line
/// may use a variable no program declared, and the registry cannot grow once running. No
/// program can write this name (`#` starts no name in either dialect).
pub const SPARE_VARIABLE: &str = "#spare";

/// What became of a typed line started on the REPL task.
#[derive(Debug, Clone, PartialEq)]
pub enum LineRun {
    /// It ran to its end.
    Done,
    /// It waits (`Wait For`, `Wait For Time`, a busy profile) or spent its budget: the machine
    /// must run on for it to finish.
    Blocked,
    /// A run-time error ended it.
    Failed(RunError),
}

/// One task as tools show it.
#[derive(Debug, Clone, PartialEq)]
pub struct TaskView {
    /// Task number.
    pub task: usize,
    /// The REPL's task (typed lines), not one of the machine's.
    pub repl: bool,
    /// The program started on it ([`REPL_PROGRAM`] for typed lines).
    pub program: u32,
    /// The program whose code it is in now (differs inside `Call Program.N`).
    pub in_program: u32,
    /// The chunk that code is in (a typed line's chunk for the REPL task).
    pub chunk: Option<usize>,
    /// Source line of the next instruction (for a `Wait For`: the line of the wait).
    pub line: u32,
    /// Its state.
    pub state: TaskState,
}

impl Machine {
    /// The last update computed (0 also before the first).
    pub fn tick(&self) -> u64 {
        self.tick
    }

    /// The update period, ns.
    pub fn tick_ns(&self) -> u64 {
        self.image.tick_ns
    }

    /// True once an update has been computed.
    pub fn has_stepped(&self) -> bool {
        self.stepped
    }

    /// The machine's name.
    pub fn name(&self) -> &str {
        &self.image.name
    }

    /// The loaded program numbers.
    pub fn program_numbers(&self) -> Vec<u32> {
        self.image.programs.keys().copied().collect()
    }

    /// Compute the next update (the first: update 0, after [`Machine::begin`]). A run-time
    /// error is left for [`Machine::take_error`].
    pub fn advance(&mut self) {
        self.begin();
        if self.stepped {
            self.tick += 1;
        }
        self.stepped = true;
        self.step();
    }

    /// The run-time error of the last update or typed line, taken: the machine goes on (the
    /// task in error has ended, as in a batch run, which stops there).
    pub fn take_error(&mut self) -> Option<RunError> {
        self.error.take()
    }

    /// Add a chunk compiled with `layout` (an extension of the layout the image was compiled
    /// with): the value array grows by the constants and hidden registers it added.
    pub fn add_chunk(&mut self, chunk: Chunk, layout: &Layout) -> usize {
        let initial = layout.initial_values(&self.image.registry);
        if initial.len() > self.values.len() {
            let from = self.values.len();
            self.values.extend_from_slice(&initial[from..]);
        }
        self.image.chunks.push(chunk);
        // The table grows by the line's literals and cells; the cells a run changed stay.
        let known = self.image.strings.len();
        if let Some(new) = layout.strings.get(known..) {
            self.image.strings.extend_from_slice(new);
        }
        self.image.chunks.len() - 1
    }

    /// A chunk by index.
    pub fn chunk(&self, index: usize) -> Option<&Chunk> {
        self.image.chunks.get(index)
    }

    /// Start chunk `chunk` (from [`Machine::add_chunk`]) on the REPL task and run it at once,
    /// at the time of the last update, before the next: as one more task turn. A line that
    /// blocks stays on the REPL task and goes on as the machine runs. Err when the REPL task
    /// is still busy with another line.
    pub fn run_line(&mut self, chunk: usize) -> Result<LineRun, String> {
        if chunk >= self.image.chunks.len() {
            return Err(format!("no chunk {chunk}"));
        }
        self.begin();
        let ti = match self.repl_task {
            Some(ti) => ti,
            None => {
                // After the machine's tasks: while it is free the round robin over them is
                // exactly what it would be without it.
                self.tasks.push(Task::free());
                self.repl_task = Some(self.tasks.len() - 1);
                self.tasks.len() - 1
            }
        };
        if self.tasks[ti].busy() {
            return Err("the REPL task is still running the last line".into());
        }
        self.tasks[ti] = Task::starting(chunk, REPL_PROGRAM);
        self.run_task(ti);
        Ok(self.line_outcome())
    }

    /// The state of the line on the REPL task: `Done` when it has ended, `Failed` when an error
    /// ended it (taken), else `Blocked`.
    pub fn line_outcome(&mut self) -> LineRun {
        let Some(ti) = self.repl_task else {
            return LineRun::Done;
        };
        if self.error.as_ref().is_some_and(|e| e.task == ti) {
            if let Some(e) = self.error.take() {
                return LineRun::Failed(e);
            }
        }
        if self.tasks[ti].busy() {
            LineRun::Blocked
        } else {
            LineRun::Done
        }
    }

    /// Drop the line on the REPL task, if any (Ctrl-C while it waits).
    pub fn cancel_line(&mut self) {
        if let Some(ti) = self.repl_task {
            if self.tasks[ti].busy() {
                self.end_task(ti, crate::trace::ProgramEvent::Stop);
            }
        }
    }

    /// Every task with its program, line and state (the REPL's last, once it exists).
    pub fn task_views(&self) -> Vec<TaskView> {
        self.tasks
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let chunk = t.frames.last().map(|f| f.chunk);
                let (in_program, line) = match t.frames.last() {
                    Some(f) => {
                        let chunk = &self.image.chunks[f.chunk];
                        let pc = match t.state {
                            TaskState::Waiting { retry, .. } => retry,
                            _ => f.pc,
                        };
                        let line = chunk
                            .lines
                            .get(pc as usize)
                            .or(chunk.lines.last())
                            .copied()
                            .unwrap_or(0);
                        (chunk.program, line)
                    }
                    None => (t.program, 0),
                };
                TaskView {
                    task: i,
                    repl: Some(i) == self.repl_task,
                    program: t.program,
                    in_program,
                    chunk,
                    line,
                    state: t.state,
                }
            })
            .collect()
    }

    /// Set an input from outside, as a scenario `[[input]]` at the time of the next update
    /// would: the edge is applied at that update (with its exact time for captures).
    pub fn set_input(&mut self, slot: SlotId, on: bool) {
        let next = if self.stepped { self.tick + 1 } else { 0 };
        let at = (next as f64 * self.image.tick_ns as f64) / 1e9;
        self.world.inject(vec![Edge { at, slot, on }]);
    }

    /// Write the trace to `trace` from now on; the old one is returned (to be ended with
    /// [`Machine::end_trace`] by the caller, before the swap). A trace started after the run
    /// began opens with its own `start` event, and its first changes are those after now.
    pub fn set_trace(&mut self, trace: Trace) -> Trace {
        let old = std::mem::replace(&mut self.trace, trace);
        if self.trace.enabled() && self.begun {
            let n = self.image.registry.slot_count();
            self.snapshot.clear();
            self.snapshot.extend_from_slice(&self.values[..n]);
            self.trace_start(self.tick);
        }
        old
    }

    /// Write the `end` event (with `reason`) and flush the trace.
    pub fn end_trace(&mut self, reason: &crate::vm::StopReason) -> std::io::Result<()> {
        if self.trace.enabled() {
            let moving: Vec<String> = self.moving().into_iter().map(|m| m.name).collect();
            self.trace.emit(
                self.tick,
                &crate::trace::Event::End {
                    reason: reason.to_string().into(),
                    instructions: self.instructions,
                    moving: moving.iter().map(|m| m.as_str().into()).collect(),
                },
            );
        }
        self.trace.finish()
    }

    /// Give the string variable in `slot` (declared by [`Machine::declare_basic_var`]) its own
    /// cell `cell` of `layout`'s string table, empty.
    pub fn bind_text_cell(&mut self, slot: SlotId, cell: u32, layout: &crate::compile::Layout) {
        let known = self.image.strings.len();
        if let Some(new) = layout.strings.get(known..) {
            self.image.strings.extend_from_slice(new);
        }
        if let Some(v) = self.values.get_mut(slot as usize) {
            *v = f64::from(cell);
        }
        if let Some(v) = self.snapshot.get_mut(slot as usize) {
            *v = f64::from(cell);
        }
    }

    /// Give a spare MotionBASIC variable slot (see [`SPARE_VARIABLE`]) the name `spelling`
    /// and type `ty`. None when every spare is taken.
    pub fn declare_basic_var(&mut self, spelling: &str, ty: ValueType) -> Option<SlotId> {
        let t = self
            .image
            .registry
            .types
            .iter_mut()
            .find(|t| t.def.kind == Kind::BasicVar)?;
        let i = t
            .display
            .iter()
            .position(|d| d.starts_with(SPARE_VARIABLE))?;
        let old = t.display[i].text().to_ascii_lowercase();
        t.names.shift_remove(&old);
        t.names.insert(spelling.to_ascii_lowercase(), i as u32);
        t.display[i] = SlotName::Text(spelling.to_string());
        let slot = t.slot(i as u32, 0, false);
        let info = &mut self.image.registry.slots[slot as usize];
        info.name = SlotName::Text(spelling.to_string());
        info.ty = ty;
        Some(slot)
    }
}
