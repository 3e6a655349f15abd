//! The servo axis: two motion profiles whose positions add up, one motion at a time on each.
//! A motion runs in time (realtime) or in master distance (synchronized); it starts now, where
//! the previous motion on its profile ended (`Using Last`), or from a capture's latched data
//! (`Using Capture.N`). A start in the past is caught up at once; a start in the future waits.

pub mod blend;
pub mod trapezoid;

use blend::Blend;
use trapezoid::{Phase, Trapezoid};

pub use crate::devices::command::Domain;

/// What a motion does over its domain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Plan {
    /// A trapezoidal move.
    Move(Trapezoid),
    /// A move of a compound chain: from a speed, or on at its velocity past its end point.
    Blend(Blend),
    /// Stand still for this long (a dwell).
    Dwell(f64),
    /// Accelerate to `velocity` (signed) and keep going until replaced (homing).
    Seek { velocity: f64, accel: f64 },
    /// Follow the master at `ratio` follower units per master unit, until stopped (gearing).
    Gear { ratio: f64 },
    /// From speed `v0` (signed), cruise and then decelerate at `decel` to stop after `distance`
    /// (same sign as `v0`, at least the stopping distance).
    Finish { v0: f64, decel: f64, distance: f64 },
}

impl Plan {
    /// Length of the plan in its domain (infinite for a seek).
    pub fn duration(&self) -> f64 {
        match *self {
            Plan::Move(t) => t.duration(),
            Plan::Blend(b) => b.duration(),
            Plan::Dwell(l) => l,
            Plan::Seek { .. } | Plan::Gear { .. } => f64::INFINITY,
            Plan::Finish {
                v0,
                decel,
                distance,
            } => {
                let stop = v0.abs() / decel;
                let cruise = (distance.abs() - v0 * v0 / (2.0 * decel)).max(0.0)
                    / v0.abs().max(f64::MIN_POSITIVE);
                cruise + stop
            }
        }
    }

    /// Velocity at the end, per domain unit: 0 but for a compounded index, which runs on into
    /// the next one.
    pub fn end_velocity(&self) -> f64 {
        match self {
            Plan::Blend(b) => b.end_velocity(),
            _ => 0.0,
        }
    }

    /// Position, velocity and phase `u` into the plan.
    pub fn at(&self, u: f64) -> (f64, f64, Phase) {
        let u = u.max(0.0);
        match *self {
            Plan::Move(t) => t.at(u),
            Plan::Blend(b) => b.at(u),
            Plan::Dwell(l) => (
                0.0,
                0.0,
                if u >= l {
                    Phase::Done
                } else {
                    Phase::AtVelocity
                },
            ),
            Plan::Gear { ratio } => (ratio * u, ratio, Phase::AtVelocity),
            Plan::Seek { velocity, accel } => {
                let ta = velocity.abs() / accel;
                let sign = velocity.signum();
                if u < ta {
                    (
                        sign * 0.5 * accel * u * u,
                        sign * accel * u,
                        Phase::Accelerating,
                    )
                } else {
                    (
                        sign * 0.5 * accel * ta * ta + velocity * (u - ta),
                        velocity,
                        Phase::AtVelocity,
                    )
                }
            }
            Plan::Finish {
                v0,
                decel,
                distance,
            } => {
                let total = self.duration();
                if u >= total {
                    return (distance, 0.0, Phase::Done);
                }
                let r = total - u;
                let sign = v0.signum();
                let stop = v0.abs() / decel;
                if r <= stop {
                    (
                        distance - sign * 0.5 * decel * r * r,
                        sign * decel * r,
                        Phase::Decelerating,
                    )
                } else {
                    (v0 * u, v0, Phase::AtVelocity)
                }
            }
        }
    }
}

/// The object a motion belongs to: its status members follow the motion, and the trace names
/// it (`Index.0`, `Dwell`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Owner {
    /// `Index.N`.
    Index(u32),
    /// `Home.N`.
    Home(u32),
    /// `Jog.N`.
    Jog(u32),
    /// The gear.
    Gear,
    /// A dwell (no object: `Dwell For Time`, `Dwell For Master Dist`).
    Dwell,
}

