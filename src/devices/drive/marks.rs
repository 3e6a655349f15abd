//! Sensors tied to the servo axis (`[[axis_marks]]` of the scenario): the axis crossing a mark
//! edge inside an update makes an input edge at the time interpolated between the update's two
//! command positions.

use crate::registry::SlotId;
use crate::world::Edge;

/// Sensor marks tied to the servo axis: the sensor is on while the axis is within
/// `[position, position + width)` of a mark at `first + k·pitch`, k < count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisMarks {
    /// The sensor input.
    pub slot: SlotId,
    /// First mark, axis units.
    pub first: f64,
    /// Distance between marks (0 for a single mark).
    pub pitch: f64,
    /// Number of marks.
    pub count: u32,
    /// Width of each mark, axis units.
    pub width: f64,
}

impl AxisMarks {
    /// Edges (with the axis position at each) when the axis moves from `a` (at `ta`) to `b`
    /// (at `tb`), times interpolated.
    pub fn crossings(&self, a: f64, b: f64, ta: f64, tb: f64, out: &mut Vec<(Edge, f64)>) {
        if a == b || self.count == 0 {
            return;
        }
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        let time = |p: f64| ta + (p - a) / (b - a) * (tb - ta);
        // Candidate marks whose window may touch [lo, hi].
        let (k0, k1) = if self.pitch > 0.0 {
            let k0 = ((lo - self.width - self.first) / self.pitch)
                .floor()
                .max(0.0);
            let k1 = ((hi - self.first) / self.pitch)
                .ceil()
                .min(f64::from(self.count - 1));
            (k0 as u32, k1.max(0.0) as u32)
        } else {
            (0, 0)
        };
        let mut local = Vec::new();
        for k in k0..=k1.min(self.count - 1) {
            let p = self.first + f64::from(k) * self.pitch;
            let q = p + self.width;
            // Moving plus: on at p, off at q. Moving minus: on at q, off at p.
            for (edge, on_when_plus) in [(p, true), (q, false)] {
                let crossed = if a < b {
                    a < edge && edge <= b
                } else {
                    b <= edge && edge < a
                };
                if crossed {
                    local.push((
                        Edge {
                            at: time(edge),
                            slot: self.slot,
                            on: on_when_plus == (a < b),
                        },
                        edge,
                    ));
                }
            }
        }
        local.sort_by(|x, y| x.0.at.total_cmp(&y.0.at));
        out.extend(local);
    }
}
