//! The PowerTools drive (the PTi-210 / EZMotion family): one servo axis with two motion
//! profiles whose positions add up, and the drive's objects — indexes, homes, jogs, the gear,
//! dwells, queues, captures, timers, programmable limit switches — behind the [`Device`]
//! interface. `motion/` is the pure model (plans on their timelines); this file binds it to the
//! members, `start.rs` starts and stops motions, `objects.rs` holds the objects' slots.

pub mod capture;
mod marks;
pub mod motion;
mod objects;
pub mod queue;
mod servo;
pub mod setup;
mod start;
pub mod timer;

pub use marks::AxisMarks;

use super::command::{Domain, StartRef};
use super::{ActOutcome, Device, Now, Profiles, Target, When};
use crate::registry::{Hook, Kind, Registry, SlotId, GLOBAL_INSTANCE};
use crate::trace::{self, MotionPhase};
use crate::world::Edge;
use capture::{Capture, Positions};
use motion::trapezoid::Phase;
use motion::{Axis, Clocks, Event, Owner};
use objects::{
    AxisSlots, GearSlots, HomeObject, IndexObject, JogGlobals, JogSlots, PlsObject, ProfileSlots,
};
use queue::Queue;
use setup::{DriveSetup, QueueSource, Units};
use timer::Timer;

/// The drive's objects, each with its set-up and slots.
#[derive(Debug, Clone)]
struct Objects {
    queues: Vec<Queue>,
    queue_sources: Vec<QueueSource>,
    captures: Vec<Capture>,
    timers: Vec<Timer>,
    indexes: Vec<IndexObject>,
    homes: Vec<HomeObject>,
    jogs: Vec<JogSlots>,
    plss: Vec<PlsObject>,
    /// A timer may be running: set when one is initiated, cleared by the update that finds
    /// none running (most updates of most machines run no timer).
    timers_running: bool,
}

/// The slots of the drive-wide members.
#[derive(Debug, Clone)]
struct DriveSlots {
    axis: AxisSlots,
    gear: GearSlots,
    jog: JogGlobals,
    /// `Index.ProfileLimited`.
    index_limited: SlotId,
    profiles: Vec<ProfileSlots>,
    /// The kind of every slot (a motion action names its object by its slot).
    kinds: Vec<Kind>,
}

/// The motion clock realtime motions run on (the feed-rate override scales it).
#[derive(Debug, Clone, Copy, Default)]
struct MotionClock {
    /// Its reading at the last update…
    time: f64,
    /// … which was at this real time, seconds.
    read_at: f64,
}

/// Sensors on the axis and the edges they made.
#[derive(Debug, Clone, Default)]
struct Sensors {
    marks: Vec<AxisMarks>,
    /// Time and command position at the previous update, for crossings inside an update.
    previous: (f64, f64),
    /// Edges made by the axis crossing marks, for the world to apply next update.
    pending: Vec<Edge>,
}

/// The PowerTools drive.
#[derive(Debug, Clone)]
pub struct Drive {
    objects: Objects,
    slots: DriveSlots,
    axis: Axis,
    clock: MotionClock,
    sensors: Sensors,
    /// Motion events of the update being computed (kept to spare an allocation per update).
    events: Vec<Event>,
    /// Registration indexes still waiting for their sensor.
    armed: Vec<bool>,
    /// Rollover of the axis's reported positions (0: none).
    rollover: f64,
    /// User units.
    units: Units,
    /// The edge (time, master position) an initiate from an input starts at, while it runs.
    edge_start: Option<(f64, f64)>,
    /// The servo loop behind the axis (`None`: ideal, feedback equals command).
    servo: Option<servo::ServoLoop>,
}

