//! The base layer: the DSP motion queue of MOVE AT (time-based velocity ramps) and GEAR AT
//! (ratio to the pacer, optionally ramped over pacer distance) segments.

use std::collections::VecDeque;

use super::After;

/// A base segment waiting in, or running at the head of, the queue.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum BaseSeg {
    /// Ramp to `speed` (units/s) over `duration` seconds, then hold it.
    Move { speed: f64, duration: f64 },
    /// Ramp the ratio to `ratio` over `pacer_dist` of pacer travel (0: at once), after `after`.
    Gear {
        ratio: f64,
        pacer_dist: f64,
        after: Option<After>,
    },
}

/// The base motion from one instant until the next piece starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum BasePiece {
    /// Time-based: `p0 + v0·τ + ½·a·τ²`, τ = t − t0.
    Time { t0: f64, p0: f64, v0: f64, a: f64 },
    /// Geared: `b0 + g(x − x0)` of the pacer position x, the ratio going linearly from `r0` to
    /// `r1` over pacer travel [0, d] (r0 before, r1 after; d = 0: a constant ratio r1).
    Geared {
        x0: f64,
        b0: f64,
        r0: f64,
        r1: f64,
        d: f64,
    },
}

impl BasePiece {
    /// True when the piece depends on the pacer's position.
    pub(super) fn geared(&self) -> bool {
        matches!(self, BasePiece::Geared { .. })
    }

    /// Base position at `t` with the pacer at `x`.
    pub(super) fn position(&self, t: f64, x: f64) -> f64 {
        match *self {
            BasePiece::Time { t0, p0, v0, a } => {
                let tau = t - t0;
                p0 + v0 * tau + 0.5 * a * tau * tau
            }
            BasePiece::Geared { x0, b0, r0, r1, d } => {
                let y = x - x0;
                if d <= 0.0 {
                    b0 + r1 * y
                } else if y <= 0.0 {
                    b0 + r0 * y
                } else if y < d {
                    b0 + r0 * y + (r1 - r0) * y * y / (2.0 * d)
                } else {
                    b0 + (r0 + r1) * 0.5 * d + r1 * (y - d)
                }
            }
        }
    }

    /// Base velocity at `t` with the pacer at `x` moving at `vx`.
    pub(super) fn velocity(&self, t: f64, x: f64, vx: f64) -> f64 {
        match *self {
            BasePiece::Time { t0, v0, a, .. } => v0 + a * (t - t0),
            BasePiece::Geared { .. } => self.ratio(x).unwrap_or(0.0) * vx,
        }
    }

    /// The ratio with the pacer at `x`, or None for time-based motion.
    pub(super) fn ratio(&self, x: f64) -> Option<f64> {
        match *self {
            BasePiece::Time { .. } => None,
            BasePiece::Geared { x0, r0, r1, d, .. } => {
                let y = x - x0;
                Some(if d <= 0.0 || y >= d {
                    r1
                } else if y <= 0.0 {
                    r0
                } else {
                    r0 + (r1 - r0) * y / d
                })
            }
        }
    }

    /// The time a time-based piece stands still (where its position may turn back).
    pub(super) fn vertex(&self) -> Option<f64> {
        match *self {
            BasePiece::Time { t0, v0, a, .. } if a != 0.0 => Some(t0 - v0 / a),
            _ => None,
        }
    }
}

/// How the running head segment ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum BaseEnd {
    /// A velocity ramp ending at this time, then holding this speed.
    At { time: f64, speed: f64 },
    /// A ratio ramp ending when the pacer reaches this position.
    PacerAt(f64),
}

/// One axis's base layer.
#[derive(Debug, Clone)]
pub(super) struct BaseLayer {
    /// Queued segments; the front is the head (running when `running` is set).
    pub(super) queue: VecDeque<BaseSeg>,
    pub(super) running: Option<BaseEnd>,
    /// Pieces of the last advanced interval, (start, piece), the first carried over from before.
    pub(super) hist: Vec<(f64, BasePiece)>,
}

