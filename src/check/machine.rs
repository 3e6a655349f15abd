//! Checks of the checked programs against their machine, which the per-line checks cannot see:
//! a motion object started that has no motion set up anywhere (no velocity in `machine.toml`
//! and none written by a program), an axis set naming an axis that is not a DSP axis of the
//! machine, division by a literal zero, REGIST with a literal LGTH of 0, and a `RETURN` the
//! program runs into without a `GOSUB`. Each would otherwise pass `pacer check` and fail at run
//! time.

use super::typed::{each_stmt, Expr, ExprKind, Op, Program, Stmt, StmtKind};
use crate::devices::command::KernelFunc;
use crate::diag::Problem;
use crate::registry::{Hook, Kind, Registry, SlotId};
use crate::span::Span;

/// What the programs are checked against.
pub struct MachineFacts<'a> {
    /// The registry.
    pub registry: &'a Registry,
    /// The DSP axes the machine defines (`[axis.N]`), by number.
    pub dsp_axes: &'a [u32],
    /// Every slot some program of the machine writes.
    pub written: &'a [SlotId],
    /// A machine file describes the machine: what it lacks is an error. Without one (loose
    /// files checked on their own) the machine is unknown and it is only a warning.
    pub described: bool,
}

/// Every slot `program` writes (assignments and counters).
pub fn written_slots(program: &Program, out: &mut Vec<SlotId>) {
    each_stmt(&program.body, &mut |s| match &s.kind {
        StmtKind::Assign { target, .. } => out.push(target.slot),
        StmtKind::For { var, .. } => out.push(var.slot),
        _ => {}
    });
}

/// The problems of `program` against the machine.
pub fn against_machine(program: &Program, facts: &MachineFacts<'_>) -> Vec<Problem> {
    let mut problems = Vec::new();
    let mut cx = Walk {
        facts,
        problems: &mut problems,
    };
    cx.stmts(&program.body);
    returns_without_gosub(program, &mut problems);
    problems
}

struct Walk<'a, 'b> {
    facts: &'a MachineFacts<'a>,
    problems: &'b mut Vec<Problem>,
}

impl Walk<'_, '_> {
    /// What the machine lacks is an error when a machine file describes it, else a warning.
    fn level(&self) -> fn(&'static str, Span, String, &'static str) -> Problem {
        if self.facts.described {
            |code, span, message, label| Problem::error(code, span, message, label)
        } else {
            |code, span, message, label| Problem::warning(code, span, message, label)
        }
    }

    fn stmts(&mut self, stmts: &[Stmt]) {
        each_stmt(stmts, &mut |s| self.stmt(s));
    }

    /// One statement's own expressions and start (its body's statements are visited too).
    fn stmt(&mut self, s: &Stmt) {
        match &s.kind {
            StmtKind::Assign { value, .. } => self.expr(value),
            StmtKind::Act { target, when, .. } => {
                if let Some(w) = when {
                    self.expr(w);
                }
                if target.hook == Hook::MotionStart {
                    self.motion_set_up(target.kind, target.instance, s);
                }
            }
            StmtKind::Dwell { length, .. } => self.expr(length),
            StmtKind::WaitTime(e) | StmtKind::WaitFor(e) => self.expr(e),
            StmtKind::If { cond, .. } | StmtKind::While { cond, .. } => self.expr(cond),
            StmtKind::For { from, to, step, .. } => {
                self.expr(from);
                self.expr(to);
                if let Some(st) = step {
                    self.expr(st);
                }
            }
            StmtKind::AxisWrite { axes, value, .. } => {
                self.expr(axes);
                self.expr(value);
            }
            StmtKind::Print(items) => {
                for item in items {
                    if let super::typed::PrintItem::Value(e, _) = item {
                        self.expr(e);
                    }
                }
            }
            StmtKind::Motion { axes, operands, .. } => {
                self.expr(axes);
                for e in operands.iter().flatten() {
                    self.expr(e);
                }
            }
            StmtKind::SetElement { place, value } => {
                place.subs.iter().for_each(|e| self.expr(e));
                self.expr(value);
            }
            StmtKind::Randomize(Some(e)) => self.expr(e),
            _ => {}
        }
    }

