//! The superinstructions of three and four instructions (`MulAddCheck`, `AddModLong`,
//! `AddModWhole`, `NotAndLong`, `NotAndWhole`), and PowerTools' `x - a MOD b` (`SubMod`) and
//! `dst = dst + a / b` (`DivAddFixed`), give what the instructions they replace give:
//! the values (negative, -0, fractions, past 32 bits), the faults (MOD by zero, an Overflow in
//! either half, a store that does not fit) at the same line, and the same instruction counts
//! against the budget. The expected figures are those of the build before these fusions.

mod common;

use common::{load_memory, run_error, run_loaded, slot_value, Run};
use pacer::compile::bytecode::Op;
use pacer::load::Loaded;

/// Load a machine running the MotionBASIC program `x.mb` (program 0) with the instruction
/// budget `budget`.
fn load_mb(name: &str, program: &str, budget: u32) -> Loaded {
    let machine = format!(
        "[machine]\nname = \"e\"\nbudget = {budget}\n\n[[program]]\nnumber = 0\nfile = \"x.mb\"\n"
    );
    match load_memory(name, &[("x.mb", program), ("machine.toml", &machine)]) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    }
}

/// Run a MotionBASIC program `x.mb` (program 0) with the instruction budget `budget`.
fn run_mb(name: &str, program: &str, budget: u32) -> Run {
    run_loaded(load_mb(name, program, budget))
}

/// The PowerTools variables of the programs below: whole ones, and `F` with 2 decimals.
const PT_VARS: &str = "[variables.A]\ndecimals = 0\n[variables.B]\ndecimals = 0\n[variables.H]\ndecimals = 0\n[variables.I]\ndecimals = 0\n[variables.F]\ndecimals = 2\n[variables.Z]\ndecimals = 0\n[variables.Y]\ndecimals = 0\n";

/// Run a PowerTools program with the instruction budget `budget`.
fn run_pt(name: &str, program: &str, budget: u32) -> Run {
    let machine = format!("[machine]\nname = \"e\"\nbudget = {budget}\n{PT_VARS}");
    match load_memory(
        name,
        &[("program0.pt", program), ("machine.toml", &machine)],
    ) {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    }
}

/// The value of a variable after the run (by its slot name; `Var.A` for PowerTools).
#[track_caller]
fn val(run: &Run, name: &str) -> f64 {
    run.machine
        .value_of(name)
        .or_else(|| slot_value(&run.machine, name))
        .unwrap_or_else(|| panic!("no `{name}`"))
}

const MB_LOOP: &str = "A& = 12345\nH& = 7\nB& = 0\nR = 0\nFOR I& = 1 TO 20\n  A& = (A& * 75 + 74) MOD 65537\n  B& = (NOT A&) AND 65535\n  C& = 65535 AND NOT A&\n  H& = (H& + (B& OR (I& AND 1023))) MOD 1000003\n  G& = (A& + H&) MOD 7\n  K& = (-A& - 3) MOD 5\n  M& = (A& * -3 + -7) MOD 10\nNEXT\nR = -0.0\nZ& = (R + 0) MOD 3\nZ2& = (0 + R) MOD 3\nF = 2.5\nY& = (F + 1) MOD 3\nY2& = (1 + F) MOD 2\nP = 4294967296.0\nW& = (P + 1) MOD 7\nV& = (NOT F) AND 255\nV2& = (NOT P) AND 255\nN& = -5\nN2& = (N& * 3 + 2) MOD 4\n";

#[test]
fn motionbasic_long_chains_give_the_values_of_their_instructions() {
    let run = run_mb("fused-mb-values", MB_LOOP, 10_000);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let want = [
        ("A&", 28919.0),
        ("B&", 36616.0),
        ("C&", 36616.0),
        ("H&", 658192.0),
        ("G&", 5.0),
        ("K&", -2.0),
        ("M&", -4.0),
        // -0 + 0 and 0 + -0 MOD 3: a long holds 0, not -0.
        ("Z&", 0.0),
        ("Z2&", 0.0),
        // 3.5 and 3.5 round to 4 (halves to even) before MOD.
        ("Y&", 1.0),
        ("Y2&", 0.0),
        // Past 32 bits: (2^32 + 1) MOD 7, NOT 2^32 AND 255.
        ("W&", 5.0),
        ("V&", 253.0),
        ("V2&", 255.0),
        ("N2&", -1.0),
    ];
    for (name, v) in want {
        let v: f64 = v;
        let got = val(&run, name);
        assert_eq!(got.to_bits(), v.to_bits(), "{name}: {got}, want {v}");
    }
    assert_eq!(run.summary.instructions, 803);
}

#[test]
fn motionbasic_faults_in_a_chain_are_those_of_its_instructions() {
    // MOD by zero in the `imod` after an `add`: the store is not reached.
    let run = run_mb(
        "fused-mb-mod0",
        "A& = 5\nB& = 0\nC& = 1\nC& = (A& + 1) MOD B&\nC& = 9\n",
        10_000,
    );
    assert_eq!(run_error(&run), (4, "MOD by zero".to_string()));
    assert_eq!(val(&run, "C&"), 1.0);
    assert_eq!(run.summary.instructions, 6);
    // The multiply half of `x * k + c` overflows.
    let run = run_mb(
        "fused-mb-ovf-mul",
        "A& = 100000\nC& = 1\nC& = A& * A& + 1\nC& = 9\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("Overflow: 10000000000 does not fit a long"),
        "{message}"
    );
    assert_eq!(run.summary.instructions, 4);
    // The add half overflows.
    let run = run_mb(
        "fused-mb-ovf-add",
        "A& = 2147483647\nC& = 1\nC& = A& * 1 + 1\nC& = 9\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("Overflow: 2147483648 does not fit"),
        "{message}"
    );
    assert_eq!(run.summary.instructions, 6);
    assert_eq!(val(&run, "C&"), 1.0);
    // A remainder that does not fit the long it is stored into.
    let run = run_mb(
        "fused-mb-ovf-store",
        "P = 4294967296.0\nC& = 1\nC& = (P + 0.5) MOD 4294967297.0\nC& = (P + 1) MOD 8589934592.0\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("Overflow: 4294967296 does not fit C&"),
        "{message}"
    );
    assert_eq!(run.summary.instructions, 5);
    // NOT of a value past 32 bits, ANDed with -1, does not fit a long.
    let run = run_mb(
        "fused-mb-ovf-not",
        "P = 4294967296.0\nC& = 1\nC& = (NOT P) AND -1\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("Overflow: -4294967297 does not fit C&"),
        "{message}"
    );
    assert_eq!(run.summary.instructions, 7);
}

const CHAIN_LOOP_MB: &str = "A& = 12345\nH& = 0\nFOR I& = 1 TO 50\n  A& = (A& * 75 + 74) MOD 65537\n  B& = (NOT A&) AND 65535\n  H& = (H& + (B& OR (I& AND 1023))) MOD 1000003\nNEXT\n";

#[test]
fn small_budgets_count_a_chain_as_its_instructions() {
    // A task yields at a `for.next` once it has run its budget: 15 instructions an iteration,
    // so a budget of 3 or 7 yields at every one, 20 at every second, 40 at every third.
    for (budget, ticks) in [(3, 50), (7, 50), (20, 26), (40, 17), (10_000, 1)] {
        let run = run_mb("fused-mb-budget", CHAIN_LOOP_MB, budget);
        assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
        assert_eq!(val(&run, "A&"), 8340.0);
        assert_eq!(val(&run, "H&"), 796359.0);
        assert_eq!(
            (run.summary.instructions, run.summary.ticks),
            (757, ticks),
            "budget {budget}"
        );
    }
}

const PT_LOOP: &str = "Var.A = 12345\nVar.H = 7\nFor Var.I = 1 To 20\n  Var.A = (Var.A * 75 + 74) MOD 65537\n  Var.B = (NOT Var.A) AND 65535\n  Var.Y = 65535 AND NOT Var.A\n  Var.H = (Var.H + (Var.B OR (Var.I AND 1023))) MOD 1000003\n  Var.Z = (-Var.A - 3) MOD 5\nNext\nVar.F = 2.5\nVar.Y = (Var.F + 1) MOD 3\nVar.Z = (1.25 + Var.F) MOD 2\nVar.B = (NOT Var.F) AND 255\nEnd\n";

