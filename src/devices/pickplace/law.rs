//! Jerk-limited ("double-S", seven-segment) motion law along a path length, after Biagiotti &
//! Melchiorri, *Trajectory Planning for Automatic Machines and Robots*, §3.4, with zero boundary
//! velocity and acceleration and separate acceleration and deceleration limits.
//!
//! Everything is closed form: planning solves for the peak velocity exactly (a few square or
//! cube roots, no iteration), and sampling evaluates one cubic, so the servo loop
//! and the planner can sample as often as they like without allocating.
//!
//! Floating-point care: the deceleration half is evaluated backwards from the end of the motion,
//! so the last sample lands on the target exactly and the velocity cannot dip below zero while
//! creeping into it; every segment is clamped between the positions of its own boundaries, so
//! rounding can never make the position step backwards where one segment hands over to the next.

/// Limits of a path motion. All must be finite and > 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Highest path velocity (length unit per second).
    pub vel: f64,
    /// Highest acceleration while speeding up (length unit per s²).
    pub acc: f64,
    /// Highest deceleration while slowing down, as a positive number (length unit per s²).
    pub dec: f64,
    /// Highest jerk magnitude, shared by all jerk phases (length unit per s³).
    pub jerk: f64,
}

impl Limits {
    /// Refuses a limit that would make the law meaningless (zero, negative, infinite or NaN),
    /// naming the first offending limit and its value.
    pub fn validate(&self) -> Result<(), LawError> {
        check_limit("vel", self.vel)?;
        check_limit("acc", self.acc)?;
        check_limit("dec", self.dec)?;
        check_limit("jerk", self.jerk)
    }
}

/// Position, velocity, acceleration and jerk along the path at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct State {
    /// Position along the path.
    pub s: f64,
    /// Velocity along the path.
    pub v: f64,
    /// Acceleration along the path.
    pub a: f64,
    /// Jerk along the path (piecewise constant: `+jerk`, `0` or `-jerk`).
    pub j: f64,
}

/// An input the motion law cannot plan with.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LawError {
    /// A limit that is not finite and > 0; the text names the limit and its value.
    #[error("bad motion limit: {0} (must be finite and > 0)")]
    BadLimit(String),
    /// A path length that is negative or not finite.
    #[error("bad path length {0} (must be finite and >= 0)")]
    BadLength(f64),
    /// A starting state a stop cannot start from (negative or non-finite velocity, non-finite
    /// acceleration); the text names the value.
    #[error("bad starting state: {0}")]
    BadStart(String),
}

fn check_limit(name: &str, value: f64) -> Result<(), LawError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(LawError::BadLimit(format!("{name} = {value}")))
    }
}

/// One speed-up from rest to `v_peak` (or, read backwards in time, one slow-down to rest):
/// jerk `+jerk`, constant acceleration `a_peak`, jerk `-jerk`. Both halves of a [`DoubleS`] are
/// this shape, so one evaluator serves both.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Ramp {
    jerk: f64,
    a_peak: f64,
    v_peak: f64,
    t_jerk: f64,
    t_const: f64,
    t_total: f64,
    /// Velocity and position at the end of the jerk-up phase.
    v1: f64,
    s1: f64,
    /// Position at the start of the jerk-down phase.
    s2: f64,
    /// Distance covered by the whole ramp.
    dist: f64,
}

impl Ramp {
    const REST: Ramp = Ramp {
        jerk: 0.0,
        a_peak: 0.0,
        v_peak: 0.0,
        t_jerk: 0.0,
        t_const: 0.0,
        t_total: 0.0,
        v1: 0.0,
        s1: 0.0,
        s2: 0.0,
        dist: 0.0,
    };

