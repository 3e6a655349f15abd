//! The high-speed labeler run verbatim (programs/labeling): every product is captured once at
//! its exact position, bounces never enter a queue, every product that reaches the head gets
//! exactly one label, each label's index starts at captured position + QueueOffset, the
//! operator's presses move the label position, and a burst of products overflows the queue.

mod common;

use pacer::load::{load, LoadRequest};
use serde_json::Value;
use std::path::{Path, PathBuf};

struct Run {
    machine: pacer::vm::Machine,
    events: Vec<Value>,
    /// Leading-edge master positions of the scenario's products.
    leads: Vec<f64>,
}

fn run(paths: Vec<PathBuf>, scenario: Option<PathBuf>) -> Run {
    let loaded = match load(&LoadRequest {
        paths,
        machine: None,
        scenario,
    }) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let leads = loaded
        .image
        .products
        .iter()
        .flat_map(|(_, ps)| ps.iter().map(|p| p.lead))
        .collect();
    let r = common::run_loaded(loaded);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    Run {
        machine: r.machine,
        events: r.events,
        leads,
    }
}

fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/labeling")
}

fn kind<'a>(r: &'a Run, k: &str) -> Vec<&'a Value> {
    r.events.iter().filter(|e| e["kind"] == k).collect()
}

fn f(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or(f64::NAN)
}

/// QueueOffset in effect at each point of the trace: (tick, value) in order.
fn offsets(r: &Run) -> Vec<(u64, f64)> {
    let mut out = vec![(0, 10.0)];
    for e in &r.events {
        if e["kind"] == "change" && e["name"] == "Queue.0.QueueOffset" {
            out.push((e["tick"].as_u64().unwrap_or(0), f(e, "value")));
        }
    }
    out
}

#[test]
fn the_labeler_labels_every_product_where_it_should() {
    let r = run(vec![folder()], None);
    let master_end = r.machine.value_of("MasterPosnFeedback").expect("master");
    assert_eq!(r.leads.len(), 2000);
    let passed: Vec<f64> = r
        .leads
        .iter()
        .copied()
        .filter(|l| *l <= master_end)
        .collect();
    assert_eq!(
        passed.len(),
        2000,
        "the line runs long enough for every product to pass"
    );

    // Every product captured once, at its exact leading edge.
    let captures = kind(&r, "capture");
    assert_eq!(captures.len(), passed.len());
    for (c, lead) in captures.iter().zip(&passed) {
        assert!(
            (f(c, "master") - lead).abs() < 1e-9,
            "captured {} for an edge at {lead}",
            f(c, "master")
        );
    }

    // No bounce entered a queue: one entry per product in each queue.
    let queued = |q: &str| {
        kind(&r, "queue_in")
            .iter()
            .filter(|e| e["object"] == q)
            .count()
    };
    assert_eq!(queued("Queue.0"), 2000);
    assert_eq!(queued("Queue.1"), 2000);
    assert_eq!(r.machine.value_of("Queue.0.QueueOverflow"), Some(0.0));

    // Every product that reached the head got exactly one label, starting at captured position
    // + QueueOffset (the offset in effect when Program 1 read the exit position).
    let starts: Vec<&Value> = kind(&r, "motion")
        .into_iter()
        .filter(|e| e["object"] == "Index.0" && e["event"] == "start")
        .collect();
    let reached = passed.iter().filter(|l| **l + 10.2 <= master_end).count();
    assert!(
        starts.len() >= reached && starts.len() <= passed.len(),
        "{} labels for {reached} products at the head",
        starts.len()
    );
    let offs = offsets(&r);
    let mut worst: f64 = 0.0;
    for (k, s) in starts.iter().enumerate() {
        let captured = f(captures[k], "master");
        let tick = s["tick"].as_u64().unwrap_or(0);
        // The exit position was read before the start; try the offsets in effect around then.
        let fits = offs
            .iter()
            .filter(|(t, _)| *t <= tick)
            .map(|(_, o)| (f(s, "master") - (captured + o)).abs())
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(fits);
    }
    assert!(worst < 1e-6, "worst label start error {worst} master units");

    // The operator's presses moved the label position by exactly +0.01, +0.10, -0.01.
    let steps: Vec<f64> = offs
        .windows(2)
        .map(|w| ((w[1].1 - w[0].1) * 100.0).round() / 100.0)
        .collect();
    assert_eq!(steps, [0.01, 0.10, -0.01]);
}

