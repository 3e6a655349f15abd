//! MotionBASIC end to end: small `.mb` programs run on a simulated two-axis ORION machine, and
//! the values they leave in the machine (variables, controller variables, axis positions) or
//! the diagnostics they draw are checked against the language contract of
//! `spec/web-registration.md` ("Language points these listings rely on"): Microsoft BASIC
//! precedence and truth values, long integers, labels and subroutines, blocks, controller
//! variables, motion, and the check-time diagnostics.

mod common;

use common::{load_error, project, run_loaded_with_writes as run_loaded, Run};
use pacer::diag::{Diagnostics, Level, Located};
use pacer::load::{load, LoadRequest, Loaded};
use pacer::vm::RunError;

/// Two DSP axes as in `programs/web-registration`: the web (axis 1, 0.001 in units, 6 in per
/// revolution) and the rotary knife (axis 2, 0.1° units, the web is its pacer); the program is
/// `x.mb`, program 0.
const MACHINE: &str = r#"
[machine]
name = "mb-language"

[[program]]
number = 0
file = "x.mb"

[axis.1]
name = "web"
units_per_rev = 6000

[axis.2]
name = "knife"
units_per_rev = 3600
pacer = 1
"#;

/// Load `program` (as `x.mb`) on [`MACHINE`], with an optional scenario; panics on errors.
fn load_mb(name: &str, program: &str, scenario: Option<&str>) -> Loaded {
    let mut files = vec![("x.mb", program), ("machine.toml", MACHINE)];
    if let Some(s) = scenario {
        files.push(("scenario.toml", s));
    }
    let dir = project(&format!("mb-{name}"), &files);
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    match loaded {
        Ok(l) => l,
        Err(d) => panic!("{name}: the program should load:\n{}", d.render_plain()),
    }
}

/// Run `program` until it ends (or fails).
fn run_mb(name: &str, program: &str) -> Run {
    run_loaded(load_mb(name, program, None))
}

/// Run `program` for `seconds` of simulated time.
fn run_mb_for(name: &str, program: &str, seconds: f64) -> Run {
    let scenario = format!("[run]\nduration = \"{seconds}s\"\n");
    run_loaded(load_mb(name, program, Some(&scenario)))
}

/// Run `program`, which must end without an error.
fn run_ok(name: &str, program: &str) -> Run {
    let run = run_mb(name, program);
    if let Some(e) = &run.summary.error {
        panic!(
            "{name}: unexpected run-time error: line {}: {}",
            e.line, e.message
        );
    }
    run
}

/// Run `program`, which must end with a run-time error.
fn run_err(name: &str, program: &str) -> RunError {
    let run = run_mb(name, program);
    match run.summary.error {
        Some(e) => e,
        None => panic!(
            "{name}: the run should have ended with an error; it stopped: {}",
            run.summary.stop_reason
        ),
    }
}

/// A value in the machine's registry after the run: an object member (`Axis.2.Position`) by
/// `Machine::value_of`, a MotionBASIC variable (`PLEN.TMP&`) by its slot name (names are
/// case-insensitive).
fn lookup(run: &Run, name: &str) -> Option<f64> {
    run.machine.value_of(name).or_else(|| {
        let slot = run
            .machine
            .registry()
            .slots
            .iter()
            .position(|s| s.name.text().eq_ignore_ascii_case(name))?;
        run.machine.values().get(slot).copied()
    })
}

/// A value in the machine's registry after the run.
#[track_caller]
fn val(run: &Run, name: &str) -> f64 {
    lookup(run, name).unwrap_or_else(|| panic!("no `{name}` in the machine's registry"))
}

/// Assert several registry values at once, listing every one that differs.
#[track_caller]
fn assert_values(run: &Run, expected: &[(&str, f64)]) {
    let wrong: Vec<String> = expected
        .iter()
        .filter_map(|(name, want)| {
            let got = lookup(run, name);
            (got != Some(*want)).then(|| format!("{name}: got {got:?}, want {want}"))
        })
        .collect();
    assert!(wrong.is_empty(), "wrong values:\n{}", wrong.join("\n"));
}

/// Every problem of a project that must be refused.
fn refused(name: &str, program: &str) -> Diagnostics {
    load_error(
        &format!("mb-{name}"),
        &[("x.mb", program), ("machine.toml", MACHINE)],
    )
}

/// The errors (not warnings) of a refused project.
fn errors(d: &Diagnostics) -> Vec<&Located> {
    d.items
        .iter()
        .filter(|l| l.problem.level == Level::Error)
        .collect()
}

/// The single error of a refused project.
#[track_caller]
fn one_error(name: &str, program: &str) -> pacer::diag::Problem {
    let d = refused(name, program);
    let e = errors(&d);
    assert_eq!(
        e.len(),
        1,
        "{name}: expected one error:\n{}",
        d.render_plain()
    );
    e[0].problem.clone()
}

/// The source text under a problem's span.
fn spanned<'a>(program: &'a str, p: &pacer::diag::Problem) -> &'a str {
    &program[p.span.start..p.span.end]
}

/// The values traced by the `change` events of one variable, in order.
fn changes(run: &Run, name: &str) -> Vec<f64> {
    run.events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == name)
        .filter_map(|e| e["value"].as_f64())
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Precedence (Microsoft BASIC): ^ > unary - > * / > \ > MOD > + - > comparisons > NOT > AND >
// OR > XOR.
// ---------------------------------------------------------------------------------------------

#[test]
fn power_binds_tighter_than_unary_minus() {
    let run = run_ok(
        "pow-neg",
        "A = -2^2\nB = (-2)^2\nC = 2^-1\nD = -[2+1]^2\nE = 2^3^2\nF = 2*3^2\n",
    );
    assert_values(
        &run,
        &[
            ("A", -4.0),
            ("B", 4.0),
            ("C", 0.5),
            ("D", -9.0),
            // Microsoft BASIC evaluates ^ left to right: (2^3)^2.
            ("E", 64.0),
            ("F", 18.0),
        ],
    );
}

#[test]
fn multiplication_binds_tighter_than_integer_division() {
    let run = run_ok(
        "mul-idiv",
        "T& = 7\nA& = 3*T&\\2\nB& = 3*(T&\\2)\nC = 8 \\ 4 / 2\nD& = 12 \\ 2 * 3\n\
         TREND.SET& = 15000\nE& = 3*TREND.SET&\\2\nF& = TREND.SET&\\2\n",
    );
    assert_values(
        &run,
        &[
            // (3*7)\2 = 21\2 = 10, not 3*(7\2) = 9.
            ("A&", 10.0),
            ("B&", 9.0),
            // 8 \ (4/2) = 4, not (8\4)/2 = 1.
            ("C", 4.0),
            // 12 \ (2*3) = 2, not (12\2)*3 = 18.
            ("D&", 2.0),
            ("E&", 22500.0),
            ("F&", 7500.0),
        ],
    );
}

#[test]
fn integer_division_binds_tighter_than_mod_and_mod_tighter_than_addition() {
    let run = run_ok(
        "idiv-mod-add",
        "A& = 10 MOD 9 \\ 2\nB& = 1 + 7 MOD 4\nC& = 7 MOD 4 + 1\nD& = 10 - 7 MOD 4\n\
         E& = 2 + 3 * 4\nF& = 10 - 4 - 3\nG& = -7 MOD 3\n",
    );
    assert_values(
        &run,
        &[
            // 10 MOD (9\2) = 10 MOD 4 = 2, not (10 MOD 9)\2 = 0.
            ("A&", 2.0),
            // 1 + (7 MOD 4) = 4, not 8 MOD 4 = 0.
            ("B&", 4.0),
            ("C&", 4.0),
            ("D&", 7.0),
            ("E&", 14.0),
            ("F&", 3.0),
            // The remainder takes the dividend's sign.
            ("G&", -1.0),
        ],
    );
}

#[test]
fn comparisons_bind_looser_than_arithmetic_and_tighter_than_not() {
    let run = run_ok(
        "cmp-not",
        "A& = 1 + 1 = 2\nB& = 2 * 3 > 5\nC& = NOT 1 = 2\nD& = NOT 1 = 1\nE& = (1 < 2) + (2 < 3)\n\
         F& = 3 <> 3\nG& = 2 >= 2\nH& = 2 <= 1\n",
    );
    assert_values(
        &run,
        &[
            ("A&", -1.0),
            ("B&", -1.0),
            // NOT (1 = 2) = NOT 0 = -1; (NOT 1) = 2 would be 0.
            ("C&", -1.0),
            ("D&", 0.0),
            ("E&", -2.0),
            ("F&", 0.0),
            ("G&", -1.0),
            ("H&", 0.0),
        ],
    );
}

