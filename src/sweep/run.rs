//! Running variants: each loaded with its values set, run in memory (no trace file: the events
//! a measure counts are counted as they happen), measured and judged; many at once on worker
//! threads, the results kept in variant order whatever order they finish in.

use super::expr::{Sum, Term};
use super::set::{Base, SetError};
use super::spec::{MeasureKind, Place, Spec, SpecError};
use crate::registry::{Access, Registry};
use crate::trace::{Event, Trace};
use crate::vm::Machine;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The result of one variant.
#[derive(Debug, Clone, PartialEq)]
pub struct VariantResult {
    /// Its number, from 0.
    pub index: usize,
    /// Its values, one per axis.
    pub values: Vec<toml::Value>,
    /// How the run ended (`duration reached`, `run-time error`, `load error`).
    pub end: String,
    /// Errors: the loader's, or the run's error events.
    pub errors: u64,
    /// Warnings: the loader's and the run's.
    pub warnings: u64,
    /// Each measure (`None` when it has no value: the run did not happen).
    pub measures: Vec<Option<f64>>,
    /// The assertions that failed, as written.
    pub failed: Vec<String>,
    /// When an assertion on members first failed, simulated seconds.
    pub failed_at: Option<f64>,
    /// The first error's message, on one line.
    pub message: Option<String>,
}

impl VariantResult {
    /// No error, every assertion met.
    pub fn pass(&self) -> bool {
        self.errors == 0 && self.failed.is_empty()
    }
}

/// A term of an expression, resolved for one machine.
#[derive(Debug, Clone, Copy)]
enum Operand {
    Const(f64),
    Slot(usize),
    Measure(usize),
}

type Resolved = Vec<(f64, Operand)>;

/// A counting measure: its index, the kind of event, the fields the event must have, and the
/// time counting starts.
type Counted = (
    usize,
    crate::trace::EventKind,
    Vec<(String, serde_json::Value)>,
    f64,
);

/// A name of an expression or measure: an earlier measure (when `measures` allows), else a
/// member a program can read.
fn resolve_name(registry: &Registry, measures: &[&str], name: &str) -> Result<Operand, String> {
    if let Some(i) = measures.iter().position(|m| *m == name) {
        return Ok(Operand::Measure(i));
    }
    let n = crate::syntax::ast::Name::from_token(name, 0);
    match crate::check::motionbasic::resolve(registry, &n) {
        Ok(r) => match registry.slots.get(r.slot as usize) {
            Some(info) if !matches!(info.member.access, Access::Action | Access::Input) => {
                Ok(Operand::Slot(r.slot as usize))
            }
            Some(_) => Err(format!("`{name}` is an action, with no value to read")),
            None => Err(format!("`{name}` has no value to read")),
        },
        Err(_) => {
            let names: Vec<_> = registry.slots.iter().map(|s| s.name.text()).collect();
            let hint = crate::export::signals::nearest(
                name,
                measures
                    .iter()
                    .copied()
                    .chain(names.iter().map(|n| n.as_ref())),
            )
            .map(|n| format!(" (did you mean `{n}`?)"))
            .unwrap_or_default();
            Err(format!("`{name}` is neither a measure nor a member{hint}"))
        }
    }
}

fn resolve_sum(registry: &Registry, measures: &[&str], sum: &Sum) -> Result<Resolved, String> {
    sum.terms
        .iter()
        .map(|(sign, t)| {
            Ok((
                *sign,
                match t {
                    Term::Number(x) => Operand::Const(*x),
                    Term::Name(n) => resolve_name(registry, measures, n)?,
                },
            ))
        })
        .collect()
}

fn eval(sum: &Resolved, values: &[f64], measures: &[Option<f64>]) -> Option<f64> {
    let mut total = 0.0;
    for (sign, op) in sum {
        total += sign
            * match op {
                Operand::Const(x) => *x,
                Operand::Slot(s) => *values.get(*s)?,
                Operand::Measure(m) => (*measures.get(*m)?)?,
            };
    }
    Some(total)
}

/// A measure resolved for one machine.
enum Probe {
    Count,
    /// The times the products of a stream reach their sensor.
    Passed(Vec<f64>),
    Final(usize),
    Max(usize),
    Min(usize),
    Value(Resolved),
}

