//! Reading what `pacer plot` draws from: a recorded JSON-lines trace and, optionally, the CSV a
//! run wrote with `--csv`. Both are read line by line (a trace of an hour is large), and
//! anything that is not what pacer writes is an error naming the file and line.

use super::ExportError;
use crate::trace::{Event, Line};
use indexmap::IndexSet;
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

fn open(path: &Path) -> Result<BufReader<File>, ExportError> {
    File::open(path)
        .map(|f| BufReader::with_capacity(1 << 16, f))
        .map_err(|e| ExportError::Input {
            path: path.to_path_buf(),
            message: format!("cannot read it: {e}"),
        })
}

fn bad(path: &Path, line: usize, message: impl Into<String>) -> ExportError {
    ExportError::Input {
        path: path.to_path_buf(),
        message: format!("line {line}: {}", message.into()),
    }
}

/// Call `each` with every line of a trace, parsed; stop at the first line that is not one.
pub fn read_trace(path: &Path, mut each: impl FnMut(&Line<'_>)) -> Result<usize, ExportError> {
    let mut reader = open(path)?;
    let mut text = String::new();
    let mut n = 0;
    loop {
        text.clear();
        let read = reader.read_line(&mut text).map_err(|e| {
            bad(
                path,
                n + 1,
                format!("cannot read it ({e}); is this a JSON-lines trace?"),
            )
        })?;
        if read == 0 {
            break;
        }
        n += 1;
        let line = text.trim_end();
        if line.is_empty() {
            continue;
        }
        let parsed: Line<'_> = serde_json::from_str(line).map_err(|e| {
            bad(
                path,
                n,
                format!(
                    "not a pacer trace line ({e}); a trace has one JSON object per line with \
                     `t`, `tick` and `kind`"
                ),
            )
        })?;
        if !parsed.t.is_finite() {
            return Err(bad(path, n, "`t` is not a time"));
        }
        each(&parsed);
    }
    if n == 0 {
        return Err(ExportError::Input {
            path: path.to_path_buf(),
            message: "the trace is empty".into(),
        });
    }
    Ok(n)
}

/// What a first reading of a trace tells about it.
#[derive(Debug, Default)]
pub struct TraceSummary {
    /// Event kinds present.
    pub kinds: IndexSet<String>,
    /// Members that have `change` events.
    pub names: IndexSet<String>,
    /// The update period from the `start` line.
    pub update: Option<f64>,
}

/// Read a trace once to learn what it holds.
pub fn survey(path: &Path) -> Result<TraceSummary, ExportError> {
    let mut s = TraceSummary::default();
    read_trace(path, |l| {
        let kind = l.event.kind().as_str();
        if !s.kinds.contains(kind) {
            s.kinds.insert(kind.to_string());
        }
        match &l.event {
            Event::Start { update, .. } => s.update = Some(*update),
            Event::Change { name, .. } if !s.names.contains(&**name) => {
                s.names.insert(name.to_string());
            }
            _ => {}
        }
    })?;
    Ok(s)
}

/// The column names of a CSV written by `--csv` (after `t` and `tick`).
pub fn csv_columns(path: &Path) -> Result<Vec<String>, ExportError> {
    let mut reader = open(path)?;
    let mut header = String::new();
    reader
        .read_line(&mut header)
        .map_err(|e| bad(path, 1, format!("cannot read it ({e})")))?;
    let fields = split_csv(header.trim_end());
    if fields.len() < 2 || fields[0] != "t" || fields[1] != "tick" {
        return Err(bad(
            path,
            1,
            "not a CSV written by pacer run --csv (its header starts with t,tick)",
        ));
    }
    Ok(fields[2..].to_vec())
}

/// Call `each(t, values)` with every row of a CSV written by `--csv`; a text field (a
/// MotionBASIC string variable's column) is given as NaN. The names of the columns that held
/// text.
pub fn read_csv(
    path: &Path,
    mut each: impl FnMut(f64, &[f64]),
) -> Result<Vec<String>, ExportError> {
    let names = csv_columns(path)?;
    let columns = names.len();
    let mut reader = open(path)?;
    let mut text = String::new();
    let mut values: Vec<f64> = Vec::with_capacity(columns);
    let mut texts = vec![false; columns];
    let mut n = 0;
    loop {
        text.clear();
        let read = reader
            .read_line(&mut text)
            .map_err(|e| bad(path, n + 1, format!("cannot read it ({e})")))?;
        if read == 0 {
            break;
        }
        n += 1;
        if n == 1 {
            continue;
        }
        let line = text.trim_end();
        if line.is_empty() {
            continue;
        }
        values.clear();
        let fields = split_csv(line);
        let mut fields = fields.iter();
        let t: f64 = fields
            .next()
            .and_then(|f| f.parse().ok())
            .filter(|t: &f64| t.is_finite())
            .ok_or_else(|| bad(path, n, "the first field is not a time"))?;
        // The update number is not needed: the time says it.
        fields.next();
        for (k, f) in fields.enumerate() {
            values.push(f.parse().unwrap_or_else(|_| {
                if let Some(t) = texts.get_mut(k) {
                    *t = true;
                }
                f64::NAN
            }));
        }
        if values.len() != columns {
            return Err(bad(
                path,
                n,
                format!("{} values for {columns} columns", values.len()),
            ));
        }
        each(t, &values);
    }
    Ok(names
        .into_iter()
        .zip(texts)
        .filter_map(|(name, t)| t.then_some(name))
        .collect())
}

/// Fields of a CSV line (quoted fields unquoted).
fn split_csv(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    out.push(cur);
    out
}