#[test]
fn not_and_or_xor_bind_in_that_order() {
    let run = run_ok(
        "not-and-or-xor",
        "A& = NOT 0 AND 0\nB& = 1 OR 2 AND 0\nC& = 3 XOR 1 OR 2\nD& = NOT 5\nE& = 5 OR 3\n\
         F& = 5 XOR 3\nG& = -1 AND 7\nH& = NOT -1\n",
    );
    assert_values(
        &run,
        &[
            // (NOT 0) AND 0 = 0; NOT (0 AND 0) would be -1.
            ("A&", 0.0),
            // 1 OR (2 AND 0) = 1; (1 OR 2) AND 0 would be 0.
            ("B&", 1.0),
            // 3 XOR (1 OR 2) = 0; (3 XOR 1) OR 2 would be 2.
            ("C&", 0.0),
            ("D&", -6.0),
            ("E&", 7.0),
            ("F&", 6.0),
            ("G&", 7.0),
            ("H&", 0.0),
        ],
    );
}

#[test]
fn integer_division_rounds_operands_half_to_even_and_truncates_toward_zero() {
    let run = run_ok(
        "idiv-round",
        "A& = 7.5\\2\nB& = -7\\2\nC& = 8.5\\2.5\nD& = 7\\2\nE& = -7.5\\2\nF& = 6.5\\2\n\
         G = 9.4\\2.6\nH& = 1\\3\nI& = -1\\3\n",
    );
    assert_values(
        &run,
        &[
            // 7.5 rounds to 8: 8\2 = 4.
            ("A&", 4.0),
            // -3.5 truncates to -3.
            ("B&", -3.0),
            // 8.5 → 8 and 2.5 → 2 (halves to even): 8\2 = 4.
            ("C&", 4.0),
            ("D&", 3.0),
            // -7.5 → -8: -8\2 = -4.
            ("E&", -4.0),
            // 6.5 → 6: 6\2 = 3.
            ("F&", 3.0),
            // 9 \ 3 = 3, into a real variable.
            ("G", 3.0),
            ("H&", 0.0),
            ("I&", 0.0),
        ],
    );
}

#[test]
fn brackets_group_like_parentheses() {
    let run = run_ok(
        "brackets",
        "A = [2 + 3] * 4\nB = 2 + 3 * 4\nC& = 10000 * [1 - 0.5]\nD = [[1 + 1] * (2 + [3])]\n\
         NUM = 5\nFCOEF& = 10000 * [1 - 0.1^(1/NUM)]\n",
    );
    assert_values(
        &run,
        &[
            ("A", 20.0),
            ("B", 14.0),
            ("C&", 5000.0),
            ("D", 10.0),
            // The REG.CONFIG filter coefficient: 10000 × (1 − 0.1^0.2) = 3690.4…, rounded.
            ("FCOEF&", 3690.0),
        ],
    );
}

#[test]
fn mod_rounds_its_operands_like_microsoft_basic() {
    // The GW-BASIC manual's own examples: 10.4 MOD 4 = 2 and 25.68 MOD 6.99 = 5 (26 MOD 7):
    // MOD, like `\`, rounds both operands to integers first.
    let run = run_ok(
        "mod-round",
        "A = 10.4 MOD 4\nB = 25.68 MOD 6.99\nC = 7.5 MOD 2\n",
    );
    assert_values(&run, &[("A", 2.0), ("B", 5.0), ("C", 0.0)]);
}

#[test]
fn logical_operators_round_real_operands_to_integers() {
    // Microsoft BASIC converts the operands of NOT, AND, OR and XOR to integers by rounding
    // (as `\` does), then works bitwise: 5.6 AND 3 = 6 AND 3.
    let run = run_ok(
        "logic-round",
        "A& = 5.6 AND 3\nB& = NOT 1.6\nC& = 6 XOR 1.6\nD& = 4.7 OR 0\nE& = NOT -0.9\n",
    );
    assert_values(
        &run,
        &[
            ("A&", 2.0),
            ("B&", -3.0),
            ("C&", 4.0),
            ("D&", 5.0),
            ("E&", 0.0),
        ],
    );
}

// ---------------------------------------------------------------------------------------------
// Truth values
// ---------------------------------------------------------------------------------------------

#[test]
fn comparisons_yield_minus_one_or_zero_and_true_is_minus_one() {
    let run = run_ok(
        "truth",
        "A& = 1 < 2\nB& = 2 < 1\nC& = TRUE\nD& = FALSE\nE = 3 = 3\nF& = (1 < 2) = TRUE\n\
         G& = NOT TRUE\nH& = NOT 0\nI& = 5 AND 3\nJ& = TRUE AND 6\n",
    );
    assert_values(
        &run,
        &[
            ("A&", -1.0),
            ("B&", 0.0),
            ("C&", -1.0),
            ("D&", 0.0),
            ("E", -1.0),
            ("F&", -1.0),
            ("G&", 0.0),
            ("H&", -1.0),
            ("I&", 1.0),
            ("J&", 6.0),
        ],
    );
}

#[test]
fn if_takes_any_non_zero_value_as_true_and_logic_is_bitwise() {
    let run = run_ok(
        "if-truth",
        "A& = 0 : B& = 0 : C& = 0 : D& = 0 : E& = 0 : F& = 0 : G& = 0 : H& = 0\n\
         IF 2 THEN A& = 1\n\
         IF 1 AND 2 THEN B& = 1\n\
         IF 1 AND 3 THEN C& = 1\n\
         IF NOT 1 THEN D& = 1\n\
         IF NOT (1 = 2) THEN E& = 1\n\
         IF -0.5 THEN F& = 1\n\
         IF 1 < 2 AND 3 < 4 THEN\nG& = 1\nENDIF\n\
         IF 1 AND 2 THEN\nH& = 1\nELSE\nH& = 2\nENDIF\n\
         X& = 4\nI& = 0\nWHILE X&\nX& = X& - 1 : I& = I& + 1\nWEND\n",
    );
    assert_values(
        &run,
        &[
            ("A&", 1.0),
            // 1 AND 2 = 0: false.
            ("B&", 0.0),
            ("C&", 1.0),
            // NOT 1 = -2: true (bitwise, as in Microsoft BASIC).
            ("D&", 1.0),
            ("E&", 1.0),
            ("F&", 1.0),
            ("G&", 1.0),
            ("H&", 2.0),
            ("I&", 4.0),
        ],
    );
}

#[test]
fn controller_truth_tests_compare_equal_to_true() {
    // `IF ASEN({web~, knife~}) = TRUE` in MAIN only works if a controller test yields -1.
    let run = run_ok(
        "ctl-truth",
        "w~ = {1} : k~ = {2}\nA& = DSP.DONE@(k~)\nB& = 0\nIF DSP.DONE({w~, k~}) = TRUE THEN B& = 1\n\
         C& = ASEN@({w~, k~})\nD& = 0\nIF ASEN({w~, k~}) = FALSE THEN D& = 1\n",
    );
    assert_values(&run, &[("A&", -1.0), ("B&", 1.0), ("C&", 0.0), ("D&", 1.0)]);
}

// ---------------------------------------------------------------------------------------------
// Long integers, reals, axis sets
// ---------------------------------------------------------------------------------------------

#[test]
fn assigning_a_real_to_a_long_rounds_halves_to_even() {
    // The spec says "rounds to the nearest integer"; Microsoft BASIC (CLNG) rounds halves to
    // even, as its `\` and MOD do.
    let run = run_ok(
        "long-round",
        "A& = 2.5\nB& = 3.5\nC& = -2.5\nD& = 2.4999\nE& = -3.5\nF& = 7 / 2\nG& = 1.005 * 1000\n\
         H& = 0.5\nI& = -0.5\nJ& = 2.6\n",
    );
    assert_values(
        &run,
        &[
            ("A&", 2.0),
            ("B&", 4.0),
            ("C&", -2.0),
            ("D&", 2.0),
            ("E&", -4.0),
            ("F&", 4.0),
            ("G&", 1005.0),
            ("H&", 0.0),
            ("I&", 0.0),
            ("J&", 3.0),
        ],
    );
}

#[test]
fn real_variables_hold_fractions() {
    let run = run_ok(
        "reals",
        "A = 2.5\nB = A / 4\nC = 7 / 2\nD! = 0.125\nE# = -1.75\nF = A * 0.5 + 0.25\n\
         G& = 9\nH = G& / 2\nI = 1 / 8 + G& \\ 2\n",
    );
    assert_values(
        &run,
        &[
            ("A", 2.5),
            ("B", 0.625),
            ("C", 3.5),
            ("D!", 0.125),
            ("E#", -1.75),
            ("F", 1.5),
            ("G&", 9.0),
            // `/` is real division even between longs.
            ("H", 4.5),
            ("I", 4.125),
        ],
    );
}

