//! The deterministic runtime: round robin over tasks, blocking, Wait For, Wait For Time, program
//! initiation and calls, the instruction budget, run-time errors, fixed-point stores, Dwell and
//! Goto, each on a small machine written to a temporary folder.

use pacer::load::{load, LoadRequest};
use pacer::trace::Trace;
use pacer::vm::{Machine, RunSummary, StopReason};
use serde_json::Value;
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

// ---------------------------------------------------------------------------------------------
// helpers

/// A trace sink the test can read after the run.
#[derive(Clone, Default)]
struct SharedBuf(Arc<Mutex<Vec<u8>>>);

impl Write for SharedBuf {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

static COUNTER: AtomicUsize = AtomicUsize::new(0);

/// A fresh folder holding `machine.toml`, the programs and, if given, `scenario.toml`.
fn project(tag: &str, machine: &str, programs: &[(&str, &str)], scenario: Option<&str>) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::SeqCst);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "pacer-scheduling-{}-{}-{tag}",
        std::process::id(),
        n
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("machine.toml"), machine).unwrap();
    for (file, text) in programs {
        std::fs::write(dir.join(file), text).unwrap();
    }
    if let Some(s) = scenario {
        std::fs::write(dir.join("scenario.toml"), s).unwrap();
    }
    dir
}

struct Run {
    machine: Machine,
    summary: RunSummary,
    trace: Vec<Value>,
}

impl Run {
    fn value(&self, name: &str) -> f64 {
        self.machine
            .value_of(name)
            .unwrap_or_else(|| panic!("no member {name}"))
    }

    /// The updates at which a program wrote (or the kernel changed) `name`.
    fn change_ticks(&self, name: &str) -> Vec<u64> {
        self.trace
            .iter()
            .filter(|e| e["kind"] == "change" && e["name"] == name)
            .map(|e| e["tick"].as_u64().unwrap())
            .collect()
    }

    fn events(&self, kind: &str) -> Vec<&Value> {
        self.trace.iter().filter(|e| e["kind"] == kind).collect()
    }
}

/// Load the folder, run it for `seconds`, and parse the trace.
fn run_for(dir: &PathBuf, seconds: f64) -> Run {
    let req = LoadRequest {
        paths: vec![dir.clone()],
        machine: None,
        scenario: None,
    };
    let loaded = match load(&req) {
        Ok(l) => l,
        Err(d) => panic!("load failed:\n{}", d.render_plain()),
    };
    let _ = std::fs::remove_dir_all(dir);
    let tick_ns = loaded.image.tick_ns;
    let buf = SharedBuf::default();
    // These tests read a program's writes, in order, as a log.
    let mut trace = Trace::new(Some(Box::new(buf.clone())), tick_ns);
    trace.record_writes(true);
    let mut machine = Machine::new(loaded.image, trace);
    let duration_ns = (seconds * 1e9).round() as u64;
    let summary = machine.run(Some(duration_ns));
    machine.finish().unwrap();
    let bytes = buf.0.lock().unwrap().clone();
    let trace = String::from_utf8(bytes)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .collect();
    Run {
        machine,
        summary,
        trace,
    }
}

/// A machine file: `[machine]` settings, then one autostarted `[[program]]` per entry of
/// `autostart` (number, file, autostart), then variables (name, decimals).
fn machine_toml(settings: &str, programs: &[(u32, &str, bool)], vars: &[(&str, u8)]) -> String {
    let mut s = format!("[machine]\nupdate = \"1ms\"\n{settings}\n");
    for (n, f, a) in programs {
        s.push_str(&format!(
            "\n[[program]]\nnumber = {n}\nfile = \"{f}\"\nautostart = {a}\n"
        ));
    }
    for (v, d) in vars {
        s.push_str(&format!("\n[variables.{v}]\ndecimals = {d}\n"));
    }
    s
}

/// Counts one iteration per turn when the budget is 1: the backward jump at `Loop` yields.
const COUNT_A: &str = "Do While TRUE\n    Var.A = Var.A + 1\nLoop\n";
const COUNT_B: &str = "Do While TRUE\n    Var.B = Var.B + 1\nLoop\n";
const COUNT_C: &str = "Do While TRUE\n    Var.C = Var.C + 1\nLoop\n";

fn ms(n: u64) -> f64 {
    n as f64 / 1000.0
}

// ---------------------------------------------------------------------------------------------
// round robin

