//! What `machine.toml` sets up for the pick & place module beyond the manual's parameters: the
//! kinematics, the real axes' limits (the manual keeps them in the axes group's AXIS_REF
//! settings), software limit positions, and the belt drives' own limits.

use crate::devices::pickplace::kinematics::delta3::Delta3;

/// How the tool's Cartesian position maps to the real axes.
#[derive(Debug, Clone, PartialEq)]
pub enum Kinematics {
    /// X, Y, Z, C and Aux1 drive axes directly.
    Cartesian,
    /// A Delta3 parallel robot: the real axes A1–A3 are the three arm angles (degrees).
    Delta3(Delta3),
}

/// Velocity, acceleration and jerk limits of one axis; 0 means no limit.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisLimit {
    /// Units/s.
    pub max_vel: f64,
    /// Units/s².
    pub max_acc: f64,
    /// Units/s³.
    pub max_jerk: f64,
}

/// A belt drive (conveying belt CVn) as the machine has it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeltSetup {
    /// Belt number, 1–16 (CV1 … CV16).
    pub number: u32,
    /// The belt drive's own limits: the scenario's belt profile must stay inside them, and the
    /// planner keeps this much of each robot axis's limits in reserve while it tracks the belt.
    pub limit: AxisLimit,
}

/// Everything `[pickplace]` in `machine.toml` sets up that is not a member of the module.
#[derive(Debug, Clone, PartialEq)]
pub struct PickPlaceSetup {
    /// The kinematics.
    pub kinematics: Kinematics,
    /// Limits of the real axes A1–A3 (Delta3 joints, degrees); unused for Cartesian.
    pub joint_limits: [AxisLimit; 3],
    /// Software limit positions (min, max) per manual axis index 1–13 (X, Y, Z, A, B, C, A1–A6,
    /// Aux1), stored at index 0–12; `None` where the machine sets none.
    pub sw_limits: [Option<(f64, f64)>; 13],
    /// The tool's position (X, Y, Z, mm) when the run starts.
    pub start: [f64; 3],
    /// The belts the machine has, in number order.
    pub belts: Vec<BeltSetup>,
    /// `prep_budget`: work units a path preparation may use per update, spread over as many
    /// updates as it needs (eTMState PREPARING_PATH meanwhile); `None`: a path is planned
    /// within the update it is asked for. A machine file without the key gets
    /// `Some(PREP_BUDGET)`; `prep_budget = false` gives `None`.
    pub prep_budget: Option<u64>,
}
