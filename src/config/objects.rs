//! `machine.toml`'s objects: instance counts, user variables and bits, queue, index, home and
//! PLS set-up, the servo axis's rollover and units, and the DSP axes. Every value is checked
//! here, with a problem located on it; what is valid goes into the description the registry
//! and the devices are built from (a value in error is left at its default, so the rest of the
//! file and the programs can still be checked).

use super::desc::{BitsDesc, DspAxisDesc, ObjectsDesc, VarDesc};
use super::machine::MachineFile;
use super::span_of;
use crate::devices::drive::setup::{
    DriveSetup, HomeConfig, IndexConfig, IndexType, PlsConfig, QueueConfig, QueueSource,
};
use crate::devices::orion::dsp::DspAxisConfig;
use crate::devices::orion::MoveDefaults;
use crate::diag::{nearest, Problem};
use crate::fixed::round_to;
use crate::registry::catalog::{self, Instances, Kind};
use crate::span::Span;

/// Highest instance count accepted for any type (also keeps instance numbers within u16 in
/// bytecode).
pub const MAX_INSTANCES: u32 = 4096;

/// The objects of `machine`: counts, variables, bits and the members' initial values; and the
/// drive's set-up. `programs` are the numbers of the programs loaded.
pub fn objects(
    machine: &MachineFile,
    programs: &[u32],
    problems: &mut Vec<Problem>,
) -> (ObjectsDesc, DriveSetup) {
    let mut d = ObjectsDesc {
        programs: programs.iter().copied().max().map_or(0, |n| n + 1),
        axes: axis_numbers(machine, problems)
            .into_iter()
            .max()
            .unwrap_or(0),
        pickplace: machine.pickplace.is_some(),
        belts: super::pickplace::belt_count(machine, problems),
        ..ObjectsDesc::default()
    };
    counts(machine, &mut d, problems);
    variables(machine, &mut d, problems);
    bits(machine, &mut d, problems);
    let mut drive = DriveSetup {
        queues: vec![QueueConfig::default(); d.count_of(&catalog::QUEUE_TYPE) as usize],
        indexes: vec![IndexConfig::default(); d.count_of(&catalog::INDEX_TYPE) as usize],
        homes: vec![HomeConfig::default(); d.count_of(&catalog::HOME_TYPE) as usize],
        plss: vec![PlsConfig::default(); d.count_of(&catalog::PLS_TYPE) as usize],
        ..DriveSetup::default()
    };
    queues(machine, &mut d, &mut drive, problems);
    indexes(machine, &mut d, &mut drive, problems);
    homes(machine, &mut d, problems);
    jogs(machine, &mut d, problems);
    plss(machine, &mut d, &mut drive, problems);
    super::pickplace::initials(machine, &mut d, problems);
    axis_set_up(machine, &mut drive, problems);
    let update_s = machine
        .machine
        .update
        .as_ref()
        .map_or(crate::registry::DEFAULT_UPDATE_NS, |u| u.get_ref().0) as f64
        / 1e9;
    super::servo::servo(machine, update_s, &mut d, &mut drive, problems);
    super::servo::dsp_initials(machine, &mut d);
    (d, drive)
}

/// `[io]` and `[objects]`: instance counts.
fn counts(machine: &MachineFile, d: &mut ObjectsDesc, problems: &mut Vec<Problem>) {
    for table in [&machine.io, &machine.objects] {
        for (key, value) in table {
            let span = span_of(value);
            match catalog::find_type(key) {
                Some(def) if def.kind == Kind::Belt => problems.push(
                    Problem::error(
                        "pacer::machine::count",
                        span,
                        "the number of belts is not set here",
                        "not a count",
                    )
                    .with_help("the highest [pickplace.belt.N] section in machine.toml sets it"),
                ),
                Some(def) if matches!(def.instances, Instances::Numbered { .. }) => {
                    let n = *value.get_ref();
                    if n > MAX_INSTANCES
                        || (def.kind == Kind::Queue && n > 8)
                        || (def.kind == Kind::Profile && n != 2)
                    {
                        let limit = match def.kind {
                            Kind::Queue => "at most 8 queues".to_string(),
                            Kind::Profile => "there are exactly 2 profiles".to_string(),
                            _ => format!("at most {MAX_INSTANCES}"),
                        };
                        problems.push(Problem::error(
                            "pacer::machine::count",
                            span,
                            format!("{n} is not a valid count of {}", def.name),
                            limit,
                        ));
                    } else {
                        d.counts.insert(def.name, n);
                    }
                }
                Some(def) => problems.push(Problem::error(
                    "pacer::machine::count",
                    span,
                    format!("{} has no instance count", def.name),
                    "set in its own table",
                )),
                None => {
                    let names = catalog::TYPES
                        .iter()
                        .filter(|t| matches!(t.instances, Instances::Numbered { .. }))
                        .map(|t| t.name);
                    problems.push(
                        Problem::error(
                            "pacer::machine::count",
                            span,
                            format!("unknown object type `{key}`"),
                            "not an object type",
                        )
                        .with_help_opt(nearest(key, names).map(|n| format!("did you mean `{n}`?"))),
                    )
                }
            }
        }
    }
}

