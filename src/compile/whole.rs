//! Which integer operators are sure to get whole operands within 32 bits, and which stores
//! into integer variables whole values.
//!
//! Every value is an `f64`, so an integer operator (`MOD`, `\`, `AND`, `OR`, `XOR`, `NOT`)
//! first tests each operand: a whole number within 32 bits takes the integer instruction, any
//! other is rounded first. The test costs two conversions and a comparison per operand, more
//! than the operation. It always passes for a long, an INTEGER or a PowerTools variable without
//! decimals (every store rounds into them), for a whole constant, and for a temporary an
//! integer operator or a long's overflow check has just written. A store into such a variable
//! tests its value the same way, then rounds it; a value known whole (a sum, difference or
//! product of those) needs only its range checked, and a `FOR` counting a long by a whole step
//! neither. This finds the instructions whose operands are all of those, before fusion;
//! [`per_instruction`] then gives each instruction of the fused chunk a flag the interpreter
//! reads to skip the tests. The result is the same either way: the test only chooses between
//! two ways to the same value.

use super::bytecode::{BinaryOp, Op, Reg, INT_STORE};
use std::collections::BTreeMap;
use std::ops::Range;

/// Flag of [`per_instruction`]: the instruction's integer operands are whole numbers within 32
/// bits; the value a store stores is whole; a `for.next` adds a whole step to a whole variable.
pub const SURE: u8 = 1;

/// Flag of [`per_instruction`]: a `MOD`'s first operand is whole (within 32 bits or not) and
/// its second within 32 bits, so only the first's range is tested. Set with [`SURE`] on every
/// instruction that is not a `MOD`.
pub const WIDE: u8 = 2;

/// Flag of [`per_instruction`]: a long or whole fixed-point store copies a variable that is
/// sure (or a sure constant), never -0: it stores the value as it is, untested. Set with
/// [`SURE`] on every instruction that is not such a store.
pub const PLAIN: u8 = 4;

/// What is known of a temporary's value at a point of the program.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Known {
    /// A whole number, perhaps outside 32 bits (a sum or product of wholes), or one past
    /// `f64`'s range (infinite, or not a number): what only range tests take.
    Whole,
    /// A whole number within 32 bits.
    Sure,
}