#[test]
fn round_robin_two_tasks_one_task_per_update() {
    let m = machine_toml(
        "budget = 1\ntasks = 2",
        &[(0, "a.pt", true), (1, "b.pt", true)],
        &[("A", 0), ("B", 0)],
    );
    let dir = project("rr2", &m, &[("a.pt", COUNT_A), ("b.pt", COUNT_B)], None);
    let r = run_for(&dir, ms(9));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.summary.ticks, 10);
    assert_eq!(r.change_ticks("Var.A"), [0, 2, 4, 6, 8]);
    assert_eq!(r.change_ticks("Var.B"), [1, 3, 5, 7, 9]);
    assert_eq!(r.value("Var.A"), 5.0);
    assert_eq!(r.value("Var.B"), 5.0);
    // Program 0 on task 0, program 1 on task 1.
    assert_eq!(r.value("Program.0.Task"), 0.0);
    assert_eq!(r.value("Program.1.Task"), 1.0);
}

#[test]
fn round_robin_three_tasks() {
    let m = machine_toml(
        "budget = 1\ntasks = 3",
        &[(0, "a.pt", true), (1, "b.pt", true), (2, "c.pt", true)],
        &[("A", 0), ("B", 0), ("C", 0)],
    );
    let dir = project(
        "rr3",
        &m,
        &[("a.pt", COUNT_A), ("b.pt", COUNT_B), ("c.pt", COUNT_C)],
        None,
    );
    let r = run_for(&dir, ms(9));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.change_ticks("Var.A"), [0, 3, 6, 9]);
    assert_eq!(r.change_ticks("Var.B"), [1, 4, 7]);
    assert_eq!(r.change_ticks("Var.C"), [2, 5, 8]);
}

#[test]
fn a_task_runs_until_it_blocks_within_its_update() {
    // With a large budget a task does everything up to its first block in one update.
    let m = machine_toml(
        "tasks = 2",
        &[(0, "a.pt", true), (1, "b.pt", true)],
        &[("A", 0), ("B", 0)],
    );
    let a = "Var.A = 1\nVar.A = 2\nVar.A = 3\nWait For Time 0.002\nVar.A = 4\n";
    let b = "Var.B = 1\nVar.B = 2\n";
    let dir = project("untilblock", &m, &[("a.pt", a), ("b.pt", b)], None);
    let r = run_for(&dir, ms(5));
    assert_eq!(r.change_ticks("Var.A"), [0, 0, 0, 2]);
    assert_eq!(r.change_ticks("Var.B"), [1, 1]);
    assert_eq!(r.value("Var.A"), 4.0);
}

#[test]
fn blocked_tasks_are_skipped() {
    let m = machine_toml(
        "budget = 1\ntasks = 3",
        &[(0, "a.pt", true), (1, "b.pt", true), (2, "c.pt", true)],
        &[("A", 0), ("B", 0), ("C", 0)],
    );
    let b = "Wait For Bit.1 = ON\nVar.B = 1\n";
    let dir = project(
        "skip",
        &m,
        &[("a.pt", COUNT_A), ("b.pt", b), ("c.pt", COUNT_C)],
        None,
    );
    let r = run_for(&dir, ms(9));
    assert_eq!(r.summary.error, None);
    // Update 1 is task 1's: it blocks. From then on tasks 0 and 2 share every update.
    assert_eq!(r.change_ticks("Var.A"), [0, 3, 5, 7, 9]);
    assert_eq!(r.change_ticks("Var.C"), [2, 4, 6, 8]);
    assert_eq!(r.value("Var.B"), 0.0);
    assert_eq!(r.value("Program.1.Running"), 1.0);
}

#[test]
fn sleeping_tasks_are_skipped_and_run_again_when_due() {
    let m = machine_toml(
        "budget = 1\ntasks = 2",
        &[(0, "a.pt", true), (1, "b.pt", true)],
        &[("A", 0), ("B", 0)],
    );
    let b = "Var.B = 1\nWait For Time 0.004\nVar.B = 2\n";
    let dir = project("sleep", &m, &[("a.pt", COUNT_A), ("b.pt", b)], None);
    let r = run_for(&dir, ms(9));
    // Task 1 runs at update 1, sleeps 4 updates (until update 5), and runs again at update 5:
    // task 0 had update 4, so task 1's turn comes first.
    assert_eq!(r.change_ticks("Var.B"), [1, 5]);
    assert_eq!(r.change_ticks("Var.A"), [0, 2, 3, 4, 6, 7, 8, 9]);
}

// ---------------------------------------------------------------------------------------------
// Wait For