impl Drive {
    /// The drive of a machine: every object instance in the registry, set up as `setup` says,
    /// with the scenario's sensors on the axis.
    pub fn new(registry: &Registry, setup: &DriveSetup, marks: Vec<AxisMarks>) -> Drive {
        let count = |k: Kind| registry.of(k).count;
        Drive {
            objects: Objects {
                queues: (0..count(Kind::Queue))
                    .map(|i| {
                        let size = setup.queues.get(i as usize).map_or(8, |q| q.size);
                        Queue::new(registry, i, size as usize)
                    })
                    .collect(),
                queue_sources: (0..count(Kind::Queue) as usize)
                    .map(|i| {
                        setup
                            .queues
                            .get(i)
                            .map_or(QueueSource::Master, |q| q.source)
                    })
                    .collect(),
                captures: (0..count(Kind::Capture))
                    .map(|i| Capture::new(registry, i))
                    .collect(),
                timers: (0..count(Kind::Timer))
                    .map(|i| Timer::new(registry, i))
                    .collect(),
                timers_running: false,
                indexes: (0..count(Kind::Index))
                    .map(|i| {
                        let config = setup.indexes.get(i as usize).copied().unwrap_or_default();
                        IndexObject::new(registry, i, config)
                    })
                    .collect(),
                homes: (0..count(Kind::Home))
                    .map(|i| {
                        let config = setup.homes.get(i as usize).copied().unwrap_or_default();
                        HomeObject::new(registry, i, config)
                    })
                    .collect(),
                jogs: (0..count(Kind::Jog))
                    .map(|i| JogSlots::of(registry, i))
                    .collect(),
                plss: (0..count(Kind::Pls))
                    .map(|i| {
                        let config = setup.plss.get(i as usize).copied().unwrap_or_default();
                        PlsObject::new(registry, i, config)
                    })
                    .collect(),
            },
            slots: DriveSlots {
                axis: AxisSlots::of(registry, 0),
                gear: GearSlots::of(registry, 0),
                jog: JogGlobals::of(registry),
                index_limited: objects::index_limited(registry),
                profiles: (0..count(Kind::Profile))
                    .map(|i| ProfileSlots::of(registry, i))
                    .collect(),
                kinds: registry.slots.iter().map(|s| s.kind).collect(),
            },
            axis: Axis::default(),
            clock: MotionClock::default(),
            sensors: Sensors {
                marks,
                ..Sensors::default()
            },
            events: Vec::new(),
            armed: vec![false; count(Kind::Index) as usize],
            rollover: setup.rollover,
            units: setup.units.clone(),
            edge_start: None,
            servo: setup.servo.map(servo::ServoLoop::new),
        }
    }

    /// The command position at any instant of the coming update (for captures), as reported
    /// (rolled over).
    pub fn command_at(&self, t: f64, v: &[f64], now: &Now<'_>) -> f64 {
        self.wrap(
            self.axis
                .position_at(self.motion_time_of(t, v), now.master_at(t)),
        )
    }

    /// Motion seconds per real second: the feed-rate override, unless FeedRateDeactivate is on
    /// (SM-EZMotion User Guide p. 106: motion then runs at its programmed velocity).
    fn rate(&self, v: &[f64]) -> f64 {
        if v[self.slots.axis.feed_rate_off as usize] != 0.0 {
            1.0
        } else {
            v[self.slots.axis.feed_rate as usize] / 100.0
        }
    }

    /// The motion clock at real time `t` (near the last update), at the present override.
    fn motion_time_of(&self, t: f64, v: &[f64]) -> f64 {
        self.clock.time + (t - self.clock.read_at) * self.rate(v)
    }

    /// A position as the axis reports it: rolled over when the machine sets a rollover.
    fn wrap(&self, p: f64) -> f64 {
        if self.rollover > 0.0 {
            p.rem_euclid(self.rollover)
        } else {
            p
        }
    }

    /// The motion object an action's target names, if it is one.
    fn owner_of(&self, target: Target) -> Option<Owner> {
        match self.kind_of(target.slot) {
            Kind::Index => Some(Owner::Index(target.instance)),
            Kind::Home => Some(Owner::Home(target.instance)),
            Kind::Jog => Some(Owner::Jog(target.instance)),
            Kind::Gear => Some(Owner::Gear),
            _ => None,
        }
    }

