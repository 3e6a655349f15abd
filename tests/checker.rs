//! The checker and name resolution: one test per diagnostic, asserting the code, the message,
//! the exact span and the help; every problem of a file reported; plain rendering.

use pacer::check::{check_program, CheckEnv};
use pacer::config::machine::MachineFile;
use pacer::diag::{Diagnostics, Problem, SourceFile};
use pacer::registry::Registry;
use pacer::span::Span;
use pacer::syntax::parse_program;

const MACHINE: &str = r#"
[variables.Count]
decimals = 0

[variables.Offset]
decimals = 2

[variables.I]
decimals = 0

[bits.names]
Ready = 3
"#;

const LOADED: &[u32] = &[0, 1, 2];

fn registry() -> Registry {
    let machine: MachineFile = toml::from_str(MACHINE).expect("machine TOML");
    let (registry, problems) = pacer::config::registry(&machine, LOADED, &[]);
    assert!(problems.is_empty(), "{problems:?}");
    registry
}

/// Parse (which must succeed) and check; every problem the checker reports.
fn check(src: &str) -> Vec<Problem> {
    let mut syntax = Vec::new();
    let ast = parse_program(src, &mut syntax);
    assert!(syntax.is_empty(), "syntax problems in {src:?}: {syntax:#?}");
    let reg = registry();
    let env = CheckEnv {
        registry: &reg,
        loaded_programs: LOADED,
        all_programs: true,
    };
    check_program(&ast, &env)
}

/// The single problem of `src`.
fn one(src: &str) -> Problem {
    let problems = check(src);
    assert_eq!(
        problems.len(),
        1,
        "expected one problem in {src:?}: {problems:#?}"
    );
    problems.into_iter().next().unwrap()
}

fn at(src: &str, needle: &str) -> Span {
    let start = src
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not in {src:?}"));
    Span::new(start, start + needle.len())
}

/// Assert everything a user sees of a problem.
#[track_caller]
fn assert_problem(
    src: &str,
    p: &Problem,
    code: &str,
    message: &str,
    span: Span,
    help: Option<&str>,
) {
    assert_eq!(p.code, code, "code of {p:#?}");
    assert_eq!(p.message, message, "message of {p:#?}");
    assert_eq!(
        &src[p.span.start..p.span.end],
        &src[span.start..span.end],
        "span text of {p:#?}"
    );
    assert_eq!(p.span, span, "span of {p:#?}");
    assert_eq!(p.help.as_deref(), help, "help of {p:#?}");
    assert_eq!(p.level, pacer::diag::Level::Error);
}

// ---------------------------------------------------------------------------------------------
// a clean program

#[test]
fn a_correct_program_has_no_problems() {
    let src = "Var.Count = 0\nVar.Offset = Var.Offset + 0.01\nBit.Ready = ON\nBit.1 = Bit.Ready AND NOT DriveInput.4\nWait For Queue.0.QueueEmpty\nWait For DriveInput.4 = ON OR Var.Count > 3\nQueue.0.DataIn = Capture.0.CapturedMasterPosition\nQueue.0.QueueRemove\nQueue.0.QueueRemove = ON\nCapture.0.CaptureReset\nIndex.0.Initiate Using Capture.1 On Profile.1\nIndex.0.Initiate Using Last\nFeedRateOverride = 50\nVar.Count = ABS(Var.Count - 10) + MAX(1, 2) MOD 3\nFor Var.I = 1 To 10 Step 2\nNext\nCall Program.1\nProgram.2.Initiate\nTop:\nWait For Time 1\nGoto Top\n";
    let problems = check(src);
    assert!(problems.is_empty(), "{problems:#?}");
}

// ---------------------------------------------------------------------------------------------
// names

#[test]
fn unknown_object_with_nearest_name() {
    let src = "Wait For Queu.0.QueueEmpty";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_object",
        "unknown object `Queu`",
        at(src, "Queu"),
        Some("did you mean `Queue`?"),
    );
    assert_eq!(p.label, "no such object");
}