#[test]
fn wait_for_is_evaluated_every_update_and_the_task_runs_at_its_next_turn() {
    // DriveInput.1 is ON during update 5 only. At update 5 it is task 0's turn, so task 1 (the
    // waiting one) cannot run then; its condition is still evaluated at update 5, and it runs
    // at its next turn, update 6, although the input is OFF again by then.
    let m = machine_toml(
        "budget = 1\ntasks = 3",
        &[(0, "a.pt", true), (1, "b.pt", true), (2, "c.pt", true)],
        &[("A", 0), ("Seen", 0), ("C", 0)],
    );
    let b = "Wait For DriveInput.1 = ON\nVar.Seen = FreeRunTime\n";
    let scenario = "[[press]]\nname = \"DriveInput.1\"\nat = 0.005\nlength = 0.001\n";
    let dir = project(
        "waitfor",
        &m,
        &[("a.pt", COUNT_A), ("b.pt", b), ("c.pt", COUNT_C)],
        Some(scenario),
    );
    let r = run_for(&dir, ms(12));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.change_ticks("DriveInput.1"), [5, 6]);
    assert_eq!(r.change_ticks("Var.A"), [0, 3, 5, 8, 10, 12]);
    assert_eq!(r.change_ticks("Var.C"), [2, 4, 7, 9, 11]);
    assert_eq!(r.change_ticks("Var.Seen"), [6]);
    assert_eq!(r.value("Var.Seen"), 6000.0, "FreeRunTime in µs at update 6");
    assert_eq!(r.value("Program.1.Running"), 0.0);
}

#[test]
fn wait_for_released_by_another_task() {
    let m = machine_toml(
        "tasks = 2",
        &[(0, "a.pt", true), (1, "b.pt", true)],
        &[("T", 0)],
    );
    let a = "Wait For Time 0.003\nBit.1 = ON\n";
    let b = "Wait For Bit.1\nVar.T = FreeRunTime\n";
    let dir = project("release", &m, &[("a.pt", a), ("b.pt", b)], None);
    let r = run_for(&dir, ms(10));
    // Task 0 sets the bit at update 3; task 1 is released and runs at update 4.
    assert_eq!(r.change_ticks("Bit.1"), [3]);
    assert_eq!(r.value("Var.T"), 4000.0);
}

#[test]
fn wait_for_true_condition_does_not_block() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("T", 0)]);
    let a = "Bit.1 = ON\nWait For Bit.1 = ON\nVar.T = 7\n";
    let dir = project("notblock", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(3));
    assert_eq!(r.change_ticks("Var.T"), [0]);
}

// ---------------------------------------------------------------------------------------------
// Wait For Time

#[test]
fn wait_for_time_delays_the_ceiling_of_seconds_over_the_update() {
    let m = machine_toml(
        "",
        &[(0, "a.pt", true)],
        &[("T0", 0), ("T1", 0), ("T2", 0), ("T3", 0)],
    );
    let a = "Var.T0 = FreeRunTime\nWait For Time 0.0035\nVar.T1 = FreeRunTime\nWait For Time 0.002\nVar.T2 = FreeRunTime\nWait For Time 0\nVar.T3 = FreeRunTime\n";
    let dir = project("waittime", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(20));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.T0"), 0.0);
    assert_eq!(r.value("Var.T1"), 4000.0, "ceil(3.5 ms / 1 ms) = 4 updates");
    assert_eq!(r.value("Var.T2"), 6000.0, "2 ms = exactly 2 updates");
    assert_eq!(r.value("Var.T3"), 6000.0, "Wait For Time 0 does not wait");
}

#[test]
fn wait_for_time_with_a_fine_update() {
    let m = "[machine]\nupdate = \"250us\"\n\n[[program]]\nnumber = 0\nfile = \"a.pt\"\n\n[variables.T1]\n[variables.T2]\n";
    let a =
        "Wait For Time 0.001\nVar.T1 = FreeRunTime\nWait For Time 0.0011\nVar.T2 = FreeRunTime\n";
    let dir = project("finetime", m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(5));
    assert_eq!(r.value("Var.T1"), 1000.0, "4 updates of 250 µs");
    assert_eq!(
        r.value("Var.T2"),
        2250.0,
        "ceil(1.1 ms / 250 µs) = 5 updates"
    );
}

#[test]
fn negative_wait_time_is_a_run_time_error() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("T", 2)]);
    let a = "Var.T = -0.5\nWait For Time Var.T\n";
    let dir = project("negwait", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(5));
    let e = r.summary.error.as_ref().expect("an error");
    assert_eq!(e.line, 2);
    assert!(e.message.starts_with("Wait For Time:"), "{}", e.message);
}

// ---------------------------------------------------------------------------------------------
// Program.N.Initiate and Call Program.N