/// `[variables]`.
fn variables(machine: &MachineFile, d: &mut ObjectsDesc, problems: &mut Vec<Problem>) {
    for (name, decl) in &machine.variables {
        let v = decl.get_ref();
        let span = span_of(decl);
        if !valid_ident(name) {
            problems.push(Problem::error(
                "pacer::machine::variable",
                span,
                format!("`{name}` is not a valid variable name"),
                "letters, digits and _; not starting with a digit",
            ));
        }
        if v.decimals > 9 {
            problems.push(Problem::error(
                "pacer::machine::variable",
                span,
                format!("Var.{name}: {} decimal places is too many", v.decimals),
                "0 to 9",
            ));
        }
        if crate::fixed::to_fixed(v.initial, v.decimals.min(9)).is_none() {
            problems.push(Problem::error(
                "pacer::machine::variable",
                span,
                format!(
                    "Var.{name}: initial value {} does not fit a 32-bit variable with {} decimals",
                    v.initial, v.decimals
                ),
                "out of range",
            ));
        }
        let decimals = v.decimals.min(9);
        d.variables.push(VarDesc {
            name: name.clone(),
            decimals,
            initial: round_to(v.initial, decimals),
        });
    }
}

/// `[bits]`.
fn bits(machine: &MachineFile, d: &mut ObjectsDesc, problems: &mut Vec<Problem>) {
    let mut count = machine.bits.count.as_ref().map_or(32, |c| *c.get_ref());
    if count > MAX_INSTANCES {
        if let Some(c) = &machine.bits.count {
            problems.push(Problem::error(
                "pacer::machine::bits",
                span_of(c),
                format!("{count} bits is too many"),
                format!("at most {MAX_INSTANCES}"),
            ));
        }
        count = 32;
    }
    let mut b = BitsDesc {
        count,
        ..BitsDesc::default()
    };
    for (name, number) in &machine.bits.names {
        let n = *number.get_ref();
        if n >= count {
            problems.push(Problem::error(
                "pacer::machine::bits",
                span_of(number),
                format!("Bit.{n} does not exist"),
                format!("bits are 0 to {}", count.saturating_sub(1)),
            ));
        } else if !valid_ident(name) || name.chars().all(|c| c.is_ascii_digit()) {
            problems.push(Problem::error(
                "pacer::machine::bits",
                span_of(number),
                format!("`{name}` is not a valid bit name"),
                "letters, digits and _",
            ));
        } else {
            b.names.push((name.clone(), n));
        }
    }
    for on in &machine.bits.initially_on {
        let key = on.get_ref();
        let idx = key.parse::<u32>().ok().filter(|n| *n < count).or_else(|| {
            b.names
                .iter()
                .rev()
                .find(|(name, _)| name.eq_ignore_ascii_case(key))
                .map(|(_, n)| *n)
        });
        match idx {
            Some(i) => b.on.push(i),
            None => problems.push(Problem::error(
                "pacer::machine::bits",
                span_of(on),
                format!("no bit `{key}`"),
                "unknown bit",
            )),
        }
    }
    d.bits = b;
}

