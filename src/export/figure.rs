//! What each picture shows, per machine: from a [`Recording`] to charts ready to draw. No
//! drawing here (that is `plot.rs`), only the choice of data, labels and units.

use super::record::{Preset, Recording, MASTER_POSITION, PP_CYCLES, SERVO_POSITION, TOOL_XYZ};
use super::series::Series;
use super::signals::unit_of;

/// A point of a chart: horizontal, vertical.
pub type Point = (f64, f64);

/// How a trace is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A solid line.
    Line,
    /// A dashed line (set points).
    Dashed,
    /// Dots (measurements, events).
    Dots,
    /// Triangles (picks; values clipped at the edge).
    Triangles,
    /// Squares (places).
    Squares,
}

/// One named set of points.
#[derive(Debug, Clone)]
pub struct Trace {
    /// Legend text.
    pub label: String,
    /// The points.
    pub points: Vec<(f64, f64)>,
    /// How they are drawn.
    pub style: Style,
    /// Colour, an index into the palette.
    pub color: usize,
}

/// One chart of a figure.
#[derive(Debug, Clone, Default)]
pub struct Chart {
    /// Caption.
    pub title: String,
    /// Horizontal axis label (with unit).
    pub x_label: String,
    /// Vertical axis label (with unit).
    pub y_label: String,
    /// Horizontal range (`None`: from the data).
    pub x_range: Option<(f64, f64)>,
    /// Vertical range (`None`: from the data).
    pub y_range: Option<(f64, f64)>,
    /// What is drawn.
    pub traces: Vec<Trace>,
    /// A line of explanation under the caption (what is missing and why).
    pub note: Option<String>,
    /// Digital rows, bottom first: row `i` spans `i … i + 1` (a timing diagram).
    pub rows: Vec<String>,
    /// One unit is as long on both axes (a path in a plane).
    pub equal_aspect: bool,
    /// Height in pixels.
    pub height: u32,
}

/// A whole picture.
#[derive(Debug, Clone)]
pub struct Figure {
    /// Heading.
    pub title: String,
    /// The charts, top to bottom.
    pub charts: Vec<Chart>,
}

const NO_POSITIONS: &str = "positions move every update and are not in the trace: shown at \
     captures and motion ends; plot a live run (pacer run --plot) or give its --csv for the curves";

fn time_chart(title: &str, y_label: String, rec: &Recording) -> Chart {
    Chart {
        title: title.to_string(),
        x_label: "time (s)".into(),
        y_label,
        x_range: Some((rec.from, rec.to.max(rec.from + rec.update))),
        height: 230,
        ..Chart::default()
    }
}

fn trace(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style, color: usize) -> Trace {
    Trace {
        label: label.into(),
        points,
        style,
        color,
    }
}

/// A series as drawn: sampled ones through their samples, changes held between changes.
fn series_points(rec: &Recording, name: &str, s: &Series) -> Vec<(f64, f64)> {
    if rec.sampled_names.contains(name) {
        s.line_points()
    } else {
        s.step_points(rec.from, rec.to)
    }
}

fn window_text(rec: &Recording) -> String {
    format!("t = {} … {} s", short(rec.from), short(rec.to))
}

