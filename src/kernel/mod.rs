//! The kernel objects' behaviour behind member writes and actions, and the motion generator.
//! Index moves and dwells run on the servo axis; Home, Jog and Gear are not simulated yet, and
//! initiating one is a clear run-time error.

pub mod capture;
pub mod dsp;
pub mod motion;
pub mod orion;
pub mod pickplace;
pub mod queue;
pub mod regist;
pub mod timer;

use crate::devices::command::StartRef;
use crate::registry::{
    HomeConfig, Hook, IndexConfig, IndexType, Kind, PlsConfig, QueueSource, Registry, SlotId,
};
use crate::trace::{self, MotionPhase, Trace};
use crate::world::Edge;
use capture::{Capture, Positions};
use motion::trapezoid::{Phase, Trapezoid};
use motion::{Axis, Clocks, Domain, Event, Motion, Owner, Plan};
use queue::Queue;
use timer::Timer;

/// The slot of a catalog member; the catalog is static, so a miss is a bug in pacer itself.
pub fn slot(registry: &Registry, kind: Kind, instance: u32, member: &str) -> SlotId {
    registry.slot_of(kind, instance, member).unwrap_or_else(|| {
        panic!("catalog has no {kind:?}.{instance}.{member} (a bug in pacer's catalog)")
    })
}

/// Axis number and member index of a slot of DSP axis `instance` (0-based).
fn registry_axis_layout(slot: SlotId, instance: u32, orion: &orion::Orion) -> (u32, u32) {
    let n = instance + 1;
    let first = orion.slot(n, 0).unwrap_or(slot);
    (n, slot.saturating_sub(first))
}

/// What an action did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActOutcome {
    /// Done; the program goes on.
    Done,
    /// Motion is running on that profile: the program waits and retries.
    ProfileBusy,
}

/// Everything the kernel objects need from the moment.
pub struct Now<'a> {
    /// The update being computed.
    pub tick: u64,
    /// Its time in nanoseconds.
    pub time_ns: u64,
    /// Update period in nanoseconds.
    pub tick_ns: u64,
    /// Master position at this update.
    pub master: f64,
    /// The trace.
    pub trace: &'a mut Trace,
}

impl Now<'_> {
    /// The time of this update, seconds.
    pub fn seconds(&self) -> f64 {
        self.time_ns as f64 / 1e9
    }

    /// The moment of update `tick` with period `tick_ns`.
    pub fn at(tick: u64, tick_ns: u64, master: f64, trace: &mut Trace) -> Now<'_> {
        Now {
            tick,
            time_ns: tick * tick_ns,
            tick_ns,
            master,
            trace,
        }
    }
}

/// The state of all kernel objects of a machine.
pub struct Kernel {
    queues: Vec<Queue>,
    queue_sources: Vec<QueueSource>,
    captures: Vec<Capture>,
    timers: Vec<Timer>,
    indexes: Vec<IndexObject>,
    axis: Axis,
    profile_busy: Vec<SlotId>,
    axis_slots: AxisSlots,
    feed_rate: SlotId,
    stop_decel: SlotId,
    gear: GearSlots,
    free_run: SlotId,
    slot_kinds: Vec<Kind>,
    events: Vec<Event>,
    homes: Vec<HomeObject>,
    /// Registration indexes still waiting for their sensor.
    armed: Vec<bool>,
    /// Rollover of the axis's reported positions (0: none).
    rollover: f64,
    /// User units.
    units: crate::registry::Units,
    /// The motion clock (realtime motions run on it) and the real time it was last read at.
    motion_time: f64,
    motion_read_at: f64,
    /// The edge (time, master position) an initiate from an input starts at, while it runs.
    edge_start: Option<(f64, f64)>,
    jogs: Vec<JogObject>,
    jog_select: SlotId,
    jog_plus: SlotId,
    jog_minus: SlotId,
    minus_initiates: Vec<SlotId>,
    plss: Vec<PlsObject>,
    master_speed: f64,
    marks: Vec<AxisMarks>,
    /// Time and command position at the previous update, for crossings inside an update.
    previous: (f64, f64),
    /// Sensor edges made by the axis crossing marks, for the world to apply next update.
    pub pending_edges: Vec<Edge>,
    /// The ORION DSP axes (machine.toml `[axis.N]`), when the machine has any.
    pub orion: Option<orion::Orion>,
    /// The pick & place module, when the machine has one.
    pub pickplace: Option<Box<pickplace::PickPlaceCell>>,
}

/// Sensor marks tied to the servo axis: the sensor is on while the axis is within
/// `[position, position + width)` of a mark at `first + k·pitch`, k < count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisMarks {
    /// The sensor input.
    pub slot: SlotId,
    /// First mark, axis units.
    pub first: f64,
    /// Distance between marks (0 for a single mark).
    pub pitch: f64,
    /// Number of marks.
    pub count: u32,
    /// Width of each mark, axis units.
    pub width: f64,
}