    fn new(v_peak: f64, a_max: f64, jerk: f64) -> Ramp {
        if v_peak <= 0.0 || v_peak.is_nan() {
            return Ramp::REST;
        }
        let (a_peak, t_jerk, t_const) = if reaches_limit(v_peak, a_max, jerk) {
            let t_jerk = a_max / jerk;
            // Rounding can put v_peak a hair below a_max²/jerk; a negative hold would fold
            // the phases over each other.
            (a_max, t_jerk, (v_peak / a_max - t_jerk).max(0.0))
        } else {
            (
                (v_peak * jerk).sqrt().min(a_max),
                (v_peak / jerk).sqrt(),
                0.0,
            )
        };
        let t_total = t_jerk + t_jerk + t_const;
        // Zero initial and final acceleration make the velocity curve point-symmetric about
        // its midpoint, so the ramp covers exactly half of v_peak · t_total.
        let dist = v_peak * t_total / 2.0;
        // s1 uses the very expression the jerk-up phase evaluates, so the hand-over is seamless.
        let s1 = (jerk * t_jerk * t_jerk * t_jerk / 6.0).min(dist);
        let s2 = (dist - (v_peak * t_jerk - jerk * t_jerk * t_jerk * t_jerk / 6.0))
            .max(s1)
            .min(dist);
        Ramp {
            jerk,
            a_peak,
            v_peak,
            t_jerk,
            t_const,
            t_total,
            v1: jerk * t_jerk * t_jerk / 2.0,
            s1,
            s2,
            dist,
        }
    }

    /// State `tau` after the start of the ramp (`0 ≤ tau ≤ t_total`, not NaN).
    fn eval(&self, tau: f64) -> State {
        let tau = tau.max(0.0).min(self.t_total);
        if tau < self.t_jerk {
            State {
                s: (self.jerk * tau * tau * tau / 6.0).min(self.s1),
                v: (self.jerk * tau * tau / 2.0).min(self.v_peak),
                a: (self.jerk * tau).min(self.a_peak),
                j: self.jerk,
            }
        } else if tau < self.t_jerk + self.t_const {
            let d = tau - self.t_jerk;
            State {
                s: (self.s1 + self.v1 * d + self.a_peak * d * d / 2.0)
                    .max(self.s1)
                    .min(self.s2),
                v: (self.v1 + self.a_peak * d).min(self.v_peak),
                a: self.a_peak,
                j: 0.0,
            }
        } else {
            // Measured back from the top, so the ramp arrives at v_peak and a = 0 exactly.
            let r = (self.t_total - tau).max(0.0);
            State {
                s: (self.dist - (self.v_peak * r - self.jerk * r * r * r / 6.0))
                    .max(self.s2)
                    .min(self.dist),
                v: (self.v_peak - self.jerk * r * r / 2.0).max(0.0),
                a: (self.jerk * r).min(self.a_peak),
                j: -self.jerk,
            }
        }
    }
}

/// Whether a ramp from rest to `v` reaches `a_max` (a constant-acceleration phase exists),
/// i.e. `v ≥ a_max² / jerk`, written so that it does not overflow for large limits.
fn reaches_limit(v: f64, a_max: f64, jerk: f64) -> bool {
    v >= a_max * (a_max / jerk)
}

/// Duration of a ramp from rest to `v` under `a_max` and `jerk`.
fn ramp_time(v: f64, a_max: f64, jerk: f64) -> f64 {
    if reaches_limit(v, a_max, jerk) {
        v / a_max + a_max / jerk
    } else {
        2.0 * (v / jerk).sqrt()
    }
}

/// Length of a rest-to-rest motion that peaks at `v` without cruising.
fn peak_distance(v: f64, lim: &Limits) -> f64 {
    v * (ramp_time(v, lim.acc, lim.jerk) + ramp_time(v, lim.dec, lim.jerk)) / 2.0
}

