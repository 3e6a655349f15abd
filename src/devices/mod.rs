//! The device models of a machine behind one interface, [`Device`], and the vocabulary programs
//! use to command them. Each device is one folder: a pure model and the adapter that binds it to
//! the machine's members (`drive` the PowerTools servo drive with its profiles and objects,
//! `orion` the ORMEC ORION DSP axes with `regist` on their fast inputs, `pickplace` the Lenze
//! Track Pick & Place module). A new controller family is one new folder and one line in
//! [`Devices::new`]'s caller.
//!
//! The devices never depend on the front end (syntax, check, compile): the front end depends
//! on them.
//!
//! Each update, [`Devices::update`] runs every device's part of the control loop in the order
//! the machine lists them (the drive, the DSP axes, pick & place), then [`Devices::derive`]
//! lets each derive its status from where everything now stands (queue compares, PLS windows,
//! timers).

pub mod bind;
pub mod command;
pub mod drive;
pub mod orion;
pub mod pickplace;
pub mod regist;
pub mod servo;

use crate::registry::{Hook, SlotId};
use crate::trace::Trace;
use crate::world::master::MasterProfile;
use crate::world::{Edge, InputActivity};
use command::{Domain, KernelFunc, MotionCmd, StartRef};
use std::any::Any;

/// What an action did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActOutcome {
    /// Done; the program goes on.
    Done,
    /// Motion is running on that profile: the program waits and retries.
    ProfileBusy,
}

/// When a write or an action takes effect.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum When {
    /// At this update (a program's statement).
    Now,
    /// At an input's edge inside this update, at this exact time in seconds (an assignment
    /// from an input: captures latch there, a latching input starts its motion there).
    Edge(f64),
}

/// A member a program or an assignment writes or acts on, as the compiler resolved it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Target {
    /// What the write does.
    pub hook: Hook,
    /// The member's slot.
    pub slot: SlotId,
    /// Its object's instance (0-based), or [`crate::registry::GLOBAL_INSTANCE`].
    pub instance: u32,
}

/// Everything the devices need from the moment.
pub struct Now<'a> {
    /// The update being computed.
    pub tick: u64,
    /// Its time in nanoseconds.
    pub time_ns: u64,
    /// Update period in nanoseconds.
    pub tick_ns: u64,
    /// Master position at this update.
    pub master: f64,
    /// The master axis at any instant (edges inside the update are exact).
    pub master_profile: &'a MasterProfile,
    /// The inputs' edges inside this update, with their exact times.
    pub activity: &'a [InputActivity],
    /// The trace.
    pub trace: &'a mut Trace,
}

impl Now<'_> {
    /// The time of this update, seconds.
    pub fn seconds(&self) -> f64 {
        self.time_ns as f64 / 1e9
    }

    /// The master's position at `t` seconds.
    pub fn master_at(&self, t: f64) -> f64 {
        self.master_profile.position(t)
    }

    /// The master's speed at this update.
    pub fn master_speed(&self) -> f64 {
        self.master_profile.speed(self.seconds())
    }
}

/// A device model bound to a machine's members.
pub trait Device: Send {
    /// Its name in messages: the place a run-time error of the device is reported at.
    fn name(&self) -> &'static str;

