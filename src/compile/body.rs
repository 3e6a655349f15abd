//! Loops whose body is straight-line arithmetic (with forward jumps: `IF … THEN … END IF`
//! inside), which the machine runs outside the interpreter on typed registers (`vm::body`):
//! what they are, and their body translated for it.
//!
//! The interpreter keeps every value as an `f64`, so an integer operator converts its operands
//! to integers and back at each instruction, and a long's store tests its value's range and
//! wholeness. Here each register the body uses gets one kind for the whole body: `Int` (an
//! `i64`) when every value written into it is whole (a long, an INTEGER, a whole PowerTools
//! variable, a whole constant, what `MOD`, `\`, `AND`, `OR`, `XOR`, `NOT`, comparisons and
//! stores into whole variables give, and sums, differences and products of those), `Real`
//! otherwise; conversions happen only where kinds meet. A value is the interpreter's exactly:
//! an `Int` holds the `f64` the interpreter would, every `Int` stays within ±2^53 (where an
//! `f64` is exact), and an operation that would leave that range, fault, or give a value the
//! integer cannot carry (a -0 reaching a real) leaves its iteration to the interpreter, undone.
//!
//! The translation works on the instructions before fusion (each of which the interpreter
//! counts as one): the superinstructions stand in place of the same instructions.

use super::bytecode::{BinaryOp, Cmp, Op, Reg, INT_STORE};
use super::whole::SURE;
use std::collections::BTreeMap;
use std::ops::Range;

/// The kind of value a register of a body holds all through it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Kind {
    /// A whole number within ±2^53, as an `i64`.
    Int,
    /// A real, as an `f64`.
    Real,
}

/// A register of the body: an index into its local registers.
pub type Local = u8;

/// The width an integer store or check keeps a value within.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Width {
    /// A long (or a whole PowerTools variable): 32 bits.
    Long,
    /// A MotionBASIC INTEGER: 16 bits.
    Short,
}

/// One instruction of a body, on local registers. The suffix says the kind of its operands
/// (`I`: `Int`, `R`: `Real`); a result is `Int` unless the name says otherwise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Micro {
    /// `d = s`, either kind.
    Mov { d: Local, s: Local },
    /// `d = a + b`.
    AddI { d: Local, a: Local, b: Local },
    /// `d = a - b`.
    SubI { d: Local, a: Local, b: Local },
    /// `d = a * b`.
    MulI { d: Local, a: Local, b: Local },
    /// `d = -s`.
    NegI { d: Local, s: Local },
    /// MotionBASIC `MOD`.
    ModI { d: Local, a: Local, b: Local },
    /// MotionBASIC `\`.
    QuotI { d: Local, a: Local, b: Local },
    /// PowerTools `MOD` (the remainder with the sign of `a`).
    RemI { d: Local, a: Local, b: Local },
    /// Bitwise `AND`.
    AndI { d: Local, a: Local, b: Local },
    /// Bitwise `OR`.
    OrI { d: Local, a: Local, b: Local },
    /// Bitwise `XOR`.
    XorI { d: Local, a: Local, b: Local },
    /// Bitwise `NOT`.
    BitNotI { d: Local, s: Local },
    /// `d = (a cmp b)` as 1 or 0.
    CmpI {
        cmp: Cmp,
        d: Local,
        a: Local,
        b: Local,
    },
    /// `d = (s = 0)` as 1 or 0.
    NotI { d: Local, s: Local },
    /// `d = s` when it fits `w`: a store into an integer variable, or (`d == s`) a check.
    FitI { d: Local, s: Local, w: Width },
    /// Real `d = a + b`.
    AddR { d: Local, a: Local, b: Local },
    /// Real `d = a - b`.
    SubR { d: Local, a: Local, b: Local },
    /// Real `d = a * b`.
    MulR { d: Local, a: Local, b: Local },
    /// Real `d = a / b`.
    DivR { d: Local, a: Local, b: Local },
    /// Real `d = -s`.
    NegR { d: Local, s: Local },
    /// PowerTools `MOD` of reals; a real.
    RemR { d: Local, a: Local, b: Local },
    /// An integer operator (`MOD`, `\`, `AND`, `OR`, `XOR`) of reals, rounded first.
    IntR {
        op: BinaryOp,
        d: Local,
        a: Local,
        b: Local,
    },
    /// Bitwise `NOT` of a real, rounded first.
    BitNotR { d: Local, s: Local },
    /// `d = (a cmp b)` of reals.
    CmpR {
        cmp: Cmp,
        d: Local,
        a: Local,
        b: Local,
    },
    /// `d = (s = 0)` of a real.
    NotR { d: Local, s: Local },
    /// The `Int` `s` as a real `d`.
    ToR { d: Local, s: Local },
    /// [`Micro::ToR`] of an `Int` that may stand for -0 (a product, a `MOD`…): a 0 leaves
    /// the iteration to the interpreter, which knows the zero's sign.
    ToRSigned { d: Local, s: Local },
    /// A real stored into a long (halves rounded to even).
    LongR { d: Local, s: Local },
    /// A real stored into an INTEGER.
    ShortR { d: Local, s: Local },
    /// A real stored into a fixed-point slot of `decimals` places: `Int` when 0, else `Real`.
    FixedR { d: Local, s: Local, decimals: u8 },
    /// A real stored into a real: `d = s` when finite.
    RealR { d: Local, s: Local },
    /// The real `s` fits `w` (a check of long or INTEGER arithmetic).
    CheckR { s: Local, w: Width },
    /// Go to `t` (each jump skips the interpreter's instructions [`Body::skips`] says).
    Jump { t: u16 },
    /// Go to `t` when `c` is 0 (`zero`) or not.
    JumpZeroI { c: Local, zero: bool, t: u16 },
    /// [`Micro::JumpZeroI`] of a real.
    JumpZeroR { c: Local, zero: bool, t: u16 },
    /// Go to `t` when `a cmp b`.
    JumpCmpI {
        cmp: Cmp,
        a: Local,
        b: Local,
        t: u16,
    },
    /// Go to `t` when `(a cmp b) == want`, of reals (a comparison with NaN is false).
    JumpCmpR {
        cmp: Cmp,
        want: bool,
        a: Local,
        b: Local,
        t: u16,
    },
    /// The end of the body: the loop's `for.next`.
    Next,
}

