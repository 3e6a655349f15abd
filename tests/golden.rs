//! Golden traces: every machine folder under `programs/` runs with its own scenario, and its
//! JSON-lines trace must equal `tests/golden/<folder>.jsonl` byte for byte.
//! Bless (rewrite) them deliberately with `PACER_BLESS=1 cargo test --test golden`.

mod common;

use pacer::load::{load, LoadRequest};
use std::path::{Path, PathBuf};

fn run_folder(folder: &Path) -> String {
    let loaded = match load(&LoadRequest {
        paths: vec![folder.to_path_buf()],
        ..Default::default()
    }) {
        Ok(l) => l,
        Err(d) => panic!("{} does not load:\n{}", folder.display(), d.render_plain()),
    };
    let r = common::run_loaded(loaded);
    assert!(
        r.summary.error.is_none(),
        "{}: {:?}",
        folder.display(),
        r.summary.error
    );
    r.text
}

/// Machine folders (those with a machine.toml) under `programs/`, one level of grouping
/// allowed (`programs/regist/case1`), with their names for the golden files (`regist-case1`).
fn program_folders() -> Vec<(String, PathBuf)> {
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
    let name = |p: &Path| {
        p.file_name()
            .expect("folder name")
            .to_string_lossy()
            .into_owned()
    };
    let mut folders = Vec::new();
    for d in dirs(&root) {
        if d.join("machine.toml").exists() {
            folders.push((name(&d), d));
        } else {
            for sub in dirs(&d) {
                folders.push((format!("{}-{}", name(&d), name(&sub)), sub));
            }
        }
    }
    folders
}

#[test]
fn every_program_folder_matches_its_golden_trace() {
    let bless = std::env::var_os("PACER_BLESS").is_some();
    let folders = program_folders();
    assert!(!folders.is_empty(), "programs/ holds no machine folders");
    let mut failures = Vec::new();
    for (name, folder) in folders {
        let golden = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/golden")
            .join(format!("{name}.jsonl"));
        let trace = run_folder(&folder);
        if bless {
            std::fs::write(&golden, &trace).expect("write golden");
            continue;
        }
        let expected = std::fs::read_to_string(&golden).unwrap_or_else(|_| {
            panic!(
                "no golden trace {} (bless with PACER_BLESS=1)",
                golden.display()
            )
        });
        if expected != trace {
            let first = expected
                .lines()
                .zip(trace.lines())
                .position(|(a, b)| a != b)
                .unwrap_or(expected.lines().count().min(trace.lines().count()));
            failures.push(format!(
                "{name}: trace differs from {} at line {}:\n  golden: {}\n  now:    {}",
                golden.display(),
                first + 1,
                expected.lines().nth(first).unwrap_or("<end>"),
                trace.lines().nth(first).unwrap_or("<end>")
            ));
        }
    }
    assert!(failures.is_empty(), "{}\n(if the change is intended: PACER_BLESS=1 cargo test --test golden, then review the diff)", failures.join("\n"));
}

#[test]
fn the_same_run_twice_gives_byte_identical_traces() {
    for (_, folder) in program_folders() {
        let a = run_folder(&folder);
        let b = run_folder(&folder);
        assert!(!a.is_empty());
        assert!(a == b, "{}: two runs differ", folder.display());
    }
}
