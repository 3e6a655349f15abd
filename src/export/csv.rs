//! Sampled numeric signals as CSV: a header `t,tick,<names>`, then one row per update, or per
//! sample period (the first update at or after each multiple of it), written as the run goes.

use super::signals::{write_real, write_value, Signal};
use super::ExportError;
use crate::vm::Machine;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A CSV being written.
pub struct CsvWriter {
    path: PathBuf,
    out: BufWriter<File>,
    signals: Vec<Signal>,
    tick_ns: u64,
    /// Sample period, ns (`None`: every update).
    period_ns: Option<u64>,
    /// Time of the next row, ns.
    next_ns: u64,
    line: String,
    failed: Option<std::io::Error>,
}

impl CsvWriter {
    /// Create the file and write its header.
    pub fn create(
        path: &Path,
        signals: Vec<Signal>,
        tick_ns: u64,
        period_ns: Option<u64>,
    ) -> Result<CsvWriter, ExportError> {
        let io = |source| ExportError::Io {
            path: path.to_path_buf(),
            source,
        };
        let file = File::create(path).map_err(io)?;
        let mut out = BufWriter::with_capacity(1 << 16, file);
        let mut header = String::from("t,tick");
        for s in &signals {
            header.push(',');
            header.push_str(&field(&s.name));
        }
        header.push('\n');
        out.write_all(header.as_bytes()).map_err(io)?;
        Ok(CsvWriter {
            path: path.to_path_buf(),
            out,
            signals,
            tick_ns,
            period_ns: period_ns.filter(|&p| p > 0),
            next_ns: 0,
            line: String::new(),
            failed: None,
        })
    }

    /// Write a row for the update just computed, if one is due.
    pub fn observe(&mut self, m: &Machine, tick: u64) {
        if self.failed.is_some() {
            return;
        }
        let t_ns = tick.saturating_mul(self.tick_ns);
        if let Some(p) = self.period_ns {
            if t_ns < self.next_ns {
                return;
            }
            self.next_ns = (t_ns / p + 1) * p;
        }
        use std::fmt::Write as _;
        let v = m.values();
        self.line.clear();
        // Time as the trace writes it (update × period), so rows and trace lines match.
        write_real(&mut self.line, (tick as f64 * self.tick_ns as f64) / 1e9);
        let _ = write!(self.line, ",{tick}");
        for s in &self.signals {
            self.line.push(',');
            if s.text {
                let i = v[s.slot as usize];
                let text = m.strings().get(i as usize).map_or("", String::as_str);
                self.line.push_str(&field(text));
            } else {
                write_value(&mut self.line, s.kind, v[s.slot as usize]);
            }
        }
        self.line.push('\n');
        if let Err(e) = self.out.write_all(self.line.as_bytes()) {
            self.failed = Some(e);
        }
    }

    /// Flush; report the first write error.
    pub fn finish(mut self) -> Result<PathBuf, ExportError> {
        let r = match self.failed.take() {
            Some(e) => Err(e),
            None => self.out.flush(),
        };
        r.map_err(|source| ExportError::Io {
            path: self.path.clone(),
            source,
        })?;
        Ok(self.path)
    }
}

/// A field, quoted when it holds a comma, a quote or a line break (RFC 4180).
fn field(name: &str) -> String {
    if name.contains([',', '"', '\n']) {
        format!("\"{}\"", name.replace('"', "\"\""))
    } else {
        name.to_string()
    }
}
