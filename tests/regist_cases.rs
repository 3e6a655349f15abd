//! REGIST's published cases (shared/spec/regist.md), each run as a machine of
//! `programs/regist/`: a MotionBASIC program enables registration on axis 1 and runs it through
//! the marks the scenario lays on its fast input. Every mark must be classified and corrected
//! exactly as the note prints it.

mod common;

use pacer::load::{load, LoadRequest};
use std::path::Path;

/// (class, position, correction) of each mark, and the positions of the DIST + TOLR events.
type Expected = (&'static [(&'static str, f64, Option<f64>)], &'static [f64]);

fn check(case: &str, (marks, windows): Expected) {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("programs/regist")
        .join(case);
    let loaded = load(&LoadRequest {
        paths: vec![folder],
        ..Default::default()
    })
    .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let run = common::run_loaded_with_writes(loaded);
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let seen: Vec<(String, f64, Option<f64>)> = run
        .events
        .iter()
        .filter(|e| e["kind"] == "regist")
        .map(|e| {
            (
                e["mark"].as_str().unwrap_or("?").to_string(),
                e["position"].as_f64().unwrap_or(f64::NAN),
                e["correction"].as_f64(),
            )
        })
        .collect();
    let expected: Vec<(String, f64, Option<f64>)> = marks
        .iter()
        .map(|(c, p, k)| (c.to_string(), *p, *k))
        .collect();
    assert_eq!(seen, expected, "{case}");
    let passed: Vec<f64> = run
        .events
        .iter()
        .filter(|e| e["kind"] == "regist_window")
        .filter_map(|e| e["position"].as_f64())
        .collect();
    assert_eq!(passed, windows, "{case}: DIST + TOLR events");
    // OK came back true, and the status bits of the last mark are the table's.
    assert_eq!(run.machine.value_of("OK&"), Some(-1.0), "{case}: OK");
}

#[test]
fn case_1_every_mark_is_good() {
    check(
        "case1",
        (
            &[
                ("good", 0.0, Some(0.0)),
                ("good", 900.0, Some(0.0)),
                ("good", 1050.0, Some(150.0)),
                ("good", 1950.0, Some(0.0)),
            ],
            &[],
        ),
    );
}

#[test]
fn case_2_a_mark_in_the_ignore_zone() {
    check(
        "case2",
        (
            &[
                ("good", 0.0, Some(0.0)),
                ("good", 1000.0, Some(0.0)),
                ("ignored", 1150.0, None),
                ("good", 2090.0, Some(90.0)),
            ],
            // After the last mark the axis runs on: the window passes 1100 after it.
            &[3190.0],
        ),
    );
}

#[test]
fn case_3_ignored_then_the_window_passes_then_a_bad_mark() {
    check(
        "case3",
        (
            &[
                ("good", 0.0, Some(0.0)),
                ("good", 1000.0, Some(0.0)),
                ("ignored", 1150.0, None),
                ("bad", 2090.0, None),
                ("good", 3090.0, Some(90.0)),
            ],
            &[2080.0, 4170.0],
        ),
    );
}

#[test]
fn case_4_a_bad_mark_resets_the_ruler() {
    check(
        "case4",
        (
            &[
                ("good", 0.0, Some(0.0)),
                ("good", 1000.0, Some(0.0)),
                ("bad", 1090.0, None),
                ("good", 2090.0, Some(90.0)),
            ],
            &[3140.0],
        ),
    );
}

#[test]
fn case_6_a_splice_hidden_by_the_ignore_zone() {
    check(
        "case6",
        (
            &[
                ("good", 0.0, Some(0.0)),
                ("good", 1000.0, Some(0.0)),
                ("ignored", 1500.0, None),
                ("good", 2050.0, Some(50.0)),
            ],
            &[3150.0],
        ),
    );
}