#[test]
fn unknown_object_without_a_near_name() {
    let src = "Var.Count = Zyxwvut.1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_object",
        "unknown object `Zyxwvut`",
        at(src, "Zyxwvut"),
        None,
    );
}

#[test]
fn unknown_bare_global_suggests_the_motion_member() {
    let src = "FeedRateOveride = 50";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_object",
        "unknown object `FeedRateOveride`",
        at(src, "FeedRateOveride"),
        Some("did you mean `FeedRateOverride`?"),
    );
}

#[test]
fn unknown_instance() {
    let src = "Wait For Queue.9.QueueEmpty";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "Queue.9 does not exist",
        at(src, "9"),
        Some("this machine has Queue.0 to Queue.7"),
    );

    // I/O points count from 1.
    let src = "Wait For DriveInput.0 = ON";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "DriveInput.0 does not exist",
        at(src, "0"),
        Some("this machine has DriveInput.1 to DriveInput.8"),
    );
}

#[test]
fn object_without_an_instance() {
    let src = "Wait For Queue = ON";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "`Queue` needs an instance",
        at(src, "Queue"),
        Some("this machine has Queue.0 to Queue.7"),
    );
}

#[test]
fn unknown_member_with_nearest_name() {
    let src = "Wait For Queue.0.QueueEmpy";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_member",
        "Queue has no member `QueueEmpy`",
        at(src, "QueueEmpy"),
        Some("did you mean `QueueEmpty`?"),
    );
}

#[test]
fn object_without_a_member() {
    let src = "Wait For Queue.0";
    let p = one(src);
    assert_eq!(p.code, "pacer::check::unknown_member");
    assert_eq!(p.message, "`Queue.0` needs a member");
    assert_eq!(p.span, at(src, "Queue.0"));
    let help = p.help.as_deref().unwrap_or_default();
    assert!(
        help.starts_with("members: DataIn, DataOut, QueueOffset"),
        "{help}"
    );
}

#[test]
fn too_many_parts_in_a_name() {
    let src = "Wait For DriveInput.4.Value.Extra";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_member",
        "too many parts in this name",
        at(src, "Extra"),
        None,
    );
}

#[test]
fn undeclared_variable() {
    let src = "Var.Speed = 1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "unknown variable `Speed`",
        at(src, "Speed"),
        Some("declare it in machine.toml under [variables]"),
    );
}

#[test]
fn misspelt_variable_suggests_the_declared_one() {
    let src = "Var.Cuont = 1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "unknown variable `Cuont`",
        at(src, "Cuont"),
        Some("did you mean `Var.Count`?"),
    );
}

#[test]
fn unknown_bit_name() {
    let src = "Bit.Redy = ON";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "unknown bit `Redy`",
        at(src, "Redy"),
        Some("did you mean `Bit.Ready`?"),
    );

    let src = "Bit.40 = ON";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "Bit.40 does not exist",
        at(src, "40"),
        Some("user bits are Bit.0 to Bit.31"),
    );
}

// ---------------------------------------------------------------------------------------------
// assignments

#[test]
fn number_assigned_to_a_bit() {
    let src = "Bit.1 = 1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::number_to_bit",
        "a number assigned to the bit Bit.1",
        Span::new(src.len() - 1, src.len()),
        Some("bits take ON/TRUE/YES/SET/ENABLE or OFF/FALSE/NO/CLEAR/DISABLE"),
    );

    let src = "DriveIO.1.Out = 0";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::number_to_bit",
        "a number assigned to the bit DriveIO.1.Out",
        at(src, "0"),
        Some("bits take ON/TRUE/YES/SET/ENABLE or OFF/FALSE/NO/CLEAR/DISABLE"),
    );
}

#[test]
fn on_assigned_to_a_number() {
    let src = "Var.Count = ON";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::bit_to_number",
        "an ON/OFF value assigned to Var.Count, which is an integer",
        at(src, "ON"),
        Some("assign a number"),
    );

    let src = "Var.Offset = DriveInput.1 AND DriveInput.2";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::bit_to_number",
        "an ON/OFF value assigned to Var.Offset, which is a number with 2 decimal places",
        at(src, "DriveInput.1 AND DriveInput.2"),
        Some("assign a number"),
    );
}