/// An assertion resolved for one machine; `always` when it reads members only (checked after
/// every update), else checked at the end.
struct Check {
    left: Resolved,
    op: super::expr::Op,
    right: Resolved,
    always: bool,
}

/// The measures and assertions of `spec` against `registry`; the message says which name is
/// unknown, and where (the place of the measure or assertion).
fn compile(
    spec: &Spec,
    image: &crate::vm::MachineImage,
) -> Result<(Vec<Probe>, Vec<Check>), (Place, String)> {
    let registry = &image.registry;
    let mut probes = Vec::new();
    let names: Vec<&str> = spec.measures.iter().map(|m| m.name.as_str()).collect();
    for (i, m) in spec.measures.iter().enumerate() {
        let member = |n: &str| match resolve_name(registry, &[], n) {
            Ok(Operand::Slot(s)) => Ok(s),
            Ok(_) => Err((m.place.clone(), format!("`{n}` is not a member"))),
            Err(e) => Err((m.place.clone(), e)),
        };
        probes.push(match &m.kind {
            MeasureKind::Count { .. } => Probe::Count,
            MeasureKind::Passed(n) => match image.products.get(*n) {
                // Each product at the update that sees its edge (the first at or after it), as
                // the trace times its capture.
                Some((_, products)) => {
                    let tick = image.tick_ns as f64 / 1e9;
                    Probe::Passed(
                        products
                            .iter()
                            .map(|p| (p.on_at / tick - 1e-9).ceil() * tick)
                            .filter(|t| *t >= m.from - 1e-12)
                            .collect(),
                    )
                }
                None => {
                    return Err((
                        m.place.clone(),
                        format!(
                            "there is no products.{n}: the scenario has {} [[products]] entr{}",
                            image.products.len(),
                            if image.products.len() == 1 {
                                "y"
                            } else {
                                "ies"
                            }
                        ),
                    ))
                }
            },
            MeasureKind::Final(n) => Probe::Final(member(n)?),
            MeasureKind::Max(n) => Probe::Max(member(n)?),
            MeasureKind::Min(n) => Probe::Min(member(n)?),
            // Earlier measures only: no measure can read itself.
            MeasureKind::Value(sum) => Probe::Value(
                resolve_sum(registry, &names[..i], sum).map_err(|e| (m.place.clone(), e))?,
            ),
        });
    }
    let mut checks = Vec::new();
    for e in &spec.expects {
        let left =
            resolve_sum(registry, &names, &e.assertion.left).map_err(|m| (e.place.clone(), m))?;
        let right =
            resolve_sum(registry, &names, &e.assertion.right).map_err(|m| (e.place.clone(), m))?;
        let always = left
            .iter()
            .chain(&right)
            .all(|(_, o)| !matches!(o, Operand::Measure(_)));
        checks.push(Check {
            left,
            op: e.assertion.op,
            right,
            always,
        });
    }
    Ok((probes, checks))
}

/// Check the sweep against the machine before running it: the machine loads as it is; each
/// varied name exists (set to its first value, the files still read); each measure and
/// assertion names known members and measures. Problems are located where they were written.
pub fn check(spec: &Spec, base: &Base) -> Result<crate::load::Loaded, CheckError> {
    let loaded = base.load(&[]).map_err(CheckError::Machine)?;
    for (axis, value) in spec.axes.iter().zip(spec.variant(0)) {
        let shown = super::set::value_text(&value);
        match base.load(&[(axis.name.clone(), value)]) {
            Ok(_) => {}
            Err(SetError::Value(m)) => {
                return Err(CheckError::Spec(SpecError::at(
                    spec.file.as_ref(),
                    &axis.place,
                    m,
                    None,
                )))
            }
            Err(SetError::Load(d)) => {
                // A name the file does not take, or a value of the wrong type, is the sweep's
                // mistake; a value the machine refuses (products that overlap) is a variant
                // that fails, and the sweep runs.
                if let Some(p) = d.items.iter().find(|i| i.problem.code == "pacer::config") {
                    return Err(CheckError::Spec(SpecError::at(
                        spec.file.as_ref(),
                        &axis.place,
                        format!(
                            "{} = {shown} does not fit its file: {}",
                            axis.name.text, p.problem.message
                        ),
                        None,
                    )));
                }
            }
        }
    }
    compile(spec, &loaded.image).map_err(|(place, m)| {
        CheckError::Spec(SpecError::at(spec.file.as_ref(), &place, m, None))
    })?;
    if let Some(m) = &spec.plot.measure {
        if !spec.measures.iter().any(|x| &x.name == m) {
            return Err(CheckError::Spec(SpecError::Arg(format!(
                "sweep.toml [plot] measure: no measure named `{m}`"
            ))));
        }
    }
    for a in [&spec.plot.x, &spec.plot.y].into_iter().flatten() {
        if !spec.axes.iter().any(|x| &x.name.text == a) {
            return Err(CheckError::Spec(SpecError::Arg(format!(
                "sweep.toml [plot]: `{a}` is not a varied name"
            ))));
        }
    }
    Ok(loaded)
}

