//! `--vcd`, `--csv`, `--plot` and `pacer plot` as a user runs them: the files they write, the
//! same bytes every run, and a clear error (never a panic) for everything given wrong.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;

mod common;

use common::{pacer, text};

fn scratch(name: &str) -> PathBuf {
    common::scratch_in("export", name)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

/// An error of the user's making: its exit code, a message, and no panic.
fn refused(o: &Output, code: i32, words: &[&str]) {
    let t = text(o);
    assert_eq!(o.status.code(), Some(code), "{t}");
    assert!(!t.contains("panicked"), "{t}");
    for w in words {
        assert!(t.contains(w), "`{w}` not in: {t}");
    }
}

#[test]
fn an_unknown_signal_is_named_with_the_nearest_known_one() {
    let dir = scratch("unknown");
    let csv = dir.join("x.csv");
    let o = pacer(&[
        "run",
        "programs/labeling",
        "--for",
        "0.1",
        "--csv",
        s(&csv),
        "--signals",
        "PosnFeedback,Queue.0.QueueCont",
    ]);
    refused(
        &o,
        1,
        &[
            "unknown signal `Queue.0.QueueCont`",
            "did you mean `Queue.0.QueueCount`?",
        ],
    );
    let o = pacer(&[
        "run",
        "programs/labeling",
        "--for",
        "0.1",
        "--plot",
        s(&dir.join("x.svg")),
        "--signals",
        "NoSuchThing",
    ]);
    refused(&o, 1, &["unknown signal `NoSuchThing`"]);
}

#[test]
fn an_unwritable_file_is_an_io_error_before_the_run() {
    let missing = Path::new("/nonexistent-pacer-dir");
    for opt in ["--vcd", "--csv", "--plot"] {
        let file = missing.join("out.file");
        let o = pacer(&["run", "programs/labeling", opt, s(&file), "-q"]);
        refused(&o, 3, &["cannot write", "/nonexistent-pacer-dir/out.file"]);
        // Refused before running: nothing was simulated.
        assert!(!text(&o).contains("simulated"), "{opt}: {}", text(&o));
    }
}

#[test]
fn options_that_need_another_or_a_value_are_refused() {
    let dir = scratch("options");
    let csv = dir.join("x.csv");
    let svg = dir.join("x.svg");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--sample", "10ms"],
            "--sample is the period of --csv rows",
        ),
        (
            vec!["--window", "1:2"],
            "--window is the time window of --plot",
        ),
        (vec!["--signals", "PosnFeedback"], "give one of them"),
        (
            vec!["--csv", s(&csv), "--sample", "ten"],
            "is not a duration",
        ),
        (
            vec!["--csv", s(&csv), "--sample", "1us"],
            "shorter than the update",
        ),
        (vec!["--plot", s(&svg), "--window", "5-9"], "write FROM:TO"),
        (
            vec!["--plot", s(&svg), "--window", "9:5"],
            "must come after",
        ),
        (
            vec!["--plot", s(&svg), "--vcd", s(&svg)],
            "given for two exports",
        ),
    ];
    for (extra, words) in cases {
        let mut args = vec!["run", "programs/labeling", "--for", "0.1"];
        args.extend(&extra);
        let o = pacer(&args);
        refused(&o, 1, &[words]);
    }
}

#[test]
fn pacer_plot_refuses_what_is_not_a_trace() {
    let dir = scratch("malformed");
    let bad = dir.join("bad.jsonl");
    std::fs::write(
        &bad,
        "{\"t\":0.0,\"tick\":0,\"kind\":\"start\",\"machine\":\"m\",\"update\":0.001,\"tasks\":1,\
         \"units\":{\"master\":\"mm\",\"motor\":\"mm\"}}\nthis is not JSON\n",
    )
    .expect("write");
    refused(&pacer(&["plot", s(&bad)]), 1, &["bad.jsonl", "line 2"]);

    let no_t = dir.join("no-t.jsonl");
    std::fs::write(&no_t, "{\"tick\":0,\"kind\":\"start\"}\n").expect("write");
    refused(
        &pacer(&["plot", s(&no_t)]),
        1,
        &["line 1", "missing field `t`"],
    );

    let empty = dir.join("empty.jsonl");
    std::fs::write(&empty, "").expect("write");
    refused(&pacer(&["plot", s(&empty)]), 1, &["the trace is empty"]);

    let binary = dir.join("binary.jsonl");
    std::fs::write(&binary, [0xff_u8, 0xfe, 0x00, 0x12, b'\n']).expect("write");
    refused(
        &pacer(&["plot", s(&binary)]),
        1,
        &["binary.jsonl", "line 1"],
    );

    refused(
        &pacer(&["plot", s(&dir.join("missing.jsonl"))]),
        1,
        &["missing.jsonl", "cannot read it"],
    );

    let trace = "tests/golden/labeling.jsonl";
    let badcsv = dir.join("bad.csv");
    std::fs::write(&badcsv, "time,x\n0,1\n").expect("write");
    refused(
        &pacer(&["plot", trace, s(&badcsv), "-o", s(&dir.join("o.svg"))]),
        1,
        &["bad.csv", "header starts with t,tick"],
    );
    let shortcsv = dir.join("short.csv");
    std::fs::write(&shortcsv, "t,tick,PosnFeedback\n0,0,1\n0.001,1\n").expect("write");
    refused(
        &pacer(&["plot", trace, s(&shortcsv), "-o", s(&dir.join("o.svg"))]),
        1,
        &["short.csv", "line 3", "0 values for 1 columns"],
    );
    refused(
        &pacer(&[
            "plot",
            trace,
            "-o",
            s(&dir.join("o.svg")),
            "--signals",
            "PosnFeedback",
        ]),
        1,
        &["`PosnFeedback` is not in", "--csv"],
    );
    refused(
        &pacer(&["plot", trace, "-o", trace]),
        1,
        &["would overwrite"],
    );
    refused(&pacer(&["plot", trace, trace]), 1, &["one trace too many"]);
}

