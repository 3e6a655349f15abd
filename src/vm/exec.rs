//! The interpreter loop: runs one task's instructions until it ends, blocks, calls, or spends
//! its budget.

use super::task::Frame;
use crate::compile::bytecode::{BinaryOp, ExtOp, KernelFunc, Op, Reg, INT_STORE, REAL_STORE};
use crate::compile::Chunk;
use crate::devices::command::{Domain, StartRef};
use crate::devices::{ActOutcome, Devices, Now, Target, When};
use crate::registry::{Hook, Registry};
use crate::trace::{Event, Origin, Value};

/// Why the interpreter stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum Exit {
    /// Budget spent; resume at `pc`.
    Yield(u32),
    /// `Wait For` false: block.
    Wait { retry: u32, resume: u32 },
    /// In probe mode: the condition's value, and where to resume.
    Probed { value: bool, resume: u32 },
    /// `Wait For Time`: sleep for this many updates, then resume at `pc`.
    Sleep { ticks: u64, pc: u32 },
    /// Motion busy on the profile: retry the instruction at `pc`.
    MotionBusy { profile: u8, pc: u32 },
    /// End of this program.
    End,
    /// Call another program; come back to `pc`.
    Call { program: u32, pc: u32 },
    /// `GOSUB`: run from `target`, come back to `ret`.
    Gosub { target: u32, ret: u32 },
    /// `RETURN` (at instruction `pc`).
    Return { pc: u32 },
    /// Program control (initiate/stop a program, stop all); go on at `pc`.
    Control { hook: Hook, instance: u32, pc: u32 },
    /// A run-time error at instruction `pc`.
    Fault { message: String, pc: u32 },
    /// The [`Op::ForTight`] at `pc`, its dispatch not counted: the caller does its `for.check`
    /// and runs the loop after it (`tight::run_plan`) when that is long enough and writes
    /// nothing traced, then the interpreter again.
    Loop { pc: u32 },
    /// The [`Op::LoopTight`] at `pc`, done (counted, its budget not spent): the caller runs
    /// the loop from its start (`vm::body`) when it can, else the interpreter does.
    Back { pc: u32, start: u32 },
}

/// The fault of a `for.check` with a step of 0.
pub const STEP_ZERO: &str = "For loop with a Step of 0 never ends";

/// A program's write to a slot below this is traced: the registry's `slot_count` slots when
/// tracing, none when not (one comparison per store instead of two tests).
#[inline(always)]
pub fn traced_below(trace_on: bool, slot_count: u32) -> u32 {
    if trace_on {
        slot_count
    } else {
        0
    }
}

