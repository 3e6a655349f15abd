//! The scenario's world: input edges from levels, presses, pulse trains and product streams,
//! and the master axis, each checked with errors that point into `scenario.toml`.

use super::limits::{thousands, MAX_BOUNCES, MAX_STREAM, MAX_TIME_NS};
use super::links::resolve_text;
use crate::config::scenario::ScenarioFile;
use crate::config::span_of;
use crate::devices::drive::AxisMarks;
use crate::diag::{nearest, Problem};
use crate::registry::{Kind, Registry};
use crate::span::Span;
use crate::world::master::{MasterProfile, SpeedChange};
use crate::world::products::{Bounce, Product, ProductStream};
use crate::world::Edge;

/// The world a scenario describes: input edges (presses, pulses, levels, product streams) and
/// the master axis. Problems are reported against the scenario file.
pub fn world(sc: &ScenarioFile, reg: &Registry, problems: &mut Vec<Problem>) -> World {
    let master = master_profile(sc, problems);
    let mut edges = Vec::new();
    let input = |name: &toml::Spanned<String>, problems: &mut Vec<Problem>| -> Option<u32> {
        let r = resolve_text(reg, name, problems)?;
        let is_input = matches!(r.kind, Kind::DriveInput | Kind::ModuleInput)
            || (r.kind == Kind::DriveIO && r.name.ends_with(".In"));
        if !is_input {
            let inputs = ["DriveInput.1", "ModuleInput.1", "DriveIO.1.In"];
            problems.push(
                Problem::error(
                    "pacer::scenario::input",
                    span_of(name),
                    format!("{} is not an input the world can drive", r.name),
                    "not an input",
                )
                .with_help_opt(
                    nearest(name.get_ref(), inputs).map(|n| format!("inputs look like `{n}`")),
                ),
            );
            return None;
        }
        Some(r.slot)
    };
    for c in &sc.inputs {
        if let Some(slot) = input(&c.name, problems) {
            edges.push(Edge {
                at: seconds(c.at.get_ref().0),
                slot,
                on: c.value.get_ref().0,
            });
        }
    }
    let mut presses: Vec<(u32, u64, u64, Span)> = Vec::new();
    for p in &sc.presses {
        let Some(slot) = input(&p.name, problems) else {
            continue;
        };
        let (at, len) = (p.at.get_ref().0, p.length.get_ref().0);
        if len == 0 {
            problems.push(Problem::error(
                "pacer::scenario::press",
                span_of(&p.length),
                "a press of length 0 never happens",
                "must be longer than 0",
            ));
            continue;
        }
        presses.push((slot, at, at + len, span_of(&p.at)));
    }
    for p in &sc.pulses {
        let Some(slot) = input(&p.name, problems) else {
            continue;
        };
        let (start, period, width, count) = (
            p.start.get_ref().0,
            p.period.get_ref().0,
            p.width.get_ref().0,
            *p.count.get_ref(),
        );
        if width == 0 || width >= period {
            problems.push(Problem::error(
                "pacer::scenario::pulses",
                span_of(&p.width),
                "the pulse width must be above 0 and below the period",
                "invalid width",
            ));
            continue;
        }
        if count > MAX_STREAM {
            problems.push(Problem::error(
                "pacer::scenario::pulses",
                span_of(&p.count),
                "at most 10,000,000 pulses per train",
                "too many",
            ));
            continue;
        }
        // The last pulse must end inside the longest time a file may give.
        let end = u128::from(start) + u128::from(count) * u128::from(period);
        if end > u128::from(MAX_TIME_NS) {
            problems.push(Problem::error(
                "pacer::scenario::pulses",
                span_of(&p.count),
                "this pulse train ends after 1,000,000 s, the longest time a scenario may give",
                "too long",
            ));
            continue;
        }
        for k in 0..u64::from(count) {
            let at = start + k * period;
            presses.push((slot, at, at + width, span_of(&p.start)));
        }
    }
    presses.sort_by_key(|p| (p.0, p.1));
    for w in presses.windows(2) {
        if w[0].0 == w[1].0 && w[1].1 <= w[0].2 {
            problems.push(
                Problem::error(
                    "pacer::scenario::overlap",
                    w[1].3,
                    "this press overlaps (or touches) the previous press of the same input",
                    "overlaps",
                )
                .with_help(format!(
                    "the previous press lasts until {} s",
                    w[0].2 as f64 / 1e9
                )),
            );
        }
    }
    for (slot, on, off, _) in presses {
        edges.push(Edge {
            at: seconds(on),
            slot,
            on: true,
        });
        edges.push(Edge {
            at: seconds(off),
            slot,
            on: false,
        });
    }
    let product_lists = products(sc, &master, &input, &mut edges, problems);
    let mut marks = Vec::new();
    for m in &sc.axis_marks {
        let Some(slot) = input(&m.sensor, problems) else {
            continue;
        };
        let ok = [m.first, m.pitch, m.width].iter().all(|x| x.is_finite())
            && m.pitch >= 0.0
            && m.width > 0.0
            && (m.count <= 1 || m.width < m.pitch);
        if !ok {
            problems.push(Problem::error(
                "pacer::scenario::axis_marks",
                span_of(&m.sensor),
                "marks need a width above 0, a pitch of 0 or more, and (with several marks) a width below the pitch",
                "these marks",
            ));
            continue;
        }
        marks.push(AxisMarks {
            slot,
            first: m.first,
            pitch: m.pitch,
            count: m.count,
            width: m.width,
        });
    }
    World {
        edges,
        master,
        marks,
        products: product_lists,
    }
}