/// `[queue.N]`.
fn queues(
    machine: &MachineFile,
    d: &mut ObjectsDesc,
    drive: &mut DriveSetup,
    problems: &mut Vec<Problem>,
) {
    let count = drive.queues.len() as u32;
    for (key, setup) in &machine.queue {
        let span = span_of(setup);
        let Some(n) = section_instance(
            key,
            count,
            span,
            "pacer::machine::queue",
            "queue",
            ("queue", "queues"),
            problems,
        ) else {
            continue;
        };
        let s = setup.get_ref();
        let size = s.size.as_ref().map_or(8, |v| *v.get_ref());
        if size == 0 || size > 10_000 {
            let sp = s.size.as_ref().map_or(span, span_of);
            problems.push(Problem::error(
                "pacer::machine::queue",
                sp,
                format!("queue size {size} is out of range"),
                "1 to 10000",
            ));
        }
        let full = s.full_level.as_ref().map_or(size, |v| *v.get_ref());
        if full > size {
            let sp = s.full_level.as_ref().map_or(span, span_of);
            problems.push(Problem::error(
                "pacer::machine::queue",
                sp,
                format!("full level {full} is above the queue size {size}"),
                "at most the size",
            ));
        }
        let q = &mut drive.queues[n as usize];
        if let Some(src) = &s.source {
            match position_source(src.get_ref()) {
                Some(source) => q.source = source,
                None => problems.push(Problem::error(
                    "pacer::machine::queue",
                    span_of(src),
                    format!("unknown queue source `{}`", src.get_ref()),
                    "MasterPosn, FeedbackPosn or CommandPosn",
                )),
            }
        }
        q.size = size;
        q.full_level = full;
        let queue = &catalog::QUEUE_TYPE;
        d.initial(
            queue,
            n,
            crate::member_index!(catalog::QUEUE_TYPE, "QueueOffset"),
            round_to(s.offset, 4),
        );
        d.initial(
            queue,
            n,
            crate::member_index!(catalog::QUEUE_TYPE, "QueueSize"),
            f64::from(size),
        );
        d.initial(
            queue,
            n,
            crate::member_index!(catalog::QUEUE_TYPE, "FullLevel"),
            f64::from(full),
        );
    }
}

/// `MasterPosn`, `FeedbackPosn` or `CommandPosn`, in any case.
fn position_source(text: &str) -> Option<QueueSource> {
    match text.to_ascii_lowercase().as_str() {
        "masterposn" => Some(QueueSource::Master),
        "feedbackposn" => Some(QueueSource::Feedback),
        "commandposn" => Some(QueueSource::Command),
        _ => None,
    }
}

/// `[index.N]` sections: type and time base, and initial member values.
fn indexes(
    machine: &MachineFile,
    d: &mut ObjectsDesc,
    drive: &mut DriveSetup,
    problems: &mut Vec<Problem>,
) {
    let count = drive.indexes.len() as u32;
    for (key, setup) in &machine.index {
        let span = span_of(setup);
        let Some(n) = section_instance(
            key,
            count,
            span,
            "pacer::machine::index",
            "index",
            ("index", "indexes"),
            problems,
        ) else {
            continue;
        };
        let s = setup.get_ref();
        let mut config = IndexConfig::default();
        if let Some(k) = &s.kind {
            match k.get_ref().to_ascii_lowercase().as_str() {
                "incremental" => config.kind = IndexType::Incremental,
                "absolute" => config.kind = IndexType::Absolute,
                "registration" => config.kind = IndexType::Registration,
                "rotaryplus" | "rotary plus" => config.kind = IndexType::RotaryPlus,
                "rotaryminus" | "rotary minus" => config.kind = IndexType::RotaryMinus,
                _ => problems.push(Problem::error(
                    "pacer::machine::index",
                    span_of(k),
                    format!("unknown index type `{}`", k.get_ref()),
                    "Incremental, Absolute, Registration, RotaryPlus or RotaryMinus",
                )),
            }
        }
        if let Some(tb) = &s.time_base {
            match tb.get_ref().to_ascii_lowercase().as_str() {
                "realtime" => config.synchronized = false,
                "synchronized" => config.synchronized = true,
                _ => problems.push(Problem::error(
                    "pacer::machine::index",
                    span_of(tb),
                    format!("unknown time base `{}`", tb.get_ref()),
                    "Realtime or Synchronized",
                )),
            }
        }
        config.timed = s.time.is_some();
        drive.indexes[n as usize] = config;
        let t = &catalog::INDEX_TYPE;
        for (member, index, value, signed) in [
            (
                "time",
                crate::member_index!(catalog::INDEX_TYPE, "Time"),
                s.time,
                false,
            ),
            (
                "distance",
                crate::member_index!(catalog::INDEX_TYPE, "Distance"),
                s.distance,
                true,
            ),
            (
                "velocity",
                crate::member_index!(catalog::INDEX_TYPE, "Velocity"),
                s.velocity,
                false,
            ),
            (
                "acceleration",
                crate::member_index!(catalog::INDEX_TYPE, "Acceleration"),
                s.acceleration,
                false,
            ),
            (
                "deceleration",
                crate::member_index!(catalog::INDEX_TYPE, "Deceleration"),
                s.deceleration,
                false,
            ),
            (
                "registrationoffset",
                crate::member_index!(catalog::INDEX_TYPE, "RegistrationOffset"),
                s.registration_offset,
                true,
            ),
        ] {
            if let Some(v) = value {
                if !v.is_finite() || (!signed && v <= 0.0) {
                    problems.push(Problem::error(
                        "pacer::machine::index",
                        span,
                        format!("[index.{n}] {member}: {v} is out of range"),
                        "must be a number (above 0 for rates)",
                    ));
                } else {
                    d.initial(t, n, index, v);
                }
            }
        }
    }
}

