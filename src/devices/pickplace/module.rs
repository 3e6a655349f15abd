//! The module itself: the state machine of the manual (§3.7), tracking modes 0–4, the profile
//! queue, stop/halt/interrupt/abort, the gripper pulse, jog, homing and limit monitoring. One
//! call of [`Module::cycle`] is one task cycle of the technology module.

use super::io::{errors, BeltParams, Edges, Inputs, Outputs, Params, TmState};
use super::law::{DoubleS, Limits, Stop};
use super::plan::{cost, Goal, PathParams, PlanError, PlanJob, Planned, Planner, Request};
use super::robot::{Pose, Robot, AUX1, AXES, AXIS_NAMES, C};
use super::setup::{AxisLimit, PickPlaceSetup};
use super::track::Belt;
use super::trajectory::{Follow, Leg, Trajectory};
use std::collections::VecDeque;

/// Most profiles the module holds (the one running and those queued behind it).
pub const MAX_PROFILES: usize = 8;

/// Work units ([`cost`]) a path preparation may use in one update when the machine spreads
/// preparation (`[pickplace] prep_budget`) without saying how much: a preparation is then
/// spread over as many updates as it needs at this rate (typically about 35 at 1 ms, most of
/// them during the move before), so no update does much more than this much planning: about
/// 9 µs on the 2-core machine of the benchmark (a whole step of it at most about 17 µs),
/// counted in work, never in time, so the split — and every trace — is the same everywhere.
pub const PREP_BUDGET: u64 = 250;

/// How much more work than expected a spread preparation's start leaves room for.
const PREP_MARGIN: f64 = 1.25;

/// Most updates ahead a move is planned for (about ten minutes at 1 ms).
const MAX_AHEAD: u64 = 600_000;

/// The longest a spread preparation may keep the tool waiting for its path, s: a preparation
/// expected to take longer (a move slowed far by its axes' limits, whose check covers thousands
/// of updates) is planned within the update instead, as with `prep_budget = false` — waiting for it
/// would let the workpiece leave the operating range. The manual speaks of up to 25 cycles;
/// 0.1 s leaves room for a Delta3's preparation at 1 ms (about 50 updates expected at 250
/// units).
const MAX_SPREAD_SECONDS: f64 = 0.1;

/// A workpiece on a belt as a candidate for the next move, before any planning.
enum Screen {
    /// Out of range by the time any move could meet it: dropped without planning.
    Gone,
    /// Too far upstream to plan for yet: its belt position (mm).
    Upstream(f64),
    /// Worth planning a move to.
    Plan,
}

/// The workpieces on `belt` whose position is known, in the order they came in.
fn candidates(belt: &Belt) -> Vec<u32> {
    belt.pieces
        .iter()
        .filter(|w| w.pos0.is_some())
        .map(|w| w.id)
        .collect()
}

/// Screen workpiece `id` of `belt`, which has travelled `travel`, for a move from `start`
/// expected to take about `t_est` seconds (the spread and the in-update planning alike).
fn screen(
    belt: &Belt,
    id: u32,
    travel: f64,
    start: &Pose,
    pp: &PathParams,
    bp: &BeltParams,
    t_est: f64,
) -> Screen {
    let sync = bp.lr_sync_time_on_belt.max(0.0);
    let v = belt.velocity;
    let w = belt.pieces.iter().find(|w| w.id == id);
    let x = w.and_then(|w| w.belt_x(travel)).unwrap_or(0.0);
    // No move is quicker than the straight line at full path speed with the belt bringing the
    // workpiece toward the tool: a workpiece that would be out of range even then is dropped.
    let t_min = w
        .and_then(|w| belt.position_of(w, travel))
        .map_or(0.0, |p| {
            let d = ((p[0] - start.p[0]).powi(2)
                + (p[1] - start.p[1]).powi(2)
                + (p[2] - start.p[2]).powi(2))
            .sqrt();
            d / (pp.law.vel + v.abs())
        });
    if x + v * (t_min + sync) > bp.lr_upper_sync_limit {
        Screen::Gone
    } else if x + v * t_est < bp.lr_lower_sync_limit {
        Screen::Upstream(x)
    } else {
        Screen::Plan
    }
}

/// What to do with a prepared move at the update it was planned for.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Then {
    /// Begin it (a static target, a mode-0 target).
    Begin { purpose: Purpose, target_out: i32 },
    /// Begin it unless the workpiece is out of the operating range then.
    Workpiece {
        i: usize,
        id: u32,
        purpose: Purpose,
        target_out: i32,
    },
    /// Go to belt `i`'s parking position.
    Park(usize),
}

/// Where the tool will be when a move being prepared starts, and what it will hold: as it is
/// now, or as the move in progress will leave it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Outset {
    /// The belt the tool will ride then, from its anchor pose.
    follow: Option<(Follow, Pose)>,
    /// The pose then, when it rides no belt.
    pose: Pose,
    /// Whether it will hold a workpiece.
    holding: bool,
    /// Updates from now to the start.
    n: u64,
}

/// A path preparation spread over updates (eTMState PREPARING_PATH): the job, the belts as
/// they are predicted for the update the move will start in, and that update.
#[derive(Debug, Clone)]
struct Prep {
    job: PlanJob,
    pp: PathParams,
    belts: Vec<Belt>,
    /// Time of the update the move starts in.
    start_t: f64,
    /// Time of the request.
    since: f64,
    then: Then,
    /// The mode-0 profile the move is for (it becomes the current one when the move begins).
    profile: Option<Profile>,
    /// The tool stands at the start and the goal is static: the move does not depend on when
    /// it begins, and begins as soon as it is prepared.
    timeless: bool,
    /// The prepared move, once the job is done, kept until `start_t`.
    result: Option<Planned>,
}

/// What the module reports to the trace.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// eTMState changed.
    State(TmState),
    /// A path was prepared.
    Planned {
        /// eSetTargetOut of the path.
        target: i32,
        /// Its duration, s.
        duration: f64,
        /// The time scale the axis limits imposed (1: none).
        scale: f64,
    },
    /// A workpiece was taken (after the synchronous travel on a belt, or at a static position).
    Pick {
        /// Belt number, or None for the static position.
        belt: Option<u32>,
        /// Workpiece id on the belt.
        id: Option<u32>,
        /// Tool position, mm.
        position: [f64; 3],
    },
    /// A workpiece was put down.
    Place {
        /// Belt number, or None for the static position.
        belt: Option<u32>,
        /// Place position id on the belt.
        id: Option<u32>,
        /// Tool position, mm.
        position: [f64; 3],
    },
    /// A mode-0 target was reached (after the synchronous travel, on a belt).
    Reached {
        /// eSetTargetOut: 0 static, n belt n.
        target: i32,
        /// Workpiece id, on a belt.
        id: Option<u32>,
        /// Tool position, mm.
        position: [f64; 3],
    },
    /// A workpiece left the operating range before it could be taken.
    Missed {
        /// Belt number.
        belt: u32,
        /// Workpiece id.
        id: u32,
        /// Its X on the belt, mm.
        x: f64,
    },
    /// xPulseGripper: `close` for a pick profile, open for a place profile.
    Gripper {
        /// True: closing (pick), false: opening (place).
        close: bool,
    },
    /// An error (state ERROR).
    Error {
        /// eErrorID.
        id: i32,
        /// What happened.
        message: String,
    },
    /// A warning (xWarning).
    Warning {
        /// eErrorID.
        id: i32,
        /// What happened.
        message: String,
    },
    /// A homing group finished.
    Homed {
        /// The aeHomingOrder value of the group.
        order: i32,
    },
}

/// A mode-0 profile: eSetTarget and the static target (lrX…TargetPos … lrAux1TargetPos).
type Profile = (i32, [f64; 7]);

/// Which side of a tracking mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Static,
    Belt(usize),
}

/// What a move is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Purpose {
    Pick,
    Place,
    /// To a belt's parking position, to wait there.
    Park(usize),
    /// A mode-0 target.
    Target,
}

/// A path-accurate braking in progress.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Braking {
    s0: f64,
    tau0: f64,
    law: Stop,
    interrupt: bool,
}

#[derive(Debug, Clone, PartialEq)]
struct Active {
    traj: Trajectory,
    tau: f64,
    purpose: Purpose,
    target_out: i32,
    wp: Option<(usize, u32)>,
    lead: f64,
    pulsed: bool,
    gripper_ok: bool,
    interrupted: bool,
    braking: Option<Braking>,
    /// Stopped on the path, waiting for a resume.
    held: bool,
    /// The move after this one has been looked for (prepared during this one if it could be).
    ahead: bool,
    /// What the source belt has added so far, and its travel at the last update.
    src_off: [f64; 3],
    src_travel: f64,
}

// One phase lives in the module at a time and changes a few times a second: its size costs
// nothing worth an allocation.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
enum Phase {
    Idle,
    Move(Box<Active>),
    /// Synchronous travel on a belt after arriving.
    Dwell {
        until: f64,
        purpose: Purpose,
        wp: Option<(usize, u32)>,
        target_out: i32,
    },
    /// Every axis braking on its own (xStopALL, a limit switch).
    AxisStop {
        t0: f64,
        from: [f64; 5],
        dir: [f64; 5],
        laws: Box<[Stop; 5]>,
    },
    Jog {
        axis: usize,
        dir: f64,
        t0: f64,
        origin: f64,
        law: DoubleS,
        stop: Option<(Stop, f64, f64)>,
    },
    Homing {
        next: i32,
    },
}