#[test]
fn program_initiate_starts_another_task_and_the_initiator_goes_on() {
    let m = machine_toml(
        "",
        &[(0, "a.pt", true), (1, "b.pt", false)],
        &[("A", 0), ("B", 0), ("T", 0)],
    );
    let a = "Var.A = 1\nProgram.1.Initiate\nVar.T = Program.1.Task\nBit.1 = Program.1.Running\nVar.A = 2\n";
    let b = "Var.B = FreeRunTime + 1\n";
    let dir = project("initiate", &m, &[("a.pt", a), ("b.pt", b)], None);
    let r = run_for(&dir, ms(5));
    assert_eq!(r.summary.error, None);
    // The initiator did not wait: everything in update 0.
    assert_eq!(r.change_ticks("Var.A"), [0, 0]);
    assert_eq!(r.value("Var.T"), 1.0, "Program 1 runs on task 1");
    assert_eq!(r.value("Bit.1"), 1.0);
    // Program 1 ran at its own turn, update 1.
    assert_eq!(r.value("Var.B"), 1001.0);
    let programs: Vec<(u64, u64, u64, String)> = r
        .events("program")
        .iter()
        .map(|e| {
            (
                e["tick"].as_u64().unwrap(),
                e["program"].as_u64().unwrap(),
                e["task"].as_u64().unwrap(),
                e["event"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    assert_eq!(
        programs,
        [
            (0, 0, 0, "start".to_string()),
            (0, 1, 1, "start".to_string()),
            (0, 0, 0, "end".to_string()),
            (1, 1, 1, "end".to_string()),
        ]
    );
    assert_eq!(r.value("Program.1.Running"), 0.0);
    assert_eq!(r.value("Program.1.Task"), -1.0);
}

#[test]
fn call_program_runs_it_on_the_same_task_and_returns() {
    // One task only: a call needs no task of its own.
    let m = machine_toml(
        "tasks = 1",
        &[(0, "a.pt", true), (1, "b.pt", false)],
        &[("A", 0), ("B", 0), ("C", 0), ("T", 0)],
    );
    let a = "Var.A = 1\nCall Program.1\nVar.C = Var.B + 1\nVar.T = FreeRunTime + 5\n";
    let b = "Var.B = Var.A + 10\nEnd\nVar.B = 999\n";
    let dir = project("call", &m, &[("a.pt", a), ("b.pt", b)], None);
    let r = run_for(&dir, ms(5));
    assert_eq!(r.summary.error, None);
    assert_eq!(
        r.value("Var.B"),
        11.0,
        "End returns from the called program"
    );
    assert_eq!(r.value("Var.C"), 12.0, "the caller goes on after the call");
    assert_eq!(r.value("Var.T"), 5.0, "all in update 0");
    // Program 1 was never started on a task of its own.
    let starts: Vec<u64> = r
        .events("program")
        .iter()
        .filter(|e| e["event"] == "start")
        .map(|e| e["program"].as_u64().unwrap())
        .collect();
    assert_eq!(starts, [0]);
}

#[test]
fn call_program_in_a_loop() {
    let m = machine_toml(
        "tasks = 1",
        &[(0, "a.pt", true), (1, "b.pt", false)],
        &[("I", 0), ("B", 0)],
    );
    let a = "For Var.I = 1 To 3\nCall Program.1\nNext\n";
    let b = "Var.B = Var.B * 10 + Var.I\n";
    let dir = project("callloop", &m, &[("a.pt", a), ("b.pt", b)], None);
    let r = run_for(&dir, ms(3));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.B"), 123.0);
    assert_eq!(r.value("Var.I"), 4.0);
}

#[test]
fn initiate_with_no_free_task_is_a_run_time_error() {
    let m = machine_toml("tasks = 1", &[(0, "a.pt", true), (1, "b.pt", false)], &[]);
    let a = "Bit.1 = ON\nProgram.1.Initiate\n";
    let dir = project("notask", &m, &[("a.pt", a), ("b.pt", "Bit.2 = ON\n")], None);
    let r = run_for(&dir, ms(3));
    let e = r.summary.error.as_ref().expect("an error");
    assert_eq!((e.task, e.program, e.line), (0, 0, 2));
    assert_eq!(e.message, "Program.1.Initiate: all 1 tasks are busy");
}

// ---------------------------------------------------------------------------------------------
// the instruction budget

#[test]
fn the_budget_stops_a_runaway_loop_from_stalling_the_clock() {
    // Default budget; program 0 never blocks. The clock still reaches the duration and the
    // other task still gets every other update.
    let m = "[[program]]\nnumber = 0\nfile = \"a.pt\"\nautostart = true\n\n[[program]]\nnumber = 1\nfile = \"b.pt\"\nautostart = true\n\n[variables.A]\n[variables.B]\n";
    let b = "Do While TRUE\nVar.B = FreeRunTime\nWait For Time 0.001\nLoop\n";
    let dir = project("runaway", m, &[("a.pt", COUNT_A), ("b.pt", b)], None);
    let r = run_for(&dir, 0.05);
    assert_eq!(r.summary.error, None);
    assert_eq!(r.summary.stop_reason, StopReason::Duration);
    assert_eq!(r.summary.ticks, 51);
    assert_eq!(r.summary.seconds, 0.05);
    let b_ticks = r.change_ticks("Var.B");
    assert_eq!(b_ticks, (1..=49).step_by(2).collect::<Vec<u64>>());
    // Program 0 ran at the 26 even updates, the same number of iterations each time.
    let a = r.value("Var.A");
    assert!(a > 26.0, "{a}");
    assert_eq!(a % 26.0, 0.0, "{a}");
    let a_ticks = r.change_ticks("Var.A");
    let mut distinct = a_ticks.clone();
    distinct.dedup();
    assert_eq!(distinct, (0..=50).step_by(2).collect::<Vec<u64>>());
    // Bounded by the budget: 10,000 instructions a turn, plus a few for the other task.
    assert!(
        r.summary.instructions <= 26 * 10_000 + 25 * 20,
        "{}",
        r.summary.instructions
    );
}

#[test]
fn a_small_budget_bounds_the_work_of_one_turn() {
    let m = machine_toml("budget = 40", &[(0, "a.pt", true)], &[("A", 0)]);
    let dir = project("smallbudget", &m, &[("a.pt", COUNT_A)], None);
    let r = run_for(&dir, ms(9));
    let a = r.value("Var.A");
    // Each update runs the same number of iterations. The budget is checked at the backward
    // jump of the loop, so a turn ends at the first `Loop` reached once 40 instructions are
    // spent: at most one loop body (a few instructions) more than the budget.
    assert_eq!(a % 10.0, 0.0, "{a}");
    let per_turn = a / 10.0;
    assert!((2.0..=40.0).contains(&per_turn), "{per_turn}");
    let per_turn_instructions = r.summary.instructions / 10;
    assert_eq!(r.summary.instructions % 10, 0, "{}", r.summary.instructions);
    assert!(
        (40..40 + 8).contains(&per_turn_instructions),
        "{per_turn_instructions} instructions per turn"
    );
}

// ---------------------------------------------------------------------------------------------
// run-time errors

#[test]
fn division_by_zero_ends_the_run_with_task_program_line_and_message() {
    let m = machine_toml(
        "tasks = 2",
        &[(0, "idle.pt", true), (3, "div.pt", true)],
        &[("A", 2), ("Z", 0)],
    );
    // Program 3 starts on task 1 at update 1 (update 0 is task 0's), waits 2 updates and
    // divides by zero at update 3.
    let div = "' divides by zero at 3 ms\nVar.A = 1\nVar.Z = 0\nWait For Time 0.002\nVar.A = Var.A / Var.Z\nVar.A = 5\n";
    let dir = project(
        "div0",
        &m,
        &[("idle.pt", "Wait For Bit.1 = ON\n"), ("div.pt", div)],
        None,
    );
    let r = run_for(&dir, 1.0);
    let e = r.summary.error.as_ref().expect("a run-time error");
    assert_eq!(e.task, 1);
    assert_eq!(e.program, 3);
    assert_eq!(e.line, 5);
    assert_eq!(e.message, "division by zero");
    assert!(e.file.ends_with("div.pt"), "{}", e.file);
    assert_eq!(e.time, 0.003);
    assert_eq!(r.summary.stop_reason, StopReason::RunTimeError);
    assert_eq!(
        r.summary.ticks, 4,
        "the run stops at the update of the error"
    );
    assert_eq!(r.value("Var.A"), 1.0, "nothing after the error ran");
    let errors = r.events("error");
    assert_eq!(errors.len(), 1);
    let ev = errors[0];
    assert_eq!(ev["tick"], 3);
    assert_eq!(ev["task"], 1);
    assert_eq!(ev["program"], 3);
    assert_eq!(ev["line"], 5);
    assert_eq!(ev["message"], "division by zero");
    let text = e.to_string();
    assert!(text.contains("Program.3"), "{text}");
    assert!(text.contains("line 5"), "{text}");
    // The trace ends with the end event.
    assert_eq!(r.trace.last().unwrap()["kind"], "end");
}

#[test]
fn mod_by_zero_is_a_run_time_error() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("A", 0)]);
    let dir = project("mod0", &m, &[("a.pt", "Var.A = 7 MOD Var.A\n")], None);
    let r = run_for(&dir, ms(3));
    let e = r.summary.error.as_ref().expect("a run-time error");
    assert_eq!((e.task, e.program, e.line), (0, 0, 1));
    assert_eq!(e.message, "MOD by zero");
}

#[test]
fn fixed_point_overflow_of_a_variable_is_a_run_time_error() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("Big", 2)]);
    let a = "Var.Big = 21474836.47\nVar.Big = Var.Big + 0.01\n";
    let dir = project("overflow", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(3));
    let e = r.summary.error.as_ref().expect("a run-time error");
    assert_eq!((e.task, e.program, e.line), (0, 0, 2));
    assert!(e.message.starts_with("overflow:"), "{}", e.message);
    assert!(e.message.contains("does not fit Var.Big"), "{}", e.message);
    assert!(e.message.contains("21474836.47"), "{}", e.message);
    assert_eq!(r.value("Var.Big"), 21474836.47);
    let ev = r.events("error");
    assert_eq!(ev.len(), 1);
    assert_eq!(ev[0]["line"], 2);
}

