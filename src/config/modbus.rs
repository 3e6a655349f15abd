//! `[modbus]` and `[[modbus.map]]` of `machine.toml`, checked against the registry into the
//! [`IoMap`] real I/O runs with: every entry bound to a member slot, with its direction, width,
//! scaling and safe value. Every problem is reported with the span of the key at fault, and a
//! map with any error yields no [`IoMap`]: a bad map never opens a connection.

use crate::config::machine::{MachineFile, ModbusMapEntry, ModbusSection};
use crate::config::span_of;
use crate::diag::{nearest, Level, Problem};
use crate::io::map::*;
use crate::registry::{Access, Kind, Registry};
use toml::Spanned;

const CODE: &str = "pacer::machine::modbus";

/// The Modbus set-up of a machine: None when it has no `[modbus]`, or when any entry is wrong
/// (the problems, with spans, go to `problems`).
pub fn validate(
    machine: &MachineFile,
    registry: &Registry,
    problems: &mut Vec<Problem>,
) -> Option<IoMap> {
    let section = machine.modbus.as_ref()?.get_ref();
    let before = problems.iter().filter(|p| p.level == Level::Error).count();
    let map = validate_section(section, registry, problems);
    let after = problems.iter().filter(|p| p.level == Level::Error).count();
    (after == before).then_some(map)
}

fn validate_section(
    section: &ModbusSection,
    registry: &Registry,
    problems: &mut Vec<Problem>,
) -> IoMap {
    let host = section.host.as_ref().and_then(|h| {
        let text = h.get_ref().trim();
        if text.is_empty() || text.contains(char::is_whitespace) {
            problems.push(
                Problem::error(CODE, span_of(h), "not a host name", "bad host")
                    .with_help("host = \"192.168.0.10\" or a host name"),
            );
            None
        } else {
            Some(text.to_string())
        }
    });
    let port = int_in(section.port.as_ref(), 1, 65535, "port", problems)
        .map_or(DEFAULT_PORT, |v| v as u16);
    let unit =
        int_in(section.unit.as_ref(), 0, 255, "unit", problems).map_or(DEFAULT_UNIT, |v| v as u8);
    let max_gap = int_in(
        section.max_gap.as_ref(),
        0,
        i64::from(MAX_GAP),
        "max_gap",
        problems,
    )
    .map_or(0, |v| v as u16);
    let overrun_limit = int_in(
        section.overrun_limit.as_ref(),
        0,
        1_000_000,
        "overrun_limit",
        problems,
    )
    .map_or(DEFAULT_OVERRUN_LIMIT, |v| v as u64);
    let enabled = section.enabled.as_ref().is_some_and(|e| *e.get_ref());
    let timeout_ns = match &section.timeout {
        Some(t) if t.get_ref().0 == 0 || t.get_ref().0 > 60_000_000_000 => {
            problems.push(Problem::error(
                CODE,
                span_of(t),
                "the timeout must be above 0 and at most 60 s",
                "out of range",
            ));
            DEFAULT_TIMEOUT_NS
        }
        Some(t) => t.get_ref().0,
        None => DEFAULT_TIMEOUT_NS,
    };
    let period_ns = duration_in(
        section.period.as_ref(),
        DEFAULT_PERIOD_NS,
        (MIN_PERIOD_NS, MAX_PERIOD_NS),
        "the exchange period must be from 1 ms to 1 s",
        problems,
    );
    let max_age_ns = duration_in(
        section.max_age.as_ref(),
        DEFAULT_MAX_AGE_NS.max(2 * period_ns),
        (1_000_000, 60_000_000_000),
        "max_age must be from 1 ms to 60 s",
        problems,
    );
    if let Some(age) = &section.max_age {
        if max_age_ns < 2 * period_ns {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(age),
                    format!(
                        "max_age must be at least two exchange periods ({} ms): an image is this old between two exchanges",
                        2 * period_ns / 1_000_000
                    ),
                    "shorter than two periods",
                )
                .with_help("raise max_age, or shorten period"),
            );
        }
    }
    let mut points: Vec<Point> = Vec::new();
    // The map entry of each point, to name the first of two overlapping entries.
    let mut origins: Vec<usize> = Vec::new();
    for (i, entry) in section.map.iter().enumerate() {
        for point in entry_points(entry.get_ref(), registry, problems) {
            let e = entry.get_ref();
            if let Some(j) = points
                .iter()
                .position(|p| p.table == point.table && overlaps(p, &point))
            {
                let first = origins[j];
                problems.push(
                    Problem::error(
                        CODE,
                        span_of(&e.address),
                        format!(
                            "{} {} is already mapped (to {}, by entry {} of the map)",
                            point.table.name(),
                            point.address.max(points[j].address),
                            points[j].member,
                            first + 1
                        ),
                        "overlaps",
                    )
                    .with_help("each Modbus address is mapped once"),
                );
                break;
            }
            if !point.table.is_output() {
                if let Some(j) = points
                    .iter()
                    .position(|p| !p.table.is_output() && p.slot == point.slot)
                {
                    problems.push(
                        Problem::error(
                            CODE,
                            span_of(&e.member),
                            format!(
                                "{} is already driven by {} {}",
                                point.member,
                                points[j].table.name(),
                                points[j].address
                            ),
                            "driven twice",
                        )
                        .with_help("a member takes its value from one device input"),
                    );
                    break;
                }
            }
            origins.push(i);
            points.push(point);
        }
    }
    IoMap {
        host,
        port,
        unit,
        timeout_ns,
        max_gap,
        enabled,
        overrun_limit,
        period_ns,
        max_age_ns,
        points,
    }
}

