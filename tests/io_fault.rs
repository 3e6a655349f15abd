//! The safe state, deterministically: a machine wired to an in-memory Modbus device (through
//! the same supervisor the Modbus TCP client runs under) loses the device in the middle of a
//! move. Motion stops with StopDeceleration, the digital outputs take their safe values in the
//! machine and on the device, the programs are held, the fault is traced with its device and
//! cause; the device's return is traced, gets the safe values before anything else, and
//! releases the programs. Time is the machine's, so every figure is exact.

mod common;

use pacer::io::map::Table;
use pacer::io::memory::{Device, MemoryDevice, PlanBackend};
use pacer::io::supervisor::{Backoff, Supervisor};
use pacer::io::IoFault;
use pacer::load::{load, LoadRequest};
use pacer::trace::Trace;
use pacer::vm::realtime::{run_real_time, RealTimeOptions};
use pacer::vm::Machine;
use serde_json::Value;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

/// A memory device the test keeps a handle on while the machine owns the supervisor; each
/// request takes `delay` of wall time (none by default).
#[derive(Clone, Default)]
struct Shared(Arc<Mutex<MemoryDevice>>, Duration);

impl Shared {
    fn lock(&self) -> MutexGuard<'_, MemoryDevice> {
        std::thread::sleep(self.1);
        self.0.lock().expect("device lock")
    }
}

impl Device for Shared {
    fn device(&self) -> String {
        "memory".into()
    }
    fn connect(&mut self) -> Result<(), IoFault> {
        self.lock().connect()
    }
    fn read_bits(&mut self, table: Table, start: u16, count: u16) -> Result<Vec<bool>, IoFault> {
        self.lock().read_bits(table, start, count)
    }
    fn read_registers(
        &mut self,
        table: Table,
        start: u16,
        count: u16,
    ) -> Result<Vec<u16>, IoFault> {
        self.lock().read_registers(table, start, count)
    }
    fn write_coils(&mut self, start: u16, bits: &[bool]) -> Result<(), IoFault> {
        self.lock().write_coils(start, bits)
    }
    fn write_registers(&mut self, start: u16, words: &[u16]) -> Result<(), IoFault> {
        self.lock().write_registers(start, words)
    }
}

const MACHINE: &str = r#"
[machine]
name = "fault"
update = "1ms"

[[program]]
number = 0
file = "program0.pt"

[io]
DriveInput = 2
DriveIO = 2

[variables.N]

# A long move at 10 u/s, reached in 0.1 s.
[index.0]
distance = 1000.0
velocity = 10.0
acceleration = 100.0
deceleration = 100.0

[modbus]
host = "memory"

[[modbus.map]]
kind = "discrete_input"
address = 0
member = "DriveInput.1"

# DriveIO.1.Out: a valve, closed when safe; DriveIO.2.Out: a brake, applied (ON) when safe.
[[modbus.map]]
kind = "coil"
address = 0
member = "DriveIO.1.Out"

[[modbus.map]]
kind = "coil"
address = 1
member = "DriveIO.2.Out"
safe = 1

[[modbus.map]]
kind = "holding_register"
address = 0
member = "Var.N"
"#;

const PROGRAM: &str = "StopDeceleration = 50
Wait For DriveInput.1=ON
DriveIO.1.Out=ON
Index.0.Initiate
Do While TRUE
Var.N=Var.N + 1
Wait For Time 0.01
Loop
";

struct Outcome {
    events: Vec<Value>,
    /// PosnCommand and VelCommand after every update.
    motion: Vec<(f64, f64)>,
    /// The device's writes from the update it came back.
    writes_on_return: Vec<(Table, u16, Vec<u16>)>,
    /// The device's writes while it was down (there must be none it served).
    served_while_down: usize,
}

/// The machine above on `device`, connected (safe values written), tracing to `sink`.
fn machine_on(device: &Shared, sink: &common::Sink) -> Machine {
    // A folder per call: the tests run in parallel.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = CALLS.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    let dir = common::project(
        &format!("io-fault-{n}"),
        &[("program0.pt", PROGRAM), ("machine.toml", MACHINE)],
    );
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let loaded = loaded.unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let map = loaded.io_map.clone().expect("the [modbus] map");
    let mut supervisor = Supervisor::new(PlanBackend::new(map, device.clone()), Backoff::default());
    supervisor.open().expect("the memory device is there");
    let tick = loaded.image.tick_ns;
    let mut machine = Machine::new(loaded.image, Trace::new(Some(Box::new(sink.clone())), tick));
    assert_eq!(machine.attach_io(Box::new(supervisor)), 0);
    machine
}

