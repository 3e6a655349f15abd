//! The sweep's picture (SVG, drawn as `pacer plot` draws): over two varied values, a map of
//! where every variant passes and the boundary of safe operation, then a measure against the
//! first value, one line per value of the second; over one varied value, the measure against it
//! with the failing values marked.

use super::results::Meta;
use super::run::VariantResult;
use super::summary::{as_number, axis_values, chosen_axes, cmp_value, passing, show};
use crate::export::figure::{Chart, Figure, Style, Trace};
use std::cmp::Ordering;

/// Lines drawn at most in the measure chart (the palette's colours).
const MAX_LINES: usize = 8;

/// Where value `v` of the sorted `values` goes on an axis: the number itself, or its place for
/// text.
fn coord(values: &[toml::Value], v: &toml::Value) -> f64 {
    as_number(v).unwrap_or_else(|| {
        values
            .iter()
            .position(|x| cmp_value(x, v) == Ordering::Equal)
            .unwrap_or(0) as f64
    })
}

fn same(a: Option<&toml::Value>, b: &toml::Value) -> bool {
    a.is_some_and(|a| cmp_value(a, b) == Ordering::Equal)
}

/// Mean of the measure `m` over the results matching `keep` (those that have it).
fn mean(results: &[VariantResult], m: usize, keep: &dyn Fn(&VariantResult) -> bool) -> Option<f64> {
    let xs: Vec<f64> = results
        .iter()
        .filter(|r| keep(r))
        .filter_map(|r| r.measures.get(m).copied().flatten())
        .collect();
    (!xs.is_empty()).then(|| xs.iter().sum::<f64>() / xs.len() as f64)
}

/// The figure of a sweep.
pub fn figure(meta: &Meta, results: &[VariantResult]) -> Figure {
    let measure = meta
        .plot
        .first()
        .filter(|s| !s.is_empty())
        .and_then(|n| meta.measures.iter().position(|m| m == n))
        .or(if meta.measures.is_empty() {
            None
        } else {
            Some(0)
        });
    let mut charts = Vec::new();
    let (x, y) = chosen_axes(meta, results);
    if let Some(x) = x {
        let xs = axis_values(results, x);
        let xn = meta.axes[x].clone();
        if let Some(y) = y {
            let ys = axis_values(results, y);
            let yn = meta.axes[y].clone();
            let mut pass = Vec::new();
            let mut fail = Vec::new();
            let mut edge = Vec::new();
            for (xv, row) in passing(results, x, y) {
                for (yv, ok) in &row {
                    let p = (coord(&xs, &xv), coord(&ys, yv));
                    if *ok {
                        pass.push(p);
                    } else {
                        fail.push(p);
                    }
                }
                // The boundary: the least passing value above which everything passes.
                if let Some(k) = row.iter().rposition(|(_, ok)| !ok) {
                    if let Some((yv, _)) = row.get(k + 1) {
                        edge.push((coord(&xs, &xv), coord(&ys, yv)));
                    }
                } else if let Some((yv, _)) = row.first() {
                    edge.push((coord(&xs, &xv), coord(&ys, yv)));
                }
            }
            charts.push(Chart {
                title: format!("where every variant passes: {xn} × {yn}"),
                x_label: xn.clone(),
                y_label: yn.clone(),
                traces: vec![
                    Trace {
                        label: "every variant passes".into(),
                        points: pass,
                        style: Style::Dots,
                        color: 2,
                    },
                    Trace {
                        label: "a variant fails".into(),
                        points: fail,
                        style: Style::Triangles,
                        color: 1,
                    },
                    Trace {
                        label: format!("least {yn} that passes"),
                        points: edge,
                        style: Style::Line,
                        color: 7,
                    },
                ],
                note: Some(format!(
                    "{} variants; assertions: {}",
                    results.len(),
                    if meta.expects.is_empty() {
                        "none (errors only)".to_string()
                    } else {
                        meta.expects.join(", ")
                    }
                )),
                height: 360,
                ..Chart::default()
            });
            if let Some(m) = measure {
                let step = ys.len().div_ceil(MAX_LINES).max(1);
                let traces = ys
                    .iter()
                    .step_by(step)
                    .enumerate()
                    .map(|(i, yv)| {
                        let points = xs
                            .iter()
                            .filter_map(|xv| {
                                mean(results, m, &|r| {
                                    same(r.values.get(x), xv) && same(r.values.get(y), yv)
                                })
                                .map(|v| (coord(&xs, xv), v))
                            })
                            .collect();
                        Trace {
                            label: format!("{yn} = {}", show(yv)),
                            points,
                            style: Style::Line,
                            color: i,
                        }
                    })
                    .collect();
                charts.push(Chart {
                    title: format!("{} against {xn}", meta.measures[m]),
                    x_label: xn.clone(),
                    y_label: meta.measures[m].clone(),
                    traces,
                    note: (meta.axes.len() > 2)
                        .then(|| "mean over the other varied values".to_string()),
                    height: 300,
                    ..Chart::default()
                });
            }
        } else if let Some(m) = measure {
            let line = xs
                .iter()
                .filter_map(|xv| {
                    mean(results, m, &|r| same(r.values.get(x), xv)).map(|v| (coord(&xs, xv), v))
                })
                .collect();
            let fail = xs
                .iter()
                .filter(|xv| {
                    results
                        .iter()
                        .any(|r| same(r.values.get(x), xv) && !r.pass())
                })
                .filter_map(|xv| {
                    mean(results, m, &|r| same(r.values.get(x), xv)).map(|v| (coord(&xs, xv), v))
                })
                .collect();
            charts.push(Chart {
                title: format!("{} against {xn}", meta.measures[m]),
                x_label: xn.clone(),
                y_label: meta.measures[m].clone(),
                traces: vec![
                    Trace {
                        label: meta.measures[m].clone(),
                        points: line,
                        style: Style::Line,
                        color: 0,
                    },
                    Trace {
                        label: "a variant fails".into(),
                        points: fail,
                        style: Style::Triangles,
                        color: 1,
                    },
                ],
                height: 320,
                ..Chart::default()
            });
        }
    }
    Figure {
        title: format!("pacer sweep: {} ({} variants)", meta.machine, results.len()),
        charts,
    }
}

/// The SVG text of the sweep's figure.
pub fn svg(meta: &Meta, results: &[VariantResult]) -> Result<String, String> {
    crate::export::plot::render(&figure(meta, results))
}
