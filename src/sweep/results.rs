//! A sweep's results on disk: `sweep.json` (what was swept, its fingerprint, which shard),
//! `results.jsonl` (one line per variant, in variant order) and `results.csv`; and the merge of
//! shards' folders into the files one unsharded run writes, byte for byte.

use super::run::VariantResult;
use indexmap::IndexMap;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format of `sweep.json` (raised when it changes).
pub const FORMAT: u32 = 1;

/// `sweep.json`: what a results folder holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Meta {
    /// [`FORMAT`].
    pub format: u32,
    /// Hash of the machine's files and the sweep: shards of one sweep share it.
    pub fingerprint: String,
    /// The machine's name.
    pub machine: String,
    /// Variants of the whole sweep.
    pub variants: usize,
    /// The varied names, in order.
    pub axes: Vec<String>,
    /// The measures, in order.
    pub measures: Vec<String>,
    /// The assertions.
    pub expects: Vec<String>,
    /// `pacer run` arguments that re-run a variant, before its `--set`s (the folder, `--for`).
    pub rerun: Vec<String>,
    /// The plot's choice: measure, x, y (names).
    pub plot: Vec<String>,
    /// The variants are a random sample (no grid: no boundary is read from them).
    pub sampled: bool,
    /// This folder holds shard `index` of `count` (none: the whole sweep).
    pub shard: Option<Shard>,
}

/// A slice of a sweep: the variants whose number modulo `count` is `index`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// From 0.
    pub index: usize,
    /// Shards in all.
    pub count: usize,
}

impl Shard {
    /// `I/N`, or `env/N` (I from `JOB_COMPLETION_INDEX`, else `SLURM_ARRAY_TASK_ID`).
    pub fn parse(text: &str, env: &dyn Fn(&str) -> Option<String>) -> Result<Shard, String> {
        let wrong =
            || format!("--shard `{text}`: write I/N, shard I (from 0) of N, e.g. 0/4, or env/N");
        let (i, n) = text.split_once('/').ok_or_else(wrong)?;
        let count: usize = n.trim().parse().map_err(|_| wrong())?;
        if count == 0 {
            return Err(format!("--shard `{text}`: 0 shards"));
        }
        let index: usize = if i.trim() == "env" {
            let (var, value) = ["JOB_COMPLETION_INDEX", "SLURM_ARRAY_TASK_ID"]
                .iter()
                .find_map(|v| env(v).map(|x| (*v, x)))
                .ok_or_else(|| {
                    format!("--shard `{text}`: neither JOB_COMPLETION_INDEX (Kubernetes) nor SLURM_ARRAY_TASK_ID (Slurm) is set")
                })?;
            value
                .trim()
                .parse()
                .map_err(|_| format!("--shard `{text}`: {var} is `{value}`, not a shard number"))?
        } else {
            i.trim().parse().map_err(|_| wrong())?
        };
        if index >= count {
            return Err(format!(
                "--shard `{text}`: shard {index} of {count} does not exist (shards are numbered 0 to {})",
                count - 1
            ));
        }
        Ok(Shard { index, count })
    }

    /// The variants of the shard, of `total`.
    pub fn indices(self, total: usize) -> Vec<usize> {
        (self.index..total).step_by(self.count).collect()
    }
}