#[test]
fn long_arithmetic_past_32_bits_is_an_overflow_error_naming_the_line() {
    let e = run_err(
        "overflow-add",
        "X& = 2147483647\nY& = 1\nY& = X& + 1\nY& = 5\n",
    );
    assert_eq!(e.line, 3, "{}", e.message);
    assert!(
        e.message.to_ascii_lowercase().contains("overflow"),
        "{}",
        e.message
    );

    // An intermediate long result overflows even when the final value would fit.
    let e = run_err(
        "overflow-intermediate",
        "X& = 2147483647\nY& = 0\nY& = (X& + 1) - 5\n",
    );
    assert_eq!(e.line, 3, "{}", e.message);
    assert!(e.message.contains("Overflow"), "{}", e.message);

    // Long arithmetic overflows even when the result goes to a real variable.
    let e = run_err("overflow-to-real", "X& = 65536\nR = 0\nR = X& * X&\n");
    assert_eq!(e.line, 3, "{}", e.message);
    assert!(e.message.contains("Overflow"), "{}", e.message);

    // Below the bottom of the range too.
    let e = run_err(
        "overflow-neg",
        "X& = -2147483647 - 1\nZ& = 0\nZ& = X& - 1\n",
    );
    assert_eq!(e.line, 3, "{}", e.message);
    assert!(
        e.message.to_ascii_lowercase().contains("overflow"),
        "{}",
        e.message
    );

    // The one long quotient that does not fit.
    let e = run_err(
        "overflow-idiv",
        "X& = -2147483647 - 1\nZ& = 0\nZ& = X& \\ -1\n",
    );
    assert_eq!(e.line, 3, "{}", e.message);
    assert!(e.message.contains("Overflow"), "{}", e.message);

    // Negating the most negative long.
    let e = run_err(
        "overflow-neg-long",
        "X& = -2147483647 - 1\nR = 0\nR = -X&\n",
    );
    assert_eq!(e.line, 3, "{}", e.message);
    assert!(e.message.contains("Overflow"), "{}", e.message);

    // At the edges nothing overflows, and the run stops at the fault: nothing after it runs.
    let run = run_mb(
        "overflow-edges",
        "X& = 2147483647\nY& = -2147483647 - 1\nZ& = X& + Y&\nW& = X& \\ 1\nV& = 1\nV& = X& * 2\nV& = 3\n",
    );
    let e = run.summary.error.as_ref().expect("X& * 2 overflows");
    assert_eq!(e.line, 6, "{}", e.message);
    assert_values(
        &run,
        &[
            ("X&", 2147483647.0),
            ("Y&", -2147483648.0),
            ("Z&", -1.0),
            ("W&", 2147483647.0),
            ("V&", 1.0),
        ],
    );
    assert!(
        run.events.iter().any(|e| e["kind"] == "error"),
        "the trace records the error"
    );
}

#[test]
fn real_arithmetic_does_not_overflow_at_32_bits() {
    let run = run_ok("real-no-overflow", "X = 2147483647\nY = X + 1\nZ = X * 4\n");
    assert_values(&run, &[("Y", 2147483648.0), ("Z", 8589934588.0)]);
}

#[test]
fn axis_set_variables_hold_axes_and_sets_of_axes() {
    let run = run_ok(
        "axis-sets",
        "a~ = {1}\nb~ = {2}\nc~ = {a~, b~}\nd~ = {1, 2}\ne~ = {c~, 2}\nf~ = b~\n\
         POS.MOD@(c~) = 1800\nA& = POS.MOD(a~)\nB& = POS.MOD(b~)\nPOS.MOD@(f~) = 900\n\
         C& = POS.MOD(a~)\nD& = POS.MOD@{b~}\nN& = 2\ng~ = {N&}\nE& = POS.MOD(g~)\n",
    );
    assert_values(
        &run,
        &[
            // An axis set is kept as a mask of axis bits.
            ("a~", 1.0),
            ("b~", 2.0),
            ("c~", 3.0),
            ("d~", 3.0),
            ("e~", 3.0),
            ("f~", 2.0),
            // A write to a set writes every axis of it.
            ("A&", 1800.0),
            ("B&", 1800.0),
            ("C&", 1800.0),
            ("D&", 900.0),
            ("E&", 900.0),
            ("Axis.1.PosMod", 1800.0),
            ("Axis.2.PosMod", 900.0),
        ],
    );
}

#[test]
fn an_axis_number_outside_1_to_16_is_a_run_time_error() {
    let e = run_err("axis-zero", "N& = 0\na~ = {N&}\nX = POS(a~)\n");
    assert_eq!(e.line, 2, "{}", e.message);
    assert!(e.message.contains("axis number"), "{}", e.message);
}

#[test]
fn names_are_case_insensitive_typed_by_suffix_and_may_hold_keywords_and_dots() {
    let run = run_ok(
        "names",
        "abc& = 1\nABC& = Abc& + 1\nQ& = 1\nQ = 2.5\nQ~ = {2}\nREMAINDER& = 5\nENDX& = 2\n\
         IN.DIST& = 3\nTO.GO& = 4\nPLEN.TMP& = 6\nA = .5 + 1E3\nB = 1.5e-1\n",
    );
    assert_values(
        &run,
        &[
            // One variable, shown as first written.
            ("abc&", 2.0),
            // Q&, Q and Q~ are three variables.
            ("Q&", 1.0),
            ("Q", 2.5),
            ("Q~", 2.0),
            ("REMAINDER&", 5.0),
            ("ENDX&", 2.0),
            ("IN.DIST&", 3.0),
            ("TO.GO&", 4.0),
            ("PLEN.TMP&", 6.0),
            ("A", 1000.5),
            ("B", 0.15),
        ],
    );
    assert!(
        run.machine
            .registry()
            .slots
            .iter()
            .any(|s| s.name == "abc&"),
        "the registry shows a variable as first written"
    );
}

#[test]
fn abs_and_sgn() {
    let run = run_ok(
        "abs-sgn",
        "A = ABS(-3.5)\nB& = ABS(7)\nC& = SGN(-2) * 300\nD& = SGN(0)\nE& = SGN(0.1)\n\
         DIFF& = -1200\nMAX.DIFF& = 300\nIF ABS(DIFF&) > MAX.DIFF& THEN DIFF& = SGN(DIFF&)* MAX.DIFF&\n",
    );
    assert_values(
        &run,
        &[
            ("A", 3.5),
            ("B&", 7.0),
            ("C&", -300.0),
            ("D&", 0.0),
            ("E&", 1.0),
            ("DIFF&", -300.0),
        ],
    );
}

#[test]
fn the_listings_arithmetic_trend_filter_and_inst_phase_fold() {
    // TREND's and INST's arithmetic, with the latched positions as plain variables.
    let run = run_ok(
        "listing-arith",
        "INST.SET& = 0 : MAX.DIFF& = 300 : INST.GAIN& = 2500 : PM& = 3600\n\
         TREND.SET& = 15000 : PLEN& = TREND.SET& : NUM = 5\n\
         FCOEF& = 10000 * [1 - 0.1^(1/NUM)]\n\
         P& = 15120 : TREND : T1& = PLEN&\n\
         P& = 30000 : TREND : T2& = PLEN&\n\
         P& = 5000 : TREND : T3& = PLEN&\n\
         POSA& = 1200 : INST : C1& = CORR&\n\
         POSA& = 3500 : INST : C2& = CORR&\n\
         POSA& = 100 : INST : C3& = CORR&\n\
         POSA& = 1800 : INST : C4& = CORR&\n\
         POSA& = 7 : INST : C5& = CORR&\n\
         POSA& = 3593 : INST : C6& = CORR&\n\
         END\n\
         TREND:\n\
         PLEN.TMP& = P&\n\
         IF PLEN.TMP& > TREND.SET&\\2 AND PLEN.TMP& < 3*TREND.SET&\\2 THEN\n\
         \x20 PLEN& = ((10000 - FCOEF&)*PLEN& + FCOEF&*PLEN.TMP&)\\10000\n\
         ENDIF\n\
         RETURN\n\
         INST:\n\
         \x20 DIFF& = INST.SET& - POSA&\n\
         \x20 IF DIFF& > PM&\\2 THEN\n\
         \x20   DIFF& = DIFF& - PM&\n\
         \x20 ELSE\n\
         \x20   IF DIFF& <= -(PM&\\2) THEN\n\
         \x20     DIFF& = DIFF& + PM&\n\
         \x20   ENDIF\n\
         \x20 ENDIF\n\
         \x20 IF ABS(DIFF&) > MAX.DIFF& THEN\n\
         \x20   DIFF& = SGN(DIFF&)* MAX.DIFF&\n\
         \x20 ENDIF\n\
         \x20 CORR& = (DIFF& * INST.GAIN&) \\ 10000\n\
         RETURN\n",
    );
    assert_values(
        &run,
        &[
            ("FCOEF&", 3690.0),
            // (6310 × 15000 + 3690 × 15120) \ 10000 = 150442800 \ 10000.
            ("T1&", 15044.0),
            // Samples outside (½ … 1½) × 15000 are rejected.
            ("T2&", 15044.0),
            ("T3&", 15044.0),
            // -1200 clamps to -300: × 0.25.
            ("C1&", -75.0),
            // -3500 folds to +100.
            ("C2&", 25.0),
            ("C3&", -25.0),
            // -1800 is ≤ -1800: folds to +1800, clamps to +300.
            ("C4&", 75.0),
            // -17500 \ 10000 truncates toward zero: -1, not -2.
            ("C5&", -1.0),
            // -3593 folds to +7: 17500 \ 10000 = 1.
            ("C6&", 1.0),
        ],
    );
}

