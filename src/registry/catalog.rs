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

/// What the kernel does when a program writes a member.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Hook {
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
    /// Re-arms a DSP axis latch (`ASEN@(axis) = 0`).
    AxisLatch,
    /// A DSP axis setting the kernel applies at once (POS.MOD@, PLS…@, SENS.MODE@).
    AxisSetting,
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

const fn alias(mut d: MemberDef, aliases: &'static [&'static str]) -> MemberDef {
    d.aliases = aliases;
    d
}

use Access::{Action, Input, Read, ReadWrite};
use ValueType::{Bit, Fixed, Integer, Real};

const INPUT: &[MemberDef] = &[m(
    "Value",
    Bit,
    Read,
    "state of the input, sampled every update",
)];
const OUTPUT: &[MemberDef] = &[hook(
    Hook::OutputWrite,
    m("Value", Bit, ReadWrite, "state of the output"),
)];
const DRIVE_IO: &[MemberDef] = &[
    m("In", Bit, Read, "state of the point as an input"),
    hook(
        Hook::OutputWrite,
        m("Out", Bit, ReadWrite, "state of the point as an output"),
    ),
];
const VAR: &[MemberDef] = &[m(
    "Value",
    Fixed(0),
    ReadWrite,
    "the variable's value (decimal places set in machine.toml)",
)];
const BIT: &[MemberDef] = &[m("Value", Bit, ReadWrite, "the bit")];
const PROGRAM: &[MemberDef] = &[
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
const TIMER: &[MemberDef] = &[
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
const QUEUE: &[MemberDef] = &[
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
const CAPTURE: &[MemberDef] = &[
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
const INDEX: &[MemberDef] = &[
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
        "timed index could not meet its time within the maxima",
    ),
];
const HOME: &[MemberDef] = &[
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
const JOG: &[MemberDef] = &[
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
const JOG_GLOBAL: &[MemberDef] = &[
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
const AXIS: &[MemberDef] = &[
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
];
const BASIC_VAR: &[MemberDef] = &[m(
    "Value",
    Real,
    ReadWrite,
    "a MotionBASIC variable (type from its suffix)",
)];
const GEAR: &[MemberDef] = &[
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
const PROFILE: &[MemberDef] = &[m("Busy", Bit, Read, "a motion object runs on this profile")];
const PLS: &[MemberDef] = &[
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
const MOTION: &[MemberDef] = &[
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
        "StopDeceleration",
        Real,
        ReadWrite,
        "deceleration used by Stop",
    ),
    continuous(m(
        "FollowingError",
        Real,
        Read,
        "command minus feedback position",
    )),
    m(
        "FollowingErrorLimit",
        Real,
        ReadWrite,
        "fault above this following error",
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

/// Every object type, in the order the docs list them.
pub static TYPES: &[TypeDef] = &[
    t(
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
    ),
    t(
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
    ),
    t(
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
    ),
    t(
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
    ),
    t(
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
    ),
    t(
        "Var",
        Kind::Var,
        Instances::Named,
        Some("Value"),
        VAR,
        &[],
        "user variable (machine.toml [variables])",
    ),
    t(
        "Bit",
        Kind::Bit,
        Instances::Named,
        Some("Value"),
        BIT,
        &[],
        "user bit (machine.toml [bits])",
    ),
    t(
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
    ),
    t(
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
    ),
    t(
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
    ),
    t(
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
    ),
    t(
        "Index",
        Kind::Index,
        Instances::Numbered {
            first: 0,
            default_count: 16,
        },
        None,
        INDEX,
        &[],
        "index motion",
    ),
    t(
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
    ),
    t(
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
    ),
    t(
        "Gear",
        Kind::Gear,
        Instances::Global,
        None,
        GEAR,
        &[],
        "electronic gearing",
    ),
    t(
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
    ),
    t(
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
    ),
    t(
        "Motion",
        Kind::Motion,
        Instances::Global,
        None,
        MOTION,
        &[],
        "drive-wide motion members, also written without `Motion.`",
    ),
    t(
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
    ),
    t(
        "BasicVar",
        Kind::BasicVar,
        Instances::Named,
        Some("Value"),
        BASIC_VAR,
        &[],
        "MotionBASIC variable",
    ),
];

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
    members.iter().find(|m| {
        m.name.eq_ignore_ascii_case(name) || m.aliases.iter().any(|a| a.eq_ignore_ascii_case(name))
    })
}