    fn kind_of(&self, slot: SlotId) -> Kind {
        self.slots
            .kinds
            .get(slot as usize)
            .copied()
            .unwrap_or(Kind::Motion)
    }

    /// The motion generator, in the control loop before the task runs: every motion advanced
    /// to this update, status members and axis positions set, `motion` events traced.
    fn generate(&mut self, v: &mut [f64], now: &mut Now<'_>) {
        let t = now.seconds();
        self.clock.time = self.motion_time_of(t, v);
        self.clock.read_at = t;
        let clocks = Clocks {
            time: t,
            motion_time: self.clock.time,
            rate: self.rate(v),
            master: now.master,
            master_speed: now.master_speed(),
        };
        let mut events = std::mem::take(&mut self.events);
        events.clear();
        let profile = now.master_profile;
        let master_at = |at: f64| profile.position(at);
        self.axis.update(clocks, &master_at, &mut events);
        // Sensors on the axis: edges where it crossed marks since the last update.
        let (t_prev, cmd_prev) = self.sensors.previous;
        let mut crossings = Vec::new();
        // An axis standing still crosses no mark: nothing to look for, sort or walk.
        if cmd_prev != self.axis.command() {
            for m in &self.sensors.marks {
                m.crossings(
                    cmd_prev,
                    self.axis.command(),
                    t_prev,
                    clocks.time,
                    &mut crossings,
                );
            }
        }
        crossings.sort_by(|a, b| a.0.at.total_cmp(&b.0.at));
        for (e, position) in &crossings {
            for h in 0..self.objects.homes.len() {
                if !(e.on && self.objects.homes[h].config.reference == Some(e.slot)) {
                    continue;
                }
                let at = self.motion_time_of(e.at, v);
                if let Some((p, warning)) = self.home_reference(h, at, *position, v) {
                    if let Some(message) = warning {
                        now.trace.machine_warning(now.tick, message);
                    }
                    // The profile's new plan at this update; its status events come after the
                    // stale ones, so they win.
                    self.axis.update_profile(p, clocks, &master_at, &mut events);
                }
            }
        }
        self.sensors
            .pending
            .extend(crossings.into_iter().map(|(e, _)| e));
        self.sensors.previous = (clocks.time, self.axis.command());
        let (feedback, feedback_velocity) = self.step_servo(now);
        for e in &events {
            match *e {
                Event::Started {
                    owner,
                    master,
                    position,
                } => {
                    now.trace.emit(
                        now.tick,
                        &trace::Event::Motion {
                            object: owner.to_string().into(),
                            phase: MotionPhase::Start { master, position },
                        },
                    );
                }
                Event::Running { owner, phase } => self.owner_status(owner, v, phase),
                Event::Done {
                    owner,
                    end,
                    position,
                } => {
                    self.owner_status(owner, v, Phase::Done);
                    now.trace.emit(
                        now.tick,
                        &trace::Event::Motion {
                            object: owner.to_string().into(),
                            phase: MotionPhase::Done {
                                end,
                                master: now.master,
                                position,
                                feedback: self.event_feedback(feedback),
                            },
                        },
                    );
                }
            }
        }
        self.events = events;
        for (i, p) in self.axis.profiles.iter().enumerate() {
            v[self.slots.profiles[i].busy as usize] = f64::from(p.busy());
        }
        // Index PLS: on while the distance the index has travelled is in [PLSOnPoint, PLSOffPoint).
        for p in &self.axis.profiles {
            let Some(m) = &p.motion else { continue };
            if let Owner::Index(i) = m.owner {
                if let Some(ix) = self.objects.indexes.get(i as usize) {
                    let travelled = (p.position - m.base).abs();
                    let on = m.started
                        && v[ix.s.pls_on as usize] <= travelled
                        && travelled < v[ix.s.pls_off as usize];
                    v[ix.s.pls_status as usize] = f64::from(on);
                }
            }
        }
        self.check_following_error(feedback, v, now);
        let a = self.slots.axis;
        let command = self.axis.command();
        v[a.command as usize] = self.wrap(command);
        v[a.feedback as usize] = self.wrap(feedback);
        v[a.vel_feedback as usize] = feedback_velocity;
        v[a.following_error as usize] = command - feedback;
        // In motor revolutions and encoder counts (the encoders count whole counts).
        let revs = feedback / self.units.motor_per_rev;
        v[a.revs as usize] = revs;
        v[a.counts as usize] = (revs * self.units.motor_counts_per_rev).floor();
        v[a.master_counts as usize] = (now.master * self.units.master_counts_per_unit).floor();
        v[a.velocity as usize] = self.axis.velocity();
    }