#[test]
fn overflow_in_a_loop_of_an_integer_variable() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("X", 0)]);
    let a = "Var.X = 1\nDo While TRUE\n    Var.X = Var.X * 10\nLoop\n";
    let dir = project("overflow-loop", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(3));
    let e = r.summary.error.as_ref().expect("a run-time error");
    assert_eq!(e.line, 3);
    assert!(e.message.starts_with("overflow:"), "{}", e.message);
    assert_eq!(r.value("Var.X"), 1e9);
}

// ---------------------------------------------------------------------------------------------
// fixed-point stores

#[test]
fn fixed_point_rounding_on_assignment() {
    let m = machine_toml(
        "",
        &[(0, "a.pt", true)],
        &[
            ("Sum", 2),
            ("Quarter", 2),
            ("MinusQuarter", 2),
            ("Third", 2),
            ("TwoThirds", 2),
            ("Small", 2),
            ("Half", 0),
            ("MinusHalf", 0),
            ("SevenHalves", 0),
            ("Acc", 2),
            ("I", 0),
        ],
    );
    let a = "\
Var.Sum = 0.1 + 0.2
Var.Quarter = 0.125
Var.MinusQuarter = -0.125
Var.Third = 10 / 3
Var.TwoThirds = 2 / 3
Var.Small = 1.004
Var.Half = 2.5
Var.MinusHalf = -2.5
Var.SevenHalves = 7 / 2
For Var.I = 1 To 100
    Var.Acc = Var.Acc + 0.01
Next
";
    let dir = project("fixed", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(2));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.Sum"), 0.3, "0.1 + 0.2 is exactly 0.30");
    assert_eq!(r.value("Var.Quarter"), 0.13, "halves round away from zero");
    assert_eq!(r.value("Var.MinusQuarter"), -0.13);
    assert_eq!(r.value("Var.Third"), 3.33);
    assert_eq!(r.value("Var.TwoThirds"), 0.67);
    assert_eq!(r.value("Var.Small"), 1.0);
    assert_eq!(r.value("Var.Half"), 3.0);
    assert_eq!(r.value("Var.MinusHalf"), -3.0);
    assert_eq!(r.value("Var.SevenHalves"), 4.0);
    assert_eq!(
        r.value("Var.Acc"),
        1.0,
        "a hundred 0.01 steps make exactly 1.00"
    );
    assert_eq!(r.value("Var.I"), 101.0);
    // The trace shows the stored value, not the computed one.
    let sum: Vec<&Value> = r
        .trace
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == "Var.Sum")
        .collect();
    assert_eq!(sum[0]["value"], 0.3);
}

