//! Resolving written names (`Queue.0.QueueOffset`, `Var.Count`, `DriveInput.4`, `FeedRateOverride`)
//! to slots, with the nearest valid name on a miss.

use super::catalog::{self, Access, Hook, Instances, Kind, MemberDef, ValueType};
use super::name::{Name, Segment};
use super::{Registry, SlotId, SlotName, TypeInstances, GLOBAL_INSTANCE};
use crate::diag::{nearest, Problem};

/// A name resolved against the registry.
#[derive(Debug, Clone, PartialEq)]
pub struct Resolved {
    /// Its storage.
    pub slot: SlotId,
    /// Value type.
    pub ty: ValueType,
    /// How programs may use it.
    pub access: Access,
    /// What a write does.
    pub hook: Hook,
    /// The object's behaviour.
    pub kind: Kind,
    /// Instance index (0-based) or [`GLOBAL_INSTANCE`].
    pub instance: u32,
    /// Canonical name.
    pub name: String,
}

const CODE_OBJECT: &str = "pacer::check::unknown_object";
const CODE_INSTANCE: &str = "pacer::check::unknown_instance";
const CODE_MEMBER: &str = "pacer::check::unknown_member";

impl Registry {
    /// Resolve a name that refers to a member.
    pub fn resolve(&self, name: &Name) -> Result<Resolved, Problem> {
        let segs = &name.segments;
        let first = &segs[0];
        let Some(def) = catalog::find_type(&first.text) else {
            // Members of the drive-wide Motion object are written bare: `FeedRateOverride`.
            let motion = self.of(Kind::Motion);
            if segs.len() == 1 {
                if let Some(idx) = member_index(motion.def.members, &first.text) {
                    return Ok(self.resolved(motion, 0, idx, false));
                }
            }
            if let Some(message) = crate::registry::not_yet::powertools(&first.text) {
                return Err(
                    Problem::error(CODE_OBJECT, first.span, message, "not run yet")
                        .with_help(crate::registry::not_yet::HELP),
                );
            }
            let candidates = catalog::TYPES
                .iter()
                .filter(|t| t.name != catalog::BARE_GLOBAL_TYPE)
                .map(|t| t.name)
                .chain(motion.def.members.iter().map(|m| m.name));
            return Err(Problem::error(
                CODE_OBJECT,
                first.span,
                format!("unknown object `{}`", first.text),
                "no such object",
            )
            .with_help_opt(
                nearest(&first.text, candidates).map(|n| format!("did you mean `{n}`?")),
            ));
        };
        let t = self.of(def.kind);
        if matches!(def.kind, Kind::PickPlace | Kind::Belt) && self.of(Kind::PickPlace).count == 0 {
            return Err(no_pickplace(first));
        }
        if def.instances == Instances::Global {
            let Some(seg) = segs.get(1) else {
                return Err(needs_member(name, t));
            };
            let idx = self.member(t.def.members, seg, t.def.name)?;
            self.no_extra(segs, 2)?;
            return Ok(self.resolved(t, 0, idx, false));
        }
        let Some(inst_seg) = segs.get(1) else {
            return Err(Problem::error(
                CODE_INSTANCE,
                name.span,
                format!("`{}` needs an instance", def.name),
                "which one?",
            )
            .with_help(instance_help(t)));
        };
        if segs.len() == 2 {
            if let Some(idx) = member_index(def.global_members, &inst_seg.text) {
                return Ok(self.resolved(t, GLOBAL_INSTANCE, idx, true));
            }
        }
        let instance = self.instance(t, inst_seg)?;
        match segs.get(2) {
            None => match def.default_member {
                Some(dm) => {
                    let idx = member_index(def.members, dm).unwrap_or(0);
                    Ok(self.resolved(t, instance, idx, false))
                }
                None => Err(needs_member(name, t)),
            },
            Some(seg) => {
                let idx = self.member(def.members, seg, def.name)?;
                self.no_extra(segs, 3)?;
                Ok(self.resolved(t, instance, idx, false))
            }
        }
    }