// ---------------------------------------------------------------------------------------------
// Labels and subroutines
// ---------------------------------------------------------------------------------------------

#[test]
fn subroutines_by_bare_name_and_gosub_nest_and_return() {
    let run = run_ok(
        "subs",
        "MAIN:\nN& = 0\nOUTER\nGOSUB INNER\nN& = N& * 2\nEND\n\
         OUTER:\nN& = N& + 1\nINNER\nN& = N& + 100\nRETURN\n\
         INNER:\nN& = N& + 10\nRETURN\n",
    );
    // OUTER: 1, +10 (nested INNER), +100; GOSUB INNER: +10; then doubled.
    assert_eq!(val(&run, "N&"), 242.0);
    assert_eq!(
        changes(&run, "N&"),
        vec![0.0, 1.0, 11.0, 111.0, 121.0, 242.0]
    );
    assert_eq!(
        run.summary.stop_reason,
        pacer::vm::StopReason::ProgramsEnded
    );
}

#[test]
fn labels_are_case_insensitive_and_may_contain_dots() {
    let run = run_ok(
        "labels",
        "N& = 0\nreg.config\nGosub Mp.Config\nGOTO finish\nN& = -1\nFinish:\nEND\n\
         REG.CONFIG:\nN& = N& + 1 : TREND.SET& = 15000\nRETURN\n\
         MP.CONFIG:\nN& = N& + 10\nreturn\n",
    );
    assert_values(&run, &[("N&", 11.0), ("TREND.SET&", 15000.0)]);
}

#[test]
fn a_label_may_share_its_line_with_statements() {
    let run = run_ok(
        "label-line",
        "GOSUB SETUP\nEND\nSETUP: A& = 1 : B& = 2\nRETURN\n",
    );
    assert_values(&run, &[("A&", 1.0), ("B&", 2.0)]);
}

#[test]
fn return_without_gosub_is_a_check_error() {
    // The program runs into RETURN from its start (issue 16: `pacer check` says so, not t = 0).
    for program in [
        "A& = 1\nRETURN\nA& = 2\n",
        // Falling into a subroutine's RETURN from the main line.
        "A& = 1\nSUB1:\nA& = A& + 1\nRETURN\n",
        // A line-numbered subroutine with no END before it.
        "GOSUB 100\n100 A& = 2\nRETURN\n",
        // The main line jumps into a subroutine's loop: it runs into the RETURN after it.
        "GOTO AGAIN\nEND\nSUB1:\nAGAIN:\nA& = A& + 1\nIF A& < 3 THEN GOTO AGAIN\nRETURN\n",
        // Reached through a chain of GOTOs from the main line.
        "GOTO FIRST\nSUB1:\nRETURN\nFIRST:\nGOTO SUB1\n",
    ] {
        let result = common::load_memory("return", &[("x.mb", program), ("machine.toml", MACHINE)]);
        let problems = common::problem_triples(&result);
        assert_eq!(
            problems,
            vec![(
                "pacer::check::return".to_string(),
                "RETURN".to_string(),
                "RETURN without GOSUB".to_string()
            )],
            "{program}"
        );
    }
    // A subroutine after END, reached by GOSUB (a name or a line number), is fine.
    let run = run_ok(
        "gosub-ok",
        "GOSUB SUB1\nGOSUB 200\nEND\nSUB1:\nA& = A& + 1\nRETURN\n200 A& = A& + 10\nRETURN\n",
    );
    assert_eq!(val(&run, "A&"), 11.0);
    // A subroutine's own GOTO loop, and an EXIT FOR inside it (a jump to a label made after
    // its NEXT), do not make the main line run into its RETURN.
    let run = run_ok(
        "gosub-loops",
        "GOSUB SUB1\nGOSUB SUB2\nEND\nSUB1:\nAGAIN:\nA& = A& + 1\nIF A& < 3 THEN GOTO AGAIN\nRETURN\nSUB2:\nFOR K& = 1 TO 9\n  IF K& = 4 THEN EXIT FOR\nNEXT\nRETURN\n",
    );
    assert_eq!(val(&run, "A&"), 3.0);
    assert_eq!(val(&run, "K&"), 4.0);
}

#[test]
fn end_inside_a_subroutine_ends_the_program() {
    let run = run_ok(
        "end-in-sub",
        "A& = 1\nSTOPPER\nA& = 2\nEND\nSTOPPER:\nA& = 3\nEND\nRETURN\n",
    );
    assert_eq!(val(&run, "A&"), 3.0);
    assert_eq!(changes(&run, "A&"), vec![1.0, 3.0]);
    assert_eq!(
        run.summary.stop_reason,
        pacer::vm::StopReason::ProgramsEnded
    );
    assert!(run
        .events
        .iter()
        .any(|e| e["kind"] == "program" && e["event"] == "end"));
}

#[test]
fn goto_jumps_forward_and_back() {
    let run = run_ok(
        "goto",
        "I& = 0\nTOP:\nI& = I& + 1\nIF I& < 5 THEN GOTO TOP\nGOTO DONE\nI& = 100\nDONE:\nJ& = I& * 2\n",
    );
    assert_values(&run, &[("I&", 5.0), ("J&", 10.0)]);
}

// ---------------------------------------------------------------------------------------------
// Blocks
// ---------------------------------------------------------------------------------------------

#[test]
fn block_if_else_endif_nests() {
    let program = |s: i32| {
        format!(
            "S& = {s}\nIF S& > 10 THEN\n  IF S& = 15 THEN\n    V& = 1\n  ELSE\n    V& = 2\n  ENDIF\n\
             ELSE\n  IF S& < 0 THEN\n    V& = 3\n  ELSE\n    V& = 4\n  END IF\nENDIF\n"
        )
    };
    for (s, v) in [(15, 1.0), (12, 2.0), (-1, 3.0), (5, 4.0)] {
        let run = run_ok(&format!("if-nest-{s}"), &program(s));
        assert_eq!(val(&run, "V&"), v, "S& = {s}");
    }
}

#[test]
fn single_line_if_with_several_statements_and_else() {
    let run = run_ok(
        "inline-if",
        "IF 1 THEN A& = 1 : B& = 2 ELSE C& = 3\n\
         IF 0 THEN D& = 1 : E& = 2 ELSE F& = 3 : G& = 4\n\
         H& = 5 : IF H& = 5 THEN I& = 6\n\
         IF 0 THEN J& = 7\n\
         IF 1 THEN SUB1 ELSE SUB2\n\
         IF 0 THEN GOSUB SUB1 ELSE GOSUB SUB2\n\
         END\nSUB1:\nK& = K& + 1\nRETURN\nSUB2:\nK& = K& + 10\nRETURN\n",
    );
    assert_values(
        &run,
        &[
            ("A&", 1.0),
            ("B&", 2.0),
            ("C&", 0.0),
            ("D&", 0.0),
            ("E&", 0.0),
            ("F&", 3.0),
            ("G&", 4.0),
            ("H&", 5.0),
            ("I&", 6.0),
            ("J&", 0.0),
            ("K&", 11.0),
        ],
    );
}

#[test]
fn while_wend_and_whiletrue_with_goto_out() {
    let run = run_ok(
        "while",
        "I& = 0 : S& = 0\nWHILE I& < 5\nI& = I& + 1 : S& = S& + I&\nWEND\n\
         Z& = 0\nWHILE 0\nZ& = 1\nWEND\n\
         W& = 0\nWHILETRUE\nW& = W& + 1\nIF W& >= 4 THEN GOTO OUT\nWEND\nOUT:\nAFTER.LOOP& = 1\n",
    );
    assert_values(
        &run,
        &[
            ("I&", 5.0),
            ("S&", 15.0),
            ("Z&", 0.0),
            ("W&", 4.0),
            ("AFTER.LOOP&", 1.0),
        ],
    );
}

