//! What a registry is built from: a machine's objects as its checked description gives them —
//! how many of each type, its user variables and bits, and the members' initial values. The
//! configuration stage fills it in.

use super::catalog::{Instances, Kind, TypeDef};
use indexmap::IndexMap;

/// The objects of a machine: how many of each, its variables and bits, and the members'
/// initial values.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ObjectsDesc {
    /// Instance counts `[io]` and `[objects]` set, by type name.
    pub counts: IndexMap<&'static str, u32>,
    /// One more than the highest program number loaded.
    pub programs: u32,
    /// The highest DSP axis number.
    pub axes: u32,
    /// The machine has the pick & place module.
    pub pickplace: bool,
    /// The number of pick & place belts (the highest belt number).
    pub belts: u32,
    /// User variables, in file order.
    pub variables: Vec<VarDesc>,
    /// User bits.
    pub bits: BitsDesc,
    /// Members that start the run at other than their default, in the order set (a later one
    /// wins).
    pub initials: Vec<Initial>,
}

/// A user variable (`[variables.NAME]`).
#[derive(Debug, Clone, PartialEq)]
pub struct VarDesc {
    /// Its name as written.
    pub name: String,
    /// Decimal places kept.
    pub decimals: u8,
    /// Its value at the start, rounded to its places.
    pub initial: f64,
}

/// The user bits (`[bits]`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BitsDesc {
    /// How many: `Bit.0` … `Bit.(count-1)`.
    pub count: u32,
    /// Names given to bits, in file order.
    pub names: Vec<(String, u32)>,
    /// Bits that start ON.
    pub on: Vec<u32>,
}

/// A member's initial value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Initial {
    /// Its object type.
    pub kind: Kind,
    /// The instance (0-based).
    pub instance: u32,
    /// The member's index in its type.
    pub member: usize,
    /// The value.
    pub value: f64,
}

impl ObjectsDesc {
    /// The number of instances of `ty` the machine has.
    pub fn count_of(&self, ty: &TypeDef) -> u32 {
        let set = match ty.instances {
            Instances::Global => 1,
            Instances::Numbered { default_count, .. } => {
                self.counts.get(ty.name).copied().unwrap_or(default_count)
            }
            Instances::Named => 0,
        };
        match ty.kind {
            Kind::Program => set.max(self.programs),
            Kind::Axis => self.axes,
            // A machine without [pickplace] has no slots for the module at all: every slot
            // is scanned every update.
            Kind::PickPlace => u32::from(self.pickplace),
            Kind::Belt => self.belts,
            Kind::Var => self.variables.len() as u32,
            Kind::Bit => self.bits.count,
            _ => set,
        }
    }

    /// Member `member` of instance `instance` of `ty` starts the run at `value`.
    pub fn initial(&mut self, ty: &TypeDef, instance: u32, member: usize, value: f64) {
        self.initials.push(Initial {
            kind: ty.kind,
            instance,
            member,
            value,
        });
    }
}