/// What the interpreter needs besides the values.
pub struct Ctx<'a, 'b> {
    /// The machine's devices.
    pub devices: &'a mut Devices,
    /// The registry (names for trace events).
    pub registry: &'a Registry,
    /// Current values of registry slots as last traced, so a program write is not traced twice.
    pub snapshot: &'a mut [f64],
    /// The moment.
    pub now: Now<'b>,
    /// Slots below this are registry members.
    pub slot_count: u32,
    /// The task running (for warnings).
    pub task: usize,
    /// The tasks' `PRINT` lines.
    pub printer: &'a mut super::print::Printer,
    /// The string table (a string value is an index into it): literals, and the cells the
    /// run changes.
    pub strings: &'a mut Vec<String>,
    /// A string being built, kept so building one does not allocate.
    pub scratch: &'a mut String,
    /// MotionBASIC's random-number generator.
    pub rnd: &'a mut super::rnd::Rnd,
    /// The scenario's seed (`RANDOMIZE` without one uses it).
    pub seed: Option<u64>,
    /// The next `DATA` constant the running task's `READ` takes.
    pub data_at: &'a mut u32,
    /// Every compiled program (`Call Program` and its `End` switch between them here).
    pub chunks: &'a [Chunk],
    /// Program numbers and their chunks.
    pub programs: &'a indexmap::IndexMap<u32, usize>,
    /// The tasks other than the one running (those before it and those after): calling a
    /// program on one of their frames is an error the machine's loop reports.
    pub other_tasks: [&'a [super::task::Task]; 2],
    /// The chunks below 64 on a frame of a busy other task (bit c: chunk c), gathered at the
    /// turn's first `Call Program` (None before): the other tasks neither run nor change
    /// while this one runs, so one look at their frames serves every call of the turn.
    pub elsewhere: Option<u64>,
}

/// Run `chunk` from `pc` on `v`. `executed` counts instructions against `budget`.
/// In probe mode the first `WaitUntil` reached returns its condition instead of blocking.
/// With the task's `frames` (the running frame last), `GOSUB` and `RETURN` run here, without
/// leaving the interpreter; only their errors return (`Exit::Gosub`/`Exit::Return`) for the
/// caller to report. Without them, every `GOSUB` and `RETURN` returns.
#[allow(clippy::too_many_arguments)]
pub fn run<'a>(
    chunk: &'a Chunk,
    mut pc: u32,
    v: &mut [f64],
    ctx: &mut Ctx<'a, '_>,
    budget: u64,
    executed: &mut u64,
    probe: bool,
    mut frames: Option<&mut Vec<Frame>>,
) -> Exit {
    // Both change when a `Call Program` or the `End` of a called program switches programs.
    let mut chunk = chunk;
    if pc as usize >= chunk.ops.len() {
        return Exit::End;
    }
    if !chunk.closed {
        return cold_fault(pc, || {
            "internal error: a program that jumps outside itself".into()
        });
    }
    if v.len() < chunk.regs_end {
        return cold_fault(pc, || {
            format!(
                "internal error: {} values for a program using {}",
                v.len(),
                chunk.regs_end
            )
        });
    }
    // Registers of the instructions below are read and written without bounds checks: every
    // one is below `chunk.regs_end` (`Op::max_register`, computed when the chunk was compiled),
    // which was just checked against the slice, whose length cannot change while it runs.
    macro_rules! rd {
        ($i:expr) => {{
            let i: usize = $i;
            debug_assert!(i < chunk.regs_end);
            // SAFETY: i < chunk.regs_end <= v.len(), as said above.
            unsafe { *v.get_unchecked(i) }
        }};
    }
    macro_rules! wr {
        ($i:expr, $x:expr) => {{
            let x: f64 = $x;
            let i: usize = $i;
            debug_assert!(i < chunk.regs_end);
            // SAFETY: i < chunk.regs_end <= v.len(), as said above.
            unsafe { *v.get_unchecked_mut(i) = x }
        }};
    }
    let trace_on = ctx.now.trace.enabled();
    let trace_below = traced_below(trace_on, ctx.slot_count);
    let mut n: u64 = *executed;
    macro_rules! fault {
        ($($arg:tt)*) => {{
            *executed = n;
            return cold_fault(pc, || format!($($arg)*));
        }};
    }
    // Store `$x` into the fixed-point slot `$dst`, faulting at this instruction when it does
    // not fit, and trace the write.
    // `$whole`: `$x` is a whole number (or not finite) and `$decimals` 0, so only its range
    // is tested (`Chunk::sure`).
    macro_rules! store_fixed {
        ($dst:expr, $x:expr, $decimals:expr, $here:expr, $whole:expr) => {{
            let (dst, x, decimals) = ($dst, $x, $decimals);
            let quick = if $whole {
                debug_assert!(decimals == 0 && (!x.is_finite() || x.fract() == 0.0), "{x}");
                whole_in_range(x)
            } else {
                None
            };
            let Some(val) = quick.or_else(|| fixed(x, decimals)) else {
                return cold_overflow(ctx, dst, x, decimals, $here, executed, n);
            };
            wr!(dst as usize, val);
            if dst < trace_below {
                traced_write(ctx, dst, val);
            }
        }};
    }
    // Store `$x` into the MotionBASIC long `$dst`: a whole number within 32 bits as it is (one
    // conversion each way, no libm), anything else rounded half to even; an Overflow at this
    // instruction outside 32 bits.
    // `$whole`: `$x` is known to be a whole number (or not finite): only its range is tested.
    macro_rules! store_long {
        ($dst:expr, $x:expr, $here:expr, $whole:expr) => {{
            let (dst, x) = ($dst, $x);
            let fits = if $whole {
                debug_assert!(!x.is_finite() || x.fract() == 0.0, "{x} not whole");
                fits_i32(x)
            } else {
                f64::from(trunc_i32(x)) == x
            };
            // `x + 0.0` is x with a -0 made 0, as `f64::from(i)` would be, but does not wait
            // for the conversions (the comparison only steers a predicted branch).
            let val = if fits {
                x + 0.0
            } else {
                match round_long(x) {
                    Some(val) => val,
                    None => {
                        pc = $here;
                        let name = name_of(ctx, dst);
                        fault!(
                            "Overflow: {x} does not fit {name} (a long integer: -2147483648 to 2147483647)"
                        );
                    }
                }
            };
            wr!(dst as usize, val);
            if dst < trace_below {
                traced_write(ctx, dst, val);
            }
        }};
    }
    // `$x` into the temporary `$dst` unless it is outside 32 bits (long arithmetic's Overflow).
    macro_rules! check_long {
        ($dst:expr, $x:expr, $here:expr) => {{
            let x = $x;
            if !fits_i32(x) {
                pc = $here;
                fault!("Overflow: {x} does not fit a long integer (-2147483648 to 2147483647)");
            }
            wr!($dst as usize, x);
        }};
    }
    // An Overflow at `$here` if `$x` is outside 16 bits (INTEGER arithmetic's `chk.int`).
    macro_rules! check_int {
        ($x:expr, $here:expr) => {{
            let x: f64 = $x;
            if !fits_i16(x) {
                pc = $here;
                fault!("Overflow: {x} does not fit an integer (-32768 to 32767): INTEGER (%) arithmetic is 16-bit; make an operand long (CLNG, a & variable, a & constant such as 2&)");
            }
        }};
    }
    // Store `$x` into the MotionBASIC INTEGER `$dst`: rounded as a long is, an Overflow outside
    // 16 bits.
    macro_rules! store_int {
        ($dst:expr, $x:expr, $here:expr, $whole:expr) => {{
            let (dst, x) = ($dst, $x);
            let quick = if $whole {
                debug_assert!(!x.is_finite() || x.fract() == 0.0, "{x} not whole");
                Some(x + 0.0).filter(|&x| fits_i16(x))
            } else {
                None
            };
            match quick.or_else(|| int16(x)) {
                Some(val) => {
                    wr!(dst as usize, val);
                    if dst < trace_below {
                        traced_write(ctx, dst, val);
                    }
                }
                None => {
                    pc = $here;
                    let name = name_of(ctx, dst);
                    fault!("Overflow: {x} does not fit {name} (an integer: -32768 to 32767)");
                }
            }
        }};
    }
    // Store the whole number `$val` (within 32 bits, not -0) into the slot `$dst` as it is:
    // what a fixed-point or long store of it stores, without the rounding.
    macro_rules! store_whole {
        ($dst:expr, $val:expr) => {{
            let (dst, val): (u32, f64) = ($dst, $val);
            wr!(dst as usize, val);
            if dst < trace_below {
                traced_write(ctx, dst, val);
            }
        }};
    }
    // The integer result `$r` of a bitwise operator into the temporary `$t` (as a real) and
    // then stored into the long `$dst` by the instruction after `$here`: as `store.l` stores
    // it, with one integer range test.
    macro_rules! long_of_int {
        ($t:expr, $dst:expr, $r:expr, $here:expr) => {{
            let r: i64 = $r;
            wr!($t as usize, r as f64);
            match i32::try_from(r) {
                Ok(r) => store_whole!($dst, f64::from(r)),
                Err(_) => store_long!($dst, r as f64, $here + 1, false),
            }
        }};
    }
    // `band`/`bor`/`bxor` (`$op`) straight into the whole fixed-point slot `$dst`: two whole
    // 32-bit operands give a 32-bit result stored as it is; anything else is rounded first.
    macro_rules! bitwise_whole {
        ($dst:expr, $a:expr, $b:expr, $op:tt, $here:expr, $sure:expr) => {{
            let (x, y) = (rd!($a as usize), rd!($b as usize));
            let (i, j) = (trunc_i32(x), trunc_i32(y));
            if $sure || (f64::from(i) == x && f64::from(j) == y) {
                debug_assert!(f64::from(i) == x && f64::from(j) == y, "{x}, {y} not sure");
                store_whole!($dst, f64::from(i $op j));
            } else {
                whole_of_int!($dst, int(x) $op int(y), $here);
            }
        }};
    }
    // `band`/`bor`/`bxor` (`$op`) into `$t`, then `store.l $dst`: two whole 32-bit operands give
    // a 32-bit result stored as it is; anything else is rounded first, as the two instructions do.
    macro_rules! bitwise_long {
        ($t:expr, $dst:expr, $a:expr, $b:expr, $op:tt, $here:expr, $sure:expr) => {{
            n += 1;
            let (x, y) = (rd!($a as usize), rd!($b as usize));
            let (i, j) = (trunc_i32(x), trunc_i32(y));
            if $sure || (f64::from(i) == x && f64::from(j) == y) {
                debug_assert!(f64::from(i) == x && f64::from(j) == y, "{x}, {y} not sure");
                let r = f64::from(i $op j);
                wr!($t as usize, r);
                store_whole!($dst, r);
            } else {
                long_of_int!($t, $dst, int(x) $op int(y), $here);
            }
            pc = $here + 2;
        }};
    }
    // The integer result `$r` of a bitwise operator into the whole fixed-point slot `$dst`, as
    // `store_fixed!` stores it, with one integer range test.
    macro_rules! whole_of_int {
        ($dst:expr, $r:expr, $here:expr) => {{
            let r: i64 = $r;
            match i32::try_from(r) {
                Ok(r) => store_whole!($dst, f64::from(r)),
                Err(_) => store_fixed!($dst, r as f64, 0, $here, false),
            }
        }};
    }
    // The `imod t <- x MOD v[b]` at `$here` (`$x` its first operand's value) and the
    // `store.l $dst <- t` after it, counted (but for the first instruction) by the caller.
    // `$sure`: both operands are whole numbers within 32 bits; `$wide`: `$x` is whole and
    // `v[$b]` within 32 bits (only `$x`'s range is tested).
    macro_rules! mod_long {
        ($t:expr, $dst:expr, $x:expr, $b:expr, $here:expr, $sure:expr, $wide:expr) => {{
            let (t, dst, x, y): (u32, u32, f64, f64) = ($t, $dst, $x, rd!($b as usize));
            let (i, j) = (trunc_i32(x), trunc_i32(y));
            if mod_int_path(x, y, $sure, $wide) && j != 0 {
                debug_assert!(f64::from(i) == x && f64::from(j) == y, "{x}, {y} not sure");
                // As `basic_mod_of`: the remainder has the sign of x, a zero one included
                // (the temporary's); the long stores it with a zero made 0.
                let r = f64::from(i.wrapping_rem(j));
                wr!(t as usize, r.copysign(x));
                store_whole!(dst, r);
            } else {
                match basic_integer(BinaryOp::BasicMod, x, y) {
                    Ok(x) => {
                        wr!(t as usize, x);
                        store_long!(dst, x, $here + 1, false);
                    }
                    Err(message) => {
                        // The `imod` failed: the store was not reached.
                        n -= 1;
                        pc = $here;
                        fault!("{message}");
                    }
                }
            }
            pc = $here + 2;
        }};
    }
    // The PowerTools `MOD` at `$here` of `$x` by `v[$b]` into the whole fixed-point slot `$dst`
    // (`Op::ModWhole`).
    macro_rules! mod_whole {
        ($dst:expr, $x:expr, $b:expr, $here:expr, $sure:expr, $wide:expr) => {{
            let (dst, x, y): (u32, f64, f64) = ($dst, $x, rd!($b as usize));
            let (i, j) = (trunc_i32(x), trunc_i32(y));
            if mod_int_path(x, y, $sure, $wide) && j != 0 {
                debug_assert!(f64::from(i) == x && f64::from(j) == y, "{x}, {y} not sure");
                // As `int_rem`, whose remainder a whole fixed-point slot keeps as it is.
                store_whole!(dst, f64::from(i.wrapping_rem(j)));
            } else {
                match binary(BinaryOp::Mod, x, y) {
                    Ok(x) => store_fixed!(dst, x, 0, $here, false),
                    Err(message) => {
                        pc = $here;
                        fault!("{message}");
                    }
                }
            }
        }};
    }
    // The end of a `For` body at instruction `$here` (see `Op::ForNext`).
    // `$sure`: a whole variable (a long, an INTEGER, a PowerTools variable without decimals)
    // and a step known to be whole (`Chunk::sure`): their sum is whole (or not finite), and
    // not -0 (the variable never is), so it is stored as it is when within range.
    macro_rules! for_next {
        ($var:expr, $limit:expr, $body:expr, $decimals:expr, $here:expr, $sure:expr) => {{
            let (var, limit, body, decimals) = ($var, $limit, $body, $decimals);
            let s = rd!(limit as usize + 1);
            let v = rd!(var as usize);
            let x = v + s;
            let val = if $sure {
                debug_assert!(
                    f64::from(trunc_i32(v)) == v && (!s.is_finite() || s.fract() == 0.0),
                    "{v}, {s} not sure"
                );
                let fits = if decimals == INT_STORE {
                    fits_i16(x)
                } else {
                    fits_i32(x)
                };
                Some(x).filter(|_| fits)
            } else if decimals == REAL_STORE {
                Some(x).filter(|x| x.is_finite())
            } else if decimals == INT_STORE {
                int16(x)
            } else {
                fixed(x, decimals)
            };
            let Some(val) = val else {
                pc = $here;
                let message = overflow_message(ctx, var, x, decimals);
                fault!("{message}");
            };
            wr!(var as usize, val);
            if var < trace_below {
                traced_write(ctx, var, val);
            }
            let l = rd!(limit as usize);
            if (s > 0.0 && val <= l) || (s < 0.0 && val >= l) {
                pc = body;
                if n >= budget {
                    *executed = n;
                    return Exit::Yield(pc);
                }
            }
        }};
    }
    // The subscript in `v[$src]` rounded to an integer (halves to even), faulting at `$here`
    // unless it is within `0..$len` (a `subscr` instruction's work).
    macro_rules! subscr {
        ($src:expr, $len:expr, $here:expr) => {{
            let (x, len): (f64, u32) = (rd!($src as usize), $len);
            let i = x.round_ties_even();
            if !(i >= 0.0 && i < f64::from(len)) {
                pc = $here;
                fault!("{}", out_of_range(x, len));
            }
            i
        }};
    }
    // `store.idx` at `$here`: `v[$src]` into element `v[$idx]` of the one-subscript array at
    // `$base`, stored as its kind (`$decimals`) says.
    macro_rules! store_idx {
        ($base:expr, $idx:expr, $src:expr, $len:expr, $decimals:expr, $here:expr) => {{
            let (base, idx, src, len, decimals, here): (u32, u32, u32, u32, u8, u32) =
                ($base, $idx, $src, $len, $decimals, $here);
            let Some(i) = subscript(rd!(idx as usize), len) else {
                pc = here;
                fault!("{}", out_of_range(rd!(idx as usize), len));
            };
            let dst = base + i;
            let x = rd!(src as usize);
            if decimals == 0 {
                store_long!(dst, x, here, sure!(here))
            } else if decimals == REAL_STORE {
                store_real!(dst, x, here)
            } else if decimals == INT_STORE {
                store_int!(dst, x, here, sure!(here))
            } else {
                store_fixed!(dst, x, decimals, here, false)
            }
        }};
    }
    // Store `$x` into a real, which must be finite.
    macro_rules! store_real {
        ($dst:expr, $x:expr, $here:expr) => {{
            let (dst, x) = ($dst, $x);
            if !x.is_finite() {
                pc = $here;
                let name = name_of(ctx, dst);
                fault!("{name} cannot take {x}: the result is not a finite number");
            }
            wr!(dst as usize, x);
            if dst < trace_below {
                traced_write(ctx, dst, x);
            }
        }};
    }
    // The outer loop runs once per program entered: the inner one sees its instructions as a
    // fixed slice, which keeps them in registers.
    'chunks: loop {
        let ops = &chunk.ops[..];
        let sures = &chunk.sure[..];
        // The flag of the instruction at `$here` (`Chunk::sure`): its integer operands are
        // whole numbers within 32 bits, the value it stores is whole, its loop counts by a whole
        // step; then they are taken without the test.
        macro_rules! flags {
            ($here:expr) => {{
                debug_assert!(($here as usize) < sures.len());
                // SAFETY: `$here` is an instruction of the chunk (the one running, or the
                // `for.next` a `JumpNext` runs, inside the chunk as its target is), and a
                // closed chunk has flags for each instruction.
                *unsafe { sures.get_unchecked($here as usize) }
            }};
        }
        macro_rules! sure {
            ($here:expr) => {
                flags!($here) & SURE != 0
            };
        }
        // A copy of a sure variable or constant (`whole::PLAIN`): whole within 32 bits, not -0,
        // stored as it is.
        macro_rules! plain_store {
            ($dst:expr, $x:expr) => {{
                let x: f64 = $x;
                debug_assert!(
                    f64::from(trunc_i32(x)) == x && x.to_bits() != (-0.0f64).to_bits(),
                    "{x} not plain"
                );
                store_whole!($dst, x);
            }};
        }
        // A `MOD`'s first operand is whole, its second within 32 bits (`whole::WIDE`).
        macro_rules! wide {
            ($here:expr) => {
                flags!($here) & WIDE != 0
            };
        }
        // A conditional jump's taken way. It stays a branch: were the handler to choose the
        // next `pc` with a conditional move (as LLVM does for an equality test), the outcome
        // would reach the processor only as the target of the indirect jump that dispatches the
        // next instruction, which its predictor guesses from the history of branches: an `IF`
        // alternating or following a pattern would be mispredicted nearly every time (an `IF
        // I& AND 1` loop ran 2.5 times slower), where a branch is learned.
        macro_rules! taken {
            ($target:expr) => {{
                keep_branch();
                pc = $target;
            }};
        }
        // The superinstruction at `$here` whose first half gives `$x` (`Err`: its fault) into
        // the temporary `$t`, and whose second (at `$here + 1`) stores it into `$dst` with
        // `$store!` (`store_long!`, `store_int!`).
        macro_rules! then_store {
            ($t:expr, $dst:expr, $x:expr, $here:expr, $store:ident) => {{
                n += 1;
                let first: Result<f64, &str> = $x;
                match first {
                    Ok(x) => {
                        wr!($t as usize, x);
                        $store!($dst, x, $here + 1, sure!($here));
                        pc = $here + 2;
                    }
                    Err(message) => {
                        // The first half failed: the second was not reached.
                        n -= 1;
                        pc = $here;
                        fault!("{message}");
                    }
                }
            }};
        }
        loop {
            debug_assert!((pc as usize) < ops.len());
            // SAFETY: pc is inside the chunk: it was on entry (checked above) and every way it
            // changes keeps it there: a jump goes to a target inside the chunk and running on past
            // an instruction never passes the last one, `End`, which returns (both checked when the
            // chunk was compiled: `chunk.closed`); a superinstruction skips its second half, never
            // the last instruction.
            let op = unsafe { ops.get_unchecked(pc as usize) };
            n += 1;
            let here = pc;
            pc += 1;
            match *op {
                Op::Move { dst, src } => wr!(dst as usize, rd!(src as usize)),
                Op::Add { dst, a, b } => wr!(dst as usize, rd!(a as usize) + rd!(b as usize)),
                Op::Sub { dst, a, b } => wr!(dst as usize, rd!(a as usize) - rd!(b as usize)),
                Op::Mul { dst, a, b } => wr!(dst as usize, rd!(a as usize) * rd!(b as usize)),
                Op::Div { dst, a, b } => {
                    let y = rd!(b as usize);
                    if y == 0.0 {
                        pc = here;
                        fault!("division by zero");
                    }
                    wr!(dst as usize, rd!(a as usize) / y);
                }
                Op::Mod { dst, a, b } => {
                    let y = rd!(b as usize);
                    if y == 0.0 {
                        pc = here;
                        fault!("MOD by zero");
                    }
                    wr!(dst as usize, int_rem_of(rd!(a as usize), y, sure!(here)));
                }
                Op::IMod { dst, a, b } => {
                    match basic_mod_of(rd!(a as usize), rd!(b as usize), sure!(here)) {
                        Ok(r) => wr!(dst as usize, r),
                        Err(message) => {
                            pc = here;
                            fault!("{message}");
                        }
                    }
                }
                Op::IDiv { dst, a, b } => {
                    match basic_div_of(rd!(a as usize), rd!(b as usize), sure!(here)) {
                        Ok(r) => wr!(dst as usize, r),
                        Err(message) => {
                            pc = here;
                            fault!("{message}");
                        }
                    }
                }
                Op::BitAnd { dst, a, b } => {
                    let sure = sure!(here);
                    wr!(
                        dst as usize,
                        (int_of(rd!(a as usize), sure) & int_of(rd!(b as usize), sure)) as f64
                    )
                }
                Op::BitOr { dst, a, b } => {
                    let sure = sure!(here);
                    wr!(
                        dst as usize,
                        (int_of(rd!(a as usize), sure) | int_of(rd!(b as usize), sure)) as f64
                    )
                }
                Op::BitXor { dst, a, b } => {
                    let sure = sure!(here);
                    wr!(
                        dst as usize,
                        (int_of(rd!(a as usize), sure) ^ int_of(rd!(b as usize), sure)) as f64
                    )
                }
                // Superinstructions: the work of this instruction and the next, which is skipped;
                // they count as two, and a fault in the second half is reported at the second.
                Op::AddLong { t, dst, a, b } => {
                    then_store!(
                        t,
                        dst,
                        Ok(rd!(a as usize) + rd!(b as usize)),
                        here,
                        store_long
                    )
                }
                Op::SubLong { t, dst, a, b } => {
                    then_store!(
                        t,
                        dst,
                        Ok(rd!(a as usize) - rd!(b as usize)),
                        here,
                        store_long
                    )
                }
                Op::MulLong { t, dst, a, b } => {
                    then_store!(
                        t,
                        dst,
                        Ok(rd!(a as usize) * rd!(b as usize)),
                        here,
                        store_long
                    )
                }
                Op::IntLong { op, t, dst, a, b } => {
                    let x = integer(op, rd!(a as usize), rd!(b as usize), sure!(here));
                    then_store!(t, dst, x, here, store_long)
                }
                Op::ModLong { t, dst, a, b } => {
                    n += 1;
                    mod_long!(t, dst, rd!(a as usize), b, here, sure!(here), wide!(here));
                }
                Op::AddModLong {
                    t,
                    x,
                    dst,
                    m,
                    t_first: _,
                } => {
                    // `add` (here), then the `imod` and `store.l` of a `ModLong` (here + 1).
                    n += 2;
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    let (p, q) = (t, x);
                    let s = rd!(p as usize) + rd!(q as usize);
                    wr!(t as usize, s);
                    // The sum is not known to be within 32 bits: never `SURE`.
                    mod_long!(t, dst, s, m, here + 1, false, wide!(here));
                }
                Op::AddModWhole {
                    t,
                    x,
                    dst,
                    m,
                    t_first: _,
                } => {
                    // `add` (here), then a `ModWhole` (here + 1).
                    n += 1;
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    let (p, q) = (t, x);
                    let s = rd!(p as usize) + rd!(q as usize);
                    wr!(t as usize, s);
                    mod_whole!(dst, s, m, here + 1, false, wide!(here));
                    pc = here + 2;
                }
                Op::NotAndLong {
                    t,
                    a,
                    b,
                    dst,
                    t_first: _,
                } => {
                    // `bnot` (here), then the `band` and `store.l` of an `AndLong` (here + 1).
                    n += 1;
                    // Every instruction it runs (`Chunk::sure` of a superinstruction).
                    let sure = sure!(here);
                    wr!(t as usize, !int_of(rd!(a as usize), sure) as f64);
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    let (p, q) = (t, b);
                    bitwise_long!(t, dst, p, q, &, here + 1, sure);
                }
                Op::NotAndWhole {
                    t,
                    a,
                    b,
                    dst,
                    t_first: _,
                } => {
                    // `bnot` (here), then an `AndWhole` (here + 1).
                    n += 1;
                    // Every instruction it runs (`Chunk::sure` of a superinstruction).
                    let sure = sure!(here);
                    wr!(t as usize, !int_of(rd!(a as usize), sure) as f64);
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    let (p, q) = (t, b);
                    bitwise_whole!(dst, p, q, &, here + 1, sure);
                    pc = here + 2;
                }
                Op::AndOr {
                    t,
                    a,
                    b,
                    x,
                    t_first: _,
                } => {
                    // `band` (here), then `bor` (here + 1).
                    n += 1;
                    // Every instruction it runs (`Chunk::sure` of a superinstruction).
                    let sure = sure!(here);
                    wr!(
                        t as usize,
                        (int_of(rd!(a as usize), sure) & int_of(rd!(b as usize), sure)) as f64
                    );
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    let (p, q) = (t, x);
                    wr!(
                        t as usize,
                        (int_of(rd!(p as usize), sure) | int_of(rd!(q as usize), sure)) as f64
                    );
                    pc = here + 2;
                }
                Op::AndXorLong {
                    t,
                    a,
                    b,
                    dst,
                    t_first: _,
                } => {
                    // `band` (here), then the `bxor` and `store.l` of a `XorLong` (here + 1).
                    n += 1;
                    // Every instruction it runs (`Chunk::sure` of a superinstruction).
                    let sure = sure!(here);
                    wr!(
                        t as usize,
                        (int_of(rd!(a as usize), sure) & int_of(rd!(b as usize), sure)) as f64
                    );
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    let (p, q) = (t, dst);
                    bitwise_long!(t, dst, p, q, ^, here + 1, sure);
                }
                Op::AndXorWhole {
                    t,
                    a,
                    b,
                    dst,
                    t_first: _,
                } => {
                    // `band` (here), then a `XorWhole` (here + 1).
                    n += 1;
                    // Every instruction it runs (`Chunk::sure` of a superinstruction).
                    let sure = sure!(here);
                    wr!(
                        t as usize,
                        (int_of(rd!(a as usize), sure) & int_of(rd!(b as usize), sure)) as f64
                    );
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    let (p, q) = (t, dst);
                    bitwise_whole!(dst, p, q, ^, here + 1, sure);
                    pc = here + 2;
                }
                Op::DivAddLong {
                    t,
                    a,
                    b,
                    dst,
                    t_first: _,
                } => {
                    // `idiv` (here), then the `add` and `store.l` of an `AddLong` (here + 1).
                    match basic_div_of(rd!(a as usize), rd!(b as usize), sure!(here)) {
                        Ok(q) => wr!(t as usize, q),
                        Err(message) => {
                            pc = here;
                            fault!("{message}");
                        }
                    }
                    n += 2;
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    let (p, q) = (t, dst);
                    let x = rd!(p as usize) + rd!(q as usize);
                    wr!(t as usize, x);
                    store_long!(dst, x, here + 2, sure!(here));
                    pc = here + 3;
                }
                Op::SubMod { t, a, b, x } => {
                    // `mod` (here), then `sub` (here + 1), which cannot fail.
                    let y = rd!(b as usize);
                    if y == 0.0 {
                        pc = here;
                        fault!("MOD by zero");
                    }
                    n += 1;
                    let r = int_rem_of(rd!(a as usize), y, sure!(here));
                    wr!(t as usize, rd!(x as usize) - r);
                    pc = here + 2;
                }
                Op::DivAddFixed {
                    t,
                    a,
                    b,
                    dst,
                    decimals,
                    t_first: _,
                } => {
                    // `div` (here), then the `add.f` (here + 1).
                    let y = rd!(b as usize);
                    if y == 0.0 {
                        pc = here;
                        fault!("division by zero");
                    }
                    n += 1;
                    let q = rd!(a as usize) / y;
                    wr!(t as usize, q);
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    store_fixed!(
                        dst,
                        q + rd!(dst as usize),
                        decimals,
                        here + 1,
                        sure!(here) && decimals == 0
                    );
                    pc = here + 2;
                }
                Op::MulAddCheck {
                    t,
                    a,
                    b,
                    c,
                    t_first: _,
                } => {
                    // A `MulCheck` (here, here + 1), then an `AddCheck` (here + 2, here + 3).
                    n += 1;
                    check_long!(t, rd!(a as usize) * rd!(b as usize), here + 1);
                    n += 2;
                    // The operator commutes (IEEE addition too): `t_first` is for the listing only.
                    let (p, q) = (t, c);
                    check_long!(t, rd!(p as usize) + rd!(q as usize), here + 3);
                    pc = here + 4;
                }
                // Chained superinstructions: the second part's operands are read where it
                // stays; the product or quotient is kept in a register between the parts.
                Op::MulAddModWhole { t, a, b } => {
                    // `mul` (here), then the `AddModWhole` after it (here + 1, here + 2).
                    let Some(&Op::AddModWhole { x, dst, m, .. }) = ops.get(here as usize + 1)
                    else {
                        pc = here;
                        fault!("internal error: a chained instruction without its second part");
                    };
                    n += 2;
                    let p = rd!(a as usize) * rd!(b as usize);
                    // `x` is read after the product is written to `t`: it may be `t` itself.
                    let s = p + if x == t { p } else { rd!(x as usize) };
                    wr!(t as usize, s);
                    mod_whole!(dst, s, m, here + 2, false, wide!(here + 1));
                    pc = here + 3;
                }
                Op::MulAddCheckModLong {
                    t,
                    a,
                    b,
                    c,
                    t_first: _,
                } => {
                    // A `MulAddCheck` (here to here + 3), then a `ModLong` (here + 4, here + 5).
                    let Some(&Op::ModLong { dst, b: m, .. }) = ops.get(here as usize + 4) else {
                        pc = here;
                        fault!("internal error: a chained instruction without its second part");
                    };
                    n += 1;
                    let p = rd!(a as usize) * rd!(b as usize);
                    check_long!(t, p, here + 1);
                    n += 2;
                    // The operator commutes (IEEE addition too): `t_first` is for the listing
                    // only; `c`, read after `t` is written, may be `t` itself.
                    let s = p + if c == t { p } else { rd!(c as usize) };
                    check_long!(t, s, here + 3);
                    n += 2;
                    mod_long!(t, dst, s, m, here + 4, sure!(here + 4), wide!(here + 4));
                }
                Op::QuotAddFixed { t, a, b } => {
                    // A `SubMod` (here, here + 1), then a `DivAddFixed` (here + 2, here + 3)
                    // dividing `t` by `b`'s value.
                    let Some(&Op::DivAddFixed { dst, decimals, .. }) = ops.get(here as usize + 2)
                    else {
                        pc = here;
                        fault!("internal error: a chained instruction without its second part");
                    };
                    let y = rd!(b as usize);
                    if y == 0.0 {
                        pc = here;
                        fault!("MOD by zero");
                    }
                    n += 3;
                    let x = rd!(a as usize);
                    let q = if sure!(here) {
                        whole_quotient(x, y)
                    } else {
                        (x - int_rem_of(x, y, false)) / y
                    };
                    wr!(t as usize, q);
                    store_fixed!(
                        dst,
                        q + rd!(dst as usize),
                        decimals,
                        here + 3,
                        sure!(here + 2) && decimals == 0
                    );
                    pc = here + 4;
                }
                Op::AndLong { t, dst, a, b } => bitwise_long!(t, dst, a, b, &, here, sure!(here)),
                Op::OrLong { t, dst, a, b } => bitwise_long!(t, dst, a, b, |, here, sure!(here)),
                Op::XorLong { t, dst, a, b } => bitwise_long!(t, dst, a, b, ^, here, sure!(here)),
                Op::MulAdd { t, a, b, c } => {
                    n += 1;
                    wr!(t as usize, rd!(a as usize) * rd!(b as usize));
                    wr!(t as usize, rd!(t as usize) + rd!(c as usize));
                    pc = here + 2;
                }
                Op::MulAcc { p, a, b, acc } => {
                    n += 1;
                    let product = rd!(a as usize) * rd!(b as usize);
                    wr!(p as usize, product);
                    wr!(acc as usize, rd!(acc as usize) + product);
                    pc = here + 2;
                }
                Op::MulSumReal {
                    acc,
                    dst,
                    a,
                    b,
                    minus,
                } => {
                    // `mul`, `add` or `sub` (here + 1), `store.r` (here + 2).
                    n += 2;
                    let product = rd!(a as usize) * rd!(b as usize);
                    wr!(acc as usize + 1, product);
                    let sum = rd!(acc as usize);
                    let x = if minus { sum - product } else { sum + product };
                    wr!(acc as usize, x);
                    store_real!(dst, x, here + 2);
                    pc = here + 3;
                }
                Op::SumReal {
                    acc,
                    p,
                    dst,
                    at,
                    slots,
                    terms,
                } => {
                    let from = at as usize;
                    let Some([last, first, rest @ ..]) =
                        chunk.terms.get(from..from + 1 + usize::from(terms))
                    else {
                        pc = here;
                        fault!("internal error: the terms of a sum are missing");
                    };
                    let mut sum = rd!(first.a as usize) * rd!(first.b as usize);
                    for t in rest {
                        let product = rd!(t.a as usize) * rd!(t.b as usize);
                        sum += f64::from_bits(product.to_bits() ^ t.mask);
                    }
                    wr!(p as usize, rd!(last.a as usize) * rd!(last.b as usize));
                    wr!(acc as usize, sum);
                    // Every instruction of the sum, its store (the last) included.
                    n += u64::from(slots) - 1;
                    store_real!(dst, sum, here + u32::from(slots) - 1);
                    pc = here + u32::from(slots);
                }
                Op::MulDec { p, a, b, acc } => {
                    n += 1;
                    let product = rd!(a as usize) * rd!(b as usize);
                    wr!(p as usize, product);
                    wr!(acc as usize, rd!(acc as usize) - product);
                    pc = here + 2;
                }
                // `c` is read after `t` is written: it may be `t` itself.
                Op::AddAdd { t, a, b, c } => {
                    n += 1;
                    wr!(t as usize, rd!(a as usize) + rd!(b as usize));
                    wr!(t as usize, rd!(t as usize) + rd!(c as usize));
                    pc = here + 2;
                }
                Op::AddSub { t, a, b, c } => {
                    n += 1;
                    wr!(t as usize, rd!(a as usize) + rd!(b as usize));
                    wr!(t as usize, rd!(t as usize) - rd!(c as usize));
                    pc = here + 2;
                }
                Op::SubAdd { t, a, b, c } => {
                    n += 1;
                    wr!(t as usize, rd!(a as usize) - rd!(b as usize));
                    wr!(t as usize, rd!(t as usize) + rd!(c as usize));
                    pc = here + 2;
                }
                // `c` is read after `t` is written: it may be `t` itself (`(a - b) * (a - b)`
                // is not written so, but a pair is made from whatever the compiler emits).
                Op::AddMul { t, a, b, c } => {
                    n += 1;
                    wr!(t as usize, rd!(a as usize) + rd!(b as usize));
                    wr!(t as usize, rd!(t as usize) * rd!(c as usize));
                    pc = here + 2;
                }
                Op::SubMul { t, a, b, c } => {
                    n += 1;
                    wr!(t as usize, rd!(a as usize) - rd!(b as usize));
                    wr!(t as usize, rd!(t as usize) * rd!(c as usize));
                    pc = here + 2;
                }
                Op::SubSub { t, a, b, c } => {
                    n += 1;
                    wr!(t as usize, rd!(a as usize) - rd!(b as usize));
                    wr!(t as usize, rd!(t as usize) - rd!(c as usize));
                    pc = here + 2;
                }
                Op::ModWhole { dst, a, b } => {
                    mod_whole!(dst, rd!(a as usize), b, here, sure!(here), wide!(here))
                }
                Op::AndWhole { dst, a, b } => bitwise_whole!(dst, a, b, &, here, sure!(here)),
                Op::OrWhole { dst, a, b } => bitwise_whole!(dst, a, b, |, here, sure!(here)),
                Op::XorWhole { dst, a, b } => bitwise_whole!(dst, a, b, ^, here, sure!(here)),
                Op::AddInt { t, dst, a, b } => {
                    then_store!(
                        t,
                        dst,
                        Ok(rd!(a as usize) + rd!(b as usize)),
                        here,
                        store_int
                    )
                }
                Op::SubInt { t, dst, a, b } => {
                    then_store!(
                        t,
                        dst,
                        Ok(rd!(a as usize) - rd!(b as usize)),
                        here,
                        store_int
                    )
                }
                Op::MulInt { t, dst, a, b } => {
                    then_store!(
                        t,
                        dst,
                        Ok(rd!(a as usize) * rd!(b as usize)),
                        here,
                        store_int
                    )
                }
                Op::IntInt { op, t, dst, a, b } => {
                    let x = integer(op, rd!(a as usize), rd!(b as usize), sure!(here));
                    then_store!(t, dst, x, here, store_int)
                }
                Op::AddCheckInt { dst, a, b } => {
                    n += 1;
                    let x = rd!(a as usize) + rd!(b as usize);
                    wr!(dst as usize, x);
                    check_int!(x, here + 1);
                    pc = here + 2;
                }
                Op::SubCheckInt { dst, a, b } => {
                    n += 1;
                    let x = rd!(a as usize) - rd!(b as usize);
                    wr!(dst as usize, x);
                    check_int!(x, here + 1);
                    pc = here + 2;
                }
                Op::MulCheckInt { dst, a, b } => {
                    n += 1;
                    let x = rd!(a as usize) * rd!(b as usize);
                    wr!(dst as usize, x);
                    check_int!(x, here + 1);
                    pc = here + 2;
                }
                Op::AddCheck { dst, a, b } => {
                    n += 1;
                    check_long!(dst, rd!(a as usize) + rd!(b as usize), here + 1);
                    pc = here + 2;
                }
                Op::SubCheck { dst, a, b } => {
                    n += 1;
                    check_long!(dst, rd!(a as usize) - rd!(b as usize), here + 1);
                    pc = here + 2;
                }
                Op::MulCheck { dst, a, b } => {
                    n += 1;
                    check_long!(dst, rd!(a as usize) * rd!(b as usize), here + 1);
                    pc = here + 2;
                }
                Op::AddReal { t, dst, a, b } => {
                    n += 1;
                    let x = rd!(a as usize) + rd!(b as usize);
                    wr!(t as usize, x);
                    store_real!(dst, x, here + 1);
                    pc = here + 2;
                }
                Op::SubReal { t, dst, a, b } => {
                    n += 1;
                    let x = rd!(a as usize) - rd!(b as usize);
                    wr!(t as usize, x);
                    store_real!(dst, x, here + 1);
                    pc = here + 2;
                }
                Op::MulReal { t, dst, a, b } => {
                    n += 1;
                    let x = rd!(a as usize) * rd!(b as usize);
                    wr!(t as usize, x);
                    store_real!(dst, x, here + 1);
                    pc = here + 2;
                }
                Op::DivReal { t, dst, a, b } => {
                    let y = rd!(b as usize);
                    if y == 0.0 {
                        pc = here;
                        fault!("division by zero");
                    }
                    n += 1;
                    let x = rd!(a as usize) / y;
                    wr!(t as usize, x);
                    store_real!(dst, x, here + 1);
                    pc = here + 2;
                }
                Op::StoreLong { dst, src } => {
                    let x = rd!(src as usize);
                    if flags!(here) & PLAIN != 0 {
                        plain_store!(dst, x);
                    } else {
                        store_long!(dst, x, here, sure!(here))
                    }
                }
                Op::StoreInt { dst, src } => store_int!(dst, rd!(src as usize), here, sure!(here)),
                Op::CheckLong { r } => check_long!(r, rd!(r as usize), here),
                Op::CheckInt { r } => check_int!(rd!(r as usize), here),
                Op::Binary { op, dst, a, b } => {
                    match binary(op, rd!(a as usize), rd!(b as usize)) {
                        Ok(x) => wr!(dst as usize, x),
                        Err(message) => {
                            pc = here;
                            fault!("{message}");
                        }
                    }
                }
                Op::AddFixed {
                    dst,
                    a,
                    b,
                    decimals,
                } => {
                    store_fixed!(
                        dst,
                        rd!(a as usize) + rd!(b as usize),
                        decimals,
                        here,
                        sure!(here) && decimals == 0
                    )
                }
                Op::SubFixed {
                    dst,
                    a,
                    b,
                    decimals,
                } => {
                    store_fixed!(
                        dst,
                        rd!(a as usize) - rd!(b as usize),
                        decimals,
                        here,
                        sure!(here) && decimals == 0
                    )
                }
                Op::MulFixed {
                    dst,
                    a,
                    b,
                    decimals,
                } => {
                    store_fixed!(
                        dst,
                        rd!(a as usize) * rd!(b as usize),
                        decimals,
                        here,
                        sure!(here) && decimals == 0
                    )
                }
                Op::ArithFixed {
                    op,
                    dst,
                    a,
                    b,
                    decimals,
                } => match binary(op, rd!(a as usize), rd!(b as usize)) {
                    Ok(x) => store_fixed!(dst, x, decimals, here, false),
                    Err(message) => {
                        pc = here;
                        fault!("{message}");
                    }
                },
                Op::Compare { cmp, dst, a, b } => {
                    wr!(
                        dst as usize,
                        f64::from(cmp.test(rd!(a as usize), rd!(b as usize)))
                    )
                }
                Op::Neg { dst, a } => wr!(dst as usize, -rd!(a as usize)),
                Op::Not { dst, a } => wr!(dst as usize, f64::from(rd!(a as usize) == 0.0)),
                Op::BitNot { dst, a } => {
                    wr!(dst as usize, !int_of(rd!(a as usize), sure!(here)) as f64)
                }
                Op::Call { func, dst, a, b } => {
                    wr!(dst as usize, func.apply(rd!(a as usize), rd!(b as usize)))
                }
                Op::StoreFixed { dst, src, decimals } => {
                    let x = rd!(src as usize);
                    if decimals == 0 && flags!(here) & PLAIN != 0 {
                        plain_store!(dst, x);
                    } else {
                        store_fixed!(dst, x, decimals, here, sure!(here) && decimals == 0)
                    }
                }
                Op::StoreReal { dst, src } => store_real!(dst, rd!(src as usize), here),
                Op::StoreBit { dst, src } => {
                    let x = f64::from(rd!(src as usize) != 0.0);
                    wr!(dst as usize, x);
                    if dst < trace_below {
                        traced_write(ctx, dst, x);
                    }
                }
                Op::Write {
                    hook,
                    slot,
                    src,
                    instance,
                } => {
                    let ty = ctx.registry.slots[slot as usize].ty;
                    let raw = rd!(src as usize);
                    let x = match ty {
                        crate::registry::ValueType::Bit => f64::from(raw != 0.0),
                        crate::registry::ValueType::Integer => crate::fixed::round_to(raw, 0),
                        crate::registry::ValueType::Fixed(d) => crate::registry::round_to(raw, d),
                        crate::registry::ValueType::Real => raw,
                    };
                    if !x.is_finite() || (ty != crate::registry::ValueType::Real && !fits_i32(x)) {
                        pc = here;
                        let name = name_of(ctx, slot);
                        fault!("{name} cannot take {raw}: out of range");
                    }
                    if trace_on {
                        traced_write(ctx, slot, x);
                    }
                    let target = Target {
                        hook,
                        slot,
                        instance,
                    };
                    if let Err(message) = ctx.devices.write(target, x, When::Now, v, &mut ctx.now) {
                        pc = here;
                        let name = name_of(ctx, slot);
                        fault!("{name}: {message}");
                    }
                    // A plain store changed only its own slot, traced above: no scan for changes.
                    if ctx.devices.reacts(hook) {
                        sync_snapshot(ctx, v);
                    }
                }
                Op::Act {
                    hook,
                    slot,
                    instance,
                    start,
                    profile,
                } => {
                    match hook {
                        Hook::ProgramInitiate | Hook::ProgramStop | Hook::StopAll => {
                            *executed = n;
                            return Exit::Control { hook, instance, pc };
                        }
                        Hook::MotionStart if ctx.devices.profile_busy(profile as usize) => {
                            *executed = n;
                            return Exit::MotionBusy { profile, pc: here };
                        }
                        _ => {}
                    }
                    let target = Target {
                        hook,
                        slot,
                        instance,
                    };
                    match ctx
                        .devices
                        .act(target, start, profile, When::Now, v, &mut ctx.now)
                    {
                        Ok(ActOutcome::Done) => sync_snapshot(ctx, v),
                        Ok(ActOutcome::ProfileBusy) => {
                            *executed = n;
                            return Exit::MotionBusy { profile, pc: here };
                        }
                        Err(message) => {
                            pc = here;
                            let name = name_of(ctx, slot);
                            fault!("{name}: {message}");
                        }
                    }
                }
                Op::Jump { target } => pc = target,
                Op::Loop { target } => {
                    pc = target;
                    if n >= budget {
                        *executed = n;
                        return Exit::Yield(pc);
                    }
                }
                Op::LoopTight { target } => {
                    pc = target;
                    if n >= budget {
                        *executed = n;
                        return Exit::Yield(pc);
                    }
                    // (The machine gives back a loop it does not take: a traced run's, one that
                    // goes round too few times; this costs every entry of the interpreter
                    // nothing.)
                    if !probe {
                        *executed = n;
                        return Exit::Back {
                            pc: here,
                            start: target,
                        };
                    }
                }
                Op::JumpIfFalse { cond, target } => {
                    if rd!(cond as usize) == 0.0 {
                        taken!(target);
                    }
                }
                Op::JumpUnlessLt { a, b, target } => {
                    // Not `>=`: a comparison with NaN is false, so NaN must jump here.
                    let holds = rd!(a as usize) < rd!(b as usize);
                    if !holds {
                        pc = target;
                    }
                }
                Op::JumpUnlessLe { a, b, target } => {
                    let holds = rd!(a as usize) <= rd!(b as usize);
                    if !holds {
                        pc = target;
                    }
                }
                Op::JumpUnlessEq { a, b, target } => {
                    if rd!(a as usize) != rd!(b as usize) {
                        taken!(target);
                    }
                }
                Op::JumpUnlessNe { a, b, target } => {
                    if rd!(a as usize) == rd!(b as usize) {
                        taken!(target);
                    }
                }
                Op::JumpWhenLt { a, b, target } => {
                    if rd!(a as usize) < rd!(b as usize) {
                        pc = target;
                    }
                }
                Op::JumpWhenLe { a, b, target } => {
                    if rd!(a as usize) <= rd!(b as usize) {
                        pc = target;
                    }
                }
                Op::JumpWhenEq { a, b, target } => {
                    if rd!(a as usize) == rd!(b as usize) {
                        taken!(target);
                    }
                }
                Op::JumpWhenNe { a, b, target } => {
                    if rd!(a as usize) != rd!(b as usize) {
                        taken!(target);
                    }
                }
                Op::AndJump {
                    t,
                    a,
                    b,
                    target,
                    nonzero,
                } => {
                    // `band` (here), then `jump.f` or `jump.t` (here + 1).
                    n += 1;
                    let sure = sure!(here);
                    let r = (int_of(rd!(a as usize), sure) & int_of(rd!(b as usize), sure)) as f64;
                    wr!(t as usize, r);
                    pc = here + 2;
                    if (r != 0.0) == nonzero {
                        taken!(target);
                    }
                }
                Op::JumpIfTrue { cond, target } => {
                    if rd!(cond as usize) != 0.0 {
                        taken!(target);
                    }
                }
                Op::ForNext {
                    var,
                    limit,
                    body,
                    decimals,
                } => for_next!(var, limit, body, decimals, here, sure!(here)),
                Op::JumpNext {
                    var,
                    limit,
                    body,
                    at,
                    decimals,
                } => {
                    // The jump, then the `for.next` at `at`.
                    n += 1;
                    pc = at + 1;
                    for_next!(var, limit, body, decimals, at, sure!(at));
                }
                Op::WaitUntil { cond, retry } => {
                    let value = rd!(cond as usize) != 0.0;
                    *executed = n;
                    if probe {
                        return Exit::Probed { value, resume: pc };
                    }
                    if !value {
                        return Exit::Wait { retry, resume: pc };
                    }
                }
                Op::WaitTime { src } => {
                    let secs = rd!(src as usize);
                    let ns = match crate::config::values::seconds_to_ns(secs) {
                        Ok(ns) => ns,
                        Err(e) => {
                            pc = here;
                            fault!("Wait For Time: {e}");
                        }
                    };
                    let ticks = ns.div_ceil(ctx.now.tick_ns.max(1));
                    if ticks > 0 {
                        *executed = n;
                        return Exit::Sleep { ticks, pc };
                    }
                }
                Op::Dwell { src, master, last } => {
                    let domain = if master { Domain::Master } else { Domain::Time };
                    let start = if last { StartRef::Last } else { StartRef::Now };
                    let started = match ctx.devices.profiles() {
                        Some(p) => p.dwell(rd!(src as usize), domain, start, v, &mut ctx.now),
                        None => Err("this machine has no motion profiles to dwell on".into()),
                    };
                    match started {
                        Ok(ActOutcome::Done) => sync_snapshot(ctx, v),
                        Ok(ActOutcome::ProfileBusy) => {
                            *executed = n;
                            return Exit::MotionBusy {
                                profile: 0,
                                pc: here,
                            };
                        }
                        Err(message) => {
                            pc = here;
                            fault!("{message}");
                        }
                    }
                }
                Op::ForCheck { var, limit, exit } => {
                    let (x, l, s) = (
                        rd!(var as usize),
                        rd!(limit as usize),
                        rd!(limit as usize + 1),
                    );
                    if s == 0.0 {
                        pc = here;
                        fault!("{STEP_ZERO}");
                    }
                    if (s > 0.0 && x > l) || (s < 0.0 && x < l) {
                        pc = exit;
                    }
                }
                Op::ForTight { .. } => {
                    // A `for.check` for the machine to do (`Machine::enter_loop`), out of this
                    // loop's code: the float tests it would add here slow every other
                    // instruction (LLVM allocates the whole loop's registers at once; written
                    // otherwise, even this return cost `bench/loop` 2 % more instructions). A
                    // probe runs a `Wait For` condition's code, which holds no loop.
                    debug_assert!(!probe, "a for.check in a Wait For condition");
                    if !probe {
                        *executed = n - 1;
                        return Exit::Loop { pc: here };
                    }
                }
                Op::CallProgram { program } => {
                    // As the machine's loop does it (`Machine::run_task`) when the call is no error:
                    // the caller's frame resumes after the call, the called program's frame runs
                    // from its start, and the task yields there if its budget is spent. Anything
                    // else (no such program, one already running, calls too deep, a chunk this
                    // loop could not run unchecked) returns for the machine to do or report.
                    let entered = match (call_target(ctx, program, v.len()), frames.as_deref_mut())
                    {
                        (Some((c, next)), Some(frames))
                            if frames.len() < super::MAX_CALL_DEPTH
                                && !frames.iter().any(|f| f.chunk == c) =>
                        {
                            match frames.last_mut() {
                                Some(top) => {
                                    top.pc = pc;
                                    frames.push(Frame {
                                        chunk: c,
                                        pc: 0,
                                        gosub: false,
                                    });
                                    Some(next)
                                }
                                None => None,
                            }
                        }
                        _ => None,
                    };
                    let Some(next) = entered else {
                        *executed = n;
                        return Exit::Call { program, pc };
                    };
                    chunk = next;
                    pc = 0;
                    if n >= budget {
                        *executed = n;
                        return Exit::Yield(pc);
                    }
                    continue 'chunks;
                }
                Op::Print { .. } | Op::PrintZone | Op::PrintLine => {
                    if let Err(message) = print(*op, chunk, v, ctx) {
                        pc = here;
                        fault!("{message}");
                    }
                }
                Op::Gosub { target } => {
                    // As the machine's loop does it (`Machine::run_task`): the caller's frame
                    // resumes after the GOSUB, the subroutine's frame runs from its label, and the
                    // task yields there if its budget is spent.
                    let pushed = match frames.as_deref_mut() {
                        Some(frames) if frames.len() < super::MAX_CALL_DEPTH => {
                            match frames.last_mut() {
                                Some(top) => {
                                    top.pc = pc;
                                    let chunk = top.chunk;
                                    frames.push(Frame {
                                        chunk,
                                        pc: target,
                                        gosub: true,
                                    });
                                    true
                                }
                                None => false,
                            }
                        }
                        _ => false,
                    };
                    if !pushed {
                        *executed = n;
                        return Exit::Gosub { target, ret: pc };
                    }
                    pc = target;
                    if n >= budget {
                        *executed = n;
                        return Exit::Yield(pc);
                    }
                }
                Op::Return => {
                    // Back to the frame below a subroutine's (the same program), where its GOSUB
                    // left it; a RETURN without a GOSUB is reported by the caller.
                    let back = match frames.as_deref_mut() {
                        Some(frames)
                            if frames.len() >= 2 && frames.last().is_some_and(|f| f.gosub) =>
                        {
                            frames.pop();
                            frames.last().map(|f| f.pc)
                        }
                        _ => None,
                    };
                    let Some(back) = back else {
                        *executed = n;
                        return Exit::Return { pc: here };
                    };
                    pc = back;
                    if n >= budget {
                        *executed = n;
                        return Exit::Yield(pc);
                    }
                }
                // The two a polling loop runs every scan go straight to their handler.
                Op::AxisRead {
                    dst,
                    axes,
                    member,
                    truth,
                } => {
                    let mask = rd!(axes as usize);
                    // The usual read, one defined axis's member, straight from its slot; every
                    // other set (and every reason to refuse one) goes through `axis_read`.
                    let quick = ctx
                        .devices
                        .axis_layout()
                        .and_then(|l| l.single_slot(mask, u32::from(member)))
                        .and_then(|s| v.get(s as usize).copied());
                    match quick {
                        Some(x) if truth => wr!(dst as usize, if x != 0.0 { -1.0 } else { 0.0 }),
                        Some(x) => wr!(dst as usize, x),
                        None => match axis_read(ctx, v, mask, u32::from(member), truth) {
                            Ok(x) => wr!(dst as usize, x),
                            Err(message) => {
                                pc = here;
                                fault!("{message}");
                            }
                        },
                    }
                }
                Op::KernelCall { func, dst, args } => {
                    let a = args as usize;
                    let polled = v
                        .get(a..a + func.arity())
                        .and_then(|xs| ctx.devices.poll(func, xs));
                    if let Some(x) = polled {
                        wr!(dst as usize, x);
                    } else if let Err(message) = kernel_call(func, dst, args, v, ctx) {
                        pc = here;
                        fault!("{message}");
                    }
                }
                Op::AxisBit { .. } | Op::AxisWrite { .. } | Op::Motion { .. } => {
                    match motionbasic(*op, here, chunk, v, ctx) {
                        Ok(None) => {}
                        Ok(Some(exit)) => {
                            *executed = n;
                            return exit;
                        }
                        Err(message) => {
                            pc = here;
                            fault!("{message}");
                        }
                    }
                }
                Op::LoadIdx {
                    dst,
                    base,
                    idx,
                    len,
                } => {
                    let Some(i) = subscript(rd!(idx as usize), len) else {
                        pc = here;
                        fault!("{}", out_of_range(rd!(idx as usize), len));
                    };
                    wr!(dst as usize, rd!(base as usize + i as usize));
                }
                Op::StoreIdx {
                    base,
                    idx,
                    src,
                    len,
                    decimals,
                } => store_idx!(base, idx, src, len, decimals, here),
                Op::StoreIdxNext {
                    base,
                    idx,
                    src,
                    len,
                    decimals,
                } => {
                    // `store.idx` (here), then the `for.next` (here + 1) it was fused with.
                    store_idx!(base, idx, src, len, decimals, here);
                    n += 1;
                    pc = here + 2;
                    let next = here + 1;
                    debug_assert!((next as usize) < ops.len());
                    // SAFETY: a superinstruction is never the chunk's last instruction (`End`
                    // is), so the one after it is inside the chunk.
                    match *unsafe { ops.get_unchecked(next as usize) } {
                        Op::ForNext {
                            var,
                            limit,
                            body,
                            decimals,
                        } => for_next!(var, limit, body, decimals, next, sure!(next)),
                        _ => {
                            pc = next;
                            fault!("internal error: a store fused with a for.next that is not one");
                        }
                    }
                }
                Op::Subscript { dst, src, len } => {
                    wr!(dst as usize, subscr!(src, len, here))
                }
                Op::Offset2 { p, i, j, lens } => {
                    // The two `subscr` (here, here + 1), the `mul` and the `add`: each subscript
                    // checked and rounded as `Subscript` does; the offset, a product and sum of
                    // whole numbers below 2^32, is exact either way.
                    let n2 = lens & 0xffff;
                    let r = subscr!(i, lens >> 16, here);
                    n += 1;
                    let c = subscr!(j, n2, here + 1);
                    n += 2;
                    wr!(p as usize + 1, c);
                    wr!(p as usize, r * f64::from(n2) + c);
                    pc = here + 4;
                }
                Op::OffsetTail { p, x, len } => {
                    // The second `subscr` (here), the `mul` and the `add`, as `Offset2`'s.
                    let c = subscr!(x, len, here);
                    n += 2;
                    wr!(p as usize + 1, c);
                    wr!(p as usize, rd!(p as usize) * f64::from(len) + c);
                    pc = here + 3;
                }
                Op::LoadAt {
                    dst,
                    base,
                    off,
                    len,
                } => {
                    let o = rd!(off as usize);
                    if !(o >= 0.0 && o < f64::from(len)) {
                        pc = here;
                        fault!("internal error: element {o} of an array of {len}");
                    }
                    wr!(dst as usize, rd!(base as usize + o as usize));
                }
                Op::StoreAt {
                    base,
                    off,
                    src,
                    decimals,
                    len,
                } => {
                    let o = rd!(off as usize);
                    if !(o >= 0.0 && o < f64::from(len)) {
                        pc = here;
                        fault!("internal error: element {o} of an array of {len}");
                    }
                    let dst = base + o as u32;
                    let x = rd!(src as usize);
                    if decimals == INT_STORE {
                        store_int!(dst, x, here, sure!(here))
                    } else if decimals == 0 {
                        store_long!(dst, x, here, sure!(here))
                    } else if decimals == REAL_STORE {
                        store_real!(dst, x, here)
                    } else {
                        store_fixed!(dst, x, decimals, here, false)
                    }
                }
                Op::TextJump {
                    at,
                    target,
                    nonzero,
                    negate,
                } => {
                    // The comparison (here), its `neg` when `negate`, then the jump.
                    let holds = match text_jump(at, negate, chunk, v, ctx.strings) {
                        Ok(holds) => holds,
                        Err(message) => {
                            pc = here;
                            fault!("{message}");
                        }
                    };
                    n += 1 + u64::from(negate);
                    pc = here + 2 + u32::from(negate);
                    if holds == nonzero {
                        taken!(target);
                    }
                }
                Op::Ext { at, copies } => {
                    n += u64::from(copies);
                    if let Err(message) = ext(at, chunk, v, ctx) {
                        pc = here;
                        fault!("{message}");
                    }
                }
                Op::ExtPair {
                    at,
                    copies,
                    next,
                    next_copies,
                } => {
                    // Each counts as when it ran alone (the loop counted the first's 1).
                    n += u64::from(copies);
                    if let Err(fault) = ext_pair(at, next, chunk, v, ctx) {
                        let second = fault.0;
                        n += u64::from(second) * (1 + u64::from(next_copies));
                        pc = here + u32::from(second);
                        fault!("{}", fault.1);
                    }
                    n += 1 + u64::from(next_copies);
                    pc = here + 2;
                }
                Op::End => {
                    // The end of a called program: back to its caller's frame, as the machine's
                    // loop does it (the program's subroutine frames go with it). The end of the
                    // task's own program, or a caller this loop could not run unchecked, returns.
                    let back = match frames.as_deref_mut() {
                        Some(frames) => match frames.last() {
                            // The called program's own frame on top (no subroutine of it left).
                            Some(top) if !top.gosub => Some(frames.len() - 1),
                            _ => frames.iter().rposition(|f| !f.gosub),
                        }
                        .filter(|&k| k >= 1)
                        .and_then(|k| {
                            let caller = frames[k - 1];
                            let next = ctx.chunks.get(caller.chunk).filter(|c| {
                                c.closed
                                    && v.len() >= c.regs_end
                                    && (caller.pc as usize) < c.ops.len()
                            })?;
                            frames.truncate(k);
                            Some((next, caller.pc))
                        }),
                        None => None,
                    };
                    let Some((next, resume)) = back else {
                        *executed = n;
                        return Exit::End;
                    };
                    chunk = next;
                    pc = resume;
                    continue 'chunks;
                }
            }
        }
    }
}