#[test]
fn for_next_counts_with_positive_negative_and_fractional_steps() {
    let run = run_ok(
        "for",
        "T& = 0\nFOR K& = 10 TO 1 STEP -3\nT& = T& * 100 + K&\nNEXT K&\n\
         U& = 0\nFOR I& = 1 TO 5\nU& = U& + I&\nNEXT\n\
         R2 = 0\nFOR R = 0 TO 1 STEP 0.25\nR2 = R2 + R\nNEXT R\n\
         N& = 0\nFOR J& = 5 TO 1\nN& = N& + 1\nNEXT J&\n\
         P& = 0\nFOR I2& = 1 TO 3\nFOR J2& = 1 TO 2\nP& = P& + I2& * J2&\nNEXT J2&\nNEXT I2&\n",
    );
    assert_values(
        &run,
        &[
            // 10, 7, 4, 1.
            ("T&", 10070401.0),
            ("K&", -2.0),
            ("U&", 15.0),
            ("I&", 6.0),
            ("R2", 2.5),
            ("R", 1.25),
            // A loop whose start is past its end runs no time.
            ("N&", 0.0),
            ("P&", 18.0),
        ],
    );
}

#[test]
fn colons_comments_and_rem() {
    let run = run_ok(
        "comments",
        "' a comment line\nREM a remark line\nrem lower-case remark\nA& = 1 : B& = 2 : C& = 3 ' trailing\n\
         D& = 4 ' D& = 5\nE& = 6 : REM E& = 7\nF& = 8 '\n' G& = 9\n\n   \nH$ = \"it's\"\n",
    );
    assert_values(
        &run,
        &[
            ("A&", 1.0),
            ("B&", 2.0),
            ("C&", 3.0),
            ("D&", 4.0),
            ("E&", 6.0),
            ("F&", 8.0),
        ],
    );
    assert!(lookup(&run, "G&").is_none(), "G& is only in a comment");
}

// ---------------------------------------------------------------------------------------------
// Controller variables
// ---------------------------------------------------------------------------------------------

#[test]
fn controller_variables_resolve_with_or_without_at_and_take_parens_or_braces() {
    let run = run_ok(
        "controllers",
        "w~ = {1}\nk~ = {2}\nPOS.MOD@(k~) = 3600\nA& = POS.MOD(k~)\nB& = POS.MOD@(k~)\n\
         C& = POS.MOD@{k~}\nD& = POS.MOD{k~}\nE& = POS.MOD@(w~)\n\
         PLS.MOD@{k~} = 3600\nPLS1.LOW@{k~} = 2000\nPLS1.HIGH@{k~} = 2400\n\
         SENS.MODE@({w~, k~}) = \"RRRGN\"\nSENS.MODE@{k~} = \"FFRNG\"\n\
         IF DSP.DONE@(k~) THEN F& = 1\nG& = DSP.DONE(w~)\nH& = DSP.DONE@({w~, k~})\n\
         I& = POS.MOD@(k~)\\2\nJ& = -(POS.MOD@(k~)\\2)\n",
    );
    assert_values(
        &run,
        &[
            ("A&", 3600.0),
            ("B&", 3600.0),
            ("C&", 3600.0),
            ("D&", 3600.0),
            ("E&", 0.0),
            ("Axis.2.PosMod", 3600.0),
            ("Axis.2.PlsMod", 3600.0),
            ("Axis.2.Pls1Low", 2000.0),
            ("Axis.2.Pls1High", 2400.0),
            ("F&", 1.0),
            ("G&", -1.0),
            ("H&", -1.0),
            ("I&", 1800.0),
            ("J&", -1800.0),
        ],
    );
}

#[test]
fn dsp_done_is_minus_one_when_idle_and_zero_while_moving() {
    let run = run_mb_for(
        "dsp-done",
        "w~ = {1}\nIDLE& = DSP.DONE@(w~)\nMOVE w~ AT 100 IN 1000\nWHILE POS(w~) = 0\nWEND\n\
         BUSY& = DSP.DONE@(w~)\n",
        0.5,
    );
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_values(&run, &[("IDLE&", -1.0), ("BUSY&", 0.0)]);
}

#[test]
fn a_bad_sensor_mode_string_is_a_clear_run_time_error() {
    let e = run_err(
        "sens-bad",
        "w~ = {1} : k~ = {2}\nSENS.MODE@({w~, k~}) = \"RRRNN\"\nSENS.MODE@({w~, k~}) = \"RRXNN\"\n",
    );
    assert_eq!(e.line, 3, "{}", e.message);
    assert!(
        e.message.contains("SENS.MODE") && e.message.contains("RRXNN"),
        "{}",
        e.message
    );
    // It says what is wrong with it: the third character, X, is not an edge.
    assert!(
        e.message.contains('X') && e.message.contains("R (rising) or F (falling)"),
        "{}",
        e.message
    );

    let e = run_err("sens-short", "SENS.MODE@({1}) = \"RRRG\"\n");
    assert_eq!(e.line, 1, "{}", e.message);
    assert!(
        e.message.contains("5 characters") && e.message.contains("RRRG"),
        "{}",
        e.message
    );
}

#[test]
fn reading_a_multi_axis_controller_variable_is_a_run_time_error() {
    let e = run_err(
        "multi-read",
        "w~ = {1} : k~ = {2}\nX& = 0\nX& = POS.ASEN@({w~, k~})\n",
    );
    assert_eq!(e.line, 3, "{}", e.message);
    assert!(e.message.contains("one axis"), "{}", e.message);

    let e = run_err("multi-read-lit", "X& = POS.ASEN@({1,2})\n");
    assert_eq!(e.line, 1, "{}", e.message);
    assert!(e.message.contains("one axis"), "{}", e.message);
}

#[test]
fn an_undefined_axis_is_a_check_error_when_written_and_a_run_time_error_when_computed() {
    for program in [
        "X = POS@({5})\n",
        "POS.MOD@({5}) = 10\n",
        "a~ = {5}\nX = POS(a~)\n",
        "a~ = {1, 5}\nPOS.MOD@(a~) = 10\n",
        "a~ = {5}\nMOVE a~ AT 100 IN 10\n",
    ] {
        let result = common::load_memory("axis", &[("x.mb", program), ("machine.toml", MACHINE)]);
        let problems = common::problem_triples(&result);
        assert_eq!(
            problems,
            vec![(
                "pacer::check::axis".to_string(),
                "5".to_string(),
                "axis 5 is not a DSP axis of this machine".to_string()
            )],
            "{program}"
        );
    }
    for (name, program, line) in [
        ("undef-read", "N& = 5\nX = POS@({N&})\n", 2),
        ("undef-var", "N& = 5\na~ = {N&}\nX = POS(a~)\n", 3),
        ("undef-move", "N& = 5\na~ = {N&}\nMOVE a~ AT 100 IN 10\n", 3),
    ] {
        let e = run_err(name, program);
        assert_eq!(e.line, line, "{name}: {}", e.message);
        assert!(
            e.message.contains("axis 5") && e.message.contains("machine.toml"),
            "{name}: {}",
            e.message
        );
    }
}

#[test]
fn an_unassigned_axis_variable_is_a_run_time_error() {
    // k~ is never assigned (a check-time warning): its set is empty.
    let e = run_err("axis-unassigned", "X = 0\nX = POS(k~)\n");
    assert_eq!(e.line, 2, "{}", e.message);
    assert!(e.message.contains("empty"), "{}", e.message);
}

// ---------------------------------------------------------------------------------------------
// Motion
// ---------------------------------------------------------------------------------------------

/// The web after 2 s of `MOVE web~ AT 1000 IN 1000`: well under way.
fn web_and_knife(run: &Run) -> (f64, f64) {
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let web = val(run, "Axis.1.Position");
    let knife = val(run, "Axis.2.Position");
    assert!(web > 100_000.0, "the web ran: {web}");
    (web, knife)
}

#[test]
fn the_knife_follows_the_web_at_the_gear_ratio() {
    let run = run_mb_for(
        "gear",
        "web~ = {1}\nknife~ = {2}\nGEAR knife~ AT 3600 TO 15000\nMOVE web~ AT 1000 IN 1000\n",
        2.0,
    );
    let (web, knife) = web_and_knife(&run);
    assert!(
        (knife - 0.24 * web).abs() < 1e-6,
        "knife {knife} should be 0.24 × web {web} = {}",
        0.24 * web
    );
    assert_eq!(val(&run, "Axis.2.Ratio"), 0.24);
}

#[test]
fn with_pos_mod_the_knife_position_wraps_at_one_turn() {
    let run = run_mb_for(
        "gear-mod",
        "web~ = {1}\nknife~ = {2}\nPOS.MOD@(knife~) = 3600\nGEAR knife~ AT 3600 TO 15000\n\
         MOVE web~ AT 1000 IN 1000\n",
        2.25,
    );
    let (web, knife) = web_and_knife(&run);
    let want = (0.24 * web).rem_euclid(3600.0);
    assert!(
        (0.0..3600.0).contains(&knife),
        "knife {knife} is within one turn"
    );
    assert!(
        (knife - want).abs() < 1e-6,
        "knife {knife} should be 0.24 × web {web} mod 3600 = {want}"
    );
    assert!(knife > 1.0, "the knife moved: {knife}");
}