/// Run 2.5 s: the input comes on at 0.1 s, the device is lost from 1.1 s to 1.5 s.
fn run() -> Outcome {
    let device = Shared::default();
    let sink = common::Sink::default();
    let mut machine = machine_on(&device, &sink);
    let mut motion = Vec::new();
    let mut writes_on_return = Vec::new();
    let mut served_while_down = 0;
    let lost = IoFault::Disconnected {
        device: "memory".into(),
        cause: "connection reset by peer".into(),
    };
    machine.run_observed(Some(2_500_000_000), &mut |m| {
        motion.push((
            m.value_of("PosnCommand").expect("PosnCommand"),
            m.value_of("VelCommand").expect("VelCommand"),
        ));
        // Set for the next update (this one is done).
        let next = (m.time() * 1000.0).round() as u64 + 1;
        let mut d = device.lock();
        match next {
            100 => d.discrete_inputs[0] = true,
            1100 => {
                d.down = Some(lost.clone());
                d.writes.clear();
            }
            1500 => {
                served_while_down = d.writes.len();
                d.down = None;
                d.writes.clear();
            }
            _ => {}
        }
        if writes_on_return.is_empty() && d.down.is_none() && next > 1500 && !d.writes.is_empty() {
            writes_on_return = d.writes.clone();
        }
    });
    machine.finish().expect("in-memory trace");
    let events = sink
        .text()
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    Outcome {
        events,
        motion,
        writes_on_return,
        served_while_down,
    }
}

fn at(events: &[Value], kind: &str) -> Vec<u64> {
    events
        .iter()
        .filter(|e| e["kind"] == kind)
        .map(|e| e["tick"].as_u64().expect("tick"))
        .collect()
}

fn change_ticks(events: &[Value], name: &str) -> Vec<(u64, Value)> {
    events
        .iter()
        .filter(|e| e["kind"] == "change" && e["name"] == name)
        .map(|e| (e["tick"].as_u64().expect("tick"), e["value"].clone()))
        .collect()
}

#[test]
fn a_lost_device_stops_motion_drives_outputs_safe_and_holds_the_programs() {
    let o = run();
    // The fault: at the first update whose read fails, with the device and the cause.
    let faults: Vec<&Value> = o
        .events
        .iter()
        .filter(|e| e["kind"] == "io_fault")
        .collect();
    assert_eq!(faults.len(), 1);
    assert_eq!(faults[0]["tick"], 1100);
    assert_eq!(faults[0]["device"], "memory");
    assert_eq!(
        faults[0]["cause"],
        "not connected (connection reset by peer)"
    );

    // Motion: cruising at 10 u/s up to the fault's update (1.1 s: 0.5 u of ramp from 0.1 s,
    // then 9 u), from there down at StopDeceleration = 50 u/s²: 10 / 50 = 0.2 s and
    // 10² / (2 × 50) = 1 u.
    let (p_before, v_before) = o.motion[1099];
    assert_eq!(v_before, 10.0);
    assert!((p_before - 9.49).abs() < 1e-9, "{p_before}");
    let stopped_at = (1100..o.motion.len())
        .find(|&i| o.motion[i].1.abs() < 1e-9)
        .expect("the axis stops");
    assert_eq!(stopped_at, 1300, "{:?}", &o.motion[1298..1302]);
    let (p_end, _) = o.motion[o.motion.len() - 1];
    assert!((p_end - 10.5).abs() < 1e-9, "{p_before} → {p_end}");
    // Every update of the ramp decelerates by 50 u/s² × 1 ms at most, and nothing moves after.
    for w in o.motion[1099..=stopped_at].windows(2) {
        let dv = w[0].1 - w[1].1;
        assert!((-1e-9..=0.05 + 1e-9).contains(&dv), "{dv}");
    }
    assert!(o.motion[stopped_at..]
        .iter()
        .all(|&(p, v)| v.abs() < 1e-9 && (p - p_end).abs() < 1e-12));

    // The outputs take their safe values at the fault's update: valve closed, brake on.
    assert_eq!(
        change_ticks(&o.events, "DriveIO.1.Out"),
        vec![(100, true.into()), (1100, false.into())]
    );
    assert_eq!(
        change_ticks(&o.events, "DriveIO.2.Out"),
        vec![(1100, true.into())]
    );

    // The program is held from the fault to the return: Var.N does not count there.
    let reconnect = at(&o.events, "io_reconnect");
    assert_eq!(reconnect.len(), 1);
    let back = reconnect[0];
    // Down at 1.1 s; retries at +100 ms (1.2, down), +200 ms (1.4, down), +400 ms (1.8, up).
    assert_eq!(back, 1800);
    let counts = change_ticks(&o.events, "Var.N");
    assert!(counts.iter().any(|(t, _)| *t < 1100));
    assert!(
        counts.iter().all(|(t, _)| *t < 1100 || *t >= back),
        "{counts:?}"
    );
    assert!(
        counts.iter().any(|(t, _)| *t > back),
        "released after the return"
    );
    let attempts = o
        .events
        .iter()
        .find(|e| e["kind"] == "io_reconnect")
        .map(|e| e["attempts"].clone());
    assert_eq!(attempts, Some(3.into()));

    // Nothing reached the device while it was down; on its return the safe values came first
    // (coils 0, 1 = OFF, ON; register 0 = 0), then the update's own writes.
    assert_eq!(o.served_while_down, 0);
    assert!(o.writes_on_return.len() >= 4, "{:?}", o.writes_on_return);
    assert_eq!(o.writes_on_return[0], (Table::Coil, 0, vec![0, 1]));
    assert_eq!(o.writes_on_return[1], (Table::HoldingRegister, 0, vec![0]));
    assert_eq!(o.writes_on_return[2].0, Table::Coil);
    assert_eq!(o.writes_on_return[3].0, Table::HoldingRegister);
    // The count the program kept (its data) is written again, not the safe 0.
    assert!(o.writes_on_return[3].2[0] > 0, "{:?}", o.writes_on_return);

    // The trace is whole: it ends at 2.5 s.
    assert_eq!(
        o.events.last().map(|e| e["kind"].clone()),
        Some("end".into())
    );
    assert_eq!(
        o.events.last().map(|e| e["tick"].clone()),
        Some(2500.into())
    );
}