/// The chunk of `program` when a `Call Program` may run it inside the interpreter: loaded, on
/// no other busy task, and runnable with the loop's unchecked registers (closed, every
/// register within the `values` values, an instruction to start at).
#[inline]
fn call_target<'c>(
    ctx: &mut Ctx<'c, '_>,
    program: u32,
    values: usize,
) -> Option<(usize, &'c Chunk)> {
    // Program n is mostly the n-th loaded; else a machine has few programs, and comparing
    // their numbers is quicker than hashing one.
    let c = match ctx.programs.get_index(program as usize) {
        Some((&p, &c)) if p == program => c,
        _ => *ctx.programs.iter().find(|(&p, _)| p == program)?.1,
    };
    let elsewhere = if c < 64 {
        // The other tasks are read at the turn's first call only.
        let mask = match ctx.elsewhere {
            Some(mask) => mask,
            None => *ctx.elsewhere.insert(busy_chunks(ctx.other_tasks)),
        };
        mask & (1 << c) != 0
    } else {
        ctx.other_tasks
            .iter()
            .flat_map(|tasks| tasks.iter())
            .any(|t| t.busy() && t.frames.iter().any(|f| f.chunk == c))
    };
    if elsewhere {
        return None;
    }
    let chunk = ctx.chunks.get(c)?;
    (chunk.closed && values >= chunk.regs_end && !chunk.ops.is_empty()).then_some((c, chunk))
}