#[test]
fn powertools_whole_chains_give_the_values_of_their_instructions() {
    let run = run_pt("fused-pt-values", PT_LOOP, 10_000);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_eq!(run.summary.instructions, 314);
    // `(2.5 + 1) MOD 3` is 0.5 and `(1.25 + 2.5) MOD 2` 1.75, rounded into whole variables;
    // `NOT 2.5` is `NOT 2` (halves to even).
    let want = [
        ("Var.A", 28919.0),
        ("Var.B", 253.0),
        ("Var.H", 658192.0),
        ("Var.I", 21.0),
        ("Var.F", 2.5),
        ("Var.Y", 1.0),
        ("Var.Z", 2.0),
    ];
    for (name, v) in want {
        assert_eq!(val(&run, name), v, "{name}");
    }
}

#[test]
fn powertools_faults_in_a_chain_are_those_of_its_instructions() {
    let run = run_pt(
        "fused-pt-mod0",
        "Var.A = 5\nVar.B = 0\nVar.H = 1\nVar.H = (Var.A + 1) MOD Var.B\nVar.H = 9\nEnd\n",
        10_000,
    );
    assert_eq!(run_error(&run), (4, "MOD by zero".to_string()));
    assert_eq!(val(&run, "Var.H"), 1.0);
    assert_eq!(run.summary.instructions, 5);
    let run = run_pt(
        "fused-pt-ovf",
        "Var.A = 2000000000\nVar.H = 1\nVar.H = (Var.A + Var.A) MOD 4000000001\nVar.H = 9\nEnd\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("overflow: 4000000000 does not fit Var.H"),
        "{message}"
    );
    assert_eq!(val(&run, "Var.H"), 1.0);
    assert_eq!(run.summary.instructions, 4);
}

const MB_ACCUMULATE: &str = "Q& = 5\nX& = 3\nA& = 1000\nZ = -0.0\nF = 2.5\nP = 4294967296.0\nFOR I& = 1 TO 30\n  A& = (A& * 75 + 74) MOD 65537\n  Q& = Q& + A& \\ 3\n  Q& = (A& - 70000) \\ 7 + Q&\n  X& = X& XOR (A& AND 255)\n  X& = (A& AND 4095) XOR X&\n  H& = (I& AND 1023) OR A&\n  H2& = A& OR (I& AND 7)\nNEXT\nR& = 0\nR& = R& + (-1) \\ 5\nR2& = 3\nR2& = R2& + F \\ 2\nX2& = 1\nX2& = X2& XOR (F AND 255)\nX3& = 7\nX3& = X3& XOR (P AND 4294967295.0)\nH3 = (F AND 3) OR P\nH4 = (P AND -1) OR 1\n";

#[test]
fn motionbasic_accumulating_chains_give_the_values_of_their_instructions() {
    // `Q& = Q& + A& \ 3` (`DivAddLong`), `X& = X& XOR (A& AND 255)` (`AndXorLong`), `(I& AND
    // 1023) OR A&` (`AndOr`), each with the temporary on either side.
    let run = run_mb("fused-mb-accumulate", MB_ACCUMULATE, 10_000);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let want = [
        ("Q&", 145501.0),
        ("X&", 771.0),
        ("H&", 5727.0),
        ("H2&", 5703.0),
        // 0 + (-1) \ 5: a -0 quotient, a long 0.
        ("R&", 0.0),
        // 2.5 \ 2 and 2.5 AND 255 take 2 (halves to even).
        ("R2&", 4.0),
        ("X2&", 3.0),
        // Past 32 bits: 2^32 AND 4294967295 is 0; a real keeps 2^32 + 2 and 2^32 + 1.
        ("X3&", 7.0),
        ("H3", 4294967298.0),
        ("H4", 4294967297.0),
    ];
    for (name, v) in want {
        let v: f64 = v;
        let got = val(&run, name);
        assert_eq!(got.to_bits(), v.to_bits(), "{name}: {got}, want {v}");
    }
    assert_eq!(run.summary.instructions, 849);
}

#[test]
fn motionbasic_faults_in_an_accumulating_chain_are_those_of_its_instructions() {
    // Division by zero in the `idiv`: the add and the store are not reached.
    let run = run_mb(
        "fused-mb-div0",
        "A& = 5\nB& = 0\nQ& = 1\nQ& = Q& + A& \\ B&\nQ& = 9\n",
        10_000,
    );
    assert_eq!(run_error(&run), (4, "division by zero".to_string()));
    assert_eq!(val(&run, "Q&"), 1.0);
    assert_eq!(run.summary.instructions, 4);
    // The sum does not fit the long it is stored into.
    let run = run_mb(
        "fused-mb-div-store",
        "A& = 2147483647\nQ& = 2147483647\nQ& = Q& + A& \\ 1\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("Overflow: 4294967294 does not fit Q&"),
        "{message}"
    );
    assert_eq!(val(&run, "Q&"), 2147483647.0);
    assert_eq!(run.summary.instructions, 5);
    // The one quotient that does not fit, and an operand past 32 bits.
    let run = run_mb(
        "fused-mb-div-quotient",
        "M& = -2147483647 - 1\nQ& = 0\nQ& = Q& + M& \\ -1\n",
        10_000,
    );
    assert_eq!(
        run_error(&run),
        (
            3,
            "Overflow: the quotient does not fit a long integer".to_string()
        )
    );
    assert_eq!(run.summary.instructions, 8);
    let run = run_mb(
        "fused-mb-div-operand",
        "P = 8589934592.0\nQ& = 0\nQ& = Q& + P \\ 1\n",
        10_000,
    );
    assert_eq!(
        run_error(&run),
        (
            3,
            "Overflow: an operand of \\ does not fit a long integer".to_string()
        )
    );
    assert_eq!(run.summary.instructions, 3);
    // An XOR past 32 bits does not fit the long.
    let run = run_mb(
        "fused-mb-xor-store",
        "P = 4294967296.0\nX& = 0\nX& = X& XOR (P AND -1)\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("Overflow: 4294967296 does not fit X&"),
        "{message}"
    );
    assert_eq!(run.summary.instructions, 7);
}

const MB_FILTER: &str = "B0 = 0.0675\nB1 = 0.135\nB2 = 0.0675\nA1 = -1.143\nA2 = 0.413\nU1 = 0\nU2 = 0\nY1 = 0\nY2 = 0\nS = 0\nFOR I& = 1 TO 40\n  IF (I& AND 7) < 4 THEN U = 1.5 ELSE U = -0.25\n  Y = B0 * U + B1 * U1 + B2 * U2 - A1 * Y1 - A2 * Y2\n  S = S - Y * 0.5\n  S = 0.25 * Y + S\n  U2 = U1\n  U1 = U\n  Y2 = Y1\n  Y1 = Y\nNEXT\n";

#[test]
fn real_multiply_accumulate_chains_give_the_values_of_their_instructions() {
    // A biquad's sum of products (`acc + p * q` and `acc - p * q` through a temporary, the
    // accumulator on either side): each product is rounded before it is added, as the two
    // instructions round it; no fused multiply-add.
    let run = run_mb("fused-mb-filter", MB_FILTER, 10_000);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let (b0, b1, b2, a1, a2) = (0.0675f64, 0.135f64, 0.0675f64, -1.143f64, 0.413f64);
    let (mut u1, mut u2, mut y1, mut y2, mut s) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for i in 1..=40 {
        let u = if (i & 7) < 4 { 1.5 } else { -0.25 };
        let y = b0 * u + b1 * u1 + b2 * u2 - a1 * y1 - a2 * y2;
        s -= y * 0.5;
        s += 0.25 * y;
        (u2, u1, y2, y1) = (u1, u, y1, y);
    }
    for (name, v) in [("Y", y1), ("S", s), ("U2", u2), ("Y2", y2)] {
        let got = val(&run, name);
        assert_eq!(got.to_bits(), v.to_bits(), "{name}: {got}, want {v}");
    }
    assert_eq!(run.summary.instructions, 1016);
}

#[test]
fn powertools_multiply_accumulate_chains_give_the_values_of_their_instructions() {
    let run = run_pt(
        "fused-pt-mac",
        "Var.A = 7\nVar.B = -3\nVar.H = 11\nVar.I = 5\nVar.F = 0.25\nFor Var.Z = 1 To 9\n  Var.F = Var.A * 0.13 + Var.F * 0.5 - Var.B * 0.07\n  Var.Y = Var.A * Var.B + Var.H * Var.I\nNext\nEnd\n",
        10_000,
    );
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    // Var.F keeps 2 decimals: each pass rounds 0.91 + F / 2 + 0.21 half away from zero, on
    // the decimal value (1.245 is 1.25): 1.25, 1.75, 2.00, 2.12, 2.18, 2.21, 2.23, 2.24, 2.24.
    assert_eq!(val(&run, "Var.F"), 2.24);
    assert_eq!(val(&run, "Var.Y"), 34.0);
    assert_eq!(run.summary.instructions, 92);
}