/// The peak velocity of the time-optimal profile over `length`. The distance needed to reach
/// a peak `v` and come back to rest grows monotonically with `v` and takes one of three closed
/// forms depending on which of the two ramps reaches its acceleration limit; the thresholds
/// `acc²/jerk` and `dec²/jerk` tell which form applies, and each form is solved exactly.
fn solve_peak(length: f64, lim: &Limits) -> f64 {
    if peak_distance(lim.vel, lim) <= length {
        return lim.vel;
    }
    let j = lim.jerk;
    let a_min = lim.acc.min(lim.dec);
    let a_max = lim.acc.max(lim.dec);
    let v_lo = a_min * (a_min / j);
    let v_hi = a_max * (a_max / j);
    let vp = if peak_distance(v_lo, lim) >= length {
        // Both ramps triangular: length = 2 vp^(3/2) / √jerk. Taking the cube roots apart
        // keeps tiny lengths from underflowing to a zero peak.
        let c = length.cbrt();
        c * c * (j / 4.0).cbrt()
    } else if peak_distance(v_hi, lim) >= length {
        // Only the lower limit a_min is reached. With u = √vp the distance is
        // u²/2 · (u/√a_min + √(a_min/jerk))², a perfect square, so √(2 length) is a quadratic
        // in u; the root is taken in the cancellation-free form.
        let b = (a_min / j).sqrt();
        let c = (2.0 * length).sqrt();
        let u = 2.0 * c / (b + (b * b + 4.0 * c / a_min.sqrt()).sqrt());
        u * u
    } else {
        // Both limits reached: length = ½(1/acc + 1/dec)·vp² + (acc + dec)/(2 jerk)·vp.
        let qa = (1.0 / lim.acc + 1.0 / lim.dec) / 2.0;
        let qb = (lim.acc + lim.dec) / (2.0 * j);
        2.0 * length / (qb + (qb * qb + 4.0 * qa * length).sqrt())
    };
    vp.min(lim.vel)
}

/// A rest-to-rest jerk-limited profile over `length` (≥ 0).
///
/// Seven phases: jerk `+J`, constant `acc`, jerk `−J`, cruise, jerk `−J`, constant `−dec`,
/// jerk `+J`. Phases that the length does not leave room for have zero duration; the peak
/// velocity and, if need be, the peak acceleration/deceleration are lowered so the profile is
/// time-optimal under the limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DoubleS {
    length: f64,
    acc: Ramp,
    dec: Ramp,
    cruise: f64,
    /// Where the cruise ends; the deceleration half never reports less, which keeps the
    /// position monotone however the two halves round.
    s_cruise_end: f64,
    duration: f64,
}

impl DoubleS {
    /// Plans the time-optimal profile over `length` under `lim`.
    ///
    /// # Errors
    /// [`LawError::BadLimit`] for a limit that is not finite and > 0 (or for limits so extreme
    /// against the length that the duration overflows f64); [`LawError::BadLength`] for a
    /// negative or non-finite length.
    pub fn plan(length: f64, lim: Limits) -> Result<DoubleS, LawError> {
        lim.validate()?;
        if !(length.is_finite() && length >= 0.0) {
            return Err(LawError::BadLength(length));
        }
        // Turns -0.0 into 0.0 so the reported end position carries no stray sign.
        let length = length.abs();
        let vp = solve_peak(length, &lim);
        let acc = Ramp::new(vp, lim.acc, lim.jerk);
        let dec = Ramp::new(vp, lim.dec, lim.jerk);
        // In the reduced-peak cases this is zero up to rounding; a positive rounding residue
        // becomes a vanishing cruise instead of a gap in position.
        let cruise = if vp > 0.0 {
            ((length - acc.dist - dec.dist) / vp).max(0.0)
        } else {
            0.0
        };
        let duration = acc.t_total + cruise + dec.t_total;
        if !duration.is_finite() {
            return Err(LawError::BadLimit(format!(
                "{lim:?} over length {length} (the profile overflows f64)"
            )));
        }
        Ok(DoubleS {
            length,
            acc,
            dec,
            cruise,
            s_cruise_end: (length - dec.dist).max(acc.dist).min(length),
            duration,
        })
    }

