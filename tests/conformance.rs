//! The manuals' own example programs (issue 16): every folder under `tests/conformance/<dialect>/`
//! holds a program as a manual prints it (restored), a machine file where the program needs
//! one, and `expect.toml`: the manual and page it comes from (`source`), what it shows
//! (`what`), and what it must do — the lines it prints (`output`), the end times of its
//! motions (`motion_ends`, seconds), values it leaves (`[values]`). Each checks and runs;
//! a folder without a source or an expectation fails.

mod common;

use pacer::load::{load, LoadRequest};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Expect {
    source: String,
    what: String,
    #[serde(default)]
    output: Option<Vec<String>>,
    #[serde(default)]
    motion_ends: Option<Vec<f64>>,
    #[serde(default)]
    values: BTreeMap<String, f64>,
}

fn examples() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/conformance");
    let mut out = Vec::new();
    for dialect in ["powertools", "motionbasic"] {
        let Ok(entries) = std::fs::read_dir(root.join(dialect)) else {
            continue;
        };
        let mut dirs: Vec<PathBuf> = entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.is_dir())
            .collect();
        dirs.sort();
        out.extend(dirs);
    }
    out
}

/// A value after the run: an object member by its name, a MotionBASIC variable or array
/// element by its registry name.
fn value(run: &common::Run, name: &str) -> Option<f64> {
    run.machine.value_of(name).or_else(|| {
        let slot = run
            .machine
            .registry()
            .slots
            .iter()
            .position(|s| s.name.text().eq_ignore_ascii_case(name))?;
        run.machine.values().get(slot).copied()
    })
}

fn check(dir: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(dir.join("expect.toml"))
        .map_err(|e| format!("no expect.toml: {e}"))?;
    let expect: Expect = toml::from_str(&text).map_err(|e| format!("expect.toml: {e}"))?;
    if expect.source.trim().is_empty() || expect.what.trim().is_empty() {
        return Err("expect.toml must name its source and what it shows".into());
    }
    if expect.output.is_none() && expect.motion_ends.is_none() && expect.values.is_empty() {
        return Err("expect.toml asserts nothing".into());
    }
    let loaded = load(&LoadRequest {
        paths: vec![dir.to_path_buf()],
        ..Default::default()
    })
    .map_err(|d| format!("does not load:\n{}", d.render_plain()))?;
    let run = common::run_loaded(loaded);
    if let Some(e) = &run.summary.error {
        return Err(format!("run-time error at line {}: {}", e.line, e.message));
    }
    let mut wrong = Vec::new();
    if let Some(want) = &expect.output {
        let got: Vec<String> = run
            .events
            .iter()
            .filter(|e| e["kind"] == "print")
            .map(|e| e["text"].as_str().unwrap_or_default().to_string())
            .collect();
        if &got != want {
            wrong.push(format!("printed {got:?}\n   wanted {want:?}"));
        }
    }
    if let Some(want) = &expect.motion_ends {
        let got: Vec<f64> = run
            .events
            .iter()
            .filter(|e| e["kind"] == "motion" && e["event"] == "done")
            .filter_map(|e| e["end"].as_f64())
            .collect();
        let same =
            got.len() == want.len() && got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-9);
        if !same {
            wrong.push(format!("motions ended at {got:?}, wanted {want:?}"));
        }
    }
    for (name, want) in &expect.values {
        let got = value(&run, name);
        if got.is_none_or(|g| (g - want).abs() > 1e-9) {
            wrong.push(format!("{name} = {got:?}, wanted {want}"));
        }
    }
    if wrong.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{} ({}):\n  {}",
            expect.what,
            expect.source,
            wrong.join("\n  ")
        ))
    }
}

#[test]
fn every_manual_example_checks_runs_and_does_what_its_manual_says() {
    let all = examples();
    assert!(all.len() >= 8, "the examples are missing: {all:?}");
    let failures: Vec<String> = all
        .iter()
        .filter_map(|d| check(d).err().map(|e| format!("{}: {e}", d.display())))
        .collect();
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}
