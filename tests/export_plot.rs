//! What the machines' pictures are drawn from, checked against the golden traces: the web
//! registration's pitch and phase per mark, the labeler's queue counts and index activity, the
//! pick & place cycles.

use pacer::export::figure::{figure, Chart, Style};
use pacer::export::input::read_trace;
use pacer::export::record::{Plan, Preset, Recorder, Recording};
use serde_json::Value;
use std::path::Path;

fn golden(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/golden/{name}.jsonl"))
}

fn record(name: &str, preset: Preset, from: f64, to: Option<f64>) -> Recording {
    let mut r = Recorder::new(Plan { preset, from, to }, 0.001);
    read_trace(&golden(name), |l| r.event(l.t, &l.event)).expect("a trace");
    r.finish()
}

fn events(name: &str) -> Vec<Value> {
    std::fs::read_to_string(golden(name))
        .expect("trace")
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect()
}

fn trace_of<'a>(c: &'a Chart, label_start: &str) -> &'a [(f64, f64)] {
    &c.traces
        .iter()
        .find(|t| t.label.starts_with(label_start))
        .unwrap_or_else(|| panic!("no `{label_start}` in {}", c.title))
        .points
}

#[test]
fn web_registration_pitch_and_phase_per_mark_come_from_the_latches_and_the_programs_variables() {
    let rec = record("web-registration", Preset::Web, 0.0, None);
    let all = events("web-registration");
    let latches: Vec<&Value> = all.iter().filter(|e| e["kind"] == "latch").collect();
    let web: Vec<f64> = latches
        .iter()
        .filter(|e| e["axis"] == 1)
        .map(|e| e["position"].as_f64().expect("position"))
        .collect();
    let knife: Vec<f64> = latches
        .iter()
        .filter(|e| e["axis"] == 2)
        .map(|e| e["position"].as_f64().expect("position"))
        .collect();
    assert_eq!(rec.marks.len(), web.len());
    assert_eq!(web.len(), knife.len());

    let fig = figure(&Preset::Web, &rec);
    assert_eq!(fig.charts.len(), 2);
    let pitch = &fig.charts[0];
    assert_eq!(pitch.y_label, "pitch (axis 1 user units)");
    let measured = trace_of(pitch, "measured");
    let outside = trace_of(pitch, "8 far from the rest");
    // Every pitch between two marks is drawn once: inside the range, or at its edge.
    assert_eq!(measured.len() + outside.len(), web.len() - 1);
    assert_eq!(measured[0], (2.0, web[1] - web[0]));
    // The pitches outside the range are the print defects: a spurious mark 6,000 after every
    // 40th mark is the 41st edge, and both the pitch to it and the one from it are short.
    let mut marks_out: Vec<u32> = outside.iter().map(|p| p.0 as u32).collect();
    marks_out.sort_unstable();
    assert_eq!(marks_out, [41, 42, 82, 83, 123, 124, 164, 165]);
    for &(k, _) in outside {
        let k = k as usize;
        assert!(web[k - 1] - web[k - 2] < 10_000.0, "mark {k}");
    }
    // The estimate is PLEN& as the program left it before the next mark came.
    let estimate = trace_of(pitch, "PLEN&");
    let plen: Vec<(u64, f64)> = all
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == "PLEN&")
        .map(|e| {
            (
                e["tick"].as_u64().expect("tick"),
                e["value"].as_f64().expect("v"),
            )
        })
        .collect();
    let last_plen = plen.last().expect("PLEN& changes").1;
    assert_eq!(estimate.last().expect("points").1, last_plen);
    assert_eq!(estimate[0], (1.0, 15000.0));
    let set_point = trace_of(pitch, "TREND.SET&");
    assert_eq!(set_point[0].1, 15000.0);
    let (lo, hi) = pitch.y_range.expect("a range");
    assert!(lo < 13_000.0 && hi > 15_120.0 && hi < 16_000.0, "{lo} {hi}");

    let phase = &fig.charts[1];
    assert_eq!(phase.y_label, "phase error (axis 2 user units)");
    let errors = trace_of(phase, "measured");
    assert_eq!(errors.len(), knife.len());
    // INST.SET& is 0 and the knife turns 3,600 units: the error is −position, within ±1,800.
    for (k, (&(x, e), p)) in errors.iter().zip(&knife).enumerate() {
        assert_eq!(x, (k + 1) as f64);
        let want = if *p > 1800.0 { 3600.0 - p } else { -p };
        assert!((e - want).abs() < 1e-9, "mark {}: {e} {want}", k + 1);
    }
    // DIFF& is limited to ±300 (MAX.DIFF&); CORR& is a quarter of it (INST.GAIN& 25 %).
    let diff = trace_of(phase, "DIFF&");
    let corr = trace_of(phase, "CORR&");
    assert_eq!(diff[0], (1.0, -300.0));
    assert_eq!(corr[0], (1.0, -75.0));
    assert!(diff.iter().all(|p| p.1.abs() <= 300.0));
    for (d, c) in diff.iter().zip(corr) {
        assert_eq!(c.1, (d.1 * 2500.0 / 10000.0).trunc(), "mark {}", d.0);
    }
}