/// A number for a caption: at most three decimals, no trailing zeros.
fn short(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

/// The figure for a recording.
pub fn figure(preset: &Preset, rec: &Recording) -> Figure {
    let name = if rec.machine.is_empty() {
        "pacer"
    } else {
        &rec.machine
    };
    match preset {
        Preset::Servo => Figure {
            title: format!(
                "{name}: master, servo, index activity, queues ({})",
                window_text(rec)
            ),
            charts: servo(rec),
        },
        Preset::Web => Figure {
            title: format!(
                "{name}: registration per printed mark ({})",
                window_text(rec)
            ),
            charts: web(rec),
        },
        Preset::PickPlace => Figure {
            title: if rec.auto_window {
                format!(
                    "{name}: tool path, the first {PP_CYCLES} pick-and-place cycles ({})",
                    window_text(rec)
                )
            } else {
                format!("{name}: tool path ({})", window_text(rec))
            },
            charts: pick_place(rec),
        },
        Preset::Signals(names) => Figure {
            title: format!("{name}: {} ({})", names.join(", "), window_text(rec)),
            charts: signals(rec, names),
        },
    }
}

fn servo(rec: &Recording) -> Vec<Chart> {
    let mut charts = Vec::new();
    for (title, name, unit, events) in [
        (
            "Master position",
            MASTER_POSITION,
            &rec.master_unit,
            &rec.master_at_events,
        ),
        (
            "Servo position",
            SERVO_POSITION,
            &rec.motor_unit,
            &rec.servo_at_events,
        ),
    ] {
        let mut c = time_chart(title, format!("position ({unit})"), rec);
        match rec.series.get(name).filter(|s| !s.is_empty()) {
            Some(s) => c
                .traces
                .push(trace(name, series_points(rec, name, s), Style::Line, 0)),
            None => {
                c.traces.push(trace(
                    format!("{name} at events"),
                    events.line_points(),
                    Style::Dots,
                    0,
                ));
                c.note = Some(NO_POSITIONS.into());
            }
        }
        charts.push(c);
    }
    let mut activity = time_chart("Index activity (CommandInProgress)", String::new(), rec);
    let mut names: Vec<&String> = rec
        .series
        .keys()
        .filter(|n| n.ends_with(".CommandInProgress"))
        .filter(|n| rec.series.get(*n).is_some_and(|s| s.changed))
        .collect();
    names.sort();
    // Indexes on top, homes below: the row order is bottom first.
    names.reverse();
    for (row, n) in names.iter().enumerate() {
        let s = &rec.series[*n];
        let pts = level_points(s.step_points(rec.from, rec.to), row);
        activity.traces.push(trace(
            n.trim_end_matches(".CommandInProgress"),
            pts,
            Style::Line,
            1 + row,
        ));
        activity
            .rows
            .push(n.trim_end_matches(".CommandInProgress").to_string());
    }
    if activity.rows.is_empty() {
        activity.note = Some("no index or home motion in this window".into());
    }
    activity.height = 90 + 34 * activity.rows.len() as u32;
    charts.push(activity);
    let mut queues = time_chart("Queue count", "entries".into(), rec);
    let mut qnames: Vec<&String> = rec
        .series
        .keys()
        .filter(|n| n.ends_with(".QueueCount"))
        .filter(|n| rec.series.get(*n).is_some_and(|s| s.changed))
        .collect();
    qnames.sort();
    for (i, n) in qnames.iter().enumerate() {
        let s = &rec.series[*n];
        queues.traces.push(trace(
            n.as_str(),
            s.step_points(rec.from, rec.to),
            Style::Line,
            4 + i,
        ));
    }
    if queues.traces.is_empty() {
        queues.note = Some("no queue entries in this window".into());
    }
    charts.push(queues);
    charts
}

/// A bit's 0/1 steps moved onto digital row `row` (low at row + 0.15, high at row + 0.75).
fn level_points(pts: Vec<(f64, f64)>, row: usize) -> Vec<(f64, f64)> {
    pts.into_iter()
        .map(|(t, v)| (t, row as f64 + if v != 0.0 { 0.75 } else { 0.15 }))
        .collect()
}

fn web(rec: &Recording) -> Vec<Chart> {
    let marks: Vec<_> = rec
        .marks
        .iter()
        .filter(|m| m.time >= rec.from && m.time <= rec.to)
        .collect();
    let axes: Vec<u32> = {
        let mut a: Vec<u32> = marks
            .iter()
            .flat_map(|m| m.positions.iter().map(|p| p.0))
            .collect();
        a.sort_unstable();
        a.dedup();
        a
    };
    // The lowest-numbered latching axis is the web (the pacer), the next the knife.
    let web_axis = axes.first().copied();
    let knife_axis = axes.get(1).copied();
    let pos = |m: &super::record::Mark, axis: Option<u32>| {
        axis.and_then(|a| m.positions.iter().find(|p| p.0 == a).map(|p| p.1))
    };
    let var = |m: &super::record::Mark, name: &str| m.after.get(name).copied();
    let x_label = "mark (sensor edge, in order)".to_string();

    // Pitch.
    let mut pitch = Chart {
        title: "Pitch per mark".into(),
        x_label: x_label.clone(),
        y_label: match web_axis {
            Some(a) => format!("pitch (axis {a} user units)"),
            None => "pitch".into(),
        },
        height: 300,
        ..Chart::default()
    };
    let mut measured = Vec::new();
    for (k, w) in marks.windows(2).enumerate() {
        if let (Some(a), Some(b)) = (pos(w[0], web_axis), pos(w[1], web_axis)) {
            measured.push(((k + 2) as f64, b - a));
        }
    }
    let estimate: Vec<(f64, f64)> = marks
        .iter()
        .enumerate()
        .filter_map(|(k, m)| var(m, "PLEN&").map(|v| ((k + 1) as f64, v)))
        .collect();
    let set_point = rec.current.get("TREND.SET&").copied();
    let mut keep: Vec<f64> = estimate.iter().map(|p| p.1).collect();
    keep.extend(set_point);
    let (inliers, outliers) = split_outliers(&measured);
    keep.extend(inliers.iter().map(|p| p.1));
    let range = padded_range(&keep);
    pitch.y_range = range;
    pitch.traces.push(trace(
        "measured: web position between latched marks",
        inliers,
        Style::Dots,
        0,
    ));
    if !estimate.is_empty() {
        pitch.traces.push(trace(
            "PLEN&: the program's pitch estimate after the mark",
            estimate,
            Style::Line,
            1,
        ));
    }
    if let (Some(sp), false) = (set_point, marks.is_empty()) {
        pitch.traces.push(trace(
            "TREND.SET&: pitch set point",
            vec![(1.0, sp), (marks.len() as f64, sp)],
            Style::Dashed,
            2,
        ));
    }
    if let (Some((lo, hi)), false) = (range, outliers.is_empty()) {
        let n = outliers.len();
        let clipped = outliers
            .into_iter()
            .map(|(k, v)| (k, if v < lo { lo } else { hi }))
            .collect();
        pitch.traces.push(trace(
            format!("{n} far from the rest (print defects, missed marks), drawn at the edge"),
            clipped,
            Style::Triangles,
            3,
        ));
    }
    if marks.is_empty() {
        pitch.note = Some("no mark latches in this window".into());
    }

    // Phase.
    let mut phase = Chart {
        title: "Phase error per mark".into(),
        x_label,
        y_label: match knife_axis {
            Some(a) => format!("phase error (axis {a} user units)"),
            None => "phase error".into(),
        },
        height: 300,
        ..Chart::default()
    };
    let modulo = knife_axis
        .and_then(|a| rec.current.get(&format!("Axis.{a}.PosMod")).copied())
        .filter(|m| *m > 0.0);
    let set = rec.current.get("INST.SET&").copied();
    let target = set.unwrap_or(0.0);
    let what = if set.is_some() {
        "INST.SET& − knife position at the mark"
    } else {
        "− knife position at the mark"
    };
    let errors: Vec<(f64, f64)> = marks
        .iter()
        .enumerate()
        .filter_map(|(k, m)| {
            let p = pos(m, knife_axis)?;
            let mut e = target - p;
            if let Some(md) = modulo {
                // The shortest way round: within half a turn either side.
                e -= md * (e / md).round();
            }
            Some(((k + 1) as f64, e))
        })
        .collect();
    phase.traces.push(trace(
        match modulo {
            Some(m) => format!("measured: {what}, within ±{}", short(m / 2.0)),
            None => format!("measured: {what}"),
        },
        errors,
        Style::Dots,
        0,
    ));
    for (name, label, color) in [
        ("DIFF&", "DIFF&: the error the program acts on (limited)", 1),
        ("CORR&", "CORR&: the correction it commands (GEAR FOR)", 4),
    ] {
        let pts: Vec<(f64, f64)> = marks
            .iter()
            .enumerate()
            .filter_map(|(k, m)| var(m, name).map(|v| ((k + 1) as f64, v)))
            .collect();
        if !pts.is_empty() {
            phase.traces.push(trace(label, pts, Style::Line, color));
        }
    }
    if marks.is_empty() {
        phase.note = Some("no mark latches in this window".into());
    }
    vec![pitch, phase]
}

/// What a value in this unit measures, for an axis label: `(mm/s)` is a velocity.
fn quantity(unit: &str) -> &'static str {
    match (unit.contains('°'), unit.ends_with("/s)")) {
        (false, false) => "position",
        (false, true) => "velocity",
        (true, false) => "angle",
        (true, true) => "angular velocity",
    }
}

