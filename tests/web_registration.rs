//! The continuous-web registration programs of the ORMEC note, run verbatim: the pitch filter,
//! the rejection of out-of-range samples, the phase correction and sensor blinding, each checked
//! mark by mark against a reference model of the listings written here.

mod common;

use common::{run_loaded, Run};
use pacer::load::{load, LoadRequest};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn folder(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("programs")
        .join(name)
}

/// Run a machine folder with `scenario` instead of its own.
fn run_with(name: &str, scenario: &str) -> Run {
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "pacer-web-{}-{name}-{}.toml",
        std::process::id(),
        scenario.len()
    ));
    std::fs::write(&path, scenario).expect("write the scenario");
    let loaded = load(&LoadRequest {
        paths: vec![folder(name)],
        scenario: Some(path.clone()),
        ..Default::default()
    });
    let _ = std::fs::remove_file(&path);
    match loaded {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    }
}

fn run_folder(name: &str) -> Run {
    match load(&LoadRequest {
        paths: vec![folder(name)],
        ..Default::default()
    }) {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    }
}

/// What the trace shows at one mark: the latched positions, and the registration variables as
/// TREND and INST left them (a variable the program rewrites with the same value shows no
/// change event, so values carry over).
#[derive(Debug, Clone, PartialEq)]
struct Mark {
    web: f64,
    knife: f64,
    plen: i64,
    diff: i64,
    corr: i64,
}

fn marks(run: &Run) -> Vec<Mark> {
    let mut out: Vec<Mark> = Vec::new();
    let mut vars = std::collections::BTreeMap::<String, i64>::new();
    let mut web = 0.0;
    let close = |out: &mut Vec<Mark>, vars: &std::collections::BTreeMap<String, i64>| {
        if let Some(m) = out.last_mut() {
            m.plen = vars.get("PLEN&").copied().unwrap_or(0);
            m.diff = vars.get("DIFF&").copied().unwrap_or(0);
            m.corr = vars.get("CORR&").copied().unwrap_or(0);
        }
    };
    for e in &run.events {
        match e["kind"].as_str() {
            Some("latch") if e["axis"] == 1 => web = e["position"].as_f64().expect("position"),
            Some("latch") if e["axis"] == 2 => {
                close(&mut out, &vars);
                out.push(Mark {
                    web,
                    knife: e["position"].as_f64().expect("position"),
                    plen: 0,
                    diff: 0,
                    corr: 0,
                });
            }
            Some("change") => {
                if let (Some(name), Some(v)) = (e["name"].as_str(), e["value"].as_i64()) {
                    vars.insert(name.to_string(), v);
                }
            }
            _ => {}
        }
    }
    close(&mut out, &vars);
    out
}

/// REG.CONFIG's values.
const TREND_SET: i64 = 15000;
const MAX_DIFF: i64 = 300;
const INST_GAIN: i64 = 2500;
const FCOEF: i64 = 3690; // 10000 * (1 - 0.1^(1/5)) = 3690.43, stored in a long

/// Microsoft BASIC `\` on integers: truncation toward zero.
fn idiv(a: i64, b: i64) -> i64 {
    a / b
}

/// TREND and INST as the listings compute them, from the latched positions.
#[derive(Debug)]
struct Reference {
    old: i64,
    plen: i64,
    rejected: usize,
    accepted: usize,
}

impl Reference {
    fn new() -> Reference {
        Reference {
            old: 0,
            plen: TREND_SET,
            rejected: 0,
            accepted: 0,
        }
    }

    /// One mark: the expected (PLEN&, DIFF&, CORR&).
    fn mark(&mut self, web: f64, knife: f64, inst_set: i64) -> (i64, i64, i64) {
        let pos = web.round_ties_even() as i64;
        if self.old != 0 {
            let tmp = pos - self.old;
            if tmp > TREND_SET / 2 && tmp < 3 * TREND_SET / 2 {
                self.plen = idiv((10000 - FCOEF) * self.plen + FCOEF * tmp, 10000);
                self.accepted += 1;
            } else {
                self.rejected += 1;
            }
        }
        self.old = pos;
        let mut diff = inst_set - knife.round_ties_even() as i64;
        if diff > 3600 / 2 {
            diff -= 3600;
        } else if diff <= -(3600 / 2) {
            diff += 3600;
        }
        if diff.abs() > MAX_DIFF {
            diff = diff.signum() * MAX_DIFF;
        }
        (self.plen, diff, idiv(diff * INST_GAIN, 10000))
    }
}

