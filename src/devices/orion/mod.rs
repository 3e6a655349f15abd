//! The ORION DSP axes as the registry sees them: MotionBASIC controller-variable writes and
//! motion statements go in; each update, positions, latches and status come out into the
//! `Axis.N.…` slots, and latches, blinded marks and stepped corrections into the trace.

pub mod dsp;
mod moves;
mod servo;

use super::command::{GearAfter, KernelFunc, MotionCmd};
use super::regist::axes::{FastTrack, RegistAxes};
use super::{ActOutcome, AxisSet, Device, Now, StartRef, Target, When};
use crate::registry::catalog::AXIS_TYPE;
use crate::registry::{Hook, Kind, Registry, SlotId};
use crate::trace::{Event, MotionPhase};
use dsp::{After, DspAxes, DspAxisConfig, DspEvent, Queued, Sensor};

/// What a mark sensor is wired to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MarkInput {
    /// An input of the axis's DSP card (ZREF, ASEN, BSEN).
    Card(Sensor),
    /// The axis's fast input (REGIST), on for `on_time` seconds at each mark.
    Fast { on_time: f64 },
}

/// A sensor tied to marks on an axis (from the scenario).
#[derive(Debug, Clone, PartialEq)]
pub struct MarkTrack {
    /// The axis the marks are printed on (in its units).
    pub axis: u32,
    /// What the sensor drives.
    pub input: MarkInput,
    /// Mark positions, ascending.
    pub positions: Vec<f64>,
    /// Length of a mark along the axis.
    pub width: f64,
}

/// One DSP axis as the machine sets it up.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisSetUp {
    /// Its motion set-up.
    pub config: DspAxisConfig,
    /// What MOVE TO/FOR use without AT or IN.
    pub defaults: MoveDefaults,
    /// The input wired to its fast input (REGIST), if any.
    pub fast_input: Option<SlotId>,
    /// Its servo loop (`[axis.N.servo]`); `None`: ideal, feedback equals command.
    pub servo: Option<crate::devices::servo::ServoParams>,
}

/// What MOVE TO / MOVE FOR use when the statement gives no speed or time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveDefaults {
    /// Acceleration and deceleration, units/s².
    pub accel: f64,
    /// Speed, RPM.
    pub speed_rpm: f64,
}

/// Offsets of the Axis members in one instance's slots.
#[derive(Debug, Clone, Copy)]
struct Members {
    position: u32,
    velocity: u32,
    ratio: u32,
    dsp_done: u32,
    latched: [u32; 3],
    latched_position: [u32; 3],
}

/// The Axis members the DSP axes set, bound when pacer is compiled.
const MEMBERS: Members = {
    Members {
        position: crate::member_index!(AXIS_TYPE, "Position") as u32,
        velocity: crate::member_index!(AXIS_TYPE, "Velocity") as u32,
        ratio: crate::member_index!(AXIS_TYPE, "Ratio") as u32,
        dsp_done: crate::member_index!(AXIS_TYPE, "DspDone") as u32,
        latched: [
            crate::member_index!(AXIS_TYPE, "Zref") as u32,
            crate::member_index!(AXIS_TYPE, "Asen") as u32,
            crate::member_index!(AXIS_TYPE, "Bsen") as u32,
        ],
        latched_position: [
            crate::member_index!(AXIS_TYPE, "PosZref") as u32,
            crate::member_index!(AXIS_TYPE, "PosAsen") as u32,
            crate::member_index!(AXIS_TYPE, "PosBsen") as u32,
        ],
    }
};

/// The DSP axes of a machine and where their members live.
#[derive(Debug, Clone)]
pub struct Orion {
    dsp: DspAxes,
    configs: Vec<DspAxisConfig>,
    /// The defined axes as a set (bit n-1 for axis n): axis sets are checked against it.
    defined: u16,
    defaults: Vec<MoveDefaults>,
    base: SlotId,
    per: u32,
    count: u32,
    members: Members,
    /// Inputs named by `AFTER`, with their value at the last update.
    after: Vec<(SlotId, bool)>,
    /// REGIST on the axes' fast inputs.
    regist: RegistAxes,
    /// The servo loop of each axis of `configs` (`None`: ideal).
    servos: Vec<Option<servo::AxisLoop>>,
}

