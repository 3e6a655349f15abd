//! A run ends when every program has ended and all motion that comes to rest by itself is at
//! rest (issue 17, "Run end"); a run cut while motion runs names what still moved, in the
//! summary and in the trace's `end` event.

mod common;

use common::{load_memory, run_loaded, Run};
use pacer::vm::StopReason;
use serde_json::Value;

/// Index 1: 4 units at 1 u/s with 1 u/s² ramps takes 5 s.
const MACHINE: &str =
    "[index.1]\ndistance = 4.0\nvelocity = 1.0\nacceleration = 1.0\ndeceleration = 1.0\n";

fn run(program: &str, scenario: &str) -> Run {
    match load_memory(
        "run-end",
        &[
            ("program0.pt", program),
            ("machine.toml", MACHINE),
            ("scenario.toml", scenario),
        ],
    ) {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    }
}

fn end_event(r: &Run) -> &Value {
    let last = r.events.last().expect("a trace");
    assert_eq!(last["kind"], "end", "{last}");
    last
}

#[test]
fn a_run_waits_for_the_last_index_to_complete() {
    let r = run("Index.1.Initiate\n", "");
    assert_eq!(r.summary.stop_reason, StopReason::ProgramsEnded);
    assert!(r.summary.moving.is_empty(), "{:?}", r.summary.moving);
    let done: Vec<&Value> = r
        .events
        .iter()
        .filter(|e| e["kind"] == "motion" && e["object"] == "Index.1" && e["event"] == "done")
        .collect();
    assert_eq!(done.len(), 1, "{}", r.text);
    assert_eq!(done[0]["tick"], 5000);
    // The run ends at the update the index completed in, with the axis there.
    assert_eq!(r.summary.ticks, 5001);
    assert_eq!(r.machine.value_of("PosnCommand"), Some(4.0));
    assert!(end_event(&r).get("moving").is_none(), "{}", end_event(&r));
}

#[test]
fn a_run_cut_by_its_duration_names_the_moving_index() {
    let r = run("Index.1.Initiate\n", "[run]\nduration = 2.0\n");
    assert_eq!(r.summary.stop_reason, StopReason::Duration);
    assert_eq!(r.summary.moving, vec!["Index.1".to_string()]);
    assert_eq!(end_event(&r)["moving"], serde_json::json!(["Index.1"]));
}

#[test]
fn a_jog_left_running_does_not_hold_the_run_open_but_is_named() {
    let r = run(
        "Jog.0.Velocity = 2\nJog.0.Acceleration = 10\nJog.0.Deceleration = 10\n\
         Jog.0.PlusInitiate\nWait For Time 0.5\n",
        "",
    );
    assert_eq!(r.summary.stop_reason, StopReason::ProgramsEnded);
    // The program ends after its 0.5 s wait; the jog would run forever.
    assert!(r.summary.seconds < 0.6, "{}", r.summary.seconds);
    assert_eq!(r.summary.moving, vec!["Jog.0".to_string()]);
    assert_eq!(end_event(&r)["moving"], serde_json::json!(["Jog.0"]));
}

#[test]
fn the_cli_says_what_still_moved() {
    let dir = common::project(
        "run-end-cli",
        &[
            ("program0.pt", "Index.1.Initiate\n"),
            ("machine.toml", MACHINE),
        ],
    );
    let dir_text = dir.to_string_lossy().to_string();
    let out = common::pacer(&["run", &dir_text, "--for", "1"]);
    let text = common::text(&out);
    assert!(text.contains("still moving: Index.1"), "{text}");
    let out = common::pacer(&["run", &dir_text]);
    let text = common::text(&out);
    assert!(!text.contains("still moving"), "{text}");
    assert!(text.contains("5.000 s simulated"), "{text}");
}

#[test]
fn a_run_that_cannot_progress_says_which_task_waits_on_what_and_where() {
    // A coarse update keeps the simulated hour short to compute.
    let loaded = load_memory(
        "stuck",
        &[
            (
                "program0.pt",
                "DriveOutput.2 = ON\nWait For DriveInput.3 AND DriveInput.4\nDriveOutput.1 = ON\n",
            ),
            ("machine.toml", "[machine]\nupdate = \"100ms\"\n"),
        ],
    );
    let r = match loaded {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    };
    assert_eq!(r.summary.stop_reason, StopReason::Cap { seconds: 3600 });
    assert_eq!(r.summary.waiting.len(), 1, "{:?}", r.summary.waiting);
    let w = &r.summary.waiting[0];
    assert_eq!((w.task, w.line, w.column), (0, 2, 1));
    assert_eq!(w.statement, "Wait For DriveInput.3 AND DriveInput.4");
    assert_eq!(
        w.to_string(),
        "task 0 waits at stuck/program0.pt:2:1 `Wait For DriveInput.3 AND DriveInput.4`: its condition never came true"
    );
    let warning = r
        .events
        .iter()
        .find(|e| e["kind"] == "warning" && e["line"] == 2)
        .expect("a warning at the waiting statement");
    assert_eq!(warning["task"], 0);
    assert_eq!(warning["column"], 1);
}
