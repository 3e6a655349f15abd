//! The robot as the module drives it: the tool pose, the thirteen axes the manual numbers
//! (X, Y, Z, A, B, C, A1–A6, Aux1) and their limits, through the kinematics.

use super::setup::{AxisLimit, Kinematics};
use crate::devices::pickplace::kinematics::KinematicsError;

/// Number of axes the manual's arrays index (1–13).
pub const AXES: usize = 13;

/// The manual's axis names, in its array order.
pub const AXIS_NAMES: [&str; AXES] = [
    "X", "Y", "Z", "A", "B", "C", "A1", "A2", "A3", "A4", "A5", "A6", "Aux1",
];

/// Index of X, Y, Z, C, A1 and Aux1 in the manual's arrays (0-based).
pub const X: usize = 0;
/// Z axis.
pub const Z: usize = 2;
/// A axis.
pub const A: usize = 3;
/// B axis.
pub const B: usize = 4;
/// C axis.
pub const C: usize = 5;
/// First real axis.
pub const A1: usize = 6;
/// The auxiliary axis.
pub const AUX1: usize = 12;

/// Where the tool is: position (mm), orientation A, B, C (degrees) and Aux1.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pose {
    /// X, Y, Z, mm.
    pub p: [f64; 3],
    /// A and B: held (neither a gantry with C nor a Delta3 has them), reported as set.
    pub ab: [f64; 2],
    /// C, degrees.
    pub c: f64,
    /// Aux1, units.
    pub aux: f64,
}

/// The robot: kinematics and the limits of every axis.
#[derive(Debug, Clone)]
pub struct Robot {
    /// The kinematics.
    pub kinematics: Kinematics,
    /// Limits per manual axis (0: none).
    pub limits: [AxisLimit; AXES],
}

impl Robot {
    /// All thirteen axis values of a pose: the Cartesian ones as they are, the real axes from
    /// the kinematics (a gantry's real axes A1–A4 are X, Y, Z and C).
    pub fn axes(&self, pose: &Pose) -> Result<[f64; AXES], KinematicsError> {
        let mut out = [0.0; AXES];
        out[..3].copy_from_slice(&pose.p);
        out[A] = pose.ab[0];
        out[B] = pose.ab[1];
        out[C] = pose.c;
        out[AUX1] = pose.aux;
        match &self.kinematics {
            Kinematics::Cartesian => {
                out[A1..A1 + 3].copy_from_slice(&pose.p);
                out[A1 + 3] = pose.c;
            }
            Kinematics::Delta3(d) => {
                let q = d.inverse(pose.p)?;
                out[A1..A1 + 3].copy_from_slice(&q);
            }
        }
        Ok(out)
    }

    /// The real axes that exist on this robot (the limits of the others are not checked).
    pub fn has_axis(&self, i: usize) -> bool {
        match self.kinematics {
            Kinematics::Cartesian => !matches!(i, A | B) && !(A1 + 4..A1 + 6).contains(&i),
            Kinematics::Delta3(_) => !matches!(i, A | B) && !(A1 + 3..A1 + 6).contains(&i),
        }
    }

    /// The tool position for real-axis values A1–A3 (jogging a joint moves the tool).
    pub fn forward(&self, q: [f64; 3]) -> Result<[f64; 3], KinematicsError> {
        match &self.kinematics {
            Kinematics::Cartesian => Ok(q),
            Kinematics::Delta3(d) => d.forward(q),
        }
    }
}
