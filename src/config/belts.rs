//! The scenario's belts and workpiece streams: `[[belts]]` speed profiles checked against the
//! machine's belts and their drive limits, and `[[workpieces]]` streams expanded into the feeds
//! the pick & place module receives. Every problem points at the value in `scenario.toml` that
//! causes it.

use crate::config::scenario::{BeltEntry, ScenarioFile, WorkpiecesEntry};
use crate::config::span_of;
use crate::devices::pickplace::setup::{AxisLimit, BeltSetup};
use crate::diag::Problem;
use crate::world::belt::{BeltChange, BeltProfile};
use crate::world::workpieces::{feeds, Stream, WorkpieceFeed};
use indexmap::IndexMap;
use toml::Spanned;

/// Most detections one `[[workpieces]]` entry may have (memory stays bounded whatever the file
/// says).
pub const MAX_WORKPIECES: u32 = 1_000_000;

/// Code of problems with `[[belts]]`.
const BELTS: &str = "pacer::scenario::belts";
/// Code of problems with `[[workpieces]]`.
const WORKPIECES: &str = "pacer::scenario::workpieces";

/// Limits are compared with this much slack so a ramp exactly at a limit is not refused for a
/// rounding of the seconds the scenario's nanoseconds become.
const SLACK: f64 = 1e-9;

/// What the scenario makes of the pick & place belts.
#[derive(Debug, Clone, Default)]
pub struct BeltWorld {
    /// One profile per machine belt, in machine order; a belt the scenario does not drive (or
    /// whose entry has errors) stands still.
    pub profiles: IndexMap<u32, BeltProfile>,
    /// All streams' workpieces merged, sorted by (receive, belt, id).
    pub feeds: Vec<WorkpieceFeed>,
}

/// The belts and workpiece streams of `sc`, checked against the machine's belts `setups`.
pub fn belts(sc: &ScenarioFile, setups: &[BeltSetup], problems: &mut Vec<Problem>) -> BeltWorld {
    let mut profiles: IndexMap<u32, BeltProfile> = setups
        .iter()
        .map(|s| (s.number, BeltProfile::stopped()))
        .collect();
    let mut driven: Vec<u32> = Vec::new();
    for e in &sc.belts {
        let Some(setup) = machine_belt(&e.belt, setups, BELTS, problems) else {
            continue;
        };
        if driven.contains(&setup.number) {
            problems.push(
                Problem::error(
                    BELTS,
                    span_of(&e.belt),
                    format!(
                        "belt {} is already driven by an earlier [[belts]] entry",
                        setup.number
                    ),
                    "second entry for this belt",
                )
                .with_help("put all of a belt's speed changes into one [[belts]] entry"),
            );
            continue;
        }
        driven.push(setup.number);
        if let Some(profile) = profile(e, setup, problems) {
            profiles.insert(setup.number, profile);
        }
    }
    let mut all = Vec::new();
    // Ids already given on each belt: a second stream on a belt continues after the first.
    let mut next_id: IndexMap<u32, u32> = IndexMap::new();
    for w in &sc.workpieces {
        let Some(setup) = machine_belt(&w.belt, setups, WORKPIECES, problems) else {
            continue;
        };
        let Some(stream) = stream(w, setup.number, problems) else {
            continue;
        };
        let stopped = BeltProfile::stopped();
        let profile = profiles.get(&setup.number).unwrap_or(&stopped);
        let offset = next_id.entry(setup.number).or_insert(0);
        all.extend(feeds(&stream, profile).into_iter().map(|mut f| {
            f.id = f.id.saturating_add(*offset);
            f
        }));
        let n = u32::try_from(stream.travel.len()).unwrap_or(u32::MAX);
        *offset = offset.saturating_add(n);
    }
    all.sort_by(|a, b| {
        a.receive
            .total_cmp(&b.receive)
            .then(a.belt.cmp(&b.belt))
            .then(a.id.cmp(&b.id))
    });
    BeltWorld {
        profiles,
        feeds: all,
    }
}

