//! Every event the trace records, as one typed enum: the emitters build these, the writer
//! serializes them (one JSON object per line), the exporters and `pacer plot` read them back.
//! `docs/trace.md` is checked against [`EventKind::ALL`] and [`Event::example`] by a test.

use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// Text in an event: borrowed when the emitter has it, owned when read back from a file.
pub type Text<'a> = Cow<'a, str>;

/// A number as the trace writes it: non-finite values are written as null, and read back as NaN.
fn real<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// A member's value in a `change` event: bits as booleans, integers as integers, the rest as
/// numbers.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Value {
    /// A bit.
    Bit(bool),
    /// An integer (integer and 0-decimal members).
    Int(i64),
    /// Any other number (non-finite values, which stores never keep, are written as null).
    Num(#[serde(deserialize_with = "real")] f64),
}

impl Value {
    /// The value of a member of type `ty` holding `x`.
    pub fn of(ty: crate::registry::ValueType, x: f64) -> Value {
        use crate::registry::ValueType;
        match ty {
            ValueType::Bit => Value::Bit(x != 0.0),
            ValueType::Integer | ValueType::Fixed(0) => Value::Int(x as i64),
            _ => Value::Num(x),
        }
    }

    /// As a number (ON is 1).
    pub fn number(self) -> f64 {
        match self {
            Value::Bit(b) => f64::from(u8::from(b)),
            Value::Int(i) => i as f64,
            Value::Num(x) => x,
        }
    }
}

/// Who a `warning` or `error` is about.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Origin<'a> {
    /// A place in a program: the task, the program (null for a line typed at the REPL), its
    /// file, and the line and column (in characters) of the expression or statement.
    At {
        /// The task it ran on.
        task: usize,
        /// The program number (null for a typed line).
        program: Option<u32>,
        /// The program's file.
        file: Text<'a>,
        /// Source line.
        line: u32,
        /// Source column.
        column: u32,
    },
    /// A program line: the task, the program (null for a line typed at the REPL) and the line.
    Program {
        /// The task it ran on.
        task: usize,
        /// The program number (null for a typed line).
        program: Option<u32>,
        /// Source line.
        line: u32,
    },
    /// The machine itself (an assignment, a device, the run): task and line are null.
    Machine {
        /// Always null.
        task: (),
        /// Always null.
        line: (),
    },
    /// A DSP axis (REGIST refused its values).
    Axis {
        /// Axis number.
        axis: u32,
    },
}

/// What happened to a motion, with where.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum MotionPhase {
    /// The motion began (at its effective start).
    Start {
        /// Master position at the effective start.
        #[serde(deserialize_with = "real")]
        master: f64,
        /// Axis position there.
        #[serde(deserialize_with = "real")]
        position: f64,
    },
    /// The motion ended.
    Done {
        /// Its end on its own timeline (seconds of the motion clock, or master units).
        #[serde(deserialize_with = "real")]
        end: f64,
        /// Master position at this update.
        #[serde(deserialize_with = "real")]
        master: f64,
        /// Axis position at the end.
        #[serde(deserialize_with = "real")]
        position: f64,
        /// Feedback position at this update, with a servo model (`[servo]`) only: the
        /// command position less the following error (an ideal servo leaves it out).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        feedback: Option<f64>,
    },
}

/// What happened to a program.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProgramEvent {
    /// Started on a task.
    Start,
    /// Ran to its end.
    End,
    /// Stopped (`Program.N.Stop`, `Stop`).
    Stop,
    /// Ended by a run-time error.
    Error,
}

/// The units of the `start` event.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Units<'a> {
    /// The master's unit.
    pub master: Text<'a>,
    /// The servo axis's unit.
    pub motor: Text<'a>,
}

