//! Every cycle of the pick & place module with 16 belts × 30 workpieces tracked (Delta3, mode
//! 3, issue 19): each cycle is timed once, as it happens, with the whole module update — the
//! detections it is given and its cycle — inside the timing, in two clocks: wall time, and the
//! thread's own CPU time (`CLOCK_THREAD_CPUTIME_ID`), which a preemption by the OS of this
//! shared machine does not inflate. The run holds thousands of path preparations.
//!
//! `cargo bench --bench pickplace`. Figures per kind of cycle, then all cycles in wall time,
//! and last `all cycles (cpu): mean X µs, p99 Y µs, p99.9 W µs, worst Z µs`.
//! With `PACER_PP_TWINS` set, each update first runs on two copies of the module and the least
//! CPU time of the three counts: a cycle still slow then is the module's own work, not an
//! interrupt or the OS charged to the thread (the rare slow ordinary cycle is the latter).
//! The module spreads each path preparation over updates at 250 work units an update
//! (`[pickplace] prep_budget = true`); `PACER_PP_BUDGET` sets another budget, 0 none (each path
//! planned within the update it is asked for, as with `prep_budget = false`).
//! The manual quotes 200 µs average / 511 µs peak on a 1.6 GHz Atom.
//!
//! Before the two `all cycles` lines, `this machine's floor`: as many cycles of a fixed
//! arithmetic workload, sized to the module's median CPU time and timed once the same way. Its
//! tail is what this machine (interrupts, the hypervisor) adds to any cycle of that length: a
//! p99.9 or worst of the module below the floor's cannot be asked of it here.

use pacer::devices::pickplace::io::{BeltParams, Edges, Inputs, Outputs, Params, TmState};
use pacer::devices::pickplace::kinematics::delta3::Delta3;
use pacer::devices::pickplace::module::{Event, Module, PREP_BUDGET};
use pacer::devices::pickplace::setup::{AxisLimit, BeltSetup, Kinematics, PickPlaceSetup};
use std::hint::black_box;
use std::time::Instant;

const BELTS: usize = 16;
const PER_BELT: usize = 30;
const DT: f64 = 0.001;
const SPEED: f64 = 250.0;
const WARMUP: u64 = 2_000;
/// Cycles timed, unless `PACER_PP_CYCLES` sets another number (fewer, to run the bench under
/// callgrind and compare instruction counts).
const CYCLES: u64 = 1_000_000;

/// Work units of path preparation per update: `PACER_PP_BUDGET`, else [`PREP_BUDGET`]; 0 none.
fn budget() -> Option<u64> {
    let b = std::env::var("PACER_PP_BUDGET")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(PREP_BUDGET);
    (b > 0).then_some(b)
}

