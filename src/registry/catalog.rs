//! The catalog of object types: every object a program can name, with its members.
//! This table is the single source the checker, compiler, kernel, trace and docs read.

/// The value type of a member.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ValueType {
    /// ON/OFF.
    Bit,
    /// A signed 32-bit integer.
    Integer,
    /// A signed 32-bit fixed-point value with this many decimal places.
    Fixed(u8),
    /// A real quantity (positions, velocities, times) kept at full precision.
    Real,
}

impl ValueType {
    /// True for a bit.
    pub fn is_bit(self) -> bool {
        self == ValueType::Bit
    }

    /// Human name used in messages.
    pub fn describe(self) -> String {
        match self {
            ValueType::Bit => "a bit".into(),
            ValueType::Integer => "an integer".into(),
            ValueType::Fixed(0) => "an integer".into(),
            ValueType::Fixed(d) => format!("a number with {d} decimal places"),
            ValueType::Real => "a number".into(),
        }
    }
}

/// Defines [`Hook`] and [`Hook::ALL`] from one list, so no hook can be left out of the devices'
/// routing table.
macro_rules! hooks {
    ($($(#[$doc:meta])* $variant:ident,)*) => {
        /// What happens when a program writes a member: which device reacts, and how.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[allow(missing_docs)]
        pub enum Hook {
            $($(#[$doc])* $variant,)*
        }

        impl Hook {
            /// Every hook, in declaration order (`ALL[h as usize] == h`).
            pub const ALL: &'static [Hook] = &[$(Hook::$variant,)*];
        }
    };
}

hooks! {
    /// Only stored; the kernel reads the stored value when it needs it.
    Store,
    OutputWrite,
    ProgramInitiate,
    ProgramStop,
    TimerInitiate,
    TimerStop,
    QueueDataIn,
    QueueOffset,
    QueueCompareEnable,
    QueueRemove,
    QueueClear,
    QueueFullLevel,
    CaptureEnable,
    CaptureActivate,
    CaptureClear,
    /// Starts a motion object (Index/Home/Jog/Gear initiate).
    MotionStart,
    /// Stops a motion object.
    MotionStop,
    /// A level input of a motion object (sensor trigger, jog/gear activate).
    MotionInput,
    /// `Stop`: programs and motion.
    StopAll,
    FeedRateOverride,
    /// Clears an index's ProfileLimited (`Index.N.ResetProfileLimited`).
    ProfileLimitedReset,
    /// Clears the drive's fault (`FaultReset`).
    FaultReset,
    /// Re-arms a DSP axis latch (`ASEN@(axis) = 0`).
    AxisLatch,
    /// A DSP axis setting the kernel applies at once (POS.MOD@, PLS…@, SENS.MODE@).
    AxisSetting,
    /// An input or parameter of the pick & place module or one of its belts: stored, and a
    /// rising edge of an edge-controlled input is remembered until the module's next cycle.
    PickPlace,
}

/// How a program may use a member.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Status: programs read it, the kernel writes it.
    Read,
    /// Setting or data: programs read and write it.
    ReadWrite,
    /// An action: a bare statement, or assigned ON to trigger. Not readable.
    Action,
    /// A write-only input that takes a value (e.g. `Queue.0.DataIn=x`). Not readable.
    Input,
}

/// One member of an object type.
#[derive(Debug, Clone, Copy)]
pub struct MemberDef {
    /// Canonical name.
    pub name: &'static str,
    /// Older or alternative names that mean the same member.
    pub aliases: &'static [&'static str],
    /// Value type (for actions: the type of value an assignment passes).
    pub ty: ValueType,
    /// How programs may use it.
    pub access: Access,
    /// What the kernel does when a program writes it; [`Hook::Store`] when it only stores.
    pub hook: Hook,
    /// Continuously moving (positions, timers): not traced as `change` events.
    pub continuous: bool,
    /// Value at the start of a run, unless the machine file sets another.
    pub initial: f64,
    /// Computed from other members that are traced (`Index.ProfileLimited` from each
    /// `Index.N.ProfileLimited`): not traced itself, so a trace says which index set it.
    pub derived: bool,
    /// One line of documentation.
    pub doc: &'static str,
}

/// How the instances of an object type are numbered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Instances {
    /// One global object: `FeedRateOverride`, `Gear.Initiate`.
    Global,
    /// Numbered instances `first..first+count`; the count may be set in `machine.toml`.
    Numbered { first: u32, default_count: u32 },
    /// Instances named in `machine.toml` (`Var.Count`), numbered or named (`Bit.3`, `Bit.Ready`).
    Named,
}

/// The behaviour the kernel attaches to an object type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[allow(missing_docs)]
pub enum Kind {
    DriveInput,
    ModuleInput,
    DriveIO,
    DriveOutput,
    ModuleOutput,
    Var,
    Bit,
    Program,
    Timer,
    Queue,
    Capture,
    Index,
    Home,
    Jog,
    Gear,
    Profile,
    Pls,
    Motion,
    Axis,
    BasicVar,
    PickPlace,
    Belt,
}

/// One object type.
#[derive(Debug, Clone, Copy)]
pub struct TypeDef {
    /// Name as written in programs.
    pub name: &'static str,
    /// Behaviour.
    pub kind: Kind,
    /// Instance numbering.
    pub instances: Instances,
    /// The member meant when a name stops at the instance (`DriveInput.4`, `Var.Count`).
    pub default_member: Option<&'static str>,
    /// Members of each instance.
    pub members: &'static [MemberDef],
    /// Members of the type itself, written `Type.Member` (`Jog.Select`).
    pub global_members: &'static [MemberDef],
    /// The instances may be named by `Using Type.N` / `On Type.N`.
    pub referable: bool,
    /// One line of documentation.
    pub doc: &'static str,
}

const fn m(name: &'static str, ty: ValueType, access: Access, doc: &'static str) -> MemberDef {
    MemberDef {
        name,
        aliases: &[],
        ty,
        access,
        hook: Hook::Store,
        continuous: false,
        initial: 0.0,
        derived: false,
        doc,
    }
}

const fn hook(h: Hook, mut d: MemberDef) -> MemberDef {
    d.hook = h;
    d
}

const fn continuous(mut d: MemberDef) -> MemberDef {
    d.continuous = true;
    d
}

const fn derived(mut d: MemberDef) -> MemberDef {
    d.derived = true;
    d
}

const fn alias(mut d: MemberDef, aliases: &'static [&'static str]) -> MemberDef {
    d.aliases = aliases;
    d
}

use Access::{Action, Input, Read, ReadWrite};
use ValueType::{Bit, Fixed, Integer, Real};

