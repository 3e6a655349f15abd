//! The summary a sweep prints: counts, which assertions failed how often, the boundary of safe
//! operation over two varied values, and the failing variants smallest first, each with the
//! command that re-runs it alone with a trace. Made from the results alone, so a merge of
//! shards prints what the unsharded run printed.

use super::results::Meta;
use super::run::VariantResult;
use super::set::value_text;
use std::cmp::Ordering;
use std::fmt::Write as _;

/// Failing variants listed in full.
const LISTED: usize = 10;

/// Values of the first axis the boundary lists at most.
const BOUNDARY_ROWS: usize = 100;

/// Order of two values: numbers by value, before text, text by text.
pub fn cmp_value(a: &toml::Value, b: &toml::Value) -> Ordering {
    match (as_number(a), as_number(b)) {
        (Some(x), Some(y)) => x.total_cmp(&y),
        (Some(_), None) => Ordering::Less,
        (None, Some(_)) => Ordering::Greater,
        (None, None) => a.to_string().cmp(&b.to_string()),
    }
}

/// A value as a number, when it is one.
pub fn as_number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Integer(i) => Some(*i as f64),
        toml::Value::Float(f) => Some(*f),
        toml::Value::Boolean(b) => Some(f64::from(u8::from(*b))),
        _ => None,
    }
}

/// A value as the summary shows it.
pub fn show(v: &toml::Value) -> String {
    value_text(v)
}