/// The technology module.
#[derive(Debug, Clone)]
pub struct Module {
    planner: Planner,
    joint_limits: [AxisLimit; 3],
    sw_machine: [Option<(f64, f64)>; AXES],
    /// The belts, in machine order.
    pub belts: Vec<Belt>,
    state: TmState,
    phase: Phase,
    /// The setpoint.
    pose: Pose,
    /// The belt the tool moves with when not on a path: (belt, anchor pose at zero offset).
    follow: Option<(Follow, Pose)>,
    holding: bool,
    looping: bool,
    finish_then_stop: bool,
    /// Mode-0 profiles: eSetTarget and the static target as they were at their edge (an
    /// accepted profile does not change, manual §3.15).
    queue: VecDeque<Profile>,
    /// A path given up by xStopALL or a jog: the next xExecute edge runs it again from the
    /// start (mode 0: this profile).
    restart: Option<(Purpose, Option<Profile>)>,
    /// The static target of the profile running (mode 0).
    current_target: Profile,
    error: Option<(i32, String)>,
    warning: Option<i32>,
    homed: bool,
    at_park: Option<usize>,
    /// Earliest time to look again for a workpiece while waiting at a park position.
    wait_until: f64,
    hist: [[f64; AXES]; 2],
    jog_armed: (bool, bool),
    last_enabled: bool,
    done: bool,
    pulse: bool,
    last_profile_time: f64,
    last_override: f64,
    dt: f64,
    t: f64,
    /// Each belt's travel this cycle (kept to spare an allocation per cycle).
    travel_buf: Vec<f64>,
    /// The path preparation in progress.
    prep: Option<Box<Prep>>,
    /// Work units of the preparation budget left in this update.
    budget_left: u64,
    /// Work units a path preparation may use per update (`[pickplace] prep_budget`); `None`:
    /// a path is planned within the update it is asked for.
    spread: Option<u64>,
    /// Limit checks the last prepared move took (a spread preparation's start is chosen for
    /// as many).
    last_iterations: u32,
    /// Spread preparations begun, and those not done by their start (planned again from the
    /// actual state within one update).
    prep_counts: (u64, u64),
    /// How long the last preparation took, s (lrPathPreparationTime).
    last_prep_time: f64,
}

/// The five Cartesian coordinates a stop brakes one by one: X, Y, Z, C, Aux1.
const STOP_AXES: [usize; 5] = [0, 1, 2, C, AUX1];

impl Module {
    /// The module of a machine with update period `dt` seconds.
    pub fn new(setup: &PickPlaceSetup, dt: f64) -> Module {
        let robot = Robot {
            kinematics: setup.kinematics.clone(),
            limits: [AxisLimit::default(); AXES],
        };
        let belts = setup.belts.iter().map(|b| Belt::new(b.number)).collect();
        let pose = Pose {
            p: setup.start,
            ..Pose::default()
        };
        let mut m = Module {
            planner: Planner {
                robot,
                sw: [None; AXES],
                dt,
                belt_limits: setup.belts.iter().map(|b| b.limit).collect(),
            },
            joint_limits: setup.joint_limits,
            sw_machine: setup.sw_limits,
            belts,
            state: TmState::Disabled,
            phase: Phase::Idle,
            pose,
            follow: None,
            holding: false,
            looping: false,
            finish_then_stop: false,
            queue: VecDeque::new(),
            restart: None,
            current_target: (0, [0.0; 7]),
            error: None,
            warning: None,
            homed: false,
            at_park: None,
            wait_until: 0.0,
            hist: [[0.0; AXES]; 2],
            jog_armed: (false, false),
            last_enabled: false,
            done: false,
            pulse: false,
            last_profile_time: 0.0,
            last_override: 1.0,
            dt,
            t: 0.0,
            travel_buf: Vec::new(),
            prep: None,
            budget_left: 0,
            spread: setup.prep_budget.filter(|&b| b > 0),
            last_iterations: 2,
            prep_counts: (0, 0),
            last_prep_time: 0.0,
        };
        if let Ok(q) = m.planner.robot.axes(&m.pose) {
            m.hist = [q, q];
        }
        m
    }

    /// The setpoint now.
    pub fn pose(&self) -> Pose {
        self.pose
    }

    /// The workpiece the tool travels synchronously with now (after arriving on it): belt
    /// number and workpiece id.
    pub fn sync_target(&self) -> Option<(u32, u32)> {
        match &self.phase {
            Phase::Dwell {
                wp: Some((i, id)), ..
            } => self.belts.get(*i).map(|b| (b.number, *id)),
            _ => None,
        }
    }

    /// The state now.
    pub fn state(&self) -> TmState {
        self.state
    }

    /// Index of belt `number` in the module's list.
    pub fn belt_index(&self, number: u32) -> Option<usize> {
        self.belts.iter().position(|b| b.number == number)
    }

    /// A receive edge on belt `index` when the belt had travelled `travel`.
    pub fn receive(&mut self, index: usize, id: u32, travel: f64, events: &mut Vec<Event>) {
        let Some(b) = self.belts.get_mut(index) else {
            return;
        };
        if !b.receive(id, travel) {
            let number = b.number;
            self.warning = Some(errors::BELT_LIST_FULL);
            events.push(Event::Warning {
                id: errors::BELT_LIST_FULL,
                message: format!(
                    "belt {number} already tracks {} workpieces: workpiece {id} is not tracked",
                    super::track::MAX_WORKPIECES
                ),
            });
        }
    }

    /// A valid-position edge on belt `index`: the oldest workpiece without a position gets it.
    pub fn validate(&mut self, index: usize, pos: [f64; 6]) -> bool {
        self.belts.get_mut(index).is_some_and(|b| b.validate(pos))
    }

    fn set_state(&mut self, s: TmState, events: &mut Vec<Event>) {
        if s != self.state {
            self.state = s;
            events.push(Event::State(s));
        }
    }

    fn fail(&mut self, id: i32, message: String, events: &mut Vec<Event>) {
        self.error = Some((id, message.clone()));
        self.prep = None;
        events.push(Event::Error { id, message });
        self.looping = false;
        self.queue.clear();
        self.set_state(TmState::Error, events);
    }

    fn plan_error(&mut self, e: PlanError, events: &mut Vec<Event>) {
        let id = match &e {
            PlanError::NoSolution(_) => errors::NO_SOLUTION,
            PlanError::SwLimit { upper: true, .. } => errors::SW_LIMIT_POS,
            PlanError::SwLimit { upper: false, .. } => errors::SW_LIMIT_NEG,
            PlanError::Limits { .. } => errors::AXIS_LIMITS,
            PlanError::Param(_) | PlanError::Gone(_) => errors::INVALID_PARAMETER,
        };
        self.fail(id, e.to_string(), events);
    }

    /// Take the parameters that shape planning.
    fn configure(&mut self, params: &Params, inputs: &Inputs, belt_params: &[BeltParams]) {
        let mut limits = [AxisLimit::default(); AXES];
        // Cartesian X, Y, Z, A, B, C from the parameters; Aux1 too; real axes from the machine.
        for (k, i) in [0usize, 1, 2, 3, 4, 5, AUX1].into_iter().enumerate() {
            let l = params.cartesian_limits[k];
            limits[i] = AxisLimit {
                max_vel: l[0],
                max_acc: l[1],
                max_jerk: l[2],
            };
        }
        if matches!(
            self.planner.robot.kinematics,
            super::setup::Kinematics::Delta3(_)
        ) {
            limits[6..9].copy_from_slice(&self.joint_limits);
        }
        self.planner.robot.limits = limits;
        for i in 0..AXES {
            self.planner.sw[i] = if inputs.ax_sw_limit_enabled[i] {
                self.sw_machine[i]
            } else {
                None
            };
        }
        for (b, p) in self.belts.iter_mut().zip(belt_params) {
            if b.origin != p.alr_conveyor_belt_origin {
                b.origin = p.alr_conveyor_belt_origin;
                b.frame = super::frame::Frame::from_pose(b.origin);
            }
        }
    }