/// The chunks below 64 on a frame of a busy task of `tasks`, as a set (bit c: chunk c).
fn busy_chunks(tasks: [&[super::task::Task]; 2]) -> u64 {
    tasks
        .iter()
        .flat_map(|tasks| tasks.iter())
        .filter(|t| t.busy())
        .flat_map(|t| t.frames.iter())
        .filter(|f| f.chunk < 64)
        .fold(0, |set, f| set | 1 << f.chunk)
}

/// The error of subscript `x` outside an array's `len` elements.
#[cold]
fn out_of_range(x: f64, len: u32) -> String {
    format!(
        "Subscript out of range: {x} is not within 0 to {}",
        len.saturating_sub(1)
    )
}

/// A subscript `x` rounded to an integer (halves to even), if within `0..len`. Whole
/// subscripts (a long's) take the quick way, without rounding.
#[inline(always)]
fn subscript(x: f64, len: u32) -> Option<u32> {
    let i = trunc_i32(x);
    let i = if f64::from(i) == x {
        i
    } else {
        let r = x.round_ties_even();
        if !(0.0..f64::from(len)).contains(&r) {
            return None;
        }
        r as i32
    };
    (i >= 0 && (i as u32) < len).then_some(i as u32)
}

/// A string handle in a register, as an index of the string table.
#[inline(always)]
fn handle(x: f64, strings: &[String]) -> Result<usize, String> {
    text_index(x, strings.len()).ok_or_else(|| not_a_string(x))
}

