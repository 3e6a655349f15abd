//! The motion statements: MOVE AT, GEAR AT, GEAR FOR and AFTER inputs, queued per axis, and
//! DSP.DONE@.

use super::gear::{BasePiece, BaseSeg};
use super::superimpose::SuperSeg;
use super::{err, After, DspAxes, DspError, Queued, Trigger};

impl DspAxes {
    /// The pacer of axis `i`, or an error for a statement `what` that needs one.
    fn pacer_for(&self, i: usize, what: &str) -> Result<usize, DspError> {
        self.axes[i].pacer.ok_or_else(|| {
            DspError(format!(
                "{what} on axis {} needs a pacer: the axis has no MotionData link",
                self.axes[i].number
            ))
        })
    }

    fn queue_full(&self, i: usize) -> bool {
        let a = &self.axes[i];
        a.base.queue.len() + a.sup.queue.len() >= a.queue_depth
    }

    /// `MOVE axis AT speed_rpm IN time_ms`: ramp the velocity linearly in time to the speed, then
    /// hold it (time-based motion; 0 ms is a velocity step).
    pub fn move_at(&mut self, axis: u32, speed_rpm: f64, time_ms: f64) -> Result<Queued, DspError> {
        let i = self.axis(axis)?;
        if !speed_rpm.is_finite() {
            return err(format!(
                "MOVE on axis {axis}: the speed must be a number, not {speed_rpm}"
            ));
        }
        if !(time_ms.is_finite() && time_ms >= 0.0) {
            return err(format!(
                "MOVE on axis {axis}: the ramp time must be 0 ms or more, not {time_ms}"
            ));
        }
        let speed = speed_rpm * self.axes[i].units_per_rev / 60.0;
        if !speed.is_finite() {
            return err(format!(
                "MOVE on axis {axis}: {speed_rpm} RPM is beyond any speed"
            ));
        }
        if self.queue_full(i) {
            return Ok(Queued::Full);
        }
        self.axes[i].base.queue.push_back(BaseSeg::Move {
            speed,
            duration: time_ms / 1000.0,
        });
        Ok(Queued::Accepted)
    }

    /// `GEAR axis AT out TO inn [IN pacer_dist] [AFTER input|sensor]`: follow the pacer at
    /// out/inn, the ratio ramping linearly over `pacer_dist` of pacer travel, starting when
    /// `after` comes (an input's rising edge, or the next edge of a sensor of the axis's card
    /// once the segment is at its queue head).
    pub fn gear_at(
        &mut self,
        axis: u32,
        out: f64,
        inn: f64,
        pacer_dist: Option<f64>,
        after: Option<After>,
    ) -> Result<Queued, DspError> {
        let i = self.axis(axis)?;
        self.pacer_for(i, "GEAR AT")?;
        if !(out.is_finite() && inn.is_finite()) {
            return err(format!(
                "GEAR AT on axis {axis}: the ratio {out} TO {inn} must be numbers"
            ));
        }
        if inn == 0.0 {
            return err(format!(
                "GEAR AT on axis {axis}: the ratio {out} TO 0 divides by zero"
            ));
        }
        let d = pacer_dist.unwrap_or(0.0);
        if !(d.is_finite() && d >= 0.0) {
            return err(format!(
                "GEAR AT on axis {axis}: the pacer distance (IN) must be 0 or more, not {d}"
            ));
        }
        if self.queue_full(i) {
            return Ok(Queued::Full);
        }
        let ratio = out / inn;
        if !ratio.is_finite() {
            return err(format!(
                "GEAR AT on axis {axis}: the ratio {out} TO {inn} is beyond any ratio"
            ));
        }
        let seg = BaseSeg::Gear {
            ratio,
            pacer_dist: d,
            after,
        };
        self.axes[i].base.queue.push_back(seg);
        Ok(Queued::Accepted)
    }

    /// Shift the axis by `delta` at the start of the next update, outside its motion queue: a
    /// registration correction released by the servo side.
    pub fn shift(&mut self, axis: u32, delta: f64) -> Result<(), DspError> {
        let i = self.axis(axis)?;
        if !delta.is_finite() {
            return err(format!("a shift of axis {axis} by {delta}"));
        }
        self.axes[i].sup.pending += delta;
        Ok(())
    }

    /// `GEAR axis FOR dist IN pacer_dist`: superimpose `dist` on the axis while its pacer covers
    /// `pacer_dist` (negative: the pacer is expected to travel negatively). IN 0 is a step.
    pub fn gear_for(&mut self, axis: u32, dist: f64, pacer_dist: f64) -> Result<Queued, DspError> {
        let i = self.axis(axis)?;
        self.pacer_for(i, "GEAR FOR")?;
        if !(dist.is_finite() && pacer_dist.is_finite()) {
            return err(format!(
                "GEAR FOR on axis {axis}: FOR {dist} IN {pacer_dist} must be numbers"
            ));
        }
        if self.queue_full(i) {
            return Ok(Queued::Full);
        }
        self.axes[i]
            .sup
            .queue
            .push_back(SuperSeg { dist, pacer_dist });
        Ok(if pacer_dist == 0.0 {
            Queued::AcceptedAsStep
        } else {
            Queued::Accepted
        })
    }