/// The exchange period's bounds, ns: a coupler is not asked more often than every millisecond,
/// and inputs a second old are no process image.
const MIN_PERIOD_NS: u64 = 1_000_000;
const MAX_PERIOD_NS: u64 = 1_000_000_000;

/// A duration setting that must lie in `lo..=hi` (ns), else `default` with the error `what`.
fn duration_in(
    value: Option<&Spanned<crate::config::values::Duration>>,
    default: u64,
    (lo, hi): (u64, u64),
    what: &str,
    problems: &mut Vec<Problem>,
) -> u64 {
    match value {
        Some(v) if !(lo..=hi).contains(&v.get_ref().0) => {
            problems.push(Problem::error(CODE, span_of(v), what, "out of range"));
            default
        }
        Some(v) => v.get_ref().0,
        None => default,
    }
}

fn overlaps(a: &Point, b: &Point) -> bool {
    u32::from(a.address) < b.end() && u32::from(b.address) < a.end()
}

/// An integer setting that must lie in `lo..=hi`.
fn int_in(
    v: Option<&Spanned<i64>>,
    lo: i64,
    hi: i64,
    what: &str,
    problems: &mut Vec<Problem>,
) -> Option<i64> {
    let v = v?;
    let x = *v.get_ref();
    if (lo..=hi).contains(&x) {
        Some(x)
    } else {
        problems.push(Problem::error(
            CODE,
            span_of(v),
            format!("{what} must be {lo} to {hi} (got {x})"),
            "out of range",
        ));
        None
    }
}

