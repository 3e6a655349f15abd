//! Loops whose body is arithmetic (loops, elements and strings inside), run outside the
//! interpreter on typed registers: integers as `i64`, reals as `f64` (`compile::body` says
//! which loops, and how their bodies are translated). The interpreter's `for.check` hands such
//! a `FOR` to the machine (`Machine::enter_loop`), as it does the loops of `vm::tight`; the
//! `loop` at the end of a `WHILE` hands it over from its second iteration
//! (`Machine::run_body`); a turn that starts where a run stopped inside one goes on in it
//! (`Machine::resume_loop`).
//!
//! Each value is the one the interpreter would compute, and each iteration counts the
//! interpreter's instructions. An iteration in which anything is not plain — a fault, an
//! overflow, an integer leaving ±2^53, a -0 reaching a real — is left undone (the variables it
//! wrote given back, its instructions uncounted) for the interpreter to run, with its fault if
//! it has one.

use super::exec::{
    basic_div_of, basic_mod_of, int as rounded_int, int16, int_rem_of, integer, keep_branch,
    put_text, round_long, text_index,
};
use super::tight::End;
use crate::compile::body::{cmp_of, Body, Code, Counter, Kind, Micro, Width, EXACT, INT_OPS};
use crate::fixed::{to_fixed, trunc_i32};

/// The fewest iterations of a loop worth leaving the interpreter for.
pub const FEWEST: f64 = 4.0;

/// `x` as an `Int`: a whole number within ±2^53 (a -0 as 0).
#[inline(always)]
fn to_int(x: f64) -> Option<i64> {
    let i = x as i64;
    (i as f64 == x && (-EXACT..=EXACT).contains(&i)).then_some(i)
}

/// Whether the `Int` `i` is within ±2^53.
#[inline(always)]
fn exact(i: i64) -> bool {
    (i.wrapping_add(EXACT) as u64) <= (2 * EXACT) as u64
}

/// Whether `i` fits `w`.
#[inline(always)]
fn fits(i: i64, w: Width) -> bool {
    match w {
        Width::Long => i32::try_from(i).is_ok(),
        Width::Short => i16::try_from(i).is_ok(),
    }
}

// The integer families on `Int`s (within ±2^53 each): `None` where the interpreter faults
// or its value is not exact as an `Int`. Within 32 bits `MOD`, `\` and PowerTools' `MOD`
// take the interpreter's integer path; past them its general one.

#[inline(always)]
fn add(x: i64, y: i64) -> Option<i64> {
    Some(x + y)
}

#[inline(always)]
fn sub(x: i64, y: i64) -> Option<i64> {
    Some(x - y)
}

#[inline(always)]
fn mul(x: i64, y: i64) -> Option<i64> {
    x.checked_mul(y)
}

#[inline(always)]
fn basic_mod(x: i64, y: i64) -> Option<i64> {
    match (i32::try_from(x), i32::try_from(y)) {
        (Ok(i), Ok(j)) if j != 0 => Some(i64::from(i.wrapping_rem(j))),
        _ => wide(basic_mod_of(x as f64, y as f64, false).ok()),
    }
}

#[inline(always)]
fn quot(x: i64, y: i64) -> Option<i64> {
    match (i32::try_from(x), i32::try_from(y)) {
        (Ok(i), Ok(j)) if j != 0 && !(i == i32::MIN && j == -1) => Some(i64::from(i / j)),
        _ => wide(basic_div_of(x as f64, y as f64, false).ok()),
    }
}

#[inline(always)]
fn rem(x: i64, y: i64) -> Option<i64> {
    match (i32::try_from(x), i32::try_from(y)) {
        (Ok(i), Ok(j)) if j != 0 => Some(i64::from(i.wrapping_rem(j))),
        _ if y == 0 => None,
        _ => wide(Some(int_rem_of(x as f64, y as f64, false))),
    }
}

#[inline(always)]
fn and(x: i64, y: i64) -> Option<i64> {
    Some(x & y)
}

#[inline(always)]
fn or(x: i64, y: i64) -> Option<i64> {
    Some(x | y)
}

#[inline(always)]
fn xor(x: i64, y: i64) -> Option<i64> {
    Some(x ^ y)
}