pub const INPUT: &[MemberDef] = &[m(
    "Value",
    Bit,
    Read,
    "state of the input, sampled every update",
)];
pub const OUTPUT: &[MemberDef] = &[hook(
    Hook::OutputWrite,
    m("Value", Bit, ReadWrite, "state of the output"),
)];
pub const DRIVE_IO: &[MemberDef] = &[
    m("In", Bit, Read, "state of the point as an input"),
    hook(
        Hook::OutputWrite,
        m("Out", Bit, ReadWrite, "state of the point as an output"),
    ),
];
pub const VAR: &[MemberDef] = &[m(
    "Value",
    Fixed(0),
    ReadWrite,
    "the variable's value (decimal places set in machine.toml)",
)];
pub const BIT: &[MemberDef] = &[m("Value", Bit, ReadWrite, "the bit")];
pub const PROGRAM: &[MemberDef] = &[
    hook(
        Hook::ProgramInitiate,
        m(
            "Initiate",
            Bit,
            Action,
            "start the program on a free task (it runs beside the caller)",
        ),
    ),
    hook(
        Hook::ProgramStop,
        m("Stop", Bit, Action, "stop the program"),
    ),
    m("Running", Bit, Read, "the program is running on a task"),
    m(
        "Task",
        Integer,
        Read,
        "the task the program runs on, -1 when not running",
    ),
];
pub const TIMER: &[MemberDef] = &[
    hook(
        Hook::TimerInitiate,
        m("Initiate", Bit, Action, "start timing from 0"),
    ),
    hook(
        Hook::TimerStop,
        m("Stop", Bit, Action, "stop timing and clear the output"),
    ),
    m(
        "Preset",
        Fixed(3),
        ReadWrite,
        "time to count, seconds (Realtime) or master units (Synchronized)",
    ),
    m(
        "Synchronized",
        Bit,
        ReadWrite,
        "count master distance instead of time",
    ),
    continuous(m(
        "Elapsed",
        Fixed(6),
        Read,
        "time (or distance) counted so far",
    )),
    m("Active", Bit, Read, "timing"),
    m(
        "Output",
        Bit,
        Read,
        "on once the preset is reached, until the next Initiate or Stop",
    ),
];
pub const QUEUE: &[MemberDef] = &[
    hook(
        Hook::QueueDataIn,
        m(
            "DataIn",
            Real,
            Input,
            "push a value; its exit position is value + QueueOffset",
        ),
    ),
    m("DataOut", Real, Read, "the oldest entry's value"),
    hook(
        Hook::QueueOffset,
        m(
            "QueueOffset",
            Fixed(4),
            ReadWrite,
            "added to each entry's value to make its exit position",
        ),
    ),
    m(
        "ExitPosition",
        Real,
        Read,
        "DataOut + the current QueueOffset",
    ),
    hook(
        Hook::QueueCompareEnable,
        m(
            "QueueCompareEnable",
            Bit,
            ReadWrite,
            "compare the source with the oldest exit position",
        ),
    ),
    m(
        "QueueExit",
        Bit,
        Read,
        "the source has reached the oldest entry's exit position",
    ),
    hook(
        Hook::QueueRemove,
        m(
            "QueueRemove",
            Bit,
            Action,
            "drop the oldest entry (clears QueueExit)",
        ),
    ),
    hook(
        Hook::QueueClear,
        m("QueueClear", Bit, Action, "empty the queue"),
    ),
    m("QueueEmpty", Bit, Read, "no entries"),
    m("QueueFull", Bit, Read, "count >= FullLevel"),
    m(
        "QueueOverflow",
        Bit,
        Read,
        "a DataIn found the queue holding QueueSize entries",
    ),
    m("QueueCount", Integer, Read, "number of entries"),
    m("QueueSize", Integer, Read, "capacity (machine.toml)"),
    hook(
        Hook::QueueFullLevel,
        m(
            "FullLevel",
            Integer,
            ReadWrite,
            "count at which QueueFull turns on",
        ),
    ),
];
pub const CAPTURE: &[MemberDef] = &[
    hook(
        Hook::CaptureEnable,
        m(
            "CaptureEnable",
            Bit,
            ReadWrite,
            "arm the capture; turning it off resets it",
        ),
    ),
    hook(
        Hook::CaptureActivate,
        m(
            "CaptureActivate",
            Bit,
            ReadWrite,
            "the rising edge latches (usually assigned from a module input)",
        ),
    ),
    hook(
        Hook::CaptureClear,
        alias(
            m(
                "CaptureClear",
                Bit,
                Action,
                "re-arm and clear CaptureTriggered",
            ),
            &["CaptureReset"],
        ),
    ),
    m(
        "CaptureTriggered",
        Bit,
        Read,
        "data latched, until CaptureClear",
    ),
    m("CapturedTime", Real, ReadWrite, "time of the edge, seconds"),
    m(
        "CapturedPosnCommand",
        Real,
        ReadWrite,
        "motor command position at the edge",
    ),
    m(
        "CapturedPosnFeedback",
        Real,
        ReadWrite,
        "motor feedback position at the edge",
    ),
    m(
        "CapturedMasterPosition",
        Real,
        ReadWrite,
        "master position at the edge",
    ),
];
pub const INDEX: &[MemberDef] = &[
    hook(
        Hook::MotionStart,
        m("Initiate", Bit, Action, "start the index"),
    ),
    hook(
        Hook::MotionStop,
        m("Stop", Bit, Action, "stop the index with its deceleration"),
    ),
    hook(
        Hook::MotionInput,
        m(
            "SensorTrigger",
            Bit,
            ReadWrite,
            "registration sensor (usually assigned from an input)",
        ),
    ),
    m(
        "Distance",
        Real,
        ReadWrite,
        "distance (incremental), position (absolute), limit (registration)",
    ),
    m("Velocity", Real, ReadWrite, "velocity"),
    m("Acceleration", Real, ReadWrite, "acceleration"),
    m("Deceleration", Real, ReadWrite, "deceleration"),
    m("Time", Real, ReadWrite, "time of a timed index, seconds"),
    m(
        "RegistrationOffset",
        Real,
        ReadWrite,
        "distance after the sensor (registration index)",
    ),
    m("CommandInProgress", Bit, Read, "moving"),
    m("AtVel", Bit, Read, "at velocity"),
    m("Decelerating", Bit, Read, "on the deceleration ramp"),
    m("CommandComplete", Bit, Read, "done, until initiated again"),
    m(
        "PLSStatus",
        Bit,
        Read,
        "on while the distance travelled by the index is in [PLSOnPoint, PLSOffPoint)",
    ),
    m(
        "PLSOnPoint",
        Real,
        ReadWrite,
        "distance from the index's start where PLSStatus turns on",
    ),
    m(
        "PLSOffPoint",
        Real,
        ReadWrite,
        "distance from the index's start where PLSStatus turns off",
    ),
    m(
        "LimitDistHit",
        Bit,
        Read,
        "registration index reached its limit without a sensor",
    ),
    m(
        "ProfileLimited",
        Bit,
        Read,
        "timed index could not meet its time within the maxima; on until ResetProfileLimited",
    ),
    hook(
        Hook::ProfileLimitedReset,
        m("ResetProfileLimited", Bit, Action, "clear ProfileLimited"),
    ),
    hook(
        Hook::MotionStart,
        m(
            "CompoundInitiate",
            Bit,
            Action,
            "start the index; at its end point it runs on into the next index, initiated on the next line, without stopping",
        ),
    ),
];
/// The members of `Index` without an instance (FM-3 reference, the `Index.ProfileLimited` source).
pub const INDEX_GLOBAL: &[MemberDef] = &[
    derived(m(
        "ProfileLimited",
        Bit,
        Read,
        "on while any Index.N.ProfileLimited is on (a timed index could not meet its time)",
    )),
    hook(
        Hook::ProfileLimitedReset,
        m(
            "ResetProfileLimited",
            Bit,
            Action,
            "clear the ProfileLimited of every index",
        ),
    ),
];
pub const HOME: &[MemberDef] = &[
    hook(
        Hook::MotionStart,
        m("Initiate", Bit, Action, "start homing"),
    ),
    hook(Hook::MotionStop, m("Stop", Bit, Action, "stop homing")),
    m("Velocity", Real, ReadWrite, "home velocity"),
    m("Acceleration", Real, ReadWrite, "acceleration"),
    m("Deceleration", Real, ReadWrite, "deceleration"),
    m(
        "Offset",
        Real,
        ReadWrite,
        "specified offset after the reference",
    ),
    m("CommandInProgress", Bit, Read, "homing"),
    m("AtVel", Bit, Read, "at home velocity"),
    m("CommandComplete", Bit, Read, "homed"),
];
pub const JOG: &[MemberDef] = &[
    hook(
        Hook::MotionStart,
        m("PlusInitiate", Bit, Action, "jog in the plus direction"),
    ),
    hook(
        Hook::MotionStart,
        m("MinusInitiate", Bit, Action, "jog in the minus direction"),
    ),
    hook(Hook::MotionStop, m("Stop", Bit, Action, "stop jogging")),
    m("Velocity", Real, ReadWrite, "jog velocity"),
    m("Acceleration", Real, ReadWrite, "acceleration"),
    m("Deceleration", Real, ReadWrite, "deceleration"),
    m("CommandInProgress", Bit, Read, "jogging"),
];
pub const JOG_GLOBAL: &[MemberDef] = &[
    m(
        "Select",
        Bit,
        ReadWrite,
        "off: Jog.0 settings, on: Jog.1 settings",
    ),
    hook(
        Hook::MotionInput,
        m("PlusActivate", Bit, ReadWrite, "jog plus while on"),
    ),
    hook(
        Hook::MotionInput,
        m("MinusActivate", Bit, ReadWrite, "jog minus while on"),
    ),
];
pub const AXIS: &[MemberDef] = &[
    continuous(m(
        "Position",
        Real,
        Read,
        "commanded position (modulo PosMod when set)",
    )),
    continuous(m("Velocity", Real, Read, "commanded velocity, units/s")),
    m(
        "Ratio",
        Real,
        Read,
        "gear ratio, follower units per pacer unit",
    ),
    m(
        "DspDone",
        Bit,
        Read,
        "no move in progress or queued (DSP.DONE@)",
    ),
    hook(
        Hook::AxisLatch,
        m("Zref", Bit, ReadWrite, "ZREF latched; write 0 to re-arm"),
    ),
    hook(
        Hook::AxisLatch,
        m("Asen", Bit, ReadWrite, "ASEN latched; write 0 to re-arm"),
    ),
    hook(
        Hook::AxisLatch,
        m("Bsen", Bit, ReadWrite, "BSEN latched; write 0 to re-arm"),
    ),
    m("PosZref", Real, Read, "position latched by ZREF"),
    m("PosAsen", Real, Read, "position latched by ASEN"),
    m("PosBsen", Real, Read, "position latched by BSEN"),
    hook(
        Hook::AxisSetting,
        m(
            "PosMod",
            Real,
            ReadWrite,
            "rollover of reported positions (0: none)",
        ),
    ),
    hook(
        Hook::AxisSetting,
        m("PlsMod", Real, ReadWrite, "cycle length of the PLS"),
    ),
    hook(
        Hook::AxisSetting,
        m("Pls1Low", Real, ReadWrite, "PLS1 turn-on point"),
    ),
    hook(
        Hook::AxisSetting,
        m("Pls1High", Real, ReadWrite, "PLS1 turn-off point"),
    ),
    hook(
        Hook::AxisSetting,
        m("Pls2Low", Real, ReadWrite, "PLS2 turn-on point"),
    ),
    hook(
        Hook::AxisSetting,
        m("Pls2High", Real, ReadWrite, "PLS2 turn-off point"),
    ),
    hook(
        Hook::AxisSetting,
        m("Pls3Low", Real, ReadWrite, "PLS3 turn-on point"),
    ),
    hook(
        Hook::AxisSetting,
        m("Pls3High", Real, ReadWrite, "PLS3 turn-off point"),
    ),
    // Holds the index of a string: traced as a `sens_mode` event with the text instead.
    continuous(hook(
        Hook::AxisSetting,
        m(
            "SensMode",
            Integer,
            ReadWrite,
            "sensor edges and gating, a SENS.MODE@ string",
        ),
    )),
    continuous(m(
        "Feedback",
        Real,
        Read,
        "feedback position, as Position is reported (Position itself on an ideal servo)",
    )),
    // Traced as it changes (every update a real servo lags; never with the ideal one), so a
    // trace shows what the servo did, not only the VCD.
    m(
        "FollowingError",
        Real,
        Read,
        "command minus feedback position",
    ),
    m(
        "FollowingErrorLimit",
        Real,
        ReadWrite,
        "fault above this following error",
    ),
    m(
        "FollowingErrorEnable",
        Bit,
        ReadWrite,
        "a following error above FollowingErrorLimit faults the axis",
    ),
    m(
        "FollowingErrorFault",
        Bit,
        Read,
        "the axis faulted on its following error: its motion stopped, until FaultReset",
    ),
    hook(
        Hook::AxisSetting,
        m(
            "FaultReset",
            Bit,
            ReadWrite,
            "write 1 to clear the axis's fault; its command restarts at the feedback",
        ),
    ),
];
pub const BASIC_VAR: &[MemberDef] = &[m(
    "Value",
    Real,
    ReadWrite,
    "a MotionBASIC variable (type from its suffix)",
)];
pub const GEAR: &[MemberDef] = &[
    hook(
        Hook::MotionStart,
        m("Initiate", Bit, Action, "start gearing"),
    ),
    hook(Hook::MotionStop, m("Stop", Bit, Action, "stop gearing")),
    hook(
        Hook::MotionInput,
        m("Activate", Bit, ReadWrite, "gear while on"),
    ),
    m("Ratio", Real, ReadWrite, "follower units per master unit"),
    m("CommandInProgress", Bit, Read, "gearing"),
];
pub const PROFILE: &[MemberDef] = &[m("Busy", Bit, Read, "a motion object runs on this profile")];
pub const PLS: &[MemberDef] = &[
    m("Enable", Bit, ReadWrite, "evaluate the window"),
    m(
        "OnPosn",
        Real,
        ReadWrite,
        "position where the output turns on",
    ),
    m("OffPosn", Real, ReadWrite, "position where it turns off"),
    m(
        "Direction",
        Integer,
        ReadWrite,
        "0 both, 1 plus only, -1 minus only",
    ),
    m("Status", Bit, Read, "inside the window"),
];
pub const MOTION: &[MemberDef] = &[
    hook(
        Hook::StopAll,
        m(
            "Stop",
            Bit,
            Action,
            "stop all programs and motion with StopDeceleration",
        ),
    ),
    hook(
        Hook::FeedRateOverride,
        m(
            "FeedRateOverride",
            Fixed(2),
            ReadWrite,
            "percent; scales all motion in time",
        ),
    ),
    m(
        "FeedRateDeactivate",
        Bit,
        ReadWrite,
        "on: motion runs at its programmed velocity, FeedRateOverride ignored",
    ),
    m(
        "StopDeceleration",
        Real,
        ReadWrite,
        "deceleration used by Stop",
    ),
    // Traced as it changes (every update a real servo lags; never with the ideal one), so a
    // trace shows what the servo did, not only the VCD.
    m(
        "FollowingError",
        Real,
        Read,
        "command minus feedback position",
    ),
    m(
        "FollowingErrorLimit",
        Real,
        ReadWrite,
        "fault above this following error",
    ),
    m(
        "FollowingErrorEnable",
        Bit,
        ReadWrite,
        "a following error above FollowingErrorLimit faults the drive",
    ),
    m(
        "FollowingErrorFault",
        Bit,
        Read,
        "the drive faulted on its following error: motion stopped, until FaultReset",
    ),
    hook(
        Hook::FaultReset,
        m(
            "FaultReset",
            Bit,
            Action,
            "clear the drive's fault; the command restarts at the feedback position",
        ),
    ),
    continuous(m(
        "FreeRunTime",
        Integer,
        Read,
        "microseconds since the start of the run",
    )),
    continuous(m(
        "MasterPosnFeedback",
        Real,
        Read,
        "master (encoder) position, master units",
    )),
    continuous(m(
        "MasterVelFeedback",
        Real,
        Read,
        "master velocity, master units per second",
    )),
    continuous(m(
        "PosnCommand",
        Real,
        Read,
        "motor command position (both profiles added)",
    )),
    continuous(m("PosnFeedback", Real, Read, "motor feedback position")),
    continuous(m(
        "VelFeedback",
        Real,
        Read,
        "motor feedback velocity, units per second",
    )),
    continuous(m(
        "VelCommand",
        Real,
        Read,
        "motor command velocity, units per second",
    )),
    continuous(m(
        "MotorRevs",
        Real,
        Read,
        "motor position in revolutions (feedback / units per revolution)",
    )),
    continuous(m(
        "MotorCounts",
        Integer,
        Read,
        "motor encoder position in counts",
    )),
    continuous(m(
        "MasterCounts",
        Integer,
        Read,
        "master encoder position in counts",
    )),
];