#[test]
fn fixed_point_rounds_decimal_halves_away_from_zero() {
    // 1.005 with 2 decimal places is a half: 1.01, as the value written says, whatever its
    // binary approximation (1.00499999999999989...) is.
    let m = machine_toml(
        "",
        &[(0, "a.pt", true)],
        &[("P", 2), ("N", 2), ("Q", 2), ("O", 4)],
    );
    let a = "Var.P = 1.005\nVar.N = -1.005\nVar.Q = 2.675\nVar.O = 1.00005\n";
    let dir = project("halves", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(2));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.P"), 1.01, "1.005 to 2 places");
    assert_eq!(r.value("Var.N"), -1.01, "-1.005 to 2 places");
    assert_eq!(r.value("Var.Q"), 2.68, "2.675 to 2 places");
    assert_eq!(r.value("Var.O"), 1.0001, "1.00005 to 4 places");
}

#[test]
fn initial_values_are_rounded_too() {
    let m = "[[program]]\nnumber = 0\nfile = \"a.pt\"\n\n[variables.X]\ndecimals = 1\ninitial = 2.25\n\n[variables.Y]\ndecimals = 2\ninitial = 0.1\n";
    let dir = project("initial", m, &[("a.pt", "Var.Y = Var.Y + 0.2\n")], None);
    let r = run_for(&dir, ms(1));
    assert_eq!(r.value("Var.X"), 2.3);
    assert_eq!(r.value("Var.Y"), 0.3);
}

// ---------------------------------------------------------------------------------------------
// Dwell

#[test]
fn a_program_continues_right_after_a_single_dwell() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("T0", 0), ("T1", 0)]);
    let a = "Var.T0 = FreeRunTime + 1\nDwell For Time 0.005\nVar.T1 = FreeRunTime + 1\nBit.1 = Profile.0.Busy\n";
    let dir = project("dwell1", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(10));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.T1"), 1.0, "no wait after one dwell");
    assert_eq!(r.value("Bit.1"), 1.0, "the dwell occupies profile 0");
    assert_eq!(r.change_ticks("Profile.0.Busy"), [0, 5]);
    assert_eq!(r.value("Profile.0.Busy"), 0.0);
}