/// Why a sweep cannot start.
#[derive(Debug)]
pub enum CheckError {
    /// The machine itself does not load.
    Machine(SetError),
    /// The sweep's input is wrong.
    Spec(SpecError),
}

/// Run variant `index`.
pub fn run_variant(spec: &Spec, base: &Base, index: usize) -> VariantResult {
    let values = spec.variant(index);
    let mut result = VariantResult {
        index,
        values: values.clone(),
        end: String::new(),
        errors: 0,
        warnings: 0,
        measures: vec![None; spec.measures.len()],
        failed: Vec::new(),
        failed_at: None,
        message: None,
    };
    let assignments: Vec<_> = spec
        .axes
        .iter()
        .map(|a| a.name.clone())
        .zip(values)
        .collect();
    let loaded = match base.load(&assignments) {
        Ok(l) => l,
        Err(e) => {
            result.end = "load error".into();
            result.errors = e.error_count() as u64;
            result.message = Some(first_line(&match &e {
                SetError::Value(m) => m.clone(),
                SetError::Load(d) => d
                    .items
                    .iter()
                    .find(|i| i.problem.level == crate::diag::Level::Error)
                    .map(|i| i.problem.message.clone())
                    .unwrap_or_default(),
            }));
            result.failed.push("the variant loads".into());
            return result;
        }
    };
    result.warnings = loaded.warnings.items.len() as u64;
    let (probes, checks) = match compile(spec, &loaded.image) {
        Ok(c) => c,
        Err((_, m)) => {
            result.end = "load error".into();
            result.errors = 1;
            result.message = Some(m);
            result.failed.push("the variant loads".into());
            return result;
        }
    };
    // Event counts, shared with the trace's observer (the run is on this thread).
    let counts = Rc::new(RefCell::new(vec![0u64; spec.measures.len()]));
    let mut trace = Trace::new(None, loaded.image.tick_ns);
    let counted: Vec<Counted> = spec
        .measures
        .iter()
        .enumerate()
        .filter_map(|(i, m)| match &m.kind {
            MeasureKind::Count { kind, filter } => Some((i, *kind, filter.clone(), m.from)),
            _ => None,
        })
        .collect();
    if !counted.is_empty() {
        let counts = counts.clone();
        trace.observe(Box::new(move |t: f64, e: &Event<'_>| {
            let kind = e.kind();
            let mut fields: Option<serde_json::Value> = None;
            for (i, k, filter, from) in &counted {
                if *k != kind || t < *from {
                    continue;
                }
                if !filter.is_empty() {
                    let f =
                        fields.get_or_insert_with(|| serde_json::to_value(e).unwrap_or_default());
                    if !filter
                        .iter()
                        .all(|(name, want)| field_is(f.get(name), want))
                    {
                        continue;
                    }
                }
                if let Some(c) = counts.borrow_mut().get_mut(*i) {
                    *c += 1;
                }
            }
        }));
    }
    let mut machine = Machine::new(loaded.image, trace);
    let mut extremes: Vec<Option<f64>> = vec![None; probes.len()];
    let mut failed_always = vec![false; checks.len()];
    let mut failed_at: Option<f64> = None;
    let none: Vec<Option<f64>> = Vec::new();
    let summary = machine.run_observed(spec.duration_ns, &mut |m| {
        let v = m.values();
        for (p, slot) in probes.iter().zip(extremes.iter_mut()) {
            match p {
                Probe::Max(s) => {
                    let x = v.get(*s).copied().unwrap_or(f64::NAN);
                    *slot = Some(slot.map_or(x, |y| y.max(x)));
                }
                Probe::Min(s) => {
                    let x = v.get(*s).copied().unwrap_or(f64::NAN);
                    *slot = Some(slot.map_or(x, |y| y.min(x)));
                }
                _ => {}
            }
        }
        for (c, failed) in checks.iter().zip(failed_always.iter_mut()) {
            if c.always && !*failed {
                let holds = match (eval(&c.left, v, &none), eval(&c.right, v, &none)) {
                    (Some(a), Some(b)) => c.op.holds(a, b),
                    _ => false,
                };
                if !holds {
                    *failed = true;
                    failed_at.get_or_insert(m.time());
                }
            }
        }
    });
    let values = machine.values();
    let end = machine.time();
    let counts = counts.borrow();
    for (i, p) in probes.iter().enumerate() {
        let x = match p {
            Probe::Count => counts.get(i).map(|c| *c as f64),
            Probe::Passed(times) => {
                Some(times.iter().filter(|t| **t <= end + 1e-12).count() as f64)
            }
            Probe::Final(s) => values.get(*s).copied(),
            Probe::Max(_) | Probe::Min(_) => extremes[i],
            Probe::Value(sum) => eval(sum, values, &result.measures),
        };
        result.measures[i] = x.filter(|x| x.is_finite());
    }
    for ((c, e), failed) in checks.iter().zip(&spec.expects).zip(&failed_always) {
        let holds = if c.always {
            !failed
        } else {
            matches!(
                (eval(&c.left, values, &result.measures), eval(&c.right, values, &result.measures)),
                (Some(a), Some(b)) if c.op.holds(a, b)
            )
        };
        if !holds {
            result.failed.push(e.text.clone());
        }
    }
    result.failed_at = failed_at;
    let count = |k: &str| {
        summary
            .events
            .iter()
            .find(|(n, _)| n == k)
            .map_or(0, |(_, c)| *c)
    };
    result.warnings += count("warning") + count("pp_warning");
    result.errors = count("error") + count("pp_error");
    if let Some(e) = &summary.error {
        result.errors = result.errors.max(1);
        result.message = Some(first_line(&e.message));
    }
    result.end = summary.stop_reason.to_string();
    result
}

