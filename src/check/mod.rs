//! The checker: resolves every name against the registry and checks types and usage,
//! reporting every problem of a file (not only the first).

pub mod basic;
pub mod functions;

use crate::diag::{nearest, Problem};
use crate::registry::{Access, Hook, Kind, Registry, Resolved};
use crate::span::Span;
use crate::syntax::ast::{BinOp, Expr, ExprKind, Name, ProgramAst, Stmt, StmtKind, UnOp, Using};
use indexmap::IndexMap;

/// The two value types of expressions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ty {
    /// ON/OFF.
    Bool,
    /// A number.
    Num,
}

impl Ty {
    fn word(self) -> &'static str {
        match self {
            Ty::Bool => "an ON/OFF value",
            Ty::Num => "a number",
        }
    }
}

/// What the checker needs to know about the other programs of the machine.
pub struct CheckEnv<'a> {
    /// The object registry.
    pub registry: &'a Registry,
    /// Program numbers that have a loaded file.
    pub loaded_programs: &'a [u32],
}

/// Check a program; returns every problem found.
pub fn check_program(ast: &ProgramAst, env: &CheckEnv<'_>) -> Vec<Problem> {
    let mut c = Checker {
        env,
        problems: Vec::new(),
        labels: IndexMap::new(),
    };
    c.labels = label_map(&ast.body, &mut c.problems);
    c.block(&ast.body);
    c.problems
}

struct Checker<'a, 'b> {
    env: &'a CheckEnv<'b>,
    problems: Vec<Problem>,
    labels: IndexMap<String, (Span, String)>,
}

/// The value of `r`, or `None` with its problem recorded.
pub(crate) fn keep<T>(problems: &mut Vec<Problem>, r: Result<T, Problem>) -> Option<T> {
    r.map_err(|p| problems.push(p)).ok()
}

/// The labels of a program by lower-case name, with where and how each is written; a label
/// defined twice is reported.
pub fn label_map(body: &[Stmt], problems: &mut Vec<Problem>) -> IndexMap<String, (Span, String)> {
    let mut labels = IndexMap::new();
    for seg in crate::syntax::ast::labels(body) {
        let key = seg.text.to_ascii_lowercase();
        if labels.contains_key(&key) {
            problems.push(
                Problem::error(
                    "pacer::check::label",
                    seg.span,
                    format!("label `{}` is defined twice", seg.text),
                    "second definition",
                )
                .with_help("labels must be unique in a program; rename one of them"),
            );
        } else {
            labels.insert(key, (seg.span, seg.text.clone()));
        }
    }
    labels
}

/// The type of an expression, with names resolved; shared with the compiler.
pub fn expr_type(e: &Expr, registry: &Registry) -> Result<Ty, Problem> {
    match &e.kind {
        ExprKind::Number(v) if !v.is_finite() => Err(Problem::error(
            "pacer::check::number",
            e.span,
            "this number is too large to represent",
            "out of range",
        )
        .with_help("numbers are 64-bit floating point while computing, and 32-bit where stored")),
        ExprKind::Number(_) => Ok(Ty::Num),
        ExprKind::Bool(_) => Ok(Ty::Bool),
        ExprKind::Paren(inner) => expr_type(inner, registry),
        ExprKind::Name(n) => {
            let r = registry.resolve(n)?;
            readable(&r, n.span)?;
            Ok(if r.ty.is_bit() { Ty::Bool } else { Ty::Num })
        }
        ExprKind::Unary(UnOp::Neg, inner) => {
            want(inner, Ty::Num, registry, "`-` needs a number")?;
            Ok(Ty::Num)
        }
        ExprKind::Unary(UnOp::Not, inner) => expr_type(inner, registry),
        ExprKind::Binary(op, a, b) => {
            let ta = expr_type(a, registry)?;
            let tb = expr_type(b, registry)?;
            match op {
                BinOp::And | BinOp::Or | BinOp::Xor => {
                    if ta != tb {
                        return Err(mixed(*op, a, ta, b, tb));
                    }
                    Ok(ta)
                }
                BinOp::Eq | BinOp::Ne => {
                    if ta != tb {
                        return Err(mixed(*op, a, ta, b, tb));
                    }
                    Ok(Ty::Bool)
                }
                BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
                    num_operand(*op, a, ta)?;
                    num_operand(*op, b, tb)?;
                    Ok(Ty::Bool)
                }
                _ => {
                    num_operand(*op, a, ta)?;
                    num_operand(*op, b, tb)?;
                    Ok(Ty::Num)
                }
            }
        }
        ExprKind::Str(_) | ExprKind::AxisSet(_) => Err(Problem::error(
            "pacer::check::dialect",
            e.span,
            "strings and axis sets are MotionBASIC values",
            "not PowerTools",
        )),
        ExprKind::Call(f, args) if functions::find_kernel(&f.text).is_some() => {
            let arity = functions::find_kernel(&f.text).map_or(0, |k| k.1);
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
            for a in args {
                expr_type(a, registry)?;
            }
            Ok(Ty::Num)
        }
        ExprKind::Call(f, args) => {
            let Some((_, arity)) = functions::find(&f.text) else {
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
            for a in args {
                want(a, Ty::Num, registry, "function arguments are numbers")?;
            }
            Ok(Ty::Num)
        }
    }
}