// ---------------------------------------------------------------------------------------------
// The Lenze "Track Pick & Place" module (L_TT1P_TrackPickAndPlaceBase) and its belts, under the
// manual's designators (sections 3.6.2–3.6.6). Array members are one member per element, named
// with the manual's 1-based index: `alrActPos[1]` … `alrActPos[13]`.

/// What a pick & place member is: an input or parameter programs set, or an output.
#[derive(Clone, Copy)]
enum PpClass {
    /// An input or parameter: read and written, and the module sees the write.
    Set,
    /// An output of the module (or a belt status): read only.
    Out,
    /// An output that moves continuously (positions, velocities): not traced as changes.
    Moving,
}

const fn pp(
    name: &'static str,
    ty: ValueType,
    class: PpClass,
    initial: f64,
    doc: &'static str,
) -> MemberDef {
    let mut d = m(name, ty, Read, doc);
    d.initial = initial;
    match class {
        PpClass::Set => {
            d.access = ReadWrite;
            d.hook = Hook::PickPlace;
        }
        PpClass::Out => {}
        PpClass::Moving => d.continuous = true,
    }
    d
}

/// One member per element of a manual array, named `name[k]` (k from 1), each documented with
/// the axis its index stands for: `indexed!(axes13; "alrActPos", Real, Moving, 0.0, "…")`.
macro_rules! indexed {
    (axes13; $($rest:tt)*) => {
        indexed!(@ [(1 "X") (2 "Y") (3 "Z") (4 "A") (5 "B") (6 "C") (7 "A1") (8 "A2") (9 "A3")
            (10 "A4") (11 "A5") (12 "A6") (13 "Aux1")] $($rest)*)
    };
    (real7; $($rest:tt)*) => {
        indexed!(@ [(1 "A1") (2 "A2") (3 "A3") (4 "A4") (5 "A5") (6 "A6") (7 "Aux1")] $($rest)*)
    };
    (pose6; $($rest:tt)*) => {
        indexed!(@ [(1 "X") (2 "Y") (3 "Z") (4 "A") (5 "B") (6 "C")] $($rest)*)
    };
    (@ [$(($i:literal $axis:literal))+] $name:literal, $ty:expr, $class:expr, $init:expr,
        $doc:literal) => {
        &[$(pp(
            concat!($name, "[", $i, "]"),
            $ty,
            $class,
            $init,
            concat!($doc, " (", $axis, ")"),
        )),+]
    };
}

