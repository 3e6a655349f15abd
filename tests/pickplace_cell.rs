//! The mode-3 Delta3 cell (`programs/pick-and-place/delta-cv1-cv2`) over its whole scenario:
//! more than 1,000 workpieces, a belt speed change mid-pick. Measured at every update:
//! the tool on the workpiece during every synchronous travel, and every axis — Cartesian and
//! Delta3 joint — within its velocity, acceleration and jerk limit.
//!
//! `cargo test --release --test pickplace_cell -- --nocapture` prints the figures.

mod common;

use pacer::devices::pickplace::cell::PickPlaceCell;
use pacer::devices::pickplace::frame::Frame;
use pacer::load::{load, LoadRequest};
use pacer::registry::{Kind, GLOBAL_INSTANCE};
use pacer::trace::Trace;
use pacer::vm::Machine;
use std::path::Path;

/// Limits of the cell's machine.toml: Cartesian X, Y, Z, C (lr?MaxVel/AccDec/Jerk) and the
/// joints A1–A3 ([pickplace.joint.*]).
const CARTESIAN: [[f64; 3]; 3] = [[3000.0, 50000.0, 6e6]; 3];
const C_AXIS: [f64; 3] = [720.0, 20000.0, 2e6];
const JOINT: [f64; 3] = [600.0, 12000.0, 1.5e6];

#[derive(Default)]
struct Watch {
    hist: Vec<[f64; 7]>,
    worst: [[f64; 3]; 7],
    sync_checks: [u64; 2],
    sync_error: f64,
    pick_during_ramp: bool,
    updates: u64,
}

