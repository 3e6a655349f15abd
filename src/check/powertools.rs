//! The PowerTools dialect's rules: every name an object member of the machine, values ON/OFF or
//! numbers (never mixed: a bit is ON or OFF, not 1 or 0), actions run bare or assigned ON, motion
//! initiates with `Using` and `On Profile`, dwells, waits and `Call Program.N`.

use super::functions;
use super::typed::{self, Cmp, ExprKind as K, Op, StmtKind as T, Ty};
use super::walk::{not_here, Context, Rules, Want};
use crate::devices::command::{Domain, StartRef};
use crate::diag::{nearest, Problem};
use crate::registry::{Access, Hook, Kind, Registry, Resolved};
use crate::span::Span;
use crate::syntax::ast::{BinOp, Expr, ExprKind, Name, Stmt, StmtKind, UnOp, Using};
use crate::syntax::Dialect;

/// The PowerTools rules.
#[derive(Debug, Default)]
pub struct PowerTools;

impl Ty {
    fn word(self) -> &'static str {
        match self {
            Ty::Bool => "an ON/OFF value",
            Ty::Num => "a number",
            Ty::Str => "a string",
            Ty::Axis => "an axis set",
        }
    }
}

/// A PowerTools expression, typed, or its first problem.
pub fn expr(e: &Expr, registry: &Registry) -> Result<typed::Expr, Problem> {
    let typed = |kind, ty| typed::Expr {
        kind,
        ty,
        long: false,
        int16: false,
        int_const: false,
        truth: ty == Ty::Bool,
        span: e.span,
    };
    match &e.kind {
        ExprKind::Number(v, _) if !v.is_finite() => Err(Problem::error(
            "pacer::check::number",
            e.span,
            "this number is too large to represent",
            "out of range",
        )
        .with_help("numbers are 64-bit floating point while computing, and 32-bit where stored")),
        ExprKind::Number(v, _) => Ok(typed(K::Const(*v), Ty::Num)),
        ExprKind::Bool(b) => Ok(typed(
            K::Bool {
                value: *b,
                number: f64::from(u8::from(*b)),
            },
            Ty::Bool,
        )),
        ExprKind::Paren(inner) => {
            let inner = expr(inner, registry)?;
            let ty = inner.ty;
            Ok(typed(K::Paren(Box::new(inner)), ty))
        }
        ExprKind::Name(n) => {
            let r = registry.resolve(n)?;
            readable(&r, n.span)?;
            let ty = if r.ty.is_bit() { Ty::Bool } else { Ty::Num };
            Ok(typed(
                K::Read {
                    target: r,
                    negate: false,
                },
                ty,
            ))
        }
        ExprKind::Unary(UnOp::Neg, inner) => {
            let inner = want(inner, Ty::Num, registry, "`-` needs a number")?;
            Ok(typed(K::Neg(Box::new(inner)), Ty::Num))
        }
        ExprKind::Unary(UnOp::Not, inner) => {
            let inner = expr(inner, registry)?;
            let ty = inner.ty;
            let kind = if ty == Ty::Bool {
                K::Not(Box::new(inner))
            } else {
                K::BitNot(Box::new(inner))
            };
            Ok(typed(kind, ty))
        }
        ExprKind::Binary(op, a, b) => {
            let ta = expr(a, registry)?;
            let tb = expr(b, registry)?;
            let (op_t, ty) = match op {
                BinOp::And | BinOp::Or | BinOp::Xor => {
                    if ta.ty != tb.ty {
                        return Err(mixed(*op, a, ta.ty, b, tb.ty));
                    }
                    let logical = ta.ty == Ty::Bool;
                    let op_t = match (op, logical) {
                        (BinOp::And, true) => Op::And,
                        (BinOp::Or, true) => Op::Or,
                        (_, true) => Op::Xor,
                        (BinOp::And, false) => Op::BitAnd,
                        (BinOp::Or, false) => Op::BitOr,
                        (_, false) => Op::BitXor,
                    };
                    (op_t, ta.ty)
                }
                BinOp::Eq | BinOp::Ne => {
                    if ta.ty != tb.ty {
                        return Err(mixed(*op, a, ta.ty, b, tb.ty));
                    }
                    (Op::Cmp(cmp_of(*op)), Ty::Bool)
                }
                BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
                    num_operand(*op, a, ta.ty)?;
                    num_operand(*op, b, tb.ty)?;
                    (Op::Cmp(cmp_of(*op)), Ty::Bool)
                }
                arith => {
                    num_operand(*op, a, ta.ty)?;
                    num_operand(*op, b, tb.ty)?;
                    (arithmetic(*arith), Ty::Num)
                }
            };
            Ok(typed(
                K::Binary {
                    op: op_t,
                    a: Box::new(ta),
                    b: Box::new(tb),
                    negate: false,
                },
                ty,
            ))
        }
        ExprKind::Str(_) | ExprKind::AxisSet(_) => Err(Problem::error(
            "pacer::check::dialect",
            e.span,
            "strings and axis sets are MotionBASIC values",
            "not PowerTools",
        )),
        ExprKind::Call(f, args) => {
            if let Some((func, arity)) = functions::find_kernel(&f.text) {
                if args.len() != arity {
                    return Err(Problem::error(
                        "pacer::check::arguments",
                        e.span,
                        format!(
                            "{} takes {arity} arguments, not {}",
                            f.text.to_ascii_uppercase(),
                            args.len()
                        ),
                        "wrong number of arguments",
                    ));
                }
                // Arguments are numbers; ON/OFF stands for 1/0 (REGIST's EN).
                let args = args
                    .iter()
                    .map(|a| expr(a, registry))
                    .collect::<Result<Vec<_>, _>>()?;
                return Ok(typed(
                    K::Kernel {
                        func,
                        args,
                        negate: false,
                    },
                    Ty::Num,
                ));
            }
            let Some((func, arity)) = functions::find(&f.text) else {
                let names = functions::FUNCTIONS
                    .iter()
                    .map(|f| f.0)
                    .chain(functions::KERNEL_FUNCTIONS.iter().map(|f| f.0));
                return Err(Problem::error(
                    "pacer::check::unknown_function",
                    f.span,
                    format!("unknown function `{}`", f.text),
                    "not a function",
                )
                .with_help_opt(nearest(&f.text, names).map(|n| format!("did you mean `{n}`?"))));
            };
            if args.len() != arity {
                return Err(Problem::error(
                    "pacer::check::arguments",
                    e.span,
                    format!(
                        "{} takes {arity} argument{}, not {}",
                        f.text.to_ascii_uppercase(),
                        if arity == 1 { "" } else { "s" },
                        args.len()
                    ),
                    "wrong number of arguments",
                ));
            }
            let args = args
                .iter()
                .map(|a| want(a, Ty::Num, registry, "function arguments are numbers"))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(typed(K::Call(func, args), Ty::Num))
        }
    }
}

