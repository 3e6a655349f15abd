//! Which members the exporters write, what they are called there, and how their values are
//! written: one place for the naming and formatting rules the VCD, CSV and plots share.

use crate::registry::{Kind, Registry, SlotId, SlotInfo, ValueType};

use super::ExportError;
use crate::check::motionbasic::SUBSCRIPT;

/// What a signal holds, as the exporters write it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SignalKind {
    /// ON/OFF: a VCD wire, 0/1 in CSV.
    Bit,
    /// A whole number (integers and fixed point with no decimals): a VCD integer.
    Integer,
    /// Anything else, positions and velocities above all: a VCD real.
    Real,
}

impl SignalKind {
    /// The kind a member of this type is written as.
    pub fn of(ty: ValueType) -> SignalKind {
        match ty {
            ValueType::Bit => SignalKind::Bit,
            ValueType::Integer | ValueType::Fixed(0) => SignalKind::Integer,
            _ => SignalKind::Real,
        }
    }
}

/// One registry member chosen for export.
#[derive(Debug, Clone, PartialEq)]
pub struct Signal {
    /// Its slot in the machine's value array.
    pub slot: SlotId,
    /// Its canonical name (`Queue.0.QueueCount`), as the trace writes it.
    pub name: String,
    /// How it is written.
    pub kind: SignalKind,
    /// It moves every update (positions, velocities) and so is not in the trace's changes.
    pub continuous: bool,
    /// A MotionBASIC text variable or element (`N$`, `B$(2)`): its slot holds the number of
    /// its string, and the CSV writes the string.
    pub text: bool,
}

impl Signal {
    fn from_slot(slot: SlotId, info: &SlotInfo) -> Signal {
        Signal {
            slot,
            name: info.name.to_string(),
            kind: SignalKind::of(info.ty),
            continuous: info.member.continuous,
            text: info.kind == Kind::BasicVar && info.name.is_text(),
        }
    }
}

/// Members that restate another member in other units or restate the clock: `MotorRevs`,
/// `MotorCounts`, `MasterCounts` (feedback and master positions scaled) and `FreeRunTime` (the
/// time axis itself). They change every update, so the VCD leaves them out: they would more
/// than double its size and add nothing a viewer cannot show from the positions.
pub fn is_derived_copy(info: &SlotInfo) -> bool {
    info.kind == Kind::Motion
        && matches!(
            info.member.name,
            "MotorRevs" | "MotorCounts" | "MasterCounts" | "FreeRunTime"
        )
}

/// A continuously moving position or velocity (the default columns of the CSV).
pub fn is_position_or_velocity(info: &SlotInfo) -> bool {
    info.member.continuous
        && SignalKind::of(info.ty) == SignalKind::Real
        && !is_derived_copy(info)
        && (info.member.name.contains("Pos") || info.member.name.contains("Vel"))
}

/// Every continuous position and velocity of the machine, in registry order.
pub fn positions_and_velocities(registry: &Registry) -> Vec<Signal> {
    registry
        .slots
        .iter()
        .enumerate()
        .filter(|(_, info)| is_position_or_velocity(info))
        .map(|(i, info)| Signal::from_slot(i as SlotId, info))
        .collect()
}

/// Resolve the names given with `--signals` (each argument a comma-separated list), in the order
/// given, without repeats. An unknown name is an error naming it and the nearest known name.
pub fn resolve_list(registry: &Registry, lists: &[String]) -> Result<Vec<Signal>, ExportError> {
    let mut out: Vec<Signal> = Vec::new();
    for name in split_names(lists) {
        let signal = resolve_one(registry, &name)?;
        if !out.iter().any(|s| s.slot == signal.slot) {
            out.push(signal);
        }
    }
    if out.is_empty() {
        return Err(ExportError::Usage(
            "--signals: no signal names given (write e.g. --signals PosnFeedback,Queue.0.QueueCount)"
                .into(),
        ));
    }
    Ok(out)
}

/// The names of comma-separated lists, trimmed, empty ones dropped. A comma inside
/// parentheses separates subscripts, not names (`G(1,2)`).
pub fn split_names(lists: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    for list in lists {
        let mut depth = 0usize;
        let mut start = 0;
        for (i, c) in list.char_indices() {
            match c {
                '(' => depth += 1,
                ')' => depth = depth.saturating_sub(1),
                ',' if depth == 0 => {
                    out.push(list[start..i].trim().to_string());
                    start = i + 1;
                }
                _ => {}
            }
        }
        out.push(list[start..].trim().to_string());
    }
    out.retain(|s| !s.is_empty());
    out
}

fn resolve_one(registry: &Registry, name: &str) -> Result<Signal, ExportError> {
    // Names resolve as programs resolve them (any case, aliases, `DriveInput.4` for its value,
    // MotionBASIC variables by their spelling), so a name copied from a program works here.
    let parsed = crate::syntax::ast::Name::from_token(name, 0);
    let resolved = match crate::check::motionbasic::resolve(registry, &parsed) {
        Ok(r) => Some(r).filter(|r| (r.slot as usize) < registry.slots.len()),
        Err(p) if p.code == SUBSCRIPT => {
            return Err(ExportError::Usage(format!("--signals: {}", p.message)))
        }
        Err(_) => None,
    };
    match resolved {
        Some(r) => Ok(Signal::from_slot(r.slot, &registry.slots[r.slot as usize])),
        None => {
            let names: Vec<_> = registry.slots.iter().map(|s| s.name.text()).collect();
            Err(ExportError::Usage(format!(
                "--signals: unknown signal `{name}`{}",
                nearest(name, names.iter().map(|n| n.as_ref()))
                    .map(|n| format!(" (did you mean `{n}`?)"))
                    .unwrap_or_default()
            )))
        }
    }
}