#[test]
fn gear_for_superimposes_a_correction_on_the_running_gear() {
    let run = run_mb_for(
        "gear-for",
        "web~ = {1}\nknife~ = {2}\nGEAR knife~ AT 3600 TO 15000\nMOVE web~ AT 1000 IN 1000\n\
         WHILE POS(web~) < 20000\nWEND\nGEAR knife~ FOR 100 IN 500\nISSUED& = POS(web~)\n",
        2.0,
    );
    let (web, knife) = web_and_knife(&run);
    assert!(val(&run, "ISSUED&") >= 20000.0);
    assert!(
        (knife - (0.24 * web + 100.0)).abs() < 1e-6,
        "knife {knife} should be 0.24 × web {web} + 100 = {}",
        0.24 * web + 100.0
    );
}

#[test]
fn gear_for_in_zero_is_a_step_with_a_warning_not_a_crash() {
    // REG.CONFIG's slip leaves I_DIST& at 0: the correction must be defined and visible.
    let run = run_mb_for(
        "gear-for-zero",
        "web~ = {1}\nknife~ = {2}\nGEAR knife~ AT 3600 TO 15000\nMOVE web~ AT 1000 IN 1000\n\
         WHILE POS(web~) < 20000\nWEND\nGEAR knife~ FOR 100 IN I_DIST&\n",
        2.0,
    );
    let (web, knife) = web_and_knife(&run);
    assert!(
        knife.is_finite() && (knife - (0.24 * web + 100.0)).abs() < 1e-6,
        "knife {knife} vs web {web}"
    );
    assert!(
        run.events
            .iter()
            .any(|e| e["kind"] == "warning" && e["line"] == 7),
        "a warning event names the GEAR FOR line"
    );
}

// ---------------------------------------------------------------------------------------------
// Check-time diagnostics
// ---------------------------------------------------------------------------------------------

#[test]
fn an_unknown_label_is_refused_with_the_near_miss() {
    let program = "GOSUB REG.CONFG\nEND\nREG.CONFIG:\nRETURN\n";
    let p = one_error("gosub-typo", program);
    assert_eq!(p.code, "pacer::check::label");
    assert_eq!(p.message, "no label `REG.CONFG` in this program");
    assert_eq!(spanned(program, &p), "REG.CONFG");
    assert_eq!(p.help.as_deref(), Some("did you mean `REG.CONFIG`?"));

    // The bare-name call form.
    let program = "MAIN:\nMP.CONFG\nEND\nMP.CONFIG:\nRETURN\n";
    let p = one_error("call-typo", program);
    assert_eq!(p.code, "pacer::check::label");
    assert_eq!(spanned(program, &p), "MP.CONFG");
    assert_eq!(p.help.as_deref(), Some("did you mean `MP.CONFIG`?"));

    // GOTO.
    let program = "GOTO FINSH\nA& = 1\nFinish:\nEND\n";
    let p = one_error("goto-typo", program);
    assert_eq!(p.code, "pacer::check::label");
    assert_eq!(p.message, "no label `FINSH` in this program");
    assert_eq!(spanned(program, &p), "FINSH");
    assert_eq!(
        p.help.as_deref().map(str::to_ascii_lowercase).as_deref(),
        Some("did you mean `finish`?")
    );

    // Nothing near: the help says how to define one.
    let program = "GOSUB NOWHERE\nEND\n";
    let p = one_error("gosub-none", program);
    assert!(
        p.help.as_deref().is_some_and(|h| h.contains("NOWHERE:")),
        "{p:?}"
    );
}

#[test]
fn type_mismatches_are_refused() {
    let program = "a~ = 5\n";
    let p = one_error("axis-from-number", program);
    assert_eq!(p.code, "pacer::check::type");
    assert_eq!(p.message, "an axis set is needed here, not a number");
    assert_eq!(spanned(program, &p), "5");

    let program = "x& = {1}\n";
    let p = one_error("long-from-axis", program);
    assert_eq!(p.code, "pacer::check::type");
    assert_eq!(p.message, "a number is needed here, not an axis set");
    assert_eq!(spanned(program, &p), "{1}");

    let program = "k~ = {2}\nGEAR 2 AT 3600 TO 15000\n";
    let p = one_error("gear-number", program);
    assert_eq!(p.code, "pacer::check::type");
    assert_eq!(spanned(program, &p), "2");

    let program = "k~ = {2}\nSENS.MODE@(k~) = 5\n";
    let p = one_error("sens-number", program);
    assert_eq!(p.code, "pacer::check::type");
    assert_eq!(p.message, "a string is needed here, not a number");

    let program = "k~ = {2}\nX = k~ + 1\n";
    let p = one_error("axis-arith", program);
    assert_eq!(p.code, "pacer::check::type");
    assert_eq!(spanned(program, &p), "k~");
}

#[test]
fn an_unknown_controller_variable_is_refused_with_the_near_miss() {
    let program = "k~ = {2}\nPOS.MDO@(k~) = 3600\n";
    let p = one_error("ctl-write-typo", program);
    assert_eq!(p.code, "pacer::check::unknown_controller");
    assert_eq!(p.message, "unknown controller variable `POS.MDO@`");
    assert_eq!(spanned(program, &p), "POS.MDO@");
    assert_eq!(p.help.as_deref(), Some("did you mean `POS.MOD@`?"));

    let program = "k~ = {2}\nX& = POS.ASN@(k~)\n";
    let p = one_error("ctl-read-typo", program);
    assert_eq!(p.code, "pacer::check::unknown_function");
    assert_eq!(spanned(program, &p), "POS.ASN@");
    assert!(
        p.help
            .as_deref()
            .is_some_and(|h| h.starts_with("did you mean `POS.ASEN")),
        "{p:?}"
    );
}

#[test]
fn writing_a_read_only_controller_variable_is_refused() {
    let program = "k~ = {2}\nPOS.ASEN@(k~) = 1\n";
    let p = one_error("ctl-read-only", program);
    assert_eq!(p.code, "pacer::check::read_only");
    assert_eq!(p.message, "POS.ASEN@ is read-only");
    assert_eq!(spanned(program, &p), "POS.ASEN@");

    let p = one_error("ctl-read-only-done", "k~ = {2}\nDSP.DONE@(k~) = 0\n");
    assert_eq!(p.code, "pacer::check::read_only");
}

#[test]
fn a_controller_variable_without_its_axis_is_refused_clearly() {
    // `POS.MOD@` needs an axis: the message must say so, not treat `POS` as an unknown
    // PowerTools object.
    let program = "X& = POS.MOD@\n";
    let d = refused("ctl-no-axis", program);
    let e = errors(&d);
    assert_eq!(e.len(), 1, "{}", d.render_plain());
    let p = &e[0].problem;
    let text = format!(
        "{} {} {}",
        p.message,
        p.label,
        p.help.as_deref().unwrap_or("")
    );
    assert!(
        text.contains("POS.MOD") && text.contains("axis"),
        "{}",
        d.render_plain()
    );
    assert!(
        !text.contains("unknown object") && !text.contains("PosnCommand"),
        "{}",
        d.render_plain()
    );
}

#[test]
fn a_variable_read_but_never_assigned_is_a_warning_naming_the_near_miss() {
    // The spec's REG.CONFIG slip: it sets L_DIST& while INST reads I_DIST&.
    let program =
        "L_DIST& = 500\nT_DIST& = 500\nk~ = {2}\nGEAR k~ FOR 10 IN I_DIST&\nX& = I_DIST& + 1\n";
    let loaded = load_mb("never-assigned", program, None);
    let warnings: Vec<_> = loaded.warnings.items.iter().map(|l| &l.problem).collect();
    assert_eq!(
        warnings.len(),
        1,
        "one warning, even for two reads:\n{}",
        loaded.warnings.render_plain()
    );
    let w = warnings[0];
    assert_eq!(w.level, Level::Warning);
    assert_eq!(w.code, "pacer::check::never_assigned");
    assert_eq!(w.message, "I_DIST& is read but never assigned");
    assert_eq!(spanned(program, w), "I_DIST&");
    assert!(
        w.help
            .as_deref()
            .is_some_and(|h| h.contains("`L_DIST&`") && !h.contains("T_DIST&")),
        "{w:?}"
    );
    // It still runs (I_DIST& is 0).
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_eq!(val(&run, "X&"), 1.0);
}