/// The operator of an arithmetic `op`.
fn arithmetic(op: BinOp) -> Op {
    match op {
        BinOp::Add => Op::Add,
        BinOp::Sub => Op::Sub,
        BinOp::Mul => Op::Mul,
        BinOp::Div => Op::Div,
        BinOp::Pow => Op::Pow,
        BinOp::IntDiv => Op::IntDiv,
        _ => Op::Mod,
    }
}

/// The comparison `op` is (`=` for the others, which never reach here).
pub fn cmp_of(op: BinOp) -> Cmp {
    match op {
        BinOp::Ne => Cmp::Ne,
        BinOp::Lt => Cmp::Lt,
        BinOp::Le => Cmp::Le,
        BinOp::Gt => Cmp::Gt,
        BinOp::Ge => Cmp::Ge,
        _ => Cmp::Eq,
    }
}

fn want(e: &Expr, ty: Ty, registry: &Registry, why: &str) -> Result<typed::Expr, Problem> {
    let t = expr(e, registry)?;
    if t.ty != ty {
        return Err(type_error(e, t.ty, ty).with_help(why.to_string()));
    }
    Ok(t)
}

fn type_error(e: &Expr, got: Ty, wanted: Ty) -> Problem {
    Problem::error(
        "pacer::check::type",
        e.span,
        format!("expected {}, found {}", wanted.word(), got.word()),
        format!("this is {}", got.word()),
    )
}