#[test]
fn a_multiply_accumulate_chain_that_overflows_faults_at_its_store() {
    // A sum or a difference of products that is not finite (`MulSumReal` either way).
    for sign in ['+', '-'] {
        let program = format!("A = 1E200\nB = 3\nY = 1\nY = B * B {sign} A * A\nY = 2\n");
        let run = run_mb("fused-mb-mac-inf", &program, 10_000);
        let (line, message) = run_error(&run);
        assert_eq!(line, 4);
        assert!(message.contains("not a finite number"), "{message}");
        assert_eq!(val(&run, "Y"), 1.0);
        assert_eq!(run.summary.instructions, 7);
    }
}

#[test]
fn a_multiply_add_with_the_product_second_gives_the_values_of_its_instructions() {
    // `c + a * b` whose sum is used by another operation (a real `R`, and a PowerTools
    // `(Chk + Acc * 3 + I) MOD m` into a whole variable, whose second add fuses with the `MOD`):
    // the product, then the sum, rounded as the two instructions round them.
    let run = run_mb(
        "fused-mb-muladd-commuted",
        "FOR I& = 1 TO 5\n  R = (0.1 + R * 0.7) * 2\nNEXT\nQ = 1E308\nQ = (-1E308 + Q * 10) * 1\n",
        10_000,
    );
    let mut r = 0.0f64;
    for _ in 0..5 {
        r = (0.1 + r * 0.7) * 2.0;
    }
    assert_eq!(val(&run, "R").to_bits(), r.to_bits());
    let (line, message) = run_error(&run);
    assert_eq!(line, 5);
    assert!(message.contains("not a finite number"), "{message}");
    assert_eq!(run.summary.instructions, 35);
    let run = run_pt(
        "fused-pt-muladd-commuted",
        "Var.A = 46341\nVar.H = 7\nFor Var.I = 1 To 5\n  Var.H = (Var.H + Var.A * 3 + Var.I) MOD 1000003\nNext\nEnd\n",
        10_000,
    );
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    // 7 + 139023 k + (1 + … + k), below the modulus for k = 5.
    assert_eq!(val(&run, "Var.H"), 695137.0);
    assert_eq!(run.summary.instructions, 32);
}

#[test]
fn chains_of_additions_and_subtractions_give_the_values_of_their_instructions() {
    // Reals through a temporary (`a + b - c` …, the temporary on either side of an add), each
    // step rounded as its instruction rounds it; and a PowerTools chain into a whole variable.
    let run = run_mb(
        "fused-mb-addsub",
        "A = 0.1\nB = 0.2\nC = 0.3\nD = 1E16\nFOR I& = 1 TO 7\n  Y = A + B - C\n  Z = A - B + C + D\n  W = D - A - B - C\n  V = C + (A + B)\n  U = A + B - C + D\n  A = A + 0.125\nNEXT\n",
        10_000,
    );
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let (mut a, b, c, d) = (0.1f64, 0.2f64, 0.3f64, 1e16f64);
    let (mut y, mut z, mut w, mut v, mut u) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for _ in 0..7 {
        y = a + b - c;
        z = a - b + c + d;
        w = d - a - b - c;
        v = c + (a + b);
        u = a + b - c + d;
        a += 0.125;
    }
    for (name, want) in [("Y", y), ("Z", z), ("W", w), ("V", v), ("U", u)] {
        let got = val(&run, name);
        assert_eq!(got.to_bits(), want.to_bits(), "{name}: {got}, want {want}");
    }
    assert_eq!(run.summary.instructions, 156);
    let run = run_pt(
        "fused-pt-addsub",
        "Var.A = 5\nVar.B = 7\nVar.F = 0.25\nVar.H = Var.A + Var.B + Var.F - 3\nVar.I = Var.A - Var.B - Var.F + 1\nEnd\n",
        10_000,
    );
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    // 9.25 and -1.25 rounded half away from zero into whole variables.
    assert_eq!(val(&run, "Var.H"), 9.0);
    assert_eq!(val(&run, "Var.I"), -1.0);
    assert_eq!(run.summary.instructions, 10);
}

/// PowerTools quotients and multiples: `(A - A MOD 3) / 3` summed, `I - A MOD 7`, a quotient
/// added to a variable of 2 decimals (rounded at every store) or 0 (fractions of eighths), a
/// real `MOD` and quotient into a variable of 1 decimal, then a division by zero in the first
/// half of a `DivAddFixed` and an overflow in its second. The expected figures are those of
/// the build before `SubMod` and `DivAddFixed` (3fdd2ab), which ran the instructions one by one.
#[test]
fn powertools_quotients_and_multiples_give_the_values_of_their_instructions() {
    let program = "Var.A = 12345\n\
        For Var.I = 1 To 20\n\
        \x20 Var.A = (Var.A * 75 + 74) MOD 65537\n\
        \x20 Var.Q = Var.Q + (Var.A - Var.A MOD 3) / 3\n\
        \x20 Var.Z = (Var.I - Var.A MOD 7) * 2\n\
        \x20 Var.F = Var.A / 7 + Var.F\n\
        \x20 Var.Y = Var.Y + (0 - Var.A) / 8\n\
        \x20 Var.G = (Var.F - Var.F MOD 0.75) / 0.25 + Var.G\n\
        Next\n\
        Var.B = 0\n\
        Var.H = 5\n\
        Var.H = Var.H + Var.A / Var.B\n\
        End\n";
    let machine = "[machine]\nname = \"e\"\nbudget = 10000\n\
        [variables.A]\n[variables.B]\n[variables.H]\n[variables.I]\n[variables.Q]\n\
        [variables.Z]\n[variables.Y]\n[variables.F]\ndecimals = 2\n[variables.G]\ndecimals = 1\n";
    let loaded = match load_memory(
        "fused-pt-quotients",
        &[("program0.pt", program), ("machine.toml", machine)],
    ) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let ops = &loaded.image.chunks[0].ops;
    let count = |f: fn(&Op) -> bool| ops.iter().filter(|op| f(op)).count();
    // `Var.Q + (Var.A - Var.A MOD 3) / 3` is chained (tested below).
    assert_eq!(count(|op| matches!(op, Op::SubMod { .. })), 2);
    assert_eq!(count(|op| matches!(op, Op::QuotAddFixed { .. })), 1);
    assert_eq!(count(|op| matches!(op, Op::DivAddFixed { .. })), 5);
    let run = run_loaded(loaded);
    assert_eq!(run_error(&run), (12, "division by zero".to_string()));
    assert_eq!(run.summary.instructions, 408);
    let want = [
        ("Var.A", 28919.0),
        ("Var.Q", 217547.0),
        ("Var.Z", 36.0),
        ("Var.F", 93237.72),
        ("Var.Y", -81584.0),
        ("Var.G", 4252089.0),
        ("Var.H", 5.0),
    ];
    for (name, v) in want {
        assert_eq!(val(&run, name), v, "{name}");
    }
    let run = run_pt(
        "fused-pt-quotient-overflow",
        "Var.A = 28919\nVar.H = 5\nVar.H = Var.A / 0.00001 + Var.H\nVar.H = 9\nEnd\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("overflow: 2891900005 does not fit Var.H"),
        "{message}"
    );
    assert_eq!(val(&run, "Var.H"), 5.0);
    assert_eq!(run.summary.instructions, 4);
}

