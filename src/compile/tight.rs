//! Loops whose whole body is one instruction (an empty `FOR … NEXT`, a fill of elements
//! subscripted by the loop's variable), which the machine runs outside the interpreter
//! (`vm::tight`): which they are, and the `for.check` that enters one ([`Op::ForTight`]).

use super::bytecode::{Op, INT_STORE, REAL_STORE};
use super::whole::SURE;

/// Make each `for.check` of `ops` entering a loop whose body is one instruction that [`plan`]
/// finds plain when nothing is traced an [`Op::ForTight`] (`sure`: their flags).
pub fn mark(ops: &mut [Op], sure: &[u8]) {
    for i in 0..ops.len() {
        let Op::ForCheck { var, limit, exit } = ops[i] else {
            continue;
        };
        let start = i as u32 + 1;
        let short = exit > start && exit <= start + 2;
        let same = |p: Plan| p.var == var && p.limit == limit && p.after == exit;
        if short && plan(ops, sure, start, 0).is_some_and(same) {
            ops[i] = Op::ForTight {
                var,
                limit,
                exit,
                kept: false,
            };
        }
    }
}

/// The store of a loop's body: `v[src]` into element `v[var]` of the array at `base`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fill {
    /// The array's first element's register.
    pub base: usize,
    /// Its number of elements.
    pub len: u32,
    /// The register stored.
    pub src: usize,
}

/// The kinds of element a [`Fill`] stores plainly: a long or an INTEGER (a whole value, stored
/// as it is within range), a real (a finite value).
pub const LONG: u8 = 0;
/// See [`LONG`].
pub const INT: u8 = 1;
/// See [`LONG`].
pub const REAL: u8 = 2;

/// A loop `vm::tight::run` can run, found at an instruction by [`plan`]: its registers, not
/// yet its values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Plan {
    /// The variable's register.
    pub var: u32,
    /// The limit's register (the step's is the one after it).
    pub limit: u32,
    /// The variable is a MotionBASIC INTEGER.
    pub int16: bool,
    /// The store of the body, if any, and the kind of its elements ([`LONG`], [`INT`], [`REAL`]).
    pub fill: Option<(Fill, u8)>,
    /// The instruction after the loop.
    pub after: u32,
}

/// The loop at instruction `pc` of `ops` (with their flags `sure`, `Chunk::sure`) when
/// `vm::tight::run` can run it: a `for.next` whose body is itself, or a `store.idx` fused with the `for.next`
/// after it whose body is the store, subscripted by the loop's variable, into an array that
/// holds neither the variable, the limit nor the step; the variable and step whole, the stored
/// value whole unless the elements are reals, and no register written below `traced_below`
/// (the slots a write of which is traced).
pub fn plan(ops: &[Op], sure: &[u8], pc: u32, traced_below: u32) -> Option<Plan> {
    let at = pc as usize;
    let flag = |i: usize| sure.get(i).is_some_and(|f| f & SURE != 0);
    match *ops.get(at)? {
        Op::ForNext {
            var,
            limit,
            body,
            decimals,
        } if body == pc && flag(at) && var >= traced_below => Some(Plan {
            var,
            limit,
            int16: decimals == INT_STORE,
            fill: None,
            after: pc + 1,
        }),
        Op::StoreIdxNext {
            base,
            idx,
            src,
            len,
            decimals,
        } => {
            let Op::ForNext {
                var,
                limit,
                body,
                decimals: kind,
            } = *ops.get(at + 1)?
            else {
                return None;
            };
            let array = u64::from(base)..u64::from(base) + u64::from(len);
            let apart = [var, limit, limit + 1]
                .iter()
                .all(|&r| !array.contains(&u64::from(r)));
            let elements = match decimals {
                0 if flag(at) => LONG,
                INT_STORE if flag(at) => INT,
                REAL_STORE => REAL,
                _ => return None,
            };
            let plain =
                body == pc && idx == var && flag(at + 1) && apart && var.min(base) >= traced_below;
            plain.then_some(Plan {
                var,
                limit,
                int16: kind == INT_STORE,
                fill: Some((
                    Fill {
                        base: base as usize,
                        len,
                        src: src as usize,
                    },
                    elements,
                )),
                after: pc + 2,
            })
        }
        _ => None,
    }
}