/// One trace event. Serialized as `{"t":…,"tick":…,"kind":"…",fields…}`, fields in the order
/// written here.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Event<'a> {
    /// The run begins.
    Start {
        /// Machine name.
        machine: Text<'a>,
        /// Update period, seconds.
        #[serde(deserialize_with = "real")]
        update: f64,
        /// Number of tasks.
        tasks: usize,
        /// User units.
        units: Units<'a>,
    },
    /// The run ends.
    End {
        /// Why.
        reason: Text<'a>,
        /// Instructions executed.
        instructions: u64,
        /// The objects whose motion still ran (left out when none did).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        moving: Vec<Text<'a>>,
    },
    /// A member changed (or a program wrote it).
    Change {
        /// The member (`Queue.0.QueueExit`).
        name: Text<'a>,
        /// Its new value.
        value: Value,
    },
    /// A MotionBASIC string variable (or string array element) changed.
    TextChange {
        /// The variable (`NAME$`, `CODES$(3)`).
        name: Text<'a>,
        /// Its new text.
        value: Text<'a>,
    },
    /// A program started or ended.
    Program {
        /// Program number.
        program: u32,
        /// Task.
        task: usize,
        /// What happened.
        event: ProgramEvent,
    },
    /// A line a program printed (`PRINT`), without its line end.
    Print {
        /// The task it ran on.
        task: usize,
        /// The program number (null for a line typed at the REPL).
        program: Option<u32>,
        /// The text.
        text: Text<'a>,
    },
    /// A capture latched.
    Capture {
        /// `Capture.N`.
        object: Text<'a>,
        /// The edge's exact time, s.
        #[serde(deserialize_with = "real")]
        time: f64,
        /// Master position at the edge.
        #[serde(deserialize_with = "real")]
        master: f64,
        /// Command position at the edge.
        #[serde(deserialize_with = "real")]
        command: f64,
        /// Feedback position at the edge.
        #[serde(deserialize_with = "real")]
        feedback: f64,
    },
    /// A value went into a queue.
    QueueIn {
        /// `Queue.N`.
        object: Text<'a>,
        /// The value.
        #[serde(deserialize_with = "real")]
        value: f64,
        /// Its exit position (value + QueueOffset).
        #[serde(deserialize_with = "real")]
        exit: f64,
    },
    /// A queue's oldest exit position was reached.
    QueueExit {
        /// `Queue.N`.
        object: Text<'a>,
        /// The exit position.
        #[serde(deserialize_with = "real")]
        exit: f64,
    },
    /// A motion started or ended.
    Motion {
        /// `Index.0`, `Home.0`, `Jog.1`, `Gear`, `Dwell`.
        object: Text<'a>,
        /// What happened, and where.
        #[serde(flatten)]
        phase: MotionPhase,
    },
    /// A DSP card's sensor latched an axis position.
    Latch {
        /// Axis number.
        axis: u32,
        /// `ZREF`, `ASEN` or `BSEN`.
        sensor: Text<'a>,
        /// The edge's exact time, s.
        #[serde(deserialize_with = "real")]
        time: f64,
        /// The latched position.
        #[serde(deserialize_with = "real")]
        position: f64,
    },
    /// A sensor edge was blinded (outside its PLS window).
    Blinded {
        /// DSP card number.
        card: u32,
        /// `ZREF`, `ASEN` or `BSEN`.
        sensor: Text<'a>,
        /// The edge's exact time, s.
        #[serde(deserialize_with = "real")]
        time: f64,
    },
    /// `SENS.MODE@` was set.
    SensMode {
        /// Axis number.
        axis: u32,
        /// The mode string.
        mode: Text<'a>,
    },
    /// REGIST classified a mark.
    Regist {
        /// Axis number.
        axis: u32,
        /// `good`, `bad` or `ignored`.
        mark: Text<'a>,
        /// The edge's exact time, s.
        #[serde(deserialize_with = "real")]
        time: f64,
        /// The registration axis's position at the edge.
        #[serde(deserialize_with = "real")]
        position: f64,
        /// The correction (good marks).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        correction: Option<f64>,
    },
    /// REGIST's DIST + TOLR window passed without a mark.
    RegistWindow {
        /// Axis number.
        axis: u32,
        /// The exact time the axis reached the threshold, s.
        #[serde(deserialize_with = "real")]
        time: f64,
        /// The threshold: the ruler's start + DIST + TOLR (continuous position).
        #[serde(deserialize_with = "real")]
        position: f64,
    },
    /// REGIST's STATUSSV changed (a mark, the window, the fast input turning off).
    RegistStatus {
        /// Axis number.
        axis: u32,
        /// The exact time of the change, s.
        #[serde(deserialize_with = "real")]
        time: f64,
        /// STATUSSV: bit 0 fast input occurred, 1 fast input, 2 good mark, 3 bad mark,
        /// 4 DIST + TOLR passed, 5 the input's state.
        status: u32,
    },
    /// A warning.
    Warning {
        /// Who it is about.
        #[serde(flatten)]
        origin: Origin<'a>,
        /// What.
        message: Text<'a>,
    },
    /// A run-time error (it ends the run).
    Error {
        /// Who it is about.
        #[serde(flatten)]
        origin: Origin<'a>,
        /// What.
        message: Text<'a>,
    },
    /// The pick & place module's eTMState changed.
    PpState {
        /// The state's name.
        state: Text<'a>,
    },
    /// The pick & place module prepared a path.
    PpPath {
        /// eSetTargetOut of the path.
        target: i32,
        /// Its duration, s.
        #[serde(deserialize_with = "real")]
        duration: f64,
        /// The time scale the axis limits imposed (1: none).
        #[serde(deserialize_with = "real")]
        scale: f64,
    },
    /// A workpiece was picked.
    Pick {
        /// Belt number (null: the static position).
        belt: Option<u32>,
        /// Workpiece id.
        id: Option<u32>,
        /// Tool X, mm.
        #[serde(deserialize_with = "real")]
        x: f64,
        /// Tool Y, mm.
        #[serde(deserialize_with = "real")]
        y: f64,
        /// Tool Z, mm.
        #[serde(deserialize_with = "real")]
        z: f64,
    },
    /// A workpiece was placed.
    Place {
        /// Belt number (null: the static position).
        belt: Option<u32>,
        /// Place position id.
        id: Option<u32>,
        /// Tool X, mm.
        #[serde(deserialize_with = "real")]
        x: f64,
        /// Tool Y, mm.
        #[serde(deserialize_with = "real")]
        y: f64,
        /// Tool Z, mm.
        #[serde(deserialize_with = "real")]
        z: f64,
    },
    /// A mode-0 target was reached.
    PpTarget {
        /// eSetTargetOut: 0 static, n belt n.
        target: i32,
        /// Workpiece id, on a belt.
        id: Option<u32>,
        /// Tool X, mm.
        #[serde(deserialize_with = "real")]
        x: f64,
        /// Tool Y, mm.
        #[serde(deserialize_with = "real")]
        y: f64,
        /// Tool Z, mm.
        #[serde(deserialize_with = "real")]
        z: f64,
    },
    /// A workpiece left the operating range before it could be taken.
    Missed {
        /// Belt number.
        belt: u32,
        /// Workpiece id.
        id: u32,
        /// Its X on the belt, mm.
        #[serde(deserialize_with = "real")]
        x: f64,
    },
    /// xPulseGripper.
    Gripper {
        /// `close` (pick) or `open` (place).
        action: Text<'a>,
    },
    /// The pick & place module's error.
    PpError {
        /// eErrorID.
        id: i32,
        /// What.
        message: Text<'a>,
    },
    /// The pick & place module's warning.
    PpWarning {
        /// The warning's id.
        id: i32,
        /// What.
        message: Text<'a>,
    },
    /// A homing group of the pick & place module finished.
    PpHomed {
        /// Its place in aeHomingOrder.
        order: i32,
    },
    /// The I/O link failed: the machine went to its safe state.
    IoFault {
        /// The device.
        device: Text<'a>,
        /// Why.
        cause: Text<'a>,
    },
    /// A drive faulted: its motion stopped.
    Fault {
        /// The axis (`Motion` for the PowerTools drive's).
        axis: Text<'a>,
        /// Which fault (`following_error`).
        fault: Text<'a>,
        /// The command position when it faulted.
        command: f64,
        /// The feedback position when it faulted.
        feedback: f64,
        /// The limit it passed.
        limit: f64,
    },
    /// The I/O link is back.
    IoReconnect {
        /// The device.
        device: Text<'a>,
        /// Connection attempts it took.
        attempts: u32,
    },
}

