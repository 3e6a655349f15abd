//! The moves of a compound chain: an index that starts at the speed the compounded index before
//! it left the axis at, and one that is itself compounded and so ends at its own velocity
//! instead of at rest. Plain indexes (from rest, to rest) stay [`super::trapezoid::Trapezoid`]s,
//! so their arithmetic is exactly what it always was.

use super::trapezoid::Phase;

/// A move of constant-acceleration pieces: from `v0` to the velocity, cruise, then to rest or
/// (compounded) on at the velocity to the end point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blend {
    sign: f64,
    distance: f64,
    /// Up to three pieces: (length, speed at its start, acceleration, phase).
    pieces: [(f64, f64, f64, Phase); 3],
    count: usize,
    /// Speed at the end point (0 unless compounded).
    v_end: f64,
}

impl Blend {
    /// Plan a move of `distance` (signed) starting at speed `v0` (0 or more, in the move's
    /// direction) toward `velocity`, with `accel` to go faster and `decel` to go slower. A
    /// compounded move ends at its end point at the speed it has there (its velocity, or less
    /// when the distance is too short to reach it) instead of at rest.
    pub fn new(
        distance: f64,
        v0: f64,
        velocity: f64,
        accel: f64,
        decel: f64,
        compounded: bool,
    ) -> Result<Blend, String> {
        super::trapezoid::settings(distance, velocity, accel, decel)?;
        if !(v0.is_finite() && v0 >= 0.0) {
            return Err(format!("the starting speed must be 0 or more, not {v0}"));
        }
        let d = distance.abs();
        // The ramp from v0 to the velocity: up at the acceleration, down at the deceleration.
        let ramp = |from: f64, to: f64| -> (f64, f64, Phase) {
            if to >= from {
                (
                    accel,
                    (to * to - from * from) / (2.0 * accel),
                    Phase::Accelerating,
                )
            } else {
                (
                    -decel,
                    (from * from - to * to) / (2.0 * decel),
                    Phase::Decelerating,
                )
            }
        };
        let mut pieces = [(0.0, 0.0, 0.0, Phase::Done); 3];
        let mut count = 0;
        let mut push = |len: f64, v: f64, a: f64, phase: Phase| {
            if len > 0.0 {
                pieces[count] = (len, v, a, phase);
                count += 1;
            }
        };
        let v_end;
        if compounded {
            let (a, s, phase) = ramp(v0, velocity);
            if s >= d {
                // Too short to reach the velocity: it ends on the ramp, at the speed it has there.
                // Slowing down, it is still at or above the velocity there: never at rest.
                let v = (v0 * v0 + 2.0 * a * d).max(0.0).sqrt();
                push((v - v0) / a, v0, a, phase);
                v_end = v;
            } else {
                push((velocity - v0) / a, v0, a, phase);
                push((d - s) / velocity, velocity, 0.0, Phase::AtVelocity);
                v_end = velocity;
            }
        } else {
            let stop = v0 * v0 / (2.0 * decel);
            if stop > d {
                return Err(format!(
                    "it cannot stop within its distance {distance} from the speed {v0} the \
                     compounded index left the axis at"
                ));
            }
            let (a, s, phase) = ramp(v0, velocity);
            let down = velocity * velocity / (2.0 * decel);
            // Slower than it starts, s + down is the stop, which fits: only a move speeding up
            // can be too short to cruise.
            if s + down <= d {
                push((velocity - v0) / a, v0, a, phase);
                push((d - s - down) / velocity, velocity, 0.0, Phase::AtVelocity);
                push(velocity / decel, velocity, -decel, Phase::Decelerating);
            } else {
                // A triangle from v0: up to the peak, down to rest.
                let k = 1.0 / (2.0 * accel) + 1.0 / (2.0 * decel);
                let peak = ((d + v0 * v0 / (2.0 * accel)) / k).sqrt().max(v0);
                push((peak - v0) / accel, v0, accel, Phase::Accelerating);
                push(peak / decel, peak, -decel, Phase::Decelerating);
            }
            v_end = 0.0;
        }
        Ok(Blend {
            sign: if distance < 0.0 { -1.0 } else { 1.0 },
            distance: d,
            pieces,
            count,
            v_end,
        })
    }

    /// Length of the move in its domain.
    pub fn duration(&self) -> f64 {
        self.pieces[..self.count].iter().map(|p| p.0).sum()
    }

    /// Speed at the end point, signed (0 unless compounded).
    pub fn end_velocity(&self) -> f64 {
        self.sign * self.v_end
    }

    /// Position, velocity and phase `u` into the move.
    pub fn at(&self, u: f64) -> (f64, f64, Phase) {
        let u = u.max(0.0);
        let total = self.duration();
        if u >= total {
            return (
                self.sign * self.distance,
                self.sign * self.v_end,
                Phase::Done,
            );
        }
        let mut start = 0.0;
        let mut p = 0.0;
        for (i, &(len, v, a, phase)) in self.pieces[..self.count].iter().enumerate() {
            let last = i + 1 == self.count;
            if u < start + len || last {
                let (pos, vel) = if last {
                    // The last piece measured back from the end point, so the end is exact.
                    let r = total - u;
                    let ve = v + a * len;
                    (self.distance - ve * r + 0.5 * a * r * r, ve - a * r)
                } else {
                    let t = u - start;
                    (p + v * t + 0.5 * a * t * t, v + a * t)
                };
                return (self.sign * pos, self.sign * vel, phase);
            }
            p += v * len + 0.5 * a * len * len;
            start += len;
        }
        (
            self.sign * self.distance,
            self.sign * self.v_end,
            Phase::Done,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_compounded_move_ends_at_its_velocity_at_its_end_point() {
        // From rest: 1 s up to 2 (1 unit), then 4 units at 2 (2 s).
        let b = Blend::new(5.0, 0.0, 2.0, 2.0, 1.0, true).expect("plan");
        assert!((b.duration() - 3.0).abs() < 1e-12);
        assert_eq!(b.at(3.0), (5.0, 2.0, Phase::Done));
        assert_eq!(b.end_velocity(), 2.0);
        assert!((b.at(1.0).0 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_move_from_speed_ramps_to_its_velocity_and_stops_at_its_end() {
        // From 2 down to 1 (decel 1: 1.5 units, 1 s), cruise, down to rest (0.5 units, 1 s).
        let b = Blend::new(-4.0, 2.0, 1.0, 1.0, 1.0, false).expect("plan");
        assert!((b.duration() - 4.0).abs() < 1e-12, "{}", b.duration());
        assert_eq!(b.at(4.0), (-4.0, 0.0, Phase::Done));
        assert_eq!(b.at(0.0).1, -2.0);
        assert_eq!(b.at(2.0).2, Phase::AtVelocity);
        // Continuous at the piece boundaries.
        for k in 1..400 {
            let u = f64::from(k) * 0.01;
            let (a, _, _) = b.at(u - 1e-9);
            let (c, _, _) = b.at(u + 1e-9);
            assert!((a - c).abs() < 1e-7, "{u}");
        }
    }

    #[test]
    fn a_triangle_from_speed_and_a_move_that_cannot_stop() {
        let b = Blend::new(1.0, 1.0, 10.0, 1.0, 1.0, false).expect("plan");
        assert!((b.at(b.duration()).0 - 1.0).abs() < 1e-12);
        assert!(Blend::new(1.0, 10.0, 1.0, 1.0, 1.0, false).is_err());
    }
}
