//! The trapezoidal move: accelerate, cruise, decelerate over a distance, in a domain that is time
//! (realtime motion) or master distance (synchronized motion). A move too short to reach its
//! velocity becomes a triangle.

/// Which way a phase of the move is going.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Speeding up.
    Accelerating,
    /// At velocity.
    AtVelocity,
    /// Slowing down.
    Decelerating,
    /// Finished.
    Done,
}

/// A planned move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trapezoid {
    sign: f64,
    distance: f64,
    peak: f64,
    accel: f64,
    decel: f64,
    t_accel: f64,
    t_cruise: f64,
    t_decel: f64,
}

/// Whether a move's settings can be planned: a finite distance, and a velocity, acceleration
/// and deceleration above 0. Err: which is not, in words.
pub fn settings(distance: f64, velocity: f64, accel: f64, decel: f64) -> Result<(), String> {
    for (name, x) in [
        ("velocity", velocity),
        ("acceleration", accel),
        ("deceleration", decel),
    ] {
        if !(x.is_finite() && x > 0.0) {
            return Err(format!("the {name} must be above 0, not {x}"));
        }
    }
    if !distance.is_finite() {
        return Err(format!("the distance must be a number, not {distance}"));
    }
    Ok(())
}

impl Trapezoid {
    /// Plan a move of `distance` (signed) with the given velocity, acceleration and
    /// deceleration (all above 0, in domain units).
    pub fn new(distance: f64, velocity: f64, accel: f64, decel: f64) -> Result<Trapezoid, String> {
        settings(distance, velocity, accel, decel)?;
        let d = distance.abs();
        let mut peak = velocity;
        let mut t_accel = velocity / accel;
        let mut t_decel = velocity / decel;
        let ramps = velocity * velocity / (2.0 * accel) + velocity * velocity / (2.0 * decel);
        let t_cruise = if ramps > d {
            peak = (2.0 * d * accel * decel / (accel + decel)).sqrt();
            t_accel = peak / accel;
            t_decel = peak / decel;
            0.0
        } else {
            (d - ramps) / velocity
        };
        Ok(Trapezoid {
            sign: if distance < 0.0 { -1.0 } else { 1.0 },
            distance: d,
            peak,
            accel,
            decel,
            t_accel,
            t_cruise,
            t_decel,
        })
    }

    /// Plan a move of `distance` that takes `time` (domain units) at the given acceleration and
    /// deceleration, cruising no faster than `max_velocity`. When that cannot be done the move
    /// is as quick as the limits allow, and the second value is true (ProfileLimited).
    pub fn timed(
        distance: f64,
        time: f64,
        max_velocity: f64,
        accel: f64,
        decel: f64,
    ) -> Result<(Trapezoid, bool), String> {
        if !(time.is_finite() && time > 0.0) {
            return Err(format!("the time must be above 0, not {time}"));
        }
        let fastest = Trapezoid::new(distance, max_velocity, accel, decel)?;
        if fastest.duration() >= time {
            return Ok((fastest, fastest.duration() > time));
        }
        // Cruise velocity v with the given ramps: time = d/v + v·k, k = 1/(2a) + 1/(2d).
        // The smaller root is the one whose ramps fit inside the move.
        let d = distance.abs();
        if d == 0.0 {
            return Ok((fastest, false));
        }
        let k = 1.0 / (2.0 * accel) + 1.0 / (2.0 * decel);
        let disc = time * time - 4.0 * k * d;
        let v = if disc >= 0.0 {
            (time - disc.sqrt()) / (2.0 * k)
        } else {
            time / (2.0 * k)
        };
        Ok((Trapezoid::new(distance, v, accel, decel)?, false))
    }

    /// Length of the move in its domain (seconds or master units).
    pub fn duration(&self) -> f64 {
        self.t_accel + self.t_cruise + self.t_decel
    }

    /// The signed distance.
    pub fn distance(&self) -> f64 {
        self.sign * self.distance
    }

    /// Position, velocity and phase `u` into the move (clamped to the move).
    pub fn at(&self, u: f64) -> (f64, f64, Phase) {
        let u = u.max(0.0);
        let (p, v, phase) = if u < self.t_accel {
            (
                0.5 * self.accel * u * u,
                self.accel * u,
                Phase::Accelerating,
            )
        } else if u < self.t_accel + self.t_cruise {
            let c = u - self.t_accel;
            (
                0.5 * self.peak * self.t_accel + self.peak * c,
                self.peak,
                Phase::AtVelocity,
            )
        } else if u < self.duration() {
            // Measured back from the end, so the end is exact.
            let r = self.duration() - u;
            (
                self.distance - 0.5 * self.decel * r * r,
                self.decel * r,
                Phase::Decelerating,
            )
        } else {
            (self.distance, 0.0, Phase::Done)
        };
        (self.sign * p, self.sign * v, phase)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_trapezoid_is_continuous_and_ends_exactly() {
        let t = Trapezoid::new(10.0, 2.0, 4.0, 1.0).expect("plan");
        // accel 0.5 s (0.5 units), decel 2 s (2 units), cruise 7.5 units = 3.75 s.
        assert!((t.duration() - 6.25).abs() < 1e-12);
        assert_eq!(t.at(t.duration()).0, 10.0);
        assert_eq!(t.at(100.0), (10.0, 0.0, Phase::Done));
        let mut last = 0.0;
        for k in 0..=625 {
            let (p, v, _) = t.at(f64::from(k) * 0.01);
            assert!(p >= last - 1e-12 && (0.0..=2.0 + 1e-12).contains(&v));
            last = p;
        }
        assert!((t.at(0.5).0 - 0.5).abs() < 1e-12);
        assert_eq!(t.at(1.0).2, Phase::AtVelocity);
        assert_eq!(t.at(5.0).2, Phase::Decelerating);
    }

    #[test]
    fn a_short_move_is_a_triangle() {
        let t = Trapezoid::new(-1.0, 10.0, 2.0, 2.0).expect("plan");
        // peak sqrt(2·1·2·2/4) = 1.414…, 0.707 s each way.
        assert!((t.duration() - 2.0 * (0.5f64).sqrt()).abs() < 1e-12);
        assert_eq!(t.at(t.duration()).0, -1.0);
        assert!((t.at(t.duration() / 2.0).0 + 0.5).abs() < 1e-12);
    }

    #[test]
    fn a_timed_move_takes_its_time_or_says_it_cannot() {
        let (t, limited) = Trapezoid::timed(10.0, 4.0, 100.0, 10.0, 10.0).expect("plan");
        assert!(!limited);
        assert!((t.duration() - 4.0).abs() < 1e-12, "{}", t.duration());
        assert_eq!(t.at(4.0).0, 10.0);
        // Too fast for the velocity limit: as quick as the limits allow.
        let (t, limited) = Trapezoid::timed(10.0, 0.5, 5.0, 10.0, 10.0).expect("plan");
        assert!(limited);
        assert!((t.duration() - 2.5).abs() < 1e-12, "{}", t.duration());
    }

    #[test]
    fn bad_parameters_are_refused() {
        assert!(Trapezoid::new(1.0, 0.0, 1.0, 1.0).is_err());
        assert!(Trapezoid::new(f64::NAN, 1.0, 1.0, 1.0).is_err());
    }
}
