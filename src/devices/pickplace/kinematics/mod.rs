//! Robot kinematics for pick & place: the transformation between the tool's Cartesian position
//! and the robot's joints. Paths are planned in Cartesian space; the kinematics turn them into
//! joint setpoints and say, by name, when a point cannot be reached.

pub mod delta3;

/// A point the robot cannot reach, or a geometry that is no robot.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KinematicsError {
    /// No joint position reaches this tool position (mm).
    #[error("the point ({x:.3}, {y:.3}, {z:.3}) mm is out of the robot's reach")]
    Unreachable {
        /// X of the point, mm.
        x: f64,
        /// Y of the point, mm.
        y: f64,
        /// Z of the point, mm.
        z: f64,
    },
    /// No tool position corresponds to these joint angles (degrees).
    #[error(
        "the joint angles ({0:.3}°, {1:.3}°, {2:.3}°) put the arms out of reach of one another"
    )]
    NoPose(f64, f64, f64),
    /// A dimension that makes no robot.
    #[error("{0}")]
    Geometry(String),
}