#[test]
fn writing_a_read_only_member() {
    let src = "Queue.0.QueueEmpty = ON";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::read_only",
        "Queue.0.QueueEmpty is read-only",
        at(src, "Queue.0.QueueEmpty"),
        Some("it is a status the controller sets"),
    );

    let src = "DriveInput.4 = OFF";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::read_only",
        "DriveInput.4 is read-only",
        at(src, "DriveInput.4"),
        Some("it is a status the controller sets"),
    );
}

#[test]
fn action_assigned_a_number() {
    let src = "Queue.0.QueueRemove = 1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "Queue.0.QueueRemove is an action: assign ON to trigger it",
        at(src, "1"),
        Some("write `Queue.0.QueueRemove=ON` or just `Queue.0.QueueRemove`"),
    );
}

#[test]
fn reading_an_action() {
    let src = "Bit.1 = Queue.0.QueueRemove";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::not_readable",
        "Queue.0.QueueRemove is an action and has no value to read",
        at(src, "Queue.0.QueueRemove"),
        Some("run it as a statement: `Queue.0.QueueRemove`"),
    );
    assert_eq!(p.label, "an action");

    let src = "Wait For Index.0.Initiate";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::not_readable",
        "Index.0.Initiate is an action and has no value to read",
        at(src, "Index.0.Initiate"),
        Some("run it as a statement: `Index.0.Initiate`"),
    );
}

#[test]
fn reading_a_write_only_input() {
    let src = "Var.Offset = Queue.0.DataIn";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::not_readable",
        "Queue.0.DataIn can only be written",
        at(src, "Queue.0.DataIn"),
        None,
    );
}

#[test]
fn non_action_as_a_bare_statement() {
    let src = "Var.Count";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::not_action",
        "Var.Count is not an action",
        at(src, "Var.Count"),
        Some("give it a value: `Var.Count=…`"),
    );

    let src = "Bit.Ready";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::not_action",
        "Bit.Ready is not an action",
        at(src, "Bit.Ready"),
        Some("to set it, write `Bit.Ready=ON`"),
    );

    let src = "Queue.0.QueueEmpty";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::not_action",
        "Queue.0.QueueEmpty is not an action",
        at(src, "Queue.0.QueueEmpty"),
        Some("it is a status; read it in a condition, e.g. `Wait For …`"),
    );

    let src = "Queue.0.DataIn";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::not_action",
        "Queue.0.DataIn is not an action",
        at(src, "Queue.0.DataIn"),
        Some("give it a value: `Queue.0.DataIn=…`"),
    );
}

// ---------------------------------------------------------------------------------------------
// types

#[test]
fn comparing_a_bit_with_a_number() {
    let src = "Wait For DriveInput.4 = 1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "`=` between an ON/OFF value and a number",
        at(src, "1"),
        Some("a bit is ON or OFF, not 1 or 0: write `= ON` or `= OFF`"),
    );

    let src = "If Var.Count <> DriveInput.4 Then\nEndif";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "`<>` between an ON/OFF value and a number",
        at(src, "Var.Count"),
        Some("both sides must be numbers, or both ON/OFF values"),
    );
}

#[test]
fn wrong_types_in_arithmetic() {
    let src = "Var.Count = Var.Count + DriveInput.4";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "`+` needs numbers, found an ON/OFF value",
        at(src, "DriveInput.4"),
        Some("compare bits with `= ON` / `= OFF`, combine them with AND/OR/NOT"),
    );

    let src = "Var.Count = ON * 2";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "`*` needs numbers, found an ON/OFF value",
        at(src, "ON"),
        Some("compare bits with `= ON` / `= OFF`, combine them with AND/OR/NOT"),
    );

    let src = "Wait For Bit.1 > Bit.2";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "`>` needs numbers, found an ON/OFF value",
        at(src, "Bit.1"),
        Some("compare bits with `= ON` / `= OFF`, combine them with AND/OR/NOT"),
    );
}