/// The members of a type made of several lists, as one array (for the arrays `indexed!` makes).
const fn flatten<const N: usize>(parts: &[&[MemberDef]]) -> [MemberDef; N] {
    let mut out = [m("", Bit, Read, ""); N];
    let mut k = 0;
    let mut i = 0;
    while i < parts.len() {
        let mut j = 0;
        while j < parts[i].len() {
            out[k] = parts[i][j];
            k += 1;
            j += 1;
        }
        i += 1;
    }
    assert!(k == N, "flatten: the length does not match the parts");
    out
}

const fn total_len(parts: &[&[MemberDef]]) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < parts.len() {
        n += parts[i].len();
        i += 1;
    }
    n
}

use PpClass::{Moving, Out, Set};

const PICKPLACE_PARTS: &[&[MemberDef]] = &[
    // Inputs (3.6.2).
    &[
        pp("xEnable", Bit, Set, 0.0, "execute the module"),
        pp(
            "xEnableInternalControl",
            Bit,
            Set,
            0.0,
            "allow the internal control of the axes (visualisation)",
        ),
        pp(
            "xResetError",
            Bit,
            Set,
            0.0,
            "reset the errors of the axes and of the module",
        ),
        pp(
            "xRegulatorOnALL",
            Bit,
            Set,
            0.0,
            "controller enable of all axes",
        ),
        pp(
            "xPathStop",
            Bit,
            Set,
            0.0,
            "stop on the path with lrPathStopDec; READY again when off at standstill",
        ),
        pp(
            "xPathHalt",
            Bit,
            Set,
            0.0,
            "halt on the path with lrPathHaltDec; READY again when off at standstill",
        ),
        pp(
            "xStopALL",
            Bit,
            Set,
            0.0,
            "stop every axis on its own with alrStopDec, leaving the path",
        ),
        pp(
            "xGroupHomeExecute",
            Bit,
            Set,
            0.0,
            "rising edge: home the real axes in the order of aeHomingOrder",
        ),
    ],
    indexed!(real7; "axHomeAbsSwitch", Bit, Set, 0.0, "reference switch of a real axis"),
    &[pp(
        "xGroupEnableHWLimit",
        Bit,
        Set,
        0.0,
        "evaluate the hardware limit switches",
    )],
    indexed!(axes13; "axHwLimitPos", Bit, Set, 0.0, "positive hardware limit switch"),
    indexed!(axes13; "axHwLimitNeg", Bit, Set, 0.0, "negative hardware limit switch"),
    &[
        pp(
            "eSelectAxis",
            Integer,
            Set,
            0.0,
            "axis to jog: 0 none, 1–6 X Y Z A B C, 7–12 A1–A6, 13 Aux1",
        ),
        pp(
            "xJogPos",
            Bit,
            Set,
            0.0,
            "jog the selected axis in the positive direction",
        ),
        pp(
            "xJogNeg",
            Bit,
            Set,
            0.0,
            "jog the selected axis in the negative direction",
        ),
        pp(
            "xExecutePickAndPlace",
            Bit,
            Set,
            0.0,
            "rising edge: prepare and run the path (queues another profile while one runs)",
        ),
        pp(
            "eSetTarget",
            Integer,
            Set,
            0.0,
            "target in mode 0: 0 the static position, n a workpiece on belt CVn",
        ),
        pp(
            "xPathInterrupt",
            Bit,
            Set,
            0.0,
            "hold on the path; off resumes from the break point",
        ),
        pp(
            "xAbort",
            Bit,
            Set,
            0.0,
            "rising edge at standstill: abort the travel on the path",
        ),
        pp(
            "lrOverride",
            Real,
            Set,
            1.0,
            "scales speed, acceleration and jerk (1.0: none; other values turn gripper control off)",
        ),
        pp(
            "xAckGripper",
            Bit,
            Set,
            0.0,
            "rising edge: gripper acknowledged, end the synchronous travel and lift",
        ),
    ],
    indexed!(axes13; "axSwLimitEnabled", Bit, Set, 0.0, "monitor the software limit positions"),
    // Outputs (3.6.4).
    &[
        pp(
            "xInternalControlActive",
            Bit,
            Out,
            0.0,
            "internal control of the axes is active",
        ),
        pp("eTMState", Integer, Out, 0.0, "current state of the module"),
        pp("xError", Bit, Out, 0.0, "the module has an error"),
        pp("xWarning", Bit, Out, 0.0, "the module has a warning"),
        pp(
            "eErrorID",
            Integer,
            Out,
            0.0,
            "number of the error or warning",
        ),
        pp("xAxesEnabled", Bit, Out, 0.0, "all axes are enabled"),
        pp("xAxesGroupEnabled", Bit, Out, 0.0, "the axes group is enabled"),
        pp(
            "xDone",
            Bit,
            Out,
            0.0,
            "the request has been completed successfully",
        ),
        pp("xBusy", Bit, Out, 0.0, "a request is being executed"),
        pp(
            "xAxesGroupHomed",
            Bit,
            Out,
            0.0,
            "all axes have been referenced",
        ),
        pp(
            "xInPosition",
            Bit,
            Out,
            0.0,
            "the tool centre point has reached its position (in the window if xPosInWindow)",
        ),
        pp(
            "xHwLimitSwitchActive",
            Bit,
            Out,
            0.0,
            "an axis has reached a hardware limit switch",
        ),
        pp(
            "xSwLimitSwitchActive",
            Bit,
            Out,
            0.0,
            "an axis has reached a software limit position",
        ),
    ],
    indexed!(axes13; "axHwLimitSwitchNeg", Bit, Out, 0.0, "at the negative hardware limit switch"),
    indexed!(axes13; "axHwLimitSwitchPos", Bit, Out, 0.0, "at the positive hardware limit switch"),
    indexed!(axes13; "axSwLimitSwitchActive", Bit, Out, 0.0, "at a software limit position"),
    &[
        pp(
            "xPathHold",
            Bit,
            Out,
            0.0,
            "the path interpolation is stopped and can be continued",
        ),
        pp("xGripperCtrlActive", Bit, Out, 0.0, "gripper control is active"),
        pp(
            "xPulseGripper",
            Bit,
            Out,
            0.0,
            "gripper pulse, on for one cycle",
        ),
        pp(
            "lrSetPathVelOut",
            Real,
            Moving,
            0.0,
            "current setpoint path speed, units/s",
        ),
        pp(
            "lrPathPreparationTime",
            Real,
            Out,
            0.0,
            "time the path preparation took, s",
        ),
        pp(
            "lrPreCalcProfileTime",
            Real,
            Out,
            0.0,
            "calculated travel time of the profile to run, s",
        ),
    ],
    indexed!(axes13; "alrActPos", Real, Moving, 0.0, "current position of the axis, units"),
    indexed!(axes13; "alrActVel", Real, Moving, 0.0, "current velocity of the axis, units/s"),
    &[
        pp(
            "iProfilePointPassed",
            Integer,
            Out,
            0.0,
            "number of the last point reached in the current profile",
        ),
        pp(
            "xProfileInPreparation",
            Bit,
            Out,
            0.0,
            "a profile is being prepared (off: another can be added)",
        ),
        pp(
            "xAccDecSync",
            Bit,
            Out,
            0.0,
            "synchronising to or from a belt (clutch closing or opening)",
        ),
        pp("xSynchronised", Bit, Out, 0.0, "synchronised to a belt"),
        pp(
            "xInTarget",
            Bit,
            Out,
            0.0,
            "the target (static or on a belt) has been reached",
        ),
        pp(
            "xInParkPos",
            Bit,
            Out,
            0.0,
            "the parking position has been reached",
        ),
        pp(
            "eSetTargetOut",
            Integer,
            Out,
            0.0,
            "the target being approached: 0 static, n belt CVn",
        ),
    ],
    // Parameters (3.6.5).
    &[
        pp(
            "lrPathStopDec",
            Real,
            Set,
            10000.0,
            "path deceleration for xPathStop, units/s²",
        ),
        pp(
            "lrPathStopJerk",
            Real,
            Set,
            100000.0,
            "path jerk for xPathStop, units/s³",
        ),
        pp(
            "lrPathHaltDec",
            Real,
            Set,
            100.0,
            "path deceleration for xPathHalt, units/s²",
        ),
        pp(
            "lrPathJerk",
            Real,
            Set,
            100000.0,
            "path jerk for xPathHalt and the path interpolation, units/s³",
        ),
        pp("lrPathVel", Real, Set, 10.0, "limit of the path speed, units/s"),
        pp(
            "lrPathAcc",
            Real,
            Set,
            100.0,
            "limit of the path acceleration, units/s²",
        ),
        pp(
            "lrPathDec",
            Real,
            Set,
            100.0,
            "limit of the path deceleration, units/s²",
        ),
    ],
    indexed!(axes13; "alrStopDec", Real, Set, 10000.0,
        "deceleration of the axis for xStopALL and limits, units/s²"),
    indexed!(axes13; "alrStopJerk", Real, Set, 100000.0,
        "jerk of the axis for xStopALL and limits, units/s³"),
    &[
        pp(
            "lrCartesianJogJerk",
            Real,
            Set,
            10000.0,
            "jerk for jogging X, Y and Z, units/s³",
        ),
        pp(
            "lrCartesianJogVel",
            Real,
            Set,
            10.0,
            "speed for jogging X, Y and Z, units/s",
        ),
        pp(
            "lrCartesianJogAcc",
            Real,
            Set,
            100.0,
            "acceleration for jogging X, Y and Z, units/s²",
        ),
        pp(
            "lrCartesianJogDec",
            Real,
            Set,
            100.0,
            "deceleration for jogging X, Y and Z, units/s²",
        ),
        pp(
            "lrOrientationJogJerk",
            Real,
            Set,
            10000.0,
            "jerk for jogging A, B and C, units/s³",
        ),
        pp(
            "lrOrientationJogVel",
            Real,
            Set,
            10.0,
            "speed for jogging A, B and C, units/s",
        ),
        pp(
            "lrOrientationJogAcc",
            Real,
            Set,
            100.0,
            "acceleration for jogging A, B and C, units/s²",
        ),
        pp(
            "lrOrientationJogDec",
            Real,
            Set,
            100.0,
            "deceleration for jogging A, B and C, units/s²",
        ),
        pp(
            "lrRealAxisJogJerk",
            Real,
            Set,
            10000.0,
            "jerk for jogging the real axes A1–A6 and Aux1, units/s³",
        ),
        pp(
            "lrRealAxisJogVel",
            Real,
            Set,
            10.0,
            "velocity for jogging the real axes A1–A6 and Aux1, units/s",
        ),
        pp(
            "lrRealAxisJogAcc",
            Real,
            Set,
            100.0,
            "acceleration for jogging the real axes A1–A6 and Aux1, units/s²",
        ),
        pp(
            "lrRealAxisJogDec",
            Real,
            Set,
            100.0,
            "deceleration for jogging the real axes A1–A6 and Aux1, units/s²",
        ),
    ],
    indexed!(real7; "alrHomePosition", Real, Set, 0.0, "home position of a real axis, units"),
    indexed!(real7; "aeHomingOrder", Integer, Set, 0.0,
        "homing order: 0 NoHoming, 1 First … 12 Twelfth"),
    &[
        pp(
            "xUseHomeExtParameter",
            Bit,
            Set,
            0.0,
            "use the application's homing parameters instead of the axis data",
        ),
        pp(
            "lrXMaxVel",
            Real,
            Set,
            10.0,
            "maximum velocity of X on the path, units/s",
        ),
        pp(
            "lrYMaxVel",
            Real,
            Set,
            10.0,
            "maximum velocity of Y on the path, units/s",
        ),
        pp(
            "lrZMaxVel",
            Real,
            Set,
            10.0,
            "maximum velocity of Z on the path, units/s",
        ),
        pp(
            "lrAMaxVel",
            Real,
            Set,
            10.0,
            "maximum velocity of A on the path, units/s",
        ),
        pp(
            "lrBMaxVel",
            Real,
            Set,
            10.0,
            "maximum velocity of B on the path, units/s",
        ),
        pp(
            "lrCMaxVel",
            Real,
            Set,
            10.0,
            "maximum velocity of C on the path, units/s",
        ),
        pp(
            "lrAux1MaxVel",
            Real,
            Set,
            10.0,
            "maximum velocity of Aux1 on the path, units/s",
        ),
        pp(
            "lrXMaxAccDec",
            Real,
            Set,
            100.0,
            "maximum acceleration/deceleration of X on the path, units/s²",
        ),
        pp(
            "lrYMaxAccDec",
            Real,
            Set,
            100.0,
            "maximum acceleration/deceleration of Y on the path, units/s²",
        ),
        pp(
            "lrZMaxAccDec",
            Real,
            Set,
            100.0,
            "maximum acceleration/deceleration of Z on the path, units/s²",
        ),
        pp(
            "lrAMaxAccDec",
            Real,
            Set,
            100.0,
            "maximum acceleration/deceleration of A on the path, units/s²",
        ),
        pp(
            "lrBMaxAccDec",
            Real,
            Set,
            100.0,
            "maximum acceleration/deceleration of B on the path, units/s²",
        ),
        pp(
            "lrCMaxAccDec",
            Real,
            Set,
            100.0,
            "maximum acceleration/deceleration of C on the path, units/s²",
        ),
        pp(
            "lrAux1MaxAccDec",
            Real,
            Set,
            100.0,
            "maximum acceleration/deceleration of Aux1 on the path, units/s²",
        ),
        pp(
            "lrXMaxJerk",
            Real,
            Set,
            10000.0,
            "maximum jerk of X on the path, units/s³",
        ),
        pp(
            "lrYMaxJerk",
            Real,
            Set,
            10000.0,
            "maximum jerk of Y on the path, units/s³",
        ),
        pp(
            "lrZMaxJerk",
            Real,
            Set,
            10000.0,
            "maximum jerk of Z on the path, units/s³",
        ),
        pp(
            "lrAMaxJerk",
            Real,
            Set,
            10000.0,
            "maximum jerk of A on the path, units/s³",
        ),
        pp(
            "lrBMaxJerk",
            Real,
            Set,
            10000.0,
            "maximum jerk of B on the path, units/s³",
        ),
        pp(
            "lrCMaxJerk",
            Real,
            Set,
            10000.0,
            "maximum jerk of C on the path, units/s³",
        ),
        // The manual's parameter listing also spells it lrAux1Jerk.
        alias(
            pp(
                "lrAux1MaxJerk",
                Real,
                Set,
                10000.0,
                "maximum jerk of Aux1 on the path, units/s³",
            ),
            &["lrAux1Jerk"],
        ),
        pp(
            "lrGripperClosingTime",
            Real,
            Set,
            0.0,
            "gripper closes this long before the end of a pick profile, s",
        ),
        pp(
            "lrGripperOpenTime",
            Real,
            Set,
            0.0,
            "gripper opens this long before the end of a place profile, s",
        ),
        pp(
            "eTargetCoordSystem",
            Integer,
            Set,
            0.0,
            "coordinate system of the static target position",
        ),
        pp(
            "lrXTargetPos",
            Real,
            Set,
            0.0,
            "static target position, X, units",
        ),
        pp(
            "lrYTargetPos",
            Real,
            Set,
            0.0,
            "static target position, Y, units",
        ),
        pp(
            "lrZTargetPos",
            Real,
            Set,
            0.0,
            "static target position, Z, units",
        ),
        pp(
            "lrATargetPos",
            Real,
            Set,
            180.0,
            "static target position, A, degrees",
        ),
        pp(
            "lrBTargetPos",
            Real,
            Set,
            0.0,
            "static target position, B, degrees",
        ),
        pp(
            "lrCTargetPos",
            Real,
            Set,
            0.0,
            "static target position, C, degrees",
        ),
        pp(
            "lrAux1TargetPos",
            Real,
            Set,
            0.0,
            "static target position, Aux1, units",
        ),
        pp(
            "lrZStartDist",
            Real,
            Set,
            0.0,
            "height of the vertical lift at the start, units",
        ),
        pp(
            "ePathMode",
            Integer,
            Set,
            0.0,
            "path shape: 0 standard, 1 elliptical",
        ),
        pp(
            "lrZDistElliptical",
            Real,
            Set,
            0.0,
            "height of the ellipse (ePathMode 1), units",
        ),
        pp(
            "lrZTargetDist",
            Real,
            Set,
            0.0,
            "height of the vertical approach at the target, units",
        ),
        pp(
            "lrBlendingRadius",
            Real,
            Set,
            0.0,
            "blending radius at the intermediate points, units",
        ),
        pp(
            "xPosInWindow",
            Bit,
            Set,
            0.0,
            "xInPosition needs the tool inside the tolerance window",
        ),
        pp(
            "lrPosInWindow",
            Real,
            Set,
            0.5,
            "size of the tolerance window, units",
        ),
        pp(
            "lrTimePosInWindow",
            Real,
            Set,
            50.0,
            "time the tool must stay inside the window, ms",
        ),
        pp(
            "eTrackingMode",
            Integer,
            Set,
            0.0,
            "0 single targets, 1 Static⇒CV1, 2 CV1⇒Static, 3 CV1⇒CV2, 4 CV2⇒CV1",
        ),
    ],
];

