//! The simulated world: digital inputs driven in time by the scenario.
//!
//! Inputs are sampled once per update at the update's end time. A pulse that starts and ends
//! inside one update (or a glitch in a steady level) is still seen, for that one update, as the
//! opposite level: pulse catching, so no press is lost however short.

use crate::registry::SlotId;

/// A level change of one input at an exact time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Edge {
    /// When, in nanoseconds from the start of the run.
    pub time_ns: u64,
    /// Which input.
    pub slot: SlotId,
    /// The new level.
    pub on: bool,
}

/// An input's activity during one update.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputActivity {
    /// The input.
    pub slot: SlotId,
    /// The level the update samples.
    pub sampled: bool,
    /// Time of the first rising edge inside the update, if any.
    pub first_rise_ns: Option<u64>,
}

/// The scenario's inputs, replayed in time order.
#[derive(Debug, Clone, Default)]
pub struct World {
    edges: Vec<Edge>,
    next: usize,
    levels: std::collections::BTreeMap<SlotId, bool>,
}

impl World {
    /// A world from edges in any order (sorted here; same-time edges keep their given order).
    pub fn new(mut edges: Vec<Edge>) -> World {
        edges.sort_by_key(|e| e.time_ns);
        World {
            edges,
            next: 0,
            levels: Default::default(),
        }
    }

    /// Time of the last edge, if any.
    pub fn last_edge_ns(&self) -> Option<u64> {
        self.edges.last().map(|e| e.time_ns)
    }

    /// Apply the edges up to and including `until_ns`; report each touched input.
    pub fn advance(&mut self, until_ns: u64, v: &mut [f64], out: &mut Vec<InputActivity>) {
        out.clear();
        while let Some(e) = self.edges.get(self.next).copied() {
            if e.time_ns > until_ns {
                break;
            }
            self.next += 1;
            let before = self
                .levels
                .get(&e.slot)
                .copied()
                .unwrap_or(v[e.slot as usize] != 0.0);
            let entry = match out.iter().position(|a| a.slot == e.slot) {
                Some(i) => i,
                None => {
                    out.push(InputActivity {
                        slot: e.slot,
                        sampled: before,
                        first_rise_ns: None,
                    });
                    out.len() - 1
                }
            };
            if e.on && !before && out[entry].first_rise_ns.is_none() {
                out[entry].first_rise_ns = Some(e.time_ns);
            }
            self.levels.insert(e.slot, e.on);
        }
        for a in out.iter_mut() {
            let start = v[a.slot as usize] != 0.0;
            let end = self.levels.get(&a.slot).copied().unwrap_or(start);
            // Level changed: sample the new level. Came back to where it was: the pulse is caught.
            a.sampled = if end != start { end } else { !start };
            v[a.slot as usize] = f64::from(a.sampled);
        }
        // An input showing a caught pulse returns to its level at the next update.
        for (slot, level) in &self.levels {
            if !out.iter().any(|a| a.slot == *slot) {
                v[*slot as usize] = f64::from(*level);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_pulse_is_seen_for_one_update() {
        let mut w = World::new(vec![
            Edge {
                time_ns: 100,
                slot: 0,
                on: true,
            },
            Edge {
                time_ns: 200,
                slot: 0,
                on: false,
            },
        ]);
        let mut v = vec![0.0];
        let mut act = Vec::new();
        w.advance(1000, &mut v, &mut act);
        assert_eq!(v[0], 1.0);
        assert_eq!(act[0].first_rise_ns, Some(100));
        w.advance(2000, &mut v, &mut act);
        assert_eq!(v[0], 0.0);
    }

    #[test]
    fn level_change_is_sampled() {
        let mut w = World::new(vec![Edge {
            time_ns: 500,
            slot: 0,
            on: true,
        }]);
        let mut v = vec![0.0];
        let mut act = Vec::new();
        w.advance(400, &mut v, &mut act);
        assert_eq!(v[0], 0.0);
        w.advance(1000, &mut v, &mut act);
        assert_eq!(v[0], 1.0);
        w.advance(2000, &mut v, &mut act);
        assert_eq!(v[0], 1.0);
    }
}
