//! The superimposed layer: GEAR FOR moves added on top of the base motion, each spread over a
//! pacer distance with a smooth (quintic) profile, ending exactly `dist` further.

use std::collections::VecDeque;

/// A queued `GEAR FOR dist IN pacer_dist`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SuperSeg {
    pub(super) dist: f64,
    pub(super) pacer_dist: f64,
}

/// A running GEAR FOR: `dist·s(u)`, u = (x − x0)/pacer_dist clamped to [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Moving {
    pub(super) x0: f64,
    pub(super) dist: f64,
    pub(super) pacer_dist: f64,
}

/// The superimposed offset from one instant until the next piece starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SuperPiece {
    /// The completed moves, added exactly.
    pub(super) acc: f64,
    pub(super) moving: Option<Moving>,
}

/// The smooth step: s(0) = 0, s(1) = 1 exactly, zero velocity and acceleration at both ends.
fn s(u: f64) -> f64 {
    u * u * u * (10.0 + u * (6.0 * u - 15.0))
}

/// ds/du.
fn ds(u: f64) -> f64 {
    let w = u * (1.0 - u);
    30.0 * w * w
}

impl Moving {
    fn u(&self, x: f64) -> f64 {
        ((x - self.x0) / self.pacer_dist).clamp(0.0, 1.0)
    }
}

impl SuperPiece {
    /// The offset with the pacer at `x`.
    pub(super) fn offset(&self, x: f64) -> f64 {
        match self.moving {
            Some(m) => self.acc + m.dist * s(m.u(x)),
            None => self.acc,
        }
    }

    /// d(offset)/dt with the pacer at `x` moving at `vx`.
    pub(super) fn velocity(&self, x: f64, vx: f64) -> f64 {
        match self.moving {
            Some(m) => m.dist * ds(m.u(x)) * vx / m.pacer_dist,
            None => 0.0,
        }
    }
}

/// One axis's superimposed layer.
#[derive(Debug, Clone)]
pub(super) struct SuperLayer {
    /// Queued moves; the front is the head (running when `running` is set).
    pub(super) queue: VecDeque<SuperSeg>,
    /// The pacer position the running head ends at.
    pub(super) running: Option<f64>,
    /// Pieces of the last advanced interval, (start, piece), the first carried over from before.
    pub(super) hist: Vec<(f64, SuperPiece)>,
    /// A shift of the constant offset to apply at the start of the next interval (registration
    /// corrections), outside the queue.
    pub(super) pending: f64,
}

impl SuperLayer {
    pub(super) fn new() -> SuperLayer {
        SuperLayer {
            queue: VecDeque::new(),
            running: None,
            pending: 0.0,
            hist: vec![(
                0.0,
                SuperPiece {
                    acc: 0.0,
                    moving: None,
                },
            )],
        }
    }

    /// The piece in force at `t` (the latest starting at or before it).
    pub(super) fn piece_at(&self, t: f64) -> SuperPiece {
        let found = self.hist.iter().rev().find(|(s, _)| *s <= t);
        match found.or(self.hist.first()) {
            Some((_, p)) => *p,
            // `hist` is never empty; no offset is the harmless answer anyway.
            None => SuperPiece {
                acc: 0.0,
                moving: None,
            },
        }
    }

    /// Keep only the piece in force at `t`, the start of a new interval.
    pub(super) fn keep_from(&mut self, t: f64) {
        let current = (t, self.piece_at(t));
        self.hist.clear();
        self.hist.push(current);
    }

    /// Apply the pending shift at `t`, the start of an interval.
    pub(super) fn apply_pending(&mut self, t: f64) {
        if self.pending != 0.0 {
            // A running GEAR FOR keeps its own profile; only the constant part moves.
            let mut piece = self.piece_at(t);
            piece.acc += self.pending;
            self.hist.push((t, piece));
            self.pending = 0.0;
        }
    }

    /// Start the head at `t` with the pacer at `x`. Returns `Some(dist)` when it was a step
    /// (pacer distance 0), already applied and popped.
    pub(super) fn start_head(&mut self, t: f64, x: f64) -> Option<f64> {
        let seg = *self.queue.front()?;
        let acc = self.piece_at(t).acc;
        if seg.pacer_dist == 0.0 {
            let moving = None;
            self.hist.push((
                t,
                SuperPiece {
                    acc: acc + seg.dist,
                    moving,
                },
            ));
            self.queue.pop_front();
            return Some(seg.dist);
        }
        let moving = Some(Moving {
            x0: x,
            dist: seg.dist,
            pacer_dist: seg.pacer_dist,
        });
        self.hist.push((t, SuperPiece { acc, moving }));
        self.running = Some(x + seg.pacer_dist);
        None
    }

    /// Complete the running head at `t`: its whole distance joins the constant offset exactly.
    pub(super) fn complete(&mut self, t: f64) {
        let piece = self.piece_at(t);
        let dist = piece.moving.map_or(0.0, |m| m.dist);
        self.hist.push((
            t,
            SuperPiece {
                acc: piece.acc + dist,
                moving: None,
            },
        ));
        self.running = None;
        self.queue.pop_front();
    }

    /// The direction the pacer travels in for the running head.
    pub(super) fn direction(&self) -> f64 {
        self.queue.front().map_or(1.0, |s| s.pacer_dist.signum())
    }
}