/// The string handle `x` as an index into a table of `len` strings, when it is one: what
/// [`handle`] takes, without its message (`vm::body` leaves an iteration on `None`).
#[inline(always)]
pub(super) fn text_index(x: f64, len: usize) -> Option<usize> {
    // A whole number converts back to itself (no `fract`, a library call on x86-64). Through
    // the bare conversion to `i64` (`usize`'s is twenty instructions): a negative, huge or NaN
    // `x` fails either test, as it failed through `usize`.
    let i = crate::fixed::trunc_i64(x);
    (i as f64 == x && (i as u64) < len as u64).then_some(i as usize)
}

/// The work of an [`Op::TextJump`] but its jump: the comparison of the side table's `at`,
/// its result (negated when `negate`) into its register; whether it holds. Its registers are
/// in the side table, outside `regs_end`: read with checks. Apart from the interpreter's loop,
/// where its registers would cost every instruction a spill.
#[inline(never)]
fn text_jump(
    at: u32,
    negate: bool,
    chunk: &Chunk,
    v: &mut [f64],
    strings: &[String],
) -> Result<bool, String> {
    let Some(&ExtOp::CompareText { cmp, dst, a, b }) = chunk.ext.get(at as usize) else {
        return Err(NO_REGISTER.to_string());
    };
    let (Some(&x), Some(&y)) = (v.get(a as usize), v.get(b as usize)) else {
        return Err(NO_REGISTER.to_string());
    };
    let holds = compare_text(cmp, x, y, strings)?;
    let Some(out) = v.get_mut(dst as usize) else {
        return Err(NO_REGISTER.to_string());
    };
    let x = f64::from(u8::from(holds));
    *out = if negate { -x } else { x };
    Ok(holds)
}