#[test]
fn unbalanced_blocks_are_reported_in_motionbasic_words() {
    let cases: &[(&str, &str, &[&str])] = &[
        ("unclosed-while", "WHILE 1\nX& = 1\n", &["WEND", "WHILE"]),
        ("unclosed-if", "IF 1 THEN\nX& = 1\n", &["ENDIF", "IF"]),
        ("stray-wend", "X& = 1\nWEND\n", &["WEND", "WHILE"]),
        ("stray-endif", "X& = 1\nENDIF\n", &["ENDIF", "IF"]),
        ("stray-else", "ELSE\nX& = 1\n", &["ELSE", "IF"]),
        (
            "unclosed-for",
            "FOR I& = 1 TO 3\nX& = 1\n",
            &["NEXT", "FOR"],
        ),
        (
            "wend-in-if",
            "IF 1 THEN\nX& = 1\nWEND\n",
            &["WEND", "ENDIF"],
        ),
        ("endif-in-while", "WHILE 1\nENDIF\n", &["ENDIF", "WEND"]),
    ];
    for (name, program, words) in cases {
        let d = refused(name, program);
        let text: String = errors(&d)
            .iter()
            .map(|l| {
                format!(
                    "{} | {} | {}\n",
                    l.problem.message,
                    l.problem.label,
                    l.problem.help.as_deref().unwrap_or("")
                )
            })
            .collect();
        assert!(!text.is_empty(), "{name}: refused with no error");
        for w in *words {
            assert!(text.contains(w), "{name}: no `{w}` in:\n{text}");
        }
        for pt in ["Loop", "Do While", "Endif", "End If", "Call"] {
            assert!(
                !text.contains(pt),
                "{name}: PowerTools word `{pt}` in:\n{text}"
            );
        }
    }
}

#[test]
fn syntax_errors_list_motionbasic_words() {
    // The expected-token help of a MotionBASIC syntax error names MotionBASIC's tokens
    // (TRUE, FALSE, NOT, TO, XOR), not PowerTools' (ON, OFF, Not, To).
    let words = |name: &str, program: &str| -> Vec<String> {
        let p = one_error(name, program);
        assert_eq!(p.code, "pacer::syntax", "{p:?}");
        let help = p.help.unwrap_or_default();
        help.trim_start_matches("expected ")
            .split(", ")
            .map(str::to_string)
            .collect()
    };
    let w = words("syntax-value", "X& = \n");
    for pt in ["ON", "OFF", "Not"] {
        assert!(!w.iter().any(|x| x == pt), "PowerTools `{pt}` in {w:?}");
    }
    for mb in ["TRUE", "FALSE", "NOT"] {
        assert!(w.iter().any(|x| x == mb), "no `{mb}` in {w:?}");
    }
    let w = words("syntax-gear", "k~ = {2}\nGEAR k~ AT 3600\n");
    assert!(w.iter().any(|x| x == "TO"), "no `TO` in {w:?}");
    assert!(!w.iter().any(|x| x == "To"), "PowerTools `To` in {w:?}");
    let w = words("syntax-then", "IF 1 THEN ELSE\n");
    for pt in ["Gosub", "Goto", "Return", "End", "Gear", "Move"] {
        assert!(
            !w.iter().any(|x| x == pt),
            "PowerTools spelling `{pt}` in {w:?}"
        );
    }
}

#[test]
fn check_from_the_command_line_reports_mb_errors_and_warnings() {
    let dir = project(
        "mb-cli-check",
        &[
            (
                "x.mb",
                "L_DIST& = 500\nX& = I_DIST&\nGOSUB REG.CONFG\nEND\nREG.CONFIG:\nRETURN\n",
            ),
            ("machine.toml", MACHINE),
        ],
    );
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pacer"))
        .args(["check", dir.to_str().expect("utf-8 path")])
        .output()
        .expect("pacer runs");
    let _ = std::fs::remove_dir_all(&dir);
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("x.mb:2:6: warning"), "{text}");
    assert!(
        text.contains("I_DIST& is read but never assigned"),
        "{text}"
    );
    assert!(text.contains("x.mb:3:7: error"), "{text}");
    assert!(text.contains("did you mean `REG.CONFIG`?"), "{text}");
    assert!(text.contains("1 error(s)"), "{text}");
}

#[test]
fn a_folder_holding_only_an_mb_file_runs_it() {
    // No machine file listing the program: the `.mb` file is found in the folder.
    let dir = project("mb-bare-folder", &[("prog.mb", "A& = 6 * 7\nB = A& / 4\n")]);
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let run = run_loaded(loaded.unwrap_or_else(|d| panic!("{}", d.render_plain())));
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_values(&run, &[("A&", 42.0), ("B", 10.5)]);
}

#[test]
fn machine_value_of_reads_motionbasic_variables() {
    // `Machine::value_of` is how callers read a machine's values by name; MotionBASIC
    // variables are in the registry under their name as first written.
    let run = run_ok(
        "value-of",
        "PLEN& = 15000\nPLEN.TMP& = 14990\nNUM = 2.5\nknife~ = {2}\n",
    );
    assert_eq!(run.machine.value_of("PLEN&"), Some(15000.0));
    assert_eq!(run.machine.value_of("PLEN.TMP&"), Some(14990.0));
    assert_eq!(run.machine.value_of("NUM"), Some(2.5));
    assert_eq!(run.machine.value_of("knife~"), Some(2.0));
}

#[test]
fn a_byte_order_mark_at_the_start_of_a_file_is_whitespace() {
    // Windows editors write one; the program must run as if it were not there.
    let run = run_ok("bom", "\u{FEFF}A& = 1 : B& = A& + 1\n");
    assert_values(&run, &[("A&", 1.0), ("B&", 2.0)]);
    let mut problems = Vec::new();
    let ast = pacer::syntax::parse_program("\u{FEFF}Var.X = 1\n", &mut problems);
    assert!(problems.is_empty(), "{problems:?}");
    assert_eq!(ast.body.len(), 1);
}

/// A string built at run time reaches the DSP card: `SENS.MODE@` takes any string expression
/// (GW-BASIC User's Guide, "String functions"; the note's `SENS.MODE@(axis) = "RRRNN"`).
#[test]
fn sens_mode_takes_a_string_built_at_run_time() {
    let run = run_ok(
        "sens-mode-expr",
        "EDGE$ = \"R\"\nM$ = STRING$(3, EDGE$) + LEFT$(\"NNX\", 2)\nSENS.MODE@({1}) = M$\nEND\n",
    );
    let modes: Vec<&serde_json::Value> = run
        .events
        .iter()
        .filter(|e| e["kind"] == "sens_mode")
        .collect();
    assert_eq!(modes.len(), 1, "{}", run.text);
    assert_eq!(modes[0]["mode"], "RRRNN");
    assert_eq!(modes[0]["axis"], 1);
    let texts: Vec<(String, String)> = run
        .events
        .iter()
        .filter(|e| e["kind"] == "text_change")
        .map(|e| {
            (
                e["name"].as_str().unwrap_or_default().to_string(),
                e["value"].as_str().unwrap_or_default().to_string(),
            )
        })
        .collect();
    assert_eq!(
        texts,
        vec![
            ("EDGE$".to_string(), "R".to_string()),
            ("M$".to_string(), "RRRNN".to_string())
        ]
    );
}

/// Array elements are variables of the machine: their values after the run, by name
/// (GW-BASIC User's Guide, "DIM": subscripts from 0; row-major storage is pacer's).
#[test]
fn array_elements_hold_their_values() {
    let run = run_ok(
        "arrays",
        "DIM P&(3), M(1, 1)\nFOR I& = 0 TO 3: P&(I&) = I& * I&: NEXT\nM(1, 0) = 2.5\nM(0, 1) = M(1, 0) * 2\nSWAP P&(0), P&(3)\nEND\n",
    );
    assert_values(
        &run,
        &[
            ("P&(0)", 9.0),
            ("P&(1)", 1.0),
            ("P&(2)", 4.0),
            ("P&(3)", 0.0),
            ("M(1,0)", 2.5),
            ("M(0,1)", 5.0),
            ("M(0,0)", 0.0),
        ],
    );
}

/// An element's name is made when something asks for it, not stored per element (a large
/// `DIM` loads without a string per element): the trace, a run-time error and the registry
/// still name each element as written, every subscript from 0 in row-major order.
#[test]
fn array_elements_are_named_where_they_are_shown() {
    let program = "DIM G(2, 3), T%(1, 1, 4), BIG&(20000)\nG(1, 2) = 1.5\nT%(1, 0, 3) = 7\nBIG&(20000) = 4\nT%(0, 1, 1) = 40000\n";
    let run = run_mb("element-names", program);
    assert_eq!(changes(&run, "G(1,2)"), vec![1.5]);
    assert_eq!(changes(&run, "T%(1,0,3)"), vec![7.0]);
    assert_eq!(changes(&run, "BIG&(20000)"), vec![4.0]);
    let e = run.summary.error.as_ref().expect("an Overflow");
    assert_eq!(e.line, 5);
    assert!(
        e.message.contains("does not fit T%(0,1,1)"),
        "{}",
        e.message
    );
    let registry = run.machine.registry();
    let big: Vec<_> = registry
        .slots
        .iter()
        .filter(|s| s.name.starts_with("BIG&("))
        .collect();
    assert_eq!(big.len(), 20001);
    assert!(big
        .iter()
        .all(|s| matches!(s.name, pacer::registry::SlotName::Element { .. })));
    assert_eq!(big[12345].name.text(), "BIG&(12345)");
    assert_values(&run, &[("G(2,3)", 0.0), ("BIG&(20000)", 4.0)]);
}

