//! The drive's set-up that is not a member: what `machine.toml` says about its queues,
//! indexes, homes, PLS, the axis's rollover and its user units. The configuration stage
//! validates it; the drive is built from it.

use crate::registry::SlotId;

/// User units: names, and how they relate to motor revolutions and encoder counts.
#[derive(Debug, Clone, PartialEq)]
pub struct Units {
    /// The servo axis's unit.
    pub motor: String,
    /// Servo units per motor revolution.
    pub motor_per_rev: f64,
    /// Motor encoder counts per revolution.
    pub motor_counts_per_rev: f64,
    /// The master's unit.
    pub master: String,
    /// Master encoder counts per master unit.
    pub master_counts_per_unit: f64,
}

impl Default for Units {
    fn default() -> Self {
        Units {
            motor: "units".into(),
            motor_per_rev: 1.0,
            motor_counts_per_rev: 4096.0,
            master: "units".into(),
            master_counts_per_unit: 1000.0,
        }
    }
}

/// The set-up of one PLS that is not a member.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlsConfig {
    /// The position the window is on.
    pub source: QueueSource,
    /// Rollover of that position (0: none).
    pub rollover: f64,
}

/// The set-up of one home that is not a member.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct HomeConfig {
    /// The slot of the reference input, if one is set.
    pub reference: Option<SlotId>,
    /// The offset is specified (`Home.N.Offset`), not calculated.
    pub specified_offset: bool,
}

/// The position a queue compares with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum QueueSource {
    /// The master (encoder) position.
    #[default]
    Master,
    /// The motor feedback position.
    Feedback,
    /// The motor command position.
    Command,
}

/// How an index moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IndexType {
    /// By its distance from where it starts.
    #[default]
    Incremental,
    /// To its distance as a position.
    Absolute,
    /// Toward its distance (the limit) until the sensor, then `RegistrationOffset` further.
    Registration,
    /// To its distance as a position on the rolled-over axis, moving plus.
    RotaryPlus,
    /// To its distance as a position on the rolled-over axis, moving minus.
    RotaryMinus,
}

/// The set-up of one index that is not a member.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IndexConfig {
    /// Incremental or absolute.
    pub kind: IndexType,
    /// Velocity and accelerations per master unit instead of per second.
    pub synchronized: bool,
    /// The move takes `Index.N.Time`; its velocity is computed.
    pub timed: bool,
}

/// The set-up of one queue that is not a member.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct QueueConfig {
    /// Capacity.
    pub size: u32,
    /// Count at which QueueFull turns on.
    pub full_level: u32,
    /// What exit positions are compared with.
    pub source: QueueSource,
}

impl Default for QueueConfig {
    fn default() -> QueueConfig {
        QueueConfig {
            size: 8,
            full_level: 8,
            source: QueueSource::Master,
        }
    }
}

/// Everything about the drive `machine.toml` sets that is not a member.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DriveSetup {
    /// Per queue.
    pub queues: Vec<QueueConfig>,
    /// Per index.
    pub indexes: Vec<IndexConfig>,
    /// Per home.
    pub homes: Vec<HomeConfig>,
    /// Per PLS.
    pub plss: Vec<PlsConfig>,
    /// Rollover of the servo axis's reported positions (0: none).
    pub rollover: f64,
    /// User units.
    pub units: Units,
    /// The servo loop (`[servo]`); `None`: the ideal servo, feedback equals command.
    pub servo: Option<crate::devices::servo::ServoParams>,
}
