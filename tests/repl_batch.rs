//! The REPL drives the batch run's own deterministic kernel: the same steps typed at the
//! prompt and run as a batch `pacer run` give the same trace, byte for byte; a typed statement
//! acts on the machine exactly where it was typed; the binary and the library agree.

use pacer::repl::session::{Ran, Session};
use serde_json::Value;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn scratch(name: &str) -> PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-replb-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `pacer ARGS` with `input` on its standard input (not a terminal: the REPL reads lines).
fn pacer(args: &[&str], input: &str, data: &Path) -> String {
    let mut child = Command::new(env!("CARGO_BIN_EXE_pacer"))
        .args(args)
        .current_dir(root())
        .env("XDG_DATA_HOME", data)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("pacer starts");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(input.as_bytes())
        .expect("script written");
    let out = child.wait_with_output().expect("pacer ends");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "pacer {args:?} failed:\n{text}");
    text
}

fn lines(path: &Path) -> Vec<String> {
    std::fs::read_to_string(path)
        .expect("trace written")
        .lines()
        .map(str::to_string)
        .collect()
}

fn json(line: &str) -> Value {
    serde_json::from_str(line).expect("a JSON trace line")
}

/// Everything but the closing `end` event, which says why each stopped.
fn body(mut trace: Vec<String>) -> Vec<String> {
    let last = trace.pop().expect("a trace");
    assert_eq!(json(&last)["kind"], "end", "the trace is closed: {last}");
    trace
}

#[test]
fn steps_and_inputs_typed_at_the_prompt_give_the_batch_trace() {
    let dir = scratch("batch");
    let repl_trace = dir.join("repl.jsonl");
    let batch_trace = dir.join("batch.jsonl");
    // The operator's coarse/fine minus button, pressed at the prompt between steps …
    let script = format!(
        ":trace {}\n:step 1.5s\n:set DriveInput.5 ON\n:step 300\n:set DriveInput.5 OFF\n:step 2.7s\nQueue.0.QueueOffset\n:quit\n",
        repl_trace.display()
    );
    let said = pacer(&["repl", "programs/labeling"], &script, &dir);
    assert!(said.contains("t=4.5 s (4501 updates"), "{said}");

    // … and the same press in the scenario of a batch run, at the updates the REPL set it.
    let mut scenario =
        std::fs::read_to_string(root().join("programs/labeling/scenario.toml")).expect("scenario");
    scenario.push_str(
        "\n[[input]]\nname = \"DriveInput.5\"\nat = 1.501\nvalue = \"ON\"\n\n[[input]]\nname = \"DriveInput.5\"\nat = 1.801\nvalue = \"OFF\"\n",
    );
    let scenario_file = dir.join("scenario.toml");
    std::fs::write(&scenario_file, scenario).expect("scenario written");
    pacer(
        &[
            "run",
            "programs/labeling",
            "--scenario",
            scenario_file.to_str().expect("utf-8 path"),
            "--for",
            "4.5",
            "--trace",
            batch_trace.to_str().expect("utf-8 path"),
        ],
        "",
        &dir,
    );

    let repl = body(lines(&repl_trace));
    let batch = body(lines(&batch_trace));
    assert!(repl.len() > 100, "a real run: {} events", repl.len());
    for (i, (a, b)) in repl.iter().zip(&batch).enumerate() {
        assert_eq!(a, b, "event {i} differs");
    }
    assert_eq!(repl.len(), batch.len());

    // The press took effect: Program 2 took the fine step off the offset, and the REPL's
    // value is the trace's.
    let offsets: Vec<f64> = batch
        .iter()
        .map(|l| json(l))
        .filter(|e| e["kind"] == "change" && e["name"] == "Queue.0.QueueOffset")
        .filter_map(|e| e["value"].as_f64())
        .collect();
    let last = *offsets.last().expect("the offset changed");
    assert!((last - 9.99).abs() < 1e-9, "offsets {offsets:?}");
    assert!(said.contains("\n9.99\n"), "{said}");
}

/// A session driven in-process as the terminal drives it; its messages.
fn session_script(trace: &Path) -> (Vec<String>, Vec<String>) {
    let mut out: Vec<String> = Vec::new();
    let (mut s, _) =
        Session::open(Some(root().join("programs/labeling")), None, false).expect("labeling loads");
    s.trace_to(trace, &mut out);
    for _ in 0..500 {
        assert!(s.advance(&mut out).is_none());
    }
    assert_eq!(s.enter("Queue.0.QueueOffset = 12", &mut out), Ran::Done);
    for _ in 0..2500 {
        assert!(s.advance(&mut out).is_none());
    }
    assert_eq!(s.enter("Queue.0.QueueOffset", &mut out), Ran::Done);
    s.trace_off(pacer::vm::StopReason::TraceOff, &mut out);
    (out, lines(trace))
}

