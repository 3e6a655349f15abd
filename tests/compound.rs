//! Compound indexes (`Index.N.CompoundInitiate`): the compounded index reaches its end point at
//! its velocity, without stopping, and the index its program initiates next takes over there on
//! the internal timeline; positions, velocities, statuses and end times are exact on any update
//! period. Also `Index.ProfileLimited` without an instance, and what `pacer check` refuses.

mod common;

use pacer::vm::Machine;

use common::Run;

/// Index 0: 4 units at 2 u/s, ramps 2 u/s²; Index 1: 6 units at 1 u/s, ramps 1 u/s².
const TWO: &str =
    "[index.0]\ndistance = 4.0\nvelocity = 2.0\nacceleration = 2.0\ndeceleration = 2.0\n\
    [index.1]\ndistance = 6.0\nvelocity = 1.0\nacceleration = 1.0\ndeceleration = 1.0\n";

const CHAIN: &str = "Index.0.CompoundInitiate\nIndex.1.Initiate\nEnd\n";

/// One update as the test saw it.
#[derive(Debug, Clone, Copy)]
struct Sample {
    t: f64,
    position: f64,
    velocity: f64,
    busy: f64,
    in_progress: [f64; 2],
    complete: [f64; 2],
    at_vel: [f64; 2],
}

fn value(m: &Machine, name: &str) -> f64 {
    m.value_of(name).unwrap_or(f64::NAN)
}

/// Run `program` on `machine` (with `update`), sampling every update.
fn sampled(update: &str, program: &str, machine: &str, seconds: f64) -> (Run, Vec<Sample>) {
    let machine = format!("[machine]\nupdate = \"{update}\"\n{machine}");
    let scenario = format!("[run]\nduration = {seconds}\n");
    let loaded = match common::load_memory(
        &format!("compound-{update}"),
        &[
            ("program0.pt", program),
            ("machine.toml", &machine),
            ("scenario.toml", &scenario),
        ],
    ) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let mut samples = Vec::new();
    let run = common::run_observed(loaded, &mut |m| {
        samples.push(Sample {
            t: m.time(),
            position: value(m, "PosnCommand"),
            velocity: value(m, "VelCommand"),
            busy: value(m, "Profile.0.Busy"),
            in_progress: [0, 1].map(|i| value(m, &format!("Index.{i}.CommandInProgress"))),
            complete: [0, 1].map(|i| value(m, &format!("Index.{i}.CommandComplete"))),
            at_vel: [0, 1].map(|i| value(m, &format!("Index.{i}.AtVel"))),
        })
    });
    (run, samples)
}

