//! Advancing the axes through an update: segments start and complete at their exact instants
//! inside it, then the sensor marks the axes crossed make their card edges.

use super::gear::{BaseEnd, BaseSeg};
use super::{err, After, DspAxes, DspError, DspEvent, Layer, Sensor, Trigger};

/// More segment starts and ends in one update of one axis than this means a bug, not a program:
/// the queue holds a handful of segments and none is added while advancing.
const LOOP_CAP: usize = 10_000;

impl DspAxes {
    /// Move every axis from the current time to `t1`, pacers before their followers. The events
    /// come in time order.
    pub fn advance(&mut self, t1: f64) -> Result<Vec<DspEvent>, DspError> {
        if !(t1.is_finite() && t1 >= self.t_now) {
            return err(format!(
                "cannot advance the DSP axes to {t1} s: the current time is {} s",
                self.t_now
            ));
        }
        let ta = self.t_now;
        // Positions just before the update, to see a step applied at its very start.
        let before: Vec<f64> = (0..self.axes.len()).map(|i| self.pos_at(i, ta)).collect();
        for a in &mut self.axes {
            a.base.keep_from(ta);
            a.sup.keep_from(ta);
            a.sup.apply_pending(ta);
        }
        self.t_prev = ta;
        self.t_now = t1;
        // A gear waiting for a sensor of its card starts at an edge that is only known once the
        // axes have moved: run the update, find the first edge that starts a waiting gear, then
        // run it again from the same state with that edge as a trigger. Nothing before the edge
        // changes, so the edges found stay where they were; each round adds one, in time order.
        let waits = self.axes.iter().any(|a| {
            a.base.queue.iter().any(|s| {
                matches!(
                    s,
                    BaseSeg::Gear {
                        after: Some(After::Sensor(_)),
                        ..
                    }
                )
            })
        });
        let saved = waits.then(|| (self.axes.clone(), self.triggers.clone()));
        let mut found: Vec<(f64, Trigger)> = Vec::new();
        for _ in 0..LOOP_CAP {
            let mut events = Vec::new();
            for k in 0..self.order.len() {
                let i = self.order[k];
                self.run_axis(i, ta, t1, &mut events)?;
            }
            let waiting = self.waiting_on_sensors(ta, &events);
            let edge = self.mark_edges(&before, ta, t1, &waiting, &found, &mut events);
            match (edge, &saved) {
                (Some(trigger), Some((axes, triggers))) => {
                    found.push(trigger);
                    self.axes.clone_from(axes);
                    self.triggers.clone_from(triggers);
                    for &(t, k) in &found {
                        let at = self.triggers.partition_point(|&(u, _)| u <= t);
                        self.triggers.insert(at, (t, k));
                    }
                }
                _ => {
                    self.triggers.retain(|&(t, _)| t > t1);
                    events.sort_by(|a, b| a.time().total_cmp(&b.time()));
                    return Ok(events);
                }
            }
        }
        err("DSP axes: too many sensor edges starting gears in one update (a bug in pacer)")
    }

    /// For each axis, the sensor its base queue head waits for at the end of the update and the
    /// instant it began to wait (the update's start, or when the segment before it completed).
    fn waiting_on_sensors(&self, ta: f64, events: &[DspEvent]) -> Vec<Option<(Sensor, f64)>> {
        self.axes
            .iter()
            .map(|a| {
                let which = match (a.base.running, a.base.queue.front()) {
                    (
                        None,
                        Some(BaseSeg::Gear {
                            after: Some(After::Sensor(w)),
                            ..
                        }),
                    ) => *w,
                    _ => return None,
                };
                let since = events
                    .iter()
                    .filter_map(|e| match *e {
                        DspEvent::SegmentDone {
                            axis,
                            layer: Layer::Base,
                            time,
                        } if axis == a.number => Some(time),
                        _ => None,
                    })
                    .fold(ta, f64::max);
                Some((which, since))
            })
            .collect()
    }

