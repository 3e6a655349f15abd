//! Members bound to storage by typed slots, checked against the catalog when pacer is
//! compiled: a device names the members it uses once, and a name the catalog does not have
//! fails to compile instead of failing at start-up.
//!
//! ```compile_fail
//! // A misspelt member is a compile error ("evaluation panicked: Distanse").
//! let _ = pacer::member_index!(pacer::registry::catalog::INDEX_TYPE, "Distanse");
//! ```

use crate::registry::{MemberDef, Registry, SlotId, TypeDef};

/// True when `a` and `b` are the same text (usable at compile time).
pub const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The index of member `name` in `members`. Evaluated at compile time by [`member_index!`], where
/// a miss stops the build.
pub const fn member(members: &[MemberDef], name: &str) -> usize {
    let mut i = 0;
    while i < members.len() {
        if same(members[i].name, name) {
            return i;
        }
        i += 1;
    }
    no_such_member_in_the_catalog(name)
}

/// The index of `name[1]` in `members`, checking that `name[1]` … `name[len]` follow each
/// other (an array member of the pick & place module).
pub const fn array(members: &[MemberDef], name: &str, len: usize) -> usize {
    let mut i = 0;
    while i < members.len() {
        if is_element(members[i].name, name, 1) {
            let mut k = 1;
            while k < len {
                if i + k >= members.len() || !is_element(members[i + k].name, name, k + 1) {
                    no_such_member_in_the_catalog(name)
                }
                k += 1;
            }
            return i;
        }
        i += 1;
    }
    no_such_member_in_the_catalog(name)
}

/// `text` is `base[k]`.
const fn is_element(text: &str, base: &str, k: usize) -> bool {
    let (t, b) = (text.as_bytes(), base.as_bytes());
    if t.len() < b.len() + 3 || t[b.len()] != b'[' || t[t.len() - 1] != b']' {
        return false;
    }
    let mut i = 0;
    while i < b.len() {
        if t[i] != b[i] {
            return false;
        }
        i += 1;
    }
    let mut n = 0usize;
    let mut j = b.len() + 1;
    while j < t.len() - 1 {
        let d = t[j];
        if !d.is_ascii_digit() {
            return false;
        }
        n = n * 10 + (d - b'0') as usize;
        j += 1;
    }
    n == k
}

/// Stops a compile-time evaluation: the name given is not a member of the type.
const fn no_such_member_in_the_catalog(name: &str) -> ! {
    panic!("{}", name)
}

/// The index of member `$name` of the catalog type `$ty` (a [`TypeDef`] constant), found when
/// pacer is compiled.
#[macro_export]
macro_rules! member_index {
    ($ty:expr, $name:literal) => {
        const { $crate::devices::bind::member($ty.members, $name) }
    };
}

/// The slot of member `$name` of instance `$instance` of the catalog type `$ty`; the name is
/// checked when pacer is compiled.
#[macro_export]
macro_rules! slot {
    ($registry:expr, $ty:expr, $instance:expr, $name:literal) => {
        $crate::devices::bind::slot_at(
            $registry,
            &$ty,
            $instance,
            $crate::member_index!($ty, $name),
        )
    };
}

/// The slots of `$name[1]` … `$name[$len]` of instance `$instance` of `$ty`, checked when pacer
/// is compiled.
#[macro_export]
macro_rules! slots {
    ($registry:expr, $ty:expr, $instance:expr, $name:literal, $len:expr) => {
        $crate::devices::bind::slots_at::<{ $len }>(
            $registry,
            &$ty,
            $instance,
            const { $crate::devices::bind::array($ty.members, $name, $len) },
        )
    };
}

/// The slot of member `$name` of the type itself (`Jog.Select`), checked when pacer is
/// compiled.
#[macro_export]
macro_rules! global_slot {
    ($registry:expr, $ty:expr, $name:literal) => {
        $crate::devices::bind::global_slot_at(
            $registry,
            &$ty,
            const { $crate::devices::bind::member($ty.global_members, $name) },
        )
    };
}

/// A struct of the slots a device uses on one instance of a catalog type, each field bound to
/// a member by name and checked when pacer is compiled.
///
/// ```
/// use pacer::registry::catalog::INDEX_TYPE;
/// pacer::bind_slots! {
///     /// The slots of one index.
///     pub struct IndexSlots for INDEX_TYPE {
///         distance: "Distance",
///         velocity: "Velocity",
///     }
/// }
/// let machine = pacer::config::machine::MachineFile::default();
/// let (registry, _) = pacer::config::registry(&machine, &[0], &[]);
/// let ix = IndexSlots::of(&registry, 0);
/// assert_ne!(ix.distance, ix.velocity);
/// ```
#[macro_export]
macro_rules! bind_slots {
    (
        $(#[$doc:meta])*
        $vis:vis struct $name:ident for $ty:path {
            $($(#[$fdoc:meta])* $field:ident: $member:literal),* $(,)?
        }
    ) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        $vis struct $name {
            $($(#[$fdoc])* #[doc = concat!("`", $member, "`")] pub $field: $crate::registry::SlotId,)*
        }

        impl $name {
            /// The slots of `instance` (0-based; global types have the one instance 0).
            pub fn of(registry: &$crate::registry::Registry, instance: u32) -> $name {
                $name {
                    $($field: $crate::slot!(registry, $ty, instance, $member),)*
                }
            }
        }
    };
}

/// The slot of member index `member` of `instance` of `ty`. The instance must exist (devices
/// bind the instances the registry was built with).
pub fn slot_at(registry: &Registry, ty: &TypeDef, instance: u32, member: usize) -> SlotId {
    registry.of(ty.kind).slot(instance, member, false)
}

/// The slots of `N` consecutive members from index `first`.
pub fn slots_at<const N: usize>(
    registry: &Registry,
    ty: &TypeDef,
    instance: u32,
    first: usize,
) -> [SlotId; N] {
    let t = registry.of(ty.kind);
    std::array::from_fn(|k| t.slot(instance, first + k, false))
}

/// The slot of global member index `member` of `ty`.
pub fn global_slot_at(registry: &Registry, ty: &TypeDef, member: usize) -> SlotId {
    registry.of(ty.kind).slot(0, member, true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::registry::catalog::{INDEX_TYPE, PICK_PLACE_TYPE};

    #[test]
    fn members_and_arrays_are_found_where_the_catalog_has_them() {
        let i = member(INDEX_TYPE.members, "Velocity");
        assert_eq!(INDEX_TYPE.members[i].name, "Velocity");
        let a = array(PICK_PLACE_TYPE.members, "alrActPos", 7);
        assert_eq!(PICK_PLACE_TYPE.members[a].name, "alrActPos[1]");
        assert_eq!(PICK_PLACE_TYPE.members[a + 6].name, "alrActPos[7]");
        assert!(!is_element("alrActPos[10]", "alrActPos", 1));
        assert!(is_element("alrActPos[10]", "alrActPos", 10));
    }
}