#[test]
fn the_same_fault_gives_the_same_trace() {
    let a = run().events;
    let b = run().events;
    assert_eq!(a, b);
}

#[test]
fn late_updates_in_a_row_are_a_real_time_fault_that_ends_the_run_safely() {
    // Every request takes 3 ms: each 1 ms update (3 requests) ends long after the next is due.
    let device = Shared(Arc::default(), Duration::from_millis(3));
    let sink = common::Sink::default();
    let mut machine = machine_on(&device, &sink);
    let interrupt = AtomicBool::new(false);
    let report = run_real_time(
        &mut machine,
        Some(10_000_000_000),
        RealTimeOptions {
            overrun_limit: 5,
            interrupt: &interrupt,
        },
        &mut |_| {},
    );
    let fault = "real-time fault: 5 updates in a row finished after the next one was due (overrun_limit = 5)";
    assert_eq!(report.overrun_fault.as_deref(), Some(fault));
    assert_eq!(report.summary.stop_reason.to_string(), fault);
    assert_eq!(report.summary.ticks, 5);
    let timing = report.timing.expect("timed updates");
    assert_eq!(
        (timing.updates, timing.overruns, timing.longest_streak),
        (5, 5, 5)
    );
    assert!(timing.worst_update_ns >= 9_000_000, "{timing:?}");
    assert_eq!(report.io.per_update, 3);
    assert_eq!(report.io.faults, 0);
    assert!(report.close_error.is_none());
    // The end drove the outputs safe: valve closed, brake on, the count register 0.
    let d = device.0.lock().expect("device lock");
    let last: Vec<_> = d.writes.iter().rev().take(2).rev().cloned().collect();
    assert_eq!(
        last,
        vec![
            (Table::Coil, 0, vec![0, 1]),
            (Table::HoldingRegister, 0, vec![0])
        ]
    );
    drop(d);
    machine.finish().expect("in-memory trace");
    let text = sink.text();
    let end = text.lines().last().expect("an end line");
    assert!(
        end.contains("\"kind\":\"end\"") && end.contains(fault),
        "{end}"
    );
}

#[test]
fn ctrl_c_ends_a_real_time_run_after_the_update_with_the_outputs_safe() {
    let device = Shared::default();
    let sink = common::Sink::default();
    let mut machine = machine_on(&device, &sink);
    let interrupt = AtomicBool::new(false);
    let report = run_real_time(
        &mut machine,
        None,
        RealTimeOptions {
            overrun_limit: 0,
            interrupt: &interrupt,
        },
        &mut |m| {
            if m.time() >= 0.049 {
                interrupt.store(true, std::sync::atomic::Ordering::SeqCst);
            }
        },
    );
    assert_eq!(
        report.summary.stop_reason,
        pacer::vm::StopReason::Interrupted
    );
    assert_eq!(report.summary.ticks, 50);
    assert!(report.overrun_fault.is_none());
    let d = device.0.lock().expect("device lock");
    assert_eq!(d.coils[..2], [false, true]);
}