    /// Total time of the motion in seconds.
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The path length the profile covers.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// State at time `t` (seconds from the start). `t` is clamped to `[0, duration]` (NaN counts
    /// as 0); at `t ≥ duration` the result is `s = length` exactly with `v = a = j = 0`.
    pub fn sample(&self, t: f64) -> State {
        if t >= self.duration {
            return State {
                s: self.length,
                ..State::default()
            };
        }
        let t = if t > 0.0 { t } else { 0.0 };
        if t < self.acc.t_total {
            let mut st = self.acc.eval(t);
            st.s = st.s.min(self.length);
            return st;
        }
        if t < self.acc.t_total + self.cruise {
            let vp = self.acc.v_peak;
            return State {
                s: (self.acc.dist + vp * (t - self.acc.t_total))
                    .max(self.acc.dist)
                    .min(self.s_cruise_end),
                v: vp,
                a: 0.0,
                j: 0.0,
            };
        }
        // The deceleration half is a speed-up ramp run backwards from the end: jerk keeps its
        // sign under time reversal while acceleration flips.
        let r = self.dec.eval(self.duration - t);
        State {
            s: (self.length - r.s).max(self.s_cruise_end).min(self.length),
            v: r.v,
            a: -r.a,
            j: r.j,
        }
    }

    /// The highest velocity reached.
    pub fn peak_velocity(&self) -> f64 {
        self.acc.v_peak
    }

    /// The highest acceleration reached while speeding up (≤ `acc`).
    pub fn peak_acceleration(&self) -> f64 {
        self.acc.a_peak
    }

    /// The highest deceleration reached while slowing down, as a positive number (≤ `dec`).
    pub fn peak_deceleration(&self) -> f64 {
        self.dec.a_peak
    }

    /// The instants at which the seven phases start, followed by the end of the motion, as
    /// `sample` switches between them (so a test or a planner can sample both sides of each).
    pub fn phase_times(&self) -> [f64; 8] {
        let a = &self.acc;
        let d = &self.dec;
        let t_end = self.duration;
        [
            0.0,
            a.t_jerk,
            a.t_jerk + a.t_const,
            a.t_total,
            a.t_total + self.cruise,
            t_end - (d.t_jerk + d.t_const),
            t_end - d.t_jerk,
            t_end,
        ]
    }
}

/// A jerk-limited stop from a moving state (v0 ≥ 0, any a0) to rest, with deceleration `dec`
/// and jerk `jerk` (both > 0): first jerk toward −dec (bringing a to ≤ 0 if positive), hold −dec
/// if needed, then jerk back to a = 0 exactly when v reaches 0. v never goes negative.
///
/// Two kinds of starting state lie outside the limits, and the final conditions take priority:
/// - already braking harder than `dec` (`a0 < −dec`): the first phase jerks *up* from `a0`
///   toward `−dec` (then holds `−dec` and jerks to 0), so `|a|` never exceeds `|a0|` and is
///   back within `dec` as soon as the jerk allows;
/// - braking so hard that even jerking straight back to `a = 0` would carry `v` below zero
///   (`a0 < 0` and `v0 < a0²/(2·jerk)`, whatever `dec`): no profile within `jerk` can end at
///   rest, so the stop is a single ramp from `a0` to 0 with the jerk raised to the smallest
///   value that works, `a0²/(2·v0)`; [`Stop::jerk`] reports it. With `v0 = 0` (or a required
///   jerk beyond f64) the stop is immediate: zero duration and distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stop {
    v0: f64,
    a0: f64,
    /// Signed jerk and duration of the first phase.
    j1: f64,
    t1: f64,
    /// The acceleration held in the second phase (≤ 0) and its duration.
    a_hold: f64,
    t2: f64,
    /// Jerk (≥ 0) and duration of the last phase, which ends at rest.
    j3: f64,
    t3: f64,
    /// Velocities at the ends of the first and second phases.
    v1: f64,
    v2: f64,
    /// Positions at the ends of the first and second phases.
    s1: f64,
    s2: f64,
    distance: f64,
    duration: f64,
    /// Whether the first phase is evaluated from its start rather than back from its end:
    /// whichever end is slower, because that is where the steps in position are smallest and
    /// a formula anchored far away would lose them to cancellation.
    phase1_forward: bool,
}

