//! The Track Pick & Place module's inputs, outputs and parameters under their manual names
//! (spec/pick-and-place.md, "How pacer exposes it"): reachable from PowerTools and MotionBASIC
//! programs (`PickPlace.alrStopDec[3]`, `Belt.2.lrZDistBelt`), set from `machine.toml`
//! (`[pickplace]`, `[pickplace.belt.N]`), with every mistake in the machine file reported at the
//! text it is about; and a machine without `[pickplace]` has no slots for it at all.

mod common;

use common::{load_error, project, run_loaded, Run};
use pacer::config::machine::MachineFile;
use pacer::config::parse_toml;
use pacer::devices::pickplace::setup::{AxisLimit, Kinematics};
use pacer::diag::{Diagnostics, Level, Problem};
use pacer::load::{load, LoadRequest, Loaded};
use pacer::registry::{Kind, Registry};

/// A delta robot over two belts, as the spec's "it works" cell.
const MACHINE: &str = r#"
[machine]
name = "pp-names"

[variables.copy]
decimals = 3

[pickplace]
kinematics = "delta3"
delta3 = { f = 400.0, e = 80.0, rf = 250.0, re = 700.0 }
start = [0.0, 0.0, -600.0]
lrPathVel = 2000.0
eTrackingMode = 3
xPosInWindow = true
alrStopDec = [50000.0, 50000.0, 50000.0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
"alrStopJerk[2]" = 1e6
lrAux1Jerk = 5000.0

[pickplace.joint.A1]
max_vel = 600.0
max_acc = 8000.0
max_jerk = 5e5

[pickplace.sw_limit]
Z = [-900.0, -300.0]
A1 = [-40.0, 95.0]

[pickplace.belt.1]
lrZDistBelt = 40.0
alrConveyorBeltOrigin = [-300.0, -400.0, -800.0, 0.0, 0.0, 0.0]
alrParkPos = [0.0, -250.0, -650.0, 0.0, 0.0, 0.0]
lrSyncTimeOnBelt = 0.06
lrLowerSyncLimit = 150.0
lrUpperSyncLimit = 650.0
max_vel = 400.0
max_acc = 2000.0
max_jerk = 40000.0

[pickplace.belt.2]
lrZDistBelt = 25.0
max_vel = 300.0
"#;

/// The same machine without the module.
const PLAIN: &str = r#"
[machine]
name = "pp-plain"

[variables.copy]
decimals = 3
"#;

/// Load one program (`x.pt` or `x.mb` by `file`) on `machine`; panics on errors.
fn load_on(name: &str, file: &str, program: &str, machine: &str) -> Loaded {
    let dir = project(
        &format!("pp-{name}"),
        &[(file, program), ("machine.toml", machine)],
    );
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    match loaded {
        Ok(l) => l,
        Err(d) => panic!("{name}: the project should load:\n{}", d.render_plain()),
    }
}

/// Run a program to its end; it must not fail.
fn run_on(name: &str, file: &str, program: &str, machine: &str) -> Run {
    let run = run_loaded(load_on(name, file, program, machine));
    if let Some(e) = &run.summary.error {
        panic!("{name}: run-time error: line {}: {}", e.line, e.message);
    }
    run
}

/// A value after the run, by member name or (MotionBASIC variables) slot name.
#[track_caller]
fn val(run: &Run, name: &str) -> f64 {
    run.machine
        .value_of(name)
        .or_else(|| {
            let slot = run
                .machine
                .registry()
                .slots
                .iter()
                .position(|s| s.name.text().eq_ignore_ascii_case(name))?;
            run.machine.values().get(slot).copied()
        })
        .unwrap_or_else(|| panic!("no `{name}` in the machine"))
}

#[track_caller]
fn assert_values(run: &Run, expected: &[(&str, f64)]) {
    let wrong: Vec<String> = expected
        .iter()
        .filter_map(|(name, want)| {
            let got = val(run, name);
            (got != *want).then(|| format!("{name}: got {got}, want {want}"))
        })
        .collect();
    assert!(wrong.is_empty(), "wrong values:\n{}", wrong.join("\n"));
}

/// The errors of a refused project with one program.
fn refused(name: &str, file: &str, program: &str, machine: &str) -> Vec<Problem> {
    let d: Diagnostics = load_error(
        &format!("pp-{name}"),
        &[(file, program), ("machine.toml", machine)],
    );
    d.items
        .iter()
        .filter(|l| l.problem.level == Level::Error)
        .map(|l| l.problem.clone())
        .collect()
}

#[track_caller]
fn one_error(name: &str, file: &str, program: &str, machine: &str) -> Problem {
    let e = refused(name, file, program, machine);
    assert_eq!(e.len(), 1, "{name}: expected one error, got {e:#?}");
    e[0].clone()
}

// ---------------------------------------------------------------------------------------------
// Programs write and read the members by their manual names.
// ---------------------------------------------------------------------------------------------

#[test]
fn a_powertools_program_writes_and_reads_module_and_belt_members() {
    let program = "\
PickPlace.lrPathVel = 1500.5
PickPlace.alrStopDec[3] = 12345
Belt.2.lrZDistBelt = 33.5
Belt.1.ascInitialObjectPosition[2] = -12.25
pickplace.ALRSTOPJERK[13] = 7
PickPlace.xExecutePickAndPlace = ON
PickPlace.eTrackingMode = 2
Var.copy = PickPlace.alrStopDec[3] + Belt.1.ascInitialObjectPosition[2]
End
";
    let run = run_on("pt-write", "x.pt", program, MACHINE);
    assert_values(
        &run,
        &[
            ("PickPlace.lrPathVel", 1500.5),
            ("PickPlace.alrStopDec[3]", 12345.0),
            ("Belt.2.lrZDistBelt", 33.5),
            ("Belt.1.ascInitialObjectPosition[2]", -12.25),
            ("PickPlace.alrStopJerk[13]", 7.0),
            ("PickPlace.xExecutePickAndPlace", 1.0),
            ("PickPlace.eTrackingMode", 2.0),
            ("Var.copy", 12332.75),
            // Untouched: the other belt's member and the neighbouring elements.
            ("Belt.1.lrZDistBelt", 40.0),
            ("PickPlace.alrStopDec[4]", 0.0),
        ],
    );
}

#[test]
fn a_motionbasic_program_writes_and_reads_module_and_belt_members() {
    let program = "\
PickPlace.lrPathVel = 1500.5
PICKPLACE.ALRSTOPDEC[3] = 12345
Belt.2.lrZDistBelt = 33.5
Belt.1.ascInitialObjectPosition[2] = -12.25
PickPlace.xExecutePickAndPlace = -1
PickPlace.xAckGripper = TRUE
Belt.2.xValidPos = 1
COPY = PickPlace.alrStopDec[3] + Belt.1.ascInitialObjectPosition[2]
ON.NOW& = PickPlace.xExecutePickAndPlace
NUM = 4
FCOEF& = 10000 * [1 - 0.1^(1/NUM)]
END
";
    let run = run_on("mb-write", "x.mb", program, MACHINE);
    assert_values(
        &run,
        &[
            ("PickPlace.lrPathVel", 1500.5),
            ("PickPlace.alrStopDec[3]", 12345.0),
            ("Belt.2.lrZDistBelt", 33.5),
            ("Belt.1.ascInitialObjectPosition[2]", -12.25),
            // MotionBASIC's true (-1) sets a bit ON (1), and a bit reads back as -1.
            ("PickPlace.xExecutePickAndPlace", 1.0),
            ("PickPlace.xAckGripper", 1.0),
            ("Belt.2.xValidPos", 1.0),
            ("COPY", 12332.75),
            ("ON.NOW&", -1.0),
            ("FCOEF&", (10000.0 * (1.0 - 0.1f64.powf(0.25))).round()),
        ],
    );
}

#[test]
fn brackets_still_group_in_motionbasic_expressions() {
    let program = "\
NUM = 2
FCOEF& = 10000 * [1 - 0.1^(1/NUM)]
A.B = 3
C = A.B [1]
D = A.B*[2]
END
";
    // `A.B [1]` (a space) is not an index: it is a name followed by a bracketed expression,
    // which is a syntax error, not a member.
    let errors = refused("mb-brackets", "x.mb", program, PLAIN);
    assert!(!errors.is_empty());
    assert!(
        errors
            .iter()
            .all(|e| &program[e.span.start..e.span.end] != "A.B [1]"),
        "{errors:#?}"
    );
    let program = "\
NUM = 2
FCOEF& = 10000 * [1 - 0.1^(1/NUM)]
A.B = 3
D = A.B*[2]
END
";
    let run = run_on("mb-brackets-ok", "x.mb", program, PLAIN);
    assert_values(
        &run,
        &[
            ("FCOEF&", (10000.0 * (1.0 - 0.1f64.sqrt())).round()),
            ("D", 6.0),
        ],
    );
}

#[test]
fn indexed_names_are_one_token_in_both_dialects() {
    use pacer::syntax::lex::lex;
    use pacer::syntax::token::Tok;
    use pacer::syntax::Dialect::{MotionBasic, PowerTools};
    let src = "Belt.2.ascInitialObjectPosition[1] = PickPlace.alrActPos[13]\n";
    let names: Vec<&str> = lex(src, PowerTools)
        .filter_map(Result::ok)
        .filter_map(|(_, t, _)| match t {
            Tok::Name(n) => Some(n),
            _ => None,
        })
        .collect();
    assert_eq!(
        names,
        [
            "Belt.2.ascInitialObjectPosition[1]",
            "PickPlace.alrActPos[13]"
        ]
    );
    let names: Vec<&str> = lex(src, MotionBasic)
        .filter_map(Result::ok)
        .filter_map(|(_, t, _)| match t {
            Tok::Name(n) => Some(n),
            _ => None,
        })
        .collect();
    assert_eq!(
        names,
        [
            "Belt.2.ascInitialObjectPosition[1]",
            "PickPlace.alrActPos[13]"
        ]
    );
    // Not an index: a bracket after a plain name, a space, or something other than digits.
    for src in ["X[1]", "A.B [1]", "A.B[I]", "A.B&[1]"] {
        let toks: Vec<Tok> = lex(src, MotionBasic)
            .filter_map(Result::ok)
            .map(|t| t.1)
            .collect();
        assert!(toks.contains(&Tok::LBracket), "{src}: {toks:?}");
    }
    let toks: Vec<Tok> = lex("Var.x[a]", PowerTools)
        .filter_map(Result::ok)
        .map(|t| t.1)
        .collect();
    assert_eq!(toks[0], Tok::Name("Var.x"), "{toks:?}");
}

// ---------------------------------------------------------------------------------------------
// machine.toml sets the members' initial values.
// ---------------------------------------------------------------------------------------------

#[test]
fn machine_file_values_are_the_initial_values() {
    let loaded = load_on("initial", "x.pt", "End\n", MACHINE);
    let reg = &loaded.image.registry;
    let initial = |name: &str| {
        let slot = reg
            .slots
            .iter()
            .position(|s| s.name == name)
            .unwrap_or_else(|| panic!("no slot {name}"));
        loaded.image.initial[slot]
    };
    let expected: &[(&str, f64)] = &[
        ("PickPlace.lrPathVel", 2000.0),
        ("PickPlace.eTrackingMode", 3.0),
        ("PickPlace.xPosInWindow", 1.0),
        ("PickPlace.alrStopDec[1]", 50000.0),
        ("PickPlace.alrStopDec[3]", 50000.0),
        ("PickPlace.alrStopDec[4]", 0.0),
        ("PickPlace.alrStopJerk[1]", 100000.0),
        ("PickPlace.alrStopJerk[2]", 1e6),
        ("PickPlace.lrAux1MaxJerk", 5000.0),
        // The manual's initial values where the file sets none.
        ("PickPlace.lrOverride", 1.0),
        ("PickPlace.lrATargetPos", 180.0),
        ("PickPlace.lrPosInWindow", 0.5),
        ("PickPlace.lrTimePosInWindow", 50.0),
        ("PickPlace.lrPathAcc", 100.0),
        ("PickPlace.lrPathStopJerk", 100000.0),
        ("PickPlace.lrXMaxJerk", 10000.0),
        ("Belt.1.lrZDistBelt", 40.0),
        ("Belt.1.alrConveyorBeltOrigin[2]", -400.0),
        ("Belt.1.alrParkPos[3]", -650.0),
        ("Belt.1.lrSyncTimeOnBelt", 0.06),
        ("Belt.1.lrUpperSyncLimit", 650.0),
        ("Belt.2.lrZDistBelt", 25.0),
        ("Belt.2.lrLowerSyncLimit", 0.0),
    ];
    let wrong: Vec<String> = expected
        .iter()
        .filter(|(n, v)| initial(n) != *v)
        .map(|(n, v)| format!("{n}: {} (want {v})", initial(n)))
        .collect();
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    // Two belts: the highest [pickplace.belt.N].
    assert_eq!(reg.of(Kind::Belt).count, 2);
    // The kernel finds members by name, the module's with instance 0 or GLOBAL_INSTANCE.
    assert!(reg
        .slot_of(Kind::PickPlace, pacer::registry::GLOBAL_INSTANCE, "xEnable")
        .is_some());
    assert_eq!(
        reg.slot_of(Kind::PickPlace, 0, "alrActPos[13]"),
        reg.slot_of(
            Kind::PickPlace,
            pacer::registry::GLOBAL_INSTANCE,
            "alrActPos[13]"
        )
    );
    assert!(reg.slot_of(Kind::Belt, 1, "Position").is_some());
    assert!(reg.slot_of(Kind::Belt, 2, "Position").is_none());
}

#[test]
fn the_setup_reads_kinematics_limits_and_belts() {
    let machine: MachineFile = parse_toml(MACHINE, "machine file").expect("machine file");
    let mut problems = Vec::new();
    let setup = pacer::config::pickplace::setup(&machine, &mut problems).expect("a setup");
    assert!(problems.is_empty(), "{problems:#?}");
    assert!(matches!(setup.kinematics, Kinematics::Delta3(_)));
    assert_eq!(setup.start, [0.0, 0.0, -600.0]);
    assert_eq!(
        setup.joint_limits[0],
        AxisLimit {
            max_vel: 600.0,
            max_acc: 8000.0,
            max_jerk: 5e5
        }
    );
    assert_eq!(setup.joint_limits[1], AxisLimit::default());
    assert_eq!(setup.sw_limits[2], Some((-900.0, -300.0)));
    assert_eq!(setup.sw_limits[6], Some((-40.0, 95.0)));
    assert_eq!(setup.sw_limits.iter().flatten().count(), 2);
    let belts: Vec<(u32, AxisLimit)> = setup.belts.iter().map(|b| (b.number, b.limit)).collect();
    assert_eq!(
        belts,
        [
            (
                1,
                AxisLimit {
                    max_vel: 400.0,
                    max_acc: 2000.0,
                    max_jerk: 40000.0
                }
            ),
            (
                2,
                AxisLimit {
                    max_vel: 300.0,
                    ..AxisLimit::default()
                }
            ),
        ]
    );

    let plain: MachineFile = parse_toml(PLAIN, "machine file").expect("machine file");
    assert!(pacer::config::pickplace::setup(&plain, &mut problems).is_none());
    let cartesian: MachineFile =
        parse_toml("[pickplace]\nlrPathVel = 5.0\n", "machine file").expect("machine file");
    let setup = pacer::config::pickplace::setup(&cartesian, &mut problems).expect("a setup");
    assert!(problems.is_empty(), "{problems:#?}");
    assert_eq!(setup.kinematics, Kinematics::Cartesian);
    assert_eq!(setup.start, [0.0; 3]);
    assert!(setup.belts.is_empty());
}

// ---------------------------------------------------------------------------------------------
// Every mistake in [pickplace] is reported at its text.
// ---------------------------------------------------------------------------------------------

/// Every problem of a machine file's `[pickplace]`: the registry's (members) and the set-up's
/// (the rest), as (code, text under the span, message, help).
fn machine_problems(toml: &str) -> Vec<(String, String, String, String)> {
    let machine: MachineFile = match parse_toml(toml, "machine file") {
        Ok(m) => m,
        Err(p) => panic!("the file should parse: {p:?}"),
    };
    let mut problems = Vec::new();
    pacer::config::machine(&machine, &[0], &[], &mut problems);
    problems
        .into_iter()
        .map(|p| {
            (
                p.code.to_string(),
                toml.get(p.span.start..p.span.end).unwrap_or("").to_string(),
                p.message,
                p.help.unwrap_or_default(),
            )
        })
        .collect()
}

#[test]
fn every_machine_file_mistake_points_at_its_text() {
    // (file, text the problem must point at, words of the message, words of the help)
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            "[pickplace]\nIrPathVel = 5.0\n",
            "IrPathVel",
            "unknown key",
            "lrPathVel",
        ),
        (
            "[pickplace]\nxError = true\n",
            "xError",
            "output",
            "inputs and parameters",
        ),
        (
            "[pickplace]\nlrPathVel = \"fast\"\n",
            "\"fast\"",
            "not a string",
            "number",
        ),
        (
            "[pickplace]\nalrStopDec = [1.0, 2.0]\n",
            "[1.0, 2.0]",
            "13 elements, not 2",
            "exactly 13",
        ),
        (
            "[pickplace]\nalrStopDec = 5.0\n",
            "5.0",
            "array of 13",
            "alrStopDec[1]",
        ),
        (
            "[pickplace]\nalrStopDec = [1, 2, 3, 4, 5, 6, 7, \"x\", 9, 10, 11, 12, 13]\n",
            "\"x\"",
            "not a string",
            "number",
        ),
        (
            "[pickplace]\n\"alrStopJerk[14]\" = 1.0\n",
            "\"alrStopJerk[14]\"",
            "no element 14",
            "alrStopJerk[1] to alrStopJerk[13]",
        ),
        (
            "[pickplace]\n\"alrStopJerk[0]\" = 1.0\n",
            "\"alrStopJerk[0]\"",
            "no element 0",
            "alrStopJerk[13]",
        ),
        (
            "[pickplace]\nxPosInWindow = 2\n",
            "2",
            "is a bit",
            "true or false",
        ),
        (
            "[pickplace]\neTrackingMode = 2.5\n",
            "2.5",
            "integer",
            "whole number",
        ),
        (
            "[pickplace]\nlrPathVel = inf\n",
            "inf",
            "finite",
            "finite",
        ),
        (
            "[pickplace]\n[pickplace.belt.17]\nlrZDistBelt = 1.0\n",
            "17",
            "no such belt",
            "1 to 16",
        ),
        (
            "[pickplace]\n[pickplace.belt.0]\nlrZDistBelt = 1.0\n",
            "0",
            "no such belt",
            "1 to 16",
        ),
        (
            "[pickplace.belt.01]\n[pickplace.belt.1]\n",
            "1",
            "set up twice",
            "",
        ),
        (
            "[pickplace.belt.1]\nPosition = 3.0\n",
            "Position",
            "status of the belt",
            "inputs and parameters",
        ),
        (
            "[pickplace.belt.1]\nlrZDistBelts = 3.0\n",
            "lrZDistBelts",
            "unknown key",
            "lrZDistBelt",
        ),
        (
            "[pickplace.belt.1]\nalrParkPos = [1.0, 2.0, 3.0]\n",
            "[1.0, 2.0, 3.0]",
            "6 elements, not 3",
            "exactly 6",
        ),
        (
            "[pickplace]\nkinematics = \"scara\"\n",
            "\"scara\"",
            "unknown kinematics",
            "delta3",
        ),
        (
            "[pickplace]\nkinematics = \"delta3\"\n",
            "\"delta3\"",
            "needs its dimensions",
            "delta3 = {",
        ),
        (
            "[pickplace]\nkinematics = \"delta3\"\ndelta3 = { f = 400.0, e = 80.0, rf = 10.0, re = 20.0 }\n",
            "{ f = 400.0, e = 80.0, rf = 10.0, re = 20.0 }",
            "not a Delta3 robot",
            "forearm",
        ),
        (
            "[pickplace]\nkinematics = \"delta3\"\ndelta3 = { f = 400.0, e = 80.0, rf = 250.0 }\n",
            "{ f = 400.0, e = 80.0, rf = 250.0 }",
            "lacks re",
            "forearm",
        ),
        (
            "[pickplace]\nkinematics = \"delta3\"\ndelta3 = { f = 400.0, e = 80.0, rf = 250.0, re = 700.0, g = 1.0 }\n",
            "g",
            "unknown key",
            "forearm",
        ),
        (
            "[pickplace]\nkinematics = \"delta3\"\ndelta3 = { f = -400.0, e = 80.0, rf = 250.0, re = 700.0 }\n",
            "{ f = -400.0, e = 80.0, rf = 250.0, re = 700.0 }",
            "positive",
            "base side",
        ),
        (
            "[pickplace]\nstart = [0.0, nan, 0.0]\n",
            "nan",
            "finite",
            "finite",
        ),
        (
            "[pickplace]\nstart = [0.0, 0.0]\n",
            "[0.0, 0.0]",
            "3 numbers, not 2",
            "X, Y and Z",
        ),
        (
            "[pickplace.joint.A4]\nmax_vel = 1.0\n",
            "A4",
            "unknown key",
            "A1, A2 and A3",
        ),
        (
            "[pickplace.joint.A1]\nmax_vel = -1.0\n",
            "-1.0",
            "cannot be negative",
            "0 for none",
        ),
        (
            "[pickplace.joint.A2]\nmax_speed = 1.0\n",
            "max_speed",
            "unknown key",
            "max_vel",
        ),
        (
            "[pickplace.belt.1]\nmax_acc = -5.0\n",
            "-5.0",
            "cannot be negative",
            "0 for none",
        ),
        (
            "[pickplace.belt.1]\nmax_jerk = nan\n",
            "nan",
            "finite",
            "finite",
        ),
        (
            "[pickplace.sw_limit]\nZ = [-300.0, -900.0]\n",
            "[-300.0, -900.0]",
            "not below the maximum",
            "min < max",
        ),
        (
            "[pickplace.sw_limit]\nW = [0.0, 1.0]\n",
            "W",
            "unknown key",
            "Aux1",
        ),
        (
            "[pickplace.sw_limit]\nAux1 = [0.0, \"far\"]\n",
            "\"far\"",
            "not a string",
            "number",
        ),
        (
            "[objects]\nBelt = 3\n[pickplace]\n",
            "3",
            "number of belts",
            "[pickplace.belt.N]",
        ),
    ];
    let mut failures = Vec::new();
    for (toml, text, message, help) in cases {
        let problems = machine_problems(toml);
        let ok = problems.len() == 1
            && problems[0].0.starts_with("pacer::machine::")
            && problems[0].1 == *text
            && problems[0].2.contains(message)
            && problems[0].3.contains(help);
        if !ok {
            failures.push(format!(
                "{toml}\n  want one problem at {text:?} ({message:?}, help {help:?})\n  got {problems:#?}"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn machine_file_mistakes_refuse_the_project_with_their_place() {
    let machine = "[pickplace]\nIrPathVel = 5.0\nkinematics = \"scara\"\n[pickplace.belt.20]\n";
    let d = load_error(
        "pp-load-refused",
        &[("x.pt", "End\n"), ("machine.toml", machine)],
    );
    let located: Vec<(&str, &str)> = d
        .items
        .iter()
        .map(|l| {
            (
                l.problem.code,
                l.file
                    .text
                    .get(l.problem.span.start..l.problem.span.end)
                    .unwrap_or(""),
            )
        })
        .collect();
    assert!(
        located.contains(&("pacer::machine::pickplace", "IrPathVel")),
        "{located:?}"
    );
    assert!(
        located.contains(&("pacer::machine::pickplace", "20")),
        "{located:?}"
    );
    assert!(
        located.contains(&("pacer::machine::pickplace", "\"scara\"")),
        "{located:?}"
    );
}

#[test]
fn a_delta3_table_without_delta3_kinematics_is_a_warning() {
    let problems =
        machine_problems("[pickplace]\ndelta3 = { f = 400.0, e = 80.0, rf = 250.0, re = 700.0 }\n");
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert!(problems[0].2.contains("not used"), "{problems:#?}");
}

// ---------------------------------------------------------------------------------------------
// Names in programs: suggestions, read-only outputs, indices, belts the machine lacks.
// ---------------------------------------------------------------------------------------------

#[test]
fn misspelt_and_misindexed_names_get_helpful_errors() {
    // (program line, text under the span, words of the message, words of the help)
    let cases: &[(&str, &str, &str, &str)] = &[
        // The manual's OCR prints l as I: the suggestion finds the real name.
        (
            "PickPlace.IrPathVel = 5\n",
            "IrPathVel",
            "no member",
            "lrPathVel",
        ),
        (
            "PickPlace.alrActPos[14] = 5\n",
            "alrActPos[14]",
            "no element 14",
            "alrActPos[1] to alrActPos[13]",
        ),
        (
            "PickPlace.alrStopDec = 5\n",
            "alrStopDec",
            "array of 13",
            "alrStopDec[1] to alrStopDec[13]",
        ),
        (
            "Belt.3.lrZDistBelt = 5\n",
            "3",
            "no belt 3",
            "[pickplace.belt.3]",
        ),
        (
            "PickPlace.xError = ON\n",
            "PickPlace.xError",
            "read-only",
            "",
        ),
        ("Belt.1.Position = 5\n", "Belt.1.Position", "read-only", ""),
    ];
    let mut failures = Vec::new();
    for (line, text, message, help) in cases {
        let errors = refused("names", "x.pt", line, MACHINE);
        let ok = errors.len() == 1
            && line.get(errors[0].span.start..errors[0].span.end) == Some(*text)
            && errors[0].message.contains(message)
            && errors[0].help.as_deref().unwrap_or("").contains(help);
        if !ok {
            failures.push(format!(
                "{line}  want {text:?} ({message:?}, help {help:?})\n  got {errors:#?}"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    // The same suggestion in MotionBASIC.
    let e = one_error("mb-ocr", "x.mb", "PICKPLACE.IRPATHVEL = 5\nEND\n", MACHINE);
    assert!(
        e.help.as_deref().unwrap_or("").contains("lrPathVel"),
        "{e:#?}"
    );
}

#[test]
fn motionbasic_variables_named_belt_dot_something_stay_variables() {
    let program = "BELT.SPEED = 2.5\nBELT.LEN& = BELT.SPEED * 4\nEND\n";
    for machine in [PLAIN, MACHINE] {
        let run = run_on("mb-belt-var", "x.mb", program, machine);
        assert_values(&run, &[("BELT.SPEED", 2.5), ("BELT.LEN&", 10.0)]);
    }
}

// ---------------------------------------------------------------------------------------------
// A machine without [pickplace] has no slots for it, and says so when a program names it.
// ---------------------------------------------------------------------------------------------

#[test]
fn a_machine_without_pickplace_has_no_module_slots() {
    let plain: MachineFile = parse_toml(PLAIN, "machine file").expect("machine file");
    let with: MachineFile = parse_toml(MACHINE, "machine file").expect("machine file");
    let (plain_reg, p) = pacer::config::registry(&plain, &[0], &[]);
    assert!(p.is_empty(), "{p:#?}");
    let (with_reg, p) = pacer::config::registry(&with, &[0], &[]);
    assert!(p.is_empty(), "{p:#?}");
    let module = |r: &Registry| {
        r.slots
            .iter()
            .filter(|s| matches!(s.kind, Kind::PickPlace | Kind::Belt))
            .count()
    };
    assert_eq!(module(&plain_reg), 0);
    assert_eq!(plain_reg.of(Kind::PickPlace).count, 0);
    assert_eq!(plain_reg.of(Kind::Belt).count, 0);
    assert!(module(&with_reg) > 300, "{}", module(&with_reg));
    // Everything else is laid out the same.
    assert_eq!(
        plain_reg.slot_count(),
        with_reg.slot_count() - module(&with_reg)
    );
    assert!(plain_reg.slot_of(Kind::PickPlace, 0, "xEnable").is_none());
    assert!(plain_reg
        .slot_of(Kind::PickPlace, pacer::registry::GLOBAL_INSTANCE, "xEnable")
        .is_none());
    assert!(plain_reg.slot_of(Kind::Belt, 0, "Position").is_none());
}

#[test]
fn naming_the_module_on_a_machine_without_it_says_how_to_add_it() {
    for (file, program, text) in [
        ("x.pt", "PickPlace.xEnable = ON\nEnd\n", "PickPlace"),
        ("x.pt", "Wait For Belt.1.xValidPos\nEnd\n", "Belt"),
        ("x.mb", "PickPlace.lrPathVel = 5\nEND\n", "PickPlace"),
        ("x.mb", "X = Belt.1.Position\nEND\n", "Belt"),
    ] {
        let e = one_error("absent", file, program, PLAIN);
        assert_eq!(&program[e.span.start..e.span.end], text, "{e:#?}");
        assert!(e.message.contains("no pick & place module"), "{e:#?}");
        assert!(
            e.help.as_deref().unwrap_or("").contains("[pickplace]"),
            "{e:#?}"
        );
    }
}