/// The offset of an element of a two-subscript array (`A&(I&, J&)`: two subscripts, a
/// multiply, an add) is one instruction (`Offset2`) that counts as four: a table filled and
/// summed, subscripts rounded (halves to even, -0.5 to 0) and computed, then a first and a
/// second subscript out of range, each failing at its line with its message. The expected
/// figures are those of the build before `Offset2` (feebe13), which ran the four one by one.
#[test]
fn two_subscript_offsets_give_the_values_faults_and_counts_of_their_instructions() {
    let program = "DIM A&(3, 4)\nDIM R(2, 2)\n\
        FOR I& = 0 TO 3\n  FOR J& = 0 TO 4\n    A&(I&, J&) = I& * 10 + J&\n  NEXT\nNEXT\n\
        S& = 0\n\
        FOR I& = 0 TO 3\n  FOR J& = 0 TO 4\n    S& = S& + A&(I&, J&) * (J& + 1)\n  NEXT\nNEXT\n\
        X = 1.5\nY = 2.5\nR(X, Y) = 7.25\n\
        Q = R(2, 2) + A&(X, Y + 1) + A&(0, -0.5)\n\
        K& = 4\nE& = A&(3, K&)\n";
    for (last, instructions, message, offsets) in [
        (
            "Z& = A&(K&, 0)",
            530,
            "Subscript out of range: 4 is not within 0 to 3",
            6,
        ),
        (
            "Z& = A&(0, K& + 1)",
            533,
            "Subscript out of range: 5 is not within 0 to 4",
            5,
        ),
    ] {
        let source = format!("{program}PRINT S&, Q, E&\n{last}\n");
        let loaded = load_mb("fused-offsets", &source, 10_000);
        let ops = &loaded.image.chunks[0].ops;
        let fused = ops
            .iter()
            .filter(|op| matches!(op, Op::Offset2 { .. }))
            .count();
        // Every element whose second subscript is a variable or a constant: the two in the
        // loops, R(X, Y), R(2, 2), A&(3, K&) and `A&(K&, 0)`; where the second subscript is
        // computed (`Y + 1`, `-0.5`, `K& + 1`), its instructions keep the two apart.
        assert_eq!(fused, offsets, "{last}");
        let run = run_loaded(loaded);
        assert_eq!(run_error(&run), (21, message.to_string()), "{last}");
        assert_eq!(run.summary.instructions, instructions, "{last}");
        for (name, v) in [
            ("S&", 1060.0),
            ("Q", 31.25),
            ("E&", 34.0),
            ("A&(2,4)", 24.0),
        ] {
            assert_eq!(val(&run, name), v, "{name}");
        }
        assert_eq!(val(&run, "R(2,2)"), 7.25);
    }
}

/// A `store.idx` with the `for.next` after it (`StoreIdxNext`: an array filled, cleared or
/// copied in a one-line loop) gives the values, faults and counts of the two: longs, reals
/// and INTEGERs stored, a loop counting down, a budget of 7 that yields inside the loops, a
/// subscript out of range in the store half and an Overflow of the `for.next` (an INTEGER
/// counted past 32767), each at its line. The expected figures are those of the build before
/// the fusion (feebe13): the same instruction counts, updates and messages.
#[test]
fn array_stores_fused_with_their_next_give_the_values_faults_and_counts_of_both() {
    let run_at = |name: &str, program: &str| {
        let loaded = load_mb(name, program, 7);
        let fused = loaded.image.chunks[0]
            .ops
            .iter()
            .filter(|op| matches!(op, Op::StoreIdxNext { .. }))
            .count();
        (fused, run_loaded(loaded))
    };
    let (fused, run) = run_at(
        "fused-store-next",
        "DIM A&(10), R(4), K%(3)\n\
         FOR I& = 0 TO 10\n  A&(I&) = I& * 3\nNEXT\n\
         FOR I& = 0 TO 4\n  R(I&) = I& / 4\nNEXT\n\
         T& = 0\n\
         FOR I& = 10 TO 0 STEP -2\n  T& = T& + A&(I&)\n  A&(I&) = 0\nNEXT\n\
         FOR J% = 32765 TO 32767\n  K%(J% - 32765) = J%\nNEXT\n",
    );
    // All four loops end with a store into an element.
    assert_eq!(fused, 4);
    assert_eq!(
        run_error(&run),
        (
            13,
            "Overflow: 32768 does not fit J% (an integer: -32768 to 32767)".to_string()
        )
    );
    assert_eq!(run.summary.instructions, 120);
    for (name, v) in [
        ("T&", 90.0),
        ("A&(9)", 27.0),
        ("A&(10)", 0.0),
        ("A&(0)", 0.0),
        ("R(3)", 0.75),
        ("K%(2)", 32767.0),
        ("J%", 32767.0),
    ] {
        assert_eq!(val(&run, name), v, "{name}");
    }
    let (_, run) = run_at(
        "fused-store-next-range",
        "DIM A&(10)\nFOR I& = 5 TO 12\n  A&(I&) = I&\nNEXT\n",
    );
    assert_eq!(
        run_error(&run),
        (
            3,
            "Subscript out of range: 11 is not within 0 to 10".to_string()
        )
    );
    assert_eq!(run.summary.instructions, 17);
    assert_eq!(val(&run, "A&(10)"), 10.0);
    let (_, run) = run_at(
        "fused-store-next-overflow",
        "DIM A&(10)\nFOR I% = 32760 TO 32767 STEP 4\n  A&(I% - 32760) = I%\nNEXT\n",
    );
    assert_eq!(
        run_error(&run),
        (
            2,
            "Overflow: 32768 does not fit I% (an integer: -32768 to 32767)".to_string()
        )
    );
    assert_eq!(run.summary.instructions, 12);
    assert_eq!(val(&run, "A&(4)"), 32764.0);
}

/// A bit tested in a condition (`IF I& AND 4 THEN`, `WHILE (I& AND 16)`: `band` then `jump.f`,
/// `AndJump`) gives the values and counts of the two: both ways of each test, a real operand
/// rounded (2.5 AND I&: 2, halves to even), a loop variable stepped inside a `WHILE`, and a
/// budget of 9 that yields in between. The expected figures are those of the build before the
/// fusion (feebe13), whose trace of this program is byte-identical.
#[test]
fn bit_tests_fused_with_their_jump_give_the_values_and_counts_of_both() {
    let program = "S& = 0\nC& = 0\nD& = 0\nX = 2.5\n\
        FOR I& = 1 TO 40\n\
        \x20 IF I& AND 4 THEN C& = C& + 1 ELSE D& = D& + 1\n\
        \x20 IF (I& AND 3) OR S& THEN S& = S& + 1\n\
        \x20 IF X AND I& THEN S& = S& + 100\n\
        \x20 WHILE (I& AND 16)\n    I& = I& + 1\n  WEND\n\
        NEXT\n";
    let loaded = load_mb("fused-and-jump", program, 9);
    let fused = loaded.image.chunks[0]
        .ops
        .iter()
        .filter(|op| matches!(op, Op::AndJump { nonzero: false, .. }))
        .count();
    // Lines 6, 8 and 9; line 7's `AND` goes on into an `OR`.
    assert_eq!(fused, 3);
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_eq!(run.summary.instructions, 461);
    for (name, v) in [("S&", 1224.0), ("C&", 12.0), ("D&", 12.0), ("I&", 41.0)] {
        assert_eq!(val(&run, name), v, "{name}");
    }
}

/// A bit test compared with 0 (`IF (I& AND 4) <> 0`, `IF 0 = (I& AND 3)`, PowerTools `If
/// (Var.I AND 4) <> 0`) is fused as the truth test it is (`AndJump`): both ways of each test,
/// the zero on either side, a real operand rounded, two negative operands (-8 AND -3 = -8), a
/// `WHILE`, and a budget of 9 that yields in between. The expected figures are those of the
/// build before the fusion (e01efec), whose traces of both programs are byte-identical.
#[test]
fn bit_tests_compared_with_zero_fused_give_the_values_and_counts_of_both() {
    let program = "S& = 0\nC& = 0\nD& = 0\nX = 2.5\n\
        FOR I& = 1 TO 40\n\
        \x20 IF (I& AND 4) <> 0 THEN C& = C& + 1 ELSE D& = D& + 1\n\
        \x20 IF 0 = (I& AND 3) THEN S& = S& + 1\n\
        \x20 IF (X AND I&) = 0 THEN S& = S& + 100\n\
        \x20 WHILE (I& AND 16) <> 0\n    I& = I& + 1\n  WEND\n\
        NEXT\n\
        IF (-8 AND -3) <> 0 THEN S& = S& + 7\n";
    let loaded = load_mb("fused-and-zero", program, 9);
    let fused = loaded.image.chunks[0]
        .ops
        .iter()
        .filter(|op| matches!(op, Op::AndJump { .. }))
        .count();
    assert_eq!(fused, 5);
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_eq!(run.summary.instructions, 409);
    for (name, v) in [("S&", 1213.0), ("C&", 12.0), ("D&", 12.0), ("I&", 41.0)] {
        assert_eq!(val(&run, name), v, "{name}");
    }
    let program = "Var.Z = 0\nVar.Y = 0\nFor Var.I = 1 To 40\n\
        \x20 If (Var.I AND 4) <> 0 Then\n    Var.Y = Var.Y + 1\n  Endif\n\
        \x20 If (Var.I AND 3) = 0 Then\n    Var.Z = Var.Z + 1\n  Endif\n\
        Next\nEnd\n";
    let run = run_pt("fused-and-zero-pt", program, 9);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_eq!(run.summary.instructions, 237);
    assert_eq!(val(&run, "Var.Z"), 10.0);
    assert_eq!(val(&run, "Var.Y"), 20.0);
}

