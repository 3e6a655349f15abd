//! The line editor (rustyline) on a thread of its own, so the machine can run on the main
//! thread while a prompt waits: completion, hints, multi-line blocks, history, and a printer
//! that writes above the prompt.
//!
//! The editor reads one line each time it is given a prompt, and sends back what it read;
//! between two prompts the terminal is in its ordinary mode, so Ctrl-C there is a signal
//! (the main thread's interrupt flag), and at a prompt it is a key ([`FromEditor::Interrupted`]).

use super::complete::{Completion, Vocabulary};
use super::validate::incomplete;
use rustyline::completion::{Completer, FilenameCompleter, Pair};
use rustyline::error::ReadlineError;
use rustyline::highlight::Highlighter;
use rustyline::hint::Hinter;
use rustyline::history::DefaultHistory;
use rustyline::validate::{ValidationContext, ValidationResult, Validator};
use rustyline::{CompletionType, Config, Context, Editor, ExternalPrinter};
use std::borrow::Cow;
use std::path::PathBuf;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;

/// What the editor read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FromEditor {
    /// A complete line (a whole block when it opened one).
    Line(String),
    /// Ctrl-C at the prompt.
    Interrupted,
    /// Ctrl-D, or the end of the input.
    Eof,
}

enum ToEditor {
    Prompt(String),
    Quit,
}

/// A printer for messages while a prompt may be showing.
pub type Printer = Box<dyn ExternalPrinter + Send>;

/// The completion, hint and validation of typed lines, from the shared vocabulary.
pub struct Helper {
    vocabulary: Arc<Mutex<Vocabulary>>,
    files: FilenameCompleter,
}

impl Helper {
    fn vocabulary(&self) -> std::sync::MutexGuard<'_, Vocabulary> {
        // A panic elsewhere cannot make the vocabulary unreadable: it is only ever replaced.
        self.vocabulary
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
    }
}

impl Completer for Helper {
    type Candidate = Pair;

    fn complete(
        &self,
        line: &str,
        pos: usize,
        ctx: &Context<'_>,
    ) -> rustyline::Result<(usize, Vec<Pair>)> {
        let completion = self.vocabulary().complete(line, pos);
        match completion {
            Completion::Words(start, words) => Ok((
                start,
                words
                    .into_iter()
                    .map(|(display, replacement)| Pair {
                        display,
                        replacement,
                    })
                    .collect(),
            )),
            Completion::Path => self.files.complete(line, pos, ctx),
        }
    }
}

impl Hinter for Helper {
    type Hint = String;

    fn hint(&self, line: &str, pos: usize, _ctx: &Context<'_>) -> Option<String> {
        self.vocabulary().hint(line, pos)
    }
}

impl Highlighter for Helper {
    fn highlight_hint<'h>(&self, hint: &'h str) -> Cow<'h, str> {
        // Dim, so a hint is not mistaken for typed text.
        Cow::Owned(format!("\x1b[2m{hint}\x1b[0m"))
    }
}

impl Validator for Helper {
    fn validate(&self, ctx: &mut ValidationContext<'_>) -> rustyline::Result<ValidationResult> {
        let dialect = self.vocabulary().dialect;
        Ok(if incomplete(ctx.input(), dialect) {
            ValidationResult::Incomplete
        } else {
            ValidationResult::Valid(None)
        })
    }
}

impl rustyline::Helper for Helper {}

/// The editor thread, seen from the main thread.
pub struct EditorThread {
    to: Sender<ToEditor>,
    from: Receiver<FromEditor>,
    thread: Option<JoinHandle<()>>,
}

impl EditorThread {
    /// Start the editor. `history`: the file to load and save it in. Returns the thread and
    /// a printer when the terminal has one (not when input or output is not a terminal).
    pub fn start(
        vocabulary: Arc<Mutex<Vocabulary>>,
        history: Option<PathBuf>,
    ) -> Result<(EditorThread, Option<Printer>), String> {
        let (to, to_rx) = channel::<ToEditor>();
        let (from_tx, from) = channel::<FromEditor>();
        let (ready_tx, ready_rx) = channel::<Result<Option<Printer>, String>>();
        let thread = std::thread::Builder::new()
            .name("pacer-repl-editor".into())
            .spawn(move || editor_thread(vocabulary, history, to_rx, from_tx, ready_tx))
            .map_err(|e| format!("cannot start the line editor: {e}"))?;
        let printer = match ready_rx.recv() {
            Ok(Ok(p)) => p,
            Ok(Err(e)) => return Err(e),
            Err(_) => return Err("the line editor stopped at its start".into()),
        };
        Ok((
            EditorThread {
                to,
                from,
                thread: Some(thread),
            },
            printer,
        ))
    }

    /// Show `prompt` and read the next line.
    pub fn prompt(&self, prompt: &str) {
        // A closed editor shows up as the end of the input at the next receive.
        let _ = self.to.send(ToEditor::Prompt(prompt.to_string()));
    }

    /// What the editor sent, if anything came within `wait` (None: wait as long as it takes).
    pub fn receive(&self, wait: Option<std::time::Duration>) -> Option<FromEditor> {
        match wait {
            None => Some(self.from.recv().unwrap_or(FromEditor::Eof)),
            Some(d) => match self.from.recv_timeout(d) {
                Ok(m) => Some(m),
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => None,
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => Some(FromEditor::Eof),
            },
        }
    }

    /// Save the history and end the thread.
    pub fn close(mut self) {
        let _ = self.to.send(ToEditor::Quit);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn editor_thread(
    vocabulary: Arc<Mutex<Vocabulary>>,
    history: Option<PathBuf>,
    to_rx: Receiver<ToEditor>,
    from_tx: Sender<FromEditor>,
    ready: Sender<Result<Option<Printer>, String>>,
) {
    let config = Config::builder()
        .completion_type(CompletionType::List)
        .auto_add_history(false)
        .max_history_size(2000)
        .map(|b| b.build());
    let config = match config {
        Ok(c) => c,
        Err(e) => {
            let _ = ready.send(Err(format!("line editor: {e}")));
            return;
        }
    };
    let mut editor: Editor<Helper, DefaultHistory> = match Editor::with_config(config) {
        Ok(e) => e,
        Err(e) => {
            let _ = ready.send(Err(format!("cannot open the line editor: {e}")));
            return;
        }
    };
    editor.set_helper(Some(Helper {
        vocabulary,
        files: FilenameCompleter::new(),
    }));
    if let Some(h) = &history {
        // No history yet is the ordinary first start.
        let _ = editor.load_history(h);
    }
    let printer = editor
        .create_external_printer()
        .ok()
        .map(|p| Box::new(p) as Printer);
    if ready.send(Ok(printer)).is_err() {
        return;
    }
    while let Ok(ToEditor::Prompt(prompt)) = to_rx.recv() {
        let message = match editor.readline(&prompt) {
            Ok(line) => {
                if !line.trim().is_empty() {
                    let _ = editor.add_history_entry(line.as_str());
                }
                FromEditor::Line(line)
            }
            Err(ReadlineError::Interrupted) => FromEditor::Interrupted,
            Err(_) => FromEditor::Eof,
        };
        if from_tx.send(message).is_err() {
            break;
        }
    }
    if let Some(h) = &history {
        if let Some(dir) = h.parent() {
            let _ = std::fs::create_dir_all(dir);
        }
        let _ = editor.save_history(h);
    }
}
