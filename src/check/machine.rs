//! Checks of the checked programs against their machine, which the per-line checks cannot see:
//! a motion object started that has no motion set up anywhere (no velocity in `machine.toml`
//! and none written by a program), an axis set naming an axis that is not a DSP axis of the
//! machine, division by a literal zero, REGIST with a literal LGTH of 0, and a `RETURN` the
//! program runs into without a `GOSUB`, and compound indexes (`Index.N.CompoundInitiate`) that
//! are not followed by the index they run into, or that the drive cannot compound. Each would
//! otherwise pass `pacer check` and fail or run wrongly at run time.

use super::typed::{each_stmt, Expr, ExprKind, Op, Program, Stmt, StmtKind};
use crate::devices::command::{KernelFunc, StartRef};
use crate::devices::drive::setup::{IndexConfig, IndexType};
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
    /// The set-up of each index (timed, registration, synchronized), by number.
    pub indexes: &'a [IndexConfig],
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
    compounds(&program.body, facts, &mut problems);
    returns_without_gosub(program, &mut problems);
    problems
}

/// The compound indexes of `body` and of the blocks in it. A compound index runs on into the
/// next index without stopping, and the program's next instruction initiates that index, so
/// the statement after `Index.N.CompoundInitiate` must be that initiate, on the same profile,
/// started where the compound index ends (not `Using Capture`). The FM-3 reference (p. 98):
/// "A Timed Index can not be compounded into or out of"; a registration index's end depends on
/// its sensor, which pacer does not compound.
fn compounds(body: &[Stmt], facts: &MachineFacts<'_>, problems: &mut Vec<Problem>) {
    let registry = facts.registry;
    let compound = |s: &Stmt| match &s.kind {
        StmtKind::Act { target, .. }
            if target.kind == Kind::Index
                && registry.slot_of(Kind::Index, target.instance, "CompoundInitiate")
                    == Some(target.slot) =>
        {
            Some(target.instance)
        }
        _ => None,
    };
    let config = |n: u32| facts.indexes.get(n as usize).copied().unwrap_or_default();
    // What keeps an index out of a compound chain, in a machine builder's words.
    let refused = |n: u32, role: &str| -> Option<(String, String)> {
        let c = config(n);
        if c.timed {
            Some((
                format!("Index.{n} is a timed index: a timed index cannot be {role}"),
                "the FM-3 reference (p. 98): \"A Timed Index can not be compounded into or out \
                 of\"; remove `time` from its [index] section or do not compound it"
                    .to_string(),
            ))
        } else if c.kind == IndexType::Registration {
            Some((
                format!("Index.{n} is a registration index: pacer does not let it be {role}"),
                "its end depends on its sensor; start it with Initiate, after an index that \
                 stops"
                    .to_string(),
            ))
        } else {
            None
        }
    };
    for (i, s) in body.iter().enumerate() {
        match &s.kind {
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => {
                compounds(then_body, facts, problems);
                compounds(else_body.as_deref().unwrap_or_default(), facts, problems);
            }
            StmtKind::While { body, .. } | StmtKind::For { body, .. } => {
                compounds(body, facts, problems)
            }
            _ => {}
        }
        let Some(n) = compound(s) else { continue };
        let StmtKind::Act {
            when, profile: on, ..
        } = &s.kind
        else {
            continue;
        };
        if when.is_some() {
            problems.push(
                Problem::error(
                    "pacer::check::compound",
                    s.span,
                    format!("Index.{n}.CompoundInitiate cannot wait for a condition"),
                    "assigned a condition",
                )
                .with_help("write it as a line of its own, followed by the next index's initiate"),
            );
            continue;
        }
        if let Some((message, help)) = refused(n, "compounded") {
            problems.push(
                Problem::error("pacer::check::compound", s.span, message, "cannot compound")
                    .with_help(help),
            );
        }
        // The next statement: the initiate of the index it runs into.
        let next = body.get(i + 1).and_then(|x| match &x.kind {
            StmtKind::Act {
                target,
                start,
                profile,
                when: None,
            } if target.kind == Kind::Index && target.hook == Hook::MotionStart => {
                Some((x, target.instance, *start, *profile))
            }
            _ => None,
        });
        let Some((x, m, start, profile)) = next else {
            problems.push(
                Problem::error(
                    "pacer::check::compound",
                    s.span,
                    format!("Index.{n}.CompoundInitiate is not followed by the index it runs into"),
                    "nothing to run into",
                )
                .with_help(
                    "a compound index does not stop at its end point: it runs on into the next \
                     index, which the next line initiates (`Index.1.Initiate`, or \
                     `Index.1.CompoundInitiate` to go on again)",
                ),
            );
            continue;
        };
        if let Some((message, help)) = refused(m, "compounded into") {
            problems.push(
                Problem::error("pacer::check::compound", x.span, message, "cannot compound")
                    .with_help(help),
            );
        }
        if profile != *on {
            problems.push(
                Problem::error(
                    "pacer::check::compound",
                    x.span,
                    format!("Index.{m} is not on the profile of Index.{n}, which runs into it"),
                    "another profile",
                )
                .with_help("initiate both on the same profile (`On Profile.N`)"),
            );
        }
        if let StartRef::Capture(c) = start {
            problems.push(
                Problem::error(
                    "pacer::check::compound",
                    x.span,
                    format!("Index.{m} cannot start Using Capture.{c}"),
                    "it starts where the compound index ends",
                )
                .with_help(format!(
                    "Index.{n} is compounded: Index.{m} starts where it ends, without stopping"
                )),
            );
        }
        if config(n).synchronized != config(m).synchronized {
            problems.push(
                Problem::error(
                    "pacer::check::compound",
                    x.span,
                    format!(
                        "Index.{m} and Index.{n}, which runs into it, are not both synchronized \
                         to the master"
                    ),
                    "cannot compound",
                )
                .with_help(
                    "compound realtime indexes into realtime ones, synchronized into synchronized",
                ),
            );
        }
    }
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
/// runs on until an `END`, a `GOTO` or a `RETURN`; a label is run into from the code before it
/// when that code goes on into it, or when a `GOTO` in code the program runs into jumps to it.
/// A label only `GOSUB` names starts a subroutine, and so does one only a subroutine's own
/// `GOTO`s name (a loop inside the subroutine, the label an `EXIT FOR` leaves to).
fn returns_without_gosub(program: &Program, problems: &mut Vec<Problem>) {
    // The top-level runs of statements between labels and ends: where each starts, its
    // label, and whether the run before it goes on into it.
    struct Run<'a> {
        stmts: &'a [Stmt],
        label: Option<&'a str>,
        fallen_into: bool,
    }
    let body = &program.body;
    let mut runs: Vec<Run<'_>> = Vec::new();
    let (mut start, mut label, mut fallen_into) = (0usize, None, true);
    for (i, s) in body.iter().enumerate() {
        match &s.kind {
            StmtKind::Label(l) => {
                runs.push(Run {
                    stmts: &body[start..i],
                    label,
                    fallen_into,
                });
                (start, label, fallen_into) = (i, Some(l.as_str()), true);
            }
            StmtKind::End | StmtKind::Goto(_) | StmtKind::Return => {
                runs.push(Run {
                    stmts: &body[start..=i],
                    label,
                    fallen_into,
                });
                (start, label, fallen_into) = (i + 1, None, false);
            }
            _ => {}
        }
    }
    runs.push(Run {
        stmts: &body[start.min(body.len())..],
        label,
        fallen_into,
    });
    // The runs the program runs into, from the first: grown until no `GOTO` in them reaches
    // another.
    let mut live = vec![false; runs.len()];
    let mut changed = true;
    while changed {
        changed = false;
        let mut targets: Vec<&str> = Vec::new();
        for (run, _) in runs.iter().zip(&live).filter(|(_, &l)| l) {
            each_stmt(run.stmts, &mut |s| {
                if let StmtKind::Goto(l) = &s.kind {
                    targets.push(l.as_str());
                }
            });
        }
        for k in 0..runs.len() {
            let into = k == 0
                || (runs[k].fallen_into && live[k - 1])
                || runs[k].label.is_some_and(|l| targets.contains(&l));
            if into && !live[k] {
                live[k] = true;
                changed = true;
            }
        }
    }
    for (run, _) in runs.iter().zip(&live).filter(|(_, &l)| l) {
        each_stmt(run.stmts, &mut |s| {
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
        });
    }
}
