//! Integer operators whose operands are sure to be whole numbers within 32 bits (longs,
//! INTEGERs, PowerTools variables without decimals, whole constants, what an integer operator
//! or a long's overflow check just wrote) take them without the test every other operand gets
//! (`src/compile/whole.rs`). The two ways must give the same value for every operand: the
//! programs below compute each operator both ways, the second with a quarter added to each
//! operand through a real variable (`R`, `Var.F`), which the operator rounds away, over
//! operands at the edges of 32 bits. A fraction taken for sure would be truncated instead
//! (wrong for negatives), and test builds assert, at each untested operand, that it is whole
//! and within 32 bits: both catch an operand wrongly taken for sure.

mod common;

use common::{load_memory, run_error, run_loaded, slot_value};
use pacer::compile::bytecode::Op;
use pacer::compile::whole::{PLAIN, SURE, WIDE};
use pacer::load::Loaded;

/// Edge operands: zero, small, the 16-bit and 32-bit edges, the MOD constants of real
/// programs.
const EDGES: &str = "DATA 0, 1, -1, 2, -2, 3, -3, 7, -7, 255, 1023, 32767, -32768, 65535, 65536, -65537, 1000003, -1000003, 2147483647, -2147483647, -2147483648";
const EDGE_COUNT: u32 = 21;

fn machine(file: &str, extra: &str) -> String {
    format!("[machine]\nname = \"sure\"\nbudget = 100000\n\n[[program]]\nnumber = 0\nfile = \"{file}\"\n{extra}")
}

/// A MotionBASIC program `x.mb`, loaded.
fn load_mb(name: &str, program: &str) -> Loaded {
    match load_memory(
        name,
        &[("x.mb", program), ("machine.toml", &machine("x.mb", ""))],
    ) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    }
}

#[test]
fn motionbasic_integer_operators_give_the_same_values_sure_or_tested() {
    let program = format!(
        "{EDGES}
DIM V&({n})
FOR K& = 1 TO {n}
  READ V&(K&)
NEXT
R = 0.25
R2 = -0.75
R3 = 2.75
R4 = 6.5
BAD& = 0
PAIRS& = 0
FOR I& = 1 TO {n}
  FOR J& = 1 TO {n}
    A& = V&(I&)
    B& = V&(J&)
    PAIRS& = PAIRS& + 1
    IF (A& AND B&) <> ((A& + R) AND (B& + R)) THEN BAD& = BAD& + 1
    IF (A& OR B&) <> ((A& + R) OR (B& + R)) THEN BAD& = BAD& + 1
    IF (A& XOR B&) <> ((A& + R) XOR (B& + R)) THEN BAD& = BAD& + 1
    C& = (NOT A&) AND B&
    D& = (NOT (A& + R)) AND (B& + R)
    IF C& <> D& THEN BAD& = BAD& + 1
    ' Reals as operands, rounded (halves to even): -1, 3, 6.
    IF (A& AND R2) <> (A& AND -1) THEN BAD& = BAD& + 1
    IF (R2 OR B&) <> (-1 OR B&) THEN BAD& = BAD& + 1
    IF (NOT R2) <> (NOT -1) THEN BAD& = BAD& + 1
    IF (A& MOD R3) <> (A& MOD 3) THEN BAD& = BAD& + 1
    IF (A& \\ R3) <> (A& \\ 3) THEN BAD& = BAD& + 1
    ' A MOD of a sum (whole, perhaps past 32 bits: the sum of a long and an OR is not
    ' checked) by a sure divisor.
    IF (A& + (B& OR 0)) MOD 1000003 <> (A& + R + (B& OR 0)) MOD 1000003 THEN BAD& = BAD& + 1
    H& = (H& + (A& AND B&)) MOD 65537
    G& = (G& + ((A& + R) AND (B& + R))) MOD 65537
    X& = X& XOR (A& AND B&)
    Y& = Y& XOR ((A& + R) AND (B& + R))
    IF B& <> 0 THEN
      C& = A& MOD B&
      D& = (A& + R) MOD (B& + R)
      IF C& <> D& THEN BAD& = BAD& + 1
      IF (R4 MOD B&) <> (6 MOD B&) THEN BAD& = BAD& + 1
      IF (R4 \\ B&) <> (6 \\ B&) THEN BAD& = BAD& + 1
      IF A& <> -2147483648 OR B& <> -1 THEN
        C& = A& \\ B&
        D& = (A& + R) \\ (B& + R)
        IF C& <> D& THEN BAD& = BAD& + 1
        S& = B& \\ 3 + (A& \\ B&) \\ 2
        T& = (B& + R) \\ 3 + ((A& + R) \\ (B& + R)) \\ 2
        IF S& <> T& THEN BAD& = BAD& + 1
      END IF
    END IF
  NEXT
NEXT
",
        n = EDGE_COUNT
    );
    let loaded = load_mb("sure-mb", &program);
    // Both ways are there: some integer instructions untested, some tested.
    let chunk = &loaded.image.chunks[0];
    let flags: Vec<u8> = chunk
        .ops
        .iter()
        .zip(&chunk.sure)
        .filter(|(op, _)| integer_reading(op))
        .map(|(_, &s)| s)
        .collect();
    assert!(
        flags.iter().filter(|&&s| s & SURE != 0).count() >= 8,
        "{flags:?}"
    );
    assert!(
        flags.iter().filter(|&&s| s == WIDE).count() >= 2,
        "{flags:?}"
    );
    assert!(flags.iter().filter(|&&s| s == 0).count() >= 8, "{flags:?}");
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let value = |name: &str| run.machine.value_of(name);
    assert_eq!(value("PAIRS&"), Some(f64::from(EDGE_COUNT * EDGE_COUNT)));
    assert_eq!(value("BAD&"), Some(0.0));
    assert_eq!(value("X&"), value("Y&"));
    assert_eq!(value("H&"), value("G&"));
}