fn check_against_reference(marks: &[Mark], inst_set: i64) -> Reference {
    let mut r = Reference::new();
    for (n, m) in marks.iter().enumerate() {
        let (plen, diff, corr) = r.mark(m.web, m.knife, inst_set);
        assert_eq!(
            (m.plen, m.diff, m.corr),
            (plen, diff, corr),
            "mark {n} at web {:.3}, knife {:.3}",
            m.web,
            m.knife
        );
    }
    r
}

#[test]
fn the_listings_run_verbatim() {
    let spec = include_str!("../../shared/spec/web-registration.md");
    let listings: Vec<&str> = spec.split("```\n").skip(1).step_by(2).collect();
    let [main, trend, inst, reg_config, blind] = listings[..] else {
        panic!("the spec has five listings");
    };
    let plain = std::fs::read_to_string(folder("web-registration").join("registration.mb"))
        .expect("program");
    for listing in [main, trend, inst, reg_config] {
        assert!(plain.contains(listing), "not verbatim:\n{listing}");
    }
    let blinding =
        std::fs::read_to_string(folder("web-registration-blinding").join("registration.mb"))
            .expect("program");
    for listing in [trend, inst, reg_config, blind] {
        assert!(blinding.contains(listing), "not verbatim:\n{listing}");
    }
}

#[test]
fn every_mark_follows_the_listings_and_out_of_range_samples_are_rejected() {
    let run = run_folder("web-registration");
    assert!(run.summary.error.is_none(), "{:?}", run.summary.error);
    let marks = marks(&run);
    assert!(marks.len() >= 190, "{} marks", marks.len());
    let r = check_against_reference(&marks, 0);
    // The print defects (a spurious mark 6 in after every 40th) make samples of about 6 in:
    // below ½ × 15 in, rejected, and PLEN& stays.
    assert!(r.rejected >= 4, "rejected {}", r.rejected);
    assert!(r.accepted >= 180, "accepted {}", r.accepted);
    // Each correction is at most MAX.DIFF& scaled by the gain.
    assert!(marks
        .iter()
        .all(|m| m.corr.abs() <= MAX_DIFF * INST_GAIN / 10000));
    // The pitch estimate follows the printed pitch (15.120 in, stretching 0.5 per product)
    // between defects: over the last marks it is within ±0.2 % of the print.
    let last = &marks[marks.len() - 1];
    let printed = 15120.0 + 0.5 * (marks.len() as f64);
    assert!(
        ((last.plen as f64) - printed).abs() / printed < 0.01,
        "PLEN& {} vs printed {printed}",
        last.plen
    );
}

const CLEAN: &str = r#"
[run]
duration = "12s"

[[marks]]
axis = 1
first = 5000
pitch = 15000
count = 80
width = 100
"#;

#[test]
fn the_phase_error_shrinks_by_the_gain_clamped_by_max_diff() {
    let run = run_with("web-registration", CLEAN);
    let marks = marks(&run);
    assert!(marks.len() >= 60, "{} marks", marks.len());
    check_against_reference(&marks, 0);
    // The web is printed at exactly the set pitch, so between marks the knife turns 3600 plus
    // the correction: the error at the next mark is the error less the correction, exactly.
    for w in marks.windows(2) {
        let advance = w[1].knife - w[0].knife;
        let expected = w[0].corr as f64;
        let off = (advance - expected + 1800.0).rem_euclid(3600.0) - 1800.0;
        assert!(
            off.abs() < 1e-6,
            "knife {} → {}: moved {advance}, correction {}",
            w[0].knife,
            w[1].knife,
            w[0].corr
        );
    }
    // The knife starts 120.0° (1200 units) out: 75 units per mark while the clamp holds, then
    // 25 % of what is left, down to the 3 units integer division cannot correct.
    let errors: Vec<i64> = marks.iter().map(|m| m.diff).collect();
    assert_eq!(&errors[..3], &[-300, -300, -300]);
    for w in errors.windows(2) {
        assert!(w[1].abs() <= w[0].abs(), "the error grew: {errors:?}");
    }
    let settled = errors
        .iter()
        .position(|e| e.abs() <= 3)
        .expect("the phase converges");
    let first_error = (1200.0 - marks[0].knife).abs();
    assert!(first_error < 1e-6, "first knife {}", marks[0].knife);
    eprintln!("phase: 1200 units out at the first mark, within 3 units after {settled} marks");
    assert_eq!(settled, 30, "settled after {settled} marks");
}

