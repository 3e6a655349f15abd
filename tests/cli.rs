//! The `pacer` command as a user runs it: exit codes, diagnostics, traces.

use std::path::{Path, PathBuf};

mod common;

use common::{pacer, text};

fn scratch(name: &str) -> PathBuf {
    common::scratch_in("cli", name)
}

#[test]
fn every_labeling_program_of_the_spec_checks_unchanged() {
    let o = pacer(&[
        "check",
        "tests/fixtures/labeling/program0.pt",
        "tests/fixtures/labeling/program1.pt",
        "tests/fixtures/labeling/program2.pt",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("3 program(s) checked"));
}

#[test]
fn the_labeling_fixtures_are_the_spec_listings_verbatim() {
    // The spec lives beside the repository (../shared), on developers' machines and in CI alike.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/spec/labeling.md");
    let spec = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    for n in 0..3 {
        let fixture = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join(format!("tests/fixtures/labeling/program{n}.pt")),
        )
        .expect("fixture");
        let heading = format!("## Program {n}");
        let after = &spec[spec.find(&heading).expect("heading")..];
        let start = after.find("```\n").expect("listing") + 4;
        let end = after[start..].find("```").expect("end of listing") + start;
        assert_eq!(
            &after[start..end],
            fixture,
            "program{n}.pt differs from the spec listing"
        );
    }
}

#[test]
fn check_reports_every_error_with_file_line_and_column() {
    let d = scratch("errors");
    let f = d.join("bad.pt");
    std::fs::write(
        &f,
        "Queue.0.QueueEmpy = ON\nBit.1 = 1\nWait For Queu.0.QueueEmpty\n",
    )
    .expect("write");
    let o = pacer(&["check", f.to_str().expect("utf-8 path")]);
    assert_eq!(o.status.code(), Some(1));
    let t = text(&o);
    assert!(t.contains("bad.pt:1:9"), "{t}");
    assert!(t.contains("QueueEmpty"), "{t}");
    assert!(t.contains("bad.pt:2:9"), "{t}");
    assert!(t.contains("bad.pt:3:10"), "{t}");
    assert!(t.contains("3 error(s)"), "{t}");
}

