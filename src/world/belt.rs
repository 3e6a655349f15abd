//! Conveying belts as the scenario drives them: a speed profile of constant speeds joined by
//! jerk-limited S-ramps. Travel, speed, acceleration and jerk are exact at any instant (the
//! profile is piecewise cubic in time), and so is the first instant the belt's travel reaches a
//! position, which is how workpiece detections tied to belt travel get their times.

/// One piece of the profile: from `t0`, travel `p0 + v0·dt + a0·dt²/2 + j·dt³/6`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    t0: f64,
    p0: f64,
    v0: f64,
    a0: f64,
    j: f64,
}

impl Piece {
    /// A piece that keeps the speed `v` from `t0` on.
    fn steady(t0: f64, p0: f64, v: f64) -> Piece {
        Piece {
            t0,
            p0,
            v0: v,
            a0: 0.0,
            j: 0.0,
        }
    }

    /// Travel since the piece's start `dt` seconds into it (Horner form: fewer roundings; kept
    /// apart from `p0` so root finding does not lose digits to a long travel).
    fn gain(&self, dt: f64) -> f64 {
        dt * (self.v0 + dt * (0.5 * self.a0 + dt * self.j / 6.0))
    }

    /// Speed `dt` seconds into the piece.
    fn speed(&self, dt: f64) -> f64 {
        self.v0 + dt * (self.a0 + 0.5 * dt * self.j)
    }

    /// Travel, speed and acceleration `dt` seconds into the piece.
    fn state(&self, dt: f64) -> (f64, f64, f64) {
        let p = self.p0 + self.gain(dt);
        let v = self.speed(dt);
        let a = self.a0 + dt * self.j;
        (p, v, a)
    }
}

/// A change of a belt's speed: from `at`, an S-ramp to `speed` taking `ramp` seconds.
///
/// The acceleration rises linearly from 0 to its peak 2Δv/T at T/2 and falls back to 0 at T
/// (jerk ±4Δv/T²), so acceleration is continuous and jerk bounded. `ramp = 0` is a step in speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeltChange {
    /// Start of the change, seconds (0 or more).
    pub at: f64,
    /// Target speed, mm/s (0 or more: a belt runs forward; 0 stops it).
    pub speed: f64,
    /// Duration of the S-ramp, seconds (0 or more; 0: at once).
    pub ramp: f64,
}

/// Why a belt profile cannot be built.
#[derive(Debug, Clone, PartialEq)]
pub struct BeltProfileError {
    /// Index of the offending change; `usize::MAX` for the initial speed.
    pub change: usize,
    /// What is wrong, phrased for the user.
    pub message: String,
}

impl std::fmt::Display for BeltProfileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for BeltProfileError {}

/// How far a change may start before the previous ramp ends and still count as touching it:
/// scenario times are whole nanoseconds, so anything closer is rounding of `at + ramp`.
const TOUCH: f64 = 1e-10;

/// A belt's motion over the whole run: travel in mm from 0 at t = 0.
#[derive(Debug, Clone, PartialEq)]
pub struct BeltProfile {
    /// Pieces in time order, no two starting at the same instant.
    pieces: Vec<Piece>,
    /// Highest speed, |acceleration| and |jerk| (infinite for a step in speed).
    peaks: (f64, f64, f64),
}

impl Default for BeltProfile {
    fn default() -> Self {
        BeltProfile::stopped()
    }
}

impl BeltProfile {
    /// A belt that stands still for the whole run.
    pub fn stopped() -> BeltProfile {
        BeltProfile {
            pieces: vec![Piece::steady(0.0, 0.0, 0.0)],
            peaks: (0.0, 0.0, 0.0),
        }
    }