#[test]
fn negating_a_bit() {
    let src = "Var.Count = -DriveInput.4";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "expected a number, found an ON/OFF value",
        at(src, "DriveInput.4"),
        Some("`-` needs a number"),
    );
}

#[test]
fn mixing_a_bit_and_a_number_in_logic() {
    let src = "Wait For DriveInput.4 AND Var.Count";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "`AND` between an ON/OFF value and a number",
        at(src, "Var.Count"),
        Some("both sides must be numbers, or both ON/OFF values"),
    );
}

#[test]
fn conditions_must_be_on_off() {
    let src = "If Var.Count Then\nEndif";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "expected an ON/OFF value, found a number",
        at(src, "Var.Count"),
        Some("If needs a condition"),
    );

    let src = "Do While Var.Count + 1\nLoop";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "expected an ON/OFF value, found a number",
        at(src, "Var.Count + 1"),
        Some("Do While needs a condition"),
    );

    let src = "Wait For Var.Count";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "expected an ON/OFF value, found a number",
        at(src, "Var.Count"),
        Some("Wait For needs a condition, e.g. `Wait For DriveInput.1=ON`"),
    );
}

#[test]
fn times_and_distances_must_be_numbers() {
    let src = "Wait For Time ON";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "expected a number, found an ON/OFF value",
        at(src, "ON"),
        Some("a time in seconds"),
    );

    let src = "Dwell For Time Bit.1";
    let p = one(src);
    assert_eq!(p.help.as_deref(), Some("a time in seconds"));
    assert_eq!(p.span, at(src, "Bit.1"));

    let src = "Dwell For Master Dist DriveInput.1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "expected a number, found an ON/OFF value",
        at(src, "DriveInput.1"),
        Some("a master distance"),
    );
}

// ---------------------------------------------------------------------------------------------
// functions

#[test]
fn unknown_function() {
    let src = "Var.Count = ABSS(1)";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_function",
        "unknown function `ABSS`",
        at(src, "ABSS"),
        Some("did you mean `ABS`?"),
    );
    assert_eq!(p.label, "not a function");
}

#[test]
fn wrong_argument_count() {
    let src = "Var.Count = MAX(1)";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::arguments",
        "MAX takes 2 arguments, not 1",
        at(src, "MAX(1)"),
        None,
    );

    let src = "Var.Count = abs(1, 2)";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::arguments",
        "ABS takes 1 argument, not 2",
        at(src, "abs(1, 2)"),
        None,
    );
}

#[test]
fn function_arguments_are_numbers() {
    let src = "Var.Count = ABS(DriveInput.1)";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "expected a number, found an ON/OFF value",
        at(src, "DriveInput.1"),
        Some("function arguments are numbers"),
    );
}

// ---------------------------------------------------------------------------------------------
// initiates

#[test]
fn using_on_a_non_motion() {
    let src = "Queue.0.QueueRemove Using Last";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::using",
        "`Using` only applies to motion initiates, not Queue.0.QueueRemove",
        at(src, "Using Last"),
        None,
    );

    let src = "Timer.0.Initiate Using Capture.1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::using",
        "`Using` only applies to motion initiates, not Timer.0.Initiate",
        at(src, "Capture.1"),
        None,
    );
}

#[test]
fn on_profile_on_a_non_motion() {
    let src = "Capture.0.CaptureClear On Profile.1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::profile",
        "`On Profile` only applies to motion initiates and stops, not Capture.0.CaptureClear",
        at(src, "Profile.1"),
        None,
    );
}

#[test]
fn using_an_unknown_capture_or_not_a_capture() {
    let src = "Index.0.Initiate Using Capture.9";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "Capture.9 does not exist",
        at(src, "9"),
        Some("this machine has Capture.0 to Capture.3"),
    );

    let src = "Index.0.Initiate Using Queue.1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_object",
        "expected `Capture.N` here",
        at(src, "Queue"),
        Some("this machine has Capture.0 to Capture.3"),
    );
}

#[test]
fn on_an_unknown_profile() {
    let src = "Index.0.Initiate On Profile.2";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "Profile.2 does not exist",
        at(src, "2"),
        Some("this machine has Profile.0 to Profile.1"),
    );
}

