//! `Call Program` runs inside the interpreter when it is no error (issue 18): these runs give the
//! figures, places and messages they gave when every call and every end of a called program
//! went back to the machine's loop (checked against that build's output, trace included).

use std::path::{Path, PathBuf};

mod common;

use common::{pacer, text};

/// A machine folder of programs `p0.pt`, `p1.pt` … with `machine` as its machine file.
fn machine(name: &str, machine: &str, programs: &[&str]) -> PathBuf {
    let d = common::scratch_in("call", name);
    std::fs::write(d.join("machine.toml"), machine).expect("machine.toml");
    for (i, src) in programs.iter().enumerate() {
        std::fs::write(d.join(format!("p{i}.pt")), src).expect("program");
    }
    d
}

fn run(dir: &Path) -> String {
    let trace = dir.join("trace.jsonl");
    let o = pacer(&[
        "run",
        dir.to_str().expect("path"),
        "--trace",
        trace.to_str().expect("path"),
    ]);
    text(&o) + &std::fs::read_to_string(trace).unwrap_or_default()
}

const TWO: &str = r#"[machine]
name = "call"
budget = 7
[[program]]
number = 0
file = "p0.pt"
autostart = true
[[program]]
number = 1
file = "p1.pt"
[variables.I]
decimals = 0
[variables.X]
decimals = 0
[variables.Y]
decimals = 2
"#;