/// The general way's value as an `Int`, away from the loop.
#[cold]
#[inline(never)]
fn wide(x: Option<f64>) -> Option<i64> {
    x.and_then(to_int)
}

/// Copy `from[..N]` to `to[..N]` one `u64` at a time. The values were just stored one by
/// one: a wider load (LLVM would merge the copies into vector moves) cannot take them from the
/// stores in flight and waits until they are written (bench/loop ran 40 % slower so).
#[inline(always)]
fn copy_each<const N: usize>(to: &mut [u64; 256], from: &[u64; 256]) {
    for i in 0..N {
        // SAFETY: both are references to elements of the arrays (`N` ≤ 256), valid and
        // aligned; volatile only keeps each access one 8-byte move.
        unsafe { std::ptr::write_volatile(&mut to[i], std::ptr::read_volatile(&from[i])) }
    }
}

/// The local registers of a body, and a copy of those an iteration may have to give back as
/// they were at its start. Every local is written before it is read (a loaded one on entry,
/// a temporary by its statement), so what a run leaves in them is never seen by the next.
#[derive(Debug, Clone)]
pub struct Registers {
    r: [u64; 256],
    saved: [u64; 256],
    /// The body's arrays ([`Body::arrays`]), each within the values (checked on entry): the
    /// value register of its first element, and how many there are. A fixed table, next to
    /// the locals: an element's instruction reaches it without a register of its own (LLVM
    /// had no register to spare for a slice).
    elems: [(u32, u32); 256],
}

impl Default for Registers {
    fn default() -> Registers {
        Registers {
            r: [0; 256],
            saved: [0; 256],
            elems: [(0, 0); 256],
        }
    }
}

/// Run the iterations of the loop `body` that are plain, starting at its body's instruction
/// `from` (its start, or the start of a loop inside where a run stopped), on the values
/// `vals` (in the registers `regs`), counting the interpreter's instructions in `n` against
/// `budget` (the interpreter's test: after a `for.next` that goes round again, or a `loop`).
/// How it ended, and the body's instruction the interpreter goes on at when it did not end
/// the loop (an iteration left to it, a budget spent); `None` when it did not start (a
/// register outside `vals`, a value an `Int` cannot hold, a constant not what the translation
/// saw; a `FOR`'s step that is not a whole number other than 0, or fewer than [`FEWEST`]
/// iterations left; `from` not an instruction a run starts at).
pub fn run(
    vals: &mut [f64],
    regs: &mut Registers,
    body: &Body,
    strings: &mut [String],
    from: u16,
    n: &mut u64,
    budget: u64,
) -> Option<(End, u32)> {
    if body.highest as usize >= vals.len() || body.locals > 256 {
        return None;
    }
    // The first instruction of `from`: the start, or one a loop inside goes back to.
    let first = if from == 0 {
        0
    } else {
        let ops = body.ops();
        let at = body.op_of.iter().position(|&o| o == from)?;
        let heads = ops
            .iter()
            .any(|m| m.code == Code::Back && (m.k & 0xffff) as usize == at);
        if !heads {
            return None;
        }
        at
    };
    for (i, &(base, len)) in body.arrays().iter().enumerate() {
        if base as usize + len as usize > vals.len() {
            return None;
        }
        *regs.elems.get_mut(i)? = (base, len);
    }
    let r = &mut regs.r;
    for &(reg, local, kind) in &body.ins {
        let x = vals[reg as usize];
        r[local as usize] = match kind {
            // A -0 is no `Int` (variables never hold one; a constant might).
            Kind::Int if x.to_bits() != (-0.0f64).to_bits() => to_int(x)? as u64,
            Kind::Int => return None,
            Kind::Real => x.to_bits(),
        };
    }
    for &(local, c) in &body.consts {
        if r[local as usize] as i64 != c {
            return None;
        }
    }
    let round = match body.counter {
        // A run going on inside an iteration goes on however few are left after it.
        Some(c) => Some(round(vals, r, c, if from == 0 { FEWEST } else { 0.0 })?),
        None => None,
    };
    // Counted as if the run started at the body's start, the instructions before `from` not
    // run (a count below them wraps, and comes back at the first iteration's end).
    let start = (*n).wrapping_sub(u64::from(from));
    let (end, stopped, count) = match round {
        // A body holding loops has its own copy: their instructions in the same one cost
        // `bench/loop` 8 % more instructions (LLVM keeping the instruction's index in memory).
        // (Strings have a third: theirs in the second cost Bubble sort's body 7 % more.)
        Some(round) if body.text => {
            iterate::<true, true, true>(vals, regs, body, strings, first, start, budget, round)
        }
        Some(round) if body.nested => {
            iterate::<true, true, false>(vals, regs, body, strings, first, start, budget, round)
        }
        Some(round) => {
            iterate::<true, false, false>(vals, regs, body, strings, 0, start, budget, round)
        }
        None => {
            let (none, s) = (Round::NONE, start);
            match (body.text, body.nested) {
                (true, _) => {
                    iterate::<false, true, true>(vals, regs, body, strings, first, s, budget, none)
                }
                (false, true) => {
                    iterate::<false, true, false>(vals, regs, body, strings, first, s, budget, none)
                }
                (false, false) => {
                    iterate::<false, false, false>(vals, regs, body, strings, 0, s, budget, none)
                }
            }
        }
    };
    let r = &regs.r;
    let (resume, count) = match (end, stopped) {
        // Left undone from the start of an iteration: the first started at `from`.
        (End::Slow, None) if count == start => (from, count.wrapping_add(u64::from(from))),
        (End::Slow, None) => (0, count),
        // Unfinished at an instruction: those before it ran (those jumped over not counted),
        // it did not. (In this order: jumps taken may have uncounted more than the count
        // held when the run started.)
        (End::Slow, Some(at)) => (
            at,
            count.wrapping_add(u64::from(at)).wrapping_sub(body.count),
        ),
        (_, at) => (at.unwrap_or(0), count),
    };
    // The temporaries live where the interpreter goes on (none at an iteration's start).
    if end != End::Done {
        for &(reg, local, kind) in body.live.get(usize::from(resume)).into_iter().flatten() {
            let x = r[local as usize];
            vals[reg as usize] = match kind {
                Kind::Int => x as i64 as f64,
                Kind::Real => f64::from_bits(x),
            };
        }
    }
    *n = count;
    if let Some(c) = body.counter {
        let (var_local, var_reg) = c.var;
        vals[var_reg as usize] = r[var_local as usize] as i64 as f64;
    }
    for &(reg, local, kind) in &body.outs {
        let x = r[local as usize];
        vals[reg as usize] = match kind {
            Kind::Int => x as i64 as f64,
            Kind::Real => f64::from_bits(x),
        };
    }
    Some((end, u32::from(resume)))
}