impl AxisMarks {
    /// Edges (with the axis position at each) when the axis moves from `a` (at `ta`) to `b`
    /// (at `tb`), times interpolated.
    fn crossings(&self, a: f64, b: f64, ta: f64, tb: f64, out: &mut Vec<(Edge, f64)>) {
        if a == b || self.count == 0 {
            return;
        }
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        let time = |p: f64| ta + (p - a) / (b - a) * (tb - ta);
        // Candidate marks whose window may touch [lo, hi].
        let (k0, k1) = if self.pitch > 0.0 {
            let k0 = ((lo - self.width - self.first) / self.pitch)
                .floor()
                .max(0.0);
            let k1 = ((hi - self.first) / self.pitch)
                .ceil()
                .min(f64::from(self.count - 1));
            (k0 as u32, k1.max(0.0) as u32)
        } else {
            (0, 0)
        };
        let mut local = Vec::new();
        for k in k0..=k1.min(self.count - 1) {
            let p = self.first + f64::from(k) * self.pitch;
            let q = p + self.width;
            // Moving plus: on at p, off at q. Moving minus: on at q, off at p.
            for (edge, on_when_plus) in [(p, true), (q, false)] {
                let crossed = if a < b {
                    a < edge && edge <= b
                } else {
                    b <= edge && edge < a
                };
                if crossed {
                    local.push((
                        Edge {
                            at: time(edge),
                            slot: self.slot,
                            on: on_when_plus == (a < b),
                        },
                        edge,
                    ));
                }
            }
        }
        local.sort_by(|x, y| x.0.at.total_cmp(&y.0.at));
        out.extend(local);
    }
}

/// A jog: the slots of its settings and status.
#[derive(Debug, Clone)]
struct JogObject {
    velocity: SlotId,
    acceleration: SlotId,
    deceleration: SlotId,
    in_progress: SlotId,
}

impl JogObject {
    fn new(registry: &Registry, i: u32) -> JogObject {
        let s = |m: &str| slot(registry, Kind::Jog, i, m);
        JogObject {
            velocity: s("Velocity"),
            acceleration: s("Acceleration"),
            deceleration: s("Deceleration"),
            in_progress: s("CommandInProgress"),
        }
    }
}

/// A programmable limit switch: a window on a position.
#[derive(Debug, Clone)]
struct PlsObject {
    config: PlsConfig,
    enable: SlotId,
    on: SlotId,
    off: SlotId,
    direction: SlotId,
    status: SlotId,
}

impl PlsObject {
    fn new(registry: &Registry, i: u32) -> PlsObject {
        let s = |m: &str| slot(registry, Kind::Pls, i, m);
        PlsObject {
            config: registry
                .pls_setups
                .get(i as usize)
                .copied()
                .unwrap_or_default(),
            enable: s("Enable"),
            on: s("OnPosn"),
            off: s("OffPosn"),
            direction: s("Direction"),
            status: s("Status"),
        }
    }

    /// On while the position is in [On, Off) (with rollover, On > Off means outside [Off, On)),
    /// and the source moves in the PLS's direction.
    fn evaluate(&self, position: f64, velocity: f64, v: &mut [f64]) {
        let p = if self.config.rollover > 0.0 {
            position.rem_euclid(self.config.rollover)
        } else {
            position
        };
        let (on, off) = (v[self.on as usize], v[self.off as usize]);
        let inside = if on <= off {
            on <= p && p < off
        } else {
            p >= on || p < off
        };
        let direction = v[self.direction as usize];
        let heading = direction == 0.0
            || (direction > 0.0 && velocity > 0.0)
            || (direction < 0.0 && velocity < 0.0);
        v[self.status as usize] = f64::from(v[self.enable as usize] != 0.0 && inside && heading);
    }
}

/// A home: its set-up and the slots of its settings and status.
#[derive(Debug, Clone)]
struct HomeObject {
    config: HomeConfig,
    velocity: SlotId,
    acceleration: SlotId,
    deceleration: SlotId,
    offset: SlotId,
    in_progress: SlotId,
    at_vel: SlotId,
    complete: SlotId,
}

impl HomeObject {
    fn new(registry: &Registry, i: u32) -> HomeObject {
        let s = |m: &str| slot(registry, Kind::Home, i, m);
        HomeObject {
            config: registry
                .home_setups
                .get(i as usize)
                .copied()
                .unwrap_or_default(),
            velocity: s("Velocity"),
            acceleration: s("Acceleration"),
            deceleration: s("Deceleration"),
            offset: s("Offset"),
            in_progress: s("CommandInProgress"),
            at_vel: s("AtVel"),
            complete: s("CommandComplete"),
        }
    }

    fn status(&self, v: &mut [f64], phase: Phase) {
        let running = phase != Phase::Done;
        v[self.in_progress as usize] = f64::from(running);
        v[self.at_vel as usize] = f64::from(phase == Phase::AtVelocity);
        v[self.complete as usize] = f64::from(!running);
    }
}

/// Slots of the gear's members.
#[derive(Debug, Clone, Copy)]
struct GearSlots {
    ratio: SlotId,
    activate: SlotId,
    in_progress: SlotId,
}

/// Slots of the servo axis's members.
#[derive(Debug, Clone, Copy)]
struct AxisSlots {
    command: SlotId,
    feedback: SlotId,
    velocity: SlotId,
    revs: SlotId,
    counts: SlotId,
    master_counts: SlotId,
}

/// An index: its set-up and the slots of its settings and status.
#[derive(Debug, Clone)]
struct IndexObject {
    config: IndexConfig,
    distance: SlotId,
    velocity: SlotId,
    acceleration: SlotId,
    deceleration: SlotId,
    in_progress: SlotId,
    at_vel: SlotId,
    decelerating: SlotId,
    complete: SlotId,
    registration_offset: SlotId,
    limit_hit: SlotId,
    sensor: SlotId,
    time: SlotId,
    profile_limited: SlotId,
    pls_status: SlotId,
    pls_on: SlotId,
    pls_off: SlotId,
}

