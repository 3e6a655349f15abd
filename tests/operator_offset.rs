//! Program 2 of the labeler, verbatim, with its scenario of operator presses: the offset changes
//! by exactly ±0.01 (fine) or ±0.10 (coarse) once per press — long presses and presses shorter
//! than one update included.

use serde_json::Value;

fn golden() -> Vec<Value> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/golden/operator-offset.jsonl"
    );
    std::fs::read_to_string(path)
        .expect("golden trace of programs/operator-offset")
        .lines()
        .map(|l| serde_json::from_str(l).expect("each trace line is JSON"))
        .collect()
}

#[test]
fn program2_is_verbatim_from_the_spec() {
    let spec = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/labeling/program2.pt"
    ))
    .expect("fixture");
    let ours = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/programs/operator-offset/program2.pt"
    ))
    .expect("program");
    assert_eq!(spec, ours);
    assert!(ours.contains("Queue.0.QueueOffset=Queue.0.QueueOffset + 0.10"));
}

#[test]
fn the_offset_moves_once_per_press_by_exactly_the_step() {
    let events = golden();
    let offsets: Vec<(f64, f64)> = events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == "Queue.0.QueueOffset")
        .map(|e| {
            (
                e["t"].as_f64().expect("t"),
                e["value"].as_f64().expect("value"),
            )
        })
        .collect();
    // (time of the press, expected change): see programs/operator-offset/scenario.toml.
    let expected = [
        (0.100, 0.01),
        (0.350, 0.10),
        (0.500, -0.10),
        (0.700, -0.01),
        (0.800, 0.01),
        (2.501, 0.01),
        (2.701, -0.01),
        (2.901, 0.10),
    ];
    assert_eq!(
        offsets.len(),
        expected.len(),
        "one change per press: {offsets:?}"
    );
    let mut previous = 10.0;
    for ((t, value), (press_t, step)) in offsets.iter().zip(expected) {
        assert!(
            (t - press_t).abs() < 1e-9,
            "change at {t}, press at {press_t}"
        );
        let delta = value - previous;
        assert!(
            (delta - step).abs() < 1e-9,
            "at {t}: changed by {delta}, expected {step}"
        );
        // Fixed point with 4 decimals: the stored value is exact to the decimal.
        assert_eq!((value * 10_000.0).round() / 10_000.0, *value);
        previous = *value;
    }
    assert_eq!(previous, 10.11);
}

#[test]
fn presses_shorter_than_one_update_are_seen() {
    let events = golden();
    // The 200 µs press at 2.5004 s shows as DriveInput.4 on for the update at 2.501 s only.
    let at = |name: &str, t: f64| {
        events
            .iter()
            .filter(|e| {
                e["kind"] == "change"
                    && e["name"] == name
                    && (e["t"].as_f64().unwrap_or(-1.0) - t).abs() < 1e-9
            })
            .map(|e| e["value"].clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(at("DriveInput.4", 2.501), vec![Value::Bool(true)]);
    assert_eq!(at("DriveInput.4", 2.502), vec![Value::Bool(false)]);
}
