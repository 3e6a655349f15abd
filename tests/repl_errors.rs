//! Nothing a user types can crash the REPL: every mistake gets a message pointing into the
//! typed line, run-time errors of typed lines leave the machine running, and a stream of
//! mangled program lines goes through without a panic.

use pacer::repl::commands;
use pacer::repl::session::{Ran, Session};
use pacer::syntax::Dialect;
use std::path::PathBuf;

fn labeling() -> Session {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("programs/labeling");
    Session::open(Some(dir), None, false)
        .expect("labeling loads")
        .0
}

fn empty(dialect: Dialect) -> Session {
    Session::open(None, Some(dialect), false)
        .expect("the empty machine loads")
        .0
}

/// Enter `text`; what it printed, and how it went.
fn enter(s: &mut Session, text: &str) -> (Ran, String) {
    let mut out = Vec::new();
    let ran = s.enter(text, &mut out);
    (ran, out.join("\n"))
}

#[test]
fn mistakes_are_reported_in_the_typed_line() {
    let mut s = labeling();
    let cases = [
        ("Queue.0.QueueOfset = 3", "did you mean `QueueOffset`?"),
        ("Queue.9.QueueOffset = 3", "Queue.9"),
        ("Queue.0.QueueEmpty = 3", "status"),
        ("Wait For Queue.0.QueueOffset", "ON/OFF"),
        ("If Bit.0 Then", "never closed"),
        ("Endif", "without a matching"),
        ("Goto Nowhere", "no label"),
        ("Call Program.7", "Program.7"),
        ("1 +", "the line ends in the middle"),
        ("Index.0.Initiate + 1", "action"),
        ("\"text\"", "unexpected character"),
    ];
    for (text, needle) in cases {
        let (ran, said) = enter(&mut s, text);
        assert_eq!(ran, Ran::Failed, "{text}: {said}");
        assert!(
            said.contains(needle),
            "{text}: expected {needle:?} in\n{said}"
        );
        assert!(said.contains("typed line:1:"), "{text}: located\n{said}");
    }
    // Nothing of it ran: the machine has not started and the offset is the machine file's.
    let (_, said) = enter(&mut s, "Queue.0.QueueOffset");
    assert_eq!(said, "10");
}

#[test]
fn run_time_errors_of_typed_lines_leave_the_machine_running() {
    let mut s = empty(Dialect::MotionBasic);
    let (ran, said) = enter(&mut s, "X& = 2147483647 + 1");
    assert_eq!(ran, Ran::Failed, "{said}");
    assert!(said.contains("in the typed line"), "{said}");
    assert!(said.contains("verflow"), "{said}");
    // The machine goes on, and so does the next line.
    let mut out = Vec::new();
    assert!(s.advance(&mut out).is_none());
    assert_eq!(enter(&mut s, "X& = 41"), (Ran::Done, String::new()));
    assert_eq!(enter(&mut s, "X& + 1"), (Ran::Done, "42".to_string()));
    // RETURN with no GOSUB is a run-time error too.
    let (ran, said) = enter(&mut s, "RETURN");
    assert_eq!(ran, Ran::Failed, "{said}");
    assert!(said.contains("RETURN without GOSUB"), "{said}");
}

#[test]
fn a_session_adds_motionbasic_variables_up_to_its_spares() {
    let mut s = empty(Dialect::MotionBasic);
    for i in 0..pacer::repl::session::SPARE_VARIABLES {
        let (ran, said) = enter(&mut s, &format!("V{i}& = {i}"));
        assert_eq!(ran, Ran::Done, "{said}");
    }
    let (ran, said) = enter(&mut s, "ONE.TOO.MANY& = 1");
    assert_eq!(ran, Ran::Failed);
    assert!(said.contains("no room for the new variable"), "{said}");
    // The ones declared keep their values and names.
    assert_eq!(enter(&mut s, "V7& * V9&").1, "63");
    assert!(s.vocabulary().complete("V6", 2) != pacer::repl::complete::Completion::Path);
}

