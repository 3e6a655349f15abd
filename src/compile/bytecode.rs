//! The bytecode: register instructions over one flat value array.
//!
//! Every operand is an index into the machine's value array, laid out as
//! `[registry slots | temporaries | constants and loop limits]`. Names were resolved to slots at
//! compile time, so the VM never looks a name up.

use crate::check::functions::Func;
pub use crate::devices::command::{KernelFunc, MotionCmd, StartRef};
use crate::registry::Hook;

/// An index into the value array.
pub type Reg = u32;

/// `ForNext.decimals` for a loop variable kept as a real.
pub const REAL_STORE: u8 = u8::MAX;

/// `ForNext.decimals` (and `StoreAt.decimals`) for a MotionBASIC INTEGER (`%`): 16 bits.
pub const INT_STORE: u8 = u8::MAX - 1;

pub use crate::check::typed::{Cmp, PrintHow};

/// Arithmetic and logic operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum BinaryOp {
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Pow,
    /// Logical on ON/OFF values.
    And,
    Or,
    Xor,
    /// Bitwise on integers.
    BitAnd,
    BitOr,
    BitXor,
    /// MotionBASIC `\`: both operands rounded to integers, quotient truncated toward zero.
    IntDiv,
    /// MotionBASIC `MOD`: both operands rounded to integers first.
    BasicMod,
}