const SENSORS: [Sensor; 3] = [Sensor::Zref, Sensor::Asen, Sensor::Bsen];

impl Orion {
    /// The DSP axes `configs` (machine.toml `[axis.N]`) with their scenario marks and start
    /// positions.
    pub fn new(
        registry: &Registry,
        axes_set_up: &[AxisSetUp],
        marks: &[MarkTrack],
        servo_update: f64,
    ) -> Result<Orion, String> {
        let axes = registry.of(Kind::Axis);
        let configs: Vec<DspAxisConfig> = axes_set_up.iter().map(|a| a.config.clone()).collect();
        let defaults: Vec<MoveDefaults> = axes_set_up.iter().map(|a| a.defaults).collect();
        let mut dsp = DspAxes::new(&configs).map_err(|e| e.0)?;
        let mut fast = Vec::new();
        for m in marks {
            match m.input {
                MarkInput::Card(sensor) => dsp
                    .add_marks(
                        m.axis,
                        dsp::card_of(m.axis),
                        sensor,
                        m.positions.clone(),
                        m.width,
                    )
                    .map_err(|e| e.0)?,
                MarkInput::Fast { on_time } => {
                    fast.push(FastTrack::new(m.axis, m.positions.clone(), on_time))
                }
            }
        }
        let mut regist = RegistAxes::new(&configs, fast, servo_update)?;
        for a in axes_set_up {
            if let Some(slot) = a.fast_input {
                regist.wire_fast_input(a.config.number, slot)?;
            }
        }
        Ok(Orion {
            dsp,
            defined: configs
                .iter()
                .filter(|c| (1..=16).contains(&c.number))
                .fold(0, |m, c| m | 1 << (c.number - 1)),
            configs,
            defaults,
            base: axes.base,
            per: AXIS_TYPE.members.len() as u32,
            count: axes.count,
            members: MEMBERS,
            after: Vec::new(),
            regist,
            servos: axes_set_up
                .iter()
                .map(|a| a.servo.map(servo::AxisLoop::new))
                .collect(),
        })
    }

    /// The position axis `i` reports: continuous, re-referenced, rolled over at POS.MOD@.
    fn reported(&self, i: usize) -> Result<f64, String> {
        let n = self.configs[i].number;
        let p = self.dsp.position(n).map_err(|e| e.0)? + self.regist.reference(i);
        let m = self.dsp.pos_mod(n).map_err(|e| e.0)?;
        Ok(if m > 0.0 { p.rem_euclid(m) } else { p })
    }