/// An event field against a wanted value: strings equal, numbers equal as numbers.
fn field_is(got: Option<&serde_json::Value>, want: &serde_json::Value) -> bool {
    match (got, want) {
        (Some(serde_json::Value::Number(a)), serde_json::Value::Number(b)) => {
            a.as_f64() == b.as_f64()
        }
        (Some(a), b) => a == b,
        (None, _) => false,
    }
}

fn first_line(text: &str) -> String {
    text.lines().next().unwrap_or_default().trim().to_string()
}

/// The most runs at once (`--jobs` above it is held to it).
pub const MAX_JOBS: usize = 256;

/// Run the variants `indices` on `jobs` threads; `progress(done, total)` after each. The
/// results are in the order of `indices`.
pub fn run_all(
    spec: &Spec,
    base: &Base,
    indices: &[usize],
    jobs: usize,
    progress: &mut dyn FnMut(usize, usize),
) -> Vec<VariantResult> {
    let total = indices.len();
    let mut slots: Vec<Option<VariantResult>> = vec![None; total];
    let next = AtomicUsize::new(0);
    let (tx, rx) = std::sync::mpsc::channel::<(usize, VariantResult)>();
    std::thread::scope(|scope| {
        // No more threads than variants, nor than a machine could hold.
        for _ in 0..jobs.clamp(1, total.clamp(1, MAX_JOBS)) {
            let tx = tx.clone();
            let next = &next;
            scope.spawn(move || loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(&index) = indices.get(k) else {
                    break;
                };
                if tx.send((k, run_variant(spec, base, index))).is_err() {
                    break;
                }
            });
        }
        drop(tx);
        let mut done = 0;
        for (k, r) in rx {
            if let Some(s) = slots.get_mut(k) {
                *s = Some(r);
            }
            done += 1;
            progress(done, total);
        }
    });
    slots.into_iter().flatten().collect()
}