/// `[home.N]` sections: initial members (the reference input is resolved once the registry
/// exists, by `links`).
fn homes(machine: &MachineFile, d: &mut ObjectsDesc, problems: &mut Vec<Problem>) {
    let count = d.count_of(&catalog::HOME_TYPE);
    for (key, setup) in &machine.home {
        let span = span_of(setup);
        let Some(n) = section_instance(
            key,
            count,
            span,
            "pacer::machine::home",
            "home",
            ("home", "homes"),
            problems,
        ) else {
            continue;
        };
        let s = setup.get_ref();
        let t = &catalog::HOME_TYPE;
        for (member, index, value) in [
            (
                "velocity",
                crate::member_index!(catalog::HOME_TYPE, "Velocity"),
                s.velocity,
            ),
            (
                "acceleration",
                crate::member_index!(catalog::HOME_TYPE, "Acceleration"),
                s.acceleration,
            ),
            (
                "deceleration",
                crate::member_index!(catalog::HOME_TYPE, "Deceleration"),
                s.deceleration,
            ),
            (
                "offset",
                crate::member_index!(catalog::HOME_TYPE, "Offset"),
                s.offset,
            ),
        ] {
            if let Some(v) = value {
                let rate = matches!(member, "acceleration" | "deceleration");
                if !v.is_finite() || (rate && v <= 0.0) || (member == "velocity" && v == 0.0) {
                    problems.push(Problem::error(
                        "pacer::machine::home",
                        span,
                        format!("[home.{n}] {member}: {v} is out of range"),
                        "must be a number (not 0 for a velocity, above 0 for a rate)",
                    ));
                } else {
                    d.initial(t, n, index, v);
                }
            }
        }
    }
}

/// `[jog.N]` sections: the jogs' initial velocity and ramps.
fn jogs(machine: &MachineFile, d: &mut ObjectsDesc, problems: &mut Vec<Problem>) {
    let count = d.count_of(&catalog::JOG_TYPE);
    for (key, setup) in &machine.jog {
        let span = span_of(setup);
        let Some(n) = section_instance(
            key,
            count,
            span,
            "pacer::machine::jog",
            "jog",
            ("jog", "jogs"),
            problems,
        ) else {
            continue;
        };
        let s = setup.get_ref();
        for (member, index, value) in [
            (
                "velocity",
                crate::member_index!(catalog::JOG_TYPE, "Velocity"),
                s.velocity,
            ),
            (
                "acceleration",
                crate::member_index!(catalog::JOG_TYPE, "Acceleration"),
                s.acceleration,
            ),
            (
                "deceleration",
                crate::member_index!(catalog::JOG_TYPE, "Deceleration"),
                s.deceleration,
            ),
        ] {
            if let Some(v) = value {
                if !(v.is_finite() && v > 0.0) {
                    problems.push(Problem::error(
                        "pacer::machine::jog",
                        span,
                        format!("[jog.{n}] {member}: {v} is out of range"),
                        "must be above 0",
                    ));
                } else {
                    d.initial(&catalog::JOG_TYPE, n, index, v);
                }
            }
        }
    }
}