/// A MotionBASIC machine on the memory device: the web (axis 1) runs at 600 RPM = 6000 units/s,
/// the knife (axis 2) geared 1:4 to it; the device is lost at 1.1 s.
const MB_MACHINE: &str = r#"
[machine]
name = "dsp-fault"
update = "1ms"

[[program]]
number = 0
file = "web.mb"

[axis.1]
units_per_rev = 600
accel = 12000

[axis.2]
units_per_rev = 3600
pacer = 1

[modbus]
host = "memory"

[[modbus.map]]
kind = "discrete_input"
address = 0
member = "DriveInput.1"

[[modbus.map]]
kind = "coil"
address = 0
member = "DriveIO.1.Out"
"#;

const MB_PROGRAM: &str = "w~ = {1} : k~ = {2}
GEAR k~ AT 1 TO 4
MOVE w~ AT 600 IN 200
END
";

#[test]
fn a_lost_device_ramps_the_dsp_axes_to_rest_the_knife_in_step_with_the_web() {
    let device = Shared::default();
    let sink = common::Sink::default();
    let dir = common::project(
        "io-fault-dsp",
        &[("web.mb", MB_PROGRAM), ("machine.toml", MB_MACHINE)],
    );
    let loaded = load(&LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    });
    let _ = std::fs::remove_dir_all(&dir);
    let loaded = loaded.unwrap_or_else(|d| panic!("{}", d.render_plain()));
    assert!(loaded.image.devices.iter().all(|d| d.safe_state()));
    let map = loaded.io_map.clone().expect("the [modbus] map");
    let mut supervisor = Supervisor::new(PlanBackend::new(map, device.clone()), Backoff::default());
    supervisor.open().expect("the memory device is there");
    let tick = loaded.image.tick_ns;
    let mut machine = Machine::new(loaded.image, Trace::new(Some(Box::new(sink.clone())), tick));
    assert_eq!(machine.attach_io(Box::new(supervisor)), 0);
    let lost = IoFault::Disconnected {
        device: "memory".into(),
        cause: "connection reset by peer".into(),
    };
    // (web position, web velocity, knife position) after every update.
    let mut axes = Vec::new();
    machine.run_observed(Some(2_500_000_000), &mut |m| {
        axes.push((
            m.value_of("Axis.1.Position").expect("web"),
            m.value_of("Axis.1.Velocity").expect("web velocity"),
            m.value_of("Axis.2.Position").expect("knife"),
        ));
        let next = (m.time() * 1000.0).round() as u64 + 1;
        let mut d = device.lock();
        match next {
            1100 => d.down = Some(lost.clone()),
            1500 => d.down = None,
            _ => {}
        }
    });
    machine.finish().expect("in-memory trace");
    let faults = sink
        .text()
        .lines()
        .filter(|l| l.contains("\"io_fault\""))
        .count();
    assert_eq!(faults, 1);
    // Cruising at 6000 units/s at the fault's update; from there down at 12,000 units/s²:
    // 0.5 s and 6000² / (2 × 12,000) = 1500 units of web, the knife a quarter of it.
    // (The observer sees update n + 1 at index n.)
    let (w0, v0, k0) = axes[1099];
    assert_eq!(v0, 6000.0);
    assert!(axes[1100].1 < 6000.0);
    let stopped = (1099..axes.len())
        .find(|&i| axes[i].1 == 0.0)
        .expect("the web stops");
    assert_eq!(stopped, 1599);
    let (w1, _, k1) = axes[axes.len() - 1];
    assert!((w1 - w0 - 1500.0).abs() < 1e-6, "{}", w1 - w0);
    assert!((k1 - k0 - 375.0).abs() < 1e-6, "{}", k1 - k0);
    for w in axes[1099..=stopped].windows(2) {
        let dv = w[0].1 - w[1].1;
        assert!((-1e-9..=12.0 + 1e-9).contains(&dv), "{dv}");
    }
    assert!(axes[stopped..]
        .iter()
        .all(|&(w, v, k)| v == 0.0 && w == w1 && k == k1));
}