/// The members of the pick & place module.
pub const PICKPLACE: [MemberDef; total_len(PICKPLACE_PARTS)] = flatten(PICKPLACE_PARTS);

const BELT_PARTS: &[&[MemberDef]] = &[
    // The input structure ascBeltInput[i] (3.6.3).
    &[
        pp(
            "xWorkpieceOnBeltReceive",
            Bit,
            Set,
            0.0,
            "rising edge: a workpiece was detected; start tracking it",
        ),
        pp(
            "xValidPos",
            Bit,
            Set,
            0.0,
            "rising edge: ascInitialObjectPosition is valid for the last detection",
        ),
    ],
    indexed!(pose6; "ascInitialObjectPosition", Real, Set, 0.0,
        "workpiece position at the detection, belt coordinates"),
    &[pp(
        "lrAux1TargetPos",
        Real,
        Set,
        0.0,
        "target position in Aux1 direction on this belt, units",
    )],
    // The parameter array ascConveyorBeltPar[i] (3.6.6).
    indexed!(pose6; "alrParkPos", Real, Set, 0.0,
        "parking position for this belt, machine coordinates"),
    &[pp(
        "lrZDistBelt",
        Real,
        Set,
        0.0,
        "height above the workpiece's synchronous position, units",
    )],
    indexed!(pose6; "alrConveyorBeltOrigin", Real, Set, 0.0,
        "origin and alignment of the belt's coordinates, machine coordinates"),
    &[
        pp(
            "lrSyncTimeOnBelt",
            Real,
            Set,
            0.0,
            "duration of the synchronous travel above the belt, s",
        ),
        pp(
            "lrLowerSyncLimit",
            Real,
            Set,
            0.0,
            "start of the operating range along the belt, units",
        ),
        pp(
            "lrUpperSyncLimit",
            Real,
            Set,
            0.0,
            "end of the operating range along the belt, units",
        ),
    ],
    // pacer's own status of the belt.
    &[
        pp("Position", Real, Moving, 0.0, "belt travel, mm"),
        pp("Velocity", Real, Moving, 0.0, "belt velocity, mm/s"),
        pp(
            "Workpieces",
            Integer,
            Out,
            0.0,
            "workpieces tracked on the belt now",
        ),
        pp(
            "Picked",
            Integer,
            Out,
            0.0,
            "workpieces picked from the belt so far",
        ),
        pp(
            "Missed",
            Integer,
            Out,
            0.0,
            "workpieces that left the operating range untaken",
        ),
    ],
];

