//! Every problem a user can make in `machine.toml` or `scenario.toml` is reported with its code,
//! at the exact text it is about; the whole set of a file is reported together.

mod common;

use pacer::load::{load, LoadRequest};

struct Case {
    machine: &'static str,
    scenario: &'static str,
}

/// Load a project with one trivial program; return (code, text under the span, message) of
/// every problem found.
fn problems(case: Case) -> Vec<(String, String, String)> {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "pacer-config-{}-{:x}",
        std::process::id(),
        hash(case.machine) ^ hash(case.scenario).rotate_left(7)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(dir.join("program0.pt"), "End\n").expect("program");
    std::fs::write(dir.join("machine.toml"), case.machine).expect("machine");
    if !case.scenario.is_empty() {
        std::fs::write(dir.join("scenario.toml"), case.scenario).expect("scenario");
    }
    let result = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    common::problem_triples(&result)
}

fn hash(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    })
}

fn one(case: Case) -> (String, String, String) {
    let mut p = problems(case);
    assert_eq!(p.len(), 1, "expected one problem, got {p:?}");
    p.remove(0)
}

fn machine(m: &'static str) -> Case {
    Case {
        machine: m,
        scenario: "",
    }
}

fn scenario(s: &'static str) -> Case {
    Case {
        machine: "",
        scenario: s,
    }
}

#[test]
fn toml_syntax_and_unknown_keys() {
    let (code, _, msg) = one(machine("[machine\nname = 1\n"));
    assert_eq!(code, "pacer::config");
    assert!(msg.starts_with("machine file:"), "{msg}");
    let (code, text, msg) = one(machine("[machine]\nupdate_rate = 1\n"));
    assert_eq!(code, "pacer::config");
    assert_eq!(text, "update_rate");
    assert!(
        msg.contains("unknown key `update_rate` in `[machine]`; the keys are `name`"),
        "{msg}"
    );
}

#[test]
fn update_period_budget_and_tasks() {
    let (code, text, _) = one(machine("[machine]\nupdate = \"2s\"\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::update", "\"2s\"")
    );
    let (code, text, msg) = one(machine("[machine]\nupdate = \"1 fortnight\"\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::config", "\"1 fortnight\"")
    );
    assert!(msg.contains("unknown time unit"), "{msg}");
    let (code, text, _) = one(machine("[machine]\nbudget = 0\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::budget", "0")
    );
    let (code, text, _) = one(machine("[machine]\ntasks = 100\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::tasks", "100")
    );
}

#[test]
fn instance_counts() {
    let (code, text, msg) = one(machine("[io]\nDriveInptu = 4\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::count", "4")
    );
    assert!(msg.contains("DriveInptu"));
    let (code, _, msg) = one(machine("[objects]\nQueue = 9\n"));
    assert_eq!(code, "pacer::machine::count");
    assert!(msg.contains("9 is not a valid count of Queue"), "{msg}");
    let (code, _, msg) = one(machine("[objects]\nGear = 2\n"));
    assert_eq!(code, "pacer::machine::count");
    assert!(msg.contains("Gear has no instance count"), "{msg}");
}

#[test]
fn variables_and_bits() {
    let (code, _, msg) = one(machine("[variables.Big]\ndecimals = 12\n"));
    assert_eq!(code, "pacer::machine::variable");
    assert!(msg.contains("12 decimal places"), "{msg}");
    let (code, _, msg) = one(machine("[variables.Big]\ndecimals = 4\ninitial = 300000\n"));
    assert_eq!(code, "pacer::machine::variable");
    assert!(msg.contains("does not fit"), "{msg}");
    let (code, _, msg) = one(machine("[variables.\"9lives\"]\n"));
    assert_eq!(code, "pacer::machine::variable");
    assert!(msg.contains("not a valid variable name"), "{msg}");
    let (code, text, _) = one(machine("[bits]\ncount = 8\nnames = { Ready = 8 }\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::bits", "8")
    );
    let (code, text, _) = one(machine(
        "[bits]\ninitially_on = [\"Redy\"]\nnames = { Ready = 1 }\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::bits", "\"Redy\"")
    );
}

#[test]
fn queues() {
    let (code, _, msg) = one(machine("[queue.8]\nsize = 4\n"));
    assert_eq!(code, "pacer::machine::queue");
    assert!(msg.contains("no such queue"), "{msg}");
    let (code, text, _) = one(machine("[queue.0]\nsize = 4\nfull_level = 5\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::queue", "5")
    );
    let (code, text, _) = one(machine("[queue.0]\nsource = \"MasterPosition\"\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::queue", "\"MasterPosition\"")
    );
    let (code, text, _) = one(machine("[queue.0]\nsize = 0\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::queue", "0")
    );
}