#[test]
fn the_labelers_picture_from_its_trace_holds_the_queue_counts_and_index_activity() {
    let rec = record("labeling", Preset::Servo, 38.0, Some(46.0));
    assert_eq!((rec.from, rec.to), (38.0, 46.0));
    let fig = figure(&Preset::Servo, &rec);
    let titles: Vec<&str> = fig.charts.iter().map(|c| c.title.as_str()).collect();
    assert_eq!(
        titles,
        [
            "Master position",
            "Servo position",
            "Index activity (CommandInProgress)",
            "Queue count"
        ]
    );
    // No positions in a trace: the master is drawn at captures and motion ends, and says so.
    let master = &fig.charts[0];
    assert!(master
        .note
        .as_deref()
        .is_some_and(|n| n.contains("not in the trace")));
    let captures: Vec<f64> = events("labeling")
        .iter()
        .filter(|e| e["kind"] == "capture")
        .filter(|e| (38.0..=46.0).contains(&e["t"].as_f64().expect("t")))
        .map(|e| e["master"].as_f64().expect("master"))
        .collect();
    let dots = trace_of(master, "MasterPosnFeedback at events");
    assert!(!captures.is_empty() && !dots.is_empty());
    for c in &captures {
        assert!(dots.iter().any(|d| d.1 == *c), "capture at master {c}");
    }
    // The digital rows and the queues that moved.
    let activity = &fig.charts[2];
    assert_eq!(activity.rows, ["Index.0", "Home.0"]);
    let queues = &fig.charts[3];
    let q0 = trace_of(queues, "Queue.0.QueueCount");
    // Held from before the window, drawn to its end, and within the queue's size of 12.
    assert_eq!(q0.first().expect("points").0, 38.0);
    assert_eq!(q0.last().expect("points").0, 46.0);
    assert!(q0.iter().all(|p| (0.0..=12.0).contains(&p.1)));
    assert!(q0.iter().any(|p| p.1 >= 10.0));
}

#[test]
fn the_pick_and_place_picture_shows_three_whole_cycles_unless_told_otherwise() {
    let rec = record("pick-and-place-delta-cv1-cv2", Preset::PickPlace, 0.0, None);
    let picks: Vec<f64> = events("pick-and-place-delta-cv1-cv2")
        .iter()
        .filter(|e| e["kind"] == "pick")
        .map(|e| e["t"].as_f64().expect("t"))
        .collect();
    // The window closes at the fourth pick.
    assert_eq!(rec.to, picks[3]);
    assert!(rec.auto_window);
    assert_eq!(rec.picks.len(), 4);
    assert_eq!(rec.places.len(), 3);
    let fig = figure(&Preset::PickPlace, &rec);
    let xy = &fig.charts[0];
    assert!(xy.equal_aspect);
    let picked = xy
        .traces
        .iter()
        .find(|t| t.style == Style::Triangles)
        .expect("picks");
    assert_eq!(picked.points[0], (rec.picks[0][1], rec.picks[0][2]));

    // A window given: every pick in it.
    let rec = record(
        "pick-and-place-delta-cv1-cv2",
        Preset::PickPlace,
        100.0,
        Some(200.0),
    );
    let want = picks
        .iter()
        .filter(|t| (100.0..=200.0).contains(*t))
        .count();
    assert!(want > 100);
    assert_eq!(rec.picks.len(), want);
    assert!(!rec.auto_window);
}
