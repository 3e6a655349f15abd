//! Drawing a [`Figure`] as SVG with plotters' SVG backend. Text goes into the SVG as `<text>`
//! for the viewer to set, so no font files are read (plotters' `ttf` feature is off); the
//! legend is laid out here, beside each chart, so it never hides a curve.

use super::figure::{Chart, Figure, Style, Trace};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Width of the picture, pixels.
const WIDTH: u32 = 1200;
/// Width of the legend column beside each chart.
const LEGEND: u32 = 330;
/// Height of the figure's heading.
const HEADING: u32 = 46;
/// Largest magnitude drawn (so every range and its span stay finite).
const LIMIT: f64 = 1e300;
/// Characters per line of a legend entry and of a note.
const LEGEND_CHARS: usize = 46;
const NOTE_CHARS: usize = 150;

/// Colours that stay apart in print and for the common colour-vision deficiencies (Okabe–Ito).
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
    RGBColor(120, 120, 120),
    RGBColor(0, 0, 0),
];

fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

const FONT: &str = "sans-serif";

fn err<E: std::fmt::Debug>(e: E) -> String {
    format!("drawing the plot: {e:?}")
}

/// Lines of at most `width` characters, broken at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// A chart with nothing to draw is its caption and note alone: empty axes say nothing.
fn body_height(c: &Chart) -> u32 {
    if c.traces.iter().all(|t| t.points.is_empty()) {
        0
    } else {
        c.height
    }
}

fn note_lines(c: &Chart) -> Vec<String> {
    c.note
        .as_deref()
        .map(|n| wrap(n, NOTE_CHARS))
        .unwrap_or_default()
}

/// The SVG text of a figure.
pub fn render(fig: &Figure) -> Result<String, String> {
    let heights: Vec<u32> = fig
        .charts
        .iter()
        .map(|c| body_height(c) + 30 + 16 * note_lines(c).len() as u32)
        .collect();
    let total = HEADING + heights.iter().sum::<u32>() + 10;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, total)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        root.draw_text(
            &fig.title,
            &(FONT, 20).into_font().style(FontStyle::Bold).color(&BLACK),
            (16, 14),
        )
        .map_err(err)?;
        let (_, mut rest) = root.split_vertically(HEADING);
        // One left margin for every chart, so their time axes line up.
        let longest_row = fig
            .charts
            .iter()
            .flat_map(|c| c.rows.iter())
            .map(|r| r.chars().count() as u32)
            .max()
            .unwrap_or(0);
        let label_w = (7 * longest_row + 24).max(84);
        for (chart, h) in fig.charts.iter().zip(&heights) {
            let (area, below) = rest.split_vertically(*h);
            draw_chart(&area, chart, label_w)?;
            rest = below;
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Draw every trace of a chart on a built chart context (a macro: the plain and the digital
/// charts differ in their vertical coordinate type).
macro_rules! draw_traces {
    ($chart:ident, $c:ident, $xr:ident, $yr:ident) => {
        for t in &$c.traces {
            let col = color(t.color);
            match t.style {
                Style::Line | Style::Dashed => {
                    let pixel = |p: &(f64, f64)| $chart.backend_coord(p);
                    let pts = if $c.equal_aspect {
                        dedupe(&t.points, pixel)
                    } else {
                        thin(&t.points, $xr, $yr, pixel)
                    };
                    if t.style == Style::Line {
                        $chart
                            .draw_series(LineSeries::new(pts, col.stroke_width(2)))
                            .map_err(err)?;
                    } else {
                        $chart
                            .draw_series(DashedLineSeries::new(pts, 9, 6, col.stroke_width(2)))
                            .map_err(err)?;
                    }
                }
                Style::Dots => {
                    $chart
                        .draw_series(
                            inside(&t.points, $xr, $yr).map(|p| Circle::new(p, 3, col.filled())),
                        )
                        .map_err(err)?;
                }
                Style::Triangles => {
                    $chart
                        .draw_series(
                            inside(&t.points, $xr, $yr)
                                .map(|p| TriangleMarker::new(p, 6, col.filled())),
                        )
                        .map_err(err)?;
                }
                Style::Squares => {
                    $chart
                        .draw_series(inside(&t.points, $xr, $yr).map(|p| {
                            EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], col.filled())
                        }))
                        .map_err(err)?;
                }
            }
        }
    };
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

fn draw_chart(area: &Area<'_>, c: &Chart, label_w: u32) -> Result<(), String> {
    let notes = note_lines(c);
    let (head, body) = area.split_vertically(30 + 16 * notes.len() as u32);
    head.draw_text(
        &c.title,
        &(FONT, 16).into_font().style(FontStyle::Bold).color(&BLACK),
        (16, 10),
    )
    .map_err(err)?;
    for (i, n) in notes.iter().enumerate() {
        head.draw_text(
            n,
            &(FONT, 12).into_font().color(&RGBColor(110, 110, 110)),
            (16, 30 + 16 * i as i32),
        )
        .map_err(err)?;
    }
    if body_height(c) == 0 {
        return Ok(());
    }
    let (plot, legend) = body.split_horizontally(WIDTH - LEGEND);
    let (xr, yr) = ranges(c, &plot, label_w);
    let digital = !c.rows.is_empty();
    let mut chart = ChartBuilder::on(&plot)
        .margin_left(8)
        .margin_right(16)
        .margin_top(6)
        .x_label_area_size(42)
        .y_label_area_size(label_w)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(err)?;
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(c.x_label.as_str())
        .x_labels(12)
        .x_label_formatter(&tick_label)
        .y_label_formatter(&tick_label)
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .bold_line_style(RGBColor(215, 215, 215))
        .light_line_style(RGBColor(242, 242, 242));
    if digital {
        // A timing diagram: one row per signal, named beside the axis (drawn below).
        mesh.y_labels(0).disable_y_mesh();
    } else {
        mesh.y_desc(c.y_label.as_str()).y_labels(7);
    }
    mesh.draw().map_err(err)?;
    if digital {
        let base = plot.get_base_pixel();
        let (x_axis, _) = chart.backend_coord(&(xr.0, yr.0));
        let style = (FONT, 12)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Right, VPos::Center));
        for (i, name) in c.rows.iter().enumerate() {
            let (_, y) = chart.backend_coord(&(xr.0, i as f64 + 0.45));
            plot.draw_text(name, &style, (x_axis - base.0 - 8, y - base.1))
                .map_err(err)?;
        }
    }
    draw_traces!(chart, c, xr, yr);
    if digital {
        // The rows are named beside the axis: a legend would only repeat them.
        return Ok(());
    }
    draw_legend(&legend, &c.traces)
}