#[test]
fn known_values_of_the_untested_way() {
    // MOD keeps the sign of the dividend, `\` truncates toward zero (MotionBASIC manual,
    // "Arithmetic operators"; Microsoft BASIC), NOT is the 32-bit complement.
    let program = "A& = -7\nB& = 3\nM& = A& MOD B&\nQ& = A& \\ B&\nN& = NOT A&\nC& = -2147483648\nE& = C& MOD -1\nF& = (C& AND 65535) OR 7\nG& = 7 MOD -2147483648\nH& = -1 \\ 2\n";
    let run = run_loaded(load_mb("sure-known", program));
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    for (name, want) in [
        ("M&", -1.0_f64),
        ("Q&", -2.0),
        ("N&", 6.0),
        ("E&", 0.0),
        ("F&", 7.0),
        ("G&", 7.0),
        ("H&", 0.0),
    ] {
        let got = run.machine.value_of(name);
        assert_eq!(
            got.map(f64::to_bits),
            Some(want.to_bits()),
            "{name}: {got:?}"
        );
    }
}

#[test]
fn an_untested_division_by_zero_still_fails_at_its_line() {
    let program = "A& = 7\nB& = 0\nC& = A& MOD B&\n";
    let run = run_loaded(load_mb("sure-zero", program));
    let e = run.summary.error.as_ref().expect("MOD by zero fails");
    assert_eq!(e.line, 3);
    assert!(e.message.contains("MOD by zero"), "{}", e.message);
}