#[test]
fn the_status_bits_follow_the_last_mark() {
    // Case 3 ends on a good mark and then the window passing: DIST + TOLR alone (bit 4).
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/regist/case3");
    let run = common::run_loaded_with_writes(
        load(&LoadRequest {
            paths: vec![folder],
            ..Default::default()
        })
        .unwrap_or_else(|d| panic!("{}", d.render_plain())),
    );
    let statuses: Vec<i64> = run
        .events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == "S&")
        .filter_map(|e| e["value"].as_i64())
        .collect();
    // good: occurred + input + good (0b111); ignored: occurred + input (0b11); window: 0b10000;
    // bad: occurred + input + bad (0b1011). FAST IN RISING (bit 5) shows while the sensor is on.
    let without_rising: Vec<i64> = statuses.iter().map(|s| s & !0b10_0000).collect();
    let mut distinct = without_rising.clone();
    distinct.dedup();
    assert_eq!(
        distinct,
        vec![0b111, 0b11, 0b1_0000, 0b1011, 0b111, 0b1_0000],
        "{statuses:?}"
    );
}

#[test]
fn a_real_input_wired_to_the_fast_input_latches_the_exact_position() {
    let dir = common::project(
        "regist-input",
        &[
            (
                "regist.mb",
                "OK& = REGIST(TRUE, 1, 900, 50, 0, 900, 0)\nMOVE {1} AT 100 IN 0\nWHILETRUE\nWEND\n",
            ),
            (
                "machine.toml",
                "[machine]\nupdate = \"1ms\"\n\n[[program]]\nnumber = 0\nfile = \"regist.mb\"\n\n\
                 [axis.1]\nunits_per_rev = 6000\nfast_input = \"ModuleInput.1\"\n",
            ),
            (
                "scenario.toml",
                // Edges between updates: 100.25 ms, then every 90 ms (900 units at 10,000/s).
                "[run]\nduration = \"0.4s\"\n\n[[pulses]]\nname = \"ModuleInput.1\"\n\
                 start = 0.10025\nperiod = \"90ms\"\nwidth = \"200us\"\ncount = 3\n",
            ),
        ],
    );
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let run =
        common::run_loaded_with_writes(loaded.unwrap_or_else(|d| panic!("{}", d.render_plain())));
    let marks: Vec<(String, f64, f64)> = run
        .events
        .iter()
        .filter(|e| e["kind"] == "regist")
        .map(|e| {
            (
                e["mark"].as_str().unwrap_or("?").to_string(),
                e["time"].as_f64().unwrap_or(f64::NAN),
                e["position"].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect();
    assert_eq!(marks.len(), 3, "{marks:?}");
    // The axis starts at the first update's start (t = 0): position = 10,000 × time, exactly at
    // the edge, not at the update that samples it.
    for (i, (class, time, position)) in marks.iter().enumerate() {
        assert_eq!(class, "good");
        let t = 0.10025 + 0.09 * i as f64;
        assert!((time - t).abs() < 1e-9, "{time}");
        assert!((position - 10000.0 * t).abs() < 1e-6, "{position}");
    }
}

#[test]
fn a_fast_input_must_be_an_input() {
    let d = common::load_error(
        "regist-bad-input",
        &[
            ("regist.mb", "END\n"),
            (
                "machine.toml",
                "[[program]]\nnumber = 0\nfile = \"regist.mb\"\n\n[axis.1]\nfast_input = \"Queue.0.QueueEmpty\"\n",
            ),
        ],
    );
    let text = d.render_plain();
    assert!(text.contains("is not an input"), "{text}");
}

/// The knife's phase (its ASEN latch) at each good mark, and the corrections, of the web-knife
/// machine with `program` in place of its own.
/// What the web-knife machine shows.
struct WebKnife {
    /// The knife's latched phase at each good mark.
    phases: Vec<f64>,
    /// Each mark's class and correction.
    marks: Vec<(String, Option<f64>)>,
    /// READ_SV(1, 10) as the program read it after each latch.
    read_back: Vec<f64>,
}

fn web_knife(program: Option<&str>) -> WebKnife {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/regist/web-knife");
    let read = |f: &str| std::fs::read_to_string(folder.join(f)).expect("web-knife file");
    let (machine, scenario, own) = (
        read("machine.toml"),
        read("scenario.toml"),
        read("regist.mb"),
    );
    let text = program.map_or(own, str::to_string);
    let dir = common::project(
        "web-knife",
        &[
            ("regist.mb", &text),
            ("machine.toml", &machine),
            ("scenario.toml", &scenario),
        ],
    );
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let run =
        common::run_loaded_with_writes(loaded.unwrap_or_else(|d| panic!("{}", d.render_plain())));
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let mut phases = Vec::new();
    let mut marks = Vec::new();
    let read_back: Vec<f64> = run
        .events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == "LAST.CORR")
        .filter_map(|e| e["value"].as_f64())
        .collect();
    let mut last_good = false;
    for e in &run.events {
        if e["kind"] == "regist" {
            last_good = e["mark"] == "good";
            marks.push((
                e["mark"].as_str().unwrap_or("?").to_string(),
                e["correction"].as_f64(),
            ));
        }
        if e["kind"] == "change" && e["name"] == "PHASE" && last_good {
            phases.push(e["value"].as_f64().unwrap_or(f64::NAN));
        }
    }
    WebKnife {
        phases,
        marks,
        read_back,
    }
}

#[test]
fn master_registration_holds_a_geared_knife_on_drifting_prints() {
    let WebKnife {
        phases,
        marks,
        read_back,
    } = web_knife(None);
    // READ_SV(1, 10), the last correction, as the program reads it after each latch.
    assert_eq!(read_back[0], 0.0);
    assert!(read_back[2..].iter().all(|&c| c == 3.0), "{read_back:?}");
    assert!(marks.len() >= 80, "{} marks", marks.len());
    // The prints are 3 units longer than LGTH: every good mark after the entrant corrects 3;
    // the splice is ignored and corrects nothing; nothing is bad.
    assert_eq!(marks[0], ("good".to_string(), Some(0.0)));
    let ignored = marks.iter().filter(|m| m.0 == "ignored").count();
    assert_eq!(ignored, 1, "{marks:?}");
    assert!(marks.iter().all(|m| m.0 != "bad"), "{marks:?}");
    assert!(marks[1..]
        .iter()
        .filter(|m| m.0 == "good")
        .all(|m| m.1 == Some(3.0)));
    // Each correction sets the knife back by 0.24 × 3 = 0.72, which is what it gains per
    // product: from the second mark on it meets every print at the same point of its turn.
    let held = phases[1];
    assert!((held - 1200.72).abs() < 1e-6, "{phases:?}");
    let worst = phases[1..]
        .iter()
        .map(|p| (p - held).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "the knife drifts by {worst}");
}

#[test]
fn a_good_mark_sets_the_web_position_to_dim() {
    // The program reads POS@(web~) an update or so after each mark: with DIM 0 it reads the
    // web's travel since the mark, 100,000 units/s × the time since the mark's exact instant.
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/regist/web-knife");
    let run = common::run_loaded_with_writes(
        load(&LoadRequest {
            paths: vec![folder],
            ..Default::default()
        })
        .unwrap_or_else(|d| panic!("{}", d.render_plain())),
    );
    let mut mark_time = f64::NAN;
    let mut checked = 0;
    for e in &run.events {
        if e["kind"] == "regist" && e["mark"] == "good" {
            mark_time = e["time"].as_f64().unwrap_or(f64::NAN);
        }
        if e["kind"] == "change" && e["name"] == "WP" && mark_time > 0.3 {
            let t = e["t"].as_f64().unwrap_or(f64::NAN);
            let wp = e["value"].as_f64().unwrap_or(f64::NAN);
            assert!(
                (wp - 100_000.0 * (t - mark_time)).abs() < 1e-6,
                "{wp} at {t}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 70, "{checked}");
}

#[test]
fn without_the_correction_the_knife_drifts_off_the_prints() {
    let own = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/regist/web-knife/regist.mb"),
    )
    .expect("program");
    let off = own.replace("WRITE_SV(1, 24, 5)", "WRITE_SV(1, 24, 4)");
    assert_ne!(off, own);
    let phases = web_knife(Some(&off)).phases;
    let n = phases.len() as f64;
    let drift = phases[phases.len() - 1] - phases[0];
    assert!(
        (drift - 0.72 * (n - 1.0)).abs() < 1e-6,
        "{drift} over {n} marks"
    );
}

/// A feed roll (axis 2) geared 1:1 to the machine (axis 1) feeds material printed every 3605
/// units; the machine's cycle is 3600. Slave registration on the feed roll, filter over 10
/// updates: returns the machine's phase (its ASEN latch, modulo 3600) at each mark.
fn feed_roll(switches: u32) -> Vec<f64> {
    let program = format!(
        "m~ = {{1}} : f~ = {{2}}
POS.MOD@(m~) = 3600
GEAR f~ AT 1 TO 1
OK& = REGIST(TRUE, 2, 3600, 100, 0, 3600, 0)
A& = WRITE_SV(2, 17, 10)
B& = WRITE_SV(2, 24, {switches})
MOVE m~ AT 600 IN 100
ASEN@({{m~, f~}}) = 0
WHILETRUE
  IF ASEN(m~) THEN
    PHASE = POS.ASEN@(m~)
    ASEN@({{m~, f~}}) = 0
  ENDIF
WEND
"
    );
    let machine = "[machine]\nupdate = \"1ms\"\nbudget = 500\n\n[[program]]\nnumber = 0\n\
                   file = \"feed.mb\"\n\n[axis.1]\nunits_per_rev = 3600\n\n[axis.2]\n\
                   units_per_rev = 3600\npacer = 1\n";
    let marks = "axis = 2\nfirst = 1000\npitch = 3605\ncount = 40\n";
    let scenario = format!(
        "[run]\nduration = \"3s\"\n\n[[marks]]\nsensor = \"FAST\"\n{marks}\n\
         [[marks]]\nsensor = \"ASEN\"\nwidth = 50\n{marks}"
    );
    let dir = common::project(
        &format!("feed-roll-{switches}"),
        &[
            ("feed.mb", &program),
            ("machine.toml", machine),
            ("scenario.toml", &scenario),
        ],
    );
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let run =
        common::run_loaded_with_writes(loaded.unwrap_or_else(|d| panic!("{}", d.render_plain())));
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    run.events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == "PHASE")
        .filter_map(|e| e["value"].as_f64())
        .collect()
}

#[test]
fn slave_registration_feeds_the_longer_product_through_the_filter() {
    // Slave correction and DIM (6): each good mark corrects +5, spread over 10 updates, so the
    // feed roll feeds 3605 per machine cycle and every mark meets the machine at one phase.
    let held = feed_roll(6);
    assert!(held.len() >= 25, "{held:?}");
    let worst = held[2..]
        .iter()
        .map(|p| (p - held[1]).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "{held:?}");
    // Without the slave correction (DIM only), the marks come 5 later every cycle.
    let drifting = feed_roll(4);
    for w in drifting.windows(2) {
        assert!(
            ((w[1] - w[0]).rem_euclid(3600.0) - 5.0).abs() < 1e-6,
            "{drifting:?}"
        );
    }
}

#[test]
fn powertools_programs_call_regist_too() {
    let run = common::run_project(
        "regist-pt",
        "Var.Ok = REGIST(ON, 1, 1000, 100, 0, 1000, 0)\nVar.S = STATUSSV(1)\n\
         Var.MinTime = READ_SV(1, 25)\nVar.W = WRITE_SV(1, 17, 4)\nVar.F = READ_SV(1, 17)\n\
         Var.Bad = REGIST(ON, 1, 1000, 100, 0, Var.L, 0)\n",
        "[variables.Ok]\n[variables.S]\n[variables.MinTime]\ndecimals = 3\n[variables.W]\n\
         [variables.F]\n[variables.Bad]\ninitial = 7\n[variables.L]\n\n[axis.1]\nunits_per_rev = 6000\n",
        "[run]\nduration = \"10ms\"\n",
    );
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let v = |n: &str| run.machine.value_of(n).unwrap_or(f64::NAN);
    assert_eq!(v("Var.Ok"), 1.0);
    assert_eq!(v("Var.S"), 0.0);
    assert_eq!(v("Var.MinTime"), 0.008, "8 servo updates of 1 ms");
    assert_eq!(v("Var.W"), 1.0);
    assert_eq!(v("Var.F"), 4.0);
    // LGTH 0 (from a variable: a literal 0 is a check error) is refused: OK is false, and the
    // trace says why.
    assert_eq!(v("Var.Bad"), 0.0);
    let warning = run
        .events
        .iter()
        .find(|e| e["kind"] == "warning")
        .expect("a warning");
    assert!(warning["message"].as_str().unwrap_or("").contains("REGIST"));
}