    /// What it is, for a user ("MotionBASIC DSP axes").
    fn describe(&self) -> &'static str {
        self.name()
    }

    /// It reaches a safe state on an I/O fault ([`Device::stop_all`] brings its motion to
    /// rest, [`Device::hold`] holds it): only such a device may run on real I/O.
    fn safe_state(&self) -> bool {
        true
    }

    /// Whether it reacts to writes of members with `hook`.
    fn serves(&self, hook: Hook) -> bool;

    /// Bring derived members in line with the initial values, before the first update.
    fn start(&mut self, _v: &mut [f64]) {}

    /// Its part of the control loop: advance its motion to this update and set its members.
    fn update(&mut self, v: &mut [f64], now: &mut Now<'_>) -> Result<(), String>;

    /// Status derived once every device has moved (queue compares, PLS windows, timers).
    fn derive(&mut self, _v: &mut [f64], _now: &mut Now<'_>) {}

    /// Input edges it made this update (sensors on its axes), for the world's next update.
    fn take_edges(&mut self, _out: &mut Vec<Edge>) {}

    /// A program or an assignment writes `value` (already rounded to the member's type).
    fn write(
        &mut self,
        target: Target,
        value: f64,
        when: When,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<(), String>;

    /// Run an action; `start` and `profile` matter to motion initiates only.
    fn act(
        &mut self,
        target: Target,
        start: StartRef,
        profile: u8,
        when: When,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<ActOutcome, String>;

    /// `Stop` or an I/O fault: bring every motion to rest as the device does.
    fn stop_all(&mut self, _v: &mut [f64], _now: &mut Now<'_>) {}

    /// Its objects whose motion still runs (or waits to start), for the end of a run.
    /// `master_moves`: the master axis moves now or the scenario will still move it.
    fn moving(&self, _master_moves: bool, _out: &mut Vec<Moving>) {}

    /// The I/O link went down (`true`: hold everything safe) or came back.
    fn hold(&mut self, _down: bool) {}

    /// The motion profiles programs dwell on and wait for, if it has them.
    fn profiles(&mut self) -> Option<&mut dyn Profiles> {
        None
    }

    /// Its axes addressed by axis sets, if it has them.
    fn axes(&mut self) -> Option<&mut dyn AxisSet> {
        None
    }

    /// The value of a kernel function that only reads (`STATUSSV`, `READ_SV`) on arguments it
    /// accepts; `None` for anything else, which [`AxisSet::call`] then does or refuses. A
    /// registration loop polls these every scan: this way costs one call, not four.
    fn poll(&self, _func: KernelFunc, _args: &[f64]) -> Option<f64> {
        None
    }

    /// For tools and tests that look inside one device.
    fn as_any(&self) -> &dyn Any;
}

/// Motion profiles a program's dwells run on and its motion initiates wait for (the PowerTools
/// drive's profiles 0 and 1).
pub trait Profiles {
    /// A motion runs (or waits to start) on `profile`.
    fn busy(&self, profile: usize) -> bool;

    /// `Dwell For Time` / `Dwell For Master Dist`: a motion on profile 0 of `length` seconds or
    /// master units, starting now or (`Using Last`) where the last motion on it ended.
    fn dwell(
        &mut self,
        length: f64,
        domain: Domain,
        start: StartRef,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<ActOutcome, String>;
}

/// Numbered axes addressed by axis sets (the ORION DSP axes): MotionBASIC's motion statements,
/// its controller variables and the kernel functions (`REGIST` …).
pub trait AxisSet {
    /// The axis numbers in an axis-set value, checked against the machine.
    fn axes_of(&self, mask: f64) -> Result<Axes, String>;

    /// The slot of member index `member` of axis `axis`.
    fn slot(&self, axis: u32, member: u32) -> Option<SlotId>;

    /// Where the axes' members live, which does not change while the machine runs.
    fn layout(&self) -> AxisLayout;

    /// A program writes a string to member index `member` of axis `axis`.
    fn write_text(
        &mut self,
        axis: u32,
        member: u32,
        text: &str,
        now: &mut Now<'_>,
    ) -> Result<(), String>;

    /// A program writes member index `member` of axis `axis`.
    fn write(
        &mut self,
        hook: Hook,
        axis: u32,
        member: u32,
        value: f64,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<(), String>;

    /// A motion statement on the axes of `mask`. `Ok((false, _))`: an axis's motion queue is
    /// full (the statement waits); `Ok((true, Some(warning)))`: done, with a warning.
    fn motion(
        &mut self,
        cmd: MotionCmd,
        mask: f64,
        operands: &[f64; 4],
        v: &mut [f64],
    ) -> Result<(bool, Option<String>), String>;

    /// A kernel function on its arguments, which are registers of the calling program: it
    /// writes no register (its value is stored by the caller).
    fn call(&mut self, func: KernelFunc, args: &[f64], now: &mut Now<'_>) -> Result<f64, String>;
}

/// An object whose motion still runs, as a run's end reports it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Moving {
    /// The object as programs name it (`Index.1`, `axis 2`, `robot`).
    pub name: String,
    /// It comes to rest (or to its end) by itself: an index, a home, a move, a dwell, a path.
    /// A gear, a jog or a speed runs until a program or an input stops it.
    pub settles: bool,
}

/// A set of DSP axis numbers (1 to 16) checked against the machine: an axis-set value as the
/// devices take it, without allocating (a program may read `POS@` every pass of a loop).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Axes(pub u16);

impl Axes {
    /// The axis numbers, ascending.
    pub fn iter(self) -> impl Iterator<Item = u32> {
        (1..=16u32).filter(move |n| self.0 & (1 << (n - 1)) != 0)
    }

    /// How many axes.
    pub fn len(self) -> usize {
        self.0.count_ones() as usize
    }

    /// No axis.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The one axis of a set of one.
    pub fn single(self) -> Option<u32> {
        (self.len() == 1).then(|| self.0.trailing_zeros() + 1)
    }
}

/// Number of [`Hook`]s (the routing table's size).
const HOOKS: usize = Hook::ALL.len();

/// Where the members of a machine's numbered axes live: axis `n` (1 to `count`, defined when
/// bit n-1 of `defined` is set) has member `m` in slot `base + (n - 1) * per + m`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AxisLayout {
    /// The defined axes as a set.
    pub defined: u16,
    /// The slot of axis 1's first member.
    pub base: SlotId,
    /// Slots per axis.
    pub per: u32,
    /// Axes with slots.
    pub count: u32,
}

impl AxisLayout {
    /// The slot of `member` of the one axis of the axis-set value `mask`, when `mask` is a set
    /// of one defined axis; `None` for anything else, whose reason [`AxisSet::axes_of`] gives.
    #[inline]
    pub fn single_slot(&self, mask: f64, member: u32) -> Option<SlotId> {
        // `as` saturates: a fraction, a negative, NaN or a value past 16 bits fails the test.
        let bits = mask as u16;
        if f64::from(bits) != mask || !bits.is_power_of_two() || bits & !self.defined != 0 {
            return None;
        }
        let n = bits.trailing_zeros() + 1;
        (n <= self.count).then(|| self.base + (n - 1) * self.per + member)
    }
}

/// The devices of a machine, in the order they update, and which serves what.
pub struct Devices {
    list: Vec<Box<dyn Device>>,
    /// For each hook, the device that serves its writes.
    route: [Option<u8>; HOOKS],
    profiles: Option<usize>,
    axes: Option<usize>,
    /// The layout of the axes' members (`axes`), kept here for the controller-variable reads a
    /// polling loop makes every scan.
    layout: Option<AxisLayout>,
}

/// A run-time error of a device: its name and what went wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct DeviceError {
    /// The device.
    pub device: &'static str,
    /// What went wrong.
    pub message: String,
}

impl Devices {
    /// The devices `list`, in update order.
    pub fn new(mut list: Vec<Box<dyn Device>>) -> Devices {
        let mut route = [None; HOOKS];
        for &hook in Hook::ALL {
            route[hook as usize] = list.iter().position(|d| d.serves(hook)).map(|i| i as u8);
        }
        let profiles = list.iter_mut().position(|d| d.profiles().is_some());
        let axes = list.iter_mut().position(|d| d.axes().is_some());
        let layout = axes
            .and_then(|i| list.get_mut(i))
            .and_then(|d| d.axes())
            .map(|a| a.layout());
        Devices {
            list,
            route,
            profiles,
            axes,
            layout,
        }
    }

    /// Bring every device's derived members in line with the initial values.
    pub fn start(&mut self, v: &mut [f64]) {
        for d in &mut self.list {
            d.start(v);
        }
    }

    /// Every device's part of the control loop, in order; the first error stops it.
    pub fn update(&mut self, v: &mut [f64], now: &mut Now<'_>) -> Result<(), DeviceError> {
        for d in &mut self.list {
            d.update(v, now).map_err(|message| DeviceError {
                device: d.name(),
                message,
            })?;
        }
        Ok(())
    }

    /// Every device's derived status, in order.
    pub fn derive(&mut self, v: &mut [f64], now: &mut Now<'_>) {
        for d in &mut self.list {
            d.derive(v, now);
        }
    }

    /// Input edges the devices made this update.
    pub fn take_edges(&mut self, out: &mut Vec<Edge>) {
        for d in &mut self.list {
            d.take_edges(out);
        }
    }

    /// A program or an assignment writes `value` to `target`: the device serving its hook
    /// reacts; a member no device serves is stored.
    pub fn write(
        &mut self,
        target: Target,
        value: f64,
        when: When,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        match self.device_for(target.hook) {
            Some(d) => d.write(target, value, when, v, now),
            None if matches!(target.hook, Hook::AxisLatch | Hook::AxisSetting) => {
                Err("this machine has no DSP axes".into())
            }
            None => {
                v[target.slot as usize] = value;
                Ok(())
            }
        }
    }

    /// Run an action on the device serving it.
    pub fn act(
        &mut self,
        target: Target,
        start: StartRef,
        profile: u8,
        when: When,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<ActOutcome, String> {
        match self.device_for(target.hook) {
            Some(d) => d.act(target, start, profile, when, v, now),
            None => Err(format!(
                "{:?} is not an action of this machine",
                target.hook
            )),
        }
    }

    /// `Stop` or an I/O fault: every device brings its motion to rest.
    pub fn stop_all(&mut self, v: &mut [f64], now: &mut Now<'_>) {
        for d in &mut self.list {
            d.stop_all(v, now);
        }
    }

    /// Every object whose motion still runs, in device order.
    pub fn moving(&self, master_moves: bool) -> Vec<Moving> {
        let mut out = Vec::new();
        for d in &self.list {
            d.moving(master_moves, &mut out);
        }
        out
    }

    /// The I/O link went down (`true`) or came back.
    pub fn hold(&mut self, down: bool) {
        for d in &mut self.list {
            d.hold(down);
        }
    }

    /// The motion profiles of the machine (its PowerTools drive).
    pub fn profiles(&mut self) -> Option<&mut dyn Profiles> {
        self.list.get_mut(self.profiles?)?.profiles()
    }

    /// True while a motion runs (or waits to start) on `profile`.
    pub fn profile_busy(&mut self, profile: usize) -> bool {
        self.profiles().is_some_and(|p| p.busy(profile))
    }

    /// The axes of the machine addressed by axis sets (its DSP axes).
    pub fn axes(&mut self) -> Option<&mut dyn AxisSet> {
        self.list.get_mut(self.axes?)?.axes()
    }

    /// A polled kernel function's value (see [`Device::poll`]).
    #[inline]
    pub fn poll(&self, func: KernelFunc, args: &[f64]) -> Option<f64> {
        self.list.get(self.axes?)?.poll(func, args)
    }

    /// Where the members of [`Devices::axes`] live.
    #[inline]
    pub fn axis_layout(&self) -> Option<&AxisLayout> {
        self.layout.as_ref()
    }

    /// The device of type `T`, if the machine has one (tools and tests look inside).
    pub fn get<T: Any>(&self) -> Option<&T> {
        self.list
            .iter()
            .find_map(|d| d.as_any().downcast_ref::<T>())
    }

    /// A device reacts to writes with `hook` (otherwise a write only stores the value).
    pub fn reacts(&self, hook: Hook) -> bool {
        self.route.get(hook as usize).copied().flatten().is_some()
    }

    fn device_for(&mut self, hook: Hook) -> Option<&mut Box<dyn Device>> {
        let i = self.route.get(hook as usize).copied().flatten()?;
        self.list.get_mut(usize::from(i))
    }
}

#[cfg(test)]
mod tests {
    use super::AxisLayout;

    /// Axes 1, 2 and 4 defined of 4, 10 slots each from slot 100.
    const LAYOUT: AxisLayout = AxisLayout {
        defined: 0b1011,
        base: 100,
        per: 10,
        count: 4,
    };

    #[test]
    fn a_set_of_one_defined_axis_reads_its_slot() {
        assert_eq!(LAYOUT.single_slot(1.0, 3), Some(103));
        assert_eq!(LAYOUT.single_slot(2.0, 0), Some(110));
        assert_eq!(LAYOUT.single_slot(8.0, 9), Some(139));
    }

    /// Everything else goes the long way, which says why it is refused (or reads a set).
    #[test]
    fn any_other_set_is_left_to_the_long_way() {
        for mask in [
            0.0,
            3.0,  // two axes
            4.0,  // axis 3, not defined
            1.5,  // a fraction
            -1.0, // negative
            f64::NAN,
            65536.0, // past 16 bits
            -0.0,
        ] {
            assert_eq!(LAYOUT.single_slot(mask, 0), None, "{mask}");
        }
        // Defined but without slots.
        let short = AxisLayout { count: 1, ..LAYOUT };
        assert_eq!(short.single_slot(2.0, 0), None);
    }
}
