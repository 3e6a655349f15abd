//! `[servo]` and `[axis.N.servo]`: the servo loops of the PowerTools drive's axis and of the
//! DSP axes. Every value is checked against its range, with a problem located on it; a valid
//! `cascade` section becomes the axis's [`ServoParams`], and its `following_error_limit` the
//! initial `FollowingErrorLimit` with `FollowingErrorEnable` on.

use super::desc::{DspAxisDesc, ObjectsDesc};
use super::machine::{MachineFile, ServoSection};
use super::span_of;
use crate::devices::drive::setup::DriveSetup;
use crate::devices::servo::ServoParams;
use crate::diag::{number, Problem};
use crate::registry::catalog::{self, TypeDef};
use toml::Spanned;

/// The most loop steps in one update (`loop_rate` × the update period): each costs time every
/// update, so this bounds a run's time as the update count does.
pub const MAX_LOOP_STEPS: f64 = 10_000.0;

/// The velocity limit when a section gives none, rpm.
const DEFAULT_TOP_RPM: f64 = 5000.0;

/// Encoder counts per revolution of a DSP axis whose `[axis.N.servo]` gives none.
const DEFAULT_COUNTS_PER_REV: f64 = 4096.0;

/// The longest latch delay, seconds (a hardware latch answers in microseconds).
const MAX_LATCH_DELAY: f64 = 1e-3;

/// A number of a servo section: its key, where it goes, and the range it must be in.
struct Field<'a> {
    key: &'static str,
    value: &'a Option<Spanned<f64>>,
    min: f64,
    /// `min` itself is allowed.
    min_ok: bool,
    max: f64,
    unit: &'static str,
}

/// Check `[servo]` and set the drive's loop up from it. `update_s` is the machine's update
/// period (the loop must fit a bounded number of steps in it).
pub fn servo(
    machine: &MachineFile,
    update_s: f64,
    d: &mut ObjectsDesc,
    drive: &mut DriveSetup,
    problems: &mut Vec<Problem>,
) {
    let Some(section) = &machine.servo else {
        return;
    };
    let counts = section
        .get_ref()
        .counts_per_rev
        .as_ref()
        .map_or(drive.units.motor_counts_per_rev, |c| *c.get_ref());
    let units = (drive.units.motor_per_rev, counts);
    let (params, limit) = loop_of(section, "[servo]", units, update_s, problems);
    drive.servo = params;
    if let Some(x) = limit {
        set_limit(d, &catalog::MOTION_TYPE, 0, x);
    }
}

/// Check each `[axis.N.servo]` and set the DSP axis's loop up from it (`dsp` as
/// `objects::dsp_axes` made it).
pub fn dsp_servos(
    machine: &MachineFile,
    update_s: f64,
    dsp: &mut [DspAxisDesc],
    problems: &mut Vec<Problem>,
) {
    for (key, setup) in &machine.axis {
        let Some(section) = &setup.get_ref().servo else {
            continue;
        };
        let Ok(n) = key.parse::<u32>() else { continue };
        let Some(axis) = dsp.iter_mut().find(|a| a.config.number == n) else {
            continue;
        };
        let counts = section
            .get_ref()
            .counts_per_rev
            .as_ref()
            .map_or(DEFAULT_COUNTS_PER_REV, |c| *c.get_ref());
        let name = format!("[axis.{n}.servo]");
        if !(counts.is_finite() && (1.0..=1e12).contains(&counts)) {
            if let Some(c) = &section.get_ref().counts_per_rev {
                problems.push(Problem::error(
                    "pacer::machine::servo",
                    span_of(c),
                    format!("{name} counts_per_rev {} is out of range", number(counts)),
                    "from 1 to 1e12",
                ));
            }
            continue;
        }
        let units = (axis.config.units_per_rev, counts);
        axis.servo = loop_of(section, &name, units, update_s, problems).0;
    }
}

/// The initial `FollowingErrorLimit` / `FollowingErrorEnable` of the DSP axes whose
/// `[axis.N.servo]` gives a valid `following_error_limit` (its problems are reported by
/// [`dsp_servos`]).
pub fn dsp_initials(machine: &MachineFile, d: &mut ObjectsDesc) {
    for (key, setup) in &machine.axis {
        let Some(section) = &setup.get_ref().servo else {
            continue;
        };
        let Ok(n) = key.parse::<u32>() else { continue };
        if n == 0 {
            continue;
        }
        let field = limit_field(&section.get_ref().following_error_limit);
        if let Some(x) = checked(&field, "", &mut Vec::new()) {
            set_limit(d, &catalog::AXIS_TYPE, n - 1, x);
        }
    }
}

fn limit_field(value: &Option<Spanned<f64>>) -> Field<'_> {
    Field {
        key: "following_error_limit",
        value,
        min: 0.0,
        min_ok: false,
        max: 1e9,
        unit: "units",
    }
}

/// `FollowingErrorLimit` of instance `instance` of `ty` starts at `x`, with
/// `FollowingErrorEnable` on.
fn set_limit(d: &mut ObjectsDesc, ty: &TypeDef, instance: u32, x: f64) {
    let index = |name: &str| ty.members.iter().position(|m| m.name == name);
    if let (Some(limit), Some(enable)) =
        (index("FollowingErrorLimit"), index("FollowingErrorEnable"))
    {
        d.initial(ty, instance, limit, x);
        d.initial(ty, instance, enable, 1.0);
    }
}

