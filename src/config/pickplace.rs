//! `[pickplace]` in machine.toml: the module's set-up — the kinematics, the tool's start
//! position, the real axes' limits, the software limit positions and the belt drives' limits —
//! and the initial values of the members it names (`lrPathVel = 2000.0`, `[pickplace.belt.N]
//! lrZDistBelt = 40.0`), every key checked.

use super::desc::ObjectsDesc;
use crate::config::machine::{
    MachineFile, TomlTable, TomlValue, BELT_SETUP_KEYS, PICKPLACE_SETUP_KEYS,
};
use crate::config::span_of;
use crate::devices::pickplace::kinematics::delta3::Delta3;
use crate::devices::pickplace::setup::{AxisLimit, BeltSetup, Kinematics, PickPlaceSetup};
use crate::diag::{nearest, Problem};
use crate::registry::catalog::{
    self, Access, Kind, MemberDef, TypeDef, ValueType, BELT_TYPE, MAX_BELTS, PICK_PLACE_TYPE,
};
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
    let belts = belt_sections(machine, None)
        .into_iter()
        .map(|(number, t)| BeltSetup {
            number,
            limit: belt_limit(number, t, problems),
        })
        .collect();
    // Spread by default: a path prepared within one update makes that update late (hundreds of
    // µs, issue 19); `prep_budget = false` asks for that.
    let prep_budget = match table.get("prep_budget") {
        Some(v) => prep_budget(v, problems),
        None => Some(crate::devices::pickplace::module::PREP_BUDGET),
    };
    Some(PickPlaceSetup {
        kinematics,
        joint_limits,
        sw_limits,
        start,
        belts,
        prep_budget,
    })
}

/// `prep_budget = 250`: work units of path preparation per update (a whole number from 20
/// up; see docs/pick-and-place.md), `true` for the default, or `false` for none (planned
/// within the update).
fn prep_budget(v: &Spanned<TomlValue>, problems: &mut Vec<Problem>) -> Option<u64> {
    match v.get_ref() {
        TomlValue::Bool(false) => None,
        TomlValue::Bool(true) => Some(crate::devices::pickplace::module::PREP_BUDGET),
        TomlValue::Integer(n) if *n >= 20 => u64::try_from(*n).ok(),
        other => {
            let what = match other {
                TomlValue::Integer(n) => format!("{n}"),
                _ => other.describe().to_string(),
            };
            problems.push(
                Problem::error(
                    CODE,
                    span_of(v),
                    format!(
                        "prep_budget is a whole number of work units from 20 up (one move built), or true/false, not {what}"
                    ),
                    "not a budget",
                )
                .with_help("prep_budget = 250 (about 9 µs an update, the default), true for that, or false to plan each path within one update"),
            );
            None
        }
    }
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

/// The belt sections `[pickplace.belt.N]`, checked: the valid ones, number and table.
pub fn belt_sections<'m>(
    machine: &'m MachineFile,
    mut problems: Option<&mut Vec<Problem>>,
) -> Vec<(u32, &'m TomlTable)> {
    let mut belts = Vec::new();
    let Some(pp) = &machine.pickplace else {
        return belts;
    };
    let Some(value) = pp.get_ref().get("belt") else {
        return belts;
    };
    let TomlValue::Table(table) = value.get_ref() else {
        if let Some(p) = problems.as_deref_mut() {
            p.push(
                Problem::error(
                    CODE,
                    span_of(value),
                    format!(
                        "`belt` is {}, not a table of belts",
                        value.get_ref().describe()
                    ),
                    "not a table",
                )
                .with_help("give each belt a section: [pickplace.belt.1]"),
            );
        }
        return belts;
    };
    for (key, section) in &table.entries {
        let number = key
            .get_ref()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=MAX_BELTS).contains(n));
        let Some(n) = number else {
            if let Some(p) = problems.as_deref_mut() {
                p.push(
                    Problem::error(
                        CODE,
                        span_of(key),
                        format!("[pickplace.belt.{}]: no such belt", key.get_ref()),
                        "not a belt number",
                    )
                    .with_help(format!(
                        "belts are numbered 1 to {} (CV1 … CV{})",
                        MAX_BELTS, MAX_BELTS
                    )),
                );
            }
            continue;
        };
        if belts.iter().any(|(m, _)| *m == n) {
            if let Some(p) = problems.as_deref_mut() {
                p.push(Problem::error(
                    CODE,
                    span_of(key),
                    format!("belt {n} is set up twice"),
                    "again",
                ));
            }
            continue;
        }
        match section.get_ref() {
            TomlValue::Table(t) => belts.push((n, t)),
            other => {
                if let Some(p) = problems.as_deref_mut() {
                    p.push(
                        Problem::error(
                            CODE,
                            span_of(section),
                            format!("belt {n} is {}, not a table", other.describe()),
                            "not a table",
                        )
                        .with_help(format!("write its settings under [pickplace.belt.{n}]")),
                    );
                }
            }
        }
    }
    belts.sort_by_key(|(n, _)| *n);
    belts
}