/// An argument as a POSIX shell reads it back.
pub fn shell_word(s: &str) -> String {
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-./:=,+@%".contains(c))
    {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

/// The command that runs variant `r` alone, tracing to `variant-N.jsonl`.
pub fn rerun_command(meta: &Meta, r: &VariantResult) -> String {
    let mut words = vec!["pacer".to_string(), "run".to_string()];
    words.extend(meta.rerun.iter().map(|w| shell_word(w)));
    for (name, v) in meta.axes.iter().zip(&r.values) {
        words.push("--set".into());
        words.push(shell_word(&format!("{name}={}", show(v))));
    }
    words.push("--trace".into());
    words.push(format!("variant-{}.jsonl", r.index));
    words.join(" ")
}

/// The distinct values of axis `k`, in order.
pub fn axis_values(results: &[VariantResult], k: usize) -> Vec<toml::Value> {
    let mut v: Vec<toml::Value> = results
        .iter()
        .filter_map(|r| r.values.get(k).cloned())
        .collect();
    v.sort_by(cmp_value);
    v.dedup_by(|a, b| cmp_value(a, b) == Ordering::Equal);
    v
}

/// For each value of axis `x`, the values of axis `y` at which every variant passes (over all
/// other varied values).
pub fn passing(
    results: &[VariantResult],
    x: usize,
    y: usize,
) -> Vec<(toml::Value, Vec<(toml::Value, bool)>)> {
    let ys = axis_values(results, y);
    axis_values(results, x)
        .into_iter()
        .map(|xv| {
            let row = ys
                .iter()
                .filter_map(|yv| {
                    let mut any = false;
                    let mut all_pass = true;
                    for r in results.iter().filter(|r| {
                        r.values
                            .get(x)
                            .is_some_and(|v| cmp_value(v, &xv) == Ordering::Equal)
                            && r.values
                                .get(y)
                                .is_some_and(|v| cmp_value(v, yv) == Ordering::Equal)
                    }) {
                        any = true;
                        all_pass &= r.pass();
                    }
                    any.then(|| (yv.clone(), all_pass))
                })
                .collect();
            (xv, row)
        })
        .collect()
}

/// Which of a sorted row of values pass, in words: `>= 0.8`, `<= 40`, `all`, `none`, or the
/// runs `0.5 … 0.6, 0.8 … 1`.
pub fn describe_row(name: &str, row: &[(toml::Value, bool)]) -> String {
    let passing = row.iter().filter(|(_, p)| *p).count();
    if passing == 0 {
        return "none passes".into();
    }
    if passing == row.len() {
        return "all pass".into();
    }
    let first = row.iter().position(|(_, p)| *p).unwrap_or(0);
    let last = row.iter().rposition(|(_, p)| *p).unwrap_or(0);
    let contiguous = row[first..=last].iter().all(|(_, p)| *p);
    if contiguous && last == row.len() - 1 {
        return format!("{name} >= {}", show(&row[first].0));
    }
    if contiguous && first == 0 {
        return format!("{name} <= {}", show(&row[last].0));
    }
    let mut runs = Vec::new();
    let mut i = 0;
    while i < row.len() {
        if !row[i].1 {
            i += 1;
            continue;
        }
        let start = i;
        while i + 1 < row.len() && row[i + 1].1 {
            i += 1;
        }
        runs.push(if start == i {
            show(&row[start].0)
        } else {
            format!("{} … {}", show(&row[start].0), show(&row[i].0))
        });
        i += 1;
    }
    format!("{name} in {}", runs.join(", "))
}

/// The axes the boundary and the plot use: the plot's choice, else the first two that take
/// more than one value (seeds left out: they are repeats, not a dimension).
pub fn chosen_axes(meta: &Meta, results: &[VariantResult]) -> (Option<usize>, Option<usize>) {
    let find = |n: &str| meta.axes.iter().position(|a| a == n);
    let mut dims: Vec<usize> = (0..meta.axes.len())
        .filter(|i| meta.axes[*i] != "run.seed")
        .collect();
    let varied: Vec<usize> = dims
        .iter()
        .copied()
        .filter(|i| axis_values(results, *i).len() > 1)
        .collect();
    if !varied.is_empty() {
        dims = varied;
    }
    let x = meta
        .plot
        .get(1)
        .filter(|s| !s.is_empty())
        .and_then(|n| find(n))
        .or(dims.first().copied());
    let y = meta
        .plot
        .get(2)
        .filter(|s| !s.is_empty())
        .and_then(|n| find(n))
        .or_else(|| dims.iter().copied().find(|d| Some(*d) != x));
    (x, y)
}

/// The summary text.
pub fn summary(meta: &Meta, results: &[VariantResult]) -> String {
    let mut out = String::new();
    let failing: Vec<&VariantResult> = results.iter().filter(|r| !r.pass()).collect();
    let _ = writeln!(
        out,
        "sweep: {}: {} variant{} over {}: {} pass, {} fail",
        meta.machine,
        results.len(),
        if results.len() == 1 { "" } else { "s" },
        meta.axes.join(" × "),
        results.len() - failing.len(),
        failing.len()
    );
    let mut reasons: Vec<(String, usize)> = Vec::new();
    for r in &failing {
        let mut why: Vec<String> = r.failed.iter().map(|f| format!("`{f}`")).collect();
        if r.errors > 0 && r.end != "load error" {
            why.push(format!(
                "{} ({})",
                r.end,
                r.message.as_deref().unwrap_or("an error")
            ));
        }
        for w in why {
            match reasons.iter_mut().find(|(x, _)| *x == w) {
                Some((_, n)) => *n += 1,
                None => reasons.push((w, 1)),
            }
        }
    }
    for (why, n) in &reasons {
        let _ = writeln!(
            out,
            "  failed {why}: {n} variant{}",
            if *n == 1 { "" } else { "s" }
        );
    }
    let rows = chosen_axes(meta, results)
        .0
        .map_or(0, |x| axis_values(results, x).len());
    if meta.sampled || rows > BOUNDARY_ROWS {
        let _ = writeln!(
            out,
            "safe operation: {}: no grid to read a boundary from; see the plot (--plot)",
            if meta.sampled {
                "a random sample".to_string()
            } else {
                format!(
                    "{rows} values of {}",
                    meta.axes[chosen_axes(meta, results).0.unwrap_or(0)]
                )
            }
        );
    } else if let (Some(x), Some(y)) = chosen_axes(meta, results) {
        let (xn, yn) = (&meta.axes[x], &meta.axes[y]);
        let _ = writeln!(
            out,
            "safe operation: for each {xn}, the {yn} at which every variant passes:"
        );
        for (xv, row) in passing(results, x, y) {
            let _ = writeln!(out, "  {xn} = {}: {}", show(&xv), describe_row(yn, &row));
        }
    } else if let (Some(x), None) = chosen_axes(meta, results) {
        let xn = &meta.axes[x];
        let row: Vec<(toml::Value, bool)> = axis_values(results, x)
            .into_iter()
            .map(|v| {
                let pass = results
                    .iter()
                    .filter(|r| {
                        r.values
                            .get(x)
                            .is_some_and(|w| cmp_value(w, &v) == Ordering::Equal)
                    })
                    .all(VariantResult::pass);
                (v, pass)
            })
            .collect();
        let _ = writeln!(out, "safe operation: {xn}: {}", describe_row(xn, &row));
    }
    if failing.is_empty() {
        return out;
    }
    let mut sorted = failing.clone();
    sorted.sort_by(|a, b| {
        a.values
            .iter()
            .zip(&b.values)
            .map(|(x, y)| cmp_value(x, y))
            .find(|o| *o != Ordering::Equal)
            .unwrap_or(Ordering::Equal)
            .then(a.index.cmp(&b.index))
    });
    let _ = writeln!(
        out,
        "failing variants, smallest first ({} of {}):",
        sorted.len().min(LISTED),
        sorted.len()
    );
    for r in sorted.iter().take(LISTED) {
        let values: Vec<String> = meta
            .axes
            .iter()
            .zip(&r.values)
            .map(|(n, v)| format!("{n}={}", show(v)))
            .collect();
        let mut why: Vec<String> = r.failed.iter().map(|f| format!("`{f}`")).collect();
        if let Some(m) = &r.message {
            why.push(m.clone());
        }
        let at = r
            .failed_at
            .map(|t| format!(" (first at t = {t:.3} s)"))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "  #{} {}: {}{at}",
            r.index,
            values.join(" "),
            why.join("; ")
        );
        let _ = writeln!(out, "    {}", rerun_command(meta, r));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(vals: &[(f64, bool)]) -> Vec<(toml::Value, bool)> {
        vals.iter()
            .map(|(v, p)| (toml::Value::Float(*v), *p))
            .collect()
    }

    #[test]
    fn rows_read_as_bounds() {
        assert_eq!(
            describe_row("p", &row(&[(0.5, false), (0.6, true), (0.7, true)])),
            "p >= 0.6"
        );
        assert_eq!(
            describe_row("p", &row(&[(0.5, true), (0.6, false)])),
            "p <= 0.5"
        );
        assert_eq!(
            describe_row("p", &row(&[(0.5, true), (0.6, true)])),
            "all pass"
        );
        assert_eq!(describe_row("p", &row(&[(0.5, false)])), "none passes");
        assert_eq!(
            describe_row(
                "p",
                &row(&[
                    (0.5, true),
                    (0.6, false),
                    (0.7, true),
                    (0.8, true),
                    (0.9, false)
                ])
            ),
            "p in 0.5, 0.7 … 0.8"
        );
    }

    #[test]
    fn shell_words_are_quoted_when_needed() {
        assert_eq!(shell_word("master.speed=40"), "master.speed=40");
        assert_eq!(shell_word("a b"), "'a b'");
        assert_eq!(shell_word("it's"), "'it'\\''s'");
        assert_eq!(shell_word("x=\"1 ms\""), "'x=\"1 ms\"'");
    }
}
