//! Index moves and dwells on the servo axis: the spec's blocking and timing examples, starts
//! from a capture, absolute moves, and the two profiles adding up.

mod common;

use serde_json::Value;

use common::Run;

fn run(name: &str, program: &str, machine: &str, scenario: &str) -> Run {
    common::run_project(name, program, machine, scenario)
}

fn motions<'a>(r: &'a Run, object: &str, event: &str) -> Vec<&'a Value> {
    r.events
        .iter()
        .filter(|e| e["kind"] == "motion" && e["object"] == object && e["event"] == event)
        .collect()
}

/// Index 0: 2 units at 1 u/s with 1 u/s² ramps = 3 s; Index 1: 4 units = 5 s.
const TWO_INDEXES: &str = "[variables.T]\ndecimals = 0\n\
    [index.0]\ndistance = 2.0\nvelocity = 1.0\nacceleration = 1.0\ndeceleration = 1.0\n\
    [index.1]\ndistance = 4.0\nvelocity = 1.0\nacceleration = 1.0\ndeceleration = 1.0\n";

#[test]
fn a_second_initiate_blocks_until_the_first_index_completes() {
    let program = "Index.0.Initiate\nIndex.1.Initiate\nVar.T = FreeRunTime\nEnd\n";
    let r = run("block", program, TWO_INDEXES, "[run]\nduration = 10.0\n");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // Index 0 ends at 3 s; the program goes on in that update, after the control loop.
    assert_eq!(r.machine.value_of("Var.T"), Some(3_000_000.0));
    assert_eq!(motions(&r, "Index.0", "done")[0]["tick"], 3000);
    assert_eq!(r.machine.value_of("PosnCommand"), Some(6.0));
    assert_eq!(r.machine.value_of("Index.1.CommandComplete"), Some(1.0));
}

#[test]
fn using_last_chains_3_s_and_a_1_s_dwell_and_5_s_into_9_s_exactly() {
    // An update of 0.7 ms divides none of the times: without chaining, updates would be lost.
    let machine = format!("[machine]\nupdate = \"700us\"\n{TWO_INDEXES}");
    let program =
        "Index.0.Initiate\nDwell For Time 1 Using Last\nIndex.1.Initiate Using Last\nEnd\n";
    let r = run("last", program, &machine, "[run]\nduration = 10.0\n");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let ends: Vec<f64> = r
        .events
        .iter()
        .filter(|e| e["kind"] == "motion" && e["event"] == "done")
        .map(|e| e["end"].as_f64().expect("end"))
        .collect();
    assert_eq!(ends.len(), 3, "index, dwell, index");
    assert!((ends[0] - 3.0).abs() < 1e-12, "{ends:?}");
    assert!((ends[1] - 4.0).abs() < 1e-12, "{ends:?}");
    assert!((ends[2] - 9.0).abs() < 1e-12, "{ends:?}");
    assert_eq!(r.machine.value_of("PosnCommand"), Some(6.0));
}

#[test]
fn without_using_last_the_chain_loses_update_time() {
    let machine = format!("[machine]\nupdate = \"700us\"\n{TWO_INDEXES}");
    let program = "Index.0.Initiate\nDwell For Time 1\nIndex.1.Initiate\nEnd\n";
    let r = run("nolast", program, &machine, "[run]\nduration = 10.0\n");
    let last = motions(&r, "Index.1", "done")[0]["end"]
        .as_f64()
        .expect("end");
    // Index 1 starts at the update its program reaches it, after the dwell was seen to end.
    assert!(last > 9.0 && last < 9.0 + 0.0007 * 2.0, "{last}");
}

#[test]
fn a_synchronized_index_starts_at_the_captured_master_position_at_any_line_speed() {
    for speed in [7.0, 40.0, 133.0, 350.0] {
        let machine = "[index.0]\ntime_base = \"Synchronized\"\ndistance = 0.5\nvelocity = 2.0\nacceleration = 20.0\ndeceleration = 20.0\n\
                       [[assignment]]\nsource = \"ModuleInput.2\"\ndestination = \"Capture.0.CaptureActivate\"\n";
        // Start the index 3.3 master units after the product edge, from the capture.
        let program = "Capture.0.CaptureEnable=ON\nWait For Capture.0.CaptureTriggered\n\
                       Capture.1.CapturedMasterPosition=Capture.0.CapturedMasterPosition + 3.3\n\
                       Index.0.Initiate Using Capture.1\nEnd\n";
        let scenario = format!("[run]\nduration = 2.0\n[master]\nspeed = {speed}\n[[products]]\nsensor = \"ModuleInput.2\"\nfirst = 1.2345678\npitch = 50.0\nlength = 1.0\ncount = 1\n");
        let r = run(&format!("sync{speed}"), program, machine, &scenario);
        assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
        let start = motions(&r, "Index.0", "start");
        assert_eq!(start.len(), 1, "at {speed}");
        let m = start[0]["master"].as_f64().expect("master");
        assert!(
            (m - (1.2345678 + 3.3)).abs() < 1e-9,
            "at {speed}: started at {m}"
        );
        // The move is 0.5 master units long in its own domain, whatever the line speed.
        let end = motions(&r, "Index.0", "done")[0]["end"]
            .as_f64()
            .expect("end");
        let len = end - m;
        assert!(
            (len - 0.35).abs() < 1e-9,
            "0.5 units at 2/unit with 20/unit² ramps span 0.35 master units, not {len}"
        );
    }
}