/// The byte order of `x` and `y` (as `Ord` on slices gives it), a short string's compared
/// here: a call to `memcmp` would make LLVM load again every constant the runner keeps in a
/// register.
#[inline(always)]
fn text_order(x: &[u8], y: &[u8]) -> std::cmp::Ordering {
    let n = x.len().min(y.len());
    if n > 16 {
        return x.cmp(y);
    }
    for (a, b) in x.iter().zip(y).take(n) {
        if a != b {
            return a.cmp(b);
        }
    }
    x.len().cmp(&y.len())
}

/// The value register of element `off` of the body's array `arr`, when it is one of its
/// (`elems` as [`Registers::elems`]).
#[inline(always)]
fn element(elems: &[(u32, u32); 256], arr: u8, off: i64) -> Option<usize> {
    let (base, len) = elems[usize::from(arr)];
    ((off as u64) < u64::from(len)).then(|| base as usize + off as usize)
}

/// How a `FOR` goes round: its variable's local, its step, and the bounds it stays within
/// (the limit's floor going up, its ceiling going down) and the width it is stored in.
#[derive(Debug, Clone, Copy)]
struct Round {
    var: usize,
    step: i64,
    up: bool,
    hi: i64,
    lo: i64,
    width: Width,
}

impl Round {
    /// For a loop without a counter (never read).
    const NONE: Round = Round {
        var: 0,
        step: 0,
        up: true,
        hi: 0,
        lo: 0,
        width: Width::Long,
    };
}