fn cycles() -> u64 {
    std::env::var("PACER_PP_CYCLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(CYCLES)
}

/// The thread's CPU time, s.
fn thread_cpu() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec, which lives on this stack frame.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc != 0 {
        panic!("clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    }
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// What a cycle did, for the figures.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// The module prepared (or went on preparing) a path in this cycle.
    Prep,
    /// A path in progress.
    Move,
    /// Synchronous travel, waiting at a park position, looking for a workpiece.
    Other,
}

const KINDS: [(Kind, &str); 3] = [
    (Kind::Move, "a path in progress"),
    (Kind::Other, "synchronous travel, waiting, looking"),
    (Kind::Prep, "preparing a path"),
];

fn setup() -> (PickPlaceSetup, Params, Vec<BeltParams>) {
    let delta = match Delta3::new(400.0, 100.0, 250.0, 600.0) {
        Ok(d) => d,
        Err(e) => panic!("bench robot: {e}"),
    };
    let setup = PickPlaceSetup {
        kinematics: Kinematics::Delta3(delta),
        joint_limits: [AxisLimit {
            max_vel: 600.0,
            max_acc: 12000.0,
            max_jerk: 1.5e6,
        }; 3],
        sw_limits: [None; 13],
        start: [0.0, 0.0, -560.0],
        belts: (1..=BELTS as u32)
            .map(|number| BeltSetup {
                number,
                limit: AxisLimit {
                    max_vel: 400.0,
                    max_acc: 800.0,
                    max_jerk: 8000.0,
                },
            })
            .collect(),
        prep_budget: budget(),
    };
    let mut params = Params::manual();
    params.e_tracking_mode = 3;
    params.lr_path_vel = 3000.0;
    params.lr_path_acc = 40000.0;
    params.lr_path_dec = 40000.0;
    params.lr_path_jerk = 4e6;
    params.cartesian_limits = [
        [3000.0, 50000.0, 6e6],
        [3000.0, 50000.0, 6e6],
        [3000.0, 50000.0, 6e6],
        [0.0; 3],
        [0.0; 3],
        [720.0, 20000.0, 2e6],
        [0.0; 3],
    ];
    params.lr_gripper_closing_time = 0.03;
    params.lr_gripper_open_time = 0.02;
    // Belts 1 and 2 run through the robot's workspace (the mode-3 cell's); the other 14 lie
    // beside it and only track their workpieces.
    let belt_params: Vec<BeltParams> = (0..BELTS)
        .map(|i| {
            let y = match i {
                0 => -150.0,
                1 => 150.0,
                _ => 600.0 + 100.0 * i as f64,
            };
            BeltParams {
                alr_park_pos: [-180.0, y.clamp(-150.0, 150.0), -600.0, 0.0, 0.0, 0.0],
                lr_z_dist_belt: 30.0,
                alr_conveyor_belt_origin: [-500.0, y, -670.0, 0.0, 0.0, 0.0],
                lr_sync_time_on_belt: 0.04,
                lr_lower_sync_limit: 320.0,
                lr_upper_sync_limit: 700.0,
                lr_aux1_target_pos: 0.0,
            }
        })
        .collect();
    (setup, params, belt_params)
}

/// Mean, p50, p99, p99.9 and worst of `v` (sorted here), µs.
fn stats(v: &mut [f64]) -> [f64; 5] {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return [0.0; 5];
    }
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let pct = |p: f64| v[((v.len() as f64 - 1.0) * p).round() as usize];
    [mean, pct(0.5), pct(0.99), pct(0.999), v[v.len() - 1]].map(|x| x * 1e6)
}

/// A fixed workload of `rounds` dependent floating-point steps: the same work every time.
fn fixed_work(rounds: u64) -> f64 {
    let mut x = 1.000_001_f64;
    for _ in 0..black_box(rounds) {
        x = x * 1.000_000_1 + 1e-9;
    }
    black_box(x)
}

/// CPU time of one timed `fixed_work(rounds)`, with the clock reads the module's cycles have.
fn timed_fixed(rounds: u64) -> (f64, f64) {
    let c0 = thread_cpu();
    let w0 = Instant::now();
    fixed_work(rounds);
    let w = w0.elapsed().as_secs_f64();
    (w, thread_cpu() - c0)
}

/// This machine's floor: `cycles` runs of a fixed workload whose median CPU time is `target`
/// (s), each timed once as the module's cycles are. Wall and CPU times (s), and the rounds.
fn floor(cycles: u64, target: f64) -> (Vec<f64>, Vec<f64>, u64) {
    // Size the work: the median of 201 timings, doubling then bisecting on the rounds.
    let median = |rounds: u64| {
        let mut v: Vec<f64> = (0..201).map(|_| timed_fixed(rounds).1).collect();
        v.sort_by(f64::total_cmp);
        v[100]
    };
    let (mut lo, mut hi) = (0u64, 64u64);
    while median(hi) < target && hi < 1 << 30 {
        lo = hi;
        hi *= 2;
    }
    for _ in 0..12 {
        let mid = (lo + hi) / 2;
        if median(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (mut wall, mut cpu) = (
        Vec::with_capacity(cycles as usize),
        Vec::with_capacity(cycles as usize),
    );
    for _ in 0..cycles {
        let (w, c) = timed_fixed(hi);
        wall.push(w);
        cpu.push(c);
    }
    (wall, cpu, hi)
}

/// What stays the same from update to update.
struct Fixed<'a> {
    inputs: &'a Inputs,
    params: &'a Params,
    belt_params: &'a [BeltParams],
}

/// One timed update at `t`: the detections that keep every belt at 30 workpieces, then the
/// module's cycle. Its outputs, wall time and thread CPU time (s).
fn update(
    m: &mut Module,
    ids: &mut [u32; BELTS],
    events: &mut Vec<Event>,
    fixed: &Fixed,
    t: f64,
    edges: Edges,
    belts: &[(f64, f64)],
) -> (Outputs, f64, f64) {
    let travel = SPEED * t;
    events.clear();
    let c0 = thread_cpu();
    let w0 = Instant::now();
    // Keep every belt at 30 workpieces: new ones come in upstream (at the detector, or far
    // upstream on the belts beside the robot, so they stay tracked).
    for (i, id) in ids.iter_mut().enumerate() {
        while m.belts[i].pieces.len() < PER_BELT {
            let n = m.belts[i].pieces.len() as f64;
            // Belts 1 and 2: 150 mm apart from the detector upstream (the mode-3 cell's
            // spacing, 100 a minute at this speed); the others far upstream.
            let x0 = if i < 2 {
                100.0 - 150.0 * n
            } else {
                -6000.0 + 20.0 * n
            };
            m.receive(i, *id, travel, events);
            m.validate(i, [x0, (*id % 7) as f64 * 5.0 - 15.0, 20.0, 0.0, 0.0, 3.0]);
            *id += 1;
        }
    }
    let out = m.cycle(
        t,
        fixed.inputs,
        edges,
        fixed.params,
        fixed.belt_params,
        belts,
        events,
    );
    let w = w0.elapsed().as_secs_f64();
    let c = thread_cpu() - c0;
    (out, w, c)
}

fn main() {
    let cycles = cycles();
    let twins = std::env::var_os("PACER_PP_TWINS").is_some();
    let (setup, params, belt_params) = setup();
    let mut m = Module::new(&setup, DT);
    let mut events: Vec<Event> = Vec::with_capacity(64);
    let inputs = Inputs {
        x_enable: true,
        x_regulator_on_all: true,
        ..Inputs::default()
    };
    let mut ids = [0u32; BELTS];
    let mut kinds: Vec<Kind> = Vec::with_capacity(cycles as usize);
    let mut wall: Vec<f64> = Vec::with_capacity(cycles as usize);
    let mut cpu: Vec<f64> = Vec::with_capacity(cycles as usize);
    let mut tracked_min = usize::MAX;
    let mut planned = 0u64;
    let mut belts = vec![(0.0, SPEED); BELTS];
    let fixed = Fixed {
        inputs: &inputs,
        params: &params,
        belt_params: &belt_params,
    };
    for k in 0..WARMUP + cycles {
        let t = k as f64 * DT;
        let travel = SPEED * t;
        for b in belts.iter_mut() {
            *b = (travel, SPEED);
        }
        let edges = Edges {
            x_execute_pick_and_place: k == 5,
            ..Edges::default()
        };
        // The twins: copies of the module as it is, each given the same update first.
        let mut least = f64::INFINITY;
        for _ in 0..if twins { 2 } else { 0 } {
            let (mut twin, mut twin_ids, mut twin_events) = (m.clone(), ids, events.clone());
            let (_, _, c) = update(
                &mut twin,
                &mut twin_ids,
                &mut twin_events,
                &fixed,
                t,
                edges,
                &belts,
            );
            least = least.min(c);
        }
        let (out, w, c) = update(&mut m, &mut ids, &mut events, &fixed, t, edges, &belts);
        let c = c.min(least);
        black_box(&out);
        if k < WARMUP {
            continue;
        }
        let tracked: usize = m.belts.iter().map(|b| b.pieces.len()).sum();
        tracked_min = tracked_min.min(tracked);
        let plan = events.iter().any(|e| matches!(e, Event::Planned { .. }));
        planned += u64::from(plan);
        kinds.push(if plan || out.e_tm_state == TmState::PreparingPath {
            Kind::Prep
        } else if out.e_tm_state == TmState::MovePp && out.lr_set_path_vel_out > 0.0 {
            Kind::Move
        } else {
            Kind::Other
        });
        wall.push(w);
        cpu.push(c);
    }
    println!(
        "pick & place module, {BELTS} belts x {PER_BELT} workpieces (at least {tracked_min} \
         tracked), {cycles} cycles timed once each, {planned} paths prepared:"
    );
    if twins {
        println!("(PACER_PP_TWINS: each cycle's CPU time is the least of three runs of it)");
    }
    let (spread, late) = m.prep_counts();
    let picked: u64 = m.belts.iter().map(|b| u64::from(b.picked)).sum();
    let missed: u64 = m.belts.iter().map(|b| u64::from(b.missed)).sum();
    match setup.prep_budget {
        Some(b) => println!(
            "preparation spread at {b} units an update: {spread} spread, {late} not done by \
             their start (planned again within one update); {picked} picked, {missed} missed"
        ),
        None => println!("each path planned within one update; {picked} picked, {missed} missed"),
    }
    for (kind, name) in KINDS {
        for (clock, v) in [("wall", &wall), ("cpu", &cpu)] {
            let mut sel: Vec<f64> = v
                .iter()
                .zip(&kinds)
                .filter(|(_, k)| **k == kind)
                .map(|(x, _)| *x)
                .collect();
            let n = sel.len();
            let [mean, p50, p99, p999, worst] = stats(&mut sel);
            println!(
                "{name} ({n}) ({clock}): mean {mean:.2} µs, p50 {p50:.2} µs, p99 {p99:.2} µs, \
                 p99.9 {p999:.2} µs, worst {worst:.2} µs"
            );
        }
    }
    let target = {
        let mut v = cpu.clone();
        stats(&mut v)[1] * 1e-6
    };
    let (mut floor_wall, mut floor_cpu, rounds) = floor(cycles, target);
    for (clock, v) in [("wall", &mut floor_wall), ("cpu", &mut floor_cpu)] {
        let [mean, p50, p99, p999, worst] = stats(v);
        println!(
            "this machine's floor, a fixed workload ({rounds} rounds) timed once as often \
             ({clock}): mean {mean:.2} µs, p50 {p50:.2} µs, p99 {p99:.2} µs, p99.9 {p999:.2} µs, \
             worst {worst:.2} µs"
        );
    }
    for (clock, v) in [("wall", &mut wall), ("cpu", &mut cpu)] {
        let [mean, _, p99, p999, worst] = stats(v);
        println!(
            "all cycles ({clock}): mean {mean:.2} µs, p99 {p99:.2} µs, p99.9 {p999:.2} µs, \
             worst {worst:.2} µs"
        );
    }
}