/// Defines [`EventKind`], its [`EventKind::ALL`] and [`EventKind::as_str`] from one list, so no
/// kind can be left out of any of them.
macro_rules! event_kinds {
    ($($variant:ident => $name:literal,)*) => {
        /// The kind of an event, without its fields.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[allow(missing_docs)]
        pub enum EventKind {
            $($variant,)*
        }

        impl EventKind {
            /// Every kind, in the order of the trace reference.
            pub const ALL: &'static [EventKind] = &[$(EventKind::$variant,)*];

            /// The `kind` as written in the trace.
            pub fn as_str(self) -> &'static str {
                match self {
                    $(EventKind::$variant => $name,)*
                }
            }
        }
    };
}

event_kinds! {
    Start => "start",
    End => "end",
    Change => "change",
    TextChange => "text_change",
    Program => "program",
    Print => "print",
    Capture => "capture",
    QueueIn => "queue_in",
    QueueExit => "queue_exit",
    Motion => "motion",
    Latch => "latch",
    Blinded => "blinded",
    SensMode => "sens_mode",
    Regist => "regist",
    RegistWindow => "regist_window",
    RegistStatus => "regist_status",
    Warning => "warning",
    Error => "error",
    PpState => "pp_state",
    PpPath => "pp_path",
    Pick => "pick",
    Place => "place",
    PpTarget => "pp_target",
    Missed => "missed",
    Gripper => "gripper",
    PpError => "pp_error",
    PpWarning => "pp_warning",
    PpHomed => "pp_homed",
    IoFault => "io_fault",
    IoReconnect => "io_reconnect",
    Fault => "fault",
}

