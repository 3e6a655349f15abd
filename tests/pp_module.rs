//! The Track Pick & Place module driven directly, one `Module::cycle` per 1 ms update (no VM):
//! override, gripper pulse, xPathStop / xPathHalt / xPathInterrupt / xAbort / xStopALL, errors
//! and warnings, jog, homing and queued profiles, each checked against the manual (§3.7–3.20)
//! and `spec/pick-and-place.md` with measured setpoints.

use pacer::devices::pickplace::io::{BeltParams, Edges, Inputs, Outputs, Params, TmState};
use pacer::devices::pickplace::kinematics::delta3::Delta3;
use pacer::devices::pickplace::law::Stop;
use pacer::devices::pickplace::module::{Event, Module};
use pacer::devices::pickplace::setup::{AxisLimit, BeltSetup, Kinematics, PickPlaceSetup};

/// The update period, s.
const DT: f64 = 0.001;

/// The straight path of most tests: start (0, 0, 0), Intermediate Point 1 (0, 0, 50),
/// Intermediate Point 2 (300, 0, 50), target (300, 0, 0): 400 mm in three rest-to-rest legs.
const TARGET: [f64; 7] = [300.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
const LIFT: f64 = 50.0;
const PATH_LENGTH: f64 = 400.0;

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn xyz(q: &[f64; 13]) -> [f64; 3] {
    [q[0], q[1], q[2]]
}

fn target_xyz(t: [f64; 7]) -> [f64; 3] {
    [t[0], t[1], t[2]]
}

/// The first update (1 = the update of the execute edge) at which the virtual profile time
/// `n · step` reaches `time`, refusing a case too close to a whole number of updates to be
/// decided without the module's own rounding.
fn updates_until(time: f64, step: f64) -> usize {
    let n = time / step;
    let frac = n - n.floor();
    assert!(
        frac > 1e-6 && frac < 1.0 - 1e-6,
        "{time} s is too close to a whole number of {step} s updates for this test"
    );
    n.ceil() as usize
}

fn cartesian_setup() -> PickPlaceSetup {
    PickPlaceSetup {
        kinematics: Kinematics::Cartesian,
        joint_limits: [AxisLimit::default(); 3],
        sw_limits: [None; 13],
        start: [0.0; 3],
        belts: Vec::new(),
        prep_budget: None,
    }
}

fn delta3() -> Delta3 {
    Delta3::new(400.0, 100.0, 250.0, 600.0).expect("a Delta3")
}

fn delta3_setup() -> PickPlaceSetup {
    PickPlaceSetup {
        kinematics: Kinematics::Delta3(delta3()),
        start: [0.0, 0.0, -600.0],
        ..cartesian_setup()
    }
}

/// Realistic path limits, no Cartesian axis limits, mode 0 to the static target via the two
/// intermediate points.
fn params() -> Params {
    let mut p = Params::manual();
    p.lr_path_vel = 500.0;
    p.lr_path_acc = 5000.0;
    p.lr_path_dec = 5000.0;
    p.lr_path_jerk = 1e5;
    p.cartesian_limits = [[0.0; 3]; 7];
    p.lr_z_start_dist = LIFT;
    p.lr_z_target_dist = LIFT;
    p.target = TARGET;
    p.e_tracking_mode = 0;
    p
}

/// The module with its inputs, parameters and everything it reported, update by update.
struct Rig {
    m: Module,
    inputs: Inputs,
    params: Params,
    belt_params: Vec<BeltParams>,
    belts: Vec<(f64, f64)>,
    /// (update index, event).
    events: Vec<(usize, Event)>,
    /// Outputs of every update; index = update index (0 = the first cycle).
    outs: Vec<Outputs>,
}

impl Rig {
    /// Enabled with the axes on, after one update (READY).
    fn new(setup: PickPlaceSetup, params: Params) -> Rig {
        let mut r = Rig::off(setup, params);
        r.inputs.x_enable = true;
        r.inputs.x_regulator_on_all = true;
        let o = r.step();
        assert_eq!(o.e_tm_state, TmState::Ready);
        r
    }

    fn cartesian() -> Rig {
        Rig::new(cartesian_setup(), params())
    }

    /// Not run yet, all inputs FALSE.
    fn off(setup: PickPlaceSetup, params: Params) -> Rig {
        let belt_params = vec![BeltParams::default(); setup.belts.len()];
        let belts = vec![(0.0, 0.0); setup.belts.len()];
        Rig {
            m: Module::new(&setup, DT),
            inputs: Inputs::default(),
            params,
            belt_params,
            belts,
            events: Vec::new(),
            outs: Vec::new(),
        }
    }

    /// Index the next update will have.
    fn k(&self) -> usize {
        self.outs.len()
    }

    fn cycle(&mut self, edges: Edges) -> Outputs {
        let k = self.k();
        let mut ev = Vec::new();
        let o = self.m.cycle(
            k as f64 * DT,
            &self.inputs,
            edges,
            &self.params,
            &self.belt_params,
            &self.belts,
            &mut ev,
        );
        self.events.extend(ev.into_iter().map(|e| (k, e)));
        self.outs.push(o);
        o
    }

    fn step(&mut self) -> Outputs {
        self.cycle(Edges::default())
    }

    /// One update with an xExecutePickAndPlace edge; returns its index.
    fn execute(&mut self) -> usize {
        let k = self.k();
        self.cycle(Edges {
            x_execute_pick_and_place: true,
            ..Edges::default()
        });
        k
    }

    fn abort(&mut self) -> Outputs {
        self.cycle(Edges {
            x_abort: true,
            ..Edges::default()
        })
    }

    fn run(&mut self, n: usize) {
        for _ in 0..n {
            self.step();
        }
    }

    /// Steps until `done` holds for the outputs (at most `max` updates); returns the index of
    /// the update where it first held.
    fn run_until(&mut self, max: usize, done: impl Fn(&Outputs) -> bool) -> usize {
        for _ in 0..max {
            let o = self.step();
            if done(&o) {
                return self.k() - 1;
            }
        }
        panic!(
            "not reached within {max} updates; last outputs {:?}",
            self.out()
        );
    }

    fn out(&self) -> Outputs {
        *self.outs.last().expect("no update yet")
    }

    /// The tool position (X, Y, Z) at update `k`.
    fn p(&self, k: usize) -> [f64; 3] {
        xyz(&self.outs[k].alr_act_pos)
    }

    fn now(&self) -> [f64; 3] {
        self.p(self.k() - 1)
    }

    /// Durations of the `Planned` events from update `from` on.
    fn planned_since(&self, from: usize) -> Vec<f64> {
        self.events
            .iter()
            .filter(|(k, _)| *k >= from)
            .filter_map(|(_, e)| match e {
                Event::Planned { duration, .. } => Some(*duration),
                _ => None,
            })
            .collect()
    }

    /// Updates (from `from` on) whose outputs satisfy `f`.
    fn updates_where(&self, from: usize, f: impl Fn(&Outputs) -> bool) -> Vec<usize> {
        (from..self.k()).filter(|&k| f(&self.outs[k])).collect()
    }

    /// Update indices of the events matching `f`.
    fn events_where(&self, f: impl Fn(&Event) -> bool) -> Vec<usize> {
        self.events
            .iter()
            .filter(|(_, e)| f(e))
            .map(|(k, _)| *k)
            .collect()
    }

    /// The path length travelled over updates `from..=to` along the polyline `poly`: every
    /// setpoint must lie on it (1e-9 mm), and the arc lengths of consecutive setpoints are
    /// summed as |Δs|, so going back along the path counts twice.
    #[track_caller]
    fn travelled(&self, poly: &[[f64; 3]], from: usize, to: usize) -> f64 {
        let s: Vec<f64> = (from..=to).map(|k| arc(poly, self.p(k), k)).collect();
        s.windows(2).map(|w| (w[1] - w[0]).abs()).sum()
    }

    /// Runs until the tool is on the IP1 → IP2 segment at least `x` along X.
    fn run_to_x(&mut self, x: f64) -> usize {
        self.run_until(5000, |o| o.alr_act_pos[0] >= x)
    }
}

/// Arc length of `p` on the polyline `poly`; panics when `p` is not on it (update `k`).
#[track_caller]
fn arc(poly: &[[f64; 3]], p: [f64; 3], k: usize) -> f64 {
    let mut s0 = 0.0;
    let mut best: Option<(f64, f64)> = None;
    for w in poly.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = dist(a, b);
        let u = (0..3).map(|i| (p[i] - a[i]) * (b[i] - a[i])).sum::<f64>() / (len * len);
        let u = u.clamp(0.0, 1.0);
        let foot = [0, 1, 2].map(|i| a[i] + u * (b[i] - a[i]));
        let off = dist(p, foot);
        if best.is_none_or(|(d, _)| off < d) {
            best = Some((off, s0 + u * len));
        }
        s0 += len;
    }
    let (off, s) = best.expect("a polyline");
    assert!(
        off < 1e-9,
        "update {k}: {p:?} is {off} mm off the path {poly:?}"
    );
    s
}

