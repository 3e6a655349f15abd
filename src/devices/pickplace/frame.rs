//! Coordinate frames: a pose (X, Y, Z, A, B, C) as the manual gives belt origins and workpiece
//! positions, and the rigid transform it stands for.
//!
//! A, B and C are rotations in degrees about X, Y and Z; the rotation is R = Rz(C)·Ry(B)·Rx(A)
//! (roll-pitch-yaw about fixed axes), so a belt rotated by C = 180° runs along −X of the machine.

/// A rigid transform: rotation matrix (rows) and translation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Rotation, row-major.
    pub rot: [[f64; 3]; 3],
    /// Origin in the parent frame.
    pub origin: [f64; 3],
}

impl Frame {
    /// The identity.
    pub const IDENTITY: Frame = Frame {
        rot: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        origin: [0.0; 3],
    };

    /// The frame of a pose `[x, y, z, a, b, c]` (mm, degrees).
    pub fn from_pose(p: [f64; 6]) -> Frame {
        let (sa, ca) = p[3].to_radians().sin_cos();
        let (sb, cb) = p[4].to_radians().sin_cos();
        let (sc, cc) = p[5].to_radians().sin_cos();
        Frame {
            rot: [
                [cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa],
                [sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa],
                [-sb, cb * sa, cb * ca],
            ],
            origin: [p[0], p[1], p[2]],
        }
    }

    /// A point given in this frame, in the parent frame.
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let r = &self.rot;
        [
            r[0][0] * p[0] + r[0][1] * p[1] + r[0][2] * p[2] + self.origin[0],
            r[1][0] * p[0] + r[1][1] * p[1] + r[1][2] * p[2] + self.origin[1],
            r[2][0] * p[0] + r[2][1] * p[1] + r[2][2] * p[2] + self.origin[2],
        ]
    }

    /// A direction given in this frame, in the parent frame.
    pub fn rotate(&self, d: [f64; 3]) -> [f64; 3] {
        let r = &self.rot;
        [
            r[0][0] * d[0] + r[0][1] * d[1] + r[0][2] * d[2],
            r[1][0] * d[0] + r[1][1] * d[1] + r[1][2] * d[2],
            r[2][0] * d[0] + r[2][1] * d[1] + r[2][2] * d[2],
        ]
    }

    /// The frame's X axis in the parent frame (a belt's direction of travel).
    pub fn x_axis(&self) -> [f64; 3] {
        [self.rot[0][0], self.rot[1][0], self.rot[2][0]]
    }

    /// The rotation about Z of this frame (its C angle, degrees), for frames not rotated in A
    /// and B.
    pub fn c_degrees(&self) -> f64 {
        self.rot[1][0].atan2(self.rot[0][0]).to_degrees()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manual_belt_example_runs_along_minus_x() {
        // The manual's belt at (400, 500, 100) rotated C = 180°.
        let f = Frame::from_pose([400.0, 500.0, 100.0, 0.0, 0.0, 180.0]);
        let p = f.apply([210.0, -50.0, 10.0]);
        assert!((p[0] - 190.0).abs() < 1e-9 && (p[1] - 550.0).abs() < 1e-9);
        assert!((p[2] - 110.0).abs() < 1e-12);
        assert!((f.x_axis()[0] + 1.0).abs() < 1e-12);
    }

    #[test]
    fn rotations_compose_z_y_x() {
        let f = Frame::from_pose([0.0, 0.0, 0.0, 90.0, 0.0, 90.0]);
        // Rx(90) takes Y to Z; Rz(90) leaves Z.
        let d = f.rotate([0.0, 1.0, 0.0]);
        assert!(d[0].abs() < 1e-12 && d[1].abs() < 1e-12 && (d[2] - 1.0).abs() < 1e-12);
    }
}