    /// A motion object started: it needs a velocity (and ramps) from the machine file or a
    /// program, or it fails at its first start.
    fn motion_set_up(&mut self, kind: Kind, instance: u32, s: &Stmt) {
        let (object, members): (&str, &[&str]) = match kind {
            Kind::Index => ("index", &["Velocity", "Acceleration", "Deceleration"]),
            Kind::Home => ("home", &["Velocity", "Acceleration", "Deceleration"]),
            Kind::Jog => ("jog", &["Velocity", "Acceleration", "Deceleration"]),
            _ => return,
        };
        let registry = self.facts.registry;
        let missing: Vec<&str> = members
            .iter()
            .copied()
            .filter(|m| {
                registry.slot_of(kind, instance, m).is_some_and(|slot| {
                    registry.slots[slot as usize].initial == 0.0
                        && !self.facts.written.contains(&slot)
                })
            })
            .collect();
        if missing.is_empty() {
            return;
        }
        let ty = registry.of(kind).def.name;
        let listed: Vec<String> = missing
            .iter()
            .map(|m| format!("{ty}.{instance}.{m}"))
            .collect();
        let problem = self.level();
        self.problems.push(
            problem(
                "pacer::check::not_set_up",
                s.span,
                format!(
                    "{ty}.{instance} is started but has no {} set up",
                    missing
                        .iter()
                        .map(|m| m.to_ascii_lowercase())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                "would fail when it starts",
            )
            .with_help(format!(
                "give them in machine.toml under [{object}.{instance}], or write {} in a program \
                 before starting it",
                listed.join(", ")
            )),
        );
    }

    fn expr(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Binary { op, a, b, .. } => {
                self.expr(a);
                self.expr(b);
                let divides = matches!(op, Op::Div | Op::Mod | Op::IntDiv | Op::BasicMod);
                if divides && constant(b) == Some(0.0) {
                    self.problems.push(
                        Problem::error(
                            "pacer::check::division_by_zero",
                            e.span,
                            "division by zero",
                            "the divisor is 0",
                        )
                        .with_help("this would stop the program with a run-time error"),
                    );
                }
            }
            ExprKind::Neg(x) | ExprKind::Not(x) | ExprKind::BitNot(x) | ExprKind::Paren(x) => {
                self.expr(x)
            }
            ExprKind::Call(_, args) | ExprKind::Text(_, args) => {
                for a in args {
                    self.expr(a);
                }
            }
            ExprKind::Element(el) => {
                for a in &el.subs {
                    self.expr(a);
                }
            }
            ExprKind::Rnd(Some(a)) => self.expr(a),
            ExprKind::Rnd(None) | ExprKind::Timer => {}
            ExprKind::Kernel { func, args, .. } => {
                for a in args {
                    self.expr(a);
                }
                let axis = args.get(if *func == KernelFunc::Regist { 1 } else { 0 });
                if let Some(n) = axis.and_then(|a| constant(a).map(|n| (n, a))) {
                    self.dsp_axis(n.0, n.1);
                }
                if *func == KernelFunc::Regist {
                    if let Some(lgth) = args.get(5) {
                        if constant(lgth).is_some_and(|x| x <= 0.0)
                            && constant(&args[0]) != Some(0.0)
                        {
                            self.problems.push(
                                Problem::error(
                                    "pacer::check::regist",
                                    lgth.span,
                                    "REGIST's LGTH must be above 0",
                                    "LGTH",
                                )
                                .with_help(
                                    "the correction is taken modulo LGTH, the machine's cycle \
                                     length: REGIST would return OK false",
                                ),
                            );
                        }
                    }
                }
            }
            ExprKind::AxisRead { axes, .. } => self.expr(axes),
            ExprKind::AxisSet(items) => {
                for item in items {
                    self.expr(item);
                    if let Some(n) = constant(item) {
                        self.dsp_axis(n, item);
                    }
                }
            }
            ExprKind::Const(_)
            | ExprKind::Bool { .. }
            | ExprKind::Str(_)
            | ExprKind::Read { .. } => {}
        }
    }

    /// An axis number written in an axis set must be a DSP axis of the machine.
    fn dsp_axis(&mut self, n: f64, item: &Expr) {
        let axes = self.facts.dsp_axes;
        if n.fract() == 0.0 && n >= 1.0 && axes.contains(&(n as u32)) {
            return;
        }
        let have = if axes.is_empty() {
            "this machine has no DSP axes: define them in machine.toml ([axis.1] …)".to_string()
        } else {
            let list: Vec<String> = axes.iter().map(u32::to_string).collect();
            format!("its DSP axes are {}", list.join(", "))
        };
        let problem = self.level();
        self.problems.push(
            problem(
                "pacer::check::axis",
                item.span,
                format!("axis {n} is not a DSP axis of this machine"),
                "no such axis",
            )
            .with_help(have),
        );
    }
}

/// The value of an expression that is a literal (possibly negated or in parentheses).
fn constant(e: &Expr) -> Option<f64> {
    match &e.kind {
        ExprKind::Const(x) => Some(*x),
        ExprKind::Paren(x) => constant(x),
        ExprKind::Neg(x) => constant(x).map(|v| -v),
        _ => None,
    }
}

/// A `RETURN` the program runs into from its start without a `GOSUB`: after the start, code
/// runs on until an `END`, a `GOTO` or a `RETURN`; a label a `GOTO` jumps to is run into too,
/// one only `GOSUB` names starts a subroutine.
fn returns_without_gosub(program: &Program, problems: &mut Vec<Problem>) {
    let mut goto_targets = Vec::new();
    each_stmt(&program.body, &mut |s| {
        if let StmtKind::Goto(l) = &s.kind {
            goto_targets.push(l.clone());
        }
    });
    let runs_into = |stmts: &[Stmt], problems: &mut Vec<Problem>| {
        each_stmt(stmts, &mut |s| {
            if matches!(s.kind, StmtKind::Return) {
                problems.push(
                    Problem::error(
                        "pacer::check::return",
                        s.span,
                        "RETURN without GOSUB",
                        "the program runs into it",
                    )
                    .with_help(
                        "the lines before it lead here without a GOSUB: end the main part with \
                         END (or GOTO) before the subroutines",
                    ),
                );
            }
        })
    };
    let mut live = true;
    let mut start = 0;
    let body = &program.body;
    for (i, s) in body.iter().enumerate() {
        match &s.kind {
            StmtKind::Label(l) => {
                if live {
                    runs_into(&body[start..i], problems);
                }
                live = live || goto_targets.contains(l);
                start = i;
            }
            StmtKind::End | StmtKind::Goto(_) | StmtKind::Return => {
                if live {
                    runs_into(&body[start..=i], problems);
                }
                live = false;
                start = i + 1;
            }
            _ => {}
        }
    }
    if live {
        runs_into(&body[start.min(body.len())..], problems);
    }
}
