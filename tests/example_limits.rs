//! Every example under `programs/` (each folder with a machine.toml) is a cell that would run on
//! a real machine (issue 19): a software limit its machine.toml declares
//! (`[pickplace.sw_limit]`) must be enabled (`axSwLimitEnabled[i]`), and the run must keep
//! every such axis inside its limit at every update, with no module error.

mod common;

use pacer::devices::pickplace::robot::AXIS_NAMES;
use pacer::load::{load, LoadRequest};
use pacer::registry::{Kind, GLOBAL_INSTANCE};
use pacer::trace::Trace;
use pacer::vm::Machine;
use std::path::{Path, PathBuf};

/// Machine folders under `programs/`, one level of grouping allowed (as the golden traces).
fn program_folders() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("programs");
    let dirs = |p: &Path| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(p)
            .expect("a readable folder")
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.is_dir())
            .collect();
        v.sort();
        v
    };
    let mut folders = Vec::new();
    for d in dirs(&root) {
        if d.join("machine.toml").exists() {
            folders.push(d);
        } else {
            folders.extend(
                dirs(&d)
                    .into_iter()
                    .filter(|s| s.join("machine.toml").exists()),
            );
        }
    }
    folders
}

/// The software limits `[pickplace.sw_limit]` declares: (axis index, min, max).
fn declared_limits(folder: &Path) -> Vec<(usize, f64, f64)> {
    let text = std::fs::read_to_string(folder.join("machine.toml")).expect("machine.toml");
    let doc: toml::Table = text.parse().expect("machine.toml is TOML");
    let Some(table) = doc
        .get("pickplace")
        .and_then(|p| p.get("sw_limit"))
        .and_then(|s| s.as_table())
    else {
        return Vec::new();
    };
    let num = |v: &toml::Value| {
        v.as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .expect("a number")
    };
    table
        .iter()
        .map(|(name, v)| {
            let i = AXIS_NAMES
                .iter()
                .position(|n| n == name)
                .unwrap_or_else(|| panic!("{}: no axis {name}", folder.display()));
            let pair = v.as_array().expect("[min, max]");
            (i, num(&pair[0]), num(&pair[1]))
        })
        .collect()
}

/// How a run kept to its limits.
struct Kept {
    /// Per declared limit: the lowest and highest position seen.
    span: Vec<(f64, f64)>,
    /// Declared limits found not enabled at some update.
    disabled: Vec<&'static str>,
    /// The module's errors, as the trace has them.
    errors: Vec<String>,
    updates: u64,
}

fn run(folder: &Path, limits: &[(usize, f64, f64)]) -> Kept {
    let loaded = load(&LoadRequest {
        paths: vec![folder.to_path_buf()],
        ..Default::default()
    })
    .unwrap_or_else(|d| panic!("{} does not load:\n{}", folder.display(), d.render_plain()));
    let tick = loaded.image.tick_ns;
    let sink = common::Sink::default();
    let mut machine = Machine::new(loaded.image, Trace::new(Some(Box::new(sink.clone())), tick));
    let reg = machine.registry().clone();
    let slot = |name: String| {
        reg.slot_of(Kind::PickPlace, GLOBAL_INSTANCE, &name)
            .unwrap_or_else(|| panic!("no PickPlace.{name}")) as usize
    };
    let slots: Vec<(usize, usize)> = limits
        .iter()
        .map(|&(i, _, _)| {
            (
                slot(format!("axSwLimitEnabled[{}]", i + 1)),
                slot(format!("alrActPos[{}]", i + 1)),
            )
        })
        .collect();
    let mut kept = Kept {
        span: vec![(f64::INFINITY, f64::NEG_INFINITY); limits.len()],
        disabled: Vec::new(),
        errors: Vec::new(),
        updates: 0,
    };
    let summary = machine.run_observed(None, &mut |m: &Machine| {
        let v = m.values();
        kept.updates += 1;
        for (k, &(enabled, pos)) in slots.iter().enumerate() {
            let name = AXIS_NAMES[limits[k].0];
            if v[enabled] == 0.0 && !kept.disabled.contains(&name) {
                kept.disabled.push(name);
            }
            let span = &mut kept.span[k];
            *span = (span.0.min(v[pos]), span.1.max(v[pos]));
        }
    });
    assert!(
        summary.error.is_none(),
        "{}: {:?}",
        folder.display(),
        summary.error
    );
    machine.finish().expect("in-memory trace");
    kept.errors = sink
        .text()
        .lines()
        .filter(|l| l.contains(r#""kind":"pp_error""#))
        .map(str::to_owned)
        .collect();
    kept
}

#[test]
fn every_example_runs_with_its_software_limits_enabled_and_kept() {
    let folders = program_folders();
    assert!(!folders.is_empty(), "programs/ holds no machine folders");
    let mut checked = 0;
    let mut failures = Vec::new();
    for folder in folders {
        let limits = declared_limits(&folder);
        if limits.is_empty() {
            continue;
        }
        checked += 1;
        let kept = run(&folder, &limits);
        let name = folder.display();
        assert!(kept.updates > 1000, "{name}: only {} updates", kept.updates);
        if !kept.disabled.is_empty() {
            failures.push(format!(
                "{name}: software limits declared but not enabled: {}",
                kept.disabled.join(", ")
            ));
        }
        for e in &kept.errors {
            failures.push(format!("{name}: module error {e}"));
        }
        for (&(i, lo, hi), &(min, max)) in limits.iter().zip(&kept.span) {
            println!(
                "{name}: {} within [{lo}, {hi}]: ran over [{min:.3}, {max:.3}]",
                AXIS_NAMES[i]
            );
            if min < lo || max > hi {
                failures.push(format!(
                    "{name}: axis {} ran over [{min:.3}, {max:.3}], beyond its limit [{lo}, {hi}]",
                    AXIS_NAMES[i]
                ));
            }
        }
    }
    assert!(
        checked >= 2,
        "only {checked} examples declare software limits"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
