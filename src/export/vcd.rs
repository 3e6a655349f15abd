//! The Value Change Dump: every digital signal, every numeric member that changed and every task's
//! state, update by update, for GTKWave, Surfer and any VCD reader.
//!
//! A VCD declares its signals before the first change, and only the end of the run tells which
//! numeric members ever changed. So the changes are streamed to a file beside the target while
//! the machine runs, and at the end the header (declarations and the values at the first update)
//! is written to the target followed by that file, copied in blocks. Memory stays what it was at
//! the first update however long the run.

use super::signals::{is_derived_copy, vcd_path, vcd_word, write_real, SignalKind};
use super::ExportError;
use crate::registry::{Access, Registry};
use crate::vm::task::TaskState;
use crate::vm::{Machine, MachineImage};
use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// A VCD being written.
pub struct VcdWriter {
    path: PathBuf,
    body_path: PathBuf,
    target: File,
    body: BufWriter<File>,
    machine: String,
    tick_ns: u64,
    /// `$timescale` (e.g. `1 ms`) and how many of its units one update lasts.
    timescale: (&'static str, u64),
    /// Per registry slot: the member is written at all (derived copies are not).
    include: Vec<bool>,
    /// Per slot: how it is written, and whether it is declared even if it never changes.
    kinds: Vec<SignalKind>,
    always: Vec<bool>,
    /// Values before the run, at the first update, and as last written.
    before: Vec<f64>,
    first: Vec<f64>,
    last: Vec<f64>,
    /// Per slot: its value ever differed from the one before the run.
    changed: Vec<bool>,
    tasks_first: Vec<TaskState>,
    tasks_last: Vec<TaskState>,
    /// The first update observed, and the last, if any.
    first_tick: Option<u64>,
    last_tick: u64,
    /// The time stamp last written to the body.
    last_stamp: Option<u64>,
    line: String,
    failed: Option<std::io::Error>,
}

/// Timescales a VCD may declare: 1, 10 or 100 of a unit, largest first, with their length in ns.
const TIMESCALES: &[(&str, u64)] = &[
    ("100 s", 100_000_000_000),
    ("10 s", 10_000_000_000),
    ("1 s", 1_000_000_000),
    ("100 ms", 100_000_000),
    ("10 ms", 10_000_000),
    ("1 ms", 1_000_000),
    ("100 us", 100_000),
    ("10 us", 10_000),
    ("1 us", 1_000),
    ("100 ns", 100),
    ("10 ns", 10),
    ("1 ns", 1),
];

/// The coarsest VCD timescale that divides the update exactly, and the update in its units:
/// `1 ms` and 1 for a 1 ms update, `100 us` and 5 for 500 µs, `1 us` and 125 for 125 µs.
pub fn timescale_for(tick_ns: u64) -> (&'static str, u64) {
    for &(name, ns) in TIMESCALES {
        if tick_ns >= ns && tick_ns.is_multiple_of(ns) {
            return (name, tick_ns / ns);
        }
    }
    ("1 ns", tick_ns.max(1))
}

/// The VCD identifier of signal `n`: printable ASCII `!`…`~`, shortest first.
pub fn id_code(mut n: usize, out: &mut String) {
    loop {
        out.push((b'!' + (n % 94) as u8) as char);
        n /= 94;
        if n == 0 {
            break;
        }
    }
}

fn task_word(s: TaskState) -> &'static str {
    match s {
        TaskState::Free => "free",
        TaskState::Ready => "ready",
        TaskState::Waiting { .. } => "wait_for",
        TaskState::Sleeping { .. } => "wait_time",
        TaskState::MotionWait { .. } => "motion_wait",
    }
}

impl VcdWriter {
    /// Create the VCD (and the file its changes stream to) for a machine about to run. Both
    /// files are created now, so an unwritable path fails before the run, not after it.
    pub fn create(path: &Path, image: &MachineImage) -> Result<VcdWriter, ExportError> {
        let io = |source| ExportError::Io {
            path: path.to_path_buf(),
            source,
        };
        let target = File::create(path).map_err(io)?;
        let body_path = body_path(path);
        let body = File::options()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(&body_path)
            .map_err(|source| ExportError::Io {
                path: body_path.clone(),
                source,
            })?;
        let registry = &image.registry;
        let n = registry.slots.len();
        Ok(VcdWriter {
            path: path.to_path_buf(),
            body_path,
            target,
            body: BufWriter::with_capacity(1 << 16, body),
            machine: image.name.clone(),
            tick_ns: image.tick_ns,
            timescale: timescale_for(image.tick_ns),
            include: registry.slots.iter().map(|s| !is_derived_copy(s)).collect(),
            kinds: registry
                .slots
                .iter()
                .map(|s| SignalKind::of(s.ty))
                .collect(),
            // Every digital signal is declared; an action member holds no level of its own,
            // so like a number it appears only if it changes.
            always: registry
                .slots
                .iter()
                .map(|s| s.ty.is_bit() && s.member.access != Access::Action)
                .collect(),
            before: Vec::with_capacity(n),
            first: Vec::new(),
            last: Vec::new(),
            changed: vec![false; n],
            tasks_first: Vec::new(),
            tasks_last: Vec::with_capacity(image.tasks),
            first_tick: None,
            last_tick: 0,
            last_stamp: None,
            line: String::new(),
            failed: None,
        })
    }