impl std::fmt::Display for Owner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Owner::Index(i) => write!(f, "Index.{i}"),
            Owner::Home(i) => write!(f, "Home.{i}"),
            Owner::Jog(i) => write!(f, "Jog.{i}"),
            Owner::Gear => f.write_str("Gear"),
            Owner::Dwell => f.write_str("Dwell"),
        }
    }
}

/// A motion on a profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// Who runs it.
    pub owner: Owner,
    /// What it does.
    pub plan: Plan,
    /// Its domain.
    pub domain: Domain,
    /// Where in the domain it starts (seconds or master position).
    pub start: f64,
    /// Profile position when it starts.
    pub base: f64,
    /// The start has been reached (and traced).
    pub started: bool,
}

impl Motion {
    /// Where in the domain it ends.
    pub fn end(&self) -> f64 {
        self.start + self.plan.duration()
    }
}

/// A profile running on at the velocity a compounded index ended at, until the next index (which
/// starts exactly at `start`, from `base`) takes over, or a stop ramps it down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coast {
    /// The compounded index.
    pub owner: Owner,
    /// Its domain.
    pub domain: Domain,
    /// Where on the domain's timeline it ended.
    pub start: f64,
    /// The profile position at its end point.
    pub base: f64,
    /// Its velocity there, per domain unit (signed).
    pub velocity: f64,
}

impl Coast {
    /// The profile position at `clock` on its domain's timeline.
    pub fn position(&self, clock: f64) -> f64 {
        self.base + self.velocity * (clock - self.start).max(0.0)
    }
}

/// One motion profile.
#[derive(Debug, Clone, Default)]
pub struct Profile {
    /// Position contributed by this profile.
    pub position: f64,
    /// Velocity contributed, per second.
    pub velocity: f64,
    /// The motion running, if any.
    pub motion: Option<Motion>,
    /// Where the last motion ended on its domain's timeline.
    pub last_end: Option<(Domain, f64)>,
    /// Running on from a compounded index, not yet taken over by the next.
    pub coast: Option<Coast>,
}

impl Profile {
    /// A motion runs (or waits to start) on this profile.
    pub fn busy(&self) -> bool {
        self.motion.is_some()
    }
}

/// What happened to a motion during an update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Event {
    /// It reached its start: master position and axis position there.
    Started {
        owner: Owner,
        master: f64,
        position: f64,
    },
    /// It is running in this phase.
    Running { owner: Owner, phase: Phase },
    /// It ended: where on its domain's timeline (seconds or master position), and the axis
    /// position there.
    Done {
        owner: Owner,
        end: f64,
        position: f64,
    },
}

/// The servo axis (an ideal servo: feedback follows command exactly).
#[derive(Debug, Clone, Default)]
pub struct Axis {
    /// The two profiles.
    pub profiles: [Profile; 2],
}

/// The two clocks a motion can run on, at one update.
#[derive(Debug, Clone, Copy)]
pub struct Clocks {
    /// Real seconds.
    pub time: f64,
    /// The motion clock realtime motions run on: it advances at the feed-rate override.
    pub motion_time: f64,
    /// Motion seconds per real second (FeedRateOverride / 100).
    pub rate: f64,
    /// Master position.
    pub master: f64,
    /// Master velocity, per second.
    pub master_speed: f64,
}

impl Clocks {
    fn of(&self, d: Domain) -> f64 {
        match d {
            Domain::Time => self.motion_time,
            Domain::Master => self.master,
        }
    }

    /// Domain units per real second.
    fn rate_of(&self, d: Domain) -> f64 {
        match d {
            Domain::Time => self.rate,
            Domain::Master => self.master_speed,
        }
    }

    /// The real time at which the motion clock read `motion_time` (at the present rate).
    fn real_time_of(&self, motion_time: f64) -> f64 {
        if self.rate > 0.0 {
            self.time - (self.motion_time - motion_time) / self.rate
        } else {
            self.time
        }
    }
}

impl Axis {
    /// Command position: the sum of both profiles.
    pub fn command(&self) -> f64 {
        self.profiles[0].position + self.profiles[1].position
    }

    /// Command velocity, per second.
    pub fn velocity(&self) -> f64 {
        self.profiles[0].velocity + self.profiles[1].velocity
    }