impl std::fmt::Display for EventKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Event<'_> {
    /// Its kind.
    pub fn kind(&self) -> EventKind {
        match self {
            Event::Start { .. } => EventKind::Start,
            Event::End { .. } => EventKind::End,
            Event::Change { .. } => EventKind::Change,
            Event::TextChange { .. } => EventKind::TextChange,
            Event::Program { .. } => EventKind::Program,
            Event::Print { .. } => EventKind::Print,
            Event::Capture { .. } => EventKind::Capture,
            Event::QueueIn { .. } => EventKind::QueueIn,
            Event::QueueExit { .. } => EventKind::QueueExit,
            Event::Motion { .. } => EventKind::Motion,
            Event::Latch { .. } => EventKind::Latch,
            Event::Blinded { .. } => EventKind::Blinded,
            Event::SensMode { .. } => EventKind::SensMode,
            Event::Regist { .. } => EventKind::Regist,
            Event::RegistWindow { .. } => EventKind::RegistWindow,
            Event::RegistStatus { .. } => EventKind::RegistStatus,
            Event::Warning { .. } => EventKind::Warning,
            Event::Error { .. } => EventKind::Error,
            Event::PpState { .. } => EventKind::PpState,
            Event::PpPath { .. } => EventKind::PpPath,
            Event::Pick { .. } => EventKind::Pick,
            Event::Place { .. } => EventKind::Place,
            Event::PpTarget { .. } => EventKind::PpTarget,
            Event::Missed { .. } => EventKind::Missed,
            Event::Gripper { .. } => EventKind::Gripper,
            Event::PpError { .. } => EventKind::PpError,
            Event::PpWarning { .. } => EventKind::PpWarning,
            Event::PpHomed { .. } => EventKind::PpHomed,
            Event::IoFault { .. } => EventKind::IoFault,
            Event::IoReconnect { .. } => EventKind::IoReconnect,
            Event::Fault { .. } => EventKind::Fault,
        }
    }

    /// A warning or error of the machine itself, not of a program line.
    pub fn machine_warning(message: impl Into<Text<'static>>) -> Event<'static> {
        Event::Warning {
            origin: Origin::Machine { task: (), line: () },
            message: message.into(),
        }
    }

    /// An error of the machine itself, not of a program line.
    pub fn machine_error(message: impl Into<Text<'static>>) -> Event<'static> {
        Event::Error {
            origin: Origin::Machine { task: (), line: () },
            message: message.into(),
        }
    }

    /// A typical event of `kind`, with every field it can carry (the trace reference shows
    /// these, and a test checks the reference against them).
    pub fn example(kind: EventKind) -> Event<'static> {
        let program = Origin::Program {
            task: 0,
            program: Some(1),
            line: 12,
        };
        match kind {
            EventKind::Start => Event::Start {
                machine: "labeling".into(),
                update: 0.001,
                tasks: 4,
                units: Units {
                    master: "in".into(),
                    motor: "in".into(),
                },
            },
            EventKind::End => Event::End {
                reason: "duration reached".into(),
                instructions: 123_456,
                moving: vec!["Index.1".into()],
            },
            EventKind::Change => Event::Change {
                name: "Queue.0.QueueExit".into(),
                value: Value::Bit(true),
            },
            EventKind::TextChange => Event::TextChange {
                name: "CODE$".into(),
                value: "A17".into(),
            },
            EventKind::Program => Event::Program {
                program: 1,
                task: 1,
                event: ProgramEvent::Start,
            },
            EventKind::Print => Event::Print {
                task: 0,
                program: Some(1),
                text: "cuts: 12 ".into(),
            },
            EventKind::Capture => Event::Capture {
                object: "Capture.1".into(),
                time: 1.5012,
                master: 12.5,
                command: 3.25,
                feedback: 3.25,
            },
            EventKind::QueueIn => Event::QueueIn {
                object: "Queue.0".into(),
                value: 12.5,
                exit: 18.0,
            },
            EventKind::QueueExit => Event::QueueExit {
                object: "Queue.0".into(),
                exit: 18.0,
            },
            EventKind::Motion => Event::Motion {
                object: "Index.0".into(),
                phase: MotionPhase::Done {
                    end: 2.25,
                    master: 30.0,
                    position: 6.5,
                    feedback: Some(6.4975),
                },
            },
            EventKind::Latch => Event::Latch {
                axis: 1,
                sensor: "ASEN".into(),
                time: 0.4003,
                position: 120.5,
            },
            EventKind::Blinded => Event::Blinded {
                card: 1,
                sensor: "ASEN".into(),
                time: 0.4003,
            },
            EventKind::SensMode => Event::SensMode {
                axis: 1,
                mode: "RRRGN".into(),
            },
            EventKind::Regist => Event::Regist {
                axis: 1,
                mark: "good".into(),
                time: 0.4003,
                position: 2100.5,
                correction: Some(-0.5),
            },
            EventKind::RegistWindow => Event::RegistWindow {
                axis: 1,
                time: 0.2103,
                position: 2103.0,
            },
            EventKind::RegistStatus => Event::RegistStatus {
                axis: 1,
                time: 0.2103,
                status: 16,
            },
            EventKind::Warning => Event::Warning {
                origin: program,
                message: "GEAR FOR over a pacer distance of 0: applied at once".into(),
            },
            EventKind::Error => Event::Error {
                origin: Origin::At {
                    task: 0,
                    program: Some(1),
                    file: "program1.pt".into(),
                    line: 12,
                    column: 9,
                },
                message: "division by zero".into(),
            },
            EventKind::PpState => Event::PpState {
                state: "MOVE_PP".into(),
            },
            EventKind::PpPath => Event::PpPath {
                target: 1,
                duration: 0.42,
                scale: 1.0,
            },
            EventKind::Pick => Event::Pick {
                belt: Some(1),
                id: Some(17),
                x: 120.0,
                y: -35.5,
                z: -800.0,
            },
            EventKind::Place => Event::Place {
                belt: Some(2),
                id: Some(3),
                x: -150.0,
                y: 40.0,
                z: -790.0,
            },
            EventKind::PpTarget => Event::PpTarget {
                target: 1,
                id: Some(17),
                x: 120.0,
                y: -35.5,
                z: -800.0,
            },
            EventKind::Missed => Event::Missed {
                belt: 1,
                id: 18,
                x: 410.0,
            },
            EventKind::Gripper => Event::Gripper {
                action: "close".into(),
            },
            EventKind::PpError => Event::PpError {
                id: 20306,
                message: "software limit of Z reached".into(),
            },
            EventKind::PpWarning => Event::PpWarning {
                id: 17918,
                message: "the belt's list of workpieces is full".into(),
            },
            EventKind::PpHomed => Event::PpHomed { order: 1 },
            EventKind::IoFault => Event::IoFault {
                device: "modbus://127.0.0.1:5020 unit 1".into(),
                cause: "no answer within 50 ms".into(),
            },
            EventKind::IoReconnect => Event::IoReconnect {
                device: "modbus://127.0.0.1:5020 unit 1".into(),
                attempts: 3,
            },
            EventKind::Fault => Event::Fault {
                axis: "Motion".into(),
                fault: "following_error".into(),
                command: 12.5,
                feedback: 12.25,
                limit: 0.2,
            },
        }
    }
}

