//! The object registry: every object instance of a machine and every member's storage slot,
//! built from the catalog and the machine's checked description (it cannot fail). Names resolve
//! to slots here, once, at compile time.

pub mod catalog;
pub mod name;
pub mod not_yet;
pub mod objects;
mod resolve;
pub mod slot_name;

pub use catalog::{Access, Hook, Instances, Kind, MemberDef, TypeDef, ValueType};
pub use resolve::Resolved;
pub use slot_name::{ArrayShape, BasicVar, SlotName};

use indexmap::IndexMap;
use objects::ObjectsDesc;

/// Default update period: 1 ms.
pub const DEFAULT_UPDATE_NS: u64 = 1_000_000;

/// Index of a member's storage in the signal table.
pub type SlotId = u32;

/// Instance index used for a type's own members (`Jog.Select`).
pub const GLOBAL_INSTANCE: u32 = u32::MAX;

/// What one storage slot holds.
#[derive(Debug, Clone)]
pub struct SlotInfo {
    /// Canonical full name, e.g. `Queue.0.QueueOffset`.
    pub name: SlotName,
    /// Its value type (user variables carry their own decimal places).
    pub ty: ValueType,
    /// The member definition.
    pub member: &'static MemberDef,
    /// The object's behaviour.
    pub kind: Kind,
    /// Instance index within its type (0-based), or [`GLOBAL_INSTANCE`].
    pub instance: u32,
    /// Value at the start of a run.
    pub initial: f64,
}

/// The instances of one type in this machine.
#[derive(Debug, Clone)]
pub struct TypeInstances {
    /// The catalog entry.
    pub def: &'static TypeDef,
    /// Number of instances.
    pub count: u32,
    /// First instance number as written (1 for I/O points, 0 for objects).
    pub first: u32,
    /// Instance names (lower-case) → index, for named instances (`Var.Count`, `Bit.Ready`).
    pub names: IndexMap<String, u32>,
    /// Display name of each instance (`0`, `Count`, `FLAG&(3)`).
    pub display: Vec<SlotName>,
    /// First slot of this type's storage.
    pub base: SlotId,
}

impl TypeInstances {
    /// The slot of `member_index` of `instance`.
    pub fn slot(&self, instance: u32, member_index: usize, global: bool) -> SlotId {
        let per = self.def.members.len() as u32;
        if global {
            self.base + self.count * per + member_index as u32
        } else {
            self.base + instance * per + member_index as u32
        }
    }
}

/// Every object of one machine.
#[derive(Debug, Clone)]
pub struct Registry {
    /// Per type, in catalog order.
    pub types: Vec<TypeInstances>,
    /// Every slot, in layout order.
    pub slots: Vec<SlotInfo>,
}

impl Registry {
    /// The registry of a machine: its objects, and the MotionBASIC variables its programs use
    /// (name as first written, and type).
    pub fn new(objects: &ObjectsDesc, basic_vars: &[BasicVar]) -> Registry {
        let mut types = Vec::new();
        // Reserved whole: a large DIM would otherwise be copied as the vector grows.
        let elements: usize = basic_vars.iter().map(BasicVar::len).sum();
        let objects_slots: usize = catalog::TYPES
            .iter()
            .map(|def| {
                let count = match def.kind {
                    Kind::Var => objects.variables.len(),
                    Kind::BasicVar => 0,
                    _ => objects.count_of(def) as usize,
                };
                count * def.members.len() + def.global_members.len()
            })
            .sum();
        let mut slots: Vec<SlotInfo> = Vec::with_capacity(elements + objects_slots);
        for def in catalog::TYPES {
            let first = match def.instances {
                Instances::Numbered { first, .. } => first,
                _ => 0,
            };
            let mut count = objects.count_of(def);
            let mut names = IndexMap::new();
            let mut display: Vec<SlotName> = (0..count)
                .map(|i| SlotName::Text((first + i).to_string()))
                .collect();
            let mut decimals: Vec<u8> = Vec::new();
            let mut basic_types: Vec<ValueType> = Vec::new();
            let mut initial: Vec<f64> = Vec::new();
            match def.kind {
                Kind::Var => {
                    display.clear();
                    for (i, v) in objects.variables.iter().enumerate() {
                        names.insert(v.name.to_ascii_lowercase(), i as u32);
                        display.push(SlotName::Text(v.name.clone()));
                        decimals.push(v.decimals);
                        initial.push(v.initial);
                    }
                }
                Kind::BasicVar => {
                    count = 0;
                    for var in basic_vars {
                        match var {
                            BasicVar::Scalar(name, ty) => {
                                names.insert(name.to_ascii_lowercase(), count);
                                display.push(SlotName::Text(name.clone()));
                                basic_types.push(*ty);
                            }
                            BasicVar::Array(shape, ty) => {
                                // An array is found by its first element (`A(0)`, `G(0,0)`):
                                // the others need no entry, nor a name until one is asked for.
                                names.insert(
                                    slot_name::array_key(&shape.written, shape.bounds.len()),
                                    count,
                                );
                                display.extend((0..shape.len() as u32).map(|index| {
                                    SlotName::Element {
                                        array: shape.clone(),
                                        index,
                                    }
                                }));
                                basic_types.resize(basic_types.len() + shape.len(), *ty);
                            }
                        }
                        count += var.len() as u32;
                    }
                }
                Kind::Bit => {
                    for (name, n) in &objects.bits.names {
                        names.insert(name.to_ascii_lowercase(), *n);
                        display[*n as usize] = SlotName::Text(name.clone());
                    }
                    initial = vec![0.0; count as usize];
                    for &on in &objects.bits.on {
                        initial[on as usize] = 1.0;
                    }
                }
                _ => {}
            }
            let base = slots.len() as SlotId;
            for i in 0..count {
                for member in def.members {
                    let ty = match def.kind {
                        Kind::Var => ValueType::Fixed(decimals[i as usize]),
                        Kind::BasicVar => basic_types[i as usize],
                        _ => member.ty,
                    };
                    let init = match def.kind {
                        Kind::Var | Kind::Bit => initial[i as usize],
                        _ => default_value(def.kind, member),
                    };
                    slots.push(SlotInfo {
                        name: slot_name(def, &display[i as usize], member),
                        ty,
                        member,
                        kind: def.kind,
                        instance: i,
                        initial: init,
                    });
                }
            }
            for member in def.global_members {
                slots.push(SlotInfo {
                    name: SlotName::Text(format!("{}.{}", def.name, member.name)),
                    ty: member.ty,
                    member,
                    kind: def.kind,
                    instance: GLOBAL_INSTANCE,
                    initial: default_value(def.kind, member),
                });
            }
            types.push(TypeInstances {
                def,
                count,
                first,
                names,
                display,
                base,
            });
        }
        debug_assert_eq!(slots.len(), elements + objects_slots);
        let mut registry = Registry { types, slots };
        for i in &objects.initials {
            let t = registry.of(i.kind);
            if i.instance < t.count && i.member < t.def.members.len() {
                let slot = t.slot(i.instance, i.member, false);
                registry.slots[slot as usize].initial = i.value;
            }
        }
        registry
    }