    /// The command position at any instant `t` (seconds), from the plans themselves: exact
    /// between updates too. `master_at` gives the master position at a time.
    pub fn position_at(&self, motion_time: f64, master: f64) -> f64 {
        self.profiles
            .iter()
            .map(|p| match &p.motion {
                Some(m) => {
                    let clock = match m.domain {
                        Domain::Time => motion_time,
                        Domain::Master => master,
                    };
                    if m.started || clock >= m.start {
                        m.base + m.plan.at(clock - m.start).0
                    } else {
                        p.position
                    }
                }
                None => match &p.coast {
                    Some(c) => c.position(match c.domain {
                        Domain::Time => motion_time,
                        Domain::Master => master,
                    }),
                    None => p.position,
                },
            })
            .sum()
    }

    /// Replace the motion on `profile` by `plan`, continuing from where it is at `at` (on its
    /// domain's timeline) with the position `position`.
    pub fn replace(&mut self, profile: usize, plan: Plan, at: f64, position: f64) {
        if let Some(m) = self.profiles[profile].motion.as_mut() {
            m.plan = plan;
            m.start = at;
            m.base = position;
            m.started = true;
        }
    }

    /// Bring the motion on `profile` to rest from its present velocity at `decel` (units/s²),
    /// starting at time `t`; with no deceleration (0) or no velocity it ends where it stands.
    /// Returns the owner of a motion that ended at once.
    pub fn decelerate(&mut self, profile: usize, t: f64, master: f64, decel: f64) -> Option<Owner> {
        let p = &mut self.profiles[profile];
        // Running on from a compounded index with no next index yet: the stop ramps that down,
        // as the compounded index's motion.
        if p.motion.is_none() {
            let c = p.coast.take()?;
            let clock = match c.domain {
                Domain::Time => t,
                Domain::Master => master,
            };
            p.position = c.position(clock);
            p.motion = Some(Motion {
                owner: c.owner,
                plan: Plan::Dwell(0.0),
                domain: Domain::Time,
                start: t,
                base: p.position,
                started: true,
            });
        }
        let m = p.motion.as_mut()?;
        // First bring the motion to the instant of the stop.
        let clock = match m.domain {
            Domain::Time => t,
            Domain::Master => master,
        };
        if m.started || clock >= m.start {
            p.position = m.base + m.plan.at(clock - m.start).0;
        }
        let v0 = p.velocity;
        if !(decel.is_finite() && decel > 0.0) || v0 == 0.0 || !m.started {
            let owner = m.owner;
            p.last_end = None;
            p.motion = None;
            p.velocity = 0.0;
            return Some(owner);
        }
        m.plan = Plan::Finish {
            v0,
            decel,
            distance: v0.signum() * v0 * v0 / (2.0 * decel),
        };
        m.domain = Domain::Time;
        m.start = t;
        m.base = p.position;
        None
    }

    /// Put a motion on `profile` (which must be free).
    pub fn begin(&mut self, profile: usize, motion: Motion) {
        let p = &mut self.profiles[profile];
        p.coast = None;
        p.motion = Some(motion);
    }

    /// Advance every motion to the clocks of this update; report what happened, in profile
    /// order. `master_at` gives the master position at a time (for realtime starts).
    pub fn update(&mut self, now: Clocks, master_at: &dyn Fn(f64) -> f64, events: &mut Vec<Event>) {
        for i in 0..self.profiles.len() {
            self.update_profile(i, now, master_at, events);
        }
    }

