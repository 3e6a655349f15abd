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
    /// Record a program's write of a member even when it leaves the value as it was.
    writes: bool,
    /// The most bytes the trace may hold (`None`: no limit).
    limit: Option<u64>,
    /// Bytes written so far.
    written: u64,
    /// An event was left out because the trace would have passed its limit.
    full: bool,
}

/// The trace's default size limit, bytes (`--trace-limit`).
pub const DEFAULT_LIMIT: u64 = 1 << 30;

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
            writes: false,
            limit: None,
            written: 0,
            full: false,
        }
    }

    /// Record every program write of a member, also those that leave its value as it was
    /// (`--trace-writes`; by default only changes are recorded).
    pub fn record_writes(&mut self, on: bool) {
        self.writes = on;
    }

    /// Whether every program write is recorded.
    pub fn writes(&self) -> bool {
        self.writes
    }

    /// Hold the trace to `limit` bytes (`None`: no limit). The event that would pass it is not
    /// written and [`Trace::full`] says so; the run's `end` event is always written, whole.
    pub fn limit(&mut self, limit: Option<u64>) {
        self.limit = limit;
    }

    /// An event was left out at the size limit: the run must end.
    pub fn full(&self) -> bool {
        self.full
    }

    /// A write to the trace failed (disk full, a closed pipe): the run must end at once, for
    /// nothing after it can be recorded. [`Trace::finish`] returns the error.
    pub fn failed(&self) -> bool {
        self.failed.is_some()
    }

    /// The size limit, if any.
    pub fn size_limit(&self) -> Option<u64> {
        self.limit
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
        let closing = matches!(event, Event::End { .. });
        // Past the size limit nothing more is recorded, counted or watched but the `end`.
        if self.full && !closing {
            return;
        }
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
        let size = line.len() as u64;
        if self
            .limit
            .is_some_and(|limit| !closing && self.written + size > limit)
        {
            self.full = true;
            if let Some(n) = self.counts.get_mut(event.kind().as_str()) {
                *n -= 1;
            }
            return;
        }
        self.written += size;
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