    /// Note the values before the run (what "changed" is measured against).
    pub fn start(&mut self, m: &Machine, tasks: usize) {
        let n = self.include.len();
        self.before = m.values()[..n].to_vec();
        self.tasks_last = (0..tasks)
            .map(|t| m.task_state(t).unwrap_or(TaskState::Free))
            .collect();
    }

    /// Record the update just computed.
    pub fn observe(&mut self, m: &Machine, tick: u64) {
        if self.failed.is_some() {
            return;
        }
        let n = self.include.len();
        let v = &m.values()[..n];
        self.last_tick = tick;
        if self.first_tick.is_none() {
            // The first update's values are the `$dumpvars` of the header.
            self.first_tick = Some(tick);
            if self.before.len() != n {
                self.before = v.to_vec();
            }
            for (i, &x) in v.iter().enumerate() {
                if x.to_bits() != self.before[i].to_bits() {
                    self.changed[i] = true;
                }
            }
            self.first = v.to_vec();
            self.last = v.to_vec();
            for (t, s) in self.tasks_last.iter_mut().enumerate() {
                *s = m.task_state(t).unwrap_or(TaskState::Free);
            }
            self.tasks_first = self.tasks_last.clone();
            return;
        }
        self.line.clear();
        let stamp = tick * self.timescale.1;
        let mut stamped = false;
        for (i, &x) in v.iter().enumerate() {
            if x.to_bits() == self.last[i].to_bits() || !self.include[i] {
                continue;
            }
            if !stamped {
                stamped = true;
                self.stamp(stamp);
            }
            self.last[i] = x;
            self.changed[i] = true;
            write_change(&mut self.line, self.kinds[i], x, i);
        }
        for t in 0..self.tasks_last.len() {
            let s = m.task_state(t).unwrap_or(TaskState::Free);
            if task_word(s) != task_word(self.tasks_last[t]) {
                if !stamped {
                    stamped = true;
                    self.stamp(stamp);
                }
                self.tasks_last[t] = s;
                self.line.push('s');
                self.line.push_str(task_word(s));
                self.line.push(' ');
                id_code(n + t, &mut self.line);
                self.line.push('\n');
            }
        }
        if !self.line.is_empty() {
            if let Err(e) = self.body.write_all(self.line.as_bytes()) {
                self.failed = Some(e);
            }
        }
    }

    fn stamp(&mut self, stamp: u64) {
        use std::fmt::Write as _;
        let _ = writeln!(self.line, "#{stamp}");
        self.last_stamp = Some(stamp);
    }

    /// Write the header, then the changes; remove the changes' file.
    pub fn finish(mut self, registry: &Registry) -> Result<PathBuf, ExportError> {
        let result = self.assemble(registry);
        let _ = std::fs::remove_file(&self.body_path);
        result.map_err(|source| ExportError::Io {
            path: self.path.clone(),
            source,
        })?;
        Ok(self.path)
    }

    fn assemble(&mut self, registry: &Registry) -> std::io::Result<()> {
        if let Some(e) = self.failed.take() {
            return Err(e);
        }
        let end_stamp = self.last_tick * self.timescale.1;
        if self.first_tick.is_some() && self.last_stamp.is_none_or(|s| s < end_stamp) {
            // A last time stamp with no change: viewers then show the run to its end.
            writeln!(self.body, "#{end_stamp}")?;
        }
        self.body.flush()?;
        let mut out = BufWriter::with_capacity(1 << 16, &self.target);
        out.write_all(self.header(registry).as_bytes())?;
        let body = self.body.get_mut();
        body.seek(SeekFrom::Start(0))?;
        std::io::copy(body, &mut out)?;
        out.flush()
    }