/// The members of a pick & place belt.
pub const BELT: [MemberDef; total_len(BELT_PARTS)] = flatten(BELT_PARTS);

/// Highest belt number (CV16).
pub const MAX_BELTS: u32 = 16;

/// The elements `name[1]` … `name[N]` of an array member (`name` without an index, any case):
/// the index of the first and N.
pub fn find_array(members: &[MemberDef], name: &str) -> Option<(usize, usize)> {
    let is_element = |m: &MemberDef, k: usize| {
        m.name
            .strip_suffix(&format!("[{k}]"))
            .is_some_and(|base| base.eq_ignore_ascii_case(name))
    };
    let first = members.iter().position(|m| is_element(m, 1))?;
    let len = members[first..]
        .iter()
        .enumerate()
        .take_while(|(i, m)| is_element(m, i + 1))
        .count();
    Some((first, len))
}

/// Split `name[k]` into `name` and k; None for a name without an index.
pub fn split_index(name: &str) -> Option<(&str, &str)> {
    let open = name.strip_suffix(']')?.rfind('[')?;
    let index = &name[open + 1..name.len() - 1];
    Some((&name[..open], index))
}

/// Every object type, in the order the docs list them.
pub static TYPES: &[TypeDef] = &[
    DRIVE_INPUT_TYPE,
    MODULE_INPUT_TYPE,
    DRIVE_IO_TYPE,
    DRIVE_OUTPUT_TYPE,
    MODULE_OUTPUT_TYPE,
    VAR_TYPE,
    BIT_TYPE,
    PROGRAM_TYPE,
    TIMER_TYPE,
    QUEUE_TYPE,
    CAPTURE_TYPE,
    INDEX_TYPE,
    HOME_TYPE,
    JOG_TYPE,
    GEAR_TYPE,
    PROFILE_TYPE,
    PLS_TYPE,
    MOTION_TYPE,
    AXIS_TYPE,
    BASIC_VAR_TYPE,
    PICK_PLACE_TYPE,
    BELT_TYPE,
];