/// A three-subscript element and two-subscript ones whose later subscripts are computed
/// (`C(I&, 3 - J&, K& / 2)`): the last three instructions of each subscript after the first
/// (`subscr`, `mul`, `add`) are one `OffsetTail`. Values, the third subscript out of range at
/// its line, counts and yields (budget 11) are those of the build before (feebe13, whose
/// trace of this program is byte-identical).
#[test]
fn later_subscripts_fused_with_their_offset_give_the_values_faults_and_counts() {
    let program = "DIM C(2, 3, 4)\n\
        FOR I& = 0 TO 2\n  FOR J& = 0 TO 3\n    FOR K& = 0 TO 4\n\
        \x20     C(I&, J&, K&) = I& * 100 + J& * 10 + K& + C(I&, 3 - J&, K& / 2)\n\
        \x20   NEXT\n  NEXT\nNEXT\n\
        PRINT C(2, 3, 4), C(1, 0, 2)\nQ& = 5\nZ = C(1, 1, Q&)\n";
    let loaded = load_mb("fused-offset-tail", program, 11);
    let ops = &loaded.image.chunks[0].ops;
    let count = |f: fn(&Op) -> bool| ops.iter().filter(|op| f(op)).count();
    // The first two subscripts of `C(I&, J&, K&)` and of the three constant or variable ones
    // are adjacent (`Offset2`); every later subscript of the five elements is a tail (those
    // inside an `Offset2` too, for a jump there).
    assert_eq!(count(|op| matches!(op, Op::Offset2 { .. })), 4);
    assert_eq!(count(|op| matches!(op, Op::OffsetTail { .. })), 10);
    let run = run_loaded(loaded);
    assert_eq!(
        run_error(&run),
        (
            11,
            "Subscript out of range: 5 is not within 0 to 4".to_string()
        )
    );
    assert_eq!(run.summary.instructions, 1845);
    for (name, v) in [("C(2,3,4)", 436.0), ("C(1,0,2)", 102.0)] {
        assert_eq!(val(&run, name), v, "{name}");
    }
}

/// The PowerTools machine of [`chained_superinstructions_give_the_values_faults_and_counts`]:
/// whole variables, `F` with 2 decimals and `G` with 1.
const CHAIN_PT_VARS: &str = "[variables.A]\n[variables.B]\n[variables.H]\n[variables.I]\n[variables.Q]\n[variables.Z]\n[variables.Y]\n[variables.W]\n[variables.F]\ndecimals = 2\n[variables.G]\ndecimals = 1\n";

/// Load the PowerTools `program` on that machine, and count its instructions of each of the
/// chained kinds: `MulAddModWhole`, `QuotAddFixed`.
fn load_chain_pt(name: &str, program: &str) -> (Loaded, usize, usize) {
    let machine = format!("[machine]\nname = \"e\"\nbudget = 10000\n{CHAIN_PT_VARS}");
    let loaded = match load_memory(
        name,
        &[("program0.pt", program), ("machine.toml", &machine)],
    ) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let ops = &loaded.image.chunks[0].ops;
    let muls = ops
        .iter()
        .filter(|op| matches!(op, Op::MulAddModWhole { .. }))
        .count();
    let quots = ops
        .iter()
        .filter(|op| matches!(op, Op::QuotAddFixed { .. }))
        .count();
    (loaded, muls, quots)
}

/// Chained superinstructions (one that also does the work of the superinstruction after it,
/// reading that one's operands where it stays): `(a * b + x) MOD m` into a whole PowerTools
/// variable (`MulAddModWhole`) or a long (`MulAddCheckModLong`), and PowerTools' quotient `v +
/// (a - a MOD b) / b` (`QuotAddFixed`: one integer division where the operands are whole), give
/// the values, faults and instruction counts of the instructions they replace: negative
/// operands and divisors, products past 32 bits, fixed-point operands with decimals, the
/// divisor a variable, -2^31 / -1, MOD by zero, an Overflow in either half of a long's
/// multiply-add. The expected figures are those of the build before chaining (9ab26a7), which
/// ran the superinstructions one by one.
#[test]
fn chained_superinstructions_give_the_values_faults_and_counts() {
    let program = "Var.A = 12345\nVar.B = 40\nVar.F = 1.25\nFor Var.I = 1 To 30\n\
        \x20 Var.A = (Var.A * 75 + 74) MOD 65537\n\
        \x20 Var.Z = (Var.A * -3 + -7) MOD 10\n\
        \x20 Var.W = (Var.A * Var.A + Var.I) MOD 1000003\n\
        \x20 Var.Y = (Var.F * 3 + 1) MOD 4 + Var.Y\n\
        \x20 Var.Q = Var.Q + (Var.A - Var.A MOD 3) / 3\n\
        \x20 Var.H = Var.H + (Var.Z - Var.Z MOD -4) / -4\n\
        \x20 Var.H = (Var.A - Var.A MOD Var.B) / Var.B + Var.H\n\
        \x20 Var.G = Var.G + (Var.F - Var.F MOD 0.75) / 0.75\n\
        \x20 Var.F = Var.F + 0.37\n\
        \x20 Var.B = Var.B - 1\n\
        Next\nEnd\n";
    let (loaded, muls, quots) = load_chain_pt("chain-pt-values", program);
    assert_eq!((muls, quots), (2, 3));
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_eq!(run.summary.instructions, 1088);
    let want = [
        ("Var.A", 50111.0),
        ("Var.B", 10.0),
        ("Var.F", 12.35),
        ("Var.W", 104818.0),
        ("Var.Y", 59.0),
        ("Var.Q", 315625.0),
        ("Var.H", 42322.0),
        ("Var.G", 253.0),
        ("Var.Z", 0.0),
    ];
    for (name, v) in want {
        assert_eq!(val(&run, name), v, "{name}");
    }

    // Operands with decimals, a real addend, a quotient divided by another divisor (not fused).
    let program = "Var.F = 2.5\nVar.G = 0\nVar.A = 7\n\
        Var.G = Var.G + (Var.F - Var.F MOD 0.5) / 0.5\n\
        Var.Q = Var.Q + (Var.F - Var.F MOD 3) / 3\n\
        Var.Y = (Var.F * 2 + Var.F) MOD 3\n\
        Var.Z = (Var.A * 2 + 0.5) MOD 4\n\
        Var.W = (Var.A - Var.A MOD 2) / 3 + Var.W\n\
        End\n";
    let (loaded, muls, quots) = load_chain_pt("chain-pt-decimals", program);
    assert_eq!((muls, quots), (2, 2));
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_eq!(run.summary.instructions, 22);
    for (name, v) in [
        ("Var.G", 5.0),
        ("Var.Q", 0.0),
        ("Var.Y", 2.0),
        ("Var.Z", 3.0),
        ("Var.W", 2.0),
    ] {
        assert_eq!(val(&run, name), v, "{name}");
    }

    // Negative divisors in a variable, then -2^31 / -1 = 2^31, which does not fit.
    let program = "Var.Z = -2147483648\nVar.A = 2\nVar.B = -3\nVar.H = 0\n\
        Var.H = Var.H + (Var.A - Var.A MOD Var.B) / Var.B\n\
        Var.Y = Var.Y + (Var.Z - Var.Z MOD Var.B) / Var.B\n\
        Var.B = -1\n\
        Var.W = Var.W + (Var.A - Var.A MOD Var.B) / Var.B\n\
        Var.Q = 5\n\
        Var.Q = Var.Q + (Var.Z - Var.Z MOD Var.B) / Var.B\n\
        End\n";
    let (loaded, _, quots) = load_chain_pt("chain-pt-min", program);
    assert_eq!(quots, 4);
    let run = run_loaded(loaded);
    let (line, message) = run_error(&run);
    assert_eq!(line, 10);
    assert!(
        message.starts_with("overflow: 2147483653 does not fit Var.Q"),
        "{message}"
    );
    assert_eq!(run.summary.instructions, 25);
    for (name, v) in [
        ("Var.H", 0.0),
        ("Var.Y", 715827882.0),
        ("Var.W", -2.0),
        ("Var.Q", 5.0),
    ] {
        assert_eq!(val(&run, name), v, "{name}");
    }

    // A product past 32 bits, then MOD by zero in the second part.
    let program = "Var.A = 100000\nVar.H = 1\n\
        Var.H = (Var.A * Var.A + 1) MOD 3\n\
        Var.H = (Var.A * 21475 + 0) MOD 2147483647\n\
        Var.B = 0\n\
        Var.Q = (Var.A * 2 + 1) MOD Var.B\n\
        End\n";
    let (loaded, muls, _) = load_chain_pt("chain-pt-mod0", program);
    assert_eq!(muls, 3);
    let run = run_loaded(loaded);
    assert_eq!(run_error(&run), (6, "MOD by zero".to_string()));
    assert_eq!(run.summary.instructions, 12);
    assert_eq!(val(&run, "Var.H"), 16353.0);

    // MotionBASIC: `(a * b + c) MOD m` into longs, the divisor a variable running down to 0.
    let loop_mb = "A& = 12345\nB& = 7\nFOR I& = 1 TO 40\n\
        \x20 A& = (A& * 75 + 74) MOD 65537\n\
        \x20 Z& = (A& * -3 - 7) MOD 10\n\
        \x20 W& = (3 * A& + I&) MOD B&\n\
        \x20 V& = (A& * 2 + 0.5) MOD 3\n\
        \x20 U& = (I& + A& * 2) MOD 1000\n\
        \x20 B& = B& - 1 + (B& = 1) * -39\n\
        NEXT\n";
    let loaded = load_mb("chain-mb-values", loop_mb, 10_000);
    let chained = loaded.image.chunks[0]
        .ops
        .iter()
        .filter(|op| matches!(op, Op::MulAddCheckModLong { .. }))
        .count();
    assert_eq!(chained, 3);
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    assert_eq!(run.summary.instructions, 1647);
    for (name, v) in [
        ("A&", 46966.0),
        ("B&", 6.0),
        ("W&", 0.0),
        ("V&", 2.0),
        ("U&", 972.0),
        ("Z&", -5.0),
    ] {
        assert_eq!(val(&run, name), v, "{name}");
    }
    let run = run_mb(
        "chain-mb-mod0",
        &loop_mb.replace("B& = 7", "B& = 0"),
        10_000,
    );
    assert_eq!(run_error(&run), (6, "MOD by zero".to_string()));
    assert_eq!(run.summary.instructions, 25);
    assert_eq!(val(&run, "A&"), 8431.0);
    // An Overflow in the multiply, then in the add: the store is not reached.
    for (program, counted, past) in [
        (
            "A& = 100000\nC& = 1\nC& = (A& * A& + 1) MOD 7\n",
            4,
            "10000000000",
        ),
        (
            "A& = 2147483647\nC& = 1\nC& = (A& * 1 + 1) MOD 7\n",
            6,
            "2147483648",
        ),
    ] {
        let run = run_mb("chain-mb-overflow", program, 10_000);
        let (line, message) = run_error(&run);
        assert_eq!(line, 3);
        assert!(
            message.starts_with(&format!("Overflow: {past} does not fit a long")),
            "{message}"
        );
        assert_eq!(run.summary.instructions, counted);
        assert_eq!(val(&run, "C&"), 1.0);
    }
}