#[test]
fn pacer_plot_draws_odd_but_well_formed_traces() {
    // Values and times no machine produces, times going backwards, a lone latch: drawn, not a
    // panic or a hang (a range's span past the largest double once made the axes loop).
    let dir = scratch("odd");
    let lines = [
        r#"{"t":0,"tick":0,"kind":"start","machine":"odd machine","update":0.001,"tasks":1,"units":{"master":"mm","motor":"mm"}}"#,
        r#"{"t":3,"tick":1,"kind":"change","name":"Queue.0.QueueCount","value":1e308}"#,
        r#"{"t":1e300,"tick":2,"kind":"change","name":"Queue.0.QueueCount","value":-1e308}"#,
        r#"{"t":-5,"tick":3,"kind":"change","name":"Index.0.CommandInProgress","value":true}"#,
        r#"{"t":4,"tick":4,"kind":"capture","object":"Capture.0","time":4,"master":null,"command":2,"feedback":null}"#,
        r#"{"t":4,"tick":4,"kind":"latch","axis":1,"sensor":"ASEN","time":4,"position":5}"#,
        r#"{"t":5,"tick":5,"kind":"latch","axis":2,"sensor":"ASEN","time":5,"position":-1e308}"#,
        r#"{"t":6,"tick":6,"kind":"pick","belt":null,"id":null,"x":1e308,"y":-1e308,"z":0}"#,
    ];
    for (name, upto) in [("servo", 5), ("web", 7), ("pp", 8)] {
        let trace = dir.join(format!("{name}.jsonl"));
        std::fs::write(&trace, lines[..upto].join("\n")).expect("write");
        let svg = dir.join(format!("{name}.svg"));
        let o = pacer(&["plot", s(&trace), "-o", s(&svg)]);
        assert!(o.status.success(), "{name}: {}", text(&o));
        let drawn = std::fs::read_to_string(&svg).expect("svg");
        assert!(drawn.starts_with("<svg") && drawn.trim_end().ends_with("</svg>"));
        assert!(!drawn.contains("NaN") && !drawn.contains("inf"), "{name}");
    }
}

/// Run the labeler for `secs` with every export into `dir`; the files' bytes.
fn export_all(dir: &Path, secs: &str) -> Vec<Vec<u8>> {
    let names = ["l.vcd", "l.csv", "l.svg", "l.jsonl"];
    let o = pacer(&[
        "run",
        "programs/labeling",
        "--for",
        secs,
        "-q",
        "--vcd",
        s(&dir.join(names[0])),
        "--csv",
        s(&dir.join(names[1])),
        "--plot",
        s(&dir.join(names[2])),
        "--trace",
        s(&dir.join(names[3])),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    names
        .iter()
        .map(|n| std::fs::read(dir.join(n)).expect("written"))
        .collect()
}

#[test]
fn the_same_run_writes_the_same_bytes() {
    let a = export_all(&scratch("same-a"), "4");
    let b = export_all(&scratch("same-b"), "4");
    for (i, (x, y)) in a.iter().zip(&b).enumerate() {
        assert!(x.len() > 1000, "file {i} has content");
        assert!(x == y, "file {i} differs between two runs");
    }
    // And a plot drawn from a trace is the same drawn twice.
    let dir = scratch("same-plot");
    let trace = dir.join("t.jsonl");
    std::fs::write(&trace, &a[3]).expect("write");
    let p1 = dir.join("1.svg");
    let p2 = dir.join("2.svg");
    assert!(pacer(&["plot", s(&trace), "-o", s(&p1)]).status.success());
    assert!(pacer(&["plot", s(&trace), "-o", s(&p2)]).status.success());
    assert_eq!(
        std::fs::read(&p1).expect("svg"),
        std::fs::read(&p2).expect("svg")
    );
}

fn csv_rows(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("csv");
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("header")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|f| f.parse().expect("a number")).collect())
        .collect();
    (header, rows)
}