/// The `DriveInput` object type.
pub const DRIVE_INPUT_TYPE: TypeDef = t(
    "DriveInput",
    Kind::DriveInput,
    Instances::Numbered {
        first: 1,
        default_count: 8,
    },
    Some("Value"),
    INPUT,
    &[],
    "digital input of the drive",
);

/// The `ModuleInput` object type.
pub const MODULE_INPUT_TYPE: TypeDef = t(
    "ModuleInput",
    Kind::ModuleInput,
    Instances::Numbered {
        first: 1,
        default_count: 8,
    },
    Some("Value"),
    INPUT,
    &[],
    "digital input of the motion module (latches in hardware)",
);

/// The `DriveIO` object type.
pub const DRIVE_IO_TYPE: TypeDef = t(
    "DriveIO",
    Kind::DriveIO,
    Instances::Numbered {
        first: 1,
        default_count: 4,
    },
    None,
    DRIVE_IO,
    &[],
    "bidirectional drive I/O point",
);

/// The `DriveOutput` object type.
pub const DRIVE_OUTPUT_TYPE: TypeDef = t(
    "DriveOutput",
    Kind::DriveOutput,
    Instances::Numbered {
        first: 1,
        default_count: 4,
    },
    Some("Value"),
    OUTPUT,
    &[],
    "digital output of the drive",
);