impl BaseLayer {
    pub(super) fn new() -> BaseLayer {
        let rest = BasePiece::Time {
            t0: 0.0,
            p0: 0.0,
            v0: 0.0,
            a: 0.0,
        };
        BaseLayer {
            queue: VecDeque::new(),
            running: None,
            hist: vec![(0.0, rest)],
        }
    }

    /// The piece in force at `t` (the latest starting at or before it).
    pub(super) fn piece_at(&self, t: f64) -> BasePiece {
        let found = self.hist.iter().rev().find(|(s, _)| *s <= t);
        match found.or(self.hist.first()) {
            Some((_, p)) => *p,
            // `hist` is never empty; standing still at 0 is the harmless answer anyway.
            None => BasePiece::Time {
                t0: 0.0,
                p0: 0.0,
                v0: 0.0,
                a: 0.0,
            },
        }
    }

    /// Keep only the piece in force at `t`, the start of a new interval.
    pub(super) fn keep_from(&mut self, t: f64) {
        let current = (t, self.piece_at(t));
        self.hist.clear();
        self.hist.push(current);
    }

    /// Start the head segment at `t`, the pacer at `x` moving at `vx` (0, 0 without a pacer).
    /// Returns true when the segment completed at once (then it is already popped).
    pub(super) fn start_head(&mut self, t: f64, x: f64, vx: f64) -> bool {
        let Some(&seg) = self.queue.front() else {
            return false;
        };
        let now = self.piece_at(t);
        let p = now.position(t, x);
        let v = now.velocity(t, x, vx);
        match seg {
            BaseSeg::Move { speed, duration } => {
                let a = (speed - v) / duration;
                // A ramp too short for a finite acceleration is a velocity step.
                if duration <= 0.0 || !a.is_finite() {
                    self.hist.push((t, time_piece(t, p, speed, 0.0)));
                    self.queue.pop_front();
                    return true;
                }
                self.hist.push((t, time_piece(t, p, v, a)));
                let time = t + duration;
                self.running = Some(BaseEnd::At { time, speed });
            }
            BaseSeg::Gear {
                ratio, pacer_dist, ..
            } => {
                // A time-based axis enters the gear at the ratio it is moving at (0 if the pacer stands).
                let r0 = match now.ratio(x) {
                    Some(r) => r,
                    None => Some(v / vx).filter(|r| r.is_finite()).unwrap_or(0.0),
                };
                let d = pacer_dist;
                let r0 = if d > 0.0 { r0 } else { ratio };
                let piece = BasePiece::Geared {
                    x0: x,
                    b0: p,
                    r0,
                    r1: ratio,
                    d,
                };
                self.hist.push((t, piece));
                if d <= 0.0 {
                    self.queue.pop_front();
                    return true;
                }
                self.running = Some(BaseEnd::PacerAt(x + d));
            }
        }
        false
    }

    /// Complete the running head at `t`: the next piece is anchored at the segment's exact end.
    pub(super) fn complete(&mut self, t: f64) {
        let now = self.piece_at(t);
        match (self.running.take(), now) {
            (Some(BaseEnd::At { time, speed }), _) => {
                let p = now.position(time, 0.0);
                self.hist.push((t, time_piece(time, p, speed, 0.0)));
            }
            (Some(BaseEnd::PacerAt(_)), BasePiece::Geared { x0, b0, r0, r1, d }) => {
                let piece = BasePiece::Geared {
                    x0: x0 + d,
                    b0: b0 + (r0 + r1) * 0.5 * d,
                    r0: r1,
                    r1,
                    d: 0.0,
                };
                self.hist.push((t, piece));
            }
            // Nothing running, or a ratio ramp over a time piece (cannot happen): no new piece.
            _ => {}
        }
        self.queue.pop_front();
    }
}

fn time_piece(t0: f64, p0: f64, v0: f64, a: f64) -> BasePiece {
    BasePiece::Time { t0, p0, v0, a }
}
