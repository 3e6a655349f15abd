//! Realtime timers: Initiate starts counting, Output turns on at the preset.

use crate::registry::{Kind, Registry, SlotId};

/// One timer.
#[derive(Debug, Clone)]
pub struct Timer {
    started_ns: Option<u64>,
    started_master: f64,
    synchronized_run: bool,
    preset: SlotId,
    synchronized: SlotId,
    elapsed: SlotId,
    active: SlotId,
    output: SlotId,
}

impl Timer {
    /// Timer `index`.
    pub fn new(registry: &Registry, index: u32) -> Timer {
        let slot = |m: &str| super::slot(registry, Kind::Timer, index, m);
        Timer {
            started_ns: None,
            started_master: 0.0,
            synchronized_run: false,
            preset: slot("Preset"),
            synchronized: slot("Synchronized"),
            elapsed: slot("Elapsed"),
            active: slot("Active"),
            output: slot("Output"),
        }
    }

    /// Start from zero at `now_ns` (and master position `master`).
    pub fn initiate(&mut self, now_ns: u64, master: f64, v: &mut [f64]) {
        self.started_ns = Some(now_ns);
        self.started_master = master;
        self.synchronized_run = v[self.synchronized as usize] != 0.0;
        v[self.active as usize] = 1.0;
        v[self.output as usize] = 0.0;
        v[self.elapsed as usize] = 0.0;
    }

    /// Stop and clear the output.
    pub fn stop(&mut self, v: &mut [f64]) {
        self.started_ns = None;
        v[self.active as usize] = 0.0;
        v[self.output as usize] = 0.0;
    }

    /// Advance to `now_ns` and master position `master`.
    pub fn update(&mut self, now_ns: u64, master: f64, v: &mut [f64]) {
        let Some(start) = self.started_ns else { return };
        let elapsed = if self.synchronized_run {
            master - self.started_master
        } else {
            now_ns.saturating_sub(start) as f64 / 1e9
        };
        v[self.elapsed as usize] = crate::registry::round_to(elapsed, 6);
        if elapsed + 1e-12 >= v[self.preset as usize] {
            v[self.output as usize] = 1.0;
            v[self.active as usize] = 0.0;
            self.started_ns = None;
        }
    }
}