/// The `ModuleOutput` object type.
pub const MODULE_OUTPUT_TYPE: TypeDef = t(
    "ModuleOutput",
    Kind::ModuleOutput,
    Instances::Numbered {
        first: 1,
        default_count: 4,
    },
    Some("Value"),
    OUTPUT,
    &[],
    "digital output of the motion module",
);

/// The `Var` object type.
pub const VAR_TYPE: TypeDef = t(
    "Var",
    Kind::Var,
    Instances::Named,
    Some("Value"),
    VAR,
    &[],
    "user variable (machine.toml [variables])",
);

/// The `Bit` object type.
pub const BIT_TYPE: TypeDef = t(
    "Bit",
    Kind::Bit,
    Instances::Named,
    Some("Value"),
    BIT,
    &[],
    "user bit (machine.toml [bits])",
);

/// The `Program` object type.
pub const PROGRAM_TYPE: TypeDef = t(
    "Program",
    Kind::Program,
    Instances::Numbered {
        first: 0,
        default_count: 16,
    },
    None,
    PROGRAM,
    &[],
    "user program",
);

/// The `Timer` object type.
pub const TIMER_TYPE: TypeDef = t(
    "Timer",
    Kind::Timer,
    Instances::Numbered {
        first: 0,
        default_count: 8,
    },
    None,
    TIMER,
    &[],
    "timer",
);

/// The `Queue` object type.
pub const QUEUE_TYPE: TypeDef = t(
    "Queue",
    Kind::Queue,
    Instances::Numbered {
        first: 0,
        default_count: 8,
    },
    None,
    QUEUE,
    &[],
    "position queue",
);

/// The `Capture` object type.
pub const CAPTURE_TYPE: TypeDef = t(
    "Capture",
    Kind::Capture,
    Instances::Numbered {
        first: 0,
        default_count: 4,
    },
    None,
    CAPTURE,
    &[],
    "high-speed capture",
);

/// The `Index` object type.
pub const INDEX_TYPE: TypeDef = t(
    "Index",
    Kind::Index,
    Instances::Numbered {
        first: 0,
        default_count: 16,
    },
    None,
    INDEX,
    INDEX_GLOBAL,
    "index motion",
);

/// The `Home` object type.
pub const HOME_TYPE: TypeDef = t(
    "Home",
    Kind::Home,
    Instances::Numbered {
        first: 0,
        default_count: 1,
    },
    None,
    HOME,
    &[],
    "home motion",
);

/// The `Jog` object type.
pub const JOG_TYPE: TypeDef = t(
    "Jog",
    Kind::Jog,
    Instances::Numbered {
        first: 0,
        default_count: 2,
    },
    None,
    JOG,
    JOG_GLOBAL,
    "jog motion",
);

/// The `Gear` object type.
pub const GEAR_TYPE: TypeDef = t(
    "Gear",
    Kind::Gear,
    Instances::Global,
    None,
    GEAR,
    &[],
    "electronic gearing",
);

/// The `Profile` object type.
pub const PROFILE_TYPE: TypeDef = t(
    "Profile",
    Kind::Profile,
    Instances::Numbered {
        first: 0,
        default_count: 2,
    },
    None,
    PROFILE,
    &[],
    "motion profile (motions on the two profiles add up)",
);

/// The `PLS` object type.
pub const PLS_TYPE: TypeDef = t(
    "PLS",
    Kind::Pls,
    Instances::Numbered {
        first: 0,
        default_count: 8,
    },
    None,
    PLS,
    &[],
    "programmable limit switch",
);

/// The `Motion` object type.
pub const MOTION_TYPE: TypeDef = t(
    "Motion",
    Kind::Motion,
    Instances::Global,
    None,
    MOTION,
    &[],
    "drive-wide motion members, also written without `Motion.`",
);

/// The `Axis` object type.
pub const AXIS_TYPE: TypeDef = t(
    "Axis",
    Kind::Axis,
    Instances::Numbered {
        first: 1,
        default_count: 0,
    },
    None,
    AXIS,
    &[],
    "ORION DSP axis (machine.toml [axis.N]); MotionBASIC axis {N}",
);

/// The `BasicVar` object type.
pub const BASIC_VAR_TYPE: TypeDef = t(
    "BasicVar",
    Kind::BasicVar,
    Instances::Named,
    Some("Value"),
    BASIC_VAR,
    &[],
    "MotionBASIC variable",
);

/// The `PickPlace` object type.
pub const PICK_PLACE_TYPE: TypeDef = t(
    "PickPlace",
    Kind::PickPlace,
    Instances::Global,
    None,
    &PICKPLACE,
    &[],
    "the Track Pick & Place module (machine.toml [pickplace]); members under the manual's names",
);

/// The `Belt` object type.
pub const BELT_TYPE: TypeDef = t(
    "Belt",
    Kind::Belt,
    Instances::Numbered {
        first: 1,
        default_count: 0,
    },
    None,
    &BELT,
    &[],
    "conveying belt CVn of the pick & place module (machine.toml [pickplace.belt.N])",
);

#[allow(clippy::too_many_arguments)]
const fn t(
    name: &'static str,
    kind: Kind,
    instances: Instances,
    default_member: Option<&'static str>,
    members: &'static [MemberDef],
    global_members: &'static [MemberDef],
    doc: &'static str,
) -> TypeDef {
    let referable = matches!(kind, Kind::Capture | Kind::Profile);
    TypeDef {
        name,
        kind,
        instances,
        default_member,
        members,
        global_members,
        referable,
        doc,
    }
}

/// Members of the global `Motion` object may be written bare (`FeedRateOverride`, `Stop`).
pub const BARE_GLOBAL_TYPE: &str = "Motion";

/// Find a type by name, ignoring case.
pub fn find_type(name: &str) -> Option<&'static TypeDef> {
    TYPES.iter().find(|t| t.name.eq_ignore_ascii_case(name))
}

/// Find a member by name or alias, ignoring case.
pub fn find_member<'a>(members: &'a [MemberDef], name: &str) -> Option<&'a MemberDef> {
    member_position(members, name).map(|i| &members[i])
}

/// The index of a member by name or alias, ignoring case.
pub fn member_position(members: &[MemberDef], name: &str) -> Option<usize> {
    members.iter().position(|m| {
        m.name.eq_ignore_ascii_case(name) || m.aliases.iter().any(|a| a.eq_ignore_ascii_case(name))
    })
}