    /// The control loop's part for the DSP axes: AFTER inputs, then motion to `now`, latches
    /// and status into the slots.
    fn generate(&mut self, v: &mut [f64], now: &mut Now<'_>) -> Result<(), String> {
        let t = now.seconds();
        for (slot, last) in &mut self.after {
            let on = v[*slot as usize] != 0.0;
            if on && !*last {
                self.dsp.trigger(*slot, t).map_err(|e| e.0)?;
            }
            *last = on;
        }
        let events = self.dsp.advance(t).map_err(|e| e.0)?;
        self.regist.update(&mut self.dsp, t, now.activity, now)?;
        for e in events {
            match e {
                DspEvent::Latched {
                    axis,
                    which,
                    time,
                    position,
                    ..
                } => now.trace.emit(
                    now.tick,
                    &Event::Latch {
                        axis,
                        sensor: which.name().into(),
                        time,
                        position,
                    },
                ),
                // Shown like a drive's motion start: the pacer (master) and axis positions at
                // the edge, as reported (rolled over at POS.MOD@ the way `Axis.N.Position` is).
                DspEvent::StartedOnEdge {
                    axis,
                    pacer,
                    position,
                    ..
                } => {
                    let i = self.configs.iter().position(|c| c.number == axis);
                    let reported = |i: usize, p: f64| {
                        let p = p + self.regist.reference(i);
                        let m = self.dsp.pos_mod(self.configs[i].number).unwrap_or(0.0);
                        if m > 0.0 {
                            p.rem_euclid(m)
                        } else {
                            p
                        }
                    };
                    let pacer_index = self.configs.get(i.unwrap_or(usize::MAX)).and_then(|c| {
                        c.pacer
                            .and_then(|p| self.configs.iter().position(|d| d.number == p))
                    });
                    now.trace.emit(
                        now.tick,
                        &Event::Motion {
                            object: format!("Axis.{axis}").into(),
                            phase: MotionPhase::Start {
                                master: pacer_index.map_or(pacer, |j| reported(j, pacer)),
                                position: i.map_or(position, |i| reported(i, position)),
                            },
                        },
                    )
                }
                DspEvent::EdgeBlinded { card, which, time } => now.trace.emit(
                    now.tick,
                    &Event::Blinded {
                        card,
                        sensor: which.name().into(),
                        time,
                    },
                ),
                _ => {}
            }
        }
        for i in 0..self.configs.len() {
            let n = self.configs[i].number;
            let m = self.members;
            self.regist
                .note_position(i, self.dsp.position(n).map_err(|e| e.0)?);
            let put = |v: &mut [f64], member: u32, x: f64| {
                if let Some(s) =
                    (n >= 1 && n <= self.count).then(|| self.base + (n - 1) * self.per + member)
                {
                    v[s as usize] = x;
                }
            };
            let reported = self.reported(i)?;
            put(v, m.position, reported);
            put(v, m.velocity, self.dsp.velocity(n).map_err(|e| e.0)?);
            put(
                v,
                m.ratio,
                self.dsp.ratio(n).map_err(|e| e.0)?.unwrap_or(0.0),
            );
            put(v, m.dsp_done, f64::from(self.dsp.done(n).map_err(|e| e.0)?));
            for (k, sensor) in SENSORS.iter().enumerate() {
                let latched = self.dsp.latched(n, *sensor).map_err(|e| e.0)?;
                put(v, m.latched[k], f64::from(latched));
                put(
                    v,
                    m.latched_position[k],
                    self.dsp.latched_position(n, *sensor).map_err(|e| e.0)?,
                );
            }
            self.servo_update(i, reported, v, now)?;
        }
        Ok(())
    }
}

impl Orion {
    /// Why `mask`, which [`AxisSet::axes_of`] refused, is not a set of this machine's axes.
    #[cold]
    #[inline(never)]
    fn not_axes(&self, mask: f64) -> String {
        if !(mask.fract() == 0.0 && (0.0..65536.0).contains(&mask)) {
            return format!("{mask} is not an axis set");
        }
        let bits = mask as u16;
        if bits == 0 {
            return "the axis set is empty (was the axis variable assigned?)".into();
        }
        // `axes_of` refused a whole nonzero mask: one of its bits is an undefined axis.
        let n = (bits & !self.defined).trailing_zeros() + 1;
        format!("axis {n} is not defined in machine.toml ([axis.{n}])")
    }
}

impl AxisSet for Orion {
    /// The axis numbers in an axis-set value, checked against the machine.
    fn axes_of(&self, mask: f64) -> Result<crate::devices::Axes, String> {
        // Every controller-variable read comes here: the usual case in three tests (`as`
        // saturates, so a fraction, a negative, NaN or a value past 16 bits fails the first),
        // the reason for anything else away from it.
        let bits = mask as u16;
        if f64::from(bits) == mask && bits != 0 && bits & !self.defined == 0 {
            return Ok(crate::devices::Axes(bits));
        }
        Err(self.not_axes(mask))
    }

    /// The slot of `member` (an index into the Axis members) of axis `n`.
    fn slot(&self, n: u32, member: u32) -> Option<SlotId> {
        (n >= 1 && n <= self.count).then(|| self.base + (n - 1) * self.per + member)
    }

    fn layout(&self) -> crate::devices::AxisLayout {
        crate::devices::AxisLayout {
            defined: self.defined,
            base: self.base,
            per: self.per,
            count: self.count,
        }
    }

