//! The Delta3 parallel robot (spec: pick-and-place.md). Base triangle side `f`, effector
//! triangle side `e`, upper arm `rf`, forearm `re` (mm). Arm 1 lies along −Y, arms 2 and 3 at
//! +30° and +150° from +X; θ = 0 with the upper arm horizontal, positive θ moving the arm down;
//! z is negative below the base. Angles in degrees.

use super::KinematicsError;

const SQRT3: f64 = 1.732_050_807_568_877_2;
const TAN30: f64 = 1.0 / SQRT3;
const SIN120: f64 = SQRT3 / 2.0;
const COS120: f64 = -0.5;

/// A Delta3 robot's dimensions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Delta3 {
    f: f64,
    e: f64,
    rf: f64,
    re: f64,
}

impl Delta3 {
    /// A robot with these dimensions (mm); each must be a positive number, and the forearm
    /// longer than the upper arm is not required, but the arms must be able to close the loop.
    pub fn new(f: f64, e: f64, rf: f64, re: f64) -> Result<Delta3, KinematicsError> {
        for (name, v) in [("f", f), ("e", e), ("rf", rf), ("re", re)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(KinematicsError::Geometry(format!(
                    "Delta3 {name} = {v}: a dimension must be a positive number of mm"
                )));
            }
        }
        let robot = Delta3 { f, e, rf, re };
        // The home pose (all arms horizontal) must exist, or the dimensions make no robot.
        robot.forward([0.0; 3]).map_err(|_| {
            KinematicsError::Geometry(format!(
                "Delta3 f {f}, e {e}, rf {rf}, re {re}: the forearms cannot reach the effector"
            ))
        })?;
        Ok(robot)
    }

    /// The tool position (mm) for joint angles `theta` (degrees).
    pub fn forward(&self, theta: [f64; 3]) -> Result<[f64; 3], KinematicsError> {
        let no_pose = || KinematicsError::NoPose(theta[0], theta[1], theta[2]);
        if theta.iter().any(|t| !t.is_finite()) {
            return Err(no_pose());
        }
        let [t1, t2, t3] = theta.map(f64::to_radians);
        let t = (self.f - self.e) * TAN30 / 2.0;
        let y1 = -(t + self.rf * t1.cos());
        let z1 = -self.rf * t1.sin();
        let y2 = (t + self.rf * t2.cos()) * 0.5;
        let x2 = y2 * SQRT3;
        let z2 = -self.rf * t2.sin();
        let y3 = (t + self.rf * t3.cos()) * 0.5;
        let x3 = -y3 * SQRT3;
        let z3 = -self.rf * t3.sin();
        let dnm = (y2 - y1) * x3 - (y3 - y1) * x2;
        if dnm.abs() < 1e-12 {
            return Err(no_pose());
        }
        let w1 = y1 * y1 + z1 * z1;
        let w2 = x2 * x2 + y2 * y2 + z2 * z2;
        let w3 = x3 * x3 + y3 * y3 + z3 * z3;
        let a1 = (z2 - z1) * (y3 - y1) - (z3 - z1) * (y2 - y1);
        let b1 = -((w2 - w1) * (y3 - y1) - (w3 - w1) * (y2 - y1)) / 2.0;
        let a2 = -(z2 - z1) * x3 + (z3 - z1) * x2;
        let b2 = ((w2 - w1) * x3 - (w3 - w1) * x2) / 2.0;
        let a = a1 * a1 + a2 * a2 + dnm * dnm;
        let b = 2.0 * (a1 * b1 + a2 * (b2 - y1 * dnm) - z1 * dnm * dnm);
        let c =
            (b2 - y1 * dnm) * (b2 - y1 * dnm) + b1 * b1 + dnm * dnm * (z1 * z1 - self.re * self.re);
        let d = b * b - 4.0 * a * c;
        if d < 0.0 {
            return Err(no_pose());
        }
        // The lower of the two solutions: the effector hangs below the base.
        let z0 = -0.5 * (b + d.sqrt()) / a;
        let p = [(a1 * z0 + b1) / dnm, (a2 * z0 + b2) / dnm, z0];
        if p.iter().all(|v| v.is_finite()) {
            Ok(p)
        } else {
            Err(no_pose())
        }
    }

    /// The joint angles (degrees) that put the tool at `p` (mm).
    pub fn inverse(&self, p: [f64; 3]) -> Result<[f64; 3], KinematicsError> {
        let [x, y, z] = p;
        let unreachable = || KinematicsError::Unreachable { x, y, z };
        if p.iter().any(|v| !v.is_finite()) {
            return Err(unreachable());
        }
        let t1 = self.arm(x, y, z).ok_or_else(unreachable)?;
        let t2 = self
            .arm(x * COS120 + y * SIN120, y * COS120 - x * SIN120, z)
            .ok_or_else(unreachable)?;
        let t3 = self
            .arm(x * COS120 - y * SIN120, y * COS120 + x * SIN120, z)
            .ok_or_else(unreachable)?;
        Ok([t1, t2, t3])
    }

    /// The angle of arm 1 (in the YZ plane) for an effector centre at (x0, y0, z0).
    fn arm(&self, x0: f64, y0: f64, z0: f64) -> Option<f64> {
        // Below the base only: at or above it the arm equations have no robot solution.
        if z0 >= 0.0 {
            return None;
        }
        let y1 = -0.5 * TAN30 * self.f;
        let y0 = y0 - 0.5 * TAN30 * self.e;
        let a = (x0 * x0 + y0 * y0 + z0 * z0 + self.rf * self.rf - self.re * self.re - y1 * y1)
            / (2.0 * z0);
        let b = (y1 - y0) / z0;
        let d = -(a + b * y1) * (a + b * y1) + self.rf * (b * b * self.rf + self.rf);
        if d < 0.0 {
            return None;
        }
        let yj = (y1 - a * b - d.sqrt()) / (b * b + 1.0);
        let zj = a + b * yj;
        let theta = (-zj / (y1 - yj)).atan().to_degrees() + if yj > y1 { 180.0 } else { 0.0 };
        theta.is_finite().then_some(theta)
    }
}