    /// Declarations in scopes by object, then the values at the first update.
    fn header(&self, registry: &Registry) -> String {
        use std::fmt::Write as _;
        let n = self.include.len();
        let declared: Vec<usize> = (0..n)
            .filter(|&i| self.include[i] && (self.always[i] || self.changed[i]))
            .collect();
        let mut tree = Scope::default();
        for &i in &declared {
            let (scopes, leaf) = vcd_path(&registry.slots[i]);
            let ty = match self.kinds[i] {
                SignalKind::Bit => "wire 1",
                SignalKind::Integer => "integer 32",
                SignalKind::Real => "real 64",
            };
            tree.at(&scopes).vars.push((ty, i, leaf));
        }
        for t in 0..self.tasks_last.len() {
            let scopes = ["Task".to_string(), t.to_string()];
            tree.at(&scopes)
                .vars
                .push(("string 1", n + t, "State".to_string()));
        }
        let mut h = String::new();
        let _ = writeln!(
            h,
            "$comment machine {} update {} s: written by pacer $end",
            vcd_word(&self.machine),
            {
                let mut s = String::new();
                write_real(&mut s, self.tick_ns as f64 / 1e9);
                s
            }
        );
        let _ = writeln!(h, "$version pacer {} $end", env!("CARGO_PKG_VERSION"));
        let _ = writeln!(h, "$timescale {} $end", self.timescale.0);
        let _ = writeln!(h, "$scope module {} $end", vcd_word(&self.machine));
        tree.write(&mut h);
        h.push_str("$upscope $end\n$enddefinitions $end\n");
        let stamp = self.first_tick.unwrap_or(0) * self.timescale.1;
        let _ = writeln!(h, "#{stamp}\n$dumpvars");
        let values = if self.first.is_empty() {
            &self.before
        } else {
            &self.first
        };
        for &i in &declared {
            write_change(&mut h, self.kinds[i], values[i], i);
        }
        let tasks = if self.tasks_first.is_empty() {
            &self.tasks_last
        } else {
            &self.tasks_first
        };
        for (t, s) in tasks.iter().enumerate() {
            h.push('s');
            h.push_str(task_word(*s));
            h.push(' ');
            id_code(n + t, &mut h);
            h.push('\n');
        }
        h.push_str("$end\n");
        h
    }
}

/// `name.vcd` streams its changes to `name.vcd.changes` until the run ends.
fn body_path(path: &Path) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(".changes");
    PathBuf::from(s)
}

/// One value change line: `1!`, `b101 "`, `r1.5 #`.
fn write_change(out: &mut String, kind: SignalKind, x: f64, id: usize) {
    use std::fmt::Write as _;
    match kind {
        SignalKind::Bit => out.push(if x != 0.0 { '1' } else { '0' }),
        SignalKind::Integer => {
            // Integers are 32-bit on the drive; two's complement, as a VCD integer is.
            let i = x.round().clamp(i32::MIN as f64, i32::MAX as f64) as i32;
            let _ = write!(out, "b{:b} ", i as u32);
        }
        SignalKind::Real => {
            out.push('r');
            write_real(out, x);
            out.push(' ');
        }
    }
    id_code(id, out);
    out.push('\n');
}

/// A scope of the hierarchy, children in order of first appearance (registry order).
#[derive(Default)]
struct Scope {
    name: String,
    children: Vec<Scope>,
    vars: Vec<(&'static str, usize, String)>,
}

impl Scope {
    fn at(&mut self, path: &[String]) -> &mut Scope {
        let mut s = self;
        for p in path {
            let i = match s.children.iter().position(|c| &c.name == p) {
                Some(i) => i,
                None => {
                    s.children.push(Scope {
                        name: p.clone(),
                        ..Scope::default()
                    });
                    s.children.len() - 1
                }
            };
            s = &mut s.children[i];
        }
        s
    }

    fn write(&self, out: &mut String) {
        for (ty, id, leaf) in &self.vars {
            out.push_str("$var ");
            out.push_str(ty);
            out.push(' ');
            id_code(*id, out);
            out.push(' ');
            out.push_str(leaf);
            out.push_str(" $end\n");
        }
        for c in &self.children {
            out.push_str("$scope module ");
            out.push_str(&c.name);
            out.push_str(" $end\n");
            c.write(out);
            out.push_str("$upscope $end\n");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_timescale_divides_the_update() {
        assert_eq!(timescale_for(1_000_000), ("1 ms", 1));
        assert_eq!(timescale_for(500_000), ("100 us", 5));
        assert_eq!(timescale_for(125_000), ("1 us", 125));
        assert_eq!(timescale_for(62_500), ("100 ns", 625));
        assert_eq!(timescale_for(1_000_000_000), ("1 s", 1));
    }

    #[test]
    fn identifiers_are_distinct_and_printable() {
        let mut seen = std::collections::BTreeSet::new();
        for n in 0..20_000 {
            let mut s = String::new();
            id_code(n, &mut s);
            assert!(s.bytes().all(|b| (b'!'..=b'~').contains(&b)));
            assert!(seen.insert(s), "{n}");
        }
    }

    #[test]
    fn changes_are_written_as_vcd_values() {
        let mut s = String::new();
        write_change(&mut s, SignalKind::Bit, 1.0, 0);
        write_change(&mut s, SignalKind::Integer, 5.0, 1);
        write_change(&mut s, SignalKind::Integer, -2.0, 2);
        write_change(&mut s, SignalKind::Real, 1.5, 94);
        assert_eq!(
            s,
            "1!\nb101 \"\nb11111111111111111111111111111110 #\nr1.5 !\"\n"
        );
    }
}
