//! The servo model on the PowerTools drive (`[servo] model = "cascade"`): a move that demands
//! more than the torque limit trips the following-error fault at the update the closed-form
//! bounds allow, motion stops, the trace and the program see it, `FaultReset` clears it; a
//! capture latches the encoder's count at the edge plus the latch delay; `[servo]` is checked.

mod common;

use common::Run;
use serde_json::Value;

/// Motor and load 2e-4 kg·m², 0.2 N·m: at most 1000 rad/s², 159.15 units/s² at one unit per
/// revolution. A fault above 0.05 units.
const WEAK_SERVO: &str = "[servo]\nmodel = \"cascade\"\nposition_gain = 100.0\n\
    velocity_gain = 314.0\nvelocity_integral = 12000.0\nmotor_inertia = 1.0e-4\n\
    load_inertia = 1.0e-4\ntorque_limit = 0.2\nfollowing_error_limit = 0.05\n";

/// Index 0 asks 1000 units/s² up to 10 units/s; index 1 is a gentle unit.
const INDEXES: &str = "[variables.T]\ndecimals = 0\n[bits]\nnames = { R = 1 }\n\
    [index.0]\ndistance = 5.0\nvelocity = 10.0\nacceleration = 1000.0\ndeceleration = 1000.0\n\
    [index.1]\ndistance = 1.0\nvelocity = 1.0\nacceleration = 10.0\ndeceleration = 10.0\n";

fn kind<'a>(r: &'a Run, k: &str) -> Vec<&'a Value> {
    r.events.iter().filter(|e| e["kind"] == k).collect()
}

fn num(e: &Value, key: &str) -> f64 {
    e[key].as_f64().unwrap_or(f64::NAN)
}

#[test]
fn a_move_past_the_torque_limit_trips_the_following_error_fault_and_stops() {
    let program = "Index.0.Initiate\nWait For FollowingErrorFault\nVar.T = FreeRunTime\n\
        Wait For Time 0.5\nIndex.1.Initiate\nFaultReset\nBit.R = FollowingErrorFault\n\
        Index.1.Initiate\nWait For Index.1.CommandComplete\nWait For Time 0.5\nEnd\n";
    let r = common::run_project(
        "servo-fault",
        program,
        &format!("{WEAK_SERVO}{INDEXES}"),
        "[run]\nduration = 3.0\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let faults = kind(&r, "fault");
    assert_eq!(faults.len(), 1, "{faults:?}");
    let f = faults[0];
    // The command is 500·t² to 10 ms (0.05), then 10 units/s. The motor cannot be ahead of
    // ½·159.15·t², so the error passes 0.05 by 11 ms; it cannot pass it before the command
    // itself does, at 10 ms. At 11 ms the command is 0.06.
    assert_eq!(f["tick"], 11, "{f}");
    assert_eq!(f["fault"], "following_error");
    assert_eq!(num(f, "limit"), 0.05);
    assert!((num(f, "command") - 0.06).abs() < 1e-12, "{f}");
    let a_max = 0.2 / 2.0e-4 / std::f64::consts::TAU;
    let reach = 0.5 * a_max * 0.011 * 0.011;
    let at_fault = num(f, "feedback");
    assert!(at_fault > 0.0 && at_fault <= reach, "{f}");
    assert!(num(f, "command") - at_fault > 0.05);
    // The fault member is traced at that update, and the program saw it there.
    let fault_on = r
        .events
        .iter()
        .find(|e| e["kind"] == "change" && e["name"] == "FollowingErrorFault")
        .expect("FollowingErrorFault traced");
    assert_eq!(fault_on["tick"], 11);
    assert_eq!(fault_on["value"], true);
    assert_eq!(r.machine.value_of("Var.T"), Some(11_000.0));
    // The index was ended at once: its status says done, with no motion left.
    let done: Vec<_> = r
        .events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == "Index.0.CommandComplete")
        .collect();
    assert!(done.iter().any(|e| e["tick"] == 11 && e["value"] == true));
    // An initiate on the faulted drive is refused with a warning.
    let refused = kind(&r, "warning");
    assert!(
        refused.iter().any(|w| w["message"]
            .as_str()
            .is_some_and(|m| m.contains("Index.1 initiate") && m.contains("FaultReset"))),
        "{refused:?}"
    );
    // Reset: the fault is off, and index 1 moved one unit from where the motor was held.
    assert_eq!(r.machine.value_of("Bit.R"), Some(0.0));
    assert_eq!(r.machine.value_of("FollowingErrorFault"), Some(0.0));
    let held = kind(&r, "motion")
        .into_iter()
        .find(|e| e["object"] == "Index.1" && e["event"] == "start")
        .map(|e| num(e, "position"))
        .expect("index 1 started after the reset");
    // The motor stopped at the torque limit within what it could travel from its speed.
    let v_max = a_max * 0.011;
    assert!(held >= at_fault && held <= at_fault + v_max * v_max / (2.0 * a_max) + 1e-3);
    let command = r.machine.value_of("PosnCommand").expect("PosnCommand");
    let feedback = r.machine.value_of("PosnFeedback").expect("PosnFeedback");
    assert!((command - held - 1.0).abs() < 1e-9, "{command} {held}");
    assert!(
        (command - feedback).abs() < 2.0 / 4096.0,
        "{command} {feedback}"
    );
}