/// Whether the strings whose handles are `a` and `b` compare as `cmp` says (byte order).
/// An equality test of strings of different lengths reads none.
#[inline(always)]
fn compare_text(
    cmp: crate::compile::bytecode::Cmp,
    a: f64,
    b: f64,
    strings: &[String],
) -> Result<bool, String> {
    // `handle` gives only indices within the table.
    let x = strings[handle(a, strings)?].as_bytes();
    let y = strings[handle(b, strings)?].as_bytes();
    Ok(cmp.test_ord(x, y))
}

/// [`handle`]'s error, apart: its formatting would otherwise be laid out in every caller.
#[cold]
#[inline(never)]
fn not_a_string(x: f64) -> String {
    format!("internal error: {x} is not a string")
}

/// Copy string `src` into `cell`; whether it changed.
fn set_text(strings: &mut [String], cell: usize, src: usize) -> bool {
    if cell == src || strings[cell] == strings[src] {
        return false;
    }
    copy_text(strings, cell, src);
    true
}

/// Copy string `src` into `cell`, without asking whether it changes.
fn copy_text(strings: &mut [String], cell: usize, src: usize) {
    put_text(strings, cell, src);
}

/// [`copy_text`]'s work, inline: in `vm::body`'s runner a call would make LLVM load again
/// every constant it keeps in a register.
#[inline(always)]
pub(super) fn put_text(strings: &mut [String], cell: usize, src: usize) {
    if cell != src {
        let (dst, from) = two(strings, cell, src);
        dst.clear();
        crate::check::text::push(dst, from);
    }
}

/// Store string `src` into the string variable (or element) in slot `slot`, whose own cell
/// that slot holds; traced when it changes.
fn store_text(slot: usize, src: f64, v: &[f64], ctx: &mut Ctx<'_, '_>) -> Result<(), String> {
    let cell = handle(v.get(slot).copied().unwrap_or(-1.0), ctx.strings)?;
    // Cell 0 is the empty string every unassigned string reads: never a variable's own.
    if cell == 0 {
        return Err("internal error: a string variable without its storage".into());
    }
    let from = handle(src, ctx.strings)?;
    if !ctx.now.trace.enabled() || slot >= ctx.slot_count as usize {
        // Untraced: whether the string changed is not asked.
        copy_text(ctx.strings, cell, from);
        return Ok(());
    }
    let changed = set_text(ctx.strings, cell, from);
    if changed || ctx.now.trace.writes() {
        ctx.now.trace.emit(
            ctx.now.tick,
            &Event::TextChange {
                name: ctx.registry.slots[slot].name.text(),
                value: ctx.strings[cell].as_str().into(),
            },
        );
    }
    Ok(())
}

/// Put the string in `ctx.scratch` into `cell`; `dst` = the cell.
#[inline(always)]
fn give_text(dst: u32, cell: u32, v: &mut [f64], ctx: &mut Ctx<'_, '_>) -> Result<(), String> {
    let Some(out) = ctx.strings.get_mut(cell as usize) else {
        return Err(no_cell());
    };
    // The cell takes the built string's buffer and the scratch the cell's old one, which the
    // next string built empties first: no copy.
    std::mem::swap(out, ctx.scratch);
    v[dst as usize] = f64::from(cell);
    Ok(())
}

/// [`give_text`]'s error, apart from the common case.
#[cold]
#[inline(never)]
fn no_cell() -> String {
    "internal error: no such string cell".into()
}

/// A string function's arguments where the interpreter has them: registers, and the string
/// table their string handles index.
struct Given<'a> {
    v: &'a [f64],
    strings: &'a [String],
    args: [u32; 4],
    argc: u8,
    texts: u8,
}

impl Given<'_> {
    /// The register of argument `i`.
    #[inline(always)]
    fn register(&self, i: usize) -> Option<f64> {
        let r = *self.args.get(i)?;
        self.v.get(r as usize).copied()
    }
}

// Each read inlined where `text::apply` asks for it (LLVM's own choice was a call each).
impl crate::check::text::Args for Given<'_> {
    #[inline(always)]
    fn count(&self) -> usize {
        usize::from(self.argc)
    }

    #[inline(always)]
    fn is_text(&self, i: usize) -> bool {
        i < self.count() && self.texts & (1 << i) != 0
    }

    #[inline(always)]
    fn num(&self, i: usize) -> f64 {
        if i < self.count() && !self.is_text(i) {
            self.register(i).unwrap_or(0.0)
        } else {
            0.0
        }
    }

    #[inline(always)]
    fn text(&self, i: usize) -> Result<&str, String> {
        if !self.is_text(i) {
            return Ok("");
        }
        let x = self.register(i).unwrap_or(-1.0);
        Ok(&self.strings[handle(x, self.strings)?])
    }
}

/// The string whose handle is in register `r`.
#[inline(always)]
fn arg_text<'a>(v: &[f64], strings: &'a [String], r: Reg) -> Result<&'a str, String> {
    Ok(&strings[handle(v[r as usize], strings)?])
}

/// Cell `a` to change and cell `b` to read: two different cells of `strings` (`a != b`).
#[inline(always)]
fn two(strings: &mut [String], a: usize, b: usize) -> (&mut String, &String) {
    if a < b {
        let (l, r) = strings.split_at_mut(b);
        (&mut l[a], &r[0])
    } else {
        let (l, r) = strings.split_at_mut(a);
        (&mut r[0], &l[b])
    }
}

/// The instructions of the side table ([`Op::Ext`]): strings, `DATA`, random numbers. The
/// error boxed, so that the result comes back in registers and not through memory.
#[cold]
#[inline(never)]
fn ext(at: u32, chunk: &Chunk, v: &mut [f64], ctx: &mut Ctx<'_, '_>) -> Result<(), Box<str>> {
    side_table(at, chunk, v, ctx).map_err(String::into_boxed_str)
}

/// The work of an [`Op::ExtPair`]: the side table's `at`, then its `next`. Err: whether the
/// second faulted, and why (boxed, as [`ext`]'s).
#[cold]
#[inline(never)]
fn ext_pair(
    at: u32,
    next: u32,
    chunk: &Chunk,
    v: &mut [f64],
    ctx: &mut Ctx<'_, '_>,
) -> Result<(), Box<(bool, String)>> {
    side_table(at, chunk, v, ctx).map_err(|message| Box::new((false, message)))?;
    side_table(next, chunk, v, ctx).map_err(|message| Box::new((true, message)))
}

/// [`ext`]'s work, and each half of an [`ext_pair`]'s.
#[inline(always)]
fn side_table(at: u32, chunk: &Chunk, v: &mut [f64], ctx: &mut Ctx<'_, '_>) -> Result<(), String> {
    use crate::check::text::{self, Value as Arg};
    use crate::compile::bytecode::ExtOp;
    let Some(op) = chunk.ext.get(at as usize) else {
        return Err("internal error: no such instruction".into());
    };
    // A string function's result, built by `$work` in the scratch string (`$out`), given to
    // `$cell`; `$dst` = the cell.
    macro_rules! into_cell {
        ($dst:expr, $cell:expr, $out:ident => $work:expr) => {{
            ctx.scratch.clear();
            let $out = &mut *ctx.scratch;
            $work?;
            give_text($dst, $cell, v, ctx)?;
        }};
    }
    match *op {
        ExtOp::Len { dst, s } => {
            v[dst as usize] = text::count(arg_text(v, ctx.strings, s)?) as f64;
        }
        ExtOp::Asc { dst, s } => v[dst as usize] = text::asc(arg_text(v, ctx.strings, s)?)?,
        ExtOp::Val { dst, s } => v[dst as usize] = text::val(arg_text(v, ctx.strings, s)?),
        ExtOp::Instr { dst, hay, needle } => {
            let (hay, needle) = (
                arg_text(v, ctx.strings, hay)?,
                arg_text(v, ctx.strings, needle)?,
            );
            v[dst as usize] = text::instr(1, hay, needle);
        }
        ExtOp::Left { dst, cell, s, n } => into_cell!(dst, cell, out => {
            text::left(arg_text(v, ctx.strings, s)?, v[n as usize], out)
        }),
        ExtOp::Right { dst, cell, s, n } => into_cell!(dst, cell, out => {
            text::right(arg_text(v, ctx.strings, s)?, v[n as usize], out)
        }),
        ExtOp::Mid {
            dst,
            cell,
            s,
            start,
        } => into_cell!(dst, cell, out => {
            text::mid(arg_text(v, ctx.strings, s)?, v[start as usize], None, out)
        }),
        ExtOp::MidN {
            dst,
            cell,
            s,
            start,
            n,
        } => into_cell!(dst, cell, out => {
            let n = Some(v[n as usize]);
            text::mid(arg_text(v, ctx.strings, s)?, v[start as usize], n, out)
        }),
        ExtOp::Chr { dst, cell, code } => {
            into_cell!(dst, cell, out => text::chr(v[code as usize], out));
        }
        ExtOp::Str { dst, cell, x, how } => into_cell!(dst, cell, out => {
            text::str_of(v[x as usize], how, out);
            Ok::<(), String>(())
        }),
        ExtOp::StoreText { dst, src } => store_text(dst as usize, v[src as usize], v, ctx)?,
        ExtOp::StoreTextAt { base, off, src, .. } => {
            let slot = base as usize + v[off as usize] as usize;
            store_text(slot, v[src as usize], v, ctx)?;
        }
        ExtOp::CopyText { dst, cell, src } => {
            let from = handle(v[src as usize], ctx.strings)?;
            ctx.scratch.clone_from(&ctx.strings[from]);
            give_text(dst, cell, v, ctx)?;
        }
        ExtOp::Concat { dst, cell, a, b } => {
            let a = handle(v[a as usize], ctx.strings)?;
            let b = handle(v[b as usize], ctx.strings)?;
            if a == cell as usize && b != a {
                // The string built so far is in this join's own cell: `b` goes on its end.
                let (built, tail) = two(ctx.strings, a, b);
                text::append(built, tail)?;
                v[dst as usize] = f64::from(cell);
            } else {
                text::concat(&ctx.strings[a], &ctx.strings[b], ctx.scratch)?;
                give_text(dst, cell, v, ctx)?;
            }
        }
        ExtOp::Text {
            func,
            dst,
            cell,
            args,
            argc,
            texts,
        } => {
            let given = Given {
                v,
                strings: ctx.strings,
                args,
                argc,
                texts,
            };
            match text::apply(func, &given, ctx.scratch)? {
                Some(x) => v[dst as usize] = x,
                None => {
                    // Never more characters than bytes: most strings need no count.
                    if ctx.scratch.len() > text::MAX_LEN
                        && ctx.scratch.chars().count() > text::MAX_LEN
                    {
                        return Err(text::too_long());
                    }
                    give_text(dst, cell, v, ctx)?;
                }
            }
        }
        ExtOp::CompareText { cmp, dst, a, b } => {
            let holds = compare_text(cmp, v[a as usize], v[b as usize], ctx.strings)?;
            v[dst as usize] = f64::from(u8::from(holds));
        }
        ExtOp::Rnd { dst, arg } => {
            let arg = arg.map(|r| v[r as usize]);
            v[dst as usize] = ctx.rnd.call(arg);
        }
        ExtOp::Randomize { seed } => {
            let n = match seed {
                Some(r) => v[r as usize],
                None => ctx.seed.unwrap_or(1) as f64,
            };
            ctx.rnd.randomize(n);
        }
        ExtOp::Timer { dst } => v[dst as usize] = ctx.now.seconds(),
        ExtOp::CheckSubscript { src, low, high } => {
            let x = v[src as usize];
            let i = x.round_ties_even();
            if !(i >= f64::from(low) && i <= f64::from(high)) {
                return Err(format!(
                    "Subscript out of range: {x} is not within {low} to {high}"
                ));
            }
        }
        ExtOp::Read { dst, text } => {
            let i = *ctx.data_at as usize;
            let Some(item) = chunk.data.get(i) else {
                return Err(format!(
                    "Out of DATA: the program's {} DATA item(s) have all been read",
                    chunk.data.len()
                ));
            };
            v[dst as usize] = if text {
                f64::from(item.text)
            } else {
                item.number.ok_or_else(|| {
                    format!(
                        "Syntax error in DATA: `{}` (line {}) is not a number",
                        item.written, item.line
                    )
                })?
            };
            *ctx.data_at += 1;
        }
        ExtOp::Restore { item } => *ctx.data_at = item,
        ExtOp::PrintUsing {
            format,
            args,
            count,
            texts,
        } => {
            let fmt = &ctx.strings[handle(v[format as usize], ctx.strings)?];
            let mut values = Vec::with_capacity(count as usize);
            for i in 0..count as usize {
                let x = v[args as usize + i];
                values.push(if texts & (1 << i) != 0 {
                    Arg::Text(&ctx.strings[handle(x, ctx.strings)?])
                } else {
                    Arg::Num(x)
                });
            }
            let text = super::using::format(fmt, &values)?;
            ctx.printer.write(ctx.task, &text);
        }
    }
    Ok(())
}

