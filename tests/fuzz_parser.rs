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
//! Environment:
//!   PACER_FUZZ_CASES   total generated inputs, split 40/35/25 (default 2000)
//!   PACER_FUZZ_SEED    u64 mixed into the fixed ChaCha seed (default 0: the standard run)
//!   PACER_FUZZ_ONLY    run one generator: grammar, mutation or raw
//!   PACER_FUZZ_DUMP    a directory: each worker writes the input it is about to run to
//!                      `<dir>/<generator>.current.pt` (to catch the input of a stack overflow)
//!   PACER_FUZZ_HANG_SECS  seconds without progress that count as a hang (default 120)
//!   PACER_FUZZ_STACK_KIB  stack of each worker thread (default 2048, as libtest's threads)

use pacer::check::{check_program, CheckEnv};
use pacer::compile::{compile, Layout};
use pacer::config::machine::MachineFile;
use pacer::diag::{Diagnostics, Level, Problem, SourceFile};
use pacer::registry::Registry;
use pacer::syntax::parse_program;
use proptest::prelude::*;
use proptest::sample::{select, Index};
use proptest::test_runner::{Config, RngAlgorithm, TestError, TestRng, TestRunner};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Once};
use std::time::{Duration, Instant};

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
        let default = Registry::build(&MachineFile::default(), LOADED).expect("default registry");
        let toml_text = "[variables.X]\n[variables.I]\n[variables.Count]\n\
                         [variables.Offset]\ndecimals = 3\n\
                         [bits]\nnames = { Ready = 3, Done = 4 }\n";
        let file: MachineFile = toml::from_str(toml_text).expect("fuzz machine file");
        let with_vars = Registry::build(&file, LOADED).expect("registry with variables");
        Machines { default, with_vars }
    }
}

#[derive(Default)]
struct Stats {
    executed: AtomicU64,
    parse_clean: AtomicU64,
    check_clean: AtomicU64,
    compiled: AtomicU64,
    /// Checked clean but the compiler still reported problems.
    compile_refused: AtomicU64,
    slowest_micros: AtomicU64,
    slowest_input: Mutex<String>,
    /// The input being run now (for the hang report).
    current: Mutex<String>,
    finished: AtomicBool,
}

fn has_errors(problems: &[Problem]) -> bool {
    problems.iter().any(|p| p.level == Level::Error)
}

/// Render a few problems as the CLI does (spans are resolved against the source there).
fn render(src: &str, problems: &[Problem]) {
    if problems.is_empty() {
        return;
    }
    let mut d = Diagnostics::new();
    let file = SourceFile::new("fuzz.pt", src);
    d.extend_file(&file, problems.iter().take(3).cloned().collect());
    std::hint::black_box(d.render_plain());
}