/// What a scenario makes of the world.
pub struct World {
    /// Input edges in any order.
    pub edges: Vec<Edge>,
    /// The master axis.
    pub master: MasterProfile,
    /// Sensors tied to the servo axis.
    pub marks: Vec<AxisMarks>,
    /// The products of each stream, with the sensor they pass.
    pub products: Vec<(u32, Vec<Product>)>,
}

fn seconds(ns: u64) -> f64 {
    ns as f64 / 1e9
}

/// The master axis from `[master]`.
fn master_profile(sc: &ScenarioFile, problems: &mut Vec<Problem>) -> MasterProfile {
    let changes: Vec<SpeedChange> = sc
        .master
        .changes
        .iter()
        .map(|c| {
            let c = c.get_ref();
            SpeedChange {
                at: seconds(c.at.0),
                speed: c.speed,
                ramp: c.ramp.map_or(0.0, |r| seconds(r.0)),
            }
        })
        .collect();
    let initial = sc.master.speed.as_ref().map_or(0.0, |s| *s.get_ref());
    match MasterProfile::new(initial, &changes) {
        Ok(m) => m,
        Err(e) => {
            let span = match sc.master.changes.get(e.change) {
                Some(c) => span_of(c),
                None => sc.master.speed.as_ref().map_or(Span::new(0, 0), span_of),
            };
            problems.push(Problem::error(
                "pacer::scenario::master",
                span,
                e.message,
                "here",
            ));
            MasterProfile::default()
        }
    }
}

/// Resolves a scenario input name to its slot, reporting problems.
type InputResolver<'a> = dyn Fn(&toml::Spanned<String>, &mut Vec<Problem>) -> Option<u32> + 'a;

/// Product streams: their sensor edges, bounces included.
fn products(
    sc: &ScenarioFile,
    master: &MasterProfile,
    input: &InputResolver<'_>,
    edges: &mut Vec<Edge>,
    problems: &mut Vec<Problem>,
) -> Vec<(u32, Vec<Product>)> {
    let mut lists = Vec::new();
    let seed = sc.run.seed.unwrap_or(1);
    for (i, p) in sc.products.iter().enumerate() {
        let Some(slot) = input(&p.sensor, problems) else {
            continue;
        };
        if let Some(b) = &p.bounce {
            let n = *b.count.get_ref();
            if n > MAX_BOUNCES {
                problems.push(
                    Problem::error(
                        "pacer::scenario::products",
                        span_of(&b.count),
                        format!(
                            "{} bounces after each edge is too many: at most {}",
                            thousands(u64::from(n)),
                            thousands(u64::from(MAX_BOUNCES))
                        ),
                        "too many",
                    )
                    .with_help("contact bounce is a handful of short excursions; each is kept in memory for the run"),
                );
                continue;
            }
        }
        let stream = ProductStream {
            first: p.first,
            pitch: p.pitch,
            length: p.length,
            jitter: p.jitter,
            count: p.count,
            missing: p.missing.clone(),
            bounce: p.bounce.as_ref().map(|b| Bounce {
                count: *b.count.get_ref(),
                width: seconds(b.width.0),
                gap: seconds(b.gap.0),
                trailing: b.trailing,
            }),
        };
        if let Err(message) = stream.validate() {
            problems.push(Problem::error(
                "pacer::scenario::products",
                span_of(&p.sensor),
                message,
                "this product stream",
            ));
            continue;
        }
        if p.count > MAX_STREAM {
            problems.push(Problem::error(
                "pacer::scenario::products",
                span_of(&p.sensor),
                "at most 10,000,000 products per stream",
                "too many",
            ));
            continue;
        }
        // Each stream draws from its own sequence, so adding a stream changes no other.
        let list = stream.products(
            master,
            seed.wrapping_add((i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)),
        );
        for e in stream.edges(&list) {
            edges.push(Edge {
                at: e.at,
                slot,
                on: e.on,
            });
        }
        lists.push((slot, list));
    }
    lists
}