#[test]
fn commands_with_bad_arguments_say_so() {
    let mut s = labeling();
    let mut out = Vec::new();
    s.watch(&["Index.0.Initiate".into()], &mut out);
    s.watch(&["Nothing.0.Here".into()], &mut out);
    s.watch(&["Queue..0".into()], &mut out);
    s.set_input("Queue.0.QueueOffset", true, &mut out);
    s.set_input("DriveInput.99", true, &mut out);
    s.unwatch(&["Queue.0.QueueEmpty".into()], &mut out);
    s.trace_to(&PathBuf::from("/nonexistent-dir/x/trace.jsonl"), &mut out);
    let said = out.join("\n");
    for needle in [
        "cannot be watched: it is an action",
        "unknown object `Nothing`",
        "`Queue..0` is not a name",
        "is not an input",
        "DriveInput.99",
        "was not watched",
        "cannot create trace file",
    ] {
        assert!(said.contains(needle), "expected {needle:?} in\n{said}");
    }
    assert!(s.watched().is_empty());
    for bad in [
        ":",
        ":frobnicate",
        ":step -1",
        ":step 1.5",
        ":run soon",
        ":set X",
        ":load",
    ] {
        assert!(commands::parse(bad).is_err(), "{bad}");
    }
    assert!(Session::open(Some(PathBuf::from("no/such/folder")), None, false).is_err());
}

/// A small deterministic generator (no dependency on the clock).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

#[test]
fn mangled_program_lines_never_crash_a_session() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut corpus: Vec<(Dialect, String)> = Vec::new();
    for (file, dialect) in [
        ("programs/labeling/program0.pt", Dialect::PowerTools),
        ("programs/labeling/program1.pt", Dialect::PowerTools),
        ("programs/labeling/program2.pt", Dialect::PowerTools),
        (
            "programs/web-registration/registration.mb",
            Dialect::MotionBasic,
        ),
    ] {
        let text = std::fs::read_to_string(root.join(file)).expect("program");
        corpus.extend(
            text.lines()
                .filter(|l| !l.trim().is_empty())
                .map(|l| (dialect, l.to_string())),
        );
    }
    let junk = [
        "",
        " ",
        "(",
        ")",
        "=",
        "\"",
        "'",
        ":",
        "{",
        "}",
        "[",
        "]",
        ".",
        "@",
        "~",
        "&",
        "$",
        "\t",
        "\u{2018}",
        "é",
        "999999999999999999999",
        "1e308",
        "Then",
        "Loop",
        "WEND",
        "Next",
    ];
    let mut rng = Lcg(2026);
    for dialect in [Dialect::PowerTools, Dialect::MotionBasic] {
        let mut s = labeling();
        s.set_dialect(dialect);
        for _ in 0..400 {
            let (_, base) = &corpus[rng.below(corpus.len())];
            let mut line = base.clone();
            for _ in 0..rng.below(3) {
                let at = (0..=line.len())
                    .filter(|&i| line.is_char_boundary(i))
                    .nth(rng.below(line.chars().count() + 1))
                    .unwrap_or(0);
                line.insert_str(at, junk[rng.below(junk.len())]);
            }
            let mut out = Vec::new();
            if s.enter(&line, &mut out) == Ran::Blocked {
                // A line that waits is cancelled, as Ctrl-C does.
                s.cancel_line();
            }
            let _ = s.advance(&mut out);
            let _ = s.vocabulary().complete(&line, line.len());
            let _ = s.vocabulary().hint(&line, line.len());
        }
    }
}

