//! Path preparation spread over updates (`[pickplace] prep_budget`, issue 19): both example
//! cells run with it as they run without it — the same picks, places, targets and misses, no
//! module error, every declared software limit kept — while the module reports PREPARING_PATH;
//! and a run with it is the same on every run (the work is counted in units, never in time).
//! It is the default: a machine file without `prep_budget` spreads at 250 units an update.

mod common;

use pacer::config::files::Memory;
use pacer::load::{load_from, LoadOptions, LoadRequest};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const CELLS: [&str; 2] = ["delta-cv1-cv2", "gantry-mode0"];

/// The cell `name` under programs/pick-and-place, with `extra` added to its `[pickplace]`.
fn run_cell(name: &str, extra: &str) -> common::Run {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("programs")
        .join("pick-and-place")
        .join(name);
    let mut memory = Memory::new();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the example's folder")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .collect();
    entries.sort();
    for p in entries {
        let file = p.file_name().expect("a file name").to_owned();
        let mut text = std::fs::read_to_string(&p).expect("a text file");
        if file == "machine.toml" {
            assert!(text.contains("\n[pickplace]\n"), "{name}: no [pickplace]");
            text = text.replacen("\n[pickplace]\n", &format!("\n[pickplace]\n{extra}\n"), 1);
        }
        memory = memory.file(Path::new("m").join(file), text);
    }
    let req = LoadRequest {
        paths: vec![PathBuf::from("m")],
        ..Default::default()
    };
    let loaded = load_from(&memory, &req, &LoadOptions::default())
        .unwrap_or_else(|d| panic!("{name} with {extra}: {}", d.render_plain()));
    let run = common::run_loaded(loaded);
    assert!(
        run.summary.error.is_none(),
        "{name}: {:?}",
        run.summary.error
    );
    run
}

/// How many events of each kind a run traced.
fn kinds(run: &common::Run) -> BTreeMap<String, usize> {
    let mut n = BTreeMap::new();
    for e in &run.events {
        if let Some(k) = e.get("kind").and_then(|k| k.as_str()) {
            *n.entry(k.to_owned()).or_insert(0) += 1;
        }
    }
    n
}

fn count(k: &BTreeMap<String, usize>, kind: &str) -> usize {
    k.get(kind).copied().unwrap_or(0)
}

#[test]
fn both_cells_keep_their_picks_places_and_misses_with_preparation_spread() {
    for cell in CELLS {
        let before = kinds(&run_cell(cell, "prep_budget = false"));
        // The default (`prep_budget = true`, 250 units an update), and more.
        for budget in ["true", "300"] {
            let run = run_cell(cell, &format!("prep_budget = {budget}"));
            let after = kinds(&run);
            assert_eq!(
                count(&after, "pp_error"),
                0,
                "{cell} at {budget}: {after:?}"
            );
            // No worse than without: as many picks, places and targets or more, as many
            // missed or fewer (the gantry cell, whose next move is now prepared during the one
            // before, reaches more targets in its 40 s).
            for kind in ["pick", "place", "pp_target"] {
                assert!(
                    count(&after, kind) >= count(&before, kind),
                    "{cell} at {budget} units an update: {kind} {} < {}",
                    count(&after, kind),
                    count(&before, kind)
                );
            }
            assert!(
                count(&after, "missed") <= count(&before, "missed"),
                "{cell} at {budget}: missed {after:?} {before:?}"
            );
            // PREPARING_PATH (eTMState 5) is seen at an update's end.
            let preparing = run.events.iter().any(|e| {
                e.get("name").and_then(|n| n.as_str()) == Some("PickPlace.eTMState")
                    && e.get("value").and_then(|v| v.as_f64()) == Some(5.0)
            });
            assert!(
                preparing,
                "{cell} at {budget}: PREPARING_PATH never reported"
            );
        }
    }
}

/// Without `prep_budget` a cell spreads its preparation at 250 units an update: the same
/// trace as `prep_budget = true` and as `prep_budget = 250`, another than `false`.
#[test]
fn spreading_is_the_default() {
    let default = run_cell("gantry-mode0", "");
    assert_eq!(
        default.text,
        run_cell("gantry-mode0", "prep_budget = true").text
    );
    assert_eq!(
        default.text,
        run_cell("gantry-mode0", "prep_budget = 250").text
    );
    assert_ne!(
        default.text,
        run_cell("gantry-mode0", "prep_budget = false").text
    );
}

/// At 150 units an update (the budget at which a first attempt, re-planning a late
/// preparation for a horizon twice as far, ended the gantry cell in error 20306): no error, and
/// the same trace on every run.
#[test]
fn a_spread_preparation_is_the_same_on_every_run() {
    let a = run_cell("gantry-mode0", "prep_budget = 150");
    let b = run_cell("gantry-mode0", "prep_budget = 150");
    assert_eq!(count(&kinds(&a), "pp_error"), 0);
    assert!(count(&kinds(&a), "pp_target") >= 20);
    assert_eq!(a.text, b.text);
}

#[test]
fn prep_budget_must_be_a_budget() {
    for bad in [
        "prep_budget = 5",
        "prep_budget = -1",
        "prep_budget = \"fast\"",
    ] {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("programs")
            .join("pick-and-place")
            .join("gantry-mode0");
        let mut memory = Memory::new();
        for f in ["cell.pt", "scenario.toml", "machine.toml"] {
            let mut text = std::fs::read_to_string(dir.join(f)).expect("the example's file");
            if f == "machine.toml" {
                text = text.replacen("\n[pickplace]\n", &format!("\n[pickplace]\n{bad}\n"), 1);
            }
            memory = memory.file(Path::new("m").join(f), text);
        }
        let req = LoadRequest {
            paths: vec![PathBuf::from("m")],
            ..Default::default()
        };
        match load_from(&memory, &req, &LoadOptions::default()) {
            Ok(_) => panic!("{bad} loaded"),
            Err(d) => assert!(d.render_plain().contains("prep_budget"), "{bad}"),
        }
    }
}