// ---------------------------------------------------------------------------------------------
// labels, programs, loops

#[test]
fn unknown_label() {
    let src = "Goto Nowhere";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::label",
        "no label `Nowhere` in this program",
        at(src, "Nowhere"),
        Some("define it on a line of its own: `Nowhere:`"),
    );
}

#[test]
fn unknown_label_suggests_the_label_as_written() {
    let src = "WaitLoop:\nGoto WaitLop";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::label",
        "no label `WaitLop` in this program",
        at(src, "WaitLop"),
        Some("did you mean `WaitLoop`?"),
    );
}

#[test]
fn labels_are_case_insensitive() {
    assert!(check("Top:\nWait For Time 1\ngoto TOP\nJump top\n").is_empty());
}

#[test]
fn duplicate_label() {
    let src = "Top:\nVar.Count = 1\nIf Bit.1 Then\ntop:\nEndif\nWait For Time 1\nGoto Top\n";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::label",
        "label `top` is defined twice",
        at(src, "top"),
        Some("labels must be unique in a program; rename one of them"),
    );
}

#[test]
fn call_of_an_unloaded_program() {
    let src = "Call Program.5";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::program",
        "Program.5 is not loaded on this machine",
        at(src, "Program.5"),
        Some("loaded: Program.0, Program.1, Program.2"),
    );

    let src = "Program.7.Initiate";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::program",
        "Program.7 is not loaded on this machine",
        at(src, "Program.7.Initiate"),
        Some("loaded: Program.0, Program.1, Program.2"),
    );

    let src = "Program.7.Initiate = ON";
    let p = one(src);
    assert_eq!(p.code, "pacer::check::program");
    assert_eq!(p.span, at(src, "Program.7.Initiate"));
}

#[test]
fn call_of_something_that_is_not_a_program() {
    let src = "Call Queue.1";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_object",
        "expected `Program.N` here",
        at(src, "Queue"),
        Some("this machine has Program.0 to Program.15"),
    );

    let src = "Call Program.99";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::unknown_instance",
        "Program.99 does not exist",
        at(src, "99"),
        Some("this machine has Program.0 to Program.15"),
    );
}

#[test]
fn for_over_a_non_variable() {
    let src = "For Bit.1 = 1 To 3\nNext";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::for_variable",
        "Bit.1 cannot count a For loop",
        at(src, "Bit.1"),
        Some("count with a user variable, e.g. `For Var.I = 1 To 10`"),
    );

    let src = "For Queue.0.QueueCount = 1 To 3\nNext";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::for_variable",
        "Queue.0.QueueCount cannot count a For loop",
        at(src, "Queue.0.QueueCount"),
        Some("count with a user variable, e.g. `For Var.I = 1 To 10`"),
    );

    // A writable member with a side effect is not a loop counter either.
    let src = "For Queue.0.QueueOffset = 1 To 3\nNext";
    let p = one(src);
    assert_eq!(p.code, "pacer::check::for_variable");
    assert_eq!(p.span, at(src, "Queue.0.QueueOffset"));
}

#[test]
fn for_bounds_must_be_numbers() {
    let src = "For Var.I = ON To 3\nNext";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::type",
        "expected a number, found an ON/OFF value",
        at(src, "ON"),
        Some("loop bounds are numbers"),
    );
}

#[test]
fn step_zero() {
    let src = "For Var.I = 1 To 3 Step 0\nNext";
    let p = one(src);
    assert_problem(
        src,
        &p,
        "pacer::check::step",
        "a Step of 0 never ends the loop",
        at(src, "0"),
        None,
    );
    assert_eq!(p.label, "zero step");

    let src = "For Var.I = 1 To 3 Step 0.0\nNext";
    assert_eq!(one(src).code, "pacer::check::step");
}

// ---------------------------------------------------------------------------------------------
// every problem of a file

