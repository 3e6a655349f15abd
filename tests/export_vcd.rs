//! The labeler's VCD, read back by an independent parser (pyvcd, installed by `tests/run.sh`),
//! against the JSON trace of the same run: names and hierarchy, the timescale, and the value
//! changes of digital, integer and real signals.

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Reads a VCD with pyvcd and prints, as JSON: the timescale, every variable (dotted path below
/// the top scope → type, size) and the changes of the variables named on the command line.
const READER: &str = r#"
import json, sys
from vcd.reader import TokenKind, tokenize

path, wanted = sys.argv[1], set(sys.argv[2:])
scopes, ids, out = [], {}, {"timescale": None, "top": None, "vars": {}, "changes": {}}
time = None
with open(path, "rb") as f:
    for tok in tokenize(f):
        k = tok.kind
        if k is TokenKind.TIMESCALE:
            ts = tok.timescale
            out["timescale"] = f"{int(ts.magnitude)} {ts.unit.value}"
        elif k is TokenKind.SCOPE:
            scopes.append(tok.scope.ident)
            if out["top"] is None:
                out["top"] = tok.scope.ident
        elif k is TokenKind.UPSCOPE:
            scopes.pop()
        elif k is TokenKind.VAR:
            v = tok.var
            name = ".".join(scopes[1:] + [v.ref_str])
            out["vars"][name] = {"type": str(v.type_), "size": v.size}
            ids.setdefault(v.id_code, []).append(name)
        elif k is TokenKind.CHANGE_TIME:
            time = tok.time_change
        elif k in (TokenKind.CHANGE_SCALAR, TokenKind.CHANGE_VECTOR,
                   TokenKind.CHANGE_REAL, TokenKind.CHANGE_STRING):
            c = tok.data
            value = c.value
            if k is TokenKind.CHANGE_SCALAR:
                value = int(value)
            elif k is TokenKind.CHANGE_VECTOR and value >= 2**31:
                value -= 2**32
            for name in ids.get(c.id_code, []):
                if name in wanted:
                    out["changes"].setdefault(name, []).append([time, value])
print(json.dumps(out))
"#;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-export-vcd-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Where `tests/run.sh` installs pyvcd (beside the build, not into the system's Python).
fn pytools() -> PathBuf {
    std::env::var_os("PACER_PYTOOLS")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target/pytools"))
}

fn read_vcd(vcd: &Path, names: &[&str]) -> Value {
    let out = Command::new("python3")
        .arg("-c")
        .arg(READER)
        .arg(vcd)
        .args(names)
        .env("PYTHONPATH", pytools())
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "pyvcd could not read the VCD (pyvcd is installed by `bash tests/run.sh` into {}):\n{}",
        pytools().display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("the reader prints JSON")
}

/// The trace's changes of `name` as a VCD shows them: the last value of each update, and only
/// where it differs from the one before.
fn trace_levels(trace: &[Value], name: &str, initial: Value) -> Vec<(u64, Value)> {
    let mut per_tick: BTreeMap<u64, Value> = BTreeMap::new();
    for e in trace {
        if e["kind"] == "change" && e["name"] == name {
            let v = match &e["value"] {
                Value::Bool(b) => Value::from(i64::from(*b)),
                other => other.clone(),
            };
            per_tick.insert(e["tick"].as_u64().expect("tick"), v);
        }
    }
    let mut out: Vec<(u64, Value)> = vec![(0, per_tick.remove(&0).unwrap_or(initial))];
    for (tick, v) in per_tick {
        if out.last().map(|l| &l.1) != Some(&v) {
            out.push((tick, v));
        }
    }
    out
}

/// Equal level lists, or a failure showing where they part.
fn assert_same(name: &str, got: &[(u64, Value)], want: &[(u64, Value)]) {
    if let Some(i) = (0..got.len().max(want.len())).find(|&i| got.get(i) != want.get(i)) {
        let show =
            |l: &[(u64, Value)]| format!("{:?}", &l[i.saturating_sub(2)..(i + 3).min(l.len())]);
        panic!(
            "{name}: the VCD and the trace part at change {i} of {}/{}: VCD {} trace {}",
            got.len(),
            want.len(),
            show(got),
            show(want)
        );
    }
}

fn vcd_levels(read: &Value, name: &str) -> Vec<(u64, Value)> {
    read["changes"][name]
        .as_array()
        .unwrap_or_else(|| panic!("no changes of {name} in the VCD"))
        .iter()
        .map(|c| (c[0].as_u64().expect("time"), c[1].clone()))
        .collect()
}

#[test]
fn the_labelers_vcd_reads_back_with_the_traces_names_times_and_values() {
    let dir = scratch("labeling");
    let vcd = dir.join("labeling.vcd");
    let trace_path = dir.join("labeling.jsonl");
    let out = Command::new(env!("CARGO_BIN_EXE_pacer"))
        .current_dir(root())
        .args(["run", "programs/labeling", "-q", "--vcd"])
        .arg(&vcd)
        .arg("--trace")
        .arg(&trace_path)
        .output()
        .expect("pacer runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        !dir.join("labeling.vcd.changes").exists(),
        "the file the changes streamed to is removed"
    );
    let trace: Vec<Value> = std::fs::read_to_string(&trace_path)
        .expect("trace")
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();

    // With the value each starts the run with (the trace has changes only).
    let digital = [
        ("ModuleInput.2", 0),
        ("Capture.0.CaptureTriggered", 0),
        ("Queue.0.QueueExit", 0),
        ("Queue.1.QueueEmpty", 1),
        ("Index.0.CommandInProgress", 0),
        ("DriveIO.1.Out", 0),
    ];
    let integers = ["Queue.0.QueueCount", "Queue.1.QueueCount"];
    let reals = [
        ("Queue.0.ExitPosition", 0.0),
        ("Capture.0.CapturedMasterPosition", 0.0),
        ("Queue.0.QueueOffset", 10.0),
    ];
    let moving = ["MasterPosnFeedback", "PosnFeedback", "Task.0.State"];
    let names: Vec<&str> = digital
        .iter()
        .map(|d| &d.0)
        .chain(&integers)
        .chain(reals.iter().map(|r| &r.0))
        .chain(&moving)
        .copied()
        .collect();
    let read = read_vcd(&vcd, &names);

    // One time unit per update of 1 ms, scopes by object under the machine.
    assert_eq!(read["timescale"], "1 ms");
    assert_eq!(read["top"], "labeling");
    let vars = &read["vars"];
    for (name, _) in digital {
        assert_eq!(vars[name]["type"], "wire", "{name}");
        assert_eq!(vars[name]["size"], 1, "{name}");
    }
    for name in integers {
        assert_eq!(vars[name]["type"], "integer", "{name}");
    }
    for name in reals
        .iter()
        .map(|r| r.0)
        .chain(["MasterPosnFeedback", "PosnFeedback"])
    {
        assert_eq!(vars[name]["type"], "real", "{name}");
    }
    assert_eq!(vars["Task.0.State"]["type"], "string");
    // Numbers that never change are left out; so are the positions restated in other units.
    assert!(vars.get("FeedRateOverride").is_none());
    assert!(vars.get("MotorCounts").is_none());
    assert!(vars.get("FreeRunTime").is_none());
    // Every digital signal is there, changed or not.
    assert!(vars.get("DriveInput.2").is_some());

    // The VCD's levels are the trace's changes, update by update.
    for (name, initial) in digital {
        let want = trace_levels(&trace, name, Value::from(initial));
        assert!(want.len() > 2, "{name} changes in the run");
        assert_same(name, &vcd_levels(&read, name), &want);
    }
    for name in integers {
        let want = trace_levels(&trace, name, Value::from(0));
        assert_same(name, &vcd_levels(&read, name), &want);
    }
    for (name, initial) in reals {
        let want = trace_levels(&trace, name, Value::from(initial));
        assert!(want.len() > 2, "{name} changes in the run");
        let got = vcd_levels(&read, name);
        assert_eq!(got.len(), want.len(), "{name}");
        for ((tg, vg), (tw, vw)) in got.iter().zip(&want) {
            assert_eq!(tg, tw, "{name}");
            // Exactly: both files write the shortest text that reads back as the same double.
            assert_eq!(vg.as_f64(), vw.as_f64(), "{name} at {tg}");
        }
    }

    // Positions are in the VCD though not in the trace: the master runs at 20 units/s from 0
    // until its first speed change at 20 s, so it is at 200 at update 10,000 …
    let master = vcd_levels(&read, "MasterPosnFeedback");
    let at = |levels: &[(u64, Value)], tick: u64| -> f64 {
        levels
            .iter()
            .rev()
            .find(|(t, _)| *t <= tick)
            .and_then(|(_, v)| v.as_f64())
            .expect("a value")
    };
    assert!((at(&master, 10_000) - 200.0).abs() < 1e-9);
    assert!((at(&master, 15_000) - 300.0).abs() < 1e-9);
    // … and the servo is where the trace's captures say it was.
    let servo = vcd_levels(&read, "PosnFeedback");
    let mut checked = 0;
    for e in trace.iter().filter(|e| e["kind"] == "capture").take(200) {
        let tick = e["tick"].as_u64().expect("tick");
        // A capture latches at the edge, inside the update before the one that traces it.
        let command = e["command"].as_f64().expect("command");
        let before = at(&servo, tick - 1);
        let after = at(&servo, tick);
        assert!(
            (before.min(after) - 1e-9..=before.max(after) + 1e-9).contains(&command),
            "capture at update {tick}: {command} not within [{before}, {after}]"
        );
        checked += 1;
    }
    assert_eq!(checked, 200);

    // Task 0 takes Program 0 when ModuleInput.1 starts it at 10 ms.
    let task0 = vcd_levels(&read, "Task.0.State");
    assert_eq!(task0[0], (0, Value::from("free")));
    assert_eq!(task0[1].0, 10);
    assert_ne!(task0[1].1, "free");
}