    /// Axis `i` through [ta, tb]: its pacer is already there.
    fn run_axis(
        &mut self,
        i: usize,
        ta: f64,
        tb: f64,
        events: &mut Vec<DspEvent>,
    ) -> Result<(), DspError> {
        let mut t = ta;
        for _ in 0..LOOP_CAP {
            self.start_heads(i, t, events);
            let a = &self.axes[i];
            let base_end = match a.base.running {
                Some(BaseEnd::At { time, .. }) => (time <= tb).then_some(time.max(t)),
                Some(BaseEnd::PacerAt(x)) => {
                    a.pacer.and_then(|p| self.first_reach(p, x, 1.0, t, tb))
                }
                None => None,
            };
            let sup_end = match (a.sup.running, a.pacer) {
                (Some(x), Some(p)) => self.first_reach(p, x, a.sup.direction(), t, tb),
                _ => None,
            };
            let trigger = match a.base.queue.front() {
                Some(BaseSeg::Gear { after: Some(k), .. }) if a.base.running.is_none() => {
                    self.trigger_time(i, *k, t, tb)
                }
                _ => None,
            };
            let next = [base_end, sup_end, trigger]
                .into_iter()
                .flatten()
                .min_by(f64::total_cmp);
            let Some(te) = next else {
                return Ok(());
            };
            let number = a.number;
            if base_end == Some(te) {
                self.axes[i].base.complete(te);
                events.push(DspEvent::SegmentDone {
                    axis: number,
                    layer: Layer::Base,
                    time: te,
                });
            }
            if sup_end == Some(te) {
                self.axes[i].sup.complete(te);
                events.push(DspEvent::SegmentDone {
                    axis: number,
                    layer: Layer::Superimposed,
                    time: te,
                });
            }
            t = te;
        }
        err(format!(
            "DSP axis {}: too many segment changes in one update (a bug in pacer)",
            self.axes[i].number
        ))
    }

    /// The first event in [t, tb] that starts `after` waiting on axis `i`.
    fn trigger_time(&self, i: usize, after: After, t: f64, tb: f64) -> Option<f64> {
        self.triggers
            .iter()
            .find(|&&(u, k)| k.starts(i, after) && t <= u && u <= tb)
            .map(|&(u, _)| u)
    }

    /// Start the heads of both layers that can start at `t`; those that complete at once
    /// (GEAR AT without IN, MOVE IN 0, FOR IN 0) let the next one start at the same instant.
    fn start_heads(&mut self, i: usize, t: f64, events: &mut Vec<DspEvent>) {
        let (x, vx) = match self.axes[i].pacer {
            Some(p) => (self.pos_at(p, t), self.vel_at(p, t)),
            None => (0.0, 0.0),
        };
        let number = self.axes[i].number;
        let has_pacer = self.axes[i].pacer.is_some();
        for _ in 0..LOOP_CAP {
            let base = &self.axes[i].base;
            let can_start = base.running.is_none()
                && match base.queue.front() {
                    Some(BaseSeg::Gear { after: Some(k), .. }) => {
                        self.trigger_time(i, *k, t, t).is_some()
                    }
                    Some(_) => true,
                    None => false,
                };
            if can_start {
                if let Some(BaseSeg::Gear {
                    after: Some(After::Sensor(which)),
                    ..
                }) = self.axes[i].base.queue.front().copied()
                {
                    // A sensor edge starts one segment: the next one waits for a later edge.
                    let edge = Trigger::Sensor(i, which);
                    if let Some(at) = self.triggers.iter().position(|&(u, k)| u == t && k == edge) {
                        self.triggers.remove(at);
                    }
                    events.push(DspEvent::StartedOnEdge {
                        axis: number,
                        which,
                        time: t,
                        pacer: x,
                        position: self.pos_at(i, t),
                    });
                }
                events.push(DspEvent::SegmentStarted {
                    axis: number,
                    layer: Layer::Base,
                    time: t,
                });
                if self.axes[i].base.start_head(t, x, vx) {
                    events.push(DspEvent::SegmentDone {
                        axis: number,
                        layer: Layer::Base,
                        time: t,
                    });
                    continue;
                }
            }
            let sup = &mut self.axes[i].sup;
            if has_pacer && sup.running.is_none() && !sup.queue.is_empty() {
                events.push(DspEvent::SegmentStarted {
                    axis: number,
                    layer: Layer::Superimposed,
                    time: t,
                });
                if let Some(dist) = sup.start_head(t, x) {
                    events.push(DspEvent::Stepped {
                        axis: number,
                        dist,
                        time: t,
                    });
                    events.push(DspEvent::SegmentDone {
                        axis: number,
                        layer: Layer::Superimposed,
                        time: t,
                    });
                    continue;
                }
            }
            return;
        }
    }

    /// Commanded position of axis `i` at `t` (inside the last interval).
    pub(super) fn pos_at(&self, i: usize, t: f64) -> f64 {
        let a = &self.axes[i];
        let base = a.base.piece_at(t);
        let sup = a.sup.piece_at(t);
        let x = match a.pacer {
            Some(p) if base.geared() || sup.moving.is_some() => self.pos_at(p, t),
            _ => 0.0,
        };
        base.position(t, x) + sup.offset(x)
    }

    /// Commanded velocity of axis `i` at `t`.
    pub(super) fn vel_at(&self, i: usize, t: f64) -> f64 {
        let a = &self.axes[i];
        let base = a.base.piece_at(t);
        let sup = a.sup.piece_at(t);
        let (x, vx) = match a.pacer {
            Some(p) if base.geared() || sup.moving.is_some() => {
                (self.pos_at(p, t), self.vel_at(p, t))
            }
            _ => (0.0, 0.0),
        };
        base.velocity(t, x, vx) + sup.velocity(x, vx)
    }
}
