//! The DSP axes' servo loops (`[axis.N.servo]`), bound to the Axis members: each axis's loop
//! stepped to its command every update, `Axis.N.Feedback` and `Axis.N.FollowingError` from it,
//! and its following-error fault: the axis's command ramps to rest (its gear let go), the motor
//! is brought to rest at its torque limit and held, `FollowingErrorFault` is on until
//! `FaultReset`. An axis without a loop is ideal: feedback is its position.

use super::Orion;
use crate::devices::servo::{Servo, ServoParams};
use crate::devices::Now;
use crate::registry::catalog::AXIS_TYPE;
use crate::trace;

/// One DSP axis's loop.
#[derive(Debug, Clone)]
pub(super) struct AxisLoop {
    model: Servo,
    /// The real time the loop was last stepped to.
    time: Option<f64>,
    faulted: bool,
}

impl AxisLoop {
    /// A loop with `params`, its motor at rest at 0.
    pub fn new(params: ServoParams) -> AxisLoop {
        AxisLoop {
            model: Servo::new(params, 0.0),
            time: None,
            faulted: false,
        }
    }
}

/// Offsets of the servo's Axis members in one instance's slots.
#[derive(Debug, Clone, Copy)]
pub(super) struct ServoMembers {
    pub feedback: u32,
    pub following_error: u32,
    pub limit: u32,
    pub enable: u32,
    pub fault: u32,
}

/// The servo's Axis members, bound when pacer is compiled.
pub(super) const SERVO_MEMBERS: ServoMembers = ServoMembers {
    feedback: crate::member_index!(AXIS_TYPE, "Feedback") as u32,
    following_error: crate::member_index!(AXIS_TYPE, "FollowingError") as u32,
    limit: crate::member_index!(AXIS_TYPE, "FollowingErrorLimit") as u32,
    enable: crate::member_index!(AXIS_TYPE, "FollowingErrorEnable") as u32,
    fault: crate::member_index!(AXIS_TYPE, "FollowingErrorFault") as u32,
};

impl Orion {
    /// The slot of servo member `member` of the axis at index `i`.
    fn servo_slot(&self, i: usize, member: u32) -> Option<usize> {
        let n = self.configs.get(i)?.number;
        (n >= 1 && n <= self.count).then(|| (self.base + (n - 1) * self.per + member) as usize)
    }

    /// Step axis `i`'s loop to its command (`reported`: its position as reported) and set
    /// `Feedback` and `FollowingError`; a following error past its limit faults the axis.
    pub(super) fn servo_update(
        &mut self,
        i: usize,
        reported: f64,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) -> Result<(), String> {
        let n = self.configs[i].number;
        let s = SERVO_MEMBERS;
        let (Some(fb_slot), Some(fe_slot)) = (
            self.servo_slot(i, s.feedback),
            self.servo_slot(i, s.following_error),
        ) else {
            return Ok(());
        };
        let Some(Some(servo)) = self.servos.get_mut(i) else {
            v[fb_slot] = reported;
            return Ok(());
        };
        let command = self.dsp.position(n).map_err(|e| e.0)?;
        let velocity = self.dsp.velocity(n).map_err(|e| e.0)?;
        let t = now.seconds();
        let dt = servo.time.map_or(0.0, |t0| t - t0);
        servo.time = Some(t);
        servo.model.step(command, velocity, dt);
        let error = command - servo.model.feedback();
        v[fb_slot] = reported - error;
        v[fe_slot] = error;
        let at = |m: u32| self.base as usize + (n as usize - 1) * self.per as usize + m as usize;
        let (limit, enable, fault) = (at(s.limit), at(s.enable), at(s.fault));
        let faulted = servo.faulted;
        if faulted || v[enable] == 0.0 || error.abs() <= v[limit] {
            return Ok(());
        }
        servo.faulted = true;
        servo.model.fault();
        v[fault] = 1.0;
        now.trace.emit(
            now.tick,
            &trace::Event::Fault {
                axis: format!("Axis.{n}").into(),
                fault: "following_error".into(),
                command: reported,
                feedback: reported - error,
                limit: v[limit],
            },
        );
        // The axis's command ramps to rest at its deceleration, its gear let go: the motor
        // cannot follow it anyway.
        let decel = self.defaults[i].accel;
        self.dsp.halt(n, decel).map_err(|e| e.0)
    }

    /// `Axis.N.FaultReset` written 1: the axis's command is moved onto its feedback (at the
    /// next update) and its loop follows again.
    pub(super) fn servo_reset(&mut self, n: u32, v: &mut [f64]) -> Result<(), String> {
        let Some(i) = self.configs.iter().position(|c| c.number == n) else {
            return Ok(());
        };
        let fault = self.servo_slot(i, SERVO_MEMBERS.fault);
        let Some(Some(servo)) = self.servos.get_mut(i) else {
            return Ok(());
        };
        if !servo.faulted {
            return Ok(());
        }
        servo.faulted = false;
        let command = self.dsp.position(n).map_err(|e| e.0)?;
        let feedback = servo.model.feedback();
        servo.model.reset(feedback);
        self.dsp.shift(n, feedback - command).map_err(|e| e.0)?;
        if let Some(f) = fault {
            v[f] = 0.0;
        }
        Ok(())
    }

    /// A faulted axis refuses motion statements.
    pub(super) fn servo_faulted(&self, n: u32) -> bool {
        self.configs
            .iter()
            .position(|c| c.number == n)
            .and_then(|i| self.servos.get(i))
            .is_some_and(|s| s.as_ref().is_some_and(|s| s.faulted))
    }
}
