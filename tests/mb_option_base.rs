//! `OPTION BASE` across the programs of a machine (MotionBASIC): the arrays are the machine's,
//! shared by its programs, and an array's lowest subscript is that of the program that
//! dimensions it (or first uses it, without DIM). One-program cases are in
//! `tests/lang/option_base.md`.

mod common;

use common::{load_memory, run_loaded_with_writes};
use pacer::diag::{Diagnostics, Level};

/// The messages of the errors of a project of these programs (`program0.mb`, …), with the
/// text under each error's span; none when it loads.
fn errors(name: &str, programs: &[&str]) -> Vec<(String, String)> {
    let files: Vec<(String, &str)> = programs
        .iter()
        .enumerate()
        .map(|(i, p)| (format!("program{i}.mb"), *p))
        .collect();
    let files: Vec<(&str, &str)> = files.iter().map(|(f, p)| (f.as_str(), *p)).collect();
    match load_memory(name, &files) {
        Ok(_) => Vec::new(),
        Err(d) => messages(&d, programs),
    }
}

fn messages(d: &Diagnostics, programs: &[&str]) -> Vec<(String, String)> {
    d.items
        .iter()
        .filter(|l| l.problem.level == Level::Error)
        .map(|l| {
            let span = l.problem.span;
            // The program the error is in, by its file's name.
            let text = programs
                .iter()
                .enumerate()
                .find(|(i, _)| l.file.name.ends_with(&format!("program{i}.mb")))
                .and_then(|(_, p)| p.get(span.start..span.end))
                .unwrap_or_default();
            (l.problem.message.clone(), text.to_string())
        })
        .collect()
}

#[test]
fn another_program_keeps_the_base_of_the_program_that_dimensions_the_array() {
    let p0 = "OPTION BASE 1\nDIM A(3)\nA(3) = 5\n";
    assert_eq!(errors("ob-keep", &[p0, "X = A(3) + A(1)\n"]), vec![]);
    assert_eq!(
        errors("ob-keep-0", &[p0, "X = A(0)\n"]),
        vec![(
            "Subscript out of range: 0 is not within 1 to 3".to_string(),
            "0".to_string()
        )]
    );
}

#[test]
fn a_dim_of_the_same_array_under_another_base_is_refused() {
    let e = errors(
        "ob-other-base",
        &["OPTION BASE 1\nDIM A(3)\n", "DIM A(3)\n"],
    );
    assert_eq!(
        e,
        vec![(
            "A is dimensioned differently elsewhere (subscripts from 0 here, under OPTION BASE 0; \
             from 1 there)"
                .to_string(),
            "A".to_string()
        )]
    );
}

#[test]
fn a_base_is_per_program() {
    // Program 1 says nothing: its own arrays start at 0.
    let e = errors(
        "ob-per-program",
        &[
            "OPTION BASE 1\nDIM A(3)\n",
            "DIM B(3)\nB(0) = 1\nX = A(0)\n",
        ],
    );
    assert_eq!(
        e,
        vec![(
            "Subscript out of range: 0 is not within 1 to 3".to_string(),
            "0".to_string()
        )]
    );
}

#[test]
fn base_one_elements_keep_their_names_and_element_zero_stays_unused() {
    let loaded = load_memory(
        "ob-run",
        &[(
            "program0.mb",
            "OPTION BASE 1\nDIM G&(2, 2)\nFOR I& = 1 TO 2: FOR J& = 1 TO 2\n\
             G&(I&, J&) = I& * 10 + J&\nNEXT J&: NEXT I&\n",
        )],
    )
    .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let run = run_loaded_with_writes(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let value = |name: &str| {
        let registry = run.machine.registry();
        let slot = registry
            .slots
            .iter()
            .position(|s| s.name == name)
            .unwrap_or_else(|| panic!("no {name}"));
        run.machine.values()[slot]
    };
    assert_eq!(value("G&(1,1)"), 11.0);
    assert_eq!(value("G&(1,2)"), 12.0);
    assert_eq!(value("G&(2,1)"), 21.0);
    assert_eq!(value("G&(2,2)"), 22.0);
    assert_eq!(value("G&(0,0)"), 0.0);
    assert_eq!(value("G&(0,2)"), 0.0);
}