fn num_operand(op: BinOp, e: &Expr, t: Ty) -> Result<(), Problem> {
    if t == Ty::Bool {
        return Err(Problem::error(
            "pacer::check::type",
            e.span,
            format!("`{}` needs numbers, found an ON/OFF value", op.symbol()),
            "this is ON/OFF",
        )
        .with_help("compare bits with `= ON` / `= OFF`, combine them with AND/OR/NOT"));
    }
    Ok(())
}

fn mixed(op: BinOp, a: &Expr, ta: Ty, b: &Expr, tb: Ty) -> Problem {
    let num_side = if ta == Ty::Num { a } else { b };
    debug_assert_ne!(ta, tb);
    let help = if matches!(num_side.kind, ExprKind::Number(v, _) if v == 0.0 || v == 1.0) {
        "a bit is ON or OFF, not 1 or 0: write `= ON` or `= OFF`".to_string()
    } else {
        "both sides must be numbers, or both ON/OFF values".to_string()
    };
    Problem::error(
        "pacer::check::type",
        num_side.span,
        format!("`{}` between an ON/OFF value and a number", op.symbol()),
        "a number",
    )
    .with_help(help)
}

fn readable(r: &Resolved, span: Span) -> Result<(), Problem> {
    match r.access {
        Access::Action => Err(Problem::error(
            "pacer::check::not_readable",
            span,
            format!("{} is an action and has no value to read", r.name),
            "an action",
        )
        .with_help(format!("run it as a statement: `{}`", r.name))),
        Access::Input => Err(Problem::error(
            "pacer::check::not_readable",
            span,
            format!("{} can only be written", r.name),
            "write-only",
        )),
        _ => Ok(()),
    }
}

/// `e` checked, every problem recorded: each name of it that does not resolve (all of them, not
/// only the first), else the first problem of the expression.
fn keep_expr(cx: &mut Context<'_>, e: &Expr) -> Option<typed::Expr> {
    fn unknown(e: &Expr, registry: &Registry, out: &mut Vec<Problem>) {
        match &e.kind {
            ExprKind::Name(n) => {
                if let Err(p) = registry.resolve(n) {
                    out.push(p);
                }
            }
            ExprKind::Unary(_, x) | ExprKind::Paren(x) => unknown(x, registry, out),
            ExprKind::Binary(_, a, b) => {
                unknown(a, registry, out);
                unknown(b, registry, out);
            }
            ExprKind::Call(_, args) | ExprKind::AxisSet(args) => {
                for a in args {
                    unknown(a, registry, out);
                }
            }
            ExprKind::Number(..) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
        }
    }
    let mut problems = Vec::new();
    unknown(e, cx.machine.registry, &mut problems);
    if problems.is_empty() {
        return cx.keep(expr(e, cx.machine.registry));
    }
    for p in problems {
        cx.push(p);
    }
    None
}

impl PowerTools {
    /// `Program.N` must be loaded on the machine.
    fn program_loaded(cx: &mut Context<'_>, index: u32, span: Span) {
        let loaded = cx.machine.loaded_programs;
        if loaded.contains(&index) {
            return;
        }
        let list = loaded
            .iter()
            .map(|n| format!("Program.{n}"))
            .collect::<Vec<_>>()
            .join(", ");
        let help = if list.is_empty() {
            "no programs are loaded".to_string()
        } else {
            format!("loaded: {list}")
        };
        if !cx.machine.all_programs {
            // Checking some files of a machine: the others may well have it.
            cx.push(
                Problem::warning(
                    "pacer::check::program",
                    span,
                    format!("Program.{index} is not among the files given"),
                    "not given",
                )
                .with_help(format!(
                    "{help}; check the whole folder (or give machine.toml) to check it too; a \
                     run stops with an error if it gets here without it"
                )),
            );
            return;
        }
        cx.push(
            Problem::error(
                "pacer::check::program",
                span,
                format!("Program.{index} is not loaded on this machine"),
                "no such program",
            )
            .with_help(help),
        );
    }