fn ends(r: &Run) -> Vec<(String, f64)> {
    r.events
        .iter()
        .filter(|e| e["kind"] == "motion" && e["event"] == "done")
        .map(|e| {
            (
                e["object"].as_str().unwrap_or("").to_string(),
                e["end"].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect()
}

/// Where the chain of `TWO` has the axis at `t`: Index 0 up to 2 u/s in 1 s (1 unit), 3 units
/// at 2 u/s (1.5 s) to its end point 4 at 2.5 s, at 2 u/s; Index 1 from there down to 1 u/s
/// in 1 s (1.5 units), 4 units at 1 u/s (4 s), down to rest in 1 s (0.5 units): 10 at 8.5 s.
fn expected(t: f64) -> (f64, f64) {
    if t < 1.0 {
        (t * t, 2.0 * t)
    } else if t < 2.5 {
        (1.0 + 2.0 * (t - 1.0), 2.0)
    } else if t < 3.5 {
        let u = t - 2.5;
        (4.0 + 2.0 * u - 0.5 * u * u, 2.0 - u)
    } else if t < 7.5 {
        (5.5 + (t - 3.5), 1.0)
    } else if t < 8.5 {
        let r = 8.5 - t;
        (10.0 - 0.5 * r * r, r)
    } else {
        (10.0, 0.0)
    }
}

#[test]
fn a_compound_index_runs_into_the_next_without_stopping_exactly_on_any_update() {
    // 0.7 ms divides neither 2.5 s nor 8.5 s; 1 ms divides both.
    for update in ["700us", "1ms"] {
        let (r, samples) = sampled(update, CHAIN, TWO, 10.0);
        assert!(r.summary.error.is_none(), "{update}: {:?}", r.summary.error);
        let e = ends(&r);
        assert_eq!(e.len(), 2, "{update}: {e:?}");
        assert_eq!(e[0].0, "Index.0");
        assert!((e[0].1 - 2.5).abs() < 1e-12, "{update}: {e:?}");
        assert!((e[1].1 - 8.5).abs() < 1e-12, "{update}: {e:?}");
        // The boundary: Index 0 is done at its end point 4, Index 1 starts there.
        let at = |object: &str, event: &str| {
            r.events
                .iter()
                .find(|x| x["kind"] == "motion" && x["object"] == object && x["event"] == event)
                .and_then(|x| x["position"].as_f64())
                .unwrap_or(f64::NAN)
        };
        assert_eq!(at("Index.0", "done"), 4.0, "{update}");
        assert_eq!(at("Index.1", "start"), 4.0, "{update}");
        assert_eq!(at("Index.1", "done"), 10.0, "{update}");
        // The update Index 0 ends in: until its program initiates Index 1 (after the control
        // loop), the axis runs on at 2 u/s from the end point, as a `Using Last` chain's next
        // motion also starts at the following update; Index 1 then takes over from the end
        // point and instant exactly (checked at every later update).
        let boundary = samples
            .iter()
            .find(|s| s.t >= 2.5)
            .map_or(f64::NAN, |s| s.t);
        for s in &samples {
            let (p, v) = if s.t == boundary {
                (4.0 + 2.0 * (s.t - 2.5), 2.0)
            } else {
                expected(s.t)
            };
            assert!((s.position - p).abs() < 1e-9, "{update}: {s:?} vs {p}");
            assert!((s.velocity - v).abs() < 1e-9, "{update}: {s:?} vs {v}");
            // The profile stays busy from the first start to the last end: no stop between.
            if s.t > 0.0 && s.t < 8.5 {
                assert_eq!(s.busy, 1.0, "{update}: {s:?}");
                assert!(s.velocity >= 1.0 - 1e-9 || s.t < 1.0 || s.t > 7.5, "{s:?}");
            }
        }
        // Through the boundary the velocity is held: 2 u/s on both sides.
        let around: Vec<&Sample> = samples
            .iter()
            .filter(|s| (s.t - 2.5).abs() <= 0.0015)
            .collect();
        assert!(around.len() >= 2, "{update}");
        for s in &around {
            assert!((s.velocity - 2.0).abs() < 0.002, "{update}: {s:?}");
        }
        // Statuses: Index 0 at velocity up to its end point, complete there; Index 1 in
        // progress from there, at its velocity from 3.5 s to 7.5 s, complete at 8.5 s.
        for s in &samples {
            let t = s.t;
            let in0 = if t < 2.5 { 1.0 } else { 0.0 };
            assert_eq!(s.in_progress[0], in0, "{update}: {s:?}");
            assert_eq!(s.complete[0], 1.0 - in0, "{update}: {s:?}");
            if t > 1.0 + 1e-9 && t < 2.5 {
                assert_eq!(s.at_vel[0], 1.0, "{update}: {s:?}");
            }
            if t >= 2.5 {
                assert_eq!(s.at_vel[0], 0.0, "{update}: {s:?}");
            }
            let in1 = if (2.5..8.5).contains(&t) { 1.0 } else { 0.0 };
            assert_eq!(s.in_progress[1], in1, "{update}: {s:?}");
            assert_eq!(s.complete[1], f64::from(t >= 8.5), "{update}: {s:?}");
            let at1 = (3.5 + 1e-9..7.5).contains(&t);
            if at1 || !(3.5..7.5 + 1e-9).contains(&t) {
                assert_eq!(s.at_vel[1], f64::from(at1), "{update}: {s:?}");
            }
        }
        assert_eq!(r.machine.value_of("PosnCommand"), Some(10.0));
    }
}

#[test]
fn a_chain_of_compound_indexes_speeds_up_and_ends_exactly() {
    // Index 0 to 1 u/s in 1 s (0.5), 1.5 at 1 u/s (1.5 s): at 2 at 2.5 s. Index 1 compounded
    // too: from 1 up to 3 u/s at 2 u/s² (1 s, 2 units), 4 at 3 u/s (4/3 s): at 8 at 29/6 s.
    // Index 2 (absolute, to 20): 12 units, from 3 down to 2 at 1 u/s² (1 s, 2.5), then down to
    // rest (2 s, 2), 7.5 at 2 u/s (3.75 s): 6.75 s, at rest at 20 at 29/6 + 6.75 s.
    let machine = "[index.0]\ndistance = 2.0\nvelocity = 1.0\nacceleration = 1.0\ndeceleration = 1.0\n\
        [index.1]\ndistance = 6.0\nvelocity = 3.0\nacceleration = 2.0\ndeceleration = 2.0\n\
        [index.2]\ntype = \"Absolute\"\ndistance = 20.0\nvelocity = 2.0\nacceleration = 1.0\ndeceleration = 1.0\n";
    let program = "Index.0.CompoundInitiate\nIndex.1.CompoundInitiate\nIndex.2.Initiate\nEnd\n";
    for update in ["700us", "1ms"] {
        let (r, samples) = sampled(update, program, machine, 15.0);
        assert!(r.summary.error.is_none(), "{update}: {:?}", r.summary.error);
        let e = ends(&r);
        let want = [2.5, 29.0 / 6.0, 29.0 / 6.0 + 6.75];
        assert_eq!(e.len(), 3, "{update}: {e:?}");
        for (got, want) in e.iter().zip(want) {
            assert!((got.1 - want).abs() < 1e-12, "{update}: {e:?}");
        }
        // Never slower than 1 u/s between the first second and the last ramp.
        for s in samples.iter().filter(|s| s.t > 1.0 && s.t < want[2] - 2.0) {
            assert!(s.velocity >= 1.0 - 1e-9, "{update}: {s:?}");
        }
        // Exact at every update on Index 1's cruise: 6 + 3 (t - 3.5).
        for s in samples.iter().filter(|s| s.t >= 3.5 && s.t < want[1]) {
            assert!(
                (s.position - (4.0 + 3.0 * (s.t - 3.5))).abs() < 1e-9,
                "{s:?}"
            );
        }
        assert_eq!(r.machine.value_of("PosnCommand"), Some(20.0));
        assert_eq!(r.machine.value_of("Index.2.CommandComplete"), Some(1.0));
    }
}

#[test]
fn a_compound_index_with_no_next_index_runs_on_until_a_stop() {
    // Program 1 stops program 0 while it waits to initiate Index 1: the axis runs on at 2 u/s
    // from Index 0's end point until `Stop` ramps it down at StopDeceleration.
    let program1 = "Wait For Time 1\nProgram.0.Stop\nWait For Time 3\nStopDeceleration = 4\nStop\n";
    let machine = format!(
        "[machine]\nupdate = \"1ms\"\n[[program]]\nnumber = 0\nfile = \"program0.pt\"\n\
         autostart = true\n[[program]]\nnumber = 1\nfile = \"program1.pt\"\nautostart = true\n{TWO}"
    );
    let loaded = match common::load_memory(
        "compound-stop",
        &[
            ("program0.pt", CHAIN),
            ("program1.pt", program1),
            ("machine.toml", &machine),
            ("scenario.toml", "[run]\nduration = 6.0\n"),
        ],
    ) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let mut m = Machine::new(loaded.image, pacer::trace::Trace::new(None, 1_000_000));
    let mut at_3_5 = None;
    let mut stop_at = None;
    let summary = m.run_observed(None, &mut |m| {
        if (m.time() - 3.5).abs() < 1e-9 {
            at_3_5 = Some((value(m, "PosnCommand"), value(m, "VelCommand")));
        }
        if stop_at.is_none() && value(m, "Program.1.Running") == 0.0 && m.time() > 1.0 {
            stop_at = Some(m.time());
        }
    });
    assert!(summary.error.is_none(), "{:?}", summary.error);
    let (p, v) = at_3_5.expect("a sample at 3.5 s");
    assert!((p - 6.0).abs() < 1e-9 && (v - 2.0).abs() < 1e-9, "{p} {v}");
    let ts = stop_at.expect("Stop ran");
    // Ramped down from 2 u/s at 4 u/s²: 0.5 units past where the stop found it.
    let end = value(&m, "PosnCommand");
    assert!(
        (end - (4.0 + 2.0 * (ts - 2.5) + 0.5)).abs() < 1e-9,
        "{end} {ts}"
    );
    assert_eq!(value(&m, "VelCommand"), 0.0);
    assert!(m.moving().is_empty(), "{:?}", m.moving());
}

#[test]
fn index_profile_limited_without_an_instance_is_on_while_any_index_is_limited() {
    // Index 0 can meet its time, Index 1 cannot (FM-3 reference, "Index.ProfileLimited").
    let machine = "[variables.A]\n[variables.B]\n[variables.C]\n[variables.D]\n\
        [index.0]\ndistance = 10.0\nvelocity = 100.0\nacceleration = 10.0\ndeceleration = 10.0\ntime = 4.0\n\
        [index.1]\ndistance = 10.0\nvelocity = 5.0\nacceleration = 10.0\ndeceleration = 10.0\ntime = 0.5\n\
        [index.2]\ndistance = 10.0\nvelocity = 5.0\nacceleration = 10.0\ndeceleration = 10.0\ntime = 0.5\n";
    let program = "Index.0.Initiate\nWait For Index.0.CommandComplete\n\
        If Index.ProfileLimited Then\nVar.A = 1\nEndif\n\
        Index.1.Initiate\nIndex.2.Initiate\nWait For Index.2.CommandComplete\n\
        If Index.ProfileLimited Then\nVar.B = 1\nEndif\n\
        Index.1.ResetProfileLimited\n\
        If Index.ProfileLimited Then\nVar.C = 1\nEndif\n\
        Index.ResetProfileLimited\n\
        If Index.ProfileLimited = OFF And Index.2.ProfileLimited = OFF Then\nVar.D = 1\nEndif\n\
        End\n";
    let r = common::run_project("limited", program, machine, "[run]\nduration = 10.0\n");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let got: Vec<f64> = ["A", "B", "C", "D"]
        .iter()
        .map(|v| r.machine.value_of(&format!("Var.{v}")).unwrap_or(f64::NAN))
        .collect();
    // Off after a timed index that met its time; on after a limited one; still on while
    // Index 2 is limited after Index 1 is reset; off after the reset of every index.
    assert_eq!(got, [0.0, 1.0, 1.0, 1.0]);
    // The trace names the index that was limited, not the derived flag.
    assert!(r.text.contains("\"Index.1.ProfileLimited\""));
    assert!(!r.text.contains("\"Index.ProfileLimited\""));
}

/// (code, line text under the span, message) of the refused project's problems.
fn refused(program: &str, machine: &str) -> Vec<(String, String, String)> {
    let files = [
        ("program0.pt", program),
        ("machine.toml", machine),
        ("scenario.toml", "[run]\nduration = 1.0\n"),
    ];
    let r = common::load_memory("compound-refused", &files);
    assert!(r.is_err(), "{program} should be refused");
    common::problem_triples(&r)
}

#[track_caller]
fn assert_refused(program: &str, machine: &str, line: &str, message: &str) {
    let problems = refused(program, machine);
    assert!(
        problems
            .iter()
            .any(|(code, text, m)| code.starts_with("pacer::")
                && text.contains(line)
                && m == message),
        "{program}: wanted {line:?} / {message:?} in {problems:#?}"
    );
}

#[test]
fn what_cannot_be_compounded_is_refused_at_its_line() {
    let timed0 = TWO.replacen(
        "deceleration = 2.0\n",
        "deceleration = 2.0\ntime = 3.0\n",
        1,
    );
    assert_refused(
        "Index.0.CompoundInitiate\nEnd\n",
        TWO,
        "Index.0.CompoundInitiate",
        "Index.0.CompoundInitiate is not followed by the index it runs into",
    );
    assert_refused(
        "Index.0.CompoundInitiate\nWait For Time 1\nIndex.1.Initiate\nEnd\n",
        TWO,
        "Index.0.CompoundInitiate",
        "Index.0.CompoundInitiate is not followed by the index it runs into",
    );
    assert_refused(
        "Index.0.CompoundInitiate\nDwell For Time 1\nEnd\n",
        TWO,
        "Index.0.CompoundInitiate",
        "Index.0.CompoundInitiate is not followed by the index it runs into",
    );
    // FM-3 reference p. 98: "A Timed Index can not be compounded into or out of."
    assert_refused(
        CHAIN,
        &timed0,
        "Index.0.CompoundInitiate",
        "Index.0 is a timed index: a timed index cannot be compounded",
    );
    let timed1 = format!("{TWO}time = 7.0\n");
    assert_refused(
        CHAIN,
        &timed1,
        "Index.1.Initiate",
        "Index.1 is a timed index: a timed index cannot be compounded into",
    );
    let registration = TWO.replacen("[index.1]\n", "[index.1]\ntype = \"Registration\"\n", 1);
    assert_refused(
        CHAIN,
        &registration,
        "Index.1.Initiate",
        "Index.1 is a registration index: pacer does not let it be compounded into",
    );
    assert_refused(
        "Index.0.CompoundInitiate\nIndex.1.Initiate Using Capture.0\nEnd\n",
        TWO,
        "Index.1.Initiate",
        "Index.1 cannot start Using Capture.0",
    );
    assert_refused(
        "Index.0.CompoundInitiate\nIndex.1.Initiate On Profile.1\nEnd\n",
        TWO,
        "Index.1.Initiate",
        "Index.1 is not on the profile of Index.0, which runs into it",
    );
    let synchronized = TWO.replacen(
        "[index.1]\n",
        "[index.1]\ntime_base = \"Synchronized\"\n",
        1,
    );
    assert_refused(
        CHAIN,
        &synchronized,
        "Index.1.Initiate",
        "Index.1 and Index.0, which runs into it, are not both synchronized to the master",
    );
    // Only inside one block: the If's end is not the next index.
    assert_refused(
        "If DriveInput.1 Then\nIndex.0.CompoundInitiate\nEndif\nIndex.1.Initiate\nEnd\n",
        TWO,
        "Index.0.CompoundInitiate",
        "Index.0.CompoundInitiate is not followed by the index it runs into",
    );
    // An assignment has no next instruction to run into.
    let assigned =
        format!("{TWO}[[assignment]]\nsource = \"DriveInput.1\"\ndestination = \"Index.0.CompoundInitiate\"\n");
    assert_refused(
        "Wait For Time 1\nEnd\n",
        &assigned,
        "Index.0.CompoundInitiate",
        "Index.0.CompoundInitiate cannot be an assignment destination",
    );
}

#[test]
fn a_compound_index_written_on_is_a_compound_initiate() {
    // `Index.0.CompoundInitiate = ON` is the action, as for any action member.
    let program = "Index.0.CompoundInitiate = ON\nIndex.1.Initiate\nEnd\n";
    let (r, _) = sampled("700us", program, TWO, 10.0);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let e = ends(&r);
    assert!((e[1].1 - 8.5).abs() < 1e-12, "{e:?}");
}
