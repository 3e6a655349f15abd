//! Starting and stopping the drive's motions: where a motion starts on its timeline (now, `Using
//! Last`, `Using Capture.N`, a latching input's edge), the plans of indexes, homes, jogs, the gear
//! and dwells, the registration sensor and the home reference, and the stops.

use super::motion::blend::Blend;
use super::motion::trapezoid::{Phase, Trapezoid};
use super::motion::{Coast, Motion, Owner, Plan};
use super::setup::IndexType;
use super::{ActOutcome, Domain, Drive, Now, StartRef};

impl Drive {
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
            StartRef::Now => clock,
            StartRef::Last => last().unwrap_or(clock),
            StartRef::Capture(c) => {
                let capture = self
                    .objects
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

    /// Start the motion of `owner` on a profile, or report that the profile is busy.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn start_motion(
        &mut self,
        owner: Owner,
        minus: bool,
        compound: bool,
        start: StartRef,
        profile: u8,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<ActOutcome, String> {
        let p = usize::from(profile);
        if p >= self.axis.profiles.len() {
            return Err(format!("there is no Profile.{profile}"));
        }
        if self.axis.profiles[p].busy() {
            return Ok(ActOutcome::ProfileBusy);
        }
        if self.faulted() {
            self.refuse_faulted(&format!("{owner} initiate"), now);
            return Ok(ActOutcome::Done);
        }
        match owner {
            Owner::Home(i) => self.start_home(i, start, p, v, now),
            Owner::Gear => self.start_gear(start, p, v, now),
            Owner::Jog(i) => self.start_jog(i, minus, start, p, v, now),
            Owner::Index(i) => self.start_index(i, compound, start, p, v, now),
            Owner::Dwell => Err("a dwell is not an object to initiate".into()),
        }
    }

    /// Start index `instance` on free profile `p`; `compound`: it runs on into the next index
    /// instead of stopping at its end point (`Index.N.CompoundInitiate`).
    fn start_index(
        &mut self,
        instance: u32,
        compound: bool,
        start: StartRef,
        p: usize,
        v: &mut [f64],
        now: &Now<'_>,
    ) -> Result<ActOutcome, String> {
        let ix = self
            .objects
            .indexes
            .get(instance as usize)
            .ok_or_else(|| format!("no Index.{instance}"))?
            .clone();
        let s = ix.s;
        let name = format!("Index.{instance}");
        // The compounded index before it, if the axis is running on from one.
        let coast = self.axis.profiles[p].coast;
        let domain = if ix.config.synchronized {
            Domain::Master
        } else {
            Domain::Time
        };
        if compound || coast.is_some() {
            // `pacer check` refuses these where it can see them (FM-3 reference p. 98: "A Timed
            // Index can not be compounded into or out of"); the rest is refused here.
            let role = if compound {
                "compounded"
            } else {
                "compounded into"
            };
            if ix.config.timed {
                return Err(format!(
                    "{name} is a timed index: a timed index cannot be {role} (FM-3 reference, p. 98)"
                ));
            }
            if ix.config.kind == IndexType::Registration {
                return Err(format!(
                    "{name} is a registration index: pacer does not compound registration indexes"
                ));
            }
        }
        let target = v[s.distance as usize];
        let r = self.rollover;
        // Where the axis is when the index starts: for one compounded into, where the compounded
        // index ended (the other profile as it is now).
        let here = match coast {
            Some(c) => self.axis.command() - self.axis.profiles[p].position + c.base,
            None => self.axis.command(),
        };
        let distance = match ix.config.kind {
            IndexType::Incremental | IndexType::Registration => target,
            IndexType::Absolute => target - here,
            // On a rolled-over axis, to the target position the short or long way round.
            IndexType::RotaryPlus => (target - here.rem_euclid(r)).rem_euclid(r),
            IndexType::RotaryMinus => -(here.rem_euclid(r) - target).rem_euclid(r),
        };
        let (velocity, accel, decel) = (
            v[s.velocity as usize],
            v[s.acceleration as usize],
            v[s.deceleration as usize],
        );
        let mut start = start;
        let v0 = match coast {
            None => 0.0,
            Some(c) => {
                let previous = c.owner;
                if c.domain != domain {
                    return Err(format!(
                        "{name} cannot follow the compounded {previous}: one is synchronized to \
                         the master and the other is not"
                    ));
                }
                if let StartRef::Capture(n) = start {
                    return Err(format!(
                        "{name} cannot start Using Capture.{n}: it follows the compounded \
                         {previous}, which runs on into it without stopping"
                    ));
                }
                if distance * c.velocity < 0.0 || distance == 0.0 {
                    return Err(format!(
                        "{name} does not go on in the direction of the compounded {previous}: \
                         a compound index cannot reverse or stop the axis"
                    ));
                }
                // It starts exactly where the compounded index ended, on the timeline.
                start = StartRef::Last;
                c.velocity.abs()
            }
        };
        let (plan, limited) = if v0 != 0.0 || compound {
            Blend::new(distance, v0, velocity, accel, decel, compound)
                .map(|b| (Plan::Blend(b), false))
        } else if ix.config.timed {
            Trapezoid::timed(distance, v[s.time as usize], velocity, accel, decel)
                .map(|(t, l)| (Plan::Move(t), l))
        } else {
            Trapezoid::new(distance, velocity, accel, decel).map(|t| (Plan::Move(t), false))
        }
        .map_err(|e| format!("cannot plan {name}: {e}"))?;
        // A registration index waits for its sensor until it reaches its limit distance.
        self.armed[instance as usize] = ix.config.kind == IndexType::Registration;
        v[s.limit_hit as usize] = 0.0;
        // Latched: the drive clears it only on Index.N.ResetProfileLimited (SM-EZMotion User
        // Guide, p. 28), not when a later index meets its time.
        if limited {
            v[s.profile_limited as usize] = 1.0;
            self.profile_limited_any(v);
        }
        let started = self.launch(p, Owner::Index(instance), plan, domain, start, v, now)?;
        ix.status(v, Phase::Accelerating);
        v[s.at_vel as usize] = 0.0;
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
        let j = *self
            .objects
            .jogs
            .get(instance as usize)
            .ok_or_else(|| format!("no Jog.{instance}"))?;
        let (velocity, accel) = (v[j.velocity as usize], v[j.acceleration as usize]);
        if !(velocity.is_finite() && velocity > 0.0 && accel.is_finite() && accel > 0.0) {
            return Err(format!(
                "Jog.{instance} needs a velocity and an acceleration above 0"
            ));
        }
        let velocity = if minus { -velocity } else { velocity };
        let started = self.launch(
            p,
            Owner::Jog(instance),
            Plan::Seek { velocity, accel },
            Domain::Time,
            start,
            v,
            now,
        )?;
        v[j.in_progress as usize] = 1.0;
        Ok(started)
    }

    /// Start gearing at the ratio of `Gear.Ratio` (read now; a later change needs a new
    /// initiate).
    fn start_gear(
        &mut self,
        start: StartRef,
        p: usize,
        v: &mut [f64],
        now: &Now<'_>,
    ) -> Result<ActOutcome, String> {
        let ratio = v[self.slots.gear.ratio as usize];
        if !ratio.is_finite() {
            return Err(format!("Gear.Ratio must be a number, not {ratio}"));
        }
        let started = self.launch(
            p,
            Owner::Gear,
            Plan::Gear { ratio },
            Domain::Master,
            start,
            v,
            now,
        )?;
        v[self.slots.gear.in_progress as usize] = 1.0;
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
            .objects
            .homes
            .get(instance as usize)
            .ok_or_else(|| format!("no Home.{instance}"))?
            .clone();
        if h.config.reference.is_none() {
            return Err(format!("Home.{instance} has no reference input: set [home.{instance}] reference in machine.toml"));
        }
        let velocity = v[h.s.velocity as usize];
        let accel = v[h.s.acceleration as usize];
        if !(velocity.is_finite()
            && velocity != 0.0
            && accel.is_finite()
            && accel > 0.0
            && v[h.s.deceleration as usize] > 0.0)
        {
            return Err(format!("Home.{instance} needs a velocity other than 0 and an acceleration and deceleration above 0"));
        }
        let started = self.launch(
            p,
            Owner::Home(instance),
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
    /// at the calculated or specified offset. The profile it runs on, and a warning.
    pub(super) fn home_reference(
        &mut self,
        home: usize,
        t: f64,
        position: f64,
        v: &[f64],
    ) -> Option<(usize, Option<String>)> {
        let h = &self.objects.homes[home];
        let owner = Owner::Home(home as u32);
        let (p, velocity, accel, start) =
            self.axis
                .profiles
                .iter()
                .enumerate()
                .find_map(|(i, p)| match &p.motion {
                    Some(m) if m.owner == owner => match m.plan {
                        Plan::Seek { velocity, accel } => Some((i, velocity, accel, m.start)),
                        _ => None,
                    },
                    _ => None,
                })?;
        let decel = v[h.s.deceleration as usize];
        // Speed at the reference (the seek may still be accelerating).
        let v0 = velocity.signum() * (accel * (t - start)).min(velocity.abs());
        let stopping = v0 * v0 / (2.0 * decel);
        let mut warning = None;
        let distance = if h.config.specified_offset {
            let offset = v[h.s.offset as usize];
            if offset * velocity.signum() < stopping - 1e-12 {
                warning = Some(format!(
                    "{owner}: the specified offset {offset} is shorter than the distance needed to stop ({stopping}); stopping at the calculated offset"
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

    /// `Index.N.SensorTrigger` driven to `on` at `time` seconds. The rising edge of the sensor
    /// of a running registration index ends the move `RegistrationOffset` past the position the
    /// axis had at that instant (further when it cannot stop that soon).
    pub(super) fn sensor_edge(
        &mut self,
        instance: u32,
        on: bool,
        time: f64,
        v: &mut [f64],
        now: &Now<'_>,
    ) {
        let i = instance as usize;
        let Some(ix) = self.objects.indexes.get(i).cloned() else {
            return;
        };
        let s = ix.s;
        let rising = on && v[s.sensor as usize] == 0.0;
        v[s.sensor as usize] = f64::from(on);
        if !rising || !self.armed.get(i).copied().unwrap_or(false) {
            return;
        }
        let owner = Owner::Index(instance);
        let Some(p) = self
            .axis
            .profiles
            .iter()
            .position(|p| p.motion.as_ref().is_some_and(|m| m.owner == owner))
        else {
            return;
        };
        let Some(m) = self.axis.profiles[p].motion else {
            return;
        };
        let clock = match m.domain {
            Domain::Time => self.motion_time_of(time, v),
            Domain::Master => now.master_at(time),
        };
        if !(m.started || clock >= m.start) {
            return;
        }
        let (dp, dv, phase) = m.plan.at(clock - m.start);
        if phase == Phase::Done || dv == 0.0 {
            return;
        }
        let decel = v[s.deceleration as usize];
        let stopping = dv * dv / (2.0 * decel);
        // The offset is a distance past the sensor in the direction of travel; an offset shorter
        // than the stopping distance stops as soon as it can.
        let offset = v[s.registration_offset as usize].max(stopping);
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
        let coast = self.axis.profiles[p].coast;
        if let (Some(c), false) = (coast, matches!(owner, Owner::Index(_))) {
            return Err(format!(
                "{owner} cannot start while the axis runs on from the compounded {}: a compound \
                 index runs into the next index",
                c.owner
            ));
        }
        let at = self.start_point(domain, start, p, v, now)?;
        // An index compounded into starts from where the compounded index ended.
        let base = coast.map_or(self.axis.profiles[p].position, |c: Coast| c.base);
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
        v[self.slots.profiles[p].busy as usize] = 1.0;
        Ok(ActOutcome::Done)
    }

    /// Stop the motion of `owner` wherever it is, at its object's deceleration.
    pub(super) fn stop_motion(&mut self, owner: Owner, v: &mut [f64], now: &Now<'_>) {
        let o = &self.objects;
        let decel = match owner {
            Owner::Index(i) => o
                .indexes
                .get(i as usize)
                .map_or(0.0, |ix| v[ix.s.deceleration as usize]),
            Owner::Home(i) => o
                .homes
                .get(i as usize)
                .map_or(0.0, |h| v[h.s.deceleration as usize]),
            Owner::Jog(i) => o
                .jogs
                .get(i as usize)
                .map_or(0.0, |j| v[j.deceleration as usize]),
            Owner::Gear | Owner::Dwell => 0.0,
        };
        for i in 0..self.axis.profiles.len() {
            let q = &self.axis.profiles[i];
            if q.motion.as_ref().is_some_and(|m| m.owner == owner)
                || q.coast.is_some_and(|c| c.owner == owner)
            {
                self.stop_profile(i, decel, v, now);
            }
        }
    }

    /// Bring the motion on `profile` to rest at `decel` (at once when it is 0).
    pub(super) fn stop_profile(
        &mut self,
        profile: usize,
        decel: f64,
        v: &mut [f64],
        now: &Now<'_>,
    ) {
        if let Some(owner) = self.axis.decelerate(
            profile,
            self.motion_time_of(now.seconds(), v),
            now.master,
            decel,
        ) {
            self.owner_status(owner, v, Phase::Done);
            v[self.slots.profiles[profile].busy as usize] = 0.0;
        }
    }

    /// `Dwell For Time` / `Dwell For Master Dist`: a motion on profile 0 lasting `length`
    /// seconds or master units.
    pub(super) fn start_dwell(
        &mut self,
        length: f64,
        domain: Domain,
        start: StartRef,
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
            return Ok(ActOutcome::ProfileBusy);
        }
        self.launch(0, Owner::Dwell, Plan::Dwell(length), domain, start, v, now)
    }
}
