//! REGIST on a running machine takes its marks, the input turning off and the DIST + TOLR window
//! at their exact times, in time order, however many fall inside one update (issue 17, "Time
//! order inside an update"). A property test against a reference model of the rules
//! (shared/spec/regist.md) walked in time order; and a mark exactly on an update boundary.

mod common;

use common::{load_memory, run_loaded, Run};
use proptest::prelude::*;
use serde_json::Value;

/// STATUSSV bits (spec regist.md, "STATUSSV").
const OCCURRED: u32 = 1;
const FAST_INPUT: u32 = 2;
const GOOD: u32 = 4;
const BAD: u32 = 8;
const DIST_TOLR: u32 = 16;
const RISING: u32 = 32;

/// 10 ms updates; 6000 units per revolution, so `MOVE … AT u` runs at `u` units per update.
const UPDATE: f64 = 0.01;
/// The sensor stays on 1.37 ms: the input turns off at a position that is never a whole number
/// (no tie with a mark or a window, whose positions are whole).
const ON_TIME: f64 = 0.00137;

/// What the trace says REGIST did: marks and windows in trace order, and every STATUSSV.
#[derive(Debug, Clone, PartialEq)]
enum Seen {
    Mark(String, f64),
    Window(f64),
}

/// The rules of regist.md taken in time order for an axis running forward at `speed` units
/// per update through `marks` (whole positions, ascending): the marks and windows, and each
/// new STATUSSV.
fn reference(dist: f64, tolr: f64, ignr: f64, speed: f64, marks: &[f64]) -> (Vec<Seen>, Vec<u32>) {
    let fall_after = ON_TIME / UPDATE * speed;
    let mut seen = Vec::new();
    let mut statuses = Vec::new();
    let mut status = 0u32;
    let mut ruler: Option<f64> = None;
    let mut window_passed = false;
    let mut falls: Vec<f64> = Vec::new();
    let mut next = 0;
    fn set(status: &mut u32, s: u32, statuses: &mut Vec<u32>) {
        if s != *status {
            *status = s;
            statuses.push(s);
        }
    }
    loop {
        let mark = marks.get(next).copied();
        let fall = falls.first().copied();
        let window = match ruler {
            Some(r) if dist > 0.0 && !window_passed => Some(r + dist + tolr),
            _ => None,
        };
        // The earliest; at the same position an edge comes before the window.
        let edge = match (mark, fall) {
            (Some(m), Some(f)) => Some(m.min(f)),
            (m, f) => m.or(f),
        };
        let (take_edge, at) = match (edge, window) {
            (None, None) => break,
            (Some(e), Some(w)) if e <= w => (true, e),
            (Some(e), None) => (true, e),
            (_, Some(w)) => (false, w),
        };
        if !take_edge {
            window_passed = true;
            seen.push(Seen::Window(at));
            set(&mut status, DIST_TOLR, &mut statuses);
            continue;
        }
        if Some(at) == fall {
            falls.remove(0);
            let s = status & !RISING;
            set(&mut status, s, &mut statuses);
            continue;
        }
        next += 1;
        falls.push(at + fall_after);
        let class = match ruler {
            None => "good",
            Some(r) => {
                let d = at - r;
                if ignr > 0.0 && d < ignr {
                    "ignored"
                } else if dist == 0.0 || (dist - tolr <= d && d <= dist + tolr) {
                    "good"
                } else {
                    "bad"
                }
            }
        };
        let bits = match class {
            "good" => OCCURRED | FAST_INPUT | GOOD,
            "bad" => OCCURRED | FAST_INPUT | BAD,
            _ => OCCURRED | FAST_INPUT,
        };
        if class != "ignored" {
            ruler = Some(at);
            window_passed = false;
        }
        seen.push(Seen::Mark(class.into(), at));
        set(&mut status, bits | RISING, &mut statuses);
    }
    (seen, statuses)
}