/// For each instruction of the unfused `ops`, its flags: [`SURE`] when every integer operand
/// it reads is sure to be a whole number within 32 bits, when the value a store into a long,
/// an INTEGER or a whole fixed-point slot stores is whole (within 32 bits or not: it is
/// checked), and when a `for.next` adds a whole step to a sure variable; [`WIDE`] and
/// [`PLAIN`] as they say; all of them for any other instruction. `sure_reg` says which
/// registers always hold a whole number within 32 bits, never -0 (variables, constants);
/// temporaries (`temps`) are followed through straight-line code, and forgotten where control
/// may arrive from elsewhere and after any instruction this does not follow; the registers of
/// a `FOR`'s limit and step (neither temporaries nor `sure_reg`'s) are written only by the
/// `move` before the loop, and are whole when each such `move` copies a whole value.
pub fn operands(ops: &[Op], temps: &Range<Reg>, sure_reg: &dyn Fn(Reg) -> bool) -> Vec<u8> {
    let mut entered = vec![false; ops.len() + 1];
    for (i, op) in ops.iter().enumerate() {
        if let Some(t) = op.target() {
            if let Some(e) = entered.get_mut(t as usize) {
                *e = true;
            }
        }
        // A subroutine comes back to the instruction after its `GOSUB`.
        if matches!(op, Op::Gosub { .. }) {
            entered[i + 1] = true;
        }
    }
    let mut known: BTreeMap<Reg, Known> = BTreeMap::new();
    // Per register outside the temporaries and `sure_reg`'s that a `move` writes: whether
    // every such `move` copies a whole value.
    let mut moved: BTreeMap<Reg, bool> = BTreeMap::new();
    let mut out = Vec::with_capacity(ops.len());
    for (i, &op) in ops.iter().enumerate() {
        if entered[i] {
            known.clear();
        }
        let level = |r: Reg| -> Option<Known> {
            if temps.contains(&r) {
                known.get(&r).copied()
            } else if sure_reg(r) {
                Some(Known::Sure)
            } else {
                None
            }
        };
        let sure = |r: Reg| level(r) == Some(Known::Sure);
        let whole = |r: Reg| level(r).is_some();
        let wide = match op {
            Op::IMod { a, b, .. }
            | Op::Mod { a, b, .. }
            | Op::ArithFixed {
                op: BinaryOp::Mod,
                a,
                b,
                decimals: 0,
                ..
            } => Some(whole(a) && sure(b)),
            _ => None,
        };
        let flag = match op {
            Op::IMod { a, b, .. }
            | Op::IDiv { a, b, .. }
            | Op::Mod { a, b, .. }
            | Op::BitAnd { a, b, .. }
            | Op::BitOr { a, b, .. }
            | Op::BitXor { a, b, .. } => sure(a) && sure(b),
            Op::ArithFixed {
                op: BinaryOp::Mod | BinaryOp::BitAnd | BinaryOp::BitOr | BinaryOp::BitXor,
                a,
                b,
                decimals: 0,
                ..
            } => sure(a) && sure(b),
            Op::BitNot { a, .. } => sure(a),
            Op::StoreLong { src, .. }
            | Op::StoreInt { src, .. }
            | Op::StoreFixed {
                src, decimals: 0, ..
            }
            | Op::StoreIdx { src, .. }
            | Op::StoreAt { src, .. } => whole(src),
            Op::AddFixed {
                a, b, decimals: 0, ..
            }
            | Op::SubFixed {
                a, b, decimals: 0, ..
            }
            | Op::MulFixed {
                a, b, decimals: 0, ..
            } => whole(a) && whole(b),
            // With decimals, a store rounds.
            Op::StoreFixed { .. }
            | Op::AddFixed { .. }
            | Op::SubFixed { .. }
            | Op::MulFixed { .. } => false,
            // Decided below, once every `move` is seen.
            Op::ForNext { .. } => false,
            _ => true,
        };
        // Every instruction that is not a `MOD` has `WIDE` as it has `SURE`.
        let wide = wide.unwrap_or(flag);
        // A sure register that is not a temporary (a variable, a constant) is never -0.
        let plain = match op {
            Op::StoreLong { src, .. }
            | Op::StoreFixed {
                src, decimals: 0, ..
            } => !temps.contains(&src) && sure_reg(src),
            _ => flag,
        };
        out.push((u8::from(flag) * SURE) | (u8::from(wide) * WIDE) | (u8::from(plain) * PLAIN));
        if let Op::Move { dst, src } = op {
            if !temps.contains(&dst) && !sure_reg(dst) {
                let w = whole(src);
                moved.entry(dst).and_modify(|m| *m &= w).or_insert(w);
            }
        }
        // What the instruction leaves in a temporary it writes.
        let wrote: Option<(Reg, Option<Known>)> = match op {
            Op::Move { dst, src } => Some((dst, level(src))),
            Op::Add { dst, a, b } | Op::Sub { dst, a, b } | Op::Mul { dst, a, b } => {
                Some((dst, (whole(a) && whole(b)).then_some(Known::Whole)))
            }
            // -(-2147483648) is past 32 bits.
            Op::Neg { dst, a } => Some((dst, whole(a).then_some(Known::Whole))),
            Op::CheckLong { r } | Op::CheckInt { r } => Some((r, whole(r).then_some(Known::Sure))),
            // A quotient is checked within 32 bits whatever its operands.
            Op::IDiv { dst, .. } | Op::Compare { dst, .. } => Some((dst, Some(Known::Sure))),
            // A remainder is smaller than its divisor (but a whole dividend may be infinite,
            // and its remainder not a number).
            Op::IMod { dst, a, b } | Op::Mod { dst, a, b } => {
                let known = if sure(a) && sure(b) {
                    Some(Known::Sure)
                } else {
                    (whole(a) && sure(b)).then_some(Known::Whole)
                };
                Some((dst, known))
            }
            Op::BitAnd { dst, a, b } | Op::BitOr { dst, a, b } | Op::BitXor { dst, a, b } => {
                Some((dst, (sure(a) && sure(b)).then_some(Known::Sure)))
            }
            Op::BitNot { dst, a } => Some((dst, sure(a).then_some(Known::Sure))),
            // Stores into variables, and jumps that fall through, leave temporaries alone.
            Op::StoreLong { dst, .. }
            | Op::StoreInt { dst, .. }
            | Op::StoreFixed { dst, .. }
            | Op::StoreReal { dst, .. }
            | Op::StoreBit { dst, .. }
            | Op::ArithFixed { dst, .. } => Some((dst, None)),
            Op::JumpIfFalse { .. }
            | Op::JumpIfTrue { .. }
            | Op::JumpUnlessLt { .. }
            | Op::JumpUnlessLe { .. }
            | Op::JumpUnlessEq { .. }
            | Op::JumpUnlessNe { .. }
            | Op::JumpWhenLt { .. }
            | Op::JumpWhenLe { .. }
            | Op::JumpWhenEq { .. }
            | Op::JumpWhenNe { .. } => None,
            _ => {
                known.clear();
                None
            }
        };
        if let Some((dst, what)) = wrote {
            if temps.contains(&dst) {
                match what {
                    Some(k) => known.insert(dst, k),
                    None => known.remove(&dst),
                };
            }
        }
    }
    // A `for.next` of a whole variable (a long, an INTEGER, a PowerTools variable without
    // decimals) by a whole step: the sum is whole, and never -0 (the variable never is).
    for (i, &op) in ops.iter().enumerate() {
        if let Op::ForNext {
            var,
            limit,
            decimals: 0 | INT_STORE,
            ..
        } = op
        {
            let step = limit.checked_add(1);
            let sure = sure_reg(var)
                && step.is_some_and(|s| !temps.contains(&s) && moved.get(&s) == Some(&true));
            out[i] = u8::from(sure) * (SURE | WIDE | PLAIN);
        }
    }
    out
}