/// How the `FOR` of `c` goes round from the values `vals` and the locals `r` loaded; `None`
/// when the step is not a whole number other than 0, or fewer than `fewest` iterations are
/// left.
fn round(vals: &[f64], r: &[u64; 256], c: Counter, fewest: f64) -> Option<Round> {
    let limit = *vals.get(c.limit as usize)?;
    let step = to_int(*vals.get(c.limit as usize + 1)?).filter(|&s| s != 0)?;
    let var = usize::from(c.var.0);
    let left = (limit - r[var] as i64 as f64) / step as f64;
    // NaN (an infinite limit less an infinite one…) is no count.
    if left.partial_cmp(&(fewest - 1.0)).is_none_or(|o| o.is_lt()) {
        return None;
    }
    let width = if c.short { Width::Short } else { Width::Long };
    // The loop goes round while the variable (an integer) is at most the limit's floor (up)
    // or at least its ceiling (down); never past a limit that is not a number.
    let bound = |x: f64| x.clamp(-(EXACT as f64), EXACT as f64) as i64;
    let (hi, lo) = if limit.is_nan() {
        (i64::MIN, i64::MAX)
    } else {
        (bound(limit.floor()), bound(limit.ceil()))
    };
    Some(Round {
        var,
        step,
        up: step > 0,
        hi,
        lo,
        width,
    })
}

