//! Loops whose whole body is one instruction: an empty `FOR … NEXT` (a delay) and a `FOR` whose
//! body is one store into an element subscripted by the loop's variable (a fill, a clear, a
//! sieve's marking). In the interpreter the variable goes through its slot from one iteration
//! to the next (a store, then a load that waits for it); here it stays in a register, in a
//! function of its own whose few values all fit in registers. The compiler makes the
//! `for.check` entering one an `Op::ForTight` (`compile::tight`), which the interpreter leaves
//! to the machine (`exec::Exit::Loop`, `Machine::enter_loop`): its own code stays as it was
//! (any test added to it changes how LLVM lays out all of it).
//!
//! Only the plain iterations run here: the variable and step whole (`Chunk::sure`), nothing
//! traced, every value in range. An iteration that is not plain (a subscript out of range, a
//! value that does not fit, a sum past the variable's range) is left undone, for the
//! interpreter to run as it runs every other (with its fault), so that both give the same
//! values, faults and instruction counts.

pub use crate::compile::tight::{plan, Fill, Plan, INT, LONG, REAL};
use crate::fixed::trunc_i32;

/// Where a run of [`run`] stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// The loop's test failed: the loop is done (the variable holds its last value).
    Done,
    /// The budget is spent, at the start of an iteration (to yield there).
    Budget,
    /// The next iteration is not plain: the interpreter runs it, from its start.
    Slow,
}

/// The loop of a `for.next` whose body is itself or the store before it.
#[derive(Debug, Clone, Copy)]
pub struct Loop {
    /// The variable's register.
    pub var: usize,
    /// The step: a whole number.
    pub step: f64,
    /// The limit.
    pub limit: f64,
    /// The variable is a MotionBASIC INTEGER (16 bits); else a 32-bit whole number.
    pub int16: bool,
}

/// Run the plain iterations of `lp` (with the store `fill` of elements of kind `KIND`, or
/// none), each counted in `n` as the interpreter counts it: on entry `n` counts the dispatch of
/// the iteration about to run. Stops at the first iteration that is not plain, untouched.
#[inline(never)]
pub fn run<const KIND: u8>(
    vals: &mut [f64],
    lp: Loop,
    fill: Option<Fill>,
    n: &mut u64,
    budget: u64,
) -> End {
    let Loop {
        var,
        step,
        limit,
        int16,
    } = lp;
    // Every register used is checked once here, so the loop indexes without checks.
    let inside = |r: usize| r < vals.len();
    if !inside(var) || fill.is_some_and(|f| !inside(f.src) || f.base + f.len as usize > vals.len())
    {
        return End::Slow;
    }
    let (up, down) = (step > 0.0, step < 0.0);
    let mut count = *n;
    let mut v = vals[var];
    let end = loop {
        let next = v + step;
        let fits = if int16 {
            (-32768.0..=32767.0).contains(&next)
        } else {
            (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&next)
        };
        if !fits {
            break End::Slow;
        }
        if let Some(f) = fill {
            // `v` is whole within 32 bits (the variable is sure): the conversion is exact.
            let i = trunc_i32(v);
            if i < 0 || i as u32 >= f.len {
                break End::Slow;
            }
            // SAFETY: `src` and every element (`base + i`, `i < len`) were checked above to be
            // inside `vals`.
            let x = unsafe { *vals.get_unchecked(f.src) };
            let plain = match KIND {
                LONG => (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&x),
                INT => (-32768.0..=32767.0).contains(&x),
                _ => x.is_finite(),
            };
            if !plain {
                break End::Slow;
            }
            // A whole -0 is stored as 0, as the interpreter's store does.
            let x = if KIND == REAL { x } else { x + 0.0 };
            // SAFETY: as above.
            unsafe { *vals.get_unchecked_mut(f.base + i as usize) = x };
            // The `for.next`.
            count += 1;
        }
        // SAFETY: `var` was checked above to be inside `vals`.
        unsafe { *vals.get_unchecked_mut(var) = next };
        v = next;
        if !(if up { v <= limit } else { down && v >= limit }) {
            break End::Done;
        }
        if count >= budget {
            break End::Budget;
        }
        // The next iteration's dispatch.
        count += 1;
    };
    *n = count;
    end
}

/// The fewest iterations of a loop worth leaving the interpreter for: leaving and entering it
/// again costs about as much as a few iterations save.
pub const FEWEST: f64 = 16.0;