/// FNV-1a, 64 bits, as 16 hex digits: a stable hash (the standard library's may change).
pub fn fingerprint(parts: &[&str]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in parts {
        for b in p.bytes().chain([0u8]) {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    format!("{h:016x}")
}

/// A results line as written and read.
#[derive(Debug, Serialize, Deserialize)]
struct Line {
    variant: usize,
    values: IndexMap<String, serde_json::Value>,
    pass: bool,
    end: String,
    errors: u64,
    warnings: u64,
    measures: IndexMap<String, Option<f64>>,
    failed: Vec<String>,
    failed_at: Option<f64>,
    message: Option<String>,
}

fn json_value(v: &toml::Value) -> serde_json::Value {
    match v {
        toml::Value::Integer(i) => serde_json::Value::from(*i),
        toml::Value::Float(f) => serde_json::Value::from(*f),
        toml::Value::Boolean(b) => serde_json::Value::Bool(*b),
        toml::Value::String(s) => serde_json::Value::String(s.clone()),
        other => serde_json::Value::String(other.to_string()),
    }
}

fn toml_value(v: &serde_json::Value) -> toml::Value {
    match v {
        serde_json::Value::Number(n) => match n.as_i64() {
            Some(i) => toml::Value::Integer(i),
            None => toml::Value::Float(n.as_f64().unwrap_or(f64::NAN)),
        },
        serde_json::Value::Bool(b) => toml::Value::Boolean(*b),
        serde_json::Value::String(s) => toml::Value::String(s.clone()),
        other => toml::Value::String(other.to_string()),
    }
}

/// One results line (with its newline).
pub fn jsonl_line(meta: &Meta, r: &VariantResult) -> String {
    let line = Line {
        variant: r.index,
        values: meta
            .axes
            .iter()
            .cloned()
            .zip(r.values.iter().map(json_value))
            .collect(),
        pass: r.pass(),
        end: r.end.clone(),
        errors: r.errors,
        warnings: r.warnings,
        measures: meta
            .measures
            .iter()
            .cloned()
            .zip(r.measures.iter().copied())
            .collect(),
        failed: r.failed.clone(),
        failed_at: r.failed_at,
        message: r.message.clone(),
    };
    let mut s = serde_json::to_string(&line).unwrap_or_default();
    s.push('\n');
    s
}

/// A CSV field, quoted when it must be (RFC 4180).
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// A number as the CSV shows it: as JSON writes it, empty when there is none.
fn num(x: Option<f64>) -> String {
    x.map(|x| serde_json::Value::from(x).to_string())
        .unwrap_or_default()
}

/// The whole CSV.
pub fn csv(meta: &Meta, results: &[VariantResult]) -> String {
    let mut out = String::from("variant");
    for a in &meta.axes {
        out.push(',');
        out.push_str(&field(a));
    }
    out.push_str(",pass,end,errors,warnings");
    for m in &meta.measures {
        out.push(',');
        out.push_str(&field(m));
    }
    out.push_str(",failed,failed_at,message\n");
    for r in results {
        out.push_str(&r.index.to_string());
        for v in &r.values {
            out.push(',');
            out.push_str(&field(&match v {
                toml::Value::String(s) => s.clone(),
                other => other.to_string(),
            }));
        }
        out.push_str(&format!(
            ",{},{},{},{}",
            r.pass(),
            field(&r.end),
            r.errors,
            r.warnings
        ));
        for m in &r.measures {
            out.push(',');
            out.push_str(&num(*m));
        }
        out.push(',');
        out.push_str(&field(&r.failed.join("; ")));
        out.push(',');
        out.push_str(&num(r.failed_at));
        out.push(',');
        out.push_str(&field(r.message.as_deref().unwrap_or_default()));
        out.push('\n');
    }
    out
}

/// Write `sweep.json`, `results.jsonl` and `results.csv` into `dir` (made if missing).
pub fn write(dir: &Path, meta: &Meta, results: &[VariantResult]) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot make {}: {e}", dir.display()))?;
    let put = |name: &str, text: String| {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| format!("cannot write {}: {e}", p.display()))
    };
    let mut m = serde_json::to_string_pretty(meta).map_err(|e| e.to_string())?;
    m.push('\n');
    put("sweep.json", m)?;
    put(
        "results.jsonl",
        results.iter().map(|r| jsonl_line(meta, r)).collect(),
    )?;
    put("results.csv", csv(meta, results))
}

/// Read a results folder.
pub fn read(dir: &Path) -> Result<(Meta, Vec<VariantResult>), String> {
    let path = |n: &str| dir.join(n);
    let text = |p: PathBuf| {
        std::fs::read_to_string(&p).map_err(|e| format!("cannot read {}: {e}", p.display()))
    };
    let meta_path = path("sweep.json");
    let meta: Meta = serde_json::from_str(&text(meta_path.clone())?).map_err(|e| {
        format!(
            "{}: not a pacer sweep's sweep.json: {e}",
            meta_path.display()
        )
    })?;
    if meta.format != FORMAT {
        return Err(format!(
            "{}: format {} (this pacer reads {FORMAT})",
            meta_path.display(),
            meta.format
        ));
    }
    // A file edited by hand must not make the merge allocate without bound or divide by zero.
    let shard_ok = meta
        .shard
        .is_none_or(|s| s.count > 0 && s.index < s.count && s.count <= super::spec::MAX_VARIANTS);
    if meta.variants > super::spec::MAX_VARIANTS || !shard_ok {
        return Err(format!(
            "{}: the variant count or the shard is out of range",
            meta_path.display()
        ));
    }
    let lines_path = path("results.jsonl");
    let mut results = Vec::new();
    for (n, l) in text(lines_path.clone())?.lines().enumerate() {
        let line: Line = serde_json::from_str(l).map_err(|e| {
            format!(
                "{}:{}: not a results line: {e}",
                lines_path.display(),
                n + 1
            )
        })?;
        if line.values.len() != meta.axes.len() || line.measures.len() != meta.measures.len() {
            return Err(format!(
                "{}:{}: the line does not match sweep.json's values and measures",
                lines_path.display(),
                n + 1
            ));
        }
        results.push(VariantResult {
            index: line.variant,
            values: line.values.values().map(toml_value).collect(),
            end: line.end,
            errors: line.errors,
            warnings: line.warnings,
            measures: line.measures.values().copied().collect(),
            failed: line.failed,
            failed_at: line.failed_at,
            message: line.message,
        });
    }
    Ok((meta, results))
}

