//! Loops whose body is arithmetic (with forward jumps: `IF … THEN … END IF` inside; loops
//! inside; array elements; string compares and assignments), which the machine runs outside
//! the interpreter on typed registers (`vm::body`): what they are, and their body translated
//! for it.
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

use super::bytecode::{BinaryOp, Cmp, ExtOp, Op, Reg, INT_STORE, REAL_STORE};
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

/// One instruction of a body as translated, on local registers, before [`lower`] packs it
/// into a [`Micro`]. The suffix says the kind of its operands (`I`: `Int`, `R`: `Real`); a
/// result is `Int` unless the name says otherwise.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Ir {
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
    /// [`Ir::ToR`] of an `Int` that may stand for -0 (a product, a `MOD`…): a 0 leaves
    /// the iteration to the interpreter, which knows the zero's sign.
    ToRSigned { d: Local, s: Local },
    /// [`Ir::ToR`] of an `Int` a `MOD` gave, whose zero has the sign of the dividend `sign`
    /// (an `Int` that is never -0): -0 when the dividend is negative.
    ToRModSign { d: Local, s: Local, sign: Local },
    /// `d = s` of an `Int` that may stand for -0, into a real variable the body keeps as an
    /// `Int`: a 0 leaves the iteration (the interpreter's variable would hold its sign).
    IntSigned { d: Local, s: Local },
    /// [`Ir::IntSigned`] of a `MOD`'s `Int`, whose zero has the sign of the dividend `sign`:
    /// a 0 leaves the iteration only when the dividend is negative.
    IntModSign { d: Local, s: Local, sign: Local },
    /// A real stored into a long (halves rounded to even).
    LongR { d: Local, s: Local },
    /// A real stored into an INTEGER.
    ShortR { d: Local, s: Local },
    /// A real stored into a fixed-point slot of `decimals` places: `Int` when 0, else `Real`.
    FixedR { d: Local, s: Local, decimals: u8 },
    /// The quotient of the `Int`s `a / b` (a real division) stored into a fixed-point slot
    /// without decimals: PowerTools' `/` into a whole variable.
    DivFixedI { d: Local, a: Local, b: Local },
    /// The `Int` `q` plus (`minus`: less) the quotient of the `Int` `a` by the constant `k`,
    /// as reals, stored so (`Q = Q + A / 3`).
    SumDivFixedI {
        d: Local,
        q: Local,
        a: Local,
        k: i32,
        minus: bool,
    },
    /// A real stored into a real: `d = s` when finite.
    RealR { d: Local, s: Local },
    /// The real `s` fits `w` (a check of long or INTEGER arithmetic).
    CheckR { s: Local, w: Width },
    // A jump's target is not in the jump: `translate` keeps it apart (as an IR index), for
    // `lower` to set.
    /// Go to the target.
    Jump,
    /// Go to the target when `c` is 0 (`zero`) or not.
    JumpZeroI { c: Local, zero: bool },
    /// [`Ir::JumpZeroI`] of a real.
    JumpZeroR { c: Local, zero: bool },
    /// Go to the target when `a cmp b`.
    JumpCmpI { cmp: Cmp, a: Local, b: Local },
    /// Go to the target when `(a cmp b) == want`, of reals (a comparison with NaN is false).
    JumpCmpR {
        cmp: Cmp,
        want: bool,
        a: Local,
        b: Local,
    },
    /// `d` = the subscript `s` (an `Int`), which must be within `0..len`.
    IdxI { d: Local, s: Local, len: u32 },
    /// `d` = the subscript `s` (a real) rounded, halves to even, within `0..len`.
    IdxR { d: Local, s: Local, len: u32 },
    /// `d` = element `off` of array `arr` (of the body's), whole: an `Int`.
    LoadI { d: Local, off: Local, arr: u8 },
    /// `d` = element `off` of array `arr`, a real.
    LoadR { d: Local, off: Local, arr: u8 },
    /// The `Int` `s` into element `off` of array `arr`, when it fits `w` (if any).
    PutI {
        s: Local,
        off: Local,
        arr: u8,
        w: Option<Width>,
    },
    /// The real `s` into element `off` of array `arr`.
    PutR { s: Local, off: Local, arr: u8 },
    /// The `loop` of a loop inside the body: back to the target, where the interpreter
    /// tests its budget.
    Back,
    /// The interpreter's budget test after the `GOSUB` or the `RETURN` of a subroutine run
    /// inside the body.
    Yield,
    /// The `for.check` of a `FOR` inside the body, on `Int`s: to the target when `var` is
    /// past `limit` in the direction of `step` (a step of 0 is the interpreter's fault).
    ForCheckI {
        var: Local,
        limit: Local,
        step: Local,
    },
    /// Its `for.next`: `var += step` within `w`; then the [`Ir::Back`] after it goes back to
    /// the target unless `var` is past `limit` (then the instruction after that goes on).
    ForNextI {
        var: Local,
        limit: Local,
        step: Local,
        w: Width,
    },
    /// `d` = whether the strings whose handles are the reals `a` and `b` compare as `cmp`.
    TextCmp {
        cmp: Cmp,
        d: Local,
        a: Local,
        b: Local,
    },
    /// The string whose handle is the real `s` into the cell whose handle is the real `cell`.
    TextSet { cell: Local, s: Local },
    /// The string whose handle is the real `s` into element `off` of the string array `arr`.
    TextPut { s: Local, off: Local, arr: u8 },
    /// The end of the body: the loop's `for.next`, or its `loop` going back.
    Next,
    /// Out of the loop: the instruction after its end.
    Exit,
}

/// What a [`Micro`] does. The integer families come in six forms: `I` on two registers,
/// `K` on a register and the constant `k`, `L` and `KL` the same stored into the long `d`
/// (an iteration whose result does not fit 32 bits is left undone), `S` and `KS` into the
/// INTEGER `d` (16 bits); `d` may be a temporary checked in place (`chk.long`, `chk.int`). Comparisons are numbered
/// as [`cmp_of`] says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
#[allow(missing_docs)]
pub enum Code {
    Mov,
    AddI,
    AddK,
    AddL,
    AddKL,
    AddS,
    AddKS,
    SubI,
    SubK,
    SubL,
    SubKL,
    SubS,
    SubKS,
    MulI,
    MulK,
    MulL,
    MulKL,
    MulS,
    MulKS,
    /// MotionBASIC `MOD`.
    ModI,
    ModK,
    ModL,
    ModKL,
    ModS,
    ModKS,
    /// MotionBASIC `\`.
    QuotI,
    QuotK,
    QuotL,
    QuotKL,
    QuotS,
    QuotKS,
    /// PowerTools `MOD`.
    RemI,
    RemK,
    RemL,
    RemKL,
    RemS,
    RemKS,
    AndI,
    AndK,
    AndL,
    AndKL,
    AndS,
    AndKS,
    OrI,
    OrK,
    OrL,
    OrKL,
    OrS,
    OrKS,
    XorI,
    XorK,
    XorL,
    XorKL,
    XorS,
    XorKS,
    NegI,
    BitNotI,
    NotI,
    /// `d = (a cmp b)`, `k` the comparison.
    CmpI,
    /// `d` = the `Int`s `a / b` divided as reals and stored into a fixed-point slot without
    /// decimals (rounded, within 32 bits); a divisor of 0 or a quotient that does not fit
    /// leaves the iteration (the interpreter's fault).
    DivFixedI,
    /// `d` = the `Int` `a` plus the quotient of the `Int` `b` by the constant `k`, as reals,
    /// stored so (`Q = Q + A / 3`).
    AddDivFixedI,
    /// The same less the quotient (`Q = Q - A / 3`).
    SubDivFixedI,
    /// `d = a` when it fits 32 bits (`k` 0) or 16 (`k` 1).
    FitI,
    AddR,
    SubR,
    MulR,
    DivR,
    NegR,
    RemR,
    /// An integer operator of reals, `k` its number in [`INT_OPS`].
    IntR,
    BitNotR,
    CmpR,
    NotR,
    ToR,
    /// `d = a` as a real; a zero leaves the iteration (`k` 0) or takes the sign of the integer
    /// `b` (`k` 1).
    ToRSigned,
    /// `d = a` of an `Int` that may stand for -0 (`Ir::IntSigned`, `k` 0; `Ir::IntModSign`,
    /// `k` 1, `b` the dividend).
    IntSigned,
    LongR,
    ShortR,
    /// `k` the decimals.
    FixedR,
    RealR,
    /// `a` fits 32 bits (`k` 0) or 16 (`k` 1).
    CheckR,
    /// Go to `k & 0xffff`, not counting the `k >> 16` instructions of the interpreter's it
    /// skips (so every jump).
    Jump,
    /// Go to `k` when `a` is 0 (`z`) or not (`nz`).
    JzI,
    JnzI,
    JzR,
    JnzR,
    /// Go to `k` when `a cmp b`.
    JeqI,
    JneI,
    JltI,
    JleI,
    JgtI,
    JgeI,
    /// Go to `k` when `(a cmp b) == want`, `d` being `cmp * 2 + want`.
    JcmpR,
    /// `d` = the `Int` subscript `a`, within `0..k`.
    IdxI,
    /// `d` = the real subscript `a` rounded (halves to even), within `0..k`.
    IdxR,
    /// `d` = the offset of element (`a`, `b`) of a two-subscript array whose lengths are
    /// `k & 0xffff` and `k >> 16` (each `Int` subscript within its own).
    Idx2,
    /// Back to `k & 0xffff` (the `loop` of a loop inside the body), counting again the
    /// `-(k >> 16)` instructions of the interpreter's it goes back over; the run stops there
    /// when the budget is spent, as the interpreter does, the `a + 256 * b` instructions of
    /// the body from there on not run.
    Back,
    /// The `for.check` of a `FOR` inside the body: to `k` (as [`Code::Jump`]) when the `Int`
    /// `a` is past `b` in the direction of the step `d`; a step of 0 leaves the iteration.
    ForCheckI,
    /// Its `for.next`, the variable a long: `d += b` (leaving the iteration when the sum does
    /// not fit), then on to the [`Code::Back`] after it, or past it when `d` is past `a`.
    ForNextL,
    /// [`Code::ForNextL`] of an INTEGER variable.
    ForNextS,
    /// `d` = whether the strings whose handles are the reals `a` and `b` compare as
    /// [`cmp_of`] `k` says; a handle that is none leaves the iteration.
    TextCmp,
    /// The string whose handle is the real `b` copied into the cell whose handle is the real
    /// `a` (a variable's own, not the empty string's).
    TextSet,
    /// The string whose handle is the real `a` copied into element `b` of the body's string
    /// array `d` (into the cell whose handle that element holds).
    TextPut,
    /// `d` = element `a` of the body's array `b` (`Body::arrays`), whole.
    LoadI,
    /// `d` = element `a` of the body's array `b`, a real.
    LoadR,
    /// The `Int` `a` into element `b` of the body's array `d`, when it fits a long (`k` 1) or
    /// an INTEGER (`k` 2).
    PutI,
    /// The real `a` into element `b` of the body's array `d`.
    PutR,
    /// The interpreter's test of its budget after a `GOSUB` or a `RETURN` of a subroutine
    /// run inside the body ([`Body::subs`]): a run whose budget is spent there stops at the
    /// instruction after it, `a | b << 8` of the body's instructions before the iteration's
    /// end.
    Yield,
    /// The end of the body (of the iteration, from a jump to it: not counting `k >> 16` of
    /// the interpreter's instructions).
    Next,
    /// Out of the loop (from a jump to it: not counting `k >> 16` of the interpreter's
    /// instructions).
    Exit,
}

impl Code {
    /// Whether it is real arithmetic, a conversion or a real store.
    pub fn real(self) -> bool {
        matches!(
            self,
            Code::AddR
                | Code::SubR
                | Code::MulR
                | Code::DivR
                | Code::NegR
                | Code::RemR
                | Code::IntR
                | Code::BitNotR
                | Code::CmpR
                | Code::NotR
                | Code::ToR
                | Code::ToRSigned
                | Code::LongR
                | Code::ShortR
                | Code::FixedR
                | Code::RealR
                | Code::CheckR
                | Code::JzR
                | Code::JnzR
                | Code::JcmpR
                | Code::IdxR
                | Code::LoadR
                | Code::PutR
        )
    }

    /// Whether it is integer arithmetic, an integer store or comparison.
    pub fn integer(self) -> bool {
        (self as u8) >= (Code::AddI as u8) && (self as u8) <= (Code::FitI as u8)
            || matches!(
                self,
                Code::JzI | Code::JnzI | Code::JeqI | Code::JneI | Code::JltI | Code::JleI
            )
            || matches!(
                self,
                Code::JgtI | Code::JgeI | Code::IdxI | Code::Idx2 | Code::LoadI | Code::PutI
            )
            || matches!(
                self,
                Code::ForCheckI | Code::ForNextL | Code::ForNextS | Code::IntSigned
            )
    }

    /// Whether `k` is a jump's target.
    pub fn jumps(self) -> bool {
        matches!(
            self,
            Code::Jump
                | Code::JzI
                | Code::JnzI
                | Code::JzR
                | Code::JnzR
                | Code::JeqI
                | Code::JneI
                | Code::JltI
                | Code::JleI
                | Code::JgtI
                | Code::JgeI
                | Code::JcmpR
                | Code::Back
                | Code::ForCheckI
        )
    }
}