    /// A profile starting at travel 0 with speed `initial` (mm/s), then `changes` in time order.
    ///
    /// A change may start when the previous one has finished (`at ≥ previous at + ramp`), not
    /// at the same instant as a previous step.
    pub fn new(initial: f64, changes: &[BeltChange]) -> Result<BeltProfile, BeltProfileError> {
        if !(initial.is_finite() && initial >= 0.0) {
            return Err(BeltProfileError {
                change: usize::MAX,
                message: format!("the initial speed must be 0 mm/s or more, not {initial}"),
            });
        }
        let mut pieces = vec![Piece::steady(0.0, 0.0, initial)];
        let mut peaks = (initial, 0.0f64, 0.0f64);
        let mut speed = initial;
        let mut busy_until = 0.0f64;
        for (i, c) in changes.iter().enumerate() {
            let bad = |message: String| Err(BeltProfileError { change: i, message });
            if !(c.speed.is_finite() && c.speed >= 0.0) {
                return bad(format!("a speed must be 0 mm/s or more, not {}", c.speed));
            }
            if !(c.ramp.is_finite() && c.ramp >= 0.0) {
                return bad(format!("a ramp must take 0 s or more, not {} s", c.ramp));
            }
            if !(c.at.is_finite() && c.at >= 0.0) {
                return bad(format!(
                    "a change must start at 0 s or later, not {} s",
                    c.at
                ));
            }
            if i > 0 && c.at <= changes[i - 1].at {
                return bad(format!(
                    "this change at {} s does not come after the previous one at {} s; changes must come in time order",
                    c.at,
                    changes[i - 1].at
                ));
            }
            if c.at < busy_until - TOUCH {
                return bad(format!(
                    "this change at {} s starts before the previous ramp has finished ({} s)",
                    c.at, busy_until
                ));
            }
            // A start within rounding of the previous ramp's end is moved onto it so the pieces
            // stay in time order.
            let at = c.at.max(busy_until);
            let dv = c.speed - speed;
            let last = pieces[pieces.len() - 1];
            let (p, _, _) = last.state(at - last.t0);
            if c.ramp > 0.0 && dv != 0.0 {
                let t = c.ramp;
                let jerk = 4.0 * dv / (t * t);
                let rise = Piece {
                    t0: at,
                    p0: p,
                    v0: speed,
                    a0: 0.0,
                    j: jerk,
                };
                push(&mut pieces, rise);
                let mid = at + 0.5 * t;
                let (pm, vm, am) = rise.state(mid - at);
                let fall = Piece {
                    t0: mid,
                    p0: pm,
                    v0: vm,
                    a0: am,
                    j: -jerk,
                };
                push(&mut pieces, fall);
                let end = at + t;
                let (pe, _, _) = fall.state(end - mid);
                // The target speed is set exactly rather than accumulated through the ramp.
                push(&mut pieces, Piece::steady(end, pe, c.speed));
                peaks.1 = peaks.1.max((2.0 * dv / t).abs());
                peaks.2 = peaks.2.max(jerk.abs());
            } else if dv != 0.0 {
                push(&mut pieces, Piece::steady(at, p, c.speed));
                // A step needs an infinite acceleration (and jerk) for an instant.
                peaks.1 = f64::INFINITY;
                peaks.2 = f64::INFINITY;
            }
            // Within an S-ramp the speed is monotonic, so the highest speed is a target speed.
            peaks.0 = peaks.0.max(c.speed);
            speed = c.speed;
            busy_until = at + c.ramp;
        }
        Ok(BeltProfile { pieces, peaks })
    }

    /// The piece in force at `t` (the last one starting at or before it).
    fn piece(&self, t: f64) -> Piece {
        let i = self.pieces.partition_point(|p| p.t0 <= t).saturating_sub(1);
        self.pieces[i]
    }

    /// Travel (mm) at `t` seconds; 0 before the run starts.
    pub fn position(&self, t: f64) -> f64 {
        if t < 0.0 {
            return 0.0;
        }
        let p = self.piece(t);
        p.state(t - p.t0).0
    }

    /// Speed (mm/s) at `t` seconds; 0 before the run starts.
    pub fn velocity(&self, t: f64) -> f64 {
        if t < 0.0 {
            return 0.0;
        }
        let p = self.piece(t);
        p.state(t - p.t0).1
    }

    /// Acceleration (mm/s²) at `t` seconds; 0 before the run starts and at a step in speed.
    pub fn acceleration(&self, t: f64) -> f64 {
        if t < 0.0 {
            return 0.0;
        }
        let p = self.piece(t);
        p.state(t - p.t0).2
    }