#[test]
fn a_fault_in_a_called_program_is_its_own_and_the_budget_counts_as_before() {
    let d = machine(
        "fault",
        TWO,
        &[
            "For Var.I = 1 To 5\n  Var.X = 3 - Var.I\n  Call Program.1\n  Var.Y = Var.Y + 0.5\nNext\nEnd\n",
            "Var.Y = Var.Y + 10 / Var.X\nEnd\n",
        ],
    );
    let out = run(&d);
    // A budget of 7 yields inside calls and their callers: 3 updates, 21 instructions.
    assert!(
        out.contains("0.002 s simulated in 3 updates of 1 ms, 21 instructions"),
        "{out}"
    );
    assert!(
        out.contains("p1.pt:1:17: run-time error at t=0.002 s in Program.1 (task 0)"),
        "{out}"
    );
    assert!(out.contains("× division by zero"), "{out}");
    assert!(
        out.contains(r#""kind":"error","task":0,"program":1"#),
        "{out}"
    );
    // Every variable's change at the update it was made in, as before.
    let changes: Vec<&str> = out
        .lines()
        .filter(|l| l.contains(r#""name":"Var."#))
        .collect();
    let want = [
        (0, "I", "1"),
        (0, "X", "2"),
        (0, "Y", "5.0"),
        (0, "Y", "5.5"),
        (0, "I", "2"),
        (1, "X", "1"),
        (1, "Y", "15.5"),
        (1, "Y", "16.0"),
        (1, "I", "3"),
        (2, "X", "0"),
    ]
    .map(|(tick, name, value)| {
        format!(
            r#"{{"t":{},"tick":{tick},"kind":"change","name":"Var.{name}","value":{value}}}"#,
            ["0.0", "0.001", "0.002"][tick]
        )
    });
    assert_eq!(changes, want, "{out}");
}

#[test]
fn a_program_calling_itself_is_refused_at_its_call() {
    let d = machine(
        "itself",
        TWO,
        &[
            "Call Program.1\nEnd\n",
            "Var.X = Var.X + 1\nIf Var.X < 3 Then\n  Call Program.1\nEndif\nEnd\n",
        ],
    );
    let out = run(&d);
    assert!(
        out.contains("p1.pt:3:3: run-time error at t=0 s in Program.1 (task 0)"),
        "{out}"
    );
    assert!(
        out.contains("× Call Program.1: the program is already running"),
        "{out}"
    );
    assert!(out.contains("4 instructions"), "{out}");
}

#[test]
fn a_program_running_on_another_task_is_refused() {
    let d = machine(
        "elsewhere",
        &TWO.replace("file = \"p1.pt\"", "file = \"p1.pt\"\nautostart = true"),
        &[
            "Wait For Time 0.01\nCall Program.1\nEnd\n",
            "Wait For Time 1\nEnd\n",
        ],
    );
    let out = run(&d);
    assert!(
        out.contains("p0.pt:2:1: run-time error at t=0.01 s in Program.0 (task 0)"),
        "{out}"
    );
    assert!(
        out.contains("× Call Program.1: the program is already running"),
        "{out}"
    );
}

#[test]
fn calls_nested_deeper_than_sixteen_are_refused() {
    let mut toml = String::from("[machine]\nname = \"deep\"\nbudget = 50\n");
    let mut programs = Vec::new();
    for i in 0..18 {
        toml += &format!("[[program]]\nnumber = {i}\nfile = \"p{i}.pt\"\n");
        if i == 0 {
            toml += "autostart = true\n";
        }
        programs.push(if i < 17 {
            format!(
                "Var.X = Var.X + 1\nCall Program.{}\nVar.X = Var.X + 1\nEnd\n",
                i + 1
            )
        } else {
            "Var.X = Var.X + 100\nEnd\n".to_string()
        });
    }
    toml += "[variables.X]\ndecimals = 0\n";
    let programs: Vec<&str> = programs.iter().map(String::as_str).collect();
    let out = run(&machine("deep", &toml, &programs));
    assert!(
        out.contains("p15.pt:2:1: run-time error at t=0 s in Program.15 (task 0)"),
        "{out}"
    );
    assert!(out.contains("× calls nested deeper than 16"), "{out}");
    assert!(out.contains("32 instructions"), "{out}");
}

#[test]
fn a_call_after_another_in_the_same_turn_still_sees_the_program_on_another_task() {
    // The tasks' frames are gathered at a turn's first call: Program.2 runs inside the
    // interpreter, then Program.1, busy on task 1 since the start, is refused all the same.
    let m = TWO.replace("file = \"p1.pt\"", "file = \"p1.pt\"\nautostart = true")
        + "[[program]]\nnumber = 2\nfile = \"p2.pt\"\n";
    let d = machine(
        "elsewhere-second",
        &m.replace("budget = 7", "budget = 1000"),
        &[
            "Wait For Time 0.01\nCall Program.2\nCall Program.1\nEnd\n",
            "Wait For Time 1\nEnd\n",
            "Var.X = Var.X + 5\nEnd\n",
        ],
    );
    let out = run(&d);
    assert!(
        out.contains("p0.pt:3:1: run-time error at t=0.01 s in Program.0 (task 0)"),
        "{out}"
    );
    assert!(
        out.contains("× Call Program.1: the program is already running"),
        "{out}"
    );
    assert!(out.contains("\"name\":\"Var.X\",\"value\":5"), "{out}");
}

#[test]
fn programs_numbered_apart_from_their_order_are_each_called() {
    // Program n is looked up as the n-th loaded first: here Program.1 is third and the second
    // is Program.5, which a lookup by place alone would run for `Call Program.1`.
    let m = r#"[machine]
name = "order"
budget = 1000
[[program]]
number = 0
file = "p0.pt"
autostart = true
[[program]]
number = 5
file = "p1.pt"
[[program]]
number = 1
file = "p2.pt"
[variables.X]
decimals = 0
"#;
    let d = machine(
        "order",
        m,
        &[
            "Var.X = 2\nCall Program.1\nCall Program.5\nCall Program.1\nEnd\n",
            "Var.X = Var.X * 10\nEnd\n",
            "Var.X = Var.X + 1\nEnd\n",
        ],
    );
    let out = run(&d);
    // ((2 + 1) * 10) + 1; a mix-up would give (2 * 10 + 1) * 10 or another.
    assert!(out.contains("\"name\":\"Var.X\",\"value\":31"), "{out}");
    assert!(!out.contains("error"), "{out}");
}