/// `PRINT`'s instructions: a value written at the task's print position, a move to the next
/// zone, the end of a line (output and traced).
#[cold]
#[inline(never)]
fn print(op: Op, chunk: &Chunk, v: &[f64], ctx: &mut Ctx<'_, '_>) -> Result<(), String> {
    match op {
        Op::Print { src, how } => {
            let x = v[src as usize];
            if how == crate::compile::bytecode::PrintHow::Text {
                let text = ctx
                    .strings
                    .get(x as usize)
                    .filter(|_| x >= 0.0 && x.fract() == 0.0)
                    .ok_or_else(|| format!("{x} is not a string"))?;
                ctx.printer.write(ctx.task, text);
            } else {
                ctx.printer.write(ctx.task, &super::print::number(x, how));
            }
        }
        Op::PrintZone => ctx.printer.zone(ctx.task),
        _ => {
            let text = ctx.printer.finish(ctx.task);
            let program = (chunk.program != super::REPL_PROGRAM).then_some(chunk.program);
            ctx.printer
                .emit(ctx.now.trace, ctx.now.tick, ctx.task, program, text);
        }
    }
    Ok(())
}

/// The instructions only MotionBASIC programs use, kept out of the hot loop: `Ok(Some(exit))`
/// when the task must stop here (a full motion queue), `Err` for a run-time error.
#[cold]
#[inline(never)]
fn motionbasic(
    op: Op,
    here: u32,
    chunk: &Chunk,
    v: &mut [f64],
    ctx: &mut Ctx<'_, '_>,
) -> Result<Option<Exit>, String> {
    match op {
        Op::AxisBit { dst, a } => {
            let x = v[a as usize];
            if !(x.fract() == 0.0 && (1.0..=16.0).contains(&x)) {
                return Err(format!("{x} is not an axis number (1 to 16)"));
            }
            v[dst as usize] = f64::from(1u32 << (x as u32 - 1));
        }
        Op::AxisRead {
            dst,
            axes,
            member,
            truth,
        } => v[dst as usize] = axis_read(ctx, v, v[axes as usize], u32::from(member), truth)?,
        Op::AxisWrite { .. } | Op::Motion { .. } => {
            return motion_or_write(op, here, chunk, v, ctx)
        }
        Op::KernelCall { func, dst, args } => kernel_call(func, dst, args, v, ctx)?,
        _ => {}
    }
    Ok(None)
}

/// `dst = func(args…)`, a kernel function on the DSP axes.
#[inline(never)]
fn kernel_call(
    func: KernelFunc,
    dst: Reg,
    args: Reg,
    v: &mut [f64],
    ctx: &mut Ctx<'_, '_>,
) -> Result<(), String> {
    let a = args as usize;
    // The arguments are read where they are: no copy, since the axes write no register.
    let values = v.get(a..a + func.arity()).unwrap_or(&[]);
    let axes = ctx
        .devices
        .axes()
        .ok_or_else(|| format!("{} works on DSP axes: {NO_AXES}", func.name()))?;
    let x = axes
        .call(func, values, &mut ctx.now)
        .map_err(|m| format!("{}: {m}", func.name()))?;
    v[dst as usize] = x;
    Ok(())
}

/// A fused string comparison without its registers (never compiled so).
const NO_REGISTER: &str = "internal error: a string comparison without its operands";

/// The fault of a MotionBASIC axis instruction on a machine without DSP axes.
const NO_AXES: &str = "this machine has no DSP axes: define them in machine.toml ([axis.1] …)";

/// The MotionBASIC instructions that write to the axes: apart from [`motionbasic`], whose reads
/// a polling loop runs every scan.
#[inline(never)]
fn motion_or_write(
    op: Op,
    here: u32,
    chunk: &Chunk,
    v: &mut [f64],
    ctx: &mut Ctx<'_, '_>,
) -> Result<Option<Exit>, String> {
    match op {
        Op::AxisWrite {
            axes,
            src,
            member,
            hook,
            text,
        } => {
            let text = if text {
                let h = handle(v[src as usize], ctx.strings)?;
                Some(ctx.strings[h].clone())
            } else {
                None
            };
            axis_write(
                ctx,
                v,
                v[axes as usize],
                u32::from(member),
                hook,
                v[src as usize],
                text.as_deref(),
            )?
        }
        Op::Motion { cmd, axes, args } => {
            let mask = v[axes as usize];
            let a = args as usize;
            let operand = |i: usize| v.get(a + i).copied().unwrap_or(0.0);
            let operands = [operand(0), operand(1), operand(2), operand(3)];
            let axes = ctx.devices.axes().ok_or(NO_AXES)?;
            match axes.motion(cmd, mask, &operands, v)? {
                (true, Some(message)) => {
                    let line = chunk.lines.get(here as usize).copied().unwrap_or(0);
                    ctx.now.trace.emit(
                        ctx.now.tick,
                        &Event::Warning {
                            origin: Origin::Program {
                                task: ctx.task,
                                program: (chunk.program != super::REPL_PROGRAM)
                                    .then_some(chunk.program),
                                line,
                            },
                            message: message.into(),
                        },
                    );
                }
                (true, None) => {}
                // The axis's motion queue is full: the statement waits for room.
                (false, _) => return Ok(Some(Exit::Sleep { ticks: 1, pc: here })),
            }
        }
        _ => {}
    }
    Ok(None)
}

/// An overflow fault, built away from the hot loop.
#[cold]
#[inline(never)]
fn cold_overflow(
    ctx: &Ctx<'_, '_>,
    slot: u32,
    x: f64,
    decimals: u8,
    pc: u32,
    executed: &mut u64,
    n: u64,
) -> Exit {
    *executed = n;
    Exit::Fault {
        message: overflow_message(ctx, slot, x, decimals),
        pc,
    }
}

/// Builds a fault away from the hot loop, so the loop's state stays in registers.
#[cold]
#[inline(never)]
fn cold_fault(pc: u32, message: impl FnOnce() -> String) -> Exit {
    Exit::Fault {
        message: message(),
        pc,
    }
}

/// A binary operator; only division and MOD by zero fail.
#[inline(always)]
fn binary(op: BinaryOp, x: f64, y: f64) -> Result<f64, &'static str> {
    Ok(match op {
        BinaryOp::Add => x + y,
        BinaryOp::Sub => x - y,
        BinaryOp::Mul => x * y,
        BinaryOp::Div => {
            if y == 0.0 {
                return Err("division by zero");
            }
            x / y
        }
        BinaryOp::Mod => {
            if y == 0.0 {
                return Err("MOD by zero");
            }
            int_rem(x, y)
        }
        BinaryOp::Pow => power(x, y),
        BinaryOp::And => f64::from(x != 0.0 && y != 0.0),
        BinaryOp::Or => f64::from(x != 0.0 || y != 0.0),
        BinaryOp::Xor => f64::from((x != 0.0) != (y != 0.0)),
        BinaryOp::BitAnd => (int(x) & int(y)) as f64,
        BinaryOp::BitOr => (int(x) | int(y)) as f64,
        BinaryOp::BitXor => (int(x) ^ int(y)) as f64,
        BinaryOp::IntDiv | BinaryOp::BasicMod => return basic_integer(op, x, y),
    })
}

/// `x ^ y`. A square is `x * x`, as Lua computes it: the correctly rounded product, where
/// the C library's `pow` (a call, several times slower) is only within an ulp of it, and may
/// differ from one library to another.
#[inline(always)]
fn power(x: f64, y: f64) -> f64 {
    if y == 2.0 {
        x * x
    } else {
        x.powf(y)
    }
}

/// MotionBASIC's `\\` and `MOD` (Microsoft BASIC): both operands rounded to integers (halves to
/// even); `\\` truncates its quotient toward zero; a long integer outside 32 bits is an Overflow.
#[cold]
#[inline(never)]
fn basic_integer(op: BinaryOp, x: f64, y: f64) -> Result<f64, &'static str> {
    let (a, b) = (x.round_ties_even(), y.round_ties_even());
    if op == BinaryOp::BasicMod {
        if b == 0.0 {
            return Err("MOD by zero");
        }
        return Ok(a % b);
    }
    if !fits_i32(a) || !fits_i32(b) {
        return Err("Overflow: an operand of \\ does not fit a long integer");
    }
    if b == 0.0 {
        return Err("division by zero");
    }
    let q = (a / b).trunc();
    if !fits_i32(q) {
        return Err("Overflow: the quotient does not fit a long integer");
    }
    Ok(q)
}

/// A barrier LLVM cannot move or speculate (an empty `asm!` block has unknown side effects):
/// placed on one side of an `if`, it keeps the `if` a branch instead of a conditional move.
/// It emits no instruction.
#[inline(always)]
pub(super) fn keep_branch() {
    #[cfg(any(target_arch = "x86_64", target_arch = "aarch64"))]
    // SAFETY: an empty template reads and writes nothing (`nomem`, `nostack`, flags kept).
    unsafe {
        std::arch::asm!("", options(nomem, nostack, preserves_flags));
    }
}

/// MotionBASIC `MOD`. Whole operands within 32 bits (every long is one) take the integer
/// remainder: exactly what rounding them and `fmod` give, sign of a zero included, without
/// libm. Anything else goes the general way ([`basic_integer`]).
///
/// `sure`: both are whole numbers within 32 bits (not tested again).
#[inline(always)]
pub(super) fn basic_mod_of(x: f64, y: f64, sure: bool) -> Result<f64, &'static str> {
    let (i, j) = (trunc_i32(x), trunc_i32(y));
    // An out-of-range or NaN operand does not convert back to itself ([`trunc_i32`]).
    if (sure || (f64::from(i) == x && f64::from(j) == y)) && j != 0 {
        debug_assert!(f64::from(i) == x && f64::from(j) == y, "{x}, {y} not sure");
        // The remainder has the sign of x, a zero one included.
        Ok(f64::from(i.wrapping_rem(j)).copysign(x))
    } else {
        basic_integer(BinaryOp::BasicMod, x, y)
    }
}

/// MotionBASIC `\`, with the integer path of [`basic_mod_of`]: the quotient truncated toward
/// zero, as `(x / y).trunc()` gives it (a float quotient of two 32-bit integers is never
/// rounded across an integer).
///
/// `sure`: as [`basic_mod_of`].
#[inline(always)]
pub(super) fn basic_div_of(x: f64, y: f64, sure: bool) -> Result<f64, &'static str> {
    let (i, j) = (trunc_i32(x), trunc_i32(y));
    if (sure || (f64::from(i) == x && f64::from(j) == y)) && j != 0 && !(i == i32::MIN && j == -1) {
        debug_assert!(f64::from(i) == x && f64::from(j) == y, "{x}, {y} not sure");
        let q = i / j;
        // A zero quotient has the sign of x / y.
        Ok(if q == 0 && x.is_sign_negative() != y.is_sign_negative() {
            -0.0
        } else {
            f64::from(q)
        })
    } else {
        basic_integer(BinaryOp::IntDiv, x, y)
    }
}

/// The integer operators a superinstruction stores into a long.
///
/// `sure`: both operands are whole numbers within 32 bits (untested).
#[inline(always)]
pub(super) fn integer(op: BinaryOp, x: f64, y: f64, sure: bool) -> Result<f64, &'static str> {
    match op {
        BinaryOp::BasicMod => basic_mod_of(x, y, sure),
        BinaryOp::IntDiv => basic_div_of(x, y, sure),
        BinaryOp::BitAnd => Ok((int_of(x, sure) & int_of(y, sure)) as f64),
        BinaryOp::BitOr => Ok((int_of(x, sure) | int_of(y, sure)) as f64),
        BinaryOp::BitXor => Ok((int_of(x, sure) ^ int_of(y, sure)) as f64),
        _ => binary(op, x, y),
    }
}

