//! The commands programs give devices, in the devices' own terms: where a motion starts, a
//! MotionBASIC motion statement, a kernel function. The front end compiles program text to
//! these; the devices never see program text.

use super::orion::dsp::Sensor;

/// Where a motion initiate starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartRef {
    /// Now.
    Now,
    /// `Using Last`.
    Last,
    /// `Using Capture.N` (capture instance index).
    Capture(u16),
}

/// A MotionBASIC motion statement; its operands are in consecutive registers from `args`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionCmd {
    /// `GEAR … AT out TO in [IN pacer] [AFTER input|sensor]`: args out, in, pacer, and for
    /// an input its slot.
    GearAt { pacer: bool, after: GearAfter },
    /// `GEAR … FOR dist IN pacer`: args dist, pacer.
    GearFor,
    /// `MOVE … AT speed [IN time]`: args speed, time.
    MoveAt { time: bool },
    /// `MOVE … TO|FOR pos [AT speed] [IN time]`: args pos, speed, time.
    MovePos {
        relative: bool,
        speed: bool,
        time: bool,
    },
}

/// What a `GEAR … AT` waits for before it starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GearAfter {
    /// Nothing: it starts when it reaches the head of its axis's queue.
    Now,
    /// A drive or module input's rising edge; its slot is the last operand.
    Input,
    /// The next edge of this sensor of the axis's own DSP card (`AFTER ZREF|ASEN|BSEN`).
    Sensor(Sensor),
}

/// A function served by the kernel (it reads or changes machine state), callable from both
/// dialects: `OK = REGIST(EN, AXIS, DIST, TOLR, IGNR, LGTH, DIM)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KernelFunc {
    /// `REGIST(EN, AXIS, DIST, TOLR, IGNR, LGTH, DIM)` → OK.
    Regist,
    /// `STATUSSV(AXIS)` → the registration status bits.
    StatusSv,
    /// `READ_SV(AXIS, VAR)` → a servo variable.
    ReadSv,
    /// `WRITE_SV(AXIS, VAR, VALUE)` → OK.
    WriteSv,
}

/// What a motion's progress is measured in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Domain {
    /// Seconds.
    Time,
    /// Master units.
    Master,
}
