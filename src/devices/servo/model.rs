//! The digital servo loop, in the cascaded form the PowerTools-family drives document: a
//! proportional position loop with velocity feedforward gives the velocity reference; a
//! proportional-integral velocity loop with acceleration feedforward gives the torque, which is
//! limited and drives the motor and its load (one rigid inertia); an encoder quantizes the
//! position the loop and the programs see.
//!
//! The loop is computed at its own rate (`loop_rate`), a whole number of times inside each
//! trajectory update, as a drive's DSP does: the command position is interpolated linearly
//! across the update, every loop step samples the encoder and the reference at its start (both
//! in whole counts, as the drive compares them) and holds its torque to the next step, and the
//! motor's motion under a held torque is integrated exactly. The same commands give the same
//! feedback, bit for bit.
//!
//! Units: positions in the axis's user units, times in seconds; inertias in kg·m² and torque
//! in N·m at the motor, turned into user units by the units per motor revolution. The gains
//! are in the acceleration form (`velocity_gain` is the velocity loop's bandwidth in rad/s for
//! the inertia the drive is set up for), so the closed-loop response does not depend on the
//! inertia when the drive's inertia ratio is right — and departs from it when it is not, as on
//! a real machine.

use std::f64::consts::TAU;

/// The loop's settings, checked by the configuration stage (every value finite; rates, gains
/// of the loops, inertias and limits above 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoParams {
    /// Loop updates per second (Hz).
    pub loop_rate: f64,
    /// Position gain, 1/s: velocity reference per unit of position error.
    pub position_gain: f64,
    /// Velocity gain, 1/s: acceleration reference per unit/s of velocity error, for the
    /// inertia the drive assumes.
    pub velocity_gain: f64,
    /// Velocity integral gain, 1/s²: acceleration reference per unit of integrated velocity
    /// error (0: a proportional velocity loop).
    pub velocity_integral: f64,
    /// Velocity feedforward, a fraction of the command velocity added to the velocity
    /// reference (0: none, 1: all of it).
    pub velocity_feedforward: f64,
    /// Acceleration feedforward, a fraction of the command acceleration added to the
    /// acceleration reference.
    pub acceleration_feedforward: f64,
    /// The motor's rotor inertia, kg·m².
    pub motor_inertia: f64,
    /// The load's inertia reflected to the motor shaft, kg·m².
    pub load_inertia: f64,
    /// The drive's inertia ratio setting (load / motor): the inertia its gains are scaled for.
    pub inertia_ratio: f64,
    /// The most torque the drive gives, N·m.
    pub torque_limit: f64,
    /// The highest velocity reference, units/s.
    pub velocity_limit: f64,
    /// User units per motor revolution.
    pub units_per_rev: f64,
    /// Encoder counts per motor revolution.
    pub counts_per_rev: f64,
    /// Time from an edge at a capture input to the encoder count it latches, seconds.
    pub latch_delay: f64,
}

impl Default for ServoParams {
    /// A mid-size servo motor on a load three times its inertia, with the gains a drive might
    /// ship with for it: a 50 Hz velocity loop, a position gain of 100/s, no feedforward.
    fn default() -> ServoParams {
        ServoParams {
            loop_rate: 8000.0,
            position_gain: 100.0,
            velocity_gain: 314.0,
            velocity_integral: 12_000.0,
            velocity_feedforward: 0.0,
            acceleration_feedforward: 0.0,
            motor_inertia: 2.0e-4,
            load_inertia: 6.0e-4,
            inertia_ratio: 3.0,
            torque_limit: 5.0,
            velocity_limit: 80.0,
            units_per_rev: 1.0,
            counts_per_rev: 4096.0,
            latch_delay: 1.0e-6,
        }
    }
}

impl ServoParams {
    /// The inertia the drive's gains are scaled for, kg·m².
    fn nominal_inertia(&self) -> f64 {
        self.motor_inertia * (1.0 + self.inertia_ratio)
    }

    /// The inertia the motor actually moves, kg·m².
    fn inertia(&self) -> f64 {
        self.motor_inertia + self.load_inertia
    }