/// One instruction of a translated body, on local registers: 8 bytes, the fields in the
/// same place for every code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Micro {
    /// What it does.
    pub code: Code,
    /// The local written (or a small operand, as [`Code`] says).
    pub d: Local,
    /// The first operand.
    pub a: Local,
    /// The second operand.
    pub b: Local,
    /// A constant, a jump's target, or a small operand, as [`Code`] says.
    pub k: i32,
}

const _: () = assert!(std::mem::size_of::<Micro>() == 8);

/// A `FOR` loop's variable, limit and step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Counter {
    /// The loop variable's local (`Int`) and register.
    pub var: (Local, Reg),
    /// The limit's register (the step's is the one after it).
    pub limit: Reg,
    /// The loop variable is a MotionBASIC INTEGER (16 bits); else 32 bits.
    pub short: bool,
}

/// A loop's body translated for `vm::body`.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// The instructions, ending with [`Ir::Next`] (and [`Ir::Exit`] after it when a jump
    /// leaves the loop); every jump's target is one of them
    /// (the only way to make a `Body` is [`find`], which makes sure of both).
    ops: Vec<Micro>,
    /// How many local registers they use.
    pub locals: usize,
    /// The registers read before they are written, loaded on entry: value register, local,
    /// kind.
    pub ins: Vec<(Reg, Local, Kind)>,
    /// Per instruction, the body's instruction it comes from (counted from the body's start;
    /// a fused store's from its operator's): where the interpreter takes over an iteration
    /// left there.
    pub op_of: Vec<u16>,
    /// Per instruction of the body, the temporaries it reads that an earlier one wrote: their
    /// registers, locals and kinds, given to the interpreter taking over there.
    pub live: Vec<Vec<(Reg, Local, Kind)>>,
    /// An iteration left unfinished is left undone from its start (its variables kept at
    /// each start), because a temporary could be a -0 the interpreter reads: otherwise the
    /// interpreter goes on from the instruction it was left at.
    pub snapshot: bool,
    /// The locals holding constants that instructions carry (`K` forms), with their values:
    /// checked on entry to be what the registers hold.
    pub consts: Vec<(Local, i64)>,
    /// The variables written, stored back on leaving (temporaries are dead by then).
    pub outs: Vec<(Reg, Local, Kind)>,
    /// The locals an iteration left undone must give back as they were at its start.
    pub kept: Vec<Local>,
    /// The arrays whose elements it reads or writes (in `vals`, not in locals): the
    /// register of the first element, and how many there are; every instruction reaching an
    /// element names one of them ([`Body::arrays`]).
    arrays: Vec<(Reg, u32)>,
    /// A `FOR`'s variable, limit and step; none for a loop that goes round by a `loop`.
    pub counter: Option<Counter>,
    /// The body's first instruction: a `FOR`'s after its `for.check`, a `WHILE`'s the first
    /// of its condition.
    pub start: u32,
    /// The interpreter's instructions of an iteration that jumps nowhere: the body's and the
    /// `for.next` or `loop`.
    pub count: u64,
    /// The lowest register written (a write below the trace's limit is traced: then the
    /// interpreter runs the loop).
    pub lowest_write: Reg,
    /// The highest register read or written.
    pub highest: Reg,
    /// The instruction after the loop.
    pub after: u32,
    /// It holds loops ([`Code::Back`], [`Code::ForCheckI`], [`Code::ForNextL`],
    /// [`Code::ForNextS`]): the runner's second copy runs it.
    pub nested: bool,
    /// It holds strings ([`Code::TextCmp`], [`Code::TextSet`]): the runner's third copy runs
    /// it.
    pub text: bool,
    /// The same body with every SINGLE and DOUBLE a real: the one to run when this one, which
    /// keeps some of them as `Int`s, cannot start (one holds a fraction on entry).
    pub fallback: Option<Box<Body>>,
    /// The subroutines it runs inside, after their `GOSUB`s (none: its instructions are the
    /// interpreter's from `start` on).
    pub subs: Vec<Sub>,
}

impl Body {
    /// Where the interpreter goes on from the body's instruction `at` (counted from its
    /// start): the instruction of the frame running the loop, and when `at` is in a
    /// subroutine run inside, the subroutine's instruction and the chunk of the program it
    /// is when a `Call Program` calls it (in a frame of its own above the loop's, which goes
    /// on after the call).
    pub fn place(&self, at: u16) -> (u32, Option<(u32, Option<usize>)>) {
        let k = usize::from(at);
        if let Some(s) = self.subs.iter().find(|s| (s.from..=s.to).contains(&k)) {
            let callee = s.call.map(|c| c.1);
            return (s.gosub + 1, Some((s.pc + (k - s.from) as u32, callee)));
        }
        let inside: usize = self
            .subs
            .iter()
            .filter(|s| s.to < k)
            .map(|s| s.to + 1 - s.from)
            .sum();
        (self.start + (k - inside) as u32, None)
    }

    /// The instructions, ending with [`Code::Next`] (then [`Code::Exit`] when a jump leaves
    /// the loop), every jump's target among them.
    pub fn ops(&self) -> &[Micro] {
        &self.ops
    }

    /// The arrays whose elements it reads or writes: the register of each one's first
    /// element, and how many there are. Every instruction reaching an element (`LoadI`,
    /// `LoadR`, `PutI`, `PutR`) names one of them by its place here.
    pub fn arrays(&self) -> &[(Reg, u32)] {
        &self.arrays
    }
}

/// The most local registers a body may use.
const MOST_LOCALS: usize = 256;

/// The largest magnitude an `Int` holds: past it an `f64` is no longer exact.
pub const EXACT: i64 = 1 << 53;

/// Every loop of the unfused `ops` (with their [`SURE`] flags `sure`) whose body [`translate`]
/// can translate, by the instruction that enters it: a `FOR`'s `for.check`, or the `loop`
/// going back to the start of a `WHILE` (or of any loop a backward jump makes).
pub fn find<'a>(
    code: Unfused<'a>,
    called: &dyn Fn(u32) -> Option<(usize, Unfused<'a>)>,
    temps: &Range<Reg>,
    whole: &dyn Fn(Reg) -> bool,
    constant: &dyn Fn(Reg) -> Option<f64>,
) -> BTreeMap<u32, Body> {
    let mut bodies = BTreeMap::new();
    for (i, op) in code.ops.iter().enumerate() {
        let entry = i as u32;
        let at = match *op {
            Op::ForCheck { var, limit, exit } => Loop {
                start: entry + 1,
                next: exit.wrapping_sub(1),
                counter: Some((var, limit)),
            },
            Op::Loop { target } if target < entry => Loop {
                start: target,
                next: entry,
                counter: None,
            },
            _ => continue,
        };
        // Real variables given only whole numbers kept as `Int`s, or not: the first where it
        // differs, the second to fall back on.
        let kept = translate(code, called, at, temps, whole, constant, true);
        let plain = translate(code, called, at, temps, whole, constant, false);
        let body = match (kept, plain) {
            (Some(mut k), Some(p)) if k != p => {
                k.fallback = Some(Box::new(p));
                k
            }
            (_, Some(p)) => p,
            (Some(k), None) => k,
            (None, None) => continue,
        };
        bodies.insert(entry, body);
    }
    bodies
}

/// Where a run of a body of `bodies` may start other than at an iteration's start from the
/// instruction entering it: at the start of a loop inside (where a run whose budget is spent
/// there stops), and at a `WHILE`'s start (where the interpreter yields at its `loop`). By
/// instruction: the instruction entering the loop, and the body's instruction. Of bodies
/// holding the same instruction, the outermost takes it.
pub fn heads(bodies: &BTreeMap<u32, Body>) -> BTreeMap<u32, (u32, u16)> {
    let mut heads: BTreeMap<u32, (u32, u16, u32)> = BTreeMap::new();
    for (&entry, b) in bodies {
        let span = b.after.saturating_sub(b.start);
        let inside = b
            .ops()
            .iter()
            .filter(|m| m.code == Code::Back)
            .filter_map(|m| b.op_of.get((m.k & 0xffff) as usize).copied());
        let own = b.counter.is_none().then_some(0);
        for at in inside.chain(own) {
            let pc = b.place(at).0;
            if heads.get(&pc).is_none_or(|h| h.2 < span) {
                heads.insert(pc, (entry, at, span));
            }
        }
    }
    heads
        .into_iter()
        .map(|(pc, (entry, at, _))| (pc, (entry, at)))
        .collect()
}

/// Make each instruction of the fused `ops` entering a loop of `bodies` the one that leaves
/// the loop to the machine: a `for.check` an [`Op::ForTight`], a `loop` an [`Op::LoopTight`].
pub fn mark(ops: &mut [Op], bodies: &BTreeMap<u32, Body>) {
    for (&entry, body) in bodies {
        let Some(op) = ops.get_mut(entry as usize) else {
            continue;
        };
        match *op {
            Op::ForCheck { var, limit, exit } if body.counter.is_some() => {
                *op = Op::ForTight {
                    var,
                    limit,
                    exit,
                    kept: false,
                };
            }
            Op::Loop { target } if body.counter.is_none() && target == body.start => {
                *op = Op::LoopTight { target };
            }
            _ => {}
        }
    }
}

/// A loop's body, and a `FOR`'s counter.
#[derive(Debug, Clone, Copy)]
struct Loop {
    /// The body's first instruction (a `WHILE`'s condition is in its body).
    start: u32,
    /// Its last: the `for.next`, or the `loop`.
    next: u32,
    /// A `FOR`'s variable and limit (the step in the register after it).
    counter: Option<(Reg, Reg)>,
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
    /// A subscript: `s` rounded (halves to even), which must be within `0..len`.
    Sub {
        d: Reg,
        s: Reg,
        len: u32,
    },
    /// `d` = element `off` of the array `arr` (whole: `int`).
    Load {
        d: Reg,
        arr: Array,
        off: Reg,
        int: bool,
    },
    /// `s` stored into element `off` of the array `arr` as `to` says.
    Put {
        arr: Array,
        off: Reg,
        s: Reg,
        to: Store,
    },
    /// The `loop` of a loop inside the body: back to `t`.
    Back {
        t: u32,
    },
    /// The `GOSUB` of a subroutine run inside the body, or its `RETURN`: the interpreter's
    /// budget test.
    Yield,
    /// `d` = whether the strings whose handles are in `a` and `b` compare as `cmp` says.
    TextCmp {
        cmp: Cmp,
        d: Reg,
        a: Reg,
        b: Reg,
    },
    /// The string whose handle is in `s` copied into the string variable whose register is
    /// `cell` (holding its handle, which stays).
    TextSet {
        cell: Reg,
        s: Reg,
    },
    /// The string whose handle is in `s` copied into element `off` of the string array `arr`
    /// (each element holding its cell's handle, which stays).
    TextPut {
        arr: Array,
        off: Reg,
        s: Reg,
    },
    /// The `for.check` of a `FOR` inside the body: to `t` when `var` is past `limit` (the
    /// step in the register after it).
    ForCheck {
        var: Reg,
        limit: Reg,
        t: u32,
    },
    /// Its `for.next`: `var += step` (an INTEGER when `short`), back to `t` unless past
    /// `limit`.
    ForNext {
        var: Reg,
        limit: Reg,
        t: u32,
        short: bool,
    },
}

/// An array: the register of its first element, and how many it has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Array {
    base: Reg,
    len: u32,
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

/// The steps of instruction `op` (a fused store, or a subscript an element's load or store
/// checks itself, goes through `scratch`, a register of its own; `whole`: a register holds
/// only whole numbers); `None` when the translation does not know it.
fn steps(op: Op, ext: &[ExtOp], scratch: Reg, whole: &dyn Fn(Reg) -> bool) -> Option<Vec<Step>> {
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
    let un = |op: Un, d: Reg, s: Reg| one(Step::Un { op, d, s });
    let store = |to: Store, d: Reg, s: Reg| one(Step::Store { to, d, s });
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
        Op::Move { dst, src } => un(Un::Move, dst, src),
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
        Op::Neg { dst, a } => un(Un::Neg, dst, a),
        Op::Not { dst, a } => un(Un::Not, dst, a),
        Op::BitNot { dst, a } => un(Un::BitNot, dst, a),
        Op::StoreLong { dst, src } => store(Store::Long, dst, src),
        Op::StoreInt { dst, src } => store(Store::Short, dst, src),
        Op::StoreReal { dst, src } => store(Store::Real, dst, src),
        Op::StoreFixed { dst, src, decimals } => store(Store::Fixed(decimals), dst, src),
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
        Op::Subscript { dst, src, len } => one(Step::Sub {
            d: dst,
            s: src,
            len,
        }),
        Op::LoadAt {
            dst,
            base,
            off,
            len,
        } => one(Step::Load {
            d: dst,
            arr: Array { base, len },
            off,
            int: whole(base),
        }),
        Op::LoadIdx {
            dst,
            base,
            idx,
            len,
        } => Some(vec![
            Step::Sub {
                d: scratch,
                s: idx,
                len,
            },
            Step::Load {
                d: dst,
                arr: Array { base, len },
                off: scratch,
                int: whole(base),
            },
        ]),
        Op::StoreAt {
            base,
            off,
            src,
            decimals,
            len,
        } => one(Step::Put {
            arr: Array { base, len },
            off,
            s: src,
            to: element_store(decimals)?,
        }),
        Op::StoreIdx {
            base,
            idx,
            src,
            len,
            decimals,
        } => Some(vec![
            Step::Sub {
                d: scratch,
                s: idx,
                len,
            },
            Step::Put {
                arr: Array { base, len },
                off: scratch,
                s: src,
                to: element_store(decimals)?,
            },
        ]),
        Op::Loop { target } => one(Step::Back { t: target }),
        // A string instruction of the side table counting as one.
        Op::Ext { at, copies: 0 } => match *ext.get(at as usize)? {
            ExtOp::CompareText { cmp, dst, a, b } => one(Step::TextCmp { cmp, d: dst, a, b }),
            ExtOp::StoreText { dst, src } => one(Step::TextSet { cell: dst, s: src }),
            ExtOp::StoreTextAt {
                base,
                off,
                src,
                len,
            } => one(Step::TextPut {
                arr: Array { base, len },
                off,
                s: src,
            }),
            _ => None,
        },
        Op::ForCheck { var, limit, exit } => one(Step::ForCheck {
            var,
            limit,
            t: exit,
        }),
        Op::ForNext {
            var,
            limit,
            body,
            decimals,
        } => one(Step::ForNext {
            var,
            limit,
            t: body,
            short: match decimals {
                0 => false,
                INT_STORE => true,
                _ => return None,
            },
        }),
        _ => None,
    }
}