#[test]
fn every_problem_of_a_file_is_reported() {
    let src = "\
Wait For Queu.0.QueueEmpty
Bit.1 = 1
Var.Count = ON
Queue.0.QueueEmpty = ON
Var.Speed = 2
If DriveInput.4 = 1 Then
    Var.Count = ABSS(Var.Count)
    Var.Count
Endif
Do While TRUE
    For Bit.2 = 1 To 3 Step 0
    Next
    Call Program.5
    Goto Nowhere
Loop
";
    let problems = check(src);
    let codes: Vec<&str> = problems.iter().map(|p| p.code).collect();
    let expected = [
        "pacer::check::unknown_object",
        "pacer::check::number_to_bit",
        "pacer::check::bit_to_number",
        "pacer::check::read_only",
        "pacer::check::unknown_instance",
        "pacer::check::type",
        "pacer::check::unknown_function",
        "pacer::check::not_action",
        "pacer::check::for_variable",
        "pacer::check::step",
        "pacer::check::program",
        "pacer::check::label",
    ];
    let mut sorted: Vec<&Problem> = problems.iter().collect();
    sorted.sort_by_key(|p| p.span.start);
    let sorted_codes: Vec<&str> = sorted.iter().map(|p| p.code).collect();
    assert_eq!(sorted_codes, expected, "{problems:#?}");
    assert_eq!(codes.len(), 12);
    // Each one is on its own line.
    let lines: Vec<usize> = sorted
        .iter()
        .map(|p| pacer::span::line_col(src, p.span.start).0)
        .collect();
    assert_eq!(lines, [1, 2, 3, 4, 5, 6, 7, 8, 11, 11, 13, 14]);
}

#[test]
fn problems_inside_an_unclosed_block_are_still_reported() {
    let src = "Do While TRUE\nWait For Time 1\nIf Bit.1 Then\nBit.2 = 1\nVar.Speed = 2\n";
    let mut problems = Vec::new();
    let ast = parse_program(src, &mut problems);
    let reg = registry();
    let env = CheckEnv {
        registry: &reg,
        loaded_programs: LOADED,
        all_programs: true,
    };
    problems.extend(check_program(&ast, &env));
    problems.sort_by_key(|p| p.span.start);
    let found: Vec<(&str, &str)> = problems
        .iter()
        .map(|p| (p.code, &src[p.span.start..p.span.end]))
        .collect();
    assert_eq!(
        found,
        [
            ("pacer::syntax::unclosed", "Do While TRUE"),
            ("pacer::syntax::unclosed", "If Bit.1 Then"),
            ("pacer::check::number_to_bit", "1"),
            ("pacer::check::unknown_instance", "Speed"),
        ],
        "{problems:#?}"
    );
}

#[test]
fn target_and_value_problems_of_one_assignment_are_both_reported() {
    let src = "Var.Speed = Var.Sped + 1";
    let problems = check(src);
    assert_eq!(problems.len(), 2, "{problems:#?}");
    assert_eq!(problems[0].span, at(src, "Speed"));
    assert_eq!(problems[1].span, at(src, "Sped"));
}

#[test]
fn load_reports_the_problems_of_every_file() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-checker-load-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("machine.toml"),
        "[[program]]\nnumber = 0\nfile = \"a.pt\"\nautostart = true\n\n[[program]]\nnumber = 1\nfile = \"b.pt\"\n\n[variables.Count]\ndecimals = 0\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("a.pt"),
        "Bit.1 = 1\nVar.Count = = 2\nCall Program.4\n",
    )
    .unwrap();
    std::fs::write(dir.join("b.pt"), "Else\nWait For Queu.0.QueueEmpty\n").unwrap();
    let req = pacer::load::LoadRequest {
        paths: vec![dir.clone()],
        machine: None,
        scenario: None,
    };
    let diags = match pacer::load::load(&req) {
        Ok(_) => panic!("expected errors"),
        Err(d) => d,
    };
    let _ = std::fs::remove_dir_all(&dir);
    let found: Vec<(String, &str)> = diags
        .items
        .iter()
        .map(|d| {
            let file = std::path::Path::new(&d.file.name)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            (file, d.problem.code)
        })
        .collect();
    assert_eq!(
        found,
        [
            ("a.pt".to_string(), "pacer::check::number_to_bit"),
            ("a.pt".to_string(), "pacer::syntax"),
            ("a.pt".to_string(), "pacer::check::program"),
            ("b.pt".to_string(), "pacer::syntax::unbalanced"),
            ("b.pt".to_string(), "pacer::check::unknown_object"),
        ],
        "{}",
        diags.render_plain()
    );
    assert_eq!(diags.error_count(), 5);
}

