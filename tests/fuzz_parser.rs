//! Fuzz target for the front end: generated inputs go through `parse_program`, then (when it
//! found no error) `check_program`, then (when that found no error) `compile`. Problems found on
//! the way (the first three of each stage) are rendered as the CLI renders them. A panic in any of these fails the test; a stack
//! overflow aborts the test binary; an input that makes no progress for a while is reported as
//! a hang.
//!
//! Three generators share the cases:
//!   * `grammar`  — programs built from the statement forms (typed and wild), deep nesting,
//!     long operator chains, deep expressions;
//!   * `mutation` — the fixture programs with tokens, bytes and lines inserted, deleted,
//!     replaced, duplicated, and block closers dropped;
//!   * `raw`      — random bytes and characters, token soup, very long lines, thousands of
//!     nested block openers.
//!
//! The harness (running the seeds and the edge inputs, the workers, the hang watchdog, the
//! report, the environment variables PACER_FUZZ_*) and the generator pieces that do not depend
//! on the dialect are `tests/common/fuzz.rs`, shared with `tests/fuzz_motionbasic.rs`;
//! inputs are saved as `<generator>.<crash|hang|slowest|current>.pt`.

use fuzz::{
    block, for_block, has_errors, if_block, layout, long_line, many_lines, many_openers, mutated,
    mutation, nested_blocks, number, op_chain, pick, pick_any, random_bytes, random_chars,
    random_text, recursive, regex, render, sp, token_soup, Stats,
};
use pacer::check::CheckEnv;
use pacer::compile::{compile, Layout};
use pacer::config::machine::MachineFile;
use pacer::registry::Registry;
use pacer::syntax::parse_program;
use proptest::prelude::*;
use proptest::sample::{select, Index};
use std::sync::atomic::Ordering;

#[path = "common/fuzz.rs"]
mod fuzz;

// ---------------------------------------------------------------------------------------------
// The pipeline under test
// ---------------------------------------------------------------------------------------------

const LOADED: &[u32] = &[0, 1, 2];

/// The two machines every input is checked against: `MachineFile::default()`, and
/// one that also declares user variables and named bits, so `Var.X` and `For Var.I` can pass.
struct Machines {
    default: Registry,
    with_vars: Registry,
}

impl Machines {
    fn new() -> Machines {
        let (default, problems) = pacer::config::registry(&MachineFile::default(), LOADED, &[]);
        assert!(problems.is_empty(), "default registry: {problems:?}");
        let toml_text = "[variables.X]\n[variables.I]\n[variables.Count]\n\
                         [variables.Offset]\ndecimals = 3\n\
                         [bits]\nnames = { Ready = 3, Done = 4 }\n";
        let file: MachineFile = toml::from_str(toml_text).expect("fuzz machine file");
        let (with_vars, problems) = pacer::config::registry(&file, LOADED, &[]);
        assert!(problems.is_empty(), "registry with variables: {problems:?}");
        Machines { default, with_vars }
    }
}