    /// Resolve a member name written as a TOML string (in `machine.toml` or `scenario.toml`);
    /// spans point inside the string.
    pub fn resolve_text(&self, text: &toml::Spanned<String>) -> Result<Resolved, Problem> {
        let range = text.span();
        let span = crate::span::Span::new(range.start, range.end);
        let s = text.get_ref();
        let plain = |seg: &str| {
            !seg.is_empty() && seg.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        };
        // A segment may end with an index: `PickPlace.alrStopDec[2]`.
        let valid = !s.is_empty()
            && s.split('.').all(|seg| match catalog::split_index(seg) {
                Some((base, index)) => {
                    plain(base) && !index.is_empty() && index.chars().all(|c| c.is_ascii_digit())
                }
                None => plain(seg),
            });
        if !valid {
            return Err(Problem::error(
                "pacer::machine::name",
                span,
                format!("`{s}` is not a member name"),
                "expected e.g. ModuleInput.2 or Capture.0.CaptureActivate",
            ));
        }
        // The span starts at the opening quote.
        self.resolve(&Name::from_token(s, span.start + 1))
    }

    /// Resolve a reference to an instance, as in `Using Capture.1` or `On Profile.1`.
    pub fn resolve_instance(&self, name: &Name, kind: Kind) -> Result<u32, Problem> {
        let t = self.of(kind);
        let segs = &name.segments;
        if !segs[0].text.eq_ignore_ascii_case(t.def.name) {
            return Err(Problem::error(
                CODE_OBJECT,
                segs[0].span,
                format!("expected `{}.N` here", t.def.name),
                format!("not a {}", t.def.name),
            )
            .with_help(instance_help(t)));
        }
        let Some(seg) = segs.get(1) else {
            return Err(Problem::error(
                CODE_INSTANCE,
                name.span,
                format!("`{}` needs an instance number", t.def.name),
                "which one?",
            )
            .with_help(instance_help(t)));
        };
        let i = self.instance(t, seg)?;
        self.no_extra(segs, 2)?;
        Ok(i)
    }

    fn resolved(&self, t: &TypeInstances, instance: u32, idx: usize, global: bool) -> Resolved {
        let member: &MemberDef = if global {
            &t.def.global_members[idx]
        } else {
            &t.def.members[idx]
        };
        let slot = t.slot(if global { 0 } else { instance }, idx, global);
        let info = &self.slots[slot as usize];
        Resolved {
            slot,
            ty: info.ty,
            access: member.access,
            hook: member.hook,
            kind: t.def.kind,
            instance,
            name: info.name.text().into_owned(),
        }
    }

    fn instance(&self, t: &TypeInstances, seg: &Segment) -> Result<u32, Problem> {
        if let Ok(n) = seg.text.parse::<u32>() {
            if t.def.instances != Instances::Named || t.def.kind == Kind::Bit {
                if n >= t.first && n - t.first < t.count {
                    return Ok(n - t.first);
                }
                if t.def.kind == Kind::Belt {
                    return Err(Problem::error(
                        CODE_INSTANCE,
                        seg.span,
                        format!("the machine has no belt {}", seg.text),
                        "no such belt",
                    )
                    .with_help(belt_help(t, &seg.text)));
                }
                return Err(Problem::error(
                    CODE_INSTANCE,
                    seg.span,
                    format!("{}.{} does not exist", t.def.name, seg.text),
                    "no such instance",
                )
                .with_help(instance_help(t)));
            }
        }
        if let Some(&i) = t.names.get(&seg.text.to_ascii_lowercase()) {
            return Ok(i);
        }
        let candidates: Vec<std::borrow::Cow<'_, str>> = t
            .display
            .iter()
            .map(SlotName::text)
            .chain(t.def.global_members.iter().map(|m| m.name.into()))
            .collect();
        let near = nearest(&seg.text, candidates.iter().map(|c| c.as_ref()));
        let help = match (near, t.def.kind) {
            (Some(n), _) => format!("did you mean `{}.{n}`?", t.def.name),
            (None, Kind::Var) => "declare it in machine.toml under [variables]".to_string(),
            (None, Kind::Bit) => "name it in machine.toml under [bits.names]".to_string(),
            _ => instance_help(t),
        };
        Err(Problem::error(
            CODE_INSTANCE,
            seg.span,
            format!("unknown {} `{}`", instance_word(t), seg.text),
            "not declared",
        )
        .with_help(help))
    }

    fn member(
        &self,
        members: &'static [MemberDef],
        seg: &Segment,
        type_name: &str,
    ) -> Result<usize, Problem> {
        member_index(members, &seg.text).ok_or_else(|| {
            if let Some(p) = array_problem(members, seg, type_name) {
                return p;
            }
            Problem::error(
                CODE_MEMBER,
                seg.span,
                format!("{type_name} has no member `{}`", seg.text),
                "unknown member",
            )
            .with_help(match nearest(&seg.text, members.iter().map(|m| m.name)) {
                Some(n) => format!("did you mean `{n}`?"),
                None => member_list(members),
            })
        })
    }