    /// An `AFTER input` event at time `t` (not before the current time): a gear segment waiting
    /// at its queue head for `input` at that instant starts then, during the next `advance`.
    pub fn trigger(&mut self, input: u32, t: f64) -> Result<(), DspError> {
        if !(t.is_finite() && t >= self.t_now) {
            return err(format!(
                "input {input} event at {t} s: it must not be before the current time {} s",
                self.t_now
            ));
        }
        let at = self.triggers.partition_point(|&(u, _)| u <= t);
        self.triggers.insert(at, (t, Trigger::Input(input)));
        Ok(())
    }

    /// Bring `axis` to rest for a stop (an I/O fault's safe state): what is queued is dropped,
    /// a time-based axis ramps its velocity linearly to 0 at `decel` units/s² from the current
    /// time, and a geared axis keeps its gear (its running ratio ramp included) and so comes to
    /// rest with its pacer, still in step with it. A superimposed correction already running
    /// ends over its pacer distance.
    pub fn stop(&mut self, axis: u32, decel: f64) -> Result<(), DspError> {
        self.stop_axis(axis, decel, true)
    }

    /// Bring `axis` to rest by its own ramp, a geared axis too (its gear let go at the ratio it
    /// moves at): a faulted axis's command, which its motor cannot follow.
    pub fn halt(&mut self, axis: u32, decel: f64) -> Result<(), DspError> {
        self.stop_axis(axis, decel, false)
    }

    fn stop_axis(&mut self, axis: u32, decel: f64, keep_gear: bool) -> Result<(), DspError> {
        let i = self.axis(axis)?;
        if !(decel.is_finite() && decel > 0.0) {
            return err(format!(
                "stopping axis {axis}: the deceleration must be above 0, not {decel}"
            ));
        }
        let t = self.time();
        let v = self.vel_at(i, t);
        let a = &mut self.axes[i];
        a.sup.queue.truncate(usize::from(a.sup.running.is_some()));
        let piece = a.base.piece_at(t);
        if keep_gear && piece.geared() && a.pacer.is_some() {
            a.base.queue.truncate(usize::from(a.base.running.is_some()));
            return Ok(());
        }
        // A geared axis let go ramps down from the velocity its gear gives it now.
        let v = if piece.geared() {
            v
        } else {
            piece.velocity(t, 0.0, 0.0)
        };
        a.base.queue.clear();
        a.base.running = None;
        if v != 0.0 {
            a.base.queue.push_back(BaseSeg::Move {
                speed: 0.0,
                duration: v.abs() / decel,
            });
        }
        Ok(())
    }

    /// DSP.DONE@: no segment running or queued in either layer (steady gear, steady velocity
    /// or standing still are done).
    pub fn done(&self, axis: u32) -> Result<bool, DspError> {
        let a = &self.axes[self.axis(axis)?];
        Ok(a.base.queue.is_empty() && a.sup.queue.is_empty())
    }

    /// Segments queued or running in both layers together.
    pub fn queued(&self, axis: u32) -> Result<usize, DspError> {
        let a = &self.axes[self.axis(axis)?];
        Ok(a.base.queue.len() + a.sup.queue.len())
    }

    /// Whether `axis` moves or has motion queued (`None`: at rest), and if so whether it comes
    /// to rest by itself: its last base segment ramps to speed 0 (a MOVE TO's deceleration, a
    /// MOVE AT 0) or to a ratio of 0; only superimposed moves remain, which end after their
    /// pacer distance. A speed or a gear ratio held runs until a program changes it.
    pub fn motion_state(&self, axis: u32) -> Result<Option<bool>, DspError> {
        let i = self.axis(axis)?;
        let a = &self.axes[i];
        if self.vel_at(i, self.t_now) == 0.0 && a.base.queue.is_empty() && a.sup.queue.is_empty() {
            return Ok(None);
        }
        let settles = match a.base.queue.back() {
            Some(BaseSeg::Move { speed, .. }) => *speed == 0.0,
            Some(BaseSeg::Gear { ratio, .. }) => *ratio == 0.0,
            None => match a.base.piece_at(self.t_now) {
                BasePiece::Time { v0, a, t0, .. } => v0 + a * (self.t_now - t0) == 0.0 && a == 0.0,
                BasePiece::Geared { r1, .. } => r1 == 0.0,
            },
        };
        Ok(Some(settles))
    }
}
