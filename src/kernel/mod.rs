//! The kernel objects' behaviour behind member writes and actions. Motion objects (index, home,
//! jog, gear) arrive with the motion kernel; until then initiating one is a clear run-time error.

pub mod capture;
pub mod queue;
pub mod timer;

use crate::registry::{Hook, Kind, Registry, SlotId};
use crate::trace::Trace;
use capture::{Capture, Positions};
use queue::Queue;
use timer::Timer;

/// The slot of a catalog member; the catalog is static, so a miss is a bug in pacer itself.
pub fn slot(registry: &Registry, kind: Kind, instance: u32, member: &str) -> SlotId {
    registry.slot_of(kind, instance, member).unwrap_or_else(|| {
        panic!("catalog has no {kind:?}.{instance}.{member} (a bug in pacer's catalog)")
    })
}

/// What an action did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActOutcome {
    /// Done; the program goes on.
    Done,
    /// Motion is running on that profile: the program waits and retries.
    ProfileBusy,
}

/// A motion profile: which motion occupies it, until when.
#[derive(Debug, Clone, Default)]
struct Profile {
    /// A timed dwell ends at this update.
    busy_until: Option<u64>,
    /// A master-distance dwell ends when the master reaches this position.
    busy_until_master: Option<f64>,
    busy_slot: SlotId,
}

impl Profile {
    fn busy(&self) -> bool {
        self.busy_until.is_some() || self.busy_until_master.is_some()
    }
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
    captures: Vec<Capture>,
    timers: Vec<Timer>,
    profiles: Vec<Profile>,
    feed_rate: SlotId,
    free_run: SlotId,
}

impl Kernel {
    /// Kernel objects for every instance in the registry.
    pub fn new(registry: &Registry) -> Kernel {
        let count = |k: Kind| registry.of(k).count;
        Kernel {
            queues: (0..count(Kind::Queue))
                .map(|i| Queue::new(registry, i))
                .collect(),
            captures: (0..count(Kind::Capture))
                .map(|i| Capture::new(registry, i))
                .collect(),
            timers: (0..count(Kind::Timer))
                .map(|i| Timer::new(registry, i))
                .collect(),
            profiles: (0..count(Kind::Profile))
                .map(|i| Profile {
                    busy_until: None,
                    busy_until_master: None,
                    busy_slot: slot(registry, Kind::Profile, i, "Busy"),
                })
                .collect(),
            feed_rate: slot(registry, Kind::Motion, 0, "FeedRateOverride"),
            free_run: slot(registry, Kind::Motion, 0, "FreeRunTime"),
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
                now.time_ns as f64 / 1e9,
                Positions {
                    master: now.master,
                    ..Positions::default()
                },
                v,
                now.trace,
                now.tick,
            ),
            Hook::FeedRateOverride => {
                if !(0.0..=200.0).contains(&value) {
                    return Err(format!("FeedRateOverride must be 0 to 200 %, not {value}"));
                }
                v[self.feed_rate as usize] = value;
            }
            Hook::OutputWrite | Hook::MotionInput | Hook::Store => v[slot as usize] = value,
            Hook::QueueRemove
            | Hook::QueueClear
            | Hook::CaptureClear
            | Hook::TimerInitiate
            | Hook::TimerStop
            | Hook::MotionStart
            | Hook::MotionStop => {
                if value != 0.0 {
                    self.act(hook, instance, v, now)?;
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

    /// Run an action.
    pub fn act(
        &mut self,
        hook: Hook,
        instance: u32,
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
            Hook::MotionStop => {}
            Hook::MotionStart => {
                return Err("motion objects (Index, Home, Jog, Gear) are not simulated yet: this build of pacer has no motion kernel".into())
            }
            other => return Err(format!("{other:?} is not an action")),
        }
        Ok(ActOutcome::Done)
    }

    /// `Dwell For Time`: a motion on profile 0 lasting `seconds`.
    pub fn dwell_time(
        &mut self,
        seconds: f64,
        v: &mut [f64],
        now: &Now<'_>,
    ) -> Result<ActOutcome, String> {
        let ns = crate::config::values::seconds_to_ns(seconds)
            .map_err(|e| format!("Dwell For Time: {e}"))?;
        let p = &mut self.profiles[0];
        if p.busy() {
            return Ok(ActOutcome::ProfileBusy);
        }
        let ticks = ns.div_ceil(now.tick_ns.max(1));
        if ticks > 0 {
            p.busy_until = Some(now.tick + ticks);
            v[p.busy_slot as usize] = 1.0;
        }
        Ok(ActOutcome::Done)
    }

    /// `Dwell For Master Dist`: a motion on profile 0 lasting until the master has moved
    /// `distance` from here.
    pub fn dwell_master(
        &mut self,
        distance: f64,
        v: &mut [f64],
        now: &Now<'_>,
    ) -> Result<ActOutcome, String> {
        if !(distance.is_finite() && distance >= 0.0) {
            return Err(format!(
                "Dwell For Master Dist needs a distance of 0 or more, not {distance}"
            ));
        }
        let p = &mut self.profiles[0];
        if p.busy() {
            return Ok(ActOutcome::ProfileBusy);
        }
        if distance > 0.0 {
            p.busy_until_master = Some(now.master + distance);
            v[p.busy_slot as usize] = 1.0;
        }
        Ok(ActOutcome::Done)
    }

    /// True while a motion runs on `profile`.
    pub fn profile_busy(&self, profile: usize) -> bool {
        self.profiles.get(profile).is_some_and(Profile::busy)
    }

    /// Status derived after the tasks ran: queue compares against their source positions.
    pub fn derive(&mut self, v: &mut [f64], now: &mut Now<'_>) {
        for q in &mut self.queues {
            q.compare(now.master, v, now.trace, now.tick);
        }
    }

    /// Per-update work before the tasks run: timers, profile completion, the free-running clock.
    pub fn update(&mut self, v: &mut [f64], now: &Now<'_>) {
        v[self.free_run as usize] = (now.time_ns / 1000) as f64;
        for t in &mut self.timers {
            t.update(now.time_ns, now.master, v);
        }
        for p in &mut self.profiles {
            if p.busy_until.is_some_and(|until| now.tick >= until) {
                p.busy_until = None;
            }
            if p.busy_until_master.is_some_and(|until| now.master >= until) {
                p.busy_until_master = None;
            }
            v[p.busy_slot as usize] = f64::from(p.busy());
        }
    }
}
