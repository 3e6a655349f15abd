//! The master axis driven by the scenario: product streams tied to master positions, captures
//! that latch the exact master position of the edge (bounce or not), queue compares against the
//! master, master-distance dwells and synchronized timers.

mod common;

use pacer::load::{load, LoadRequest};
use serde_json::Value;

use common::Run;

fn run(name: &str, program: &str, machine: &str, scenario: &str) -> Run {
    common::run_project(name, program, machine, scenario)
}

fn kind<'a>(events: &'a [Value], k: &str) -> Vec<&'a Value> {
    events.iter().filter(|e| e["kind"] == k).collect()
}

/// Program 0 of the labeler without its Home lines (the motion kernel has no Home yet): the
/// capture and the two queues, verbatim otherwise.
const PROGRAM0_WITHOUT_HOME: &str = "Capture.0.CaptureEnable=ON
Capture.0.CaptureClear
Queue.0.QueueClear=ON
Queue.1.QueueClear=ON

Wait For Queue.0.QueueEmpty
Queue.0.QueueCompareEnable=ON
Queue.1.QueueCompareEnable=ON

Do While TRUE

Wait For Capture.0.CaptureTriggered
Queue.0.DataIn=Capture.0.CapturedMasterPosition
Queue.1.DataIn=Capture.0.CapturedMasterPosition
Wait For Queue.1.QueueExit

Queue.1.QueueRemove
Capture.0.CaptureClear

Loop
";

const LABELER_QUEUES: &str = r#"
[queue.0]
name = "Label"
size = 12
offset = 10.0
[queue.1]
name = "Deadband"
size = 2
offset = 0.25
[[assignment]]
source = "ModuleInput.2"
destination = "Capture.0.CaptureActivate"
"#;

#[test]
fn each_product_is_captured_once_at_its_exact_master_position_despite_bounce() {
    let scenario = r#"
[run]
duration = 3.0
[master]
speed = 40.0
[[master.change]]
at = 1.0
speed = 0.0
ramp = 0.2
[[master.change]]
at = 1.5
speed = 90.0
ramp = 0.3
[[products]]
sensor = "ModuleInput.2"
first = 1.0
pitch = 1.0
length = 0.2
count = 500
bounce = { count = 3, width = "40us", gap = "60us", trailing = true }
"#;
    let r = run("capture", PROGRAM0_WITHOUT_HOME, LABELER_QUEUES, scenario);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let captures = kind(&r.events, "capture");
    let master_end = r.machine.value_of("MasterPosnFeedback").expect("master");
    // Products whose leading edge passed the sensor by the end; the last may still be
    // waiting for the deadband when the run stops, so it may or may not be captured.
    let passed = (1..).take_while(|k| f64::from(*k) <= master_end).count();
    assert!(passed > 100, "the line ran: {passed} products");
    assert!(
        captures.len() == passed || captures.len() + 1 == passed,
        "{} captures for {passed} products",
        captures.len()
    );
    for (k, c) in captures.iter().enumerate() {
        let lead = 1.0 + k as f64;
        let m = c["master"].as_f64().expect("master");
        assert!(
            (m - lead).abs() < 1e-9,
            "product {k}: captured {m}, edge at {lead}"
        );
    }
    // The deadband queue takes every product once: no bounce entered it.
    let deadband: Vec<f64> = kind(&r.events, "queue_in")
        .iter()
        .filter(|e| e["object"] == "Queue.1")
        .map(|e| e["value"].as_f64().expect("value"))
        .collect();
    assert_eq!(
        deadband.len(),
        captures.len(),
        "bounces never entered a queue"
    );
    for (k, q) in deadband.iter().enumerate() {
        // DataIn stores 4 decimals.
        assert!((q - (1.0 + k as f64)).abs() < 1e-4, "entry {k} is {q}");
    }
    // Nothing removes labels here (Program 1 is not running): the label queue holds its 12
    // and then overflows, as the spec says, storing nothing more.
    let labels = kind(&r.events, "queue_in")
        .iter()
        .filter(|e| e["object"] == "Queue.0")
        .count();
    assert_eq!(labels, 12);
    assert_eq!(r.machine.value_of("Queue.0.QueueOverflow"), Some(1.0));
    assert_eq!(r.machine.value_of("Queue.0.QueueFull"), Some(1.0));
}