/// A real stored into a long, when it is not already a whole number within 32 bits: halves
/// rounded to even (Microsoft BASIC's CLNG), `None` outside 32 bits.
#[cold]
#[inline(never)]
pub(super) fn round_long(raw: f64) -> Option<f64> {
    // `+ 0.0` turns a rounded -0.0 into 0.
    let x = raw.round_ties_even() + 0.0;
    fits_i32(x).then_some(x)
}

/// The integer a bitwise operator works on: halves rounded to even, as Microsoft BASIC does.
#[inline]
pub(super) fn int(x: f64) -> i64 {
    // Integers (the common case) convert with one instruction each way; only fractions need
    // rounding, and only values past 32 bits the 64-bit conversion.
    let i = trunc_i32(x);
    if f64::from(i) == x {
        return i64::from(i);
    }
    let i = x as i64;
    if i as f64 == x {
        i
    } else {
        x.round_ties_even() as i64
    }
}

/// Whether a `MOD`'s operands `x` and `y` take the integer path (both whole within 32 bits):
/// when `sure` they are known to be; when `wide`, `x` is known whole and `y` within 32 bits,
/// so only `x`'s range is tested; otherwise both are tested.
#[inline(always)]
fn mod_int_path(x: f64, y: f64, sure: bool, wide: bool) -> bool {
    if sure {
        true
    } else if wide {
        debug_assert!(!x.is_finite() || x.fract() == 0.0, "{x} not whole");
        fits_i32(x)
    } else {
        f64::from(trunc_i32(x)) == x && f64::from(trunc_i32(y)) == y
    }
}

/// `(x - x MOD y) / y` (PowerTools' whole quotient, [`int_rem_of`] then a division) of two
/// whole numbers within 32 bits, `y` not 0: one integer division gives it, with the sign of a
/// zero quotient the float division gives (`+0 / y`: -0 when `y` is negative).
#[inline(always)]
fn whole_quotient(x: f64, y: f64) -> f64 {
    let (i, j) = (trunc_i32(x), trunc_i32(y));
    debug_assert!(
        f64::from(i) == x && f64::from(j) == y && j != 0,
        "{x}, {y} not sure"
    );
    match i.checked_div(j) {
        Some(0) => 0.0 / y,
        Some(q) => f64::from(q),
        // -2^31 / -1: 2^31, outside 32 bits but exact as a float.
        None => -x,
    }
}

/// [`int`] of `x`, which is, when `sure`, a whole number within 32 bits (untested).
#[inline(always)]
fn int_of(x: f64, sure: bool) -> i64 {
    if sure {
        debug_assert!(f64::from(trunc_i32(x)) == x, "{x} not sure");
        i64::from(trunc_i32(x))
    } else {
        int(x)
    }
}

/// Read member `member` of the DSP axes in `mask`.
#[inline(never)]
fn axis_read(
    ctx: &mut Ctx<'_, '_>,
    v: &[f64],
    mask: f64,
    member: u32,
    truth: bool,
) -> Result<f64, String> {
    let Some(orion) = ctx.devices.axes() else {
        return Err(NO_AXES.into());
    };
    let axes = orion.axes_of(mask)?;
    let slot = |n: u32| orion.slot(n, member).map(|s| v[s as usize]).unwrap_or(0.0);
    if truth {
        // MotionBASIC's true is -1; a test on a set of axes holds when it holds on each.
        return Ok(if axes.iter().all(|n| slot(n) != 0.0) {
            -1.0
        } else {
            0.0
        });
    }
    match axes.single() {
        Some(n) => Ok(slot(n)),
        None => Err(format!(
            "this controller variable reads one axis, not the set {:?}",
            axes.iter().collect::<Vec<_>>()
        )),
    }
}

/// Write member `member` of every DSP axis in `mask`.
fn axis_write(
    ctx: &mut Ctx<'_, '_>,
    v: &mut [f64],
    mask: f64,
    member: u32,
    hook: Hook,
    value: f64,
    text: Option<&str>,
) -> Result<(), String> {
    let Some(orion) = ctx.devices.axes() else {
        return Err(NO_AXES.into());
    };
    let axes = orion.axes_of(mask)?;
    if let Some(text) = text {
        for n in axes.iter() {
            orion.write_text(n, member, text, &mut ctx.now)?;
        }
        return Ok(());
    }
    let mut written = Vec::with_capacity(axes.len());
    for n in axes.iter() {
        orion.write(hook, n, member, value, v, &mut ctx.now)?;
        written.extend(orion.slot(n, member));
    }
    if ctx.now.trace.enabled() {
        for slot in written {
            traced_write(ctx, slot, value);
        }
    }
    Ok(())
}

use crate::compile::whole::{PLAIN, SURE, WIDE};
use crate::fixed::to_fixed as fixed;
use crate::fixed::trunc_i32;

#[cold]
#[inline(never)]
fn overflow_message(ctx: &Ctx<'_, '_>, slot: u32, x: f64, decimals: u8) -> String {
    let name = name_of(ctx, slot);
    if decimals == REAL_STORE {
        return format!("{name} cannot take {x}: the result is not a finite number");
    }
    if decimals == INT_STORE {
        return format!("Overflow: {x} does not fit {name} (an integer: -32768 to 32767)");
    }
    if x.is_finite() {
        let range = crate::fixed::range_text(decimals);
        format!(
            "overflow: {x} does not fit {name} (32-bit with {decimals} decimal places: {range})"
        )
    } else {
        format!("{name} cannot take {x}: the result is not a number")
    }
}

/// `x` as a MotionBASIC INTEGER: rounded to the nearest whole number (halves to even), `None`
/// outside 16 bits.
pub(super) fn int16(x: f64) -> Option<f64> {
    // A whole number (the common case) needs no rounding: `round_ties_even` is a library call
    // on the x86-64 baseline.
    let r = if f64::from(trunc_i32(x)) == x {
        x
    } else {
        x.round_ties_even()
    };
    fits_i16(r).then_some(r + 0.0)
}

/// The whole number `x` (or a non-finite one) as a long or a whole fixed-point slot stores it
/// (a -0 made 0), `None` outside 32 bits or not finite: only its range is tested.
#[inline(always)]
fn whole_in_range(x: f64) -> Option<f64> {
    fits_i32(x).then_some(x + 0.0)
}

/// Whether `x` is within a long's 32 bits (NaN is not).
#[inline(always)]
fn fits_i32(x: f64) -> bool {
    (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&x)
}

/// Whether `x` is within a MotionBASIC INTEGER's 16 bits (NaN is not).
#[inline(always)]
fn fits_i16(x: f64) -> bool {
    (-32768.0..=32767.0).contains(&x)
}

/// `x MOD y` with the sign of `x`; exact and fast (no libm `fmod`) when both are whole numbers.
#[inline(always)]
fn int_rem(x: f64, y: f64) -> f64 {
    int_rem_of(x, y, false)
}

/// [`int_rem`] of operands that are, when `sure`, whole numbers within 32 bits (untested).
#[inline(always)]
pub(super) fn int_rem_of(x: f64, y: f64, sure: bool) -> f64 {
    // Within 32 bits (every integer variable) a 32-bit division, quicker than a 64-bit one;
    // both give the same remainder, a zero one as 0.
    let (i, j) = (trunc_i32(x), trunc_i32(y));
    if (sure || (f64::from(i) == x && f64::from(j) == y)) && j != 0 {
        debug_assert!(f64::from(i) == x && f64::from(j) == y, "{x}, {y} not sure");
        return f64::from(i.wrapping_rem(j));
    }
    let (a, b) = (x as i64, y as i64);
    if a as f64 == x && b as f64 == y && b != 0 && a != i64::MIN {
        (a % b) as f64
    } else {
        x % y
    }
}

fn name_of(ctx: &Ctx<'_, '_>, slot: u32) -> String {
    ctx.registry
        .slots
        .get(slot as usize)
        .map_or_else(|| "a loop variable".to_string(), |s| s.name.to_string())
}

/// Trace a program's write to a registry slot, whether or not the value changed.
#[inline(never)]
fn traced_write(ctx: &mut Ctx<'_, '_>, slot: u32, value: f64) {
    let info = &ctx.registry.slots[slot as usize];
    if info.member.continuous || info.member.derived {
        return;
    }
    // A write that leaves the value as last traced is no change (unless every write is
    // recorded): a loop mirroring an input would otherwise fill a disk.
    if !ctx.now.trace.writes() && ctx.snapshot[slot as usize].to_bits() == value.to_bits() {
        return;
    }
    ctx.snapshot[slot as usize] = value;
    ctx.now.trace.emit(
        ctx.now.tick,
        &Event::Change {
            name: info.name.text(),
            value: Value::of(info.ty, value),
        },
    );
}

/// After a kernel write or action, trace the members it changed, right away and in slot order.
fn sync_snapshot(ctx: &mut Ctx<'_, '_>, v: &[f64]) {
    if !ctx.now.trace.enabled() {
        return;
    }
    super::trace_changes(ctx.registry, v, ctx.snapshot, ctx.now.trace, ctx.now.tick);
}

#[cfg(test)]
mod tests {
    use super::{
        basic_div_of, basic_integer, basic_mod_of, binary, handle, int, int_of, int_rem,
        int_rem_of, power, BinaryOp,
    };

    /// A string handle is a whole index of the table; anything else (a fraction, a negative,
    /// -0's neighbours, past the table, past `i64`, infinite, NaN) is refused, never wrapped.
    #[test]
    fn string_handles_are_whole_indices_of_the_table() {
        let table = vec![String::new(); 3];
        for (x, want) in [(0.0, Some(0)), (-0.0, Some(0)), (2.0, Some(2))] {
            assert_eq!(handle(x, &table).ok(), want, "{x}");
        }
        let refused = [
            3.0,
            1.5,
            -1.0,
            -f64::MIN_POSITIVE,
            9.3e18,
            -9.3e18,
            -9_223_372_036_854_775_808.0,
            18_446_744_073_709_551_616.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for x in refused {
            assert!(handle(x, &table).is_err(), "{x}");
        }
    }

    /// The integer paths of MOD and `\` give exactly (bit for bit, the sign of zero and every
    /// error included) what rounding both operands and dividing as reals gives.
    #[test]
    fn integer_paths_match_the_general_ones() {
        let values = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            2.0,
            -2.0,
            3.0,
            -3.0,
            7.0,
            -7.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            6.5,
            -6.5,
            2147483647.0,
            -2147483648.0,
            2147483648.0,
            -2147483649.0,
            2147483647.5,
            1e10,
            -1e10,
            f64::NAN,
            f64::INFINITY,
        ];
        fn bits(r: Result<f64, &'static str>) -> Result<u64, &'static str> {
            r.map(f64::to_bits)
        }
        for &x in &values {
            for &y in &values {
                assert_eq!(
                    bits(basic_mod_of(x, y, false)),
                    bits(basic_integer(BinaryOp::BasicMod, x, y)),
                    "{x} MOD {y}"
                );
                assert_eq!(
                    bits(basic_div_of(x, y, false)),
                    bits(basic_integer(BinaryOp::IntDiv, x, y)),
                    "{x} \\ {y}"
                );
                // Operands known whole within 32 bits, taken untested, give the same.
                let whole = |v: f64| f64::from(crate::fixed::trunc_i32(v)) == v;
                if whole(x) && whole(y) {
                    assert_eq!(
                        bits(basic_mod_of(x, y, true)),
                        bits(basic_mod_of(x, y, false))
                    );
                    assert_eq!(
                        bits(basic_div_of(x, y, true)),
                        bits(basic_div_of(x, y, false))
                    );
                    assert_eq!(int_rem_of(x, y, true).to_bits(), int_rem(x, y).to_bits());
                    assert_eq!(int_of(x, true), int(x));
                }
            }
        }
    }

    #[test]
    fn a_square_is_the_product_and_other_powers_are_pow() {
        let xs = [
            0.0,
            -0.0,
            1.1,
            -3.7,
            0.1,
            1e-200,
            1e200,
            -1e200,
            123_456.789,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for x in xs {
            let square = power(x, 2.0);
            assert_eq!(square.to_bits(), (x * x).to_bits(), "{x} ^ 2");
            // Within pow's own error of it (special values alike).
            let pow = x.powf(2.0);
            assert!(
                square == pow
                    || (square.is_nan() && pow.is_nan())
                    || (square - pow).abs() <= pow.abs() * f64::EPSILON,
                "{x}: {square} against {pow}"
            );
            for y in [0.5, 3.0, -2.0, 2.5] {
                assert_eq!(power(x, y).to_bits(), x.powf(y).to_bits(), "{x} ^ {y}");
            }
        }
        assert_eq!(power(1.1, 2.0), 1.2100000000000002);
        assert_eq!(binary(BinaryOp::Pow, -3.0, 2.0), Ok(9.0));
    }

    #[test]
    fn remainder_matches_fmod() {
        for (x, y) in [
            (7.0, 3.0),
            (-7.0, 3.0),
            (7.0, -3.0),
            (7.5, 2.0),
            (1e18, 7.0),
            (-0.0, 5.0),
        ] {
            assert_eq!(int_rem(x, y), x % y, "{x} {y}");
        }
    }
}
