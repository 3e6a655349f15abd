//! Fuzz target for the MotionBASIC front end: generated inputs go through
//! `parse_program_as(.., Dialect::MotionBasic, ..)`, then the variables they use are collected
//! and a registry is built with them (for two machines), then `check::basic::check`, then, when
//! neither the parser nor the checker reported an error, `compile`, which must succeed: anything
//! the checker accepts, the compiler compiles. Problems found on the way (the first three of each
//! stage) are rendered as the CLI renders them. A panic in any of these fails the test; a stack
//! overflow aborts the test binary; an input that makes no progress for a while is reported as a
//! hang.
//!
//! Three generators share the cases:
//!   * `grammar`  — programs built from the MotionBASIC statement forms (typed and wild): type
//!     suffixes, dotted names, controller variables with and without `@` and with `( )` or `{ }`
//!     arguments, axis sets, labels and subroutines, block and single-line IF, WHILE/WHILETRUE,
//!     FOR/NEXT/STEP, `:` separators, comments, GEAR and MOVE in all their forms; deep nesting,
//!     long operator chains, deep expressions;
//!   * `mutation` — the listings of the web-registration note (verbatim) and the full program,
//!     with tokens, bytes and lines inserted, deleted, replaced, duplicated, and block closers
//!     dropped;
//!   * `raw`      — random bytes and characters, token soup, very long lines, thousands of
//!     nested block openers, thousands of labels and calls.
//!
//! The harness (running the seeds and the edge inputs, the workers, the hang watchdog, the
//! report, the environment variables PACER_FUZZ_*) and the generator pieces that do not depend
//! on the dialect are `tests/common/fuzz.rs`, shared with `tests/fuzz_parser.rs`;
//! inputs are saved as `<generator>.<crash|hang|slowest|current>.mb`.
//!
//! The big run: `PACER_FUZZ_CASES=1000000 cargo test --release --test fuzz_motionbasic -- --nocapture`

use fuzz::{
    block, for_block, has_errors, if_block, indent, layout, long_line, many_lines, many_openers,
    mutated, mutation, nested_blocks, number, op_chain, pick, pick_any, random_bytes, random_chars,
    random_text, recursive, regex, render, sp, token_soup, Stats,
};
use pacer::check::{check, CheckEnv, Variables};
use pacer::compile::{compile, Layout};
use pacer::config::machine::MachineFile;
use pacer::config::parse_toml;
use pacer::syntax::{parse_program_as, Dialect};
use proptest::prelude::*;
use proptest::sample::{select, Index};
use std::sync::atomic::Ordering;

#[path = "common/fuzz.rs"]
mod fuzz;

// ---------------------------------------------------------------------------------------------
// The pipeline under test
// ---------------------------------------------------------------------------------------------

const PROGRAMS: &[u32] = &[0];

/// The machine file with the two DSP axes of the web-registration machine.
const AXES_TOML: &str =
    "[axis.1]\nunits_per_rev = 6000\n\n[axis.2]\nunits_per_rev = 3600\npacer = 1\n";

/// The two machines every input is checked against: `MachineFile::default()` (no DSP axes),
/// and one with the web and knife axes, so `Axis.1.Position` and `AFTER Axis.2.DspDone` resolve.
struct Machines {
    default: MachineFile,
    axes: MachineFile,
}

impl Machines {
    fn new() -> Machines {
        let axes: MachineFile = parse_toml(AXES_TOML, "machine file").expect("fuzz machine file");
        let m = Machines {
            default: MachineFile::default(),
            axes,
        };
        for file in m.all() {
            let (_, problems) = pacer::config::registry(file, PROGRAMS, &[]);
            assert!(
                !has_errors(&problems),
                "the fuzz machine files must build: {problems:?}"
            );
        }
        m
    }

    fn all(&self) -> [&MachineFile; 2] {
        [&self.default, &self.axes]
    }
}