    fn path_params(&self, params: &Params) -> Result<PathParams, String> {
        let law = Limits {
            vel: params.lr_path_vel,
            acc: params.lr_path_acc,
            dec: params.lr_path_dec,
            jerk: params.lr_path_jerk,
        };
        for (name, v) in [
            ("lrPathVel", law.vel),
            ("lrPathAcc", law.acc),
            ("lrPathDec", law.dec),
            ("lrPathJerk", law.jerk),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} = {v}: it must be more than 0"));
            }
        }
        for (name, v) in [
            ("lrBlendingRadius", params.lr_blending_radius),
            ("lrZDistElliptical", params.lr_z_dist_elliptical),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("{name} = {v}: it must be 0 or more"));
            }
        }
        if !matches!(params.e_path_mode, 0 | 1) {
            return Err(format!(
                "ePathMode = {}: it must be 0 (linear) or 1 (elliptical)",
                params.e_path_mode
            ));
        }
        if params.e_target_coord_system != 0 {
            return Err(format!(
                "eTargetCoordSystem = {}: pacer supports the machine coordinate system (0) only",
                params.e_target_coord_system
            ));
        }
        Ok(PathParams {
            law,
            radius: params.lr_blending_radius,
            elliptical: params.e_path_mode == 1,
            ellipse_height: params.lr_z_dist_elliptical,
        })
    }

    /// The pose of the tool on the current phase.
    fn current_pose(&self) -> Pose {
        match &self.follow {
            Some((f, anchor)) => {
                let o = f.offset_at(self.belts.get(f.belt).map_or(f.base, |b| b.travel));
                let mut p = *anchor;
                for (x, d) in p.p.iter_mut().zip(o) {
                    *x += d;
                }
                p
            }
            None => self.pose,
        }
    }

    /// One cycle at time `t`. `belts`: each belt's travel and speed now.
    #[allow(clippy::too_many_arguments)]
    pub fn cycle(
        &mut self,
        t: f64,
        inputs: &Inputs,
        edges: Edges,
        params: &Params,
        belt_params: &[BeltParams],
        belts: &[(f64, f64)],
        events: &mut Vec<Event>,
    ) -> Outputs {
        self.t = t;
        self.pulse = false;
        self.budget_left = self.spread.unwrap_or(0);
        self.travel_buf.clear();
        for (b, &(travel, v)) in self.belts.iter_mut().zip(belts) {
            b.travel = travel;
            b.velocity = v;
            self.travel_buf.push(travel);
        }
        self.configure(params, inputs, belt_params);
        let enabled = inputs.x_enable;
        let axes_on = enabled && inputs.x_regulator_on_all;
        if !enabled {
            self.phase = Phase::Idle;
            self.prep = None;
            self.set_state(TmState::Disabled, events);
        } else if self.state == TmState::Disabled {
            self.set_state(TmState::Ready, events);
        }
        // Commands set while the axes were off need a new rising edge once they are on.
        if axes_on && !self.last_enabled {
            self.jog_armed = (!inputs.x_jog_pos, !inputs.x_jog_neg);
        }
        if !inputs.x_jog_pos {
            self.jog_armed.0 = true;
        }
        if !inputs.x_jog_neg {
            self.jog_armed.1 = true;
        }
        self.last_enabled = axes_on;
        let edges = if axes_on { edges } else { Edges::default() };
        if enabled && !axes_on && (!matches!(self.phase, Phase::Idle) || self.prep.is_some()) {
            // The drives are off: nothing moves any more, and nothing is prepared.
            self.phase = Phase::Idle;
            self.prep = None;
            self.follow = None;
            self.looping = false;
            self.queue.clear();
        }

        if enabled {
            self.limits_switches(inputs, params, events);
            if self.state == TmState::Error {
                if inputs.x_reset_error && !self.hw_active(inputs) {
                    self.error = None;
                    self.warning = None;
                    if matches!(self.phase, Phase::Idle) {
                        self.set_state(TmState::Ready, events);
                    }
                }
            } else if inputs.x_reset_error {
                self.warning = None;
            }
            if axes_on && self.state != TmState::Error {
                self.commands(inputs, edges, params, belt_params, events);
            }
        }
        self.advance(inputs, edges, params, belt_params, events);
        self.drop_missed(belt_params, events);
        self.outputs(inputs, params, axes_on)
    }

    fn hw_active(&self, inputs: &Inputs) -> bool {
        inputs.x_group_enable_hw_limit
            && (inputs.ax_hw_limit_pos.iter().any(|&x| x)
                || inputs.ax_hw_limit_neg.iter().any(|&x| x))
    }

    fn limits_switches(&mut self, inputs: &Inputs, params: &Params, events: &mut Vec<Event>) {
        if !self.hw_active(inputs) || self.state == TmState::Error {
            return;
        }
        let (i, pos) = match inputs.ax_hw_limit_pos.iter().position(|&x| x) {
            Some(i) => (i, true),
            None => (
                inputs.ax_hw_limit_neg.iter().position(|&x| x).unwrap_or(0),
                false,
            ),
        };
        self.stop_axes(params);
        let (id, which) = if pos {
            (errors::HW_LIMIT_POS, "positive")
        } else {
            (errors::HW_LIMIT_NEG, "negative")
        };
        self.fail(
            id,
            format!(
                "the {which} hardware limit switch of axis {} is active",
                AXIS_NAMES[i]
            ),
            events,
        );
    }

    /// Every axis brakes on its own from where it is going (xStopALL, limit switches).
    fn stop_axes(&mut self, params: &Params) {
        let dt = self.dt;
        let now = self.hist[0];
        let prev = self.hist[1];
        let pose = self.pose;
        let from = [pose.p[0], pose.p[1], pose.p[2], pose.c, pose.aux];
        let mut dir = [0.0; 5];
        let mut laws = [Stop::plan(0.0, 0.0, 1.0, 1.0).ok(); 5];
        for (k, &i) in STOP_AXES.iter().enumerate() {
            let v = (now[i] - prev[i]) / dt;
            dir[k] = if v < 0.0 { -1.0 } else { 1.0 };
            let dec = params.alr_stop_dec[i].max(1e-9);
            let jerk = params.alr_stop_jerk[i].max(1e-9);
            laws[k] = Stop::plan(v.abs(), 0.0, dec, jerk).ok();
        }
        let laws = laws.map(|l| {
            l.unwrap_or_else(|| {
                Stop::plan(0.0, 0.0, 1.0, 1.0).unwrap_or_else(|_| unreachable_stop())
            })
        });
        self.follow = None;
        // The laws start from the last update's setpoint and speed.
        self.phase = Phase::AxisStop {
            t0: self.t - self.dt,
            from,
            dir,
            laws: Box::new(laws),
        };
    }

    fn commands(
        &mut self,
        inputs: &Inputs,
        edges: Edges,
        params: &Params,
        belt_params: &[BeltParams],
        events: &mut Vec<Event>,
    ) {
        let stop = inputs.x_path_stop || inputs.x_path_halt;
        if inputs.x_stop_all || stop {
            // A move being prepared is given up with the mode (mode 0: its profile stays
            // first in the queue).
            self.prep = None;
        }
        if inputs.x_stop_all && !matches!(self.phase, Phase::AxisStop { .. }) {
            let moving = !matches!(self.phase, Phase::Idle) || self.follow.is_some();
            if moving {
                if let Phase::Move(a) = &self.phase {
                    let again = (a.purpose == Purpose::Target).then_some(self.current_target);
                    self.restart = Some((a.purpose, again));
                }
                self.stop_axes(params);
            }
            self.looping = false;
            self.set_state(TmState::Stop, events);
            return;
        }
        if stop {
            match &mut self.phase {
                Phase::Move(a) if a.braking.is_none() && !a.held => {
                    let (dec, jerk) = if inputs.x_path_stop {
                        (params.lr_path_stop_dec, params.lr_path_stop_jerk)
                    } else {
                        (params.lr_path_halt_dec, params.lr_path_jerk)
                    };
                    brake(a, dec, jerk, false);
                    a.gripper_ok = false;
                }
                Phase::Dwell { .. } => self.stop_axes(params),
                Phase::Idle if self.follow.is_some() => self.stop_axes(params),
                _ => {}
            }
            // The modes end at once on a stop or halt (manual §3.19).
            self.looping = false;
            self.set_state(TmState::Stop, events);
            return;
        }
        if self.state == TmState::Stop && self.is_still() {
            self.set_state(TmState::Ready, events);
        }
        if matches!(self.state, TmState::JogPos | TmState::JogNeg)
            && matches!(self.phase, Phase::Idle)
            && !inputs.x_jog_pos
            && !inputs.x_jog_neg
        {
            self.set_state(TmState::Ready, events);
        }
        // Interrupt: brake on the path, resume from the break point when released.
        if let Phase::Move(a) = &mut self.phase {
            if inputs.x_path_interrupt && a.braking.is_none() && !a.held {
                // The move's end is no longer known: the next move is prepared afresh.
                self.prep = None;
                brake(a, params.lr_path_stop_dec, params.lr_path_stop_jerk, true);
                a.gripper_ok = false;
                a.interrupted = true;
                self.set_state(TmState::PathInterrupt, events);
            } else if !inputs.x_path_interrupt && a.held && self.state == TmState::PathInterrupt {
                resume(a);
                self.set_state(TmState::MovePp, events);
            }
        }
        if edges.x_abort && self.is_still() {
            self.prep = None;
            if matches!(self.phase, Phase::Move(_)) || self.restart.is_some() {
                self.phase = Phase::Idle;
                self.restart = None;
            }
            self.looping = false;
            self.queue.clear();
            self.finish_then_stop = false;
            self.set_state(TmState::Ready, events);
        } else if edges.x_abort && self.looping {
            // In motion: the current path is travelled to its end, then the mode stops.
            self.finish_then_stop = true;
        }
        if edges.x_group_home_execute && self.state == TmState::Ready && self.is_idle() {
            self.phase = Phase::Homing { next: 1 };
            self.set_state(TmState::Homing, events);
        }
        // Jogging is allowed from READY, also with a path held by a stop (manual §3.16); the
        // held path is then run again from the start by the next xExecute edge, from wherever
        // the jog left the tool.
        let held = matches!(&self.phase, Phase::Move(a) if a.held);
        if self.state == TmState::Ready && (self.is_idle() || held) {
            let sel = inputs.e_select_axis;
            if (1..=13).contains(&sel) {
                let pos = inputs.x_jog_pos && self.jog_armed.0;
                let neg = inputs.x_jog_neg && self.jog_armed.1;
                if pos || neg {
                    if let Phase::Move(a) = &self.phase {
                        let again = (a.purpose == Purpose::Target).then_some(self.current_target);
                        self.restart = Some((a.purpose, again));
                    }
                    self.start_jog(
                        (sel - 1) as usize,
                        if pos { 1.0 } else { -1.0 },
                        params,
                        events,
                    );
                }
            }
        }
        if edges.x_execute_pick_and_place {
            self.execute(inputs, params, belt_params, events);
        }
    }

    /// Whether the robot moves (`None`: it stands), and if so whether it comes to rest by
    /// itself (a path, a dwell on a belt, a stop, a homing, a jog being stopped); following a
    /// belt or jogging goes on until an input ends it.
    pub fn motion(&self) -> Option<bool> {
        if self.is_still() {
            return None;
        }
        Some(match &self.phase {
            Phase::Idle => false,
            Phase::Jog { stop, .. } => stop.is_some(),
            _ => true,
        })
    }

    fn is_idle(&self) -> bool {
        matches!(self.phase, Phase::Idle) && self.follow.is_none()
    }

    fn is_still(&self) -> bool {
        match &self.phase {
            Phase::Idle => self.follow.is_none(),
            Phase::Move(a) => a.held,
            _ => false,
        }
    }

    fn execute(
        &mut self,
        inputs: &Inputs,
        params: &Params,
        belt_params: &[BeltParams],
        events: &mut Vec<Event>,
    ) {
        self.done = false;
        if let Some((_, again)) = self.restart.take() {
            // The path given up runs again from the start, from where the tool is now.
            if let Some(entry) = again {
                self.queue.push_front(entry);
            }
            if params.e_tracking_mode != 0 {
                self.looping = true;
            }
            // Spread: the move is prepared from this update on, when the module advances.
            if self.spread.is_none() && matches!(self.phase, Phase::Idle) {
                self.next_move_now(params, belt_params, events);
            }
            return;
        }
        if let Phase::Move(a) = &mut self.phase {
            if a.held && self.state == TmState::Ready {
                resume(a);
                self.set_state(TmState::MovePp, events);
                if params.e_tracking_mode != 0 {
                    self.looping = true;
                }
                return;
            }
        }
        match params.e_tracking_mode {
            0 => {
                if self.queue.len() + usize::from(!matches!(self.phase, Phase::Idle)) < MAX_PROFILES
                {
                    self.queue.push_back((inputs.e_set_target, params.target));
                }
            }
            1..=4 => {
                self.looping = true;
                self.finish_then_stop = false;
            }
            m => {
                self.fail(
                    errors::INVALID_PARAMETER,
                    format!("eTrackingMode = {m}: it must be 0 to 4"),
                    events,
                );
                return;
            }
        }
        // Spread: the move is prepared from this update on, when the module advances.
        self.restart = None;
        if self.spread.is_none() && matches!(self.phase, Phase::Idle) {
            self.next_move_now(params, belt_params, events);
        }
    }

    /// The two sides of a tracking mode: (pick from, place onto).
    fn sides(&self, mode: i32) -> Result<(Side, Side), String> {
        let belt = |n: u32| {
            self.belt_index(n).map(Side::Belt).ok_or_else(|| {
                format!(
                    "eTrackingMode = {mode} needs belt {n} ([pickplace.belt.{n}] in machine.toml)"
                )
            })
        };
        Ok(match mode {
            1 => (Side::Static, belt(1)?),
            2 => (belt(1)?, Side::Static),
            3 => (belt(1)?, belt(2)?),
            4 => (belt(2)?, belt(1)?),
            m => return Err(format!("eTrackingMode = {m}: it must be 0 to 4")),
        })
    }

    /// Updates a spread preparation is expected to take, from the work its job will have to
    /// do ([`cost`]): as many limit checks as the last move took (at least two: about half the
    /// moves are slowed once), each of every update of a move as long as the last one, after
    /// an interception solve of six rounds (about five on average) each summing the source belt's share over
    /// those updates; with [`PREP_MARGIN`] to spare and two updates more (the update that
    /// chooses the move plans nothing, and the move begins in the update after the last step).
    fn prep_updates(&self) -> u64 {
        let budget = self.spread.unwrap_or(PREP_BUDGET).max(1) as f64;
        let t = if self.last_profile_time > 0.0 {
            self.last_profile_time
        } else {
            0.3
        };
        let n = (t / self.dt).ceil().clamp(0.0, 1e7);
        let round = cost::ROUND as f64 + cost::SRC_UPDATE as f64 * n;
        let check = cost::CHECK_UPDATE as f64 * (n + 7.0);
        let checks = f64::from(self.last_iterations.clamp(2, 12));
        let units = checks * (6.0 * round + check) * PREP_MARGIN;
        (units / budget).ceil() as u64 + 2
    }

    /// Spread preparations begun, and those of them not done by the update they were planned
    /// for (planned again from the actual state within one update).
    pub fn prep_counts(&self) -> (u64, u64) {
        self.prep_counts
    }

    /// Where the tool will be `lead` seconds from now if it stays on its present course (riding
    /// its belt at the belt's present speed, or standing): the start pose, the source belt
    /// (its base the travel predicted then) and the lift of Intermediate Point 1.
    fn origin(
        &self,
        params: &Params,
        belt_params: &[BeltParams],
        o: &Outset,
    ) -> (Pose, Option<Follow>, f64) {
        let lead = o.n as f64 * self.dt;
        match o.follow {
            Some((f, anchor)) => {
                let travel = self
                    .belts
                    .get(f.belt)
                    .map_or(f.base, |b| b.travel + b.velocity * lead);
                let mut p = anchor;
                for (x, d) in p.p.iter_mut().zip(f.offset_at(travel)) {
                    *x += d;
                }
                let lift = belt_params.get(f.belt).map_or(0.0, |b| b.lr_z_dist_belt);
                (p, Some(Follow { base: travel, ..f }), lift)
            }
            None => (o.pose, None, params.lr_z_start_dist),
        }
    }

    /// Most updates a spread preparation may keep the tool waiting ([`MAX_SPREAD_SECONDS`]).
    fn max_spread(&self) -> u64 {
        (MAX_SPREAD_SECONDS / self.dt)
            .ceil()
            .clamp(1.0, MAX_AHEAD as f64) as u64
    }

    /// The tool as it is now, for a move prepared from now on: spread over the updates it is
    /// expected to need, or (`n` 0) planned within this update when that is too many.
    fn outset_now(&self) -> Outset {
        let n = self.prep_updates();
        Outset {
            follow: self.follow,
            pose: self.pose,
            holding: self.holding,
            n: if n > self.max_spread() {
                0
            } else {
                n.clamp(1, MAX_AHEAD)
            },
        }
    }

    /// Begin preparing `req` for the update `n` updates from now: the belts as they are
    /// predicted to be then (at their present speeds). Only the goal's belt takes its
    /// workpieces along; the others are needed for their travel alone.
    #[allow(clippy::too_many_arguments)]
    fn prepare(
        &mut self,
        req: Request,
        pp: PathParams,
        n: u64,
        then: Then,
        profile: Option<Profile>,
        params: &Params,
        belt_params: &[BeltParams],
        events: &mut Vec<Event>,
    ) {
        if n == 0 {
            // Now, within this update: the belts as they are.
            if let Goal::Workpiece { belt, id, .. } = req.goal {
                let tracked = self
                    .belts
                    .get(belt)
                    .is_some_and(|b| b.pieces.iter().any(|w| w.id == id && w.pos0.is_some()));
                if !tracked {
                    // Dropped meanwhile (the belt sped up): choose again.
                    return self.next_move(params, belt_params, events);
                }
            }
            return match self.planner.plan(&req, &pp, &self.belts) {
                Err(e) => self.plan_error(e, events),
                Ok(p) => {
                    if let Some(profile) = profile {
                        self.current_target = profile;
                    }
                    self.apply(then, p, params, belt_params, events)
                }
            };
        }
        self.prep_counts.0 += 1;
        let lead = n as f64 * self.dt;
        let goal_belt = match req.goal {
            Goal::Workpiece { belt, .. } => Some(belt),
            _ => None,
        };
        let belts: Vec<Belt> = self
            .belts
            .iter()
            .enumerate()
            .map(|(k, b)| Belt {
                number: b.number,
                travel: b.travel + b.velocity * lead,
                velocity: b.velocity,
                frame: b.frame,
                origin: b.origin,
                pieces: if goal_belt == Some(k) {
                    b.pieces.clone()
                } else {
                    Vec::new()
                },
                picked: b.picked,
                missed: b.missed,
            })
            .collect();
        let job = PlanJob::new(&req, &pp, &belts);
        // The update that chose the move and copied the belts does no more planning.
        self.budget_left = 0;
        let timeless = req.src.is_none() && !matches!(req.goal, Goal::Workpiece { .. });
        self.prep = Some(Box::new(Prep {
            job,
            pp,
            belts,
            start_t: self.t + lead,
            since: self.t,
            then,
            profile,
            timeless,
            result: None,
        }));
    }

    /// Go on with the preparation in progress, with what is left of this update's budget; at
    /// the update it was planned for, begin its move (or, for a workpiece out of the range,
    /// choose again). An error ends it at once; a preparation not done by then (its work was
    /// underestimated, or the move before ended later than foreseen) is planned again from the
    /// actual state within that update, once: a start chosen further ahead would have the tool
    /// ride its belt on, possibly beyond a limit, for a path planned for where it was.
    fn run_prep(&mut self, params: &Params, belt_params: &[BeltParams], events: &mut Vec<Event>) {
        while let Some(mut prep) = self.prep.take() {
            if prep.result.is_none() {
                match prep
                    .job
                    .step_within(&self.planner, &prep.belts, &mut self.budget_left)
                {
                    None => {}
                    Some(Err(e)) => return self.plan_error(e, events),
                    Some(Ok(p)) => prep.result = Some(p),
                }
            }
            let ready = prep.result.is_some() && prep.timeless;
            if self.t + 1e-9 < prep.start_t && !ready {
                self.prep = Some(prep);
                return;
            }
            self.last_prep_time = self.t - prep.since;
            // Prepared during the move before, which ended later than foreseen (an override,
            // a stop): the start is past, so it is prepared again like one not done in time.
            let late = self.t > prep.start_t + 0.5 * self.dt && !prep.timeless;
            match prep.result.take().filter(|_| !late) {
                None => {
                    // The same goal, from where the tool is now.
                    self.prep_counts.1 += 1;
                    let o = Outset {
                        n: 0,
                        ..self.outset_now()
                    };
                    let (start, src, lift) = self.origin(params, belt_params, &o);
                    let req = Request {
                        start,
                        src,
                        lift,
                        ..*prep.job.request()
                    };
                    let (pp, then, profile) = (prep.pp, prep.then, prep.profile);
                    self.prepare(req, pp, 0, then, profile, params, belt_params, events);
                }
                Some(p) => {
                    if let Some(profile) = prep.profile {
                        self.current_target = profile;
                    }
                    self.apply(prep.then, p, params, belt_params, events)
                }
            }
            // A new preparation goes on with what is left of this update's budget, if any: its
            // start lies at least an update ahead, so the loop ends (a move planned within the
            // update leaves no preparation).
        }
    }

    /// At the update a prepared move was planned for: begin it, or for a workpiece the plan
    /// found out of the range, drop it (missed) or wait for it at the park position.
    fn apply(
        &mut self,
        then: Then,
        p: Planned,
        params: &Params,
        belt_params: &[BeltParams],
        events: &mut Vec<Event>,
    ) {
        self.last_iterations = p.iterations;
        match then {
            Then::Begin {
                purpose,
                target_out,
            } => self.begin(p.traj, p.scale, purpose, target_out, None, params, events),
            Then::Park(i) => {
                self.at_park = Some(i);
                let out = self.belts.get(i).map_or(0, |b| b.number as i32);
                self.begin_inner(p.traj, p.scale, Purpose::Park(i), out, None, 0.0, events);
            }
            Then::Workpiece {
                i,
                id,
                purpose,
                target_out,
            } => {
                let (Some(bp), Some(b)) = (belt_params.get(i).copied(), self.belts.get(i)) else {
                    return;
                };
                let pp = match self.path_params(params) {
                    Ok(p) => p,
                    Err(m) => return self.fail(errors::INVALID_PARAMETER, m, events),
                };
                let v = b.velocity;
                let sync = bp.lr_sync_time_on_belt.max(0.0);
                let x = p.arrival_x.unwrap_or(0.0);
                if !b.pieces.iter().any(|w| w.id == id) {
                    // Dropped meanwhile (the belt sped up): choose again.
                    return self.next_move(params, belt_params, events);
                }
                if x + v * sync > bp.lr_upper_sync_limit {
                    self.miss(i, id, events);
                    return self.next_move(params, belt_params, events);
                }
                if x < bp.lr_lower_sync_limit {
                    // Not in the operating range yet: wait at the park position until it can
                    // be met there.
                    let wait = if v > 0.0 {
                        (bp.lr_lower_sync_limit - x) / v
                    } else {
                        0.05
                    };
                    let o = self.outset_now();
                    return self.park(i, &bp, &pp, params, belt_params, wait, &o, events);
                }
                self.at_park = None;
                self.begin(
                    p.traj,
                    p.scale,
                    purpose,
                    target_out,
                    Some((i, id)),
                    params,
                    events,
                );
            }
        }
    }

    /// During a move whose end is known, prepare the next one for the update it will start in
    /// (after the synchronous travel, when the tool leaves the belt), so the preparation's
    /// updates are hidden in the move; and go on with such a preparation until the move ends.
    fn prepare_ahead(
        &mut self,
        params: &Params,
        belt_params: &[BeltParams],
        rate: f64,
        events: &mut Vec<Event>,
    ) {
        if self.spread.is_none() {
            return;
        }
        let dt = self.dt;
        // The updates to the move's end and its synchronous travel.
        let hidden;
        let o = match &mut self.phase {
            Phase::Move(a) if !a.ahead && self.prep.is_none() => {
                a.ahead = true;
                let plain = a.braking.is_none() && !a.held && !a.interrupted && rate == 1.0;
                if !plain || matches!(a.purpose, Purpose::Park(_)) || self.state != TmState::MovePp
                {
                    return;
                }
                // The updates to the arrival and those of the synchronous travel, as `advance`
                // counts them (the tolerance keeps a whole number of updates whole). Should
                // the count be off, the move is prepared again when it ends (`run_prep`).
                let arrive = ((a.traj.duration - a.tau) / dt - 1e-9)
                    .ceil()
                    .clamp(0.0, 1e7) as u64;
                let dwell = match a.wp {
                    Some((i, _)) => {
                        let sync = belt_params.get(i).map_or(0.0, |b| b.lr_sync_time_on_belt);
                        ((sync.max(dt * 0.5) - 1e-9) / dt).ceil().clamp(0.0, 1e7) as u64
                    }
                    // Arrived at a static position: the next move is chosen an update later.
                    None => 1,
                };
                hidden = arrive + dwell;
                let anchor = a.traj.pose_at(a.traj.length(), [0.0; 3], &[]);
                Outset {
                    follow: a.traj.dst.map(|f| (f, anchor)),
                    pose: anchor,
                    holding: match a.purpose {
                        Purpose::Pick => true,
                        Purpose::Place => false,
                        _ => self.holding,
                    },
                    n: (arrive + dwell)
                        .max(self.prep_updates())
                        .clamp(1, MAX_AHEAD),
                }
            }
            Phase::Move(_) | Phase::Dwell { .. } => {
                if let Some(prep) = self.prep.as_mut() {
                    if prep.result.is_none() {
                        match prep.job.step_within(
                            &self.planner,
                            &prep.belts,
                            &mut self.budget_left,
                        ) {
                            None => {}
                            // Raised when the move ends, by a preparation made afresh then
                            // (an error does not stop the move in progress).
                            Some(Err(_)) => self.prep = None,
                            Some(Ok(p)) => prep.result = Some(p),
                        }
                    }
                }
                return;
            }
            _ => return,
        };
        // Prepared during this move only if that keeps the tool waiting at its end no longer
        // than a spread preparation may; else the move is chosen when this one ends.
        if o.n > hidden.saturating_add(self.max_spread()) {
            return;
        }
        if self.looping || !self.queue.is_empty() {
            self.next_move_from(params, belt_params, &o, events);
        } else if let Some((f, _)) = o.follow {
            if let (Some(bp), Ok(pp)) = (belt_params.get(f.belt).copied(), self.path_params(params))
            {
                self.park(f.belt, &bp, &pp, params, belt_params, 0.0, &o, events);
            }
        }
    }

    /// Choose the next move, if there is one to make, and begin its preparation for the
    /// update it is expected to be ready by ([`Module::prep_updates`]): the tool's start and
    /// the belts are predicted for that update.
    fn next_move(&mut self, params: &Params, belt_params: &[BeltParams], events: &mut Vec<Event>) {
        if self.spread.is_none() {
            return self.next_move_now(params, belt_params, events);
        }
        let o = self.outset_now();
        self.next_move_from(params, belt_params, &o, events);
    }

    /// [`Module::next_move`] from outset `o` (now, or the end of the move in progress).
    fn next_move_from(
        &mut self,
        params: &Params,
        belt_params: &[BeltParams],
        o: &Outset,
        events: &mut Vec<Event>,
    ) {
        let pp = match self.path_params(params) {
            Ok(p) => p,
            Err(m) => return self.fail(errors::INVALID_PARAMETER, m, events),
        };
        let Some((side, purpose, target_out, profile)) = self.choose(params, o.holding, events)
        else {
            return;
        };
        let n = o.n;
        let lead = n as f64 * self.dt;
        let (start, src, lift) = self.origin(params, belt_params, o);
        let request = |goal| Request {
            start,
            src,
            lift,
            goal,
        };
        match side {
            Side::Static => {
                let t = match profile {
                    Some((_, t)) => t,
                    None => params.target,
                };
                let goal = point_goal(&t, params, &start);
                let then = Then::Begin {
                    purpose,
                    target_out,
                };
                self.prepare(
                    request(goal),
                    pp,
                    n,
                    then,
                    profile,
                    params,
                    belt_params,
                    events,
                );
            }
            Side::Belt(i) => {
                let Some(bp) = belt_params.get(i).copied() else {
                    return;
                };
                if self.t < self.wait_until && self.at_park == Some(i) {
                    return;
                }
                let sync = bp.lr_sync_time_on_belt.max(0.0);
                let v = self.belts[i].velocity;
                // The belt as it will be when the move starts.
                let travel = self.belts[i].travel + v * lead;
                let t_est = self.travel_estimate();
                for id in candidates(&self.belts[i]) {
                    match screen(&self.belts[i], id, travel, &start, &pp, &bp, t_est) {
                        Screen::Gone => {
                            self.miss(i, id, events);
                            continue;
                        }
                        Screen::Upstream(x_then) => {
                            // No use planning yet (the wait counts from now).
                            let wait = if v > 0.0 {
                                lead + (bp.lr_lower_sync_limit - x_then) / v - t_est
                            } else {
                                0.05
                            };
                            return self.park(i, &bp, &pp, params, belt_params, wait, o, events);
                        }
                        Screen::Plan => {}
                    }
                    let goal = workpiece_goal(i, id, &bp, v * sync);
                    let then = Then::Workpiece {
                        i,
                        id,
                        purpose,
                        target_out,
                    };
                    return self.prepare(
                        request(goal),
                        pp,
                        n,
                        then,
                        profile,
                        params,
                        belt_params,
                        events,
                    );
                }
                self.park(i, &bp, &pp, params, belt_params, 0.0, o, events);
            }
        }
    }

    /// Go to belt `i`'s parking position (unless the tool waits there already) from outset
    /// `o`, and wait there `wait` seconds from now before looking for a workpiece again.
    #[allow(clippy::too_many_arguments)]
    fn park(
        &mut self,
        i: usize,
        bp: &BeltParams,
        pp: &PathParams,
        params: &Params,
        belt_params: &[BeltParams],
        wait: f64,
        o: &Outset,
        events: &mut Vec<Event>,
    ) {
        self.wait_until = self.t + wait.max(0.0);
        if self.at_park == Some(i) && o.follow.is_none() {
            return;
        }
        let n = o.n;
        let (start, src, lift) = self.origin(params, belt_params, o);
        let goal = park_goal(bp, &start);
        let req = Request {
            start,
            src,
            lift,
            goal,
        };
        self.prepare(
            req,
            *pp,
            n,
            Then::Park(i),
            None,
            params,
            belt_params,
            events,
        );
    }

    /// A first guess of the next move's travel time: the last move's (0.3 s before any).
    fn travel_estimate(&self) -> f64 {
        if self.last_profile_time > 0.0 {
            self.last_profile_time
        } else {
            0.3
        }
    }

    /// The next move to make, if there is one: its side, purpose and `eActTarget`, and in
    /// target mode the queued target it takes (`holding`: the tool holds a workpiece). `None`
    /// when there is none, or when the choice failed (the error is raised).
    fn choose(
        &mut self,
        params: &Params,
        holding: bool,
        events: &mut Vec<Event>,
    ) -> Option<(Side, Purpose, i32, Option<Profile>)> {
        if self.looping {
            let (pick, place) = match self.sides(params.e_tracking_mode) {
                Ok(s) => s,
                Err(m) => {
                    self.fail(errors::INVALID_PARAMETER, m, events);
                    return None;
                }
            };
            return Some(if holding {
                (place, Purpose::Place, side_target(place), None)
            } else {
                (pick, Purpose::Pick, side_target(pick), None)
            });
        }
        let &(target, static_target) = self.queue.front()?;
        let side = if target == 0 {
            Side::Static
        } else {
            match u32::try_from(target).ok().and_then(|n| self.belt_index(n)) {
                Some(i) => Side::Belt(i),
                None => {
                    self.queue.pop_front();
                    self.fail(
                        errors::INVALID_PARAMETER,
                        format!("eSetTarget = {target}: the machine has no belt {target}"),
                        events,
                    );
                    return None;
                }
            }
        };
        Some((side, Purpose::Target, target, Some((target, static_target))))
    }

    /// Choose and prepare the next move within this update (no `prep_budget`: the path is
    /// planned in the update it is asked for).
    fn next_move_now(
        &mut self,
        params: &Params,
        belt_params: &[BeltParams],
        events: &mut Vec<Event>,
    ) {
        let pp = match self.path_params(params) {
            Ok(p) => p,
            Err(m) => return self.fail(errors::INVALID_PARAMETER, m, events),
        };
        // The target taken is the current one even when its belt turns out not to exist.
        if let (false, Some(&p)) = (self.looping, self.queue.front()) {
            self.current_target = p;
        }
        let Some((side, purpose, target_out, _)) = self.choose(params, self.holding, events) else {
            return;
        };
        let start = self.current_pose();
        let src = self.follow.map(|(f, _)| Follow {
            base: self.belts.get(f.belt).map_or(f.base, |b| b.travel),
            ..f
        });
        let lift = match self.follow {
            Some((f, _)) => belt_params.get(f.belt).map_or(0.0, |b| b.lr_z_dist_belt),
            None => params.lr_z_start_dist,
        };
        let request = |goal| Request {
            start,
            src,
            lift,
            goal,
        };
        match side {
            Side::Static => {
                let t = if purpose == Purpose::Target {
                    self.current_target.1
                } else {
                    params.target
                };
                let goal = point_goal(&t, params, &start);
                match self.planner.plan(&request(goal), &pp, &self.belts) {
                    Ok(p) => self.begin(p.traj, p.scale, purpose, target_out, None, params, events),
                    Err(e) => self.plan_error(e, events),
                }
            }
            Side::Belt(i) => {
                let Some(bp) = belt_params.get(i).copied() else {
                    return;
                };
                if self.t < self.wait_until && self.at_park == Some(i) {
                    return;
                }
                let sync = bp.lr_sync_time_on_belt.max(0.0);
                let v = self.belts[i].velocity;
                let travel = self.belts[i].travel;
                let t_est = self.travel_estimate();
                for id in candidates(&self.belts[i]) {
                    match screen(&self.belts[i], id, travel, &start, &pp, &bp, t_est) {
                        Screen::Gone => {
                            self.miss(i, id, events);
                            continue;
                        }
                        Screen::Upstream(x_now) => {
                            // No use planning yet.
                            let wait = if v > 0.0 {
                                (bp.lr_lower_sync_limit - x_now) / v - t_est
                            } else {
                                0.05
                            };
                            return self.park_now(i, &bp, &pp, start, src, lift, wait, events);
                        }
                        Screen::Plan => {}
                    }
                    let goal = workpiece_goal(i, id, &bp, v * sync);
                    match self.planner.plan(&request(goal), &pp, &self.belts) {
                        Ok(p) => {
                            let x = p.arrival_x.unwrap_or(0.0);
                            if x + v * sync > bp.lr_upper_sync_limit {
                                self.miss(i, id, events);
                                continue;
                            }
                            if x < bp.lr_lower_sync_limit {
                                // Not in the operating range yet: wait at the park position
                                // until it can be met there.
                                let wait = if v > 0.0 {
                                    (bp.lr_lower_sync_limit - x) / v
                                } else {
                                    0.05
                                };
                                return self.park_now(i, &bp, &pp, start, src, lift, wait, events);
                            }
                            self.at_park = None;
                            return self.begin(
                                p.traj,
                                p.scale,
                                purpose,
                                target_out,
                                Some((i, id)),
                                params,
                                events,
                            );
                        }
                        Err(e) => return self.plan_error(e, events),
                    }
                }
                self.park_now(i, &bp, &pp, start, src, lift, 0.0, events);
            }
        }
    }

    /// [`Module::park`] within this update (no `prep_budget`).
    #[allow(clippy::too_many_arguments)]
    fn park_now(
        &mut self,
        i: usize,
        bp: &BeltParams,
        pp: &PathParams,
        start: Pose,
        src: Option<Follow>,
        lift: f64,
        wait: f64,
        events: &mut Vec<Event>,
    ) {
        self.wait_until = self.t + wait.max(0.0);
        if self.at_park == Some(i) && self.follow.is_none() {
            return;
        }
        let goal = park_goal(bp, &start);
        let req = Request {
            start,
            src,
            lift,
            goal,
        };
        match self.planner.plan(&req, pp, &self.belts) {
            Ok(p) => {
                self.at_park = Some(i);
                let out = self.belts.get(i).map_or(0, |b| b.number as i32);
                self.begin_inner(p.traj, p.scale, Purpose::Park(i), out, None, 0.0, events);
            }
            Err(e) => self.plan_error(e, events),
        }
    }

    fn miss(&mut self, i: usize, id: u32, events: &mut Vec<Event>) {
        let b = &mut self.belts[i];
        if let Some(w) = b.remove(id) {
            b.missed += 1;
            events.push(Event::Missed {
                belt: b.number,
                id,
                x: w.belt_x(b.travel).unwrap_or(0.0),
            });
        }
    }

    /// Workpieces the tool can no longer meet inside the operating range are dropped.
    fn drop_missed(&mut self, belt_params: &[BeltParams], events: &mut Vec<Event>) {
        let busy: Option<(usize, u32)> = match &self.phase {
            Phase::Move(a) => a.wp,
            Phase::Dwell { wp, .. } => *wp,
            _ => None,
        };
        for i in 0..self.belts.len() {
            let Some(bp) = belt_params.get(i) else {
                continue;
            };
            // Checked every cycle for every workpiece: no allocation unless one is late.
            let limit = bp.lr_upper_sync_limit;
            let sync = bp.lr_sync_time_on_belt.max(0.0);
            let skip = busy.filter(|(b, _)| *b == i).map(|(_, id)| id);
            // What the belt carries a workpiece during the synchronous travel; missing one
            // changes neither the speed nor the travel.
            let carry = self.belts[i].velocity * sync;
            while let Some(id) = self.belts[i].first_beyond(skip, carry, limit) {
                self.miss(i, id, events);
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn begin(
        &mut self,
        traj: Trajectory,
        scale: f64,
        purpose: Purpose,
        target_out: i32,
        wp: Option<(usize, u32)>,
        params: &Params,
        events: &mut Vec<Event>,
    ) {
        let lead = match purpose {
            Purpose::Pick | Purpose::Target => params.lr_gripper_closing_time,
            Purpose::Place => params.lr_gripper_open_time,
            Purpose::Park(_) => 0.0,
        };
        if purpose == Purpose::Target {
            self.queue.pop_front();
        }
        self.begin_inner(traj, scale, purpose, target_out, wp, lead, events);
    }

    #[allow(clippy::too_many_arguments)]
    fn begin_inner(
        &mut self,
        traj: Trajectory,
        scale: f64,
        purpose: Purpose,
        target_out: i32,
        wp: Option<(usize, u32)>,
        lead: f64,
        events: &mut Vec<Event>,
    ) {
        events.push(Event::Planned {
            target: target_out,
            duration: traj.duration,
            scale,
        });
        self.last_profile_time = traj.duration;
        self.follow = None;
        let src_travel = traj
            .src
            .map_or(0.0, |f| self.belts.get(f.belt).map_or(f.base, |b| b.travel));
        // The move was planned with the source belt where it was predicted to be now; what
        // it really travelled meanwhile (a speed change) is where the tool really is, and the
        // clutch takes it up like any other deviation of the source belt.
        let src_off = match (self.spread, traj.src) {
            (Some(_), Some(f)) => f.offset_at(src_travel),
            _ => [0.0; 3],
        };
        self.phase = Phase::Move(Box::new(Active {
            traj,
            tau: 0.0,
            purpose,
            target_out,
            wp,
            lead,
            pulsed: false,
            gripper_ok: lead > 0.0,
            interrupted: false,
            braking: None,
            held: false,
            ahead: false,
            src_off,
            src_travel,
        }));
        self.set_state(TmState::MovePp, events);
    }

    fn start_jog(&mut self, axis: usize, dir: f64, params: &Params, events: &mut Vec<Event>) {
        let [jerk, vel, acc, dec] = match axis {
            0..=2 => params.cartesian_jog,
            3..=5 => params.orientation_jog,
            _ => params.real_axis_jog,
        };
        if !self.planner.robot.has_axis(axis) {
            return;
        }
        let law = match DoubleS::plan(
            1e12,
            Limits {
                vel,
                acc,
                dec,
                jerk,
            },
        ) {
            Ok(l) => l,
            Err(e) => return self.fail(errors::INVALID_PARAMETER, format!("jog: {e}"), events),
        };
        let origin = match self.planner.robot.axes(&self.pose) {
            Ok(q) => q[axis],
            Err(e) => return self.fail(errors::NO_SOLUTION, e.to_string(), events),
        };
        self.phase = Phase::Jog {
            axis,
            dir,
            t0: self.t,
            origin,
            law,
            stop: None,
        };
        self.set_state(
            if dir > 0.0 {
                TmState::JogPos
            } else {
                TmState::JogNeg
            },
            events,
        );
    }

    /// Put `value` on manual axis `axis` of the pose (real axes through the kinematics).
    fn set_axis(&self, axis: usize, value: f64) -> Result<Pose, String> {
        let mut p = self.pose;
        match axis {
            0..=2 => p.p[axis] = value,
            3 | 4 => p.ab[axis - 3] = value,
            5 => p.c = value,
            AUX1 => p.aux = value,
            _ => {
                let mut q = self
                    .planner
                    .robot
                    .axes(&self.pose)
                    .map_err(|e| e.to_string())?;
                q[axis] = value;
                if axis == 9 {
                    p.c = value;
                } else {
                    p.p = self
                        .planner
                        .robot
                        .forward([q[6], q[7], q[8]])
                        .map_err(|e| e.to_string())?;
                }
            }
        }
        Ok(p)
    }

    fn advance(
        &mut self,
        inputs: &Inputs,
        edges: Edges,
        params: &Params,
        belt_params: &[BeltParams],
        events: &mut Vec<Event>,
    ) {
        let dt = self.dt;
        if self.state == TmState::Error
            && self.follow.is_some()
            && matches!(self.phase, Phase::Idle)
        {
            // An error while riding a belt: the tool cannot stay on it; every axis brakes.
            self.stop_axes(params);
        }
        let ovr = inputs.lr_override;
        let rate = if ovr.is_finite() {
            ovr.clamp(0.0, 1.0)
        } else {
            1.0
        };
        let travels = std::mem::take(&mut self.travel_buf);
        let phase = std::mem::replace(&mut self.phase, Phase::Idle);
        self.phase = match phase {
            Phase::Idle => {
                self.pose = self.current_pose();
                if (self.looping || !self.queue.is_empty() || self.prep.is_some())
                    && self.state != TmState::Error
                    && self.state != TmState::Stop
                    && inputs.x_regulator_on_all
                {
                    self.phase = Phase::Idle;
                    if self.prep.is_none() {
                        self.next_move(params, belt_params, events);
                    }
                    self.run_prep(params, belt_params, events);
                    if matches!(self.phase, Phase::Idle)
                        && self.at_park.is_some()
                        && self.prep.is_none()
                        && self.state != TmState::Error
                    {
                        self.set_state(TmState::MovePp, events);
                    }
                    std::mem::replace(&mut self.phase, Phase::Idle)
                } else {
                    self.prep = None;
                    if matches!(self.state, TmState::MovePp | TmState::PreparingPath)
                        && !self.looping
                        && self.queue.is_empty()
                    {
                        self.done = true;
                        self.set_state(TmState::Ready, events);
                    }
                    Phase::Idle
                }
            }
            Phase::Move(mut a) => {
                if rate != 1.0 || ovr != self.last_override {
                    a.gripper_ok = false;
                }
                a.tau += rate * dt;
                let s = match a.braking {
                    // Braking at the stretch's own end: it runs on until then.
                    Some(b) if a.tau < b.tau0 => a.traj.state(a.tau).s,
                    Some(b) => {
                        if a.tau - b.tau0 >= b.law.duration() {
                            a.held = true;
                            a.tau = b.tau0 + b.law.duration();
                        }
                        b.s0 + b.law.sample(a.tau - b.tau0).s
                    }
                    None => a.traj.state(a.tau).s,
                };
                if let Some(f) = a.traj.src {
                    let now = travels.get(f.belt).copied().unwrap_or(a.src_travel);
                    let step = a.traj.src_step(s, now - a.src_travel);
                    for (o, x) in a.src_off.iter_mut().zip(step) {
                        *o += x;
                    }
                    a.src_travel = now;
                }
                self.pose = a.traj.pose_at(s, a.src_off, &travels);
                let remaining = a.traj.duration - a.tau;
                if a.gripper_ok && !a.pulsed && a.braking.is_none() && remaining <= a.lead + 1e-9 {
                    a.pulsed = true;
                    self.pulse = true;
                    events.push(Event::Gripper {
                        close: a.purpose != Purpose::Place,
                    });
                }
                if a.braking.is_none() && !a.held && a.tau >= a.traj.duration {
                    if a.interrupted && a.lead > 0.0 && !a.pulsed {
                        self.pulse = true;
                        events.push(Event::Gripper {
                            close: a.purpose != Purpose::Place,
                        });
                    }
                    self.arrive(*a, belt_params, events)
                } else {
                    Phase::Move(a)
                }
            }
            Phase::Dwell {
                until,
                purpose,
                wp,
                target_out,
            } => {
                self.pose = self.current_pose();
                if self.t + 1e-9 >= until || edges.x_ack_gripper {
                    self.finish_dwell(purpose, wp, target_out, events);
                    // The next move, prepared during this one, is kept if it is still the one
                    // to make (the mode still runs) and its start is not past.
                    let wanted = self.looping || !self.queue.is_empty();
                    let keep = self.prep.as_ref().is_some_and(|p| {
                        self.t <= p.start_t + 0.5 * dt
                            && (wanted || matches!(p.then, Then::Park(_)))
                    });
                    if !keep {
                        self.prep = None;
                        if wanted {
                            self.next_move(params, belt_params, events);
                        } else if let Some((f, _)) = self.follow {
                            // Nothing more to do on this belt: leave it for its parking
                            // position.
                            if let (Some(bp), Ok(pp)) =
                                (belt_params.get(f.belt).copied(), self.path_params(params))
                            {
                                if self.spread.is_some() {
                                    let o = self.outset_now();
                                    self.park(
                                        f.belt,
                                        &bp,
                                        &pp,
                                        params,
                                        belt_params,
                                        0.0,
                                        &o,
                                        events,
                                    );
                                } else {
                                    let start = self.current_pose();
                                    let src = Some(Follow {
                                        base: self.belts[f.belt].travel,
                                        ..f
                                    });
                                    self.park_now(
                                        f.belt,
                                        &bp,
                                        &pp,
                                        start,
                                        src,
                                        bp.lr_z_dist_belt,
                                        0.0,
                                        events,
                                    );
                                }
                            }
                        }
                    }
                    self.run_prep(params, belt_params, events);
                    std::mem::replace(&mut self.phase, Phase::Idle)
                } else {
                    Phase::Dwell {
                        until,
                        purpose,
                        wp,
                        target_out,
                    }
                }
            }
            Phase::AxisStop {
                t0,
                from,
                dir,
                laws,
            } => {
                let t = self.t - t0;
                let mut done = true;
                let mut vals = [0.0; 5];
                for k in 0..5 {
                    let st = laws[k].sample(t);
                    vals[k] = from[k] + dir[k] * st.s;
                    done &= t >= laws[k].duration();
                }
                self.pose.p = [vals[0], vals[1], vals[2]];
                self.pose.c = vals[3];
                self.pose.aux = vals[4];
                if done {
                    Phase::Idle
                } else {
                    Phase::AxisStop {
                        t0,
                        from,
                        dir,
                        laws,
                    }
                }
            }
            Phase::Jog {
                axis,
                dir,
                t0,
                origin,
                law,
                mut stop,
            } => {
                let t = self.t - t0;
                let held = if dir > 0.0 {
                    inputs.x_jog_pos
                } else {
                    inputs.x_jog_neg
                };
                let [_, _, _, dec] = match axis {
                    0..=2 => params.cartesian_jog,
                    3..=5 => params.orientation_jog,
                    _ => params.real_axis_jog,
                };
                let jerk = match axis {
                    0..=2 => params.cartesian_jog[0],
                    3..=5 => params.orientation_jog[0],
                    _ => params.real_axis_jog[0],
                };
                let run = law.sample(t);
                // Brake in time for a software limit the jog is heading for.
                let limit = self.planner.sw[axis].map(|(lo, hi)| if dir > 0.0 { hi } else { lo });
                if stop.is_none() {
                    let brake_now = !held
                        || limit.is_some_and(|l| {
                            Stop::plan(run.v, run.a, dec, jerk).is_ok_and(|s| {
                                (origin + dir * (run.s + s.distance()) - l) * dir >= 0.0
                            })
                        });
                    if brake_now {
                        if let Ok(s) = Stop::plan(run.v, run.a, dec, jerk) {
                            stop = Some((s, t, run.s));
                        }
                    }
                }
                let (s, finished) = match stop {
                    Some((law_s, ts, s0)) => {
                        let st = law_s.sample(t - ts);
                        (s0 + st.s, t - ts >= law_s.duration())
                    }
                    None => (run.s, false),
                };
                // A Cartesian jog must stay where the robot reaches.
                let moved = self.set_axis(axis, origin + dir * s).and_then(|p| {
                    self.planner
                        .robot
                        .axes(&p)
                        .map(|_| p)
                        .map_err(|e| e.to_string())
                });
                match moved {
                    Ok(p) => self.pose = p,
                    Err(m) => {
                        self.fail(errors::NO_SOLUTION, format!("jog: {m}"), events);
                        return;
                    }
                }
                if finished {
                    if held && limit.is_some() {
                        let (id, which) = if dir > 0.0 {
                            (errors::SW_LIMIT_POS, "positive")
                        } else {
                            (errors::SW_LIMIT_NEG, "negative")
                        };
                        self.fail(
                            id,
                            format!(
                                "jog of axis {} stopped at its {which} software limit",
                                AXIS_NAMES[axis]
                            ),
                            events,
                        );
                        return;
                    }
                    // READY only once both jog inputs are reset (manual §3.8).
                    if !inputs.x_jog_pos && !inputs.x_jog_neg {
                        self.set_state(TmState::Ready, events);
                    }
                    self.jog_armed = (!inputs.x_jog_pos, !inputs.x_jog_neg);
                    Phase::Idle
                } else {
                    Phase::Jog {
                        axis,
                        dir,
                        t0,
                        origin,
                        law,
                        stop,
                    }
                }
            }
            Phase::Homing { next } => self.home(next, params, events),
        };
        self.prepare_ahead(params, belt_params, rate, events);
        // PREPARING_PATH while the tool waits for its next move (riding its belt, or standing).
        if self.prep.is_some() && matches!(self.phase, Phase::Idle) {
            if matches!(self.state, TmState::Ready | TmState::MovePp) {
                self.set_state(TmState::PreparingPath, events);
            }
        } else if self.state == TmState::PreparingPath {
            self.set_state(TmState::MovePp, events);
        }
        self.travel_buf = travels;
    }

    fn home(&mut self, next: i32, params: &Params, events: &mut Vec<Event>) -> Phase {
        // One homing group per cycle, in aeHomingOrder: the group's real axes take their
        // alrHomePosition (the reference is known from then on).
        let mut order = next;
        while order <= 12 {
            let group: Vec<usize> = (0..7)
                .filter(|&k| params.ae_homing_order[k] == order)
                .collect();
            if !group.is_empty() {
                if let Ok(mut q) = self.planner.robot.axes(&self.pose) {
                    for &k in &group {
                        if k < 6 {
                            q[6 + k] = params.alr_home_position[k];
                        } else {
                            self.pose.aux = params.alr_home_position[6];
                        }
                    }
                    match self.planner.robot.forward([q[6], q[7], q[8]]) {
                        Ok(p) => self.pose.p = p,
                        Err(e) => {
                            self.fail(errors::NO_SOLUTION, format!("homing: {e}"), events);
                            return Phase::Idle;
                        }
                    }
                }
                events.push(Event::Homed { order });
                return Phase::Homing { next: order + 1 };
            }
            order += 1;
        }
        self.homed = true;
        self.set_state(TmState::Ready, events);
        Phase::Idle
    }

    fn arrive(&mut self, a: Active, belt_params: &[BeltParams], events: &mut Vec<Event>) -> Phase {
        let end = a.traj.length();
        let anchor = a.traj.pose_at(end, a.src_off, &[]);
        match a.traj.dst {
            // The anchor is the end point with the belt at its predicted travel.
            Some(f) => self.follow = Some((f, anchor)),
            None => {
                self.follow = None;
                self.pose = anchor;
            }
        }
        self.pose = self.current_pose();
        match (a.purpose, a.wp) {
            (Purpose::Park(_), _) => {
                self.follow = None;
                Phase::Idle
            }
            (_, Some((i, _))) => {
                let sync = belt_params
                    .get(i)
                    .map_or(0.0, |b| b.lr_sync_time_on_belt.max(0.0));
                Phase::Dwell {
                    until: self.t + sync.max(self.dt * 0.5),
                    purpose: a.purpose,
                    wp: a.wp,
                    target_out: a.target_out,
                }
            }
            (purpose, None) => {
                self.finish_dwell(purpose, None, a.target_out, events);
                Phase::Idle
            }
        }
    }

    fn finish_dwell(
        &mut self,
        purpose: Purpose,
        wp: Option<(usize, u32)>,
        target_out: i32,
        events: &mut Vec<Event>,
    ) {
        let position = self.pose.p;
        let belt = wp.and_then(|(i, _)| self.belts.get(i).map(|b| b.number));
        let id = wp.map(|(_, id)| id);
        if let Some((i, id)) = wp {
            if let Some(b) = self.belts.get_mut(i) {
                if b.remove(id).is_some() {
                    b.picked += 1;
                }
            }
        }
        match purpose {
            Purpose::Pick => {
                self.holding = true;
                events.push(Event::Pick { belt, id, position });
            }
            Purpose::Place => {
                self.holding = false;
                events.push(Event::Place { belt, id, position });
                if self.finish_then_stop {
                    self.looping = false;
                    self.finish_then_stop = false;
                }
            }
            Purpose::Target => events.push(Event::Reached {
                target: target_out,
                id,
                position,
            }),
            Purpose::Park(_) => {}
        }
    }

    fn outputs(&mut self, inputs: &Inputs, params: &Params, axes_on: bool) -> Outputs {
        let q = self.planner.robot.axes(&self.pose).unwrap_or(self.hist[0]);
        let dt = self.dt;
        let mut vel = [0.0; AXES];
        for i in 0..AXES {
            vel[i] = (q[i] - self.hist[0][i]) / dt;
        }
        self.hist[1] = self.hist[0];
        self.hist[0] = q;
        let mut o = Outputs {
            e_tm_state: self.state,
            x_error: self.error.is_some(),
            x_warning: self.warning.is_some(),
            e_error_id: self
                .error
                .as_ref()
                .map(|e| e.0)
                .or(self.warning)
                .unwrap_or(0),
            x_axes_enabled: axes_on,
            x_done: self.done,
            x_axes_group_homed: self.homed,
            alr_act_pos: q,
            alr_act_vel: vel,
            x_pulse_gripper: self.pulse,
            lr_pre_calc_profile_time: self.last_profile_time,
            lr_path_preparation_time: match self.spread {
                Some(_) => self.last_prep_time,
                None if self.last_profile_time > 0.0 => dt,
                None => 0.0,
            },
            x_profile_in_preparation: self.queue.len() + 1 >= MAX_PROFILES,
            ..Outputs::default()
        };
        o.x_busy = !matches!(self.phase, Phase::Idle)
            || self.looping
            || !self.queue.is_empty()
            || self.prep.is_some();
        let hw = inputs.x_group_enable_hw_limit;
        o.ax_hw_limit_switch_pos = inputs.ax_hw_limit_pos.map(|x| hw && x);
        o.ax_hw_limit_switch_neg = inputs.ax_hw_limit_neg.map(|x| hw && x);
        o.ax_sw_limit_switch_active = std::array::from_fn(|i| {
            self.planner.sw[i].is_some_and(|(lo, hi)| q[i] <= lo + 1e-9 || q[i] >= hi - 1e-9)
        });
        o.x_hw_limit_switch_active = o
            .ax_hw_limit_switch_pos
            .iter()
            .chain(o.ax_hw_limit_switch_neg.iter())
            .any(|&x| x);
        o.x_sw_limit_switch_active = o.ax_sw_limit_switch_active.iter().any(|&x| x);
        o.x_gripper_ctrl_active = (params.lr_gripper_closing_time > 0.0
            || params.lr_gripper_open_time > 0.0)
            && inputs.lr_override == 1.0;
        match &self.phase {
            Phase::Move(a) => {
                let st = a.traj.state(a.tau);
                let speed = match a.braking {
                    _ if a.held => 0.0,
                    Some(b) if a.tau >= b.tau0 => b.law.sample(a.tau - b.tau0).v,
                    _ => st.v,
                };
                o.lr_set_path_vel_out = speed * inputs.lr_override.clamp(0.0, 1.0);
                o.i_profile_point_passed = a.traj.points_passed(st.s) as i32;
                let w = a.traj.weight(st.s);
                let follows = a.traj.src.is_some() || a.traj.dst.is_some();
                o.x_acc_dec_sync = follows && w > 0.0 && w < 1.0;
                o.x_synchronised =
                    (a.traj.src.is_some() && w == 0.0) || (a.traj.dst.is_some() && w == 1.0);
                o.x_path_hold = a.held;
                o.e_set_target_out = a.target_out;
                o.x_gripper_ctrl_active &= a.gripper_ok;
            }
            Phase::Dwell { target_out, .. } => {
                o.x_synchronised = true;
                o.x_in_target = true;
                o.x_in_position = true;
                o.e_set_target_out = *target_out;
            }
            Phase::Idle => {
                o.x_in_park_pos = self.at_park.is_some() && self.follow.is_none();
                o.x_in_position = self.follow.is_none();
                o.x_in_target = self.follow.is_none() && self.at_park.is_none() && self.done;
                o.x_synchronised = self.follow.is_some();
            }
            _ => {}
        }
        self.last_override = inputs.lr_override;
        o
    }
}

fn side_target(side: Side) -> i32 {
    match side {
        Side::Static => 0,
        Side::Belt(i) => i as i32 + 1,
    }
}

fn unreachable_stop() -> Stop {
    // Stop::plan(0, 0, 1, 1) always succeeds; this only satisfies the type.
    Stop::plan(0.0, 0.0, 1.0, 1.0).unwrap_or_else(|_| unreachable_stop())
}

/// Brake along the path from where the move is, without overrunning the stretch's end.
fn brake(a: &mut Active, dec: f64, jerk: f64, interrupt: bool) {
    let tau = a.tau;
    let Some(leg) = a.traj.legs.iter().rev().find(|l| tau >= l.t0).copied() else {
        return;
    };
    let st = leg.law.sample(tau - leg.t0);
    let leg_end = leg.s0 + leg.law.length();
    // The manual takes the stop's deceleration and jerk only where they are higher than the
    // path's, so a stop never ends beyond where the path itself would.
    let dec = dec.max(a.traj.law.dec);
    let jerk = jerk.max(a.traj.law.jerk);
    if let Ok(stop) = Stop::plan(st.v.max(0.0), st.a, dec, jerk) {
        let s0 = leg.s0 + st.s;
        if s0 + stop.distance() <= leg_end + 1e-9 {
            a.braking = Some(Braking {
                s0,
                tau0: tau,
                law: stop,
                interrupt,
            });
            return;
        }
    }
    // The stretch's own deceleration ends sooner: let it bring the tool to rest at its end.
    let rest = leg.t0 + leg.law.duration();
    let stop = Stop::plan(0.0, 0.0, 1.0, 1.0).unwrap_or_else(|_| unreachable_stop());
    a.braking = Some(Braking {
        s0: leg_end,
        tau0: rest,
        law: stop,
        interrupt,
    });
    // Until `rest` the leg runs on; `advance` samples the braking only from tau0.
}

/// Continue a held move from where it stopped: the rest of its stretch gets a new law.
fn resume(a: &mut Active) {
    let Some(b) = a.braking.take() else {
        a.held = false;
        return;
    };
    let s = b.s0 + b.law.distance();
    let tau = a.tau;
    let idx = a
        .traj
        .legs
        .iter()
        .rposition(|l| l.s0 <= s + 1e-12)
        .unwrap_or(0);
    let leg = a.traj.legs[idx];
    let leg_end = leg.s0 + leg.law.length();
    let lim = a.traj.law;
    let mut legs = Vec::with_capacity(a.traj.legs.len());
    let mut t0 = tau;
    if let Ok(law) = DoubleS::plan((leg_end - s).max(0.0), lim) {
        legs.push(Leg { s0: s, t0, law });
        t0 += law.duration();
    }
    for l in &a.traj.legs[idx + 1..] {
        legs.push(Leg { t0, ..*l });
        t0 += l.law.duration();
    }
    a.traj.legs = legs;
    a.traj.duration = t0;
    a.held = false;
}

/// A static target `t` (X, Y, Z, A, B, C, Aux1) as a goal: the tool's A and B as they are at
/// `start`, approached from `lrZTargetDist` above.
fn point_goal(t: &[f64; 7], params: &Params, start: &Pose) -> Goal {
    Goal::Point {
        pose: Pose {
            p: [t[0], t[1], t[2]],
            ab: start.ab,
            c: t[5],
            aux: t[6],
        },
        approach: params.lr_z_target_dist,
    }
}

/// Workpiece `id` on belt `i` as a goal, met within the belt's operating range, the tool
/// carried `carry` mm on by the belt during its synchronous travel.
fn workpiece_goal(i: usize, id: u32, bp: &BeltParams, carry: f64) -> Goal {
    Goal::Workpiece {
        belt: i,
        id,
        approach: bp.lr_z_dist_belt,
        aux: bp.lr_aux1_target_pos,
        upper: bp.lr_upper_sync_limit,
        carry,
    }
}

/// The park position of a belt as a goal: its X, Y, Z and C, the tool's other axes as they are
/// at `start`.
fn park_goal(bp: &BeltParams, start: &Pose) -> Goal {
    let park = bp.alr_park_pos;
    Goal::Park {
        pose: Pose {
            p: [park[0], park[1], park[2]],
            ab: start.ab,
            c: park[5],
            aux: start.aux,
        },
    }
}