#[test]
fn an_absolute_index_moves_to_its_position_and_profiles_add_up() {
    let machine = "[index.0]\ntype = \"Absolute\"\ndistance = 5.0\nvelocity = 10.0\nacceleration = 100.0\ndeceleration = 100.0\n\
                   [index.1]\ndistance = 2.0\nvelocity = 10.0\nacceleration = 100.0\ndeceleration = 100.0\n";
    let program = "Index.0.Initiate\nIndex.1.Initiate On Profile.1\nWait For Index.0.CommandComplete AND Index.1.CommandComplete\n\
                   Index.0.Distance = 3.0\nIndex.0.Initiate\nEnd\n";
    let r = run("abs", program, machine, "[run]\nduration = 2.0\n");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // 5 (absolute, profile 0) + 2 (profile 1) = 7; then absolute 3 moves profile 0 by 3 - 7.
    assert_eq!(r.machine.value_of("PosnCommand"), Some(3.0));
    assert_eq!(r.machine.value_of("Index.0.CommandComplete"), Some(1.0));
    assert_eq!(r.machine.value_of("Index.0.CommandInProgress"), Some(0.0));
}

#[test]
fn an_unknown_index_type_is_refused_where_it_is_set() {
    let machine = "[index.0]\ntype = \"Spiral\"\n";
    let d = common::load_error(
        "spiral",
        &[
            ("program0.pt", "Index.0.Initiate\n"),
            ("machine.toml", machine),
        ],
    );
    assert_eq!(d.items.len(), 1);
    let p = &d.items[0].problem;
    assert_eq!(p.code, "pacer::machine::index");
    assert_eq!(&machine[p.span.start..p.span.end], "\"Spiral\"");
    assert!(p.message.contains("unknown index type"), "{}", p.message);
    assert!(
        p.label.contains("Registration") && p.label.contains("RotaryPlus"),
        "{}",
        p.label
    );
}

const HOME: &str = "[home.0]\nreference = \"ModuleInput.3\"\nvelocity = 10.0\nacceleration = 100.0\ndeceleration = 50.0\n";
const HOME_SENSOR: &str = "[run]\nduration = 3.0\n[[axis_marks]]\nsensor = \"ModuleInput.3\"\nfirst = 12.5537\nwidth = 5.0\n";