#[test]
fn a_second_dwell_waits_for_the_first_to_complete() {
    let m = machine_toml(
        "",
        &[(0, "a.pt", true)],
        &[("T0", 0), ("T1", 0), ("T2", 0), ("T3", 0)],
    );
    let a = "Var.T0 = FreeRunTime + 1\nDwell For Time 0.005\nVar.T1 = FreeRunTime + 1\nDwell For Time 0.002\nVar.T2 = FreeRunTime + 1\nWait For Profile.0.Busy = OFF\nVar.T3 = FreeRunTime + 1\n";
    let dir = project("dwell2", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(12));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.T0"), 1.0);
    assert_eq!(r.value("Var.T1"), 1.0);
    assert_eq!(
        r.value("Var.T2"),
        5001.0,
        "the second dwell starts when the first ends"
    );
    assert_eq!(r.value("Var.T3"), 7001.0, "and lasts its own 2 ms");
}

#[test]
fn dwell_blocks_only_its_own_task() {
    let m = machine_toml(
        "budget = 1\ntasks = 2",
        &[(0, "a.pt", true), (1, "b.pt", true)],
        &[("T", 0), ("B", 0)],
    );
    let a = "Dwell For Time 0.004\nDwell For Time 0.001\nVar.T = FreeRunTime\n";
    let dir = project("dwell3", &m, &[("a.pt", a), ("b.pt", COUNT_B)], None);
    let r = run_for(&dir, ms(8));
    assert_eq!(r.summary.error, None);
    // Task 0 blocks at update 0 on its second dwell; task 1 counts at every other update.
    assert_eq!(r.change_ticks("Var.B"), [1, 2, 3, 5, 6, 7, 8]);
    assert_eq!(r.value("Var.T"), 4000.0);
}

// ---------------------------------------------------------------------------------------------
// Goto

#[test]
fn goto_backwards_loops() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("I", 0), ("Done", 0)]);
    let a = "Var.I = 0\nAgain:\nVar.I = Var.I + 1\nIf Var.I < 5 Then\n    Goto Again\nEndif\nVar.Done = 1\n";
    let dir = project("goto", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(2));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.I"), 5.0);
    assert_eq!(r.value("Var.Done"), 1.0);
    assert_eq!(r.change_ticks("Var.I"), [0, 0, 0, 0, 0, 0]);
}

#[test]
fn goto_forwards_skips_and_jump_to_works() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("A", 0)]);
    let a = "Var.A = 1\nGoto Skip\nVar.A = 2\nSkip:\nJump To Last_Line\nVar.A = 3\nLast_Line:\n";
    let dir = project("gotofwd", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(2));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.A"), 1.0);
}

#[test]
fn an_endless_goto_loop_yields_to_the_budget() {
    let m = machine_toml("budget = 1", &[(0, "a.pt", true)], &[("A", 0)]);
    let a = "Top:\nVar.A = Var.A + 1\nGoto Top\n";
    let dir = project("gotoloop", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(10));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.summary.stop_reason, StopReason::Duration);
    assert_eq!(r.value("Var.A"), 11.0, "one pass per update");
}

// ---------------------------------------------------------------------------------------------
// End

#[test]
fn end_stops_the_program() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("A", 0)]);
    let a = "Var.A = 1\nEnd\nVar.A = 2\n";
    let dir = project("end", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(3));
    assert_eq!(r.value("Var.A"), 1.0);
    assert_eq!(r.value("Program.0.Running"), 0.0);
}

// ---------------------------------------------------------------------------------------------
// For loops at run time

#[test]
fn for_loops_count_up_down_and_not_at_all() {
    let m = machine_toml(
        "",
        &[(0, "a.pt", true)],
        &[
            ("I", 0),
            ("Up", 0),
            ("Down", 0),
            ("None", 0),
            ("Frac", 2),
            ("J", 2),
        ],
    );
    let a = "\
For Var.I = 1 To 5
    Var.Up = Var.Up * 10 + Var.I
Next Var.I
For Var.I = 3 To 1 Step -1
    Var.Down = Var.Down * 10 + Var.I
Next
For Var.I = 3 To 1
    Var.None = Var.None + 1
Next
For Var.J = 0 To 1 Step 0.25
    Var.Frac = Var.Frac + 1
Next
";
    let dir = project("forloops", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(2));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.Up"), 12345.0);
    assert_eq!(r.value("Var.Down"), 321.0);
    assert_eq!(
        r.value("Var.None"),
        0.0,
        "3 To 1 with a positive step runs no pass"
    );
    assert_eq!(r.value("Var.I"), 3.0);
    assert_eq!(r.value("Var.Frac"), 5.0, "0, 0.25, 0.5, 0.75, 1");
    assert_eq!(r.value("Var.J"), 1.25);
}

