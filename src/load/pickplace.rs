//! `[pickplace]` in machine.toml: what it sets up beyond the module's members — the kinematics,
//! the tool's start position, the real axes' limits, the software limit positions and the belt
//! drives' limits. The members' initial values (`lrPathVel = 2000.0`, `[pickplace.belt.N]
//! lrZDistBelt = 40.0`) are the registry's, which also reports unknown keys and bad belt
//! numbers; this module reports every problem of the keys it reads.

use crate::config::machine::{MachineFile, TomlTable, TomlValue, BELT_SETUP_KEYS};
use crate::config::span_of;
use crate::devices::pickplace::kinematics::delta3::Delta3;
use crate::devices::pickplace::setup::{AxisLimit, BeltSetup, Kinematics, PickPlaceSetup};
use crate::diag::{nearest, Problem};
use toml::Spanned;

const CODE: &str = "pacer::machine::pickplace";

/// The manual's axis names, by axis index 1–13 (stored at 0–12).
pub const AXIS_NAMES: [&str; 13] = [
    "X", "Y", "Z", "A", "B", "C", "A1", "A2", "A3", "A4", "A5", "A6", "Aux1",
];

/// The real axes whose limits `[pickplace.joint.*]` sets.
const JOINTS: [&str; 3] = ["A1", "A2", "A3"];

/// The pick & place set-up of a machine, None when it has no `[pickplace]`. Problems go to
/// `problems` with spans.
pub fn setup(machine: &MachineFile, problems: &mut Vec<Problem>) -> Option<PickPlaceSetup> {
    let table = machine.pickplace.as_ref()?.get_ref();
    let kinematics = kinematics(table, problems);
    let start = match table.get("start") {
        Some(v) => numbers::<3>(
            v,
            "start",
            "the tool's X, Y and Z at the start, mm",
            problems,
        )
        .unwrap_or([0.0; 3]),
        None => [0.0; 3],
    };
    let joint_limits = table
        .get("joint")
        .map_or([AxisLimit::default(); 3], |v| joint_limits(v, problems));
    let sw_limits = table
        .get("sw_limit")
        .map_or([None; 13], |v| sw_limits(v, problems));
    let belts = crate::registry::belt_sections(machine, None)
        .into_iter()
        .map(|(number, t)| BeltSetup {
            number,
            limit: belt_limit(number, t, problems),
        })
        .collect();
    Some(PickPlaceSetup {
        kinematics,
        joint_limits,
        sw_limits,
        start,
        belts,
    })
}

/// `kinematics` and `delta3`.
fn kinematics(table: &TomlTable, problems: &mut Vec<Problem>) -> Kinematics {
    let delta3 = table.get("delta3");
    let mut want_delta3 = false;
    let mut known = true;
    if let Some(k) = table.get("kinematics") {
        match k.get_ref() {
            TomlValue::String(s) if s.eq_ignore_ascii_case("cartesian") => {}
            TomlValue::String(s) if s.eq_ignore_ascii_case("delta3") => want_delta3 = true,
            other => {
                known = false;
                let message = match other {
                    TomlValue::String(s) => format!("unknown kinematics `{s}`"),
                    _ => format!("kinematics is a name, not {}", other.describe()),
                };
                problems.push(
                    Problem::error(CODE, span_of(k), message, "unknown kinematics")
                        .with_help("kinematics = \"cartesian\" (the default) or \"delta3\""),
                );
            }
        }
        if want_delta3 && delta3.is_none() {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(k),
                    "a Delta3 robot needs its dimensions",
                    "no delta3 = { … }",
                )
                .with_help("add delta3 = { f = 400.0, e = 80.0, rf = 250.0, re = 700.0 } (mm)"),
            );
        }
    }
    let Some(d) = delta3 else {
        return Kinematics::Cartesian;
    };
    let robot = delta3_of(d, problems);
    if !want_delta3 && known {
        problems.push(
            Problem::warning(
                CODE,
                span_of(d),
                "delta3 is given, but the kinematics is cartesian: it is not used",
                "not used",
            )
            .with_help("set kinematics = \"delta3\" to use it"),
        );
        return Kinematics::Cartesian;
    }
    robot.map_or(Kinematics::Cartesian, Kinematics::Delta3)
}

