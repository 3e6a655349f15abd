//! The exit-code table of docs/cli.md, command by command: each code a command can give, given.

mod common;

use common::{pacer, text};
use std::path::{Path, PathBuf};

fn folder(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let d = common::scratch_in("exit", name);
    for (file, body) in files {
        std::fs::write(d.join(file), body).expect("write a project file");
    }
    d
}

fn arg(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temp path")
}

fn code(args: &[&str]) -> Option<i32> {
    let o = pacer(args);
    eprintln!("pacer {args:?}: {}", text(&o));
    o.status.code()
}

#[test]
fn the_table_in_the_docs_lists_every_code() {
    let cli = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/cli.md"))
        .expect("docs/cli.md");
    let table = &cli[cli.find("## Exit codes").expect("an exit-code section")..];
    for c in ["| 0 |", "| 1 |", "| 2 |", "| 3 |", "| 64 |", "| 130 |"] {
        assert!(table.contains(c), "docs/cli.md lacks the row {c}");
    }
}

#[test]
fn run_gives_0_1_2_3_and_64() {
    let ok = folder("run-ok", &[("program0.pt", "End\n")]);
    let bad = folder(
        "run-bad",
        &[
            ("program0.pt", "End\n"),
            ("machine.toml", "[machine]\ntasks = 0\n"),
        ],
    );
    let failing = folder(
        "run-error",
        &[
            (
                "program0.pt",
                "Var.A = 1\nVar.B = 0\nVar.A = Var.A / Var.B\n",
            ),
            ("machine.toml", "[variables.A]\n[variables.B]\n"),
        ],
    );
    assert_eq!(code(&["run", arg(&ok)]), Some(0));
    assert_eq!(code(&["run", arg(&bad)]), Some(1));
    // An `--io` the machine cannot take (no [modbus] here) is an input problem; one that is no
    // I/O at all is a usage error.
    assert_eq!(code(&["run", arg(&ok), "--io", "modbus"]), Some(1));
    assert_eq!(code(&["run", arg(&ok), "--io", "carrier-pigeon"]), Some(64));
    assert_eq!(code(&["run", arg(&failing)]), Some(2));
    let nowhere = ok.join("no-such-folder").join("t.jsonl");
    assert_eq!(code(&["run", arg(&ok), "--trace", arg(&nowhere)]), Some(3));
    assert_eq!(code(&["run", arg(&ok), "--for", "abc"]), Some(64));
    assert_eq!(code(&["run"]), Some(64));
}

#[test]
fn check_and_disasm_give_0_1_and_64() {
    let ok = folder("check-ok", &[("program0.pt", "End\n")]);
    let bad = folder("check-bad", &[("program0.pt", "Wait For Nothing.1\n")]);
    for command in ["check", "disasm"] {
        assert_eq!(code(&[command, arg(&ok)]), Some(0), "{command}");
        assert_eq!(code(&[command, arg(&bad)]), Some(1), "{command}");
        assert_eq!(
            code(&[command, arg(&ok), "--frobnicate"]),
            Some(64),
            "{command}"
        );
    }
}

#[test]
fn plot_gives_0_1_3_and_64() {
    let ok = folder(
        "plot",
        &[
            ("program0.pt", "Var.A = 1\nEnd\n"),
            ("machine.toml", "[variables.A]\n"),
        ],
    );
    let trace = ok.join("t.jsonl");
    assert_eq!(code(&["run", arg(&ok), "--trace", arg(&trace)]), Some(0));
    let svg = ok.join("t.svg");
    assert_eq!(code(&["plot", arg(&trace), "-o", arg(&svg)]), Some(0));
    let not_a_trace = ok.join("program0.pt");
    assert_eq!(code(&["plot", arg(&not_a_trace)]), Some(1));
    let nowhere = ok.join("no-such-folder").join("t.svg");
    assert_eq!(code(&["plot", arg(&trace), "-o", arg(&nowhere)]), Some(3));
    assert_eq!(code(&["plot"]), Some(64));
}

#[test]
fn repl_gives_1_and_64_and_help_and_version_0() {
    let bad = folder("repl-bad", &[("program0.pt", "Wait For Nothing.1\n")]);
    assert_eq!(code(&["repl", arg(&bad)]), Some(1));
    assert_eq!(code(&["repl", "--dialect", "fortran"]), Some(64));
    assert_eq!(code(&["--help"]), Some(0));
    assert_eq!(code(&["--version"]), Some(0));
    assert_eq!(code(&["repl", "--help"]), Some(0));
}

#[test]
fn sweep_gives_0_1_2_3_and_64() {
    let ok = folder(
        "sweep",
        &[
            ("program0.pt", "Var.A = 1\nEnd\n"),
            ("machine.toml", "[variables.A]\n"),
            (
                "sweep.toml",
                "[vary]\n\"run.seed\" = \"1..2\"\n[[measure]]\nname = \"a\"\nfinal = \"Var.A\"\n",
            ),
        ],
    );
    let bad = folder(
        "sweep-bad",
        &[
            ("program0.pt", "End\n"),
            ("sweep.toml", "[vary]\nspeed = [1]\n"),
        ],
    );
    let d = arg(&ok);
    assert_eq!(code(&["sweep", d, "--expect", "a == 1", "-q"]), Some(0));
    assert_eq!(code(&["sweep", d, "--expect", "a == 2", "-q"]), Some(2));
    assert_eq!(code(&["sweep", arg(&bad)]), Some(1));
    let under_a_file = ok.join("program0.pt").join("out");
    assert_eq!(
        code(&["sweep", d, "-q", "--out", arg(&under_a_file)]),
        Some(3)
    );
    assert_eq!(code(&["sweep", d, "--vary", "run.seed=3..1"]), Some(64));
    assert_eq!(code(&["sweep"]), Some(64));
}