    /// The most acceleration the torque limit gives the motor and its load, units/s².
    pub fn acceleration_limit(&self) -> f64 {
        self.torque_limit / self.inertia() * self.units_per_rev / TAU
    }

    /// Loop steps inside an update of `dt` seconds: the loop rate's period or shorter, a whole
    /// number of them (at least one).
    pub fn steps_in(&self, dt: f64) -> u32 {
        let n = (dt * self.loop_rate - 1e-9).ceil();
        if n.is_finite() && n >= 1.0 {
            n.min(f64::from(u32::MAX)) as u32
        } else {
            1
        }
    }
}

/// `x.floor()` without the library call the default x86-64 target makes of it (it has no
/// rounding instruction): the loop quantizes every step. Exact for |x| < 2⁵²; beyond that
/// every float is whole anyway.
fn floor(x: f64) -> f64 {
    if x.abs() < 4_503_599_627_370_496.0 {
        let t = x as i64 as f64;
        if t > x {
            t - 1.0
        } else {
            t
        }
    } else {
        x.floor()
    }
}

/// What the motor is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The loop follows the command.
    Following,
    /// A fault: the drive brings the motor to rest at its torque limit, ignoring the command.
    Stopping,
    /// At rest after a fault, held where it stopped until the fault is reset.
    Held,
}

/// One servo axis: the loop's state between updates.
#[derive(Debug, Clone)]
pub struct Servo {
    params: ServoParams,
    /// Counts per user unit.
    counts_per_unit: f64,
    /// User units per count (the loop multiplies: a division every loop step costs).
    unit_per_count: f64,
    /// Actual acceleration per acceleration reference: the inertia the drive assumes over the
    /// inertia it moves.
    plant_gain: f64,
    /// The torque limit as an acceleration, units/s².
    accel_limit: f64,
    /// Motor position, units (not quantized).
    position: f64,
    /// Motor velocity, units/s.
    velocity: f64,
    /// The velocity loop's integral of velocity error, units.
    integral: f64,
    /// Command position and velocity at the last update (where the next one's interpolation
    /// starts).
    command: (f64, f64),
    mode: Mode,
}

/// The command across one update, as every loop step of it sees it.
#[derive(Debug, Clone, Copy)]
struct Segment {
    /// Command position at the update's start.
    from: f64,
    /// Command velocity across the update (the interpolation's slope).
    slope: f64,
    /// Command velocity for the feedforward.
    velocity: f64,
    /// Command acceleration for the feedforward.
    accel: f64,
}

impl Servo {
    /// A servo at rest at `position`, its command there too.
    pub fn new(params: ServoParams, position: f64) -> Servo {
        Servo {
            params,
            counts_per_unit: params.counts_per_rev / params.units_per_rev,
            unit_per_count: params.units_per_rev / params.counts_per_rev,
            plant_gain: params.nominal_inertia() / params.inertia(),
            accel_limit: params.acceleration_limit(),
            position,
            velocity: 0.0,
            integral: 0.0,
            command: (position, 0.0),
            mode: Mode::Following,
        }
    }

    /// Its settings.
    pub fn params(&self) -> &ServoParams {
        &self.params
    }

    /// What the motor is doing.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The encoder's count of a position (whole counts, rounded down as an encoder counts).
    pub fn count_of(&self, position: f64) -> f64 {
        floor(position * self.counts_per_unit)
    }

    /// Feedback position: the encoder's count in user units.
    pub fn feedback(&self) -> f64 {
        self.in_counts(self.position)
    }

    /// A position in whole encoder counts, in user units: what the drive's position loop
    /// compares (its command is in counts too).
    fn in_counts(&self, position: f64) -> f64 {
        self.count_of(position) * self.unit_per_count
    }

    /// Motor velocity, units/s (the velocity an observer on the encoder gives).
    pub fn velocity(&self) -> f64 {
        self.velocity
    }

    /// The motor's true position, units (tests compare it with closed forms).
    pub fn position(&self) -> f64 {
        self.position
    }