impl Stop {
    /// Plans the quickest stop from velocity `v0` (≥ 0) and acceleration `a0` under `dec` and
    /// `jerk` (see [`Stop`] for starts outside those limits).
    ///
    /// # Errors
    /// [`LawError::BadLimit`] for a `dec` or `jerk` that is not finite and > 0;
    /// [`LawError::BadStart`] for a negative or non-finite `v0` or a non-finite `a0`, or for a
    /// combination so extreme that the stop's distance overflows f64.
    pub fn plan(v0: f64, a0: f64, dec: f64, jerk: f64) -> Result<Stop, LawError> {
        check_limit("dec", dec)?;
        check_limit("jerk", jerk)?;
        if !(v0.is_finite() && v0 >= 0.0) {
            return Err(LawError::BadStart(format!(
                "velocity {v0} (must be finite and >= 0)"
            )));
        }
        if !a0.is_finite() {
            return Err(LawError::BadStart(format!(
                "acceleration {a0} (must be finite)"
            )));
        }
        let v0 = v0.abs();
        let immediate = Stop {
            v0,
            a0,
            j1: 0.0,
            t1: 0.0,
            a_hold: 0.0,
            t2: 0.0,
            j3: 0.0,
            t3: 0.0,
            v1: v0,
            v2: v0,
            s1: 0.0,
            s2: 0.0,
            distance: 0.0,
            duration: 0.0,
            phase1_forward: true,
        };
        // (j1, t1, a_hold, t2, j3, t3)
        let phases = if a0 < 0.0 && v0 < a0 * (a0 / (2.0 * jerk)) {
            // Velocity drop of the fastest return to a = 0 is a0²/(2·jerk) > v0: no profile
            // within the jerk limit avoids reversing, so raise the jerk just enough.
            if v0 == 0.0 {
                return Ok(immediate);
            }
            let j3 = a0 * (a0 / (2.0 * v0));
            let t3 = 2.0 * v0 / -a0;
            if !j3.is_finite() || t3 <= 0.0 {
                return Ok(immediate);
            }
            (0.0, 0.0, a0, 0.0, j3, t3)
        } else if a0 < -dec {
            // Feasible (v0 ≥ a0²/(2·jerk)); ramping up to −dec, holding, and ramping to 0 loses
            // exactly a0²/(2·jerk) + dec·t2 of velocity.
            let t2 = ((v0 - a0 * (a0 / (2.0 * jerk))) / dec).max(0.0);
            (jerk, (-dec - a0) / jerk, -dec, t2, jerk, dec / jerk)
        } else {
            if v0 == 0.0 && a0 == 0.0 {
                return Ok(immediate);
            }
            // Ramping from a0 down to −ap and back to 0 loses (a0² − ap²)/(2J) + ap²/(2J)
            // + ap·t2 of velocity; solve with ap = dec, else with t2 = 0.
            let spare = v0 + a0 * (a0 / (2.0 * jerk)) - dec * (dec / jerk);
            let (ap, t2) = if spare >= 0.0 {
                (dec, spare / dec)
            } else {
                let ap = (jerk * v0 + a0 * a0 / 2.0).sqrt().min(dec);
                (ap, 0.0)
            };
            (-jerk, ((a0 + ap) / jerk).max(0.0), -ap, t2, jerk, ap / jerk)
        };
        let (j1, t1, a_hold, t2, j3, t3) = phases;
        // The velocities are chained back from rest, so the hold and the last phase, whose
        // slow ends are where the stop creeps to a halt, are exact at that end.
        let v2 = j3 * t3 * t3 / 2.0;
        let v1 = v2 - a_hold * t2;
        let phase1_forward = v0 <= v1;
        let s1 = if phase1_forward {
            v0 * t1 + a0 * t1 * t1 / 2.0 + j1 * t1 * t1 * t1 / 6.0
        } else {
            v1 * t1 - a_hold * t1 * t1 / 2.0 + j1 * t1 * t1 * t1 / 6.0
        }
        .max(0.0);
        let s2 = s1 + (v2 * t2 - a_hold * t2 * t2 / 2.0).max(0.0);
        let distance = s2 + j3 * t3 * t3 * t3 / 6.0;
        let duration = t1 + t2 + t3;
        if !(distance.is_finite() && duration.is_finite()) {
            return Err(LawError::BadStart(format!(
                "velocity {v0}, acceleration {a0} with dec {dec}, jerk {jerk} overflow f64"
            )));
        }
        Ok(Stop {
            v0,
            a0,
            j1,
            t1,
            a_hold,
            t2,
            j3,
            t3,
            v1,
            v2,
            s1,
            s2,
            distance,
            duration,
            phase1_forward,
        })
    }