/// Run axis 1 forward at `speed` units per update through `marks` with REGIST(DIST, TOLR,
/// IGNR) and a 2 ms minimum time between marks.
fn run(dist: f64, tolr: f64, ignr: f64, speed: u32, marks: &[f64]) -> Run {
    let machine = "[machine]\nupdate = \"10ms\"\n[[program]]\nnumber = 0\nfile = \"regist.mb\"\n\
                   [axis.1]\nname = \"web\"\nunits_per_rev = 6000\n";
    let program = format!(
        "ax~ = {{1}}\nMOVE ax~ TO -50\nWHILE DSP.DONE@(ax~) = 0 : WEND\n\
         X& = WRITE_SV(1, 25, 0.002)\nOK& = REGIST(TRUE, 1, {dist}, {tolr}, {ignr}, 100000, 0)\n\
         MOVE ax~ AT {speed} IN 0\nWHILETRUE\nWEND\n"
    );
    let last = marks.last().copied().unwrap_or(0.0);
    // The back-off takes well under 2 s; then the axis must pass the last mark and a window.
    let duration = 2.0
        + (last + 50.0 + 2.0 * (dist + tolr) + 10.0 * f64::from(speed)) / f64::from(speed) * UPDATE;
    let at: Vec<String> = marks.iter().map(|m| format!("{m}")).collect();
    let scenario = format!(
        "[run]\nduration = {duration}\n[[marks]]\naxis = 1\nsensor = \"FAST\"\non_time = {ON_TIME}\nat = [{}]\n",
        at.join(", ")
    );
    match load_memory(
        "regist-order",
        &[
            ("machine.toml", machine),
            ("regist.mb", &program),
            ("scenario.toml", &scenario),
        ],
    ) {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    }
}

fn regist_events(r: &Run) -> Vec<&Value> {
    r.events
        .iter()
        .filter(|e| {
            e["kind"] == "regist" || e["kind"] == "regist_window" || e["kind"] == "regist_status"
        })
        .collect()
}

fn seen(r: &Run) -> (Vec<Seen>, Vec<u32>) {
    let mut seen = Vec::new();
    let mut statuses = Vec::new();
    for e in regist_events(r) {
        match e["kind"].as_str() {
            Some("regist") => seen.push(Seen::Mark(
                e["mark"].as_str().unwrap_or("?").into(),
                e["position"].as_f64().unwrap_or(f64::NAN),
            )),
            Some("regist_window") => {
                seen.push(Seen::Window(e["position"].as_f64().unwrap_or(f64::NAN)))
            }
            _ => statuses.push(e["status"].as_u64().unwrap_or(u64::MAX) as u32),
        }
    }
    (seen, statuses)
}

/// Marks from `gaps` (each kind picks a gap: inside the ignore zone, inside the window,
/// anywhere), all at least the minimum time apart at `speed`.
fn marks_of(dist: f64, tolr: f64, ignr: f64, speed: u32, gaps: &[(u8, u32)]) -> Vec<f64> {
    // 2 ms at `speed` units per 10 ms, rounded up, plus one unit.
    let min_gap = (0.2 * f64::from(speed)).ceil() + 1.0;
    let mut p = 0.0;
    let mut marks = Vec::new();
    for &(kind, f) in gaps {
        marks.push(p);
        let f = f64::from(f);
        let gap = match kind {
            0 if ignr > 0.0 => f % ignr,
            1 => dist - tolr + f % (2.0 * tolr + 1.0),
            _ => f % 400.0,
        };
        p += gap.max(min_gap);
    }
    marks
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn marks_windows_and_status_follow_the_rules_in_time_order(
        dist in prop_oneof![1 => Just(0u32), 4 => 5..300u32],
        tolr in 0..40u32,
        ignr in prop_oneof![1 => Just(0u32), 2 => 1..100u32],
        speed in 1..=50u32,
        gaps in prop::collection::vec((0..3u8, 0..1000u32), 1..25),
    ) {
        let (dist, tolr, ignr) = (f64::from(dist), f64::from(tolr), f64::from(ignr));
        let marks = marks_of(dist, tolr, ignr, speed, &gaps);
        let r = run(dist, tolr, ignr, speed, &marks);
        prop_assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
        let warned: Vec<&Value> = r.events.iter().filter(|e| e["kind"] == "warning").collect();
        prop_assert!(warned.is_empty(), "{:?}", warned);
        let (want, want_status) = reference(dist, tolr, ignr, f64::from(speed), &marks);
        let (got, got_status) = seen(&r);
        prop_assert_eq!(&got, &want, "marks {:?} speed {}", marks, speed);
        prop_assert_eq!(&got_status, &want_status, "marks {:?} speed {}", marks, speed);
        // In time order, and each in the update its time falls in: (t - update, t].
        let mut last = f64::NEG_INFINITY;
        for e in regist_events(&r) {
            let time = e["time"].as_f64().unwrap_or(f64::NAN);
            let t = e["t"].as_f64().unwrap_or(f64::NAN);
            prop_assert!(time >= last, "{} after {}", e, last);
            prop_assert!(time <= t + 1e-12 && time > t - UPDATE - 1e-12, "{}", e);
            last = time;
        }
    }
}