/// An instruction is 8 bytes: the interpreter of bodies finds the next at `pc * 8`.
const _: () = assert!(std::mem::size_of::<Micro>() == 8);

/// A loop's body translated for `vm::body`.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// The instructions, ending with [`Micro::Next`]; every jump's target is one of them
    /// (the only way to make a `Body` is [`find`], which makes sure of both).
    ops: Vec<Micro>,
    /// Per instruction, for a jump, how many of the interpreter's instructions it skips (not
    /// counted when it is taken).
    pub skips: Vec<u16>,
    /// How many local registers they use.
    pub locals: usize,
    /// The registers read before they are written, loaded on entry: value register, local,
    /// kind.
    pub ins: Vec<(Reg, Local, Kind)>,
    /// The registers written, stored back on leaving.
    pub outs: Vec<(Reg, Local, Kind)>,
    /// The locals an iteration left undone must give back as they were at its start.
    pub kept: Vec<Local>,
    /// The loop variable's local (`Int`) and register.
    pub var: (Local, Reg),
    /// The limit's register (the step's is the one after it).
    pub limit: Reg,
    /// The loop variable is a MotionBASIC INTEGER (16 bits); else 32 bits.
    pub short: bool,
    /// The interpreter's instructions of an iteration that jumps nowhere: the body's and the
    /// `for.next`.
    pub count: u64,
    /// The lowest register written (a write below the trace's limit is traced: then the
    /// interpreter runs the loop).
    pub lowest_write: Reg,
    /// The highest register read or written.
    pub highest: Reg,
    /// The instruction after the loop.
    pub after: u32,
}

impl Body {
    /// The instructions, ending with [`Micro::Next`], every jump's target among them.
    pub fn ops(&self) -> &[Micro] {
        &self.ops
    }
}

/// The most local registers a body may use.
const MOST_LOCALS: usize = 256;

/// The largest magnitude an `Int` holds: past it an `f64` is no longer exact.
pub const EXACT: i64 = 1 << 53;

/// Every loop of the unfused `ops` (with their [`SURE`] flags `sure`) whose body [`translate`]
/// can translate, by the instruction its body starts at.
pub fn find(
    ops: &[Op],
    sure: &[u8],
    temps: &Range<Reg>,
    whole: &dyn Fn(Reg) -> bool,
    constant: &dyn Fn(Reg) -> Option<f64>,
) -> BTreeMap<u32, Body> {
    let mut bodies = BTreeMap::new();
    for (i, op) in ops.iter().enumerate() {
        if let Op::ForCheck { var, limit, exit } = *op {
            let at = Loop {
                check: i as u32,
                var,
                limit,
                exit,
            };
            if let Some(body) = translate(ops, sure, at, temps, whole, constant) {
                bodies.insert(at.check + 1, body);
            }
        }
    }
    bodies
}