/// Run one input through the front end. Panics propagate (that is the failure we look for).
fn exercise(src: &str, m: &Machines, stats: &Stats) {
    let mut problems = Vec::new();
    let ast = parse_program(src, &mut problems);
    render(src, &problems);
    if has_errors(&problems) {
        return;
    }
    stats.parse_clean.fetch_add(1, Ordering::Relaxed);
    for reg in [&m.default, &m.with_vars] {
        let env = CheckEnv {
            registry: reg,
            loaded_programs: LOADED,
        };
        let problems = check_program(&ast, &env);
        render(src, &problems);
        if has_errors(&problems) {
            continue;
        }
        stats.check_clean.fetch_add(1, Ordering::Relaxed);
        let mut layout = Layout::new(reg);
        match compile(
            &ast,
            src,
            "fuzz.pt",
            0,
            reg,
            &mut layout,
            pacer::syntax::Dialect::PowerTools,
        ) {
            Ok(chunk) => {
                stats.compiled.fetch_add(1, Ordering::Relaxed);
                std::hint::black_box(chunk);
            }
            Err(problems) => {
                stats.compile_refused.fetch_add(1, Ordering::Relaxed);
                render(src, &problems);
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

fn pick(xs: &'static [&'static str]) -> BoxedStrategy<String> {
    select(xs).prop_map(str::to_string).boxed()
}

/// Concatenation of several static pools.
fn pick_any(pools: &[&'static [&'static str]]) -> BoxedStrategy<String> {
    let all: Vec<&'static str> = pools.iter().flat_map(|p| p.iter().copied()).collect();
    select(all).prop_map(str::to_string).boxed()
}

/// A regex strategy compiled once (a `&str` strategy would compile its regex for every value).
fn regex(re: &str) -> BoxedStrategy<String> {
    proptest::string::string_regex(re)
        .expect("valid regex")
        .boxed()
}

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

fn number() -> BoxedStrategy<String> {
    prop_oneof![
        3 => pick(NUMBERS),
        2 => (0u32..100_000).prop_map(|n| n.to_string()),
        1 => any::<f64>()
            .prop_filter("finite", |f| f.is_finite())
            .prop_map(|f| f.abs().to_string()),
        1 => regex("[0-9]{1,40}(\\.[0-9]{0,20})?([eE][+-]?[0-9]{1,4})?"),
    ]
    .boxed()
}

fn sp() -> BoxedStrategy<&'static str> {
    prop_oneof![6 => Just(" "), 1 => Just(""), 1 => Just("  "), 1 => Just("\t")].boxed()
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
    let leaf = prop_oneof![2 => number(), 2 => names];
    leaf.prop_recursive(6, 24, 3, |inner| {
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
    leaf.prop_recursive(5, 16, 3, |inner| {
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
        3 => number(),
        1 => pick(BOOL_WORDS),
        4 => any_name(),
        1 => pick(&["Last", "Then", "To", "Step", "If", "", "(", ")", ",", "-", "NOT"]),
    ];
    leaf.prop_recursive(8, 96, 4, |inner| {
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

fn indent(lines: Vec<String>) -> impl Iterator<Item = String> {
    lines.into_iter().map(|l| format!("  {l}"))
}

fn stmt_tree(v: Vocab) -> BoxedStrategy<Vec<String>> {
    let leaf = v.leaf.clone().prop_map(|l| vec![l]);
    leaf.prop_recursive(5, 24, 4, move |inner| {
        let body = prop::collection::vec(inner, 0..5).prop_map(|b| b.concat());
        prop_oneof![
            3 => (v.cond.clone(), body.clone(), prop::option::of(body.clone()), 0u8..8).prop_map(
                |(c, then_b, else_b, form)| {
                    let mut out = vec![format!("If {c} Then")];
                    out.extend(indent(then_b));
                    if let Some(e) = else_b {
                        out.push("Else".into());
                        out.extend(indent(e));
                    }
                    out.push(if form == 0 { "End If".into() } else { "Endif".into() });
                    out
                }
            ),
            2 => (v.cond.clone(), body.clone()).prop_map(|(c, b)| {
                let mut out = vec![format!("Do While {c}")];
                out.extend(indent(b));
                out.push("Loop".into());
                out
            }),
            2 => (
                v.loop_var.clone(),
                v.num.clone(),
                v.num.clone(),
                prop::option::of(v.num.clone()),
                body,
                any::<bool>()
            )
                .prop_map(|(var, a, b, step, body, named_next)| {
                    let mut out = vec![match step {
                        Some(s) => format!("For {var} = {a} To {b} Step {s}"),
                        None => format!("For {var} = {a} To {b}"),
                    }];
                    out.extend(indent(body));
                    out.push(if named_next { format!("Next {var}") } else { "Next".into() });
                    out
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
        1 => num.clone().prop_map(|e| format!("Dwell For Time {e}")),
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
                if !lines.is_empty() {
                    let closers: Vec<usize> = (0..lines.len())
                        .filter(|&i| {
                            let t = lines[i].trim();
                            t == "Endif" || t == "End If" || t == "Loop" || t.starts_with("Next")
                        })
                        .collect();
                    match what {
                        0 if !closers.is_empty() => {
                            lines.remove(closers[at.index(closers.len())]);
                        }
                        1 => {
                            let i = at.index(lines.len());
                            let l = lines[i].clone();
                            lines.insert(i, l);
                        }
                        2 => {
                            lines.remove(at.index(lines.len()));
                        }
                        _ => {
                            let i = at.index(lines.len());
                            lines.insert(i, "Else".into());
                        }
                    }
                }
            }
            let unit = ["  ", "\t", "", "    ", " ", " \t"][ind as usize];
            let eol = match eol {
                0 => "\r\n",
                1 => "\r",
                _ => "\n",
            };
            let mut out = String::new();
            for l in &lines {
                let depth = l.len() - l.trim_start_matches("  ").len();
                out.push_str(&unit.repeat(depth / 2));
                out.push_str(l.trim_start_matches("  "));
                out.push_str(eol);
            }
            match case {
                0 => out.to_uppercase(),
                1 => out.to_lowercase(),
                _ => out,
            }
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
                let mut s = String::new();
                for (d, k) in kinds.iter().enumerate() {
                    s.push_str(match k {
                        0 => "If DriveInput.1 Then\n",
                        1 => "Do While Queue.0.QueueEmpty = OFF\n",
                        _ => "For Capture.0.CapturedMasterPosition = 1 To 10 Step 2\n",
                    });
                    if d % 3 == 0 {
                        s.push_str(&leaf);
                        s.push('\n');
                    }
                }
                if close {
                    for k in kinds.iter().rev() {
                        s.push_str(["Endif\n", "Loop\n", "Next\n"][*k as usize]);
                    }
                }
                s
            }
        ),
        // Long chains of binary operators (many of them longer than 512 tokens).
        2 => (prop::collection::vec((pick(NUM_OPS), num_atom()), 1..400), num_atom()).prop_map(
            |(rest, first)| {
                let mut s = format!("Queue.0.QueueOffset = {first}");
                for (op, a) in rest {
                    s.push_str(&format!(" {op} {a}"));
                }
                s.push('\n');
                s
            }
        ),
        1 => (prop::collection::vec((pick(BOOL_OPS), pick_any(&[BOOL_RO, BOOL_WORDS])), 1..300))
            .prop_map(|rest| {
                let mut s = "Wait For DriveInput.1".to_string();
                for (op, a) in rest {
                    s.push_str(&format!(" {op} {a}"));
                }
                s.push('\n');
                s
            }),
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
    prop_oneof![1 => number(), 1 => pick(NUM_RW)].boxed()
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

fn seeds() -> Vec<&'static str> {
    vec![
        include_str!("fixtures/labeling/program0.pt"),
        include_str!("fixtures/labeling/program1.pt"),
        include_str!("fixtures/labeling/program2.pt"),
        EXTRA_SEED,
    ]
}

#[derive(Debug, Clone)]
enum Mutation {
    InsertToken(Index, &'static str),
    ReplaceWord(Index, &'static str),
    DeleteWord(Index),
    DeleteRange(Index, usize),
    InsertText(Index, String),
    SetByte(Index, u8),
    FlipBit(Index, u8),
    DuplicateLine(Index, usize),
    DeleteLine(Index),
    DropCloser(Index),
    SwapLines(Index, Index),
    InsertLine(Index, String),
}

fn mutation() -> BoxedStrategy<Mutation> {
    let idx = any::<Index>();
    prop_oneof![
        3 => (idx.clone(), select(TOKENS)).prop_map(|(i, t)| Mutation::InsertToken(i, t)),
        3 => (idx.clone(), select(TOKENS)).prop_map(|(i, t)| Mutation::ReplaceWord(i, t)),
        2 => idx.clone().prop_map(Mutation::DeleteWord),
        2 => (idx.clone(), 1usize..40).prop_map(|(i, n)| Mutation::DeleteRange(i, n)),
        2 => (idx.clone(), regex("(?s).{0,12}")).prop_map(|(i, s)| Mutation::InsertText(i, s)),
        1 => (idx.clone(), any::<u8>()).prop_map(|(i, b)| Mutation::SetByte(i, b)),
        1 => (idx.clone(), 0u8..8).prop_map(|(i, b)| Mutation::FlipBit(i, b)),
        2 => (idx.clone(), prop_oneof![4 => 1usize..4, 1 => 4usize..200, 1 => 200usize..2000])
            .prop_map(|(i, n)| Mutation::DuplicateLine(i, n)),
        2 => idx.clone().prop_map(Mutation::DeleteLine),
        3 => idx.clone().prop_map(Mutation::DropCloser),
        1 => (idx.clone(), idx.clone()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        2 => (idx, prop_oneof![2 => typed_leaf(true), 1 => wild_leaf(), 1 => pick(&[
            "If DriveInput.1 Then", "Else", "Endif", "Do While ON", "Loop",
            "For Var.I = 1 To 2", "Next", "L1:", "Goto L1",
        ])])
            .prop_map(|(i, l)| Mutation::InsertLine(i, l)),
    ]
    .boxed()
}

/// Largest char boundary at or below `i`.
fn boundary(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn words(s: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in s.char_indices() {
        match (c.is_whitespace(), start) {
            (false, None) => start = Some(i),
            (true, Some(st)) => {
                out.push((st, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(st) = start {
        out.push((st, s.len()));
    }
    out
}

fn apply(mut s: String, m: &Mutation) -> String {
    match m {
        Mutation::InsertToken(i, t) => {
            let at = boundary(&s, i.index(s.len() + 1));
            let sep = if i.index(2) == 0 { " " } else { "" };
            s.insert_str(at, &format!("{sep}{t}{sep}"));
            s
        }
        Mutation::ReplaceWord(i, t) => {
            let w = words(&s);
            if !w.is_empty() {
                let (a, b) = w[i.index(w.len())];
                s.replace_range(a..b, t);
            }
            s
        }
        Mutation::DeleteWord(i) => {
            let w = words(&s);
            if !w.is_empty() {
                let (a, b) = w[i.index(w.len())];
                s.replace_range(a..b, "");
            }
            s
        }
        Mutation::DeleteRange(i, n) => {
            let a = boundary(&s, i.index(s.len() + 1));
            let b = boundary(&s, a + n);
            s.replace_range(a..b, "");
            s
        }
        Mutation::InsertText(i, t) => {
            let at = boundary(&s, i.index(s.len() + 1));
            s.insert_str(at, t);
            s
        }
        Mutation::SetByte(i, v) | Mutation::FlipBit(i, v) => {
            let mut b = s.into_bytes();
            if !b.is_empty() {
                let k = i.index(b.len());
                if matches!(m, Mutation::SetByte(..)) {
                    b[k] = *v;
                } else {
                    b[k] ^= 1 << v;
                }
            }
            String::from_utf8_lossy(&b).into_owned()
        }
        Mutation::DuplicateLine(i, n) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            let k = i.index(lines.len());
            let l = lines[k];
            for _ in 0..*n {
                lines.insert(k, l);
            }
            lines.join("\n")
        }
        Mutation::DeleteLine(i) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            lines.remove(i.index(lines.len()));
            lines.join("\n")
        }
        Mutation::DropCloser(i) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            let closers: Vec<usize> = (0..lines.len())
                .filter(|&k| {
                    let t = lines[k].trim().to_ascii_lowercase();
                    t == "endif"
                        || t == "end if"
                        || t == "loop"
                        || t.starts_with("next")
                        || t == "else"
                })
                .collect();
            if !closers.is_empty() {
                lines.remove(closers[i.index(closers.len())]);
            }
            lines.join("\n")
        }
        Mutation::SwapLines(a, b) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            let (x, y) = (a.index(lines.len()), b.index(lines.len()));
            lines.swap(x, y);
            lines.join("\n")
        }
        Mutation::InsertLine(i, l) => {
            let mut lines: Vec<&str> = s.split('\n').collect();
            lines.insert(i.index(lines.len() + 1), l);
            lines.join("\n")
        }
    }
}

fn mutation_input() -> BoxedStrategy<String> {
    let n = seeds().len();
    (
        0..n,
        prop::option::of(0..n), // sometimes append a second program
        prop::collection::vec(mutation(), 1..8),
    )
        .prop_map(|(a, b, muts)| {
            let seeds = seeds();
            let mut s = seeds[a].to_string();
            if let Some(b) = b.filter(|_| a % 4 == 0) {
                s.push_str(seeds[b]);
            }
            for m in &muts {
                s = apply(s, m);
            }
            s
        })
        .boxed()
}

// ---------------------------------------------------------------------------------------------
// (c) Raw strings and bytes
// ---------------------------------------------------------------------------------------------

const SPECIAL_CHARS: &[char] = &[
    '\'',
    '‘',
    '’',
    '\r',
    '\n',
    '\t',
    '(',
    ')',
    ' ',
    '.',
    ':',
    '=',
    '<',
    '>',
    '-',
    '+',
    '*',
    '/',
    '^',
    ',',
    '"',
    '_',
    '0',
    '9',
    'e',
    'E',
    'I',
    'f',
    'x',
    '\u{0}',
    '\u{b}',
    '\u{c}',
    '\u{85}',
    '\u{a0}',
    '\u{2028}',
    '\u{feff}',
    'é',
    'ﬁ',
    'İ',
    'ß',
    '\u{10FFFF}',
    '😀',
    '\u{301}',
];

fn raw_input() -> BoxedStrategy<String> {
    let ch = prop_oneof![
        4 => select(SPECIAL_CHARS),
        4 => proptest::char::range(' ', '~'),
        1 => any::<char>(),
    ];
    prop_oneof![
        // Random characters biased to the ones that matter.
        4 => prop::collection::vec(ch, 0..400).prop_map(|v| v.into_iter().collect::<String>()),
        // Arbitrary unicode text.
        2 => regex("(?s).{0,200}"),
        // Random bytes, made valid UTF-8 the way a lossy file reader would.
        2 => prop::collection::vec(any::<u8>(), 0..600)
            .prop_map(|b| String::from_utf8_lossy(&b).into_owned()),
        // Token soup.
        3 => prop::collection::vec((select(TOKENS), pick(&[" ", "", "\n", "\t", "\r\n", "  "])), 0..200)
            .prop_map(|v| v.into_iter().map(|(t, s)| format!("{t}{s}")).collect::<String>()),
        // Very long lines of one fragment.
        2 => (
            pick(&["", "Var.X = ", "Queue.0.QueueOffset = ", "Wait For ", "If ", "Call ", "Goto ", "x"]),
            pick(&[
                "(", ")", "a+", "x ", ".", "1", "A", "a.", "-", "NOT ", "If ", "'", "‘", "’", "é",
                "\u{200b}", "\r", "\t", "( ", "1,", ",", ":", "<>", "Then ", "A.1",
            ]),
            prop_oneof![3 => 1usize..600, 2 => 600usize..6000, 1 => 6000usize..40_000],
        )
            .prop_map(|(pre, frag, n)| format!("{pre}{}\n", frag.repeat(n))),
        // Thousands of nested block openers, closed in part, in full, or not at all.
        2 => (
            pick(&[
                "If x Then\n",
                "If DriveInput.1 Then\n",
                "Do While ON\n",
                "For Var.I = 1 To 2\n",
                "If ON Then\nElse\n",
                "If x Then\r",
            ]),
            prop_oneof![1 => 1usize..100, 2 => 100usize..4000],
            pick(&["", "Endif\n", "Loop\n", "Next\n", "Else\n", "x = 1\n"]),
            0usize..5000,
        )
            .prop_map(|(open, n, close, m)| format!("{}{}", open.repeat(n), close.repeat(m))),
        // Many lines of one statement.
        1 => (
            pick(&["Endif\n", "Loop\n", "Next\n", "Else\n", "L:\n", "Goto L\n", "\n", "End\n", "'\n", "Queue.0.QueueOffset = 1\n"]),
            1usize..5000,
            pick(&["", "Do While ON\n", "If ON Then\n", "L:\n"]),
        )
            .prop_map(|(line, n, pre)| format!("{pre}{}", line.repeat(n))),
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
        String::new(),
        "\n".into(),
        "'".into(),
        "‘".into(),
        "’".into(),
        "\r".into(),
        "\r\n\r\n".into(),
        "\t\t".into(),
        "\u{feff}End\n".into(),
        "(".repeat(10_000),
        ")".repeat(10_000),
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
        "L:\n".repeat(5000),
        "Goto L\n".repeat(5000),
        "A".repeat(200_000),
        "9".repeat(100_000),
        format!("Var.{}", "a.".repeat(20_000)),
        "\r".repeat(20_000),
        "‘’".repeat(10_000),
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
    for s in seeds() {
        v.push(s.to_string());
    }
    v
}

// ---------------------------------------------------------------------------------------------
// Harness
// ---------------------------------------------------------------------------------------------

fn env_u64(name: &str, default: u64) -> u64 {
    match std::env::var(name) {
        Ok(s) => s
            .trim()
            .replace('_', "")
            .parse()
            .unwrap_or_else(|_| panic!("{name}={s:?} is not a number")),
        Err(_) => default,
    }
}

/// A 32-byte ChaCha seed from the run seed and the generator number (splitmix64).
fn seed_bytes(run_seed: u64, generator: u64) -> [u8; 32] {
    let mut x = run_seed ^ generator.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x5041_4345_5246_555A;
    let mut out = [0u8; 32];
    for chunk in out.chunks_mut(8) {
        x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = x;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        chunk.copy_from_slice(&z.to_le_bytes());
    }
    out
}

/// What a panic in a worker thread said, with its backtrace.
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);
static HOOK: Once = Once::new();

fn install_panic_hook() {
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let in_worker = std::thread::current()
                .name()
                .is_some_and(|n| n.starts_with("fuzz-"));
            if in_worker {
                // Quiet: shrinking re-runs failing inputs many times. Keep the last report.
                let bt = std::backtrace::Backtrace::force_capture();
                *LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()) =
                    Some(format!("{info}\nbacktrace:\n{bt}"));
            } else {
                default(info);
            }
        }));
    });
}

fn out_dir() -> std::path::PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz_parser");
    let _ = std::fs::create_dir_all(&d);
    d
}

fn shown(s: &str) -> String {
    const MAX: usize = 3000;
    if s.len() <= MAX {
        format!("{s:?}")
    } else {
        let cut = boundary(s, MAX);
        format!("{:?}… ({} bytes in all)", &s[..cut], s.len())
    }
}

/// Builds a generator's strategy (inside its worker: strategies are not `Send`).
type MakeStrategy = fn() -> BoxedStrategy<String>;

struct Worker {
    name: &'static str,
    cases: u32,
    stats: Arc<Stats>,
    handle: std::thread::JoinHandle<Result<(), String>>,
}

fn spawn_worker(
    name: &'static str,
    index: u64,
    cases: u32,
    make_strategy: MakeStrategy,
    machines: Arc<Machines>,
) -> Worker {
    let stats = Arc::new(Stats::default());
    let st = Arc::clone(&stats);
    let stack = env_u64("PACER_FUZZ_STACK_KIB", 2048) as usize * 1024;
    let run_seed = env_u64("PACER_FUZZ_SEED", 0);
    let dump = std::env::var_os("PACER_FUZZ_DUMP").map(std::path::PathBuf::from);
    let handle = std::thread::Builder::new()
        .name(format!("fuzz-{name}"))
        .stack_size(stack)
        .spawn(move || {
            let strategy = make_strategy();
            let config = Config {
                cases,
                failure_persistence: None,
                source_file: None,
                fork: false,
                timeout: 0,
                verbose: 0,
                max_shrink_iters: 4000,
                max_shrink_time: 120_000,
                max_local_rejects: 1_000_000,
                max_global_rejects: 1_000_000,
                ..Config::default()
            };
            let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes(run_seed, index));
            let mut runner = TestRunner::new_with_rng(config, rng);
            let dump_file = dump.map(|d| {
                let _ = std::fs::create_dir_all(&d);
                d.join(format!("{name}.current.pt"))
            });
            let result = runner.run(&strategy, |input| {
                st.executed.fetch_add(1, Ordering::Relaxed);
                {
                    let mut cur = st.current.lock().unwrap_or_else(|e| e.into_inner());
                    cur.clear();
                    cur.push_str(&input);
                }
                if let Some(f) = &dump_file {
                    std::fs::write(f, &input).expect("write PACER_FUZZ_DUMP file");
                }
                let t0 = Instant::now();
                exercise(&input, &machines, &st);
                let us = t0.elapsed().as_micros() as u64;
                if us > st.slowest_micros.load(Ordering::Relaxed) {
                    st.slowest_micros.store(us, Ordering::Relaxed);
                    *st.slowest_input.lock().unwrap_or_else(|e| e.into_inner()) = input;
                }
                Ok(())
            });
            st.finished.store(true, Ordering::SeqCst);
            match result {
                Ok(()) => Ok(()),
                Err(TestError::Fail(reason, input)) => {
                    // Re-run the minimal input once to capture its own panic report.
                    *LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()) = None;
                    let again = catch_unwind(AssertUnwindSafe(|| {
                        exercise(&input, &machines, &Stats::default())
                    }));
                    let report = LAST_PANIC
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .take()
                        .unwrap_or_else(|| format!("{reason} (did not panic again: {again:?})"));
                    let path = out_dir().join(format!("{name}.crash.pt"));
                    let _ = std::fs::write(&path, &input);
                    Err(format!(
                        "generator `{name}`: the front end panicked.\nminimal input ({} bytes, saved to {}):\n{}\n{report}",
                        input.len(),
                        path.display(),
                        shown(&input)
                    ))
                }
                Err(TestError::Abort(reason)) => Err(format!("generator `{name}` aborted: {reason}")),
            }
        })
        .expect("spawn fuzz worker");
    Worker {
        name,
        cases,
        stats,
        handle,
    }
}

#[test]
fn fuzz_front_end() {
    install_panic_hook();
    let started = Instant::now();
    let total = env_u64("PACER_FUZZ_CASES", 2000);
    let hang = Duration::from_secs(env_u64("PACER_FUZZ_HANG_SECS", 120));
    let only = std::env::var("PACER_FUZZ_ONLY").ok();
    let machines = Arc::new(Machines::new());

    // Sanity: the fixtures go all the way through, so the harness reaches the compiler.
    for (i, s) in seeds().iter().enumerate() {
        let st = Stats::default();
        exercise(s, &machines, &st);
        assert_eq!(
            st.compiled.load(Ordering::Relaxed),
            2,
            "seed program {i} should compile on both machines"
        );
    }
    // Fixed edge inputs.
    let edges = edge_inputs();
    let edge_stats = Stats::default();
    for e in &edges {
        let t0 = Instant::now();
        exercise(e, &machines, &edge_stats);
        let el = t0.elapsed();
        assert!(
            el < Duration::from_secs(20),
            "edge input took {el:?}: {}",
            shown(e)
        );
    }
    let edge_count = edges.len() as u64;

    let grammar = total * 40 / 100;
    let mutation = total * 35 / 100;
    let raw = total - grammar - mutation;
    let plan: Vec<(&'static str, u64, MakeStrategy)> = vec![
        ("grammar", grammar, grammar_input),
        ("mutation", mutation, mutation_input),
        ("raw", raw, raw_input),
    ];
    let mut workers = Vec::new();
    for (i, (name, n, make)) in plan.into_iter().enumerate() {
        if only.as_deref().is_some_and(|o| o != name) || n == 0 {
            continue;
        }
        let cases = u32::try_from(n).expect("PACER_FUZZ_CASES too large");
        workers.push(spawn_worker(
            name,
            i as u64,
            cases,
            make,
            Arc::clone(&machines),
        ));
    }

    // Watchdog: report an input that makes no progress, print progress now and then.
    let mut last: Vec<(u64, Instant)> = workers.iter().map(|_| (0, Instant::now())).collect();
    let mut last_report = Instant::now();
    loop {
        if workers
            .iter()
            .all(|w| w.stats.finished.load(Ordering::SeqCst))
        {
            break;
        }
        std::thread::sleep(Duration::from_millis(200));
        for (w, (seen, at)) in workers.iter().zip(last.iter_mut()) {
            let now = w.stats.executed.load(Ordering::Relaxed);
            if now != *seen || w.stats.finished.load(Ordering::SeqCst) {
                *seen = now;
                *at = Instant::now();
            } else if at.elapsed() > hang {
                let cur = w
                    .stats
                    .current
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .clone();
                let path = out_dir().join(format!("{}.hang.pt", w.name));
                let _ = std::fs::write(&path, &cur);
                panic!(
                    "generator `{}`: no progress for {:?} on input #{} ({} bytes, saved to {}):\n{}",
                    w.name,
                    hang,
                    now,
                    cur.len(),
                    path.display(),
                    shown(&cur)
                );
            }
        }
        if last_report.elapsed() > Duration::from_secs(30) {
            last_report = Instant::now();
            let progress: Vec<String> = workers
                .iter()
                .map(|w| {
                    format!(
                        "{} {}/{}",
                        w.name,
                        w.stats.executed.load(Ordering::Relaxed),
                        w.cases
                    )
                })
                .collect();
            eprintln!(
                "fuzz_parser: {:.0?} {}",
                started.elapsed(),
                progress.join(", ")
            );
        }
    }

    let mut failures = Vec::new();
    let mut generated = 0u64;
    for w in workers {
        let s = &w.stats;
        let executed = s.executed.load(Ordering::Relaxed);
        generated += executed;
        eprintln!(
            "fuzz_parser: {:<8} executed {:>8} (planned {:>8}); parse clean {}, check clean {} \
             (of 2 machines each), compiled {}, refused by compiler after clean check {}; \
             slowest {} µs ({} bytes, saved as {}.slowest.pt)",
            w.name,
            executed,
            w.cases,
            s.parse_clean.load(Ordering::Relaxed),
            s.check_clean.load(Ordering::Relaxed),
            s.compiled.load(Ordering::Relaxed),
            s.compile_refused.load(Ordering::Relaxed),
            s.slowest_micros.load(Ordering::Relaxed),
            s.slowest_input
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .len(),
            w.name,
        );
        let _ = std::fs::write(
            out_dir().join(format!("{}.slowest.pt", w.name)),
            &*s.slowest_input.lock().unwrap_or_else(|e| e.into_inner()),
        );
        match w.handle.join() {
            Ok(Ok(())) => {}
            Ok(Err(msg)) => failures.push(msg),
            Err(_) => failures.push(format!("worker `{}` died", w.name)),
        }
    }
    eprintln!(
        "fuzz_parser: total inputs executed: {} ({} generated + {} fixed edge inputs) in {:.1?}",
        generated + edge_count,
        generated,
        edge_count,
        started.elapsed()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