    /// Advance the loop by one update of `dt` seconds, to the command position `command` and
    /// command velocity `velocity` at its end.
    pub fn step(&mut self, command: f64, velocity: f64, dt: f64) {
        if dt.is_nan() || dt <= 0.0 {
            return;
        }
        let segment = self.segment(command, velocity, dt);
        // The command stands still across the update: a motor at rest on it (or held after a
        // fault) computes nothing but zeros in every loop step, so the steps are skipped — the
        // same result, bit for bit. An axis spends most of its time so.
        let still = segment.slope == 0.0 && velocity == 0.0 && segment.accel == 0.0;
        let resting = self.mode == Mode::Following
            && self.velocity == 0.0
            && self.integral == 0.0
            && self.feedback() == self.in_counts(command);
        if !(still && (resting || self.mode == Mode::Held)) {
            let n = self.params.steps_in(dt);
            let h = dt / f64::from(n);
            for k in 0..n {
                self.loop_step(&segment, f64::from(k) * h, h);
            }
            // Settled on a still command: the velocity and the integral decay toward 0 without
            // ever reaching it in floating point; below a millionth of a count per second (and
            // an integral worth as little) they are 0, so the motor rests.
            let tiny = 1e-6 * self.unit_per_count;
            if still
                && self.mode == Mode::Following
                && self.velocity.abs() < tiny
                && self.integral.abs() < tiny
                && self.feedback() == self.in_counts(command)
            {
                self.velocity = 0.0;
                self.integral = 0.0;
            }
        }
        self.command = (command, velocity);
    }

    /// The feedback position `at` seconds into the coming update of `dt` seconds (`at` may
    /// pass its end), if the command then ends at `command` with velocity `velocity`: what an
    /// encoder latch sees. The loop's state is not changed.
    pub fn feedback_at(&self, command: f64, velocity: f64, dt: f64, at: f64) -> f64 {
        if dt.is_nan() || dt <= 0.0 || at.is_nan() || at <= 0.0 {
            return self.feedback();
        }
        let h = dt / f64::from(self.params.steps_in(dt));
        let segment = self.segment(command, velocity, dt);
        let mut ahead = self.clone();
        let whole = (at / h).floor();
        let mut k = 0.0;
        while k < whole {
            ahead.loop_step(&segment, k * h, h);
            k += 1.0;
        }
        let rest = at - whole * h;
        if rest > 0.0 {
            ahead.loop_step(&segment, whole * h, rest);
        }
        ahead.feedback()
    }

    /// The drive faulted: bring the motor to rest at the torque limit, whatever the command.
    pub fn fault(&mut self) {
        if self.mode == Mode::Following {
            self.mode = if self.velocity == 0.0 {
                Mode::Held
            } else {
                Mode::Stopping
            };
        }
    }

    /// The fault is reset: follow the command again from `command` (where the drive puts its
    /// command: at the feedback), with the integral cleared.
    pub fn reset(&mut self, command: f64) {
        self.mode = Mode::Following;
        self.integral = 0.0;
        self.command = (command, 0.0);
    }

    /// The command moved without motion to `command` (a faulted drive's command follows its
    /// feedback): the next update's interpolation starts there.
    pub fn reset_command(&mut self, command: f64) {
        self.command = (command, 0.0);
    }

    /// The command across an update ending at `command`, `velocity`.
    fn segment(&self, command: f64, velocity: f64, dt: f64) -> Segment {
        Segment {
            from: self.command.0,
            slope: (command - self.command.0) / dt,
            velocity,
            accel: (velocity - self.command.1) / dt,
        }
    }