#[test]
fn the_pitch_reaches_ninety_percent_of_a_step_as_the_integer_filter_allows() {
    let step = |to: f64| {
        format!(
            "[run]\nduration = \"12s\"\n\n[[marks]]\naxis = 1\nfirst = 5000\npitch = 15000\n\
             count = 80\nwidth = 100\nsteps = [{{ at = 30, pitch = {to} }}]\n"
        )
    };
    for (to, within) in [(15300.0, 6usize), (14700.0, 5usize)] {
        let run = run_with("web-registration", &step(to));
        let marks = marks(&run);
        check_against_reference(&marks, 0);
        // Marks 30 → 31 is the first sample at the new pitch.
        let plens: Vec<i64> = marks[31..40].iter().map(|m| m.plen).collect();
        let reached = |k: usize| (plens[k - 1] as f64 - 15000.0) / (to - 15000.0);
        let first = (1..=plens.len())
            .find(|&k| reached(k) >= 0.9)
            .expect("reaches 90 %");
        eprintln!(
            "step 15000 → {to}: PLEN& {plens:?}; {:.2} % after NUM = 5 samples, 90 % after {first}",
            100.0 * reached(5)
        );
        assert_eq!(first, within, "{plens:?}");
        // The note's filter, c = 1 − 0.1^(1/NUM), reaches 90 % in exactly NUM samples; the
        // listing stores c as 3690/10000 (from 3690.43) and its integer division truncates
        // each step by up to one unit, which costs an upward step a third of a percent.
        let c = 1.0 - 0.1f64.powf(1.0 / 5.0);
        let mut real = 15000.0;
        for _ in 0..5 {
            real = (1.0 - c) * real + c * to;
        }
        assert!(((real - 15000.0) / (to - 15000.0) - 0.9).abs() < 1e-12);
        assert!(reached(5) > 0.895, "{}", reached(5));
    }
}

#[test]
fn with_blinding_marks_outside_the_window_change_nothing() {
    let with_defects = run_folder("web-registration-blinding");
    let scenario =
        std::fs::read_to_string(folder("web-registration-blinding").join("scenario.toml"))
            .expect("scenario");
    let clean = scenario.replace("spurious = { every = 7, offset = 7500 }\n", "");
    assert_ne!(clean, scenario);
    let without = run_with("web-registration-blinding", &clean);
    let a = marks(&with_defects);
    let b = marks(&without);
    assert!(a.len() >= 190, "{} marks", a.len());
    assert_eq!(a, b, "the blinded defects changed the registration");
    check_against_reference(&a, 2200);
    let blinded = with_defects
        .events
        .iter()
        .filter(|e| e["kind"] == "blinded")
        .count();
    assert!(blinded >= 25, "{blinded} defects blinded");
    assert_eq!(
        without
            .events
            .iter()
            .filter(|e| e["kind"] == "blinded")
            .count(),
        0
    );
    // Every mark seen was inside the knife's window, and the phase holds near 220.0°.
    assert!(a.iter().all(|m| (2000.0..2400.0).contains(&m.knife)));
    let worst = a[20..].iter().map(|m| m.diff.abs()).max().unwrap_or(0);
    eprintln!(
        "blinding: {blinded} defects blinded; phase error after 20 marks at most {worst} units"
    );
    assert!(worst <= 15, "phase error {worst} units");
}

#[test]
fn the_i_dist_slip_is_reported_and_the_correction_is_a_visible_step() {
    let run = run_folder("web-registration");
    let warnings: Vec<&Value> = run
        .events
        .iter()
        .filter(|e| e["kind"] == "warning")
        .collect();
    let marks = marks(&run);
    assert_eq!(warnings.len(), marks.len(), "one warning per correction");
    let message = warnings[0]["message"].as_str().expect("message");
    assert!(message.contains("IN 0"), "{message}");
    assert_eq!(warnings[0]["line"], 64);
}

#[test]
fn pacer_check_reports_the_l_dist_slip_before_the_machine_runs() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pacer"))
        .arg("check")
        .arg(folder("web-registration"))
        .output()
        .expect("run pacer check");
    let text =
        String::from_utf8_lossy(&out.stderr).to_string() + &String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "a warning does not fail the check:\n{text}"
    );
    assert!(
        text.contains("I_DIST& is read but never assigned"),
        "{text}"
    );
    assert!(
        text.contains("`L_DIST&` is assigned: did you mean it?"),
        "{text}"
    );
    assert!(text.contains("registration.mb:64:28"), "{text}");
}