#[test]
fn the_csv_has_every_position_and_velocity_by_default_one_row_per_update() {
    let dir = scratch("csv-default");
    let csv = dir.join("d.csv");
    let o = pacer(&[
        "run",
        "programs/labeling",
        "--for",
        "2",
        "-q",
        "--csv",
        s(&csv),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let (header, rows) = csv_rows(&csv);
    assert_eq!(
        header,
        [
            "t",
            "tick",
            "MasterPosnFeedback",
            "MasterVelFeedback",
            "PosnCommand",
            "PosnFeedback",
            "VelFeedback",
            "VelCommand"
        ]
    );
    // Updates 0 … 2000 of 1 ms.
    assert_eq!(rows.len(), 2001);
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r[1], i as f64);
        assert_eq!(r[0], i as f64 / 1000.0);
        // The master runs at 20 units/s from 0 over these two seconds.
        assert!((r[2] - 20.0 * r[0]).abs() < 1e-9, "row {i}: {r:?}");
        assert_eq!(r[3], 20.0);
        // An ideal servo: feedback is command.
        assert_eq!(r[4], r[5]);
        assert_eq!(r[6], r[7]);
    }
}

#[test]
fn the_csv_samples_chosen_signals_at_the_chosen_period() {
    let dir = scratch("csv-chosen");
    let csv = dir.join("c.csv");
    let trace = dir.join("c.jsonl");
    let o = pacer(&[
        "run",
        "programs/labeling",
        "--for",
        "6",
        "-q",
        "--csv",
        s(&csv),
        "--sample",
        "250ms",
        "--signals",
        "masterposnfeedback, Queue.0.QueueCount",
        "--signals",
        "DriveIO.1.Out",
        "--trace",
        s(&trace),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let (header, rows) = csv_rows(&csv);
    // Names as the registry spells them, in the order given.
    assert_eq!(
        header,
        [
            "t",
            "tick",
            "MasterPosnFeedback",
            "Queue.0.QueueCount",
            "DriveIO.1.Out"
        ]
    );
    assert_eq!(rows.len(), 25);
    let events: Vec<Value> = std::fs::read_to_string(&trace)
        .expect("trace")
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    // The trace's last value of a member at or before an update.
    let traced = |name: &str, tick: u64, initial: f64| -> f64 {
        events
            .iter()
            .rev()
            .filter(|e| e["kind"] == "change" && e["name"] == name)
            .find(|e| e["tick"].as_u64().is_some_and(|t| t <= tick))
            .map_or(initial, |e| match &e["value"] {
                Value::Bool(b) => f64::from(u8::from(*b)),
                v => v.as_f64().expect("number"),
            })
    };
    let mut counts_seen = 0.0_f64;
    for (k, r) in rows.iter().enumerate() {
        let tick = 250 * k as u64;
        assert_eq!(r[1], tick as f64);
        assert!((r[2] - 20.0 * r[0]).abs() < 1e-9);
        assert_eq!(
            r[3],
            traced("Queue.0.QueueCount", tick, 0.0),
            "update {tick}"
        );
        assert_eq!(r[4], traced("DriveIO.1.Out", tick, 0.0), "update {tick}");
        counts_seen = counts_seen.max(r[3]);
    }
    assert!(counts_seen >= 5.0, "the queue fills up: {counts_seen}");
}

#[test]
fn a_live_plot_and_a_plot_from_the_trace_and_csv_label_axes_units_and_legends() {
    let dir = scratch("plots");
    let live = dir.join("live.svg");
    let trace = dir.join("pp.jsonl");
    let csv = dir.join("pp.csv");
    let o = pacer(&[
        "run",
        "programs/pick-and-place/delta-cv1-cv2",
        "--for",
        "5",
        "-q",
        "--plot",
        s(&live),
        "--trace",
        s(&trace),
        "--csv",
        s(&csv),
        "--sample",
        "2ms",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let live_svg = std::fs::read_to_string(&live).expect("svg");
    for words in [
        "Tool path seen from above (X/Y)",
        "X (mm)",
        "Y (mm)",
        "Z (mm)",
        "time (s)",
        "pick (from its belt)",
        "place (onto its belt)",
        "the first 3 pick-and-place cycles",
        "<polyline",
    ] {
        assert!(live_svg.contains(words), "{words}");
    }
    // The same picture from the recorded trace and the CSV, with the default output name.
    let o = pacer(&["plot", s(&trace), s(&csv)]);
    assert!(o.status.success(), "{}", text(&o));
    let from_files = std::fs::read_to_string(dir.join("pp.svg")).expect("svg");
    assert!(from_files.contains("tool (alrActPos[1], alrActPos[2])"));
    assert!(!from_files.contains("not in the trace"));
    // From the trace alone: picks and places, and a note saying where the path is.
    let only = dir.join("only.svg");
    let o = pacer(&["plot", s(&trace), "-o", s(&only)]);
    assert!(o.status.success(), "{}", text(&o));
    let only_svg = std::fs::read_to_string(&only).expect("svg");
    assert!(only_svg.contains("is not in the trace"));
    assert!(!only_svg.contains("tool (alrActPos[1], alrActPos[2])"));
    // Chosen signals from the trace and CSV: a velocity chart and a timing diagram.
    let chosen = dir.join("chosen.svg");
    let o = pacer(&[
        "plot",
        s(&trace),
        s(&csv),
        "-o",
        s(&chosen),
        "--signals",
        "Belt.1.Velocity,PickPlace.xPulseGripper",
        "--window",
        "1:4",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let chosen_svg = std::fs::read_to_string(&chosen).expect("svg");
    for words in [
        "velocity (mm/s)",
        "Digital signals",
        "PickPlace.xPulseGripper",
        "t = 1 … 4 s",
    ] {
        assert!(chosen_svg.contains(words), "{words}");
    }
}

/// Array elements and text variables chosen by name (MotionBASIC: GW-BASIC User's Guide,
/// "DIM", subscripts from 0; strings by `$`): a comma between subscripts is not a list's
/// comma; the CSV writes a string as text, quoted where RFC 4180 says; a plot, which draws
/// numbers, refuses a text variable by name, live and from a CSV, and draws the other columns
/// of that CSV; an element outside its array is refused with the array's bounds, a name of
/// the wrong shape as unknown.
#[test]
fn elements_and_text_variables_are_signals_by_name() {
    let dir = scratch("elements");
    let project = dir.join("p");
    std::fs::create_dir_all(&project).expect("dir");
    std::fs::write(
        project.join("main.mb"),
        "DIM G(2, 3), F&(10)\nFOR I& = 0 TO 10\n  F&(I&) = I& * I&\nNEXT\nG(1, 2) = 2.5\n\
         S$ = \"A, \" + CHR$(34) + \"B\" + CHR$(34)\nT$ = \"plain\"\n",
    )
    .expect("program");
    std::fs::write(
        project.join("machine.toml"),
        "[machine]\nname = \"e\"\n\n[[program]]\nnumber = 0\nfile = \"main.mb\"\n",
    )
    .expect("machine");
    let (csv, trace) = (dir.join("e.csv"), dir.join("e.jsonl"));
    let o = pacer(&[
        "run",
        s(&project),
        "-q",
        "--csv",
        s(&csv),
        "--trace",
        s(&trace),
        "--signals",
        "f&(3), G( 1, 2 ),F&(10)",
        "--signals",
        "S$,T$",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let written = std::fs::read_to_string(&csv).expect("csv");
    assert_eq!(
        written.lines().collect::<Vec<_>>(),
        [
            "t,tick,F&(3),\"G(1,2)\",F&(10),S$,T$",
            "0,0,9,2.5,100,\"A, \"\"B\"\"\",plain"
        ]
    );
    let svg = dir.join("e.svg");
    let plot = |names: &str| {
        pacer(&[
            "plot",
            s(&trace),
            s(&csv),
            "-o",
            s(&svg),
            "--signals",
            names,
        ])
    };
    let o = plot("F&(10)");
    assert!(o.status.success(), "{}", text(&o));
    assert!(std::fs::read_to_string(&svg)
        .expect("svg")
        .contains("F&amp;(10)"));
    refused(&plot("S$"), 1, &["S$ holds text", "e.csv"]);
    refused(
        &pacer(&[
            "run",
            s(&project),
            "-q",
            "--plot",
            s(&svg),
            "--signals",
            "F&(1),T$",
        ]),
        1,
        &["T$ holds text", "--plot draws numbers"],
    );
    // Names that are not elements of the arrays, and why.
    for (names, why) in [
        (
            "F&(11)",
            "Subscript out of range: F&(11) is outside F&(0 to 10)",
        ),
        ("G(1)", "unknown signal `G(1)`"),
        ("G(1,4)", "G(1,4) is outside G(0 to 2, 0 to 3)"),
    ] {
        let args = [
            "run",
            s(&project),
            "-q",
            "--csv",
            s(&csv),
            "--signals",
            names,
        ];
        refused(&pacer(&args), 1, &[why]);
    }
}