    /// One loop step of `h` seconds starting `t` seconds into the update: sample, compute the
    /// torque, hold it for the step.
    fn loop_step(&mut self, s: &Segment, t: f64, h: f64) {
        let p = &self.params;
        let accel = match self.mode {
            Mode::Following => {
                let reference = self.in_counts(s.from + s.slope * t);
                let error = reference - self.feedback();
                let limit = p.velocity_limit;
                let v_ref = (p.position_gain * error + p.velocity_feedforward * s.velocity)
                    .clamp(-limit, limit);
                let v_error = v_ref - self.velocity;
                let demand = p.velocity_gain * v_error
                    + p.velocity_integral * self.integral
                    + p.acceleration_feedforward * s.accel;
                let wanted = demand * self.plant_gain;
                let accel = wanted.clamp(-self.accel_limit, self.accel_limit);
                // No integration while the torque is at its limit and the error would push it
                // further: the integral would wind up and overshoot when the limit lets go.
                if accel == wanted || v_error.signum() != wanted.signum() {
                    self.integral += v_error * h;
                }
                accel
            }
            Mode::Stopping => {
                let a = -self.velocity.signum() * self.accel_limit;
                let to_rest = self.velocity.abs() / self.accel_limit;
                if to_rest <= h {
                    self.position += self.velocity * to_rest + 0.5 * a * to_rest * to_rest;
                    self.velocity = 0.0;
                    self.mode = Mode::Held;
                    return;
                }
                a
            }
            Mode::Held => return,
        };
        self.position += self.velocity * h + 0.5 * accel * h * h;
        self.velocity += accel * h;
    }
}

#[cfg(test)]
mod tests {
    //! The sampled loop against the continuous loop it implements: closed forms where the loop
    //! has one (a proportional position loop over a proportional velocity loop is the
    //! second-order system x'' + kv·x' + kv·kp·x = kv·kp·r), a fine Runge-Kutta solution of the
    //! same equations where it has an integral. "Within 1 %" is of the step's size, or of the
    //! steady following error of a ramp.

    use super::*;

    /// A loop with no limits in the way and an encoder fine enough not to matter.
    fn ideal_loop(kp: f64, kv: f64, ki: f64) -> ServoParams {
        ServoParams {
            position_gain: kp,
            velocity_gain: kv,
            velocity_integral: ki,
            torque_limit: 1.0e9,
            velocity_limit: 1.0e9,
            counts_per_rev: 1.0e12,
            ..ServoParams::default()
        }
    }