/// The flags ([`SURE`], [`WIDE`]) of each instruction of the fused `ops`: for a
/// superinstruction, those every instruction it does the work of has (`base`, from
/// [`operands`] before fusion); an instruction left as it was keeps its own.
pub fn per_instruction(ops: &[Op], base: &[u8]) -> Vec<u8> {
    (0..ops.len())
        .map(|i| {
            let span = covers(ops[i]);
            base.get(i..i + span).map_or(0, |halves| {
                halves.iter().fold(SURE | WIDE | PLAIN, |all, &f| all & f)
            })
        })
        .collect()
}

/// How many adjacent instructions `op` does the work of, for the superinstructions whose
/// operands the interpreter may take without the test.
fn covers(op: Op) -> usize {
    match op {
        Op::AddLong { .. }
        | Op::SubLong { .. }
        | Op::MulLong { .. }
        | Op::ModLong { .. }
        | Op::IntLong { .. }
        | Op::AndLong { .. }
        | Op::OrLong { .. }
        | Op::XorLong { .. }
        | Op::AddInt { .. }
        | Op::SubInt { .. }
        | Op::MulInt { .. }
        | Op::IntInt { .. }
        | Op::NotAndWhole { .. }
        | Op::AndOr { .. }
        | Op::AndXorWhole { .. } => 2,
        // A chained instruction's flags are those of its first superinstruction; the second's
        // are read where it stays.
        Op::AddModWhole { .. }
        | Op::SubMod { .. }
        | Op::QuotAddFixed { .. }
        | Op::DivAddFixed { .. } => 2,
        Op::NotAndLong { .. }
        | Op::AndXorLong { .. }
        | Op::DivAddLong { .. }
        | Op::AddModLong { .. } => 3,
        Op::Offset2 { .. } => 4,
        Op::OffsetTail { .. } => 3,
        Op::AndJump { .. } => 2,
        _ => 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compile::bytecode::REAL_STORE;

    const T: Reg = 100;

    fn temps() -> Range<Reg> {
        T..T + 8
    }

    fn sure_bits(flags: &[u8]) -> Vec<bool> {
        flags.iter().map(|f| f & SURE != 0).collect()
    }

    /// Registers below 10 are long variables, 50 a whole constant; others are reals.
    fn sure_reg(r: Reg) -> bool {
        r < 10 || r == 50
    }

    #[test]
    fn variables_constants_and_checked_temporaries_are_sure() {
        let ops = [
            // A& * 75 + 74, checked, MOD 65537 (constant), stored.
            Op::Mul {
                dst: T,
                a: 1,
                b: 50,
            },
            Op::CheckLong { r: T },
            Op::Add {
                dst: T,
                a: T,
                b: 50,
            },
            Op::CheckLong { r: T },
            Op::IMod {
                dst: T,
                a: T,
                b: 50,
            },
            Op::StoreLong { dst: 1, src: T },
            // A real variable (20) is not sure, nor what it makes.
            Op::BitAnd {
                dst: T,
                a: 20,
                b: 1,
            },
            Op::BitOr { dst: T, a: T, b: 2 },
            // A sum not checked may be past 32 bits.
            Op::Add {
                dst: T + 1,
                a: 1,
                b: 2,
            },
            Op::IMod {
                dst: T + 1,
                a: T + 1,
                b: 50,
            },
            // NOT of a long is sure, and so is the AND of it.
            Op::BitNot { dst: T + 2, a: 3 },
            Op::BitAnd {
                dst: T + 2,
                a: T + 2,
                b: 50,
            },
            Op::End,
        ];
        let sure = sure_bits(&operands(&ops, &temps(), &sure_reg));
        assert_eq!(
            sure,
            [true, true, true, true, true, true, false, false, true, false, true, true, true]
        );
    }

    #[test]
    fn temporaries_are_forgotten_where_control_arrives_and_after_other_instructions() {
        let ops = [
            Op::IMod { dst: T, a: 1, b: 2 },
            // A jump lands on the next instruction: t may come from elsewhere.
            Op::BitAnd {
                dst: T + 1,
                a: T,
                b: 1,
            },
            Op::Jump { target: 1 },
            Op::IMod { dst: T, a: 1, b: 2 },
            // A division (a real result) forgets t.
            Op::Div { dst: T, a: 1, b: 2 },
            Op::BitAnd {
                dst: T + 1,
                a: T,
                b: 1,
            },
            Op::IMod { dst: T, a: 1, b: 2 },
            // Any instruction not followed forgets every temporary.
            Op::PrintLine,
            Op::BitAnd {
                dst: T + 1,
                a: T,
                b: 1,
            },
            Op::IMod { dst: T, a: 1, b: 2 },
            Op::Gosub { target: 11 },
            // The subroutine comes back here.
            Op::BitAnd {
                dst: T + 1,
                a: T,
                b: 1,
            },
            Op::End,
        ];
        let sure = sure_bits(&operands(&ops, &temps(), &sure_reg));
        assert_eq!(
            sure,
            [true, false, true, true, true, false, true, true, false, true, true, false, true]
        );
    }

    #[test]
    fn stores_of_whole_values_and_loops_of_whole_steps_are_flagged() {
        let (limit, step) = (60, 61);
        let ops = [
            // FOR with a whole step (a constant) into a long.
            Op::Move { dst: limit, src: 1 },
            Op::Move { dst: step, src: 50 },
            Op::ForCheck {
                var: 2,
                limit,
                exit: 9,
            },
            // A sum of longs, stored: whole, perhaps past 32 bits.
            Op::Add { dst: T, a: 1, b: 2 },
            Op::StoreLong { dst: 3, src: T },
            // A sum with a real is not.
            Op::Add {
                dst: T,
                a: 1,
                b: 20,
            },
            Op::StoreLong { dst: 3, src: T },
            // Into a whole fixed-point slot, and into one with decimals (which rounds).
            Op::AddFixed {
                dst: 4,
                a: 1,
                b: 50,
                decimals: 0,
            },
            Op::AddFixed {
                dst: 4,
                a: 1,
                b: 50,
                decimals: 2,
            },
            Op::ForNext {
                var: 2,
                limit,
                body: 3,
                decimals: 0,
            },
            // The same loop by a real step, and a loop of a real variable.
            Op::Move {
                dst: step + 2,
                src: 20,
            },
            Op::ForNext {
                var: 2,
                limit: step + 1,
                body: 3,
                decimals: 0,
            },
            Op::Move {
                dst: step + 4,
                src: 50,
            },
            Op::ForNext {
                var: 20,
                limit: step + 3,
                body: 3,
                decimals: REAL_STORE,
            },
            Op::End,
        ];
        let sure = sure_bits(&operands(&ops, &temps(), &sure_reg));
        assert_eq!(
            sure,
            [
                true, true, true, true, true, true, false, true, false, true, true, false, true,
                false, true
            ]
        );
    }

    #[test]
    fn a_superinstruction_is_sure_when_every_instruction_it_runs_is() {
        let fused = [
            Op::ModLong {
                t: T,
                dst: 1,
                a: 1,
                b: 50,
            },
            Op::StoreLong { dst: 1, src: T },
            Op::AndLong {
                t: T,
                dst: 1,
                a: 20,
                b: 50,
            },
            Op::StoreLong { dst: 1, src: T },
        ];
        const ALL: u8 = SURE | WIDE | PLAIN;
        let base = [ALL, ALL, 0, ALL];
        assert_eq!(per_instruction(&fused, &base), [ALL, ALL, 0, ALL]);
        // The last instruction's halves run past the end: not sure.
        assert_eq!(per_instruction(&fused[..3], &base[..3]), [ALL, ALL, 0]);
    }

    #[test]
    fn a_mod_of_a_whole_sum_by_a_sure_divisor_is_wide() {
        let ops = [
            // (H& + B&) MOD 7: the sum is whole, perhaps past 32 bits.
            Op::Add { dst: T, a: 1, b: 2 },
            Op::IMod {
                dst: T,
                a: T,
                b: 50,
            },
            Op::StoreLong { dst: 3, src: T },
            // A MOD of the sum by a real is neither; its remainder is not known whole.
            Op::Add { dst: T, a: 1, b: 2 },
            Op::IMod {
                dst: T,
                a: T,
                b: 20,
            },
            Op::StoreLong { dst: 3, src: T },
            Op::End,
        ];
        let flags = operands(&ops, &temps(), &sure_reg);
        const ALL: u8 = SURE | WIDE | PLAIN;
        // A store of a temporary is never `PLAIN` (a temporary may be -0).
        assert_eq!(flags, [ALL, WIDE, SURE | WIDE, ALL, 0, 0, ALL]);
        // Fused as `AddModLong` (add, imod, store): WIDE only.
        let fused = [
            Op::AddModLong {
                t: T,
                x: 2,
                dst: 3,
                m: 50,
                t_first: true,
            },
            ops[1],
            ops[2],
        ];
        assert_eq!(
            per_instruction(&fused, &flags[..3]),
            [WIDE, WIDE, SURE | WIDE]
        );
    }

    #[test]
    fn a_copy_of_a_sure_variable_or_constant_is_plain() {
        let ops = [
            Op::StoreLong { dst: 3, src: 1 },
            Op::StoreLong { dst: 3, src: 50 },
            Op::StoreFixed {
                dst: 3,
                src: 2,
                decimals: 0,
            },
            // A real, a sure temporary, a store with decimals: not plain.
            Op::StoreLong { dst: 3, src: 20 },
            Op::IMod { dst: T, a: 1, b: 2 },
            Op::StoreLong { dst: 3, src: T },
            Op::StoreFixed {
                dst: 3,
                src: 2,
                decimals: 2,
            },
            Op::End,
        ];
        let plain: Vec<bool> = operands(&ops, &temps(), &sure_reg)
            .iter()
            .map(|f| f & PLAIN != 0)
            .collect();
        assert_eq!(plain, [true, true, true, false, true, false, false, true]);
    }
}
