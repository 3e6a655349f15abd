//! What a run records stays the truth and stays small (issue 17, "Trace volume"): a program's
//! write is traced when it changes the value (every write with `--trace-writes`), and a size
//! limit ends the run cleanly with a trace whose every line parses.

mod common;

use common::{load_memory, Sink};
use pacer::trace::Trace;
use pacer::vm::{Machine, StopReason};

/// The one-line mirror loop of the issue, with the scenario toggling DriveInput.1 every 100 ms.
const MIRROR: &str = "Do While ON\n  DriveOutput.1 = DriveInput.1\nLoop\n";
const SCENARIO: &str = "[run]\nduration = 60.0\n\n[[pulses]]\nname = \"DriveInput.1\"\nstart = 0.05\nperiod = \"200ms\"\nwidth = \"100ms\"\ncount = 300\n";

fn mirror_run(configure: impl FnOnce(&mut Trace)) -> (String, StopReason) {
    let loaded = match load_memory(
        "mirror",
        &[("program0.pt", MIRROR), ("scenario.toml", SCENARIO)],
    ) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let sink = Sink::default();
    let mut trace = Trace::new(Some(Box::new(sink.clone())), loaded.image.tick_ns);
    configure(&mut trace);
    let mut machine = Machine::new(loaded.image, trace);
    let summary = machine.run(None);
    machine.finish().expect("in-memory trace");
    (sink.text(), summary.stop_reason)
}

#[test]
fn a_mirror_loop_traces_its_edges_not_its_writes() {
    let (text, reason) = mirror_run(|_| {});
    assert_eq!(reason, StopReason::Duration);
    assert!(text.len() < 1_000_000, "{} bytes", text.len());
    let outputs = text
        .lines()
        .filter(|l| l.contains("\"name\":\"DriveOutput.1\""))
        .count();
    // 300 input periods in 60 s: one rising and one falling edge each, mirrored.
    assert_eq!(outputs, 600, "{}", &text[..text.len().min(2000)]);
}

#[test]
fn every_write_is_traced_when_asked() {
    let (text, _) = mirror_run(|t| {
        t.record_writes(true);
        t.limit(Some(200_000));
    });
    let writes = text
        .lines()
        .filter(|l| l.contains("\"name\":\"DriveOutput.1\""))
        .count();
    assert!(writes > 1000, "{writes}");
}

#[test]
fn the_size_limit_ends_the_run_with_a_whole_trace() {
    let (text, reason) = mirror_run(|t| {
        t.record_writes(true);
        t.limit(Some(50_000));
    });
    assert_eq!(reason, StopReason::TraceLimit { bytes: 50_000 });
    let lines: Vec<&str> = text.lines().collect();
    for l in &lines {
        serde_json::from_str::<serde_json::Value>(l).unwrap_or_else(|e| panic!("{e}: {l}"));
    }
    let last: serde_json::Value = serde_json::from_str(lines[lines.len() - 1]).expect("json");
    assert_eq!(last["kind"], "end");
    assert!(last["reason"]
        .as_str()
        .is_some_and(|r| r.contains("size limit of 50000 bytes")));
    // Only the closing line may pass the limit.
    let before_end = text.len() - lines[lines.len() - 1].len() - 1;
    assert!(before_end <= 50_000, "{before_end}");
}

#[test]
fn pacer_run_says_the_limit_was_reached_and_exits_3() {
    let dir = common::scratch_in("trace-volume", "cli");
    std::fs::write(dir.join("program0.pt"), MIRROR).expect("write");
    std::fs::write(dir.join("scenario.toml"), SCENARIO).expect("write");
    let trace = dir.join("t.jsonl");
    let o = common::pacer(&[
        "run",
        dir.to_str().expect("utf-8"),
        "--trace",
        trace.to_str().expect("utf-8"),
        "--trace-writes",
        "--trace-limit",
        "64K",
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", common::text(&o));
    assert!(common::text(&o).contains("size limit of 65536 bytes"));
    let text = std::fs::read_to_string(&trace).expect("trace");
    assert!(text
        .lines()
        .all(|l| serde_json::from_str::<serde_json::Value>(l).is_ok()));
    let o = common::pacer(&["run", dir.to_str().expect("utf-8"), "--trace-limit", "12X"]);
    // A usage error (docs/cli.md, "Exit codes").
    assert_eq!(o.status.code(), Some(64), "{}", common::text(&o));
    assert!(common::text(&o).contains("unknown unit"));
}
