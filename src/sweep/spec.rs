//! What a sweep runs: `sweep.toml` beside the machine and the command line's `--vary`,
//! `--seeds`, `--sample`, `--expect`, read into the varied values (axes), the measures, the
//! assertions, and from them the list of variants (a pure function of the two).

use super::expr::{parse_assertion, parse_sum, Assertion, Sum};
use super::set::Name;
use crate::config::values::Duration;
use crate::diag::{Diagnostics, Problem, SourceFile};
use crate::span::Span;
use crate::trace::EventKind;
use indexmap::IndexMap;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;
use toml::Spanned;

/// Where something of the sweep was written: a span of `sweep.toml`, or a command-line
/// argument.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// In `sweep.toml`.
    File(Span),
    /// A command-line argument, as given (`--vary master.speed=10..60:26`).
    Arg(String),
}

/// A problem with the sweep's input: located in `sweep.toml` (exit 1) or in a command-line
/// argument (a usage error, exit 64).
#[derive(Debug)]
pub enum SpecError {
    /// Problems in `sweep.toml`, located.
    File(Diagnostics),
    /// A command-line argument that is wrong, with the message naming it.
    Arg(String),
}

impl SpecError {
    /// The problem at `place` (of `file`, when it is there).
    pub fn at(
        file: Option<&SourceFile>,
        place: &Place,
        message: String,
        help: Option<String>,
    ) -> SpecError {
        match (place, file) {
            (Place::File(span), Some(file)) => {
                let mut d = Diagnostics::new();
                d.extend_file(
                    file,
                    vec![Problem::error("pacer::sweep", *span, message, "here").with_help_opt(help)],
                );
                SpecError::File(d)
            }
            (Place::Arg(arg), _) => SpecError::Arg(match help {
                Some(h) => format!("{arg}: {message}; {h}"),
                None => format!("{arg}: {message}"),
            }),
            (Place::File(_), None) => SpecError::Arg(message),
        }
    }
}

/// The values one varied name takes.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// These values, in order.
    List(Vec<toml::Value>),
    /// `from..to:count`: `count` evenly spaced values, both ends included (a random sample
    /// draws from the whole interval); whole numbers when both ends and the step are.
    Range {
        /// First value.
        from: f64,
        /// Last value.
        to: f64,
        /// How many.
        count: usize,
    },
}

impl Values {
    /// The grid's values.
    pub fn grid(&self) -> Vec<toml::Value> {
        match self {
            Values::List(v) => v.clone(),
            Values::Range { from, to, count } => {
                let integral = self.integral();
                (0..*count)
                    .map(|i| {
                        let x = if *count == 1 {
                            *from
                        } else {
                            from + (to - from) * i as f64 / (*count - 1) as f64
                        };
                        number(round12(x), integral)
                    })
                    .collect()
            }
        }
    }

    /// Whole numbers only (both ends and the step whole).
    fn integral(&self) -> bool {
        match self {
            Values::List(_) => false,
            Values::Range { from, to, count } => {
                let step = if *count > 1 {
                    (to - from) / (*count - 1) as f64
                } else {
                    0.0
                };
                from.fract() == 0.0 && to.fract() == 0.0 && step.fract() == 0.0
            }
        }
    }

    /// A value drawn at random.
    fn draw(&self, rng: &mut ChaCha8Rng) -> toml::Value {
        match self {
            Values::List(v) => {
                let i = (rng.next_u64() % v.len().max(1) as u64) as usize;
                v.get(i).cloned().unwrap_or(toml::Value::Integer(0))
            }
            Values::Range { from, to, .. } if self.integral() => {
                let span = (to - from) as u64 + 1;
                number(from + (rng.next_u64() % span) as f64, true)
            }
            Values::Range { from, to, .. } => {
                let u = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
                number(round12(from + (to - from) * u), false)
            }
        }
    }

    /// How it reads (for the fingerprint).
    fn describe(&self) -> String {
        match self {
            Values::List(v) => v
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(","),
            Values::Range { from, to, count } => format!("{from}..{to}:{count}"),
        }
    }
}