#[test]
fn powertools_whole_variables_give_the_same_values_sure_or_tested() {
    // `Var.F`, `Var.G` and `Var.H` have 2 decimals: operands through them are tested. The
    // bitwise operators round away `Var.F`'s quarter and round `Var.H` to -1; PowerTools `MOD`
    // is a real remainder, so it gets `Var.G`'s zero.
    let vars = "[variables.A]\n[variables.B]\n[variables.C]\n[variables.D]\n[variables.K]\n[variables.BAD]\n[variables.F]\ndecimals = 2\n[variables.G]\ndecimals = 2\n[variables.H]\ndecimals = 2\n";
    let mut program = String::from("Var.BAD = 0\nVar.F = 0.25\nVar.G = 0\nVar.H = -0.75\n");
    let values = [0, 1, -1, 7, -7, 65535, -65537, 2147483647, -2147483647];
    for a in values {
        for b in values {
            program.push_str(&format!(
                "Var.A = {a}\nVar.B = {b}\nVar.K = Var.K + 1\n\
                 Var.C = Var.A AND Var.B\nVar.D = (Var.A + Var.F) AND (Var.B + Var.F)\n\
                 If Var.C <> Var.D Then\n  Var.BAD = Var.BAD + 1\nEndif\n\
                 Var.C = Var.A AND -1\nVar.D = Var.A AND Var.H\n\
                 If Var.C <> Var.D Then\n  Var.BAD = Var.BAD + 1\nEndif\n\
                 Var.C = (Var.A + Var.B) MOD 65537\nVar.D = (Var.A + Var.B + Var.G) MOD 65537\n\
                 If Var.C <> Var.D Then\n  Var.BAD = Var.BAD + 1\nEndif\n\
                 Var.C = Var.A XOR (Var.B OR 255)\nVar.D = (Var.A + Var.F) XOR ((Var.B + Var.F) OR 255)\n\
                 If Var.C <> Var.D Then\n  Var.BAD = Var.BAD + 1\nEndif\n"
            ));
            if b != 0 {
                program.push_str(
                    "Var.C = Var.A MOD Var.B\nVar.D = (Var.A + Var.G) MOD (Var.B + Var.G)\n\
                     If Var.C <> Var.D Then\n  Var.BAD = Var.BAD + 1\nEndif\n",
                );
            }
        }
    }
    program.push_str("End\n");
    let machine = format!("[machine]\nname = \"sure\"\nbudget = 100000\n{vars}");
    let loaded = match load_memory(
        "sure-pt",
        &[("program0.pt", &program), ("machine.toml", &machine)],
    ) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let chunk = &loaded.image.chunks[0];
    let sure = chunk
        .ops
        .iter()
        .zip(&chunk.sure)
        .filter(|(op, &s)| integer_reading(op) && s & SURE != 0)
        .count();
    assert!(sure >= values.len() * values.len(), "{sure}");
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let k = (values.len() * values.len()) as f64;
    assert_eq!(run.machine.value_of("Var.K"), Some(k));
    assert_eq!(run.machine.value_of("Var.BAD"), Some(0.0));
}

/// An instruction that tests integer operands unless they are sure.
fn integer_reading(op: &Op) -> bool {
    matches!(
        op,
        Op::IMod { .. }
            | Op::IDiv { .. }
            | Op::Mod { .. }
            | Op::BitAnd { .. }
            | Op::BitOr { .. }
            | Op::BitXor { .. }
            | Op::BitNot { .. }
            | Op::ModLong { .. }
            | Op::IntLong { .. }
            | Op::AndLong { .. }
            | Op::OrLong { .. }
            | Op::XorLong { .. }
            | Op::ModWhole { .. }
            | Op::AndWhole { .. }
            | Op::OrWhole { .. }
            | Op::XorWhole { .. }
            | Op::NotAndLong { .. }
            | Op::NotAndWhole { .. }
            | Op::AndOr { .. }
            | Op::AndXorLong { .. }
            | Op::AndXorWhole { .. }
            | Op::DivAddLong { .. }
            | Op::SubMod { .. }
            | Op::AddModLong { .. }
            | Op::AddModWhole { .. }
    )
}

/// The error a MotionBASIC program ends with: its line and message.
fn mb_error(name: &str, program: &str) -> (u32, String) {
    let run = run_loaded(load_mb(name, program));
    run_error(&run)
}