/// Measurements far from the rest (by the median absolute deviation): a spurious mark gives
/// a pitch a fraction of the others, which would flatten the picture of the real ones.
fn split_outliers(pts: &[Point]) -> (Vec<Point>, Vec<Point>) {
    if pts.len() < 5 {
        return (pts.to_vec(), Vec::new());
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let mut vals: Vec<f64> = pts.iter().map(|p| p.1).collect();
    let med = median(&mut vals);
    let mut dev: Vec<f64> = pts.iter().map(|p| (p.1 - med).abs()).collect();
    let mad = median(&mut dev);
    let limit = (10.0 * mad).max(0.01 * med.abs()).max(1e-9);
    pts.iter().partition(|p| (p.1 - med).abs() <= limit)
}

fn padded_range(vals: &[f64]) -> Option<(f64, f64)> {
    let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !lo.is_finite() || !hi.is_finite() {
        return None;
    }
    // At least a thousandth of the value either side: equal values get readable ticks.
    let pad = ((hi - lo) * 0.08).max(hi.abs().max(1.0) * 1e-3);
    Some((lo - pad, hi + pad))
}

fn pick_place(rec: &Recording) -> Vec<Chart> {
    let in_w = |p: &&[f64; 4]| p[0] >= rec.from && p[0] <= rec.to;
    let mut xy = Chart {
        title: "Tool path seen from above (X/Y)".into(),
        x_label: "X (mm)".into(),
        y_label: "Y (mm)".into(),
        equal_aspect: true,
        height: 520,
        ..Chart::default()
    };
    if rec.path.points.is_empty() {
        xy.note = Some(
            "the tool path moves every update and is not in the trace: picks and places only; \
             plot a live run (pacer run --plot) or give its --csv for the path"
                .into(),
        );
    } else {
        xy.traces.push(trace(
            "tool (alrActPos[1], alrActPos[2])",
            rec.path.points.clone(),
            Style::Line,
            0,
        ));
        if rec.path.dropped > 0 {
            xy.note = Some(format!(
                "path cut short: {} later points left out (choose a shorter --window)",
                rec.path.dropped
            ));
        }
    }
    let picks = rec
        .picks
        .iter()
        .filter(in_w)
        .map(|p| (p[1], p[2]))
        .collect();
    let places = rec
        .places
        .iter()
        .filter(in_w)
        .map(|p| (p[1], p[2]))
        .collect();
    xy.traces
        .push(trace("pick (from its belt)", picks, Style::Triangles, 2));
    xy.traces
        .push(trace("place (onto its belt)", places, Style::Squares, 4));

    let mut z = time_chart("Tool height (Z) against time", "Z (mm)".into(), rec);
    let zname = TOOL_XYZ[2];
    match rec.series.get(zname).filter(|s| !s.is_empty()) {
        Some(s) => z.traces.push(trace(
            "tool Z (alrActPos[3])",
            series_points(rec, zname, s),
            Style::Line,
            0,
        )),
        None => {
            z.note = Some(
                "Z moves every update and is not in the trace: picks and places only; plot a \
                 live run (pacer run --plot) or give its --csv for the curve"
                    .into(),
            )
        }
    }
    let tz = |v: &Vec<[f64; 4]>| -> Vec<(f64, f64)> {
        v.iter()
            .filter(|p| p[0] >= rec.from && p[0] <= rec.to)
            .map(|p| (p[0], p[3]))
            .collect()
    };
    z.traces
        .push(trace("pick", tz(&rec.picks), Style::Triangles, 2));
    z.traces
        .push(trace("place", tz(&rec.places), Style::Squares, 4));
    vec![xy, z]
}

fn signals(rec: &Recording, names: &[String]) -> Vec<Chart> {
    let mut charts: Vec<Chart> = Vec::new();
    let bits: Vec<&String> = names.iter().filter(|n| rec.bits.contains(*n)).collect();
    let mut missing: Vec<&str> = Vec::new();
    // Numbers with a known unit share a chart per unit; the others get one each.
    let mut groups: Vec<(String, Vec<&String>)> = Vec::new();
    for n in names.iter().filter(|n| !rec.bits.contains(*n)) {
        let key = unit_of(n, &rec.motor_unit, &rec.master_unit)
            .map(|u| format!("({u})"))
            .unwrap_or_else(|| n.to_string());
        match groups.iter_mut().find(|g| g.0 == key) {
            Some(g) => g.1.push(n),
            None => groups.push((key, vec![n])),
        }
    }
    let mut color = 0;
    for (key, members) in &groups {
        let (title, y_label) = if key.starts_with('(') {
            let joined: Vec<&str> = members.iter().map(|s| s.as_str()).collect();
            (joined.join(", "), format!("{} {key}", quantity(key)))
        } else {
            (key.clone(), "value".to_string())
        };
        let mut c = time_chart(&title, y_label, rec);
        for n in members {
            match rec.series.get(n.as_str()).filter(|s| !s.is_empty()) {
                Some(s) => {
                    c.traces.push(trace(
                        n.as_str(),
                        series_points(rec, n, s),
                        Style::Line,
                        color,
                    ));
                    color += 1;
                }
                None => missing.push(n),
            }
        }
        if !c.traces.is_empty() {
            charts.push(c);
        }
    }
    if !bits.is_empty() {
        let mut d = time_chart("Digital signals", String::new(), rec);
        for (row, n) in bits.iter().rev().enumerate() {
            match rec.series.get(n.as_str()).filter(|s| !s.is_empty()) {
                Some(s) => {
                    d.rows.push(n.to_string());
                    d.traces.push(trace(
                        n.as_str(),
                        level_points(s.step_points(rec.from, rec.to), d.rows.len() - 1),
                        Style::Line,
                        1 + row,
                    ));
                }
                None => missing.push(n),
            }
        }
        d.height = 90 + 34 * d.rows.len() as u32;
        if !d.rows.is_empty() {
            charts.push(d);
        }
    }
    if !missing.is_empty() {
        let note = format!(
            "no value in this window (never changed in the trace, or moving and not sampled): {}",
            missing.join(", ")
        );
        match charts.first_mut() {
            Some(c) => c.note = Some(note),
            None => charts.push(Chart {
                title: "No data".into(),
                note: Some(note),
                ..time_chart("No data", String::new(), rec)
            }),
        }
    }
    charts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spurious_pitches_are_set_apart() {
        let mut pts: Vec<(f64, f64)> = (0..40)
            .map(|k| (k as f64, 15120.0 + (k % 5) as f64 * 4.0))
            .collect();
        pts.push((40.0, 6000.0));
        pts.push((41.0, 9120.0));
        let (inl, out) = split_outliers(&pts);
        assert_eq!(inl.len(), 40);
        assert_eq!(out, vec![(40.0, 6000.0), (41.0, 9120.0)]);
    }

    #[test]
    fn captions_keep_three_decimals_at_most() {
        assert_eq!(short(38.0), "38");
        assert_eq!(short(1.2345), "1.234");
        assert_eq!(short(-0.0001), "0");
    }
}
