//! MotionBASIC motion on DSP axes, driven from programs. `GEAR … FOR … IN …` superimposed on
//! `GEAR … AT …`: the
//! follower lands exactly `dist` ahead of where the gear alone puts it, whatever the pacer does
//! meanwhile, a stop in the middle of the correction included.

mod common;

use common::{project, run_loaded_with_writes};
use pacer::load::{load, LoadRequest};

const MACHINE: &str = r#"
[machine]
update = "1ms"
# A slow interpreter, so the FOR loop below keeps the web stopped for 0.1 s.
budget = 100

[[program]]
number = 0
file = "gear.mb"

[axis.1]
units_per_rev = 600

[axis.2]
units_per_rev = 3600
pacer = 1
"#;

const SCENARIO: &str = "[run]\nduration = \"6s\"\n";

/// Run `program`; the pacer's and the follower's final positions, and the trace.
fn run(name: &str, program: &str) -> (f64, f64, Vec<serde_json::Value>) {
    let dir = project(
        name,
        &[
            ("gear.mb", program),
            ("machine.toml", MACHINE),
            ("scenario.toml", SCENARIO),
        ],
    );
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let r = match loaded {
        Ok(l) => run_loaded_with_writes(l),
        Err(d) => panic!("{}", d.render_plain()),
    };
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let web = r.machine.value_of("Axis.1.Position").expect("web");
    let knife = r.machine.value_of("Axis.2.Position").expect("knife");
    (web, knife, r.events)
}

/// Start the web, correct the knife by DIST over 3000 units of web starting at 2000, stop the
/// web at 3200 (in the middle of the correction), wait, restart faster, stop again.
fn program(dist: &str) -> String {
    format!(
        "w~ = {{1}} : k~ = {{2}}
GEAR k~ AT 1 TO 4
MOVE w~ AT 600 IN 200
WHILE POS@(w~) < 2000 : WEND
GEAR k~ FOR {dist} IN 3000
WHILE POS@(w~) < 3200 : WEND
MOVE w~ AT 0 IN 30
WHILE VEL@(w~) > 0 : WEND
STOPPED& = DSP.DONE@(k~)
FOR I& = 1 TO 10000 : NEXT
MOVE w~ AT 900 IN 100
WHILE POS@(w~) < 9000 : WEND
MOVE w~ AT 0 IN 100
END
"
    )
}

#[test]
fn the_follower_lands_exactly_dist_ahead_across_a_pacer_stop() {
    for dist in ["1000", "-437.25", "0.001"] {
        let (web, knife, events) = run("gear-for", &program(dist));
        let dist: f64 = dist.parse().expect("number");
        assert!(web > 9000.0, "web at {web}");
        let ahead = knife - web / 4.0;
        assert!(
            (ahead - dist).abs() < 1e-9,
            "dist {dist}: the knife is {ahead} ahead of the gear"
        );
        // The web stood still while the correction was in progress, for more than 50 updates.
        let stopped: Vec<&serde_json::Value> = events
            .iter()
            .filter(|e| e["kind"] == "change" && e["name"] == "STOPPED&")
            .collect();
        assert_eq!(stopped.len(), 1);
        assert_eq!(
            stopped[0]["value"], 0,
            "DSP.DONE@ was true when the web stopped"
        );
        let loop_updates = events
            .iter()
            .filter(|e| e["kind"] == "change" && e["name"] == "I&")
            .map(|e| e["tick"].as_u64().unwrap_or(0))
            .collect::<std::collections::BTreeSet<u64>>()
            .len();
        assert!(loop_updates > 50, "stopped for {loop_updates} updates");
    }
}

#[test]
fn without_a_correction_the_follower_is_the_gear() {
    let plain = program("0").replace("GEAR k~ FOR 0 IN 3000\n", "");
    let (web, knife, _) = run("gear-plain", &plain);
    assert!((knife - web / 4.0).abs() < 1e-9, "{knife} vs {web}");
}

#[test]
fn move_to_and_move_for_reach_their_positions_from_rest() {
    let program = "w~ = {1}
MOVE w~ TO 5000
WHILE DSP.DONE@(w~) = 0 : WEND
A = POS@(w~)
MOVE w~ FOR -1200 AT 300 IN 500
WHILE DSP.DONE@(w~) = 0 : WEND
B = POS@(w~)
MOVE w~ FOR 3 IN 20
WHILE DSP.DONE@(w~) = 0 : WEND
C = POS@(w~)
END
";
    let (web, _, events) = run("move-to", program);
    let value = |name: &str| {
        events
            .iter()
            .rev()
            .find(|e| e["kind"] == "change" && e["name"] == name)
            .and_then(|e| e["value"].as_f64())
            .unwrap_or(f64::NAN)
    };
    assert!((value("A") - 5000.0).abs() < 1e-6, "A = {}", value("A"));
    assert!((value("B") - 3800.0).abs() < 1e-6, "B = {}", value("B"));
    assert!((value("C") - 3803.0).abs() < 1e-6, "C = {}", value("C"));
    assert!((web - 3803.0).abs() < 1e-6);
    // 1200 units at 300 RPM (3000 units/s) in 500 ms: B is read 0.5 s after A (to the update).
    let at = |name: &str| {
        events
            .iter()
            .find(|e| e["kind"] == "change" && e["name"] == name)
            .and_then(|e| e["t"].as_f64())
            .unwrap_or(f64::NAN)
    };
    assert!(
        (at("B") - at("A") - 0.5).abs() < 1.5e-3,
        "{} {}",
        at("A"),
        at("B")
    );
}