#[test]
fn mode_3_cell_over_a_thousand_workpieces() {
    let folder =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/pick-and-place/delta-cv1-cv2");
    let loaded = load(&LoadRequest {
        paths: vec![folder],
        ..Default::default()
    })
    .unwrap_or_else(|d| panic!("the cell does not load:\n{}", d.render_plain()));
    let tick = loaded.image.tick_ns;
    let dt = tick as f64 / 1e9;
    let mut machine = Machine::new(loaded.image, Trace::new(None, tick));
    let reg = machine.registry().clone();
    let g = |name: &str| {
        reg.slot_of(Kind::PickPlace, GLOBAL_INSTANCE, name)
            .unwrap_or_else(|| panic!("no PickPlace.{name}")) as usize
    };
    let pos: Vec<usize> = [1, 2, 3, 6, 7, 8, 9]
        .iter()
        .map(|k| g(&format!("alrActPos[{k}]")))
        .collect();
    let target_out = g("eSetTargetOut");
    let state = g("eTMState");
    // The machine's own limits must be the ones this test holds the axes to.
    for (k, a) in ["X", "Y", "Z"].iter().enumerate() {
        let v = machine.values();
        assert_eq!(v[g(&format!("lr{a}MaxVel"))], CARTESIAN[k][0]);
        assert_eq!(v[g(&format!("lr{a}MaxAccDec"))], CARTESIAN[k][1]);
        assert_eq!(v[g(&format!("lr{a}MaxJerk"))], CARTESIAN[k][2]);
    }
    let origin = |belt: u32| {
        let v = machine.values();
        let mut o = [0.0; 6];
        for (k, x) in o.iter_mut().enumerate() {
            *x = v[reg
                .slot_of(
                    Kind::Belt,
                    belt - 1,
                    &format!("alrConveyorBeltOrigin[{}]", k + 1),
                )
                .expect("belt origin") as usize];
        }
        Frame::from_pose(o)
    };
    let frames = [origin(1), origin(2)];
    let mut w = Watch::default();
    let summary = machine.run_observed(None, &mut |m: &Machine| {
        let v = m.values();
        let t = m.time();
        let q: [f64; 7] = std::array::from_fn(|k| v[pos[k]]);
        w.updates += 1;
        w.hist.insert(0, q);
        w.hist.truncate(4);
        if w.hist.len() == 4 {
            let h = &w.hist;
            for i in 0..7 {
                let vel = (h[0][i] - h[1][i]) / dt;
                let acc = (h[0][i] - 2.0 * h[1][i] + h[2][i]) / (dt * dt);
                let jerk = (h[0][i] - 3.0 * h[1][i] + 3.0 * h[2][i] - h[3][i]) / (dt * dt * dt);
                let lim = match i {
                    0..=2 => CARTESIAN[i],
                    3 => C_AXIS,
                    _ => JOINT,
                };
                for (k, x) in [vel, acc, jerk].into_iter().enumerate() {
                    w.worst[i][k] = w.worst[i][k].max(x.abs() / lim[k]);
                }
            }
        }
        let cell = m
            .device::<PickPlaceCell>()
            .expect("the cell has a pick & place module");
        if let Some((belt, id)) = cell.module().sync_target() {
            let i = (belt - 1) as usize;
            let feed = cell
                .feeds()
                .iter()
                .find(|f| f.belt == belt && f.id == id)
                .expect("the workpiece came from the scenario");
            let profile = &cell.profiles()[i];
            let travel = profile.position(t) - profile.position(feed.receive);
            let p = feed.position;
            let truth = frames[i].apply([p[0] + travel, p[1], p[2]]);
            for k in 0..3 {
                w.sync_error = w.sync_error.max((q[k] - truth[k]).abs());
            }
            w.sync_checks[i] += 1;
        }
        // A pick (a move to belt 1 or the synchronous travel on it) while belt 1 ramps from
        // 250 to 300 mm/s.
        if (300.0..=300.5).contains(&t) && v[target_out] == 1.0 && v[state] == 6.0 {
            w.pick_during_ramp = true;
        }
    });
    assert!(summary.error.is_none(), "{:?}", summary.error);
    let count = |kind: &str| {
        summary
            .events
            .iter()
            .find(|(k, _)| k == kind)
            .map_or(0, |(_, n)| *n)
    };
    let cell = machine.device::<PickPlaceCell>().expect("module");
    let belt1 = &cell.module().belts[0];
    let received = cell
        .feeds()
        .iter()
        .filter(|f| f.belt == 1 && f.receive <= summary.seconds)
        .count() as u64;
    let picks = count("pick");
    let minutes = summary.seconds / 60.0;
    println!(
        "{received} workpieces detected on CV1 in {:.0} s: {picks} picked ({:.1} per minute), \
         {} missed, {} still on the belt; {} placed",
        summary.seconds,
        picks as f64 / minutes,
        belt1.missed,
        belt1.pieces.len(),
        count("place"),
    );
    println!(
        "synchronous travel checked at {} + {} updates (CV1 + CV2): largest |setpoint - workpiece| = {:.3e} mm",
        w.sync_checks[0], w.sync_checks[1], w.sync_error
    );
    let names = ["X", "Y", "Z", "C", "A1", "A2", "A3"];
    for (i, n) in names.iter().enumerate() {
        println!(
            "{n}: peak velocity {:.1} %, acceleration {:.1} %, jerk {:.1} % of its limit",
            w.worst[i][0] * 100.0,
            w.worst[i][1] * 100.0,
            w.worst[i][2] * 100.0
        );
    }
    assert!(received >= 1000, "only {received} workpieces detected");
    assert_eq!(
        picks,
        u64::from(belt1.picked),
        "every pick took a workpiece off CV1"
    );
    assert_eq!(
        received,
        u64::from(belt1.picked + belt1.missed) + belt1.pieces.len() as u64,
        "every detected workpiece is picked, missed or still tracked"
    );
    assert!(picks >= 1000, "only {picks} picks");
    assert!(w.sync_checks[0] > 1000 && w.sync_checks[1] > 1000);
    assert!(
        w.sync_error <= 1e-6,
        "tool off the workpiece by {} mm during synchronous travel",
        w.sync_error
    );
    for (i, n) in names.iter().enumerate() {
        for (k, what) in ["velocity", "acceleration", "jerk"].iter().enumerate() {
            assert!(
                w.worst[i][k] <= 1.0 + 1e-9,
                "axis {n} exceeded its {what} limit: {:.3} of it",
                w.worst[i][k]
            );
        }
    }
    assert!(
        w.pick_during_ramp,
        "no pick was under way during the belt's speed change"
    );
}
