//! Fuzz target for the files around the programs: every example machine's `machine.toml` and
//! `scenario.toml` (`programs/*/`), mutated structurally, then loaded with the machine's own
//! programs and, when it loads, run for 20 simulated milliseconds. Mutations: a key dropped,
//! duplicated into another table or under a new name, retyped (text, number, boolean, array,
//! table, date); numbers made huge, negative, fractional, NaN or infinite; a table written as an
//! array of tables and the other way round; strange characters (NUL, zero-width, direction
//! marks, long text) in keys and values; bytes of the text changed.
//!
//! Every input must end within its time (`PACER_FUZZ_HANG_SECS`, default 30 s), without a
//! panic or an abort, and no message (the load's problems, the run-time error) may name a Rust
//! type. The ordinary run does 300 inputs; the long one:
//!
//! ```sh
//! PACER_FUZZ_CASES=1000000 cargo test --release --test fuzz_config -- --nocapture
//! ```
//!
//! `PACER_FUZZ_SEED` picks another stream. A failing input is written to
//! `CARGO_TARGET_TMPDIR/fuzz_config/` with its folder's name.

mod common;

use pacer::config::files::Memory;
use pacer::load::{load_from, LoadOptions, LoadRequest};
use pacer::trace::Trace;
use pacer::vm::Machine;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use toml::Value;

/// One example machine: its folder's files (programs, machine.toml, scenario.toml).
struct Example {
    name: String,
    files: Vec<(String, String)>,
}

fn examples() -> Vec<Example> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("programs");
    let mut out = Vec::new();
    let mut dirs = vec![root.clone()];
    while let Some(d) = dirs.pop() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&d)
            .expect("programs folder")
            .filter_map(Result::ok)
            .map(|e| e.path())
            .collect();
        entries.sort();
        if entries.iter().any(|p| p.ends_with("machine.toml")) {
            let files = entries
                .iter()
                .filter(|p| p.is_file())
                .filter_map(|p| {
                    let text = std::fs::read_to_string(p).ok()?;
                    Some((p.file_name()?.to_string_lossy().into_owned(), text))
                })
                .collect();
            let name = d
                .strip_prefix(&root)
                .map_or_else(|_| "x".into(), |r| r.to_string_lossy().replace('/', "-"));
            out.push(Example { name, files });
        }
        dirs.extend(entries.into_iter().filter(|p| p.is_dir()));
    }
    out.sort_by(|a, b| a.name.cmp(&b.name));
    assert!(out.len() >= 5, "the example machines under programs/");
    out
}

/// A small deterministic generator (splitmix64): the same seed gives the same inputs.
struct TestRng(u64);

impl TestRng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in `range` (which must not be empty).
    fn random_range(&mut self, range: std::ops::Range<usize>) -> usize {
        range.start + (self.next() % (range.end - range.start) as u64) as usize
    }

    fn random(&mut self) -> bool {
        self.next() & 1 == 1
    }
}

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|s| s.trim().replace('_', "").parse().ok())
        .unwrap_or(default)
}

// ---------------------------------------------------------------------------------------------
// Mutations
// ---------------------------------------------------------------------------------------------

const NUMBERS: &[f64] = &[
    0.0,
    -1.0,
    1.5,
    -0.000001,
    1e300,
    -1e300,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    4294967296.0,
    1e15,
    1e9,
];

const INTEGERS: &[i64] = &[
    0,
    -1,
    1,
    2,
    7,
    65,
    255,
    65536,
    200_000_000,
    4_294_967_295,
    4_294_967_296,
    100_000_000_000,
    i64::MAX,
    i64::MIN,
];

const STRANGE: &[&str] = &[
    "",
    "\0",
    "a\u{200b}b",
    "\u{202e}evil",
    "\u{feff}",
    "ModuleInput.1\0",
    "DriveInput.99999999999",
    "1000000000 s",
    "1e300 s",
    "-5ms",
    "nan",
    "inf s",
    "ON",
    "💥",
    "\t\r\n",
    "µs",
    "Var.",
    "[[machine]]",
];

const KEYS: &[&str] = &[
    "count",
    "budget",
    "tasks",
    "update",
    "duration",
    "size",
    "bounce",
    "at",
    "pitch",
    "width",
    "machine",
    "run",
    "program",
    "products",
    "pulses",
    "marks",
    "seed",
    "missing",
    "steps",
    "queue",
    "number",
    "x\0y",
    "\u{200b}",
    "Capture",
    "DriveInput",
];