fn want(e: &Expr, ty: Ty, registry: &Registry, why: &str) -> Result<(), Problem> {
    let t = expr_type(e, registry)?;
    if t != ty {
        return Err(type_error(e, t, ty).with_help(why.to_string()));
    }
    Ok(())
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
    let help = if matches!(num_side.kind, ExprKind::Number(v) if v == 0.0 || v == 1.0) {
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

impl Checker<'_, '_> {
    fn reg(&self) -> &Registry {
        self.env.registry
    }

    fn block(&mut self, body: &[Stmt]) {
        for s in body {
            self.stmt(s);
        }
    }

    fn report<T>(&mut self, r: Result<T, Problem>) -> Option<T> {
        keep(&mut self.problems, r)
    }

    fn expect(&mut self, e: &Expr, ty: Ty, why: &str) {
        let r = expr_type(e, self.reg());
        if let Some(t) = self.report(r) {
            if t != ty {
                let p = type_error(e, t, ty).with_help(why.to_string());
                self.problems.push(p);
            }
        }
    }

    fn stmt(&mut self, s: &Stmt) {
        match &s.kind {
            StmtKind::Assign { target, value } => self.assign(target, value),
            StmtKind::Action {
                target,
                using,
                profile,
            } => self.action(target, using.as_ref(), profile.as_ref()),
            StmtKind::DwellTime(e) | StmtKind::WaitTime(e) => {
                self.expect(e, Ty::Num, "a time in seconds")
            }
            StmtKind::DwellMaster(e) => self.expect(e, Ty::Num, "a master distance"),
            StmtKind::WaitFor(e) => self.expect(
                e,
                Ty::Bool,
                "Wait For needs a condition, e.g. `Wait For DriveInput.1=ON`",
            ),
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                self.expect(cond, Ty::Bool, "If needs a condition");
                self.block(then_body);
                if let Some(e) = else_body {
                    self.block(e);
                }
            }
            StmtKind::DoWhile { cond, body } => {
                self.expect(cond, Ty::Bool, "Do While needs a condition");
                self.block(body);
            }
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => {
                if let Some(r) = self.report(self.reg().resolve(var)) {
                    if r.access != Access::ReadWrite || r.ty.is_bit() || r.hook != Hook::Store {
                        self.problems.push(
                            Problem::error(
                                "pacer::check::for_variable",
                                var.span,
                                format!("{} cannot count a For loop", r.name),
                                "not a numeric variable",
                            )
                            .with_help("count with a user variable, e.g. `For Var.I = 1 To 10`"),
                        );
                    }
                }
                self.expect(from, Ty::Num, "loop bounds are numbers");
                self.expect(to, Ty::Num, "loop bounds are numbers");
                if let Some(st) = step {
                    self.expect(st, Ty::Num, "the step is a number");
                    if matches!(st.kind, ExprKind::Number(v) if v == 0.0) {
                        self.problems.push(Problem::error(
                            "pacer::check::step",
                            st.span,
                            "a Step of 0 never ends the loop",
                            "zero step",
                        ));
                    }
                }
                self.block(body);
            }
            StmtKind::Call(name) => {
                if let Some(n) = self.report(self.reg().resolve_instance(name, Kind::Program)) {
                    self.program_loaded(n, name.span);
                }
            }
            StmtKind::Goto(seg) => {
                if !self.labels.contains_key(&seg.text.to_ascii_lowercase()) {
                    let near = nearest(
                        &seg.text,
                        self.labels.values().map(|(_, text)| text.as_str()),
                    )
                    .map(|n| format!("did you mean `{n}`?"));
                    self.problems.push(
                        Problem::error(
                            "pacer::check::label",
                            seg.span,
                            format!("no label `{}` in this program", seg.text),
                            "unknown label",
                        )
                        .with_help(near.unwrap_or_else(|| {
                            format!("define it on a line of its own: `{}:`", seg.text)
                        })),
                    );
                }
            }
            StmtKind::Label(_) | StmtKind::End => {}
            StmtKind::SetCall { .. }
            | StmtKind::Gosub(_)
            | StmtKind::Return
            | StmtKind::Gear { .. }
            | StmtKind::Move { .. } => self.problems.push(Problem::error(
                "pacer::check::dialect",
                s.span,
                "not a PowerTools statement",
                "MotionBASIC only",
            )),
        }
    }

    fn program_loaded(&mut self, index: u32, span: Span) {
        if !self.env.loaded_programs.contains(&index) {
            let loaded = self
                .env
                .loaded_programs
                .iter()
                .map(|n| format!("Program.{n}"))
                .collect::<Vec<_>>()
                .join(", ");
            self.problems.push(
                Problem::error(
                    "pacer::check::program",
                    span,
                    format!("Program.{index} is not loaded on this machine"),
                    "no such program",
                )
                .with_help(if loaded.is_empty() {
                    "no programs are loaded".to_string()
                } else {
                    format!("loaded: {loaded}")
                }),
            );
        }
    }

    fn assign(&mut self, target: &Name, value: &Expr) {
        let Some(r) = self.report(self.reg().resolve(target)) else {
            let _ = self.report(expr_type(value, self.reg()));
            return;
        };
        let Some(vt) = self.report(expr_type(value, self.reg())) else {
            return;
        };
        match r.access {
            Access::Read => {
                self.problems.push(
                    Problem::error(
                        "pacer::check::read_only",
                        target.span,
                        format!("{} is read-only", r.name),
                        "cannot be written",
                    )
                    .with_help("it is a status the controller sets"),
                );
                return;
            }
            Access::Action => {
                if vt != Ty::Bool {
                    self.problems.push(
                        Problem::error(
                            "pacer::check::type",
                            value.span,
                            format!("{} is an action: assign ON to trigger it", r.name),
                            "a number",
                        )
                        .with_help(format!("write `{}=ON` or just `{}`", r.name, r.name)),
                    );
                }
                if r.hook == Hook::ProgramInitiate {
                    self.program_loaded(r.instance, target.span);
                }
                return;
            }
            Access::Input | Access::ReadWrite => {}
        }
        if r.ty.is_bit() && vt == Ty::Num {
            self.problems.push(
                Problem::error(
                    "pacer::check::number_to_bit",
                    value.span,
                    format!("a number assigned to the bit {}", r.name),
                    "a number",
                )
                .with_help("bits take ON/TRUE/YES/SET/ENABLE or OFF/FALSE/NO/CLEAR/DISABLE"),
            );
        } else if !r.ty.is_bit() && vt == Ty::Bool {
            self.problems.push(
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
        }
    }

    fn action(&mut self, target: &Name, using: Option<&Using>, profile: Option<&Name>) {
        let Some(r) = self.report(self.reg().resolve(target)) else {
            return;
        };
        if r.access != Access::Action {
            let help = match (r.access, r.ty.is_bit()) {
                (Access::ReadWrite, true) => format!("to set it, write `{}=ON`", r.name),
                (Access::Input, _) | (Access::ReadWrite, false) => {
                    format!("give it a value: `{}=…`", r.name)
                }
                _ => "it is a status; read it in a condition, e.g. `Wait For …`".to_string(),
            };
            self.problems.push(
                Problem::error(
                    "pacer::check::not_action",
                    target.span,
                    format!("{} is not an action", r.name),
                    "not an action",
                )
                .with_help(help),
            );
            return;
        }
        if r.hook == Hook::ProgramInitiate {
            self.program_loaded(r.instance, target.span);
        }
        let is_motion = r.hook == Hook::MotionStart;
        if let Some(u) = using {
            let span = match u {
                Using::Last(s) => *s,
                Using::Capture(n) => n.span,
            };
            if !is_motion {
                self.problems.push(Problem::error(
                    "pacer::check::using",
                    span,
                    format!("`Using` only applies to motion initiates, not {}", r.name),
                    "not a motion",
                ));
            } else if let Using::Capture(n) = u {
                let _ = self.report(self.reg().resolve_instance(n, Kind::Capture));
            }
        }
        if let Some(p) = profile {
            if !is_motion {
                self.problems.push(Problem::error(
                    "pacer::check::profile",
                    p.span,
                    format!(
                        "`On Profile` only applies to motion initiates, not {}",
                        r.name
                    ),
                    "not a motion",
                ));
            } else {
                let _ = self.report(self.reg().resolve_instance(p, Kind::Profile));
            }
        }
    }
}
