//! Fast-input edges and the axis position: marks classified, the DIST+TOLR event, corrections
//! queued and released.

use super::{
    err, Mark, MarkClass, Regist, RegistError, BAD_MARK, DIST_TOLR, FAST_INPUT, FAST_IN_OCCURRED,
    FAST_IN_RISING, GOOD_MARK, SWITCH_DIM, SWITCH_MASTER, SWITCH_SLAVE, TIME_RESOLUTION,
};

/// `x mod lgth` folded into (-lgth/2, lgth/2].
fn fold(x: f64, lgth: f64) -> f64 {
    let c = x.rem_euclid(lgth);
    // rem_euclid may round up to lgth itself for a tiny negative x: that folds to 0 too.
    if c > lgth / 2.0 {
        c - lgth
    } else {
        c
    }
}

impl Regist {
    /// A fast-input edge at `time` seconds with the registration axis at continuous
    /// `position`. Rising edges are marks; a falling edge only clears [`FAST_IN_RISING`]. A
    /// mark closer than the minimum time (var 25) to the last latched mark is not seen at all
    /// (None, nothing changes). While registration is off an edge only updates the input
    /// state. Refused: non-finite values, an edge earlier than the previous one, or a position
    /// so far from the ruler that the distance overflows.
    pub fn edge(
        &mut self,
        time: f64,
        position: f64,
        rising: bool,
    ) -> Result<Option<Mark>, RegistError> {
        if !time.is_finite() {
            return err(format!("fast-input edge time must be finite, not {time}"));
        }
        if !position.is_finite() {
            return err(format!(
                "fast-input edge position must be finite, not {position}"
            ));
        }
        if let Some((t0, _)) = self.last_edge {
            if time < t0 {
                return err(format!(
                    "fast-input edge at {time} s is earlier than the previous edge at {t0} s"
                ));
            }
        }
        // A falling edge, or any edge while registration is off, is only the input's state.
        let Some(p) = self.params.filter(|_| rising) else {
            self.input_state(rising);
            self.last_edge = Some((time, position));
            return Ok(None);
        };
        if let Some(t) = self.last_mark_time {
            if time - t < self.min_time - TIME_RESOLUTION {
                return Ok(None);
            }
        }
        // Everything is computed before anything changes, so a refusal leaves no trace.
        let (class, distance, correction) = if self.armed {
            let d = position - self.ruler_start;
            let since_good = position - self.last_good;
            if !(d.is_finite() && since_good.is_finite()) {
                return err(format!(
                    "fast-input position {position} is too far from the ruler start {} and the last good mark {} to measure",
                    self.ruler_start, self.last_good
                ));
            }
            if p.ignr > 0.0 && d < p.ignr {
                (MarkClass::Ignored, Some(d), None)
            } else if p.dist == 0.0 || (p.dist - p.tolr <= d && d <= p.dist + p.tolr) {
                (MarkClass::Good, Some(d), Some(fold(since_good, p.lgth)))
            } else {
                (MarkClass::Bad, Some(d), None)
            }
        } else {
            (MarkClass::Good, None, Some(0.0))
        };
        let entrant = !self.armed;
        self.direction = match self.last_edge {
            Some((_, q)) if position > q => 1.0,
            Some((_, q)) if position < q => -1.0,
            _ => 0.0,
        };
        self.last_edge = Some((time, position));
        self.last_mark_time = Some(time);
        self.armed = true;
        self.latch = position;
        self.distance = distance.unwrap_or(0.0);
        let mut rereference = None;
        match class {
            MarkClass::Good => {
                let c = correction.unwrap_or(0.0);
                self.ruler_start = position;
                self.last_good = position;
                self.window_passed = false;
                self.bad_count = 0;
                self.status = FAST_IN_OCCURRED | FAST_INPUT | GOOD_MARK;
                self.last_correction = c;
                self.apply_correction(c);
                if self.switches & SWITCH_DIM != 0 {
                    rereference = Some(p.dim);
                }
            }
            MarkClass::Bad => {
                self.ruler_start = position;
                self.window_passed = false;
                self.bad_count = self.bad_count.saturating_add(1);
                self.status = FAST_IN_OCCURRED | FAST_INPUT | BAD_MARK;
            }
            MarkClass::Ignored => self.status = FAST_IN_OCCURRED | FAST_INPUT,
        }
        self.input_state(true);
        Ok(Some(Mark {
            class,
            entrant,
            position,
            distance,
            correction,
            rereference,
        }))
    }

    fn input_state(&mut self, on: bool) {
        if on {
            self.status |= FAST_IN_RISING;
        } else {
            self.status &= !FAST_IN_RISING;
        }
    }

    /// Queue a correction on the channels var 24 switches on (sign: see the module doc).
    pub(super) fn apply_correction(&mut self, c: f64) {
        if self.switches & SWITCH_SLAVE != 0 {
            self.slave.queue(c);
        }
        if self.switches & SWITCH_MASTER != 0 {
            self.master.queue(-c);
        }
    }

    /// A rising edge at `time` would not be seen, being closer than the minimum time (var 25)
    /// to the last latched mark: how long after it the edge comes, seconds.
    pub fn too_soon(&self, time: f64) -> Option<f64> {
        self.params?;
        let t = self.last_mark_time?;
        (time - t < self.min_time - TIME_RESOLUTION).then_some(time - t)
    }

    /// The minimum time between marks (var 25), seconds.
    pub fn min_time(&self) -> f64 {
        self.min_time
    }

    /// The position at which the DIST + TOLR event fires next (`ruler_start + DIST + TOLR`), or
    /// None when it cannot fire (registration off or not armed, DIST 0, already passed for this
    /// ruler).
    pub fn window_threshold(&self) -> Option<f64> {
        let p = self.params?;
        (self.armed && p.dist > 0.0 && !self.window_passed)
            .then_some(self.ruler_start + p.dist + p.tolr)
    }

    /// The axis reached [`Regist::window_threshold`]: the DIST + TOLR event, once per ruler;
    /// STATUSSV then holds [`DIST_TOLR`] alone. False when it could not fire.
    pub fn pass_window(&mut self) -> bool {
        if self.window_threshold().is_none() {
            return false;
        }
        self.window_passed = true;
        self.status = DIST_TOLR;
        true
    }

    /// Called each update with the registration axis's continuous position: true exactly once
    /// per ruler when (DIST > 0) the axis reaches `ruler_start + DIST + TOLR` without a
    /// recognised mark. STATUSSV then holds [`DIST_TOLR`] alone, per the spec's table.
    pub fn passed(&mut self, position: f64) -> Result<bool, RegistError> {
        if !position.is_finite() {
            return err(format!("axis position must be finite, not {position}"));
        }
        let Some(p) = self.params else {
            return Ok(false);
        };
        if !self.armed || p.dist <= 0.0 || self.window_passed {
            return Ok(false);
        }
        if position >= self.ruler_start + p.dist + p.tolr {
            return Ok(self.pass_window());
        }
        Ok(false)
    }

    /// Called each update: the (slave, master) offset deltas to add at this update. Queued
    /// corrections are released only while `master_moving && slave_ratio_move` (registration
    /// never causes motion by itself), spread evenly over var 17 / var 18 updates; vars 13–16
    /// follow.
    pub fn take_correction(&mut self, master_moving: bool, slave_ratio_move: bool) -> (f64, f64) {
        let running = master_moving && slave_ratio_move;
        (self.slave.release(running), self.master.release(running))
    }
}