impl IndexObject {
    fn new(registry: &Registry, i: u32) -> IndexObject {
        let s = |m: &str| slot(registry, Kind::Index, i, m);
        IndexObject {
            config: registry
                .index_setups
                .get(i as usize)
                .copied()
                .unwrap_or_default(),
            distance: s("Distance"),
            velocity: s("Velocity"),
            acceleration: s("Acceleration"),
            deceleration: s("Deceleration"),
            in_progress: s("CommandInProgress"),
            at_vel: s("AtVel"),
            decelerating: s("Decelerating"),
            complete: s("CommandComplete"),
            registration_offset: s("RegistrationOffset"),
            limit_hit: s("LimitDistHit"),
            sensor: s("SensorTrigger"),
            time: s("Time"),
            profile_limited: s("ProfileLimited"),
            pls_status: s("PLSStatus"),
            pls_on: s("PLSOnPoint"),
            pls_off: s("PLSOffPoint"),
        }
    }

    fn status(&self, v: &mut [f64], phase: Phase) {
        let running = phase != Phase::Done;
        v[self.in_progress as usize] = f64::from(running);
        v[self.at_vel as usize] = f64::from(phase == Phase::AtVelocity);
        v[self.decelerating as usize] = f64::from(phase == Phase::Decelerating);
        v[self.complete as usize] = f64::from(!running);
    }
}

impl Kernel {
    /// Kernel objects for every instance in the registry.
    pub fn new(registry: &Registry) -> Kernel {
        let count = |k: Kind| registry.of(k).count;
        Kernel {
            queues: (0..count(Kind::Queue))
                .map(|i| Queue::new(registry, i))
                .collect(),
            queue_sources: registry.queue_sources.clone(),
            captures: (0..count(Kind::Capture))
                .map(|i| Capture::new(registry, i))
                .collect(),
            timers: (0..count(Kind::Timer))
                .map(|i| Timer::new(registry, i))
                .collect(),
            indexes: (0..count(Kind::Index))
                .map(|i| IndexObject::new(registry, i))
                .collect(),
            axis: Axis::default(),
            profile_busy: (0..count(Kind::Profile))
                .map(|i| slot(registry, Kind::Profile, i, "Busy"))
                .collect(),
            axis_slots: AxisSlots {
                command: slot(registry, Kind::Motion, 0, "PosnCommand"),
                feedback: slot(registry, Kind::Motion, 0, "PosnFeedback"),
                velocity: slot(registry, Kind::Motion, 0, "VelCommand"),
                revs: slot(registry, Kind::Motion, 0, "MotorRevs"),
                counts: slot(registry, Kind::Motion, 0, "MotorCounts"),
                master_counts: slot(registry, Kind::Motion, 0, "MasterCounts"),
            },
            feed_rate: slot(registry, Kind::Motion, 0, "FeedRateOverride"),
            stop_decel: slot(registry, Kind::Motion, 0, "StopDeceleration"),
            gear: GearSlots {
                ratio: slot(registry, Kind::Gear, 0, "Ratio"),
                activate: slot(registry, Kind::Gear, 0, "Activate"),
                in_progress: slot(registry, Kind::Gear, 0, "CommandInProgress"),
            },
            free_run: slot(registry, Kind::Motion, 0, "FreeRunTime"),
            slot_kinds: registry.slots.iter().map(|s| s.kind).collect(),
            events: Vec::new(),
            homes: (0..count(Kind::Home))
                .map(|i| HomeObject::new(registry, i))
                .collect(),
            plss: (0..count(Kind::Pls))
                .map(|i| PlsObject::new(registry, i))
                .collect(),
            armed: vec![false; count(Kind::Index) as usize],
            rollover: registry.axis_rollover,
            units: registry.units.clone(),
            motion_time: 0.0,
            motion_read_at: 0.0,
            edge_start: None,
            jogs: (0..count(Kind::Jog))
                .map(|i| JogObject::new(registry, i))
                .collect(),
            jog_select: slot(
                registry,
                Kind::Jog,
                crate::registry::GLOBAL_INSTANCE,
                "Select",
            ),
            jog_plus: slot(
                registry,
                Kind::Jog,
                crate::registry::GLOBAL_INSTANCE,
                "PlusActivate",
            ),
            jog_minus: slot(
                registry,
                Kind::Jog,
                crate::registry::GLOBAL_INSTANCE,
                "MinusActivate",
            ),
            minus_initiates: (0..count(Kind::Jog))
                .map(|i| slot(registry, Kind::Jog, i, "MinusInitiate"))
                .collect(),
            master_speed: 0.0,
            marks: Vec::new(),
            previous: (0.0, 0.0),
            pending_edges: Vec::new(),
            orion: None,
            pickplace: None,
        }
    }

    /// Sensor marks tied to the axis (from the scenario).
    pub fn set_marks(&mut self, marks: Vec<AxisMarks>) {
        self.marks = marks;
    }

    /// The command position at any instant of the coming update (for captures), as reported
    /// (rolled over).
    pub fn command_at(&self, t: f64, master_at: &dyn Fn(f64) -> f64, v: &[f64]) -> f64 {
        self.wrap(
            self.axis
                .position_at(self.motion_time_of(t, v), master_at(t)),
        )
    }

    /// Motion seconds per real second: the feed-rate override.
    fn rate(&self, v: &[f64]) -> f64 {
        v[self.feed_rate as usize] / 100.0
    }