#[test]
fn whole_stores_and_loops_overflow_as_tested_ones_do() {
    // A sum of longs past 32 bits, stored untested (only its range) and tested (through a
    // real zero).
    let sure = mb_error("sure-sum", "A& = 2147483646\nA& = A& + 1\nA& = A& + 1\n");
    let tested = mb_error(
        "tested-sum",
        "R = 0\nA& = 2147483646\nA& = A& + R + 1\nA& = A& + R + 1\n",
    );
    assert_eq!(sure.0, 3);
    assert_eq!(tested.0, 4);
    assert_eq!(sure.1, tested.1);
    assert!(sure.1.to_lowercase().contains("overflow"), "{}", sure.1);
    // A FOR of an INTEGER past 16 bits, by a whole step and by a real one.
    let sure = mb_error(
        "sure-for",
        "N& = 0\nFOR I% = 32760 TO 32767\n  N& = N& + 1\nNEXT\n",
    );
    let tested = mb_error(
        "tested-for",
        "N& = 0\nS = 1\nFOR I% = 32760 TO 32767 STEP S\n  N& = N& + 1\nNEXT\n",
    );
    assert_eq!(sure.1, tested.1);
    assert!(sure.1.to_lowercase().contains("overflow"), "{}", sure.1);
    // And of a long past 32 bits.
    let sure = mb_error(
        "sure-for-long",
        "FOR I& = 2147483640 TO 2147483647 STEP 4\nNEXT\n",
    );
    let tested = mb_error(
        "tested-for-long",
        "S = 4\nFOR I& = 2147483640 TO 2147483647 STEP S\nNEXT\n",
    );
    assert_eq!(sure.1, tested.1);
    assert!(sure.1.to_lowercase().contains("overflow"), "{}", sure.1);
}

#[test]
fn whole_loops_and_stores_count_as_tested_ones_do() {
    let program = "T& = 0\nK% = 0\nFOR I& = -5 TO 20 STEP 3\n  T& = T& + I& * 2 - 1\n  K% = K% + 1\nNEXT\nFOR J% = 10 TO -10 STEP -4\n  T& = T& - J%\n  K% = K% - 1\nNEXT\nDIM E&(3)\nE&(1) = T& + K%\n";
    let loaded = load_mb("sure-loops", program);
    // Both loops count untested; every long and INTEGER store of a sum is range-tested only.
    let chunk = &loaded.image.chunks[0];
    let flagged = |want: fn(&Op) -> bool| {
        chunk
            .ops
            .iter()
            .zip(&chunk.sure)
            .filter(|(op, _)| want(op))
            .map(|(_, &s)| s & SURE != 0)
            .collect::<Vec<bool>>()
    };
    assert_eq!(flagged(|op| matches!(op, Op::ForNext { .. })), [true, true]);
    let stores = flagged(|op| {
        matches!(
            op,
            Op::AddLong { .. } | Op::SubLong { .. } | Op::StoreLong { .. } | Op::StoreInt { .. }
        )
    });
    assert!(stores.len() >= 4 && stores.iter().all(|&s| s), "{stores:?}");
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    // I& = -5, -2, …, 19 (9 values, sum 63): T& = 2·63 − 9 = 117; J% = 10, 6, …, -10 (6
    // values, sum 0); K% = 9 − 6 = 3; past their ends I& = 22 and J% = -14.
    for (name, want) in [
        ("T&", 117.0),
        ("K%", 3.0),
        ("I&", 22.0),
        ("J%", -14.0),
        ("E&(1)", 120.0),
    ] {
        assert_eq!(slot_value(&run.machine, name), Some(want), "{name}");
    }
}

#[test]
fn copies_of_longs_are_stored_as_they_are() {
    // Euclid's GCD (1071, 462) = 21 by copies of longs; a copy of the most negative long; a
    // copy of a zero stays +0.
    let program = "X& = 1071\nY& = 462\nWHILE Y& <> 0\n  T& = X& MOD Y&\n  X& = Y&\n  Y& = T&\nWEND\nG& = X&\nA& = -2147483648\nB& = A&\nC& = -0\nD& = C&\nE& = 7\n";
    let loaded = load_mb("sure-copies", program);
    let chunk = &loaded.image.chunks[0];
    let plain = chunk
        .ops
        .iter()
        .zip(&chunk.sure)
        .filter(|(op, &f)| matches!(op, Op::StoreLong { .. }) && f & PLAIN != 0)
        .count();
    // X& <- Y&, Y& <- T&, G& <- X&, B& <- A&, D& <- C&, and the constants' stores.
    assert!(plain >= 5, "{plain}");
    let run = run_loaded(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    for (name, want) in [
        ("G&", 21.0_f64),
        ("B&", -2147483648.0),
        ("D&", 0.0),
        ("E&", 7.0),
    ] {
        let got = run.machine.value_of(name);
        assert_eq!(
            got.map(f64::to_bits),
            Some(want.to_bits()),
            "{name}: {got:?}"
        );
    }
}
