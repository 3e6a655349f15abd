//! `GEAR … AFTER ZREF|ASEN|BSEN` on the DSP axes: the gear waits at the head of its axis's queue
//! for the next edge of that sensor of the axis's DSP card and starts at the edge's exact instant
//! inside the update, not at an update boundary.
//!
//! Source: ORMEC's MotionBASIC product page (ormec.com, "MotionBASIC Language Features", Motion
//! Statements): motion statements go to each axis module through a FIFO queue and "can be
//! executed unconditionally or conditionally based on the state of a DSP sensor input" — the
//! DSP, not the program, sees the edge, so the start is the edge's instant. Which edge (the
//! next one once the statement is at its queue head, of the SENS.MODE@ polarity, through the
//! PLS gate, never one latched before) is settled in docs/decisions.md.
//!
//! The web (axis 1) runs at 600 RPM × 600 units/rev = 6000 units/s from t = 0, so its position is
//! exactly 6000·t; a mark from 3003.3 to 3053.3 makes the ASEN rising edge at 0.50055 s (inside
//! the update ending at 0.501 s) and the falling edge at 0.508883… s. The knife (axis 2) gears
//! 1 TO 4 over 200 units of web: with y the web's travel since the edge, it is at
//! 0.25·y²/400 while y < 200, then 0.25·y − 25.

mod common;

use common::{project, run_loaded_with_writes};
use pacer::load::{load, LoadRequest};

const MACHINE: &str = r#"
[machine]
update = "1ms"

[[program]]
number = 0
file = "gear.mb"

[axis.1]
units_per_rev = 600

[axis.2]
units_per_rev = 3600
pacer = 1
"#;

/// The web's speed, units/s.
const SPEED: f64 = 6000.0;

/// The knife's position with the web `y` past the edge (`GEAR … AT 1 TO 4 IN 200`).
fn knife_at(y: f64) -> f64 {
    if y <= 0.0 {
        0.0
    } else if y < 200.0 {
        0.25 * y * y / 400.0
    } else {
        0.25 * y - 25.0
    }
}