/// How an element store of `decimals` stores: a MotionBASIC array's elements are longs,
/// INTEGERs or reals.
fn element_store(decimals: u8) -> Option<Store> {
    match decimals {
        0 => Some(Store::Long),
        INT_STORE => Some(Store::Short),
        REAL_STORE => Some(Store::Real),
        _ => None,
    }
}

fn jump_cmp(cmp: Cmp, want: bool, a: Reg, b: Reg, t: u32) -> Step {
    Step::JumpCmp { cmp, want, a, b, t }
}

impl Step {
    fn written(&self) -> Option<Reg> {
        match *self {
            Step::Bin { d, .. }
            | Step::Un { d, .. }
            | Step::Store { d, .. }
            | Step::Sub { d, .. }
            | Step::Load { d, .. } => Some(d),
            Step::ForNext { var, .. } => Some(var),
            Step::TextCmp { d, .. } => Some(d),
            _ => None,
        }
    }

    fn read(&self) -> Vec<Reg> {
        match *self {
            Step::Bin { a, b, .. } | Step::JumpCmp { a, b, .. } => vec![a, b],
            Step::Un { s, .. } | Step::Store { s, .. } => vec![s],
            Step::Check { r, .. } => vec![r],
            Step::JumpZero { c, .. } => vec![c],
            Step::Jump { .. } | Step::Yield => vec![],
            Step::Sub { s, .. } => vec![s],
            Step::Load { off, .. } => vec![off],
            Step::Put { off, s, .. } => vec![off, s],
            Step::Back { .. } => vec![],
            Step::TextCmp { a, b, .. } => vec![a, b],
            Step::TextSet { cell, s } => vec![cell, s],
            Step::TextPut { off, s, .. } => vec![off, s],
            Step::ForCheck { var, limit, .. } | Step::ForNext { var, limit, .. } => {
                vec![var, limit, limit.wrapping_add(1)]
            }
        }
    }

    fn target(&self) -> Option<u32> {
        match *self {
            Step::Jump { t }
            | Step::JumpZero { t, .. }
            | Step::JumpCmp { t, .. }
            | Step::Back { t }
            | Step::ForCheck { t, .. }
            | Step::ForNext { t, .. } => Some(t),
            _ => None,
        }
    }

    /// Its jump's target mapped by `to`.
    fn retarget(&mut self, to: impl Fn(u32) -> u32) {
        match self {
            Step::Jump { t }
            | Step::JumpZero { t, .. }
            | Step::JumpCmp { t, .. }
            | Step::Back { t }
            | Step::ForCheck { t, .. }
            | Step::ForNext { t, .. } => *t = to(*t),
            _ => {}
        }
    }

    /// Whether its jump goes back (to the start of a loop inside the body).
    fn goes_back(&self) -> bool {
        matches!(self, Step::Back { .. } | Step::ForNext { .. })
    }
}

/// The first register number of the translation's own registers: a temporary's versions
/// and the scratch registers of fused stores.
const VIRTUAL: Reg = 1 << 31;

impl Step {
    /// This step with each register it reads mapped by `read` and the one it writes
    /// replaced by `write`.
    fn renamed(self, read: &dyn Fn(Reg) -> Reg, write: Option<Reg>) -> Step {
        let w = |d: Reg| write.unwrap_or(d);
        match self {
            Step::Bin { op, d, a, b } => Step::Bin {
                op,
                d: w(d),
                a: read(a),
                b: read(b),
            },
            Step::Un { op, d, s } => Step::Un {
                op,
                d: w(d),
                s: read(s),
            },
            Step::Store { to, d, s } => Step::Store {
                to,
                d: w(d),
                s: read(s),
            },
            Step::Check { w: width, r } => Step::Check {
                w: width,
                r: read(r),
            },
            Step::Jump { t } => Step::Jump { t },
            Step::JumpZero { c, zero, t } => Step::JumpZero {
                c: read(c),
                zero,
                t,
            },
            Step::JumpCmp { cmp, want, a, b, t } => Step::JumpCmp {
                cmp,
                want,
                a: read(a),
                b: read(b),
                t,
            },
            Step::Sub { d, s, len } => Step::Sub {
                d: w(d),
                s: read(s),
                len,
            },
            Step::Load { d, arr, off, int } => Step::Load {
                d: w(d),
                arr,
                off: read(off),
                int,
            },
            Step::Put { arr, off, s, to } => Step::Put {
                arr,
                off: read(off),
                s: read(s),
                to,
            },
            // A loop's variable, limit and step are never temporaries (`translate` refuses
            // them).
            Step::Back { .. } | Step::ForCheck { .. } | Step::ForNext { .. } | Step::Yield => self,
            Step::TextCmp { cmp, d, a, b } => Step::TextCmp {
                cmp,
                d: w(d),
                a: read(a),
                b: read(b),
            },
            Step::TextSet { cell, s } => Step::TextSet {
                cell: read(cell),
                s: read(s),
            },
            Step::TextPut { arr, off, s } => Step::TextPut {
                arr,
                off: read(off),
                s: read(s),
            },
        }
    }
}

/// Give each write of a temporary a register of its own (a version), and each read the
/// version last written before it, so that a temporary holding an integer in one statement
/// and a real in the next is an `Int` in the one and a `Real` in the other. A read that some
/// way into it reaches without passing that write (a jump over it, a loop inside going back
/// to between the two) refuses the body, and so does a read of a temporary no instruction
/// before it writes.
fn rename_temporaries(
    by_op: &mut [Vec<Step>],
    temps: &Range<Reg>,
    start: u32,
) -> Option<BTreeMap<Reg, Reg>> {
    let mut origin: BTreeMap<Reg, Reg> = BTreeMap::new();
    let mut current: BTreeMap<Reg, (Reg, usize)> = BTreeMap::new();
    let mut versions: Reg = VIRTUAL;
    // Jumps by instruction: (from, to) relative to the body's start.
    let mut jumps: Vec<(usize, usize)> = Vec::new();
    for (k, steps) in by_op.iter().enumerate() {
        for s in steps {
            if let Some(t) = s.target() {
                jumps.push((k, (t - start) as usize));
            }
        }
    }
    for (k, steps) in by_op.iter_mut().enumerate() {
        for s in steps.iter_mut() {
            let skipped = std::cell::Cell::new(false);
            let read = |r: Reg| -> Reg {
                match current.get(&r) {
                    Some(&(v, w)) if temps.contains(&r) => {
                        // A jump to past the write and up to here, from before the write or
                        // (going back) from here or after.
                        if jumps
                            .iter()
                            .any(|&(from, to)| (from < w || from >= k) && to > w && to <= k)
                        {
                            skipped.set(true);
                        }
                        v
                    }
                    None if temps.contains(&r) => {
                        skipped.set(true);
                        r
                    }
                    _ => r,
                }
            };
            let write = match s.written() {
                Some(d) if temps.contains(&d) => {
                    versions += 1;
                    Some(versions)
                }
                _ => None,
            };
            let renamed = s.renamed(&read, write);
            if skipped.get() || versions >= VIRTUAL + (1 << 30) {
                return None;
            }
            if let (Some(d), Some(v)) = (s.written(), write) {
                current.insert(d, (v, k));
                origin.insert(v, d);
            }
            *s = renamed;
        }
    }
    Some(origin)
}

/// Whether the step `s`, if it reads the integer `v`, gives something other when `v` is -0
/// than when it is 0 (a store into a long, a comparison, a bitwise operator do not; a real,
/// a copy, a product do).
fn sign_matters(s: &Step, v: Reg, kind_of: &dyn Fn(Reg) -> Known) -> bool {
    if !s.read().contains(&v) {
        return false;
    }
    // An integer that is never -0 itself.
    let plain = |r: Reg| {
        let k = kind_of(r);
        k.kind == Kind::Int && !k.signed_zero
    };
    match *s {
        Step::Bin { op, a, b, .. } => match op {
            Bin::Int(BinaryOp::BitAnd | BinaryOp::BitOr | BinaryOp::BitXor) | Bin::Cmp(_) => false,
            // -0 + x is x + 0 unless x is -0 too.
            Bin::Add => !(plain(a) || plain(b)),
            // x - -0 is x - 0 unless x is -0.
            Bin::Sub => !(b == v && a != v && plain(a)),
            _ => true,
        },
        Step::Un { op, .. } => matches!(op, Un::Move | Un::Neg),
        Step::Store { to, .. } => matches!(to, Store::Real | Store::Fixed(1..)),
        // A subscript or an offset picks the same element either way.
        Step::Put { s, to, .. } => s == v && matches!(to, Store::Real | Store::Fixed(1..)),
        Step::Check { .. }
        | Step::Jump { .. }
        | Step::JumpZero { .. }
        | Step::JumpCmp { .. }
        | Step::Sub { .. }
        | Step::Load { .. }
        | Step::Back { .. }
        | Step::Yield
        | Step::ForCheck { .. }
        | Step::ForNext { .. }
        | Step::TextCmp { .. }
        | Step::TextSet { .. }
        | Step::TextPut { .. } => false,
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
fn result(
    s: &Step,
    of: &dyn Fn(Reg) -> Known,
    constant: &dyn Fn(Reg) -> Option<f64>,
) -> Option<Known> {
    let int = |r: Reg| of(r).kind == Kind::Int;
    let positive = |r: Reg| constant(r).is_some_and(|c| c > 0.0);
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
                // A product by a positive constant is -0 only of a -0.
                Bin::Mul if ints && positive(b) => signed(of(a).signed_zero),
                Bin::Mul if ints && positive(a) => signed(of(b).signed_zero),
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
            // -x is -0 only of a +0: never of a nonzero constant.
            Un::Neg if int(s) => signed(constant(s).is_none_or(|c| c == 0.0)),
            Un::Neg => REAL,
            Un::Not | Un::BitNot => INT,
        },
        // (A real variable given only whole numbers may be an `Int`: `translate` says.)
        Step::Store { to, .. } => match to {
            Store::Long | Store::Short | Store::Fixed(0) => INT,
            Store::Real | Store::Fixed(_) => REAL,
        },
        // A subscript's sign never matters (`sign_matters`); an element is no -0 (one that
        // is leaves the iteration).
        Step::Sub { .. } => INT,
        Step::Load { int: true, .. } => INT,
        Step::Load { int: false, .. } => REAL,
        // A whole variable plus a whole step (`translate` sees that both are `Int`s).
        Step::ForNext { .. } => INT,
        Step::TextCmp { .. } => INT,
        _ => return None,
    })
}

/// The most instructions of a subroutine a body runs inside.
const MOST_INLINED: u32 = 256;

/// A program's instructions as the translation reads them: before fusion, with the side
/// table [`Op::Ext`] names (before it is specialized) and their [`SURE`] flags.
#[derive(Debug, Clone, Copy)]
pub struct Unfused<'a> {
    /// The instructions.
    pub ops: &'a [Op],
    /// The side table.
    pub ext: &'a [ExtOp],
    /// The flags, one per instruction.
    pub sure: &'a [u8],
}

/// A subroutine run inside a body (or a program it calls): the interpreter's `GOSUB` (or
/// `Call Program`) calling it, its first instruction and its `RETURN` (or `End`), and where
/// they are among the body's instructions (counted from the body's start, the call just
/// before the first).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sub {
    /// The call's instruction.
    pub gosub: u32,
    /// The subroutine's first instruction.
    pub pc: u32,
    /// The first's place among the body's instructions.
    pub from: usize,
    /// The `RETURN`'s.
    pub to: usize,
    /// A program called (`Call Program`): its number and its chunk; none for a `GOSUB`.
    pub call: Option<(u32, usize)>,
}

impl Sub {
    /// Its `RETURN`'s instruction (a program's `End`).
    fn last(&self) -> u32 {
        self.pc + (self.to - self.from) as u32
    }
}

