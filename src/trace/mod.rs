//! The trace: every change and event of a run, as typed [`Event`]s written one JSON object per
//! line (`{"t":…,"tick":…,"kind":"…",fields…}`), counted by kind for the run's summary, and
//! handed to an observer (a live plot) when one is attached.

pub mod event;

pub use event::{Event, EventKind, Line, MotionPhase, Origin, ProgramEvent, Text, Units, Value};

use std::io::Write;

/// Something that watches the trace's events as they are written (a live plot).
pub type Observer = Box<dyn FnMut(f64, &Event<'_>)>;

/// Where trace lines go, and counts of what was written.
pub struct Trace {
    out: Option<Box<dyn Write>>,
    observer: Option<Observer>,
    /// Update period in nanoseconds (to turn ticks into seconds).
    tick_ns: u64,
    /// Events written, by kind, in order of first appearance.
    pub counts: indexmap::IndexMap<&'static str, u64>,
    line: Vec<u8>,
    body: Vec<u8>,
    failed: Option<std::io::Error>,
}

impl Trace {
    /// A trace writing to `out`, or counting only when `None`.
    pub fn new(out: Option<Box<dyn Write>>, tick_ns: u64) -> Trace {
        Trace {
            out,
            observer: None,
            tick_ns,
            counts: indexmap::IndexMap::new(),
            line: Vec::new(),
            body: Vec::new(),
            failed: None,
        }
    }

    /// Hand every event to `observer` too, with its time.
    pub fn observe(&mut self, observer: Observer) {
        self.observer = Some(observer);
    }

    /// True when events are written or watched (callers skip building events otherwise).
    pub fn enabled(&self) -> bool {
        self.out.is_some() || self.observer.is_some()
    }

    /// Seconds at the start of `tick`.
    pub fn seconds(&self, tick: u64) -> f64 {
        (tick as f64 * self.tick_ns as f64) / 1e9
    }

    /// Count an event without building it (when no trace is written, for the summary).
    pub fn count(&mut self, kind: EventKind) {
        *self.counts.entry(kind.as_str()).or_insert(0) += 1;
    }

    /// Record one event at update `tick`.
    pub fn emit(&mut self, tick: u64, event: &Event<'_>) {
        self.count(event.kind());
        let t = self.seconds(tick);
        if let Some(observe) = self.observer.as_mut() {
            observe(t, event);
        }
        let Some(out) = self.out.as_mut() else { return };
        if self.failed.is_some() {
            return;
        }
        // `t` and `tick` lead, then the event with its `kind` first: the event's own object
        // is spliced in after its opening brace.
        self.body.clear();
        if let Err(e) = serde_json::to_writer(&mut self.body, event) {
            self.failed = Some(std::io::Error::other(e));
            return;
        }
        let line = &mut self.line;
        line.clear();
        line.extend_from_slice(b"{\"t\":");
        let _ = serde_json::to_writer(&mut *line, &t);
        line.extend_from_slice(b",\"tick\":");
        line.extend_from_slice(tick.to_string().as_bytes());
        line.push(b',');
        line.extend_from_slice(self.body.get(1..).unwrap_or_default());
        line.push(b'\n');
        if let Err(e) = out.write_all(line) {
            self.failed = Some(e);
        }
    }

    /// A warning of the machine itself, not of a program line (`task` and `line` null).
    pub fn machine_warning(&mut self, tick: u64, message: impl Into<Text<'static>>) {
        self.emit(tick, &Event::machine_warning(message));
    }

    /// An error of the machine itself, not of a program line (`task` and `line` null).
    pub fn machine_error(&mut self, tick: u64, message: impl Into<Text<'static>>) {
        self.emit(tick, &Event::machine_error(message));
    }

    /// Flush; report the first write error, if any.
    pub fn finish(&mut self) -> std::io::Result<()> {
        if let Some(e) = self.failed.take() {
            return Err(e);
        }
        match self.out.as_mut() {
            Some(o) => o.flush(),
            None => Ok(()),
        }
    }
}
