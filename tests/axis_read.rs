//! Controller-variable reads of the DSP axes (`POS@(ax~)`, `DSP.DONE@(ax~)`): a set of one
//! defined axis is read straight from its member's slot, any other set the long way, which
//! refuses it with its reason. Both give what they gave before that short way existed.

mod common;

use common::{project, run_loaded_with_writes};
use pacer::load::{load, LoadRequest};

const MACHINE: &str = r#"
[machine]
update = "1ms"

[[program]]
number = 0
file = "read.mb"

[axis.1]
units_per_rev = 600

[axis.2]
units_per_rev = 3600
"#;

/// Run `program` to its end: the values of `names` then, or the run's error.
fn run(name: &str, program: &str, names: &[&str]) -> Result<Vec<f64>, String> {
    let dir = project(name, &[("read.mb", program), ("machine.toml", MACHINE)]);
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let r = match loaded {
        Ok(l) => run_loaded_with_writes(l),
        Err(d) => panic!("{}", d.render_plain()),
    };
    if let Some(e) = r.summary.error {
        return Err(format!("{e:?}"));
    }
    Ok(names
        .iter()
        .map(|n| r.machine.value_of(n).expect("a variable"))
        .collect())
}

#[test]
fn one_axis_reads_its_member() {
    // The axes stand where they start; a set of one gives its value, a bit member -1 or 0.
    let got = run(
        "axis_read_one",
        "a~ = {1} : b~ = {2}\nPOS.MOD@(b~) = 900\nP = POS@(a~) : Q = POS.MOD@(b~)\nD = DSP.DONE@(a~) : E = DSP.DONE@({2})\n",
        &["P", "Q", "D", "E"],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(got[0], 0.0);
    assert_eq!(got[1], 900.0);
    // A standing axis's DSP is done: true is -1.
    assert_eq!(got[2], -1.0);
    assert_eq!(got[3], -1.0);
}

#[test]
fn other_sets_are_refused_with_their_reason() {
    for (name, program, says) in [
        (
            "axis_read_two",
            "c~ = {1, 2}\nP = POS@(c~)\n",
            "reads one axis",
        ),
        // Reading a set of two as a number (the checker cannot tell a set's size).
        ("axis_read_both", "P = POS@({1, 2})\n", "reads one axis"),
    ] {
        let err = run(name, program, &["P"]).expect_err(name);
        assert!(err.contains(says), "{name}: {err}");
    }
}
