//! The Capture object: the first rising edge of CaptureActivate while enabled latches the time
//! and positions at the exact edge instant.

use crate::registry::{Kind, Registry, SlotId};
use crate::trace::{Event, Trace};

/// One capture.
#[derive(Debug, Clone)]
pub struct Capture {
    index: u32,
    enable: SlotId,
    activate: SlotId,
    triggered: SlotId,
    time: SlotId,
    command: SlotId,
    feedback: SlotId,
    master: SlotId,
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
        let slot = |m: &str| super::slot(registry, Kind::Capture, index, m);
        Capture {
            index,
            enable: slot("CaptureEnable"),
            activate: slot("CaptureActivate"),
            triggered: slot("CaptureTriggered"),
            time: slot("CapturedTime"),
            command: slot("CapturedPosnCommand"),
            feedback: slot("CapturedPosnFeedback"),
            master: slot("CapturedMasterPosition"),
        }
    }

    /// The latched time (seconds) and master position, as programs may have rewritten them.
    pub fn latched(&self, v: &[f64]) -> (f64, f64) {
        (v[self.time as usize], v[self.master as usize])
    }

    /// CaptureEnable written; turning it off resets the capture.
    pub fn set_enable(&self, on: bool, v: &mut [f64]) {
        v[self.enable as usize] = f64::from(on);
        if !on {
            v[self.triggered as usize] = 0.0;
        }
    }

    /// CaptureClear / CaptureReset.
    pub fn clear(&self, v: &mut [f64]) {
        v[self.triggered as usize] = 0.0;
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
        let rising = on && v[self.activate as usize] == 0.0;
        v[self.activate as usize] = f64::from(on);
        if rising && v[self.enable as usize] != 0.0 && v[self.triggered as usize] == 0.0 {
            let t = time;
            v[self.time as usize] = t;
            v[self.master as usize] = at.master;
            v[self.command as usize] = at.command;
            v[self.feedback as usize] = at.feedback;
            v[self.triggered as usize] = 1.0;
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
