//! The findings of issue 22 about the files around the programs and the command line, one test
//! each: every count, budget and time of `machine.toml` and `scenario.toml` has a limit checked
//! at its text; a trace that cannot be written stops the run at once; messages name the key and
//! what it takes in words, with short numbers and escaped invisible characters.

mod common;

use common::{pacer, rust_names, text};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A machine folder of this test process holding `files`.
fn folder(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let d = common::scratch_in("hardening", name);
    for (file, body) in files {
        std::fs::write(d.join(file), body).expect("write a project file");
    }
    d
}

fn arg(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 temp path")
}

/// Run `pacer` with `args`, killed after `limit`; its output, and how long it took.
fn pacer_within(args: &[&str], limit: Duration) -> (std::process::Output, Duration) {
    let start = Instant::now();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_pacer"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("pacer starts");
    loop {
        if child.try_wait().expect("wait").is_some() {
            break;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("pacer {args:?} still ran after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().expect("output");
    (out, start.elapsed())
}

/// `pacer check` of a folder with one program, `machine` and `scenario`: exit code and text.
fn check(name: &str, program: &str, machine: &str, scenario: &str) -> (Option<i32>, String) {
    let d = folder(
        name,
        &[
            ("program0.pt", program),
            ("machine.toml", machine),
            ("scenario.toml", scenario),
        ],
    );
    let (o, _) = pacer_within(&["check", arg(&d)], Duration::from_secs(20));
    (o.status.code(), text(&o))
}

#[test]
fn a_bounce_count_past_its_limit_is_refused_at_the_count_without_allocating() {
    let (code, t) = check(
        "bounce",
        "End\n",
        "",
        "[master]\nspeed = 1.0\n\n[[products]]\nsensor = \"ModuleInput.1\"\nfirst = 1\npitch = 1\nlength = 0.2\ncount = 10\nbounce = { count = 200000000, width = \"1us\", gap = \"1us\" }\n",
    );
    assert_eq!(code, Some(1), "{t}");
    assert!(
        t.contains("scenario.toml:10:20")
            && t.contains("200,000,000 bounces after each edge is too many: at most 1,000"),
        "{t}"
    );
}

#[test]
fn a_budget_past_its_limit_is_refused_at_the_budget() {
    let (code, t) = check(
        "budget",
        "Do While TRUE\nLoop\n",
        "[machine]\nbudget = 100000000000\n",
        "",
    );
    assert_eq!(code, Some(1), "{t}");
    assert!(
        t.contains("machine.toml:2:10")
            && t.contains(
                "a budget of 100,000,000,000 instructions per update is too many: at most 1,000,000"
            ),
        "{t}"
    );
}

#[test]
fn a_time_past_a_million_seconds_is_refused_at_its_text() {
    let (code, t) = check(
        "duration",
        "End\n",
        "",
        "[run]\nduration = \"1000000000 s\"\n",
    );
    assert_eq!(code, Some(1), "{t}");
    assert!(
        t.contains("scenario.toml:2:12")
            && t.contains("1000000000 s is too long: times are at most 1,000,000 s"),
        "{t}"
    );
}

#[test]
fn a_run_of_more_updates_than_the_limit_is_refused() {
    let (code, t) = check(
        "updates",
        "End\n",
        "[machine]\nupdate = \"1us\"\n",
        "[run]\nduration = 1000\n",
    );
    assert_eq!(code, Some(1), "{t}");
    assert!(
        t.contains("scenario.toml:2:12")
            && t.contains("a run of 1,000,000,000 updates is too long: at most 100,000,000"),
        "{t}"
    );
    let d = folder("updates-for", &[("program0.pt", "End\n")]);
    let (o, _) = pacer_within(
        &["run", arg(&d), "--for", "1000000"],
        Duration::from_secs(20),
    );
    assert_eq!(o.status.code(), Some(64), "{}", text(&o));
    assert!(
        text(&o).contains("--for: a run of 1,000,000,000 updates is too long"),
        "{}",
        text(&o)
    );
}

#[test]
fn a_scenario_that_would_lay_out_too_much_is_refused_before_it_is_made() {
    let trains: String = (1..=3)
        .map(|n| {
            format!(
                "[[pulses]]\nname = \"ModuleInput.{n}\"\nstart = 0\nperiod = \"1ms\"\nwidth = \"100us\"\ncount = 1000000\n\n"
            )
        })
        .collect();
    let (code, t) = check("world", "End\n", "", &trains);
    assert_eq!(code, Some(1), "{t}");
    // The third train passes 5,000,000 (2 edges a pulse): the error is on its count.
    assert!(
        t.contains("scenario.toml:20:9")
            && t.contains("this pulse train takes the scenario past 5,000,000 things"),
        "{t}"
    );
}

#[test]
fn long_missing_and_steps_lists_cost_no_quadratic_time() {
    let missing: Vec<String> = (0..60_000).map(|i| (i * 2).to_string()).collect();
    let scenario = format!(
        "[master]\nspeed = 1000.0\n\n[[products]]\nsensor = \"ModuleInput.1\"\nfirst = 1\npitch = 1\nlength = 0.2\ncount = 1000000\nmissing = [{}]\n",
        missing.join(", ")
    );
    let start = Instant::now();
    let (code, t) = check("missing", "End\n", "", &scenario);
    assert_eq!(code, Some(0), "{t}");
    assert!(
        start.elapsed() < Duration::from_secs(15),
        "{:?}",
        start.elapsed()
    );
}

#[test]
fn a_trace_that_cannot_be_written_stops_the_run_at_once() {
    if !Path::new("/dev/full").exists() {
        return;
    }
    let d = folder(
        "trace-full",
        &[
            (
                "program0.pt",
                "Do While TRUE\n  Var.X = Var.X + 1\n  Wait For Time 0.001\nLoop\n",
            ),
            ("machine.toml", "[variables.X]\n"),
        ],
    );
    let (o, took) = pacer_within(
        &[
            "run",
            arg(&d),
            "--for",
            "3000",
            "--trace",
            "/dev/full",
            "-q",
        ],
        Duration::from_secs(60),
    );
    let t = text(&o);
    assert_eq!(o.status.code(), Some(3), "{t}");
    assert!(
        t.contains("error: cannot write the trace to /dev/full: No space left on device"),
        "{t}"
    );
    // It stopped at the first failed write (64 KiB of trace: a few simulated seconds), not at
    // the end of the 3000 s asked for.
    let at: f64 = t
        .split("the run stopped at t = ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no stop time in {t}"));
    assert!(at < 60.0, "stopped at {at} s: {t}");
    assert!(took < Duration::from_secs(30), "{took:?}");
}

#[test]
fn usage_errors_exit_64_not_the_run_time_error_code() {
    let d = folder("usage", &[("program0.pt", "End\n")]);
    for args in [
        vec!["run", arg(&d), "--for", "abc"],
        vec!["run", arg(&d), "--for", "-1"],
        vec!["run", arg(&d), "--for", "nan"],
        vec!["run", arg(&d), "--for", "1e30"],
        vec!["run", arg(&d), "--trace-limit", "lots"],
        vec!["run", arg(&d), "--no-such-flag"],
        vec!["check"],
        vec!["frobnicate"],
        vec!["repl", "--dialect", "cobol"],
    ] {
        let o = pacer(&args);
        assert_eq!(o.status.code(), Some(64), "{args:?}: {}", text(&o));
    }
    for args in [vec!["--help"], vec!["--version"], vec!["run", "--help"]] {
        let o = pacer(&args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", text(&o));
    }
}

#[test]
fn a_move_at_zero_speed_says_it_never_arrives() {
    let d = folder(
        "move-zero",
        &[
            (
                "program0.mb",
                "w~ = {1}\nMOVE w~ FOR 2147483647 AT 0\nEND\n",
            ),
            ("machine.toml", "[axis.1]\nunits_per_rev = 3600\n"),
            ("scenario.toml", "[run]\nduration = 1\n"),
        ],
    );
    let o = pacer(&["run", arg(&d)]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains(
            "MOVE TO/FOR on axis 1: at 0 RPM the axis never arrives; give a speed above 0 (AT)"
        ),
        "{t}"
    );
    assert!(!t.contains("inf"), "{t}");
}

#[test]
fn invisible_characters_are_escaped_in_unexpected_character() {
    for (bad, shown) in [
        ("\0", "\\0"),
        ("\u{200b}", "\\u{200b}"),
        ("\u{7}", "\\u{0007}"),
    ] {
        let d = folder(
            "invisible",
            &[("program0.pt", &format!("Var.X = 1 {bad}\n"))],
        );
        let o = pacer(&["check", arg(&d)]);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(1), "{t}");
        assert!(
            t.contains(&format!("unexpected character `{shown}`")),
            "{bad:?}: {t}"
        );
    }
}

#[test]
fn configuration_messages_are_in_words() {
    let machine_cases: &[(&str, &str)] = &[
        (
            "[[machine]]\nname = \"x\"\n",
            "`[machine]` is one table; write `[machine]`, not `[[machine]]`",
        ),
        (
            "[machine]\ntasks = -1\n",
            "`tasks` in `[machine]` takes a whole number from 1 to 64, not -1",
        ),
        (
            "[machine]\ntasks = 99999999999999999999\n",
            "`tasks` in `[machine]` takes a whole number from 1 to 64, not 1e20",
        ),
        (
            "[machine]\nbudget = \"x\"\n",
            "`budget` in `[machine]` takes a whole number from 1 to 1,000,000, not the text \"x\"",
        ),
        ("[machine]\nupdate = 1e300\n", "1e300 s is too long"),
        (
            "[machine]\nname = 1\n",
            "`name` in `[machine]` takes text (the machine's name), not 1",
        ),
        (
            "machine = 3\n",
            "`machine` takes a table: write `[machine]` once, not 3",
        ),
        (
            "[io]\nDriveInput = 1.5\n",
            "`DriveInput` in `[io]` takes a whole number from 0 to 4,096, not 1.5",
        ),
        (
            "[variables.X]\ndecimals = 300\n",
            "`decimals` in `[variables.X]` takes a whole number from 0 to 9, not 300",
        ),
        (
            "[bits]\ncount = true\n",
            "`count` in `[bits]` takes a whole number from 0 to 4,096, not true",
        ),
        ("[[program]]\nnumber = 1\n", "`[[program]]` needs `file`"),
        (
            "[program]\nnumber = 1\n",
            "`program` is a list of tables: write each one as `[[program]]`, not `[program]`",
        ),
        (
            "[queue]\n0 = 1\n",
            "`0` in `[queue]` takes a table (`[queue.0]`), not 1",
        ),
        (
            "[modbus]\nport = \"x\"\n",
            "`port` in `[modbus]` takes a whole number from 1 to 65,535, not the text \"x\"",
        ),
        (
            "[axis.1]\nqueue = [1]\n",
            "`queue` in `[axis.1]` takes a whole number from 1 to 64, not an array",
        ),
        (
            "[machine]\ntasks = 1e400\n",
            "larger than any pacer can hold",
        ),
    ];
    let scenario_cases: &[(&str, &str)] = &[
        ("[[run]]\nduration = 1\n", "`[run]` is one table; write `[run]`, not `[[run]]`"),
        ("[[products]]\nsensor = \"ModuleInput.1\"\nfirst = 1\npitch = 1\nlength = 0.2\ncount = -5\n", "`count` in `[[products]]` takes a whole number from 0 to 10,000,000, not -5"),
        ("[[products]]\nsensor = \"ModuleInput.1\"\nfirst = 1\npitch = 1\nlength = 0.2\ncount = 5\nbounce = { count = 1.5, width = 1, gap = 1 }\n", "`bounce.count` in `[[products]]` takes a whole number from 0 to 1,000, not 1.5"),
        ("[run]\nseed = -1\n", "`seed` in `[run]` takes a whole number, 0 or more, not -1"),
        ("[master]\nspeed = \"fast\"\n", "`speed` in `[master]` takes a number (master units per second), not the text \"fast\""),
    ];
    let all = machine_cases
        .iter()
        .map(|(m, want)| (*m, "", *want))
        .chain(scenario_cases.iter().map(|(s, want)| ("", *s, *want)));
    for (i, (machine, scenario, want)) in all.enumerate() {
        let name = format!("words-{i}");
        let result = common::load_memory(
            &name,
            &[
                ("program0.pt", "End\n"),
                ("machine.toml", machine),
                ("scenario.toml", scenario),
            ],
        );
        let problems = common::problem_triples(&result);
        let messages: Vec<&str> = problems.iter().map(|(_, _, m)| m.as_str()).collect();
        assert!(
            messages.iter().any(|m| m.contains(want)),
            "{machine}{scenario}: wanted {want:?} in {messages:?}"
        );
        for m in &messages {
            assert!(rust_names(m).is_empty(), "{machine}{scenario}: {m}");
            // No number of more than 16 digits (a 301-digit duration was printed once).
            let longest = m
                .split(|c: char| !c.is_ascii_digit())
                .map(str::len)
                .max()
                .unwrap_or(0);
            assert!(longest <= 16, "{machine}{scenario}: {m}");
        }
    }
    // The command shows the same, exit code 1.
    let (code, t) = check("words-cli", "End\n", "[[machine]]\n", "");
    assert_eq!(code, Some(1), "{t}");
    assert!(t.contains("`[machine]` is one table"), "{t}");
}

#[test]
fn a_program_number_past_the_limit_is_refused_at_the_number() {
    // Found by tests/fuzz_config.rs: Program.200000000 made 200,000,001 program objects.
    let d = folder(
        "program-number",
        &[
            ("program0.pt", "End\n"),
            (
                "machine.toml",
                "[[program]]\nnumber = 200000000\nfile = \"program0.pt\"\n",
            ),
        ],
    );
    let (o, took) = pacer_within(&["check", arg(&d)], Duration::from_secs(20));
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(
        t.contains("machine.toml:2:10")
            && t.contains("Program.200,000,000 cannot be: programs are numbered 0 to 4,095"),
        "{t}"
    );
    assert!(took < Duration::from_secs(10), "{took:?}");
}