/// `[pls.N]` sections: source, rollover, initial window and direction.
fn plss(
    machine: &MachineFile,
    d: &mut ObjectsDesc,
    drive: &mut DriveSetup,
    problems: &mut Vec<Problem>,
) {
    let count = drive.plss.len() as u32;
    for (key, setup) in &machine.pls {
        let span = span_of(setup);
        let Some(n) = section_instance(
            key,
            count,
            span,
            "pacer::machine::pls",
            "pls",
            ("PLS", "PLS"),
            problems,
        ) else {
            continue;
        };
        let s = setup.get_ref();
        let mut config = PlsConfig {
            rollover: s.rollover,
            ..PlsConfig::default()
        };
        if !(s.rollover.is_finite() && s.rollover >= 0.0) {
            problems.push(Problem::error(
                "pacer::machine::pls",
                span,
                format!("[pls.{n}] rollover {} must be 0 or more", s.rollover),
                "out of range",
            ));
        }
        if let Some(src) = &s.source {
            match position_source(src.get_ref()) {
                Some(source) => config.source = source,
                None => problems.push(Problem::error(
                    "pacer::machine::pls",
                    span_of(src),
                    format!("unknown PLS source `{}`", src.get_ref()),
                    "MasterPosn, FeedbackPosn or CommandPosn",
                )),
            }
        }
        drive.plss[n as usize] = config;
        let t = &catalog::PLS_TYPE;
        if let Some(v) = s.on {
            d.initial(t, n, crate::member_index!(catalog::PLS_TYPE, "OnPosn"), v);
        }
        if let Some(v) = s.off {
            d.initial(t, n, crate::member_index!(catalog::PLS_TYPE, "OffPosn"), v);
        }
        if let Some(dir) = &s.direction {
            let x = match dir.get_ref().to_ascii_lowercase().as_str() {
                "both" => Some(0.0),
                "plus" => Some(1.0),
                "minus" => Some(-1.0),
                _ => None,
            };
            match x {
                Some(x) => d.initial(
                    t,
                    n,
                    crate::member_index!(catalog::PLS_TYPE, "Direction"),
                    x,
                ),
                None => problems.push(Problem::error(
                    "pacer::machine::pls",
                    span_of(dir),
                    format!("unknown direction `{}`", dir.get_ref()),
                    "Both, Plus or Minus",
                )),
            }
        }
    }
}

/// `[machine] rollover` and `[units]`, and the rotary indexes that need a rollover.
fn axis_set_up(machine: &MachineFile, drive: &mut DriveSetup, problems: &mut Vec<Problem>) {
    if let Some(r) = &machine.machine.rollover {
        let value = *r.get_ref();
        if value.is_finite() && value >= 0.0 {
            drive.rollover = value;
        } else {
            problems.push(Problem::error(
                "pacer::machine::rollover",
                span_of(r),
                format!("a rollover of {value} is not possible"),
                "0 (none) or more",
            ));
        }
    }
    let u = &machine.units;
    drive.units.motor = u.motor.clone();
    drive.units.master = u.master.clone();
    for (value, target, what) in [
        (
            &u.motor_per_rev,
            &mut drive.units.motor_per_rev,
            "motor_per_rev",
        ),
        (
            &u.motor_counts_per_rev,
            &mut drive.units.motor_counts_per_rev,
            "motor_counts_per_rev",
        ),
        (
            &u.master_counts_per_unit,
            &mut drive.units.master_counts_per_unit,
            "master_counts_per_unit",
        ),
    ] {
        if let Some(x) = value {
            let x_value = *x.get_ref();
            if x_value.is_finite() && x_value > 0.0 {
                *target = x_value;
            } else {
                problems.push(Problem::error(
                    "pacer::machine::units",
                    span_of(x),
                    format!("[units] {what} must be above 0, not {x_value}"),
                    "out of range",
                ));
            }
        }
    }
    if drive.rollover <= 0.0 {
        for (key, setup) in &machine.index {
            let Some(kind) = setup.get_ref().kind.as_ref() else {
                continue;
            };
            if kind.get_ref().to_ascii_lowercase().starts_with("rotary") {
                problems.push(
                    Problem::error(
                        "pacer::machine::index",
                        span_of(kind),
                        format!("[index.{key}] is rotary, but the axis has no rollover"),
                        "needs [machine] rollover",
                    )
                    .with_help("set e.g. rollover = 360.0 under [machine]"),
                );
            }
        }
    }
}