    /// Advance the motion on one profile to the clocks of this update.
    pub fn update_profile(
        &mut self,
        i: usize,
        now: Clocks,
        master_at: &dyn Fn(f64) -> f64,
        events: &mut Vec<Event>,
    ) {
        // The motion is updated where it lies: moving it out and back costs a copy of the
        // whole plan at every update.
        let positions = [self.profiles[0].position, self.profiles[1].position];
        let p = &mut self.profiles[i];
        let Some(m) = p.motion.as_mut() else {
            match p.coast {
                Some(c) => {
                    p.position = c.position(now.of(c.domain));
                    p.velocity = c.velocity * now.rate_of(c.domain);
                }
                None => p.velocity = 0.0,
            }
            return;
        };
        let clock = now.of(m.domain);
        if !m.started {
            if clock < m.start {
                p.velocity = 0.0;
                return;
            }
            m.started = true;
            let master = match m.domain {
                Domain::Master => m.start,
                Domain::Time => master_at(now.real_time_of(m.start)),
            };
            // The axis where the motion starts: its profile at the motion's base (the end point
            // of a compounded index it runs on from, which the profile has since passed).
            let mut at = positions;
            at[i] = m.base;
            events.push(Event::Started {
                owner: m.owner,
                master,
                position: at[0] + at[1],
            });
        }
        let (dp, dv, phase) = m.plan.at(clock - m.start);
        let rate = now.rate_of(m.domain);
        p.position = m.base + dp;
        p.velocity = dv * rate;
        if phase != Phase::Done {
            events.push(Event::Running {
                owner: m.owner,
                phase,
            });
            return;
        }
        let (owner, domain, end, base) = (m.owner, m.domain, m.end(), m.base);
        let v_end = m.plan.end_velocity();
        p.motion = None;
        p.last_end = Some((domain, end));
        p.velocity = 0.0;
        let position = self.command();
        events.push(Event::Done {
            owner,
            end,
            position,
        });
        // A compounded index does not stop at its end point: the axis runs on at its end
        // velocity, on the timeline, until the next index takes over from that instant.
        if v_end != 0.0 {
            let c = Coast {
                owner,
                domain,
                start: end,
                base: base + dp,
                velocity: v_end,
            };
            self.profiles[i].coast = Some(c);
            self.profiles[i].position = c.position(clock);
            self.profiles[i].velocity = v_end * rate;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clocks(time: f64, master: f64, master_speed: f64) -> Clocks {
        Clocks {
            time,
            motion_time: time,
            rate: 1.0,
            master,
            master_speed,
        }
    }

    fn owner() -> Owner {
        Owner::Index(0)
    }

    #[test]
    fn a_synchronized_move_follows_the_master_and_a_late_start_is_caught_up() {
        let mut axis = Axis::default();
        let plan = Plan::Move(Trapezoid::new(10.0, 1.0, 1.0, 1.0).expect("plan"));
        // Started from a capture at master 100 while the master is already at 100.5.
        axis.begin(
            0,
            Motion {
                owner: owner(),
                plan,
                domain: Domain::Master,
                start: 100.0,
                base: 0.0,
                started: false,
            },
        );
        let mut ev = Vec::new();
        axis.update(clocks(1.0, 100.5, 50.0), &|_| 0.0, &mut ev);
        assert!(matches!(ev[0], Event::Started { master, .. } if master == 100.0));
        assert!((axis.command() - 0.125).abs() < 1e-12, "{}", axis.command());
        ev.clear();
        axis.update(clocks(2.0, 111.0, 50.0), &|_| 0.0, &mut ev);
        assert_eq!(axis.command(), 10.0);
        assert!(matches!(ev[0], Event::Done { .. }));
        assert_eq!(axis.profiles[0].last_end, Some((Domain::Master, 111.0)));
    }

    #[test]
    fn a_future_start_waits_and_profiles_add_up() {
        let mut axis = Axis::default();
        let dwell = Motion {
            owner: owner(),
            plan: Plan::Dwell(1.0),
            domain: Domain::Time,
            start: 0.5,
            base: 0.0,
            started: false,
        };
        axis.begin(0, dwell);
        let mv = Plan::Move(Trapezoid::new(2.0, 10.0, 100.0, 100.0).expect("plan"));
        axis.begin(
            1,
            Motion {
                owner: owner(),
                plan: mv,
                domain: Domain::Time,
                start: 0.0,
                base: 3.0,
                started: false,
            },
        );
        let mut ev = Vec::new();
        axis.update(clocks(0.25, 0.0, 0.0), &|_| 0.0, &mut ev);
        assert!(axis.profiles[0].busy());
        assert_eq!(
            ev.len(),
            2,
            "profile 0 waits silently; profile 1 starts and runs: {ev:?}"
        );
        axis.update(clocks(5.0, 0.0, 0.0), &|_| 0.0, &mut ev);
        assert_eq!(axis.command(), 5.0);
    }
}