    /// `e`, which must be of type `ty`.
    fn expect(cx: &mut Context<'_>, e: &Expr, ty: Ty, why: &str) -> Option<typed::Expr> {
        let t = keep_expr(cx, e)?;
        if t.ty != ty {
            cx.push(type_error(e, t.ty, ty).with_help(why.to_string()));
            return None;
        }
        Some(t)
    }
}

impl Rules for PowerTools {
    fn dialect(&self) -> Dialect {
        Dialect::PowerTools
    }

    fn resolve(&mut self, cx: &mut Context<'_>, name: &Name) -> Result<Resolved, Problem> {
        cx.registry().resolve(name)
    }

    fn expr(&mut self, cx: &mut Context<'_>, e: &Expr, want: Want<'_>) -> Option<typed::Expr> {
        match want {
            Want::Any => keep_expr(cx, e),
            Want::Number(why) => Self::expect(cx, e, Ty::Num, why),
            Want::Condition(why) => Self::expect(cx, e, Ty::Bool, why),
        }
    }

    fn assign(&mut self, cx: &mut Context<'_>, target: &Name, value: &Expr) -> Option<T> {
        let registry = cx.machine.registry;
        let Some(r) = cx.keep(registry.resolve(target)) else {
            let _ = keep_expr(cx, value);
            return None;
        };
        let v = keep_expr(cx, value)?;
        match r.access {
            Access::Read => {
                cx.push(
                    Problem::error(
                        "pacer::check::read_only",
                        target.span,
                        format!("{} is read-only", r.name),
                        "cannot be written",
                    )
                    .with_help("it is a status the controller sets"),
                );
                return None;
            }
            Access::Action => {
                let mut ok = true;
                if v.ty != Ty::Bool {
                    cx.push(
                        Problem::error(
                            "pacer::check::type",
                            value.span,
                            format!("{} is an action: assign ON to trigger it", r.name),
                            "a number",
                        )
                        .with_help(format!("write `{}=ON` or just `{}`", r.name, r.name)),
                    );
                    ok = false;
                }
                if r.hook == Hook::ProgramInitiate {
                    Self::program_loaded(cx, r.instance, target.span);
                }
                return ok.then(|| triggered(r, v));
            }
            Access::Input | Access::ReadWrite => {}
        }
        if r.ty.is_bit() && v.ty == Ty::Num {
            cx.push(
                Problem::error(
                    "pacer::check::number_to_bit",
                    value.span,
                    format!("a number assigned to the bit {}", r.name),
                    "a number",
                )
                .with_help("bits take ON/TRUE/YES/SET/ENABLE or OFF/FALSE/NO/CLEAR/DISABLE"),
            );
            return None;
        }
        if !r.ty.is_bit() && v.ty == Ty::Bool {
            cx.push(
                Problem::error(
                    "pacer::check::bit_to_number",
                    value.span,
                    format!(
                        "an ON/OFF value assigned to {}, which is {}",
                        r.name,
                        r.ty.describe()
                    ),
                    "ON/OFF",
                )
                .with_help("assign a number"),
            );
            return None;
        }
        Some(T::Assign {
            target: r,
            value: v,
        })
    }

    fn for_variable(&mut self, cx: &mut Context<'_>, var: &Name) -> Option<Resolved> {
        let r = cx.keep(cx.registry().resolve(var))?;
        if r.access != Access::ReadWrite || r.ty.is_bit() || r.hook != Hook::Store {
            cx.push(
                Problem::error(
                    "pacer::check::for_variable",
                    var.span,
                    format!("{} cannot count a For loop", r.name),
                    "not a numeric variable",
                )
                .with_help("count with a user variable, e.g. `For Var.I = 1 To 10`"),
            );
            return None;
        }
        Some(r)
    }