/// The number of belts: the highest `[pickplace.belt.N]`; reports bad belt numbers.
pub fn belt_count(machine: &MachineFile, problems: &mut Vec<Problem>) -> u32 {
    belt_sections(machine, Some(problems))
        .iter()
        .map(|(n, _)| *n)
        .max()
        .unwrap_or(0)
}

/// `[pickplace]` and `[pickplace.belt.N]`: the initial values of the members they name. The
/// other keys (kinematics, limits) are [`setup`]'s.
pub fn initials(machine: &MachineFile, d: &mut ObjectsDesc, problems: &mut Vec<Problem>) {
    let Some(pp) = &machine.pickplace else {
        return;
    };
    for (key, value) in &pp.get_ref().entries {
        if !PICKPLACE_SETUP_KEYS.contains(&key.get_ref().as_str()) {
            member_initial(d, &PICK_PLACE_TYPE, 0, key, value, problems);
        }
    }
    for (n, table) in belt_sections(machine, None) {
        for (key, value) in &table.entries {
            if !BELT_SETUP_KEYS.contains(&key.get_ref().as_str()) {
                member_initial(d, &BELT_TYPE, n - 1, key, value, problems);
            }
        }
    }
}

/// One `key = value` of a pick & place section: a member, an element (`"alrStopDec[2]"`) or a
/// whole array (`alrStopDec = [ … ]`).
fn member_initial(
    d: &mut ObjectsDesc,
    ty: &TypeDef,
    instance: u32,
    key: &toml::Spanned<String>,
    value: &toml::Spanned<TomlValue>,
    problems: &mut Vec<Problem>,
) {
    {
        let kind = ty.kind;
        let members = ty.members;
        let (section, setup_keys) = if kind == Kind::Belt {
            (
                format!("[pickplace.belt.{}]", instance + 1),
                BELT_SETUP_KEYS,
            )
        } else {
            ("[pickplace]".to_string(), PICKPLACE_SETUP_KEYS)
        };
        let name = key.get_ref().as_str();
        let (first, len, array) = match catalog::member_position(members, name) {
            Some(i) => (i, 1, false),
            None => match catalog::find_array(members, name) {
                Some((first, len)) => (first, len, true),
                None => {
                    problems.push(unknown_key(key, members, setup_keys, &section));
                    return;
                }
            },
        };
        let def = &members[first];
        if def.access != Access::ReadWrite {
            let what = if kind == Kind::Belt {
                "a status of the belt"
            } else {
                "an output of the module"
            };
            problems.push(
                Problem::error(
                    CODE,
                    span_of(key),
                    format!(
                        "{section}: `{}` is {what}; it cannot be given a value",
                        base_name(def.name, array)
                    ),
                    "read-only",
                )
                .with_help("only inputs and parameters take values here"),
            );
            return;
        }
        if !array {
            if let Some(x) = member_value(def, value, &section, problems) {
                d.initial(ty, instance, first, x);
            }
            return;
        }
        let base = base_name(def.name, true);
        let TomlValue::Array(items) = value.get_ref() else {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(value),
                    format!(
                        "{section}: `{base}` is an array of {len}: it takes {len} values, not {}",
                        value.get_ref().describe()
                    ),
                    "not an array",
                )
                .with_help(format!(
                    "give all {len} values in [ ], or one element as \"{base}[1]\" = …"
                )),
            );
            return;
        };
        if items.len() != len {
            problems.push(
                Problem::error(
                    CODE,
                    span_of(value),
                    format!(
                        "{section}: `{base}` has {len} elements, not {}",
                        items.len()
                    ),
                    format!("{} values", items.len()),
                )
                .with_help(format!(
                    "give exactly {len} values, or set single elements as \"{base}[k]\" = …"
                )),
            );
            return;
        }
        for (i, item) in items.iter().enumerate() {
            if let Some(x) = member_value(&members[first + i], item, &section, problems) {
                d.initial(ty, instance, first + i, x);
            }
        }
    }
}