#[test]
fn a_burst_of_products_overflows_the_label_queue_onto_drive_io_3() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-labeling-burst-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    // More than 12 products within the 10 master units between sensor and head.
    let scenario = "[run]\nduration = 4.0\n[master]\nspeed = 20.0\n\
                    [[products]]\nsensor = \"ModuleInput.2\"\nfirst = 5.0\npitch = 0.6\nlength = 0.2\ncount = 30\n\
                    [[axis_marks]]\nsensor = \"DriveInput.1\"\nfirst = 1.0\nwidth = 1000000.0\n\
                    [[press]]\nname = \"ModuleInput.1\"\nat = 0.01\nlength = 0.05\n";
    let sc = dir.join("burst.toml");
    std::fs::write(&sc, scenario).expect("scenario");
    let r = run(vec![folder()], Some(sc));
    let _ = std::fs::remove_dir_all(&dir);
    let overflow_on = r
        .events
        .iter()
        .any(|e| e["kind"] == "change" && e["name"] == "DriveIO.3.Out" && e["value"] == true);
    assert!(overflow_on, "QueueOverflow reached DriveIO.3.Out");
    assert_eq!(r.machine.value_of("Queue.0.QueueOverflow"), Some(1.0));
}

#[test]
fn without_using_capture_labels_start_late_by_the_scheduling_delay_times_line_speed() {
    // A copy of Program 1 with `Using Capture.1` removed (programs/labeling stays verbatim).
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-labeling-nocapture-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    for f in [
        "program0.pt",
        "program2.pt",
        "machine.toml",
        "scenario.toml",
    ] {
        std::fs::copy(folder().join(f), dir.join(f)).expect("copy");
    }
    let p1 = std::fs::read_to_string(folder().join("program1.pt")).expect("program 1");
    assert!(p1.contains("Index.0.Initiate Using Capture.1"));
    std::fs::write(
        dir.join("program1.pt"),
        p1.replace("Index.0.Initiate Using Capture.1", "Index.0.Initiate"),
    )
    .expect("write");
    let r = run(vec![dir.clone()], None);
    let _ = std::fs::remove_dir_all(&dir);

    // Without the capture, the index for product k starts when Program 1 reaches it: right
    // after it removed product k-1 at that product's exit. The start is then
    // exit(k-1) + (the delay from that exit to the initiate) × line speed.
    let exits: Vec<(u64, f64)> = kind(&r, "queue_exit")
        .iter()
        .filter(|e| e["object"] == "Queue.0")
        .map(|e| (e["tick"].as_u64().unwrap_or(0), f(e, "exit")))
        .collect();
    let starts: Vec<(u64, f64)> = kind(&r, "motion")
        .iter()
        .filter(|e| e["object"] == "Index.0" && e["event"] == "start")
        .map(|e| (e["tick"].as_u64().unwrap_or(0), f(e, "master")))
        .collect();
    assert!(starts.len() > 1900, "{} labels", starts.len());
    // Line speed at a tick, from the master positions the trace records at captures.
    let captures: Vec<(u64, f64, f64)> = kind(&r, "capture")
        .iter()
        .map(|c| {
            (
                c["tick"].as_u64().unwrap_or(0),
                f(c, "master"),
                f(c, "time"),
            )
        })
        .collect();
    let mut by_speed: std::collections::BTreeMap<i64, (f64, f64, usize)> = Default::default();
    for k in 1..starts.len().min(exits.len()) {
        let (start_tick, start) = starts[k];
        let (_, prev_exit) = exits[k - 1];
        let intended = exits[k].1;
        // Speed from the two captures around this product (master distance over time).
        let (a, b) = (
            captures[k.min(captures.len() - 1) - 1],
            captures[k.min(captures.len() - 1)],
        );
        let speed = if b.2 > a.2 {
            (b.1 - a.1) / (b.2 - a.2)
        } else {
            0.0
        };
        if speed <= 1.0 || start_tick == 0 {
            continue; // stopped line: no meaningful speed
        }
        let late = start - prev_exit;
        let error = start - intended;
        let band = (speed / 5.0).round() as i64 * 5;
        let e = by_speed.entry(band).or_insert((0.0, f64::NEG_INFINITY, 0));
        e.0 += late / speed;
        e.1 = e.1.max(error.abs());
        e.2 += 1;
        // The delay is at most a few updates (three tasks take turns).
        assert!(
            late >= -1e-9 && late <= 4.0 * 0.001 * speed + 1e-6,
            "product {k}: {late} units late at {speed} u/s"
        );
    }
    eprintln!("labels without Using Capture.1, by line speed:");
    eprintln!("  speed (u/s)  labels  mean delay after the previous exit  worst error vs captured + offset");
    for (band, (delay, worst, n)) in &by_speed {
        eprintln!(
            "  {band:>10}  {n:>6}  {:>10.2} ms ({:.4} units)  {worst:>10.3} units",
            delay / *n as f64 * 1000.0,
            delay / *n as f64 * *band as f64
        );
    }
    assert!(by_speed.len() >= 3, "several line speeds were seen");
}