/// INTEGER (`%`) arithmetic: an `add`/`sub`/`mul` fused with its `chk.int` or its `store.i`,
/// an integer operator (`MOD`, `\`, `AND`, `OR`, `XOR`) fused with its `store.i`, all give
/// the values and instruction counts of their instructions (the figures of the build before
/// these fusions, e019472), at every budget.
#[test]
fn integer_chains_give_the_values_and_counts_of_their_instructions() {
    let program = "A% = 0\nB% = 1\nK% = 7\nX = 2.5\nFOR I& = 1 TO 30\n\
        \x20 C% = (A% + B%) MOD 10007\n  A% = B%\n  B% = C%\n\
        \x20 IF B% > 5000 THEN B% = B% - 5000\n\
        \x20 D% = A% * K% - B% * K%\n  E% = (A% AND 255) OR 4096\n\
        \x20 F% = A% \\ K% + (B% XOR 21845)\n  G% = X * 3 + I&\n  H% = -A%\n\
        \x20 M% = X * K%\n  Q% = A% \\ K%\n  R% = A% XOR B%\n  T% = A% - B%\n\
        \x20 U% = (A% - B%) AND 1023\n\
        \x20 S% = S% + (I& MOD 3) * 2\nNEXT\n";
    let loaded = load_mb("fused-int", program, 10_000);
    let ops = &loaded.image.chunks[0].ops;
    let count = |f: fn(&Op) -> bool| ops.iter().filter(|op| f(op)).count();
    let fused = [
        count(|op| matches!(op, Op::AddCheckInt { .. })),
        count(|op| matches!(op, Op::SubCheckInt { .. })),
        count(|op| matches!(op, Op::MulCheckInt { .. })),
        count(|op| matches!(op, Op::IntInt { .. })),
        count(|op| matches!(op, Op::AddInt { .. })),
        count(|op| matches!(op, Op::SubInt { .. })),
        count(|op| matches!(op, Op::MulInt { .. })),
    ];
    assert_eq!(fused, [1, 1, 2, 4, 3, 3, 1]);
    for (budget, ticks) in [(3, 30), (7, 30), (20, 30), (10_000, 1)] {
        let run = run_mb("fused-int", program, budget);
        assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
        assert_eq!(
            (run.summary.instructions, run.summary.ticks),
            (1341, ticks),
            "budget {budget}"
        );
        for (name, v) in [
            ("A%", 2040.0),
            ("B%", 1269.0),
            ("C%", 6269.0),
            ("D%", 5397.0),
            ("E%", 4344.0),
            ("F%", 21187.0),
            // 2.5 * 3 + 30 = 37.5, rounded half to even.
            ("G%", 38.0),
            ("H%", -2040.0),
            // 2.5 * 7 = 17.5, rounded half to even.
            ("M%", 18.0),
            ("Q%", 291.0),
            ("R%", 781.0),
            ("T%", 771.0),
            ("S%", 60.0),
            ("U%", 771.0),
        ] {
            assert_eq!(val(&run, name), v, "{name} at budget {budget}");
        }
    }
}

/// The faults of fused INTEGER arithmetic are those of its instructions, at the same place
/// and count: an Overflow in the `chk.int` half, in the `store.i` half (of a real product, of
/// an `AND` past 16 bits), `MOD` and `\` by zero in the first half (the store not reached).
#[test]
fn integer_chains_fault_where_their_instructions_do() {
    let cases = [
        (
            "A% = 32767\nB% = 1\nB% = (A% + B%) \\ 2\nB% = 9\n",
            "Overflow: 32768 does not fit an integer (-32768 to 32767)",
        ),
        (
            "X = 2.5\nB% = 1\nB% = X * 20000\nB% = 9\n",
            "Overflow: 50000 does not fit B% (an integer: -32768 to 32767)",
        ),
        (
            "A% = 7\nB% = 1\nZ% = 0\nB% = A% MOD Z%\nB% = 9\n",
            "MOD by zero",
        ),
        (
            "A% = 7\nB% = 1\nZ% = 0\nB% = A% \\ Z%\nB% = 9\n",
            "division by zero",
        ),
        (
            "L& = 100000\nB% = 1\nB% = L& AND 65535\nB% = 9\n",
            "Overflow: 34464 does not fit B% (an integer: -32768 to 32767)",
        ),
    ];
    for (program, want) in cases {
        let run = run_mb("fused-int-fault", program, 10_000);
        let (line, message) = run_error(&run);
        let last = program.lines().count() as u32 - 1;
        assert_eq!(line, last, "{program}");
        assert!(message.starts_with(want), "{message}");
        assert_eq!(val(&run, "B%"), 1.0, "{program}");
        // Three stores before it, and the instruction that faults.
        assert_eq!(run.summary.instructions, 4, "{program}");
    }
}

/// A string comparison, the `neg` of MotionBASIC's -1 and the jump on it run as one
/// instruction (`TextJump`): every comparison operator, both ways of a jump, comparisons
/// joined by `AND`/`OR` (not fused: their results are combined), `NOT`, `WHILE`, and the empty
/// string; values, counts and budget yields are those of the build before the fusion
/// (e019472).
#[test]
fn string_comparisons_fused_with_their_jump_give_the_values_and_counts_of_all() {
    let program = "DIM N$(5)\n\
        N$(0) = \"AB\": N$(1) = \"ABC\": N$(2) = \"B\": N$(3) = \"\": N$(4) = \"ab\"\n\
        FOR I& = 0 TO 49\n  K$ = N$(I& MOD 5)\n\
        \x20 IF K$ = \"ABC\" THEN C& = C& + 1\n\
        \x20 IF K$ < \"B\" AND K$ <> \"\" THEN D& = D& + 1\n\
        \x20 IF K$ >= \"AB\" OR K$ = \"\" THEN E& = E& + 1\n\
        \x20 IF NOT (K$ > \"a\") THEN F& = F& + 1\n\
        \x20 IF K$ <= \"AB\" THEN G& = G& + 1 ELSE G& = G& - 1\n\
        \x20 WHILE K$ <> \"\" AND LEN(K$) < 3: K$ = K$ + \"Z\": W& = W& + 1: WEND\n\
        \x20 IF K$ > \"B\" THEN H& = H& + 1\nNEXT\n";
    let loaded = load_mb("fused-text", program, 10_000);
    let fused = loaded.image.chunks[0]
        .ops
        .iter()
        .filter(|op| matches!(op, Op::TextJump { .. }))
        .count();
    assert_eq!(fused, 8);
    for (budget, ticks) in [(3, 90), (7, 90), (20, 61), (10_000, 1)] {
        let run = run_mb("fused-text", program, budget);
        assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
        assert_eq!(
            (run.summary.instructions, run.summary.ticks),
            (2555, ticks),
            "budget {budget}"
        );
        for (name, v) in [
            ("C&", 10.0),
            ("D&", 20.0),
            ("E&", 50.0),
            ("F&", 40.0),
            ("G&", -10.0),
            ("H&", 20.0),
            ("W&", 40.0),
        ] {
            assert_eq!(val(&run, name), v, "{name} at budget {budget}");
        }
    }
}