#[test]
fn move_to_while_moving_is_a_clear_error() {
    let dir = project(
        "move-moving",
        &[
            (
                "gear.mb",
                "w~ = {1}\nMOVE w~ AT 100 IN 10\nMOVE w~ TO 5000\nEND\n",
            ),
            ("machine.toml", MACHINE),
            ("scenario.toml", SCENARIO),
        ],
    );
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let r = run_loaded_with_writes(loaded.unwrap_or_else(|d| panic!("{}", d.render_plain())));
    let error = r.summary.error.expect("a run-time error");
    assert_eq!(error.line, 3);
    assert!(
        error.message.contains("starts from rest"),
        "{}",
        error.message
    );
}

#[test]
fn a_motion_statement_waits_only_when_the_queue_is_full() {
    // Depth 4: four corrections queue at once; the fifth waits for the first to finish.
    let program = "w~ = {1} : k~ = {2}
GEAR k~ AT 1 TO 4
MOVE w~ AT 600 IN 10
GEAR k~ FOR 10 IN 1000
GEAR k~ FOR 10 IN 1000
GEAR k~ FOR 10 IN 1000
GEAR k~ FOR 10 IN 1000
A = POS@(w~)
GEAR k~ FOR 10 IN 1000
B = POS@(w~)
WHILE DSP.DONE@(k~) = 0 : WEND
END
";
    let (web, knife, events) = run("queue-full", program);
    let value = |name: &str| {
        events
            .iter()
            .find(|e| e["kind"] == "change" && e["name"] == name)
            .and_then(|e| e["value"].as_f64())
            .unwrap_or(f64::NAN)
    };
    assert!(
        value("A") < 1.0,
        "the first four did not wait: A = {}",
        value("A")
    );
    // The fifth was queued once the first correction's 1000 units of web had passed.
    assert!((1000.0..1020.0).contains(&value("B")), "B = {}", value("B"));
    assert!((knife - web / 4.0 - 50.0).abs() < 1e-9);
}

#[test]
fn motionbasic_programs_use_the_other_kernel_objects_by_their_dotted_names() {
    let program = "Queue.0.DataIn = 5
Queue.0.DataIn = 7.5
N& = Queue.0.QueueCount
IF Queue.0.QueueEmpty THEN E& = 1 ELSE E& = 2
Queue.0.QueueRemove
M& = Queue.0.QueueCount
F = Queue.0.QueueEmpty
END
";
    let (_, _, events) = run("kernel-objects", program);
    let value = |name: &str| {
        events
            .iter()
            .rev()
            .find(|e| e["kind"] == "change" && e["name"] == name)
            .and_then(|e| e["value"].as_f64())
            .unwrap_or(f64::NAN)
    };
    assert_eq!(value("N&"), 2.0);
    assert_eq!(value("E&"), 2.0);
    assert_eq!(value("M&"), 1.0);
    // A bit read by MotionBASIC is a BASIC truth value: false is 0.
    assert_eq!(value("F"), 0.0);
}

#[test]
fn gear_after_an_input_starts_at_its_edge() {
    let dir = project(
        "gear-after",
        &[
            (
                "gear.mb",
                "w~ = {1} : k~ = {2}\nMOVE w~ AT 600 IN 0\nGEAR k~ AT 1 TO 4 AFTER DriveInput.1\nEND\n",
            ),
            ("machine.toml", MACHINE),
            (
                "scenario.toml",
                "[run]\nduration = \"2s\"\n\n[[input]]\nname = \"DriveInput.1\"\nat = 0.5\nvalue = \"ON\"\n",
            ),
        ],
    );
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let r = run_loaded_with_writes(loaded.unwrap_or_else(|d| panic!("{}", d.render_plain())));
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let web = r.machine.value_of("Axis.1.Position").expect("web");
    let knife = r.machine.value_of("Axis.2.Position").expect("knife");
    // 6000 units/s: the web is at 3000 when the input comes at 0.5 s; the knife follows from there.
    assert!((web - 12000.0).abs() < 1e-6, "web {web}");
    assert!((knife - (web - 3000.0) / 4.0).abs() < 1e-6, "knife {knife}");
}
