//! The Capture object: the first rising edge of CaptureActivate while enabled latches the time
//! and positions at the exact edge instant.

use crate::registry::catalog::CAPTURE_TYPE;
use crate::registry::Registry;
use crate::trace::{Event, Trace};

crate::bind_slots! {
    /// Slots of one capture's members.
    struct Slots for CAPTURE_TYPE {
        enable: "CaptureEnable",
        activate: "CaptureActivate",
        triggered: "CaptureTriggered",
        time: "CapturedTime",
        command: "CapturedPosnCommand",
        feedback: "CapturedPosnFeedback",
        master: "CapturedMasterPosition",
    }
}

/// One capture.
#[derive(Debug, Clone)]
pub struct Capture {
    index: u32,
    s: Slots,
}

/// Positions of the axes at an instant (the motion kernel supplies them; zero without axes).
#[derive(Debug, Clone, Copy, Default)]
pub struct Positions {
    /// Master position.
    pub master: f64,
    /// Motor command position.
    pub command: f64,
    /// Motor feedback position.
    pub feedback: f64,
}

impl Capture {
    /// Capture `index`.
    pub fn new(registry: &Registry, index: u32) -> Capture {
        Capture {
            index,
            s: Slots::of(registry, index),
        }
    }

    /// The latched time (seconds) and master position, as programs may have rewritten them.
    pub fn latched(&self, v: &[f64]) -> (f64, f64) {
        (v[self.s.time as usize], v[self.s.master as usize])
    }

    /// CaptureEnable written; turning it off resets the capture.
    pub fn set_enable(&self, on: bool, v: &mut [f64]) {
        v[self.s.enable as usize] = f64::from(on);
        if !on {
            v[self.s.triggered as usize] = 0.0;
        }
    }

    /// CaptureClear / CaptureReset.
    pub fn clear(&self, v: &mut [f64]) {
        v[self.s.triggered as usize] = 0.0;
    }

    /// CaptureActivate driven to `on` at `time` seconds, with the positions at that instant.
    pub fn activate(
        &self,
        on: bool,
        time: f64,
        at: Positions,
        v: &mut [f64],
        trace: &mut Trace,
        tick: u64,
    ) {
        let rising = on && v[self.s.activate as usize] == 0.0;
        v[self.s.activate as usize] = f64::from(on);
        if rising && v[self.s.enable as usize] != 0.0 && v[self.s.triggered as usize] == 0.0 {
            let t = time;
            v[self.s.time as usize] = t;
            v[self.s.master as usize] = at.master;
            v[self.s.command as usize] = at.command;
            v[self.s.feedback as usize] = at.feedback;
            v[self.s.triggered as usize] = 1.0;
            trace.emit(
                tick,
                &Event::Capture {
                    object: format!("Capture.{}", self.index).into(),
                    time: t,
                    master: at.master,
                    command: at.command,
                    feedback: at.feedback,
                },
            );
        }
    }
}
