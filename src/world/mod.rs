//! The simulated world: digital inputs driven in time by the scenario.
//!
//! Inputs are sampled once per update at the update's end time. A pulse that starts and ends
//! inside one update (or a glitch in a steady level) is still seen, for that one update, as the
//! opposite level: pulse catching, so no press is lost however short.

pub mod belt;
pub mod master;
pub mod products;
pub mod workpieces;

use crate::registry::SlotId;
use master::MasterProfile;

/// A level change of one input at an exact time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// When, in seconds from the start of the run (exact: not rounded to the update).
    pub at: f64,
    /// Which input.
    pub slot: SlotId,
    /// The new level.
    pub on: bool,
}

/// An input's activity during one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputActivity {
    /// The input.
    pub slot: SlotId,
    /// The level the update samples.
    pub sampled: bool,
    /// Time of the first rising edge inside the update, if any (seconds, exact).
    pub first_rise: Option<f64>,
    /// Time of the first falling edge inside the update, if any (seconds, exact).
    pub first_fall: Option<f64>,
    level_before: bool,
}

/// The scenario's world: the master axis and the inputs, replayed in time order.
#[derive(Debug, Clone, Default)]
pub struct World {
    edges: Vec<Edge>,
    next: usize,
    levels: std::collections::BTreeMap<SlotId, bool>,
    /// The master axis.
    pub master: MasterProfile,
    /// Edges made by the servo axis during the last update, applied first at the next advance.
    pending: Vec<Edge>,
    /// Inputs showing a caught pulse (sampled opposite to their level) this update.
    caught: Vec<SlotId>,
}

impl World {
    /// A world from edges in any order (sorted by time here; same-time edges keep their order).
    pub fn new(mut edges: Vec<Edge>, master: MasterProfile) -> World {
        edges.sort_by(|a, b| a.at.total_cmp(&b.at));
        World {
            edges,
            next: 0,
            levels: Default::default(),
            master,
            pending: Vec::new(),
            caught: Vec::new(),
        }
    }

    /// Add edges made during the last update (sensors on the servo axis); they are applied at
    /// the next advance, before the scenario's own edges of that update.
    pub fn inject(&mut self, mut edges: Vec<Edge>) {
        edges.sort_by(|a, b| a.at.total_cmp(&b.at));
        self.pending.extend(edges);
    }

    /// Drop the scenario's edges on `slots` (inputs a real device drives); returns how many
    /// were dropped. Called before the run starts.
    pub fn drop_inputs(&mut self, slots: &[SlotId]) -> usize {
        let before = self.edges.len();
        self.edges.retain(|e| !slots.contains(&e.slot));
        self.next = self.next.min(self.edges.len());
        before - self.edges.len()
    }

    /// Time of the last edge, if any (seconds).
    pub fn last_edge(&self) -> Option<f64> {
        self.edges.last().map(|e| e.at)
    }

    /// Apply the edges up to and including `until` seconds; report each touched input.
    pub fn advance(&mut self, until: f64, v: &mut [f64], out: &mut Vec<InputActivity>) {
        out.clear();
        let pending = std::mem::take(&mut self.pending);
        let mut pending = pending.into_iter();
        loop {
            // The axis's edges (from the last update) come before the scenario's of this one.
            let e = match pending.next() {
                Some(e) => e,
                None => match self.edges.get(self.next).copied() {
                    Some(e) if e.at <= until => {
                        self.next += 1;
                        e
                    }
                    _ => break,
                },
            };
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
                        first_rise: None,
                        first_fall: None,
                        level_before: before,
                    });
                    out.len() - 1
                }
            };
            if e.on && !before && out[entry].first_rise.is_none() {
                out[entry].first_rise = Some(e.at);
            }
            if !e.on && before && out[entry].first_fall.is_none() {
                out[entry].first_fall = Some(e.at);
            }
            self.levels.insert(e.slot, e.on);
        }
        for a in out.iter_mut() {
            let end = self.levels.get(&a.slot).copied().unwrap_or(a.level_before);
            // Level changed: sample the new level. Came back to where it was: the pulse is caught.
            a.sampled = if end != a.level_before {
                end
            } else {
                !a.level_before
            };
            v[a.slot as usize] = f64::from(a.sampled);
        }
        // An input that showed a caught pulse returns to its level at the next update.
        for slot in std::mem::take(&mut self.caught) {
            if !out.iter().any(|a| a.slot == slot) {
                v[slot as usize] = f64::from(self.levels.get(&slot).copied().unwrap_or(false));
            }
        }
        self.caught.extend(
            out.iter()
                .filter(|a| self.levels.get(&a.slot) != Some(&a.sampled))
                .map(|a| a.slot),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge(at: f64, on: bool) -> Edge {
        Edge { at, slot: 0, on }
    }

    #[test]
    fn short_pulse_is_seen_for_one_update() {
        let mut w = World::new(
            vec![edge(100e-9, true), edge(200e-9, false)],
            MasterProfile::default(),
        );
        let mut v = vec![0.0];
        let mut act = Vec::new();
        w.advance(1e-6, &mut v, &mut act);
        assert_eq!(v[0], 1.0);
        assert_eq!(act[0].first_rise, Some(100e-9));
        w.advance(2e-6, &mut v, &mut act);
        assert_eq!(v[0], 0.0);
    }

    #[test]
    fn short_pulses_in_consecutive_updates_are_each_seen() {
        let edges = vec![
            edge(0.0001, true),
            edge(0.0002, false),
            edge(0.0011, true),
            edge(0.0012, false),
        ];
        let mut w = World::new(edges, MasterProfile::default());
        let mut v = vec![0.0];
        let mut act = Vec::new();
        w.advance(0.001, &mut v, &mut act);
        assert_eq!(v[0], 1.0);
        w.advance(0.002, &mut v, &mut act);
        assert_eq!(v[0], 1.0, "the second pulse is caught too");
        w.advance(0.003, &mut v, &mut act);
        assert_eq!(v[0], 0.0);
    }

    #[test]
    fn level_change_is_sampled() {
        let mut w = World::new(vec![edge(500e-9, true)], MasterProfile::default());
        let mut v = vec![0.0];
        let mut act = Vec::new();
        w.advance(400e-9, &mut v, &mut act);
        assert_eq!(v[0], 0.0);
        w.advance(1e-6, &mut v, &mut act);
        assert_eq!(v[0], 1.0);
        w.advance(2e-6, &mut v, &mut act);
        assert_eq!(v[0], 1.0);
    }
}