    /// The instances of a type.
    pub fn of(&self, kind: Kind) -> &TypeInstances {
        // The registry holds every catalog type, so the lookup cannot fail.
        self.types
            .iter()
            .find(|t| t.def.kind == kind)
            .unwrap_or(&self.types[0])
    }

    /// The slot of a member by name (for kernel code that knows its members). The one
    /// instance of a global type (`Gear`, `PickPlace`) is 0, or [`GLOBAL_INSTANCE`]. None when
    /// the machine has no such instance (no `[pickplace]`: no `PickPlace` slots).
    pub fn slot_of(&self, kind: Kind, instance: u32, member: &str) -> Option<SlotId> {
        let t = self.of(kind);
        let instance = if instance == GLOBAL_INSTANCE && t.def.instances == Instances::Global {
            0
        } else {
            instance
        };
        if instance == GLOBAL_INSTANCE {
            let idx = t.def.global_members.iter().position(|m| m.name == member)?;
            return Some(t.slot(0, idx, true));
        }
        let idx = t.def.members.iter().position(|m| m.name == member)?;
        (instance < t.count).then(|| t.slot(instance, idx, false))
    }

    /// The instance of the MotionBASIC array element named `text` as the registry names it
    /// (`F&(3)`, `g(1, 2)`: any case, spaces around subscripts), when its array exists: `Err`
    /// says why the subscripts are not an element of it (every array's elements are held
    /// from 0). None when `text` is not an element of an array of this machine.
    pub fn basic_element(&self, text: &str) -> Option<Result<u32, String>> {
        let (base, rest) = text.split_once('(')?;
        let subs = rest.trim_end().strip_suffix(')')?;
        let subs: Vec<u32> = subs
            .split(',')
            .map(|s| s.trim().parse().ok())
            .collect::<Option<_>>()?;
        let vars = self.of(Kind::BasicVar);
        let &i = vars
            .names
            .get(&slot_name::array_key(base.trim(), subs.len()))?;
        let SlotName::Element { array, .. } = vars.display.get(i as usize)? else {
            return None;
        };
        let shape = || {
            let bounds: Vec<String> = array.bounds.iter().map(|b| format!("0 to {b}")).collect();
            format!("{}({})", array.written, bounds.join(", "))
        };
        let mut offset: u64 = 0;
        for (&s, &b) in subs.iter().zip(&array.bounds) {
            if s > b {
                return Some(Err(format!("{text} is outside {}", shape())));
            }
            offset = offset * (u64::from(b) + 1) + u64::from(s);
        }
        // An array of another number of subscripts would have another first element.
        debug_assert_eq!(array.bounds.len(), subs.len());
        Some(
            u32::try_from(offset)
                .ok()
                .and_then(|o| i.checked_add(o))
                .ok_or_else(|| format!("{text} is outside {}", shape())),
        )
    }

    /// Number of slots.
    pub fn slot_count(&self) -> usize {
        self.slots.len()
    }
}

fn default_value(kind: Kind, member: &MemberDef) -> f64 {
    match (kind, member.name) {
        (Kind::Queue, "QueueEmpty") => 1.0,
        (Kind::Queue, "QueueSize" | "FullLevel") => 8.0,
        (Kind::Program, "Task") => -1.0,
        (Kind::Motion, "FeedRateOverride") => 100.0,
        (Kind::Pls, "Enable") => 1.0,
        _ => member.initial,
    }
}

/// The canonical name of `member` of the instance displayed as `display` of `def`.
fn slot_name(def: &TypeDef, display: &SlotName, member: &MemberDef) -> SlotName {
    if def.name == catalog::BARE_GLOBAL_TYPE {
        return SlotName::Text(member.name.to_string());
    }
    if def.kind == Kind::BasicVar {
        return display.clone();
    }
    SlotName::Text(if def.instances == Instances::Global {
        format!("{}.{}", def.name, member.name)
    } else {
        match (def.default_member, def.kind) {
            (
                Some(_),
                Kind::Var
                | Kind::Bit
                | Kind::DriveInput
                | Kind::ModuleInput
                | Kind::DriveOutput
                | Kind::ModuleOutput,
            ) => format!("{}.{}", def.name, display),
            _ => format!("{}.{}.{}", def.name, display, member.name),
        }
    })
}

pub use crate::fixed::{round_to, POW10};
