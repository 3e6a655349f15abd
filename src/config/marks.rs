//! The scenario's printed marks: explicit mark positions on a DSP axis, from a pitch that
//! drifts and steps, seeded print jitter and spurious marks.

use crate::config::scenario::PrintedMarks;
use crate::config::span_of;
use crate::devices::orion::dsp::Sensor;
use crate::devices::orion::{MarkInput, MarkTrack};
use crate::diag::Problem;
use crate::world::products::unit;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Most marks one `[[marks]]` entry may lay.
pub const MAX_MARKS: u32 = 1_000_000;

/// The mark tracks of `entries`, checked against the DSP axes `axes` of the machine.
pub fn tracks(
    entries: &[PrintedMarks],
    axes: &[u32],
    problems: &mut Vec<Problem>,
) -> Vec<MarkTrack> {
    let mut out = Vec::new();
    for e in entries {
        let before = problems.len();
        let axis = *e.axis.get_ref();
        if !axes.contains(&axis) {
            problems.push(
                Problem::error(
                    "pacer::scenario::marks",
                    span_of(&e.axis),
                    format!("axis {axis} is not a DSP axis of this machine"),
                    "no such axis",
                )
                .with_help(format!("machine.toml defines axes {axes:?}")),
            );
        }
        let input = match e.sensor.as_ref().map(|s| s.get_ref().to_ascii_uppercase()) {
            None => MarkInput::Card(Sensor::Asen),
            Some(s) if s == "ASEN" => MarkInput::Card(Sensor::Asen),
            Some(s) if s == "BSEN" => MarkInput::Card(Sensor::Bsen),
            Some(s) if s == "ZREF" => MarkInput::Card(Sensor::Zref),
            Some(s) if s == "FAST" => MarkInput::Fast {
                on_time: e
                    .on_time
                    .as_ref()
                    .map_or(1e-3, |d| d.get_ref().0 as f64 / 1e9),
            },
            Some(s) => {
                if let Some(span) = e.sensor.as_ref().map(span_of) {
                    problems.push(Problem::error(
                        "pacer::scenario::marks",
                        span,
                        format!("`{s}` is not an input marks can drive"),
                        "ASEN, BSEN, ZREF or FAST",
                    ));
                }
                MarkInput::Card(Sensor::Asen)
            }
        };
        if let (Some(d), false) = (&e.on_time, matches!(input, MarkInput::Fast { .. })) {
            problems.push(Problem::error(
                "pacer::scenario::marks",
                span_of(d),
                "on_time is for a fast input (sensor = \"FAST\")",
                "not used here",
            ));
        }
        let span = span_of(&e.axis);
        let (pitch, count) = match (&e.at, &e.pitch, &e.count) {
            (Some(_), None, None) => (0.0, 0),
            (None, Some(p), Some(c)) => {
                if !(p.get_ref().is_finite() && *p.get_ref() > 0.0) {
                    problems.push(Problem::error(
                        "pacer::scenario::marks",
                        span_of(p),
                        "the pitch must be a positive number",
                        "not positive",
                    ));
                }
                let n = *c.get_ref();
                if n == 0 || n > MAX_MARKS {
                    problems.push(Problem::error(
                        "pacer::scenario::marks",
                        span_of(c),
                        format!("{n} marks"),
                        format!("1 to {MAX_MARKS}"),
                    ));
                }
                (*p.get_ref(), n)
            }
            _ => {
                problems.push(
                    Problem::error(
                        "pacer::scenario::marks",
                        span,
                        "say where the marks are: `at = [...]`, or `first`, `pitch` and `count`",
                        "these marks",
                    )
                    .with_help("give one of the two, not both"),
                );
                (0.0, 0)
            }
        };
        if let Some(at) = &e.at {
            let list = at.get_ref();
            if list.is_empty()
                || list.len() > MAX_MARKS as usize
                || list.iter().any(|x| !x.is_finite())
                || list.windows(2).any(|w| w[1] <= w[0])
            {
                problems.push(Problem::error(
                    "pacer::scenario::marks",
                    span_of(at),
                    "mark positions must be finite numbers in increasing order",
                    "not increasing",
                ));
            }
        }
        let width = e.width.as_ref().map_or(50.0, |w| *w.get_ref());
        let jitter = e.jitter.as_ref().map_or(0.0, |j| *j.get_ref());
        if let Some(j) = &e.jitter {
            if !(jitter.is_finite() && jitter >= 0.0) {
                problems.push(Problem::error(
                    "pacer::scenario::marks",
                    span_of(j),
                    "the jitter must be 0 or more",
                    "negative",
                ));
            }
        }
        if problems.len() > before {
            continue;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(e.seed);
        let mut positions = e.at.as_ref().map_or_else(Vec::new, |a| a.get_ref().clone());
        let mut nominal = e.first;
        let mut p = pitch;
        // The step of each mark, looked up by mark number: the last step written for a mark
        // wins (a long `steps` list must not cost its length for every mark).
        let steps: std::collections::HashMap<u32, f64> =
            e.steps.iter().map(|s| (s.at, s.pitch)).collect();
        for k in 0..count {
            if let Some(step) = steps.get(&k) {
                p = *step;
            }
            positions.push(nominal + jitter * unit(&mut rng));
            if let Some(sp) = &e.spurious {
                let every = *sp.every.get_ref();
                if every > 0 && (k + 1) % every == 0 {
                    positions.push(nominal + *sp.offset.get_ref());
                }
            }
            nominal += p;
            p += e.drift;
        }
        positions.sort_by(f64::total_cmp);
        let min_gap = positions
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        let fast = matches!(input, MarkInput::Fast { .. });
        let fits = width.is_finite() && width > 0.0 && width < min_gap;
        if !fast && !fits {
            let span = e.width.as_ref().map_or(span, span_of);
            problems.push(
                Problem::error(
                    "pacer::scenario::marks",
                    span,
                    format!("marks of width {width} overlap (the closest are {min_gap:.3} apart)"),
                    "marks must not touch",
                )
                .with_help(
                    "make the marks narrower, the jitter smaller or the spurious offset larger",
                ),
            );
            continue;
        }
        out.push(MarkTrack {
            axis,
            input,
            positions,
            width,
        });
    }
    out
}
