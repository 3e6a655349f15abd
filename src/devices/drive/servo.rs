//! The drive's servo loop bound to its members: the loop stepped to each update's command,
//! `PosnFeedback`, `VelFeedback` and `FollowingError` from it, the following-error fault
//! (motion stopped, the motor brought to rest at the torque limit and held, `FollowingErrorFault`
//! on until `FaultReset`), and the encoder count a capture latches. Without `[servo]` none of
//! this runs: feedback is the command, as it always was.

use super::{Drive, Now};
use crate::devices::servo::{Servo, ServoParams};
use crate::trace;

/// The servo loop behind the drive's axis.
#[derive(Debug, Clone)]
pub(super) struct ServoLoop {
    /// The loop itself.
    pub model: Servo,
    /// The real time (seconds) the loop was last stepped to; `None` before the first update.
    pub time: Option<f64>,
    /// The drive is faulted: motion stopped, initiates ignored until `FaultReset`.
    pub faulted: bool,
}

impl ServoLoop {
    /// A loop with `params`, its motor at rest at 0.
    pub fn new(params: ServoParams) -> ServoLoop {
        ServoLoop {
            model: Servo::new(params, 0.0),
            time: None,
            faulted: false,
        }
    }
}

impl Drive {
    /// Step the servo loop to this update's command: feedback position and velocity (not
    /// rolled over), or the command itself on an ideal servo. Before the motion events are
    /// traced, so a motion's end carries the feedback there.
    pub(super) fn step_servo(&mut self, now: &Now<'_>) -> (f64, f64) {
        let command = self.axis.command();
        let Some(servo) = self.servo.as_mut() else {
            return (command, self.axis.velocity());
        };
        let t = now.seconds();
        let dt = servo.time.map_or(0.0, |t0| t - t0);
        servo.time = Some(t);
        servo.model.step(command, self.axis.velocity(), dt);
        if servo.faulted {
            // A faulted drive's command follows its feedback (it commands nothing), so the
            // reset starts from where the motor is.
            let shift = servo.model.feedback() - command;
            self.axis.profiles[0].position += shift;
            servo.model.reset_command(self.axis.command());
        }
        (servo.model.feedback(), servo.model.velocity())
    }

    /// The feedback position a motion event reports: only with a servo model.
    pub(super) fn event_feedback(&self, feedback: f64) -> Option<f64> {
        self.servo.as_ref().map(|_| self.wrap(feedback))
    }

    /// A following error past its limit (with FollowingErrorEnable on) faults the drive: the
    /// loop brings the motor to rest, every motion stops at once, the fault is traced.
    pub(super) fn check_following_error(
        &mut self,
        feedback: f64,
        v: &mut [f64],
        now: &mut Now<'_>,
    ) {
        let command = self.axis.command();
        let a = self.slots.axis;
        let Some(servo) = self.servo.as_mut() else {
            return;
        };
        let over = (command - feedback).abs() > v[a.fe_limit as usize];
        if servo.faulted || v[a.fe_enable as usize] == 0.0 || !over {
            return;
        }
        servo.faulted = true;
        servo.model.fault();
        v[a.fault as usize] = 1.0;
        now.trace.emit(
            now.tick,
            &trace::Event::Fault {
                axis: "Motion".into(),
                fault: "following_error".into(),
                command: self.wrap(command),
                feedback: self.wrap(feedback),
                limit: v[a.fe_limit as usize],
            },
        );
        // The drive stops every motion at once: its profiles end where they stand.
        for i in 0..self.axis.profiles.len() {
            self.stop_profile(i, 0.0, v, now);
        }
    }

    /// The drive is faulted (motion initiates are ignored).
    pub(super) fn faulted(&self) -> bool {
        self.servo.as_ref().is_some_and(|s| s.faulted)
    }

    /// `FaultReset`: the drive follows its command again, starting at the feedback position.
    pub(super) fn fault_reset(&mut self, v: &mut [f64]) {
        let Some(servo) = self.servo.as_mut() else {
            return;
        };
        if servo.faulted {
            servo.faulted = false;
            servo.model.reset(self.axis.command());
            v[self.slots.axis.fault as usize] = 0.0;
        }
    }

    /// The feedback position an encoder latch takes for an edge at `t` (within the coming
    /// update), as reported: the loop run ahead to the edge plus the latch delay, quantized.
    /// `command` is the command position at `t`, the feedback on an ideal servo.
    pub(super) fn latched_feedback(&self, t: f64, command: f64, v: &[f64], now: &Now<'_>) -> f64 {
        let Some(servo) = &self.servo else {
            return command;
        };
        let Some(t0) = servo.time else {
            return self.wrap(servo.model.feedback());
        };
        let t1 = now.seconds();
        let end = self
            .axis
            .position_at(self.motion_time_of(t1, v), now.master_at(t1));
        let at = t - t0 + servo.model.params().latch_delay;
        self.wrap(
            servo
                .model
                .feedback_at(end, self.axis.velocity(), t1 - t0, at),
        )
    }

    /// A motion initiate on a faulted drive: ignored, with a warning in the trace.
    pub(super) fn refuse_faulted(&self, what: &str, now: &mut Now<'_>) {
        now.trace.machine_warning(
            now.tick,
            format!("{what}: the drive has a following-error fault; FaultReset clears it"),
        );
    }
}
