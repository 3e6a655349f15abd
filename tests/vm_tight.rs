//! Loops whose whole body is one instruction (an empty `FOR … NEXT`, a `FOR` storing one
//! element subscripted by its variable) of at least 16 iterations run outside the interpreter
//! (`vm::tight`) when nothing they write is traced, and every iteration through the
//! interpreter when the trace is on. Both ways give the same values, faults and instruction
//! counts as the build before (7cc5e93), whose figures these are: fills up and down by whole
//! steps, of long, INTEGER and real elements (a -0 kept in a real), loops too short to leave the
//! interpreter, a subscript that is not the variable, a real loop variable (the interpreter's
//! way), yields at a budget of 7 (a loop resumed outside the interpreter at each turn), an
//! INTEGER loop variable stepping past 32767, a fill past its array, a step of 0.

mod common;

use common::{load_memory, run_loaded, slot_value};
use pacer::load::Loaded;
use pacer::trace::Trace;
use pacer::vm::{Machine, RunSummary};

const PROGRAM: &str = "DIM F%(400), G(300), H&(50)
FOR J& = 0 TO 400 STEP 3
  F%(J&) = J& * 2
NEXT
FOR K& = 1 TO 300
NEXT
FOR X = 0.5 TO 100 STEP 0.25
  G(X) = X
NEXT
FOR J& = 400 TO 200 STEP -1
  F%(J&) = 7
NEXT
B& = -5
FOR J& = 120 TO 300 STEP 2
  F%(J&) = B&
NEXT
R = -0.0
FOR J& = 30 TO 90
  G(J&) = R
NEXT
FOR J& = 0 TO 50
  H&(J&) = J& * J&
NEXT
FOR J& = 0 TO 50
  H&(J&) = J&
NEXT
FOR J& = 0 TO 30
  H&(J& MOD 6) = J&
NEXT
K& = 3
FOR J& = 0 TO 50
  H&(K&) = J&
NEXT
FOR J& = 1 TO 5
  F%(J&) = 2
NEXT
FOR I% = 1 TO 100
  F%(I%) = 9
NEXT
S = 0
FOR J& = 0 TO 400
  S = S + F%(J&) * (J& + 1)
NEXT
FOR J& = 0 TO 300
  S = S + G(J&) * (J& + 3)
NEXT
FOR J& = 0 TO 50
  S = S + H&(J&) * (J& + 5)
NEXT
PRINT S, J&, K&, H&(3), H&(50), F%(5), F%(150), F%(399), G(29), G(95), I%
FOR I% = 32700 TO 32767
NEXT
";

fn load(name: &str, program: &str, budget: u32) -> Loaded {
    let machine = format!(
        "[machine]\nname = \"e\"\nbudget = {budget}\n\n[[program]]\nnumber = 0\nfile = \"x.mb\"\n"
    );
    match load_memory(name, &[("x.mb", program), ("machine.toml", &machine)]) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    }
}

/// Run without a trace (the way `pacer run` runs without `--trace`).
fn run_untraced(loaded: Loaded) -> (Machine, RunSummary) {
    let tick = loaded.image.tick_ns;
    let mut machine = Machine::new(loaded.image, Trace::new(None, tick));
    let summary = machine.run_observed(None, &mut |_| {});
    (machine, summary)
}

#[track_caller]
fn value(machine: &Machine, name: &str) -> f64 {
    machine
        .value_of(name)
        .or_else(|| slot_value(machine, name))
        .unwrap_or_else(|| panic!("no `{name}`"))
}

#[test]
fn loops_of_one_instruction_give_the_values_faults_and_counts_traced_or_not() {
    for budget in [7, 10_000] {
        let traced = run_loaded(load("tight-traced", PROGRAM, budget));
        let (machine, summary) = run_untraced(load("tight-untraced", PROGRAM, budget));
        // Traced, every loop runs in the interpreter; untraced, the seven long enough ones
        // (the empty ones of 300 and 68 iterations, the fills of 201, 91, 61, 51 and 100)
        // outside it, once each, or at each turn they take at a budget of 7; and the six
        // whose one statement reads or stores elements otherwise (`vm::body`: the squares, the
        // fills at `J& MOD 6` and at `K&`, the three sums).
        assert_eq!(traced.machine.tight_runs(), 0);
        if budget == 10_000 {
            assert_eq!(machine.tight_runs(), 7 + 6);
        } else {
            assert!(machine.tight_runs() > 100, "{}", machine.tight_runs());
        }
        for (machine, summary) in [(&traced.machine, &traced.summary), (&machine, &summary)] {
            assert_eq!(summary.instructions, 8937, "budget {budget}");
            let error = summary.error.as_ref().expect("the INTEGER loop overflows");
            assert_eq!(error.line, 51);
            assert!(
                error.message.starts_with("Overflow: 32768 does not fit I%"),
                "{}",
                error.message
            );
            for (name, want) in [
                ("S", 1_259_418.5),
                ("J&", 51.0),
                ("K&", 3.0),
                ("H&(3)", 50.0),
                ("H&(50)", 50.0),
                ("F%(5)", 9.0),
                ("F%(150)", -5.0),
                ("F%(399)", 7.0),
                ("G(29)", 29.25),
                ("G(95)", 95.25),
                ("I%", 32767.0),
            ] {
                assert_eq!(value(machine, name), want, "{name}, budget {budget}");
            }
            // A -0 stored into a real element stays -0.
            assert!(value(machine, "G(40)").is_sign_negative());
        }
    }
}

#[test]
fn a_fill_past_its_array_faults_at_the_element_after_the_last_stored() {
    let program = "DIM F%(40)\nFOR J& = 0 TO 50\n  F%(J&) = 1\nNEXT\n";
    for budget in [7, 10_000] {
        let (machine, summary) = run_untraced(load("tight-range", program, budget));
        assert!(machine.tight_runs() > 0);
        let error = summary.error.as_ref().expect("out of range");
        assert_eq!(
            (error.line, error.message.as_str()),
            (3, "Subscript out of range: 41 is not within 0 to 40")
        );
        assert_eq!(summary.instructions, 87);
        assert_eq!(value(&machine, "J&"), 41.0);
        assert_eq!(value(&machine, "F%(40)"), 1.0);
    }
}

#[test]
fn a_loop_left_to_the_machine_with_a_step_of_0_faults_at_its_for() {
    let program = "S& = 0\nDIM F%(200)\nFOR J& = 1 TO 100 STEP S&\n  F%(J&) = 1\nNEXT\n";
    let (machine, summary) = run_untraced(load("tight-step", program, 10_000));
    assert_eq!(machine.tight_runs(), 0);
    let error = summary.error.as_ref().expect("a step of 0");
    assert_eq!(
        (error.line, error.column, error.message.as_str()),
        (3, 1, "For loop with a Step of 0 never ends")
    );
    assert_eq!(summary.instructions, 5);
    assert_eq!(value(&machine, "F%(1)"), 0.0);
}