/// An axis number as short as it can be: `10`, not `10.0`; `0.25`.
fn tick_label(v: &f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// Points within the ranges (markers outside them would spill over the next chart).
fn inside(
    pts: &[(f64, f64)],
    xr: (f64, f64),
    yr: (f64, f64),
) -> impl Iterator<Item = (f64, f64)> + '_ {
    pts.iter()
        .copied()
        .filter(move |&(x, y)| x >= xr.0 && x <= xr.1 && y >= yr.0 && y <= yr.1)
}

/// A polyline with at most four points per pixel column (first, lowest, highest, last): what
/// the eye sees, in a file a fraction of the size. Values beyond the vertical range are held at
/// its edge.
fn thin(
    pts: &[(f64, f64)],
    xr: (f64, f64),
    yr: (f64, f64),
    to_pixel: impl Fn(&(f64, f64)) -> (i32, i32),
) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(pts.len().min(8192));
    let mut column: Vec<(f64, f64)> = Vec::new();
    let mut col_x: Option<i32> = None;
    let flush = |column: &mut Vec<(f64, f64)>, out: &mut Vec<(f64, f64)>| {
        if column.is_empty() {
            return;
        }
        let first = column[0];
        let last = column[column.len() - 1];
        let lo = column
            .iter()
            .copied()
            .fold(first, |a, p| if p.1 < a.1 { p } else { a });
        let hi = column
            .iter()
            .copied()
            .fold(first, |a, p| if p.1 > a.1 { p } else { a });
        let (a, b) = if lo.0 <= hi.0 { (lo, hi) } else { (hi, lo) };
        for p in [first, a, b, last] {
            if out.last() != Some(&p) {
                out.push(p);
            }
        }
        column.clear();
    };
    for &(x, y) in pts {
        if !(x.is_finite() && y.is_finite()) || x < xr.0 || x > xr.1 {
            continue;
        }
        let p = (x, y.clamp(yr.0, yr.1));
        let px = to_pixel(&p).0;
        if col_x != Some(px) {
            flush(&mut column, &mut out);
            col_x = Some(px);
        }
        column.push(p);
    }
    flush(&mut column, &mut out);
    out
}