    fn no_extra(&self, segs: &[Segment], allowed: usize) -> Result<(), Problem> {
        match segs.get(allowed) {
            Some(extra) => {
                let last = segs.last().map_or(extra.span, |s| s.span);
                Err(Problem::error(
                    CODE_MEMBER,
                    extra.span.to(last),
                    "too many parts in this name",
                    "unexpected",
                ))
            }
            None => Ok(()),
        }
    }
}

fn member_index(members: &[MemberDef], name: &str) -> Option<usize> {
    catalog::member_position(members, name)
}

/// The problem for an array member written without its index, or with one out of range.
fn array_problem(members: &[MemberDef], seg: &Segment, type_name: &str) -> Option<Problem> {
    let text = seg.text.as_str();
    if let Some((first, len)) = catalog::find_array(members, text) {
        let base = catalog::split_index(members[first].name)?.0;
        return Some(
            Problem::error(
                CODE_MEMBER,
                seg.span,
                format!("{type_name}.{base} is an array of {len}: name one element"),
                "which element?",
            )
            .with_help(format!("write {base}[1] to {base}[{len}]")),
        );
    }
    let (base, index) = catalog::split_index(text)?;
    let (first, len) = catalog::find_array(members, base)?;
    let base = catalog::split_index(members[first].name)?.0;
    Some(
        Problem::error(
            CODE_MEMBER,
            seg.span,
            format!("{type_name}.{base} has no element {index}"),
            "index out of range",
        )
        .with_help(format!("its elements are {base}[1] to {base}[{len}]")),
    )
}

/// The members of a type for a help line; a long list (the pick & place module's) is cut short.
fn member_list(members: &[MemberDef]) -> String {
    const SHOWN: usize = 24;
    let mut names: Vec<&str> = Vec::new();
    for m in members {
        let name = match catalog::split_index(m.name) {
            Some((base, _)) => base,
            None => m.name,
        };
        if !names.contains(&name) {
            names.push(name);
        }
    }
    if names.len() > SHOWN {
        format!(
            "members include {}, … ({} in all; arrays are written name[k])",
            names[..SHOWN].join(", "),
            names.len()
        )
    } else {
        format!("members: {}", names.join(", "))
    }
}

/// A machine without `[pickplace]` named the module or a belt.
fn no_pickplace(seg: &Segment) -> Problem {
    Problem::error(
        "pacer::check::no_pickplace",
        seg.span,
        format!(
            "this machine has no pick & place module, so `{}` does not exist",
            seg.text
        ),
        "no [pickplace] in machine.toml",
    )
    .with_help(
        "add a [pickplace] table to machine.toml (and [pickplace.belt.N] for each belt) to give \
         the machine the Track Pick & Place module",
    )
}

/// Help for a belt the machine does not have.
fn belt_help(t: &TypeInstances, written: &str) -> String {
    let add = format!("add [pickplace.belt.{written}] to machine.toml");
    match t.count {
        0 => format!("the machine has no belts: {add}"),
        1 => format!("the machine has Belt.1; {add}"),
        n => format!("the machine has Belt.1 to Belt.{n}; {add}"),
    }
}

fn instance_word(t: &TypeInstances) -> &'static str {
    match t.def.kind {
        Kind::Var => "variable",
        Kind::Bit => "bit",
        _ => "instance",
    }
}

fn instance_help(t: &TypeInstances) -> String {
    match t.def.kind {
        Kind::Var => {
            "user variables are written Var.Name and declared in machine.toml [variables]".into()
        }
        Kind::Bit => format!("user bits are Bit.0 to Bit.{}", t.count.saturating_sub(1)),
        _ if t.count == 0 => format!("this machine has no {} instances", t.def.name),
        _ => format!(
            "this machine has {}.{} to {}.{}",
            t.def.name,
            t.first,
            t.def.name,
            t.first + t.count - 1
        ),
    }
}

fn needs_member(name: &Name, t: &TypeInstances) -> Problem {
    Problem::error(
        CODE_MEMBER,
        name.span,
        format!("`{}` needs a member", name.text()),
        "which member?",
    )
    .with_help(member_list(t.def.members))
}
