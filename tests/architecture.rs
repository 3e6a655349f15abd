//! The shape of the house, checked: every top-level folder of `src/` says its one job in its
//! module comment, and the device models sit below the front end — no module of the devices,
//! the world or the trace imports the front end (syntax, check, compile) or anything built on
//! it (the loader, the configuration stage, the VM, the REPL, the exporters).

use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`.
fn sources(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("a source folder") {
            let path = entry.expect("a folder entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

#[test]
fn every_top_level_folder_says_its_one_job() {
    let mut folders: Vec<PathBuf> = std::fs::read_dir(src())
        .expect("src")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.is_dir())
        .collect();
    folders.sort();
    assert!(folders.len() >= 10, "{folders:?}");
    for f in folders {
        let text = std::fs::read_to_string(f.join("mod.rs"))
            .unwrap_or_else(|e| panic!("{}: no mod.rs ({e})", f.display()));
        let comment: Vec<&str> = text.lines().take_while(|l| l.starts_with("//!")).collect();
        let words: usize = comment.iter().map(|l| l.split_whitespace().count()).sum();
        assert!(
            words >= 12,
            "{}/mod.rs must open with a `//!` comment saying what the folder does",
            f.display()
        );
    }
}

/// The `use crate::…` and `crate::…::` paths a file names, outside comments.
fn crate_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(i) = rest.find("crate::") {
            let after = &rest[i + "crate::".len()..];
            let name: String = after
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            out.push(name);
            rest = after;
        }
    }
    out
}

#[test]
fn the_device_models_never_import_the_front_end_or_what_is_built_on_it() {
    const ABOVE: &[&str] = &[
        "syntax", "check", "compile", "load", "config", "vm", "repl", "export", "io",
    ];
    for layer in ["devices", "world", "trace"] {
        for file in sources(&src().join(layer)) {
            let text = std::fs::read_to_string(&file).expect("a source file");
            for module in crate_paths(&text) {
                assert!(
                    !ABOVE.contains(&module.as_str()),
                    "{} imports crate::{module}: the {layer} layer must not depend on it",
                    file.display()
                );
            }
        }
    }
}

#[test]
fn the_registry_configuration_and_diagnostics_do_not_depend_on_the_front_end() {
    const FRONT: &[&str] = &["syntax", "check", "compile", "load", "vm", "repl", "export"];
    let mut files = sources(&src().join("registry"));
    files.extend(sources(&src().join("config")));
    files.push(src().join("diag.rs"));
    files.push(src().join("span.rs"));
    for file in files {
        let text = std::fs::read_to_string(&file).expect("a source file");
        for module in crate_paths(&text) {
            assert!(
                !FRONT.contains(&module.as_str()),
                "{} imports crate::{module}",
                file.display()
            );
        }
    }
}

#[test]
fn the_checker_finds_what_it_looks_for() {
    assert_eq!(
        crate_paths(
            "use crate::syntax::ast::Name; // crate::vm\nlet x = crate::devices::bind::same(a, b);"
        ),
        vec!["syntax".to_string(), "devices".to_string()]
    );
}