fn pick<'a, T>(rng: &mut TestRng, xs: &'a [T]) -> &'a T {
    &xs[rng.random_range(0..xs.len())]
}

fn strange_text(rng: &mut TestRng) -> String {
    if rng.random_range(0..8) == 0 {
        "x".repeat(rng.random_range(1..20_000))
    } else {
        (*pick(rng, STRANGE)).to_string()
    }
}

/// A value of any kind.
fn any_value(rng: &mut TestRng) -> Value {
    match rng.random_range(0..9) {
        0 => Value::Float(*pick(rng, NUMBERS)),
        1 => Value::Integer(*pick(rng, INTEGERS)),
        2 => Value::String(strange_text(rng)),
        3 => Value::Boolean(rng.random()),
        4 => Value::Array(vec![
            Value::Integer(*pick(rng, INTEGERS));
            rng.random_range(0..4)
        ]),
        5 => {
            let mut t = toml::Table::new();
            t.insert(
                (*pick(rng, KEYS)).to_string(),
                Value::Integer(*pick(rng, INTEGERS)),
            );
            Value::Table(t)
        }
        6 => Value::Array(vec![Value::Table(toml::Table::new())]),
        7 => "1979-05-27T07:32:00Z"
            .parse()
            .map_or(Value::Integer(0), Value::Datetime),
        _ => Value::Float(*pick(rng, NUMBERS) * f64::from(rng.random_range(1..1000) as u32)),
    }
}

/// The path (keys and array indices) of every value in `v`.
fn paths(v: &Value, here: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    match v {
        Value::Table(t) => {
            for (k, x) in t {
                here.push(Step::Key(k.clone()));
                out.push(here.clone());
                paths(x, here, out);
                here.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                here.push(Step::Index(i));
                out.push(here.clone());
                paths(x, here, out);
                here.pop();
            }
        }
        _ => {}
    }
}