/// The machine's setup of the belt `belt` names, or a problem saying which belts there are.
fn machine_belt<'a>(
    belt: &Spanned<u32>,
    setups: &'a [BeltSetup],
    code: &'static str,
    problems: &mut Vec<Problem>,
) -> Option<&'a BeltSetup> {
    let n = *belt.get_ref();
    let found = setups.iter().find(|s| s.number == n);
    if found.is_none() {
        let help = if setups.is_empty() {
            "the machine has no belts: declare them in [pickplace] of machine.toml".to_string()
        } else {
            let list: Vec<String> = setups.iter().map(|s| s.number.to_string()).collect();
            format!(
                "the machine has belt{} {}",
                plural(setups.len()),
                list.join(", ")
            )
        };
        problems.push(
            Problem::error(
                code,
                span_of(belt),
                format!("belt {n} is not a belt of this machine"),
                "no such belt",
            )
            .with_help(help),
        );
    }
    found
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// A number as a person would write it: at most three decimals, no trailing zeros.
fn num(x: f64) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    let s = format!("{x:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

fn seconds(ns: u64) -> f64 {
    ns as f64 / 1e9
}

/// The shortest ramp that keeps a speed change of `dv` inside `limit`'s acceleration and jerk.
fn shortest_ramp(dv: f64, limit: &AxisLimit) -> f64 {
    let mut t = 0.0f64;
    if limit.max_acc > 0.0 {
        t = t.max(2.0 * dv / limit.max_acc);
    }
    if limit.max_jerk > 0.0 {
        t = t.max(2.0 * (dv / limit.max_jerk).sqrt());
    }
    // Round up to the millisecond so the suggested value passes.
    (t * 1000.0).ceil() / 1000.0
}

/// The profile of one `[[belts]]` entry, or `None` (with problems) if it is not valid.
fn profile(e: &BeltEntry, setup: &BeltSetup, problems: &mut Vec<Problem>) -> Option<BeltProfile> {
    let before = problems.len();
    let n = setup.number;
    let limit = setup.limit;
    let over = |x: f64, max: f64| max > 0.0 && x > max * (1.0 + SLACK);
    let initial = e.speed.as_ref().map_or(0.0, |s| *s.get_ref());
    if let Some(s) = &e.speed {
        if !(initial.is_finite() && initial >= 0.0) {
            problems.push(
                Problem::error(
                    BELTS,
                    span_of(s),
                    format!("the speed must be a finite number of mm/s, 0 or more, not {initial}"),
                    "invalid speed",
                )
                .with_help("a belt runs forward or stands still"),
            );
        } else if over(initial, limit.max_vel) {
            problems.push(Problem::error(
                BELTS,
                span_of(s),
                format!(
                    "the belt starts at {} mm/s but belt {n} allows {} (max_vel)",
                    num(initial),
                    num(limit.max_vel)
                ),
                "too fast",
            ));
        }
    }
    let mut speed = if initial.is_finite() && initial >= 0.0 {
        initial
    } else {
        0.0
    };
    let mut changes = Vec::with_capacity(e.changes.len());
    let mut previous: Option<(u64, u64)> = None;
    for (i, c) in e.changes.iter().enumerate() {
        let ch = c.get_ref();
        let name = format!(
            "change {} (at {} s)",
            i + 1,
            num(seconds(ch.at.get_ref().0))
        );
        let at = ch.at.get_ref().0;
        let ramp = ch.ramp.as_ref().map_or(0, |r| r.get_ref().0);
        if let Some((prev_at, busy)) = previous {
            let problem = if at < prev_at {
                Some((
                    format!(
                        "{name} comes before the previous change (at {} s)",
                        num(seconds(prev_at))
                    ),
                    "out of order",
                    "list a belt's changes in time order".to_string(),
                ))
            } else if at == prev_at {
                Some((
                    format!("{name} starts at the same instant as the previous change"),
                    "same instant",
                    "only the later of the two would ever take effect: remove one".to_string(),
                ))
            } else if at < busy {
                Some((
                    format!(
                        "{name} starts before the previous ramp has finished (at {} s)",
                        num(seconds(busy))
                    ),
                    "overlaps the previous ramp",
                    format!(
                        "start it at {} s or later, or shorten the previous ramp",
                        num(seconds(busy))
                    ),
                ))
            } else {
                None
            };
            if let Some((message, label, help)) = problem {
                problems
                    .push(Problem::error(BELTS, span_of(&ch.at), message, label).with_help(help));
            }
        }
        previous = Some((at, at.saturating_add(ramp)));
        let target = *ch.speed.get_ref();
        if !(target.is_finite() && target >= 0.0) {
            problems.push(
                Problem::error(
                    BELTS,
                    span_of(&ch.speed),
                    format!("the speed must be a finite number of mm/s, 0 or more, not {target}"),
                    "invalid speed",
                )
                .with_help("a belt runs forward or stands still; 0 stops it"),
            );
            continue;
        }
        if over(target, limit.max_vel) {
            problems.push(Problem::error(
                BELTS,
                span_of(&ch.speed),
                format!(
                    "{name} runs belt {n} at {} mm/s but belt {n} allows {} (max_vel)",
                    num(target),
                    num(limit.max_vel)
                ),
                "too fast",
            ));
        }
        let dv = (target - speed).abs();
        if dv > 0.0 {
            // Point at the ramp if it is written, else at the whole change that lacks one.
            let span = ch.ramp.as_ref().map_or_else(|| span_of(c), span_of);
            let help = format!(
                "give this change a ramp of at least {} s",
                num(shortest_ramp(dv, &limit))
            );
            if ramp == 0 {
                let which = if limit.max_acc > 0.0 {
                    Some(("acceleration", "mm/s²", limit.max_acc, "max_acc"))
                } else if limit.max_jerk > 0.0 {
                    Some(("jerk", "mm/s³", limit.max_jerk, "max_jerk"))
                } else {
                    None
                };
                if let Some((what, unit, max, key)) = which {
                    problems.push(
                        Problem::error(
                            BELTS,
                            span,
                            format!(
                                "{name} steps the speed from {} to {} mm/s at once, an infinite {what}, but belt {n} allows {} {unit} ({key})",
                                num(speed),
                                num(target),
                                num(max)
                            ),
                            "no ramp",
                        )
                        .with_help(help),
                    );
                }
            } else {
                let t = seconds(ramp);
                let acc = 2.0 * dv / t;
                let jerk = 4.0 * dv / (t * t);
                if over(acc, limit.max_acc) {
                    problems.push(
                        Problem::error(
                            BELTS,
                            span,
                            format!(
                                "this ramp accelerates at {} mm/s² but belt {n} allows {} (max_acc)",
                                num(acc),
                                num(limit.max_acc)
                            ),
                            format!("{name}: too steep"),
                        )
                        .with_help(help.clone()),
                    );
                }
                if over(jerk, limit.max_jerk) {
                    problems.push(
                        Problem::error(
                            BELTS,
                            span,
                            format!(
                                "this ramp jerks at {} mm/s³ but belt {n} allows {} (max_jerk)",
                                num(jerk),
                                num(limit.max_jerk)
                            ),
                            format!("{name}: too abrupt"),
                        )
                        .with_help(help),
                    );
                }
            }
        }
        speed = target;
        changes.push(BeltChange {
            at: seconds(at),
            speed: target,
            ramp: seconds(ramp),
        });
    }
    if problems.len() > before {
        return None;
    }
    match BeltProfile::new(initial, &changes) {
        Ok(p) => Some(p),
        Err(err) => {
            // Checked above already; this only guards against the two checks drifting apart.
            let span = e
                .changes
                .get(err.change)
                .map_or_else(|| span_of(&e.belt), span_of);
            problems.push(Problem::error(BELTS, span, err.message, "here"));
            None
        }
    }
}

/// Reports a problem at `span` unless `x` is a finite number of at least `min` (if any).
fn check_number(
    x: &Spanned<f64>,
    min: Option<f64>,
    what: &str,
    problems: &mut Vec<Problem>,
) -> bool {
    let v = *x.get_ref();
    let ok = v.is_finite() && min.is_none_or(|m| v >= m);
    if !ok {
        let message = match min {
            Some(m) => format!(
                "{what} must be a finite number, {} or more, not {v}",
                num(m)
            ),
            None => format!("{what} must be a finite number, not {v}"),
        };
        problems.push(Problem::error(WORKPIECES, span_of(x), message, "invalid"));
    }
    ok
}

/// The stream of one `[[workpieces]]` entry, or `None` (with problems) if it is not valid.
fn stream(w: &WorkpiecesEntry, belt: u32, problems: &mut Vec<Problem>) -> Option<Stream> {
    let before = problems.len();
    let sequence = w.first.is_some() || w.pitch.is_some() || w.count.is_some();
    let mut travel: Vec<f64> = match (&w.at, sequence) {
        (Some(at), true) => {
            problems.push(
                Problem::error(
                    WORKPIECES,
                    span_of(at),
                    "the detections are given twice: as `at` and as `first`/`pitch`/`count`",
                    "remove this or first/pitch/count",
                )
                .with_help("give either `at = [...]` or `first`, `pitch` and `count`, not both"),
            );
            Vec::new()
        }
        (None, false) => {
            problems.push(
                Problem::error(
                    WORKPIECES,
                    span_of(&w.belt),
                    "say where the workpieces are detected",
                    "these workpieces",
                )
                .with_help(
                    "give `first`, `pitch` and `count` (belt travel in mm), or `at = [...]`",
                ),
            );
            Vec::new()
        }
        (Some(at), false) => explicit(at, problems),
        (None, true) => sequence_travel(w, problems),
    };
    // Missing indices are only checked against a valid list of detections.
    let listed = problems.len() == before;
    for m in &w.missing {
        let i = *m.get_ref();
        if listed && i as usize >= travel.len() {
            problems.push(
                Problem::error(
                    WORKPIECES,
                    span_of(m),
                    format!(
                        "workpiece {i} cannot be missing: the stream has {} (indices 0 to {})",
                        travel.len(),
                        travel.len().saturating_sub(1)
                    ),
                    "no such workpiece",
                )
                .with_help("missing indices count from 0"),
            );
        }
    }
    let detect = w.detect.as_ref().map_or([0.0; 3], |d| *d.get_ref());
    if let Some(d) = &w.detect {
        if detect.iter().any(|x| !x.is_finite()) {
            problems.push(Problem::error(
                WORKPIECES,
                span_of(d),
                "the detection position must be three finite numbers (X, Y, Z in mm)",
                "invalid",
            ));
        }
    }
    let c = match &w.c {
        Some(c) if check_number(c, None, "C", problems) => *c.get_ref(),
        _ => 0.0,
    };
    let mut jitter = [0.0; 3];
    if let Some(j) = &w.jitter {
        for (k, (amp, what)) in [
            (&j.x, "the X jitter"),
            (&j.y, "the Y jitter"),
            (&j.c, "the C jitter"),
        ]
        .into_iter()
        .enumerate()
        {
            if let Some(a) = amp {
                if check_number(a, Some(0.0), what, problems) {
                    jitter[k] = *a.get_ref();
                }
            }
        }
    }
    if problems.len() > before {
        return None;
    }
    if !w.missing.is_empty() {
        let mut keep = vec![true; travel.len()];
        for m in &w.missing {
            if let Some(k) = keep.get_mut(*m.get_ref() as usize) {
                *k = false;
            }
        }
        let mut flags = keep.into_iter();
        travel.retain(|_| flags.next().unwrap_or(true));
    }
    Some(Stream {
        belt,
        travel,
        detect,
        jitter,
        c,
        delay: w.delay.as_ref().map_or(0.0, |d| seconds(d.get_ref().0)),
        seed: w.seed,
    })
}

/// Detection travels from an explicit `at` list; a problem points at the first bad element.
fn explicit(at: &Spanned<Vec<Spanned<f64>>>, problems: &mut Vec<Problem>) -> Vec<f64> {
    let list = at.get_ref();
    let help = "list the belt travels (mm) at which the detector sees each workpiece, ascending";
    let problem = if list.is_empty() {
        Some((
            span_of(at),
            "an empty list detects no workpieces".to_string(),
        ))
    } else if list.len() > MAX_WORKPIECES as usize {
        Some((
            span_of(at),
            format!(
                "{} detections; at most {MAX_WORKPIECES} per entry",
                list.len()
            ),
        ))
    } else if let Some(x) = list
        .iter()
        .find(|x| !(x.get_ref().is_finite() && *x.get_ref() >= 0.0))
    {
        Some((
            span_of(x),
            format!(
                "{} is not a belt travel: detections must be finite, 0 mm or more (the belt's travel is 0 when the run starts)",
                x.get_ref()
            ),
        ))
    } else {
        list.windows(2)
            .find(|w| w[1].get_ref() <= w[0].get_ref())
            .map(|w| {
                (
                    span_of(&w[1]),
                    format!(
                        "the detections must be in increasing order, but {} follows {}",
                        num(*w[1].get_ref()),
                        num(*w[0].get_ref())
                    ),
                )
            })
    };
    match problem {
        Some((span, message)) => {
            problems.push(
                Problem::error(WORKPIECES, span, message, "not a valid detection").with_help(help),
            );
            Vec::new()
        }
        None => list.iter().map(|x| *x.get_ref()).collect(),
    }
}

/// Detection travels from `first`, `pitch` and `count`.
fn sequence_travel(w: &WorkpiecesEntry, problems: &mut Vec<Problem>) -> Vec<f64> {
    let before = problems.len();
    let first = match &w.first {
        Some(f) if check_number(f, Some(0.0), "the first detection's belt travel", problems) => {
            *f.get_ref()
        }
        _ => 0.0,
    };
    let pitch = match &w.pitch {
        Some(p) => {
            let v = *p.get_ref();
            if !(v.is_finite() && v > 0.0) {
                problems.push(
                    Problem::error(
                        WORKPIECES,
                        span_of(p),
                        format!("the pitch must be a positive number of mm, not {v}"),
                        "not positive",
                    )
                    .with_help("the belt travel from one detection to the next"),
                );
            }
            v
        }
        None => {
            problems.push(
                Problem::error(
                    WORKPIECES,
                    span_of(&w.belt),
                    "`pitch` is missing: the belt travel from one detection to the next",
                    "these workpieces",
                )
                .with_help("give `first`, `pitch` and `count` together"),
            );
            0.0
        }
    };
    let count = match &w.count {
        Some(c) => {
            let n = *c.get_ref();
            if n == 0 || n > MAX_WORKPIECES {
                problems.push(Problem::error(
                    WORKPIECES,
                    span_of(c),
                    format!("{n} workpieces; give 1 to {MAX_WORKPIECES}"),
                    "out of range",
                ));
            }
            n
        }
        None => {
            problems.push(
                Problem::error(
                    WORKPIECES,
                    span_of(&w.belt),
                    "`count` is missing: how many workpieces the detector reports",
                    "these workpieces",
                )
                .with_help("give `first`, `pitch` and `count` together"),
            );
            0
        }
    };
    if problems.len() > before {
        return Vec::new();
    }
    // Each travel from its index, not by adding pitches, so no rounding accumulates.
    (0..count).map(|k| first + f64::from(k) * pitch).collect()
}