/// Run the plain iterations of the loop `plan` over the values `vals`, counted in `n` as
/// [`run`] counts them, and say where the interpreter goes on: after the loop when it is done,
/// at its start when the budget is spent or the next iteration is not plain.
pub fn run_plan(vals: &mut [f64], plan: Plan, pc: u32, n: &mut u64, budget: u64) -> (End, u32) {
    let (Some(&limit), Some(&step)) = (
        vals.get(plan.limit as usize),
        vals.get(plan.limit as usize + 1),
    ) else {
        return (End::Slow, pc);
    };
    let lp = Loop {
        var: plan.var as usize,
        step,
        limit,
        int16: plan.int16,
    };
    let end = match plan.fill {
        None => run::<LONG>(vals, lp, None, n, budget),
        Some((fill, LONG)) => run::<LONG>(vals, lp, Some(fill), n, budget),
        Some((fill, INT)) => run::<INT>(vals, lp, Some(fill), n, budget),
        Some((fill, _)) => run::<REAL>(vals, lp, Some(fill), n, budget),
    };
    (end, if end == End::Done { plan.after } else { pc })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lp(step: f64, limit: f64) -> Loop {
        Loop {
            var: 0,
            step,
            limit,
            int16: false,
        }
    }

    #[test]
    fn an_empty_loop_counts_one_a_turn_and_stops_at_its_limit_or_budget() {
        let mut vals = [1.0];
        let mut n = 1;
        assert_eq!(
            run::<LONG>(&mut vals, lp(1.0, 10.0), None, &mut n, 100),
            End::Done
        );
        assert_eq!((vals[0], n), (11.0, 10));
        let mut vals = [1.0];
        let mut n = 1;
        assert_eq!(
            run::<LONG>(&mut vals, lp(2.0, 100.0), None, &mut n, 5),
            End::Budget
        );
        assert_eq!((vals[0], n), (11.0, 5));
        // Counting down; a zero step runs once.
        let mut vals = [5.0];
        let mut n = 1;
        assert_eq!(
            run::<LONG>(&mut vals, lp(-1.0, 0.0), None, &mut n, 100),
            End::Done
        );
        assert_eq!((vals[0], n), (-1.0, 6));
        let mut vals = [5.0];
        let mut n = 1;
        assert_eq!(
            run::<LONG>(&mut vals, lp(0.0, 9.0), None, &mut n, 100),
            End::Done
        );
        assert_eq!((vals[0], n), (5.0, 1));
    }

    #[test]
    fn an_iteration_past_the_range_is_left_undone() {
        let mut vals = [32765.0];
        let mut n = 1;
        let int = Loop {
            int16: true,
            ..lp(1.0, 40000.0)
        };
        assert_eq!(run::<LONG>(&mut vals, int, None, &mut n, 100), End::Slow);
        // 32766 and 32767 stored; the step to 32768 is the interpreter's (its Overflow).
        assert_eq!((vals[0], n), (32767.0, 3));
    }

    #[test]
    fn a_fill_stores_each_element_and_stops_before_one_out_of_range_or_not_fitting() {
        // var, src, then the array of 4.
        let fill = Some(Fill {
            base: 2,
            len: 4,
            src: 1,
        });
        let mut vals = [0.0, -0.0, 9.0, 9.0, 9.0, 9.0];
        let mut n = 1;
        assert_eq!(
            run::<LONG>(&mut vals, lp(1.0, 3.0), fill, &mut n, 100),
            End::Done
        );
        assert_eq!(vals, [4.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!(vals[2].is_sign_positive());
        assert_eq!(n, 8);
        // Past the array: the element 4 is the interpreter's.
        let mut vals = [2.0, 7.0, 9.0, 9.0, 9.0, 9.0];
        let mut n = 1;
        assert_eq!(
            run::<LONG>(&mut vals, lp(1.0, 10.0), fill, &mut n, 100),
            End::Slow
        );
        assert_eq!(vals, [4.0, 7.0, 9.0, 9.0, 7.0, 7.0]);
        assert_eq!(n, 5);
        // A value that does not fit an INTEGER: nothing done.
        let mut vals = [0.0, 40000.0, 9.0, 9.0, 9.0, 9.0];
        let mut n = 1;
        assert_eq!(
            run::<INT>(&mut vals, lp(1.0, 3.0), fill, &mut n, 100),
            End::Slow
        );
        assert_eq!((vals[0], vals[2], n), (0.0, 9.0, 1));
        // A real element keeps -0 and refuses infinity.
        let mut vals = [0.0, -0.0, 9.0, 9.0, 9.0, 9.0];
        let mut n = 1;
        assert_eq!(
            run::<REAL>(&mut vals, lp(1.0, 0.0), fill, &mut n, 100),
            End::Done
        );
        assert!(vals[2].is_sign_negative());
        let mut vals = [0.0, f64::INFINITY, 9.0, 9.0, 9.0, 9.0];
        let mut n = 1;
        assert_eq!(
            run::<REAL>(&mut vals, lp(1.0, 3.0), fill, &mut n, 100),
            End::Slow
        );
        assert_eq!(vals[2], 9.0);
        // Registers outside the values: all left to the interpreter.
        let mut vals = [0.0, 1.0];
        let mut n = 1;
        assert_eq!(
            run::<LONG>(&mut vals, lp(1.0, 3.0), fill, &mut n, 100),
            End::Slow
        );
    }
}