/// `delta3 = { f, e, rf, re }`.
fn delta3_of(d: &Spanned<TomlValue>, problems: &mut Vec<Problem>) -> Option<Delta3> {
    const KEYS: [&str; 4] = ["f", "e", "rf", "re"];
    let help = "delta3 = { f = …, e = …, rf = …, re = … }: base side, effector side, upper arm, \
                forearm (mm)";
    let TomlValue::Table(t) = d.get_ref() else {
        problems.push(
            Problem::error(
                CODE,
                span_of(d),
                format!("delta3 is {}, not a table", d.get_ref().describe()),
                "not a table",
            )
            .with_help(help),
        );
        return None;
    };
    let mut dims = [None; 4];
    let mut ok = true;
    for (key, value) in &t.entries {
        let Some(i) = KEYS.iter().position(|k| k == key.get_ref()) else {
            problems.push(unknown(key, &KEYS, "delta3", help));
            ok = false;
            continue;
        };
        match finite(value, &format!("delta3 {}", KEYS[i]), problems) {
            Some(x) => dims[i] = Some(x),
            None => ok = false,
        }
    }
    let missing: Vec<&str> = KEYS
        .iter()
        .zip(dims)
        .filter(|(_, v)| v.is_none())
        .map(|(k, _)| *k)
        .collect();
    if ok && !missing.is_empty() {
        problems.push(
            Problem::error(
                CODE,
                span_of(d),
                format!("delta3 lacks {}", missing.join(", ")),
                "incomplete",
            )
            .with_help(help),
        );
    }
    let [Some(f), Some(e), Some(rf), Some(re)] = dims else {
        return None;
    };
    Delta3::new(f, e, rf, re)
        .map_err(|err| {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(d),
                    format!("not a Delta3 robot: {err}"),
                    "bad geometry",
                )
                .with_help(help),
            );
        })
        .ok()
}

/// `[pickplace.joint.A1]` … `[pickplace.joint.A3]`.
fn joint_limits(v: &Spanned<TomlValue>, problems: &mut Vec<Problem>) -> [AxisLimit; 3] {
    let mut limits = [AxisLimit::default(); 3];
    let Some(t) = table(v, "joint", "[pickplace.joint.A1] max_vel = …", problems) else {
        return limits;
    };
    for (key, section) in &t.entries {
        let Some(i) = JOINTS
            .iter()
            .position(|j| j.eq_ignore_ascii_case(key.get_ref()))
        else {
            problems.push(unknown(
                key,
                &JOINTS,
                "joint",
                "the joints are the real axes A1, A2 and A3: [pickplace.joint.A1] …",
            ));
            continue;
        };
        limits[i] = limit(section, &format!("joint {}", JOINTS[i]), problems);
    }
    limits
}

/// `[pickplace.sw_limit]`: `Z = [min, max]` per axis.
fn sw_limits(v: &Spanned<TomlValue>, problems: &mut Vec<Problem>) -> [Option<(f64, f64)>; 13] {
    let mut limits = [None; 13];
    let Some(t) = table(
        v,
        "sw_limit",
        "[pickplace.sw_limit] Z = [-900.0, -300.0]",
        problems,
    ) else {
        return limits;
    };
    for (key, value) in &t.entries {
        let Some(i) = AXIS_NAMES
            .iter()
            .position(|a| a.eq_ignore_ascii_case(key.get_ref()))
        else {
            problems.push(unknown(
                key,
                &AXIS_NAMES,
                "sw_limit",
                &format!(
                    "software limits are set per axis: {}",
                    AXIS_NAMES.join(", ")
                ),
            ));
            continue;
        };
        let what = format!("sw_limit {}", AXIS_NAMES[i]);
        let Some([min, max]) = numbers::<2>(value, &what, "[min, max]", problems) else {
            continue;
        };
        if min >= max {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(value),
                    format!("{what}: the minimum {min} is not below the maximum {max}"),
                    "min ≥ max",
                )
                .with_help("give [min, max] with min < max"),
            );
            continue;
        }
        limits[i] = Some((min, max));
    }
    limits
}

/// The drive limits of belt `n`: `max_vel`, `max_acc`, `max_jerk` in its section (the other
/// keys are its members).
fn belt_limit(n: u32, t: &TomlTable, problems: &mut Vec<Problem>) -> AxisLimit {
    let mut l = AxisLimit::default();
    for (key, value) in &t.entries {
        let target = match key.get_ref().as_str() {
            "max_vel" => &mut l.max_vel,
            "max_acc" => &mut l.max_acc,
            "max_jerk" => &mut l.max_jerk,
            _ => continue,
        };
        if let Some(x) = non_negative(value, &format!("belt {n} {}", key.get_ref()), problems) {
            *target = x;
        }
    }
    l
}