/// The path of most tests.
const PATH: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [0.0, 0.0, LIFT],
    [300.0, 0.0, LIFT],
    [300.0, 0.0, 0.0],
];

/// Steps until the setpoint has not moved for `still` updates; returns the first update of
/// that rest.
fn run_to_rest(r: &mut Rig, still: usize, max: usize) -> usize {
    let mut rest_from = r.k() - 1;
    for _ in 0..max {
        let before = r.now();
        r.step();
        if r.now() != before {
            rest_from = r.k() - 1;
        } else if r.k() - 1 - rest_from >= still {
            return rest_from;
        }
    }
    panic!("the tool did not come to rest within {max} updates");
}

/// Largest |second difference| / dt² of coordinate `i` over updates `from..=to`.
fn peak_acc(r: &Rig, i: usize, from: usize, to: usize) -> f64 {
    (from.max(2)..=to)
        .map(|k| {
            let q = |k: usize| r.outs[k].alr_act_pos[i];
            ((q(k) - 2.0 * q(k - 1) + q(k - 2)) / (DT * DT)).abs()
        })
        .fold(0.0, f64::max)
}

/// Asserts that every setpoint over `from..=to` lies on the IP1 → IP2 line (y = 0, z = 50)
/// strictly between its ends.
#[track_caller]
fn assert_on_segment(r: &Rig, from: usize, to: usize) {
    for k in from..=to {
        let p = r.p(k);
        assert!(
            p[1].abs() < 1e-9 && (p[2] - LIFT).abs() < 1e-9 && p[0] > 0.0 && p[0] < 300.0,
            "update {k}: {p:?} is off the segment (0, 0, 50) → (300, 0, 50)"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 1. Override
// ---------------------------------------------------------------------------------------------

#[test]
fn override_half_takes_exactly_twice_the_time() {
    let run = |ovr: f64| {
        let mut r = Rig::cartesian();
        r.inputs.lr_override = ovr;
        let k0 = r.execute();
        let end = r.run_until(20_000, |o| !o.x_busy);
        r.run(10);
        let d = r.planned_since(k0);
        assert_eq!(d.len(), 1, "one Planned event");
        assert_eq!(
            r.outs[k0].lr_pre_calc_profile_time, d[0],
            "lrPreCalcProfileTime"
        );
        // Update n of the move (n = 1 at the execute edge) is index k0 + n - 1.
        let setpoints: Vec<[f64; 13]> = r.outs[k0 - 1..].iter().map(|o| o.alr_act_pos).collect();
        (d[0], end - k0 + 1, setpoints, r.now())
    };
    let (d1, n1, s1, end1) = run(1.0);
    let (d05, n05, s05, end05) = run(0.5);
    assert_eq!(
        d1, d05,
        "the planned duration does not depend on the override"
    );
    assert_eq!(
        n1,
        updates_until(d1, DT),
        "override 1 ends after ceil(D/dt) updates"
    );
    assert_eq!(
        n05,
        updates_until(2.0 * d1, DT),
        "override 0.5 ends after ceil(2D/dt) updates"
    );
    for end in [end1, end05] {
        assert!(
            dist(end, target_xyz(TARGET)) < 1e-9,
            "ends at the target: {end:?}"
        );
    }
    // s[n] is the setpoint after update n (s[0]: before the move).
    for k in 0..=n1 + 4 {
        for i in 0..13 {
            assert!(
                (s05[2 * k][i] - s1[k][i]).abs() < 1e-9,
                "axis {i}: update {} at override 0.5 is {}, update {k} at override 1 is {}",
                2 * k,
                s05[2 * k][i],
                s1[k][i]
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Gripper pulse
// ---------------------------------------------------------------------------------------------

/// One mode-0 move with a gripper closing time; returns the rig, the execute update and D.
fn gripper_move(closing: f64, ovr: f64) -> (Rig, usize, f64) {
    let mut p = params();
    p.lr_gripper_closing_time = closing;
    let mut r = Rig::new(cartesian_setup(), p);
    r.inputs.lr_override = ovr;
    let k0 = r.execute();
    r.run_until(20_000, |o| !o.x_busy);
    r.run(5);
    let d = r.planned_since(k0)[0];
    (r, k0, d)
}

#[test]
fn gripper_pulse_comes_closing_time_before_the_end_for_one_cycle() {
    let (r, k0, d) = gripper_move(0.1, 1.0);
    // Update n has run the profile for n·dt: the first with D − n·dt ≤ 0.1.
    let n = updates_until(d - 0.1, DT);
    let pulses = r.updates_where(0, |o| o.x_pulse_gripper);
    assert_eq!(
        pulses,
        vec![k0 + n - 1],
        "xPulseGripper for exactly one cycle, D = {d}"
    );
    let grips = r.events_where(|e| matches!(e, Event::Gripper { .. }));
    assert_eq!(grips, vec![k0 + n - 1], "one Gripper event, with the pulse");
    assert!(r
        .events
        .iter()
        .any(|(_, e)| *e == Event::Gripper { close: true }));
    let end = r.updates_where(k0, |o| !o.x_busy)[0];
    for k in k0..=end {
        assert!(
            r.outs[k].x_gripper_ctrl_active,
            "xGripperCtrlActive during the move (update {k})"
        );
    }
}

#[test]
fn gripper_pulse_off_with_override_other_than_one() {
    let (r, k0, _) = gripper_move(0.1, 0.8);
    assert!(r.updates_where(0, |o| o.x_pulse_gripper).is_empty());
    assert!(r
        .events_where(|e| matches!(e, Event::Gripper { .. }))
        .is_empty());
    let end = r.updates_where(k0, |o| !o.x_busy)[0];
    for k in k0..=end {
        assert!(
            !r.outs[k].x_gripper_ctrl_active,
            "xGripperCtrlActive FALSE with override 0.8 (update {k})"
        );
    }
}

#[test]
fn gripper_pulse_off_after_an_override_change_during_travel() {
    let mut p = params();
    p.lr_gripper_closing_time = 0.1;
    let mut r = Rig::new(cartesian_setup(), p);
    let k0 = r.execute();
    r.run(100);
    assert!(r.out().x_gripper_ctrl_active);
    r.inputs.lr_override = 0.9;
    r.run(10);
    r.inputs.lr_override = 1.0;
    let back = r.k();
    r.run_until(20_000, |o| !o.x_busy);
    r.run(5);
    assert!(r.updates_where(k0, |o| o.x_pulse_gripper).is_empty());
    assert!(r
        .events_where(|e| matches!(e, Event::Gripper { .. }))
        .is_empty());
    let end = r.updates_where(back, |o| !o.x_busy)[0];
    for k in back..end {
        assert!(
            !r.outs[k].x_gripper_ctrl_active,
            "gripper control off for the path (update {k})"
        );
    }
}

#[test]
fn gripper_lead_longer_than_the_profile_pulses_at_the_first_update() {
    let (_, _, d) = gripper_move(0.1, 1.0);
    let (r, k0, d2) = gripper_move(d + 0.25, 1.0);
    assert_eq!(d, d2);
    assert_eq!(r.updates_where(0, |o| o.x_pulse_gripper), vec![k0]);
    assert_eq!(
        r.events_where(|e| *e == Event::Gripper { close: true }),
        vec![k0]
    );
}

// ---------------------------------------------------------------------------------------------
// 3. / 4. xPathStop and xPathHalt
// ---------------------------------------------------------------------------------------------

/// Stop and halt tests: a stiffer jerk so the decelerations, not the jerk, set the distances.
fn stop_params() -> Params {
    let mut p = params();
    p.lr_path_jerk = 1e6;
    p.lr_path_stop_dec = 10_000.0;
    p.lr_path_stop_jerk = 1e6;
    p.lr_path_halt_dec = 7000.0;
    p
}

/// What a path-accurate stop did: the update of the command, where the tool came to rest.
struct Braked {
    cmd: usize,
    rest: usize,
}

/// Runs to X = 150 (cruising at 500 mm/s on IP1 → IP2), then holds xPathStop (or xPathHalt)
/// until the tool is at rest.
fn brake_mid_path(r: &mut Rig, halt: bool) -> Braked {
    r.execute();
    r.run_to_x(150.0);
    if halt {
        r.inputs.x_path_halt = true;
    } else {
        r.inputs.x_path_stop = true;
    }
    let cmd = r.k();
    let o = r.step();
    assert_eq!(o.e_tm_state, TmState::Stop, "STOP (7) at once");
    let rest = run_to_rest(r, 20, 2000);
    Braked { cmd, rest }
}

#[test]
fn path_stop_brakes_along_the_path_and_resumes_from_the_break_point() {
    let mut r = Rig::new(cartesian_setup(), stop_params());
    let b = brake_mid_path(&mut r, false);
    let o = r.out();
    assert_eq!(o.e_tm_state, TmState::Stop);
    assert!(o.x_path_hold, "xPathHold at rest");
    assert_eq!(o.lr_set_path_vel_out, 0.0);
    assert_on_segment(&r, b.cmd - 2, r.k() - 1);
    for k in b.cmd..=b.rest {
        assert!(r.p(k)[0] >= r.p(k - 1)[0], "no reversal at update {k}");
    }
    let lim = f64::max(r.params.lr_path_stop_dec, r.params.lr_path_dec) * (1.0 + 1e-6);
    let acc = peak_acc(&r, 0, b.cmd - 2, r.k() - 1);
    assert!(acc <= lim, "path deceleration {acc} > {lim}");
    // From cruise (500 mm/s, a = 0) the stop covers exactly the Stop law's distance.
    let expect = Stop::plan(500.0, 0.0, 10_000.0, 1e6).unwrap().distance();
    let got = r.p(b.rest)[0] - r.p(b.cmd - 1)[0];
    assert!(
        (got - expect).abs() < 1e-6,
        "stopping distance {got}, expected {expect}"
    );
    let hold = r.now();

    // Still STOP while xPathStop is TRUE; READY once it is released.
    r.run(50);
    assert_eq!(r.out().e_tm_state, TmState::Stop);
    r.inputs.x_path_stop = false;
    assert_eq!(r.step().e_tm_state, TmState::Ready);
    r.run(20);
    assert_eq!(r.out().e_tm_state, TmState::Ready);
    assert_eq!(r.now(), hold, "no motion in READY");

    // A new edge resumes from the break point: no new path.
    let k1 = r.execute();
    assert_eq!(r.out().e_tm_state, TmState::MovePp);
    assert!(r.planned_since(k1).is_empty(), "resumed, not planned anew");
    let first = r.p(k1);
    assert!(
        first[0] >= hold[0] && dist(first, hold) < 1e-2,
        "resumes at {hold:?}: {first:?}"
    );
    let end = r.run_until(5000, |o| !o.x_busy);
    r.run(3);
    assert!(
        dist(r.now(), target_xyz(TARGET)) < 1e-9,
        "at the target: {:?}",
        r.now()
    );
    let len = r.travelled(&PATH, 0, end);
    assert!(
        (len - PATH_LENGTH).abs() < 1e-6,
        "travelled {len} mm of a {PATH_LENGTH} mm path"
    );
    assert!(r.out().x_done);
}

#[test]
fn path_halt_brakes_with_halt_dec_and_stops_later_than_path_stop() {
    let mut stop = Rig::new(cartesian_setup(), stop_params());
    let mut halt = Rig::new(cartesian_setup(), stop_params());
    let bs = brake_mid_path(&mut stop, false);
    let bh = brake_mid_path(&mut halt, true);
    assert_eq!(bs.cmd, bh.cmd, "both commands at the same instant");
    assert_eq!(stop.p(bs.cmd - 1), halt.p(bh.cmd - 1));
    let ds = stop.p(bs.rest)[0] - stop.p(bs.cmd - 1)[0];
    let dh = halt.p(bh.rest)[0] - halt.p(bh.cmd - 1)[0];
    let expect_h = Stop::plan(500.0, 0.0, 7000.0, 1e6).unwrap().distance();
    assert!(
        (dh - expect_h).abs() < 1e-6,
        "halt distance {dh}, expected {expect_h}"
    );
    assert!(
        dh > ds + 1.0,
        "halt {dh} mm must be longer than stop {ds} mm"
    );
    assert_on_segment(&halt, bh.cmd - 2, halt.k() - 1);
    assert!(halt.out().x_path_hold);
    assert_eq!(halt.out().e_tm_state, TmState::Stop);
    // lrPathHaltDec (7000, above lrPathDec 5000) is the deceleration used.
    let acc = peak_acc(&halt, 0, bh.cmd - 2, halt.k() - 1);
    assert!(
        acc <= 7000.0 * (1.0 + 1e-6) && acc > 6900.0,
        "halt deceleration {acc}"
    );

    halt.inputs.x_path_halt = false;
    assert_eq!(halt.step().e_tm_state, TmState::Ready);
    halt.execute();
    let end = halt.run_until(5000, |o| !o.x_busy);
    assert!(dist(halt.now(), target_xyz(TARGET)) < 1e-9);
    let len = halt.travelled(&PATH, 0, end);
    assert!((len - PATH_LENGTH).abs() < 1e-6, "travelled {len} mm");
}

// ---------------------------------------------------------------------------------------------
// 5. xPathInterrupt
// ---------------------------------------------------------------------------------------------

#[test]
fn path_interrupt_holds_on_the_path_resumes_on_release_and_pulses_at_arrival() {
    let mut p = stop_params();
    p.lr_gripper_closing_time = 0.1;
    let mut r = Rig::new(cartesian_setup(), p);
    r.execute();
    r.run_to_x(150.0);
    r.inputs.x_path_interrupt = true;
    let cmd = r.k();
    assert_eq!(
        r.step().e_tm_state,
        TmState::PathInterrupt,
        "PATH_INTERRUPT (8)"
    );
    assert!(
        !r.out().x_gripper_ctrl_active,
        "gripper control off once interrupted"
    );
    let rest = run_to_rest(&mut r, 20, 2000);
    let o = r.out();
    assert_eq!(o.e_tm_state, TmState::PathInterrupt);
    assert!(o.x_path_hold, "xPathHold while interrupted");
    assert_on_segment(&r, cmd - 2, r.k() - 1);
    let expect = Stop::plan(500.0, 0.0, 10_000.0, 1e6).unwrap().distance();
    let got = r.p(rest)[0] - r.p(cmd - 1)[0];
    assert!(
        (got - expect).abs() < 1e-6,
        "interrupt distance {got}, expected {expect}"
    );
    let hold = r.now();

    // Released: MOVE_PP at once, from the break point, without an xExecute edge.
    r.inputs.x_path_interrupt = false;
    let k1 = r.k();
    assert_eq!(
        r.step().e_tm_state,
        TmState::MovePp,
        "MOVE_PP (6) on release"
    );
    assert!(r.planned_since(k1).is_empty(), "resumed, not planned anew");
    assert!(dist(r.now(), hold) < 1e-2 && r.now()[0] >= hold[0]);
    let arrival = r.run_until(5000, |o| !o.x_busy);
    r.run(5);
    assert!(
        dist(r.p(arrival), target_xyz(TARGET)) < 1e-9,
        "at the target"
    );
    let len = r.travelled(&PATH, 0, arrival);
    assert!((len - PATH_LENGTH).abs() < 1e-6, "travelled {len} mm");
    // The pulse is given at the end of the profile only (§3.17), once.
    assert_eq!(r.updates_where(0, |o| o.x_pulse_gripper), vec![arrival]);
    assert_eq!(
        r.events_where(|e| *e == Event::Gripper { close: true }),
        vec![arrival]
    );
}

// ---------------------------------------------------------------------------------------------
// 6. xAbort
// ---------------------------------------------------------------------------------------------

#[test]
fn abort_after_a_stop_drops_the_path_and_the_next_edge_plans_anew() {
    let mut r = Rig::new(cartesian_setup(), stop_params());
    let b = brake_mid_path(&mut r, false);
    let hold = r.p(b.rest);
    r.inputs.x_path_stop = false;
    assert_eq!(r.step().e_tm_state, TmState::Ready);
    let o = r.abort();
    assert_eq!(o.e_tm_state, TmState::Ready);
    assert!(!o.x_path_hold, "the path is dropped");
    assert!(!o.x_busy);
    r.run(20);
    assert_eq!(r.now(), hold);

    let k1 = r.execute();
    let plans = r.planned_since(k1);
    assert_eq!(plans.len(), 1, "a new path is planned");
    // The new path starts with the lift above the break point, not along the old segment.
    let first = r.p(k1);
    assert!(
        (first[0] - hold[0]).abs() < 1e-9 && first[1].abs() < 1e-9 && first[2] > hold[2],
        "lifts from {hold:?}: {first:?}"
    );
    let end = r.run_until(5000, |o| !o.x_busy);
    assert!(dist(r.now(), target_xyz(TARGET)) < 1e-9);
    let ip1 = [hold[0], 0.0, hold[2] + LIFT];
    let ip2 = [300.0, 0.0, LIFT];
    let expect = LIFT + dist(ip1, ip2) + LIFT;
    let len = r.travelled(&[hold, ip1, ip2, target_xyz(TARGET)], k1 - 1, end);
    assert!(
        (len - expect).abs() < 1e-6,
        "new path {len} mm, expected {expect}"
    );
}

#[test]
fn abort_while_moving_is_ignored_in_mode_0() {
    let mut r = Rig::new(cartesian_setup(), stop_params());
    let k0 = r.execute();
    r.run_to_x(150.0);
    let o = r.abort();
    assert_eq!(o.e_tm_state, TmState::MovePp);
    assert!(o.x_busy);
    let end = r.run_until(5000, |o| !o.x_busy);
    r.run(2);
    assert!(dist(r.now(), target_xyz(TARGET)) < 1e-9);
    assert_eq!(r.planned_since(k0).len(), 1);
    let len = r.travelled(&PATH, 0, end);
    assert!((len - PATH_LENGTH).abs() < 1e-6, "travelled {len} mm");
    assert!(r.out().x_done);
}

// ---------------------------------------------------------------------------------------------
// 7. xStopALL
// ---------------------------------------------------------------------------------------------

/// A diagonal IP1 → IP2 segment so X and Y both move; each axis its own alrStopDec.
fn stop_all_rig() -> Rig {
    let mut p = stop_params();
    p.target = [300.0, 200.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    p.alr_stop_dec[0] = 4000.0;
    p.alr_stop_dec[1] = 9000.0;
    p.alr_stop_dec[2] = 10_000.0;
    p.alr_stop_jerk = [1e6; 13];
    Rig::new(cartesian_setup(), p)
}

/// Runs to X = 150 on the diagonal segment and sets xStopALL until the tool is at rest;
/// returns the update of the command, the first update of the rest, and the X and Y
/// velocities the axes had.
fn stop_all_mid_path(r: &mut Rig) -> (usize, usize, [f64; 2]) {
    r.execute();
    r.run_to_x(150.0);
    let k = r.k();
    let v = [0, 1].map(|i| (r.outs[k - 1].alr_act_pos[i] - r.outs[k - 2].alr_act_pos[i]) / DT);
    r.inputs.x_stop_all = true;
    assert_eq!(r.step().e_tm_state, TmState::Stop, "STOP (7) at once");
    let rest = run_to_rest(r, 20, 3000);
    (k, rest, v)
}

#[test]
fn stop_all_brakes_each_axis_on_its_own_and_stays_stop_while_set() {
    let mut r = stop_all_rig();
    let (cmd, rest, v) = stop_all_mid_path(&mut r);
    for (i, &vi) in v.iter().enumerate() {
        let dec = r.params.alr_stop_dec[i];
        let expect = Stop::plan(vi, 0.0, dec, 1e6).unwrap().distance();
        let got = r.p(rest)[i] - r.p(cmd - 1)[i];
        assert!(
            (got - expect).abs() < 1e-6,
            "axis {i}: braked over {got}, expected {expect} (alrStopDec {dec})"
        );
    }
    // Y (9000 mm/s²) is still well before X (4000 mm/s²): the axes brake on their own.
    let y_still = (cmd..=rest).find(|&k| r.p(k)[1] == r.p(rest)[1]).unwrap();
    let x_still = (cmd..=rest).find(|&k| r.p(k)[0] == r.p(rest)[0]).unwrap();
    assert!(
        y_still + 20 < x_still,
        "Y still at {y_still}, X at {x_still}"
    );
    assert_eq!(r.p(rest)[2], LIFT, "Z was not moving");
    for _ in 0..200 {
        let o = r.step();
        assert_eq!(o.e_tm_state, TmState::Stop, "STOP while xStopALL is TRUE");
        assert!(!o.x_path_hold, "xStopALL leaves the path: no xPathHold");
    }
    assert_eq!(r.now(), r.p(rest));
}

#[test]

fn stop_all_brakes_every_axis_within_its_stop_dec() {
    let mut r = stop_all_rig();
    let (cmd, rest, _) = stop_all_mid_path(&mut r);
    for i in 0..3 {
        let dec = r.params.alr_stop_dec[i];
        let acc = peak_acc(&r, i, cmd, rest + 2);
        assert!(
            acc <= dec * (1.0 + 1e-6),
            "axis {i}: deceleration {acc} > alrStopDec {dec}"
        );
    }
}

#[test]

fn stop_all_stays_stop_while_set_then_ready_without_moving() {
    let mut r = stop_all_rig();
    stop_all_mid_path(&mut r);
    r.run(200);
    assert_eq!(
        r.out().e_tm_state,
        TmState::Stop,
        "STOP while xStopALL is TRUE"
    );
    let rest = r.now();
    r.inputs.x_stop_all = false;
    let k1 = r.k();
    assert_eq!(
        r.step().e_tm_state,
        TmState::Ready,
        "READY once released and still"
    );
    r.run(100);
    assert_eq!(
        r.out().e_tm_state,
        TmState::Ready,
        "waits for a new command"
    );
    assert_eq!(r.now(), rest, "no motion without a new xExecute edge");
    assert!(
        r.planned_since(k1).is_empty(),
        "no path without a new xExecute edge"
    );
    // A new edge runs the profile again from the start, once.
    let k2 = r.execute();
    assert_eq!(r.planned_since(k2).len(), 1);
    r.run_until(5000, |o| !o.x_busy);
    r.run(50);
    assert!(
        dist(r.now(), [300.0, 200.0, 0.0]) < 1e-9,
        "at the target: {:?}",
        r.now()
    );
    assert_eq!(r.planned_since(k2).len(), 1, "the target is travelled once");
    assert_eq!(r.out().e_tm_state, TmState::Ready);
}

// ---------------------------------------------------------------------------------------------
// 8. Errors and warnings
// ---------------------------------------------------------------------------------------------

/// The (x, y, z) an error message names.
fn point_in(message: &str) -> [f64; 3] {
    let a = message.find('(').expect("a point in the message");
    let b = a + message[a..].find(')').expect("a closing parenthesis");
    let v: Vec<f64> = message[a + 1..b]
        .split(',')
        .map(|s| s.trim().parse().expect("a number"))
        .collect();
    assert_eq!(v.len(), 3, "three coordinates in {message:?}");
    [v[0], v[1], v[2]]
}

#[test]
fn unreachable_delta3_target_is_error_29001_naming_the_point() {
    let mut p = params();
    p.target = [0.0, 0.0, -1000.0, 0.0, 0.0, 0.0, 0.0];
    let mut r = Rig::new(delta3_setup(), p);
    let start = r.now();
    let k0 = r.execute();
    r.run(10);
    let errs: Vec<(i32, String)> = r
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Event::Error { id, message } => Some((*id, message.clone())),
            _ => None,
        })
        .collect();
    assert_eq!(errs.len(), 1, "one error: {errs:?}");
    assert_eq!(errs[0].0, 29001);
    let q = point_in(&errs[0].1);
    // The point is on the planned (vertical) path, just beyond the robot's reach.
    assert!(q[0].abs() < 1e-3 && q[1].abs() < 1e-3 && (-1000.0..=-550.0).contains(&q[2]));
    let d = delta3();
    assert!(
        d.inverse([q[0], q[1], q[2] - 0.01]).is_err(),
        "{q:?} must be out of reach"
    );
    assert!(
        d.inverse([q[0], q[1], q[2] + 1.0]).is_ok(),
        "{q:?} is the first unreachable point"
    );
    let o = r.out();
    assert_eq!(o.e_tm_state, TmState::Error);
    assert!(o.x_error);
    assert_eq!(o.e_error_id, 29001);
    for o in &r.outs[k0..] {
        assert!(o
            .alr_act_pos
            .iter()
            .chain(o.alr_act_vel.iter())
            .all(|x| x.is_finite()));
        assert!(o.lr_set_path_vel_out.is_finite());
    }
    assert!(dist(r.now(), start) < 1e-9, "no motion");
    r.inputs.x_reset_error = true;
    let o = r.step();
    assert_eq!(o.e_tm_state, TmState::Ready);
    assert!(!o.x_error);
    assert_eq!(o.e_error_id, 0);
}

#[test]
fn software_limit_on_the_path_is_error_20306_before_any_motion() {
    let mut setup = cartesian_setup();
    setup.sw_limits[2] = Some((-10.0, 400.0));
    let mut p = params();
    p.lr_z_start_dist = 500.0; // Intermediate Point 1 at Z = 500, above the limit.
    let mut r = Rig::new(setup, p);
    r.inputs.ax_sw_limit_enabled[2] = true;
    let k0 = r.execute();
    r.run(10);
    let ids: Vec<i32> = r
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Event::Error { id, .. } => Some(*id),
            _ => None,
        })
        .collect();
    assert_eq!(ids, vec![20306]);
    assert_eq!(r.out().e_tm_state, TmState::Error);
    assert_eq!(r.out().e_error_id, 20306);
    for k in k0..r.k() {
        assert_eq!(r.p(k), [0.0; 3], "no motion (update {k})");
    }

    // The same path with the limit switched off goes.
    let mut setup = cartesian_setup();
    setup.sw_limits[2] = Some((-10.0, 400.0));
    let mut r = Rig::new(setup, p);
    r.execute();
    r.run_until(10_000, |o| !o.x_busy);
    assert!(dist(r.now(), target_xyz(TARGET)) < 1e-9);
}

/// Mode 0 to a workpiece on belt 1 (along +X from the origin, 100 mm/s), detected at belt
/// X = 150 with the operating range ending at `upper`, and X's software limit at 180 enabled:
/// the errors the module reports.
fn workpiece_beyond_x_limit(upper: f64) -> (Rig, Vec<i32>) {
    let mut setup = cartesian_setup();
    setup.sw_limits[0] = Some((-10.0, 180.0));
    setup.belts = vec![BeltSetup {
        number: 1,
        limit: AxisLimit::default(),
    }];
    let mut r = Rig::new(setup, params());
    r.inputs.ax_sw_limit_enabled[0] = true;
    r.inputs.e_set_target = 1;
    r.belts = vec![(0.0, 100.0)];
    r.belt_params[0].lr_z_dist_belt = LIFT;
    r.belt_params[0].lr_lower_sync_limit = 0.0;
    r.belt_params[0].lr_upper_sync_limit = upper;
    let mut ev = Vec::new();
    r.m.receive(0, 1, 0.0, &mut ev);
    assert!(r.m.validate(0, [150.0, 0.0, 0.0, 0.0, 0.0, 0.0]));
    r.execute();
    r.run(5);
    let ids = r
        .events
        .iter()
        .filter_map(|(_, e)| match e {
            Event::Error { id, .. } => Some(*id),
            _ => None,
        })
        .collect();
    (r, ids)
}

#[test]
fn workpiece_met_only_beyond_the_range_is_missed_even_past_a_software_limit() {
    // The tool can meet the workpiece only past X = 200, the end of the operating range and
    // past the limit: it is missed, and the path it would have needed raises no error.
    let (r, ids) = workpiece_beyond_x_limit(200.0);
    assert_eq!(ids, Vec::<i32>::new());
    let missed = r.events_where(|e| matches!(e, Event::Missed { belt: 1, id: 1, .. }));
    assert_eq!(missed.len(), 1);
    assert_eq!(r.m.belts[0].missed, 1);
    assert!(r.m.belts[0].pieces.is_empty());
    assert!(!r.out().x_error);
    // With the range reaching further the same workpiece can be taken, and the path to it
    // crosses the limit: error 20306 before any motion.
    let (r, ids) = workpiece_beyond_x_limit(400.0);
    assert_eq!(ids, vec![20306]);
    assert_eq!(r.m.belts[0].missed, 0);
    assert_eq!(r.out().e_tm_state, TmState::Error);
}

#[test]
fn hardware_limit_switch_is_error_20500() {
    let mut r = Rig::cartesian();
    r.inputs.x_group_enable_hw_limit = true;
    r.inputs.ax_hw_limit_pos[0] = true;
    let o = r.step();
    assert_eq!(o.e_tm_state, TmState::Error);
    assert!(o.x_error);
    assert_eq!(o.e_error_id, 20500);
    assert!(o.ax_hw_limit_switch_pos[0]);
    assert!(o.x_hw_limit_switch_active);
    assert_eq!(
        r.events_where(|e| matches!(e, Event::Error { id: 20500, .. }))
            .len(),
        1
    );
    // Not resettable while the switch is active.
    r.inputs.x_reset_error = true;
    assert_eq!(r.step().e_tm_state, TmState::Error);
    r.inputs.ax_hw_limit_pos[0] = false;
    let o = r.step();
    assert_eq!(o.e_tm_state, TmState::Ready);
    assert!(!o.ax_hw_limit_switch_pos[0] && !o.x_error);
}

#[test]

fn hardware_limit_while_moving_brakes_every_axis_with_its_stop_dec() {
    let mut r = stop_all_rig();
    r.execute();
    r.run_to_x(150.0);
    r.inputs.x_group_enable_hw_limit = true;
    r.inputs.ax_hw_limit_pos[1] = true;
    let cmd = r.k();
    let o = r.step();
    assert_eq!(o.e_tm_state, TmState::Error);
    assert_eq!(o.e_error_id, 20500);
    assert!(o.ax_hw_limit_switch_pos[1]);
    let rest = run_to_rest(&mut r, 20, 3000);
    for i in 0..3 {
        let dec = r.params.alr_stop_dec[i];
        let acc = peak_acc(&r, i, cmd, rest + 2);
        assert!(
            acc <= dec * (1.0 + 1e-6),
            "axis {i}: deceleration {acc} > alrStopDec {dec}"
        );
    }
}

#[test]
fn thirty_first_workpiece_on_a_belt_warns_17918() {
    let mut setup = cartesian_setup();
    setup.belts = vec![BeltSetup {
        number: 1,
        limit: AxisLimit::default(),
    }];
    let mut r = Rig::new(setup, params());
    let mut ev = Vec::new();
    for id in 1..=30 {
        r.m.receive(0, id, id as f64, &mut ev);
    }
    assert!(ev.is_empty(), "30 workpieces fit: {ev:?}");
    r.m.receive(0, 31, 31.0, &mut ev);
    assert_eq!(ev.len(), 1);
    assert!(
        matches!(ev[0], Event::Warning { id: 17918, .. }),
        "{:?}",
        ev[0]
    );
    let o = r.step();
    assert!(o.x_warning);
    assert!(!o.x_error);
    assert_eq!(o.e_error_id, 17918);
    assert_eq!(o.e_tm_state, TmState::Ready);
    assert_eq!(r.m.belts[0].pieces.len(), 30);
}

// ---------------------------------------------------------------------------------------------
// 9. Jog
// ---------------------------------------------------------------------------------------------

fn jog_params() -> Params {
    let mut p = params();
    // [jerk, vel, acc, dec]
    p.cartesian_jog = [1e5, 100.0, 1000.0, 2000.0];
    p
}

#[test]
fn jog_x_positive_runs_at_jog_speed_and_stops_on_release() {
    let mut r = Rig::new(cartesian_setup(), jog_params());
    r.inputs.e_select_axis = 1;
    r.inputs.x_jog_pos = true;
    let k0 = r.k();
    assert_eq!(r.step().e_tm_state, TmState::JogPos, "JOGPOS (2)");
    r.run(400);
    assert_eq!(r.out().e_tm_state, TmState::JogPos);
    let rel = r.k();
    r.inputs.x_jog_pos = false;
    let rest = run_to_rest(&mut r, 20, 2000);
    assert_eq!(r.out().e_tm_state, TmState::Ready);
    let mut vmax: f64 = 0.0;
    for k in k0..r.k() {
        let v = (r.p(k)[0] - r.p(k - 1)[0]) / DT;
        assert!(v >= 0.0, "X never goes back (update {k})");
        assert!(
            v <= 100.0 * (1.0 + 1e-9),
            "jog speed {v} > 100 at update {k}"
        );
        assert!(r.p(k)[1] == 0.0 && r.p(k)[2] == 0.0, "only X moves");
        vmax = vmax.max(v);
    }
    assert!(vmax > 99.9, "reaches the jog speed: {vmax}");
    assert!(
        r.p(rest)[0] > r.p(rel - 1)[0],
        "decelerates over a distance"
    );
    let dec = peak_acc(&r, 0, rel, rest + 2);
    assert!(
        dec <= 2000.0 * (1.0 + 1e-6),
        "deceleration {dec} > lrCartesianJogDec 2000"
    );
    assert!(dec > 1900.0, "brakes with lrCartesianJogDec: {dec}");
    let acc = peak_acc(&r, 0, k0, rel - 1);
    assert!(
        acc <= 1000.0 * (1.0 + 1e-6) && acc > 990.0,
        "acceleration {acc}"
    );
}

#[test]
fn jog_input_set_before_enable_needs_a_new_edge() {
    let mut r = Rig::off(cartesian_setup(), jog_params());
    r.inputs.x_enable = true;
    r.inputs.e_select_axis = 1;
    r.run(3);
    // Manual §3.2, step 1: xJogPos set TRUE while the axes are inhibited.
    r.inputs.x_jog_pos = true;
    for _ in 0..5 {
        let o = r.step();
        assert_eq!(o.e_tm_state, TmState::Ready);
        assert!(!o.x_axes_enabled);
    }
    r.inputs.x_regulator_on_all = true;
    for _ in 0..100 {
        let o = r.step();
        assert_eq!(
            o.e_tm_state,
            TmState::Ready,
            "a jog set while inhibited does nothing"
        );
        assert!(o.x_axes_enabled);
    }
    assert_eq!(r.now(), [0.0; 3]);
    r.inputs.x_jog_pos = false;
    r.step();
    r.inputs.x_jog_pos = true;
    assert_eq!(r.step().e_tm_state, TmState::JogPos);
    r.run(50);
    assert!(r.now()[0] > 0.0, "X moves after the new edge");
}

#[test]

fn jog_is_possible_after_a_path_stop_before_abort() {
    let mut r = Rig::new(cartesian_setup(), stop_params());
    r.params.cartesian_jog = jog_params().cartesian_jog;
    brake_mid_path(&mut r, false);
    r.inputs.x_path_stop = false;
    assert_eq!(r.step().e_tm_state, TmState::Ready);
    let hold = r.now();
    r.inputs.e_select_axis = 3;
    r.inputs.x_jog_pos = true;
    let o = r.step();
    assert_eq!(
        o.e_tm_state,
        TmState::JogPos,
        "§3.16: the axes can be jogged before abort"
    );
    r.run(100);
    assert!(
        r.now()[2] > hold[2],
        "Z moves up: {:?} from {hold:?}",
        r.now()
    );
}

#[test]

fn jog_returns_to_ready_only_when_both_inputs_are_reset() {
    let mut r = Rig::new(cartesian_setup(), jog_params());
    r.inputs.e_select_axis = 1;
    r.inputs.x_jog_pos = true;
    assert_eq!(r.step().e_tm_state, TmState::JogPos);
    r.run(100);
    // The negative direction does not replace the running jog …
    r.inputs.x_jog_neg = true;
    r.run(50);
    assert_eq!(r.out().e_tm_state, TmState::JogPos);
    r.inputs.x_jog_pos = false;
    run_to_rest(&mut r, 20, 2000);
    // … and READY only comes once both inputs are FALSE.
    assert_ne!(r.out().e_tm_state, TmState::Ready, "xJogNeg is still TRUE");
    r.inputs.x_jog_neg = false;
    r.step();
    assert_eq!(r.out().e_tm_state, TmState::Ready);
}

// ---------------------------------------------------------------------------------------------
// 10. Homing
// ---------------------------------------------------------------------------------------------

#[test]
fn homing_in_order_sets_the_real_axes() {
    let mut p = params();
    p.ae_homing_order = [1, 1, 2, 0, 0, 0, 0];
    p.alr_home_position = [10.0, 10.0, 20.0, 0.0, 0.0, 0.0, 0.0];
    let mut r = Rig::new(delta3_setup(), p);
    assert!(!r.out().x_axes_group_homed);
    let k0 = r.k();
    let o = r.cycle(Edges {
        x_group_home_execute: true,
        ..Edges::default()
    });
    assert_eq!(o.e_tm_state, TmState::Homing, "HOMING (4)");
    r.run(10);
    let seq: Vec<&Event> = r
        .events
        .iter()
        .filter(|(k, _)| *k >= k0)
        .map(|(_, e)| e)
        .filter(|e| matches!(e, Event::Homed { .. } | Event::State(_)))
        .collect();
    assert_eq!(
        seq,
        vec![
            &Event::State(TmState::Homing),
            &Event::Homed { order: 1 },
            &Event::Homed { order: 2 },
            &Event::State(TmState::Ready),
        ]
    );
    let o = r.out();
    assert_eq!(o.e_tm_state, TmState::Ready);
    assert!(o.x_axes_group_homed);
    for (i, want) in [10.0, 10.0, 20.0].into_iter().enumerate() {
        let got = o.alr_act_pos[6 + i];
        assert!(
            (got - want).abs() < 1e-9,
            "A{} = {got}, expected {want}",
            i + 1
        );
    }
    // The tool is where those joint angles put it.
    let p = delta3().forward([10.0, 10.0, 20.0]).unwrap();
    assert!(dist(xyz(&o.alr_act_pos), p) < 1e-9);
}

// ---------------------------------------------------------------------------------------------
// 11. Queued profiles
// ---------------------------------------------------------------------------------------------

const T2: [f64; 7] = [100.0, 150.0, -20.0, 0.0, 0.0, 0.0, 0.0];

#[test]
fn queued_profiles_are_travelled_in_order() {
    let mut r = Rig::cartesian();
    let k0 = r.execute();
    r.run(20);
    r.params.target = T2;
    let k1 = r.execute();
    assert!(r.out().x_busy && !r.out().x_done);
    // The first move ends at the first target, then the second begins.
    let first_end = r.run_until(10_000, |o| {
        dist(xyz(&o.alr_act_pos), target_xyz(TARGET)) < 1e-9
    });
    assert!(dist(r.p(first_end), target_xyz(TARGET)) < 1e-9);
    assert!(!r.out().x_done, "not done with a profile queued");
    let end = r.run_until(10_000, |o| !o.x_busy);
    r.run(3);
    assert!(
        dist(r.now(), target_xyz(T2)) < 1e-9,
        "at the second target: {:?}",
        r.now()
    );
    assert!(r.out().x_done, "xDone at the end");
    assert_eq!(r.out().e_tm_state, TmState::Ready);
    assert!(r.updates_where(k1, |o| o.x_done).iter().all(|&k| k > end));
    let plans = r.planned_since(k0);
    assert_eq!(plans.len(), 2, "two profiles");
    // Second path: lift 50 at the first target, over to 50 above the second, down.
    let second = [
        target_xyz(TARGET),
        [300.0, 0.0, LIFT],
        [100.0, 150.0, 30.0],
        target_xyz(T2),
    ];
    let len = r.travelled(&PATH, 0, first_end) + r.travelled(&second, first_end, end);
    let expect = PATH_LENGTH + LIFT + dist(second[1], second[2]) + LIFT;
    assert!(
        (len - expect).abs() < 1e-6,
        "travelled {len}, expected {expect}"
    );
}

#[test]

fn queued_profile_keeps_the_target_of_its_edge() {
    let mut r = Rig::cartesian();
    r.execute();
    r.run(20);
    r.params.target = T2;
    r.execute();
    r.run(20);
    // The application prepares its next target while the queue is still being travelled.
    r.params.target = [-50.0, -50.0, 10.0, 0.0, 0.0, 0.0, 0.0];
    r.run_until(10_000, |o| !o.x_busy);
    r.run(3);
    assert!(
        dist(r.now(), target_xyz(T2)) < 1e-9,
        "the second profile must end at the target given with its edge {:?}, not at {:?}",
        target_xyz(T2),
        r.now()
    );
}

/// A queued target on a belt the machine does not have (`eSetTarget = 5`, no belts): error
/// 29002 naming it, whether the path is planned in the update or spread over updates.
#[test]
fn a_target_on_a_missing_belt_is_error_29002_in_both_preparations() {
    for prep_budget in [None, Some(250)] {
        let setup = PickPlaceSetup {
            prep_budget,
            ..cartesian_setup()
        };
        let mut r = Rig::new(setup, params());
        r.inputs.e_set_target = 5;
        r.execute();
        r.run(3);
        let errors: Vec<(i32, String)> = r
            .events
            .iter()
            .filter_map(|(_, e)| match e {
                Event::Error { id, message } => Some((*id, message.to_string())),
                _ => None,
            })
            .collect();
        assert_eq!(
            errors,
            vec![(
                29002,
                "eSetTarget = 5: the machine has no belt 5".to_string()
            )],
            "prep_budget {prep_budget:?}"
        );
        assert_eq!(r.out().e_tm_state, TmState::Error);
        assert_eq!(r.out().e_error_id, 29002);
        assert_eq!(r.now(), [0.0; 3], "no motion");
    }
}