    /// The motion clock at real time `t` (near the last update), at the present override.
    fn motion_time_of(&self, t: f64, v: &[f64]) -> f64 {
        self.motion_time + (t - self.motion_read_at) * self.rate(v)
    }

    /// A position as the axis reports it: rolled over when the machine sets a rollover.
    fn wrap(&self, p: f64) -> f64 {
        if self.rollover > 0.0 {
            p.rem_euclid(self.rollover)
        } else {
            p
        }
    }

    /// Bring derived members in line with the initial values.
    pub fn start(&self, v: &mut [f64]) {
        for q in &self.queues {
            q.refresh(v);
        }
    }

    /// A program (or an assignment) writes `value` (already rounded to the member's type).
    pub fn write(
        &mut self,
        hook: Hook,
        instance: u32,
        slot: SlotId,
        value: f64,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        let i = instance as usize;
        match hook {
            Hook::QueueDataIn => self.queues[i].data_in(value, v, now.trace, now.tick),
            Hook::QueueOffset | Hook::QueueFullLevel => {
                v[slot as usize] = value;
                self.queues[i].refresh(v);
            }
            Hook::QueueCompareEnable => v[slot as usize] = value,
            Hook::CaptureEnable => self.captures[i].set_enable(value != 0.0, v),
            // Written by a program: the edge is now, at this update's positions.
            Hook::CaptureActivate => self.captures[i].activate(
                value != 0.0,
                now.seconds(),
                Positions {
                    master: now.master,
                    ..Positions::default()
                },
                v,
                now.trace,
                now.tick,
            ),
            Hook::AxisLatch | Hook::AxisSetting => {
                let Some(orion) = self.orion.as_mut() else {
                    return Err("this machine has no DSP axes".into());
                };
                let axes = registry_axis_layout(slot, instance, orion);
                orion.write(hook, axes.0, axes.1, value, v, now)?;
            }
            Hook::FeedRateOverride => {
                if !(0.0..=200.0).contains(&value) {
                    return Err(format!("FeedRateOverride must be 0 to 200 %, not {value}"));
                }
                v[self.feed_rate as usize] = value;
            }
            // Level-sensitive motion: Gear.Activate gears while on; Jog.PlusActivate /
            // MinusActivate jog while on, with Jog.Select's settings.
            Hook::MotionInput
                if slot == self.gear.activate
                    || slot == self.jog_plus
                    || slot == self.jog_minus =>
            {
                let (kind, instance, name) = if slot == self.gear.activate {
                    (Kind::Gear, 0, "Gear.Activate")
                } else {
                    (
                        Kind::Jog,
                        u32::from(v[self.jog_select as usize] != 0.0),
                        "jog",
                    )
                };
                let was = v[slot as usize] != 0.0;
                v[slot as usize] = value;
                if value != 0.0 && !was {
                    let minus = slot == self.jog_minus;
                    if self.start_motion(kind, instance, minus, StartRef::Now, 0, v, now)?
                        == ActOutcome::ProfileBusy
                    {
                        return Err(format!("{name}: a motion is running on profile 0"));
                    }
                } else if value == 0.0 && was {
                    self.stop_motion(kind, instance, v, now);
                }
            }
            // Index.N.SensorTrigger written by a program: the edge is now.
            Hook::MotionInput if self.kind_of(slot) == Kind::Index => {
                self.sensor_edge(instance, value != 0.0, now.seconds(), v, &|_| now.master);
            }
            Hook::OutputWrite | Hook::MotionInput | Hook::Store => v[slot as usize] = value,
            Hook::PickPlace => match self.pickplace.as_mut() {
                Some(pp) => pp.write(slot, value, v),
                None => v[slot as usize] = value,
            },
            Hook::QueueRemove
            | Hook::QueueClear
            | Hook::CaptureClear
            | Hook::TimerInitiate
            | Hook::TimerStop
            | Hook::MotionStart
            | Hook::MotionStop => {
                if value != 0.0 {
                    self.act(hook, slot, instance, StartRef::Now, 0, v, now)?;
                }
            }
            Hook::ProgramInitiate | Hook::ProgramStop | Hook::StopAll => {
                return Err("program control is handled by the task scheduler".into());
            }
        }
        Ok(())
    }

    /// Drive a capture input from an assignment, with the exact edge time and the positions at
    /// that instant.
    pub fn capture_edge(
        &mut self,
        instance: u32,
        on: bool,
        time: f64,
        at: Positions,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) {
        if let Some(c) = self.captures.get(instance as usize) {
            c.activate(on, time, at, v, now.trace, now.tick);
        }
    }