    /// Total time of the stop in seconds.
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Distance travelled until rest.
    pub fn distance(&self) -> f64 {
        self.distance
    }

    /// The jerk magnitude the stop applies: the requested one, unless the starting state
    /// forced it higher (see [`Stop`]); 0 for a stop of zero duration.
    pub fn jerk(&self) -> f64 {
        self.j1.abs().max(self.j3)
    }

    /// The highest deceleration applied, as a positive number.
    pub fn peak_deceleration(&self) -> f64 {
        (-self.a_hold).max(-self.a0).max(0.0)
    }

    /// Durations of the three phases: jerk toward the hold deceleration, hold, jerk to rest.
    pub fn phase_durations(&self) -> [f64; 3] {
        [self.t1, self.t2, self.t3]
    }

    /// State relative to the start of the stop (s from 0). `t` is clamped to `[0, duration]`
    /// (NaN counts as 0); at `t ≥ duration` the result is `s = distance` exactly, at rest.
    pub fn sample(&self, t: f64) -> State {
        if t >= self.duration {
            return State {
                s: self.distance,
                ..State::default()
            };
        }
        if t.is_nan() || t <= 0.0 {
            // The exact starting state, so the hand-over from the motion being stopped is
            // seamless whichever way the first phase is evaluated.
            let j = if self.t1 > 0.0 {
                self.j1
            } else if self.t2 > 0.0 {
                0.0
            } else {
                self.j3
            };
            return State {
                s: 0.0,
                v: self.v0,
                a: self.a0,
                j,
            };
        }
        if t < self.t1 {
            let (v0, a0, j1) = (self.v0, self.a0, self.j1);
            let (s, v, a) = if self.phase1_forward {
                (
                    v0 * t + a0 * t * t / 2.0 + j1 * t * t * t / 6.0,
                    v0 + a0 * t + j1 * t * t / 2.0,
                    a0 + j1 * t,
                )
            } else {
                let (v1, a1) = (self.v1, self.a_hold);
                let r = (self.t1 - t).max(0.0);
                (
                    self.s1 - (v1 * r - a1 * r * r / 2.0 + j1 * r * r * r / 6.0),
                    v1 - a1 * r + j1 * r * r / 2.0,
                    a1 - j1 * r,
                )
            };
            return State {
                s: s.max(0.0).min(self.s1),
                v: v.max(0.0),
                a,
                j: j1,
            };
        }
        if t < self.t1 + self.t2 {
            // Back from the end of the hold: every term is positive, so rounding cannot make
            // the position step backwards as the velocity dwindles.
            let r = (self.t1 + self.t2 - t).max(0.0);
            let h = -self.a_hold;
            return State {
                s: (self.s2 - (self.v2 * r + h * r * r / 2.0))
                    .max(self.s1)
                    .min(self.s2),
                v: self.v2 + h * r,
                a: self.a_hold,
                j: 0.0,
            };
        }
        // Measured back from the end, so the stop lands on v = a = 0 without overshooting
        // into negative velocity.
        let r = (self.duration - t).max(0.0).min(self.t3);
        State {
            s: (self.distance - self.j3 * r * r * r / 6.0)
                .max(self.s2)
                .min(self.distance),
            v: self.j3 * r * r / 2.0,
            a: (-self.j3 * r).max(self.a_hold.min(0.0)),
            j: self.j3,
        }
    }
}