/// A table of `max_vel`, `max_acc`, `max_jerk`.
fn limit(v: &Spanned<TomlValue>, what: &str, problems: &mut Vec<Problem>) -> AxisLimit {
    let mut l = AxisLimit::default();
    let Some(t) = table(v, what, "max_vel = …, max_acc = …, max_jerk = …", problems) else {
        return l;
    };
    for (key, value) in &t.entries {
        let target = match key.get_ref().as_str() {
            "max_vel" => &mut l.max_vel,
            "max_acc" => &mut l.max_acc,
            "max_jerk" => &mut l.max_jerk,
            _ => {
                problems.push(unknown(
                    key,
                    BELT_SETUP_KEYS,
                    what,
                    "limits are max_vel, max_acc and max_jerk (units/s, /s², /s³; 0: no limit)",
                ));
                continue;
            }
        };
        if let Some(x) = non_negative(value, &format!("{what} {}", key.get_ref()), problems) {
            *target = x;
        }
    }
    l
}

/// The table `v` is, or a problem.
fn table<'a>(
    v: &'a Spanned<TomlValue>,
    what: &str,
    example: &str,
    problems: &mut Vec<Problem>,
) -> Option<&'a TomlTable> {
    match v.get_ref() {
        TomlValue::Table(t) => Some(t),
        other => {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(v),
                    format!("{what} is {}, not a table", other.describe()),
                    "not a table",
                )
                .with_help(format!("e.g. {example}")),
            );
            None
        }
    }
}

/// A finite number, or a problem.
fn finite(v: &Spanned<TomlValue>, what: &str, problems: &mut Vec<Problem>) -> Option<f64> {
    match v.get_ref().as_number() {
        Some(x) if x.is_finite() => Some(x),
        Some(x) => {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(v),
                    format!("{what} must be a finite number, not {x}"),
                    "not finite",
                )
                .with_help("give a finite number"),
            );
            None
        }
        None => {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(v),
                    format!("{what} takes a number, not {}", v.get_ref().describe()),
                    "not a number",
                )
                .with_help("give a number, e.g. 100.0"),
            );
            None
        }
    }
}

/// A finite number ≥ 0 (a limit; 0 means none), or a problem.
fn non_negative(v: &Spanned<TomlValue>, what: &str, problems: &mut Vec<Problem>) -> Option<f64> {
    let x = finite(v, what, problems)?;
    if x < 0.0 {
        problems.push(
            Problem::error(
                CODE,
                span_of(v),
                format!("{what} is {x}: a limit cannot be negative"),
                "negative",
            )
            .with_help("give a positive limit, or 0 for none"),
        );
        return None;
    }
    Some(x)
}

/// An array of exactly `N` finite numbers, or a problem.
fn numbers<const N: usize>(
    v: &Spanned<TomlValue>,
    what: &str,
    meaning: &str,
    problems: &mut Vec<Problem>,
) -> Option<[f64; N]> {
    let TomlValue::Array(items) = v.get_ref() else {
        problems.push(
            Problem::error(
                CODE,
                span_of(v),
                format!("{what} takes {N} numbers, not {}", v.get_ref().describe()),
                "not an array",
            )
            .with_help(format!("give {meaning}")),
        );
        return None;
    };
    if items.len() != N {
        problems.push(
            Problem::error(
                CODE,
                span_of(v),
                format!("{what} takes {N} numbers, not {}", items.len()),
                format!("{} values", items.len()),
            )
            .with_help(format!("give {meaning}")),
        );
        return None;
    }
    let mut out = [0.0; N];
    let mut ok = true;
    for (slot, item) in out.iter_mut().zip(items) {
        match finite(item, what, problems) {
            Some(x) => *slot = x,
            None => ok = false,
        }
    }
    ok.then_some(out)
}

/// An unknown key of `what`, with the nearest valid one, or else `help`.
fn unknown(key: &Spanned<String>, valid: &[&str], what: &str, help: &str) -> Problem {
    let name = key.get_ref();
    Problem::error(
        CODE,
        span_of(key),
        format!("{what}: unknown key `{name}`"),
        "unknown key",
    )
    .with_help(match nearest(name, valid.iter().copied()) {
        Some(n) => format!("did you mean `{n}`? ({help})"),
        None => help.to_string(),
    })
}