/// The DSP axis numbers `[axis.N]` defines, checking each set-up.
fn axis_numbers(machine: &MachineFile, problems: &mut Vec<Problem>) -> Vec<u32> {
    let mut numbers = Vec::new();
    for (key, setup) in &machine.axis {
        let span = span_of(setup);
        let n = match key.parse::<u32>() {
            Ok(n) if (1..=16).contains(&n) => n,
            _ => {
                problems.push(Problem::error(
                    "pacer::machine::axis",
                    span,
                    format!("`axis.{key}`: axes are numbered 1 to 16"),
                    "not an axis number",
                ));
                continue;
            }
        };
        numbers.push(n);
    }
    for (key, setup) in &machine.axis {
        let s = setup.get_ref();
        let positive = |v: &Option<toml::Spanned<f64>>, what: &str, p: &mut Vec<Problem>| {
            if let Some(v) = v {
                if !(v.get_ref().is_finite() && *v.get_ref() > 0.0) {
                    p.push(Problem::error(
                        "pacer::machine::axis",
                        span_of(v),
                        format!("axis.{key}: {what} must be a positive number"),
                        "not positive",
                    ));
                }
            }
        };
        positive(&s.units_per_rev, "units_per_rev", problems);
        positive(&s.accel, "accel", problems);
        positive(&s.speed, "speed", problems);
        if let Some(q) = &s.queue {
            if !(1..=64).contains(q.get_ref()) {
                problems.push(Problem::error(
                    "pacer::machine::axis",
                    span_of(q),
                    format!("axis.{key}: a queue of {} moves", q.get_ref()),
                    "1 to 64",
                ));
            }
        }
        if let Some(p) = &s.pacer {
            let n = *p.get_ref();
            if !numbers.contains(&n) || key.parse::<u32>().ok() == Some(n) {
                problems.push(
                    Problem::error(
                        "pacer::machine::axis",
                        span_of(p),
                        format!("axis.{key}: pacer {n} is not another axis of this machine"),
                        "no such axis",
                    )
                    .with_help(format!("axes defined: {numbers:?}")),
                );
            }
        }
    }
    numbers
}

/// The DSP axes of `[axis.N]` (their values already checked by [`axis_numbers`]), in the order
/// the file gives them.
pub fn dsp_axes(machine: &MachineFile) -> Vec<DspAxisDesc> {
    machine
        .axis
        .iter()
        .filter_map(|(k, setup)| {
            let n = k.parse::<u32>().ok()?;
            let s = setup.get_ref();
            let mut c = DspAxisConfig::new(
                n,
                s.pacer.as_ref().map(|p| *p.get_ref()),
                s.units_per_rev.as_ref().map_or(1.0, |u| *u.get_ref()),
            );
            if let Some(q) = &s.queue {
                c.queue_depth = *q.get_ref() as usize;
            }
            let defaults = MoveDefaults {
                accel: s
                    .accel
                    .as_ref()
                    .map_or(10.0 * c.units_per_rev, |a| *a.get_ref()),
                speed_rpm: s.speed.as_ref().map_or(100.0, |v| *v.get_ref()),
            };
            Some(DspAxisDesc {
                config: c,
                defaults,
                fast_input: None,
                servo: None,
            })
        })
        .collect()
}

fn valid_ident(s: &str) -> bool {
    let mut c = s.chars();
    matches!(c.next(), Some(ch) if ch.is_ascii_alphabetic() || ch == '_')
        && c.all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
}

/// The instance a `[section.N]` key names, or a problem located on the section; `what` is its
/// object in the singular and the plural.
fn section_instance(
    key: &str,
    count: u32,
    span: Span,
    code: &'static str,
    section: &str,
    what: (&str, &str),
    problems: &mut Vec<Problem>,
) -> Option<u32> {
    let n = key.parse::<u32>().ok().filter(|n| *n < count);
    if n.is_none() {
        problems.push(Problem::error(
            code,
            span,
            format!("[{section}.{key}]: no such {}", what.0),
            format!("{} are 0 to {}", what.1, count.saturating_sub(1)),
        ));
    }
    n
}