    /// Jerk (mm/s³) at `t` seconds; at a piece boundary, the jerk of the piece starting there.
    pub fn jerk(&self, t: f64) -> f64 {
        if t < 0.0 {
            return 0.0;
        }
        self.piece(t).j
    }

    /// First time the belt's travel reaches `position` (mm), `None` if it never does (the belt
    /// stops for good before). Positions at or below 0 are reached at t = 0.
    ///
    /// Inside a piece the travel is a monotonic cubic; the root is found by Newton's method kept
    /// inside a shrinking bracket (bisection when a step would leave it), to about 1e-14 s.
    pub fn time_at(&self, position: f64) -> Option<f64> {
        if position.is_nan() {
            return None;
        }
        if position <= 0.0 {
            return Some(0.0);
        }
        // Travel never decreases, so the piece where `position` is reached is the last one
        // starting below it.
        let k = self
            .pieces
            .partition_point(|p| p.p0 < position)
            .saturating_sub(1);
        let piece = self.pieces[k];
        let d = position - piece.p0;
        let Some(next) = self.pieces.get(k + 1) else {
            // The last piece runs at constant speed forever.
            if piece.v0 <= 0.0 {
                return None;
            }
            let t = piece.t0 + d / piece.v0;
            return t.is_finite().then_some(t);
        };
        let len = next.t0 - piece.t0;
        Some(piece.t0 + solve(&piece, d, len))
    }

    /// Highest speed (mm/s), |acceleration| (mm/s²) and |jerk| (mm/s³) anywhere in the
    /// profile; a step in speed counts as infinite acceleration and jerk.
    pub fn peaks(&self) -> (f64, f64, f64) {
        self.peaks
    }
}

/// Append a piece, replacing one that starts at the same instant (it would last no time).
fn push(pieces: &mut Vec<Piece>, piece: Piece) {
    if pieces.last().is_some_and(|l| l.t0 == piece.t0) {
        pieces.pop();
    }
    pieces.push(piece);
}

/// The `dt` in `[0, len]` where the piece's travel beyond `p0` first reaches `d` (> 0).
fn solve(piece: &Piece, d: f64, len: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, len);
    let f_hi = piece.gain(hi) - d;
    if f_hi <= 0.0 {
        // Reached only at the end (rounding of the boundary travel).
        return hi;
    }
    // Start from the chord through the bracket's ends: exact for constant speed.
    let mut x = hi * d / (f_hi + d);
    if !(x > lo && x < hi) {
        x = 0.5 * (lo + hi);
    }
    for _ in 0..200 {
        let fx = piece.gain(x) - d;
        let v = piece.speed(x);
        if fx == 0.0 {
            return x;
        }
        if fx < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - fx / v;
        let next = if v > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 1e-15 * (1.0 + hi) || hi - lo <= 1e-15 {
            return next;
        }
        x = next;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn s_ramp_travel_is_the_average_speed() {
        let b = BeltProfile::new(
            100.0,
            &[BeltChange {
                at: 1.0,
                speed: 300.0,
                ramp: 2.0,
            }],
        )
        .expect("profile");
        // 100 mm in the first second, then 2 s at an average of 200 mm/s.
        assert!(close(b.position(3.0), 500.0));
        assert!(close(b.velocity(2.0), 200.0));
        assert!(close(b.acceleration(2.0), 200.0));
        assert!(close(b.jerk(1.5), 200.0));
        assert!(close(b.jerk(2.5), -200.0));
        assert_eq!(b.peaks(), (300.0, 200.0, 200.0));
        let t = b.time_at(250.0).expect("reached");
        assert!(close(b.position(t), 250.0));
    }

    #[test]
    fn stop_for_good_is_never_passed() {
        let b = BeltProfile::new(
            10.0,
            &[BeltChange {
                at: 1.0,
                speed: 0.0,
                ramp: 0.0,
            }],
        )
        .expect("profile");
        assert_eq!(b.time_at(10.5), None);
        assert!(close(b.time_at(5.0).expect("reached"), 0.5));
        assert_eq!(b.peaks().1, f64::INFINITY);
    }
}