    /// `Index.ProfileLimited` (no instance): on while any index's ProfileLimited is on.
    fn profile_limited_any(&self, v: &mut [f64]) {
        let any = self
            .objects
            .indexes
            .iter()
            .any(|ix| v[ix.s.profile_limited as usize] != 0.0);
        v[self.slots.index_limited as usize] = f64::from(any);
    }

    /// The status members of the object `owner` names, in `phase`.
    fn owner_status(&mut self, owner: Owner, v: &mut [f64], phase: Phase) {
        match owner {
            Owner::Index(i) => {
                let i = i as usize;
                if let Some(ix) = self.objects.indexes.get(i) {
                    ix.status(v, phase);
                    if phase == Phase::Done {
                        v[ix.s.pls_status as usize] = 0.0;
                    }
                    // A registration index that reached its limit without seeing its sensor.
                    if phase == Phase::Done && self.armed.get(i).copied().unwrap_or(false) {
                        v[ix.s.limit_hit as usize] = 1.0;
                        self.armed[i] = false;
                    }
                }
            }
            Owner::Home(i) => {
                if let Some(h) = self.objects.homes.get(i as usize) {
                    h.status(v, phase);
                }
            }
            Owner::Gear => {
                v[self.slots.gear.in_progress as usize] = f64::from(phase != Phase::Done)
            }
            Owner::Jog(i) => {
                if let Some(j) = self.objects.jogs.get(i as usize) {
                    v[j.in_progress as usize] = f64::from(phase != Phase::Done);
                }
            }
            Owner::Dwell => {}
        }
    }

    /// A level input of a motion object written: `Gear.Activate` gears while on;
    /// `Jog.PlusActivate` / `MinusActivate` jog while on, with `Jog.Select`'s settings;
    /// `Index.N.SensorTrigger` is the sensor of a registration index.
    fn motion_input(
        &mut self,
        target: Target,
        value: f64,
        when: When,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        let slot = target.slot;
        let g = self.slots.jog;
        if slot == self.slots.gear.activate || slot == g.plus || slot == g.minus {
            let (owner, name) = if slot == self.slots.gear.activate {
                (Owner::Gear, "Gear.Activate")
            } else {
                (Owner::Jog(u32::from(v[g.select as usize] != 0.0)), "jog")
            };
            let was = v[slot as usize] != 0.0;
            v[slot as usize] = value;
            if value != 0.0 && !was {
                let minus = slot == g.minus;
                if self.start_motion(owner, minus, false, StartRef::Now, 0, v, now)?
                    == ActOutcome::ProfileBusy
                {
                    return Err(format!("{name}: a motion is running on profile 0"));
                }
            } else if value == 0.0 && was {
                self.stop_motion(owner, v, now);
            }
            return Ok(());
        }
        if self.kind_of(slot) == Kind::Index {
            let time = match when {
                When::Now => now.seconds(),
                When::Edge(t) => t,
            };
            self.sensor_edge(target.instance, value != 0.0, time, v, now);
            return Ok(());
        }
        v[slot as usize] = value;
        Ok(())
    }
}

