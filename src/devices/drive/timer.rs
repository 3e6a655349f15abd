//! Realtime timers: Initiate starts counting, Output turns on at the preset.

use crate::registry::catalog::TIMER_TYPE;
use crate::registry::Registry;

crate::bind_slots! {
    /// Slots of one timer's members.
    struct Slots for TIMER_TYPE {
        preset: "Preset",
        synchronized: "Synchronized",
        elapsed: "Elapsed",
        active: "Active",
        output: "Output",
    }
}

/// One timer.
#[derive(Debug, Clone)]
pub struct Timer {
    started_ns: Option<u64>,
    started_master: f64,
    synchronized_run: bool,
    s: Slots,
}

impl Timer {
    /// Timer `index`.
    pub fn new(registry: &Registry, index: u32) -> Timer {
        Timer {
            started_ns: None,
            started_master: 0.0,
            synchronized_run: false,
            s: Slots::of(registry, index),
        }
    }

    /// Start from zero at `now_ns` (and master position `master`).
    pub fn initiate(&mut self, now_ns: u64, master: f64, v: &mut [f64]) {
        self.started_ns = Some(now_ns);
        self.started_master = master;
        self.synchronized_run = v[self.s.synchronized as usize] != 0.0;
        v[self.s.active as usize] = 1.0;
        v[self.s.output as usize] = 0.0;
        v[self.s.elapsed as usize] = 0.0;
    }

    /// Stop and clear the output.
    pub fn stop(&mut self, v: &mut [f64]) {
        self.started_ns = None;
        v[self.s.active as usize] = 0.0;
        v[self.s.output as usize] = 0.0;
    }

    /// Whether it is timing (initiated and not yet at its preset or stopped).
    pub fn running(&self) -> bool {
        self.started_ns.is_some()
    }

    /// Advance to `now_ns` and master position `master`.
    pub fn update(&mut self, now_ns: u64, master: f64, v: &mut [f64]) {
        let Some(start) = self.started_ns else { return };
        let elapsed = if self.synchronized_run {
            master - self.started_master
        } else {
            now_ns.saturating_sub(start) as f64 / 1e9
        };
        v[self.s.elapsed as usize] = crate::registry::round_to(elapsed, 6);
        if elapsed + 1e-12 >= v[self.s.preset as usize] {
            v[self.s.output as usize] = 1.0;
            v[self.s.active as usize] = 0.0;
            self.started_ns = None;
        }
    }
}