/// Run `program` with marks at `marks` (width 50, on axis 1's ASEN) for `seconds`: the web's
/// and the knife's positions at the end, and the trace.
fn run(name: &str, program: &str, marks: &str, seconds: f64) -> (f64, f64, Vec<serde_json::Value>) {
    let scenario = format!(
        "[run]\nduration = \"{seconds}s\"\n\n[[marks]]\naxis = 1\nsensor = \"ASEN\"\nat = [{marks}]\nwidth = 50\n"
    );
    let dir = project(
        name,
        &[
            ("gear.mb", program),
            ("machine.toml", MACHINE),
            ("scenario.toml", &scenario),
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
    (web, knife, r.events)
}

const RISING: &str = "w~ = {1} : k~ = {2}
MOVE w~ AT 600 IN 0
GEAR k~ AT 1 TO 4 IN 200 AFTER ASEN
END
";

/// Runs ending at these updates: the knife is where the closed form from the exact edge puts it.
fn check_closed_form(program: &str, edge: f64, ends: &[f64]) {
    for &end in ends {
        let (web, knife, _) = run("after-form", program, "3003.3", end);
        assert!((web - SPEED * end).abs() < 1e-9, "web {web} at {end} s");
        let want = knife_at(SPEED * end - edge);
        assert!(
            (knife - want).abs() < 1e-9,
            "knife {knife} at {end} s, want {want} (edge at web {edge})"
        );
    }
}

#[test]
fn a_gear_after_asen_starts_at_the_rising_edge_exactly() {
    // 0.5 s: the last update before the edge, nothing moves. 0.501 s: the update holding the edge
    // (0.00455625 from the edge, where a start at the update's start would give 0.0225 and one
    // at its end 0). Then inside the ramp, at its end (web 3203.3 at 0.53388 s) and beyond.
    check_closed_form(
        RISING,
        3003.3,
        &[0.5, 0.501, 0.502, 0.51, 0.533, 0.534, 0.6],
    );
    let (_, knife, _) = run("after-before", RISING, "3003.3", 0.5);
    assert_eq!(knife, 0.0, "nothing moves before the edge");
    let (_, knife, _) = run("after-first", RISING, "3003.3", 0.501);
    assert!((knife - 0.00455625).abs() < 1e-9, "knife {knife}");
}

#[test]
fn the_trace_shows_the_start_at_the_edge() {
    let (_, _, events) = run("after-trace", RISING, "3003.3", 0.51);
    let start = events
        .iter()
        .find(|e| e["kind"] == "motion" && e["object"] == "Axis.2")
        .expect("a motion start of Axis.2");
    assert_eq!(start["event"], "start");
    assert_eq!(
        start["tick"], 501,
        "reported at the update holding the edge"
    );
    assert!((start["master"].as_f64().unwrap() - 3003.3).abs() < 1e-9);
    assert_eq!(start["position"].as_f64(), Some(0.0));
    let latch = events
        .iter()
        .find(|e| e["kind"] == "latch" && e["axis"] == 2)
        .expect("the same edge latches the knife's ASEN");
    assert!((latch["time"].as_f64().unwrap() - 0.50055).abs() < 1e-12);
}

#[test]
fn with_sens_mode_f_the_gear_starts_at_the_falling_edge() {
    let program = "w~ = {1} : k~ = {2}
SENS.MODE@(k~) = \"RFRNN\"
MOVE w~ AT 600 IN 0
GEAR k~ AT 1 TO 4 IN 200 AFTER ASEN
END
";
    // The mark ends at 3053.3: the falling edge at 0.50888… s, inside the update ending at 0.509.
    check_closed_form(program, 3053.3, &[0.508, 0.509, 0.51, 0.6]);
    let (_, knife, _) = run("after-f-before", program, "3003.3", 0.508);
    assert_eq!(knife, 0.0, "the rising edge does not start it");
}

#[test]
fn it_waits_for_the_next_edge_not_one_latched_before() {
    // The first mark (at 1000.5) latches ASEN before the statement; the latch is never re-armed,
    // yet the gear waits for the next edge, the mark at 3003.3.
    let program = "w~ = {1} : k~ = {2}
MOVE w~ AT 600 IN 0
WHILE POS@(w~) < 2000 : WEND
L& = ASEN(k~)
GEAR k~ AT 1 TO 4 IN 200 AFTER ASEN
END
";
    for end in [0.5, 0.501, 0.6] {
        let (web, knife, _) = run("after-next", program, "1000.5, 3003.3", end);
        assert!((web - SPEED * end).abs() < 1e-9);
        let want = knife_at(SPEED * end - 3003.3);
        assert!(
            (knife - want).abs() < 1e-9,
            "knife {knife} at {end}, want {want}"
        );
    }
}

#[test]
fn a_gear_without_in_steps_to_the_ratio_at_the_edge_and_the_next_waits_again() {
    // Two gears queued AFTER ASEN: the first (1 TO 4 at once) starts at the first mark, the
    // second (1 TO 2 at once) at the second, each exact.
    let program = "w~ = {1} : k~ = {2}
MOVE w~ AT 600 IN 0
GEAR k~ AT 1 TO 4 AFTER ASEN
GEAR k~ AT 1 TO 2 AFTER ASEN
END
";
    let marks = "1000.5, 3003.3";
    let (_, knife, _) = run("after-two", program, marks, 0.3);
    assert!(
        (knife - (1800.0 - 1000.5) / 4.0).abs() < 1e-9,
        "knife {knife}"
    );
    let (web, knife, _) = run("after-two", program, marks, 0.6);
    let want = (3003.3 - 1000.5) / 4.0 + (web - 3003.3) / 2.0;
    assert!((knife - want).abs() < 1e-9, "knife {knife}, want {want}");
}