/// The interpreter's instructions an iteration of the body of `code` from `start` to `next`
/// (its `for.next` or `loop`, not among them) runs, in order, each with the program it is of
/// (0: `code`; then those in the list given): each subroutine a `GOSUB` of it calls comes
/// after that `GOSUB`, when it lies outside the loop, reaches its `RETURN` within
/// [`MOST_INLINED`] instructions and calls none; each program a `Call Program` calls
/// (`called` gives its chunk and instructions) after that call, when it reaches its first
/// `End` so and calls none (the jumps of either are seen to go forward to that end at most
/// where they are translated). `None` when a subroutine or a program called is not one of
/// those: the interpreter runs that loop.
#[allow(clippy::type_complexity)]
fn inline<'a>(
    code: Unfused<'a>,
    called: &dyn Fn(u32) -> Option<(usize, Unfused<'a>)>,
    start: u32,
    next: u32,
) -> Option<(Vec<(usize, u32)>, Vec<Sub>, Vec<Unfused<'a>>)> {
    let mut order = Vec::new();
    let mut subs = Vec::new();
    let mut programs = vec![code];
    // The first instruction from `from` of `ops` that is none of the subroutine's, when it is
    // `end`.
    let last_of = |ops: &[Op], from: u32, end: Op| {
        let last = (from..from.saturating_add(MOST_INLINED)).find(|&p| {
            !matches!(ops.get(p as usize), Some(op) if !matches!(op,
                Op::Return | Op::Gosub { .. } | Op::End | Op::CallProgram { .. }))
        })?;
        (ops.get(last as usize) == Some(&end)).then_some(last)
    };
    for pc in start..next {
        order.push((0, pc));
        let (source, first, last, call) = match code.ops.get(pc as usize) {
            Some(&Op::Gosub { target }) => {
                let last = last_of(code.ops, target, Op::Return)?;
                if target <= next + 1 && last >= start {
                    return None;
                }
                (0, target, last, None)
            }
            Some(&Op::CallProgram { program }) => {
                let (chunk, callee) = called(program)?;
                let last = last_of(callee.ops, 0, Op::End)?;
                programs.push(callee);
                (programs.len() - 1, 0, last, Some((program, chunk)))
            }
            _ => continue,
        };
        let from = order.len();
        order.extend((first..=last).map(|p| (source, p)));
        subs.push(Sub {
            gosub: pc,
            pc: first,
            from,
            to: order.len() - 1,
            call,
        });
    }
    Some((order, subs, programs))
}