/// The points of one map entry (none when it is wrong; its problems are reported).
fn entry_points(
    e: &ModbusMapEntry,
    registry: &Registry,
    problems: &mut Vec<Problem>,
) -> Vec<Point> {
    let Some(table) = Table::from_name(e.kind.get_ref()) else {
        problems.push(
            Problem::error(
                CODE,
                span_of(&e.kind),
                format!("unknown Modbus table `{}`", e.kind.get_ref()),
                "unknown kind",
            )
            .with_help(match nearest(e.kind.get_ref(), TABLE_NAMES) {
                Some(n) => format!("did you mean `{n}`?"),
                None => format!("kind is one of {}", TABLE_NAMES.join(", ")),
            }),
        );
        return Vec::new();
    };
    let mut ok = true;
    let address = *e.address.get_ref();
    if !(0..=65535).contains(&address) {
        problems.push(Problem::error(
            CODE,
            span_of(&e.address),
            format!("a Modbus address is 0 to 65535 (got {address})"),
            "out of range",
        ));
        ok = false;
    }
    let count = e.count.as_ref().map_or(1, |c| *c.get_ref());
    let count_ok = if table.is_bit() {
        (1..=i64::from(table.max_read())).contains(&count)
    } else {
        count == 1 || count == 2
    };
    if let Some(c) = &e.count {
        if !count_ok {
            let help = if table.is_bit() {
                "a run of bits is 1 to 2000 points"
            } else {
                "a register value is 1 register (16-bit) or 2 (32-bit, high word first)"
            };
            problems.push(
                Problem::error(
                    CODE,
                    span_of(c),
                    format!("count {count} is not valid for a {}", table.name()),
                    "bad count",
                )
                .with_help(help),
            );
            ok = false;
        }
    }
    if ok && address + if table.is_bit() { count } else { count.max(1) } > 65536 {
        problems.push(Problem::error(
            CODE,
            span_of(&e.address),
            format!("the entry runs past address 65535 ({count} points from {address})"),
            "past the end",
        ));
        ok = false;
    }
    // Scaling belongs to registers; the safe value to outputs.
    if table.is_bit() {
        for (key, span) in [
            ("scale", e.scale.as_ref().map(span_of)),
            ("offset", e.offset.as_ref().map(span_of)),
            ("signed", e.signed.as_ref().map(span_of)),
        ] {
            if let Some(span) = span {
                problems.push(Problem::error(
                    CODE,
                    span,
                    format!("{key} is for registers, not a {}", table.name()),
                    "not for bits",
                ));
                ok = false;
            }
        }
    }
    let scale = e.scale.as_ref().map_or(1.0, |s| *s.get_ref());
    if let Some(s) = &e.scale {
        if !scale.is_finite() || scale == 0.0 {
            problems.push(Problem::error(
                CODE,
                span_of(s),
                format!("scale must be a finite number other than 0 (got {scale})"),
                "bad scale",
            ));
            ok = false;
        }
    }
    let offset = e.offset.as_ref().map_or(0.0, |o| *o.get_ref());
    if let Some(o) = &e.offset {
        if !offset.is_finite() {
            problems.push(Problem::error(
                CODE,
                span_of(o),
                "offset must be a finite number",
                "bad offset",
            ));
            ok = false;
        }
    }
    let safe = e.safe.as_ref().map_or(0.0, |s| *s.get_ref());
    if let Some(s) = &e.safe {
        if !table.is_output() {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(s),
                    format!("a {} is an input: it has no safe value", table.name()),
                    "not an output",
                )
                .with_help("safe values are for coils and holding registers"),
            );
            ok = false;
        } else if table.is_bit() && safe != 0.0 && safe != 1.0 {
            problems.push(Problem::error(
                CODE,
                span_of(s),
                format!("the safe value of a coil is 0 or 1 (got {safe})"),
                "not a bit",
            ));
            ok = false;
        } else if !safe.is_finite() {
            problems.push(Problem::error(
                CODE,
                span_of(s),
                "the safe value must be a finite number",
                "bad value",
            ));
            ok = false;
        }
    }
    // A bad count has been reported: resolve the written member alone.
    let run = if table.is_bit() && count_ok { count } else { 1 };
    let names = member_names(&e.member, run, problems);
    let Some(names) = names else {
        return Vec::new();
    };
    let width = if table.is_bit() || !count_ok {
        1
    } else {
        count as u16
    };
    let mut points = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let resolved = match registry.resolve_text(name) {
            Ok(r) => r,
            Err(mut p) => {
                if names.len() > 1 {
                    // The name was made from the first one: point at what was written.
                    p.span = span_of(&e.member);
                    p.message = format!(
                        "point {} of the run ({}): {}",
                        i + 1,
                        name.get_ref(),
                        p.message
                    );
                }
                problems.push(p);
                ok = false;
                break;
            }
        };
        if table.is_bit() != resolved.ty.is_bit() {
            problems.push(Problem::error(
                CODE,
                span_of(&e.member),
                format!(
                    "{} is {}, but a {} holds {}",
                    resolved.name,
                    resolved.ty.describe(),
                    table.name(),
                    if table.is_bit() { "a bit" } else { "a number" }
                ),
                "wrong type",
            ));
            ok = false;
            break;
        }
        if table.is_output() {
            if !matches!(resolved.access, Access::Read | Access::ReadWrite) {
                problems.push(Problem::error(
                    CODE,
                    span_of(&e.member),
                    format!(
                        "{} cannot be read, so it cannot drive a {}",
                        resolved.name,
                        table.name()
                    ),
                    "not readable",
                ));
                ok = false;
                break;
            }
        } else {
            let input = matches!(
                resolved.kind,
                Kind::DriveInput | Kind::ModuleInput | Kind::DriveIO
            ) && resolved.access == Access::Read;
            if !input && resolved.access != Access::ReadWrite {
                problems.push(
                    Problem::error(
                        CODE,
                        span_of(&e.member),
                        format!(
                            "{} is kept by pacer; a {} cannot write it",
                            resolved.name,
                            table.name()
                        ),
                        "not writable from the device",
                    )
                    .with_help("device inputs drive DriveInput, ModuleInput, DriveIO.N.In, Var and Bit members"),
                );
                ok = false;
                break;
            }
        }
        points.push(Point {
            table,
            address: (address.clamp(0, 65535) as u16).saturating_add(i as u16),
            width,
            slot: resolved.slot,
            member: resolved.name,
            scale,
            offset,
            signed: e.signed.as_ref().is_some_and(|s| *s.get_ref()),
            safe,
            io_point: matches!(
                resolved.kind,
                Kind::DriveInput | Kind::ModuleInput | Kind::DriveIO
            ),
            ty: resolved.ty,
        });
    }
    if ok {
        points
    } else {
        Vec::new()
    }
}

/// The member names of a run: `DriveInput.3` with 3 points is DriveInput.3, .4 and .5.
fn member_names(
    member: &Spanned<String>,
    count: i64,
    problems: &mut Vec<Problem>,
) -> Option<Vec<Spanned<String>>> {
    if count <= 1 {
        return Some(vec![member.clone()]);
    }
    let text = member.get_ref();
    let mut segs = text.split('.');
    let ty = segs.next().unwrap_or("");
    let first = segs.next().and_then(|n| n.parse::<u32>().ok());
    let rest: Vec<&str> = segs.collect();
    let Some(first) = first else {
        problems.push(
            Problem::error(
                CODE,
                span_of(member),
                format!("a run of {count} points needs a numbered first member, not `{text}`"),
                "not numbered",
            )
            .with_help("e.g. member = \"DriveInput.1\", count = 4 maps DriveInput.1 to .4"),
        );
        return None;
    };
    let tail: String = rest.iter().map(|s| format!(".{s}")).collect();
    Some(
        (0..count as u32)
            .map(|i| Spanned::new(member.span(), format!("{ty}.{}{tail}", first + i)))
            .collect(),
    )
}