    /// The unit step response of x'' + 2ζω·x' + ω²·x = ω²·r.
    fn second_order_step(zeta: f64, wn: f64, t: f64) -> f64 {
        if (zeta - 1.0).abs() < 1e-12 {
            1.0 - (1.0 + wn * t) * (-wn * t).exp()
        } else if zeta < 1.0 {
            let wd = wn * (1.0 - zeta * zeta).sqrt();
            1.0 - (-zeta * wn * t).exp()
                * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin())
        } else {
            let r = (zeta * zeta - 1.0).sqrt();
            let (s1, s2) = (-wn * (zeta - r), -wn * (zeta + r));
            1.0 + (s2 * (s1 * t).exp() - s1 * (s2 * t).exp()) / (s1 - s2)
        }
    }

    /// Largest difference between the model and `expected` over `seconds`, stepping by `dt`
    /// toward the command `command(t)` (velocity `velocity(t)`).
    fn worst(
        params: ServoParams,
        dt: f64,
        seconds: f64,
        command: impl Fn(f64) -> (f64, f64),
        expected: impl Fn(f64) -> f64,
    ) -> f64 {
        let mut s = Servo::new(params, 0.0);
        let mut worst: f64 = 0.0;
        let n = (seconds / dt).round() as u32;
        for k in 1..=n {
            let t = f64::from(k) * dt;
            let (p, v) = command(t);
            s.step(p, v, dt);
            worst = worst.max((s.position() - expected(t)).abs());
        }
        worst
    }

    #[test]
    fn a_step_follows_the_closed_form_of_the_p_p_loop_within_1_percent() {
        // Critically damped (kv = 4·kp) and underdamped (ζ = 0.707), loop rate 8 kHz, one
        // loop step per call: the step lands at the first loop step.
        for (kp, kv) in [(40.0, 160.0), (100.0, 200.0)] {
            let wn = f64::sqrt(kv * kp);
            let zeta = kv / (2.0 * wn);
            let e = worst(
                ideal_loop(kp, kv, 0.0),
                1.0 / 8000.0,
                0.3,
                |_| (1.0, 0.0),
                |t| second_order_step(zeta, wn, t),
            );
            assert!(e < 0.01, "kp {kp} kv {kv}: {:.3} % of the step", e * 100.0);
        }
    }

    #[test]
    fn a_ramp_lags_by_the_closed_form_and_settles_at_v_over_kp() {
        // Critically damped, ωn = 80 rad/s: the ramp's following error is
        // V·(2 − (2 + ωn·t)·e^(−ωn·t))/ωn, settling at V/kp. Updates of 1 ms, 8 loop steps each.
        let (kp, kv, speed) = (40.0, 160.0, 2.0);
        let wn = 80.0;
        let steady = speed / kp;
        let mut s = Servo::new(ideal_loop(kp, kv, 0.0), 0.0);
        let mut worst: f64 = 0.0;
        for k in 1..=500 {
            let t = f64::from(k) * 1e-3;
            s.step(speed * t, speed, 1e-3);
            let error = speed * t - s.position();
            let closed = speed * (2.0 - (2.0 + wn * t) * (-wn * t).exp()) / wn;
            worst = worst.max((error - closed).abs());
        }
        assert!(
            worst < 0.01 * steady,
            "{:.3} % of V/kp",
            worst / steady * 100.0
        );
        assert!((speed * 0.5 - s.position() - steady).abs() < 1e-4 * steady);
    }

    #[test]
    fn velocity_feedforward_takes_the_steady_ramp_error_away() {
        let params = ServoParams {
            velocity_feedforward: 1.0,
            ..ideal_loop(40.0, 160.0, 0.0)
        };
        let mut s = Servo::new(params, 0.0);
        for k in 1..=500 {
            let t = f64::from(k) * 1e-3;
            s.step(2.0 * t, 2.0, 1e-3);
        }
        let error = 1.0 - s.position();
        assert!(error.abs() < 1e-9, "{error}");
    }

    /// The continuous P position / PI velocity loop, by Runge-Kutta at 1 µs: the reference
    /// the sampled loop is held to where no closed form is handy.
    fn continuous_pi_step(kp: f64, kv: f64, ki: f64, until: f64, every: f64) -> Vec<f64> {
        let f = |y: [f64; 3]| {
            let v_ref = kp * (1.0 - y[0]);
            let e = v_ref - y[1];
            [y[1], kv * e + ki * y[2], e]
        };
        let h = 1e-6;
        let mut y = [0.0; 3];
        let mut out = Vec::new();
        let steps = (until / h).round() as u64;
        let stride = (every / h).round() as u64;
        for k in 1..=steps {
            let add = |a: [f64; 3], b: [f64; 3], c: f64| {
                [a[0] + b[0] * c, a[1] + b[1] * c, a[2] + b[2] * c]
            };
            let k1 = f(y);
            let k2 = f(add(y, k1, h / 2.0));
            let k3 = f(add(y, k2, h / 2.0));
            let k4 = f(add(y, k3, h));
            for i in 0..3 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            if k % stride == 0 {
                out.push(y[0]);
            }
        }
        out
    }

    #[test]
    fn a_step_with_the_velocity_integral_follows_the_continuous_loop_within_1_percent() {
        let (kp, kv, ki) = (100.0, 314.0, 12_000.0);
        let expected = continuous_pi_step(kp, kv, ki, 0.3, 1e-3);
        let mut s = Servo::new(ideal_loop(kp, kv, ki), 0.0);
        let mut worst: f64 = 0.0;
        // Updates of one loop step, so the step lands whole at the first one.
        for x in &expected {
            for _ in 0..8 {
                s.step(1.0, 0.0, 1.0 / 8000.0);
            }
            worst = worst.max((s.position() - x).abs());
        }
        assert!(worst < 0.01, "{:.3} %", worst * 100.0);
    }

    #[test]
    fn the_torque_limit_caps_the_acceleration() {
        let params = ServoParams {
            torque_limit: 0.5,
            ..ideal_loop(100.0, 314.0, 0.0)
        };
        let a = params.acceleration_limit();
        // 0.5 N·m on 8e-4 kg·m²: 625 rad/s², 99.47 rev/s².
        assert!((a - 0.5 / 8.0e-4 / TAU).abs() < 1e-9);
        let mut s = Servo::new(params, 0.0);
        s.step(1000.0, 0.0, 1e-3);
        let (p1, v1) = (s.position(), s.velocity());
        s.step(1000.0, 0.0, 1e-3);
        // Saturated all through the second update: exactly the limit's acceleration.
        assert!((s.velocity() - v1 - a * 1e-3).abs() < 1e-9 * a);
        let travelled = s.position() - p1;
        assert!((travelled - v1 * 1e-3 - 0.5 * a * 1e-6).abs() < 1e-9);
    }

    #[test]
    fn the_velocity_limit_caps_the_velocity_reference() {
        let params = ServoParams {
            velocity_limit: 3.0,
            ..ideal_loop(100.0, 314.0, 0.0)
        };
        let mut s = Servo::new(params, 0.0);
        for _ in 0..200 {
            s.step(1000.0, 0.0, 1e-3);
        }
        assert!((s.velocity() - 3.0).abs() < 1e-6, "{}", s.velocity());
    }

    #[test]
    fn the_quick_floor_is_floor() {
        for x in [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999_999,
            -2.000_001,
            1e15 + 0.5,
            -1e15 - 0.5,
            1e300,
            -1e300,
        ] {
            assert_eq!(floor(x), x.floor(), "{x}");
        }
        assert!(floor(f64::NAN).is_nan());
        assert_eq!(floor(f64::NEG_INFINITY), f64::NEG_INFINITY);
    }

    #[test]
    fn the_encoder_counts_whole_counts() {
        let params = ServoParams {
            counts_per_rev: 4096.0,
            units_per_rev: 10.0,
            ..ServoParams::default()
        };
        let mut s = Servo::new(params, 0.0);
        s.step(0.123_456, 0.0, 1e-3);
        let counts = s.feedback() * 409.6;
        assert!((counts - counts.round()).abs() < 1e-9, "{counts}");
        assert_eq!(s.count_of(s.position()), counts.round());
    }

    #[test]
    fn a_latch_at_the_update_end_sees_what_the_update_computes() {
        let mut s = Servo::new(ServoParams::default(), 0.0);
        for k in 1..=20 {
            let t = f64::from(k) * 1e-3;
            let seen = s.feedback_at(t * t, 2.0 * t, 1e-3, 1e-3);
            let middle = s.feedback_at(t * t, 2.0 * t, 1e-3, 0.4e-3);
            s.step(t * t, 2.0 * t, 1e-3);
            assert_eq!(seen.to_bits(), s.feedback().to_bits());
            assert!(middle <= s.feedback());
        }
    }

    #[test]
    fn a_fault_stops_the_motor_at_the_torque_limit_and_holds_it() {
        let params = ServoParams {
            velocity_feedforward: 1.0,
            ..ServoParams::default()
        };
        let a = params.acceleration_limit();
        let mut s = Servo::new(params, 0.0);
        for k in 1..=300 {
            let t = f64::from(k) * 1e-3;
            s.step(5.0 * t, 5.0, 1e-3);
        }
        let (p0, v0) = (s.position(), s.velocity());
        s.fault();
        for k in 301..=600 {
            s.step(5.0 * f64::from(k) * 1e-3, 5.0, 1e-3);
        }
        assert_eq!(s.mode(), Mode::Held);
        assert_eq!(s.velocity(), 0.0);
        let travelled = s.position() - p0;
        assert!(
            (travelled - v0 * v0 / (2.0 * a)).abs() < 1e-9,
            "{travelled}"
        );
        s.reset(s.feedback());
        s.step(s.feedback(), 0.0, 1e-3);
        assert_eq!(s.mode(), Mode::Following);
    }
}