/// Run one input through the front end. Panics propagate (that is the failure we look for).
fn exercise(src: &str, m: &Machines, stats: &Stats) {
    let mut problems = Vec::new();
    let ast = parse_program(src, &mut problems);
    render("fuzz.pt", src, &problems);
    if has_errors(&problems) {
        return;
    }
    stats.parse_clean.fetch_add(1, Ordering::Relaxed);
    for reg in [&m.default, &m.with_vars] {
        let env = CheckEnv {
            registry: reg,
            loaded_programs: LOADED,
            all_programs: true,
        };
        let (program, problems) = pacer::check::check(
            &ast,
            pacer::syntax::Dialect::PowerTools,
            &env,
            &Default::default(),
        );
        render("fuzz.pt", src, &problems);
        if has_errors(&problems) {
            continue;
        }
        stats.check_clean.fetch_add(1, Ordering::Relaxed);
        let mut layout = Layout::new(reg);
        match compile(&program, src, "fuzz.pt", 0, &mut layout) {
            Ok(chunk) => {
                stats.compiled.fetch_add(1, Ordering::Relaxed);
                std::hint::black_box(chunk);
            }
            Err(problems) => {
                stats.compile_refused.fetch_add(1, Ordering::Relaxed);
                render("fuzz.pt", src, &problems);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Vocabulary
// ---------------------------------------------------------------------------------------------

/// Numeric members a program may read and write (default machine).
const NUM_RW: &[&str] = &[
    "Queue.0.QueueOffset",
    "Queue.7.QueueOffset",
    "Queue.3.FullLevel",
    "Timer.0.Preset",
    "Capture.0.CapturedMasterPosition",
    "Capture.3.CapturedTime",
    "Capture.1.CapturedPosnCommand",
    "Capture.2.CapturedPosnFeedback",
    "Index.0.Distance",
    "Index.15.Velocity",
    "Index.2.Acceleration",
    "Index.1.Deceleration",
    "Index.0.Time",
    "Index.4.RegistrationOffset",
    "Home.0.Offset",
    "Home.0.Velocity",
    "Jog.1.Velocity",
    "Gear.Ratio",
    "PLS.2.OnPosn",
    "PLS.7.Direction",
    "PLS.0.OffPosn",
    "Motion.FeedRateOverride",
    "FeedRateOverride",
    "StopDeceleration",
    "Motion.FollowingErrorLimit",
];
/// Numeric members that can count a For loop (stored, read-write).
const NUM_LOOP: &[&str] = &[
    "Capture.0.CapturedMasterPosition",
    "Index.0.Distance",
    "Home.0.Offset",
    "PLS.7.Direction",
    "Var.I",
    "Var.X",
    "var.count",
];
/// Read-only numeric members.
const NUM_RO: &[&str] = &[
    "Queue.0.DataOut",
    "Queue.1.ExitPosition",
    "Queue.2.QueueCount",
    "Queue.0.QueueSize",
    "Timer.1.Elapsed",
    "Program.1.Task",
    "FollowingError",
    "FreeRunTime",
    "Motion.FreeRunTime",
];
/// User variables (only the second machine declares them).
const VARS: &[&str] = &[
    "Var.X",
    "Var.I",
    "Var.Count",
    "Var.Offset",
    "var.x",
    "VAR.OFFSET",
];
/// Write-only inputs that take a number.
const NUM_IN: &[&str] = &["Queue.0.DataIn", "Queue.7.DataIn", "queue.1.datain"];
const BOOL_RW: &[&str] = &[
    "DriveOutput.1",
    "DriveOutput.4.Value",
    "ModuleOutput.2",
    "DriveIO.1.Out",
    "Bit.0",
    "Bit.31",
    "Bit.Ready",
    "Queue.0.QueueCompareEnable",
    "Capture.0.CaptureEnable",
    "Capture.2.CaptureActivate",
    "Index.0.SensorTrigger",
    "Jog.Select",
    "Jog.PlusActivate",
    "Gear.Activate",
    "PLS.0.Enable",
    "Timer.0.Synchronized",
];
const BOOL_RO: &[&str] = &[
    "DriveInput.1",
    "DriveInput.8",
    "DriveInput.4.Value",
    "ModuleInput.3",
    "DriveIO.2.In",
    "Program.0.Running",
    "Timer.0.Active",
    "Timer.0.Output",
    "Queue.0.QueueEmpty",
    "Queue.1.QueueExit",
    "Queue.0.QueueFull",
    "Queue.5.QueueOverflow",
    "Capture.0.CaptureTriggered",
    "Index.0.CommandComplete",
    "Index.3.AtVel",
    "Index.0.CommandInProgress",
    "Index.0.PLSStatus",
    "Index.0.LimitDistHit",
    "Index.0.ProfileLimited",
    "Index.ProfileLimited",
    "Index.0.Decelerating",
    "Home.0.CommandComplete",
    "Jog.0.CommandInProgress",
    "Gear.CommandInProgress",
    "Profile.0.Busy",
    "PLS.1.Status",
];
const ACTIONS: &[&str] = &[
    "Queue.0.QueueRemove",
    "Queue.1.QueueClear",
    "Capture.0.CaptureClear",
    "Capture.0.CaptureReset",
    "Index.0.Initiate",
    "Index.5.Stop",
    "Home.0.Initiate",
    "Home.0.Stop",
    "Jog.0.PlusInitiate",
    "Jog.1.MinusInitiate",
    "Jog.0.Stop",
    "Gear.Initiate",
    "Gear.Stop",
    "Program.1.Initiate",
    "Program.2.Stop",
    "Timer.0.Initiate",
    "Timer.3.Stop",
    "Stop",
    "Motion.Stop",
];
const MOTION_STARTS: &[&str] = &[
    "Index.0.Initiate",
    "Index.1.Initiate",
    "Home.0.Initiate",
    "Jog.0.PlusInitiate",
    "Jog.1.MinusInitiate",
    "Gear.Initiate",
];
const MODIFIERS: &[&str] = &[
    " Using Last",
    " Using Capture.0",
    " Using Capture.3",
    " On Profile.0",
    " On Profile.1",
    " Using Last On Profile.1",
    " On Profile.0 Using Capture.1",
];
const WILD_MODIFIERS: &[&str] = &[
    " Using Last",
    " Using Capture.0",
    " Using Capture.9",
    " Using Capture",
    " On Profile.0",
    " On Profile.5",
    " On Profile",
    " Using Var.X",
    " On Queue.0",
    " Using Last Using Last",
    " On Profile.0 On Profile.1",
    " Using",
    " On",
];
const INVALID_NAMES: &[&str] = &[
    "Foo",
    "Queue",
    "Queue.0",
    "Queue.8.QueueOffset",
    "Queue.99999999999999999999.QueueOffset",
    "Queue.4294967296.QueueOffset",
    "Queue.0.Nope",
    "Queue.00.QueueOffset",
    "Queue.0x1.QueueOffset",
    "Queue.0.QueueOffset.0",
    "DriveInput",
    "DriveInput.0",
    "DriveInput.9",
    "DriveInput.4.Value.Extra",
    "Var",
    "Var.Undeclared",
    "Var.0",
    "Var.X.Value.Value",
    "Bit.32",
    "Bit.Nope",
    "Bit.4294967295",
    "Program.17.Initiate",
    "Program.3.Initiate",
    "Capture.4.CaptureEnable",
    "Profile.2.Busy",
    "Motion",
    "Motion.Motion.Stop",
    "Gear.0.Initiate",
    "Jog.2.Velocity",
    "Jog.Velocity",
    "x",
    "_",
    "a.b.c.d.e.f.g.h.i.j",
    "ABS",
    "Index.0.If",
    "Index.0.Then",
    "PLS.1e3.Status",
    "Timer.Initiate",
    "Home.Initiate",
    "Value",
    "Initiate",
];
const TYPES: &[&str] = &[
    "DriveInput",
    "ModuleInput",
    "DriveIO",
    "DriveOutput",
    "ModuleOutput",
    "Var",
    "Bit",
    "Program",
    "Timer",
    "Queue",
    "Capture",
    "Index",
    "Home",
    "Jog",
    "Gear",
    "Profile",
    "PLS",
    "Motion",
];
const MEMBERS: &[&str] = &[
    "Value",
    "In",
    "Out",
    "Initiate",
    "Stop",
    "Running",
    "Task",
    "Preset",
    "Synchronized",
    "Elapsed",
    "Active",
    "Output",
    "DataIn",
    "DataOut",
    "QueueOffset",
    "ExitPosition",
    "QueueCompareEnable",
    "QueueExit",
    "QueueRemove",
    "QueueClear",
    "QueueEmpty",
    "QueueFull",
    "QueueOverflow",
    "QueueCount",
    "QueueSize",
    "FullLevel",
    "CaptureEnable",
    "CaptureActivate",
    "CaptureClear",
    "CaptureReset",
    "CaptureTriggered",
    "CapturedTime",
    "CapturedPosnCommand",
    "CapturedPosnFeedback",
    "CapturedMasterPosition",
    "SensorTrigger",
    "Distance",
    "Velocity",
    "Acceleration",
    "Deceleration",
    "Time",
    "RegistrationOffset",
    "CommandInProgress",
    "AtVel",
    "Decelerating",
    "CommandComplete",
    "PLSStatus",
    "LimitDistHit",
    "ProfileLimited",
    "Offset",
    "PlusInitiate",
    "MinusInitiate",
    "Select",
    "PlusActivate",
    "MinusActivate",
    "Activate",
    "Ratio",
    "Busy",
    "Enable",
    "OnPosn",
    "OffPosn",
    "Direction",
    "Status",
    "FeedRateOverride",
    "StopDeceleration",
    "FollowingError",
    "FollowingErrorLimit",
    "FreeRunTime",
];
const INSTANCES: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "4",
    "7",
    "8",
    "15",
    "16",
    "31",
    "32",
    "255",
    "007",
    "4294967295",
    "4294967296",
    "18446744073709551616",
    "X",
    "I",
    "Ready",
    "Count",
];
const NUMBERS: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "10",
    "0.5",
    ".5",
    "1.",
    "10.25",
    "0.01",
    "0.10",
    "1e3",
    "1E-3",
    "2.5e2",
    "1e308",
    "1e309",
    "1e-400",
    "4294967296",
    "2147483647",
    "2147483648",
    "99999999999999999999999",
    "0.0001",
    "3.14159",
    "00012",
    "0e0",
    "123456789.123456789",
];
const BOOL_WORDS: &[&str] = &[
    "ON", "OFF", "TRUE", "FALSE", "YES", "NO", "SET", "CLEAR", "ENABLE", "DISABLE", "on", "Off",
    "true",
];
const FUNC1: &[&str] = &[
    "ABS", "SQRT", "SQR", "SIN", "COS", "TAN", "ATAN", "ATN", "EXP", "LN", "LOG", "LOG10", "INT",
    "FIX", "TRUNC", "ROUND", "SGN", "abs", "Round",
];
const FUNC2: &[&str] = &["ATAN2", "MIN", "MAX", "min"];
const WILD_FUNCS: &[&str] = &[
    "ABS",
    "SQRT",
    "ATAN2",
    "MIN",
    "MAX",
    "FOO",
    "Var.X",
    "Queue.0.QueueOffset",
    "x",
    "LOG10",
];
const NUM_OPS: &[&str] = &["+", "-", "*", "/", "MOD", "^", "mod"];
const CMP_OPS: &[&str] = &["=", "<>", "<", "<=", ">", ">="];
const BOOL_OPS: &[&str] = &["AND", "OR", "XOR", "and", "Or"];
const ALL_OPS: &[&str] = &[
    "+", "-", "*", "/", "MOD", "^", "=", "<>", "<", "<=", ">", ">=", "AND", "OR", "XOR",
];
const LABELS: &[&str] = &["Top", "L1", "L2", "done", "Again", "top"];
/// Tokens and fragments for mutations and token soup.
const TOKENS: &[&str] = &[
    "Wait",
    "For",
    "Time",
    "Dwell",
    "Master",
    "Dist",
    "If",
    "Then",
    "Else",
    "Endif",
    "End If",
    "Do",
    "While",
    "Loop",
    "End",
    "Using",
    "Last",
    "On",
    "To",
    "Step",
    "Next",
    "Goto",
    "Jump",
    "Call",
    "TRUE",
    "FALSE",
    "ON",
    "OFF",
    "YES",
    "NO",
    "SET",
    "CLEAR",
    "ENABLE",
    "DISABLE",
    "NOT",
    "AND",
    "OR",
    "XOR",
    "MOD",
    "=",
    "<>",
    "<",
    "<=",
    ">",
    ">=",
    "+",
    "-",
    "*",
    "/",
    "^",
    "(",
    ")",
    ",",
    ":",
    "'",
    "‘",
    "’",
    "\"",
    "\r",
    "\t",
    "\n",
    "\r\n",
    " ",
    ".",
    "..",
    "0",
    "1",
    ".5",
    "1e",
    "1e999",
    "Var.X",
    "Var.I",
    "Queue.0.QueueOffset",
    "DriveInput.4",
    "Capture.0",
    "Profile.1",
    "Program.1",
    "Program.9",
    "ABS(",
    "MIN(",
    "x",
    "_",
    "é",
    "ß",
    "\u{200b}",
    "\u{feff}",
    "😀",
    "\u{0301}",
    "\0",
    "#",
    "$",
    "[",
    "]",
    "{",
    "}",
    ";",
    "!",
    "&",
    "|",
    "\\",
    "Top:",
    "L1",
];

fn ident() -> BoxedStrategy<String> {
    regex("[A-Za-z_][A-Za-z0-9_]{0,10}")
}

/// `Type.N.Member` built from pieces: mostly invalid combinations, some valid.
fn built_name() -> BoxedStrategy<String> {
    (
        prop_oneof![4 => pick(TYPES), 1 => ident()],
        prop::option::of(prop_oneof![3 => pick(INSTANCES), 1 => ident()]),
        prop::option::of(prop_oneof![3 => pick(MEMBERS), 1 => ident()]),
        0u8..4,
    )
        .prop_map(|(t, i, m, case)| {
            let mut s = t;
            if let Some(i) = i {
                s.push('.');
                s.push_str(&i);
            }
            if let Some(m) = m {
                s.push('.');
                s.push_str(&m);
            }
            match case {
                0 => s.to_ascii_lowercase(),
                1 => s.to_ascii_uppercase(),
                _ => s,
            }
        })
        .boxed()
}

fn any_name() -> BoxedStrategy<String> {
    prop_oneof![
        4 => pick_any(&[NUM_RW, NUM_RO, BOOL_RW, BOOL_RO, ACTIONS, VARS, NUM_IN]),
        2 => pick(INVALID_NAMES),
        2 => built_name(),
        1 => ident(),
    ]
    .boxed()
}

// ---------------------------------------------------------------------------------------------
// (a) Grammar-aware generator
// ---------------------------------------------------------------------------------------------

/// Numeric expressions over readable numeric names: these should type-check.
fn num_expr(with_vars: bool) -> BoxedStrategy<String> {
    let names = if with_vars {
        pick_any(&[NUM_RW, NUM_RO, VARS])
    } else {
        pick_any(&[NUM_RW, NUM_RO])
    };
    let leaf = prop_oneof![2 => number(NUMBERS), 2 => names];
    recursive(leaf.boxed(), 6, 24, 3, |inner| {
        prop_oneof![
            4 => (inner.clone(), sp(), pick(NUM_OPS), sp(), inner.clone()).prop_map(
                |(a, s1, op, s2, b)| {
                    // Word operators need spaces around them.
                    let (s1, s2) = if op.chars().all(char::is_alphabetic) { (" ", " ") } else { (s1, s2) };
                    format!("{a}{s1}{op}{s2}{b}")
                }
            ),
            2 => inner.clone().prop_map(|a| format!("({a})")),
            1 => inner.clone().prop_map(|a| format!("-{a}")),
            1 => (pick(FUNC1), inner.clone()).prop_map(|(f, a)| format!("{f}({a})")),
            1 => (pick(FUNC2), inner.clone(), inner).prop_map(|(f, a, b)| format!("{f}({a}, {b})")),
        ]
    })
    .boxed()
}

/// Conditions: these should type-check as ON/OFF values.
fn bool_expr(with_vars: bool) -> BoxedStrategy<String> {
    let num = num_expr(with_vars);
    let leaf = prop_oneof![
        1 => pick(BOOL_WORDS),
        3 => pick_any(&[BOOL_RW, BOOL_RO]),
        3 => (num.clone(), pick(CMP_OPS), num).prop_map(|(a, op, b)| format!("{a} {op} {b}")),
        2 => (pick_any(&[BOOL_RW, BOOL_RO]), pick(BOOL_WORDS))
            .prop_map(|(n, v)| format!("{n}={v}")),
    ];
    recursive(leaf.boxed(), 5, 16, 3, |inner| {
        prop_oneof![
            4 => (inner.clone(), pick(BOOL_OPS), inner.clone())
                .prop_map(|(a, op, b)| format!("{a} {op} {b}")),
            1 => inner.clone().prop_map(|a| format!("NOT {a}")),
            2 => inner.prop_map(|a| format!("({a})")),
        ]
    })
    .boxed()
}

/// Any expression: random names, any operator, any function, occasional stray keywords.
fn wild_expr() -> BoxedStrategy<String> {
    let leaf = prop_oneof![
        3 => number(NUMBERS),
        1 => pick(BOOL_WORDS),
        4 => any_name(),
        1 => pick(&["Last", "Then", "To", "Step", "If", "", "(", ")", ",", "-", "NOT"]),
    ];
    recursive(leaf.boxed(), 8, 96, 4, |inner| {
        prop_oneof![
            5 => (inner.clone(), sp(), pick(ALL_OPS), sp(), inner.clone()).prop_map(
                |(a, s1, op, s2, b)| {
                    let (s1, s2) = if op.chars().all(char::is_alphabetic) { (" ", " ") } else { (s1, s2) };
                    format!("{a}{s1}{op}{s2}{b}")
                }
            ),
            2 => inner.clone().prop_map(|a| format!("({a})")),
            2 => (pick(&["-", "+", "NOT ", "- -", "NOT NOT "]), inner.clone())
                .prop_map(|(u, a)| format!("{u}{a}")),
            1 => (pick(WILD_FUNCS), prop::collection::vec(inner, 0..4))
                .prop_map(|(f, args)| format!("{f}({})", args.join(", "))),
        ]
    })
    .boxed()
}

/// A statement tree, rendered as lines (children indented by two spaces).
#[derive(Clone)]
struct Vocab {
    leaf: BoxedStrategy<String>,
    cond: BoxedStrategy<String>,
    num: BoxedStrategy<String>,
    loop_var: BoxedStrategy<String>,
}

fn stmt_tree(v: Vocab) -> BoxedStrategy<Vec<String>> {
    let leaf = v.leaf.clone().prop_map(|l| vec![l]);
    recursive(leaf.boxed(), 5, 24, 4, move |inner| {
        let body = prop::collection::vec(inner, 0..5).prop_map(|b| b.concat());
        prop_oneof![
            3 => (v.cond.clone(), body.clone(), prop::option::of(body.clone()), 0u8..8).prop_map(
                |(c, then_b, else_b, form)| {
                    let end = if form == 0 { "End If" } else { "Endif" };
                    if_block(["If", "Then", "Else"], &c, then_b, else_b, end)
                }
            ),
            2 => (v.cond.clone(), body.clone())
                .prop_map(|(c, b)| block(format!("Do While {c}"), b, "Loop")),
            2 => (
                v.loop_var.clone(),
                v.num.clone(),
                v.num.clone(),
                prop::option::of(v.num.clone()),
                body,
                any::<bool>()
            )
                .prop_map(|(var, a, b, step, body, named_next)| {
                    for_block(["For", "To", "Step", "Next"], &var, &a, &b, step, body, named_next)
                }),
        ]
    })
    .boxed()
}

fn typed_leaf(with_vars: bool) -> BoxedStrategy<String> {
    let num = num_expr(with_vars);
    let cond = bool_expr(with_vars);
    let num_targets = if with_vars {
        pick_any(&[NUM_RW, NUM_IN, VARS])
    } else {
        pick_any(&[NUM_RW, NUM_IN])
    };
    prop_oneof![
        6 => (num_targets, sp(), sp(), num.clone()).prop_map(|(t, a, b, e)| format!("{t}{a}={b}{e}")),
        3 => (pick(BOOL_RW), cond.clone()).prop_map(|(t, e)| format!("{t}={e}")),
        3 => pick(ACTIONS),
        1 => pick(ACTIONS).prop_map(|a| format!("{a}=ON")),
        2 => (pick(MOTION_STARTS), pick(MODIFIERS)).prop_map(|(a, m)| format!("{a}{m}")),
        // A compound index: most often followed at once by the initiate it blends into (the
        // one form `pacer check` accepts), otherwise alone or into another kind of motion.
        1 => (
            pick(&["Index.0.CompoundInitiate", "Index.1.CompoundInitiate"]),
            pick(&["\nIndex.1.Initiate", "\nIndex.0.Initiate", "\nIndex.0.CompoundInitiate",
                   "\nHome.0.Initiate", "\nDwell For Time 0.1", "", "\nIndex.1.Initiate Using Capture.0"]),
            pick(&["", " On Profile.1", " Using Last"]),
        )
            .prop_map(|(c, next, m)| format!("{c}{m}{next}")),
        1 => pick(&["Index.ResetProfileLimited", "Index.ProfileLimited=OFF"]),
        1 => num.clone().prop_map(|e| format!("Dwell For Time {e}")),
        1 => num.clone().prop_map(|e| format!("Dwell For Time {e} Using Last")),
        1 => num.clone().prop_map(|e| format!("Dwell For Master Dist {e}")),
        1 => num.prop_map(|e| format!("Wait For Time {e}")),
        3 => cond.prop_map(|e| format!("Wait For {e}")),
        1 => pick(&[
            "Call Program.1", "Call Program.2", "Call Program.0", "Call Program.1", "Call Program.2",
            "Call Program.0", "call program.2", "Call Program.3",
        ]),
        1 => pick(LABELS).prop_map(|l| format!("{l}:")),
        1 => (pick(&["Goto ", "Jump To ", "Jump ", "GOTO "]), pick(LABELS))
            .prop_map(|(g, l)| format!("{g}{l}")),
        1 => pick(&["End", "", "' a comment", "‘curly comment’", "   ", "\t' tab comment"]),
    ]
    .boxed()
}

fn wild_leaf() -> BoxedStrategy<String> {
    let e = wild_expr();
    prop_oneof![
        6 => (any_name(), sp(), sp(), e.clone()).prop_map(|(t, a, b, e)| format!("{t}{a}={b}{e}")),
        3 => (any_name(), prop::collection::vec(pick(WILD_MODIFIERS), 0..3))
            .prop_map(|(n, m)| format!("{n}{}", m.concat())),
        1 => e.clone().prop_map(|e| format!("Dwell For Time {e}")),
        1 => e.clone().prop_map(|e| format!("Dwell For Master Dist {e}")),
        1 => e.clone().prop_map(|e| format!("Wait For Time {e}")),
        2 => e.clone().prop_map(|e| format!("Wait For {e}")),
        1 => any_name().prop_map(|n| format!("Call {n}")),
        1 => ident().prop_map(|l| format!("{l}:")),
        1 => ident().prop_map(|l| format!("Goto {l}")),
        1 => (ident(), any::<bool>()).prop_map(|(l, to)| if to { format!("Jump To {l}") } else { format!("Jump {l}") }),
        1 => pick(&[
            "End", "Else", "Endif", "End If", "Loop", "Next", "Next Var.I", "If", "If Then",
            "Do While", "Do", "For", "For Var.I", "For Var.I = 1", "For Var.I = 1 To",
            "Wait", "Wait For", "Dwell For", "Goto", "Call", ":", "End End", "' only a comment",
        ]),
        1 => (e.clone(), e).prop_map(|(a, b)| format!("{a} {b}")),
    ]
    .boxed()
}

/// A line that ends a block, as the statement generator writes it.
fn block_end(t: &str) -> bool {
    t == "Endif" || t == "End If" || t == "Loop" || t.starts_with("Next")
}

/// Render a statement list as a program with random indentation, case and line endings.
fn program(v: Vocab) -> BoxedStrategy<String> {
    (
        prop::collection::vec(stmt_tree(v), 0..12),
        0u8..10, // case style
        0u8..6,  // indentation unit
        0u8..8,  // line ending
        any::<bool>(),
        prop::option::weighted(0.15, (any::<Index>(), 0u8..4)), // light damage
    )
        .prop_map(|(stmts, case, ind, eol, final_end, damage)| {
            let mut lines: Vec<String> = stmts.concat();
            if final_end {
                lines.push("End".into());
            }
            if let Some((at, what)) = damage {
                fuzz::damage(&mut lines, at, what, block_end, "Else");
            }
            layout(&lines, case, ind, eol)
        })
        .boxed()
}

fn typed_program() -> BoxedStrategy<String> {
    let vocab = |with_vars: bool| Vocab {
        leaf: typed_leaf(with_vars),
        cond: bool_expr(with_vars),
        num: num_expr(with_vars),
        loop_var: pick(NUM_LOOP),
    };
    prop_oneof![program(vocab(false)), program(vocab(true))].boxed()
}

fn wild_program() -> BoxedStrategy<String> {
    program(Vocab {
        leaf: prop_oneof![3 => wild_leaf(), 1 => typed_leaf(true)].boxed(),
        cond: prop_oneof![1 => wild_expr(), 1 => bool_expr(true)].boxed(),
        num: prop_oneof![1 => wild_expr(), 1 => num_expr(true)].boxed(),
        loop_var: prop_oneof![1 => any_name(), 1 => pick(NUM_LOOP)].boxed(),
    })
}

/// Deep block nesting, long operator chains, deeply nested expressions: around the limits
/// (512 tokens a line, 64 nested blocks).
fn deep_input() -> BoxedStrategy<String> {
    const KINDS: &[u8] = &[0, 1, 2];
    let opener = select(KINDS);
    prop_oneof![
        // Nested blocks, closed properly (or not), each level with a statement.
        2 => (prop::collection::vec(opener, 1..130), any::<bool>(), typed_leaf(false)).prop_map(
            |(kinds, close, leaf)| {
                let openers = [
                    "If DriveInput.1 Then\n",
                    "Do While Queue.0.QueueEmpty = OFF\n",
                    "For Capture.0.CapturedMasterPosition = 1 To 10 Step 2\n",
                ];
                nested_blocks(&kinds, close, &leaf, &openers, &["Endif\n", "Loop\n", "Next\n"])
            }
        ),
        // Long chains of binary operators (many of them longer than 512 tokens).
        2 => (prop::collection::vec((pick(NUM_OPS), num_atom()), 1..400), num_atom()).prop_map(
            |(rest, first)| op_chain(format!("Queue.0.QueueOffset = {first}"), rest)
        ),
        1 => (prop::collection::vec((pick(BOOL_OPS), pick_any(&[BOOL_RO, BOOL_WORDS])), 1..300))
            .prop_map(|rest| op_chain("Wait For DriveInput.1".to_string(), rest)),
        // Deep nesting inside one expression.
        2 => (1usize..300, pick(&["(", "-", "+", "- ", "-(", "ABS(", "MIN(1,", "(1+", "2^("]), any::<bool>())
            .prop_map(|(n, open, closed)| {
                let close = match open.as_str() {
                    "(" | "ABS(" | "MIN(1," | "(1+" | "2^(" | "-(" => ")",
                    _ => "",
                };
                let tail = if closed { close.repeat(n) } else { String::new() };
                format!("Queue.0.QueueOffset = {}1{}\n", open.repeat(n), tail)
            }),
        1 => (1usize..560, pick(&["NOT ", "(", "NOT ("])).prop_map(|(n, open)| {
            let close = if open.contains('(') { ")" } else { "" };
            format!("Wait For {}DriveInput.1{}\n", open.repeat(n), close.repeat(n))
        }),
        // Right-nested sums and a left-nested power chain.
        1 => (1usize..200).prop_map(|n| {
            format!("Index.0.Distance = {}1{}\n", "(1 + ".repeat(n), ")".repeat(n))
        }),
        1 => (1usize..300).prop_map(|n| format!("Index.0.Distance = 2{}\n", " ^ 2".repeat(n))),
    ]
    .boxed()
}

fn num_atom() -> BoxedStrategy<String> {
    prop_oneof![1 => number(NUMBERS), 1 => pick(NUM_RW)].boxed()
}

fn grammar_input() -> BoxedStrategy<String> {
    prop_oneof![
        6 => typed_program(),
        3 => wild_program(),
        1 => deep_input(),
    ]
    .boxed()
}

// ---------------------------------------------------------------------------------------------
// (b) Mutations of the fixture programs
// ---------------------------------------------------------------------------------------------

const EXTRA_SEED: &str = "' exercises the forms the fixtures lack\n\
Top:\n\
For Capture.0.CapturedMasterPosition = 1 To 10 Step 0.5\n\
  Dwell For Time 0.25\n\
  If Queue.0.QueueCount > 3 AND NOT Queue.0.QueueEmpty Then\n\
    Index.0.Initiate Using Last On Profile.1\n\
  Else\n\
    Dwell For Master Dist ABS(-2.5) * 3 MOD 2 ^ 2\n\
  End If\n\
Next\n\
Wait For Time 1.5\n\
Queue.0.QueueOffset = -(Queue.0.QueueOffset + MIN(1, 2)) / 4\n\
Call Program.1\n\
If DriveInput.1 XOR DriveInput.2 Then\n\
  Goto Top\n\
Endif\n\
End\n";

fn seeds() -> Vec<String> {
    vec![
        include_str!("fixtures/labeling/program0.pt").to_string(),
        include_str!("fixtures/labeling/program1.pt").to_string(),
        include_str!("fixtures/labeling/program2.pt").to_string(),
        EXTRA_SEED.to_string(),
    ]
}

/// A line a mutation may drop (any case): the end of a block, or an `Else`.
fn closer(line: &str) -> bool {
    let t = line.to_ascii_lowercase();
    t == "endif" || t == "end if" || t == "loop" || t.starts_with("next") || t == "else"
}

fn mutation_input() -> BoxedStrategy<String> {
    let line = prop_oneof![2 => typed_leaf(true), 1 => wild_leaf(), 1 => pick(&[
        "If DriveInput.1 Then", "Else", "Endif", "Do While ON", "Loop",
        "For Var.I = 1 To 2", "Next", "L1:", "Goto L1",
    ])];
    mutated(seeds(), 4, mutation(TOKENS, line.boxed(), false), closer)
}

// ---------------------------------------------------------------------------------------------
// (c) Raw strings and bytes
// ---------------------------------------------------------------------------------------------

/// The ASCII characters that matter to PowerTools (`random_chars` adds the unusual ones).
const SPECIAL_CHARS: &[char] = &[
    '\'', '‘', '’', '\r', '\n', '\t', '(', ')', ' ', '.', ':', '=', '<', '>', '-', '+', '*', '/',
    '^', ',', '"', '_', '0', '9', 'e', 'E', 'I', 'f', 'x',
];

fn raw_input() -> BoxedStrategy<String> {
    prop_oneof![
        4 => random_chars(SPECIAL_CHARS),
        2 => random_text(),
        2 => random_bytes(),
        3 => token_soup(TOKENS, &[" ", "", "\n", "\t", "\r\n", "  "]),
        2 => long_line(
            &["", "Var.X = ", "Queue.0.QueueOffset = ", "Wait For ", "If ", "Call ", "Goto ", "x"],
            &[
                "(", ")", "a+", "x ", ".", "1", "A", "a.", "-", "NOT ", "If ", "'", "‘", "’", "é",
                "\u{200b}", "\r", "\t", "( ", "1,", ",", ":", "<>", "Then ", "A.1",
            ],
        ),
        2 => many_openers(
            &[
                "If x Then\n",
                "If DriveInput.1 Then\n",
                "Do While ON\n",
                "For Var.I = 1 To 2\n",
                "If ON Then\nElse\n",
                "If x Then\r",
            ],
            &["", "Endif\n", "Loop\n", "Next\n", "Else\n", "x = 1\n"],
        ),
        1 => many_lines(
            &["Endif\n", "Loop\n", "Next\n", "Else\n", "L:\n", "Goto L\n", "\n", "End\n", "'\n", "Queue.0.QueueOffset = 1\n"],
            &["", "Do While ON\n", "If ON Then\n", "L:\n"],
        ),
        // Many distinct labels and jumps.
        1 => (1usize..2000, any::<bool>()).prop_map(|(n, dup)| {
            let mut s = String::new();
            for i in 0..n {
                let l = if dup { i % 7 } else { i };
                s.push_str(&format!("L{l}:\nGoto L{}\n", (i * 7919) % n));
            }
            s
        }),
    ]
    .boxed()
}

// ---------------------------------------------------------------------------------------------
// Fixed edge inputs (run once, before the generators)
// ---------------------------------------------------------------------------------------------

fn edge_inputs() -> Vec<String> {
    let mut v: Vec<String> = vec![
        "\u{feff}End\n".into(),
        format!("Var.X = {}1", "(".repeat(10_000)),
        format!(
            "Queue.0.QueueOffset = {}1{}",
            "(".repeat(254),
            ")".repeat(254)
        ),
        format!(
            "Queue.0.QueueOffset = {}1{}",
            "(".repeat(255),
            ")".repeat(255)
        ),
        format!("Queue.0.QueueOffset = {}1", "-".repeat(509)),
        format!("Queue.0.QueueOffset = {}1", "-".repeat(510)),
        format!("Wait For {}DriveInput.1", "NOT ".repeat(509)),
        format!("Wait For {}DriveInput.1", "NOT ".repeat(100_000)),
        format!("Index.0.Distance = 2{}", " ^ 2".repeat(254)),
        format!(
            "Index.0.Distance = {}1{}",
            "ABS(".repeat(170),
            ")".repeat(170)
        ),
        "If x Then\n".repeat(5000),
        "If DriveInput.1 Then\n".repeat(64) + "Stop\n" + &"Endif\n".repeat(64),
        "If DriveInput.1 Then\n".repeat(65) + "Stop\n" + &"Endif\n".repeat(65),
        "Do While ON\n".repeat(64) + &"Loop\n".repeat(64),
        "For Var.I = 1 To 2\n".repeat(64) + &"Next\n".repeat(64),
        "Endif\n".repeat(10_000),
        "Do While ON\n".to_string() + &"Endif\n".repeat(5000),
        "If ON Then\n".to_string() + &"Else\n".repeat(5000),
        "Goto L\n".repeat(5000),
        format!("Var.{}", "a.".repeat(20_000)),
        "Var.X = 1 ‘curly comment’\nWait For DriveInput.1 ’x\n".into(),
        "Var.X = 1\rVar.X = 2\r".into(),
        "Index.0.Initiate Using Last Using Last On Profile.0 On Profile.1\n".into(),
        "For Var.I = 1 To 10 Step 0\nNext\n".into(),
        "Jump To\nJump\nGoto\n".into(),
        "ABS()\nVar.X = ABS()\nVar.X = MIN(1)\nVar.X = ATAN2(1,2,3)\n".into(),
        "Var.X = 1e999999\nVar.X = 1e-999999\n".into(),
        format!("Var.X = {}", "1 + ".repeat(255) + "1"),
        format!("Var.X = {}", "1 + ".repeat(256) + "1"),
    ];
    v.extend(seeds());
    v
}

#[test]
fn fuzz_front_end() {
    fuzz::run(fuzz::Target {
        name: "fuzz_parser",
        ext: "pt",
        salt: 0x5041_4345_5246_555A, // "PACERFUZ"
        machines: Machines::new,
        exercise,
        complete_seeds: seeds,
        edge_inputs,
        grammar: grammar_input,
        mutation: mutation_input,
        raw: raw_input,
        report_refused: true,
    });
}