/// Join shards' folders into the results of the whole sweep: every shard of one sweep (one
/// fingerprint, one shard count) exactly once, each holding exactly its variants.
pub fn merge(dirs: &[PathBuf]) -> Result<(Meta, Vec<VariantResult>), String> {
    let mut parts = Vec::new();
    for d in dirs {
        parts.push((d, read(d)?));
    }
    let Some((first_dir, (first, _))) = parts.first() else {
        return Err("merge: give the shards' folders".into());
    };
    let Some(shard) = first.shard else {
        return Err(format!(
            "{}: not a shard (it holds a whole sweep)",
            first_dir.display()
        ));
    };
    let mut seen: Vec<Option<&PathBuf>> = vec![None; shard.count];
    let mut all: Vec<Option<VariantResult>> = vec![None; first.variants];
    for (dir, (meta, results)) in &parts {
        if meta.fingerprint != first.fingerprint {
            return Err(format!(
                "{} is of another sweep than {} (fingerprint {} against {}): the machine, its files or the sweep differ",
                dir.display(),
                first_dir.display(),
                meta.fingerprint,
                first.fingerprint
            ));
        }
        let Some(s) = meta.shard else {
            return Err(format!(
                "{}: not a shard (it holds a whole sweep)",
                dir.display()
            ));
        };
        if s.count != shard.count {
            return Err(format!(
                "{} is shard {}/{}, {} is shard {}/{}: the shard counts differ",
                dir.display(),
                s.index,
                s.count,
                first_dir.display(),
                shard.index,
                shard.count
            ));
        }
        let slot = seen
            .get_mut(s.index)
            .ok_or_else(|| format!("{}: shard {} of {}?", dir.display(), s.index, s.count))?;
        if let Some(other) = slot {
            return Err(format!(
                "shard {}/{} twice: {} and {}",
                s.index,
                s.count,
                other.display(),
                dir.display()
            ));
        }
        *slot = Some(dir);
        let expected = s.indices(meta.variants);
        let got: Vec<usize> = results.iter().map(|r| r.index).collect();
        if got != expected {
            return Err(format!(
                "{}: shard {}/{} should hold {} variants ({}…), it holds {}: rerun it",
                dir.display(),
                s.index,
                s.count,
                expected.len(),
                expected
                    .iter()
                    .take(3)
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(", "),
                got.len()
            ));
        }
        for r in results {
            if let Some(x) = all.get_mut(r.index) {
                *x = Some(r.clone());
            }
        }
    }
    let missing: Vec<String> = seen
        .iter()
        .enumerate()
        .filter(|(_, d)| d.is_none())
        .map(|(i, _)| format!("{i}/{}", shard.count))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "merge: missing shard{} {}",
            if missing.len() == 1 { "" } else { "s" },
            missing.join(", ")
        ));
    }
    let mut meta = first.clone();
    meta.shard = None;
    Ok((meta, all.into_iter().flatten().collect()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_slice() {
        let none = |_: &str| None;
        assert_eq!(Shard::parse("1/4", &none), Ok(Shard { index: 1, count: 4 }));
        assert_eq!(Shard { index: 1, count: 4 }.indices(10), vec![1, 5, 9]);
        assert!(Shard::parse("4/4", &none)
            .expect_err("past the end")
            .contains("does not exist"));
        assert!(Shard::parse("1/0", &none).is_err());
        assert!(Shard::parse("x", &none).is_err());
        assert!(Shard::parse("env/4", &none)
            .expect_err("no env")
            .contains("JOB_COMPLETION_INDEX"));
        let slurm = |v: &str| (v == "SLURM_ARRAY_TASK_ID").then(|| "3".to_string());
        assert_eq!(
            Shard::parse("env/4", &slurm),
            Ok(Shard { index: 3, count: 4 })
        );
    }

    #[test]
    fn the_fingerprint_is_stable() {
        assert_eq!(fingerprint(&["a", "b"]), fingerprint(&["a", "b"]));
        assert_ne!(fingerprint(&["ab", ""]), fingerprint(&["a", "b"]));
    }
}
