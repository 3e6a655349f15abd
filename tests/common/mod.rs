//! What the integration tests share: an in-memory trace, and running a loaded machine to the end.
#![allow(dead_code)]

use pacer::config::files::Memory;
use pacer::load::{load_from, LoadOptions, LoadRequest, Loaded};
use pacer::trace::Trace;
use pacer::vm::{Machine, RunSummary};
use serde_json::Value;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// A trace sink the test can read back.
#[derive(Clone, Default)]
pub struct Sink(pub Arc<Mutex<Vec<u8>>>);

impl std::io::Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0
            .lock()
            .map_err(|_| std::io::Error::other("poisoned"))?
            .extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Sink {
    /// Everything written, as text.
    pub fn text(&self) -> String {
        String::from_utf8(self.0.lock().expect("trace buffer").clone()).expect("the trace is UTF-8")
    }
}

/// A finished run.
pub struct Run {
    /// The machine as it ended.
    pub machine: Machine,
    /// How it went.
    pub summary: RunSummary,
    /// The trace as text.
    pub text: String,
    /// The trace, one JSON value per line.
    pub events: Vec<Value>,
}

/// The value of the registry slot named `name` (an array element as `E&(1)`, a PowerTools
/// variable's slot by its registry name) after a run, if there is one.
pub fn slot_value(machine: &Machine, name: &str) -> Option<f64> {
    let slot = machine
        .registry()
        .slots
        .iter()
        .position(|s| s.name.text().eq_ignore_ascii_case(name))?;
    machine.values().get(slot).copied()
}

/// The error a run ended with: its line and message.
#[track_caller]
pub fn run_error(run: &Run) -> (u32, String) {
    let e = run
        .summary
        .error
        .as_ref()
        .expect("the run ends with an error");
    (e.line, e.message.clone())
}

/// Run a loaded machine with its own duration, tracing to memory (changes only, as `pacer run`).
pub fn run_loaded(loaded: Loaded) -> Run {
    run_traced(loaded, false)
}

/// [`run_loaded`], tracing every program write too (`--trace-writes`): for tests that read the
/// values a program wrote, in order, as a log.
pub fn run_loaded_with_writes(loaded: Loaded) -> Run {
    run_traced(loaded, true)
}

fn run_traced(loaded: Loaded, writes: bool) -> Run {
    run_with(loaded, writes, &mut |_| {})
}

/// [`run_loaded`], calling `observe` with the machine after every update (to sample values
/// the trace does not hold at each update).
pub fn run_observed(loaded: Loaded, observe: &mut dyn FnMut(&Machine)) -> Run {
    run_with(loaded, false, observe)
}

fn run_with(loaded: Loaded, writes: bool, observe: &mut dyn FnMut(&Machine)) -> Run {
    let sink = Sink::default();
    let tick = loaded.image.tick_ns;
    let mut trace = Trace::new(Some(Box::new(sink.clone())), tick);
    trace.record_writes(writes);
    let mut machine = Machine::new(loaded.image, trace);
    let summary = machine.run_observed(None, observe);
    machine.finish().expect("in-memory trace");
    let text = sink.text();
    let events = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("each trace line is JSON"))
        .collect();
    Run {
        machine,
        summary,
        text,
        events,
    }
}

/// A fresh folder under the system's temp dir holding `files`.
pub fn project(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (file, text) in files {
        std::fs::write(dir.join(file), text).expect("write a project file");
    }
    dir
}

/// Load a one-program project (program, machine file, scenario), held in memory, and run it to
/// its duration.
pub fn run_project(name: &str, program: &str, machine: &str, scenario: &str) -> Run {
    let loaded = load_memory(
        name,
        &[
            ("program0.pt", program),
            ("machine.toml", machine),
            ("scenario.toml", scenario),
        ],
    );
    match loaded {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    }
}

/// Load the project folder `name` made of `files`, held in memory (no folder on disk).
pub fn load_memory(name: &str, files: &[(&str, &str)]) -> Result<Loaded, pacer::diag::Diagnostics> {
    let memory = files.iter().fold(Memory::new(), |m, (file, text)| {
        m.file(std::path::Path::new(name).join(file), *text)
    });
    load_from(
        &memory,
        &LoadRequest {
            paths: vec![PathBuf::from(name)],
            ..Default::default()
        },
        &LoadOptions::default(),
    )
}

/// Load a project of `files` that must be refused; its diagnostics.
pub fn load_error(name: &str, files: &[(&str, &str)]) -> pacer::diag::Diagnostics {
    match load_memory(name, files) {
        Ok(_) => panic!("{name}: the project should have been refused"),
        Err(d) => d,
    }
}

/// (code, text under the span, message) of every problem of a load; none when it loaded.
pub fn problem_triples<T>(
    result: &Result<T, pacer::diag::Diagnostics>,
) -> Vec<(String, String, String)> {
    match result {
        Ok(_) => Vec::new(),
        Err(d) => d
            .items
            .iter()
            .map(|l| {
                let text = l
                    .file
                    .text
                    .get(l.problem.span.start..l.problem.span.end)
                    .unwrap_or("")
                    .to_string();
                (l.problem.code.to_string(), text, l.problem.message.clone())
            })
            .collect(),
    }
}

/// Run the `pacer` binary with `args` from the crate's folder.
pub fn pacer(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_pacer"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("pacer runs")
}

/// Everything a command printed, stdout then stderr.
pub fn text(o: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// An empty scratch folder of this test process, named `pacer-<group>-<pid>-<name>`.
pub fn scratch_in(group: &str, name: &str) -> PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-{group}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Words that name a Rust type, which no message to a user may show.
pub const RUST_WORDS: &[&str] = &[
    "u8", "u16", "u32", "u64", "u128", "usize", "i8", "i16", "i32", "i64", "i128", "isize", "f32",
    "f64",
];

/// The Rust type names (and serde's wording of them) in `message`, if any.
pub fn rust_names(message: &str) -> Vec<String> {
    let mut found: Vec<String> = message
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| RUST_WORDS.contains(w))
        .map(str::to_string)
        .collect();
    for pat in [
        "struct ",
        "enum ",
        "Option<",
        "Vec<",
        "invalid type: map",
        "as i128",
        "Spanned",
    ] {
        if message.contains(pat) {
            found.push(pat.to_string());
        }
    }
    found
}
