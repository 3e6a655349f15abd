//! Loops whose whole body is one instruction (an empty `FOR … NEXT`, a `FOR` storing one
//! element subscripted by its variable) run their plain iterations with the variable in a
//! register (`vm::tight`) when nothing is traced, and every iteration through the interpreter
//! when the trace is on. Both ways give the same values, faults and instruction counts as the
//! build before (9ab26a7), whose figures these are: fills up and down by whole steps, of long,
//! INTEGER and real elements (a -0 kept in a real, made 0 in an INTEGER), a subscript that is
//! not the variable, a real loop variable (the interpreter's way), yields at a budget of 7, and
//! an INTEGER loop variable stepping past 32767.

mod common;

use common::{load_memory, run_loaded, slot_value};
use pacer::load::Loaded;
use pacer::trace::Trace;
use pacer::vm::{Machine, RunSummary};

const PROGRAM: &str = "DIM F%(40), G(30), H&(5)
FOR J& = 0 TO 40 STEP 3
  F%(J&) = J& * 2
NEXT
FOR K& = 1 TO 30
NEXT
FOR X = 0.5 TO 10 STEP 0.25
  G(X) = X
NEXT
FOR J& = 10 TO 0 STEP -1
  F%(J&) = 7
NEXT
B& = -5
FOR J& = 12 TO 30 STEP 2
  F%(J&) = B&
NEXT
R = -0.0
FOR J& = 3 TO 9
  G(J&) = R
NEXT
FOR J& = 0 TO 30
  H&(J& MOD 6) = J&
NEXT
K& = 3
FOR J& = 0 TO 5
  H&(K&) = J&
NEXT
S = 0
FOR J& = 0 TO 40
  S = S + F%(J&) * (J& + 1)
NEXT
FOR J& = 0 TO 30
  S = S + G(J&) * (J& + 3)
NEXT
FOR I% = 32760 TO 32767
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
        for (machine, summary) in [(&traced.machine, &traced.summary), (&machine, &summary)] {
            assert_eq!(summary.instructions, 931, "budget {budget}");
            let error = summary.error.as_ref().expect("the INTEGER loop overflows");
            assert_eq!(error.line, 35);
            assert!(
                error.message.starts_with("Overflow: 32768 does not fit I%"),
                "{}",
                error.message
            );
            for (name, want) in [
                ("S", 10455.0),
                ("J&", 31.0),
                ("K&", 3.0),
                ("H&(0)", 30.0),
                ("H&(3)", 5.0),
                ("H&(5)", 29.0),
                ("F%(12)", -5.0),
                ("F%(39)", 78.0),
                ("G(10)", 10.0),
                ("I%", 32767.0),
            ] {
                assert_eq!(value(machine, name), want, "{name}, budget {budget}");
            }
            // A -0 stored into a real element stays -0.
            assert!(value(machine, "G(5)").is_sign_negative());
        }
    }
}

#[test]
fn a_fill_past_its_array_faults_at_the_element_after_the_last_stored() {
    let program = "DIM F%(40)\nFOR J& = 0 TO 50\n  F%(J&) = 1\nNEXT\n";
    for budget in [7, 10_000] {
        let (machine, summary) = run_untraced(load("tight-range", program, budget));
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
