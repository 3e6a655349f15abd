//! Every comparison and logic form, in every code shape the compiler emits (value, If, Do While,
//! short-circuit AND/OR, NOT), gives the BASIC answer; fused stores round and overflow like plain
//! ones.

use pacer::load::{load, LoadRequest};
use pacer::trace::Trace;
use pacer::vm::Machine;

fn run(program: &str, vars: &[(&str, u8)]) -> (Machine, pacer::vm::RunSummary) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "pacer-vmops-{}-{:x}",
        std::process::id(),
        fxhash(program)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(dir.join("program0.pt"), program).expect("program");
    let mut machine = String::new();
    for (name, decimals) in vars {
        machine.push_str(&format!("[variables.{name}]\ndecimals = {decimals}\n"));
    }
    std::fs::write(dir.join("machine.toml"), machine).expect("machine");
    let loaded = match load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    }) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let _ = std::fs::remove_dir_all(&dir);
    let tick = loaded.image.tick_ns;
    let mut m = Machine::new(loaded.image, Trace::new(None, tick));
    let s = m.run(Some(1_000_000_000));
    (m, s)
}

fn fxhash(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    })
}

#[test]
fn comparisons_agree_in_every_shape() {
    let pairs = [
        (1.0, 2.0),
        (2.0, 1.0),
        (2.0, 2.0),
        (-1.5, -1.5),
        (-3.0, 0.0),
    ];
    type Op = (&'static str, fn(f64, f64) -> bool);
    let ops: [Op; 6] = [
        ("<", |a, b| a < b),
        ("<=", |a, b| a <= b),
        (">", |a, b| a > b),
        (">=", |a, b| a >= b),
        ("=", |a, b| a == b),
        ("<>", |a, b| a != b),
    ];
    for (a, b) in pairs {
        for (sym, f) in ops {
            // As a jump (If), a negated jump (If NOT), a value (Bit), and a loop condition.
            let program = format!(
                "Var.A = {a}\nVar.B = {b}\nVar.R = 0\nVar.N = 0\nVar.L = 0\n\
                 If Var.A {sym} Var.B Then\nVar.R = 1\nEndif\n\
                 If NOT (Var.A {sym} Var.B) Then\nVar.N = 1\nEndif\n\
                 Bit.1 = Var.A {sym} Var.B\n\
                 Do While Var.A {sym} Var.B AND Var.L < 3\nVar.L = Var.L + 1\nLoop\nEnd\n"
            );
            let (m, s) = run(
                &program,
                &[("A", 2), ("B", 2), ("R", 0), ("N", 0), ("L", 0)],
            );
            assert!(s.error.is_none(), "{:?}", s.error);
            let expect = f(a, b);
            assert_eq!(
                m.value_of("Var.R"),
                Some(f64::from(expect)),
                "If {a} {sym} {b}"
            );
            assert_eq!(
                m.value_of("Var.N"),
                Some(f64::from(!expect)),
                "If NOT {a} {sym} {b}"
            );
            assert_eq!(
                m.value_of("Bit.1"),
                Some(f64::from(expect)),
                "Bit = {a} {sym} {b}"
            );
            assert_eq!(
                m.value_of("Var.L"),
                Some(if expect { 3.0 } else { 0.0 }),
                "Do While {a} {sym} {b}"
            );
        }
    }
}

#[test]
fn and_or_xor_not_truth_tables_in_conditions_and_values() {
    for a in [false, true] {
        for b in [false, true] {
            let w = |x: bool| if x { "ON" } else { "OFF" };
            let program = format!(
                "Bit.1 = {}\nBit.2 = {}\n\
                 If Bit.1 AND Bit.2 Then\nVar.And = 1\nEndif\n\
                 If Bit.1 OR Bit.2 Then\nVar.Or = 1\nEndif\n\
                 If Bit.1 XOR Bit.2 Then\nVar.Xor = 1\nEndif\n\
                 If NOT Bit.1 OR Bit.2 Then\nVar.Imp = 1\nEndif\n\
                 If (Var.And = 0 AND Bit.1) OR (Bit.2 AND NOT Bit.1) Then\nVar.Mix = 1\nEndif\n\
                 Bit.3 = Bit.1 AND NOT Bit.2\nEnd\n",
                w(a),
                w(b)
            );
            let (m, s) = run(
                &program,
                &[("And", 0), ("Or", 0), ("Xor", 0), ("Imp", 0), ("Mix", 0)],
            );
            assert!(s.error.is_none(), "{:?}", s.error);
            let v = |n: &str| m.value_of(n).map(|x| x != 0.0);
            assert_eq!(v("Var.And"), Some(a && b));
            assert_eq!(v("Var.Or"), Some(a || b));
            assert_eq!(v("Var.Xor"), Some(a != b));
            assert_eq!(v("Var.Imp"), Some(!a || b));
            // (NOT (a AND b) AND a) OR (b AND NOT a) is a XOR b.
            assert_eq!(v("Var.Mix"), Some(a != b));
            assert_eq!(v("Bit.3"), Some(a && !b));
        }
    }
}

#[test]
fn the_skipped_side_of_or_still_faults_when_it_could() {
    // `1/Var.Z` could fail, so OR evaluates it even though the left side decides.
    let (_, s) = run(
        "Var.Z = 0\nIf Var.Z = 0 OR 1 / Var.Z > 1 Then\nVar.Z = 5\nEndif\nEnd\n",
        &[("Z", 0)],
    );
    let e = s.error.expect("division by zero is reported");
    assert_eq!((e.line, e.message.as_str()), (2, "division by zero"));
}

#[test]
fn fused_stores_round_and_overflow_like_plain_stores() {
    let (m, s) = run("Var.A = 0.5\nVar.B = Var.A + 0.005\nVar.C = Var.A * 3\nVar.D = 10 - Var.A\nVar.I = 7\nVar.I = Var.I / 2\nEnd\n", &[("A", 2), ("B", 2), ("C", 0), ("D", 1), ("I", 0)]);
    assert!(s.error.is_none(), "{:?}", s.error);
    assert_eq!(m.value_of("Var.B"), Some(0.51));
    assert_eq!(m.value_of("Var.C"), Some(2.0)); // 1.5 rounds half away from zero
    assert_eq!(m.value_of("Var.D"), Some(9.5));
    assert_eq!(m.value_of("Var.I"), Some(4.0)); // 3.5 → 4
    let (_, s) = run(
        "Var.X = 2000000000\nVar.X = Var.X + Var.X\nEnd\n",
        &[("X", 0)],
    );
    let e = s.error.expect("overflow is reported");
    assert_eq!(e.line, 2);
    assert!(
        e.message.contains("overflow") && e.message.contains("Var.X"),
        "{}",
        e.message
    );
    let (_, s) = run("Var.X = 1\nVar.X = Var.X * 1000000000\nEnd\n", &[("X", 2)]);
    assert!(s
        .error
        .expect("overflow")
        .message
        .contains("2 decimal places"));
}

#[test]
fn for_loops_count_both_ways_and_with_real_steps() {
    let program = "Var.S = 0\nFor Var.I = 10 To 1 Step -3\nVar.S = Var.S + Var.I\nNext\n\
                   Var.T = 0\nFor Var.J = 0 To 1 Step 0.25\nVar.T = Var.T + 1\nNext\n\
                   Var.U = 0\nFor Var.K = 5 To 1\nVar.U = 1\nNext\nEnd\n";
    let (m, s) = run(
        program,
        &[("S", 0), ("I", 0), ("T", 0), ("J", 2), ("U", 0), ("K", 0)],
    );
    assert!(s.error.is_none(), "{:?}", s.error);
    assert_eq!(m.value_of("Var.S"), Some(10.0 + 7.0 + 4.0 + 1.0));
    assert_eq!(m.value_of("Var.I"), Some(-2.0));
    assert_eq!(m.value_of("Var.T"), Some(5.0));
    assert_eq!(m.value_of("Var.J"), Some(1.25));
    assert_eq!(
        m.value_of("Var.U"),
        Some(0.0),
        "a loop whose start is past its end does not run"
    );
}