/// Make each `for.check` of the fused `ops` entering a loop of `bodies` an [`Op::ForTight`].
pub fn mark(ops: &mut [Op], bodies: &BTreeMap<u32, Body>) {
    for &start in bodies.keys() {
        let Some(at) = (start as usize).checked_sub(1) else {
            continue;
        };
        if let Some(&Op::ForCheck { var, limit, exit }) = ops.get(at) {
            ops[at] = Op::ForTight { var, limit, exit };
        }
    }
}

/// A `for.check` and what it names.
#[derive(Debug, Clone, Copy)]
struct Loop {
    check: u32,
    var: Reg,
    limit: Reg,
    exit: u32,
}

/// One instruction of the body in the few shapes the translation knows.
#[derive(Debug, Clone, Copy)]
enum Step {
    Bin {
        op: Bin,
        d: Reg,
        a: Reg,
        b: Reg,
    },
    Un {
        op: Un,
        d: Reg,
        s: Reg,
    },
    Store {
        to: Store,
        d: Reg,
        s: Reg,
    },
    Check {
        w: Width,
        r: Reg,
    },
    Jump {
        t: u32,
    },
    JumpZero {
        c: Reg,
        zero: bool,
        t: u32,
    },
    JumpCmp {
        cmp: Cmp,
        want: bool,
        a: Reg,
        b: Reg,
        t: u32,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Bin {
    Add,
    Sub,
    Mul,
    Div,
    /// PowerTools `MOD`.
    Rem,
    /// MotionBASIC `MOD`, `\`, bitwise `AND`, `OR`, `XOR`.
    Int(BinaryOp),
    Cmp(Cmp),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Un {
    Move,
    Neg,
    Not,
    BitNot,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Store {
    Long,
    Short,
    Real,
    Fixed(u8),
}

/// The steps of instruction `op` (a fused store goes through `scratch`, a register of its
/// own); `None` when the translation does not know it.
fn steps(op: Op, scratch: Reg) -> Option<Vec<Step>> {
    let bin = |op: BinaryOp| -> Option<Bin> {
        Some(match op {
            BinaryOp::Add => Bin::Add,
            BinaryOp::Sub => Bin::Sub,
            BinaryOp::Mul => Bin::Mul,
            BinaryOp::Div => Bin::Div,
            BinaryOp::Mod => Bin::Rem,
            BinaryOp::BitAnd
            | BinaryOp::BitOr
            | BinaryOp::BitXor
            | BinaryOp::IntDiv
            | BinaryOp::BasicMod => Bin::Int(op),
            BinaryOp::Pow | BinaryOp::And | BinaryOp::Or | BinaryOp::Xor => return None,
        })
    };
    let one = |s: Step| Some(vec![s]);
    let b = |op: Bin, d: Reg, a: Reg, b: Reg| Step::Bin { op, d, a, b };
    let fixed = |op: Bin, dst: Reg, a: Reg, b_: Reg, decimals: u8| {
        Some(vec![
            b(op, scratch, a, b_),
            Step::Store {
                to: Store::Fixed(decimals),
                d: dst,
                s: scratch,
            },
        ])
    };
    match op {
        Op::Move { dst, src } => one(Step::Un {
            op: Un::Move,
            d: dst,
            s: src,
        }),
        Op::Add { dst, a, b: y } => one(b(Bin::Add, dst, a, y)),
        Op::Sub { dst, a, b: y } => one(b(Bin::Sub, dst, a, y)),
        Op::Mul { dst, a, b: y } => one(b(Bin::Mul, dst, a, y)),
        Op::Div { dst, a, b: y } => one(b(Bin::Div, dst, a, y)),
        Op::Mod { dst, a, b: y } => one(b(Bin::Rem, dst, a, y)),
        Op::IMod { dst, a, b: y } => one(b(Bin::Int(BinaryOp::BasicMod), dst, a, y)),
        Op::IDiv { dst, a, b: y } => one(b(Bin::Int(BinaryOp::IntDiv), dst, a, y)),
        Op::BitAnd { dst, a, b: y } => one(b(Bin::Int(BinaryOp::BitAnd), dst, a, y)),
        Op::BitOr { dst, a, b: y } => one(b(Bin::Int(BinaryOp::BitOr), dst, a, y)),
        Op::BitXor { dst, a, b: y } => one(b(Bin::Int(BinaryOp::BitXor), dst, a, y)),
        Op::Binary { op, dst, a, b: y } => one(b(bin(op)?, dst, a, y)),
        Op::Compare { cmp, dst, a, b: y } => one(b(Bin::Cmp(cmp), dst, a, y)),
        Op::AddFixed {
            dst,
            a,
            b: y,
            decimals,
        } => fixed(Bin::Add, dst, a, y, decimals),
        Op::SubFixed {
            dst,
            a,
            b: y,
            decimals,
        } => fixed(Bin::Sub, dst, a, y, decimals),
        Op::MulFixed {
            dst,
            a,
            b: y,
            decimals,
        } => fixed(Bin::Mul, dst, a, y, decimals),
        Op::ArithFixed {
            op,
            dst,
            a,
            b: y,
            decimals,
        } => fixed(bin(op)?, dst, a, y, decimals),
        Op::Neg { dst, a } => one(Step::Un {
            op: Un::Neg,
            d: dst,
            s: a,
        }),
        Op::Not { dst, a } => one(Step::Un {
            op: Un::Not,
            d: dst,
            s: a,
        }),
        Op::BitNot { dst, a } => one(Step::Un {
            op: Un::BitNot,
            d: dst,
            s: a,
        }),
        Op::StoreLong { dst, src } => one(Step::Store {
            to: Store::Long,
            d: dst,
            s: src,
        }),
        Op::StoreInt { dst, src } => one(Step::Store {
            to: Store::Short,
            d: dst,
            s: src,
        }),
        Op::StoreReal { dst, src } => one(Step::Store {
            to: Store::Real,
            d: dst,
            s: src,
        }),
        Op::StoreFixed { dst, src, decimals } => one(Step::Store {
            to: Store::Fixed(decimals),
            d: dst,
            s: src,
        }),
        Op::CheckLong { r } => one(Step::Check { w: Width::Long, r }),
        Op::CheckInt { r } => one(Step::Check { w: Width::Short, r }),
        Op::Jump { target } => one(Step::Jump { t: target }),
        Op::JumpIfFalse { cond, target } => one(Step::JumpZero {
            c: cond,
            zero: true,
            t: target,
        }),
        Op::JumpIfTrue { cond, target } => one(Step::JumpZero {
            c: cond,
            zero: false,
            t: target,
        }),
        Op::JumpUnlessLt { a, b, target } => one(jump_cmp(Cmp::Lt, false, a, b, target)),
        Op::JumpUnlessLe { a, b, target } => one(jump_cmp(Cmp::Le, false, a, b, target)),
        Op::JumpUnlessEq { a, b, target } => one(jump_cmp(Cmp::Eq, false, a, b, target)),
        Op::JumpUnlessNe { a, b, target } => one(jump_cmp(Cmp::Ne, false, a, b, target)),
        Op::JumpWhenLt { a, b, target } => one(jump_cmp(Cmp::Lt, true, a, b, target)),
        Op::JumpWhenLe { a, b, target } => one(jump_cmp(Cmp::Le, true, a, b, target)),
        Op::JumpWhenEq { a, b, target } => one(jump_cmp(Cmp::Eq, true, a, b, target)),
        Op::JumpWhenNe { a, b, target } => one(jump_cmp(Cmp::Ne, true, a, b, target)),
        _ => None,
    }
}

fn jump_cmp(cmp: Cmp, want: bool, a: Reg, b: Reg, t: u32) -> Step {
    Step::JumpCmp { cmp, want, a, b, t }
}

impl Step {
    fn written(&self) -> Option<Reg> {
        match *self {
            Step::Bin { d, .. } | Step::Un { d, .. } | Step::Store { d, .. } => Some(d),
            _ => None,
        }
    }

    fn read(&self) -> Vec<Reg> {
        match *self {
            Step::Bin { a, b, .. } | Step::JumpCmp { a, b, .. } => vec![a, b],
            Step::Un { s, .. } | Step::Store { s, .. } => vec![s],
            Step::Check { r, .. } => vec![r],
            Step::JumpZero { c, .. } => vec![c],
            Step::Jump { .. } => vec![],
        }
    }

    fn target(&self) -> Option<u32> {
        match *self {
            Step::Jump { t } | Step::JumpZero { t, .. } | Step::JumpCmp { t, .. } => Some(t),
            _ => None,
        }
    }
}

/// What is known of a register: its kind, and (an `Int`) whether it may stand for -0.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Known {
    kind: Kind,
    /// An `Int` that may be the interpreter's -0 when it is 0.
    signed_zero: bool,
}

const INT: Known = Known {
    kind: Kind::Int,
    signed_zero: false,
};
const REAL: Known = Known {
    kind: Kind::Real,
    signed_zero: false,
};

fn join(x: Known, y: Known) -> Known {
    Known {
        kind: x.kind.max(y.kind),
        signed_zero: x.signed_zero || y.signed_zero,
    }
}

/// What step `s` writes, its operands being as `of` says.
fn result(s: &Step, of: &dyn Fn(Reg) -> Known) -> Option<Known> {
    let int = |r: Reg| of(r).kind == Kind::Int;
    let signed = |z: bool| Known {
        kind: Kind::Int,
        signed_zero: z,
    };
    Some(match *s {
        Step::Bin { op, a, b, .. } => {
            let ints = int(a) && int(b);
            match op {
                Bin::Add if ints => signed(of(a).signed_zero && of(b).signed_zero),
                // -0 - +0 is -0, and only that.
                Bin::Sub if ints => signed(of(a).signed_zero),
                Bin::Mul if ints => signed(true),
                Bin::Rem if ints => INT,
                Bin::Add | Bin::Sub | Bin::Mul | Bin::Div | Bin::Rem => REAL,
                // A remainder takes the sign of the dividend, a zero quotient that of the
                // quotient.
                Bin::Int(BinaryOp::BasicMod | BinaryOp::IntDiv) => signed(true),
                Bin::Int(_) | Bin::Cmp(_) => INT,
            }
        }
        Step::Un { op, s, .. } => match op {
            Un::Move => of(s),
            Un::Neg if int(s) => signed(true),
            Un::Neg => REAL,
            Un::Not | Un::BitNot => INT,
        },
        Step::Store { to, .. } => match to {
            Store::Long | Store::Short | Store::Fixed(0) => INT,
            Store::Real | Store::Fixed(_) => REAL,
        },
        _ => return None,
    })
}

/// The body of the loop `at` translated, when every instruction of it is one the translation
/// knows, its jumps go forward within it (or to its `for.next`), its loop variable is whole
/// with a whole step (`sure`), and the registers it uses fit.
fn translate(
    ops: &[Op],
    sure: &[u8],
    at: Loop,
    temps: &Range<Reg>,
    whole: &dyn Fn(Reg) -> bool,
    constant: &dyn Fn(Reg) -> Option<f64>,
) -> Option<Body> {
    let start = at.check + 1;
    let next = at.exit.checked_sub(1)?;
    if next < start {
        return None;
    }
    let Op::ForNext {
        var,
        limit,
        body,
        decimals,
    } = *ops.get(next as usize)?
    else {
        return None;
    };
    let sure_next = sure.get(next as usize).is_some_and(|f| f & SURE != 0);
    if body != start || var != at.var || limit != at.limit || !sure_next {
        return None;
    }
    if decimals != 0 && decimals != INT_STORE {
        return None;
    }
    // The body's steps, by instruction.
    let mut by_op: Vec<Vec<Step>> = Vec::new();
    for i in start..next {
        let scratch = u32::MAX - i;
        let s = steps(*ops.get(i as usize)?, scratch)?;
        for step in &s {
            if let Some(t) = step.target() {
                if t <= i || t > next {
                    return None;
                }
            }
        }
        by_op.push(s);
    }
    let all: Vec<Step> = by_op.iter().flatten().copied().collect();
    let scratch_reg = |r: Reg| r > u32::MAX - next;
    // The registers surely written before each instruction, whichever way control came (jumps
    // go forward only, so one pass in order sees every way into an instruction first). A
    // register read where it may not have been written holds the value of the iteration before
    // or of before the loop: a variable is loaded on entry; a temporary cannot be.
    let len = by_op.len();
    let mut before: Vec<Option<Vec<Reg>>> = vec![None; len + 1];
    before[0] = Some(Vec::new());
    let meet = |slot: &mut Option<Vec<Reg>>, set: &[Reg]| {
        *slot = Some(match slot.take() {
            None => set.to_vec(),
            Some(old) => old.into_iter().filter(|r| set.contains(r)).collect(),
        });
    };
    for (k, s) in by_op.iter().enumerate() {
        let mut set = before[k].clone().unwrap_or_default();
        let mut falls = true;
        for step in s {
            for r in step.read() {
                if !set.contains(&r) && (temps.contains(&r) || scratch_reg(r)) {
                    return None;
                }
            }
            if let Some(d) = step.written() {
                set.push(d);
            }
            if let Some(t) = step.target() {
                meet(&mut before[(t - start) as usize], &set);
            }
            falls &= !matches!(step, Step::Jump { .. });
        }
        if falls {
            meet(&mut before[k + 1], &set);
        }
    }
    // Every variable and constant the body reads or writes is loaded, and the loop variable.
    let mut ins: Vec<Reg> = vec![var];
    for s in &all {
        for r in s.read().into_iter().chain(s.written()) {
            if !temps.contains(&r) && !scratch_reg(r) && !ins.contains(&r) {
                ins.push(r);
            }
        }
    }
    if ins.iter().any(|&r| r == limit || r == limit + 1) {
        return None;
    }
    let written: Vec<Reg> = {
        let mut w: Vec<Reg> = all.iter().filter_map(Step::written).collect();
        w.sort_unstable();
        w.dedup();
        w
    };
    if written.iter().any(|&r| r == limit || r == limit + 1) {
        return None;
    }
    // Kinds: loaded registers as their values are; written ones as every write makes them.
    let mut known: BTreeMap<Reg, Known> = BTreeMap::new();
    for &r in &ins {
        let int = whole(r) && constant(r).is_none_or(|c| c.abs() <= EXACT as f64);
        known.insert(r, if int { INT } else { REAL });
    }
    loop {
        let mut changed = false;
        for s in &all {
            let Some(d) = s.written() else { continue };
            let of = |r: Reg| known.get(&r).copied().unwrap_or(INT);
            let Some(k) = result(s, &of) else { continue };
            let now = match known.get(&d) {
                Some(&old) => join(old, k),
                None => k,
            };
            if known.get(&d) != Some(&now) {
                known.insert(d, now);
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let kind_of = |r: Reg| known.get(&r).copied().unwrap_or(INT);
    // The loop variable, and every variable written, hold what the interpreter would store:
    // the variable whole, an integer never a -0 it could not give back.
    if kind_of(var) != INT {
        return None;
    }
    if written
        .iter()
        .any(|&r| !temps.contains(&r) && !scratch_reg(r) && kind_of(r).signed_zero)
    {
        return None;
    }
    // Locals: the registers, then two for conversions.
    let mut local: BTreeMap<Reg, Local> = BTreeMap::new();
    for &r in ins.iter().chain(&written) {
        let n = local.len();
        local.entry(r).or_insert(n as Local);
        if local.len() > MOST_LOCALS - 2 {
            return None;
        }
    }
    let conv = [local.len() as Local, local.len() as Local + 1];
    let locals = local.len() + 2;
    let l = |r: Reg| local.get(&r).copied().unwrap_or(0);
    let mut out: Vec<Micro> = Vec::new();
    let mut first_micro: Vec<usize> = Vec::new();
    // Jumps to patch: micro index, target instruction.
    let mut patches: Vec<(usize, u32)> = Vec::new();
    let mut skip_at: Vec<(usize, u16)> = Vec::new();
    for (k, s) in by_op.iter().enumerate() {
        first_micro.push(out.len());
        let i = start + k as u32;
        for step in s {
            emit(
                step,
                i,
                &kind_of,
                &l,
                conv,
                &mut out,
                &mut patches,
                &mut skip_at,
            );
        }
    }
    let end = out.len();
    out.push(Micro::Next);
    for (m, t) in patches {
        let to = if t == next {
            end
        } else {
            *first_micro.get((t - start) as usize)?
        };
        let to = u16::try_from(to).ok()?;
        if let Some(op) = out.get_mut(m) {
            match op {
                Micro::Jump { t, .. }
                | Micro::JumpZeroI { t, .. }
                | Micro::JumpZeroR { t, .. }
                | Micro::JumpCmpI { t, .. }
                | Micro::JumpCmpR { t, .. } => *t = to,
                _ => return None,
            }
        }
    }
    let ins_l: Vec<(Reg, Local, Kind)> = ins.iter().map(|&r| (r, l(r), kind_of(r).kind)).collect();
    let outs: Vec<(Reg, Local, Kind)> = written
        .iter()
        .filter(|&&r| !scratch_reg(r))
        .map(|&r| (r, l(r), kind_of(r).kind))
        .collect();
    // An iteration left undone gives back the variables it wrote (the loop variable among them).
    let mut kept: Vec<Local> = ins
        .iter()
        .filter(|r| written.contains(r))
        .map(|&r| l(r))
        .collect();
    kept.push(l(var));
    kept.sort_unstable();
    kept.dedup();
    let regs = ins.iter().chain(&written).filter(|&&r| !scratch_reg(r));
    let highest = regs.clone().copied().max()?.max(limit + 1);
    let lowest_write = outs.iter().map(|o| o.0).min().unwrap_or(var).min(var);
    let mut skips = vec![0u16; out.len()];
    for (m, k) in skip_at {
        *skips.get_mut(m)? = k;
    }
    Some(Body {
        skips,
        ops: out,
        locals,
        ins: ins_l,
        outs,
        kept,
        var: (l(var), var),
        limit,
        short: decimals == INT_STORE,
        count: u64::from(next - start) + 1,
        lowest_write,
        highest,
        after: at.exit,
    })
}

/// Emit the micro-instructions of `step` (of instruction `i`), converting `Int` operands to
/// reals where a real operation reads them (into the locals `conv`).
#[allow(clippy::too_many_arguments)]
fn emit(
    step: &Step,
    i: u32,
    kind_of: &dyn Fn(Reg) -> Known,
    l: &dyn Fn(Reg) -> Local,
    conv: [Local; 2],
    out: &mut Vec<Micro>,
    patches: &mut Vec<(usize, u32)>,
    skips: &mut Vec<(usize, u16)>,
) {
    let int = |r: Reg| kind_of(r).kind == Kind::Int;
    // The register `r` as a real: itself, or converted into `conv[k]` (checked for -0 when
    // `sign` matters to what reads it).
    let real = |r: Reg, k: usize, sign: bool, out: &mut Vec<Micro>| -> Local {
        if !int(r) {
            return l(r);
        }
        let d = conv[k];
        out.push(if sign && kind_of(r).signed_zero {
            Micro::ToRSigned { d, s: l(r) }
        } else {
            Micro::ToR { d, s: l(r) }
        });
        d
    };
    // An `Int` result for `d`: straight into it, or (a real register) through `conv[0]`.
    let int_into = |d: Reg, make: &dyn Fn(Local) -> Micro, signed: bool, out: &mut Vec<Micro>| {
        if int(d) {
            out.push(make(l(d)));
        } else {
            out.push(make(conv[0]));
            out.push(if signed {
                Micro::ToRSigned {
                    d: l(d),
                    s: conv[0],
                }
            } else {
                Micro::ToR {
                    d: l(d),
                    s: conv[0],
                }
            });
        }
    };
    let skip = |t: u32, out: &Vec<Micro>, skips: &mut Vec<(usize, u16)>| {
        skips.push((out.len(), (t - i - 1) as u16));
    };
    match *step {
        Step::Bin { op, d, a, b } => {
            let ints = int(a) && int(b);
            let (la, lb) = (l(a), l(b));
            match op {
                Bin::Add | Bin::Sub | Bin::Mul if ints => {
                    let signed = match op {
                        Bin::Add => kind_of(a).signed_zero && kind_of(b).signed_zero,
                        Bin::Sub => kind_of(a).signed_zero,
                        _ => true,
                    };
                    let make = |d: Local| match op {
                        Bin::Add => Micro::AddI { d, a: la, b: lb },
                        Bin::Sub => Micro::SubI { d, a: la, b: lb },
                        _ => Micro::MulI { d, a: la, b: lb },
                    };
                    int_into(d, &make, signed, out);
                }
                Bin::Rem if ints => int_into(d, &|d| Micro::RemI { d, a: la, b: lb }, false, out),
                Bin::Add | Bin::Sub | Bin::Mul | Bin::Div | Bin::Rem => {
                    let (ra, rb) = (real(a, 0, true, out), real(b, 1, true, out));
                    let d = l(d);
                    out.push(match op {
                        Bin::Add => Micro::AddR { d, a: ra, b: rb },
                        Bin::Sub => Micro::SubR { d, a: ra, b: rb },
                        Bin::Mul => Micro::MulR { d, a: ra, b: rb },
                        Bin::Div => Micro::DivR { d, a: ra, b: rb },
                        _ => Micro::RemR { d, a: ra, b: rb },
                    });
                }
                Bin::Int(bop) if ints => {
                    let make = |d: Local| match bop {
                        BinaryOp::BasicMod => Micro::ModI { d, a: la, b: lb },
                        BinaryOp::IntDiv => Micro::QuotI { d, a: la, b: lb },
                        BinaryOp::BitAnd => Micro::AndI { d, a: la, b: lb },
                        BinaryOp::BitOr => Micro::OrI { d, a: la, b: lb },
                        _ => Micro::XorI { d, a: la, b: lb },
                    };
                    let signed = matches!(bop, BinaryOp::BasicMod | BinaryOp::IntDiv);
                    int_into(d, &make, signed, out);
                }
                Bin::Int(bop) => {
                    let (ra, rb) = (real(a, 0, false, out), real(b, 1, false, out));
                    let signed = matches!(bop, BinaryOp::BasicMod | BinaryOp::IntDiv);
                    let make = |d: Local| Micro::IntR {
                        op: bop,
                        d,
                        a: ra,
                        b: rb,
                    };
                    // Both conversions used `conv`: the result goes into `d` (an `Int`, or
                    // converted after from `conv[0]`, which `IntR` has read by then).
                    int_into(d, &make, signed, out);
                }
                Bin::Cmp(cmp) if ints => int_into(
                    d,
                    &|d| Micro::CmpI {
                        cmp,
                        d,
                        a: la,
                        b: lb,
                    },
                    false,
                    out,
                ),
                Bin::Cmp(cmp) => {
                    let (ra, rb) = (real(a, 0, false, out), real(b, 1, false, out));
                    int_into(
                        d,
                        &|d| Micro::CmpR {
                            cmp,
                            d,
                            a: ra,
                            b: rb,
                        },
                        false,
                        out,
                    )
                }
            }
        }
        Step::Un { op, d, s } => {
            let ls = l(s);
            match op {
                Un::Move if int(s) && !int(d) => out.push(if kind_of(s).signed_zero {
                    Micro::ToRSigned { d: l(d), s: ls }
                } else {
                    Micro::ToR { d: l(d), s: ls }
                }),
                Un::Move => out.push(Micro::Mov { d: l(d), s: ls }),
                Un::Neg if int(s) => int_into(d, &|d| Micro::NegI { d, s: ls }, true, out),
                Un::Neg => out.push(Micro::NegR { d: l(d), s: ls }),
                Un::Not if int(s) => int_into(d, &|d| Micro::NotI { d, s: ls }, false, out),
                Un::Not => int_into(d, &|d| Micro::NotR { d, s: ls }, false, out),
                Un::BitNot if int(s) => int_into(d, &|d| Micro::BitNotI { d, s: ls }, false, out),
                Un::BitNot => int_into(d, &|d| Micro::BitNotR { d, s: ls }, false, out),
            }
        }
        Step::Store { to, d, s } => {
            let ls = l(s);
            match to {
                Store::Long | Store::Fixed(0) if int(s) => int_into(
                    d,
                    &|d| Micro::FitI {
                        d,
                        s: ls,
                        w: Width::Long,
                    },
                    false,
                    out,
                ),
                Store::Short if int(s) => int_into(
                    d,
                    &|d| Micro::FitI {
                        d,
                        s: ls,
                        w: Width::Short,
                    },
                    false,
                    out,
                ),
                Store::Long => int_into(d, &|d| Micro::LongR { d, s: ls }, false, out),
                Store::Short => int_into(d, &|d| Micro::ShortR { d, s: ls }, false, out),
                Store::Fixed(0) => int_into(
                    d,
                    &|d| Micro::FixedR {
                        d,
                        s: ls,
                        decimals: 0,
                    },
                    false,
                    out,
                ),
                Store::Fixed(decimals) => {
                    let rs = real(s, 0, true, out);
                    out.push(Micro::FixedR {
                        d: l(d),
                        s: rs,
                        decimals,
                    });
                }
                Store::Real if int(s) => out.push(if kind_of(s).signed_zero {
                    Micro::ToRSigned { d: l(d), s: ls }
                } else {
                    Micro::ToR { d: l(d), s: ls }
                }),
                Store::Real => out.push(Micro::RealR { d: l(d), s: ls }),
            }
        }
        Step::Check { w, r } => out.push(if int(r) {
            Micro::FitI {
                d: l(r),
                s: l(r),
                w,
            }
        } else {
            Micro::CheckR { s: l(r), w }
        }),
        Step::Jump { t } => {
            patches.push((out.len(), t));
            skip(t, out, skips);
            out.push(Micro::Jump { t: 0 });
        }
        Step::JumpZero { c, zero, t } => {
            patches.push((out.len(), t));
            skip(t, out, skips);
            out.push(if int(c) {
                Micro::JumpZeroI {
                    c: l(c),
                    zero,
                    t: 0,
                }
            } else {
                Micro::JumpZeroR {
                    c: l(c),
                    zero,
                    t: 0,
                }
            });
        }
        Step::JumpCmp { cmp, want, a, b, t } => {
            let ints = int(a) && int(b);
            let m = if ints {
                let cmp = if want { cmp } else { negate(cmp) };
                Micro::JumpCmpI {
                    cmp,
                    a: l(a),
                    b: l(b),
                    t: 0,
                }
            } else {
                let (ra, rb) = (real(a, 0, false, out), real(b, 1, false, out));
                Micro::JumpCmpR {
                    cmp,
                    want,
                    a: ra,
                    b: rb,
                    t: 0,
                }
            };
            patches.push((out.len(), t));
            skip(t, out, skips);
            out.push(m);
        }
    }
}

/// The comparison that holds exactly when `cmp` does not, of integers.
fn negate(cmp: Cmp) -> Cmp {
    match cmp {
        Cmp::Eq => Cmp::Ne,
        Cmp::Ne => Cmp::Eq,
        Cmp::Lt => Cmp::Ge,
        Cmp::Le => Cmp::Gt,
        Cmp::Gt => Cmp::Le,
        Cmp::Ge => Cmp::Lt,
    }
}