#[test]
fn queue_exit_turns_on_at_the_first_update_at_or_past_the_exit_position() {
    let program = "Queue.0.QueueCompareEnable=ON\nQueue.0.DataIn=2.5\nWait For Queue.0.QueueExit\nVar.T = FreeRunTime\nEnd\n";
    let machine = "[variables.T]\n[queue.0]\noffset = 10.0\n";
    let scenario = "[run]\nduration = 1.0\n[master]\nspeed = 100.0\n";
    let r = run("compare", program, machine, scenario);
    let exits = kind(&r.events, "queue_exit");
    assert_eq!(exits.len(), 1);
    // Exit at 12.5 units, reached at 0.125 s exactly: the update at 125 ms.
    assert_eq!(exits[0]["tick"], 125);
    assert_eq!(exits[0]["exit"], 12.5);
    // The compare is part of the control loop, which runs before the task: the waiting program
    // goes on in that same update.
    assert_eq!(r.machine.value_of("Var.T"), Some(125_000.0));
}

#[test]
fn dwell_for_master_dist_lasts_until_the_master_has_moved() {
    let program = "Dwell For Master Dist 7.5\nDwell For Time 0\nVar.T = FreeRunTime\nEnd\n";
    let scenario = "[run]\nduration = 1.0\n[master]\nspeed = 50.0\n";
    let r = run("dwell", program, "[variables.T]\n", scenario);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // 7.5 units at 50/s: 150 ms; the second dwell starts at the first update after.
    assert_eq!(r.machine.value_of("Var.T"), Some(150_000.0));
}

#[test]
fn synchronized_timers_count_master_distance() {
    let program = "Timer.0.Synchronized=ON\nTimer.0.Preset=10\nTimer.0.Initiate\nWait For Timer.0.Output\nVar.T = FreeRunTime\nEnd\n";
    let scenario = "[run]\nduration = 1.0\n[master]\nspeed = 20.0\n";
    let r = run("timer", program, "[variables.T]\n", scenario);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // 10 units at 20/s: the output is on at 500 ms. Timers update before the tasks run, so the
    // waiting program goes on in that same update.
    assert_eq!(r.machine.value_of("Var.T"), Some(500_000.0));
}

#[test]
fn scenario_master_and_product_problems_point_at_their_place() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-master-{}-bad", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(dir.join("program0.pt"), "End\n").expect("program");
    let scenario = "[master]\nspeed = 10.0\n[[master.change]]\nat = 1.0\nspeed = 5.0\nramp = 2.0\n[[master.change]]\nat = 2.0\nspeed = 1.0\n\
                    [[products]]\nsensor = \"ModuleInput.2\"\nfirst = 0.0\npitch = 1.0\nlength = 0.9\njitter = 0.1\ncount = 3\n";
    std::fs::write(dir.join("scenario.toml"), scenario).expect("scenario");
    let err = match load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    }) {
        Ok(_) => panic!("the scenario is wrong"),
        Err(d) => d,
    };
    let _ = std::fs::remove_dir_all(&dir);
    let codes: Vec<&str> = err.items.iter().map(|d| d.problem.code).collect();
    assert_eq!(
        codes,
        ["pacer::scenario::master", "pacer::scenario::products"]
    );
    let master = &err.items[0].problem;
    assert!(
        master
            .message
            .contains("before the previous one has finished"),
        "{}",
        master.message
    );
    // The span is the offending [[master.change]] entry: the second one.
    let second = scenario
        .match_indices("[[master.change]]")
        .nth(1)
        .map(|(i, _)| i);
    assert_eq!(Some(master.span.start), second);
    let products = &err.items[1].problem;
    assert!(products.message.contains("overlap"), "{}", products.message);
    assert_eq!(
        &scenario[products.span.start..products.span.end],
        "\"ModuleInput.2\""
    );
}

#[test]
fn pls_windows_follow_their_source_with_rollover_and_direction() {
    let machine = "[pls.0]\nsource = \"MasterPosn\"\nrollover = 10.0\non = 2.0\noff = 4.0\n\
                   [pls.1]\nrollover = 10.0\non = 8.0\noff = 2.0\n\
                   [pls.2]\nrollover = 10.0\non = 2.0\noff = 4.0\ndirection = \"Minus\"\n";
    let r = run(
        "pls",
        "Wait For Time 5\n",
        machine,
        "[run]\nduration = 1.5\n[master]\nspeed = 10.0\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let changes = |name: &str| -> Vec<(u64, bool)> {
        r.events
            .iter()
            .filter(|e| e["kind"] == "change" && e["name"] == name)
            .map(|e| (e["tick"].as_u64().unwrap_or(0), e["value"] == true))
            .collect()
    };
    // Master at 10 u/s: [2, 4) is 200..400 ms, then again 1200..1400 ms.
    assert_eq!(
        changes("PLS.0.Status"),
        [(200, true), (400, false), (1200, true), (1400, false)]
    );
    // On 8, off 2 with rollover: active outside [2, 8): from the start, off at 200, on at 800…
    assert_eq!(
        changes("PLS.1.Status"),
        [(0, true), (200, false), (800, true), (1200, false)]
    );
    // Minus only, and the master runs plus: never on.
    assert!(changes("PLS.2.Status").is_empty());
}