// ---------------------------------------------------------------------------------------------
// rendering

#[test]
fn plain_rendering_shows_place_code_message_label_and_help() {
    let src = "Var.Count = 1\n  Wait For Queu.0.QueueEmpty\nBit.1 = 1\n";
    let problems = check(src);
    assert_eq!(problems.len(), 2, "{problems:#?}");
    let file = SourceFile::new("label.pt", src);
    let mut diags = Diagnostics::new();
    diags.extend_file(&file, problems);
    assert_eq!(diags.error_count(), 2);
    assert!(diags.has_errors());
    let out = diags.render_plain();
    assert!(out.contains("label.pt:2:12: error"), "{out}");
    assert!(out.contains("label.pt:3:9: error"), "{out}");
    assert!(out.contains("pacer::check::unknown_object"), "{out}");
    assert!(out.contains("unknown object `Queu`"), "{out}");
    assert!(out.contains("no such object"), "{out}");
    assert!(out.contains("help: did you mean `Queue`?"), "{out}");
    assert!(out.contains("a number assigned to the bit Bit.1"), "{out}");
    assert!(
        out.contains("help: bits take ON/TRUE/YES/SET/ENABLE or OFF/FALSE/NO/CLEAR/DISABLE"),
        "{out}"
    );
    // The source line is quoted.
    assert!(out.contains("Wait For Queu.0.QueueEmpty"), "{out}");
    // In position order: line 2 before line 3.
    assert!(out.find("label.pt:2:12").unwrap() < out.find("label.pt:3:9").unwrap());
    // No colour codes in the plain rendering.
    assert!(!out.contains('\u{1b}'), "{out:?}");
}

#[test]
fn rendering_counts_columns_in_characters() {
    // A curly-quote comment before the problem on the same line is not possible, but one on
    // the line above must not shift the column of the next line.
    let src = "‘ comment ‘’\nVar.Cuont = 1\n";
    let problems = check(src);
    let file = SourceFile::new("p.pt", src);
    let mut diags = Diagnostics::new();
    diags.extend_file(&file, problems);
    let out = diags.render_plain();
    assert!(out.contains("p.pt:2:5: error"), "{out}");
    assert!(out.contains("help: did you mean `Var.Count`?"), "{out}");
}

#[test]
fn syntax_problems_render_too() {
    let src = "Var.Count = 1\nElse\n";
    let mut problems = Vec::new();
    let _ = parse_program(src, &mut problems);
    let file = SourceFile::new("s.pt", src);
    let mut diags = Diagnostics::new();
    diags.extend_file(&file, problems);
    let out = diags.render_plain();
    assert!(out.contains("s.pt:2:1: error"), "{out}");
    assert!(out.contains("Else without a matching If"), "{out}");
    assert!(
        out.contains("help: remove this Else or add the If it belongs to"),
        "{out}"
    );
}

#[test]
fn a_number_too_large_to_represent_is_reported() {
    let (reg, problems) = pacer::config::registry(
        &toml::from_str("[variables.X]\ndecimals = 0\n").expect("machine"),
        &[0],
        &[],
    );
    assert!(problems.is_empty(), "{problems:?}");
    let src = "Var.X = 1e999\n";
    let mut problems = Vec::new();
    let ast = pacer::syntax::parse_program(src, &mut problems);
    assert!(problems.is_empty());
    let problems = pacer::check::check_program(
        &ast,
        &pacer::check::CheckEnv {
            registry: &reg,
            loaded_programs: &[0],
            all_programs: true,
        },
    );
    assert_eq!(problems.len(), 1);
    assert_eq!(problems[0].code, "pacer::check::number");
    assert_eq!(&src[problems[0].span.start..problems[0].span.end], "1e999");
}
