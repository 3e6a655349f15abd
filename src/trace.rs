//! The JSON-lines trace: one object per line with `t`, `tick`, `kind` and fields by kind.

use serde_json::Value;
use std::io::Write;

/// Where trace lines go, and counts of what was written.
pub struct Trace {
    out: Option<Box<dyn Write>>,
    /// Update period in nanoseconds (to turn ticks into seconds).
    tick_ns: u64,
    /// Events written, by kind, in order of first appearance.
    pub counts: indexmap::IndexMap<&'static str, u64>,
    line: String,
    failed: Option<std::io::Error>,
}

impl Trace {
    /// A trace writing to `out`, or counting only when `None`.
    pub fn new(out: Option<Box<dyn Write>>, tick_ns: u64) -> Trace {
        Trace {
            out,
            tick_ns,
            counts: indexmap::IndexMap::new(),
            line: String::new(),
            failed: None,
        }
    }

    /// True when lines are written (callers skip building events otherwise).
    pub fn enabled(&self) -> bool {
        self.out.is_some()
    }

    /// Seconds at the start of `tick`.
    pub fn seconds(&self, tick: u64) -> f64 {
        (tick as f64 * self.tick_ns as f64) / 1e9
    }

    /// Count an event without building it (when no trace is written, for the summary).
    pub fn count(&mut self, kind: &'static str) {
        *self.counts.entry(kind).or_insert(0) += 1;
    }

    /// Write one event.
    pub fn event(&mut self, tick: u64, kind: &'static str, fields: &[(&str, Value)]) {
        *self.counts.entry(kind).or_insert(0) += 1;
        let Some(out) = self.out.as_mut() else { return };
        if self.failed.is_some() {
            return;
        }
        let line = &mut self.line;
        line.clear();
        line.push_str("{\"t\":");
        line.push_str(&Value::from((tick as f64 * self.tick_ns as f64) / 1e9).to_string());
        line.push_str(",\"tick\":");
        line.push_str(&tick.to_string());
        line.push_str(",\"kind\":\"");
        line.push_str(kind);
        line.push('"');
        for (k, v) in fields {
            line.push_str(",\"");
            line.push_str(k);
            line.push_str("\":");
            line.push_str(&v.to_string());
        }
        line.push_str("}\n");
        if let Err(e) = out.write_all(line.as_bytes()) {
            self.failed = Some(e);
        }
    }

    /// A warning or error of the machine itself, not of a program line (`task` and `line` null).
    pub fn machine_message(&mut self, tick: u64, kind: &'static str, message: String) {
        self.event(
            tick,
            kind,
            &[
                ("task", Value::Null),
                ("line", Value::Null),
                ("message", message.into()),
            ],
        );
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

/// A member value as JSON: bits as booleans, integers as integers, others as numbers.
pub fn value_json(ty: crate::registry::ValueType, v: f64) -> Value {
    use crate::registry::ValueType;
    match ty {
        ValueType::Bit => Value::Bool(v != 0.0),
        ValueType::Integer | ValueType::Fixed(0) => Value::from(v as i64),
        _ => number(v),
    }
}

/// A float as JSON (non-finite values, which stores never keep, become null).
pub fn number(v: f64) -> Value {
    serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number)
}