impl Device for Drive {
    fn name(&self) -> &'static str {
        "the drive"
    }

    fn serves(&self, hook: Hook) -> bool {
        matches!(
            hook,
            Hook::TimerInitiate
                | Hook::TimerStop
                | Hook::QueueDataIn
                | Hook::QueueOffset
                | Hook::QueueCompareEnable
                | Hook::QueueRemove
                | Hook::QueueClear
                | Hook::QueueFullLevel
                | Hook::CaptureEnable
                | Hook::CaptureActivate
                | Hook::CaptureClear
                | Hook::MotionStart
                | Hook::MotionStop
                | Hook::MotionInput
                | Hook::FeedRateOverride
                | Hook::ProfileLimitedReset
                | Hook::FaultReset
        )
    }

    fn start(&mut self, v: &mut [f64]) {
        for q in &self.objects.queues {
            q.refresh(v);
        }
    }

    fn update(&mut self, v: &mut [f64], now: &mut Now<'_>) -> Result<(), String> {
        self.generate(v, now);
        Ok(())
    }

    /// Queue compares and PLS windows on the new positions, then timers and the free-running
    /// clock.
    fn derive(&mut self, v: &mut [f64], now: &mut Now<'_>) {
        let command = self.axis.command();
        let velocity = self.axis.velocity();
        // The feedback is the command's on an ideal servo.
        let feedback = command - v[self.slots.axis.following_error as usize];
        let feedback_velocity = v[self.slots.axis.vel_feedback as usize];
        let master_speed = now.master_speed();
        for pls in &self.objects.plss {
            let (p, vel) = match pls.config.source {
                QueueSource::Master => (now.master, master_speed),
                QueueSource::Feedback => (feedback, feedback_velocity),
                QueueSource::Command => (command, velocity),
            };
            pls.evaluate(p, vel, v);
        }
        let o = &mut self.objects;
        for (q, source) in o.queues.iter_mut().zip(&o.queue_sources) {
            // An empty queue has nothing to compare (most of a machine's queues are unused).
            if q.is_empty() {
                continue;
            }
            let position = match source {
                QueueSource::Master => now.master,
                QueueSource::Feedback => feedback,
                QueueSource::Command => command,
            };
            q.compare(position, v, now.trace, now.tick);
        }
        v[self.slots.axis.free_run as usize] = (now.time_ns / 1000) as f64;
        if o.timers_running {
            for t in &mut o.timers {
                t.update(now.time_ns, now.master, v);
            }
            o.timers_running = o.timers.iter().any(Timer::running);
        }
    }

    fn take_edges(&mut self, out: &mut Vec<Edge>) {
        if !self.sensors.pending.is_empty() {
            out.append(&mut self.sensors.pending);
        }
    }

    fn write(
        &mut self,
        target: Target,
        value: f64,
        when: When,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        let i = target.instance as usize;
        let slot = target.slot;
        match target.hook {
            Hook::QueueDataIn => self.objects.queues[i].data_in(value, v, now.trace, now.tick),
            Hook::QueueOffset | Hook::QueueFullLevel => {
                v[slot as usize] = value;
                self.objects.queues[i].refresh(v);
            }
            Hook::QueueCompareEnable => v[slot as usize] = value,
            Hook::CaptureEnable => self.objects.captures[i].set_enable(value != 0.0, v),
            Hook::CaptureActivate => {
                let (time, at) = match when {
                    // Written by a program: the edge is now, at this update's master position.
                    When::Now => (
                        now.seconds(),
                        Positions {
                            master: now.master,
                            ..Positions::default()
                        },
                    ),
                    // From an input: latched at the edge's exact instant.
                    When::Edge(t) => {
                        let command = self.command_at(t, v, now);
                        (
                            t,
                            Positions {
                                master: now.master_at(t),
                                command,
                                feedback: self.latched_feedback(t, command, v, now),
                            },
                        )
                    }
                };
                if let Some(c) = self.objects.captures.get(i) {
                    c.activate(value != 0.0, time, at, v, now.trace, now.tick);
                }
            }
            Hook::FeedRateOverride => {
                if !(0.0..=200.0).contains(&value) {
                    return Err(format!("FeedRateOverride must be 0 to 200 %, not {value}"));
                }
                v[self.slots.axis.feed_rate as usize] = value;
            }
            Hook::MotionInput => self.motion_input(target, value, when, v, now)?,
            Hook::QueueRemove
            | Hook::QueueClear
            | Hook::CaptureClear
            | Hook::TimerInitiate
            | Hook::TimerStop
            | Hook::MotionStart
            | Hook::MotionStop
            | Hook::ProfileLimitedReset
            | Hook::FaultReset => {
                if value != 0.0 {
                    self.act(target, StartRef::Now, 0, When::Now, v, now)?;
                }
            }
            _ => v[slot as usize] = value,
        }
        Ok(())
    }

    fn act(
        &mut self,
        target: Target,
        start: StartRef,
        profile: u8,
        when: When,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<ActOutcome, String> {
        let i = target.instance as usize;
        let o = &mut self.objects;
        match target.hook {
            Hook::QueueRemove => o.queues[i].remove(v),
            Hook::QueueClear => o.queues[i].clear(v),
            Hook::CaptureClear => o.captures[i].clear(v),
            Hook::TimerInitiate => {
                o.timers[i].initiate(now.time_ns, now.master, v);
                o.timers_running = true;
            }
            Hook::TimerStop => o.timers[i].stop(v),
            Hook::ProfileLimitedReset => {
                // `Index.ResetProfileLimited` (no instance) clears every index's.
                for (n, ix) in o.indexes.iter().enumerate() {
                    if target.instance == GLOBAL_INSTANCE || n == i {
                        v[ix.s.profile_limited as usize] = 0.0;
                    }
                }
                self.profile_limited_any(v);
            }
            Hook::FaultReset => self.fault_reset(v),
            Hook::MotionStop => {
                if let Some(owner) = self.owner_of(target) {
                    self.stop_motion(owner, v, now);
                }
            }
            Hook::MotionStart => {
                if usize::from(profile) >= self.axis.profiles.len() {
                    return Err(format!("there is no Profile.{profile}"));
                }
                let minus = self
                    .objects
                    .jogs
                    .iter()
                    .any(|j| j.minus_initiate == target.slot);
                let compound = self
                    .objects
                    .indexes
                    .get(i)
                    .is_some_and(|ix| ix.s.compound == target.slot);
                let Some(owner) = self.owner_of(target) else {
                    return Err(format!(
                        "{:?} motion is not simulated yet in this build of pacer",
                        self.kind_of(target.slot)
                    ));
                };
                // An initiate from an input that latches in hardware starts at its edge, as
                // `Using Capture` would.
                if let When::Edge(t) = when {
                    self.edge_start = Some((t, now.master_at(t)));
                }
                let r = self.start_motion(owner, minus, compound, start, profile, v, now);
                self.edge_start = None;
                return r;
            }
            other => return Err(format!("{other:?} is not an action")),
        }
        Ok(ActOutcome::Done)
    }

    fn stop_all(&mut self, v: &mut [f64], now: &mut Now<'_>) {
        let decel = v[self.slots.axis.stop_decel as usize];
        for i in 0..self.axis.profiles.len() {
            self.stop_profile(i, decel, v, now);
        }
    }

    fn moving(&self, master_moves: bool, out: &mut Vec<super::Moving>) {
        for m in self.axis.profiles.iter().filter_map(|p| p.motion.as_ref()) {
            let ends = m.plan.duration().is_finite();
            out.push(super::Moving {
                name: m.owner.to_string(),
                settles: ends && (m.domain == Domain::Time || master_moves),
            });
        }
        // Running on from a compounded index that no index has taken over yet: it does not
        // stop by itself.
        for c in self.axis.profiles.iter().filter_map(|p| p.coast.as_ref()) {
            out.push(super::Moving {
                name: format!("{} (compounded, no next index)", c.owner),
                settles: false,
            });
        }
    }

    fn profiles(&mut self) -> Option<&mut dyn Profiles> {
        Some(self)
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

impl Profiles for Drive {
    fn busy(&self, profile: usize) -> bool {
        self.axis
            .profiles
            .get(profile)
            .is_some_and(motion::Profile::busy)
    }

    fn dwell(
        &mut self,
        length: f64,
        domain: Domain,
        start: StartRef,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<ActOutcome, String> {
        self.start_dwell(length, domain, start, v, now)
    }
}