/// `[run] seed` starts RND with `RANDOMIZE seed`: two runs with one seed print the same
/// numbers, another seed others, and no seed QuickBASIC's first number.
#[test]
fn rnd_follows_the_scenario_seed() {
    let program = "X = RND\nY = RND\nEND\n";
    let with = |seed: Option<u64>| {
        let scenario = seed.map(|s| format!("[run]\nseed = {s}\n"));
        let run = run_loaded(load_mb("rnd", program, scenario.as_deref()));
        (val(&run, "X"), val(&run, "Y"))
    };
    let (a, b, c, none) = (with(Some(7)), with(Some(7)), with(Some(8)), with(None));
    assert_eq!(a, b);
    assert_ne!(a, c);
    assert_ne!(a.0, a.1);
    assert!((0.0..1.0).contains(&a.0) && (0.0..1.0).contains(&c.1));
    assert_eq!(none.0 as f32, 0.705_547_5);
}

/// READ past the last DATA item is Microsoft BASIC's "Out of DATA", at the READ.
#[test]
fn out_of_data_is_an_error_at_the_read() {
    let e = run_err("out-of-data", "DATA 1\nREAD A\nREAD B\n");
    assert_eq!(e.line, 3);
    assert!(e.message.starts_with("Out of DATA"), "{}", e.message);
}

/// `STATUSSV` and `READ_SV` with right arguments are read on a quick path (a registration loop
/// polls them every scan); anything else takes the full one, which does it or says what is
/// wrong, at the line of the call. ORMEC's REGIST note: STATUSSV(axis), READ_SV(axis, var),
/// WRITE_SV(axis, var, value).
#[test]
fn polled_kernel_functions_read_the_axis_and_refuse_what_is_wrong_at_their_line() {
    use pacer::devices::regist::SWITCH_DEFAULT;
    let run = run_ok(
        "poll-values",
        "N& = 1\nS& = STATUSSV(N&)\nD& = READ_SV(N&, 24)\nW = WRITE_SV(N&, 24, 5)\n\
         R& = READ_SV(N&, 24)\nB& = READ_SV(1, 11)\nK& = STATUSSV(2)\n",
    );
    assert_values(
        &run,
        &[
            ("S&", 0.0),
            ("D&", f64::from(SWITCH_DEFAULT)),
            ("W", -1.0),
            ("R&", 5.0),
            ("B&", 0.0),
            ("K&", 0.0),
        ],
    );
    for (name, program, line, says) in [
        (
            "poll-axis",
            "N& = 3\nS& = STATUSSV(N&)\n",
            2,
            "axis 3 is not a DSP axis",
        ),
        (
            "poll-frac",
            "A = 1.5\nS& = STATUSSV(A)\n",
            2,
            "axis 1.5 is not a DSP axis",
        ),
        (
            "poll-var",
            "V& = 12\nX = READ_SV(1, V&)\n",
            2,
            "servo variable 12",
        ),
        (
            "poll-varfrac",
            "V = 9.5\nX = READ_SV(1, V)\n",
            2,
            "9.5 is not a servo variable",
        ),
        (
            "poll-varneg",
            "V = -1\nX = READ_SV(1, V)\n",
            2,
            "-1 is not a servo variable",
        ),
        (
            "poll-axis-sv",
            "N& = 7\nX = READ_SV(N&, 9)\n",
            2,
            "axis 7 is not a DSP axis",
        ),
    ] {
        let e = run_err(name, program);
        assert_eq!(e.line, line, "{name}: {}", e.message);
        assert!(e.message.contains(says), "{name}: {}", e.message);
        let function = if program.contains("STATUSSV") {
            "STATUSSV"
        } else {
            "READ_SV"
        };
        assert!(e.message.starts_with(function), "{name}: {}", e.message);
    }
}

#[test]
fn on_gosub_computes_its_selector_once() {
    // `ON n GOSUB` picks by `n` computed once (Microsoft BASIC's ON … GOSUB, as
    // spec/basic-language.md restates it): `RND` in it draws one number per `ON`, so a pick of
    // three is uniform and the same as drawing first and testing after. (Computed once per
    // case, it drew up to three numbers: 10,022 / 6,601 / 4,458 of 30,000.)
    let on = "FOR I& = 1 TO 3000
  ON INT(RND(1) * 3) + 1 GOSUB 10, 20, 30
NEXT
END
10 A& = A& + 1: RETURN
20 B& = B& + 1: RETURN
30 C& = C& + 1: RETURN
";
    let drawn = "FOR I& = 1 TO 3000
  K& = INT(RND(1) * 3) + 1
  IF K& = 1 THEN GOSUB 10
  IF K& = 2 THEN GOSUB 20
  IF K& = 3 THEN GOSUB 30
NEXT
END
10 A& = A& + 1: RETURN
20 B& = B& + 1: RETURN
30 C& = C& + 1: RETURN
";
    let (on, drawn) = (run_ok("on-rnd", on), run_ok("on-drawn", drawn));
    let counts = |run: &Run| [val(run, "A&"), val(run, "B&"), val(run, "C&")];
    assert_eq!(counts(&on), counts(&drawn));
    assert_eq!(counts(&on).iter().sum::<f64>(), 3000.0);
    for n in counts(&on) {
        assert!((850.0..1150.0).contains(&n), "{:?}", counts(&on));
    }
}

#[test]
fn a_single_line_if_may_hold_another_and_an_else_belongs_to_the_nearest() {
    // Microsoft BASIC (GW-BASIC reference, IF statement: "IF...THEN...ELSE statements may be
    // nested"; an ELSE goes with the nearest IF without one): `ELSE IF` chains on one line, and
    // an IF in a THEN part.
    let run = run_ok(
        "inline-if",
        "FOR X& = 0 TO 3
  IF X& = 1 THEN A& = 1 ELSE IF X& = 2 THEN A& = 2 ELSE A& = 3
  IF X& > 0 THEN IF X& > 1 THEN B& = 5 ELSE B& = 6
  IF X& > 0 THEN IF X& > 2 THEN C& = 7 ELSE C& = 8 ELSE C& = 9
  S& = S& + 1000 * A& + 100 * B& + 10 * C&: IF X& = 0 THEN Z& = C&
NEXT
",
    );
    // A& 3, 1, 2, 3; B& 0, 6, 5, 5; C& 9, 8, 8, 7.
    assert_values(
        &run,
        &[
            ("A&", 3.0),
            ("B&", 5.0),
            ("C&", 7.0),
            ("Z&", 9.0),
            ("S&", 9000.0 + 1600.0 + 320.0),
        ],
    );
}

/// A QuickBASIC `ELSEIF` chain at its longest (each ELSEIF nests one level deeper in the tree,
/// 256 levels in all: the FOR around it, the IF, 253 ELSEIFs, the FOR inside the last) with a
/// block in every branch checks, compiles and runs on a test thread's
/// stack, and picks the branch of the first true condition.
#[test]
fn a_longest_elseif_chain_runs_and_picks_the_first_true_branch() {
    let mut program = String::from("N& = 0\nFOR X& = 0 TO 300\nIF X& = 0 THEN\nN& = N& + 1\n");
    for k in 1..254 {
        program += &format!("ELSEIF X& = {k} THEN\nFOR I% = 1 TO {k}\nN& = N& + 1\nNEXT\n");
    }
    program += "ELSEIF X& < 1000 THEN\nN& = N& + 100000\nELSE\nN& = -1\nEND IF\nNEXT\n";
    let run = run_ok("elseif_chain", &program);
    // Branch k adds k (branch 0 adds 1), the 47 values past 253 add 100000 each.
    let want = 1.0 + (1..254).sum::<i64>() as f64 + 47.0 * 100000.0;
    assert_values(&run, &[("N&", want)]);
    // One more ELSEIF is refused at its line, not by a stack overflow.
    let longer = program.replacen(
        "ELSEIF X& < 1000",
        "ELSEIF X& = 254 THEN\nN& = 0\nELSEIF X& < 1000",
        1,
    );
    let p = one_error("elseif_too_long", &longer);
    assert_eq!(p.code, "pacer::syntax::nesting");
    assert!(
        p.message.contains("nested deeper than 256"),
        "{}",
        p.message
    );
}