/// `alrStopDec[1]` → `alrStopDec` for an array's element.
fn base_name(name: &str, array: bool) -> &str {
    match catalog::split_index(name) {
        Some((base, _)) if array => base,
        _ => name,
    }
}

/// The problem for a key of a pick & place section that names nothing.
fn unknown_key(
    key: &toml::Spanned<String>,
    members: &'static [MemberDef],
    setup_keys: &[&'static str],
    section: &str,
) -> Problem {
    let name = key.get_ref();
    let span = span_of(key);
    if let Some((base, index)) = catalog::split_index(name) {
        if let Some((_, len)) = catalog::find_array(members, base) {
            return Problem::error(
                CODE,
                span,
                format!("{section}: `{name}`: {base} has no element {index}"),
                "index out of range",
            )
            .with_help(format!("its elements are {base}[1] to {base}[{len}]"));
        }
    }
    let mut candidates: Vec<&str> = setup_keys.to_vec();
    for m in members {
        let base = base_name(m.name, true);
        if !candidates.contains(&base) {
            candidates.push(base);
        }
    }
    let help = match nearest(name, candidates.iter().copied()) {
        Some(n) => format!("did you mean `{n}`?"),
        None => format!(
            "keys are the manual's names of the inputs and parameters, and {}",
            setup_keys.join(", ")
        ),
    };
    Problem::error(
        CODE,
        span,
        format!("{section}: unknown key `{name}`"),
        "unknown key",
    )
    .with_help(help)
}

/// The value `value` gives the member `def`, or a problem located on it.
fn member_value(
    def: &MemberDef,
    value: &toml::Spanned<TomlValue>,
    section: &str,
    problems: &mut Vec<Problem>,
) -> Option<f64> {
    let v = value.get_ref();
    let span = span_of(value);
    let name = format!("{section}: `{}`", def.name);
    let problem = |message: String, label: &str, help: &str| {
        Problem::error(CODE, span, message, label).with_help(help)
    };
    let result = match (def.ty, v) {
        (ValueType::Bit, TomlValue::Bool(b)) => Ok(f64::from(u8::from(*b))),
        (ValueType::Bit, TomlValue::Integer(i @ (0 | 1))) => Ok(*i as f64),
        (ValueType::Bit, _) => Err(problem(
            format!("{name} is a bit, not {}", v.describe()),
            "not a bit",
            "give true or false (or 1 or 0)",
        )),
        (_, TomlValue::Float(x)) if !x.is_finite() => Err(problem(
            format!("{name} must be a finite number, not {x}"),
            "not finite",
            "give a finite number",
        )),
        (ValueType::Integer | ValueType::Fixed(_), _) => match v.as_number() {
            Some(x)
                if x.fract() == 0.0 && (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&x) =>
            {
                Ok(x)
            }
            Some(x) => Err(problem(
                format!("{name} is an integer: {x} is not one"),
                "not an integer",
                "give a whole number",
            )),
            None => Err(problem(
                format!("{name} takes an integer, not {}", v.describe()),
                "not an integer",
                "give a whole number",
            )),
        },
        (ValueType::Real, _) => v.as_number().ok_or_else(|| {
            problem(
                format!("{name} takes a number, not {}", v.describe()),
                "not a number",
                "give a number, e.g. 100.0",
            )
        }),
    };
    result.map_err(|p| problems.push(p)).ok()
}