/// One line of a trace read back: the time, the update and the event.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct Line<'a> {
    /// Seconds.
    #[serde(deserialize_with = "real")]
    pub t: f64,
    /// The update.
    pub tick: u64,
    /// The event.
    #[serde(flatten)]
    pub event: Event<'a>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_an_example_of_its_kind_that_reads_back() {
        for &kind in EventKind::ALL {
            let e = Event::example(kind);
            assert_eq!(e.kind(), kind);
            let json = serde_json::to_value(&e).expect("serializes");
            assert_eq!(json["kind"], kind.as_str(), "{kind:?}");
            let line = format!(
                "{{\"t\":1.0,\"tick\":1000,{}",
                &serde_json::to_string(&e).expect("serializes")[1..]
            );
            let back: Line<'_> = serde_json::from_str(&line).expect("reads back");
            assert_eq!(back.event, e, "{line}");
        }
    }

    #[test]
    fn non_finite_numbers_are_written_null_and_read_back_as_nan() {
        let e = Event::Capture {
            object: "Capture.0".into(),
            time: 0.5,
            master: f64::NAN,
            command: f64::INFINITY,
            feedback: 1.0,
        };
        let text = serde_json::to_string(&e).expect("serializes");
        assert!(text.contains("\"master\":null,\"command\":null"), "{text}");
        let line = format!("{{\"t\":0.5,\"tick\":500,{}", &text[1..]);
        let back: Line<'_> = serde_json::from_str(&line).expect("reads back");
        let Event::Capture {
            master, command, ..
        } = back.event
        else {
            panic!("a capture: {line}");
        };
        assert!(master.is_nan() && command.is_nan());
        let change: Line<'_> =
            serde_json::from_str(r#"{"t":0,"tick":0,"kind":"change","name":"Var.X","value":null}"#)
                .expect("a null value reads back");
        assert!(matches!(change.event, Event::Change { value: Value::Num(x), .. } if x.is_nan()));
    }

    #[test]
    fn kinds_are_distinct() {
        let mut seen = std::collections::BTreeSet::new();
        for k in EventKind::ALL {
            assert!(seen.insert(k.as_str()), "{k} twice");
        }
    }
}