/// `x` to 12 significant digits, so `0.3 + 0.1 × 4` is `0.7`.
fn round12(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

fn number(x: f64, integral: bool) -> toml::Value {
    if integral && x.abs() < 9.0e15 {
        toml::Value::Integer(x as i64)
    } else {
        toml::Value::Float(x)
    }
}

/// One varied name.
#[derive(Debug, Clone)]
pub struct Axis {
    /// What it sets.
    pub name: Name,
    /// Its values.
    pub values: Values,
    /// Where it was given.
    pub place: Place,
}

/// What a measure reads from a run.
#[derive(Debug, Clone)]
pub enum MeasureKind {
    /// Trace events of a kind, those whose fields have the given values.
    Count {
        /// The kind.
        kind: EventKind,
        /// Field → value the event must have (`object = "Index.0"`).
        filter: Vec<(String, serde_json::Value)>,
    },
    /// A member's value at the end.
    Final(String),
    /// A member's greatest value over the run (every update).
    Max(String),
    /// A member's least value over the run (every update).
    Min(String),
    /// A sum of other measures and members' final values.
    Value(Sum),
    /// Products of the scenario's `[[products]]` entry N whose leading edge reached its sensor
    /// by the end (what a sensor should have seen: compare with the captures).
    Passed(usize),
}

/// A named result of each run.
#[derive(Debug, Clone)]
pub struct Measure {
    /// Its name (a column of the results).
    pub name: String,
    /// What it reads.
    pub kind: MeasureKind,
    /// Counts only from this simulated time on, seconds (`from`; 0: the whole run).
    pub from: f64,
    /// Where it was written.
    pub place: Place,
}

/// An assertion every variant must meet.
#[derive(Debug, Clone)]
pub struct Expect {
    /// As written.
    pub text: String,
    /// Parsed.
    pub assertion: Assertion,
    /// Where it was written.
    pub place: Place,
}

/// The sweep.
#[derive(Debug, Clone)]
pub struct Spec {
    /// The varied names, slowest first (the grid's last axis changes fastest).
    pub axes: Vec<Axis>,
    /// A random sample of this many variants (and its seed) instead of the grid.
    pub sample: Option<(usize, u64)>,
    /// Simulated time of each run, ns (default: the scenario's).
    pub duration_ns: Option<u64>,
    /// The measures.
    pub measures: Vec<Measure>,
    /// The assertions.
    pub expects: Vec<Expect>,
    /// What the plot shows: a measure, against one or two axes (by index).
    pub plot: PlotSpec,
    /// `sweep.toml`, when there is one.
    pub file: Option<SourceFile>,
}

/// What `--plot` draws.
#[derive(Debug, Clone, Default)]
pub struct PlotSpec {
    /// The measure (default: the first).
    pub measure: Option<String>,
    /// The horizontal axis (default: the first).
    pub x: Option<String>,
    /// The second axis (default: the second, if any).
    pub y: Option<String>,
}

/// The most variants one sweep may have.
pub const MAX_VARIANTS: usize = 10_000_000;

impl Spec {
    /// How many variants.
    pub fn len(&self) -> usize {
        match self.sample {
            Some((n, _)) => n,
            None => self.axes.iter().map(|a| a.values.grid().len()).product(),
        }
    }

    /// No variants (never, once checked).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The values of variant `i` (0-based), one per axis.
    pub fn variant(&self, i: usize) -> Vec<toml::Value> {
        match self.sample {
            Some((_, seed)) => {
                // One generator per variant: a variant's values do not depend on which others
                // run (shards), only on the seed and its number.
                let mut rng = ChaCha8Rng::seed_from_u64(mix(seed, i as u64));
                self.axes.iter().map(|a| a.values.draw(&mut rng)).collect()
            }
            None => {
                let grids: Vec<Vec<toml::Value>> =
                    self.axes.iter().map(|a| a.values.grid()).collect();
                let mut rest = i;
                let mut out = vec![toml::Value::Integer(0); grids.len()];
                for (k, g) in grids.iter().enumerate().rev() {
                    let n = g.len().max(1);
                    out[k] = g.get(rest % n).cloned().unwrap_or(toml::Value::Integer(0));
                    rest /= n;
                }
                out
            }
        }
    }

    /// The names and values of variant `i`, ready to set.
    pub fn assignments(&self, i: usize) -> Vec<(Name, toml::Value)> {
        self.axes
            .iter()
            .map(|a| a.name.clone())
            .zip(self.variant(i))
            .collect()
    }

    /// Everything that decides the variants and their results, as text (hashed into the
    /// fingerprint that ties shards to one sweep).
    pub fn describe(&self) -> String {
        let mut s = String::new();
        for a in &self.axes {
            s.push_str(&format!("vary {}={}\n", a.name.text, a.values.describe()));
        }
        s.push_str(&format!(
            "sample {:?}\nduration {:?}\n",
            self.sample, self.duration_ns
        ));
        for m in &self.measures {
            s.push_str(&format!(
                "measure {} {:?} from {}\n",
                m.name, m.kind, m.from
            ));
        }
        for e in &self.expects {
            s.push_str(&format!("expect {}\n", e.text));
        }
        s
    }
}

/// SplitMix64 of a seed and a number: well-spread generator seeds.
fn mix(seed: u64, i: u64) -> u64 {
    let mut z = seed ^ i.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

// --- sweep.toml ------------------------------------------------------------------------------

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepFile {
    #[serde(default)]
    sweep: SweepSection,
    #[serde(default)]
    vary: IndexMap<String, Spanned<toml::Value>>,
    #[serde(default)]
    measure: Vec<Spanned<MeasureEntry>>,
    #[serde(default)]
    plot: PlotEntry,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepSection {
    duration: Option<Spanned<Duration>>,
    seeds: Option<Spanned<i64>>,
    sample: Option<Spanned<i64>>,
    sample_seed: Option<u64>,
    #[serde(default)]
    expect: Vec<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MeasureEntry {
    name: Spanned<String>,
    count: Option<Spanned<String>>,
    #[serde(rename = "where")]
    filter: Option<IndexMap<String, toml::Value>>,
    #[serde(rename = "final")]
    last: Option<Spanned<String>>,
    max: Option<Spanned<String>>,
    min: Option<Spanned<String>>,
    value: Option<Spanned<String>>,
    passed: Option<Spanned<i64>>,
    from: Option<Spanned<Duration>>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct PlotEntry {
    measure: Option<String>,
    x: Option<String>,
    y: Option<String>,
}

/// What the command line adds to `sweep.toml`.
#[derive(Debug, Clone, Default)]
pub struct ArgSpec {
    /// `--vary NAME=VALUES`, as given.
    pub vary: Vec<String>,
    /// `--seeds N`.
    pub seeds: Option<u64>,
    /// `--sample N`.
    pub sample: Option<u64>,
    /// `--sample-seed S`.
    pub sample_seed: Option<u64>,
    /// `--for`, ns.
    pub duration_ns: Option<u64>,
    /// `--expect`, as given.
    pub expects: Vec<String>,
}

fn span_of<T>(s: &Spanned<T>) -> Place {
    Place::File(crate::config::span_of(s))
}

/// Read `sweep.toml` (its text, when there is one) and the command line into a sweep.
pub fn parse(file: Option<SourceFile>, args: &ArgSpec) -> Result<Spec, SpecError> {
    let parsed: SweepFile = match &file {
        None => SweepFile::default(),
        Some(f) => crate::config::parse_toml(&f.text, "sweep.toml").map_err(|p| {
            let mut d = Diagnostics::new();
            d.extend_file(f, vec![p]);
            SpecError::File(d)
        })?,
    };
    let fail = |place: &Place, message: String, help: Option<String>| {
        SpecError::at(file.as_ref(), place, message, help)
    };
    let mut axes: Vec<Axis> = Vec::new();
    for (key, value) in &parsed.vary {
        let place = span_of(value);
        let name = Name::parse(key).map_err(|m| fail(&place, m, None))?;
        let values = values_of(value.get_ref()).map_err(|m| fail(&place, m, None))?;
        push_axis(
            &mut axes,
            Axis {
                name,
                values,
                place,
            },
        );
    }
    for arg in &args.vary {
        let place = Place::Arg(format!("--vary `{arg}`"));
        let Some((key, text)) = arg.split_once('=') else {
            return Err(fail(
                &place,
                "write NAME=VALUES, e.g. master.speed=10..60:26".into(),
                None,
            ));
        };
        let name = Name::parse(key).map_err(|m| fail(&place, m, None))?;
        let values =
            values_of(&toml::Value::String(text.to_string())).map_err(|m| fail(&place, m, None))?;
        push_axis(
            &mut axes,
            Axis {
                name,
                values,
                place,
            },
        );
    }
    let seeds = match (args.seeds, &parsed.sweep.seeds) {
        (Some(n), _) => Some((n as i64, Place::Arg(format!("--seeds {n}")))),
        (None, Some(s)) => Some((*s.get_ref(), span_of(s))),
        (None, None) => None,
    };
    if let Some((n, place)) = seeds {
        if n < 1 {
            return Err(fail(&place, format!("{n} seeds: give at least 1"), None));
        }
        let name = Name::parse("seed").map_err(|m| fail(&place, m, None))?;
        push_axis(
            &mut axes,
            Axis {
                name,
                values: Values::Range {
                    from: 1.0,
                    to: n as f64,
                    count: n as usize,
                },
                place,
            },
        );
    }
    let sample = match (args.sample, &parsed.sweep.sample) {
        (Some(n), _) => Some((n as i64, Place::Arg(format!("--sample {n}")))),
        (None, Some(s)) => Some((*s.get_ref(), span_of(s))),
        (None, None) => None,
    };
    let sample = match sample {
        None => None,
        Some((n, place)) if n < 1 || n as usize > MAX_VARIANTS => {
            return Err(fail(
                &place,
                format!("a sample of {n}: give 1 to {MAX_VARIANTS} variants"),
                None,
            ))
        }
        Some((n, _)) => Some((
            n as usize,
            args.sample_seed.or(parsed.sweep.sample_seed).unwrap_or(1),
        )),
    };
    let duration_ns = args
        .duration_ns
        .or(parsed.sweep.duration.as_ref().map(|d| d.get_ref().0));
    let mut measures: Vec<Measure> = Vec::new();
    for m in &parsed.measure {
        let whole = span_of(m);
        let m = m.get_ref();
        let name = m.name.get_ref().trim().to_string();
        if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(fail(
                &span_of(&m.name),
                format!("`{name}` is not a measure name: letters, digits and _"),
                None,
            ));
        }
        if measures.iter().any(|x| x.name == name) {
            return Err(fail(
                &span_of(&m.name),
                format!("a second measure named `{name}`"),
                None,
            ));
        }
        let given = [
            m.count.is_some(),
            m.last.is_some(),
            m.max.is_some(),
            m.min.is_some(),
            m.value.is_some(),
            m.passed.is_some(),
        ];
        if given.iter().filter(|g| **g).count() != 1 {
            return Err(fail(
                &whole,
                format!("measure `{name}`: give one of count, final, max, min, value, passed"),
                None,
            ));
        }
        if m.filter.is_some() && m.count.is_none() {
            return Err(fail(
                &whole,
                format!("measure `{name}`: `where` goes with `count`"),
                None,
            ));
        }
        // Located at the field that says what to measure: an unknown name is there.
        let (kind, place) = if let Some(k) = &m.count {
            let Some(kind) = EventKind::ALL.iter().find(|e| e.as_str() == k.get_ref()) else {
                let known: Vec<&str> = EventKind::ALL.iter().map(|e| e.as_str()).collect();
                return Err(fail(
                    &span_of(k),
                    format!("`{}` is not a trace event kind", k.get_ref()),
                    Some(format!("one of {}", known.join(", "))),
                ));
            };
            let filter = m
                .filter
                .iter()
                .flatten()
                .map(|(f, v)| (f.clone(), json_of(v)))
                .collect();
            (
                MeasureKind::Count {
                    kind: *kind,
                    filter,
                },
                span_of(k),
            )
        } else if let Some(n) = &m.last {
            (
                MeasureKind::Final(n.get_ref().trim().to_string()),
                span_of(n),
            )
        } else if let Some(n) = &m.max {
            (MeasureKind::Max(n.get_ref().trim().to_string()), span_of(n))
        } else if let Some(n) = &m.min {
            (MeasureKind::Min(n.get_ref().trim().to_string()), span_of(n))
        } else if let Some(v) = &m.value {
            (
                MeasureKind::Value(parse_sum(v.get_ref()).map_err(|e| fail(&span_of(v), e, None))?),
                span_of(v),
            )
        } else if let Some(n) = &m.passed {
            let Ok(stream) = usize::try_from(*n.get_ref()) else {
                return Err(fail(
                    &span_of(n),
                    format!(
                        "passed = {}: a [[products]] entry's number, from 0",
                        n.get_ref()
                    ),
                    None,
                ));
            };
            (MeasureKind::Passed(stream), span_of(n))
        } else {
            return Err(fail(
                &whole,
                format!("measure `{name}`: nothing to measure"),
                None,
            ));
        };
        let from = match &m.from {
            None => 0.0,
            Some(f) if matches!(kind, MeasureKind::Count { .. } | MeasureKind::Passed(_)) => {
                f.get_ref().seconds()
            }
            Some(f) => {
                return Err(fail(
                    &span_of(f),
                    format!("measure `{name}`: `from` goes with `count` and `passed`"),
                    None,
                ))
            }
        };
        measures.push(Measure {
            name,
            kind,
            from,
            place,
        });
    }
    let mut expects = Vec::new();
    for e in &parsed.sweep.expect {
        let place = span_of(e);
        let assertion = parse_assertion(e.get_ref()).map_err(|m| fail(&place, m, None))?;
        expects.push(Expect {
            text: e.get_ref().trim().to_string(),
            assertion,
            place,
        });
    }
    for e in &args.expects {
        let place = Place::Arg(format!("--expect `{e}`"));
        let assertion = parse_assertion(e).map_err(|m| fail(&place, m, None))?;
        expects.push(Expect {
            text: e.trim().to_string(),
            assertion,
            place,
        });
    }
    let spec = Spec {
        axes,
        sample,
        duration_ns,
        measures,
        expects,
        plot: PlotSpec {
            measure: parsed.plot.measure.clone(),
            x: parsed.plot.x.clone(),
            y: parsed.plot.y.clone(),
        },
        file: file.clone(),
    };
    if spec.axes.is_empty() {
        return Err(SpecError::Arg(
            "nothing to vary: give --vary NAME=VALUES (e.g. master.speed=10..60:26), --seeds N, or a [vary] table in sweep.toml"
                .into(),
        ));
    }
    let total = spec
        .axes
        .iter()
        .try_fold(1usize, |n, a| n.checked_mul(a.values.grid().len().max(1)));
    if spec.sample.is_none() && total.is_none_or(|n| n > MAX_VARIANTS) {
        let place = spec
            .axes
            .last()
            .map(|a| a.place.clone())
            .unwrap_or(Place::Arg("--vary".into()));
        return Err(fail(
            &place,
            format!("the grid has more than {MAX_VARIANTS} variants"),
            Some("vary fewer values, or draw a random sample (--sample N)".into()),
        ));
    }
    Ok(spec)
}

/// A later axis of the same name replaces the earlier one in its place (the command line
/// overrides `sweep.toml`).
fn push_axis(axes: &mut Vec<Axis>, axis: Axis) {
    match axes.iter_mut().find(|a| a.name.text == axis.name.text) {
        Some(a) => *a = axis,
        None => axes.push(axis),
    }
}

fn json_of(v: &toml::Value) -> serde_json::Value {
    match v {
        toml::Value::String(s) => serde_json::Value::String(s.clone()),
        toml::Value::Integer(i) => serde_json::Value::from(*i),
        toml::Value::Float(f) => serde_json::Value::from(*f),
        toml::Value::Boolean(b) => serde_json::Value::Bool(*b),
        other => serde_json::Value::String(other.to_string()),
    }
}

/// The values of `[vary]`'s entry or a `--vary`: a list (TOML array, or `a,b,c`), a range
/// `from..to:count` (or `from..to`, whole numbers), or one value.
pub fn values_of(v: &toml::Value) -> Result<Values, String> {
    match v {
        toml::Value::Array(items) => {
            if items.is_empty() {
                return Err("an empty list of values".into());
            }
            if let Some(bad) = items
                .iter()
                .find(|i| matches!(i, toml::Value::Array(_) | toml::Value::Table(_)))
            {
                return Err(format!("`{bad}` is not a single value"));
            }
            Ok(Values::List(items.clone()))
        }
        toml::Value::String(s) => {
            let s = s.trim();
            if s.is_empty() {
                return Err("no values".into());
            }
            if let Some((from, rest)) = s.split_once("..") {
                return range(from, rest);
            }
            let items: Vec<toml::Value> = s
                .split(',')
                .map(str::trim)
                .filter(|p| !p.is_empty())
                .map(super::set::parse_value)
                .collect();
            if items.is_empty() {
                return Err(format!("`{s}`: no values"));
            }
            Ok(Values::List(items))
        }
        toml::Value::Table(_) => {
            Err("a table is not a value: give a list, a range \"from..to:count\" or a value".into())
        }
        one => Ok(Values::List(vec![one.clone()])),
    }
}

fn range(from: &str, rest: &str) -> Result<Values, String> {
    let text = format!("{from}..{rest}");
    let (to, count) = match rest.split_once(':') {
        Some((to, n)) => (to, Some(n)),
        None => (rest, None),
    };
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                format!(
                    "`{text}`: `{}` is not a number (write from..to:count, e.g. 10..60:26)",
                    t.trim()
                )
            })
    };
    let (a, b) = (num(from)?, num(to)?);
    if b < a {
        return Err(format!(
            "the range `{text}` is empty: write the smaller end first"
        ));
    }
    let count = match count {
        Some(n) => n
            .trim()
            .parse::<usize>()
            .map_err(|_| format!("`{text}`: `{}` is not a count of values", n.trim()))?,
        None if a.fract() == 0.0 && b.fract() == 0.0 => (b - a) as usize + 1,
        None => {
            return Err(format!(
                "`{text}`: how many values? write from..to:count, e.g. {from}..{to}:5"
            ))
        }
    };
    if count == 0 {
        return Err(format!("the range `{text}` is empty: it asks for 0 values"));
    }
    if count == 1 && a != b {
        return Err(format!(
            "`{text}`: 1 value cannot span {a} to {b}: give 2 or more"
        ));
    }
    if count > MAX_VARIANTS {
        return Err(format!("`{text}`: more than {MAX_VARIANTS} values"));
    }
    Ok(Values::Range {
        from: a,
        to: b,
        count,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(toml: &str, args: &ArgSpec) -> Result<Spec, SpecError> {
        parse(Some(SourceFile::new("sweep.toml", toml)), args)
    }

    #[test]
    fn a_grid_with_seeds_is_the_product() {
        let args = ArgSpec {
            vary: vec!["master.speed=10..60:26".into()],
            seeds: Some(40),
            ..ArgSpec::default()
        };
        let s = parse(None, &args).expect("a sweep");
        assert_eq!(s.len(), 1040);
        assert_eq!(
            s.variant(0),
            vec![toml::Value::Integer(10), toml::Value::Integer(1)]
        );
        assert_eq!(
            s.variant(41),
            vec![toml::Value::Integer(12), toml::Value::Integer(2)]
        );
        assert_eq!(
            s.variant(1039),
            vec![toml::Value::Integer(60), toml::Value::Integer(40)]
        );
    }

    #[test]
    fn ranges_round_and_lists_read() {
        let v = values_of(&toml::Value::String("0.3..1.0:8".into())).expect("a range");
        let g = v.grid();
        assert_eq!(g.len(), 8);
        assert_eq!(g[4], toml::Value::Float(0.7));
        let l = values_of(&toml::Value::String("1ms, 2ms".into())).expect("a list");
        assert_eq!(l.grid()[1], toml::Value::String("2ms".into()));
        for bad in ["60..10:3", "1..2:0", "a..2:3", "0.5..1", ""] {
            assert!(
                values_of(&toml::Value::String(bad.into())).is_err(),
                "{bad}"
            );
        }
        let e = values_of(&toml::Value::String("60..10:3".into())).expect_err("empty");
        assert!(e.contains("empty"), "{e}");
    }

    #[test]
    fn a_sample_is_a_function_of_its_seed() {
        let args = ArgSpec {
            vary: vec![
                "master.speed=10..60:26".into(),
                "products.0.pitch=0.5..1.0:6".into(),
            ],
            sample: Some(50),
            sample_seed: Some(7),
            ..ArgSpec::default()
        };
        let a = parse(None, &args).expect("a sweep");
        let b = parse(None, &args).expect("a sweep");
        assert_eq!(a.len(), 50);
        for i in 0..50 {
            assert_eq!(a.variant(i), b.variant(i));
            let toml::Value::Float(p) = a.variant(i)[1] else {
                panic!("a float pitch")
            };
            assert!((0.5..=1.0).contains(&p));
        }
    }

    #[test]
    fn errors_point_at_the_file_or_name_the_argument() {
        let e = spec(
            "[vary]\n\"mastr.speed\" = \"10..60:26\"\n",
            &ArgSpec::default(),
        )
        .expect_err("unknown");
        let SpecError::File(d) = e else {
            panic!("located in the file")
        };
        let text = d.render_plain();
        assert!(text.contains("sweep.toml:2:"), "{text}");
        assert!(text.contains("did you mean `master`"), "{text}");
        let e = spec(
            "",
            &ArgSpec {
                vary: vec!["master.speed=60..10:3".into()],
                ..ArgSpec::default()
            },
        )
        .expect_err("empty");
        let SpecError::Arg(m) = e else {
            panic!("an argument")
        };
        assert!(
            m.contains("--vary `master.speed=60..10:3`") && m.contains("empty"),
            "{m}"
        );
        let e = spec(
            "[[measure]]\nname = \"x\"\ncount = \"labels\"\n[vary]\nseed = [1]\n",
            &ArgSpec::default(),
        )
        .expect_err("kind");
        let SpecError::File(d) = e else {
            panic!("located")
        };
        assert!(d.render_plain().contains("not a trace event kind"));
    }
}