#[test]
fn a_wait_nothing_can_end_is_given_up_not_hung() {
    use std::io::Write as _;
    let data = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-repl-wait-{}", std::process::id()));
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_pacer"))
        .arg("repl")
        .env("XDG_DATA_HOME", &data)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("pacer repl starts");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(b"Wait For Bit.7\nBit.7 = ON\nBit.7\n")
        .expect("script written");
    // The end of the input is the end of the session, like Ctrl-D.
    let out = child.wait_with_output().expect("pacer ends");
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{said}");
    assert!(
        said.contains("gave up after 3600 s simulated: the typed line was cancelled"),
        "{said}"
    );
    // The REPL task is free again: the next lines run.
    assert!(said.trim_end().ends_with("\nON"), "{said}");
}

#[test]
fn a_run_time_error_of_a_typed_line_is_shown_in_the_line_and_traced_with_its_place() {
    let mut s = empty(Dialect::MotionBasic);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-repl-error-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let trace = dir.join("t.jsonl");
    let mut out = Vec::new();
    s.trace_to(&trace, &mut out);
    assert_eq!(enter(&mut s, "Z = 0").0, Ran::Done);
    let (ran, said) = enter(&mut s, "R = 10 + 1 / Z");
    assert_eq!(ran, Ran::Failed, "{said}");
    // `typed line:1:10`: the division, not the line, is where it failed; it is underlined.
    assert!(
        said.starts_with("typed line:1:10: run-time error at t=0 s in the typed line"),
        "{said}"
    );
    let lines: Vec<&str> = said.lines().collect();
    let shown = lines
        .iter()
        .position(|l| l.ends_with("│ R = 10 + 1 / Z"))
        .unwrap_or_else(|| panic!("the typed line is shown: {said}"));
    let code: Vec<char> = lines[shown].chars().collect();
    let underline: Vec<char> = lines[shown + 1].chars().collect();
    let start = code.iter().position(|&c| c == 'R').unwrap_or(0) + "R = 10 + ".len();
    let marks = |c: &char| matches!(c, '─' | '┬');
    assert_eq!(
        (
            underline.iter().position(marks),
            underline.iter().filter(|c| marks(c)).count()
        ),
        (Some(start), "1 / Z".len()),
        "{said}"
    );
    s.trace_off(pacer::vm::StopReason::TraceOff, &mut out);
    let text = std::fs::read_to_string(&trace).expect("the trace");
    let error: serde_json::Value = text
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .find(|e: &serde_json::Value| e["kind"] == "error")
        .unwrap_or_else(|| panic!("an error event: {text}"));
    assert_eq!(error["program"], serde_json::Value::Null);
    assert_eq!(error["file"], "typed line");
    assert_eq!(
        (error["line"].as_u64(), error["column"].as_u64()),
        (Some(1), Some(10))
    );
    assert_eq!(error["message"], "division by zero");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A typed line takes the subscripts of a program's `OPTION BASE 1` array from 1, as the
/// program does: 0 is out of range when checked (a literal) and when run (a variable).
#[test]
fn typed_lines_keep_a_programs_option_base() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-repl-base-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(
        dir.join("program0.mb"),
        "OPTION BASE 1\nDIM A(3)\nA(1) = 7\nEND\n",
    )
    .expect("program written");
    let mut s = Session::open(Some(dir.clone()), None, false)
        .expect("the machine loads")
        .0;
    assert_eq!(enter(&mut s, "A(3) = 4"), (Ran::Done, String::new()));
    assert_eq!(enter(&mut s, "A(3) * 2"), (Ran::Done, "8".to_string()));
    let (ran, said) = enter(&mut s, "A(0) = 5");
    assert_eq!(ran, Ran::Failed, "{said}");
    assert!(said.contains("0 is not within 1 to 3"), "{said}");
    assert_eq!(enter(&mut s, "I& = 0"), (Ran::Done, String::new()));
    let (ran, said) = enter(&mut s, "A(I&)");
    assert_eq!(ran, Ran::Failed, "{said}");
    assert!(said.contains("0 is not within 1 to 3"), "{said}");
    let _ = std::fs::remove_dir_all(&dir);
}
