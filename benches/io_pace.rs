//! The real-time runner's pacing (issue 8): a 1 ms update for 60 s (`PACER_PACE_SECONDS`
//! changes it), each update running the labeler's Modbus poll plan — today against the
//! in-memory device, so it measures pacing and the plan's own cost, not the network.
//!
//! `cargo bench --bench io_pace` (or `bash bench/io.sh`). Prints the scheduling obtained,
//! requests per update, the start jitter (p50/p99/max against the absolute deadlines), the
//! worst update time and the overruns.

use pacer::io::map::{IoMap, Point, Table};
use pacer::io::memory::{MemoryDevice, PlanBackend};
use pacer::io::pace::{request_realtime, run_paced};
use std::time::Duration;

fn point(table: Table, address: u16, width: u16, slot: u32) -> Point {
    Point {
        table,
        address,
        width,
        slot,
        member: format!("slot{slot}"),
        scale: 1.0,
        offset: 0.0,
        signed: false,
        safe: 0.0,
        io_point: false,
        ty: if table.is_bit() {
            pacer::registry::ValueType::Bit
        } else {
            pacer::registry::ValueType::Real
        },
    }
}

/// The labeler's map of `tests/io_map.rs`: 10 discrete inputs, 3 coils, an analog input and a
/// 32-bit setpoint.
fn labeler_map() -> IoMap {
    let mut points: Vec<Point> = (0..10)
        .map(|a| point(Table::DiscreteInput, a, 1, u32::from(a)))
        .collect();
    points.extend((0..3).map(|a| point(Table::Coil, a, 1, 10 + u32::from(a))));
    points.push(point(Table::InputRegister, 0, 1, 13));
    points.push(point(Table::HoldingRegister, 10, 2, 14));
    IoMap {
        host: None,
        port: 502,
        unit: 1,
        timeout_ns: 20_000_000,
        max_gap: 0,
        enabled: false,
        overrun_limit: 10,
        period_ns: pacer::io::map::DEFAULT_PERIOD_NS,
        max_age_ns: pacer::io::map::DEFAULT_MAX_AGE_NS,
        points,
    }
}

fn main() {
    let seconds: u64 = std::env::var("PACER_PACE_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    let handle = std::thread::spawn(move || {
        let rt = request_realtime(80);
        for w in &rt.warnings {
            eprintln!("warning: {w}");
        }
        let mut backend = PlanBackend::new(labeler_map(), MemoryDevice::default());
        let per_update = backend.plan.requests_per_update();
        let mut values = vec![0.0; 15];
        let mut faults = 0u64;
        let timing = run_paced(Duration::from_millis(1), seconds * 1000, |n| {
            backend.device.discrete_inputs[(n % 10) as usize] ^= true;
            if backend.read_inputs(&mut values).is_err() {
                faults += 1;
            }
            values[10] = values[0];
            values[14] = n as f64;
            if backend.write_outputs(&values).is_err() {
                faults += 1;
            }
            true
        });
        (rt, per_update, timing, faults, backend.device.requests)
    });
    let Ok((rt, per_update, timing, faults, requests)) = handle.join() else {
        eprintln!("the pacing thread panicked");
        std::process::exit(1);
    };
    let Some(s) = timing.summary() else {
        eprintln!("no updates ran");
        std::process::exit(1);
    };
    println!(
        "scheduling: {} · memory {}",
        if rt.fifo { "SCHED_FIFO 80" } else { "normal" },
        if rt.locked { "locked" } else { "not locked" }
    );
    println!(
        "requests per update (the 4-request map of tests/io_map.rs): {per_update} (served {requests} in {} updates)",
        s.updates
    );
    println!("1 ms update for {seconds} s: {s}; faults {faults}");
}