/// Run one input through the front end. Panics propagate (that is the failure we look for),
/// and a program the checker accepted but the compiler refused is a panic too.
fn exercise(src: &str, m: &Machines, stats: &Stats) {
    let mut problems = Vec::new();
    let ast = parse_program_as(src, Dialect::MotionBasic, &mut problems);
    render("fuzz.mb", src, &problems);
    let parse_clean = !has_errors(&problems);
    if parse_clean {
        stats.parse_clean.fetch_add(1, Ordering::Relaxed);
    }
    // The CLI checks what parsed even when the parser reported errors: so does this.
    let mut vars = Variables::default();
    vars.collect(&ast);
    let list = vars.list();
    for machine in m.all() {
        let (registry, registry_problems) = pacer::config::registry(machine, PROGRAMS, &list);
        let env = CheckEnv {
            registry: &registry,
            loaded_programs: PROGRAMS,
            all_programs: true,
        };
        let (program, problems) = check(&ast, Dialect::MotionBasic, &env, &vars);
        render("fuzz.mb", src, &problems);
        if !parse_clean || has_errors(&registry_problems) || has_errors(&problems) {
            continue;
        }
        stats.check_clean.fetch_add(1, Ordering::Relaxed);
        let mut layout = Layout::new(&registry);
        match compile(&program, src, "fuzz.mb", 0, &mut layout) {
            Ok(chunk) => {
                stats.compiled.fetch_add(1, Ordering::Relaxed);
                std::hint::black_box(chunk);
            }
            Err(refused) => {
                render("fuzz.mb", src, &refused);
                let shown: Vec<String> = refused
                    .iter()
                    .map(|p| format!("{}: {} ({:?})", p.code, p.message, p.span))
                    .collect();
                panic!(
                    "the checker accepted this program but the compiler refused it:\n  {}",
                    shown.join("\n  ")
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Vocabulary
// ---------------------------------------------------------------------------------------------

/// Numeric variables: `&` and `%` long integers, `!`, `#` and no suffix reals; dotted names.
const NUM_VARS: &[&str] = &[
    "PLEN&",
    "PLEN.TMP&",
    "TREND.SET&",
    "OLD.POS.ASEN&",
    "DIFF&",
    "CORR&",
    "FCOEF&",
    "INST.GAIN&",
    "MAX.DIFF&",
    "T_DIST&",
    "I_DIST&",
    "L_DIST&",
    "NUM",
    "X",
    "Y!",
    "Z#",
    "I%",
    "J%",
    "K&",
    "T.1",
    "count",
    "Ratio.X",
    "a_b.c_d!",
    "REMAINDER&",
    "plen&",
    "x",
];
/// Variables that can count a FOR loop (numeric: not `~`, not `$`).
const FOR_VARS: &[&str] = &["I%", "J%", "K&", "X", "Y!", "Z#", "count", "PLEN&", "i%"];
/// Axis-set variables.
const AXIS_VARS: &[&str] = &["web~", "knife~", "axis~", "A~", "both.axes~", "WEB~"];
/// String variables.
const STR_VARS: &[&str] = &["S$", "MODE$", "NAME.X$", "s$"];
/// Readable numeric controller variables (written with `@`; also used without).
const CTL_READ: &[&str] = &[
    "POS",
    "VEL",
    "RATIO",
    "DSP.DONE",
    "ZREF",
    "ASEN",
    "BSEN",
    "POS.ZREF",
    "POS.ASEN",
    "POS.BSEN",
    "POS.MOD",
    "PLS.MOD",
    "PLS1.LOW",
    "PLS1.HIGH",
    "PLS2.LOW",
    "PLS2.HIGH",
    "PLS3.LOW",
    "PLS3.HIGH",
    "pos.asen",
    "dsp.done",
];
/// Writable numeric controller variables.
const CTL_WRITE: &[&str] = &[
    "ZREF",
    "ASEN",
    "BSEN",
    "POS.MOD",
    "PLS.MOD",
    "PLS1.LOW",
    "PLS1.HIGH",
    "PLS2.LOW",
    "PLS2.HIGH",
    "PLS3.LOW",
    "PLS3.HIGH",
    "asen",
];
/// Read-only controller variables (assigning one is an error).
const CTL_RO: &[&str] = &[
    "POS", "VEL", "RATIO", "DSP.DONE", "POS.ZREF", "POS.ASEN", "POS.BSEN",
];
/// SENS.MODE strings: five characters (R/F edges, G/N gating), and some that are not.
const SENS_MODES: &[&str] = &[
    "\"RRRNN\"",
    "\"RRRGN\"",
    "\"FFFGG\"",
    "\"RFRNG\"",
    "\"ZABGG\"",
    "\"\"",
    "\"R\"",
    "\"RRRNNN\"",
    "\"rrrnn\"",
    "\"é€\"",
];
/// Other object names MotionBASIC programs may read (numbers and bits).
const OBJ_READ: &[&str] = &[
    "DriveInput.1",
    "DriveInput.8",
    "Queue.0.QueueCount",
    "Queue.1.QueueEmpty",
    "Timer.0.Elapsed",
    "Bit.3",
    "DriveOutput.2",
    "Axis.1.Position",
    "Axis.2.DspDone",
    "Axis.2.PosAsen",
    "Axis.1.Asen",
];
/// Inputs an AFTER may name.
const AFTER_INPUTS: &[&str] = &[
    "DriveInput.1",
    "DriveInput.4",
    "DriveInput.8",
    "ModuleInput.1",
    "DriveOutput.1",
    "Bit.0",
    "Axis.2.DspDone",
    "Axis.1.Asen",
    "driveinput.2",
];
/// Actions written as a bare statement (MotionBASIC calls them like a subroutine).
const ACTIONS: &[&str] = &[
    "Queue.0.QueueClear",
    "Queue.1.QueueRemove",
    "Capture.0.CaptureClear",
    "Timer.0.Initiate",
    "Timer.1.Stop",
];
/// The subroutine labels every generated program defines (after its main part).
const SUBS: &[&str] = &["TREND", "INST", "REG.CONFIG", "MP.CONFIG", "Sub_1"];
/// Labels inside the main part (may be defined twice: an error the checker reports).
const LOCAL_LABELS: &[&str] = &["Here", "LOOP.TOP", "again", "L1", "L2"];
/// Axis sets and axis expressions.
const AXIS_LITERALS: &[&str] = &[
    "{1}",
    "{2}",
    "{1, 2}",
    "{2,1}",
    "{16}",
    "{web~, knife~}",
    "{ {1}, knife~ }",
    "{web~}",
    "{1, knife~}",
];
const NUMBERS: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "10",
    "1000",
    "3600",
    "10000",
    "15000",
    "0.5",
    ".5",
    "1.",
    "0.1",
    "1e3",
    "1E-3",
    "2.5e2",
    "1e308",
    "1e309",
    "1e-400",
    "2147483647",
    "2147483648",
    "4294967296",
    "99999999999999999999999",
    "00012",
    "0e0",
    "123456789.123456789",
];
const FINITE_NUMBERS: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "5",
    "10",
    "1000",
    "2000",
    "2400",
    "3600",
    "10000",
    "15000",
    "0.5",
    ".5",
    "1.",
    "0.1",
    "1e3",
    "1E-3",
    "2.5e2",
    "2147483647",
    "2147483648",
    "4294967296",
    "00012",
    "0e0",
];
const FUNC1: &[&str] = &[
    "ABS", "SGN", "SQR", "SQRT", "INT", "FIX", "SIN", "COS", "ATN", "EXP", "LOG", "abs", "Sgn",
];
const FUNC2: &[&str] = &["MIN", "MAX", "ATAN2"];
/// Arithmetic operators (Microsoft BASIC), including the integer division `\`.
const NUM_OPS: &[&str] = &["+", "-", "*", "/", "\\", "MOD", "^", "mod"];
const CMP_OPS: &[&str] = &["=", "<>", "<", "<=", ">", ">=", "><", "=<", "=>"];
const BOOL_OPS: &[&str] = &["AND", "OR", "XOR", "and", "Or"];
const ALL_OPS: &[&str] = &[
    "+", "-", "*", "/", "\\", "MOD", "^", "=", "<>", "<", "<=", ">", ">=", "AND", "OR", "XOR",
    "><", "=<", "=>",
];
const COMMENTS: &[&str] = &[
    "' a comment",
    "'",
    "REM a remark",
    "REM",
    "rem\tlower case",
    "‘curly comment’",
    "’ closing quote",
    "' MOVE web~ AT 1 ' IF THEN \"",
];
/// Names that are wrong in some way: unknown controllers, bad suffixes, keywords with
/// suffixes, object-like names that do not resolve.
const INVALID_NAMES: &[&str] = &[
    "FOO@",
    "X@",
    "POS.ASEN@",
    "SENS.MODE@",
    "ASEN@",
    "A.&",
    "A..B&",
    "A.",
    "IF&",
    "TO~",
    "END$",
    "REM.X",
    "Queue",
    "Queue.0",
    "Queue.9.QueueCount",
    "Axis.3.Position",
    "Axis.0.Position",
    "Axis.1",
    "Axis.1.Nope",
    "Index.X",
    "DriveInput.0",
    "web~~",
    "a.b.c.d.e.f.g.h.i.j&",
    "ABS",
    "MIN",
    "MAIN",
    "TREND",
    "TRUE.X",
    "Z",
];
/// Tokens and fragments for mutations and token soup.
const TOKENS: &[&str] = &[
    "IF",
    "THEN",
    "ELSE",
    "ENDIF",
    "END IF",
    "END",
    "WHILE",
    "WHILETRUE",
    "WEND",
    "FOR",
    "TO",
    "STEP",
    "NEXT",
    "GOSUB",
    "GOTO",
    "ON",
    "100",
    "RETURN",
    "GEAR",
    "MOVE",
    "AT",
    "IN",
    "AFTER",
    "TRUE",
    "FALSE",
    "NOT",
    "AND",
    "OR",
    "XOR",
    "MOD",
    "DIM",
    "DATA 1, A",
    "READ",
    "RESTORE",
    "SWAP",
    "LET",
    "RANDOMIZE",
    "DEFINT",
    "LEFT$(",
    "MID$(A$, 2) = ",
    "OPTION BASE 1",
    "RND",
    "REM",
    "REM ",
    "=",
    "<>",
    "><",
    "<",
    "<=",
    "=<",
    ">",
    ">=",
    "=>",
    "+",
    "-",
    "*",
    "/",
    "\\",
    "^",
    "(",
    ")",
    "[",
    "]",
    "{",
    "}",
    ",",
    ":",
    "'",
    "‘",
    "’",
    "\"",
    "\"RRRNN\"",
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
    "&",
    "~",
    "@",
    "$",
    "!",
    "#",
    "%",
    "web~",
    "knife~",
    "{1}",
    "{web~, knife~}",
    "PLEN&",
    "PLEN.TMP&",
    "NUM",
    "S$",
    "POS.ASEN@",
    "POS.ASEN@(web~)",
    "ASEN(",
    "DSP.DONE@{knife~}",
    "SENS.MODE@",
    "PLS1.LOW@{",
    "ABS(",
    "MIN(",
    "DriveInput.1",
    "Axis.1.Position",
    "MAIN:",
    "TREND",
    "INST",
    "x",
    "_",
    "é",
    "ß",
    "\u{200b}",
    "\u{feff}",
    "😀",
    "\u{0301}",
    "\0",
    ";",
    "|",
    "?",
];

/// A MotionBASIC-shaped name: letters, digits, `_` and dots, with an optional type suffix.
fn ident() -> BoxedStrategy<String> {
    regex("[A-Za-z][A-Za-z0-9_.]{0,10}[&~@%!#$]?")
}

/// Numbers that stay finite (typed programs: an overflowing literal is a checker error).
fn finite_number() -> BoxedStrategy<String> {
    prop_oneof![
        3 => pick(FINITE_NUMBERS),
        3 => (0u32..100_000).prop_map(|n| n.to_string()),
        1 => (0u32..1000, 0u32..1000).prop_map(|(a, b)| format!("{a}.{b}")),
        1 => regex("[0-9]{1,12}(\\.[0-9]{0,6})?([eE][+-]?[0-9]{1,2})?"),
    ]
    .boxed()
}

/// `(`…`)` or `{`…`}` around an argument (controller variables take either).
fn wrap_arg(arg: &str, brace: bool) -> String {
    if brace {
        format!("{{{arg}}}")
    } else {
        format!("({arg})")
    }
}

/// `@` or not: a controller name resolves either way.
fn at_sign(with: bool) -> &'static str {
    if with {
        "@"
    } else {
        ""
    }
}

// ---------------------------------------------------------------------------------------------
// (a) Grammar-aware generator
// ---------------------------------------------------------------------------------------------

/// Axis-set expressions: literals, axis variables, unions of them, in `( )` or `[ ]`.
fn axis_expr() -> BoxedStrategy<String> {
    let leaf = prop_oneof![
        3 => pick(AXIS_VARS),
        2 => pick(AXIS_LITERALS),
        1 => (1u32..=16).prop_map(|n| format!("{{{n}}}")),
    ];
    recursive(leaf.boxed(), 3, 8, 3, |inner| {
        prop_oneof![
            2 => prop::collection::vec(inner.clone(), 1..4)
                .prop_map(|v| format!("{{{}}}", v.join(", "))),
            1 => inner.clone().prop_map(|a| format!("({a})")),
            1 => inner.prop_map(|a| format!("[{a}]")),
        ]
    })
    .boxed()
}

/// The argument of a controller variable: an axis set, in parentheses or braces.
fn ctl_arg() -> BoxedStrategy<String> {
    prop_oneof![
        // `(web~)`, `{knife~}`, `({web~, knife~})`
        3 => (pick(AXIS_VARS), any::<bool>()).prop_map(|(a, b)| wrap_arg(&a, b)),
        2 => pick(AXIS_LITERALS).prop_map(|a| if a.starts_with('{') { a } else { format!("({a})") }),
        2 => pick(AXIS_LITERALS).prop_map(|a| format!("({a})")),
        1 => axis_expr().prop_map(|a| format!("({a})")),
        1 => (1u32..=3).prop_map(|n| format!("{{{n}}}")),
    ]
    .boxed()
}

/// A controller read: `POS.ASEN@(web~)`, `DSP.DONE@{knife~}`, `ASEN({web~, knife~})`.
fn ctl_read() -> BoxedStrategy<String> {
    (pick(CTL_READ), any::<bool>(), ctl_arg())
        .prop_map(|(n, at, a)| format!("{n}{}{a}", at_sign(at)))
        .boxed()
}

/// Numeric expressions over numeric variables, controller reads and objects: these should
/// type-check.
fn num_expr() -> BoxedStrategy<String> {
    let leaf = prop_oneof![
        4 => finite_number(),
        4 => pick(NUM_VARS),
        3 => ctl_read(),
        1 => pick(&["TRUE", "FALSE", "true"]),
        1 => pick(OBJ_READ),
    ];
    // Built once: proptest calls the closure below for every value it generates.
    let (space, num_ops, cmp_ops, bool_ops) = (sp(), pick(NUM_OPS), pick(CMP_OPS), pick(BOOL_OPS));
    let (number, func1, func2) = (finite_number(), pick(FUNC1), pick(FUNC2));
    recursive(leaf.boxed(), 6, 24, 3, move |inner| {
        prop_oneof![
            5 => (inner.clone(), space.clone(), num_ops.clone(), space.clone(), inner.clone()).prop_map(
                |(a, s1, op, s2, b)| {
                    // Word operators need spaces around them.
                    let (s1, s2) = if op.chars().all(char::is_alphabetic) { (" ", " ") } else { (s1, s2) };
                    format!("{a}{s1}{op}{s2}{b}")
                }
            ),
            2 => (inner.clone(), cmp_ops.clone(), inner.clone())
                .prop_map(|(a, op, b)| format!("{a} {op} {b}")),
            1 => (inner.clone(), bool_ops.clone(), inner.clone())
                .prop_map(|(a, op, b)| format!("{a} {op} {b}")),
            2 => inner.clone().prop_map(|a| format!("({a})")),
            1 => inner.clone().prop_map(|a| format!("[{a}]")),
            1 => inner.clone().prop_map(|a| format!("-{a}")),
            1 => inner.clone().prop_map(|a| format!("(NOT {a})")),
            // `a ^ -b` (the unary minus after `^`)
            1 => (inner.clone(), number.clone()).prop_map(|(a, b)| format!("{a}^-{b}")),
            1 => (func1.clone(), inner.clone()).prop_map(|(f, a)| format!("{f}({a})")),
            1 => (pick(NUM_ARRAYS), inner.clone()).prop_map(|(a, i)| format!("{a}({i})")),
            1 => (pick(&["LEN", "ASC", "VAL"]), str_expr()).prop_map(|(f, a)| format!("{f}({a})")),
            1 => (str_expr(), str_expr()).prop_map(|(a, b)| format!("INSTR({a}, {b})")),
            1 => pick(&["RND", "RND(1)", "RND(-2)", "TIMER"]),
            1 => (func2.clone(), inner.clone(), inner).prop_map(|(f, a, b)| format!("{f}({a}, {b})")),
        ]
    })
    .boxed()
}

/// String expressions: literals, string variables, SENS.MODE@ reads.
fn str_expr() -> BoxedStrategy<String> {
    let leaf = prop_oneof![
        3 => pick(SENS_MODES),
        2 => pick(STR_VARS),
        1 => (any::<bool>(), ctl_arg()).prop_map(|(at, a)| format!("SENS.MODE{}{a}", at_sign(at))),
        1 => regex("\"[ -!#-~]{0,12}\""),
        1 => (pick(STR_ARRAYS), index_expr()).prop_map(|(a, i)| format!("{a}({i})")),
    ];
    recursive(leaf.boxed(), 3, 8, 2, |inner| {
        prop_oneof![
            2 => (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("{a} + {b}")),
            1 => (pick(&["LEFT$", "RIGHT$"]), inner.clone(), index_expr())
                .prop_map(|(f, a, n)| format!("{f}({a}, {n})")),
            1 => (inner.clone(), index_expr(), prop::option::of(index_expr())).prop_map(|(a, n, m)| match m {
                Some(m) => format!("MID$({a}, {n}, {m})"),
                None => format!("MID$({a}, {n})"),
            }),
            1 => (pick(&["UCASE$", "LCASE$", "LTRIM$", "RTRIM$"]), inner.clone())
                .prop_map(|(f, a)| format!("{f}({a})")),
            1 => (pick(&["STR$", "CHR$", "SPACE$", "HEX$", "OCT$"]), index_expr())
                .prop_map(|(f, n)| format!("{f}({n})")),
            1 => (index_expr(), inner.clone()).prop_map(|(n, a)| format!("STRING$({n}, {a})")),
        ]
    })
    .boxed()
}

/// Arrays of numbers and of strings.
const NUM_ARRAYS: &[&str] = &["TBL", "PITCH&", "GRID", "q"];
const STR_ARRAYS: &[&str] = &["NAMES$", "CODE$"];

/// A subscript or a count: small numbers mostly, sometimes a variable or one out of range.
fn index_expr() -> BoxedStrategy<String> {
    prop_oneof![
        4 => (0u32..12).prop_map(|n| n.to_string()),
        1 => pick(NUM_VARS),
        1 => pick(&["-1", "300", "1.5", "I&", "40000"]),
    ]
    .boxed()
}

/// The Microsoft BASIC data and storage statements: DIM, element stores, DATA, READ,
/// RESTORE, SWAP, LET, the MID$ statement, OPTION BASE, RANDOMIZE, DEFINT and its kin.
fn storage_stmt() -> BoxedStrategy<String> {
    let dims = prop::collection::vec(index_expr(), 1..3).prop_map(|v| v.join(", "));
    prop_oneof![
        2 => (pick_any(&[NUM_ARRAYS, STR_ARRAYS]), dims.clone()).prop_map(|(a, d)| format!("DIM {a}({d})")),
        3 => (pick(NUM_ARRAYS), dims.clone(), num_expr()).prop_map(|(a, d, e)| format!("{a}({d}) = {e}")),
        2 => (pick(STR_ARRAYS), index_expr(), str_expr()).prop_map(|(a, i, e)| format!("{a}({i}) = {e}")),
        2 => prop::collection::vec(
            prop_oneof![
                2 => finite_number(),
                1 => regex("[A-Za-z ]{0,8}"),
                1 => regex("\"[ -!#-~]{0,8}\""),
            ],
            0..4,
        )
        .prop_map(|v| format!("DATA {}", v.join(", "))),
        2 => prop::collection::vec(
            prop_oneof![
                2 => pick(NUM_VARS),
                1 => pick(STR_VARS),
                1 => (pick(NUM_ARRAYS), index_expr()).prop_map(|(a, i)| format!("{a}({i})")),
            ],
            1..4,
        )
        .prop_map(|v| format!("READ {}", v.join(", "))),
        1 => prop::option::of(pick(SUBS)).prop_map(|l| format!("RESTORE {}", l.unwrap_or_default())),
        1 => (pick_any(&[NUM_VARS, STR_VARS]), pick_any(&[NUM_VARS, STR_VARS]))
            .prop_map(|(a, b)| format!("SWAP {a}, {b}")),
        1 => (pick(NUM_VARS), num_expr()).prop_map(|(t, e)| format!("LET {t} = {e}")),
        1 => pick(&["OPTION BASE 1", "OPTION BASE 0", "option base 1", "OPTION BASE 2", "OPTION BASE X", "OPTION  BASE"]),
        1 => (
            prop_oneof![
                3 => pick(STR_VARS),
                2 => (pick(STR_ARRAYS), index_expr()).prop_map(|(a, i)| format!("{a}({i})")),
                1 => pick(NUM_VARS),
            ],
            index_expr(),
            prop::option::of(index_expr()),
            str_expr(),
        )
            .prop_map(|(t, n, m, e)| match m {
                Some(m) => format!("MID$({t}, {n}, {m}) = {e}"),
                None => format!("MID$({t}, {n}) = {e}"),
            }),
        1 => (
            pick(&["\"##.##\"", "\"+#,###.#^^^^ & \\  \\ !\"", "\"**$##.##-\"", "\"_!x\"", "F$", "\"\""]),
            prop::collection::vec(prop_oneof![2 => num_expr(), 1 => str_expr()], 0..4),
            pick(&["", ";", ","]),
        )
            .prop_map(|(f, v, end)| format!("PRINT USING {f}; {}{end}", v.join("; "))),
        1 => prop::option::of(num_expr()).prop_map(|e| format!("RANDOMIZE {}", e.unwrap_or_default())),
        1 => (pick(&["DEFINT", "DEFLNG", "DEFSNG", "DEFDBL", "DEFSTR", "defint"]), pick(&["I-N", "A", "X, Y-Z", "Q", "1", "AB-C"]))
            .prop_map(|(d, r)| format!("{d} {r}")),
    ]
    .boxed()
}

/// Conditions: numbers (non-zero is true), comparisons, and `=`/`<>` between two values of
/// the same type (axis sets, strings).
fn cond_expr() -> BoxedStrategy<String> {
    prop_oneof![
        4 => num_expr(),
        2 => (ctl_read(), pick(&["= TRUE", "= FALSE", "<> 0", ""]))
            .prop_map(|(c, t)| format!("{c} {t}")),
        1 => (axis_expr(), pick(&["=", "<>"]), axis_expr()).prop_map(|(a, op, b)| format!("{a} {op} {b}")),
        1 => (str_expr(), pick(&["=", "<>"]), str_expr()).prop_map(|(a, op, b)| format!("{a} {op} {b}")),
    ]
    .boxed()
}

/// Any expression: random names, any operator, any function, stray keywords and brackets.
fn wild_expr() -> BoxedStrategy<String> {
    let leaf = prop_oneof![
        3 => number(NUMBERS),
        3 => pick_any(&[NUM_VARS, AXIS_VARS, STR_VARS, INVALID_NAMES, OBJ_READ, CTL_READ]),
        2 => ctl_read(),
        1 => pick(AXIS_LITERALS),
        1 => pick(SENS_MODES),
        1 => ident(),
        1 => pick(&["TRUE", "THEN", "TO", "STEP", "AT", "IN", "IF", "", "(", ")", "[", "]", "{", "}", ",", "-", "NOT", "\"", ":"]),
    ];
    // Built once: proptest calls the closure below for every value it generates.
    let (space, ops) = (sp(), pick(ALL_OPS));
    let unary = pick(&["-", "+", "NOT ", "- -", "NOT NOT ", "^-"]);
    let funcs = pick_any(&[FUNC1, FUNC2, CTL_READ, NUM_VARS, INVALID_NAMES]);
    recursive(leaf.boxed(), 8, 96, 4, move |inner| {
        prop_oneof![
            5 => (inner.clone(), space.clone(), ops.clone(), space.clone(), inner.clone()).prop_map(
                |(a, s1, op, s2, b)| {
                    let (s1, s2) = if op.chars().all(char::is_alphabetic) { (" ", " ") } else { (s1, s2) };
                    format!("{a}{s1}{op}{s2}{b}")
                }
            ),
            2 => (inner.clone(), 0u8..3).prop_map(|(a, k)| match k {
                0 => format!("({a})"),
                1 => format!("[{a}]"),
                _ => format!("{{{a}}}"),
            }),
            2 => (unary.clone(), inner.clone())
                .prop_map(|(u, a)| format!("{u}{a}")),
            1 => (
                funcs.clone(),
                any::<bool>(),
                prop::collection::vec(inner, 0..4),
                any::<bool>(),
            )
                .prop_map(|(f, at, args, brace)| {
                    format!("{f}{}{}", at_sign(at && !f.ends_with('@')), wrap_arg(&args.join(", "), brace))
                }),
        ]
    })
    .boxed()
}

/// The expression pools a statement generator draws from (typed or wild).
#[derive(Clone)]
struct Vocab {
    num: BoxedStrategy<String>,
    cond: BoxedStrategy<String>,
    axis: BoxedStrategy<String>,
    string: BoxedStrategy<String>,
    ctl_arg: BoxedStrategy<String>,
    for_var: BoxedStrategy<String>,
}

fn typed_vocab() -> Vocab {
    Vocab {
        num: num_expr(),
        cond: cond_expr(),
        axis: axis_expr(),
        string: str_expr(),
        ctl_arg: ctl_arg(),
        for_var: pick(FOR_VARS),
    }
}

fn wild_vocab() -> Vocab {
    let w = wild_expr();
    Vocab {
        num: prop_oneof![1 => w.clone(), 1 => num_expr()].boxed(),
        cond: prop_oneof![1 => w.clone(), 1 => cond_expr()].boxed(),
        axis: prop_oneof![1 => w.clone(), 2 => axis_expr()].boxed(),
        string: prop_oneof![1 => w.clone(), 2 => str_expr()].boxed(),
        ctl_arg: prop_oneof![
            2 => ctl_arg(),
            1 => (prop::collection::vec(w.clone(), 0..3), any::<bool>())
                .prop_map(|(a, b)| wrap_arg(&a.join(", "), b)),
        ]
        .boxed(),
        for_var: prop_oneof![
            3 => pick(FOR_VARS),
            1 => pick_any(&[AXIS_VARS, STR_VARS, INVALID_NAMES, CTL_WRITE]),
            1 => ident(),
        ]
        .boxed(),
    }
}

/// A simple statement (one that may share a line with others and sit in a single-line IF).
fn simple_stmt(v: &Vocab) -> BoxedStrategy<String> {
    let gear_at = (
        v.axis.clone(),
        v.num.clone(),
        v.num.clone(),
        prop::option::of(v.num.clone()),
        prop::option::weighted(0.3, pick(AFTER_INPUTS)),
    )
        .prop_map(|(a, o, i, p, after)| {
            let mut s = format!("GEAR {a} AT {o} TO {i}");
            if let Some(p) = p {
                s.push_str(&format!(" IN {p}"));
            }
            if let Some(f) = after {
                s.push_str(&format!(" AFTER {f}"));
            }
            s
        });
    let gear_for = (v.axis.clone(), v.num.clone(), v.num.clone())
        .prop_map(|(a, d, p)| format!("GEAR {a} FOR {d} IN {p}"));
    let move_at = (
        v.axis.clone(),
        v.num.clone(),
        prop::option::of(v.num.clone()),
    )
        .prop_map(|(a, s, t)| match t {
            Some(t) => format!("MOVE {a} AT {s} IN {t}"),
            None => format!("MOVE {a} AT {s}"),
        });
    let move_pos = (
        v.axis.clone(),
        any::<bool>(),
        v.num.clone(),
        prop::option::of(v.num.clone()),
        prop::option::of(v.num.clone()),
    )
        .prop_map(|(a, rel, p, s, t)| {
            let mut out = format!("MOVE {a} {} {p}", if rel { "FOR" } else { "TO" });
            if let Some(s) = s {
                out.push_str(&format!(" AT {s}"));
            }
            if let Some(t) = t {
                out.push_str(&format!(" IN {t}"));
            }
            out
        });
    prop_oneof![
        6 => (pick(NUM_VARS), sp(), sp(), v.num.clone()).prop_map(|(t, a, b, e)| format!("{t}{a}={b}{e}")),
        2 => (pick(AXIS_VARS), v.axis.clone()).prop_map(|(t, e)| format!("{t} = {e}")),
        1 => (pick(STR_VARS), v.string.clone()).prop_map(|(t, e)| format!("{t} = {e}")),
        // Controller writes: `ASEN@({web~, knife~}) = 0`, `PLS1.LOW@{knife~} = 2000`.
        3 => (pick(CTL_WRITE), any::<bool>(), v.ctl_arg.clone(), v.num.clone())
            .prop_map(|(n, at, a, e)| format!("{n}{}{a} = {e}", at_sign(at))),
        2 => (any::<bool>(), v.ctl_arg.clone(), v.string.clone())
            .prop_map(|(at, a, e)| format!("SENS.MODE{}{a} = {e}", at_sign(at))),
        3 => gear_at,
        2 => gear_for,
        2 => move_at,
        2 => move_pos,
        // Subroutine calls, bare or with GOSUB; GOTO; RETURN; END.
        3 => pick(SUBS),
        1 => pick(SUBS).prop_map(|s| format!("GOSUB {s}")),
        1 => pick_any(&[SUBS, &["MAIN"]]).prop_map(|s| format!("GOTO {s}")),
        // `ON n GOTO/GOSUB` over labels and line numbers.
        1 => (v.num.clone(), any::<bool>(), prop::collection::vec(pick(SUBS), 1..4))
            .prop_map(|(n, sub, t)| format!("ON {n} {} {}", if sub { "GOSUB" } else { "GOTO" }, t.join(", "))),
        1 => (1u32..500).prop_map(|n| format!("GOTO {n}")),
        1 => pick(ACTIONS),
        1 => pick(&["RETURN", "END", "return", "End"]),
        4 => storage_stmt(),
    ]
    .boxed()
}

/// A line of simple statements: one, several joined by `:`, or ending in a single-line IF.
fn line_stmt(v: &Vocab) -> BoxedStrategy<String> {
    let simple = simple_stmt(v);
    let inline = prop::collection::vec(simple.clone(), 1..4).prop_map(|v| v.join(" : "));
    prop_oneof![
        8 => simple.clone(),
        2 => (prop::collection::vec(simple.clone(), 2..5), any::<bool>())
            .prop_map(|(v, trailing)| format!("{}{}", join_line(&v), if trailing { " :" } else { "" })),
        // Single-line IF: `IF c THEN a : b ELSE c`, possibly after other statements.
        3 => (
            prop::collection::vec(simple, 0..2),
            v.cond.clone(),
            inline.clone(),
            prop::option::of(inline),
        )
            .prop_map(|(mut pre, c, t, e)| {
                pre.push(format!("IF {c} THEN {t}"));
                let mut s = join_line(&pre);
                if let Some(e) = e {
                    s.push_str(&format!(" ELSE {e}"));
                }
                s
            }),
        1 => (simple_stmt(v), pick(COMMENTS)).prop_map(|(s, c)| format!("{s} {c}")),
        1 => pick(COMMENTS),
        1 => Just(String::new()),
        1 => local_label().prop_map(|l| format!("{l}:")),
        // A GW-BASIC line number starting the line.
        1 => ((1u32..500), simple_stmt(v)).prop_map(|(n, s)| format!("{n} {s}")),
        1 => (local_label(), simple_stmt(v)).prop_map(|(l, s)| format!("{l}: {s}")),
    ]
    .boxed()
}

/// A label for the main part: numbered, so two of them rarely clash.
fn local_label() -> BoxedStrategy<String> {
    (pick(LOCAL_LABELS), 0u32..100_000)
        .prop_map(|(l, n)| format!("{l}{n}"))
        .boxed()
}

/// Statements joined by `:` on one line. A bare name followed by `:` at the start of a line is
/// a label (as in QuickBASIC), so a subroutine called first is called with GOSUB.
fn join_line(stmts: &[String]) -> String {
    let mut out = stmts.join(" : ");
    if let Some(first) = stmts.first() {
        let bare = !first.is_empty()
            && first
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '.' || c == '_');
        let keyword = ["RETURN", "END"].contains(&first.to_ascii_uppercase().as_str());
        if bare && !keyword && stmts.len() > 1 {
            out.insert_str(0, "GOSUB ");
        }
    }
    out
}

/// A statement tree, rendered as lines (children indented by two spaces).
fn stmt_tree(v: Vocab) -> BoxedStrategy<Vec<String>> {
    let leaf = line_stmt(&v).prop_map(|l| vec![l]);
    // Built once: proptest calls the closure below for every value it generates.
    let simple = simple_stmt(&v);
    recursive(leaf.boxed(), 5, 24, 4, move |inner| {
        let body = prop::collection::vec(inner, 0..5).prop_map(|b| b.concat());
        prop_oneof![
            3 => (v.cond.clone(), body.clone(), prop::option::of(body.clone()), 0u8..6).prop_map(
                |(c, then_b, else_b, form)| {
                    let end = if form == 0 { "END IF" } else { "ENDIF" };
                    if_block(["IF", "THEN", "ELSE"], &c, then_b, else_b, end)
                }
            ),
            2 => (v.cond.clone(), body.clone())
                .prop_map(|(c, b)| block(format!("WHILE {c}"), b, "WEND")),
            1 => body.clone().prop_map(|b| block("WHILETRUE".into(), b, "WEND")),
            2 => (
                v.for_var.clone(),
                v.num.clone(),
                v.num.clone(),
                prop::option::of(v.num.clone()),
                body,
                any::<bool>()
            )
                .prop_map(|(var, a, b, step, body, named_next)| {
                    for_block(["FOR", "TO", "STEP", "NEXT"], &var, &a, &b, step, body, named_next)
                }),
            // A whole loop on one line: `FOR I% = 1 TO 3 : X = X + I% : NEXT`.
            1 => (v.for_var.clone(), v.num.clone(), simple.clone()).prop_map(|(var, b, s)| {
                vec![format!("FOR {var} = 1 TO {b} : {s} : NEXT {var}")]
            }),
            1 => (v.cond.clone(), simple.clone()).prop_map(|(c, s)| {
                vec![format!("IF {c} THEN : {s} : ELSE : {s} : ENDIF")]
            }),
        ]
    })
    .boxed()
}

/// A line that ends a block, as the statement generator writes it.
fn block_end(t: &str) -> bool {
    t == "ENDIF" || t == "END IF" || t == "WEND" || t.starts_with("NEXT")
}

/// Render a program: `MAIN:` and a main part, `END`, then one subroutine per name of `SUBS`
/// (label, body, `RETURN`); random indentation, case and line endings, light damage.
fn program(v: Vocab) -> BoxedStrategy<String> {
    (
        (
            proptest::bool::weighted(0.85),
            prop::collection::vec(stmt_tree(v.clone()), 0..8),
            any::<bool>(),
            prop::collection::vec(prop::collection::vec(stmt_tree(v), 0..2), SUBS.len()),
        ),
        0u8..10,                                                // case style
        0u8..6,                                                 // indentation unit
        0u8..16,                                                // line ending
        prop::option::weighted(0.15, (any::<Index>(), 0u8..4)), // light damage
    )
        .prop_map(|((main_label, main, end, subs), case, ind, eol, damage)| {
            let mut lines: Vec<String> = Vec::new();
            if main_label {
                lines.push("MAIN:".into());
            }
            lines.extend(main.concat());
            if end {
                lines.push("END".into());
            }
            for (name, body) in SUBS.iter().zip(subs) {
                lines.push(String::new());
                lines.push(format!("{name}:"));
                lines.extend(indent(body.concat()));
                lines.push("RETURN".into());
            }
            if let Some((at, what)) = damage {
                fuzz::damage(&mut lines, at, what, block_end, "ELSE");
            }
            layout(&lines, case, ind, eol)
        })
        .boxed()
}

/// Statements anything may be: random names as targets and calls, wrong arguments, fragments.
fn wild_line() -> BoxedStrategy<String> {
    let e = wild_expr();
    let names = || {
        prop_oneof![
            3 => pick_any(&[NUM_VARS, AXIS_VARS, STR_VARS, INVALID_NAMES, CTL_READ, CTL_WRITE, CTL_RO, SUBS, OBJ_READ]),
            1 => ident(),
        ]
    };
    prop_oneof![
        6 => (names(), sp(), sp(), e.clone()).prop_map(|(t, a, b, e)| format!("{t}{a}={b}{e}")),
        3 => (names(), any::<bool>(), prop::collection::vec(e.clone(), 0..3), any::<bool>(), e.clone())
            .prop_map(|(n, at, args, brace, v)| {
                format!("{n}{}{} = {v}", at_sign(at), wrap_arg(&args.join(", "), brace))
            }),
        2 => names(),
        2 => (pick(&["GEAR", "MOVE"]), prop::collection::vec((pick(&["AT", "TO", "IN", "FOR", "AFTER", ""]), e.clone()), 0..6))
            .prop_map(|(k, parts)| {
                let mut s = k;
                for (w, x) in parts {
                    s.push_str(&format!(" {w} {x}"));
                }
                s
            }),
        1 => (pick(&["GOSUB ", "GOTO ", "gosub ", "GOTO"]), names()).prop_map(|(g, l)| format!("{g}{l}")),
        1 => ident().prop_map(|l| format!("{l}:")),
        1 => (e.clone(), prop::collection::vec(e.clone(), 0..3))
            .prop_map(|(c, t)| format!("IF {c} THEN {}", t.join(" : "))),
        1 => pick(&[
            "END", "ELSE", "ENDIF", "END IF", "WEND", "NEXT", "NEXT X", "IF", "IF THEN", "WHILE",
            "WHILETRUE", "FOR", "FOR X", "FOR X = 1", "FOR X = 1 TO", "FOR X = 1 TO 2 STEP",
            "GEAR", "MOVE", "GOSUB", "GOTO", "RETURN", ":", "::", "END END", "REM", "THEN",
            "ELSE X = 1", "IF 1 THEN ELSE", "IF 1 THEN X = 1 ELSE", "MAIN: MAIN:", "RETURN 1",
        ]),
        1 => (e.clone(), e).prop_map(|(a, b)| format!("{a} {b}")),
    ]
    .boxed()
}

fn typed_program() -> BoxedStrategy<String> {
    program(typed_vocab())
}

fn wild_program() -> BoxedStrategy<String> {
    let v = wild_vocab();
    (
        program(v),
        prop::collection::vec((any::<Index>(), wild_line()), 0..6),
    )
        .prop_map(|(p, extra)| {
            let mut lines: Vec<&str> = p.split('\n').collect();
            for (at, l) in &extra {
                lines.insert(at.index(lines.len() + 1), l);
            }
            lines.join("\n")
        })
        .boxed()
}

/// Deep block nesting, long operator chains, deeply nested expressions: around the limits
/// (512 tokens a line, 64 nested blocks, 256 levels with ELSEIF chains).
fn deep_input() -> BoxedStrategy<String> {
    const KINDS: &[u8] = &[0, 1, 2, 3];
    let opener = select(KINDS);
    prop_oneof![
        // Nested blocks, closed properly (or not), each level with a statement.
        2 => (prop::collection::vec(opener, 1..130), any::<bool>(), simple_stmt(&typed_vocab())).prop_map(
            |(kinds, close, leaf)| {
                let openers = [
                    "IF DSP.DONE@(knife~) THEN\n",
                    "WHILE ASEN({web~, knife~}) = 0\n",
                    "FOR I% = 1 TO 10 STEP 2\n",
                    "WHILETRUE\n",
                ];
                let closers = ["ENDIF\n", "WEND\n", "NEXT\n", "WEND\n"];
                nested_blocks(&kinds, close, &leaf, &openers, &closers)
            }
        ),
        // ELSEIF chains around their limit (each ELSEIF nests one deeper, 256 in all), some
        // with a block inside every branch.
        1 => (1usize..300, any::<bool>()).prop_map(|(n, nested)| {
            let mut s = String::from("IF X = 0 THEN\n");
            for k in 1..n {
                s += &format!("ELSEIF X = {k} THEN\n");
                if nested {
                    s += "FOR I% = 1 TO 2\nX = X + 1\nNEXT\n";
                }
            }
            s + "ELSE\nX = 1\nEND IF\n"
        }),
        // Long chains of binary operators (many of them longer than 512 tokens).
        2 => (prop::collection::vec((pick(ALL_OPS), num_atom()), 1..400), num_atom()).prop_map(
            |(rest, first)| op_chain(format!("PLEN& = {first}"), rest)
        ),
        // Many statements on one line, and a single-line IF with many statements.
        1 => (1usize..300, any::<bool>()).prop_map(|(n, inline_if)| {
            let body = vec!["X = X + 1"; n].join(" : ");
            if inline_if {
                format!("IF X < 10 THEN {body} ELSE {body}\n")
            } else {
                format!("{body}\n")
            }
        }),
        // Deep nesting inside one expression.
        2 => (
            1usize..300,
            pick(&["(", "[", "-", "- ", "-(", "-[", "ABS(", "MIN(1,", "(1+", "2^(", "2^-", "NOT ", "[(", "SGN["]),
            any::<bool>(),
        )
            .prop_map(|(n, open, closed)| {
                let close = match open.as_str() {
                    "(" | "ABS(" | "MIN(1," | "(1+" | "2^(" | "-(" => ")",
                    "[" | "-[" => "]",
                    "[(" => ")]",
                    "SGN[" => "]",
                    _ => "",
                };
                let tail = if closed { close.repeat(n) } else { String::new() };
                format!("X = {}1{}\n", open.repeat(n), tail)
            }),
        // Nested axis sets and controller arguments.
        1 => (1usize..300, pick(&["{", "({", "{web~, ", "POS@({", "{ASEN("]), any::<bool>()).prop_map(
            |(n, open, closed)| {
                let close = match open.as_str() {
                    "({" => "})",
                    "POS@({" => "})",
                    "{ASEN(" => ")}",
                    _ => "}",
                };
                let tail = if closed { close.repeat(n) } else { String::new() };
                format!("web~ = {}1{}\n", open.repeat(n), tail)
            }
        ),
        // Right-nested sums and a left-nested power chain.
        1 => (1usize..200).prop_map(|n| format!("X = {}1{}\n", "(1 + ".repeat(n), ")".repeat(n))),
        1 => (1usize..300).prop_map(|n| format!("X = 2{}\n", " ^ 2".repeat(n))),
        1 => (1usize..300).prop_map(|n| format!("X& = 7{}\n", " \\ 2".repeat(n))),
    ]
    .boxed()
}

fn num_atom() -> BoxedStrategy<String> {
    prop_oneof![2 => number(NUMBERS), 2 => pick(NUM_VARS), 1 => ctl_read()].boxed()
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
// (b) Mutations of the web-registration listings
// ---------------------------------------------------------------------------------------------

/// The listings of `shared/spec/web-registration.md`, verbatim.
const LISTING_MAIN: &str = "MAIN:

' Set axis values into appropriate variables
web~ = {1}
knife~ = {2}

' Set up all values for motors specified including user
' unit scaling values and MotionData links between the
' web axis and knife axis.
MP.CONFIG

' Set the registration default values
REG.CONFIG

' Implement initial ratio between web and knife
GEAR knife~ AT 3600 TO TREND.SET&

' Start web axis; run to 1000 RPM in 1.000 seconds
MOVE web~ AT 1000 IN 1000

' Clear sensor latch
ASEN@({web~, knife~}) = 0

' Loop to perform registration action
WHILETRUE
' Check sensor
IF ASEN({web~, knife~}) = TRUE THEN
' Do trending registration subroutine
TREND
' Do instantaneous registration subroutine
INST
' Clear sensor latch
ASEN@({web~, knife~}) = 0
ENDIF
WEND
END
";

const LISTING_TREND: &str = "TREND:
IF OLD.POS.ASEN& <> 0 THEN
  PLEN.TMP& = POS.ASEN@(web~) - OLD.POS.ASEN&
  IF PLEN.TMP& > TREND.SET&\\2 AND PLEN.TMP& < 3*TREND.SET&\\2 THEN
    PLEN& = ((10000 - FCOEF&)*PLEN& + FCOEF&*PLEN.TMP&)\\10000
  ENDIF
ENDIF
OLD.POS.ASEN& = POS.ASEN@(web~)
IF DSP.DONE@(knife~) THEN
  GEAR knife~ AT 3600 TO PLEN& IN T_DIST&
ENDIF
RETURN
";

const LISTING_INST: &str = "INST:
  DIFF& = INST.SET& - POS.ASEN(knife~)
  IF DIFF& > POS.MOD@(knife~)\\2 THEN
    DIFF& = DIFF& - POS.MOD(knife~)
  ELSE
    IF DIFF& <= -(POS.MOD@(knife~)\\2) THEN
      DIFF& = DIFF& + POS.MOD(knife~)
    ENDIF
  ENDIF
  IF ABS(DIFF&) > MAX.DIFF& THEN
    DIFF& = SGN(DIFF&)* MAX.DIFF&
  ENDIF
  CORR& = (DIFF& * INST.GAIN&) \\ 10000
  GEAR knife~ FOR CORR& IN I_DIST&
RETURN
";

const LISTING_REG_CONFIG: &str = "REG.CONFIG:
INST.SET& = 0           ' 0.0 degrees
MAX.DIFF& = 300        ' 30.0 degrees for allowed error
L_DIST& = 500           ' 0.5 ins of web travel for tool adj.
INST.GAIN& = 2500       ' Correction gain set to 25.00%
TREND.SET& = 15000     ' Set point of 15.000 ins for pitch
T_DIST& = 500           ' 0.5 ins of web for pitch adj.
PLEN& = TREND.SET&     ' Initial pitch length value set.
NUM = 5                 ' Samples to spread pitch length adj.

' Sets up the mark sensor interface on DSP Axis Motion I/O
SENS.MODE@({web~, knife~}) = \"RRRNN\"

' Filter coefficient floating point calculation scaled to 10000
' and converted to a long integer.
FCOEF& = 10000 * [1 - 0.1^(1/NUM)]

' Force two register reads before calculating a new pitch.
OLD.POS.ASEN& = 0
RETURN
";

/// The note's last page: blinding the mark sensor with PLS1.
const LISTING_BLINDING: &str = "PLS.MOD@{knife~} = 3600
PLS1.LOW@{knife~} = 2000 ' 200.0 degrees
PLS1.HIGH@{knife~} = 2400 ' 240.0 degrees
SENS.MODE@{axis~} = \"RRRGN\"
";

/// The subroutine the note leaves to the controller's set-up menus.
const MP_CONFIG: &str = "MP.CONFIG:
POS.MOD@(knife~) = 3600
RETURN
";

/// The forms the listings lack: FOR/NEXT/STEP, WHILE, GOSUB/GOTO, single-line IF with `:`
/// and ELSE, REM, the other suffixes, MOVE TO/FOR, GEAR … AFTER, strings.
const EXTRA_SEED: &str = "REM exercises the forms the listings lack
MAIN: web~ = {1} : knife~ = {2}
both~ = {web~, knife~}
S$ = \"RRRGN\" : SENS.MODE@(both~) = S$
FOR I% = 1 TO 10 STEP 2
  X = X + I% ^ 2 MOD 7 - -3 / [2 + I%]
  Y! = -X ^ -2 : Z# = X \\ 3
NEXT I%
WHILE X > 0 AND NOT DSP.DONE@{knife~}
  X = X - 1
WEND
IF X >= 1 THEN GOSUB SUB1 : X = 0 ELSE GOTO DONE
MOVE web~ TO 1000 AT 50 IN 200
MOVE web~ FOR -500
MOVE {1} AT 0
GEAR knife~ AT 1 TO 2 IN 500 AFTER DriveInput.1
GEAR knife~ FOR 10 IN 0
PLS2.LOW@{knife~} = 100 : PLS2.HIGH@{knife~} = 200
IF POS@(knife~) > MIN(1, 2) OR VEL(web~) <> 0 XOR RATIO@{knife~} = 1 THEN X = 1
DONE:
END
SUB1:
  K& = 2147483647 \\ 2 : I% = 0
  ZREF@(web~) = 0 : BSEN{knife~} = 0
RETURN
";

fn full_listings() -> String {
    [
        LISTING_MAIN,
        LISTING_TREND,
        LISTING_INST,
        LISTING_REG_CONFIG,
        MP_CONFIG,
    ]
    .join("\n")
}

fn seeds() -> Vec<String> {
    vec![
        LISTING_MAIN.to_string(),
        LISTING_TREND.to_string(),
        LISTING_INST.to_string(),
        LISTING_REG_CONFIG.to_string(),
        LISTING_BLINDING.to_string(),
        full_listings(),
        include_str!("../programs/web-registration/registration.mb").to_string(),
        EXTRA_SEED.to_string(),
    ]
}

/// The seeds that must go all the way through on both machines.
fn complete_seeds() -> Vec<String> {
    vec![
        full_listings(),
        include_str!("../programs/web-registration/registration.mb").to_string(),
        EXTRA_SEED.to_string(),
        LISTING_TREND.to_string(),
        LISTING_INST.to_string(),
        LISTING_REG_CONFIG.to_string(),
        LISTING_BLINDING.to_string(),
    ]
}

/// A line a mutation may drop (any case): the end of a block, an `ELSE`, a `RETURN`.
fn closer(line: &str) -> bool {
    let t = line.to_ascii_uppercase();
    t == "ENDIF"
        || t == "END IF"
        || t == "WEND"
        || t.starts_with("NEXT")
        || t == "ELSE"
        || t == "RETURN"
}

fn mutation_input() -> BoxedStrategy<String> {
    let line = prop_oneof![2 => line_stmt(&typed_vocab()), 1 => wild_line(), 1 => pick(&[
        "IF ASEN({web~, knife~}) = TRUE THEN", "ELSE", "ENDIF", "WHILETRUE", "WHILE X < 3",
        "WEND", "FOR I% = 1 TO 2", "NEXT", "L1:", "GOTO L1", "TREND", "RETURN", "END",
    ])];
    mutated(seeds(), 3, mutation(TOKENS, line.boxed(), true), closer)
}

// ---------------------------------------------------------------------------------------------
// (c) Raw strings and bytes
// ---------------------------------------------------------------------------------------------

/// The ASCII characters that matter to MotionBASIC (`random_chars` adds the unusual ones).
const SPECIAL_CHARS: &[char] = &[
    '\'', '‘', '’', '\r', '\n', '\t', '(', ')', '[', ']', '{', '}', ' ', '.', ':', '=', '<', '>',
    '-', '+', '*', '/', '\\', '^', ',', '"', '_', '&', '~', '@', '$', '!', '#', '%', '0', '9', 'e',
    'E', 'R', 'm', 'x',
];

fn raw_input() -> BoxedStrategy<String> {
    prop_oneof![
        4 => random_chars(SPECIAL_CHARS),
        2 => random_text(),
        2 => random_bytes(),
        3 => token_soup(TOKENS, &[" ", "", "\n", "\t", "\r\n", "  ", " : "]),
        2 => long_line(
            &["", "X = ", "web~ = ", "S$ = ", "IF ", "GEAR ", "MOVE web~ AT ", "GOSUB ", "x", "ASEN@(", "REM "],
            &[
                "(", ")", "[", "]", "{", "}", "a+", "x ", ".", "1", "A", "a.", "-", "NOT ", "IF ",
                "'", "‘", "’", "é", "\u{200b}", "\r", "\t", "( ", "1,", ",", ":", "<>", "THEN ",
                "A.1", "\\", "^-", "&", "~", "@", "\"", "{1},", "X:", " : X = 1", "A&",
            ],
        ),
        2 => many_openers(
            &[
                "IF x THEN\n",
                "IF DSP.DONE@(knife~) THEN\n",
                "WHILE 1\n",
                "WHILETRUE\n",
                "FOR I% = 1 TO 2\n",
                "IF 1 THEN\nELSE\n",
                "IF x THEN\r",
                "IF x THEN : ",
            ],
            &["", "ENDIF\n", "END IF\n", "WEND\n", "NEXT\n", "ELSE\n", "x = 1\n", ": ENDIF "],
        ),
        1 => many_lines(
            &["ENDIF\n", "WEND\n", "NEXT\n", "ELSE\n", "L:\n", "GOTO L\n", "L\n", "\n", "END\n", "'\n", "REM\n", "RETURN\n", "PLEN& = 1\n", ":\n"],
            &["", "WHILETRUE\n", "IF 1 THEN\n", "L:\n"],
        ),
        // Many distinct labels, calls and jumps.
        1 => (1usize..2000, any::<bool>(), any::<bool>()).prop_map(|(n, dup, call)| {
            let mut s = String::new();
            for i in 0..n {
                let l = if dup { i % 7 } else { i };
                let target = (i * 7919) % n;
                if call {
                    s.push_str(&format!("L{l}:\nL{target}\nRETURN\n"));
                } else {
                    s.push_str(&format!("L{l}: GOTO L{target}\n"));
                }
            }
            s
        }),
        // Many distinct variables (the registry grows with them).
        1 => (1usize..3000, pick(&["&", "~", "$", "", "!", "#", "%"])).prop_map(|(n, suffix)| {
            let mut s = String::new();
            for i in 0..n {
                s.push_str(&format!("V.{i}{suffix} = V.{}{suffix}\n", i / 2));
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
        ":".into(),
        "::::".into(),
        ":\n:\n".into(),
        "REM".into(),
        "rem".into(),
        "REM\n".into(),
        "REM\tx\nREMARK& = 1\nX.REM = REMARK& : REM tail".into(),
        "\u{feff}END\n".into(),
        "A:".into(),
        "A::".into(),
        ":A".into(),
        "A: B: C".into(),
        "MAIN:\nMAIN:\n".into(),
        "main:\nMAIN:\nGOTO Main\n".into(),
        "END:".into(),
        "END IF".into(),
        "IF: X = 1".into(),
        "1:".into(),
        "GOTO\nGOSUB\nRETURN 1\n".into(),
        "web~ = {}".into(),
        "web~ = {1,}".into(),
        "web~ = {0}\nknife~ = {17}\naxis~ = {-1}\nA~ = {1.5}\nB~ = {1e300}\n".into(),
        "web~ = {1} : GEAR web~ AT 1 TO 2 : GEAR {0} FOR 1 IN 0 : MOVE {65536} AT 1\n".into(),
        "X = {1}".into(),
        "{1}".into(),
        "\"".into(),
        "\"abc".into(),
        "S$ = \"a\nS$ = \"\"\"\"".into(),
        "S$ = \"RRRNN\" + \"X\"\n".into(),
        "ASEN@() = 0".into(),
        "ASEN@ = 0".into(),
        "ASEN@{} = 0".into(),
        "ASEN@(web~, knife~) = 0\nX = ASEN@(web~, knife~)\n".into(),
        "X = ASEN\nASEN = 1\nASEN(web~) = 1\nX = ASEN + ASEN(web~)\n".into(),
        "POS@(web~) = 1\nDSP.DONE@{web~} = 0\n".into(),
        "SENS.MODE@(web~) = 1\nX = SENS.MODE@(web~) + 1\nSENS.MODE@(web~) = SENS.MODE@{knife~}\n"
            .into(),
        "X = FOO@(web~)\nFOO@(web~) = 1\nX = ABS{1}\nX = ABS(web~)\nX = MIN(1)\n".into(),
        "GEAR".into(),
        "GEAR web~".into(),
        "GEAR web~ AT".into(),
        "GEAR web~ AT 1 TO 2 AFTER".into(),
        "GEAR web~ AT 1 TO 2 AFTER DriveInput.1 + 1\n".into(),
        "GEAR web~ AT 1 TO 2 AFTER Queue.0.QueueClear\n".into(),
        "GEAR web~ AT 1 TO 2 AFTER Axis.2.DspDone\nGEAR web~ AT 1 TO 2 AFTER Axis.9.DspDone\n"
            .into(),
        "GEAR 1 AT 1 TO 2\nGEAR S$ FOR 1 IN 2\nMOVE X AT 1\n".into(),
        "MOVE web~ TO 1 AT 2 IN 3\nMOVE web~ FOR 1 IN 3\nMOVE web~ TO\n".into(),
        "IF 1 THEN".into(),
        "IF 1 THEN ELSE".into(),
        "IF 1 THEN X = 1 ELSE".into(),
        "IF 1 THEN IF 1 THEN X = 1".into(),
        "IF 1 THEN X = 1 ELSE Y = 2 ELSE Z = 3".into(),
        "IF 1 THEN : X = 1 : ELSE : X = 2 : ENDIF".into(),
        "IF 1 THEN GOTO L1 ELSE L1\nL1:\n".into(),
        "IF web~ THEN END\nIF S$ THEN END\nWHILE web~\nWEND\n".into(),
        "X = 2^-2^-2\nX = 2 ^ - - 2\nX = -2 ^ 2\nX = 2 ^ -(3)\n".into(),
        "X& = 2147483647 + 1\nX& = 1e10\nX& = -2147483648 \\ -1\n".into(),
        "X = 1 \\ 0\nX = 1 MOD 0\nX = 0 / 0\nX = 0 ^ -1\n".into(),
        "X = 1e999999\nX = 1e-999999\nX& = 99999999999999999999999\n".into(),
        "FOR X = 1 TO 10 STEP 0 : NEXT".into(),
        "FOR web~ = 1 TO 2\nNEXT\nFOR S$ = 1 TO 2\nNEXT\nFOR ASEN@ = 1 TO 2\nNEXT\n".into(),
        "FOR Axis.1.Position = 1 TO 2\nNEXT\nFOR DriveInput.1 = 1 TO 2\nNEXT\n".into(),
        "FOR I% = 1 TO 2\nNEXT J%\nNEXT I%\n".into(),
        "NEXT X NEXT".into(),
        "WHILETRUE\nWEND\nWHILE\nWEND\n".into(),
        "Axis.1.Asen = 0\nAxis.1.SensMode = \"RRRNN\"\nX = Axis.3.Position\n".into(),
        "Queue.0.QueueRemove\nGOSUB Queue.0.QueueRemove\nGOTO Queue.0.QueueRemove\n".into(),
        "Queue = 1\nAxis = {1}\nX = Queue + Axis\n".into(),
        "IF& = 1\nTO~ = {1}\nEND$ = \"x\"\n".into(),
        "A..B& = 1\nA.& = 2\nX = A..B& + A.&\n".into(),
        "web~~ = {1}\nX = 1.2.3\nX = 1e\nX = .e1\n".into(),
        "X = 1 ‘curly comment’\nY = 2 ’x\n".into(),
        "X = 1\rY = 2\r".into(),
        "TREND\nTREND:\nTREND\nRETURN\n".into(),
        "{".repeat(10_000),
        "[".repeat(10_000),
        format!("X = {}1", "(".repeat(10_000)),
        format!("X = {}1{}", "(".repeat(254), ")".repeat(254)),
        format!("X = {}1{}", "(".repeat(255), ")".repeat(255)),
        format!("X = {}1{}", "[".repeat(255), "]".repeat(255)),
        format!("web~ = {}1{}", "{".repeat(254), "}".repeat(254)),
        format!("web~ = {}1{}", "{".repeat(255), "}".repeat(255)),
        format!("X = POS@({}1{})", "{POS@(".repeat(120), ")}".repeat(120)),
        format!("X = {}1", "-".repeat(509)),
        format!("X = {}1", "-".repeat(510)),
        format!("X = {}1", "NOT ".repeat(509)),
        format!("X = {}1", "NOT ".repeat(100_000)),
        format!("X = 2{}", " ^ 2".repeat(254)),
        format!("X = 2{}", " ^ -2".repeat(169)),
        format!("X& = 7{}", " \\ 2".repeat(254)),
        format!("X = {}1{}", "ABS(".repeat(170), ")".repeat(170)),
        format!("X = {}", "1 + ".repeat(254) + "1"),
        format!("X = {}", "1 + ".repeat(255) + "1"),
        format!("web~ = {{{}}}", vec!["1"; 255].join(", ")),
        format!("web~ = {{{}}}", vec!["knife~"; 255].join(", ")),
        format!("GEAR {{{}}} AT 1 TO 2", vec!["{1}"; 80].join(", ")),
        format!("X = 1{}", " : X = 1".repeat(127)),
        format!("IF 1 THEN {}", vec!["X = 1"; 170].join(" : ")),
        "IF x THEN\n".repeat(5000),
        "IF DSP.DONE@(knife~) THEN\n".repeat(64) + "X = 1\n" + &"ENDIF\n".repeat(64),
        "IF DSP.DONE@(knife~) THEN\n".repeat(65) + "X = 1\n" + &"ENDIF\n".repeat(65),
        "IF 1 THEN\n".repeat(64) + "IF 1 THEN X = 1 ELSE Y = 2\n" + &"ENDIF\n".repeat(64),
        "WHILETRUE\n".repeat(64) + &"WEND\n".repeat(64),
        "WHILETRUE\n".repeat(65) + &"WEND\n".repeat(65),
        "FOR I% = 1 TO 2\n".repeat(64) + &"NEXT\n".repeat(64),
        "FOR I% = 1 TO 2 : ".repeat(64) + &"NEXT : ".repeat(64),
        "ENDIF\n".repeat(10_000),
        "WEND\n".repeat(10_000),
        "NEXT\n".repeat(10_000),
        "RETURN\n".repeat(10_000),
        "WHILETRUE\n".to_string() + &"ENDIF\n".repeat(5000),
        "IF 1 THEN\n".to_string() + &"ELSE\n".repeat(5000),
        "GOTO L\n".repeat(5000),
        "L\n".repeat(5000),
        "A&".repeat(100_000),
        format!("X{} = 1", ".a".repeat(20_000)),
        ":".repeat(20_000),
        "\"".repeat(20_001),
    ];
    // Many labels, each called from the one before.
    let mut labels = String::new();
    for i in 0..2000 {
        labels.push_str(&format!("L{i}:\nL{}\nRETURN\n", (i + 1) % 2000));
    }
    v.push(labels);
    v.extend(seeds());
    v
}

#[test]
fn fuzz_motionbasic_front_end() {
    fuzz::run(fuzz::Target {
        name: "fuzz_motionbasic",
        ext: "mb",
        salt: 0x4D42_4153_4943_465A, // "MBASICFZ"
        machines: Machines::new,
        exercise,
        complete_seeds,
        edge_inputs,
        grammar: grammar_input,
        mutation: mutation_input,
        raw: raw_input,
        report_refused: false,
    });
}