/// A path in a plane with consecutive points on one pixel merged: nothing visible is lost.
fn dedupe(pts: &[(f64, f64)], to_pixel: impl Fn(&(f64, f64)) -> (i32, i32)) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(pts.len().min(8192));
    let mut last: Option<(i32, i32)> = None;
    for p in pts {
        let px = to_pixel(p);
        if last != Some(px) {
            out.push(*p);
            last = Some(px);
        }
    }
    // The path ends where it ends, even inside the last pixel.
    if let (Some(&end), Some(&kept)) = (pts.last(), out.last()) {
        if end != kept {
            out.push(end);
        }
    }
    out
}

/// Horizontal and vertical ranges: the chart's own, else the data's with a margin.
fn ranges(c: &Chart, plot: &Area<'_>, label_w: u32) -> ((f64, f64), (f64, f64)) {
    let all = c.traces.iter().flat_map(|t| t.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in all {
        // Beyond ±1e300 a range's span is no longer a number; no machine quantity gets there.
        let (x, y) = (x.clamp(-LIMIT, LIMIT), y.clamp(-LIMIT, LIMIT));
        if x.is_finite() && y.is_finite() {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    }
    let pad = |lo: f64, hi: f64| {
        if !lo.is_finite() {
            return (0.0, 1.0);
        }
        let span = hi - lo;
        let p = if span > 0.0 {
            span * 0.06
        } else {
            lo.abs().max(1.0) * 0.05
        };
        (lo - p, hi + p)
    };
    let sane = |r: (f64, f64)| (r.0.clamp(-LIMIT, LIMIT), r.1.clamp(-LIMIT, LIMIT));
    let mut xr = sane(c.x_range.unwrap_or_else(|| pad(x0, x1)));
    let mut yr = if !c.rows.is_empty() {
        (0.0, c.rows.len() as f64)
    } else {
        sane(c.y_range.unwrap_or_else(|| pad(y0, y1)))
    };
    // A range with no width (one value, or values past the limit) gets some around it.
    let widen = |r: &mut (f64, f64)| {
        if r.1 - r.0 <= r.0.abs().max(r.1.abs()) * 1e-12 || r.1 <= r.0 {
            let d = r.0.abs().max(1.0) * 0.05;
            *r = (r.0 - d, r.0 + d);
        }
    };
    widen(&mut xr);
    widen(&mut yr);
    if c.equal_aspect {
        // One millimetre as long across as up: widen the range that is short for its side.
        let (w, h) = plot.dim_in_pixel();
        let pw = f64::from(w.saturating_sub(label_w + 24).max(1));
        let ph = f64::from(h.saturating_sub(42 + 6).max(1));
        let per_px = ((xr.1 - xr.0) / pw).max((yr.1 - yr.0) / ph);
        let (cx, cy) = (0.5 * (xr.0 + xr.1), 0.5 * (yr.0 + yr.1));
        xr = (cx - 0.5 * per_px * pw, cx + 0.5 * per_px * pw);
        yr = (cy - 0.5 * per_px * ph, cy + 0.5 * per_px * ph);
    }
    (xr, yr)
}

fn draw_legend(area: &Area<'_>, traces: &[Trace]) -> Result<(), String> {
    let text = (FONT, 12).into_font().color(&BLACK);
    let mut y = 14;
    for t in traces {
        let col = color(t.color);
        let mid = y + 7;
        match t.style {
            Style::Line => area
                .draw(&PathElement::new(
                    vec![(6, mid), (32, mid)],
                    col.stroke_width(2),
                ))
                .map_err(err)?,
            Style::Dashed => {
                for x in [6, 18, 30] {
                    area.draw(&PathElement::new(
                        vec![(x, mid), (x + 7, mid)],
                        col.stroke_width(2),
                    ))
                    .map_err(err)?;
                }
            }
            Style::Dots => area
                .draw(&Circle::new((19, mid), 3, col.filled()))
                .map_err(err)?,
            Style::Triangles => area
                .draw(&TriangleMarker::new((19, mid), 6, col.filled()))
                .map_err(err)?,
            Style::Squares => area
                .draw(&Rectangle::new(
                    [(15, mid - 4), (23, mid + 4)],
                    col.filled(),
                ))
                .map_err(err)?,
        }
        for line in wrap(&t.label, LEGEND_CHARS) {
            area.draw_text(&line, &text, (40, y)).map_err(err)?;
            y += 16;
        }
        y += 6;
    }
    Ok(())
}