#[test]
fn without_following_error_enable_the_servo_only_lags() {
    let machine = format!(
        "{}{INDEXES}",
        WEAK_SERVO.replace("following_error_limit = 0.05\n", "")
    );
    let r = common::run_project(
        "servo-lag",
        "Index.0.Initiate\nWait For Index.0.CommandComplete\nWait For Time 0.5\nEnd\n",
        &machine,
        "[run]\nduration = 2.0\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    assert!(kind(&r, "fault").is_empty());
    let command = r.machine.value_of("PosnCommand").expect("PosnCommand");
    let feedback = r.machine.value_of("PosnFeedback").expect("PosnFeedback");
    assert_eq!(command, 5.0);
    // It got there in the end, within a count or two.
    assert!((feedback - 5.0).abs() < 2.0 / 4096.0, "{feedback}");
}

#[test]
fn a_capture_latches_the_encoder_count_at_the_edge_plus_the_latch_delay() {
    // Geared 1:1 to a master at 10 units/s with full velocity feedforward: in steady state the
    // motor is on its command, so the latch sees the command 2 µs later, in whole counts.
    let machine = "[servo]\nmodel = \"cascade\"\nvelocity_feedforward = 100.0\n\
        acceleration_feedforward = 100.0\nlatch_delay = \"2us\"\n\
        [[assignment]]\nsource = \"ModuleInput.2\"\ndestination = \"Capture.0.CaptureActivate\"\n";
    let program = "Gear.Ratio = 1\nGear.Initiate\nCapture.0.CaptureEnable = ON\n\
        Wait For Capture.0.CaptureTriggered\nEnd\n";
    let scenario = "[run]\nduration = 2.0\n[master]\nspeed = 10.0\n\
        [[press]]\nname = \"ModuleInput.2\"\nat = 1.2345678\nlength = 0.01\n";
    let r = common::run_project("servo-capture", program, machine, scenario);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let c = kind(&r, "capture");
    assert_eq!(c.len(), 1, "{c:?}");
    let (command, feedback) = (num(c[0], "command"), num(c[0], "feedback"));
    assert!((command - 12.345678).abs() < 1e-6, "{command}");
    let counts = feedback * 4096.0;
    assert_eq!(counts, counts.round(), "{feedback} is not a whole count");
    let expected = ((command + 10.0 * 2e-6) * 4096.0).floor();
    assert!((counts - expected).abs() <= 1.0, "{counts} {expected}");
}

#[test]
fn servo_values_out_of_range_are_errors_at_their_text() {
    let machine = "[servo]\nmodel = \"cascade\"\nmodel_x = 1\n";
    let err = common::load_memory(
        "servo-bad",
        &[
            ("program0.pt", "End\n"),
            ("machine.toml", machine),
            ("scenario.toml", "[run]\nduration = 1.0\n"),
        ],
    )
    .err()
    .expect("errors");
    let text = err.render_plain();
    assert!(text.contains("model_x"), "{text}");
    let machine = "[servo]\nmodel = \"stepper\"\n";
    let text = common::load_memory(
        "servo-model",
        &[("program0.pt", "End\n"), ("machine.toml", machine)],
    )
    .err()
    .expect("an unknown model is an error")
    .render_plain();
    assert!(text.contains("`stepper` is not a servo model"), "{text}");
    let machine = "[machine]\nupdate = \"1s\"\n[servo]\ntorque_limit = -1.0\n\
        loop_rate = 100000.0\nvelocity_feedforward = 300.0\n";
    let text = common::load_memory(
        "servo-range",
        &[("program0.pt", "End\n"), ("machine.toml", machine)],
    )
    .err()
    .expect("out of range")
    .render_plain();
    assert!(
        text.contains("torque_limit -1 N·m is out of range"),
        "{text}"
    );
    assert!(
        text.contains("velocity_feedforward 300 % is out of range"),
        "{text}"
    );
    assert!(
        text.contains("makes 100,000 loop steps per update"),
        "{text}"
    );
}

/// A MotionBASIC web axis on the weak servo (one unit per revolution: 159.15 units/s² at most)
/// ramped at 1000 units/s², and a PowerTools program that watches its fault and resets it.
const DSP_MACHINE: &str = "[machine]\nupdate = \"1ms\"\n\
    [[program]]\nnumber = 0\nfile = \"web.mb\"\nautostart = true\n\
    [[program]]\nnumber = 1\nfile = \"watch.pt\"\nautostart = true\n\
    [variables.T]\ndecimals = 0\n\
    [axis.1]\nunits_per_rev = 1\naccel = 10\n\
    [axis.1.servo]\nmodel = \"cascade\"\nposition_gain = 100.0\nvelocity_gain = 314.0\n\
    velocity_integral = 12000.0\nmotor_inertia = 1.0e-4\nload_inertia = 1.0e-4\n\
    torque_limit = 0.2\nfollowing_error_limit = 0.05\n";

#[test]
fn a_dsp_axis_past_its_torque_limit_faults_its_command_ramps_to_rest_and_a_reset_clears_it() {
    let loaded = common::load_memory(
        "dsp-servo-fault",
        &[
            ("web.mb", "w~ = {1}\nMOVE w~ AT 6000 IN 100\nEND\n"),
            (
                "watch.pt",
                "Wait For Axis.1.FollowingErrorFault\nVar.T = FreeRunTime\nWait For Time 2\n\
                 Axis.1.FaultReset = ON\nEnd\n",
            ),
            ("machine.toml", DSP_MACHINE),
            ("scenario.toml", "[run]\nduration = 3.0\n"),
        ],
    )
    .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let r = common::run_loaded(loaded);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let faults = kind(&r, "fault");
    assert_eq!(faults.len(), 1, "{faults:?}");
    let f = faults[0];
    // As on the drive: the command 500·t² passes 0.05 at 10 ms, the motor cannot be ahead of
    // ½·159.15·t², so the error passes the limit at the 11 ms update, the command at 0.0605.
    assert_eq!(f["tick"], 11, "{f}");
    assert_eq!(f["axis"], "Axis.1");
    assert!((num(f, "command") - 0.0605).abs() < 1e-12, "{f}");
    assert!(num(f, "command") - num(f, "feedback") > 0.05, "{f}");
    assert_eq!(r.machine.value_of("Var.T"), Some(11_000.0));
    // The command ramped to rest at 10 units/s² (from 11 units/s: 1.1 s) and the reset put it
    // on the held motor: no error left, nothing moving, the fault off.
    assert_eq!(r.machine.value_of("Axis.1.Velocity"), Some(0.0));
    assert_eq!(r.machine.value_of("Axis.1.FollowingErrorFault"), Some(0.0));
    let error = r.machine.value_of("Axis.1.FollowingError").expect("error");
    assert!(error.abs() < 2.0 / 4096.0, "{error}");
    let position = r.machine.value_of("Axis.1.Position").expect("position");
    let feedback = r.machine.value_of("Axis.1.Feedback").expect("feedback");
    assert!((position - feedback - error).abs() < 1e-12);
    let a_max = 0.2 / 2.0e-4 / std::f64::consts::TAU;
    let v_max = a_max * 0.011;
    assert!(
        feedback > 0.0
            && feedback < 0.5 * a_max * 0.011 * 0.011 + v_max * v_max / (2.0 * a_max) + 1e-3
    );
}

/// Issue 20: the labeler on a real servo shows its following error in the trace (a `change` at
/// each update it moves) and in the VCD (a real variable with the same changes).
#[test]
fn the_labeler_on_a_real_servo_traces_its_following_error_and_exports_it_to_vcd() {
    let dir = common::scratch_in("servo", "labeling-vcd");
    let trace = dir.join("t.jsonl");
    let vcd = dir.join("t.vcd");
    let (trace_arg, vcd_arg) = (trace.to_string_lossy(), vcd.to_string_lossy());
    let o = common::pacer(&[
        "run",
        "programs/labeling-servo",
        "--for",
        "2",
        "--quiet",
        "--trace",
        &trace_arg,
        "--vcd",
        &vcd_arg,
    ]);
    assert!(o.status.success(), "{}", common::text(&o));
    let text = std::fs::read_to_string(&trace).expect("the trace");
    let errors: Vec<f64> = text
        .lines()
        .filter(|l| l.contains("\"name\":\"FollowingError\""))
        .map(|l| {
            let e: Value = serde_json::from_str(l).expect("a JSON line");
            num(&e, "value")
        })
        .collect();
    assert!(errors.len() > 100, "{} changes", errors.len());
    // The servo lags while the label moves, within its 1-unit fault limit.
    let worst = errors.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    assert!(worst > 1e-4 && worst < 1.0, "worst following error {worst}");
    let vcd_text = std::fs::read_to_string(&vcd).expect("the VCD");
    let id = vcd_text
        .lines()
        .find(|l| l.starts_with("$var real") && l.contains(" FollowingError "))
        .and_then(|l| l.split_whitespace().nth(3))
        .expect("FollowingError declared in the VCD")
        .to_string();
    let changes = vcd_text
        .lines()
        .filter(|l| l.starts_with('r') && l.ends_with(&format!(" {id}")))
        .count();
    assert!(changes > 100, "{changes} VCD changes");
}