/// The body of the loop `at` translated, when every instruction of it is one the translation
/// knows, its jumps go forward within it (or to its `for.next` or `loop`, or out of the loop
/// to the instruction after that), a `FOR`'s variable is whole with a whole step (`sure`),
/// and the registers it uses fit. With `speculate`, a real variable every write of the body
/// gives a whole number is an `Int` (loaded as one: a loop entered while it holds a fraction
/// does not start); without, every real variable is a real.
#[allow(clippy::too_many_arguments)]
fn translate<'a>(
    code: Unfused<'a>,
    called: &dyn Fn(u32) -> Option<(usize, Unfused<'a>)>,
    at: Loop,
    temps: &Range<Reg>,
    whole: &dyn Fn(Reg) -> bool,
    constant: &dyn Fn(Reg) -> Option<f64>,
    speculate: bool,
) -> Option<Body> {
    let (start, next_op) = (at.start, at.next);
    // Scratch registers are numbered down from the top (`u32::MAX - i`), versions up from
    // `VIRTUAL`: they never meet.
    if next_op < start || next_op >= 1 << 27 {
        return None;
    }
    // The interpreter's instructions an iteration runs, in order: the body's, each
    // subroutine a `GOSUB` calls that can run inside ([`inline`]) after that `GOSUB`. From
    // here on an instruction is its place in that order (`start` + its index), `next` the
    // `for.next` or `loop`.
    let (order, subs, programs) = inline(code, called, start, next_op)?;
    let (ops, sure) = (code.ops, code.sure);
    let next = start + order.len() as u32;
    if next >= 1 << 28 {
        return None;
    }
    // A jump's target in that order, from the instruction at index `k`: within the body
    // (its instructions, its end, the one after it) or forward within the subroutine `k` is
    // in; `u32::MAX` (which every test refuses) anywhere else.
    let place = |t: u32, k: usize| -> u32 {
        match subs.iter().find(|s| (s.from..=s.to).contains(&k)) {
            Some(s) if t > order[k].1 && t <= s.last() => {
                start + (s.from + (t - s.pc) as usize) as u32
            }
            Some(_) => u32::MAX,
            None if (start..=next_op + 1).contains(&t) => {
                let before: usize = subs
                    .iter()
                    .filter(|s| s.gosub < t)
                    .map(|s| s.to + 1 - s.from)
                    .sum();
                t + before as u32
            }
            None => u32::MAX,
        }
    };
    // A `FOR`'s variable, limit, and whether the variable is an INTEGER.
    let counter: Option<(Reg, Reg, bool)> = match (at.counter, *ops.get(next_op as usize)?) {
        (
            Some((var, limit)),
            Op::ForNext {
                var: v,
                limit: lim,
                body,
                decimals,
            },
        ) => {
            // A real variable (`FOR I = 1 TO N` without a suffix) counts as an `Int` when it
            // holds a whole number on entry (`vm::body::run` loads it so, or leaves the loop
            // to the interpreter) and only the `for.next` writes it: a whole step (tested at
            // each entry) keeps it whole, its sum exact while it fits 32 bits (past them the
            // interpreter's `for.next` adds it).
            let sure_next = sure.get(next_op as usize).is_some_and(|f| f & SURE != 0);
            let real_var = decimals == REAL_STORE;
            if body != start || v != var || lim != limit || !(sure_next || real_var) {
                return None;
            }
            if decimals != 0 && decimals != INT_STORE && !real_var {
                return None;
            }
            Some((var, limit, decimals == INT_STORE))
        }
        (None, Op::Loop { target }) if target == start => None,
        _ => return None,
    };
    let var = counter.map(|c| c.0);
    // The registers of the limit and the step, which the body must not touch.
    let bounds = |r: Reg| counter.is_some_and(|(_, limit, _)| r == limit || r == limit + 1);
    // The body's steps, by instruction.
    let mut by_op: Vec<Vec<Step>> = Vec::new();
    for (k, &(source, pc)) in order.iter().enumerate() {
        let i = start + k as u32;
        let scratch = u32::MAX - i;
        debug_assert!(scratch >= VIRTUAL);
        let program = programs.get(source)?;
        // A `GOSUB`, its `RETURN` and a `Call Program` are the interpreter's budget tests; a
        // called program's `End` only goes back.
        let call = subs
            .iter()
            .any(|s| k + 1 == s.from || (k == s.to && s.call.is_none()));
        let end = subs.iter().any(|s| k == s.to && s.call.is_some());
        let mut s = if call {
            vec![Step::Yield]
        } else if end {
            Vec::new()
        } else {
            steps(*program.ops.get(pc as usize)?, program.ext, scratch, whole)?
        };
        for step in &mut s {
            step.retarget(|t| place(t, k));
        }
        for step in &s {
            // A loop inside goes back within the body (to an instruction that is not before
            // its start); every other jump goes forward, at most out of the loop.
            match step.target() {
                Some(t) if step.goes_back() && !(start..=i).contains(&t) => return None,
                Some(t) if !step.goes_back() && (t <= i || t > next + 1) => return None,
                _ => {}
            }
            match *step {
                // A `for.next` inside adds a step known to be whole to a whole variable, as
                // the body's own does.
                Step::ForNext { .. }
                    if program.sure.get(pc as usize).is_none_or(|f| f & SURE == 0) =>
                {
                    return None
                }
                Step::ForCheck { var, limit, .. } | Step::ForNext { var, limit, .. }
                    if [var, limit, limit.wrapping_add(1)]
                        .iter()
                        .any(|r| temps.contains(r)) =>
                {
                    return None
                }
                _ => {}
            }
        }
        by_op.push(s);
    }
    let origin = rename_temporaries(&mut by_op, temps, start)?;
    let all: Vec<Step> = by_op.iter().flatten().copied().collect();
    // Temporaries, their versions and scratch registers: dead at the end of their statement.
    let scratch_reg = |r: Reg| r >= VIRTUAL;
    // The registers surely written before each instruction, whichever way control came
    // (passes in order until nothing changes: a loop inside goes back to what a pass has
    // seen). A register read where it may not have been written holds the value of the
    // iteration before or of before the loop: a variable is loaded on entry (`observed`); a
    // temporary cannot be.
    let len = by_op.len();
    let mut before: Vec<Option<Vec<Reg>>> = vec![None; len + 1];
    before[0] = Some(Vec::new());
    let meet = |slot: &mut Option<Vec<Reg>>, set: &[Reg]| -> bool {
        let now: Vec<Reg> = match slot {
            None => set.to_vec(),
            Some(old) => old.iter().copied().filter(|r| set.contains(r)).collect(),
        };
        let changed = slot.as_ref().is_none_or(|old| old.len() != now.len());
        *slot = Some(now);
        changed
    };
    let mut observed: Vec<Reg> = Vec::new();
    loop {
        let mut changed = false;
        observed.clear();
        for (k, s) in by_op.iter().enumerate() {
            let mut set = before[k].clone().unwrap_or_default();
            let mut falls = true;
            for step in s {
                for r in step.read() {
                    if !set.contains(&r) {
                        if scratch_reg(r) {
                            return None;
                        }
                        observed.push(r);
                    }
                }
                if let Some(d) = step.written() {
                    set.push(d);
                }
                // A jump out of the loop goes nowhere in it.
                if let Some(t) = step.target().filter(|&t| t <= next) {
                    changed |= meet(&mut before[(t - start) as usize], &set);
                }
                falls &= !matches!(step, Step::Jump { .. } | Step::Back { .. });
            }
            if falls {
                changed |= meet(&mut before[k + 1], &set);
            }
        }
        if !changed {
            break;
        }
    }
    // Every variable and constant the body reads or writes is loaded, and the loop variable.
    let mut ins: Vec<Reg> = var.into_iter().collect();
    for s in &all {
        for r in s.read().into_iter().chain(s.written()) {
            if !scratch_reg(r) && !ins.contains(&r) {
                ins.push(r);
            }
        }
    }
    if ins.iter().any(|&r| bounds(r)) {
        return None;
    }
    let written: Vec<Reg> = {
        let mut w: Vec<Reg> = all.iter().filter_map(Step::written).collect();
        w.sort_unstable();
        w.dedup();
        w
    };
    if written.iter().any(|&r| bounds(r)) {
        return None;
    }
    // Kinds: loaded registers as their values are; written ones as every write makes them.
    // A register the body always writes before it reads it (a `FOR`'s limit inside) is what
    // its writes make it: the value loaded is only stored back (and one that is not that kind
    // keeps the loop from starting).
    let mut known: BTreeMap<Reg, Known> = BTreeMap::new();
    for &r in &ins {
        let int =
            (whole(r) && constant(r).is_none_or(|c| c.abs() <= EXACT as f64)) || Some(r) == var;
        if !int && written.contains(&r) && !observed.contains(&r) && Some(r) != var {
            continue;
        }
        // A real variable the body writes starts as an `Int` (its writes may make it a real):
        // one that stays so is loaded as an `Int`; a loop entered while it holds anything
        // else runs the body translated without (`Body::fallback`), if there is one.
        if speculate && !int && written.contains(&r) && constant(r).is_none() {
            known.insert(r, INT);
            continue;
        }
        known.insert(r, if int { INT } else { REAL });
    }
    // Speculating, a real variable given an `Int` is an `Int` while it holds them; given one
    // that may be -0 (a `MOD`'s remainder), only when the body reads it (its sums and tests
    // stay integer), a zero that may be -0 leaving the iteration (`Ir::IntSigned`): one the
    // body only writes stays a real, which holds the zero's sign (`Ir::ToRModSign`).
    let read: Vec<Reg> = all.iter().flat_map(Step::read).collect();
    loop {
        let mut changed = false;
        for s in &all {
            let Some(d) = s.written() else { continue };
            let of = |r: Reg| known.get(&r).copied().unwrap_or(INT);
            let Some(mut k) = result(s, &of, constant) else {
                continue;
            };
            if let Step::Store {
                to: Store::Real,
                s: from,
                ..
            } = *s
            {
                let given = of(from);
                if speculate && given.kind == Kind::Int && (!given.signed_zero || read.contains(&d))
                {
                    k = INT;
                }
            }
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
    // the variable whole, an integer never a -0 it could not give back. So do the variables,
    // limits and steps of the loops inside.
    if var.is_some_and(|v| kind_of(v) != INT) {
        return None;
    }
    let inside_not_int = all.iter().any(|s| match *s {
        Step::ForCheck { var, limit, .. } | Step::ForNext { var, limit, .. } => {
            [var, limit, limit.wrapping_add(1)]
                .iter()
                .any(|&r| kind_of(r) != INT)
        }
        _ => false,
    });
    if inside_not_int {
        return None;
    }
    if written
        .iter()
        .any(|&r| !scratch_reg(r) && kind_of(r).signed_zero)
    {
        return None;
    }
    // Locals: the variables an iteration writes first (an iteration's start copies them, a
    // few at once), then the other registers, then a real copy of each integer the body only
    // reads (a constant, a variable it does not write: converted once, on entry), then two
    // for conversions.
    let mut local: BTreeMap<Reg, Local> = BTreeMap::new();
    let kept_regs: Vec<Reg> = ins
        .iter()
        .copied()
        .filter(|r| written.contains(r) || Some(*r) == var)
        .collect();
    for &r in kept_regs.iter().chain(&ins).chain(&written) {
        let n = local.len();
        local.entry(r).or_insert(n as Local);
        if local.len() > MOST_LOCALS / 2 {
            return None;
        }
    }
    let mut shadow: BTreeMap<Reg, Local> = BTreeMap::new();
    for &r in &ins {
        // The loop variable changes at each `for.next`: it has none.
        if !written.contains(&r) && Some(r) != var && kind_of(r).kind == Kind::Int {
            shadow.insert(r, (local.len() + shadow.len()) as Local);
        }
    }
    let conv_base = local.len() + shadow.len();
    if conv_base + 2 > MOST_LOCALS {
        return None;
    }
    let conv = [conv_base as Local, conv_base as Local + 1];
    let locals = conv_base + 2;
    let l = |r: Reg| local.get(&r).copied().unwrap_or(0);
    // The arrays the body reads or writes elements of, numbered.
    let mut arrays: Vec<Array> = Vec::new();
    for step in &all {
        if let Step::Load { arr, .. } | Step::Put { arr, .. } | Step::TextPut { arr, .. } = *step {
            if !arrays.contains(&arr) {
                arrays.push(arr);
            }
        }
    }
    if arrays.len() > usize::from(u8::MAX) {
        return None;
    }
    // An element the body names by its register (a constant subscript) is a copy in a local,
    // which a store through its array would not change: a body that stores through that
    // array stays with the interpreter.
    let aliased = |r: &Reg| {
        all.iter().any(|s| match *s {
            Step::Put { arr, .. } | Step::TextPut { arr, .. } => {
                (arr.base..arr.base.saturating_add(arr.len)).contains(r)
            }
            _ => false,
        })
    };
    if ins.iter().chain(&written).any(aliased) {
        return None;
    }
    let arr_of = |a: Array| arrays.iter().position(|&x| x == a).unwrap_or(0) as u8;
    let mut out: Vec<Ir> = Vec::new();
    let mut first_micro: Vec<usize> = Vec::new();
    // Jumps to patch: micro index, target instruction.
    let mut patches: Vec<(usize, u32)> = Vec::new();
    let mut skip_at: Vec<(usize, i32)> = Vec::new();
    // The body's instruction each IR instruction comes from.
    let mut ir_op: Vec<u16> = Vec::new();
    // The `Int` results of a `MOD` whose dividend is an `Int` never -0, by that dividend, while
    // it keeps its value: a zero result has the dividend's sign (`basic_mod_of`).
    let mut signs: BTreeMap<Reg, Reg> = BTreeMap::new();
    // PowerTools' `/` of two `Int`s into a whole variable (`div.f0`, or a `div` and the store
    // after it, nothing jumping to the store) is one instruction when nothing else reads the
    // quotient (a temporary): by the division's instruction, its operands, the variable, and
    // whether the store is the next instruction's.
    let targets: Vec<u32> = all.iter().filter_map(Step::target).collect();
    let read_once = |t: Reg| all.iter().filter(|x| x.read().contains(&t)).count() == 1;
    // And the quotient by a constant added to (or taken from) a whole variable stored so (a
    // `div`, then an `add.f0` or `sub.f0`): by the division's instruction, the sum's operand,
    // the quotient's dividend and divisor, the variable, and whether it is taken away.
    let sums: BTreeMap<usize, (Reg, Reg, i32, Reg, bool)> = (0..by_op.len())
        .filter_map(|k| {
            let [Step::Bin {
                op: Bin::Div,
                d: t,
                a,
                b,
            }] = *by_op[k].as_slice()
            else {
                return None;
            };
            let [Step::Bin {
                op,
                d: u,
                a: x,
                b: y,
            }, Step::Store {
                to: Store::Fixed(0),
                d,
                s,
            }] = *by_op.get(k + 1)?.as_slice()
            else {
                return None;
            };
            let (q, minus) = match op {
                Bin::Add if y == t => (x, false),
                Bin::Add if x == t => (y, false),
                Bin::Sub if y == t => (x, true),
                _ => return None,
            };
            let divisor = constant(b).filter(|c| *c != 0.0 && f64::from(*c as i32) == *c)?;
            let ints = [q, a, b].iter().all(|&r| kind_of(r).kind == Kind::Int);
            let landed = targets.contains(&(start + k as u32 + 1));
            let temps = scratch_reg(t) && scratch_reg(u) && read_once(t) && read_once(u);
            (s == u && ints && temps && !landed && q != t)
                .then_some((k, (q, a, divisor as i32, d, minus)))
        })
        .collect();
    let quotients: BTreeMap<usize, (Reg, Reg, Reg, bool)> = (0..by_op.len())
        .filter_map(|k| {
            let next_store = by_op.get(k + 1).map_or(&[][..], |s| s.as_slice());
            let (div, store, across) = match by_op[k].as_slice() {
                [div, store] => (div, store, false),
                [div] => (div, next_store.first()?, next_store.len() == 1),
                _ => return None,
            };
            let (
                &Step::Bin {
                    op: Bin::Div,
                    d: t,
                    a,
                    b,
                },
                &Step::Store {
                    to: Store::Fixed(0),
                    d,
                    s,
                },
            ) = (div, store)
            else {
                return None;
            };
            let once = read_once(t);
            let ints = kind_of(a).kind == Kind::Int && kind_of(b).kind == Kind::Int;
            let landed = across && targets.contains(&(start + k as u32 + 1));
            let shaped = across || by_op[k].len() == 2;
            (s == t && scratch_reg(t) && once && ints && shaped && !landed)
                .then_some((k, (a, b, d, across)))
        })
        .collect();
    let mut stored = false;
    for (k, s) in by_op.iter().enumerate() {
        first_micro.push(out.len());
        let i = start + k as u32;
        if std::mem::take(&mut stored) {
            // The store of the division before, done with it.
            continue;
        }
        // (A variable written forgets the remainders it held or was the dividend of.)
        if let Some(&(_, _, _, w, _)) = sums.get(&k) {
            signs.retain(|&r, &mut a| r != w && a != w);
        }
        if let Some(&(_, _, w, _)) = quotients.get(&k) {
            signs.retain(|&r, &mut a| r != w && a != w);
        }
        if let Some(&(q, a, k_, d, minus)) = sums.get(&k) {
            out.push(Ir::SumDivFixedI {
                d: l(d),
                q: l(q),
                a: l(a),
                k: k_,
                minus,
            });
            ir_op.resize(out.len(), u16::try_from(k).ok()?);
            stored = true;
            continue;
        }
        if let Some(&(a, b, d, across)) = quotients.get(&k) {
            out.push(Ir::DivFixedI {
                d: l(d),
                a: l(a),
                b: l(b),
            });
            ir_op.resize(out.len(), u16::try_from(k).ok()?);
            stored = across;
            continue;
        }
        for step in s {
            emit(
                step,
                i,
                &kind_of,
                &l,
                &shadow,
                &signs,
                conv,
                &arr_of,
                &mut out,
                &mut patches,
                &mut skip_at,
            );
            if let Some(w) = step.written() {
                signs.retain(|&r, &mut a| r != w && a != w);
            }
            if let Step::Bin {
                op: Bin::Int(BinaryOp::BasicMod),
                d,
                a,
                b,
            } = *step
            {
                if kind_of(a) == INT && kind_of(b).kind == Kind::Int && kind_of(d).kind == Kind::Int
                {
                    signs.insert(d, a);
                }
            }
        }
        ir_op.resize(out.len(), u16::try_from(k).ok()?);
    }
    let end = out.len();
    out.push(Ir::Next);
    ir_op.push(u16::try_from(by_op.len()).ok()?);
    // A jump out of the loop goes to an `Exit` after the end.
    let leaves = patches.iter().any(|&(_, t)| t == next + 1);
    if leaves {
        out.push(Ir::Exit);
        ir_op.push(u16::try_from(by_op.len()).ok()?);
    }
    // Jumps: IR instruction, target IR instruction.
    let mut jumps: Vec<(usize, usize)> = Vec::new();
    for (m, t) in patches {
        let to = if t == next {
            end
        } else if t == next + 1 {
            end + 1
        } else {
            *first_micro.get((t - start) as usize)?
        };
        jumps.push((m, to));
    }
    // Temporaries (and scratch registers) are dead once their statement is done: the compiler
    // gives each statement its own, written before they are read. They are not stored back.
    let temp_local =
        |x: Local| local.iter().any(|(&r, &lx)| lx == x && scratch_reg(r)) || conv.contains(&x);
    // Constants whose value an instruction can carry.
    let mut consts: Vec<(Local, i64)> = Vec::new();
    for &r in &ins {
        if let Some(c) = constant(r) {
            let int = kind_of(r).kind == Kind::Int;
            if int && !written.contains(&r) && f64::from(c as i32) == c {
                consts.push((l(r), c as i64));
            }
        }
    }
    let const_of = |x: Local| consts.iter().find(|c| c.0 == x).map(|c| c.1 as i32);
    let arr_len = |a: u8| arrays.get(usize::from(a)).map(|x| x.len);
    let (ops, op_of) = lower(
        &out,
        &ir_op,
        &jumps,
        &skip_at,
        &temp_local,
        &const_of,
        &arr_len,
    )?;
    // A body mostly of real arithmetic gains nothing here: its values are the interpreter's
    // `f64`s already, and the interpreter fuses its real operations in pairs (`MulAcc` …)
    // where each is one instruction here, and conversions more (bench/filter ran 1.7 times
    // slower here).
    let reals = ops.iter().filter(|m| m.code.real()).count();
    let ints = ops.iter().filter(|m| m.code.integer()).count();
    if reals > ints {
        return None;
    }
    // Nor one that takes more instructions here than the interpreter's before its fusion
    // (conversions added, fused PowerTools stores taken apart: bench/int's PowerTools
    // version, which the interpreter runs in 11 dispatches an iteration, took 21 here and
    // 1.2 times as long).
    if ops.len() - usize::from(leaves) > (next - start) as usize + 1 {
        return None;
    }
    // At each instruction, the temporaries' versions written before it and read at or after
    // it: what an iteration left at that instruction must give the interpreter.
    let mut span: BTreeMap<Reg, (usize, usize)> = BTreeMap::new();
    for (k, steps) in by_op.iter().enumerate() {
        for step in steps {
            for r in step.read() {
                if let Some(e) = span.get_mut(&r) {
                    e.1 = e.1.max(k);
                }
            }
            if let Some(d) = step.written() {
                if origin.contains_key(&d) {
                    span.insert(d, (k, k));
                }
            }
        }
    }
    let mut live: Vec<Vec<(Reg, Local, Kind)>> = vec![Vec::new(); by_op.len() + 1];
    let mut snapshot = false;
    // The instructions a run can stop at: those the body's instructions come from (the test
    // of a remainder's zero sign stops at its `MOD`, never at the store: `lower`).
    let stops: Vec<u16> = {
        let mut s = op_of.clone();
        s.push(0);
        s.sort_unstable();
        s.dedup();
        s
    };
    for (&v, &(w, last)) in &span {
        for (k, at) in live.iter_mut().enumerate() {
            if w < k && k <= last {
                let known = kind_of(v);
                // An integer that may be the interpreter's -0 cannot be given back as one:
                // when a zero's sign matters to what reads it, an iteration is left undone
                // from its start.
                let stop = u16::try_from(k).is_ok_and(|k| stops.binary_search(&k).is_ok());
                snapshot |= stop
                    && known.kind == Kind::Int
                    && known.signed_zero
                    && all.iter().any(|s| sign_matters(s, v, &kind_of));
                at.push((*origin.get(&v)?, l(v), known.kind));
            }
        }
    }
    let mut ins_l: Vec<(Reg, Local, Kind)> =
        ins.iter().map(|&r| (r, l(r), kind_of(r).kind)).collect();
    ins_l.extend(shadow.iter().map(|(&r, &x)| (r, x, Kind::Real)));
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
    kept.extend(var.map(l));
    kept.sort_unstable();
    kept.dedup();
    // They are the first locals.
    if kept.iter().enumerate().any(|(i, &k)| usize::from(k) != i) {
        return None;
    }
    // An element stored cannot be given back as it was: an iteration left undone from its
    // start would store it again.
    let stored: Vec<Reg> = all
        .iter()
        .filter_map(|s| match *s {
            Step::Put { arr, .. } | Step::TextPut { arr, .. } => Some(arr.base),
            // A string variable's text, traced as the variable.
            Step::TextSet { cell, .. } => Some(cell),
            _ => None,
        })
        .collect();
    if snapshot && !stored.is_empty() {
        return None;
    }
    // A run whose budget is spent at the start of a loop inside stops there, and may start
    // there again: the instruction going back lands on the first of the interpreter's
    // instruction it goes back to, where no temporary is live. It carries how many of the
    // body's instructions are left from there.
    let count = u64::from(next - start) + 1;
    let mut ops = ops;
    for (m, micro) in ops.iter_mut().enumerate() {
        // After a `GOSUB` or a `RETURN` inside: the instructions after it.
        if micro.code == Code::Yield {
            let at = u64::from(*op_of.get(m)?);
            [micro.a, micro.b] = u16::try_from(count.checked_sub(at + 1)?)
                .ok()?
                .to_le_bytes();
            continue;
        }
        if micro.code != Code::Back {
            continue;
        }
        let to = usize::try_from(micro.k & 0xffff).ok()?;
        let from = i64::from(*op_of.get(m)?);
        let head = from + 1 + i64::from(micro.k >> 16);
        let at = *op_of.get(to)?;
        if i64::from(at) != head || !live.get(usize::from(at))?.is_empty() {
            return None;
        }
        [micro.a, micro.b] = u16::try_from(count - u64::from(at)).ok()?.to_le_bytes();
    }
    // Every register read or written on entry, on leaving, or given to the interpreter, and
    // every element.
    let given = live.iter().flatten().map(|g| g.0);
    let regs = ins.iter().chain(&written).filter(|&&r| !scratch_reg(r));
    let elements = arrays
        .iter()
        .map(|a| a.base.checked_add(a.len.checked_sub(1)?))
        .collect::<Option<Vec<Reg>>>()?;
    let highest = regs
        .copied()
        .chain(given)
        .chain(counter.map(|(_, limit, _)| limit + 1))
        .chain(elements)
        .max()?;
    let lowest_write = outs
        .iter()
        .map(|o| o.0)
        .chain(stored)
        .chain(var)
        .min()
        .unwrap_or(Reg::MAX);
    // Every instruction reaching an element names one of the arrays (`vm::body` reaches
    // elements unchecked past that).
    let names_array = |m: &Micro| match m.code {
        Code::LoadI | Code::LoadR => usize::from(m.b) < arrays.len(),
        Code::PutI | Code::PutR | Code::TextPut => usize::from(m.d) < arrays.len(),
        _ => true,
    };
    if !ops.iter().all(names_array) {
        return None;
    }
    let nested = ops.iter().any(|m| {
        matches!(
            m.code,
            Code::Back | Code::ForCheckI | Code::ForNextL | Code::ForNextS
        )
    });
    let text = ops
        .iter()
        .any(|m| matches!(m.code, Code::TextCmp | Code::TextSet | Code::TextPut));
    Some(Body {
        ops,
        op_of,
        live,
        snapshot,
        locals,
        ins: ins_l,
        consts,
        outs,
        kept,
        arrays: arrays.iter().map(|a| (a.base, a.len)).collect(),
        counter: counter.map(|(var, limit, short)| Counter {
            var: (l(var), var),
            limit,
            short,
        }),
        start,
        count,
        lowest_write,
        highest,
        after: next_op + 1,
        nested,
        text,
        fallback: None,
        subs,
    })
}

/// The integer operators that have the four forms of [`Code`]: on two registers (`I`), on a
/// register and a constant (`K`), and each stored into a long (`L`, `KL`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Family {
    Add,
    Sub,
    Mul,
    Mod,
    Quot,
    Rem,
    And,
    Or,
    Xor,
}

impl Family {
    fn of(ir: &Ir) -> Option<(Family, Local, Local, Local)> {
        Some(match *ir {
            Ir::AddI { d, a, b } => (Family::Add, d, a, b),
            Ir::SubI { d, a, b } => (Family::Sub, d, a, b),
            Ir::MulI { d, a, b } => (Family::Mul, d, a, b),
            Ir::ModI { d, a, b } => (Family::Mod, d, a, b),
            Ir::QuotI { d, a, b } => (Family::Quot, d, a, b),
            Ir::RemI { d, a, b } => (Family::Rem, d, a, b),
            Ir::AndI { d, a, b } => (Family::And, d, a, b),
            Ir::OrI { d, a, b } => (Family::Or, d, a, b),
            Ir::XorI { d, a, b } => (Family::Xor, d, a, b),
            _ => return None,
        })
    }

    fn commutes(self) -> bool {
        matches!(
            self,
            Family::Add | Family::Mul | Family::And | Family::Or | Family::Xor
        )
    }

    /// The code of the form: `k`, a constant second operand; `width`, stored into (or
    /// checked to fit) a long or an INTEGER.
    fn code(self, k: bool, width: Option<Width>) -> Code {
        use Code::*;
        let forms = match self {
            Family::Add => [AddI, AddK, AddL, AddKL, AddS, AddKS],
            Family::Sub => [SubI, SubK, SubL, SubKL, SubS, SubKS],
            Family::Mul => [MulI, MulK, MulL, MulKL, MulS, MulKS],
            Family::Mod => [ModI, ModK, ModL, ModKL, ModS, ModKS],
            Family::Quot => [QuotI, QuotK, QuotL, QuotKL, QuotS, QuotKS],
            Family::Rem => [RemI, RemK, RemL, RemKL, RemS, RemKS],
            Family::And => [AndI, AndK, AndL, AndKL, AndS, AndKS],
            Family::Or => [OrI, OrK, OrL, OrKL, OrS, OrKS],
            Family::Xor => [XorI, XorK, XorL, XorKL, XorS, XorKS],
        };
        let w = match width {
            None => 0,
            Some(Width::Long) => 2,
            Some(Width::Short) => 4,
        };
        forms[usize::from(k) + w]
    }
}

/// The reads and the write of an IR instruction, on locals.
fn ir_regs(ir: &Ir) -> (Vec<Local>, Option<Local>) {
    match *ir {
        Ir::Mov { d, s }
        | Ir::NegI { d, s }
        | Ir::BitNotI { d, s }
        | Ir::NotI { d, s }
        | Ir::FitI { d, s, .. }
        | Ir::NegR { d, s }
        | Ir::BitNotR { d, s }
        | Ir::NotR { d, s }
        | Ir::ToR { d, s }
        | Ir::ToRSigned { d, s }
        | Ir::IntSigned { d, s }
        | Ir::LongR { d, s }
        | Ir::ShortR { d, s }
        | Ir::FixedR { d, s, .. }
        | Ir::RealR { d, s } => (vec![s], Some(d)),
        Ir::ToRModSign { d, s: a, sign: b }
        | Ir::IntModSign { d, s: a, sign: b }
        | Ir::DivFixedI { d, a, b }
        | Ir::SumDivFixedI { d, q: a, a: b, .. }
        | Ir::AddI { d, a, b }
        | Ir::SubI { d, a, b }
        | Ir::MulI { d, a, b }
        | Ir::ModI { d, a, b }
        | Ir::QuotI { d, a, b }
        | Ir::RemI { d, a, b }
        | Ir::AndI { d, a, b }
        | Ir::OrI { d, a, b }
        | Ir::XorI { d, a, b }
        | Ir::CmpI { d, a, b, .. }
        | Ir::AddR { d, a, b }
        | Ir::SubR { d, a, b }
        | Ir::MulR { d, a, b }
        | Ir::DivR { d, a, b }
        | Ir::RemR { d, a, b }
        | Ir::IntR { d, a, b, .. }
        | Ir::CmpR { d, a, b, .. } => (vec![a, b], Some(d)),
        Ir::CheckR { s, .. } => (vec![s], None),
        Ir::JumpZeroI { c, .. } | Ir::JumpZeroR { c, .. } => (vec![c], None),
        Ir::JumpCmpI { a, b, .. } | Ir::JumpCmpR { a, b, .. } => (vec![a, b], None),
        Ir::IdxI { d, s, .. } | Ir::IdxR { d, s, .. } => (vec![s], Some(d)),
        Ir::LoadI { d, off, .. } | Ir::LoadR { d, off, .. } => (vec![off], Some(d)),
        Ir::PutI { s, off, .. } | Ir::PutR { s, off, .. } => (vec![s, off], None),
        Ir::ForCheckI { var, limit, step } => (vec![var, limit, step], None),
        Ir::TextCmp { d, a, b, .. } => (vec![a, b], Some(d)),
        Ir::TextSet { cell, s } => (vec![cell, s], None),
        Ir::TextPut { s, off, .. } => (vec![s, off], None),
        Ir::ForNextI {
            var, limit, step, ..
        } => (vec![var, limit, step], Some(var)),
        Ir::Jump | Ir::Back | Ir::Yield | Ir::Next | Ir::Exit => (vec![], None),
    }
}

/// Whether the temporary `t` is read by none of the IR instructions after `after` before one
/// writes it again, whichever way control goes (forward, or back into a loop inside; the
/// iteration's end ends the search: a temporary is dead once its statement is done).
fn dead_after(ir: &[Ir], jumps: &[(usize, usize)], t: Local, after: usize) -> bool {
    let mut seen = vec![false; ir.len()];
    let mut ways = vec![after + 1];
    while let Some(j) = ways.pop() {
        let Some(op) = ir.get(j) else { continue };
        if std::mem::replace(&mut seen[j], true) {
            continue;
        }
        let (reads, write) = ir_regs(op);
        if reads.contains(&t) {
            return false;
        }
        if write == Some(t) {
            continue;
        }
        if !matches!(op, Ir::Jump | Ir::Back | Ir::Next | Ir::Exit) {
            ways.push(j + 1);
        }
        // A `for.next` done goes on past its `Back`.
        if matches!(op, Ir::ForNextI { .. }) {
            ways.push(j + 2);
        }
        ways.extend(jumps.iter().filter(|w| w.0 == j).map(|w| w.1));
    }
    true
}

/// Pack the IR instructions `ir` (whose jumps `jumps` give, as IR indices, and skip what
/// `skip_at` says) into [`Micro`]s: an integer operator whose second operand is a constant
/// carries it (`K`), and one whose temporary a long's store takes at once stores into the
/// long itself (`L`), the store gone (not when a jump goes to the store).
fn lower(
    ir: &[Ir],
    ir_op: &[u16],
    jumps: &[(usize, usize)],
    skip_at: &[(usize, i32)],
    temp_local: &dyn Fn(Local) -> bool,
    const_of: &dyn Fn(Local) -> Option<i32>,
    arr_len: &dyn Fn(u8) -> Option<u32>,
) -> Option<(Vec<Micro>, Vec<u16>)> {
    let targets: Vec<usize> = jumps.iter().map(|j| j.1).collect();
    let mut out: Vec<Micro> = Vec::new();
    let mut op_of: Vec<u16> = Vec::new();
    let mut index = vec![0usize; ir.len() + 1];
    let mut k = 0;
    while k < ir.len() {
        index[k] = out.len();
        let op = &ir[k];
        // An integer subscript that only picks the element of the one-subscript array the
        // next instruction loads or stores: that instruction's test of its offset against
        // the array's length is the subscript's (`load.idx`, `store.idx`).
        // The offset of an element of a two-subscript array: both subscripts checked, the
        // first times the second's length plus the second, in one instruction when its
        // temporaries are read nowhere else.
        if let Some(m) = offset2(ir, k, jumps, &targets, temp_local, const_of) {
            op_of.push(*ir_op.get(k)?);
            out.push(m);
            let at = out.len() - 1;
            index.get_mut(k + 1..k + 4)?.fill(at);
            k += 4;
            continue;
        }
        if let Ir::IdxI { d: t, s: idx, len } = *op {
            let next = ir.get(k + 1).copied();
            let picks = |off: Local, arr: u8| {
                off == t
                    && arr_len(arr) == Some(len)
                    && !targets.contains(&(k + 1))
                    && temp_local(t)
                    && dead_after(ir, jumps, t, k + 1)
            };
            let fused = match next {
                Some(Ir::LoadI { d, off, arr }) if picks(off, arr) => {
                    Some(Ir::LoadI { d, off: idx, arr })
                }
                Some(Ir::LoadR { d, off, arr }) if picks(off, arr) => {
                    Some(Ir::LoadR { d, off: idx, arr })
                }
                Some(Ir::PutI { s, off, arr, w }) if picks(off, arr) => Some(Ir::PutI {
                    s,
                    off: idx,
                    arr,
                    w,
                }),
                Some(Ir::PutR { s, off, arr }) if picks(off, arr) => {
                    Some(Ir::PutR { s, off: idx, arr })
                }
                Some(Ir::TextPut { s, off, arr }) if picks(off, arr) => {
                    Some(Ir::TextPut { s, off: idx, arr })
                }
                _ => None,
            };
            if let Some(f) = fused {
                op_of.push(*ir_op.get(k)?);
                out.push(pack(&f));
                index[k + 1] = out.len() - 1;
                k += 2;
                continue;
            }
            // A real stored into an element: its test (or its conversion) between the
            // subscript and the store, all three of one instruction (`store.idx.r`), goes
            // first, and the store takes the subscript.
            let value = match next {
                Some(Ir::RealR { d, s } | Ir::ToR { d, s }) if d != t && s != t => Some(d),
                _ => None,
            };
            let same = |j: usize| ir_op.get(j).is_some() && ir_op.get(j) == ir_op.get(k);
            if let (Some(c), Some(&Ir::PutR { s, off, arr })) = (value, ir.get(k + 2)) {
                let fused = off == t
                    && s == c
                    && arr_len(arr) == Some(len)
                    && !targets.contains(&(k + 1))
                    && !targets.contains(&(k + 2))
                    && temp_local(t)
                    && dead_after(ir, jumps, t, k + 2);
                if fused && same(k + 1) && same(k + 2) {
                    op_of.push(*ir_op.get(k + 1)?);
                    out.push(pack(ir.get(k + 1)?));
                    index[k] = out.len() - 1;
                    index[k + 1] = out.len() - 1;
                    op_of.push(*ir_op.get(k)?);
                    out.push(pack(&Ir::PutR { s, off: idx, arr }));
                    index[k + 2] = out.len() - 1;
                    k += 3;
                    continue;
                }
            }
        }
        if let Some((family, d, a, b)) = Family::of(op) {
            // The store that follows, when it takes this result into a long or an INTEGER and
            // nothing else reads the temporary; or the check of the temporary in place.
            // (Or a move of it into a real variable the body keeps as an `Int`.)
            let store = match ir.get(k + 1) {
                Some(&Ir::FitI { d: v, s, w })
                    if s == d
                        && !targets.contains(&(k + 1))
                        && (v == d || temp_local(d) && dead_after(ir, jumps, d, k + 1)) =>
                {
                    Some((v, Some(w)))
                }
                Some(&Ir::Mov { d: v, s })
                    if s == d
                        && !targets.contains(&(k + 1))
                        && temp_local(d)
                        && dead_after(ir, jumps, d, k + 1) =>
                {
                    Some((v, None))
                }
                _ => None,
            };
            let (a, b) = match (const_of(a), const_of(b)) {
                (Some(_), None) if family.commutes() => (b, a),
                _ => (a, b),
            };
            // A constant divisor of 0 or -1 stays in a register: the general way takes it.
            let k_const = const_of(b).filter(|&c| match family {
                Family::Mod | Family::Quot => c != 0 && c != -1,
                Family::Rem => c != 0,
                _ => true,
            });
            let code = family.code(k_const.is_some(), store.and_then(|s| s.1));
            op_of.push(*ir_op.get(k)?);
            out.push(Micro {
                code,
                d: store.map_or(d, |s| s.0),
                a,
                b,
                k: k_const.unwrap_or(0),
            });
            if store.is_some() {
                index[k + 1] = out.len() - 1;
                k += 2;
            } else {
                k += 1;
            }
            continue;
        }
        // The test of a zero's sign (a remainder, a product stored into a real variable the
        // body keeps as an `Int`) leaves the iteration at the instruction that gave the zero,
        // when that is one instruction of its own just before: the interpreter computes it
        // again, with its sign, rather than be given the temporary (an `Int` has no -0).
        let from = match *op {
            Ir::IntSigned { s, .. } | Ir::IntModSign { s, .. }
                if k > 0 && !targets.contains(&k) =>
            {
                let whole = |j: usize| j == 0 || ir_op.get(j - 1) != ir_op.get(j);
                let gives = ir.get(k - 1).is_some_and(|p| ir_regs(p).1 == Some(s));
                let apart = ir_op.get(k - 1) != ir_op.get(k) && whole(k - 1);
                if gives && apart {
                    ir_op.get(k - 1)
                } else {
                    ir_op.get(k)
                }
            }
            _ => ir_op.get(k),
        };
        op_of.push(*from?);
        out.push(pack(op));
        k += 1;
    }
    index[ir.len()] = out.len();
    // A jump's `k`: its target, and above it how many of the interpreter's instructions it
    // skips (uncounted when it is taken).
    let mut skip_of = vec![0i32; ir.len()];
    for &(m, n) in skip_at {
        *skip_of.get_mut(m)? = n;
    }
    for &(from, to) in jumps {
        let t = *index.get(to)?;
        let skip = i16::try_from(*skip_of.get(from)?).ok()?;
        if t > usize::from(u16::MAX) {
            return None;
        }
        out.get_mut(*index.get(from)?)?.k = t as i32 | i32::from(skip) << 16;
    }
    // A jump to the end (`ELSE` done, `END IF` at the end of the body) ends the iteration
    // itself; one out of the loop leaves it itself.
    let next_at = out.iter().position(|m| m.code == Code::Next)?;
    for m in out.iter_mut() {
        let to = (m.k & 0xffff) as usize;
        if m.code == Code::Jump && to == next_at {
            m.code = Code::Next;
        } else if m.code == Code::Jump && to > next_at {
            m.code = Code::Exit;
        }
    }
    // Every jump lands on an instruction, and the body ends with `Next` (and `Exit` after
    // it when a jump leaves the loop): neither goes on to the instruction after it.
    let len = out.len() as i32;
    let codes: Vec<Code> = out.iter().map(|m| m.code).collect();
    let ends = matches!(
        codes.as_slice(),
        [.., Code::Next] | [.., Code::Next, Code::Exit]
    );
    // A `for.next` inside goes on to the `Back` after it or past it: to an instruction.
    let for_next = |m: usize| {
        matches!(out[m].code, Code::ForNextL | Code::ForNextS)
            && (codes.get(m + 1) != Some(&Code::Back) || m + 2 >= out.len())
    };
    if !ends
        || out
            .iter()
            .any(|m| m.code.jumps() && !(0..len).contains(&(m.k & 0xffff)))
        || (0..out.len()).any(for_next)
    {
        return None;
    }
    Some((out, op_of))
}

/// The [`Code::Idx2`] standing for the IR instructions from `k`: the subscripts of an element
/// of a two-subscript array (`subscr`, `subscr`, a product by the second's length, a sum),
/// when each subscript is within 16 bits' lengths, no jump lands inside, and the temporaries
/// before the sum are read nowhere after it.
fn offset2(
    ir: &[Ir],
    k: usize,
    jumps: &[(usize, usize)],
    targets: &[usize],
    temp_local: &dyn Fn(Local) -> bool,
    const_of: &dyn Fn(Local) -> Option<i32>,
) -> Option<Micro> {
    let [Ir::IdxI {
        d: t1,
        s: s1,
        len: l1,
    }, Ir::IdxI {
        d: t2,
        s: s2,
        len: l2,
    }, Ir::MulI { d: t3, a: x, b: y }, Ir::AddI { d, a: p, b: q }] = *ir.get(k..k + 4)?
    else {
        return None;
    };
    let by_len = |c: Local| const_of(c).is_some_and(|c| i64::from(c) == i64::from(l2));
    let product = (x == t1 && by_len(y)) || (y == t1 && by_len(x));
    let sum = (p == t3 && q == t2) || (p == t2 && q == t3);
    let temps = [t1, t2, t3];
    let fits = l1 <= 0xffff && l2 <= 0xffff && l1 > 0 && l2 > 0;
    let plain = product
        && sum
        && fits
        && s2 != t1
        && t1 != t2
        && t3 != t2
        && (k + 1..k + 4).all(|j| !targets.contains(&j))
        && temps
            .iter()
            .all(|&t| t == d || (temp_local(t) && dead_after(ir, jumps, t, k + 3)));
    plain.then_some(Micro {
        code: Code::Idx2,
        d,
        a: s1,
        b: s2,
        k: (l1 | l2 << 16) as i32,
    })
}

fn cmp_index(c: Cmp) -> u8 {
    match c {
        Cmp::Eq => 0,
        Cmp::Ne => 1,
        Cmp::Lt => 2,
        Cmp::Le => 3,
        Cmp::Gt => 4,
        Cmp::Ge => 5,
    }
}

/// The comparison [`cmp_index`] numbers `i`.
pub fn cmp_of(i: u8) -> Cmp {
    [Cmp::Eq, Cmp::Ne, Cmp::Lt, Cmp::Le, Cmp::Gt, Cmp::Ge][usize::from(i % 6)]
}

/// The operators of [`Code::IntR`], by number.
pub const INT_OPS: [BinaryOp; 5] = [
    BinaryOp::BasicMod,
    BinaryOp::IntDiv,
    BinaryOp::BitAnd,
    BinaryOp::BitOr,
    BinaryOp::BitXor,
];

/// The [`Micro`] of an IR instruction outside the integer families (a jump's target is set
/// after).
fn pack(ir: &Ir) -> Micro {
    let m = |code: Code, d: Local, a: Local, b: Local, k: i32| Micro { code, d, a, b, k };
    let width = |w: Width| i32::from(w == Width::Short);
    match *ir {
        Ir::Mov { d, s } => m(Code::Mov, d, s, 0, 0),
        Ir::NegI { d, s } => m(Code::NegI, d, s, 0, 0),
        Ir::BitNotI { d, s } => m(Code::BitNotI, d, s, 0, 0),
        Ir::NotI { d, s } => m(Code::NotI, d, s, 0, 0),
        Ir::CmpI { cmp, d, a, b } => m(Code::CmpI, d, a, b, i32::from(cmp_index(cmp))),
        Ir::FitI { d, s, w } => m(Code::FitI, d, s, 0, width(w)),
        Ir::AddR { d, a, b } => m(Code::AddR, d, a, b, 0),
        Ir::SubR { d, a, b } => m(Code::SubR, d, a, b, 0),
        Ir::MulR { d, a, b } => m(Code::MulR, d, a, b, 0),
        Ir::DivR { d, a, b } => m(Code::DivR, d, a, b, 0),
        Ir::NegR { d, s } => m(Code::NegR, d, s, 0, 0),
        Ir::RemR { d, a, b } => m(Code::RemR, d, a, b, 0),
        Ir::IntR { op, d, a, b } => {
            let i = INT_OPS.iter().position(|&o| o == op).unwrap_or(0);
            m(Code::IntR, d, a, b, i as i32)
        }
        Ir::BitNotR { d, s } => m(Code::BitNotR, d, s, 0, 0),
        Ir::CmpR { cmp, d, a, b } => m(Code::CmpR, d, a, b, i32::from(cmp_index(cmp))),
        Ir::NotR { d, s } => m(Code::NotR, d, s, 0, 0),
        Ir::ToR { d, s } => m(Code::ToR, d, s, 0, 0),
        Ir::ToRSigned { d, s } => m(Code::ToRSigned, d, s, 0, 0),
        Ir::ToRModSign { d, s, sign } => m(Code::ToRSigned, d, s, sign, 1),
        Ir::IntSigned { d, s } => m(Code::IntSigned, d, s, 0, 0),
        Ir::IntModSign { d, s, sign } => m(Code::IntSigned, d, s, sign, 1),
        Ir::LongR { d, s } => m(Code::LongR, d, s, 0, 0),
        Ir::ShortR { d, s } => m(Code::ShortR, d, s, 0, 0),
        Ir::FixedR { d, s, decimals } => m(Code::FixedR, d, s, 0, i32::from(decimals)),
        Ir::DivFixedI { d, a, b } => m(Code::DivFixedI, d, a, b, 0),
        Ir::SumDivFixedI { d, q, a, k, minus } => {
            let code = if minus {
                Code::SubDivFixedI
            } else {
                Code::AddDivFixedI
            };
            m(code, d, q, a, k)
        }
        Ir::RealR { d, s } => m(Code::RealR, d, s, 0, 0),
        Ir::CheckR { s, w } => m(Code::CheckR, 0, s, 0, width(w)),
        Ir::Jump => m(Code::Jump, 0, 0, 0, 0),
        Ir::JumpZeroI { c, zero, .. } => m(if zero { Code::JzI } else { Code::JnzI }, 0, c, 0, 0),
        Ir::JumpZeroR { c, zero, .. } => m(if zero { Code::JzR } else { Code::JnzR }, 0, c, 0, 0),
        Ir::JumpCmpI { cmp, a, b, .. } => {
            let code = match cmp {
                Cmp::Eq => Code::JeqI,
                Cmp::Ne => Code::JneI,
                Cmp::Lt => Code::JltI,
                Cmp::Le => Code::JleI,
                Cmp::Gt => Code::JgtI,
                Cmp::Ge => Code::JgeI,
            };
            m(code, 0, a, b, 0)
        }
        Ir::JumpCmpR {
            cmp, want, a, b, ..
        } => m(Code::JcmpR, cmp_index(cmp) * 2 + u8::from(want), a, b, 0),
        Ir::IdxI { d, s, len } => m(Code::IdxI, d, s, 0, len as i32),
        Ir::IdxR { d, s, len } => m(Code::IdxR, d, s, 0, len as i32),
        Ir::LoadI { d, off, arr } => m(Code::LoadI, d, off, arr, 0),
        Ir::LoadR { d, off, arr } => m(Code::LoadR, d, off, arr, 0),
        Ir::PutI { s, off, arr, w } => {
            let k = match w {
                None => 0,
                Some(Width::Long) => 1,
                Some(Width::Short) => 2,
            };
            m(Code::PutI, arr, s, off, k)
        }
        Ir::PutR { s, off, arr } => m(Code::PutR, arr, s, off, 0),
        Ir::Back => m(Code::Back, 0, 0, 0, 0),
        Ir::Yield => m(Code::Yield, 0, 0, 0, 0),
        Ir::TextCmp { cmp, d, a, b } => m(Code::TextCmp, d, a, b, i32::from(cmp_index(cmp))),
        Ir::TextSet { cell, s } => m(Code::TextSet, 0, cell, s, 0),
        Ir::TextPut { s, off, arr } => m(Code::TextPut, arr, s, off, 0),
        Ir::ForCheckI { var, limit, step } => m(Code::ForCheckI, step, var, limit, 0),
        Ir::ForNextI {
            var,
            limit,
            step,
            w,
        } => {
            let code = match w {
                Width::Long => Code::ForNextL,
                Width::Short => Code::ForNextS,
            };
            m(code, var, limit, step, 0)
        }
        Ir::Next => m(Code::Next, 0, 0, 0, 0),
        Ir::Exit => m(Code::Exit, 0, 0, 0, 0),
        // The families go through `Family` first; this is their form on registers.
        Ir::AddI { d, a, b } => m(Code::AddI, d, a, b, 0),
        Ir::SubI { d, a, b } => m(Code::SubI, d, a, b, 0),
        Ir::MulI { d, a, b } => m(Code::MulI, d, a, b, 0),
        Ir::ModI { d, a, b } => m(Code::ModI, d, a, b, 0),
        Ir::QuotI { d, a, b } => m(Code::QuotI, d, a, b, 0),
        Ir::RemI { d, a, b } => m(Code::RemI, d, a, b, 0),
        Ir::AndI { d, a, b } => m(Code::AndI, d, a, b, 0),
        Ir::OrI { d, a, b } => m(Code::OrI, d, a, b, 0),
        Ir::XorI { d, a, b } => m(Code::XorI, d, a, b, 0),
    }
}

/// Emit the micro-instructions of `step` (of instruction `i`), converting `Int` operands to
/// reals where a real operation reads them (into the locals `conv`).
#[allow(clippy::too_many_arguments)]
fn emit(
    step: &Step,
    i: u32,
    kind_of: &dyn Fn(Reg) -> Known,
    l: &dyn Fn(Reg) -> Local,
    shadow: &BTreeMap<Reg, Local>,
    signs: &BTreeMap<Reg, Reg>,
    conv: [Local; 2],
    arr_of: &dyn Fn(Array) -> u8,
    out: &mut Vec<Ir>,
    patches: &mut Vec<(usize, u32)>,
    skips: &mut Vec<(usize, i32)>,
) {
    let int = |r: Reg| kind_of(r).kind == Kind::Int;
    // The `Int` register `r` (in local `s`) as the real `d`. A zero that may be the
    // interpreter's -0 takes the sign of the dividend of the `MOD` that gave it, where that is
    // known (`signs`); otherwise it leaves the iteration to the interpreter.
    let to_real = |d: Local, r: Reg, s: Local| -> Ir {
        if !kind_of(r).signed_zero {
            Ir::ToR { d, s }
        } else if let Some(&a) = signs.get(&r) {
            Ir::ToRModSign { d, s, sign: l(a) }
        } else {
            Ir::ToRSigned { d, s }
        }
    };
    // The register `r` as a real: itself, or converted into `conv[k]` (checked for -0 when
    // `sign` matters to what reads it).
    let real = |r: Reg, k: usize, sign: bool, out: &mut Vec<Ir>| -> Local {
        if !int(r) {
            return l(r);
        }
        if let Some(&x) = shadow.get(&r) {
            return x;
        }
        let d = conv[k];
        out.push(if sign {
            to_real(d, r, l(r))
        } else {
            Ir::ToR { d, s: l(r) }
        });
        d
    };
    // An `Int` result for `d`: straight into it, or (a real register) through `conv[0]`.
    let int_into = |d: Reg, make: &dyn Fn(Local) -> Ir, signed: bool, out: &mut Vec<Ir>| {
        if int(d) {
            out.push(make(l(d)));
        } else {
            out.push(make(conv[0]));
            out.push(if signed {
                Ir::ToRSigned {
                    d: l(d),
                    s: conv[0],
                }
            } else {
                Ir::ToR {
                    d: l(d),
                    s: conv[0],
                }
            });
        }
    };
    // How many of the interpreter's instructions a jump from `i` to `t` skips (going back,
    // minus how many it goes back over).
    let skip = |t: u32, out: &Vec<Ir>, skips: &mut Vec<(usize, i32)>| {
        skips.push((out.len(), t as i32 - i as i32 - 1));
    };
    match *step {
        Step::Bin { op, d, a, b } => {
            let ints = int(a) && int(b);
            let (la, lb) = (l(a), l(b));
            match op {
                Bin::Add | Bin::Sub | Bin::Mul if ints => {
                    // As `result` found it (a temporary's version is written once).
                    let signed = kind_of(d).signed_zero;
                    let make = |d: Local| match op {
                        Bin::Add => Ir::AddI { d, a: la, b: lb },
                        Bin::Sub => Ir::SubI { d, a: la, b: lb },
                        _ => Ir::MulI { d, a: la, b: lb },
                    };
                    int_into(d, &make, signed, out);
                }
                Bin::Rem if ints => int_into(d, &|d| Ir::RemI { d, a: la, b: lb }, false, out),
                Bin::Add | Bin::Sub | Bin::Mul | Bin::Div | Bin::Rem => {
                    let (ra, rb) = (real(a, 0, true, out), real(b, 1, true, out));
                    let d = l(d);
                    out.push(match op {
                        Bin::Add => Ir::AddR { d, a: ra, b: rb },
                        Bin::Sub => Ir::SubR { d, a: ra, b: rb },
                        Bin::Mul => Ir::MulR { d, a: ra, b: rb },
                        Bin::Div => Ir::DivR { d, a: ra, b: rb },
                        _ => Ir::RemR { d, a: ra, b: rb },
                    });
                }
                Bin::Int(bop) if ints => {
                    let make = |d: Local| match bop {
                        BinaryOp::BasicMod => Ir::ModI { d, a: la, b: lb },
                        BinaryOp::IntDiv => Ir::QuotI { d, a: la, b: lb },
                        BinaryOp::BitAnd => Ir::AndI { d, a: la, b: lb },
                        BinaryOp::BitOr => Ir::OrI { d, a: la, b: lb },
                        _ => Ir::XorI { d, a: la, b: lb },
                    };
                    if bop == BinaryOp::BasicMod && !int(d) && kind_of(a) == INT {
                        // Converted at once, the dividend at hand: a zero takes its sign.
                        out.push(make(conv[0]));
                        out.push(Ir::ToRModSign {
                            d: l(d),
                            s: conv[0],
                            sign: la,
                        });
                    } else {
                        let signed = matches!(bop, BinaryOp::BasicMod | BinaryOp::IntDiv);
                        int_into(d, &make, signed, out);
                    }
                }
                Bin::Int(bop) => {
                    let (ra, rb) = (real(a, 0, false, out), real(b, 1, false, out));
                    let signed = matches!(bop, BinaryOp::BasicMod | BinaryOp::IntDiv);
                    let make = |d: Local| Ir::IntR {
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
                    &|d| Ir::CmpI {
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
                        &|d| Ir::CmpR {
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
                Un::Move if int(s) && !int(d) => out.push(to_real(l(d), s, ls)),
                Un::Move => out.push(Ir::Mov { d: l(d), s: ls }),
                Un::Neg if int(s) => int_into(d, &|d| Ir::NegI { d, s: ls }, true, out),
                Un::Neg => out.push(Ir::NegR { d: l(d), s: ls }),
                Un::Not if int(s) => int_into(d, &|d| Ir::NotI { d, s: ls }, false, out),
                Un::Not => int_into(d, &|d| Ir::NotR { d, s: ls }, false, out),
                Un::BitNot if int(s) => int_into(d, &|d| Ir::BitNotI { d, s: ls }, false, out),
                Un::BitNot => int_into(d, &|d| Ir::BitNotR { d, s: ls }, false, out),
            }
        }
        Step::Store { to, d, s } => {
            let ls = l(s);
            match to {
                Store::Long | Store::Fixed(0) if int(s) => int_into(
                    d,
                    &|d| Ir::FitI {
                        d,
                        s: ls,
                        w: Width::Long,
                    },
                    false,
                    out,
                ),
                Store::Short if int(s) => int_into(
                    d,
                    &|d| Ir::FitI {
                        d,
                        s: ls,
                        w: Width::Short,
                    },
                    false,
                    out,
                ),
                Store::Long => int_into(d, &|d| Ir::LongR { d, s: ls }, false, out),
                Store::Short => int_into(d, &|d| Ir::ShortR { d, s: ls }, false, out),
                Store::Fixed(0) => int_into(
                    d,
                    &|d| Ir::FixedR {
                        d,
                        s: ls,
                        decimals: 0,
                    },
                    false,
                    out,
                ),
                Store::Fixed(decimals) => {
                    let rs = real(s, 0, true, out);
                    out.push(Ir::FixedR {
                        d: l(d),
                        s: rs,
                        decimals,
                    });
                }
                Store::Real if int(s) && int(d) => out.push(if !kind_of(s).signed_zero {
                    Ir::Mov { d: l(d), s: ls }
                } else if let Some(&a) = signs.get(&s) {
                    Ir::IntModSign {
                        d: l(d),
                        s: ls,
                        sign: l(a),
                    }
                } else {
                    Ir::IntSigned { d: l(d), s: ls }
                }),
                Store::Real if int(s) => out.push(to_real(l(d), s, ls)),
                Store::Real => out.push(Ir::RealR { d: l(d), s: ls }),
            }
        }
        Step::Check { w, r } => out.push(if int(r) {
            Ir::FitI {
                d: l(r),
                s: l(r),
                w,
            }
        } else {
            Ir::CheckR { s: l(r), w }
        }),
        Step::Jump { t } => {
            patches.push((out.len(), t));
            skip(t, out, skips);
            out.push(Ir::Jump);
        }
        Step::Back { t } => {
            patches.push((out.len(), t));
            skip(t, out, skips);
            out.push(Ir::Back);
        }
        Step::Yield => out.push(Ir::Yield),
        // Handles as reals (a constant's real copy is made on entry).
        Step::TextCmp { cmp, d, a, b } => {
            let (ra, rb) = (real(a, 0, false, out), real(b, 1, false, out));
            int_into(
                d,
                &|d| Ir::TextCmp {
                    cmp,
                    d,
                    a: ra,
                    b: rb,
                },
                false,
                out,
            );
        }
        Step::TextSet { cell, s } => {
            let (rc, rs) = (real(cell, 0, false, out), real(s, 1, false, out));
            out.push(Ir::TextSet { cell: rc, s: rs });
        }
        Step::TextPut { arr, off, s } => {
            let rs = real(s, 0, false, out);
            out.push(Ir::TextPut {
                s: rs,
                off: l(off),
                arr: arr_of(arr),
            });
        }
        // `translate` has seen that the variable, the limit and the step are `Int`s.
        Step::ForCheck { var, limit, t } => {
            patches.push((out.len(), t));
            skip(t, out, skips);
            out.push(Ir::ForCheckI {
                var: l(var),
                limit: l(limit),
                step: l(limit.wrapping_add(1)),
            });
        }
        Step::ForNext {
            var,
            limit,
            t,
            short,
        } => {
            out.push(Ir::ForNextI {
                var: l(var),
                limit: l(limit),
                step: l(limit.wrapping_add(1)),
                w: if short { Width::Short } else { Width::Long },
            });
            patches.push((out.len(), t));
            skip(t, out, skips);
            out.push(Ir::Back);
        }
        Step::JumpZero { c, zero, t } => {
            patches.push((out.len(), t));
            skip(t, out, skips);
            out.push(if int(c) {
                Ir::JumpZeroI { c: l(c), zero }
            } else {
                Ir::JumpZeroR { c: l(c), zero }
            });
        }
        Step::JumpCmp { cmp, want, a, b, t } => {
            let ints = int(a) && int(b);
            let m = if ints {
                let cmp = if want { cmp } else { negate(cmp) };
                Ir::JumpCmpI {
                    cmp,
                    a: l(a),
                    b: l(b),
                }
            } else {
                let (ra, rb) = (real(a, 0, false, out), real(b, 1, false, out));
                Ir::JumpCmpR {
                    cmp,
                    want,
                    a: ra,
                    b: rb,
                }
            };
            patches.push((out.len(), t));
            skip(t, out, skips);
            out.push(m);
        }
        Step::Sub { d, s, len } => {
            let ls = l(s);
            if int(s) {
                int_into(d, &|d| Ir::IdxI { d, s: ls, len }, false, out);
            } else {
                int_into(d, &|d| Ir::IdxR { d, s: ls, len }, false, out);
            }
        }
        Step::Load {
            d,
            arr,
            off,
            int: true,
        } => {
            let (off, arr) = (l(off), arr_of(arr));
            int_into(d, &|d| Ir::LoadI { d, off, arr }, false, out);
        }
        Step::Load { d, arr, off, .. } => out.push(Ir::LoadR {
            d: l(d),
            off: l(off),
            arr: arr_of(arr),
        }),
        Step::Put { arr, off, s, to } => {
            let (arr, off, ls, c) = (arr_of(arr), l(off), l(s), conv[0]);
            // The value as the store makes it, then into the element.
            let width = match to {
                Store::Long | Store::Fixed(0) => Width::Long,
                _ => Width::Short,
            };
            match to {
                Store::Long | Store::Short | Store::Fixed(0) if int(s) => out.push(Ir::PutI {
                    s: ls,
                    off,
                    arr,
                    w: Some(width),
                }),
                Store::Long | Store::Short | Store::Fixed(0) => {
                    out.push(match to {
                        Store::Long => Ir::LongR { d: c, s: ls },
                        Store::Short => Ir::ShortR { d: c, s: ls },
                        _ => Ir::FixedR {
                            d: c,
                            s: ls,
                            decimals: 0,
                        },
                    });
                    out.push(Ir::PutI {
                        s: c,
                        off,
                        arr,
                        w: None,
                    });
                }
                Store::Fixed(decimals) => {
                    let rs = real(s, 0, true, out);
                    out.push(Ir::FixedR {
                        d: c,
                        s: rs,
                        decimals,
                    });
                    out.push(Ir::PutR { s: c, off, arr });
                }
                Store::Real if int(s) => {
                    out.push(to_real(c, s, ls));
                    out.push(Ir::PutR { s: c, off, arr });
                }
                Store::Real => {
                    out.push(Ir::RealR { d: c, s: ls });
                    out.push(Ir::PutR { s: c, off, arr });
                }
            }
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