/// One instruction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Op {
    /// `dst = src`.
    Move { dst: Reg, src: Reg },
    /// `dst = a + b` (the hot arithmetic ops get their own variants).
    Add { dst: Reg, a: Reg, b: Reg },
    /// `dst = a - b`.
    Sub { dst: Reg, a: Reg, b: Reg },
    /// `dst = a * b`.
    Mul { dst: Reg, a: Reg, b: Reg },
    /// `dst = a / b` (fails on division by zero).
    Div { dst: Reg, a: Reg, b: Reg },
    /// `dst = a MOD b` (fails on zero).
    Mod { dst: Reg, a: Reg, b: Reg },
    /// `dst = a + b` stored into a fixed-point slot (an add fused with its `StoreFixed`).
    AddFixed {
        dst: Reg,
        a: Reg,
        b: Reg,
        decimals: u8,
    },
    /// `dst = a - b` stored into a fixed-point slot.
    SubFixed {
        dst: Reg,
        a: Reg,
        b: Reg,
        decimals: u8,
    },
    /// `dst = a * b` stored into a fixed-point slot.
    MulFixed {
        dst: Reg,
        a: Reg,
        b: Reg,
        decimals: u8,
    },
    /// `dst = a op b` stored straight into a fixed-point slot (an arithmetic op fused with
    /// the `StoreFixed` that followed it).
    ArithFixed {
        op: BinaryOp,
        dst: Reg,
        a: Reg,
        b: Reg,
        decimals: u8,
    },
    /// MotionBASIC `MOD`. Whole operands within 32 bits (every long) take an integer
    /// remainder; anything else is rounded first as [`BinaryOp::BasicMod`] says. Either way the
    /// result is the same: the integer path only avoids libm's `fmod` and `rint`.
    IMod { dst: Reg, a: Reg, b: Reg },
    /// MotionBASIC `\`, with the same integer path as [`Op::IMod`].
    IDiv { dst: Reg, a: Reg, b: Reg },
    /// `AND` bitwise on integers (halves of fractions rounded to even).
    BitAnd { dst: Reg, a: Reg, b: Reg },
    /// `OR` bitwise on integers.
    BitOr { dst: Reg, a: Reg, b: Reg },
    /// `XOR` bitwise on integers.
    BitXor { dst: Reg, a: Reg, b: Reg },
    // Superinstructions. The compiler emits none of them: `fuse` (at the end of compiling)
    // rewrites the first of two adjacent instructions into one that does the work of both and
    // skips the second, which stays in place (a jump to it still runs it alone). A fused
    // instruction counts as two against the budget, reports a fault in its second half at the
    // second's place, and still writes the temporary that joined them, so the program, its
    // instruction counts, its faults and its disassembly are exactly those without fusion.
    /// `add t <- a + b` then `store.l dst <- t`.
    AddLong { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `sub t <- a - b` then `store.l dst <- t`.
    SubLong { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `mul t <- a * b` then `store.l dst <- t`.
    MulLong { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `idiv t <- a \ b` (`op`: [`BinaryOp::IntDiv`]) then `store.l dst <- t` (`MOD` and the
    /// bitwise operators have superinstructions of their own: [`Op::ModLong`] …).
    IntLong {
        op: BinaryOp,
        t: Reg,
        dst: Reg,
        a: Reg,
        b: Reg,
    },
    /// `imod t <- a MOD b` then `store.l dst <- t`: whole operands within 32 bits take an
    /// integer remainder, which needs no rounding and fits a long.
    ModLong { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `band t <- a AND b` then `store.l dst <- t`: the integer result is stored after one
    /// integer range test.
    AndLong { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `bor t <- a OR b` then `store.l dst <- t`.
    OrLong { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `bxor t <- a XOR b` then `store.l dst <- t`.
    XorLong { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `add t <- a + b` then `store.i dst <- t` (an INTEGER, `%`).
    AddInt { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `sub t <- a - b` then `store.i dst <- t`.
    SubInt { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `mul t <- a * b` then `store.i dst <- t`.
    MulInt { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// An integer operator (`op`: `imod`, `idiv`, `band`, `bor`, `bxor`) `t <- a op b`, then
    /// `store.i dst <- t`.
    IntInt {
        op: BinaryOp,
        t: Reg,
        dst: Reg,
        a: Reg,
        b: Reg,
    },
    /// `mul t <- a * b` then `add t <- t + c` or `c + t` (no fused multiply-add: the product is
    /// rounded first, as the two instructions round it).
    MulAdd { t: Reg, a: Reg, b: Reg, c: Reg },
    /// `mul p <- a * b` then `add acc <- acc + p` (or `p + acc`): the next term of a sum of
    /// products, as a filter or a dot product writes it. The product is rounded first, as the
    /// two instructions round it; IEEE addition is commutative, so either order is one result.
    MulAcc { p: Reg, a: Reg, b: Reg, acc: Reg },
    /// `mul p <- a * b` then `sub acc <- acc - p`.
    MulDec { p: Reg, a: Reg, b: Reg, acc: Reg },
    // Two additions or subtractions in a row through the temporary `t` (`a + b - c` …): the
    // first into `t`, then `t` with `c` into `t` (for an add, `c + t` is `t + c`).
    /// `add t <- a + b` then `add t <- t + c`.
    AddAdd { t: Reg, a: Reg, b: Reg, c: Reg },
    /// `add t <- a + b` then `sub t <- t - c`.
    AddSub { t: Reg, a: Reg, b: Reg, c: Reg },
    /// `sub t <- a - b` then `add t <- t + c`.
    SubAdd { t: Reg, a: Reg, b: Reg, c: Reg },
    /// `sub t <- a - b` then `sub t <- t - c`.
    SubSub { t: Reg, a: Reg, b: Reg, c: Reg },
    // A sum or a difference scaled (a filter's `(x - y) * k`): the first into `t`, then `t`
    // times `c` into `t` (`c * t` is `t * c`: IEEE multiplication is commutative).
    /// `add t <- a + b` then `mul t <- t * c`.
    AddMul { t: Reg, a: Reg, b: Reg, c: Reg },
    /// `sub t <- a - b` then `mul t <- t * c`.
    SubMul { t: Reg, a: Reg, b: Reg, c: Reg },
    /// `jump` to the `for.next` at `at`, and run it there (the two count as two; a fault of the
    /// `for.next` is reported at `at`). Made by [`fuse`] from a `Jump` whose target is a
    /// `ForNext` (its fields copied here); `at` keeps that `ForNext` for a jump to it.
    JumpNext {
        var: Reg,
        limit: Reg,
        body: u32,
        at: u32,
        decimals: u8,
    },
    // Specialisations of [`Op::ArithFixed`] into a fixed-point slot without decimals (one
    // instruction each, made by [`fuse`]): an integer operator's integer result is stored
    // after one integer range test instead of the fixed-point rounding.
    /// `dst = a MOD b` (PowerTools) into a whole fixed-point slot.
    ModWhole { dst: Reg, a: Reg, b: Reg },
    /// `dst = a AND b` (bitwise) into a whole fixed-point slot.
    AndWhole { dst: Reg, a: Reg, b: Reg },
    /// `dst = a OR b` (bitwise) into a whole fixed-point slot.
    OrWhole { dst: Reg, a: Reg, b: Reg },
    /// `dst = a XOR b` (bitwise) into a whole fixed-point slot.
    XorWhole { dst: Reg, a: Reg, b: Reg },
    /// `add dst <- a + b` then `chk.long dst`.
    AddCheck { dst: Reg, a: Reg, b: Reg },
    /// `sub dst <- a - b` then `chk.long dst`.
    SubCheck { dst: Reg, a: Reg, b: Reg },
    /// `mul dst <- a * b` then `chk.long dst`.
    MulCheck { dst: Reg, a: Reg, b: Reg },
    /// `add dst <- a + b` then `chk.int dst` (INTEGER arithmetic's 16 bits).
    AddCheckInt { dst: Reg, a: Reg, b: Reg },
    /// `sub dst <- a - b` then `chk.int dst`.
    SubCheckInt { dst: Reg, a: Reg, b: Reg },
    /// `mul dst <- a * b` then `chk.int dst`.
    MulCheckInt { dst: Reg, a: Reg, b: Reg },
    // Superinstructions of three or four instructions, made by [`fuse`] as the pairs are (and
    // with the same rules: each counts as the instructions it replaces, reports a fault at the
    // place of the instruction that failed, writes the temporary as they do, and is listed as
    // its first instruction, the others following). `t_first`: the temporary is the first
    // operand of the instruction that reads it (the order the disassembly shows and the
    // arithmetic takes).
    /// `mul t <- a * b`, `chk.long t`, `add t <- t + c` (or `c + t`), `chk.long t`: a long's
    /// `x * k + c`.
    MulAddCheck {
        t: Reg,
        a: Reg,
        b: Reg,
        c: Reg,
        t_first: bool,
    },
    /// `add t <- t + x` (or `x + t`), `imod t <- t MOD m`, `store.l dst <- t`: a long's
    /// `(… + x) MOD m`.
    AddModLong {
        t: Reg,
        x: Reg,
        dst: Reg,
        m: Reg,
        t_first: bool,
    },
    /// `add t <- t + x` (or `x + t`), then `mod.f0 dst <- t MOD m` (a [`Op::ModWhole`]).
    AddModWhole {
        t: Reg,
        x: Reg,
        dst: Reg,
        m: Reg,
        t_first: bool,
    },
    /// `mul t <- a * b`, then the [`Op::AddModWhole`] after it, whose operands it reads there
    /// (a chained superinstruction: it does the work of three instructions and keeps the
    /// product in a register): `(a * b + x) MOD m` into a whole fixed-point slot.
    MulAddModWhole { t: Reg, a: Reg, b: Reg },
    /// A [`Op::MulAddCheck`] (`mul`, `chk.long`, `add`, `chk.long` through `t`), then the
    /// [`Op::ModLong`] four instructions on (`imod t <- t MOD m`, `store.l dst <- t`), whose
    /// operands it reads there: a long's `(a * b + c) MOD m`.
    MulAddCheckModLong {
        t: Reg,
        a: Reg,
        b: Reg,
        c: Reg,
        t_first: bool,
    },
    /// `mod t <- a MOD b`, `sub t <- a - t`, then the [`Op::DivAddFixed`] two instructions on
    /// (`div t <- t / b`, `add.f dst <- dst + t`), whose operands it reads there: PowerTools'
    /// whole quotient `(a - a MOD b) / b` (it has no `\`) added to a variable. Both divisions
    /// by `b` are one when the operands are whole within 32 bits.
    QuotAddFixed { t: Reg, a: Reg, b: Reg },
    /// `bnot t <- NOT a`, `band t <- t AND b` (or `b AND t`), `store.l dst <- t`.
    NotAndLong {
        t: Reg,
        a: Reg,
        b: Reg,
        dst: Reg,
        t_first: bool,
    },
    /// `bnot t <- NOT a`, then `band.f0 dst <- t AND b` (or `b AND t`, a [`Op::AndWhole`]).
    NotAndWhole {
        t: Reg,
        a: Reg,
        b: Reg,
        dst: Reg,
        t_first: bool,
    },
    /// `band t <- a AND b`, then `bor t <- t OR x` (or `x OR t`).
    AndOr {
        t: Reg,
        a: Reg,
        b: Reg,
        x: Reg,
        t_first: bool,
    },
    /// `band t <- a AND b`, `bxor t <- t XOR dst` (or `dst XOR t`), `store.l dst <- t`: a long's
    /// `dst = dst XOR (a AND b)`.
    AndXorLong {
        t: Reg,
        a: Reg,
        b: Reg,
        dst: Reg,
        t_first: bool,
    },
    /// `band t <- a AND b`, then `bxor.f0 dst <- t XOR dst` (or `dst XOR t`, a
    /// [`Op::XorWhole`]).
    AndXorWhole {
        t: Reg,
        a: Reg,
        b: Reg,
        dst: Reg,
        t_first: bool,
    },
    /// `idiv t <- a \ b`, `add t <- t + dst` (or `dst + t`), `store.l dst <- t`: a long's
    /// `dst = dst + a \ b`.
    DivAddLong {
        t: Reg,
        a: Reg,
        b: Reg,
        dst: Reg,
        t_first: bool,
    },
    /// PowerTools `mod t <- a MOD b`, then `sub t <- x - t`: `x - a MOD b`, the multiple of
    /// `b` at or below `x` when `x` is `a` (a count of whole pitches, a position on a grid).
    SubMod { t: Reg, a: Reg, b: Reg, x: Reg },
    /// `div t <- a / b`, then `add.f dst <- dst + t` (or `t + dst`): a fixed-point
    /// accumulator's `dst = dst + a / b` (a mean's sum, a scaled increment).
    DivAddFixed {
        t: Reg,
        a: Reg,
        b: Reg,
        dst: Reg,
        decimals: u8,
        t_first: bool,
    },
    /// The offset of an element of a two-subscript array (made by [`fuse_with_constants`]):
    /// `subscr p <- i in 0..n1`, `subscr p+1 <- j in 0..n2`, `mul p <- p * n2` (a constant)
    /// and `add p <- p + p+1`, with `lens` = `n1 << 16 | n2`.
    Offset2 { p: Reg, i: Reg, j: Reg, lens: u32 },
    /// The last three of those (made by [`fuse_with_constants`] where the first subscript is not
    /// right before: a second subscript computed, a third subscript): `subscr p+1 <- x in
    /// 0..len`, `mul p <- p * len` (a constant) and `add p <- p + p+1`.
    OffsetTail { p: Reg, x: Reg, len: u32 },
    /// `band t <- a AND b`, then `jump.f t` (`nonzero` false) or `jump.t t` (true) to
    /// `target`: a bit of a status word or counter tested (`IF S& AND 8 THEN`).
    AndJump {
        t: Reg,
        a: Reg,
        b: Reg,
        target: u32,
        nonzero: bool,
    },
    /// `add t <- a + b` then `store.r dst <- t`.
    AddReal { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `mul acc+1 <- a * b`, `add acc <- acc + (acc+1)` (or the other order; `minus`:
    /// `sub acc <- acc - (acc+1)`), then `store.r dst <- acc`: the last term of a sum of
    /// products stored, as a filter writes it (`F = F * K1 + X * K2`). The product, in the
    /// temporary after `acc`, is rounded first, as the three instructions round it.
    MulSumReal {
        acc: Reg,
        dst: Reg,
        a: Reg,
        b: Reg,
        minus: bool,
    },
    /// A sum of three or more terms, two products at least, stored into a real
    /// ([`fuse_sums`]: `Y = B0 * U + B1 * U1 + B2 * U2 - A1 * Y1 - A2 * Y2`, a filter's or a
    /// controller's): `mul acc <- a * b` of the first term; for each further one, a product
    /// `mul p <- a * b` and `add`/`sub acc <- acc ± p`, or an `add`/`sub` of a register (a
    /// term that is the product of that register with the constant 1, which is exact); then
    /// `store.r dst <- acc`. The terms are entries `at + 1 ..= at + terms` of
    /// [`super::Chunk::terms`], summed in the instructions' order; entry `at` is the last
    /// product's, whose value `p` is left holding. It counts as its `slots` instructions;
    /// listed as the first, the others following (nothing jumps among them).
    SumReal {
        acc: Reg,
        p: Reg,
        dst: Reg,
        at: u32,
        slots: u8,
        terms: u8,
    },
    /// `sub t <- a - b` then `store.r dst <- t`.
    SubReal { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `mul t <- a * b` then `store.r dst <- t`.
    MulReal { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// `div t <- a / b` then `store.r dst <- t` (a division by zero faults at the `div`).
    DivReal { t: Reg, dst: Reg, a: Reg, b: Reg },
    /// Any other binary operator (division checks for zero).
    Binary {
        op: BinaryOp,
        dst: Reg,
        a: Reg,
        b: Reg,
    },
    /// `dst = a cmp b` as 1/0.
    Compare { cmp: Cmp, dst: Reg, a: Reg, b: Reg },
    /// `dst = -a`.
    Neg { dst: Reg, a: Reg },
    /// Logical NOT of an ON/OFF value.
    Not { dst: Reg, a: Reg },
    /// Bitwise NOT of an integer.
    BitNot { dst: Reg, a: Reg },
    /// A math function.
    Call {
        func: Func,
        dst: Reg,
        a: Reg,
        b: Reg,
    },
    /// Store into a fixed-point slot: round to `decimals`, fail outside 32 bits.
    StoreFixed { dst: Reg, src: Reg, decimals: u8 },
    /// Store into a MotionBASIC long integer: halves rounded to even (Microsoft BASIC's CLNG),
    /// an Overflow outside 32 bits.
    StoreLong { dst: Reg, src: Reg },
    /// Store into a MotionBASIC INTEGER (`%`): halves rounded to even, an Overflow outside
    /// -32768 to 32767 (Microsoft BASIC's 16 bits).
    StoreInt { dst: Reg, src: Reg },
    /// Store a real quantity (must be finite).
    StoreReal { dst: Reg, src: Reg },
    /// Store an ON/OFF value.
    StoreBit { dst: Reg, src: Reg },
    /// Write a member whose object reacts (after the same rounding as a store).
    Write {
        hook: Hook,
        slot: Reg,
        src: Reg,
        instance: u32,
    },
    /// Run an action member.
    Act {
        hook: Hook,
        slot: Reg,
        instance: u32,
        start: StartRef,
        profile: u8,
    },
    /// Go to `target`.
    Jump { target: u32 },
    /// Go to `target` backwards; the task may yield here when its budget is spent.
    Loop { target: u32 },
    /// A [`Op::Loop`] going back to the start of a loop whose body the machine may run outside
    /// the interpreter (`compile::body`): unless the budget is spent, the interpreter leaves
    /// the loop to its caller there (`exec::Exit::Back`).
    LoopTight { target: u32 },
    /// Go to `target` when `cond` is OFF.
    JumpIfFalse { cond: Reg, target: u32 },
    /// Go to `target` unless `a < b` (comparisons are specialised; `>`/`>=` swap operands).
    JumpUnlessLt { a: Reg, b: Reg, target: u32 },
    /// Go to `target` unless `a <= b`.
    JumpUnlessLe { a: Reg, b: Reg, target: u32 },
    /// Go to `target` unless `a = b`.
    JumpUnlessEq { a: Reg, b: Reg, target: u32 },
    /// Go to `target` unless `a <> b`.
    JumpUnlessNe { a: Reg, b: Reg, target: u32 },
    /// Go to `target` when `a < b`.
    JumpWhenLt { a: Reg, b: Reg, target: u32 },
    /// Go to `target` when `a <= b`.
    JumpWhenLe { a: Reg, b: Reg, target: u32 },
    /// Go to `target` when `a = b`.
    JumpWhenEq { a: Reg, b: Reg, target: u32 },
    /// Go to `target` when `a <> b`.
    JumpWhenNe { a: Reg, b: Reg, target: u32 },
    /// Go to `target` when `cond` is ON.
    JumpIfTrue { cond: Reg, target: u32 },
    /// Block until `cond` is ON; the condition's code starts at `retry`.
    WaitUntil { cond: Reg, retry: u32 },
    /// Block for `src` seconds.
    WaitTime { src: Reg },
    /// A dwell motion on profile 0, for `src` seconds or master units; `last`: `Using Last`.
    Dwell { src: Reg, master: bool, last: bool },
    /// Leave the loop at `exit` when `var` is past `limit` in the direction of the step, which
    /// is in the register after `limit`.
    ForCheck { var: Reg, limit: Reg, exit: u32 },
    /// A [`Op::ForCheck`] entering a loop whose body is one instruction the machine may run
    /// outside the interpreter (`compile::tight`): when it has enough iterations, the
    /// interpreter leaves it to its caller (`exec::Exit::Loop`). `kept`: the machine has
    /// tried it and keeps running it (`Machine::judge_for`); one that does not pay becomes a
    /// plain [`Op::ForCheck`].
    ForTight {
        var: Reg,
        limit: Reg,
        exit: u32,
        kept: bool,
    },
    /// The end of a `For` body: `var += step` (the step is in the register after `limit`;
    /// stored as `decimals`, or as a real when
    /// [`REAL_STORE`]), then back to `body` unless past `limit`; the task may yield there.
    ForNext {
        var: Reg,
        limit: Reg,
        body: u32,
        decimals: u8,
    },
    /// Run another program on this task, then come back.
    CallProgram { program: u32 },
    /// Fail with "Overflow" unless `r` fits a 32-bit long integer (MotionBASIC `&` arithmetic).
    CheckLong { r: Reg },
    /// Fail with "Overflow" unless `r` fits a 16-bit INTEGER (MotionBASIC `%` arithmetic).
    CheckInt { r: Reg },
    /// `dst` = the axis set holding axis number `a` (1..16).
    AxisBit { dst: Reg, a: Reg },
    /// Read member `member` of the DSP axis in the set `axes`; `truth` gives -1/0 for a bit
    /// and, for a set of several axes, is true when it holds on every axis.
    AxisRead {
        dst: Reg,
        axes: Reg,
        member: u8,
        truth: bool,
    },
    /// Write member `member` of every DSP axis in the set `axes`; `text`: the value is a
    /// string.
    AxisWrite {
        axes: Reg,
        src: Reg,
        member: u8,
        hook: Hook,
        text: bool,
    },
    /// A MotionBASIC motion statement on the axes in `axes`.
    Motion {
        cmd: MotionCmd,
        axes: Reg,
        args: Reg,
    },
    /// A kernel function (`REGIST`, `READ_SV` …) on the arguments in consecutive registers
    /// from `args`.
    KernelCall {
        func: KernelFunc,
        dst: Reg,
        args: Reg,
    },
    /// `PRINT`: write the value in `src` at the task's print position, as `how` says.
    Print { src: Reg, how: PrintHow },
    /// `PRINT`'s `,`: move the task's print position to the next print zone.
    PrintZone,
    /// The end of a `PRINT` line: the task's line is output and traced.
    PrintLine,
    /// `GOSUB`: run the subroutine at `target`, then come back here.
    Gosub { target: u32 },
    /// `dst` = element `v[idx]` (rounded to an integer, halves to even; "Subscript out of
    /// range" outside `0..len`) of the one-subscript array starting at `base`.
    LoadIdx {
        dst: Reg,
        base: Reg,
        idx: Reg,
        len: u32,
    },
    /// Store `src` into element `v[idx]` of the one-subscript array starting at `base`, as
    /// [`Op::StoreAt`] stores.
    StoreIdx {
        base: Reg,
        idx: Reg,
        src: Reg,
        len: u32,
        decimals: u8,
    },
    /// [`Op::StoreIdx`] (its fields), then the `for.next` after it, which stays in place and is
    /// read from there (made by [`fuse_with_constants`]): an array filled or cleared in a loop. Counts
    /// as two; a fault of the `for.next` is reported at its place.
    StoreIdxNext {
        base: Reg,
        idx: Reg,
        src: Reg,
        len: u32,
        decimals: u8,
    },
    /// `dst` = the subscript in `src` rounded to an integer (halves to even), which must be
    /// within `0..len` ("Subscript out of range" otherwise).
    Subscript { dst: Reg, src: Reg, len: u32 },
    /// `dst` = the array element at `base + v[off]` (`off` from [`Op::Subscript`]s, below the
    /// array's `len`).
    LoadAt {
        dst: Reg,
        base: Reg,
        off: Reg,
        len: u32,
    },
    /// Store `src` into the array element at `base + v[off]`: rounded to a long integer when
    /// `decimals` is 0, a real when [`REAL_STORE`] (traced as any store).
    StoreAt {
        base: Reg,
        off: Reg,
        src: Reg,
        decimals: u8,
        len: u32,
    },
    /// A rarer instruction, described in the chunk's side table ([`Chunk::ext`]) so every
    /// instruction stays small: strings, `DATA`, random numbers. It counts against the budget
    /// as `1 + copies` instructions: a string function reads its arguments where they are, and
    /// each counts as the copy into a call's argument registers it stands for (as a kernel
    /// call's still are), so budgets yield where they did when those copies were made.
    Ext { at: u32, copies: u8 },
    /// A superinstruction ([`fuse_text`]): the string comparison of the side table's
    /// [`ExtOp::CompareText`] at `at` (an `Op::Ext` counting as one), the `neg` of its result
    /// when `negate` (MotionBASIC's true is -1), and the `jump.t` (`nonzero`) or `jump.f` on
    /// it. Listed as the comparison, the others following.
    TextJump {
        at: u32,
        target: u32,
        nonzero: bool,
        negate: bool,
    },
    /// A superinstruction ([`fuse_ext_pairs`]): the [`Op::Ext`] of side-table entry `at`
    /// (counting `1 + copies`) and the `Op::Ext` after it, of entry `next` (counting
    /// `1 + next_copies`), in one call out of the interpreter's loop. A string expression is
    /// mostly such instructions one after the other (a function, the join of its result, the
    /// store), and each paid for the call alone. A fault is at the one that faults. Listed as
    /// the first, the second following.
    ExtPair {
        at: u32,
        copies: u8,
        next: u32,
        next_copies: u8,
    },
    /// `RETURN` from a subroutine.
    Return,
    /// End of this program (returns to a caller if called).
    End,
}

/// A term of an [`Op::SumReal`]: the product of registers `a` and `b`, its sign bit flipped
/// by `mask` (a term taken away: `x - y` is `x + -y` in IEEE arithmetic, and `-(a * b)` is
/// the product negated exactly).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Term {
    /// The first factor.
    pub a: Reg,
    /// The second factor.
    pub b: Reg,
    /// `1 << 63` for a term taken away, else 0.
    pub mask: u64,
}

/// The instructions of [`Op::Ext`]. A string value is a handle: an index into the machine's
/// string table, which holds the programs' literals and one cell per string variable, array
/// element and string-making instruction (a string variable's slot always holds its own cell).
#[derive(Debug, Clone, PartialEq)]
pub enum ExtOp {
    /// Copy the string `src` into the cell of the string variable `dst` (traced when it changes).
    StoreText { dst: Reg, src: Reg },
    /// Copy the string `src` into the cell of the string array element at `base + v[off]`
    /// (`off` within `0..len`).
    StoreTextAt {
        base: Reg,
        off: Reg,
        src: Reg,
        len: u32,
    },
    /// Copy the string `src` into `cell`; `dst` = that cell (SWAP keeps a value this way).
    CopyText { dst: Reg, cell: u32, src: Reg },
    /// `a + b` of strings into `cell`; `dst` = that cell.
    Concat { dst: Reg, cell: u32, a: Reg, b: Reg },
    /// A string function on the first `argc` of `args`, each read where it is (bit i of
    /// `texts`: argument i is a string); a string result goes into `cell` (and `dst` = the
    /// cell), a number into `dst`.
    Text {
        func: TextFunc,
        dst: Reg,
        cell: u32,
        args: [Reg; 4],
        argc: u8,
        texts: u8,
    },
    // The string functions programs call most, each naming only the registers it reads
    // ([`specialize_text`] makes them of [`ExtOp::Text`], and [`ExtOp::general`] gives that
    // back): the interpreter reads no argument count or kinds, and branches once.
    /// `LEN(s)`.
    Len { dst: Reg, s: Reg },
    /// `ASC(s)`.
    Asc { dst: Reg, s: Reg },
    /// `VAL(s)`.
    Val { dst: Reg, s: Reg },
    /// `INSTR(hay, needle)`, from the first character.
    Instr { dst: Reg, hay: Reg, needle: Reg },
    /// `LEFT$(s, n)` into `cell`; `dst` = the cell.
    Left { dst: Reg, cell: u32, s: Reg, n: Reg },
    /// `RIGHT$(s, n)` into `cell`; `dst` = the cell.
    Right { dst: Reg, cell: u32, s: Reg, n: Reg },
    /// `MID$(s, start)` into `cell`; `dst` = the cell.
    Mid {
        dst: Reg,
        cell: u32,
        s: Reg,
        start: Reg,
    },
    /// `MID$(s, start, n)` into `cell`; `dst` = the cell.
    MidN {
        dst: Reg,
        cell: u32,
        s: Reg,
        start: Reg,
        n: Reg,
    },
    /// `CHR$(code)` into `cell`; `dst` = the cell.
    Chr { dst: Reg, cell: u32, code: Reg },
    /// `STR$(x)` of a value of type `how` into `cell`; `dst` = the cell.
    Str {
        dst: Reg,
        cell: u32,
        x: Reg,
        how: PrintHow,
    },
    /// `dst` = 1 when the strings compare as `cmp` says (character codes, a prefix first), else 0.
    CompareText { cmp: Cmp, dst: Reg, a: Reg, b: Reg },
    /// `dst` = RND, or RND(`arg`).
    Rnd { dst: Reg, arg: Option<Reg> },
    /// `RANDOMIZE` with a seed, or the scenario's.
    Randomize { seed: Option<Reg> },
    /// `dst` = simulated seconds since the run started.
    Timer { dst: Reg },
    /// `dst` = the next `DATA` constant: its string when `text`, else its number.
    Read { dst: Reg, text: bool },
    /// The next `READ` takes `DATA` constant `item` (0: the first).
    Restore { item: u32 },
    /// "Subscript out of range" unless `v[src]`, rounded (halves to even), is within
    /// `low..=high`: a subscript of an array whose subscripts start at `low` (`OPTION BASE 1`),
    /// checked before the subscript instructions, which take it from 0.
    CheckSubscript { src: Reg, low: u32, high: u32 },
    /// `PRINT USING`: the format in `format`, `count` values in consecutive registers from
    /// `args` (bit i of `texts`: value i is a string), written at the task's print position.
    PrintUsing {
        format: Reg,
        args: Reg,
        count: u32,
        texts: u64,
    },
}

impl ExtOp {
    /// The [`ExtOp::Text`] a specialised string function stands for (what the listing shows);
    /// any other instruction as it is.
    pub fn general(&self) -> ExtOp {
        use crate::check::text::TextFunc as F;
        let text = |func, dst, cell, given: &[Reg], texts| {
            let mut args = [0; 4];
            args[..given.len()].copy_from_slice(given);
            ExtOp::Text {
                func,
                dst,
                cell,
                args,
                argc: given.len() as u8,
                texts,
            }
        };
        match *self {
            ExtOp::Len { dst, s } => text(F::Len, dst, 0, &[s], 0b1),
            ExtOp::Asc { dst, s } => text(F::Asc, dst, 0, &[s], 0b1),
            ExtOp::Val { dst, s } => text(F::Val, dst, 0, &[s], 0b1),
            ExtOp::Instr { dst, hay, needle } => text(F::Instr, dst, 0, &[hay, needle], 0b11),
            ExtOp::Left { dst, cell, s, n } => text(F::Left, dst, cell, &[s, n], 0b1),
            ExtOp::Right { dst, cell, s, n } => text(F::Right, dst, cell, &[s, n], 0b1),
            ExtOp::Mid {
                dst,
                cell,
                s,
                start,
            } => text(F::Mid, dst, cell, &[s, start], 0b1),
            ExtOp::MidN {
                dst,
                cell,
                s,
                start,
                n,
            } => text(F::Mid, dst, cell, &[s, start, n], 0b1),
            ExtOp::Chr { dst, cell, code } => text(F::Chr, dst, cell, &[code], 0),
            ExtOp::Str { dst, cell, x, how } => text(F::Str(how), dst, cell, &[x], 0),
            ref other => other.clone(),
        }
    }
}

/// Make each [`ExtOp::Text`] of a function with a specialised instruction that instruction,
/// when [`ExtOp::general`] gives the same `Text` back (arguments of the kinds the checker
/// gives that function, nothing in the registers it does not read).
pub fn specialize_text(ext: &mut [ExtOp]) {
    use crate::check::text::TextFunc as F;
    for op in ext.iter_mut() {
        let ExtOp::Text {
            func,
            dst,
            cell,
            args: [a, b, c, _],
            argc,
            ..
        } = *op
        else {
            continue;
        };
        let special = match (func, argc) {
            (F::Len, 1) => ExtOp::Len { dst, s: a },
            (F::Asc, 1) => ExtOp::Asc { dst, s: a },
            (F::Val, 1) => ExtOp::Val { dst, s: a },
            (F::Instr, 2) => ExtOp::Instr {
                dst,
                hay: a,
                needle: b,
            },
            (F::Left, 2) => ExtOp::Left {
                dst,
                cell,
                s: a,
                n: b,
            },
            (F::Right, 2) => ExtOp::Right {
                dst,
                cell,
                s: a,
                n: b,
            },
            (F::Mid, 2) => ExtOp::Mid {
                dst,
                cell,
                s: a,
                start: b,
            },
            (F::Mid, 3) => ExtOp::MidN {
                dst,
                cell,
                s: a,
                start: b,
                n: c,
            },
            (F::Chr, 1) => ExtOp::Chr { dst, cell, code: a },
            (F::Str(how), 1) => ExtOp::Str {
                dst,
                cell,
                x: a,
                how,
            },
            _ => continue,
        };
        if special.general() == *op {
            *op = special;
        }
    }
}

/// A `DATA` constant of a compiled program.
#[derive(Debug, Clone, PartialEq)]
pub struct DataConst {
    /// Its value when it reads as a number.
    pub number: Option<f64>,
    /// The string it is (a handle).
    pub text: u32,
    /// As written, for messages.
    pub written: String,
    /// Its source line.
    pub line: u32,
}

pub use crate::check::text::TextFunc;

/// Before [`fuse`]: each sum of three or more terms, two of them products at least, stored
/// into a real becomes one [`Op::SumReal`], its terms pushed onto `table`; `one` gives the
/// register of the constant 1 (asked for only when a term is a plain register). A real
/// filter's or controller's line was a dispatch a product; now it is one. Nothing may jump
/// among a sum's instructions, which stay in place, as a superinstruction's second half does.
pub fn fuse_sums(
    ops: &mut [Op],
    temps: &std::ops::Range<Reg>,
    one: &mut dyn FnMut() -> Reg,
    table: &mut Vec<Term>,
) {
    let targets: std::collections::BTreeSet<u32> = ops.iter().filter_map(Op::target).collect();
    let mut i = 0;
    while i < ops.len() {
        let Some(sum) = sum_at(ops, i, temps) else {
            i += 1;
            continue;
        };
        let end = i + usize::from(sum.slots) - 1;
        if targets.range(i as u32 + 1..=end as u32).next().is_some() {
            i += 1;
            continue;
        }
        let at = table.len() as u32;
        table.push(Term {
            a: sum.last.0,
            b: sum.last.1,
            mask: 0,
        });
        let mut plain_one = None;
        for &(a, b, minus) in &sum.terms {
            let b = match b {
                Some(b) => b,
                None => *plain_one.get_or_insert_with(&mut *one),
            };
            table.push(Term {
                a,
                b,
                mask: if minus { 1 << 63 } else { 0 },
            });
        }
        ops[i] = Op::SumReal {
            acc: sum.acc,
            p: sum.p,
            dst: sum.dst,
            at,
            slots: sum.slots,
            terms: sum.terms.len() as u8,
        };
        i = end + 1;
    }
}

/// A sum [`fuse_sums`] makes one instruction.
struct Sum {
    acc: Reg,
    p: Reg,
    dst: Reg,
    slots: u8,
    /// Each term: its factors (a plain register's second is `None`: the constant 1), and
    /// whether it is taken away.
    terms: Vec<(Reg, Option<Reg>, bool)>,
    /// The factors of the last product into `p`.
    last: (Reg, Reg),
}

/// The sum starting at `ops[i]`: `mul acc <- a * b`, then terms (`mul p <- a * b` and `add acc
/// <- acc + p`, `add acc <- p + acc` or `sub acc <- acc - p`; or `add`/`sub` of a register
/// other than `acc` and `p`), then `store.r dst <- acc`. No term reads `acc` or `p` once the sum
/// has written them: the instruction reads every operand before it writes.
fn sum_at(ops: &[Op], i: usize, temps: &std::ops::Range<Reg>) -> Option<Sum> {
    // The most terms a sum takes (its instructions then fit `slots`).
    const MOST: usize = 100;
    let Op::Mul { dst: acc, a, b } = *ops.get(i)? else {
        return None;
    };
    if !temps.contains(&acc) {
        return None;
    }
    let mut terms = vec![(a, Some(b), false)];
    let mut p: Option<Reg> = None;
    let mut last = (a, b);
    let mut j = i + 1;
    let dst = loop {
        if terms.len() > MOST {
            return None;
        }
        match *ops.get(j)? {
            Op::StoreReal { dst, src } if src == acc => break dst,
            Op::Mul { dst: w, a, b }
                if temps.contains(&w)
                    && w != acc
                    && p.is_none_or(|p| p == w)
                    && ![acc, w].contains(&a)
                    && ![acc, w].contains(&b) =>
            {
                let minus = match *ops.get(j + 1)? {
                    Op::Add { dst, a: x, b: y }
                        if dst == acc && ((x == acc && y == w) || (x == w && y == acc)) =>
                    {
                        false
                    }
                    Op::Sub { dst, a: x, b: y } if dst == acc && x == acc && y == w => true,
                    _ => return None,
                };
                terms.push((a, Some(b), minus));
                p = Some(w);
                last = (a, b);
                j += 2;
            }
            Op::Add { dst, a: x, b: y } if dst == acc && (x == acc) != (y == acc) => {
                let c = if x == acc { y } else { x };
                if p == Some(c) {
                    return None;
                }
                terms.push((c, None, false));
                j += 1;
            }
            Op::Sub { dst, a: x, b: y } if dst == acc && x == acc && y != acc && p != Some(y) => {
                terms.push((y, None, true));
                j += 1;
            }
            _ => return None,
        }
    };
    let products = terms.iter().filter(|t| t.1.is_some()).count();
    if terms.len() < 3 || products < 2 {
        return None;
    }
    Some(Sum {
        acc,
        p: p?,
        dst,
        slots: u8::try_from(j - i + 1).ok()?,
        terms,
        last,
    })
}

/// Fuse adjacent pairs of instructions into superinstructions (see [`Op::AddLong`]). Only a pair
/// joined by a temporary in `temps` is fused. Before that, single instructions are specialised
/// in place: an integer operator into a whole fixed-point slot ([`Op::ModWhole`] …), a jump to a
/// `for.next` ([`Op::JumpNext`]).
pub fn fuse(ops: &mut [Op], temps: std::ops::Range<Reg>) {
    // Single instructions first: each rewrite keeps the instruction's place and count.
    for i in 0..ops.len() {
        let cur = ops[i];
        ops[i] = match cur {
            Op::ArithFixed {
                op,
                dst,
                a,
                b,
                decimals: 0,
            } => match op {
                BinaryOp::Mod => Op::ModWhole { dst, a, b },
                BinaryOp::BitAnd => Op::AndWhole { dst, a, b },
                BinaryOp::BitOr => Op::OrWhole { dst, a, b },
                BinaryOp::BitXor => Op::XorWhole { dst, a, b },
                _ => cur,
            },
            Op::Jump { target } => match ops.get(target as usize) {
                Some(&Op::ForNext {
                    var,
                    limit,
                    body,
                    decimals,
                }) => Op::JumpNext {
                    var,
                    limit,
                    body,
                    at: target,
                    decimals,
                },
                _ => cur,
            },
            _ => cur,
        };
    }
    // Which instructions to fuse: as many dispatches saved as the chunk allows (a pair saves
    // one, a triple two), chosen from the end: `gain[i]` is the most saved from `i` on. Taking
    // the first fusion found could spoil a better one (a multiply-add taking the add that would
    // have fused with the `MOD` after it and the multiply with nothing).
    let len = ops.len();
    let mut gain = vec![0u32; len + 3];
    let mut choice = vec![0u8; len];
    for i in (0..len).rev() {
        // A sum ([`fuse_sums`]) is taken whole: its other instructions are not run.
        if let Op::SumReal { slots, .. } = ops[i] {
            gain[i] = gain[(i + usize::from(slots)).min(len)];
            continue;
        }
        let (mut best, mut pick) = (gain[i + 1], 0u8);
        let fused = ops.get(i + 1).and_then(|&second| pair(ops[i], second));
        if let Some(op) = fused.filter(|&op| joined(op, &temps)) {
            let g = 1 + gain[i + 2];
            // On a tie, an arithmetic pair gives way to the fusion of its second instruction
            // with what follows it (an add with its store: the store's test is the dearer).
            if g > best || (g == best && !gives_way(op)) {
                (best, pick) = (g, 2);
            }
        }
        if let (Some(&second), Some(&third)) = (ops.get(i + 1), ops.get(i + 2)) {
            if let Some((_, t)) = triple(ops[i], second, third) {
                let g = 2 + gain[i + 3];
                // (A product summed and stored goes through the temporary after `t` too.)
                let product = matches!(op_of_triple(ops[i], second, third), Some(true));
                if temps.contains(&t) && (!product || temps.contains(&(t + 1))) && g >= best {
                    (best, pick) = (g, 3);
                }
            }
        }
        gain[i] = best;
        choice[i] = pick;
    }
    let mut i = 0;
    while i < len {
        match choice[i] {
            3 => {
                // A triple's last two instructions are fused as a pair too, for a jump to the
                // second.
                if let Some((op, _)) = triple(ops[i], ops[i + 1], ops[i + 2]) {
                    if let Some(second) = pair(ops[i + 1], ops[i + 2]) {
                        ops[i + 1] = second;
                    }
                    ops[i] = op;
                }
                i += 3;
            }
            2 => {
                if let Some(op) = pair(ops[i], ops[i + 1]) {
                    ops[i] = op;
                }
                i += 2;
            }
            _ => {
                i += match ops[i] {
                    Op::SumReal { slots, .. } => usize::from(slots).max(1),
                    _ => 1,
                }
            }
        }
    }
    // Then a long multiply-add: a `MulCheck` and the `AddCheck` of its product after it.
    for i in 0..ops.len().saturating_sub(2) {
        if let (Op::MulCheck { dst: t, a, b }, Op::AddCheck { dst, a: x, b: y }) =
            (ops[i], ops[i + 2])
        {
            if dst == t && (x == t || y == t) && temps.contains(&t) {
                let t_first = x == t;
                let c = if t_first { y } else { x };
                ops[i] = Op::MulAddCheck {
                    t,
                    a,
                    b,
                    c,
                    t_first,
                };
            }
        }
    }
}

/// Whether the pair `op` joins its two instructions through a temporary in `temps`: a pair
/// through a variable is left alone (the first half's write would be traced).
fn joined(op: Op, temps: &std::ops::Range<Reg>) -> bool {
    match op {
        Op::AddLong { t, .. }
        | Op::SubLong { t, .. }
        | Op::MulLong { t, .. }
        | Op::IntLong { t, .. }
        | Op::ModLong { t, .. }
        | Op::AndLong { t, .. }
        | Op::OrLong { t, .. }
        | Op::XorLong { t, .. }
        | Op::AddInt { t, .. }
        | Op::SubInt { t, .. }
        | Op::MulInt { t, .. }
        | Op::IntInt { t, .. }
        | Op::MulAdd { t, .. }
        | Op::MulAcc { p: t, .. }
        | Op::MulDec { p: t, .. }
        | Op::AddAdd { t, .. }
        | Op::AddSub { t, .. }
        | Op::SubAdd { t, .. }
        | Op::SubSub { t, .. }
        | Op::AddMul { t, .. }
        | Op::SubMul { t, .. }
        | Op::AddModWhole { t, .. }
        | Op::NotAndWhole { t, .. }
        | Op::AndOr { t, .. }
        | Op::AndXorWhole { t, .. }
        | Op::SubMod { t, .. }
        | Op::AndJump { t, .. }
        | Op::DivAddFixed { t, .. }
        | Op::AddReal { t, .. }
        | Op::SubReal { t, .. }
        | Op::MulReal { t, .. }
        | Op::DivReal { t, .. }
        | Op::AddCheck { dst: t, .. }
        | Op::SubCheck { dst: t, .. }
        | Op::MulCheck { dst: t, .. }
        | Op::AddCheckInt { dst: t, .. }
        | Op::SubCheckInt { dst: t, .. }
        | Op::MulCheckInt { dst: t, .. } => temps.contains(&t),
        _ => false,
    }
}

/// Whether the pair `op` gives way, on a tie, to a fusion of its second instruction with the
/// one after it.
fn gives_way(op: Op) -> bool {
    matches!(
        op,
        Op::MulAdd { .. }
            | Op::MulAcc { .. }
            | Op::MulDec { .. }
            | Op::AddAdd { .. }
            | Op::AddSub { .. }
            | Op::SubAdd { .. }
            | Op::SubSub { .. }
            | Op::AddMul { .. }
            | Op::SubMul { .. }
    )
}

/// After [`fuse`], the fusions that need the constants' values (and the one of a store with
/// the loop's end): a `store.idx` with the `for.next` after it becomes one
/// [`Op::StoreIdxNext`]; the four instructions that compute the offset of an element of a
/// two-subscript array (`A(I, J)`: two subscripts, then `first * n2 + second`) become one
/// [`Op::Offset2`] where both subscripts go to adjacent temporaries (`p`, `p + 1`), the
/// multiplier is the constant `n2` (`constant` gives a constant register's value) and both
/// lengths are below 2^16; where only the last three are so, an [`Op::OffsetTail`]; a `band`
/// and a comparison of its result with 0, one [`Op::AndJump`]. The others stay in place (they
/// are not jumped to: they are one expression's), as a superinstruction's do. Last, the
/// chained superinstructions ([`chain`]).
pub fn fuse_with_constants(
    ops: &mut [Op],
    temps: &std::ops::Range<Reg>,
    constant: &dyn Fn(Reg) -> Option<f64>,
) {
    for i in 0..ops.len().saturating_sub(1) {
        if let (
            Op::StoreIdx {
                base,
                idx,
                src,
                len,
                decimals,
            },
            Op::ForNext { .. },
        ) = (ops[i], ops[i + 1])
        {
            ops[i] = Op::StoreIdxNext {
                base,
                idx,
                src,
                len,
                decimals,
            };
        }
    }
    for i in 0..ops.len().saturating_sub(3) {
        let (
            Op::Subscript {
                dst: p,
                src: a,
                len: n1,
            },
            Op::Subscript {
                dst: s,
                src: b,
                len: n2,
            },
        ) = (ops[i], ops[i + 1])
        else {
            continue;
        };
        // The multiply, fused with the add after it or not.
        let k = match ops[i + 2] {
            Op::Mul { dst, a: x, b: k }
            | Op::MulAdd {
                t: dst, a: x, b: k, ..
            } if dst == p && x == p => k,
            _ => continue,
        };
        let added =
            matches!(ops[i + 3], Op::Add { dst, a: x, b: y } if dst == p && x == p && y == s);
        if added
            && s == p + 1
            && temps.contains(&p)
            && temps.contains(&s)
            && n1 < 1 << 16
            && n2 < 1 << 16
            && constant(k) == Some(f64::from(n2))
        {
            ops[i] = Op::Offset2 {
                p,
                i: a,
                j: b,
                lens: n1 << 16 | n2,
            };
        }
    }
    // Then the last three where the four were not (and inside the four, for a jump there).
    for i in 1..ops.len().saturating_sub(2) {
        let Op::Subscript {
            dst: s,
            src: x,
            len,
        } = ops[i]
        else {
            continue;
        };
        let Some(p) = s.checked_sub(1) else {
            continue;
        };
        let times = matches!(ops[i + 1], Op::Mul { dst, a, b: k } | Op::MulAdd { t: dst, a, b: k, .. }
            if dst == p && a == p && constant(k) == Some(f64::from(len)));
        let added = matches!(ops[i + 2], Op::Add { dst, a, b } if dst == p && a == p && b == s);
        if times && added && temps.contains(&p) && temps.contains(&s) {
            ops[i] = Op::OffsetTail { p, x, len };
        }
    }
    // A `band` whose result is compared with the constant 0 (`If (Var.S AND 8) <> 0`, `IF
    // (I& AND 4) = 0`): as a `band` and a `jump.f`/`jump.t`, which jump on the same values (a
    // comparison with 0 is one with -0, and no `band` gives NaN).
    for i in 0..ops.len().saturating_sub(1) {
        let Op::BitAnd { dst: t, a, b } = ops[i] else {
            continue;
        };
        let zero_test = |x: Reg, y: Reg| {
            (x == t && constant(y) == Some(0.0)) || (y == t && constant(x) == Some(0.0))
        };
        let (target, nonzero) = match ops[i + 1] {
            Op::JumpUnlessNe { a: x, b: y, target } | Op::JumpWhenEq { a: x, b: y, target }
                if zero_test(x, y) =>
            {
                (target, false)
            }
            Op::JumpUnlessEq { a: x, b: y, target } | Op::JumpWhenNe { a: x, b: y, target }
                if zero_test(x, y) =>
            {
                (target, true)
            }
            _ => continue,
        };
        ops[i] = Op::AndJump {
            t,
            a,
            b,
            target,
            nonzero,
        };
    }
    chain(ops, temps, constant);
}

/// Chained superinstructions: where a superinstruction follows the instruction that computes
/// its temporary, one instruction does both, reading the second's operands where it stays
/// (for a jump to it, as a superinstruction's halves stay): [`Op::MulAddModWhole`],
/// [`Op::MulAddCheckModLong`], and [`Op::QuotAddFixed`] where both divisors are the same
/// register or the same constant.
fn chain(ops: &mut [Op], temps: &std::ops::Range<Reg>, constant: &dyn Fn(Reg) -> Option<f64>) {
    for i in 0..ops.len() {
        let chained = match (ops[i], ops.get(i + 1), ops.get(i + 2), ops.get(i + 4)) {
            (Op::Mul { dst: t, a, b }, Some(&Op::AddModWhole { t: u, .. }), _, _)
                if u == t && temps.contains(&t) =>
            {
                Op::MulAddModWhole { t, a, b }
            }
            (
                Op::MulAddCheck {
                    t,
                    a,
                    b,
                    c,
                    t_first,
                },
                _,
                _,
                Some(&Op::ModLong { t: u, a: x, .. }),
            ) if u == t && x == t => Op::MulAddCheckModLong {
                t,
                a,
                b,
                c,
                t_first,
            },
            (
                Op::SubMod { t, a, b, x },
                _,
                Some(&Op::DivAddFixed {
                    t: u, a: q, b: k, ..
                }),
                _,
            ) if x == a
                && u == t
                && q == t
                && (k == b || constant(k).is_some_and(|v| constant(b) == Some(v))) =>
            {
                Op::QuotAddFixed { t, a, b }
            }
            _ => continue,
        };
        ops[i] = chained;
    }
}

/// After [`fuse_with_constants`], a string comparison into a temporary (`ext` is the side
/// table), the `neg` of it that may follow, and the `jump.t`/`jump.f` on it: one
/// [`Op::TextJump`]. The others stay in place, as a superinstruction's halves do.
pub fn fuse_text(ops: &mut [Op], ext: &[ExtOp], temps: &std::ops::Range<Reg>) {
    for i in 0..ops.len() {
        let Op::Ext { at, copies: 0 } = ops[i] else {
            continue;
        };
        let Some(&ExtOp::CompareText { dst, .. }) = ext.get(at as usize) else {
            continue;
        };
        if !temps.contains(&dst) {
            continue;
        }
        let negate = matches!(ops.get(i + 1), Some(&Op::Neg { dst: d, a }) if d == dst && a == dst);
        let (target, nonzero) = match ops.get(i + 1 + usize::from(negate)) {
            Some(&Op::JumpIfTrue { cond, target }) if cond == dst => (target, true),
            Some(&Op::JumpIfFalse { cond, target }) if cond == dst => (target, false),
            _ => continue,
        };
        ops[i] = Op::TextJump {
            at,
            target,
            nonzero,
            negate,
        };
    }
}

/// Make an [`Op::Ext`] followed by another an [`Op::ExtPair`] of the two, pairing a run of
/// them from its first (the second of a pair stays as it is: a jump to it runs it alone).
pub fn fuse_ext_pairs(ops: &mut [Op]) {
    let mut i = 0;
    while i + 1 < ops.len() {
        if let (
            Op::Ext { at, copies },
            Op::Ext {
                at: next,
                copies: next_copies,
            },
        ) = (ops[i], ops[i + 1])
        {
            ops[i] = Op::ExtPair {
                at,
                copies,
                next,
                next_copies,
            };
            i += 2;
        } else {
            i += 1;
        }
    }
}

/// The superinstruction doing the work of `first`, `second` and `third`, and the temporary
/// joining them, if there is one.
/// Whether [`triple`] fuses the three into a product summed and stored (which goes through
/// two temporaries): `Some(true)`; another triple `Some(false)`; none, `None`.
fn op_of_triple(first: Op, second: Op, third: Op) -> Option<bool> {
    triple(first, second, third).map(|(op, _)| matches!(op, Op::MulSumReal { .. }))
}

fn triple(first: Op, second: Op, third: Op) -> Option<(Op, Reg)> {
    match (first, second, third) {
        (
            Op::Mul { dst: p, a, b },
            sum @ (Op::Add {
                dst: acc,
                a: x,
                b: y,
            }
            | Op::Sub {
                dst: acc,
                a: x,
                b: y,
            }),
            Op::StoreReal { dst, src },
        ) if p == acc.wrapping_add(1)
            && src == acc
            // `acc - p` only; `p + acc` is `acc + p`.
            && ((x == acc && y == p) || (x == p && y == acc && matches!(sum, Op::Add { .. }))) =>
        {
            let minus = matches!(sum, Op::Sub { .. });
            Some((
                Op::MulSumReal {
                    acc,
                    dst,
                    a,
                    b,
                    minus,
                },
                acc,
            ))
        }
        (
            Op::Add { dst: t, a, b },
            Op::IMod {
                dst: t2,
                a: u,
                b: m,
            },
            Op::StoreLong { dst, src },
        ) if t2 == t && u == t && src == t && (a == t || b == t) => {
            let t_first = a == t;
            let x = if t_first { b } else { a };
            Some((
                Op::AddModLong {
                    t,
                    x,
                    dst,
                    m,
                    t_first,
                },
                t,
            ))
        }
        (
            Op::BitNot { dst: t, a },
            Op::BitAnd {
                dst: t2,
                a: x,
                b: y,
            },
            Op::StoreLong { dst, src },
        ) if t2 == t && src == t && (x == t || y == t) => {
            let t_first = x == t;
            let b = if t_first { y } else { x };
            Some((
                Op::NotAndLong {
                    t,
                    a,
                    b,
                    dst,
                    t_first,
                },
                t,
            ))
        }
        (
            Op::BitAnd { dst: t, a, b },
            Op::BitXor {
                dst: t2,
                a: x,
                b: y,
            },
            Op::StoreLong { dst, src },
        ) if t2 == t && src == t && ((x == t && y == dst) || (y == t && x == dst)) => Some((
            Op::AndXorLong {
                t,
                a,
                b,
                dst,
                t_first: x == t,
            },
            t,
        )),
        (
            Op::IDiv { dst: t, a, b },
            Op::Add {
                dst: t2,
                a: x,
                b: y,
            },
            Op::StoreLong { dst, src },
        ) if t2 == t && src == t && ((x == t && y == dst) || (y == t && x == dst)) => Some((
            Op::DivAddLong {
                t,
                a,
                b,
                dst,
                t_first: x == t,
            },
            t,
        )),
        _ => None,
    }
}

/// The superinstruction doing the work of `first` and then `second`, if there is one.
fn pair(first: Op, second: Op) -> Option<Op> {
    match (first, second) {
        (Op::BitAnd { dst: t, a, b }, Op::JumpIfFalse { cond, target }) if cond == t => {
            Some(Op::AndJump {
                t,
                a,
                b,
                target,
                nonzero: false,
            })
        }
        (Op::BitAnd { dst: t, a, b }, Op::JumpIfTrue { cond, target }) if cond == t => {
            Some(Op::AndJump {
                t,
                a,
                b,
                target,
                nonzero: true,
            })
        }
        (Op::Add { dst: t, a, b }, Op::StoreLong { dst, src }) if src == t => {
            Some(Op::AddLong { t, dst, a, b })
        }
        (Op::Sub { dst: t, a, b }, Op::StoreLong { dst, src }) if src == t => {
            Some(Op::SubLong { t, dst, a, b })
        }
        (Op::Mul { dst: t, a, b }, Op::StoreLong { dst, src }) if src == t => {
            Some(Op::MulLong { t, dst, a, b })
        }
        (Op::IMod { dst: t, a, b }, Op::StoreLong { dst, src }) if src == t => {
            Some(Op::ModLong { t, dst, a, b })
        }
        (Op::IDiv { dst: t, a, b }, Op::StoreLong { dst, src }) if src == t => Some(Op::IntLong {
            op: BinaryOp::IntDiv,
            t,
            dst,
            a,
            b,
        }),
        (Op::BitAnd { dst: t, a, b }, Op::StoreLong { dst, src }) if src == t => {
            Some(Op::AndLong { t, dst, a, b })
        }
        (Op::BitOr { dst: t, a, b }, Op::StoreLong { dst, src }) if src == t => {
            Some(Op::OrLong { t, dst, a, b })
        }
        (Op::BitXor { dst: t, a, b }, Op::StoreLong { dst, src }) if src == t => {
            Some(Op::XorLong { t, dst, a, b })
        }
        (Op::Add { dst: t, a, b }, Op::StoreInt { dst, src }) if src == t => {
            Some(Op::AddInt { t, dst, a, b })
        }
        (Op::Sub { dst: t, a, b }, Op::StoreInt { dst, src }) if src == t => {
            Some(Op::SubInt { t, dst, a, b })
        }
        (Op::Mul { dst: t, a, b }, Op::StoreInt { dst, src }) if src == t => {
            Some(Op::MulInt { t, dst, a, b })
        }
        (
            Op::IMod { dst: t, a, b }
            | Op::IDiv { dst: t, a, b }
            | Op::BitAnd { dst: t, a, b }
            | Op::BitOr { dst: t, a, b }
            | Op::BitXor { dst: t, a, b },
            Op::StoreInt { dst, src },
        ) if src == t => Some(Op::IntInt {
            op: match first {
                Op::IMod { .. } => BinaryOp::BasicMod,
                Op::IDiv { .. } => BinaryOp::IntDiv,
                Op::BitAnd { .. } => BinaryOp::BitAnd,
                Op::BitOr { .. } => BinaryOp::BitOr,
                _ => BinaryOp::BitXor,
            },
            t,
            dst,
            a,
            b,
        }),
        (Op::Add { dst, a, b }, Op::CheckInt { r }) if r == dst => {
            Some(Op::AddCheckInt { dst, a, b })
        }
        (Op::Sub { dst, a, b }, Op::CheckInt { r }) if r == dst => {
            Some(Op::SubCheckInt { dst, a, b })
        }
        (Op::Mul { dst, a, b }, Op::CheckInt { r }) if r == dst => {
            Some(Op::MulCheckInt { dst, a, b })
        }
        // `c + t` is `t + c` (IEEE addition is commutative).
        (Op::Mul { dst: t, a, b }, Op::Add { dst, a: x, b: y })
            if dst == t && (x == t || y == t) =>
        {
            let c = if x == t { y } else { x };
            Some(Op::MulAdd { t, a, b, c })
        }
        (
            Op::Mul { dst: p, a, b },
            Op::Add {
                dst: acc,
                a: x,
                b: y,
            },
        ) if acc != p && ((x == acc && y == p) || (x == p && y == acc)) => {
            Some(Op::MulAcc { p, a, b, acc })
        }
        (
            Op::Mul { dst: p, a, b },
            Op::Sub {
                dst: acc,
                a: x,
                b: y,
            },
        ) if acc != p && x == acc && y == p => Some(Op::MulDec { p, a, b, acc }),
        // Two adds or subtracts through `t`; the second takes `t` first (or second, for an add).
        (
            first @ (Op::Add { dst: t, a, b } | Op::Sub { dst: t, a, b }),
            second @ (Op::Add { dst, a: x, b: y } | Op::Sub { dst, a: x, b: y }),
        ) if dst == t && (x == t || (y == t && matches!(second, Op::Add { .. }))) => {
            let c = if x == t { y } else { x };
            Some(
                match (
                    matches!(first, Op::Add { .. }),
                    matches!(second, Op::Add { .. }),
                ) {
                    (true, true) => Op::AddAdd { t, a, b, c },
                    (true, false) => Op::AddSub { t, a, b, c },
                    (false, true) => Op::SubAdd { t, a, b, c },
                    (false, false) => Op::SubSub { t, a, b, c },
                },
            )
        }
        (Op::Add { dst, a, b }, Op::CheckLong { r }) if r == dst => {
            Some(Op::AddCheck { dst, a, b })
        }
        (Op::Sub { dst, a, b }, Op::CheckLong { r }) if r == dst => {
            Some(Op::SubCheck { dst, a, b })
        }
        (Op::Mul { dst, a, b }, Op::CheckLong { r }) if r == dst => {
            Some(Op::MulCheck { dst, a, b })
        }
        (Op::Add { dst: t, a, b }, Op::ModWhole { dst, a: u, b: m })
            if u == t && (a == t || b == t) =>
        {
            let t_first = a == t;
            let x = if t_first { b } else { a };
            Some(Op::AddModWhole {
                t,
                x,
                dst,
                m,
                t_first,
            })
        }
        (Op::BitNot { dst: t, a }, Op::AndWhole { dst, a: x, b: y })
            if (x == t || y == t) && dst != t =>
        {
            let t_first = x == t;
            let b = if t_first { y } else { x };
            Some(Op::NotAndWhole {
                t,
                a,
                b,
                dst,
                t_first,
            })
        }
        (Op::Add { dst: t, a, b }, Op::StoreReal { dst, src }) if src == t => {
            Some(Op::AddReal { t, dst, a, b })
        }
        (Op::Mod { dst: t, a, b }, Op::Sub { dst, a: x, b: y }) if dst == t && y == t && x != t => {
            Some(Op::SubMod { t, a, b, x })
        }
        (
            Op::Div { dst: t, a, b },
            Op::AddFixed {
                dst,
                a: x,
                b: y,
                decimals,
            },
        ) if dst != t && ((x == t && y == dst) || (y == t && x == dst)) => Some(Op::DivAddFixed {
            t,
            a,
            b,
            dst,
            decimals,
            t_first: x == t,
        }),
        (Op::Sub { dst: t, a, b }, Op::StoreReal { dst, src }) if src == t => {
            Some(Op::SubReal { t, dst, a, b })
        }
        (Op::Mul { dst: t, a, b }, Op::StoreReal { dst, src }) if src == t => {
            Some(Op::MulReal { t, dst, a, b })
        }
        (Op::Div { dst: t, a, b }, Op::StoreReal { dst, src }) if src == t => {
            Some(Op::DivReal { t, dst, a, b })
        }
        (
            first @ (Op::Add { dst: t, a, b } | Op::Sub { dst: t, a, b }),
            Op::Mul { dst, a: x, b: y },
        ) if dst == t && (x == t || y == t) => {
            let c = if x == t { y } else { x };
            Some(if matches!(first, Op::Add { .. }) {
                Op::AddMul { t, a, b, c }
            } else {
                Op::SubMul { t, a, b, c }
            })
        }
        (
            Op::BitAnd { dst: t, a, b },
            Op::BitOr {
                dst: t2,
                a: x,
                b: y,
            },
        ) if t2 == t && (x == t || y == t) => {
            let t_first = x == t;
            Some(Op::AndOr {
                t,
                a,
                b,
                x: if t_first { y } else { x },
                t_first,
            })
        }
        (Op::BitAnd { dst: t, a, b }, Op::XorWhole { dst, a: x, b: y })
            if (x == t && y == dst) || (y == t && x == dst) =>
        {
            Some(Op::AndXorWhole {
                t,
                a,
                b,
                dst,
                t_first: x == t,
            })
        }
        _ => None,
    }
}

impl Op {
    /// Where this instruction may send the interpreter, besides the next instruction.
    pub fn target(&self) -> Option<u32> {
        match *self {
            Op::Jump { target }
            | Op::Loop { target }
            | Op::LoopTight { target }
            | Op::JumpIfFalse { target, .. }
            | Op::JumpIfTrue { target, .. }
            | Op::JumpUnlessLt { target, .. }
            | Op::JumpUnlessLe { target, .. }
            | Op::JumpUnlessEq { target, .. }
            | Op::JumpUnlessNe { target, .. }
            | Op::JumpWhenLt { target, .. }
            | Op::JumpWhenLe { target, .. }
            | Op::JumpWhenEq { target, .. }
            | Op::JumpWhenNe { target, .. }
            | Op::AndJump { target, .. }
            | Op::TextJump { target, .. }
            | Op::Gosub { target } => Some(target),
            Op::ForCheck { exit, .. } | Op::ForTight { exit, .. } => Some(exit),
            Op::ForNext { body, .. } => Some(body),
            // Both ways on: the loop's body, or past the `for.next` at `at` (never the last
            // instruction, which is `End`); the larger is checked inside the chunk.
            Op::JumpNext { body, at, .. } => Some(body.max(at.saturating_add(1))),
            Op::WaitUntil { retry, .. } => Some(retry),
            _ => None,
        }
    }

    /// The largest register the interpreter's loop reads or writes directly for this
    /// instruction (the step of a `For` is the register after its limit); `None` for an
    /// instruction with no register or whose registers are read in a function of its own (with
    /// bounds checks). The interpreter checks once per entry that the value array holds every
    /// such register of a chunk, then reads them without a bounds check each.
    pub fn max_register(&self) -> Option<Reg> {
        let max = match *self {
            Op::Move { dst, src }
            | Op::StoreFixed { dst, src, .. }
            | Op::StoreLong { dst, src }
            | Op::StoreInt { dst, src }
            | Op::StoreReal { dst, src }
            | Op::StoreBit { dst, src } => dst.max(src),
            Op::Add { dst, a, b }
            | Op::Sub { dst, a, b }
            | Op::Mul { dst, a, b }
            | Op::Div { dst, a, b }
            | Op::Mod { dst, a, b }
            | Op::IMod { dst, a, b }
            | Op::IDiv { dst, a, b }
            | Op::BitAnd { dst, a, b }
            | Op::BitOr { dst, a, b }
            | Op::BitXor { dst, a, b }
            | Op::ModWhole { dst, a, b }
            | Op::AndWhole { dst, a, b }
            | Op::OrWhole { dst, a, b }
            | Op::XorWhole { dst, a, b }
            | Op::AddCheck { dst, a, b }
            | Op::SubCheck { dst, a, b }
            | Op::MulCheck { dst, a, b }
            | Op::AddCheckInt { dst, a, b }
            | Op::SubCheckInt { dst, a, b }
            | Op::MulCheckInt { dst, a, b }
            | Op::AddFixed { dst, a, b, .. }
            | Op::SubFixed { dst, a, b, .. }
            | Op::MulFixed { dst, a, b, .. }
            | Op::ArithFixed { dst, a, b, .. }
            | Op::Binary { dst, a, b, .. }
            | Op::Compare { dst, a, b, .. }
            | Op::Call { dst, a, b, .. } => dst.max(a).max(b),
            Op::AddLong { t, dst, a, b }
            | Op::SubLong { t, dst, a, b }
            | Op::MulLong { t, dst, a, b }
            | Op::IntLong { t, dst, a, b, .. }
            | Op::ModLong { t, dst, a, b }
            | Op::AndLong { t, dst, a, b }
            | Op::OrLong { t, dst, a, b }
            | Op::XorLong { t, dst, a, b }
            | Op::AddInt { t, dst, a, b }
            | Op::SubInt { t, dst, a, b }
            | Op::MulInt { t, dst, a, b }
            | Op::IntInt { t, dst, a, b, .. }
            | Op::MulAdd { t, c: dst, a, b }
            | Op::MulAcc {
                p: t,
                acc: dst,
                a,
                b,
            }
            | Op::MulDec {
                p: t,
                acc: dst,
                a,
                b,
            }
            | Op::AddReal { t, dst, a, b }
            | Op::SubReal { t, dst, a, b }
            | Op::MulReal { t, dst, a, b }
            | Op::DivReal { t, dst, a, b } => t.max(dst).max(a).max(b),
            // The product's temporary is the one after `acc`.
            Op::MulSumReal { acc, dst, a, b, .. } => acc.saturating_add(1).max(dst).max(a).max(b),
            // (Its terms' registers are counted with the chunk's table.)
            Op::SumReal { acc, p, dst, .. } => acc.max(p).max(dst),
            Op::MulAddCheck { t, a, b, c, .. }
            | Op::MulAddCheckModLong { t, a, b, c, .. }
            | Op::AddAdd { t, a, b, c }
            | Op::AddSub { t, a, b, c }
            | Op::SubAdd { t, a, b, c }
            | Op::SubSub { t, a, b, c }
            | Op::AddMul { t, a, b, c }
            | Op::SubMul { t, a, b, c } => t.max(a).max(b).max(c),
            Op::AddModLong { t, x, dst, m, .. } | Op::AddModWhole { t, x, dst, m, .. } => {
                t.max(x).max(dst).max(m)
            }
            Op::NotAndLong { t, a, b, dst, .. }
            | Op::NotAndWhole { t, a, b, dst, .. }
            | Op::AndOr {
                t, a, b, x: dst, ..
            }
            | Op::AndXorLong { t, a, b, dst, .. }
            | Op::AndXorWhole { t, a, b, dst, .. }
            | Op::DivAddLong { t, a, b, dst, .. }
            | Op::DivAddFixed { t, a, b, dst, .. } => t.max(a).max(b).max(dst),
            Op::SubMod { t, a, b, x } => t.max(a).max(b).max(x),
            // The chained instruction's second part is checked where it stays.
            Op::MulAddModWhole { t, a, b } | Op::QuotAddFixed { t, a, b } => t.max(a).max(b),
            Op::Offset2 { p, i, j, .. } => (p + 1).max(i).max(j),
            Op::OffsetTail { p, x, .. } => (p + 1).max(x),
            Op::AndJump { t, a, b, .. } => t.max(a).max(b),
            Op::Neg { dst, a } | Op::Not { dst, a } | Op::BitNot { dst, a } => dst.max(a),
            Op::Write { slot, src, .. } => slot.max(src),
            Op::JumpIfFalse { cond, .. }
            | Op::JumpIfTrue { cond, .. }
            | Op::WaitUntil { cond, .. }
            | Op::CheckLong { r: cond }
            | Op::CheckInt { r: cond } => cond,
            Op::JumpUnlessLt { a, b, .. }
            | Op::JumpUnlessLe { a, b, .. }
            | Op::JumpUnlessEq { a, b, .. }
            | Op::JumpUnlessNe { a, b, .. }
            | Op::JumpWhenLt { a, b, .. }
            | Op::JumpWhenLe { a, b, .. }
            | Op::JumpWhenEq { a, b, .. }
            | Op::JumpWhenNe { a, b, .. } => a.max(b),
            Op::WaitTime { src } | Op::Dwell { src, .. } => src,
            Op::Subscript { dst, src, .. } => dst.max(src),
            Op::LoadIdx {
                dst,
                base,
                idx,
                len,
            } => dst.max(idx).max(base + len.saturating_sub(1)),
            Op::StoreIdx {
                base,
                idx,
                src,
                len,
                ..
            }
            | Op::StoreIdxNext {
                base,
                idx,
                src,
                len,
                ..
            } => idx.max(src).max(base + len.saturating_sub(1)),
            Op::LoadAt {
                dst,
                base,
                off,
                len,
            } => dst.max(off).max(base + len.saturating_sub(1)),
            Op::StoreAt {
                base,
                off,
                src,
                len,
                ..
            } => off.max(src).max(base + len.saturating_sub(1)),
            Op::ForCheck { var, limit, .. }
            | Op::ForTight { var, limit, .. }
            | Op::ForNext { var, limit, .. }
            | Op::JumpNext { var, limit, .. } => var.max(limit.saturating_add(1)),
            _ => return None,
        };
        Some(max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fuse_specialises_in_place_and_keeps_every_instruction() {
        let temps = 100..110;
        let ops = vec![
            // @0: a whole PowerTools MOD; @1: one with decimals stays general.
            Op::ArithFixed {
                op: BinaryOp::Mod,
                dst: 1,
                a: 2,
                b: 3,
                decimals: 0,
            },
            Op::ArithFixed {
                op: BinaryOp::BitAnd,
                dst: 1,
                a: 2,
                b: 3,
                decimals: 2,
            },
            // @2 + @3: a multiply-add through a temporary.
            Op::Mul {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::Add {
                dst: 100,
                a: 100,
                b: 3,
            },
            // @4 + @5 + @6: the add's long store wins over the multiply-add.
            Op::Mul {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::Add {
                dst: 100,
                a: 100,
                b: 3,
            },
            Op::StoreLong { dst: 4, src: 100 },
            // @7: a jump to the `for.next` at @8.
            Op::Jump { target: 8 },
            Op::ForNext {
                var: 5,
                limit: 6,
                body: 0,
                decimals: 0,
            },
            Op::End,
        ];
        let mut fused = ops.clone();
        fuse(&mut fused, temps);
        assert_eq!(fused.len(), ops.len());
        assert_eq!(fused[0], Op::ModWhole { dst: 1, a: 2, b: 3 });
        assert_eq!(fused[1], ops[1]);
        assert_eq!(
            fused[2],
            Op::MulAdd {
                t: 100,
                a: 1,
                b: 2,
                c: 3
            }
        );
        assert_eq!(fused[3], ops[3]);
        assert_eq!(fused[4], ops[4]);
        assert_eq!(
            fused[5],
            Op::AddLong {
                t: 100,
                dst: 4,
                a: 100,
                b: 3
            }
        );
        assert_eq!(
            fused[7],
            Op::JumpNext {
                var: 5,
                limit: 6,
                body: 0,
                at: 8,
                decimals: 0
            }
        );
        // The second halves and the `for.next` stay in place for a jump to them.
        assert_eq!(fused[6], ops[6]);
        assert_eq!(fused[8], ops[8]);
        assert_eq!(fused[7].target(), Some(9));
    }

    #[test]
    fn fuse_makes_chains_of_three_and_four_through_a_temporary() {
        let temps = 100..110;
        let ops = vec![
            // @0..@3: a long's `a * b + c`, the temporary second in the add.
            Op::Mul {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::CheckLong { r: 100 },
            Op::Add {
                dst: 100,
                a: 3,
                b: 100,
            },
            Op::CheckLong { r: 100 },
            // @4..@6: `(x + t) MOD m` into a long.
            Op::Add {
                dst: 100,
                a: 4,
                b: 100,
            },
            Op::IMod {
                dst: 100,
                a: 100,
                b: 5,
            },
            Op::StoreLong { dst: 6, src: 100 },
            // @7..@9: `(NOT a) AND b` into a long.
            Op::BitNot { dst: 100, a: 1 },
            Op::BitAnd {
                dst: 100,
                a: 100,
                b: 2,
            },
            Op::StoreLong { dst: 7, src: 100 },
            // @10, @11: `(t + x) MOD m` into a whole fixed-point slot.
            Op::Add {
                dst: 100,
                a: 100,
                b: 4,
            },
            Op::ArithFixed {
                op: BinaryOp::Mod,
                dst: 8,
                a: 100,
                b: 5,
                decimals: 0,
            },
            // @12, @13: `b AND (NOT a)` into one; @14..@16: through a variable, left alone.
            Op::BitNot { dst: 100, a: 1 },
            Op::ArithFixed {
                op: BinaryOp::BitAnd,
                dst: 9,
                a: 2,
                b: 100,
                decimals: 0,
            },
            Op::Add { dst: 9, a: 9, b: 4 },
            Op::IMod { dst: 9, a: 9, b: 5 },
            Op::StoreLong { dst: 6, src: 9 },
            Op::End,
        ];
        let mut fused = ops.clone();
        fuse(&mut fused, temps);
        assert_eq!(
            fused[0],
            Op::MulAddCheck {
                t: 100,
                a: 1,
                b: 2,
                c: 3,
                t_first: false
            }
        );
        assert_eq!(
            fused[2],
            Op::AddCheck {
                dst: 100,
                a: 3,
                b: 100
            }
        );
        assert_eq!(
            fused[4],
            Op::AddModLong {
                t: 100,
                x: 4,
                dst: 6,
                m: 5,
                t_first: false
            }
        );
        // The last two of a triple are a pair of their own, for a jump to the second.
        assert_eq!(
            fused[5],
            Op::ModLong {
                t: 100,
                dst: 6,
                a: 100,
                b: 5
            }
        );
        assert_eq!(
            fused[7],
            Op::NotAndLong {
                t: 100,
                a: 1,
                b: 2,
                dst: 7,
                t_first: true
            }
        );
        assert_eq!(
            fused[8],
            Op::AndLong {
                t: 100,
                dst: 7,
                a: 100,
                b: 2
            }
        );
        assert_eq!(
            fused[10],
            Op::AddModWhole {
                t: 100,
                x: 4,
                dst: 8,
                m: 5,
                t_first: true
            }
        );
        assert_eq!(
            fused[11],
            Op::ModWhole {
                dst: 8,
                a: 100,
                b: 5
            }
        );
        assert_eq!(
            fused[12],
            Op::NotAndWhole {
                t: 100,
                a: 1,
                b: 2,
                dst: 9,
                t_first: false
            }
        );
        assert_eq!(&fused[14..], &ops[14..]);
        for (i, (f, o)) in fused.iter().zip(&ops).enumerate() {
            if matches!(i, 1 | 3 | 6 | 9 | 14 | 15 | 16 | 17) {
                assert_eq!(f, o, "@{i} stays as it was");
            }
        }
    }

    #[test]
    fn fuse_sums_makes_one_instruction_of_each_stored_sum_of_products() {
        let temps = 100..110;
        let mul = |dst, a, b| Op::Mul { dst, a, b };
        let add = |dst, a, b| Op::Add { dst, a, b };
        let sub = |dst, a, b| Op::Sub { dst, a, b };
        let store = |dst, src| Op::StoreReal { dst, src };
        let mut ops = vec![
            // @0..@7: `Y = a * b + c * d - e * f + x`, the product after the sum in an add.
            mul(100, 1, 2),
            mul(101, 3, 4),
            add(100, 101, 100),
            mul(101, 5, 6),
            sub(100, 100, 101),
            add(100, 100, 7),
            store(9, 100),
            // @7..@11: two terms only: left to `fuse`.
            mul(100, 1, 2),
            mul(101, 3, 4),
            add(100, 100, 101),
            store(9, 100),
            // @11..@16: a term reading the product before it: left alone.
            mul(100, 1, 2),
            mul(101, 3, 4),
            add(100, 100, 101),
            sub(100, 100, 101),
            store(9, 100),
            // @16..@22: a jump to its store (@21): left alone.
            mul(100, 1, 2),
            mul(101, 3, 4),
            add(100, 100, 101),
            mul(101, 5, 6),
            add(100, 100, 101),
            store(9, 100),
            Op::Jump { target: 21 },
            // @23..@28: `x - a * b - c * d`, stored into a long: not a real sum.
            mul(100, 1, 2),
            sub(100, 7, 100),
            mul(101, 3, 4),
            sub(100, 100, 101),
            Op::StoreLong { dst: 9, src: 100 },
            Op::End,
        ];
        let plain = ops.clone();
        let mut table = Vec::new();
        let mut asked = 0;
        fuse_sums(
            &mut ops,
            &temps,
            &mut || {
                asked += 1;
                50
            },
            &mut table,
        );
        assert_eq!(
            ops[0],
            Op::SumReal {
                acc: 100,
                p: 101,
                dst: 9,
                at: 0,
                slots: 7,
                terms: 4
            }
        );
        // Its other instructions, and every other one, stay as they were.
        assert_eq!(ops[1..], plain[1..]);
        let minus = 1 << 63;
        let term = |a, b, mask| Term { a, b, mask };
        assert_eq!(
            table,
            [
                term(5, 6, 0),
                term(1, 2, 0),
                term(3, 4, 0),
                term(5, 6, minus),
                term(7, 50, 0)
            ]
        );
        assert_eq!(asked, 1);
        // `fuse` keeps the sum whole: nothing inside it is fused, and it fuses with nothing.
        let mut fused = ops.clone();
        fuse(&mut fused, temps.clone());
        assert_eq!(fused[..7], ops[..7]);
    }

    #[test]
    fn fuse_makes_sums_of_products_through_a_temporary_product() {
        let temps = 100..110;
        let mul = |dst, a, b| Op::Mul { dst, a, b };
        let add = |dst, a, b| Op::Add { dst, a, b };
        let sub = |dst, a, b| Op::Sub { dst, a, b };
        let ops = vec![
            // @0..@2: `t0 = a * b`, then `t0 + c * d` (the accumulator first) and `t0 - e * f`.
            mul(100, 1, 2),
            mul(101, 3, 4),
            add(100, 100, 101),
            mul(101, 5, 6),
            sub(100, 100, 101),
            // @5, @6: the product first in the add.
            mul(101, 1, 3),
            add(100, 101, 100),
            // @7, @8: `p - acc` is not an accumulation: left alone.
            mul(101, 2, 4),
            sub(100, 101, 100),
            // @9..@11: the last term and its store are one instruction (the last two fused as
            // a pair too, for a jump to the second).
            mul(101, 5, 6),
            sub(100, 100, 101),
            Op::StoreReal { dst: 9, src: 100 },
            // @12, @13: a product in a variable (its write would be traced): not fused.
            mul(8, 1, 2),
            add(100, 100, 8),
            // @14..@16: the product not in the temporary after the sum's: the sum and its
            // store are a pair.
            mul(103, 5, 6),
            add(100, 100, 103),
            Op::StoreReal { dst: 9, src: 100 },
            // @17..@19: the temporary after the sum's is not one (the last of `temps`).
            mul(110, 5, 6),
            add(109, 109, 110),
            Op::StoreReal { dst: 9, src: 109 },
            Op::End,
        ];
        let mut fused = ops.clone();
        fuse(&mut fused, temps);
        let acc = |p, a, b| Op::MulAcc { p, a, b, acc: 100 };
        assert_eq!(fused[0], ops[0]);
        assert_eq!(fused[1], acc(101, 3, 4));
        assert_eq!(
            fused[3],
            Op::MulDec {
                p: 101,
                a: 5,
                b: 6,
                acc: 100
            }
        );
        assert_eq!(fused[5], acc(101, 1, 3));
        assert_eq!(fused[7], ops[7]);
        assert_eq!(
            fused[9],
            Op::MulSumReal {
                acc: 100,
                dst: 9,
                a: 5,
                b: 6,
                minus: true
            }
        );
        assert!(matches!(fused[10], Op::SubReal { t: 100, dst: 9, .. }));
        assert_eq!(fused[12], ops[12]);
        assert_eq!(fused[14], ops[14]);
        assert!(matches!(fused[15], Op::AddReal { t: 100, dst: 9, .. }));
        assert_eq!(fused[17], ops[17]);
        assert!(matches!(fused[18], Op::AddReal { t: 109, dst: 9, .. }));
        // The second halves stay in place for a jump to them.
        for i in [2, 4, 6, 8, 13] {
            assert_eq!(fused[i], ops[i], "@{i}");
        }
        assert_eq!(fused[1].max_register(), Some(101));
    }

    #[test]
    fn fuse_makes_a_multiply_add_with_the_product_on_either_side() {
        let temps = 100..110;
        let mul = Op::Mul {
            dst: 100,
            a: 1,
            b: 2,
        };
        for (x, y) in [(100, 3), (3, 100)] {
            let mut ops = vec![
                mul,
                Op::Add {
                    dst: 100,
                    a: x,
                    b: y,
                },
                Op::End,
            ];
            fuse(&mut ops, temps.clone());
            assert_eq!(
                ops[0],
                Op::MulAdd {
                    t: 100,
                    a: 1,
                    b: 2,
                    c: 3
                },
                "{x} + {y}"
            );
        }
        // `c - t` is not `t - c`: left alone.
        let sub = Op::Sub {
            dst: 100,
            a: 3,
            b: 100,
        };
        let mut ops = vec![mul, sub, Op::End];
        fuse(&mut ops, temps);
        assert_eq!(ops[..2], [mul, sub]);
    }

    #[test]
    fn a_bit_test_pairs_with_the_jump_on_its_result_only() {
        let and = Op::BitAnd {
            dst: 100,
            a: 1,
            b: 2,
        };
        for (jump, nonzero) in [
            (
                Op::JumpIfFalse {
                    cond: 100,
                    target: 9,
                },
                false,
            ),
            (
                Op::JumpIfTrue {
                    cond: 100,
                    target: 9,
                },
                true,
            ),
        ] {
            assert_eq!(
                pair(and, jump),
                Some(Op::AndJump {
                    t: 100,
                    a: 1,
                    b: 2,
                    target: 9,
                    nonzero
                })
            );
        }
        assert_eq!(
            pair(
                and,
                Op::JumpIfFalse {
                    cond: 101,
                    target: 9
                }
            ),
            None
        );
        assert_eq!(pair(and, Op::JumpIfTrue { cond: 1, target: 9 }), None);
    }

    /// `(x AND m) <> 0` and `= 0`, the zero on either side, jump as `jump.f`/`jump.t` on the
    /// `band`'s result; a comparison with another value, or of another register, is left.
    #[test]
    fn a_bit_test_compared_with_zero_is_fused_as_a_truth_test() {
        let and = Op::BitAnd {
            dst: 100,
            a: 1,
            b: 2,
        };
        // Register 7 holds 0, 8 holds -0, 9 holds 4.
        let constant = |r: Reg| match r {
            7 => Some(0.0),
            8 => Some(-0.0),
            9 => Some(4.0),
            _ => None,
        };
        let fused = |jump: Op| {
            let mut ops = [and, jump, Op::End];
            fuse_with_constants(&mut ops, &(100..108), &constant);
            assert_eq!(ops[1], jump, "the jump stays in place");
            match ops[0] {
                Op::AndJump {
                    t: 100,
                    a: 1,
                    b: 2,
                    target: 5,
                    nonzero,
                } => Some(nonzero),
                other => {
                    assert_eq!(other, and);
                    None
                }
            }
        };
        let (a, b, target) = (100, 7, 5);
        assert_eq!(fused(Op::JumpUnlessNe { a, b, target }), Some(false));
        assert_eq!(fused(Op::JumpWhenEq { a, b, target }), Some(false));
        assert_eq!(fused(Op::JumpUnlessEq { a, b, target }), Some(true));
        assert_eq!(fused(Op::JumpWhenNe { a, b, target }), Some(true));
        assert_eq!(
            fused(Op::JumpUnlessNe {
                a: 8,
                b: 100,
                target
            }),
            Some(false)
        );
        assert_eq!(fused(Op::JumpUnlessNe { a, b: 9, target }), None);
        assert_eq!(fused(Op::JumpUnlessNe { a: 101, b, target }), None);
        assert_eq!(
            fused(Op::JumpUnlessLt {
                a: 7,
                b: 100,
                target
            }),
            None
        );
    }

    #[test]
    fn fuse_with_constants_joins_a_two_subscript_offset_only_as_the_compiler_makes_it() {
        let (t, i, j, k, other) = (100, 1, 2, 50, 51);
        let constant = |r: Reg| match r {
            50 => Some(5.0),
            51 => Some(6.0),
            _ => None,
        };
        let offset = |p: Reg, s: Reg, n1: u32, n2: u32, k: Reg, fused_mul: bool| {
            let mul = if fused_mul {
                Op::MulAdd {
                    t: p,
                    a: p,
                    b: k,
                    c: s,
                }
            } else {
                Op::Mul { dst: p, a: p, b: k }
            };
            vec![
                Op::Subscript {
                    dst: p,
                    src: i,
                    len: n1,
                },
                Op::Subscript {
                    dst: s,
                    src: j,
                    len: n2,
                },
                mul,
                Op::Add { dst: p, a: p, b: s },
                Op::End,
            ]
        };
        let fused = |mut ops: Vec<Op>| {
            fuse_with_constants(&mut ops, &(100..108), &constant);
            ops[0]
        };
        let want = Op::Offset2 {
            p: t,
            i,
            j,
            lens: 4 << 16 | 5,
        };
        assert_eq!(fused(offset(t, t + 1, 4, 5, k, false)), want);
        assert_eq!(fused(offset(t, t + 1, 4, 5, k, true)), want);
        // Not adjacent temporaries, a multiplier that is not the second length, a temporary
        // that is a variable, a length past 16 bits: left alone.
        for ops in [
            offset(t, t + 2, 4, 5, k, false),
            offset(t, t + 1, 4, 5, other, false),
            offset(7, 8, 4, 5, k, false),
            offset(t, t + 1, 70_000, 5, k, false),
        ] {
            assert_eq!(fused(ops.clone()), ops[0]);
        }
    }

    #[test]
    fn fuse_makes_chains_of_additions_and_subtractions() {
        let temps = 100..110;
        let add = |dst, a, b| Op::Add { dst, a, b };
        let sub = |dst, a, b| Op::Sub { dst, a, b };
        let ops = vec![
            add(100, 1, 2),
            add(100, 100, 3),
            add(100, 1, 2),
            add(100, 3, 100),
            add(100, 1, 2),
            sub(100, 100, 3),
            sub(100, 1, 2),
            add(100, 3, 100),
            sub(100, 1, 2),
            sub(100, 100, 3),
            // `c - t` is not `t - c`: left alone.
            add(100, 1, 2),
            sub(100, 3, 100),
            Op::End,
        ];
        let mut fused = ops.clone();
        fuse(&mut fused, temps);
        let (t, a, b, c) = (100, 1, 2, 3);
        assert_eq!(fused[0], Op::AddAdd { t, a, b, c });
        assert_eq!(fused[2], Op::AddAdd { t, a, b, c });
        assert_eq!(fused[4], Op::AddSub { t, a, b, c });
        assert_eq!(fused[6], Op::SubAdd { t, a, b, c });
        assert_eq!(fused[8], Op::SubSub { t, a, b, c });
        assert_eq!(fused[10..], ops[10..]);
        for i in [1, 3, 5, 7, 9] {
            assert_eq!(fused[i], ops[i], "@{i}");
        }
    }

    #[test]
    fn fuse_makes_scaled_sums_and_real_quotients() {
        let temps = 100..110;
        let ops = vec![
            // `Y = Y + (A - B) * K`: the difference scaled, then the add with its store.
            Op::Sub {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::Mul {
                dst: 100,
                a: 100,
                b: 3,
            },
            Op::Add {
                dst: 100,
                a: 4,
                b: 100,
            },
            Op::StoreReal { dst: 4, src: 100 },
            // `K * (A + B)`: the sum second.
            Op::Add {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::Mul {
                dst: 100,
                a: 3,
                b: 100,
            },
            // `Q = A / B`.
            Op::Div {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::StoreReal { dst: 5, src: 100 },
            // `(A - B) * K` stored: the multiply goes with its store (a tie, and the store's
            // test is the dearer).
            Op::Sub {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::Mul {
                dst: 100,
                a: 100,
                b: 3,
            },
            Op::StoreReal { dst: 6, src: 100 },
            // Through a variable, not a temporary: left alone.
            Op::Sub { dst: 7, a: 1, b: 2 },
            Op::Mul { dst: 7, a: 7, b: 3 },
            Op::End,
        ];
        let mut fused = ops.clone();
        fuse(&mut fused, temps);
        let (t, a, b, c) = (100, 1, 2, 3);
        assert_eq!(fused[0], Op::SubMul { t, a, b, c });
        assert_eq!(
            fused[2],
            Op::AddReal {
                t,
                dst: 4,
                a: 4,
                b: t
            }
        );
        assert_eq!(fused[4], Op::AddMul { t, a, b, c });
        assert_eq!(fused[6], Op::DivReal { t, dst: 5, a, b });
        assert_eq!(fused[8], ops[8]);
        assert_eq!(
            fused[9],
            Op::MulReal {
                t,
                dst: 6,
                a: t,
                b: c
            }
        );
        assert_eq!(fused[11..], ops[11..]);
        for i in [1, 3, 5, 7, 10] {
            assert_eq!(fused[i], ops[i], "@{i}");
        }
    }

    #[test]
    fn fuse_saves_the_most_dispatches_not_the_first_fusion_found() {
        let temps = 100..110;
        // `Chk = (Chk + Acc * 3 + I) MOD m` into a whole variable: fusing the first add with
        // the multiply (`MulAdd`) and the second with the `MOD` (`AddModWhole`) saves two
        // dispatches; fusing the two adds (`AddAdd`) would save one.
        let ops = vec![
            Op::Mul {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::Add {
                dst: 100,
                a: 3,
                b: 100,
            },
            Op::Add {
                dst: 100,
                a: 100,
                b: 4,
            },
            Op::ArithFixed {
                op: BinaryOp::Mod,
                dst: 3,
                a: 100,
                b: 5,
                decimals: 0,
            },
            Op::End,
        ];
        let mut fused = ops.clone();
        fuse(&mut fused, temps);
        assert_eq!(
            fused[0],
            Op::MulAdd {
                t: 100,
                a: 1,
                b: 2,
                c: 3
            }
        );
        assert!(
            matches!(fused[2], Op::AddModWhole { t: 100, dst: 3, .. }),
            "{:?}",
            fused[2]
        );
        assert_eq!(fused[1], ops[1]);
    }

    #[test]
    fn fuse_makes_accumulating_chains_only_into_the_variable_they_read() {
        let temps = 100..110;
        let ops = vec![
            // @0..@2: `Q = Q + a \ b`; @3..@5: `X = (a AND b) XOR X`.
            Op::IDiv {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::Add {
                dst: 100,
                a: 7,
                b: 100,
            },
            Op::StoreLong { dst: 7, src: 100 },
            Op::BitAnd {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::BitXor {
                dst: 100,
                a: 100,
                b: 8,
            },
            Op::StoreLong { dst: 8, src: 100 },
            // @6, @7: `x OR (a AND b)` into the temporary; @8: its store.
            Op::BitAnd {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::BitOr {
                dst: 100,
                a: 3,
                b: 100,
            },
            Op::StoreLong { dst: 9, src: 100 },
            // @9, @10: `X = X XOR (a AND b)` into a whole fixed-point slot.
            Op::BitAnd {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::ArithFixed {
                op: BinaryOp::BitXor,
                dst: 8,
                a: 8,
                b: 100,
                decimals: 0,
            },
            // @11..@13: the sum stored into another variable than it reads: not fused.
            Op::IDiv {
                dst: 100,
                a: 1,
                b: 2,
            },
            Op::Add {
                dst: 100,
                a: 7,
                b: 100,
            },
            Op::StoreLong { dst: 6, src: 100 },
            Op::End,
        ];
        let mut fused = ops.clone();
        fuse(&mut fused, temps);
        let chain = |t_first| (1, 2, t_first);
        match fused[0] {
            Op::DivAddLong {
                t: 100,
                a,
                b,
                dst: 7,
                t_first,
            } => assert_eq!((a, b, t_first), chain(false)),
            other => panic!("@0: {other:?}"),
        }
        match fused[3] {
            Op::AndXorLong {
                t: 100,
                a,
                b,
                dst: 8,
                t_first,
            } => assert_eq!((a, b, t_first), chain(true)),
            other => panic!("@3: {other:?}"),
        }
        match fused[6] {
            Op::AndOr {
                t: 100,
                a,
                b,
                x: 3,
                t_first,
            } => assert_eq!((a, b, t_first), chain(false)),
            other => panic!("@6: {other:?}"),
        }
        match fused[9] {
            Op::AndXorWhole {
                t: 100,
                a,
                b,
                dst: 8,
                t_first,
            } => assert_eq!((a, b, t_first), chain(false)),
            other => panic!("@9: {other:?}"),
        }
        assert_eq!(fused[8], ops[8]);
        // `idiv` alone, then the add and its store as the pair they are.
        assert_eq!(fused[11], ops[11]);
        assert_eq!(
            fused[12],
            Op::AddLong {
                t: 100,
                dst: 6,
                a: 7,
                b: 100
            }
        );
    }

    #[test]
    fn an_instruction_stays_small() {
        assert!(std::mem::size_of::<Op>() <= 20);
    }
}