    /// A program writes a string to a controller variable of axis `n` (`SENS.MODE@`).
    fn write_text(
        &mut self,
        n: u32,
        member: u32,
        text: &str,
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        if self.slot(n, member).is_none() {
            return Err(format!("axis {n} is not defined in machine.toml"));
        }
        if member != crate::member_index!(AXIS_TYPE, "SensMode") as u32 {
            return Err("this controller variable takes a number, not a string".into());
        }
        self.dsp.set_sens_mode(n, text).map_err(|e| e.0)?;
        now.trace.emit(
            now.tick,
            &Event::SensMode {
                axis: n,
                mode: text.to_ascii_uppercase().into(),
            },
        );
        Ok(())
    }

    /// A program writes a controller variable of axis `n`.
    fn write(
        &mut self,
        hook: Hook,
        n: u32,
        member: u32,
        value: f64,
        v: &mut [f64],
        _now: &mut Now<'_>,
    ) -> Result<(), String> {
        let Some(slot) = self.slot(n, member) else {
            return Err(format!("axis {n} is not defined in machine.toml"));
        };
        let name = crate::registry::catalog::find_type("Axis")
            .and_then(|d| d.members.get(member as usize))
            .map_or("?", |m| m.name);
        match hook {
            Hook::AxisLatch => {
                if value != 0.0 {
                    return Err(format!(
                        "Axis.{n}.{name}: a latch is only re-armed, by writing 0"
                    ));
                }
                let which = SENSORS[self
                    .members
                    .latched
                    .iter()
                    .position(|&m| m == member)
                    .unwrap_or(1)];
                self.dsp.clear_latch(n, which).map_err(|e| e.0)?;
            }
            _ => {
                let r = match name {
                    "FaultReset" => {
                        if value != 0.0 {
                            self.servo_reset(n, v)?;
                        }
                        return Ok(());
                    }
                    "PosMod" => self.dsp.set_pos_mod(n, value),
                    "PlsMod" => self.dsp.set_pls_mod(n, value),
                    "SensMode" => {
                        return Err(format!(
                            "SENS.MODE@ needs a string such as \"RRRNN\", not {value}"
                        ))
                    }
                    pls => {
                        let k = pls.as_bytes().get(3).map_or(0, |c| u32::from(c - b'0'));
                        if pls.ends_with("Low") {
                            self.dsp.set_pls_low(n, k, value)
                        } else {
                            self.dsp.set_pls_high(n, k, value)
                        }
                    }
                };
                r.map_err(|e| e.0)?;
            }
        }
        v[slot as usize] = value;
        Ok(())
    }