#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn at_mut<'a>(v: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    let mut cur = v;
    for s in path {
        cur = match (s, cur) {
            (Step::Key(k), Value::Table(t)) => t.get_mut(k)?,
            (Step::Index(i), Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

/// One structural change to `doc`.
fn mutate(doc: &mut Value, rng: &mut TestRng) {
    let mut all = Vec::new();
    paths(doc, &mut Vec::new(), &mut all);
    let target = if all.is_empty() {
        Vec::new()
    } else {
        pick(rng, &all).clone()
    };
    let Some((last, parent)) = target.split_last() else {
        // An empty document: add something.
        if let Value::Table(t) = doc {
            t.insert((*pick(rng, KEYS)).to_string(), any_value(rng));
        }
        return;
    };
    let op = rng.random_range(0..10);
    match op {
        // Drop it.
        0 => match (at_mut(doc, parent), last) {
            (Some(Value::Table(t)), Step::Key(k)) => {
                t.remove(k);
            }
            (Some(Value::Array(a)), Step::Index(i)) if *i < a.len() => {
                a.remove(*i);
            }
            _ => {}
        },
        // Duplicate: under another name here, or into another table.
        1 => {
            let value = at_mut(doc, &target).map(|v| v.clone());
            let other = pick(rng, &all).clone();
            if let (Some(value), Some(Value::Table(t))) = (value, at_mut(doc, &other)) {
                let key = match last {
                    Step::Key(k) if rng.random() => k.clone(),
                    _ => (*pick(rng, KEYS)).to_string(),
                };
                t.insert(key, value);
            }
            if let Some(Value::Array(a)) = at_mut(doc, parent) {
                if let Some(first) = a.first().cloned() {
                    a.push(first);
                }
            }
        }
        // Retype.
        2 | 3 => {
            if let Some(v) = at_mut(doc, &target) {
                *v = any_value(rng);
            }
        }
        // A number made extreme.
        4 | 5 => {
            if let Some(v) = at_mut(doc, &target) {
                *v = match v {
                    Value::Integer(_) => Value::Integer(*pick(rng, INTEGERS)),
                    Value::Float(_) => Value::Float(*pick(rng, NUMBERS)),
                    Value::String(s) if s.chars().any(|c| c.is_ascii_digit()) => {
                        Value::String(format!("{} s", pick(rng, INTEGERS)))
                    }
                    _ => Value::Float(*pick(rng, NUMBERS)),
                };
            }
        }
        // A table as an array of tables, an array of tables as one table.
        6 => {
            if let Some(v) = at_mut(doc, &target) {
                *v = match std::mem::replace(v, Value::Boolean(false)) {
                    Value::Table(t) => Value::Array(vec![Value::Table(t.clone()), Value::Table(t)]),
                    Value::Array(a) => a.into_iter().next().unwrap_or(Value::Integer(1)),
                    other => Value::Array(vec![other]),
                };
            }
        }
        // Strange text in a key or a value.
        7 => match (at_mut(doc, parent), last) {
            (Some(Value::Table(t)), Step::Key(k)) => {
                if let Some(v) = t.remove(k) {
                    t.insert(format!("{k}{}", strange_text(rng)), v);
                }
            }
            _ => {
                if let Some(v) = at_mut(doc, &target) {
                    *v = Value::String(strange_text(rng));
                }
            }
        },
        // A new key of any kind.
        8 => {
            if let Some(Value::Table(t)) = at_mut(doc, parent) {
                t.insert((*pick(rng, KEYS)).to_string(), any_value(rng));
            }
        }
        // A count or size raised to a large number (the fields that allocate).
        _ => {
            if let Some(v) = at_mut(doc, &target) {
                *v = Value::Integer(
                    [
                        1_000,
                        100_000,
                        1_000_000,
                        5_000_001,
                        10_000_000,
                        200_000_000,
                    ][rng.random_range(0..6)],
                );
            }
        }
    }
}

/// A mutated copy of `text`: structural changes when it reads as TOML, then sometimes a change
/// of its bytes.
fn mutated(text: &str, rng: &mut TestRng) -> String {
    let mut out = match text.parse::<toml::Table>() {
        Ok(t) => {
            let mut doc = Value::Table(t);
            for _ in 0..rng.random_range(1..3) {
                mutate(&mut doc, rng);
            }
            toml::to_string(&doc).unwrap_or_else(|_| text.to_string())
        }
        Err(_) => text.to_string(),
    };
    match rng.random_range(0..10) {
        0 if !out.is_empty() => {
            // Raw bytes: cut, or insert a strange character at a char boundary.
            let mut at = rng.random_range(0..out.len());
            while !out.is_char_boundary(at) {
                at -= 1;
            }
            if rng.random() {
                out.truncate(at);
            } else {
                let strange: &&str = pick(rng, STRANGE);
                out.insert_str(at, strange);
            }
        }
        1 => {
            let header = *pick(
                rng,
                &[
                    "[[machine]]",
                    "[machine]\n[machine]",
                    "[[run]]",
                    "[run]",
                    "[products]",
                    "[[io]]",
                ],
            );
            out = format!("{header}\n{out}");
        }
        _ => {}
    }
    out
}

// ---------------------------------------------------------------------------------------------
// The pipeline
// ---------------------------------------------------------------------------------------------

/// Load the example with `file` replaced by `text`; run it for 20 ms when it loads. Every
/// message it gave.
fn exercise(example: &Example, file: &str, text: &str) -> (bool, Vec<String>) {
    let mut memory = Memory::new();
    for (name, body) in &example.files {
        let body = if name == file { text } else { body.as_str() };
        memory = memory.file(Path::new("m").join(name), body.to_string());
    }
    let req = LoadRequest {
        paths: vec![PathBuf::from("m")],
        ..Default::default()
    };
    match load_from(&memory, &req, &LoadOptions::default()) {
        Err(d) => {
            let mut out: Vec<String> = d.items.iter().map(|l| l.problem.message.clone()).collect();
            out.extend(d.items.iter().filter_map(|l| l.problem.help.clone()));
            out.push(d.render_plain());
            (false, out)
        }
        Ok(loaded) => {
            let mut out: Vec<String> = loaded
                .warnings
                .items
                .iter()
                .map(|l| l.problem.message.clone())
                .collect();
            let tick = loaded.image.tick_ns;
            let mut machine = Machine::new(loaded.image, Trace::new(None, tick));
            let summary = machine.run(Some(20_000_000));
            if let Some(e) = &summary.error {
                out.push(e.render(false));
            }
            (true, out)
        }
    }
}

fn save(name: &str, file: &str, text: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz_config");
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(format!("{name}.{file}"));
    let _ = std::fs::write(&path, text);
    path
}

/// Inputs the fuzzing found, each once a hang: they must now end quickly.
#[test]
fn found_inputs_end_quickly() {
    let examples = examples();
    let gantry = examples
        .iter()
        .find(|e| e.name == "pick-and-place-gantry-mode0")
        .expect("the gantry example");
    let machine = gantry
        .files
        .iter()
        .find(|(f, _)| f == "machine.toml")
        .map(|(_, t)| t.replace("lrZDistElliptical = 60.0", "lrZDistElliptical = 1e9"))
        .expect("its machine file");
    assert!(machine.contains("lrZDistElliptical = 1e9"));
    let start = Instant::now();
    let (_, messages) = exercise(gantry, "machine.toml", &machine);
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "{:?}: {messages:?}",
        start.elapsed()
    );
}

#[test]
fn fuzz_machine_and_scenario_files() {
    let cases = env_u64("PACER_FUZZ_CASES", 300);
    let seed = env_u64("PACER_FUZZ_SEED", 0);
    let hang = Duration::from_secs(env_u64("PACER_FUZZ_HANG_SECS", 30));
    let examples = examples();
    // The examples themselves load clean.
    for e in &examples {
        let (loaded, messages) = exercise(e, "", "");
        assert!(loaded, "{}: {messages:?}", e.name);
    }
    let (tx, rx) = mpsc::channel::<(usize, String, &'static str, String)>();
    let (done_tx, done_rx) = mpsc::channel::<Result<u64, String>>();
    let worker = std::thread::Builder::new()
        .name("fuzz-config".into())
        .stack_size(8 << 20)
        .spawn(move || {
            let mut rng = TestRng(seed ^ 0x6366_6766_757a_7a21);
            let mut loaded = 0u64;
            for n in 0..cases {
                let e = &examples[rng.random_range(0..examples.len())];
                let file: &'static str = if rng.random() {
                    "machine.toml"
                } else {
                    "scenario.toml"
                };
                let original = e
                    .files
                    .iter()
                    .find(|(f, _)| f == file)
                    .map_or("", |(_, t)| t.as_str());
                let text = mutated(original, &mut rng);
                let _ = tx.send((n as usize, e.name.clone(), file, text.clone()));
                let result = std::panic::catch_unwind(|| exercise(e, file, &text));
                match result {
                    Err(_) => {
                        let path = save(&e.name, file, &text);
                        let _ = done_tx.send(Err(format!(
                            "input {n} panicked: {} with {} from {}",
                            e.name,
                            file,
                            path.display()
                        )));
                        return;
                    }
                    Ok((ran, messages)) => {
                        loaded += u64::from(ran);
                        for m in &messages {
                            let names = common::rust_names(m);
                            if !names.is_empty() {
                                let path = save(&e.name, file, &text);
                                let _ = done_tx.send(Err(format!(
                                    "input {n} ({}, {file}, saved to {}): a message names {names:?}:\n{m}",
                                    e.name,
                                    path.display()
                                )));
                                return;
                            }
                        }
                    }
                }
            }
            let _ = done_tx.send(Ok(loaded));
        })
        .expect("the fuzz worker starts");
    let start = Instant::now();
    let mut current = (0, String::new(), "", String::new());
    let mut last = Instant::now();
    let mut slowest = Duration::ZERO;
    let ran;
    loop {
        while let Ok(c) = rx.try_recv() {
            slowest = slowest.max(last.elapsed());
            current = c;
            last = Instant::now();
        }
        match done_rx.recv_timeout(Duration::from_millis(50)) {
            Ok(Ok(n)) => {
                ran = n;
                break;
            }
            Ok(Err(e)) => panic!("{e}"),
            Err(mpsc::RecvTimeoutError::Disconnected) => panic!("the fuzz worker stopped"),
            Err(mpsc::RecvTimeoutError::Timeout) => {}
        }
        if last.elapsed() > hang {
            let path = save(&current.1, current.2, &current.3);
            panic!(
                "input {} ({}, {}) still ran after {hang:?}: saved to {}",
                current.0,
                current.1,
                current.2,
                path.display()
            );
        }
    }
    let _ = worker.join();
    eprintln!(
        "fuzz_config: {cases} inputs ({ran} loaded and ran) in {:.1} s, slowest {:.2} s",
        start.elapsed().as_secs_f64(),
        slowest.as_secs_f64()
    );
}
