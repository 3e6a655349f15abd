//! Loops whose body is straight-line arithmetic, run outside the interpreter on typed
//! registers: integers as `i64`, reals as `f64` (`compile::body` says which loops, and how
//! their bodies are translated). The interpreter's `for.check` hands such a loop to the
//! machine (`Machine::enter_loop`), as it does the loops of `vm::tight`.
//!
//! Each value is the one the interpreter would compute, and each iteration counts the
//! interpreter's instructions. An iteration in which anything is not plain — a fault, an
//! overflow, an integer leaving ±2^53, a -0 reaching a real — is left undone (the variables it
//! wrote given back, its instructions uncounted) for the interpreter to run, with its fault if
//! it has one.

use super::exec::{
    basic_div_of, basic_mod_of, int as rounded_int, int16, int_rem_of, integer, round_long,
};
use super::tight::End;
use crate::compile::body::{Body, Kind, Micro, Width, EXACT};
use crate::fixed::to_fixed;

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

/// Run the iterations of the loop `body` that are plain, starting at the start of its body,
/// on the values `vals`, counting the interpreter's instructions in `n` against `budget` (the
/// interpreter's test: after a `for.next` that goes round again). Where it stopped; `None`
/// when it did not start (a register outside `vals`, a value an `Int` cannot hold, a step
/// that is not a whole number other than 0, fewer than [`FEWEST`] iterations left).
pub fn run(vals: &mut [f64], body: &Body, n: &mut u64, budget: u64) -> Option<End> {
    if body.highest as usize >= vals.len() || body.locals > 256 {
        return None;
    }
    let mut r = [0u64; 256];
    for &(reg, local, kind) in &body.ins {
        let x = vals[reg as usize];
        r[local as usize] = match kind {
            // A -0 is no `Int` (variables never hold one; a constant might).
            Kind::Int if x.to_bits() != (-0.0f64).to_bits() => to_int(x)? as u64,
            Kind::Int => return None,
            Kind::Real => x.to_bits(),
        };
    }
    let limit = vals[body.limit as usize];
    let step = to_int(vals[body.limit as usize + 1]).filter(|&s| s != 0)?;
    let var = body.var.0 as usize;
    let left = (limit - r[var] as i64 as f64) / step as f64;
    // NaN (an infinite limit less an infinite one…) is no count.
    if left.partial_cmp(&(FEWEST - 1.0)).is_none_or(|o| o.is_lt()) {
        return None;
    }
    let width = if body.short {
        Width::Short
    } else {
        Width::Long
    };
    let up = step > 0;
    let ops = body.ops();
    let skips = &body.skips[..];
    debug_assert_eq!(ops.len(), skips.len());
    let mut saved = [0u64; 256];
    let mut count = *n;
    let mut at_start;
    let end = 'iterations: loop {
        for &k in &body.kept {
            saved[k as usize] = r[k as usize];
        }
        at_start = count;
        count += body.count;
        let mut pc = 0usize;
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
            () => {
                break 'iterations End::Slow
            };
        }
        // An `Int` result, which must stay within ±2^53.
        macro_rules! checked {
            ($d:expr, $x:expr) => {{
                let x: i64 = $x;
                if !exact(x) {
                    undone!();
                }
                set_int!($d, x);
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
        // A jump taken from the instruction before `pc` to `t`: the interpreter's instructions
        // it skips are not run.
        macro_rules! jump {
            ($t:expr) => {{
                count -= u64::from(skips.get(pc - 1).copied().unwrap_or(0));
                pc = $t as usize;
            }};
        }
        loop {
            debug_assert!(pc < ops.len());
            // SAFETY: `pc` is 0 or a jump's target, or one past an instruction that is not
            // the last (`Next`, which leaves this loop): each is an instruction of `ops`
            // (`Body::ops`).
            let op = unsafe { *ops.get_unchecked(pc) };
            pc += 1;
            match op {
                Micro::Mov { d, s } => r[d as usize] = r[s as usize],
                Micro::AddI { d, a, b } => checked!(d, int!(a) + int!(b)),
                Micro::SubI { d, a, b } => checked!(d, int!(a) - int!(b)),
                Micro::MulI { d, a, b } => match int!(a).checked_mul(int!(b)) {
                    Some(x) => checked!(d, x),
                    None => undone!(),
                },
                Micro::NegI { d, s } => set_int!(d, -int!(s)),
                Micro::ModI { d, a, b } => {
                    let (x, y) = (int!(a), int!(b));
                    match (i32::try_from(x), i32::try_from(y)) {
                        (Ok(i), Ok(j)) if j != 0 => set_int!(d, i.wrapping_rem(j)),
                        _ => from_real!(d, basic_mod_of(x as f64, y as f64, false)),
                    }
                }
                Micro::QuotI { d, a, b } => {
                    let (x, y) = (int!(a), int!(b));
                    match (i32::try_from(x), i32::try_from(y)) {
                        (Ok(i), Ok(j)) if j != 0 && !(i == i32::MIN && j == -1) => {
                            set_int!(d, i / j)
                        }
                        _ => from_real!(d, basic_div_of(x as f64, y as f64, false)),
                    }
                }
                Micro::RemI { d, a, b } => {
                    let (x, y) = (int!(a), int!(b));
                    if y == 0 {
                        undone!();
                    }
                    match (i32::try_from(x), i32::try_from(y)) {
                        (Ok(i), Ok(j)) => set_int!(d, i.wrapping_rem(j)),
                        _ => from_real!(d, Ok::<f64, ()>(int_rem_of(x as f64, y as f64, false))),
                    }
                }
                Micro::AndI { d, a, b } => checked!(d, int!(a) & int!(b)),
                Micro::OrI { d, a, b } => checked!(d, int!(a) | int!(b)),
                Micro::XorI { d, a, b } => checked!(d, int!(a) ^ int!(b)),
                Micro::BitNotI { d, s } => checked!(d, !int!(s)),
                Micro::CmpI { cmp, d, a, b } => {
                    set_int!(d, cmp.test_ord(&int!(a), &int!(b)) as i64)
                }
                Micro::NotI { d, s } => set_int!(d, (int!(s) == 0) as i64),
                Micro::FitI { d, s, w } => {
                    let x = int!(s);
                    if !fits(x, w) {
                        undone!();
                    }
                    set_int!(d, x);
                }
                Micro::AddR { d, a, b } => set_real!(d, real!(a) + real!(b)),
                Micro::SubR { d, a, b } => set_real!(d, real!(a) - real!(b)),
                Micro::MulR { d, a, b } => set_real!(d, real!(a) * real!(b)),
                Micro::DivR { d, a, b } => {
                    let y = real!(b);
                    if y == 0.0 {
                        undone!();
                    }
                    set_real!(d, real!(a) / y);
                }
                Micro::NegR { d, s } => set_real!(d, -real!(s)),
                Micro::RemR { d, a, b } => {
                    let y = real!(b);
                    if y == 0.0 {
                        undone!();
                    }
                    set_real!(d, int_rem_of(real!(a), y, false));
                }
                Micro::IntR { op, d, a, b } => {
                    from_real!(d, integer(op, real!(a), real!(b), false))
                }
                Micro::BitNotR { d, s } => checked!(d, !rounded_int(real!(s))),
                Micro::CmpR { cmp, d, a, b } => set_int!(d, cmp.test(real!(a), real!(b)) as i64),
                Micro::NotR { d, s } => set_int!(d, (real!(s) == 0.0) as i64),
                Micro::ToR { d, s } => set_real!(d, int!(s) as f64),
                Micro::ToRSigned { d, s } => {
                    let x = int!(s);
                    if x == 0 {
                        undone!();
                    }
                    set_real!(d, x as f64);
                }
                Micro::LongR { d, s } => {
                    let x = real!(s);
                    let fits = f64::from(crate::fixed::trunc_i32(x)) == x;
                    let v = if fits { Some(x + 0.0) } else { round_long(x) };
                    from_real!(d, v.ok_or(()))
                }
                Micro::ShortR { d, s } => from_real!(d, int16(real!(s)).ok_or(())),
                Micro::FixedR { d, s, decimals } => match to_fixed(real!(s), decimals) {
                    Some(x) if decimals == 0 => from_real!(d, Ok::<f64, ()>(x)),
                    Some(x) => set_real!(d, x),
                    None => undone!(),
                },
                Micro::RealR { d, s } => {
                    let x = real!(s);
                    if !x.is_finite() {
                        undone!();
                    }
                    set_real!(d, x);
                }
                Micro::CheckR { s, w } => {
                    let x = real!(s);
                    let ok = match w {
                        Width::Long => (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&x),
                        Width::Short => (-32768.0..=32767.0).contains(&x),
                    };
                    if !ok {
                        undone!();
                    }
                }
                Micro::Jump { t } => {
                    jump!(t);
                }
                Micro::JumpZeroI { c, zero, t } => {
                    if (int!(c) == 0) == zero {
                        jump!(t);
                    }
                }
                Micro::JumpZeroR { c, zero, t } => {
                    if (real!(c) == 0.0) == zero {
                        jump!(t);
                    }
                }
                Micro::JumpCmpI { cmp, a, b, t } => {
                    if cmp.test_ord(&int!(a), &int!(b)) {
                        jump!(t);
                    }
                }
                Micro::JumpCmpR { cmp, want, a, b, t } => {
                    if cmp.test(real!(a), real!(b)) == want {
                        jump!(t);
                    }
                }
                Micro::Next => break,
            }
        }
        // The `for.next`.
        let v = int!(var) + step;
        if !fits(v, width) {
            undone!();
        }
        set_int!(var, v);
        let x = v as f64;
        if !(if up { x <= limit } else { x >= limit }) {
            break End::Done;
        }
        if count >= budget {
            break End::Budget;
        }
    };
    if end == End::Slow {
        for &k in &body.kept {
            r[k as usize] = saved[k as usize];
        }
        count = at_start;
    }
    *n = count;
    let (var_local, var_reg) = body.var;
    vals[var_reg as usize] = r[var_local as usize] as i64 as f64;
    for &(reg, local, kind) in &body.outs {
        let x = r[local as usize];
        vals[reg as usize] = match kind {
            Kind::Int => x as i64 as f64,
            Kind::Real => f64::from_bits(x),
        };
    }
    Some(end)
}