#[test]
fn a_runtime_error_names_task_program_and_line_and_keeps_the_trace() {
    let d = scratch("runtime");
    std::fs::write(
        d.join("program0.pt"),
        "Var.A = 1\nVar.B = 0\nVar.A = Var.A / Var.B\n",
    )
    .expect("write");
    std::fs::write(
        d.join("machine.toml"),
        "[variables.A]\ndecimals = 2\n[variables.B]\ndecimals = 0\n",
    )
    .expect("write");
    let trace = d.join("t.jsonl");
    let o = pacer(&[
        "run",
        d.to_str().expect("path"),
        "--trace",
        trace.to_str().expect("path"),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let t = text(&o);
    // Located as compile-time problems are: file:line:column, the line, the divisor's
    // expression underlined.
    assert!(
        t.contains("program0.pt:3:9: run-time error at t=0 s in Program.0 (task 0)")
            && t.contains("division by zero"),
        "{t}"
    );
    let shown = t
        .lines()
        .position(|l| l.ends_with("│ Var.A = Var.A / Var.B"))
        .unwrap_or_else(|| panic!("the line is shown: {t}"));
    // In characters: the underline starts under the `Var.A / Var.B` after `Var.A = ` and is
    // as long as it.
    let underline: Vec<char> = t.lines().nth(shown + 1).unwrap_or("").chars().collect();
    let code: Vec<char> = t.lines().nth(shown).unwrap_or("").chars().collect();
    let start = code.iter().position(|&c| c == 'V').unwrap_or(0) + "Var.A = ".len();
    let marks = |c: &char| matches!(c, '─' | '┬');
    let first = underline.iter().position(marks).unwrap_or(0);
    assert_eq!(
        (first, underline.iter().filter(|c| marks(c)).count()),
        (start, "Var.A / Var.B".len()),
        "`Var.A / Var.B` is underlined: {t}"
    );
    let lines = std::fs::read_to_string(&trace).expect("trace");
    let error = lines
        .lines()
        .find(|l| l.contains("\"kind\":\"error\""))
        .unwrap_or_else(|| panic!("an error event: {lines}"));
    let e: serde_json::Value = serde_json::from_str(error).expect("JSON");
    assert_eq!(e["message"], "division by zero");
    assert!(
        e["file"]
            .as_str()
            .is_some_and(|f| f.ends_with("program0.pt")),
        "{e}"
    );
    assert_eq!(
        (e["line"].as_u64(), e["column"].as_u64()),
        (Some(3), Some(9))
    );
    assert!(
        lines
            .lines()
            .last()
            .is_some_and(|l| l.contains("\"kind\":\"end\"")),
        "trace is flushed to its end"
    );
}

#[test]
fn a_bad_machine_file_points_at_the_value() {
    let d = scratch("machine");
    std::fs::write(d.join("program0.pt"), "End\n").expect("write");
    std::fs::write(d.join("machine.toml"), "[io]\nDriveInptu = 4\n").expect("write");
    let o = pacer(&["run", d.to_str().expect("path")]);
    assert_eq!(o.status.code(), Some(1));
    let t = text(&o);
    assert!(
        t.contains("machine.toml:2:14") && t.contains("DriveInput"),
        "{t}"
    );
}

#[test]
fn a_bad_scenario_points_at_the_value() {
    let d = scratch("scenario");
    std::fs::write(d.join("program0.pt"), "End\n").expect("write");
    std::fs::write(
        d.join("scenario.toml"),
        "[[press]]\nname = \"DriveOutput.1\"\nat = 0.1\nlength = \"5 parsecs\"\n",
    )
    .expect("write");
    let o = pacer(&["run", d.to_str().expect("path")]);
    assert_eq!(o.status.code(), Some(1));
    let t = text(&o);
    assert!(
        t.contains("scenario.toml:4:10") && t.contains("parsecs"),
        "{t}"
    );
}

#[test]
fn two_runs_write_byte_identical_trace_files() {
    let d = scratch("twice");
    let (a, b) = (d.join("a.jsonl"), d.join("b.jsonl"));
    for f in [&a, &b] {
        let o = pacer(&[
            "run",
            "programs/operator-offset",
            "--trace",
            f.to_str().expect("path"),
        ]);
        assert!(o.status.success(), "{}", text(&o));
    }
    let (x, y) = (std::fs::read(&a).expect("a"), std::fs::read(&b).expect("b"));
    assert!(!x.is_empty());
    assert_eq!(x, y);
}

#[test]
fn disasm_lists_resolved_slots() {
    let o = pacer(&["disasm", "programs/operator-offset"]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("write     Queue.0.QueueOffset <- t0"), "{t}");
    assert!(t.contains("wait      t0 (retry @"), "{t}");
}

#[test]
fn an_error_far_along_a_very_wide_line_is_reported_not_a_crash() {
    // miette cannot draw a span that starts past column 65,535; such problems print compactly.
    let d = scratch("wide");
    let f = d.join("wide.pt");
    std::fs::write(&f, format!("{}(\n", "\t".repeat(16_384))).expect("write");
    let o = pacer(&["check", f.to_str().expect("path")]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("wide.pt:1:16385: error[pacer::syntax]: unexpected `(`"),
        "{t}"
    );
}

#[test]
fn many_errors_are_all_listed_quickly() {
    let d = scratch("many");
    let f = d.join("many.pt");
    std::fs::write(
        &f,
        format!(
            "{}Do While ON\n{}",
            "Stop\n".repeat(20_000),
            "Endif\n".repeat(20_000)
        ),
    )
    .expect("write");
    let o = pacer(&["check", f.to_str().expect("path")]);
    assert_eq!(o.status.code(), Some(1));
    let t = text(&o);
    assert!(
        t.contains("20001 error(s)"),
        "{}",
        &t[t.len().saturating_sub(300)..]
    );
    // The first problems are drawn with their source, the rest listed one per line.
    assert!(t.contains(
        "many.pt:40001:1: error[pacer::syntax::unbalanced]: Endif without a matching If"
    ));
}