/// The string functions programs call most run as instructions of their own in the side
/// table (`LEN`, `ASC`, `VAL`, `INSTR` from the start, `LEFT$`, `RIGHT$`, `MID$` of two and
/// three arguments, `CHR$`, `STR$`), and two side-table instructions in a row as one call
/// (`ExtPair`). Values, counts and budget yields are those of the build before (1a8a6a4):
/// a non-ASCII character, an empty string found by `INSTR`, `STR$` of an INTEGER, a long, a
/// SINGLE and a DOUBLE, and the general functions (`UCASE$`, `SPACE$`, `HEX$`) among them.
#[test]
fn string_functions_of_their_own_and_in_pairs_give_the_values_and_counts_of_before() {
    let program = "DEFINT K\nW# = 7\n\
        S$ = \"K-1234/XY\": D$ = CHR$(176) + \"C\" + STR$(-12)\n\
        FOR I& = 1 TO 12\n\
        \x20 C$ = CHR$(64 + I&) + LEFT$(S$, I& MOD 4) + RIGHT$(D$, I& MOD 5) + MID$(S$, I&)\n\
        \x20 L& = L& + LEN(C$) + LEN(D$) + ASC(C$) + ASC(D$)\n\
        \x20 P& = P& + INSTR(C$, \"/\") * 3 + INSTR(I& MOD 3 + 1, D$, \"C\") + INSTR(C$, \"\")\n\
        \x20 T = T + VAL(MID$(S$, 3, I& MOD 6)) + VAL(D$) + VAL(RIGHT$(D$, 3))\n\
        \x20 K = I& * 7: E$ = STR$(K) + STR$(I& / 4) + STR$(-I& * 1000000) + STR$(T / W#)\n\
        \x20 G$ = G$ + MID$(C$, 2, 1) + LEFT$(E$, 2)\n\
        \x20 U$ = UCASE$(LCASE$(C$)) + SPACE$(I& MOD 3) + HEX$(I& * 37)\n\
        \x20 H& = (H& * 31 + LEN(E$) + LEN(U$) + ASC(RIGHT$(G$, 1))) MOD 1000003\n\
        NEXT\n";
    let loaded = load_mb("own-text", program, 10_000);
    let chunk = &loaded.image.chunks[0];
    // A specialised instruction stands for another `Text` (`ExtOp::general`).
    let own = chunk.ext.iter().filter(|op| op.general() != **op).count();
    // All but INSTR from a start, UCASE$, LCASE$, SPACE$ and HEX$.
    assert_eq!(own, 27);
    let pairs = chunk
        .ops
        .iter()
        .filter(|op| matches!(op, Op::ExtPair { .. }))
        .count();
    assert_eq!(pairs, 18);
    // Each listed as the `text` instruction it stands for.
    let listing =
        pacer::compile::disasm::disassemble(chunk, &loaded.layout, &loaded.image.registry);
    for line in [
        "text      t0 <- LEN(C$)",
        "text      t0 <- INSTR(C$, \"/\")",
        "text      t0 <- MID$(S$, 3, t0) (cell 17)",
        "text      t1 <- MID$(S$, I&) (cell 14)",
        "text      t0 <- STR$(K%) (cell 19)",
        "text      t1 <- INSTR(t1, D$, \"C\")",
    ] {
        assert!(listing.contains(line), "no `{line}` in\n{listing}");
    }
    for (budget, ticks) in [(3, 12), (7, 12), (20, 12), (10_000, 1)] {
        let run = run_mb("own-text", program, budget);
        assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
        assert_eq!(
            (run.summary.instructions, run.summary.ticks),
            (1672, ticks),
            "budget {budget}"
        );
        for (name, v) in [
            ("L&", 3116.0),
            ("P&", 208.0),
            ("T", 5064.0),
            ("H&", 895664.0),
        ] {
            assert_eq!(val(&run, name), v, "{name} at budget {budget}");
        }
        let text = |name: &str| {
            let slot = slot_value(&run.machine, name).unwrap_or_else(|| panic!("no {name}"));
            run.machine.strings()[slot as usize].clone()
        };
        assert_eq!(text("E$"), " 84 3-12000000 723.4285714285714");
        assert_eq!(text("U$"), "L121BC");
        assert_eq!(text("G$"), "K 7K 1K 2C 2K 3K 4K 4- 5K 6K 7K 71 8");
    }
}

/// A fault in either instruction of an `ExtPair` is where that instruction is, counted as
/// when they ran one by one, the string stored before left as it was (figures of 1a8a6a4).
#[test]
fn string_instructions_in_pairs_fault_where_each_is() {
    let cases = [
        // The second of the pair (LEFT$, MID$) faults; then the first of (MID$, LEFT$).
        (
            "C$ = LEFT$(B$, 1) + MID$(B$, 0)",
            21,
            13,
            "Illegal function call: MID$ takes a start",
        ),
        (
            "C$ = MID$(B$, 0) + LEFT$(B$, 1)",
            6,
            10,
            "Illegal function call: MID$ takes a start",
        ),
        // The join after a LEFT$ in its pair.
        (
            "C$ = A$ + LEFT$(A$, 100)",
            6,
            11,
            "String too long: a string holds at most 255",
        ),
        (
            "C& = LEN(C$) + ASC(E$)",
            16,
            11,
            "Illegal function call: ASC of an empty string",
        ),
        (
            "C$ = RIGHT$(B$, 1) + CHR$(256)",
            22,
            12,
            "Illegal function call: CHR$ takes a code",
        ),
        (
            "C& = INSTR(B$, \"Y\") + INSTR(0, B$, \"Y\")",
            23,
            14,
            "Illegal function call: INSTR",
        ),
    ];
    for (line, column, count, want) in cases {
        let program = format!(
            "A$ = STRING$(200, \"A\"): B$ = \"XY\": E$ = \"\"\nC$ = \"Q\"\n{line}\nC$ = \"Z\"\n"
        );
        let run = run_mb("pair-fault", &program, 10_000);
        let e = run.summary.error.as_ref().expect("a fault");
        assert_eq!((e.line, e.column), (3, column), "{line}: {}", e.message);
        assert!(e.message.starts_with(want), "{line}: {}", e.message);
        assert_eq!(run.summary.instructions, count, "{line}");
        let slot = slot_value(&run.machine, "C$").unwrap_or(-1.0);
        assert_eq!(run.machine.strings()[slot as usize], "Q", "{line}");
    }
}

/// `Y = Y + (A - B) * K` (`SubMul`, then `AddReal`), `Z = K * (A + B) + 1` (`AddMul` with the
/// sum second), `Q = A / B` and `R = (A - B) / (A + B)` (`DivReal`).
const MB_SCALED: &str = "A = 3.5: B = 1.25: K = 0.05: Y = 0.5\nY = Y + (A - B) * K\nZ = K * (A + B) + 1\nQ = A / B\nR = (A - B) / (A + B)\n";