#[test]
fn several_marks_and_a_window_in_one_update_are_taken_in_time_order() {
    // 50 units per update: the window of the mark at 0 (DIST 20 + TOLR 5 = 25) closes between
    // the marks at 10 and 40, all inside the first update of the run.
    let marks = [0.0, 10.0, 40.0, 48.0];
    let r = run(20.0, 5.0, 15.0, 50, &marks);
    let (got, status) = seen(&r);
    assert_eq!(
        got,
        vec![
            Seen::Mark("good".into(), 0.0),
            Seen::Mark("ignored".into(), 10.0),
            Seen::Window(25.0),
            Seen::Mark("bad".into(), 40.0),
            Seen::Window(65.0),
        ]
    );
    assert_eq!(status.last(), Some(&DIST_TOLR));
    let window = r
        .events
        .iter()
        .find(|e| e["kind"] == "regist_window")
        .expect("a window");
    let good = r
        .events
        .iter()
        .find(|e| e["kind"] == "regist")
        .expect("a mark");
    // The window closes 25 units after the mark at 0: half an update at 50 units per update.
    let dt = window["time"].as_f64().unwrap_or(f64::NAN) - good["time"].as_f64().unwrap_or(0.0);
    assert!((dt - 0.005).abs() < 1e-12, "{dt}");
}

#[test]
fn a_mark_exactly_on_an_update_boundary_belongs_to_the_update_that_ends_there() {
    // From -50 at 10 units per update the axis is at 0 exactly at the end of an update.
    let r = run(0.0, 0.0, 0.0, 10, &[0.0, 100.0]);
    let marks: Vec<&Value> = r.events.iter().filter(|e| e["kind"] == "regist").collect();
    assert_eq!(marks.len(), 2);
    for m in marks {
        let (time, t) = (
            m["time"].as_f64().unwrap_or(f64::NAN),
            m["t"].as_f64().unwrap_or(0.0),
        );
        assert!(
            (time - t).abs() < 1e-9,
            "{m}: recorded in the update ending at its time"
        );
    }
}

#[test]
fn a_mark_inside_the_minimum_time_is_a_warning_not_a_silent_loss() {
    // 50 units per update, 2 ms minimum: marks 5 units (1 ms) apart.
    let r = run(0.0, 0.0, 0.0, 50, &[0.0, 5.0, 30.0]);
    let (got, _) = seen(&r);
    assert_eq!(
        got,
        vec![
            Seen::Mark("good".into(), 0.0),
            Seen::Mark("good".into(), 30.0)
        ]
    );
    let warning = r
        .events
        .iter()
        .find(|e| e["kind"] == "warning")
        .expect("a warning");
    let message = warning["message"].as_str().unwrap_or("");
    assert!(
        message.contains("position 5") && message.contains("minimum time"),
        "{message}"
    );
    assert_eq!(warning["axis"], 1);
}

#[test]
fn enabling_regist_on_a_mark_warns_that_it_is_never_seen() {
    let machine = "[machine]\nupdate = \"1ms\"\n[[program]]\nnumber = 0\nfile = \"regist.mb\"\n\
                   [axis.1]\nname = \"web\"\nunits_per_rev = 6000\n";
    let program = "ax~ = {1}\nOK& = REGIST(TRUE, 1, 0, 0, 0, 1000, 0)\nMOVE ax~ AT 100 IN 0\n\
                   WHILETRUE\nWEND\n";
    let scenario = "[run]\nduration = 0.1\n[[marks]]\naxis = 1\nsensor = \"FAST\"\non_time = \"1ms\"\nat = [0, 500]\n";
    let r = match load_memory(
        "regist-on-mark",
        &[
            ("machine.toml", machine),
            ("regist.mb", program),
            ("scenario.toml", scenario),
        ],
    ) {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    };
    let (got, _) = seen(&r);
    assert_eq!(got, vec![Seen::Mark("good".into(), 500.0)]);
    let warning = r
        .events
        .iter()
        .find(|e| e["kind"] == "warning")
        .expect("a warning");
    assert!(
        warning["message"]
            .as_str()
            .unwrap_or("")
            .contains("standing on a mark"),
        "{warning}"
    );
}