/// Run iterations of `body` (one holding loops when `NESTED`) on the locals `r`, the first
/// from its instruction `first` (0 unless `NESTED`),
/// counting the interpreter's instructions from `count` (as if the first had started at the
/// body's start) against `budget`; a `FOR`'s (`COUNTED`) going round as `round` says, any
/// other's by its `loop`. How it ended; the body's instruction an iteration was left
/// unfinished in (its count not yet taken back to it), or where the budget was spent at the
/// start of a loop inside (counted), or `None` when it was left undone from its start (its
/// variables given back as they were, and the count as it was then); and the count.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn iterate<const COUNTED: bool, const NESTED: bool, const TEXT: bool>(
    vals: &mut [f64],
    regs: &mut Registers,
    body: &Body,
    strings: &mut [String],
    first: usize,
    mut count: u64,
    budget: u64,
    round: Round,
) -> (End, Option<u16>, u64) {
    let Round {
        var,
        step,
        up,
        hi,
        lo,
        width,
    } = round;
    let Registers { r, saved, elems } = regs;
    let kept = body.kept.len().min(256);
    debug_assert!(body
        .kept
        .iter()
        .enumerate()
        .all(|(i, &k)| usize::from(k) == i));
    let ops = body.ops();
    let base = ops.as_ptr();
    // Elements are reached from here: every array of the body is within the values (`run`).
    let vals = vals.as_mut_ptr();
    let mut at_start;
    let mut first = first;
    // The body's instruction an iteration stopped in (counted from its start).
    let mut stopped = 0u16;
    let end = 'iterations: loop {
        // The kept variables are the first locals: a few are copied by a fixed number of
        // moves (only for a body whose iterations are left undone from their start).
        if body.snapshot {
            if kept <= 4 {
                copy_each::<4>(saved, r);
            } else {
                for i in 0..kept {
                    // SAFETY: as `copy_each`'s.
                    unsafe {
                        std::ptr::write_volatile(&mut saved[i], std::ptr::read_volatile(&r[i]))
                    }
                }
            }
        }
        at_start = count;
        count = count.wrapping_add(body.count);
        let at = if NESTED {
            std::mem::take(&mut first)
        } else {
            0
        };
        debug_assert!(at < ops.len());
        // SAFETY: `first` is an instruction of `ops` (`run` found it there).
        let mut pc: *const Micro = unsafe { base.add(at) };
        macro_rules! int {
            ($l:expr) => {
                r[$l as usize] as i64
            };
        }
        macro_rules! real {
            ($l:expr) => {
                f64::from_bits(r[$l as usize])
            };
        }
        macro_rules! set_int {
            ($l:expr, $x:expr) => {
                r[$l as usize] = ($x) as u64
            };
        }
        macro_rules! set_real {
            ($l:expr, $x:expr) => {
                r[$l as usize] = f64::to_bits($x)
            };
        }
        macro_rules! undone {
            () => {{
                // SAFETY: both point into `ops`.
                let at = unsafe { pc.offset_from(base) } as usize;
                stopped = body.op_of.get(at - 1).copied().unwrap_or(0);
                break 'iterations End::Slow;
            }};
        }
        // A result the interpreter's function gives as an `f64`, taken as an `Int`.
        macro_rules! from_real {
            ($d:expr, $x:expr) => {{
                match $x.ok().and_then(to_int) {
                    Some(i) => set_int!($d, i),
                    None => undone!(),
                }
            }};
        }
        // A jump taken (`Code::Jump`): the interpreter's instructions it skips are not run.
        // It stays a branch (`exec::keep_branch`): chosen by a conditional move, the next
        // instruction's dispatch would wait for the comparison.
        macro_rules! jump {
            ($k:expr) => {{
                keep_branch();
                let k: i64 = $k;
                count = count.wrapping_sub((k >> 16) as u64);
                // SAFETY: a jump's target is an instruction of `ops` (`Body::ops`).
                pc = unsafe { base.add((k & 0xffff) as usize) };
            }};
        }
        loop {
            debug_assert!(ops.as_ptr_range().contains(&pc));
            // SAFETY: `pc` points at the first instruction or a jump's target, or one past an
            // instruction that is not the last (`Next`, which leaves this loop), or past the
            // `Back` after a `for.next` (not the last either): each is an instruction of `ops`
            // (`Body::ops`).
            let m = unsafe { *pc };
            pc = unsafe { pc.add(1) };
            // (`k` widened once: its 32-bit and 64-bit forms would take two registers.)
            let (d, a, b, k) = (m.d, m.a, m.b, i64::from(m.k));
            // An integer family: `$f` of `a` and `b` (`$k`: the constant instead), stored
            // within ±2^53, or (`$w` 1) into a long, or (`$w` 2) into an INTEGER.
            macro_rules! family {
                ($f:ident, $k:expr, $w:expr) => {{
                    let y = if $k { k } else { int!(b) };
                    match $f(int!(a), y) {
                        Some(x)
                            if (match $w {
                                1 => fits(x, Width::Long),
                                2 => fits(x, Width::Short),
                                _ => exact(x),
                            }) =>
                        {
                            set_int!(d, x)
                        }
                        _ => undone!(),
                    }
                }};
            }
            // The interpreter's budget test where the body's `a | b << 8` last instructions
            // are left: spent, the run stops there (counted to there).
            macro_rules! budget_test {
                () => {{
                    let left = u64::from(a) | u64::from(b) << 8;
                    let done = count.wrapping_sub(left);
                    if done >= budget {
                        stopped = (body.count - left) as u16;
                        count = done;
                        break 'iterations End::Budget;
                    }
                }};
            }
            match m.code {
                Code::Mov => r[d as usize] = r[a as usize],
                Code::AddI => family!(add, false, 0),
                Code::AddK => family!(add, true, 0),
                Code::AddL => family!(add, false, 1),
                Code::AddKL => family!(add, true, 1),
                Code::AddS => family!(add, false, 2),
                Code::AddKS => family!(add, true, 2),
                Code::SubI => family!(sub, false, 0),
                Code::SubK => family!(sub, true, 0),
                Code::SubL => family!(sub, false, 1),
                Code::SubKL => family!(sub, true, 1),
                Code::SubS => family!(sub, false, 2),
                Code::SubKS => family!(sub, true, 2),
                Code::MulI => family!(mul, false, 0),
                Code::MulK => family!(mul, true, 0),
                Code::MulL => family!(mul, false, 1),
                Code::MulKL => family!(mul, true, 1),
                Code::MulS => family!(mul, false, 2),
                Code::MulKS => family!(mul, true, 2),
                Code::ModI => family!(basic_mod, false, 0),
                Code::ModK => family!(basic_mod, true, 0),
                Code::ModL => family!(basic_mod, false, 1),
                Code::ModKL => family!(basic_mod, true, 1),
                Code::ModS => family!(basic_mod, false, 2),
                Code::ModKS => family!(basic_mod, true, 2),
                Code::QuotI => family!(quot, false, 0),
                Code::QuotK => family!(quot, true, 0),
                Code::QuotL => family!(quot, false, 1),
                Code::QuotKL => family!(quot, true, 1),
                Code::QuotS => family!(quot, false, 2),
                Code::QuotKS => family!(quot, true, 2),
                Code::RemI => family!(rem, false, 0),
                Code::RemK => family!(rem, true, 0),
                Code::RemL => family!(rem, false, 1),
                Code::RemKL => family!(rem, true, 1),
                Code::RemS => family!(rem, false, 2),
                Code::RemKS => family!(rem, true, 2),
                Code::AndI => family!(and, false, 0),
                Code::AndK => family!(and, true, 0),
                Code::AndL => family!(and, false, 1),
                Code::AndKL => family!(and, true, 1),
                Code::AndS => family!(and, false, 2),
                Code::AndKS => family!(and, true, 2),
                Code::OrI => family!(or, false, 0),
                Code::OrK => family!(or, true, 0),
                Code::OrL => family!(or, false, 1),
                Code::OrKL => family!(or, true, 1),
                Code::OrS => family!(or, false, 2),
                Code::OrKS => family!(or, true, 2),
                Code::XorI => family!(xor, false, 0),
                Code::XorK => family!(xor, true, 0),
                Code::XorL => family!(xor, false, 1),
                Code::XorKL => family!(xor, true, 1),
                Code::XorS => family!(xor, false, 2),
                Code::XorKS => family!(xor, true, 2),
                Code::NegI => set_int!(d, -int!(a)),
                Code::BitNotI => {
                    let x = !int!(a);
                    if !exact(x) {
                        undone!();
                    }
                    set_int!(d, x);
                }
                Code::NotI => set_int!(d, i64::from(int!(a) == 0)),
                Code::CmpI => {
                    set_int!(d, i64::from(cmp_of(k as u8).test_ord(&int!(a), &int!(b))))
                }
                Code::FitI => {
                    let x = int!(a);
                    let w = if k == 0 { Width::Long } else { Width::Short };
                    if !fits(x, w) {
                        undone!();
                    }
                    set_int!(d, x);
                }
                Code::AddR => set_real!(d, real!(a) + real!(b)),
                Code::SubR => set_real!(d, real!(a) - real!(b)),
                Code::MulR => set_real!(d, real!(a) * real!(b)),
                Code::DivR => {
                    let y = real!(b);
                    if y == 0.0 {
                        undone!();
                    }
                    set_real!(d, real!(a) / y);
                }
                Code::NegR => set_real!(d, -real!(a)),
                Code::RemR => {
                    let y = real!(b);
                    if y == 0.0 {
                        undone!();
                    }
                    set_real!(d, int_rem_of(real!(a), y, false));
                }
                Code::IntR => {
                    let op = INT_OPS[(k as usize) % INT_OPS.len()];
                    from_real!(d, integer(op, real!(a), real!(b), false))
                }
                Code::BitNotR => {
                    let x = !rounded_int(real!(a));
                    if !exact(x) {
                        undone!();
                    }
                    set_int!(d, x);
                }
                Code::CmpR => set_int!(d, i64::from(cmp_of(k as u8).test(real!(a), real!(b)))),
                Code::NotR => set_int!(d, i64::from(real!(a) == 0.0)),
                Code::ToR => set_real!(d, int!(a) as f64),
                Code::ToRSigned => {
                    let x = int!(a);
                    if x == 0 {
                        // `k` 1: a `MOD`'s zero, which has the sign of its dividend `b`.
                        if k == 0 {
                            undone!();
                        }
                        set_real!(d, if int!(b) < 0 { -0.0 } else { 0.0 });
                    } else {
                        set_real!(d, x as f64);
                    }
                }
                Code::IntSigned => {
                    let x = int!(a);
                    // `k` 1: a `MOD`'s zero, which has the sign of its dividend `b`.
                    if x == 0 && (k == 0 || int!(b) < 0) {
                        undone!();
                    }
                    set_int!(d, x);
                }
                Code::LongR => {
                    let x = real!(a);
                    let v = if f64::from(trunc_i32(x)) == x {
                        Some(x + 0.0)
                    } else {
                        round_long(x)
                    };
                    from_real!(d, v.ok_or(()))
                }
                Code::ShortR => from_real!(d, int16(real!(a)).ok_or(())),
                // As `div` then `store.f0`: a division by zero is the interpreter's fault.
                Code::DivFixedI => {
                    let y = int!(b);
                    if y == 0 {
                        undone!();
                    }
                    match to_fixed(int!(a) as f64 / y as f64, 0) {
                        Some(x) => set_int!(d, x as i64),
                        None => undone!(),
                    }
                }
                // As `div`, then `add.f0` or `sub.f0` (the divisor a constant other than 0).
                // (Two handlers: one testing the code would keep it in a register through
                // every other instruction's dispatch.)
                Code::AddDivFixedI => match to_fixed(int!(a) as f64 + int!(b) as f64 / k as f64, 0)
                {
                    Some(x) => set_int!(d, x as i64),
                    None => undone!(),
                },
                Code::SubDivFixedI => match to_fixed(int!(a) as f64 - int!(b) as f64 / k as f64, 0)
                {
                    Some(x) => set_int!(d, x as i64),
                    None => undone!(),
                },
                Code::FixedR => match to_fixed(real!(a), k as u8) {
                    Some(x) if k == 0 => from_real!(d, Ok::<f64, ()>(x)),
                    Some(x) => set_real!(d, x),
                    None => undone!(),
                },
                Code::RealR => {
                    let x = real!(a);
                    if !x.is_finite() {
                        undone!();
                    }
                    set_real!(d, x);
                }
                Code::CheckR => {
                    let x = real!(a);
                    let ok = if k == 0 {
                        (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&x)
                    } else {
                        (-32768.0..=32767.0).contains(&x)
                    };
                    if !ok {
                        undone!();
                    }
                }
                Code::Jump => jump!(k),
                Code::JzI => {
                    if int!(a) == 0 {
                        jump!(k);
                    }
                }
                Code::JnzI => {
                    if int!(a) != 0 {
                        jump!(k);
                    }
                }
                Code::JzR => {
                    if real!(a) == 0.0 {
                        jump!(k);
                    }
                }
                Code::JnzR => {
                    if real!(a) != 0.0 {
                        jump!(k);
                    }
                }
                Code::JeqI => {
                    if int!(a) == int!(b) {
                        jump!(k);
                    }
                }
                Code::JneI => {
                    if int!(a) != int!(b) {
                        jump!(k);
                    }
                }
                Code::JltI => {
                    if int!(a) < int!(b) {
                        jump!(k);
                    }
                }
                Code::JleI => {
                    if int!(a) <= int!(b) {
                        jump!(k);
                    }
                }
                Code::JgtI => {
                    if int!(a) > int!(b) {
                        jump!(k);
                    }
                }
                Code::JgeI => {
                    if int!(a) >= int!(b) {
                        jump!(k);
                    }
                }
                Code::JcmpR => {
                    if cmp_of(d / 2).test(real!(a), real!(b)) == (d % 2 == 1) {
                        jump!(k);
                    }
                }
                Code::IdxI => {
                    let x = int!(a);
                    if !(0..k).contains(&x) {
                        undone!();
                    }
                    set_int!(d, x);
                }
                Code::Idx2 => {
                    let (i, j) = (int!(a), int!(b));
                    let (n, m) = (k & 0xffff, (k >> 16) & 0xffff);
                    if !((0..n).contains(&i) && (0..m).contains(&j)) {
                        undone!();
                    }
                    set_int!(d, i * m + j);
                }
                Code::IdxR => {
                    let x = real!(a).round_ties_even();
                    if !(x >= 0.0 && x < k as f64) {
                        undone!();
                    }
                    set_int!(d, x as i64);
                }
                Code::LoadI => match element(elems, b, int!(a)) {
                    Some(at) => {
                        // SAFETY: an element of one of the body's arrays, each within the
                        // values (`run`); an instruction names only the body's (`Body::ops`).
                        let x = unsafe { *vals.add(at) };
                        // An element of a long or INTEGER array is a 32-bit integer, never
                        // -0 (the bits tell both); any other is left to the interpreter.
                        let i = x as i32;
                        if f64::from(i).to_bits() != x.to_bits() {
                            undone!();
                        }
                        set_int!(d, i64::from(i));
                    }
                    None => undone!(),
                },
                // SAFETY (elements): as `LoadI`'s.
                Code::LoadR => match element(elems, b, int!(a)) {
                    Some(at) => set_real!(d, unsafe { *vals.add(at) }),
                    None => undone!(),
                },
                Code::PutI => {
                    let x = int!(a);
                    let fits = match k {
                        1 => fits(x, Width::Long),
                        2 => fits(x, Width::Short),
                        _ => true,
                    };
                    match element(elems, d, int!(b)) {
                        Some(at) if fits => unsafe { *vals.add(at) = x as f64 },
                        _ => undone!(),
                    }
                }
                Code::PutR => match element(elems, d, int!(b)) {
                    Some(at) => unsafe { *vals.add(at) = real!(a) },
                    None => undone!(),
                },
                Code::Back | Code::ForCheckI | Code::ForNextL | Code::ForNextS if !NESTED => {
                    undone!()
                }
                Code::TextCmp | Code::TextSet | Code::TextPut if !TEXT => undone!(),
                // A handle that is none is the interpreter's fault to give.
                Code::TextCmp => {
                    let n = strings.len();
                    match (text_index(real!(a), n), text_index(real!(b), n)) {
                        (Some(x), Some(y)) => {
                            let (x, y) = (strings[x].as_bytes(), strings[y].as_bytes());
                            // (`k` as `cmp_index` numbers them: `=`, `<>`, `<`, `<=`, `>`,
                            // `>=`; an equality first tests the lengths.)
                            let holds = if k < 2 {
                                (x.len() == y.len() && text_order(x, y).is_eq()) == (k == 0)
                            } else {
                                let o = text_order(x, y);
                                match k {
                                    2 => o.is_lt(),
                                    3 => o.is_le(),
                                    4 => o.is_gt(),
                                    _ => o.is_ge(),
                                }
                            };
                            set_int!(d, i64::from(holds));
                        }
                        _ => undone!(),
                    }
                }
                // Cell 0 is the empty string every unassigned string reads: never a variable's.
                Code::TextSet => {
                    let n = strings.len();
                    match (text_index(real!(a), n), text_index(real!(b), n)) {
                        (Some(cell), Some(from)) if cell != 0 => put_text(strings, cell, from),
                        _ => undone!(),
                    }
                }
                // An element holds its own cell's handle (never the empty string's).
                Code::TextPut => {
                    let n = strings.len();
                    let cell = element(elems, d, int!(b))
                        .and_then(|at| text_index(unsafe { *vals.add(at) }, n));
                    match (cell, text_index(real!(a), n)) {
                        (Some(cell), Some(from)) if cell != 0 => put_text(strings, cell, from),
                        _ => undone!(),
                    }
                }
                Code::Back => {
                    jump!(k);
                    // There the interpreter tests its budget, the body's instructions from
                    // there on not run.
                    budget_test!();
                }
                // After a `GOSUB`, a `RETURN` or a `Call Program`, the interpreter tests its
                // budget: the run stops at the next instruction when it is spent.
                Code::Yield => budget_test!(),
                Code::ForCheckI => {
                    let (x, l, s) = (int!(a), int!(b), int!(d));
                    if s == 0 {
                        undone!();
                    }
                    if (s > 0 && x > l) || (s < 0 && x < l) {
                        jump!(k);
                    }
                }
                Code::ForNextL | Code::ForNextS => {
                    let s = int!(b);
                    let v = int!(d) + s;
                    let w = if m.code == Code::ForNextL {
                        Width::Long
                    } else {
                        Width::Short
                    };
                    if !fits(v, w) {
                        undone!();
                    }
                    set_int!(d, v);
                    let l = int!(a);
                    // On to the `Back` after it, or past it.
                    let round = (s > 0 && v <= l) || (s < 0 && v >= l);
                    // SAFETY: a `Back` follows, not the last instruction (`Body::ops`).
                    pc = unsafe { pc.add(usize::from(!round)) };
                }
                Code::Next => {
                    count = count.wrapping_sub((k >> 16) as u64);
                    break;
                }
                Code::Exit => {
                    count = count.wrapping_sub((k >> 16) as u64);
                    break 'iterations End::Done;
                }
            }
        }
        // The `for.next`, or the `loop` (which the interpreter's test follows).
        if COUNTED {
            let v = int!(var) + step;
            if !fits(v, width) {
                stopped = (body.count - 1) as u16;
                break End::Slow;
            }
            set_int!(var, v);
            if !(if up { v <= hi } else { v >= lo }) {
                break End::Done;
            }
        }
        if count >= budget {
            break End::Budget;
        }
    };
    if end == End::Slow && body.snapshot {
        r[..kept].copy_from_slice(&saved[..kept]);
        return (end, None, at_start);
    }
    (end, Some(stopped), count)
}