    /// Run an action. `start` and `profile` matter to motion initiates only.
    #[allow(clippy::too_many_arguments)]
    pub fn act(
        &mut self,
        hook: Hook,
        slot: SlotId,
        instance: u32,
        start: StartRef,
        profile: u8,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<ActOutcome, String> {
        let i = instance as usize;
        match hook {
            Hook::QueueRemove => self.queues[i].remove(v),
            Hook::QueueClear => self.queues[i].clear(v),
            Hook::CaptureClear => self.captures[i].clear(v),
            Hook::TimerInitiate => self.timers[i].initiate(now.time_ns, now.master, v),
            Hook::TimerStop => self.timers[i].stop(v),
            Hook::MotionStop => self.stop_motion(self.kind_of(slot), instance, v, now),
            Hook::MotionStart => {
                let minus = self.minus_initiates.contains(&slot);
                return self.start_motion(
                    self.kind_of(slot),
                    instance,
                    minus,
                    start,
                    profile,
                    v,
                    now,
                );
            }
            other => return Err(format!("{other:?} is not an action")),
        }
        Ok(ActOutcome::Done)
    }

    fn kind_of(&self, slot: SlotId) -> Kind {
        self.slot_kinds
            .get(slot as usize)
            .copied()
            .unwrap_or(Kind::Motion)
    }

    /// Where a motion in `domain` starts: now, at the end of the last motion on its profile,
    /// or from a capture's latched time or master position.
    fn start_point(
        &self,
        domain: Domain,
        start: StartRef,
        profile: usize,
        v: &[f64],
        now: &Now<'_>,
    ) -> Result<f64, String> {
        // An initiate from a capture-capable input starts at the input's edge.
        let (time_now, master_now) = self.edge_start.unwrap_or((now.seconds(), now.master));
        let clock = match domain {
            Domain::Time => self.motion_time_of(time_now, v),
            Domain::Master => master_now,
        };
        let p = &self.axis.profiles[profile];
        let last = || p.last_end.filter(|(d, _)| *d == domain).map(|(_, at)| at);
        Ok(match start {
            StartRef::Now if p.chained => last().unwrap_or(clock),
            StartRef::Now => clock,
            StartRef::Last => last().unwrap_or(clock),
            StartRef::Capture(c) => {
                let capture = self
                    .captures
                    .get(usize::from(c))
                    .ok_or_else(|| format!("no Capture.{c}"))?;
                let (time, master) = capture.latched(v);
                match domain {
                    Domain::Time => self.motion_time_of(time, v),
                    Domain::Master => master,
                }
            }
        })
    }

    /// Start a motion object on a profile, or report that the profile is busy.
    #[allow(clippy::too_many_arguments)]
    fn start_motion(
        &mut self,
        kind: Kind,
        instance: u32,
        minus: bool,
        start: StartRef,
        profile: u8,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<ActOutcome, String> {
        let p = usize::from(profile);
        if p >= self.axis.profiles.len() {
            return Err(format!("there is no Profile.{profile}"));
        }
        if !matches!(kind, Kind::Index | Kind::Home | Kind::Gear | Kind::Jog) {
            return Err(format!(
                "{kind:?} motion is not simulated yet in this build of pacer"
            ));
        }
        if self.axis.profiles[p].busy() {
            self.axis.profiles[p].chained = true;
            return Ok(ActOutcome::ProfileBusy);
        }
        if kind == Kind::Home {
            return self.start_home(instance, start, p, v, now);
        }
        if kind == Kind::Gear {
            return self.start_gear(start, p, v, now);
        }
        if kind == Kind::Jog {
            return self.start_jog(instance, minus, start, p, v, now);
        }
        let ix = self
            .indexes
            .get(instance as usize)
            .ok_or_else(|| format!("no Index.{instance}"))?
            .clone();
        let target = v[ix.distance as usize];
        let r = self.rollover;
        let here = self.axis.command();
        let distance = match ix.config.kind {
            IndexType::Incremental | IndexType::Registration => target,
            IndexType::Absolute => target - here,
            // On a rolled-over axis, to the target position the short or long way round.
            IndexType::RotaryPlus => (target - here.rem_euclid(r)).rem_euclid(r),
            IndexType::RotaryMinus => -(here.rem_euclid(r) - target).rem_euclid(r),
        };
        // A registration index waits for its sensor until it reaches its limit distance.
        self.armed[instance as usize] = ix.config.kind == IndexType::Registration;
        v[ix.limit_hit as usize] = 0.0;
        let (velocity, accel, decel) = (
            v[ix.velocity as usize],
            v[ix.acceleration as usize],
            v[ix.deceleration as usize],
        );
        let (plan, limited) = if ix.config.timed {
            Trapezoid::timed(distance, v[ix.time as usize], velocity, accel, decel)
        } else {
            Trapezoid::new(distance, velocity, accel, decel).map(|t| (t, false))
        }
        .map_err(|e| format!("cannot plan the index: {e}"))?;
        v[ix.profile_limited as usize] = f64::from(limited);
        let domain = if ix.config.synchronized {
            Domain::Master
        } else {
            Domain::Time
        };
        let owner = Owner {
            name: format!("Index.{instance}"),
            status: Some((Kind::Index, instance as usize)),
        };
        let started = self.launch(p, owner, Plan::Move(plan), domain, start, v, now)?;
        ix.status(v, Phase::Accelerating);
        v[ix.at_vel as usize] = 0.0;
        Ok(started)
    }

    /// Jog `instance` plus or minus at its velocity until stopped.
    fn start_jog(
        &mut self,
        instance: u32,
        minus: bool,
        start: StartRef,
        p: usize,
        v: &mut [f64],
        now: &Now<'_>,
    ) -> Result<ActOutcome, String> {
        let j = self
            .jogs
            .get(instance as usize)
            .ok_or_else(|| format!("no Jog.{instance}"))?
            .clone();
        let (velocity, accel) = (v[j.velocity as usize], v[j.acceleration as usize]);
        if !(velocity.is_finite() && velocity > 0.0 && accel.is_finite() && accel > 0.0) {
            return Err(format!(
                "Jog.{instance} needs a velocity and an acceleration above 0"
            ));
        }
        let velocity = if minus { -velocity } else { velocity };
        let owner = Owner {
            name: format!("Jog.{instance}"),
            status: Some((Kind::Jog, instance as usize)),
        };
        let started = self.launch(
            p,
            owner,
            Plan::Seek { velocity, accel },
            Domain::Time,
            start,
            v,
            now,
        )?;
        v[j.in_progress as usize] = 1.0;
        Ok(started)
    }

    /// Run a motion initiate from a capture-capable input whose edge came at `time`, with the
    /// master at `master` then: the motion starts there, as with `Using Capture`.
    #[allow(clippy::too_many_arguments)]
    pub fn initiate_from_edge(
        &mut self,
        hook: Hook,
        slot: SlotId,
        instance: u32,
        time: f64,
        master: f64,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<ActOutcome, String> {
        self.edge_start = Some((time, master));
        let r = self.act(hook, slot, instance, StartRef::Now, 0, v, now);
        self.edge_start = None;
        r
    }

    /// `Index.N.SensorTrigger` driven to `on` at `time` seconds. The rising edge of the sensor of
    /// a running registration index ends the move `RegistrationOffset` past the position the
    /// axis had at that instant (further when it cannot stop that soon).
    pub fn sensor_edge(
        &mut self,
        instance: u32,
        on: bool,
        time: f64,
        v: &mut [f64],
        master_at: &dyn Fn(f64) -> f64,
    ) {
        let i = instance as usize;
        let Some(ix) = self.indexes.get(i).cloned() else {
            return;
        };
        let rising = on && v[ix.sensor as usize] == 0.0;
        v[ix.sensor as usize] = f64::from(on);
        if !rising || !self.armed.get(i).copied().unwrap_or(false) {
            return;
        }
        let name = format!("Index.{instance}");
        let Some(p) = self
            .axis
            .profiles
            .iter()
            .position(|p| p.motion.as_ref().is_some_and(|m| m.owner.name == name))
        else {
            return;
        };
        let Some(m) = self.axis.profiles[p].motion.clone() else {
            return;
        };
        let clock = match m.domain {
            Domain::Time => self.motion_time_of(time, v),
            Domain::Master => master_at(time),
        };
        if !(m.started || clock >= m.start) {
            return;
        }
        let (dp, dv, phase) = m.plan.at(clock - m.start);
        if phase == Phase::Done || dv == 0.0 {
            return;
        }
        let decel = v[ix.deceleration as usize];
        let stopping = dv * dv / (2.0 * decel);
        // The offset is a distance past the sensor in the direction of travel; an offset shorter
        // than the stopping distance stops as soon as it can.
        let offset = v[ix.registration_offset as usize].max(stopping);
        let distance = dv.signum() * offset;
        self.armed[i] = false;
        self.axis.replace(
            p,
            Plan::Finish {
                v0: dv,
                decel,
                distance,
            },
            clock,
            m.base + dp,
        );
    }

    /// Put a motion on free profile `p`, starting per `start` on its domain's timeline.
    #[allow(clippy::too_many_arguments)]
    fn launch(
        &mut self,
        p: usize,
        owner: Owner,
        plan: Plan,
        domain: Domain,
        start: StartRef,
        v: &mut [f64],
        now: &Now<'_>,
    ) -> Result<ActOutcome, String> {
        let at = self.start_point(domain, start, p, v, now)?;
        let base = self.axis.profiles[p].position;
        self.axis.begin(
            p,
            Motion {
                owner,
                plan,
                domain,
                start: at,
                base,
                started: false,
            },
        );
        v[self.profile_busy[p] as usize] = 1.0;
        Ok(ActOutcome::Done)
    }

    /// Start gearing at the ratio of `Gear.Ratio` (read now; a later change needs a new initiate).
    fn start_gear(
        &mut self,
        start: StartRef,
        p: usize,
        v: &mut [f64],
        now: &Now<'_>,
    ) -> Result<ActOutcome, String> {
        let ratio = v[self.gear.ratio as usize];
        if !ratio.is_finite() {
            return Err(format!("Gear.Ratio must be a number, not {ratio}"));
        }
        let owner = Owner {
            name: "Gear".into(),
            status: Some((Kind::Gear, 0)),
        };
        let started = self.launch(
            p,
            owner,
            Plan::Gear { ratio },
            Domain::Master,
            start,
            v,
            now,
        )?;
        v[self.gear.in_progress as usize] = 1.0;
        Ok(started)
    }

    /// Start homing: seek the reference at home velocity.
    fn start_home(
        &mut self,
        instance: u32,
        start: StartRef,
        p: usize,
        v: &mut [f64],
        now: &Now<'_>,
    ) -> Result<ActOutcome, String> {
        let h = self
            .homes
            .get(instance as usize)
            .ok_or_else(|| format!("no Home.{instance}"))?
            .clone();
        if h.config.reference.is_none() {
            return Err(format!("Home.{instance} has no reference input: set [home.{instance}] reference in machine.toml"));
        }
        let velocity = v[h.velocity as usize];
        let accel = v[h.acceleration as usize];
        if !(velocity.is_finite()
            && velocity != 0.0
            && accel.is_finite()
            && accel > 0.0
            && v[h.deceleration as usize] > 0.0)
        {
            return Err(format!("Home.{instance} needs a velocity other than 0 and an acceleration and deceleration above 0"));
        }
        let owner = Owner {
            name: format!("Home.{instance}"),
            status: Some((Kind::Home, instance as usize)),
        };
        let started = self.launch(
            p,
            owner,
            Plan::Seek { velocity, accel },
            Domain::Time,
            start,
            v,
            now,
        )?;
        h.status(v, Phase::Accelerating);
        Ok(started)
    }

    /// A seeking home whose reference rose at `t` with the axis at `position`: finish the move
    /// at the calculated or specified offset.
    fn home_reference(
        &mut self,
        home: usize,
        t: f64,
        position: f64,
        v: &[f64],
    ) -> Option<(usize, Option<String>)> {
        let h = &self.homes[home];
        let name = format!("Home.{home}");
        let (p, velocity, accel, start) =
            self.axis
                .profiles
                .iter()
                .enumerate()
                .find_map(|(i, p)| match &p.motion {
                    Some(m) if m.owner.name == name => match m.plan {
                        Plan::Seek { velocity, accel } => Some((i, velocity, accel, m.start)),
                        _ => None,
                    },
                    _ => None,
                })?;
        let decel = v[h.deceleration as usize];
        // Speed at the reference (the seek may still be accelerating).
        let v0 = velocity.signum() * (accel * (t - start)).min(velocity.abs());
        let stopping = v0 * v0 / (2.0 * decel);
        let mut warning = None;
        let distance = if h.config.specified_offset {
            let offset = v[h.offset as usize];
            if offset * velocity.signum() < stopping - 1e-12 {
                warning = Some(format!(
                    "{name}: the specified offset {offset} is shorter than the distance needed to stop ({stopping}); stopping at the calculated offset"
                ));
                velocity.signum() * stopping
            } else {
                offset
            }
        } else {
            velocity.signum() * stopping
        };
        let other: f64 = self
            .axis
            .profiles
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != p)
            .map(|(_, q)| q.position)
            .sum();
        self.axis.replace(
            p,
            Plan::Finish {
                v0,
                decel,
                distance,
            },
            t,
            position - other,
        );
        Some((p, warning))
    }

    /// Stop an index wherever it is (the motion ends where it stands).
    fn stop_motion(&mut self, kind: Kind, instance: u32, v: &mut [f64], now: &Now<'_>) {
        let name = if kind == Kind::Gear {
            "Gear".to_string()
        } else {
            format!("{kind:?}.{instance}")
        };
        let decel = match kind {
            Kind::Index => self
                .indexes
                .get(instance as usize)
                .map_or(0.0, |ix| v[ix.deceleration as usize]),
            Kind::Home => self
                .homes
                .get(instance as usize)
                .map_or(0.0, |h| v[h.deceleration as usize]),
            Kind::Jog => self
                .jogs
                .get(instance as usize)
                .map_or(0.0, |j| v[j.deceleration as usize]),
            _ => 0.0,
        };
        for i in 0..self.axis.profiles.len() {
            if self.axis.profiles[i]
                .motion
                .as_ref()
                .is_some_and(|m| m.owner.name == name)
            {
                self.stop_profile(i, decel, v, now);
            }
        }
    }

    /// `Stop`: every motion comes to rest at StopDeceleration (at once when it is 0).
    pub fn stop_all(&mut self, v: &mut [f64], now: &Now<'_>) {
        let decel = v[self.stop_decel as usize];
        for i in 0..self.axis.profiles.len() {
            self.stop_profile(i, decel, v, now);
        }
    }

    fn stop_profile(&mut self, profile: usize, decel: f64, v: &mut [f64], now: &Now<'_>) {
        if let Some(owner) = self.axis.decelerate(
            profile,
            self.motion_time_of(now.seconds(), v),
            now.master,
            decel,
        ) {
            self.owner_status(&owner, v, Phase::Done);
            v[self.profile_busy[profile] as usize] = 0.0;
        }
    }

    /// `Dwell For Time` / `Dwell For Master Dist`: a motion on profile 0 lasting `length`
    /// seconds or master units.
    pub fn dwell(
        &mut self,
        length: f64,
        domain: Domain,
        v: &mut [f64],
        now: &Now<'_>,
    ) -> Result<ActOutcome, String> {
        if !(length.is_finite() && length >= 0.0) {
            return Err(match domain {
                Domain::Time => format!("Dwell For Time needs 0 seconds or more, not {length}"),
                Domain::Master => {
                    format!("Dwell For Master Dist needs a distance of 0 or more, not {length}")
                }
            });
        }
        if self.axis.profiles[0].busy() {
            self.axis.profiles[0].chained = true;
            return Ok(ActOutcome::ProfileBusy);
        }
        let owner = Owner {
            name: "Dwell".into(),
            status: None,
        };
        self.launch(0, owner, Plan::Dwell(length), domain, StartRef::Now, v, now)
    }

    /// The motion generator, in the control loop before the task runs: every motion advanced
    /// to this update, status members and axis positions set, `motion` events traced.
    pub fn generate(
        &mut self,
        v: &mut [f64],
        now: &mut Now<'_>,
        master_speed: f64,
        master_at: &dyn Fn(f64) -> f64,
    ) {
        self.master_speed = master_speed;
        let t = now.seconds();
        self.motion_time = self.motion_time_of(t, v);
        self.motion_read_at = t;
        let clocks = Clocks {
            time: t,
            motion_time: self.motion_time,
            rate: self.rate(v),
            master: now.master,
            master_speed,
        };
        let mut events = std::mem::take(&mut self.events);
        events.clear();
        self.axis.update(clocks, master_at, &mut events);
        // Sensors on the axis: edges where it crossed marks since the last update.
        let (t_prev, cmd_prev) = self.previous;
        let mut crossings = Vec::new();
        for m in &self.marks {
            m.crossings(
                cmd_prev,
                self.axis.command(),
                t_prev,
                clocks.time,
                &mut crossings,
            );
        }
        crossings.sort_by(|a, b| a.0.at.total_cmp(&b.0.at));
        for (e, position) in &crossings {
            for h in 0..self.homes.len() {
                if !(e.on && self.homes[h].config.reference == Some(e.slot)) {
                    continue;
                }
                let at = self.motion_time_of(e.at, v);
                if let Some((p, warning)) = self.home_reference(h, at, *position, v) {
                    if let Some(message) = warning {
                        now.trace.machine_warning(now.tick, message);
                    }
                    // The profile's new plan at this update; its status events come after the
                    // stale ones, so they win.
                    self.axis.update_profile(p, clocks, master_at, &mut events);
                }
            }
        }
        self.pending_edges
            .extend(crossings.into_iter().map(|(e, _)| e));
        self.previous = (clocks.time, self.axis.command());
        for e in &events {
            match e {
                Event::Started {
                    owner,
                    master,
                    position,
                } => {
                    now.trace.emit(
                        now.tick,
                        &trace::Event::Motion {
                            object: owner.name.as_str().into(),
                            phase: MotionPhase::Start {
                                master: *master,
                                position: *position,
                            },
                        },
                    );
                }
                Event::Running { owner, phase } => self.owner_status(owner, v, *phase),
                Event::Done {
                    owner,
                    end,
                    position,
                } => {
                    self.owner_status(owner, v, Phase::Done);
                    now.trace.emit(
                        now.tick,
                        &trace::Event::Motion {
                            object: owner.name.as_str().into(),
                            phase: MotionPhase::Done {
                                end: *end,
                                master: now.master,
                                position: *position,
                            },
                        },
                    );
                }
            }
        }
        self.events = events;
        for (i, p) in self.axis.profiles.iter().enumerate() {
            v[self.profile_busy[i] as usize] = f64::from(p.busy());
        }
        // Index PLS: on while the distance the index has travelled is in [PLSOnPoint, PLSOffPoint).
        for p in &self.axis.profiles {
            let Some(m) = &p.motion else { continue };
            if let Some((Kind::Index, i)) = m.owner.status {
                if let Some(ix) = self.indexes.get(i) {
                    let travelled = (p.position - m.base).abs();
                    let on = m.started
                        && v[ix.pls_on as usize] <= travelled
                        && travelled < v[ix.pls_off as usize];
                    v[ix.pls_status as usize] = f64::from(on);
                }
            }
        }
        let reported = self.wrap(self.axis.command());
        v[self.axis_slots.command as usize] = reported;
        v[self.axis_slots.feedback as usize] = reported;
        // In motor revolutions and encoder counts (the encoders count whole counts).
        let revs = self.axis.command() / self.units.motor_per_rev;
        v[self.axis_slots.revs as usize] = revs;
        v[self.axis_slots.counts as usize] = (revs * self.units.motor_counts_per_rev).floor();
        v[self.axis_slots.master_counts as usize] =
            (now.master * self.units.master_counts_per_unit).floor();
        v[self.axis_slots.velocity as usize] = self.axis.velocity();
    }

    fn owner_status(&mut self, owner: &Owner, v: &mut [f64], phase: Phase) {
        match owner.status {
            Some((Kind::Index, i)) => {
                if let Some(ix) = self.indexes.get(i) {
                    ix.status(v, phase);
                    if phase == Phase::Done {
                        v[ix.pls_status as usize] = 0.0;
                    }
                    // A registration index that reached its limit without seeing its sensor.
                    if phase == Phase::Done && self.armed.get(i).copied().unwrap_or(false) {
                        v[ix.limit_hit as usize] = 1.0;
                        self.armed[i] = false;
                    }
                }
            }
            Some((Kind::Home, i)) => {
                if let Some(h) = self.homes.get(i) {
                    h.status(v, phase);
                }
            }
            Some((Kind::Gear, _)) => {
                v[self.gear.in_progress as usize] = f64::from(phase != Phase::Done)
            }
            Some((Kind::Jog, i)) => {
                if let Some(j) = self.jogs.get(i) {
                    v[j.in_progress as usize] = f64::from(phase != Phase::Done);
                }
            }
            _ => {}
        }
    }

    /// True while a motion runs (or waits to start) on `profile`.
    pub fn profile_busy(&self, profile: usize) -> bool {
        self.axis
            .profiles
            .get(profile)
            .is_some_and(motion::Profile::busy)
    }

    /// Status derived after the motion: queue compares and PLS windows on their sources.
    pub fn derive(&mut self, v: &mut [f64], now: &mut Now<'_>) {
        let command = self.axis.command();
        let velocity = self.axis.velocity();
        for pls in &self.plss {
            let (p, vel) = match pls.config.source {
                QueueSource::Master => (now.master, self.master_speed),
                QueueSource::Feedback | QueueSource::Command => (command, velocity),
            };
            pls.evaluate(p, vel, v);
        }
        for (q, source) in self.queues.iter_mut().zip(&self.queue_sources) {
            let position = match source {
                QueueSource::Master => now.master,
                QueueSource::Feedback | QueueSource::Command => command,
            };
            q.compare(position, v, now.trace, now.tick);
        }
    }

    /// Per-update work before the tasks run: timers and the free-running clock.
    pub fn update(&mut self, v: &mut [f64], now: &Now<'_>) {
        v[self.free_run as usize] = (now.time_ns / 1000) as f64;
        for t in &mut self.timers {
            t.update(now.time_ns, now.master, v);
        }
    }
}