/// The known name closest to `name`, when one is close enough to be a likely slip.
pub fn nearest<'a>(name: &str, known: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    let lower = name.to_ascii_lowercase();
    let mut best: Option<(f64, &str)> = None;
    for k in known {
        let score = strsim::jaro_winkler(&lower, &k.to_ascii_lowercase());
        // Strictly greater: the first of equals wins, so the answer does not depend on order
        // beyond the registry's own.
        if best.is_none_or(|(s, _)| score > s) {
            best = Some((score, k));
        }
    }
    best.filter(|(s, _)| *s >= 0.8).map(|(_, k)| k)
}

/// Where a member sits in the VCD's hierarchy: scopes by object (`Queue`, `0`) and the member's
/// own name (`QueueExit`). MotionBASIC variables keep their whole spelling (dots included) in
/// a `BASIC` scope: their dots are part of the name, not a path.
pub fn vcd_path(info: &SlotInfo) -> (Vec<String>, String) {
    if info.kind == Kind::BasicVar {
        return (vec!["BASIC".to_string()], vcd_word(&info.name.text()));
    }
    let mut parts: Vec<String> = info.name.text().split('.').map(vcd_word).collect();
    let leaf = parts.pop().unwrap_or_default();
    (parts, leaf)
}

/// A name as a VCD word: VCD separates words by white space, so none may contain any.
pub fn vcd_word(s: &str) -> String {
    let w: String = s
        .chars()
        .map(|c| if c.is_whitespace() { '_' } else { c })
        .collect();
    if w.is_empty() {
        "_".to_string()
    } else {
        w
    }
}

/// The unit a member's values are in, for axis labels, when pacer knows it.
pub fn unit_of(name: &str, motor: &str, master: &str) -> Option<String> {
    let member = name.rsplit('.').next().unwrap_or(name);
    let per_s = |u: &str| format!("{u}/s");
    match member {
        "MasterPosnFeedback" => Some(master.to_string()),
        "MasterVelFeedback" => Some(per_s(master)),
        "PosnCommand" | "PosnFeedback" | "FollowingError" => Some(motor.to_string()),
        "VelCommand" => Some(per_s(motor)),
        _ if name.starts_with("Belt.") && member == "Position" => Some("mm".into()),
        _ if name.starts_with("Belt.") && member == "Velocity" => Some("mm/s".into()),
        _ if name.starts_with("PickPlace.") => pickplace_unit(member),
        _ => None,
    }
}

/// X, Y and Z of the robot are in mm, the orientation and joint angles in degrees.
fn pickplace_unit(member: &str) -> Option<String> {
    let (base, index) = crate::registry::catalog::split_index(member)?;
    let i: usize = index.parse().ok()?;
    let length = match i {
        1..=3 => true,
        4..=9 => false,
        _ => return None,
    };
    match (base, length) {
        ("alrActPos", true) => Some("mm".into()),
        ("alrActPos", false) => Some("°".into()),
        ("alrActVel", true) => Some("mm/s".into()),
        ("alrActVel", false) => Some("°/s".into()),
        _ => None,
    }
}

/// Append a real number: the shortest text that reads back as the same `f64` (so files are
/// exact and byte-identical from run to run), in exponent form when plain digits would be long.
pub fn write_real(out: &mut String, v: f64) {
    use std::fmt::Write as _;
    let a = v.abs();
    if a != 0.0 && !(1e-4..1e15).contains(&a) {
        let _ = write!(out, "{v:e}");
    } else {
        let _ = write!(out, "{v}");
    }
}

/// Append a value of a signal: bits as 0/1, whole numbers without decimals, reals exactly.
pub fn write_value(out: &mut String, kind: SignalKind, v: f64) {
    use std::fmt::Write as _;
    match kind {
        SignalKind::Bit => out.push(if v != 0.0 { '1' } else { '0' }),
        SignalKind::Integer if v.is_finite() && v.abs() < 9.0e15 => {
            let _ = write!(out, "{}", v.round() as i64);
        }
        _ => write_real(out, v),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn real(v: f64) -> String {
        let mut s = String::new();
        write_real(&mut s, v);
        s
    }

    #[test]
    fn reals_read_back_exactly() {
        for v in [
            0.0,
            1.1,
            -2.5,
            30.039862314058155,
            1e-7,
            2.2e-16,
            1e20,
            -0.001,
        ] {
            let s = real(v);
            assert_eq!(s.parse::<f64>().expect("a number"), v, "{s}");
        }
        assert_eq!(real(0.001), "0.001");
        assert_eq!(real(1e-7), "1e-7");
        assert_eq!(real(40.0), "40");
    }

    #[test]
    fn units_are_known_for_the_moving_members() {
        assert_eq!(unit_of("PosnFeedback", "mm", "m").as_deref(), Some("mm"));
        assert_eq!(
            unit_of("MasterVelFeedback", "mm", "m").as_deref(),
            Some("m/s")
        );
        assert_eq!(
            unit_of("PickPlace.alrActPos[3]", "u", "u").as_deref(),
            Some("mm")
        );
        assert_eq!(
            unit_of("PickPlace.alrActPos[7]", "u", "u").as_deref(),
            Some("°")
        );
        assert_eq!(unit_of("Queue.0.QueueCount", "u", "u"), None);
    }

    #[test]
    fn the_nearest_name_is_a_likely_slip_or_nothing() {
        let known = ["Queue.0.QueueCount", "PosnFeedback", "PosnCommand"];
        assert_eq!(
            nearest("PosnFeedbak", known.iter().copied()),
            Some("PosnFeedback")
        );
        assert_eq!(nearest("zzzz", known.iter().copied()), None);
    }
}