#[test]
fn programs() {
    let m = "[[program]]\nnumber = 0\nfile = \"program0.pt\"\n[[program]]\nnumber = 0\nfile = \"program0.pt\"\n";
    let (code, text, _) = one(machine(m));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::program", "0")
    );
    let (code, text, msg) = one(machine("[[program]]\nnumber = 1\nfile = \"missing.pt\"\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::load::read", "\"missing.pt\"")
    );
    assert!(msg.contains("cannot read"), "{msg}");
}

#[test]
fn assignments() {
    let (code, text, msg) = one(machine(
        "[[assignment]]\nsource = \"ModuleInput.1\"\ndestination = \"Capture.0.CaptureTrigered\"\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::check::unknown_member", "CaptureTrigered")
    );
    assert!(msg.contains("Capture has no member"), "{msg}");
    let (code, text, _) = one(machine(
        "[[assignment]]\nsource = \"Queue.0.QueueCount\"\ndestination = \"DriveIO.1.Out\"\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::assignment", "\"Queue.0.QueueCount\"")
    );
    let (code, text, _) = one(machine(
        "[[assignment]]\nsource = \"ModuleInput.1\"\ndestination = \"Queue.0.QueueEmpty\"\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::assignment", "\"Queue.0.QueueEmpty\"")
    );
    let (code, text, _) = one(machine("[[assignment]]\nsource = \"ModuleInput.1\"\ndestination = \"DriveIO.1.Out\"\npolarity = \"ActiveHigh\"\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::assignment", "\"ActiveHigh\"")
    );
    let (code, text, _) = one(machine(
        "[[assignment]]\nsource = \"ModuleInput.1\"\ndestination = \"Program.5.Initiate\"\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::assignment", "\"Program.5.Initiate\"")
    );
    let (code, text, _) = one(machine(
        "[[assignment]]\nsource = \"Module Input 1\"\ndestination = \"DriveIO.1.Out\"\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::machine::name", "\"Module Input 1\"")
    );
}

#[test]
fn scenario_inputs_presses_and_pulses() {
    let (code, text, _) = one(scenario(
        "[[press]]\nname = \"DriveIO.1.Out\"\nat = 0.1\nlength = 0.1\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::scenario::input", "\"DriveIO.1.Out\"")
    );
    let (code, text, _) = one(scenario(
        "[[input]]\nname = \"DriveInput.9\"\nat = 0.1\nvalue = \"ON\"\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::check::unknown_instance", "9")
    );
    let (code, text, msg) = one(scenario(
        "[[input]]\nname = \"DriveInput.1\"\nat = 0.1\nvalue = \"MAYBE\"\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::config", "\"MAYBE\"")
    );
    assert!(msg.contains("not a level"), "{msg}");
    let (code, text, _) = one(scenario(
        "[[press]]\nname = \"DriveInput.1\"\nat = 0.1\nlength = 0\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::scenario::press", "0")
    );
    let (code, text, _) = one(scenario(
        "[[pulses]]\nname = \"DriveInput.1\"\nstart = 0\nperiod = 0.01\nwidth = 0.02\ncount = 3\n",
    ));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::scenario::pulses", "0.02")
    );
    let (code, text, _) = one(scenario("[[press]]\nname = \"DriveInput.1\"\nat = 0.1\nlength = 0.2\n[[press]]\nname = \"DriveInput.1\"\nat = 0.2\nlength = 0.1\n"));
    assert_eq!(
        (code.as_str(), text.as_str()),
        ("pacer::scenario::overlap", "0.2")
    );
    let (code, text, msg) = one(scenario("[run]\nduration = -1\n"));
    assert_eq!((code.as_str(), text.as_str()), ("pacer::config", "-1"));
    assert!(msg.contains("at least 0"), "{msg}");
}

#[test]
fn all_problems_of_the_machine_file_are_reported_together() {
    let p = problems(machine("[machine]\nbudget = 0\ntasks = 0\n[queue.0]\nsize = 4\nfull_level = 9\n[[assignment]]\nsource = \"ModuleInput.1\"\ndestination = \"DriveIO.1.Ot\"\n"));
    let codes: Vec<&str> = p.iter().map(|x| x.0.as_str()).collect();
    assert_eq!(codes.len(), 4, "{p:?}");
    for c in [
        "pacer::machine::budget",
        "pacer::machine::tasks",
        "pacer::machine::queue",
        "pacer::check::unknown_member",
    ] {
        assert!(codes.contains(&c), "{c} missing from {codes:?}");
    }
}

#[test]
fn front_end_limits_are_errors_not_crashes() {
    let long = format!("Var.X = {}1\n", "1 + ".repeat(600));
    let mut problems = Vec::new();
    pacer::syntax::parse_program(&long, &mut problems);
    assert_eq!(problems.len(), 1);
    assert_eq!(problems[0].code, "pacer::syntax::line_too_long");
    let deep = format!("{}Bit.1 = ON\n", "If Bit.2 Then\n".repeat(70));
    let mut problems = Vec::new();
    pacer::syntax::parse_program(&deep, &mut problems);
    assert!(
        problems.iter().any(|p| p.code == "pacer::syntax::nesting"),
        "{problems:?}"
    );
}