    /// A motion statement on the axes of `mask`. `Ok(false)`: a queue is full, retry later.
    /// `Ok(true)` and a message: accepted, with a warning to show.
    fn motion(
        &mut self,
        cmd: MotionCmd,
        mask: f64,
        args: &[f64; 4],
        v: &mut [f64],
    ) -> Result<(bool, Option<String>), String> {
        let axes = self.axes_of(mask)?;
        if let Some(n) = axes.iter().find(|&n| self.servo_faulted(n)) {
            // A faulted axis takes no motion until Axis.N.FaultReset: the statement is
            // dropped, as a drive with its power stage off ignores commands.
            return Ok((
                true,
                Some(format!(
                    "axis {n} has a following-error fault: the motion statement is ignored until Axis.{n}.FaultReset"
                )),
            ));
        }
        for n in axes.iter() {
            let depth = self
                .configs
                .iter()
                .find(|c| c.number == n)
                .map_or(0, |c| c.queue_depth);
            if self.dsp.queued(n).map_err(|e| e.0)? >= depth {
                return Ok((false, None));
            }
        }
        let arg = |i: usize| args.get(i).copied().unwrap_or(0.0);
        let mut warning = None;
        for n in axes.iter() {
            let q = match cmd {
                MotionCmd::GearAt { pacer, after } => {
                    let after = match after {
                        GearAfter::Now => None,
                        GearAfter::Input => {
                            let slot = arg(3) as u32;
                            if !self.after.iter().any(|(s, _)| *s == slot) {
                                self.after.push((slot, false));
                            }
                            Some(After::Input(slot))
                        }
                        GearAfter::Sensor(which) => Some(After::Sensor(which)),
                    };
                    self.dsp
                        .gear_at(n, arg(0), arg(1), pacer.then(|| arg(2)), after)
                        .map_err(|e| e.0)?
                }
                MotionCmd::GearFor => self.dsp.gear_for(n, arg(0), arg(1)).map_err(|e| e.0)?,
                MotionCmd::MoveAt { time } => self
                    .dsp
                    .move_at(n, arg(0), if time { arg(1) } else { 0.0 })
                    .map_err(|e| e.0)?,
                MotionCmd::MovePos {
                    relative,
                    speed,
                    time,
                } => self.move_to(
                    n,
                    relative,
                    arg(0),
                    speed.then(|| arg(1)),
                    time.then(|| arg(2)),
                )?,
            };
            match q {
                Queued::Full => return Ok((false, None)),
                Queued::AcceptedAsStep => {
                    warning = Some(format!(
                        "GEAR FOR {} IN 0 on axis {n}: a pacer distance of 0 applies the \
                         correction as a step at the next update",
                        number_text(arg(0))
                    ));
                }
                Queued::Accepted => {}
            }
            // DSP.DONE@ reads false as soon as a move is queued, not from the next update.
            if let Some(slot) = self.slot(n, self.members.dsp_done) {
                v[slot as usize] = f64::from(self.dsp.done(n).map_err(|e| e.0)?);
            }
        }
        Ok((true, warning))
    }

    fn call(&mut self, func: KernelFunc, args: &[f64], now: &mut Now<'_>) -> Result<f64, String> {
        self.regist.call(func, args, now)
    }
}

impl Device for Orion {
    fn name(&self) -> &'static str {
        "DSP axes"
    }

    fn describe(&self) -> &'static str {
        "MotionBASIC DSP axes"
    }

    fn serves(&self, hook: Hook) -> bool {
        matches!(hook, Hook::AxisLatch | Hook::AxisSetting)
    }

    fn update(&mut self, v: &mut [f64], now: &mut Now<'_>) -> Result<(), String> {
        self.generate(v, now)
    }

    /// A member of `Axis.N` written by name (`Axis.2.PosMod`, from PowerTools or an
    /// assignment).
    fn write(
        &mut self,
        target: Target,
        value: f64,
        _when: When,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        let n = target.instance + 1;
        let first = AxisSet::slot(self, n, 0).unwrap_or(target.slot);
        let member = target.slot.saturating_sub(first);
        AxisSet::write(self, target.hook, n, member, value, v, now)
    }

    fn act(
        &mut self,
        target: Target,
        _start: StartRef,
        _profile: u8,
        _when: When,
        _v: &mut [f64],
        _now: &mut Now<'_>,
    ) -> Result<ActOutcome, String> {
        Err(format!("{:?} is not an action", target.hook))
    }

    /// `Stop` or an I/O fault: each axis ramps to rest at its `[axis.N] accel` (the
    /// deceleration of its MOVE TO/FOR), pacers and time-based axes by their own ramp, geared
    /// axes with their pacer.
    fn stop_all(&mut self, _v: &mut [f64], now: &mut Now<'_>) {
        for (c, d) in self.configs.iter().zip(&self.defaults) {
            if let Err(e) = self.dsp.stop(c.number, d.accel) {
                now.trace.machine_warning(now.tick, e.0);
            }
        }
    }

    fn moving(&self, _master_moves: bool, out: &mut Vec<crate::devices::Moving>) {
        for c in &self.configs {
            if let Ok(Some(settles)) = self.dsp.motion_state(c.number) {
                out.push(crate::devices::Moving {
                    name: format!("Axis.{}", c.number),
                    settles,
                });
            }
        }
    }

    fn axes(&mut self) -> Option<&mut dyn AxisSet> {
        Some(self)
    }

    fn poll(&self, func: KernelFunc, args: &[f64]) -> Option<f64> {
        self.regist.poll(func, args)
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

fn number_text(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x}")
    }
}