#[test]
fn a_step_of_zero_at_run_time_is_an_error() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("I", 0), ("S", 0)]);
    let a = "Var.S = 0\nFor Var.I = 1 To 3 Step Var.S\nNext\n";
    let dir = project("step0", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(2));
    let e = r.summary.error.as_ref().expect("a run-time error");
    assert_eq!((e.task, e.program, e.line), (0, 0, 2));
    assert_eq!(e.message, "For loop with a Step of 0 never ends");
}

#[test]
fn an_error_in_a_blocked_wait_for_condition_is_reported() {
    // The condition is evaluated while the task waits; it divides by zero at update 5.
    let m = machine_toml(
        "tasks = 2",
        &[(0, "a.pt", true), (1, "b.pt", true)],
        &[("Z", 0)],
    );
    let a = "Var.Z = 1\nWait For 10 / Var.Z > 100\n";
    let b = "Wait For Time 0.003\nVar.Z = 0\n";
    let dir = project("probe-error", &m, &[("a.pt", a), ("b.pt", b)], None);
    let r = run_for(&dir, ms(20));
    let e = r.summary.error.as_ref().expect("a run-time error");
    assert_eq!((e.task, e.program, e.line), (0, 0, 2));
    assert_eq!(e.message, "division by zero");
    assert_eq!(e.time, 0.005);
    let ev = r.events("error");
    assert_eq!(ev.len(), 1);
    assert_eq!(ev[0]["tick"], 5);
    assert_eq!(ev[0]["task"], 0);
}

// ---------------------------------------------------------------------------------------------
// stopping programs

#[test]
fn program_stop_ends_another_task() {
    let m = machine_toml(
        "budget = 1",
        &[(0, "a.pt", true), (1, "b.pt", false)],
        &[("B", 0)],
    );
    let a = "Program.1.Initiate\nWait For Time 0.004\nProgram.1.Stop\nBit.1 = Program.1.Running\n";
    let dir = project("stop", &m, &[("a.pt", a), ("b.pt", COUNT_B)], None);
    let r = run_for(&dir, ms(10));
    assert_eq!(r.summary.error, None);
    // Program 1 counts at updates 1, 2, 3; program 0 stops it at update 4.
    assert_eq!(r.change_ticks("Var.B"), [1, 2, 3]);
    assert_eq!(r.value("Bit.1"), 0.0);
    assert_eq!(r.value("Program.1.Running"), 0.0);
    let stops: Vec<(u64, u64)> = r
        .events("program")
        .iter()
        .filter(|e| e["event"] == "stop")
        .map(|e| (e["tick"].as_u64().unwrap(), e["program"].as_u64().unwrap()))
        .collect();
    assert_eq!(stops, [(4, 1)]);
}

#[test]
fn stop_ends_every_program() {
    let m = machine_toml(
        "budget = 1",
        &[(0, "a.pt", true), (1, "b.pt", true)],
        &[("A", 0), ("B", 0)],
    );
    let a = "Wait For Time 0.003\nStop\nVar.A = 1\n";
    let dir = project("stopall", &m, &[("a.pt", a), ("b.pt", COUNT_B)], None);
    let r = run_for(&dir, ms(10));
    assert_eq!(r.summary.error, None);
    assert_eq!(
        r.value("Var.A"),
        0.0,
        "Stop ends the program that runs it too"
    );
    assert_eq!(r.change_ticks("Var.B"), [1, 2]);
    assert_eq!(r.value("Program.0.Running"), 0.0);
    assert_eq!(r.value("Program.1.Running"), 0.0);
}

// ---------------------------------------------------------------------------------------------
// the range of a 32-bit variable

#[test]
fn the_full_signed_32_bit_range_is_accepted() {
    // A signed 32-bit value runs from -2147483648 to 2147483647.
    let m = machine_toml(
        "",
        &[(0, "a.pt", true)],
        &[("Max", 0), ("Min", 0), ("MinFixed", 2)],
    );
    let a = "Var.Max = 2147483647\nVar.Min = -2147483648\nVar.MinFixed = -21474836.48\n";
    let dir = project("range", &m, &[("a.pt", a)], None);
    let r = run_for(&dir, ms(2));
    assert_eq!(r.summary.error, None);
    assert_eq!(r.value("Var.Max"), 2147483647.0);
    assert_eq!(r.value("Var.Min"), -2147483648.0);
    assert_eq!(r.value("Var.MinFixed"), -21474836.48);
}

#[test]
fn one_past_the_range_is_an_overflow() {
    let m = machine_toml("", &[(0, "a.pt", true)], &[("X", 0)]);
    let dir = project(
        "range-over",
        &m,
        &[("a.pt", "Var.X = 2147483647\nVar.X = Var.X + 1\n")],
        None,
    );
    let r = run_for(&dir, ms(2));
    let e = r.summary.error.as_ref().expect("an overflow");
    assert_eq!(e.line, 2);
    assert!(e.message.starts_with("overflow:"), "{}", e.message);
}