    fn action(
        &mut self,
        cx: &mut Context<'_>,
        _s: &Stmt,
        target: &Name,
        using: Option<&Using>,
        profile: Option<&Name>,
    ) -> Option<T> {
        let registry = cx.machine.registry;
        let r = cx.keep(registry.resolve(target))?;
        if r.access != Access::Action {
            let help = match (r.access, r.ty.is_bit()) {
                (Access::ReadWrite, true) => format!("to set it, write `{}=ON`", r.name),
                (Access::Input, _) | (Access::ReadWrite, false) => {
                    format!("give it a value: `{}=…`", r.name)
                }
                _ => "it is a status; read it in a condition, e.g. `Wait For …`".to_string(),
            };
            cx.push(
                Problem::error(
                    "pacer::check::not_action",
                    target.span,
                    format!("{} is not an action", r.name),
                    "not an action",
                )
                .with_help(help),
            );
            return None;
        }
        if r.hook == Hook::ProgramInitiate {
            Self::program_loaded(cx, r.instance, target.span);
        }
        let is_motion = r.hook == Hook::MotionStart;
        let mut ok = true;
        let mut start = StartRef::Now;
        if let Some(u) = using {
            let span = match u {
                Using::Last(s) => *s,
                Using::Capture(n) => n.span,
            };
            if !is_motion {
                cx.push(Problem::error(
                    "pacer::check::using",
                    span,
                    format!("`Using` only applies to motion initiates, not {}", r.name),
                    "not a motion",
                ));
                ok = false;
            } else {
                match u {
                    Using::Last(_) => start = StartRef::Last,
                    Using::Capture(n) => {
                        match cx.keep(registry.resolve_instance(n, Kind::Capture)) {
                            Some(i) => start = StartRef::Capture(i as u16),
                            None => ok = false,
                        }
                    }
                }
            }
        }
        let mut on = 0;
        // A stop takes `On Profile.N` too: the FM-3/FM-4 manual (p. 109) requires it after
        // `Gear.Stop` when the gear runs on Profile.1. The object's motion stops on whichever
        // profile it runs; the modifier names it.
        let is_stop = r.hook == Hook::MotionStop;
        if let Some(p) = profile {
            if !is_motion && !is_stop {
                cx.push(Problem::error(
                    "pacer::check::profile",
                    p.span,
                    format!(
                        "`On Profile` only applies to motion initiates and stops, not {}",
                        r.name
                    ),
                    "not a motion",
                ));
                ok = false;
            } else {
                match cx.keep(registry.resolve_instance(p, Kind::Profile)) {
                    Some(i) => on = i as u8,
                    None => ok = false,
                }
            }
        }
        ok.then_some(T::Act {
            target: r,
            start,
            profile: on,
            when: None,
        })
    }

    fn other(&mut self, cx: &mut Context<'_>, s: &Stmt) -> Option<T> {
        match &s.kind {
            StmtKind::DwellTime(e, last) => Some(T::Dwell {
                length: Self::expect(cx, e, Ty::Num, "a time in seconds")?,
                domain: Domain::Time,
                last: last.is_some(),
            }),
            StmtKind::DwellMaster(e, last) => Some(T::Dwell {
                length: Self::expect(cx, e, Ty::Num, "a master distance")?,
                domain: Domain::Master,
                last: last.is_some(),
            }),
            StmtKind::WaitTime(e) => Some(T::WaitTime(Self::expect(
                cx,
                e,
                Ty::Num,
                "a time in seconds",
            )?)),
            StmtKind::WaitFor(e) => Some(T::WaitFor(Self::expect(
                cx,
                e,
                Ty::Bool,
                "Wait For needs a condition, e.g. `Wait For DriveInput.1=ON`",
            )?)),
            StmtKind::Call(name) => {
                let n = cx.keep(cx.registry().resolve_instance(name, Kind::Program))?;
                Self::program_loaded(cx, n, name.span);
                Some(T::Call(n))
            }
            _ => not_here(cx, s, Dialect::PowerTools),
        }
    }
}

/// An action assigned a value: run at once for ON, never for OFF, else when the value is ON.
pub fn triggered(target: Resolved, value: typed::Expr) -> T {
    match value.kind {
        K::Bool { value: true, .. } => T::Act {
            target,
            start: StartRef::Now,
            profile: 0,
            when: None,
        },
        K::Bool { value: false, .. } => T::Nothing,
        _ => T::Act {
            target,
            start: StartRef::Now,
            profile: 0,
            when: Some(value),
        },
    }
}