#[test]
fn scaled_sums_and_real_quotients_give_the_values_faults_and_counts_of_their_instructions() {
    let (a, b, k): (f64, f64, f64) = (3.5, 1.25, 0.05);
    let want = [
        ("Y", 0.5 + (a - b) * k),
        ("Z", k * (a + b) + 1.0),
        ("Q", a / b),
        ("R", (a - b) / (a + b)),
    ];
    // The same values whatever the budget cuts the run into: a pair counts as two.
    for budget in [10_000, 1, 2, 3, 5] {
        let run = run_mb("fused-scaled", MB_SCALED, budget);
        assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
        for (name, v) in want {
            let got = val(&run, name);
            assert_eq!(got.to_bits(), v.to_bits(), "{name}: {got}, want {v}");
        }
        // 4 stores, 4 + 4 + 2 + 4 instructions, `end` (`pacer disasm` of the program).
        assert_eq!(run.summary.instructions, 19, "budget {budget}");
    }
    // A division by zero faults at the division, before its store: `Q` keeps its value.
    let run = run_mb(
        "fused-div0",
        &format!("{MB_SCALED}Z0 = 0\nQ = B / Z0\n"),
        10_000,
    );
    assert_eq!(run_error(&run), (7, "division by zero".to_string()));
    assert_eq!(val(&run, "Q"), a / b);
    assert_eq!(run.summary.instructions, 20);
    // A quotient past the largest double faults at the store, naming the variable.
    let run = run_mb(
        "fused-div-inf",
        "A# = 1D300\nQ = 1\nQ = A# / 1D-300\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("Q cannot take inf: the result is not a finite number"),
        "{message}"
    );
    assert_eq!(val(&run, "Q"), 1.0);
    assert_eq!(run.summary.instructions, 4);
}

#[test]
fn a_product_summed_and_stored_gives_the_values_faults_and_counts_of_its_three_instructions() {
    // A first-order filter (`F = F * K1 + X * K2`), the accumulator on either side, and a
    // product taken away (`G = G * K1 - X * K2`): `mul`, `add`/`sub` and `store.r` are one
    // instruction, the product rounded before the sum as the three round it.
    let program = "F = 0: G = 1: H = 0\nFOR I& = 1 TO 30\n  M& = I& MOD 7\n  F = F * 0.875 + M& * 0.125\n  G = G * 0.5 - M& * 0.3\n  H = M& * 0.1 + H * 0.9\nNEXT\n";
    let loaded = load_mb("fused-filter-store", program, 7);
    let fused = |want: fn(&Op) -> bool| {
        loaded.image.chunks[0]
            .ops
            .iter()
            .filter(|op| want(op))
            .count()
    };
    let sums = |minus: bool| {
        fused(if minus {
            |op| matches!(op, Op::MulSumReal { minus: true, .. })
        } else {
            |op| matches!(op, Op::MulSumReal { minus: false, .. })
        })
    };
    assert_eq!((sums(false), sums(true)), (2, 1));
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let (mut f, mut g, mut h) = (0.0f64, 1.0f64, 0.0f64);
    for i in 1..=30i64 {
        let m = (i % 7) as f64;
        f = f * 0.875 + m * 0.125;
        g = g * 0.5 - m * 0.3;
        h = m * 0.1 + h * 0.9;
    }
    for (name, v) in [("F", f), ("G", g), ("H", h)] {
        let got = val(&run, name);
        assert_eq!(got.to_bits(), v.to_bits(), "{name}: {got}, want {v}");
    }
    // 3 stores and the FOR's 4 before the loop, 30 iterations of 2 + 3 * 4 + 1 instructions,
    // the END.
    assert_eq!(run.summary.instructions, 7 + 30 * 15 + 1);
}

#[test]
fn a_stored_sum_of_products_gives_the_values_faults_and_counts_of_its_instructions() {
    // Sums of three and four terms (`fuse_sums`): products, a variable added or taken away
    // anywhere, all summed in the instructions' order; one instruction each.
    let program = "A = 0.3: B = -1.7: C = 2.5: D = 0.125: E = -3.25\nX# = 1.1\nFOR I& = 1 TO 25\n  X# = X# * 1.01\n  Y = A * X# + B * C - D * E + E * X#\n  Z = X# + A * B - C + D * E\n  W# = A * B - X# * X# - C\nNEXT\n";
    let (a, b, c, d, e) = (0.3f64, -1.7f64, 2.5f64, 0.125f64, -3.25f64);
    let (mut x, mut y, mut z, mut w) = (1.1f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..25 {
        x *= 1.01;
        y = a * x + b * c - d * e + e * x;
        z = x + a * b - c + d * e;
        w = a * b - x * x - c;
    }
    let loaded = load_mb("fused-sums", program, 7);
    let sums = loaded.image.chunks[0]
        .ops
        .iter()
        .filter(|op| matches!(op, Op::SumReal { .. }))
        .count();
    assert_eq!(sums, 3);
    // The same values whatever the budget cuts the run into: a sum counts as its
    // instructions.
    for budget in [10_000, 1, 2, 3, 7] {
        let run = run_mb("fused-sums", program, budget);
        assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
        for (name, v) in [("X#", x), ("Y", y), ("Z", z), ("W#", w)] {
            let got = val(&run, name);
            assert_eq!(got.to_bits(), v.to_bits(), "{name}: {got}, want {v}");
        }
        // 8 before the loop, the FOR's 4, 25 iterations of 2 + 8 + 6 + 5 + 1, the END
        // (`pacer disasm` of the program).
        assert_eq!(
            run.summary.instructions,
            8 + 4 + 25 * 22 + 1,
            "budget {budget}"
        );
    }
    // A sum past the largest double faults at its store, naming the variable, after all its
    // instructions; the variable keeps its value.
    let run = run_mb(
        "fused-sum-inf",
        "A# = 1D300\nY = 1\nY = A# * A# + A# * 2 + 3 * A#\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(
        message.starts_with("Y cannot take inf: the result is not a finite number"),
        "{message}"
    );
    assert_eq!(val(&run, "Y"), 1.0);
    assert_eq!(run.summary.instructions, 2 + 6);
    // Infinities taken from each other: not a number.
    let run = run_mb(
        "fused-sum-nan",
        "A# = 1D300\nY = 1\nY = A# * A# - A# * A# - 1\n",
        10_000,
    );
    let (line, message) = run_error(&run);
    assert_eq!(line, 3);
    assert!(message.starts_with("Y cannot take NaN"), "{message}");
    assert_eq!(val(&run, "Y"), 1.0);
}

#[test]
fn random_sums_give_the_values_and_faults_of_their_instructions_summed_in_order() {
    // 400 sums of 3 to 8 terms drawn at random (a fixed seed): products of two variables or
    // a variable alone, added or taken away, among values with a -0, a tenth and 1e200 (whose
    // products overflow). Each is the left-to-right IEEE sum of its terms, to the bit, or,
    // not finite, a fault at its line naming its variable.
    let values = [1.5, -2.25, 0.1, -0.0, 1e200, 7.0, -3.0e-5];
    let names = ["V0", "V1", "V2", "V3", "V4", "V5", "V6"];
    let mut setup = String::new();
    for (name, v) in names.iter().zip(values) {
        // `-0.0` is the negation of 0: the variable holds -0.
        setup.push_str(&format!("{name} = {v:?}\n"));
    }
    let mut seed: u64 = 0x5EED_0F5A_u64;
    let mut next = |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n as u64) as usize
    };
    let mut fused = 0;
    for case in 0..400 {
        let count = 3 + next(6);
        let mut text = String::new();
        let mut sum = 0.0f64;
        for t in 0..count {
            let minus = t > 0 && next(2) == 1;
            let product = t == 0 || next(3) > 0;
            let (i, j) = (next(names.len()), next(names.len()));
            let x = if product {
                values[i] * values[j]
            } else {
                values[i]
            };
            if t > 0 {
                text.push_str(if minus { " - " } else { " + " });
            }
            if product {
                text.push_str(&format!("{} * {}", names[i], names[j]));
            } else {
                text.push_str(names[i]);
            }
            sum = if t == 0 {
                x
            } else if minus {
                sum - x
            } else {
                sum + x
            };
        }
        let program = format!("{setup}Y = 0.5\nY = {text}\n");
        let loaded = load_mb("fused-random-sum", &program, 10_000);
        fused += loaded.image.chunks[0]
            .ops
            .iter()
            .filter(|op| matches!(op, Op::SumReal { .. }))
            .count();
        let run = run_loaded(loaded);
        if sum.is_finite() {
            assert!(
                run.summary.error.is_none(),
                "case {case}: {:?}\n{program}",
                run.summary.error
            );
            let got = val(&run, "Y");
            assert_eq!(
                got.to_bits(),
                sum.to_bits(),
                "case {case}: {got}, want {sum}\n{program}"
            );
        } else {
            let (line, message) = run_error(&run);
            assert_eq!(line, names.len() as u32 + 2, "case {case}\n{program}");
            assert!(
                message.starts_with("Y cannot take"),
                "case {case}: {message}"
            );
            assert_eq!(val(&run, "Y"), 0.5, "case {case}");
        }
    }
    // Most of them are sums the interpreter runs as one instruction.
    assert!(fused > 300, "{fused} of 400 fused");
}