/// One servo section (`name` in messages): its loop (`None` when ideal or in error) and its
/// following-error limit. `units` are (user units, encoder counts) per motor revolution.
fn loop_of(
    section: &Spanned<ServoSection>,
    name: &str,
    units: (f64, f64),
    update_s: f64,
    problems: &mut Vec<Problem>,
) -> (Option<ServoParams>, Option<f64>) {
    let s = section.get_ref();
    let cascade = match &s.model {
        None => true,
        Some(m) => match m.get_ref().to_ascii_lowercase().as_str() {
            "ideal" => false,
            "cascade" => true,
            other => {
                problems.push(
                    Problem::error(
                        "pacer::machine::servo",
                        span_of(m),
                        format!("{name} model `{other}` is not a servo model"),
                        "ideal or cascade",
                    )
                    .with_help(
                        "`ideal`: feedback equals command; `cascade`: the position / velocity loop",
                    ),
                );
                return (None, None);
            }
        },
    };
    let (units_per_rev, counts_per_rev) = units;
    let mut p = ServoParams {
        units_per_rev,
        counts_per_rev,
        // A servo motor's usual top speed, 5,000 rpm, unless the section says otherwise.
        velocity_limit: DEFAULT_TOP_RPM / 60.0 * units_per_rev,
        ..ServoParams::default()
    };
    let mut ratio_given = false;
    let before = problems.len();
    let limit;
    {
        let ServoSection {
            loop_rate,
            position_gain,
            velocity_gain,
            velocity_integral,
            velocity_feedforward,
            acceleration_feedforward,
            motor_inertia,
            load_inertia,
            inertia_ratio,
            torque_limit,
            velocity_limit,
            following_error_limit,
            ..
        } = s;
        let gain = |key, value, max, unit| Field {
            key,
            value,
            min: 0.0,
            min_ok: false,
            max,
            unit,
        };
        let fields = [
            (gain("loop_rate", loop_rate, 1e6, "Hz"), &mut p.loop_rate),
            (
                gain("position_gain", position_gain, 1e5, "1/s"),
                &mut p.position_gain,
            ),
            (
                gain("velocity_gain", velocity_gain, 1e6, "rad/s"),
                &mut p.velocity_gain,
            ),
            (
                Field {
                    min_ok: true,
                    ..gain("velocity_integral", velocity_integral, 1e9, "1/s²")
                },
                &mut p.velocity_integral,
            ),
            (
                Field {
                    min_ok: true,
                    ..gain("velocity_feedforward", velocity_feedforward, 200.0, "%")
                },
                &mut p.velocity_feedforward,
            ),
            (
                Field {
                    min_ok: true,
                    ..gain(
                        "acceleration_feedforward",
                        acceleration_feedforward,
                        200.0,
                        "%",
                    )
                },
                &mut p.acceleration_feedforward,
            ),
            (
                gain("motor_inertia", motor_inertia, 1e3, "kg·m²"),
                &mut p.motor_inertia,
            ),
            (
                Field {
                    min_ok: true,
                    ..gain("load_inertia", load_inertia, 1e3, "kg·m²")
                },
                &mut p.load_inertia,
            ),
            (
                Field {
                    min_ok: true,
                    ..gain("inertia_ratio", inertia_ratio, 1e3, "")
                },
                &mut p.inertia_ratio,
            ),
            (
                gain("torque_limit", torque_limit, 1e6, "N·m"),
                &mut p.torque_limit,
            ),
            (
                gain("velocity_limit", velocity_limit, 1e9, "units/s"),
                &mut p.velocity_limit,
            ),
        ];
        for (field, target) in fields {
            if let Some(x) = checked(&field, name, problems) {
                *target = x;
                if field.key == "inertia_ratio" {
                    ratio_given = true;
                }
            }
        }
        limit = checked(&limit_field(following_error_limit), name, problems);
    }
    // Feedforwards are written in percent, as the drive's set-up shows them.
    if s.velocity_feedforward.is_some() {
        p.velocity_feedforward /= 100.0;
    }
    if s.acceleration_feedforward.is_some() {
        p.acceleration_feedforward /= 100.0;
    }
    if !ratio_given {
        p.inertia_ratio = p.load_inertia / p.motor_inertia;
    }
    if let Some(delay) = &s.latch_delay {
        let x = delay.get_ref().seconds();
        if x <= MAX_LATCH_DELAY {
            p.latch_delay = x;
        } else {
            problems.push(Problem::error(
                "pacer::machine::servo",
                span_of(delay),
                format!("{name} latch_delay {} s is out of range", number(x)),
                "0 to 1 ms",
            ));
        }
    }
    let steps = update_s * p.loop_rate;
    if steps > MAX_LOOP_STEPS {
        let span = s
            .loop_rate
            .as_ref()
            .map_or_else(|| span_of(section), span_of);
        problems.push(
            Problem::error(
                "pacer::machine::servo",
                span,
                format!(
                    "{name} loop_rate {} Hz makes {} loop steps per update",
                    number(p.loop_rate),
                    super::limits::thousands(steps.ceil() as u64)
                ),
                "at most 10,000 loop steps per update",
            )
            .with_help("lower loop_rate, or shorten [machine] update"),
        );
    }
    let params = (cascade && problems.len() == before).then_some(p);
    (params, limit)
}

/// The value of `field`, if it is given and in its range (a problem on it otherwise).
fn checked(field: &Field<'_>, name: &str, problems: &mut Vec<Problem>) -> Option<f64> {
    let v = field.value.as_ref()?;
    let x = *v.get_ref();
    let above_min = if field.min_ok {
        x >= field.min
    } else {
        x > field.min
    };
    if x.is_finite() && above_min && x <= field.max {
        return Some(x);
    }
    let from = if field.min_ok { "from" } else { "above" };
    let unit = if field.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", field.unit)
    };
    problems.push(Problem::error(
        "pacer::machine::servo",
        span_of(v),
        format!("{name} {} {}{unit} is out of range", field.key, number(x)),
        format!(
            "{from} {} to {}{unit}",
            number(field.min),
            number(field.max)
        ),
    ));
    None
}