#[test]
fn home_with_a_calculated_offset_stops_as_soon_as_it_can_after_the_reference() {
    let program = "Home.0.Initiate\nWait For Home.0.CommandComplete\nVar.T = FreeRunTime\nEnd\n";
    let r = run(
        "home-calc",
        program,
        &format!("[variables.T]\n{HOME}"),
        HOME_SENSOR,
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // 10 u/s, decel 50 u/s²: 1 unit to stop after the reference at 12.5537.
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert!((end - 13.5537).abs() < 1e-9, "{end}");
    assert_eq!(r.machine.value_of("Home.0.CommandComplete"), Some(1.0));
    // Reference at 12.5537: 0.5 u while accelerating (0.1 s) + 12.0537 u at 10 u/s = 1.30537 s,
    // inside an update; 0.2 s to stop: done at 1.50537 s, so at the update at 1.506 s.
    assert_eq!(r.machine.value_of("Var.T"), Some(1_506_000.0));
    assert_eq!(
        r.machine.value_of("ModuleInput.3"),
        Some(1.0),
        "the sensor is on over its mark"
    );
}

#[test]
fn home_with_a_specified_offset_goes_on_to_it() {
    let machine = format!("{HOME}offset = 2.0\n");
    let r = run("home-spec", "Home.0.Initiate\nEnd\n", &machine, HOME_SENSOR);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert!((end - 14.5537).abs() < 1e-9, "{end}");
}

#[test]
fn a_specified_offset_too_short_to_stop_in_falls_back_to_the_calculated_one_with_a_warning() {
    let machine = format!("{HOME}offset = 0.5\n");
    let r = run(
        "home-short",
        "Home.0.Initiate\nEnd\n",
        &machine,
        HOME_SENSOR,
    );
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert!((end - 13.5537).abs() < 1e-9, "{end}");
    let warnings: Vec<&Value> = r.events.iter().filter(|e| e["kind"] == "warning").collect();
    assert_eq!(warnings.len(), 1);
    assert!(warnings[0]["message"]
        .as_str()
        .unwrap_or("")
        .contains("shorter than the distance needed to stop"));
}

#[test]
fn a_capture_from_a_sensor_on_the_axis_latches_the_axis_position_at_the_mark() {
    let machine = "[index.0]\ndistance = 30.0\nvelocity = 7.0\nacceleration = 20.0\ndeceleration = 20.0\n\
                   [[assignment]]\nsource = \"ModuleInput.3\"\ndestination = \"Capture.0.CaptureActivate\"\n";
    let program = "Capture.0.CaptureEnable=ON\nIndex.0.Initiate\nEnd\n";
    let scenario = "[run]\nduration = 6.0\n[[axis_marks]]\nsensor = \"ModuleInput.3\"\nfirst = 4.321\npitch = 10.0\ncount = 3\nwidth = 0.5\n";
    let r = run("axis-capture", program, machine, scenario);
    let captures: Vec<&Value> = r.events.iter().filter(|e| e["kind"] == "capture").collect();
    assert_eq!(captures.len(), 1, "captures latch once until cleared");
    let c = captures[0]["command"].as_f64().expect("command");
    // The axis cruises at the mark: positions interpolated inside the update are exact there.
    assert!((c - 4.321).abs() < 1e-9, "{c}");
    assert_eq!(captures[0]["feedback"], captures[0]["command"]);
}

/// Index 0: a long move at 10 u/s (reached in 0.1 s), deceleration 100 u/s².
const LONG_INDEX: &str =
    "[index.0]\ndistance = 1000.0\nvelocity = 10.0\nacceleration = 100.0\ndeceleration = 100.0\n";

#[test]
fn index_stop_decelerates_at_the_index_deceleration() {
    let program = "Index.0.Initiate\nWait For Time 1.0\nIndex.0.Stop\nWait For Index.0.CommandComplete\nEnd\n";
    let r = run("index-stop", program, LONG_INDEX, "[run]\nduration = 3.0\n");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // At 1.0 s: 0.5 u while accelerating + 9 u at 10 u/s = 9.5 u; then 10²/(2·100) = 0.5 u more.
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert!((end - 10.0).abs() < 1e-9, "{end}");
    assert_eq!(r.machine.value_of("Index.0.CommandComplete"), Some(1.0));
    let decelerating = r.events.iter().any(|e| {
        e["kind"] == "change" && e["name"] == "Index.0.Decelerating" && e["value"] == true
    });
    assert!(decelerating, "the stop ramps down");
}

#[test]
fn stop_ends_the_programs_and_ramps_motion_down_at_stop_deceleration() {
    let program =
        "StopDeceleration = 50\nIndex.0.Initiate\nWait For Time 1.0\nStop\nVar.X = 1\nEnd\n";
    let r = run(
        "stop-all",
        program,
        &format!("[variables.X]\n{LONG_INDEX}"),
        "[run]\nduration = 3.0\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    assert_eq!(
        r.machine.value_of("Var.X"),
        Some(0.0),
        "the program stopped at Stop"
    );
    // 9.5 u at the stop, then 10²/(2·50) = 1 u.
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert!((end - 10.5).abs() < 1e-9, "{end}");
    assert_eq!(r.machine.value_of("VelCommand"), Some(0.0));
}

#[test]
fn stop_with_no_stop_deceleration_halts_at_once() {
    let program = "Index.0.Initiate\nWait For Time 1.0\nStop\n";
    let r = run("stop-now", program, LONG_INDEX, "[run]\nduration = 2.0\n");
    let end = r.machine.value_of("PosnCommand").expect("position");
    // The stop comes in the task after the control loop of the update at 1.0 s.
    assert!((end - 9.5).abs() < 1e-9, "{end}");
    assert_eq!(r.machine.value_of("Profile.0.Busy"), Some(0.0));
}

#[test]
fn gear_follows_the_master_at_its_ratio_and_stops() {
    let program =
        "Gear.Ratio = 0.5\nGear.Initiate\nWait For Time 1.0\nVar.P = PosnCommand\nGear.Stop\nEnd\n";
    let r = run(
        "gear",
        program,
        "[variables.P]\ndecimals = 6\n",
        "[run]\nduration = 2.0\n[master]\nspeed = 20.0\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // Geared from master 0 at update 0; at 1.0 s the master is at 20: the axis at 10.
    assert_eq!(r.machine.value_of("Var.P"), Some(10.0));
    assert_eq!(
        r.machine.value_of("PosnCommand"),
        Some(10.0),
        "stopped where it was"
    );
    assert_eq!(r.machine.value_of("Gear.CommandInProgress"), Some(0.0));
}

#[test]
fn gear_activate_from_an_assignment_gears_while_the_input_is_on() {
    let machine = "[[assignment]]\nsource = \"DriveInput.2\"\ndestination = \"Gear.Activate\"\n";
    let program = "Gear.Ratio = 2\nWait For Time 5\n";
    let scenario = "[run]\nduration = 3.0\n[master]\nspeed = 10.0\n[[press]]\nname = \"DriveInput.2\"\nat = 0.5\nlength = 1.0\n";
    let r = run("gear-activate", program, machine, scenario);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // Geared from master 5 to master 15 at ratio 2.
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert!((end - 20.0).abs() < 1e-9, "{end}");
}

const JOGS: &str = "[variables.P]\ndecimals = 6\n";

#[test]
fn jog_initiates_run_until_stopped_and_ramp_down() {
    let program = "Jog.0.Velocity = 5\nJog.0.Acceleration = 50\nJog.0.Deceleration = 25\n\
                   Jog.0.MinusInitiate\nWait For Time 1\nJog.0.Stop\nWait For Time 1\nVar.P = PosnCommand\n";
    let r = run("jog-initiate", program, JOGS, "[run]\nduration = 3.0\n");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // Minus: 0.25 u accelerating (0.1 s) + 0.9 s at 5 u/s = 4.75 u; then 5²/(2·25) = 0.5 u.
    assert_eq!(r.machine.value_of("Var.P"), Some(-5.25));
    assert_eq!(r.machine.value_of("Jog.0.CommandInProgress"), Some(0.0));
}

#[test]
fn jog_activate_is_level_sensitive_and_select_picks_the_jog() {
    let machine = "[[assignment]]\nsource = \"DriveInput.3\"\ndestination = \"Jog.PlusActivate\"\n";
    let program = "Jog.1.Velocity = 2\nJog.1.Acceleration = 1000\nJog.1.Deceleration = 1000\nJog.Select = ON\nWait For Time 5\n";
    let scenario =
        "[run]\nduration = 3.0\n[[press]]\nname = \"DriveInput.3\"\nat = 0.5\nlength = 1.0\n";
    let r = run("jog-activate", program, machine, scenario);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // About 1 s at 2 u/s with near-instant ramps (ramps of 2 ms each way).
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert!((end - 2.0).abs() < 0.01, "{end}");
    assert_eq!(r.machine.value_of("Jog.1.CommandInProgress"), Some(0.0));
}

fn registration(name: &str, mark_at: f64, offset: f64) -> Run {
    let machine = format!(
        "[index.0]\ntype = \"Registration\"\ndistance = 20.0\nvelocity = 10.0\nacceleration = 100.0\ndeceleration = 100.0\nregistration_offset = {offset}\n\
         [[assignment]]\nsource = \"ModuleInput.3\"\ndestination = \"Index.0.SensorTrigger\"\n"
    );
    let scenario = format!("[run]\nduration = 4.0\n[[axis_marks]]\nsensor = \"ModuleInput.3\"\nfirst = {mark_at}\nwidth = 0.2\n");
    run(
        name,
        "Index.0.Initiate\nWait For Index.0.CommandComplete\nEnd\n",
        &machine,
        &scenario,
    )
}

#[test]
fn a_registration_index_stops_its_offset_past_the_sensor() {
    let r = registration("reg", 7.3, 0.75);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert!((end - 8.05).abs() < 1e-9, "{end}");
    assert_eq!(r.machine.value_of("Index.0.LimitDistHit"), Some(0.0));
    assert_eq!(r.machine.value_of("Index.0.CommandComplete"), Some(1.0));
}

#[test]
fn without_its_sensor_a_registration_index_stops_at_its_limit_and_says_so() {
    let r = registration("reg-limit", 30.0, 0.75);
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert_eq!(end, 20.0);
    assert_eq!(r.machine.value_of("Index.0.LimitDistHit"), Some(1.0));
}

#[test]
fn a_registration_offset_shorter_than_the_stop_stops_as_soon_as_it_can() {
    // 10 u/s at 100 u/s²: 0.5 u to stop.
    let r = registration("reg-short", 7.3, 0.1);
    let end = r.machine.value_of("PosnCommand").expect("position");
    assert!((end - 7.8).abs() < 1e-9, "{end}");
}

#[test]
fn a_timed_index_takes_its_time_or_reports_profile_limited() {
    let machine = "[variables.T]\n[index.0]\ndistance = 10.0\nvelocity = 100.0\nacceleration = 10.0\ndeceleration = 10.0\ntime = 4.0\n";
    let program = "Index.0.Initiate\nWait For Index.0.CommandComplete\nVar.T = FreeRunTime\n\
                   Index.0.Velocity = 5\nIndex.0.Time = 0.5\nIndex.0.Initiate\nEnd\n";
    let r = run("timed", program, machine, "[run]\nduration = 10.0\n");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // 10 units in exactly 4 s.
    assert_eq!(r.machine.value_of("Var.T"), Some(4_000_000.0));
    let ends: Vec<f64> = r
        .events
        .iter()
        .filter(|e| e["kind"] == "motion" && e["event"] == "done")
        .map(|e| e["end"].as_f64().unwrap_or(f64::NAN))
        .collect();
    assert!((ends[0] - 4.0).abs() < 1e-9, "{ends:?}");
    // 0.5 s is impossible at 5 u/s: the move takes 2.5 s and says so.
    assert!((ends[1] - ends[0] - 2.5).abs() < 1e-9, "{ends:?}");
    assert_eq!(r.machine.value_of("Index.0.ProfileLimited"), Some(1.0));
    assert_eq!(r.machine.value_of("PosnCommand"), Some(20.0));
}

#[test]
fn a_module_input_assigned_to_initiate_starts_the_index_at_its_exact_edge() {
    let machine = "[index.0]\ntime_base = \"Synchronized\"\ndistance = 0.2\nvelocity = 1.0\nacceleration = 50.0\ndeceleration = 50.0\n\
                   [[assignment]]\nsource = \"ModuleInput.2\"\ndestination = \"Index.0.Initiate\"\n";
    let scenario = "[run]\nduration = 3.0\n[master]\nspeed = 37.0\n[[products]]\nsensor = \"ModuleInput.2\"\nfirst = 3.21\npitch = 5.0\nlength = 1.0\ncount = 10\n";
    let r = run("edge-initiate", "Wait For Time 10\n", machine, scenario);
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let starts: Vec<f64> = r
        .events
        .iter()
        .filter(|e| e["kind"] == "motion" && e["event"] == "start")
        .map(|e| e["master"].as_f64().unwrap_or(f64::NAN))
        .collect();
    assert_eq!(starts.len(), 10);
    for (k, m) in starts.iter().enumerate() {
        let lead = 3.21 + 5.0 * k as f64;
        assert!(
            (m - lead).abs() < 1e-9,
            "index {k} started at {m}, edge at {lead}"
        );
    }
}

#[test]
fn a_drive_input_assigned_to_initiate_starts_at_the_update() {
    let machine = "[index.0]\ntime_base = \"Synchronized\"\ndistance = 0.2\nvelocity = 1.0\nacceleration = 50.0\ndeceleration = 50.0\n\
                   [[assignment]]\nsource = \"DriveInput.2\"\ndestination = \"Index.0.Initiate\"\n";
    let scenario = "[run]\nduration = 1.0\n[master]\nspeed = 37.0\n[[press]]\nname = \"DriveInput.2\"\nat = 0.1004\nlength = 0.01\n";
    let r = run("drive-initiate", "Wait For Time 10\n", machine, scenario);
    let start = r
        .events
        .iter()
        .find(|e| e["kind"] == "motion" && e["event"] == "start")
        .map(|e| e["master"].as_f64().unwrap_or(f64::NAN));
    // Sampled at the update at 0.101 s: the master was at 3.737 there.
    assert!(
        (start.unwrap_or(f64::NAN) - 3.737).abs() < 1e-9,
        "{start:?}"
    );
}

#[test]
fn rotary_indexes_go_round_a_rolled_over_axis_in_their_direction() {
    let machine = "[machine]\nrollover = 360.0\n[variables.A]\ndecimals = 3\n[variables.B]\ndecimals = 3\n\
                   [index.0]\ntype = \"RotaryPlus\"\ndistance = 90.0\nvelocity = 720.0\nacceleration = 7200.0\ndeceleration = 7200.0\n\
                   [index.1]\ntype = \"RotaryMinus\"\ndistance = 300.0\nvelocity = 720.0\nacceleration = 7200.0\ndeceleration = 7200.0\n";
    let program = "Index.0.Initiate\nIndex.1.Initiate\nWait For Index.1.CommandComplete\nVar.A = PosnCommand\n\
                   Index.0.Distance = 10\nIndex.0.Initiate\nWait For Index.0.CommandComplete\nVar.B = PosnCommand\nEnd\n";
    let r = run("rotary", program, machine, "[run]\nduration = 3.0\n");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // 0 → 90 plus; 90 → 300 minus (150° back); 300 → 10 plus (70° on).
    assert_eq!(r.machine.value_of("Var.A"), Some(300.0));
    assert_eq!(r.machine.value_of("Var.B"), Some(10.0));
    let moves: Vec<f64> = r
        .events
        .iter()
        .filter(|e| e["kind"] == "motion" && e["event"] == "done")
        .map(|e| e["position"].as_f64().unwrap_or(f64::NAN))
        .collect();
    // Unwrapped positions along the way: 90, -60, 10.
    assert_eq!(moves, [90.0, -60.0, 10.0]);
}

#[test]
fn a_rotary_index_needs_an_axis_rollover() {
    let machine = "[index.0]\ntype = \"RotaryMinus\"\n";
    let d = common::load_error(
        "rotary-norollover",
        &[
            ("program0.pt", "Index.0.Initiate\n"),
            ("machine.toml", machine),
        ],
    );
    let p = &d.items[0].problem;
    assert_eq!(p.code, "pacer::machine::index");
    assert!(p.message.contains("no rollover"), "{}", p.message);
    assert_eq!(&machine[p.span.start..p.span.end], "\"RotaryMinus\"");
}

/// 10 units at 1 u/s with near-instant ramps: 10.001 s at 100 %.
const SLOW_INDEX: &str = "[variables.T]\n[index.0]\ndistance = 10.0\nvelocity = 1.0\nacceleration = 1000.0\ndeceleration = 1000.0\n";

#[test]
fn feed_rate_override_scales_realtime_motion_in_time() {
    let program = "FeedRateOverride = 50\nIndex.0.Initiate\nWait For Index.0.CommandComplete\nVar.T = FreeRunTime\nEnd\n";
    let r = run(
        "override-50",
        program,
        SLOW_INDEX,
        "[run]\nduration = 30.0\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // 10.001 s of motion at half speed: 20.002 s.
    assert_eq!(r.machine.value_of("Var.T"), Some(20_002_000.0));
    assert_eq!(r.machine.value_of("PosnCommand"), Some(10.0));
}

#[test]
fn feed_rate_override_takes_effect_at_once() {
    let program = "Index.0.Initiate\nWait For Time 2\nFeedRateOverride = 200\nWait For Index.0.CommandComplete\nVar.T = FreeRunTime\nEnd\n";
    let r = run(
        "override-change",
        program,
        SLOW_INDEX,
        "[run]\nduration = 30.0\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // 2 s at 100 %, then the remaining 8.001 s of motion at twice the speed: about 6 s.
    let t = r.machine.value_of("Var.T").expect("T") / 1e6;
    assert!((t - 6.0005).abs() <= 0.0015, "{t}");
}

#[test]
fn feed_rate_override_scales_dwells_but_not_program_waits() {
    let program = "FeedRateOverride = 25\nDwell For Time 1\nDwell For Time 0\nVar.T = FreeRunTime\nWait For Time 1\nVar.T = FreeRunTime - Var.T\nEnd\n";
    let r = run(
        "override-dwell",
        program,
        "[variables.T]\n",
        "[run]\nduration = 10.0\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // The dwell took 4 s; the program's own 1 s wait is still 1 s.
    assert_eq!(r.machine.value_of("Var.T"), Some(1_000_000.0));
    let dwell_end = r
        .events
        .iter()
        .find(|e| e["kind"] == "motion" && e["event"] == "done")
        .map(|e| e["tick"].clone());
    assert_eq!(dwell_end, Some(serde_json::json!(4000)));
}

#[test]
fn index_pls_status_follows_the_distance_the_index_has_travelled() {
    let machine = "[index.0]\ndistance = 10.0\nvelocity = 10.0\nacceleration = 1000.0\ndeceleration = 1000.0\n";
    let program =
        "Index.0.PLSOnPoint = 2.034\nIndex.0.PLSOffPoint = 5.073\nIndex.0.Initiate\nEnd\n";
    let r = run("index-pls", program, machine, "[run]\nduration = 2.0\n");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let changes: Vec<(u64, bool)> = r
        .events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == "Index.0.PLSStatus")
        .map(|e| (e["tick"].as_u64().unwrap_or(0), e["value"] == true))
        .collect();
    // 10 u/s after a 10 ms ramp (0.05 u): 2.034 u at 0.2084 s, 5.073 u at 0.5123 s.
    assert_eq!(changes, [(209, true), (513, false)]);
}

#[test]
fn user_units_give_motor_revolutions_and_encoder_counts() {
    let machine = "[units]\nmotor = \"mm\"\nmotor_per_rev = 10.0\nmotor_counts_per_rev = 4096\nmaster = \"in\"\nmaster_counts_per_unit = 100\n\
                   [index.0]\ndistance = 25.0\nvelocity = 100.0\nacceleration = 1000.0\ndeceleration = 1000.0\n";
    let r = run(
        "units",
        "Index.0.Initiate\nEnd\n",
        machine,
        "[run]\nduration = 1.0\n[master]\nspeed = 12.345\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    assert_eq!(r.machine.value_of("MotorRevs"), Some(2.5));
    assert_eq!(r.machine.value_of("MotorCounts"), Some(10240.0));
    assert_eq!(r.machine.value_of("MasterCounts"), Some(1234.0));
    assert_eq!(
        r.events[0]["units"],
        serde_json::json!({"motor": "mm", "master": "in"})
    );
}

#[test]
fn bad_units_point_at_the_value() {
    let machine = "[units]\nmotor_per_rev = 0\n";
    let d = common::load_error(
        "bad-units",
        &[("program0.pt", "End\n"), ("machine.toml", machine)],
    );
    let p = &d.items[0].problem;
    assert_eq!(p.code, "pacer::machine::units");
    assert_eq!(&machine[p.span.start..p.span.end], "0");
}

/// SM-EZMotion User Guide, p. 28: ProfileLimited "will remain active until cleared by the
/// Index.ResetProfileLimited destination" — a later index that meets its time leaves it on.
#[test]
fn profile_limited_stays_on_until_reset_profile_limited() {
    let machine = "[variables.A]\n[variables.B]\n[variables.C]\n[index.0]\ndistance = 10.0\n\
                   velocity = 5.0\nacceleration = 10.0\ndeceleration = 10.0\ntime = 0.5\n";
    let program = "Index.0.Initiate\nWait For Index.0.CommandComplete\n\
                   If Index.0.ProfileLimited Then\nVar.A = 1\nEndif\n\
                   Index.0.Velocity = 100\nIndex.0.Time = 4.0\nIndex.0.Initiate\n\
                   Wait For Index.0.CommandComplete\n\
                   If Index.0.ProfileLimited Then\nVar.B = 1\nEndif\n\
                   Index.0.ResetProfileLimited\n\
                   If Index.0.ProfileLimited Then\nVar.C = 1\nElse\nVar.C = 2\nEndif\nEnd\n";
    let r = run(
        "reset-limited",
        program,
        machine,
        "[run]\nduration = 20.0\n",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    assert_eq!(r.machine.value_of("Var.A"), Some(1.0));
    // The second index meets its 4 s: the flag stays on all the same.
    assert_eq!(r.machine.value_of("Var.B"), Some(1.0));
    assert_eq!(r.machine.value_of("Var.C"), Some(2.0));
    let cleared = r
        .events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == "Index.0.ProfileLimited")
        .map(|e| e["value"].clone())
        .collect::<Vec<_>>();
    assert_eq!(cleared, [Value::Bool(true), Value::Bool(false)]);
}

/// The one chaining rule (docs/powertools.md, "Chaining"): a motion starts at the update it is
/// started in — after a blocked initiate or dwell, the update the profile became free — unless
/// it says `Using Last`, which starts it exactly where the previous motion on its profile ended,
/// whatever it waited for. An update of 0.7 ms: Index 0 ends at 3 s, inside the update at
/// 3.0002 s (update 4286).
fn chained_ends(program: &str) -> (Vec<(String, f64)>, Run) {
    let machine = format!("[machine]\nupdate = \"700us\"\n{TWO_INDEXES}");
    let r = run("chain", program, &machine, "");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let ends = r
        .events
        .iter()
        .filter(|e| e["kind"] == "motion" && e["event"] == "done")
        .map(|e| {
            (
                e["object"].as_str().unwrap_or("").to_string(),
                e["end"].as_f64().expect("end"),
            )
        })
        .collect();
    (ends, r)
}

fn assert_ends(ends: &[(String, f64)], expected: &[(&str, f64)]) {
    assert_eq!(ends.len(), expected.len(), "{ends:?}");
    for ((object, end), (want_object, want_end)) in ends.iter().zip(expected) {
        assert_eq!(object, want_object, "{ends:?}");
        assert!(
            (end - want_end).abs() < 1e-9,
            "{object} ends at {end}, not {want_end}"
        );
    }
}

#[test]
fn chaining_a_plain_initiate_after_a_busy_profile_starts_at_the_update_it_became_free() {
    let (ends, _) = chained_ends("Index.0.Initiate\nIndex.1.Initiate\n");
    assert_ends(&ends, &[("Index.0", 3.0), ("Index.1", 3.0002 + 5.0)]);
}

#[test]
fn chaining_using_last_after_a_busy_profile_starts_where_the_last_motion_ended() {
    let (ends, _) = chained_ends("Index.0.Initiate\nIndex.1.Initiate Using Last\n");
    assert_ends(&ends, &[("Index.0", 3.0), ("Index.1", 8.0)]);
}

#[test]
fn chaining_a_dwell_after_a_busy_profile_follows_the_same_rule() {
    let (ends, _) = chained_ends("Index.0.Initiate\nDwell For Time 1\n");
    assert_ends(&ends, &[("Index.0", 3.0), ("Dwell", 3.0002 + 1.0)]);
    let (ends, _) = chained_ends("Index.0.Initiate\nDwell For Time 1 Using Last\n");
    assert_ends(&ends, &[("Index.0", 3.0), ("Dwell", 4.0)]);
}

#[test]
fn chaining_using_last_after_a_wait_for_is_exact_and_caught_up_at_once() {
    let (ends, _) = chained_ends(
        "Index.0.Initiate\nWait For Index.0.CommandComplete\nIndex.1.Initiate Using Last\n",
    );
    assert_ends(&ends, &[("Index.0", 3.0), ("Index.1", 8.0)]);
    // Half a second later still starts at 3 s: the position owed is there at the next update.
    let machine = format!("[machine]\nupdate = \"700us\"\n{TWO_INDEXES}");
    let program = "Index.0.Initiate\nWait For Index.0.CommandComplete\nWait For Time 0.5\n\
                   Index.1.Initiate Using Last\n";
    let r = run("chain-late", program, &machine, "[run]\nduration = 3.6\n");
    let t = r.summary.seconds;
    assert!(t > 3.59 && t <= 3.6, "{t}");
    let expected = 2.0 + 0.5 * (t - 3.0) * (t - 3.0);
    let position = r.machine.value_of("PosnCommand").expect("PosnCommand");
    assert!(
        (position - expected).abs() < 1e-9,
        "{position} at {t} s, not {expected}"
    );
}

/// SM-EZMotion User Guide p. 106: with FeedRate Deactivate on, index motion runs at its
/// programmed velocity whatever FeedRate Override says; off again, the override scales it.
#[test]
fn feed_rate_deactivate_runs_motion_at_its_programmed_velocity() {
    let program = "FeedRateOverride = 50\nFeedRateDeactivate = ON\nIndex.0.Initiate\n\
                   Wait For Index.0.CommandComplete\nFeedRateDeactivate = OFF\nIndex.0.Initiate\n";
    let (ends, _) = {
        let r = run("feed-off", program, TWO_INDEXES, "");
        assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
        let ends: Vec<f64> = r
            .events
            .iter()
            .filter(|e| e["kind"] == "motion" && e["event"] == "done")
            .map(|e| e["end"].as_f64().unwrap_or(f64::NAN))
            .collect();
        (ends, r)
    };
    // 3 s at full speed; then 3 more motion seconds at half speed (6 real seconds), on the
    // motion clock that ran at 1 real second per second until then.
    assert_eq!(ends.len(), 2, "{ends:?}");
    assert!((ends[0] - 3.0).abs() < 1e-9, "{ends:?}");
    assert!((ends[1] - 6.0).abs() < 1e-9, "{ends:?}");
}

#[test]
fn a_stop_takes_on_profile_as_the_fm_manuals_write_it() {
    // FM-3/FM-4 Programming Module Reference Manual p. 109: `On Profile.1` after `Gear.Stop`.
    let program = "Index.0.Initiate On Profile.1\nWait For Time 1\nIndex.0.Stop On Profile.1\n\
                   Gear.Stop On Profile.1\n";
    let r = run("stop-on-profile", program, TWO_INDEXES, "");
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    let done = r
        .events
        .iter()
        .find(|e| e["kind"] == "motion" && e["object"] == "Index.0" && e["event"] == "done")
        .expect("the index ends");
    // Stopped at 1 s, at 1 u/s from 0.5 u: 1 s of deceleration at 1 u/s², 0.5 u more.
    assert!(
        (done["end"].as_f64().unwrap_or(0.0) - 2.0).abs() < 1e-9,
        "{done}"
    );
    assert!(
        (done["position"].as_f64().unwrap_or(0.0) - 1.0).abs() < 1e-9,
        "{done}"
    );
}

#[test]
fn a_jog_is_set_up_in_the_machine_file() {
    let machine = "[jog.0]\nvelocity = 2.0\nacceleration = 10.0\ndeceleration = 10.0\n";
    let r = run(
        "jog-setup",
        "Jog.0.PlusInitiate\nWait For Time 1\nJog.0.Stop\n",
        machine,
        "",
    );
    assert!(r.summary.error.is_none(), "{:?}", r.summary.error);
    // 0.2 s to 2 u/s (0.2 u), 0.8 s at 2 u/s (1.6 u), then 0.2 s down (0.2 u).
    let p = r.machine.value_of("PosnCommand").unwrap_or(f64::NAN);
    assert!((p - 2.0).abs() < 1e-9, "{p}");
    let bad = common::load_error(
        "jog-bad",
        &[
            ("program0.pt", "Jog.0.PlusInitiate\n"),
            ("machine.toml", "[jog.0]\nvelocity = -1.0\n"),
        ],
    );
    assert!(bad
        .render_plain()
        .contains("[jog.0] velocity: -1 is out of range"));
}