#[test]
fn a_typed_statement_acts_where_it_was_typed() {
    let dir = scratch("statement");
    let (out, trace) = session_script(&dir.join("a.jsonl"));
    assert!(out.iter().any(|l| l == "12"), "the value printed: {out:?}");
    let events: Vec<Value> = trace.iter().map(|l| json(l)).collect();
    // The write is traced at the update it was typed after (the 500th: tick 499).
    let write = events
        .iter()
        .position(|e| e["kind"] == "change" && e["name"] == "Queue.0.QueueOffset")
        .expect("the typed write is traced");
    assert_eq!(events[write]["tick"], 499);
    assert_eq!(events[write]["value"], 12.0);
    // Every product queued from then on exits 12 after its capture; none was queued before
    // (the first product arrives at t = 1.5 s).
    let queued: Vec<(u64, f64)> = events
        .iter()
        .filter(|e| e["kind"] == "queue_in" && e["object"] == "Queue.0")
        .map(|e| {
            let exit = e["exit"].as_f64().expect("exit") - e["value"].as_f64().expect("value");
            (e["tick"].as_u64().expect("tick"), exit)
        })
        .collect();
    assert!(queued.len() > 10, "{queued:?}");
    for (tick, offset) in &queued {
        assert!(*tick > 499);
        assert!((offset - 12.0).abs() < 1e-9, "tick {tick}: offset {offset}");
    }

    // The same script again: the same trace, byte for byte.
    let (_, again) = session_script(&dir.join("b.jsonl"));
    assert_eq!(trace, again);

    // Up to the typed line the trace is the batch run's.
    let batch = dir.join("batch.jsonl");
    pacer(
        &[
            "run",
            "programs/labeling",
            "--for",
            "3",
            "--trace",
            batch.to_str().expect("utf-8 path"),
        ],
        "",
        &dir,
    );
    let batch = lines(&batch);
    assert_eq!(trace[..write], batch[..write]);
    assert_ne!(trace[write], batch[write]);

    // The binary says and writes what the library does.
    let typed = dir.join("typed.jsonl");
    let said = pacer(
        &["repl", "programs/labeling"],
        &format!(
            ":trace {}\n:step 500\nQueue.0.QueueOffset = 12\n:step 2500\nQueue.0.QueueOffset\n:quit\n",
            typed.display()
        ),
        &dir,
    );
    assert!(said.contains("\n12\n"), "{said}");
    assert_eq!(body(lines(&typed)), body(trace.clone()));
}

/// A typed `Wait For` nothing can satisfy is cut by Ctrl-C (SIGINT, as the terminal sends it
/// between prompts) long before the REPL's one-hour limit: the machine looks at the flag every
/// update (issue 17, "Stuck programs").
#[test]
fn ctrl_c_cancels_a_typed_wait_that_nothing_satisfies() {
    let dir = scratch("ctrl-c");
    let mut child = Command::new(env!("CARGO_BIN_EXE_pacer"))
        .args(["repl", "programs/labeling"])
        .current_dir(root())
        .env("XDG_DATA_HOME", &dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("pacer starts");
    let mut stdin = child.stdin.take().expect("stdin");
    stdin
        .write_all(b"Wait For DriveInput.3 AND DriveInput.4\n")
        .expect("line written");
    stdin.flush().expect("flushed");
    std::thread::sleep(std::time::Duration::from_millis(500));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    stdin.write_all(b":quit\n").expect("quit written");
    drop(stdin);
    let out = child.wait_with_output().expect("pacer ends");
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let at = text
        .split("interrupted at t=")
        .nth(1)
        .unwrap_or_else(|| panic!("no interruption in:\n{text}"));
    let t: f64 = at
        .split(" s")
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no time in: {at}"));
    assert!(t > 0.0 && t < 3600.0, "interrupted at {t} s");
}

/// Strings and arrays at the prompt (issue 16): a program's arrays and string elements are
/// read and joined by typed lines, a new string variable gets its own storage (a second one
/// stays empty), and a DIM typed at the prompt is refused in place.
#[test]
fn strings_and_arrays_at_the_prompt() {
    let dir = scratch("strings");
    std::fs::write(
        dir.join("a.mb"),
        "DIM T(3), N$(2)\nT(1) = 7\nN$(2) = \"ok\"\n",
    )
    .expect("program written");
    let script = ":step 1\nT(1) * 2\nN$(2) + \"!\"\nB$ = \"x\" + N$(2)\nB$\nLEFT$(B$, 2)\nC$ = \"\"\n\"[\" + C$ + \"]\"\nDIM Q(3)\n";
    let folder = dir.to_string_lossy().to_string();
    let out = pacer(&["repl", &folder], script, &dir);
    for want in [
        "14",
        "\"ok!\"",
        "\"xok\"",
        "\"xo\"",
        "\"[]\"",
        "Q cannot be dimensioned here",
    ] {
        assert!(out.contains(want), "no {want} in:\n{out}");
    }
}

/// Array elements watched by name at the prompt (`:watch F&(5) G(1, 2)`: spaces between
/// subscripts allowed), each change printed with the element's name; an element outside its
/// array is refused with its bounds, not a panic.
#[test]
fn array_elements_are_watched_by_name() {
    let dir = scratch("watch-elements");
    std::fs::write(dir.join("a.mb"), "DIM F&(10), G(2, 3)\nF&(5) = 1\n").expect("program written");
    let script = ":watch F&(5) G(1, 2)\n:step 1\nF&(5) = 42\nG(1, 2) = 2.5\n:step 1\n:watch\n:watch F&(11)\n";
    let folder = dir.to_string_lossy().to_string();
    let out = pacer(&["repl", &folder], script, &dir);
    for want in ["F&(5)", "42", "G(1,2)", "2.5"] {
        assert!(out.contains(want), "no {want} in:\n{out}");
    }
    assert!(!out.contains("is not a name"), "{out}");
    assert!(!out.contains("panicked"), "{out}");
    assert!(
        out.contains("Subscript out of range: F&(11) is outside F&(0 to 10)"),
        "{out}"
    );
}
