//! MotionBASIC names and checks: variables typed by their suffix and declared by use,
//! controller variables (`POS.ASEN@(axis)`) as members of the DSP axis objects, labels and
//! subroutines, and the lint for a variable read but never assigned.

use super::functions;
use crate::diag::{nearest, Problem};
use crate::registry::{Access, Kind, Registry, Resolved, ValueType};
use crate::span::Span;
use crate::syntax::ast::{
    BinOp, Expr, ExprKind, GearForm, MoveForm, Name, ProgramAst, Segment, Stmt, StmtKind, UnOp,
};
use indexmap::{IndexMap, IndexSet};

/// What a MotionBASIC value is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BasicTy {
    /// A number (long integer or real; truth values are numbers).
    Num,
    /// An axis set (`{1}`, `web~`).
    Axis,
    /// A string.
    Str,
}

impl BasicTy {
    fn word(self) -> &'static str {
        match self {
            BasicTy::Num => "a number",
            BasicTy::Axis => "an axis set",
            BasicTy::Str => "a string",
        }
    }
}

/// The storage type of a variable, from its suffix: `&`/`%` long integer, `~` axis set,
/// `$` string, none/`!`/`#` real. `None` for a controller name (`@`).
pub fn var_type(name: &str) -> Option<(ValueType, BasicTy)> {
    match name.chars().last()? {
        '@' => None,
        '&' | '%' => Some((ValueType::Fixed(0), BasicTy::Num)),
        '~' => Some((ValueType::Integer, BasicTy::Axis)),
        '$' => Some((ValueType::Integer, BasicTy::Str)),
        _ => Some((ValueType::Real, BasicTy::Num)),
    }
}

/// A controller variable and the DSP axis member it names.
#[derive(Debug, Clone, Copy)]
pub struct Controller {
    /// MotionBASIC name without `@`.
    pub name: &'static str,
    /// The `Axis` member.
    pub member: &'static str,
    /// Programs may assign it.
    pub writable: bool,
    /// Type of its value.
    pub ty: BasicTy,
}

const fn ctl(name: &'static str, member: &'static str, writable: bool, ty: BasicTy) -> Controller {
    Controller {
        name,
        member,
        writable,
        ty,
    }
}

/// Every controller variable pacer knows.
pub const CONTROLLERS: &[Controller] = &[
    ctl("POS", "Position", false, BasicTy::Num),
    ctl("VEL", "Velocity", false, BasicTy::Num),
    ctl("RATIO", "Ratio", false, BasicTy::Num),
    ctl("DSP.DONE", "DspDone", false, BasicTy::Num),
    ctl("ZREF", "Zref", true, BasicTy::Num),
    ctl("ASEN", "Asen", true, BasicTy::Num),
    ctl("BSEN", "Bsen", true, BasicTy::Num),
    ctl("POS.ZREF", "PosZref", false, BasicTy::Num),
    ctl("POS.ASEN", "PosAsen", false, BasicTy::Num),
    ctl("POS.BSEN", "PosBsen", false, BasicTy::Num),
    ctl("POS.MOD", "PosMod", true, BasicTy::Num),
    ctl("PLS.MOD", "PlsMod", true, BasicTy::Num),
    ctl("PLS1.LOW", "Pls1Low", true, BasicTy::Num),
    ctl("PLS1.HIGH", "Pls1High", true, BasicTy::Num),
    ctl("PLS2.LOW", "Pls2Low", true, BasicTy::Num),
    ctl("PLS2.HIGH", "Pls2High", true, BasicTy::Num),
    ctl("PLS3.LOW", "Pls3Low", true, BasicTy::Num),
    ctl("PLS3.HIGH", "Pls3High", true, BasicTy::Num),
    ctl("SENS.MODE", "SensMode", true, BasicTy::Str),
];

/// The controller variable `name` names, written with or without its `@`.
pub fn controller(name: &str) -> Option<&'static Controller> {
    let bare = name.strip_suffix('@').unwrap_or(name);
    CONTROLLERS
        .iter()
        .find(|c| c.name.eq_ignore_ascii_case(bare))
}

/// A name in a MotionBASIC program: an object member when it resolves as one
/// (`Queue.0.QueueEmpty`), else a MotionBASIC variable.
pub fn resolve(registry: &Registry, name: &Name) -> Result<Resolved, Problem> {
    let text = name.text();
    if text.ends_with('@') {
        let help = match controller(&text) {
            Some(c) => format!("give its axis: `{}@(knife~)`", c.name),
            None => "controller variables take an axis in ( ) or { }".to_string(),
        };
        return Err(Problem::error(
            "pacer::check::controller_axis",
            name.span,
            format!("{text} is a controller variable: it needs an axis"),
            "no axis given",
        )
        .with_help(help));
    }
    if crate::registry::catalog::find_type(&name.segments[0].text).is_some() {
        if let Ok(r) = registry.resolve(name) {
            return Ok(r);
        }
    }
    let vars = registry.of(Kind::BasicVar);
    match vars.names.get(&text.to_ascii_lowercase()) {
        Some(&i) => {
            let slot = vars.slot(i, 0, false);
            let info = &registry.slots[slot as usize];
            Ok(Resolved {
                slot,
                ty: info.ty,
                access: Access::ReadWrite,
                hook: crate::registry::Hook::Store,
                kind: Kind::BasicVar,
                instance: i,
                name: info.name.clone(),
            })
        }
        None => registry.resolve(name),
    }
}

/// The variables of MotionBASIC programs, in order of first appearance, with their types, and
/// the ones assigned somewhere (for the read-never-assigned lint).
#[derive(Debug, Default)]
pub struct Variables {
    /// Name (upper-case) → spelling at first use (as the trace shows it) and storage type.
    pub all: IndexMap<String, (String, ValueType)>,
    /// Names assigned (or used as a FOR variable) somewhere.
    pub assigned: IndexSet<String>,
}

impl Variables {
    /// Collect the variables `ast` uses. Names that are objects of the machine, labels and
    /// controller names are not variables.
    pub fn collect(&mut self, ast: &ProgramAst) {
        self.stmts(&ast.body);
    }

    /// As `(name, type)` pairs for the registry.
    pub fn list(&self) -> Vec<(String, ValueType)> {
        self.all.values().cloned().collect()
    }

    fn note(&mut self, n: &Name, assigned: bool) {
        // `BELT.SPEED` stays a variable: a belt is always written with its number.
        let object = match crate::registry::catalog::find_type(&n.segments[0].text) {
            Some(def) if def.kind == Kind::Belt => n
                .segments
                .get(1)
                .is_some_and(|s| !s.text.is_empty() && s.text.bytes().all(|b| b.is_ascii_digit())),
            Some(_) => n.segments.len() > 1,
            None => false,
        };
        if object {
            return;
        }
        let written = n.text();
        let text = written.to_ascii_uppercase();
        let Some((ty, _)) = var_type(&text) else {
            return;
        };
        self.all.entry(text.clone()).or_insert((written, ty));
        if assigned {
            self.assigned.insert(text);
        }
    }

    fn stmts(&mut self, body: &[Stmt]) {
        for s in body {
            match &s.kind {
                StmtKind::Assign { target, value } => {
                    self.note(target, true);
                    self.expr(value);
                }
                StmtKind::SetCall { args, value, .. } => {
                    args.iter().for_each(|a| self.expr(a));
                    self.expr(value);
                }
                StmtKind::If {
                    cond,
                    then_body,
                    else_body,
                } => {
                    self.expr(cond);
                    self.stmts(then_body);
                    if let Some(e) = else_body {
                        self.stmts(e);
                    }
                }
                StmtKind::DoWhile { cond, body } => {
                    self.expr(cond);
                    self.stmts(body);
                }
                StmtKind::For {
                    var,
                    from,
                    to,
                    step,
                    body,
                } => {
                    self.note(var, true);
                    self.expr(from);
                    self.expr(to);
                    if let Some(s) = step {
                        self.expr(s);
                    }
                    self.stmts(body);
                }
                StmtKind::Gear { axis, form } => {
                    self.expr(axis);
                    match form {
                        GearForm::At {
                            out,
                            inn,
                            pacer,
                            after,
                        } => {
                            self.expr(out);
                            self.expr(inn);
                            pacer.iter().chain(after.iter()).for_each(|e| self.expr(e));
                        }
                        GearForm::For { dist, pacer } => {
                            self.expr(dist);
                            self.expr(pacer);
                        }
                    }
                }
                StmtKind::Move { axis, form } => {
                    self.expr(axis);
                    match form {
                        MoveForm::At { speed, time } => {
                            self.expr(speed);
                            time.iter().for_each(|e| self.expr(e));
                        }
                        MoveForm::Position {
                            target,
                            speed,
                            time,
                            ..
                        } => {
                            self.expr(target);
                            speed.iter().chain(time.iter()).for_each(|e| self.expr(e));
                        }
                    }
                }
                StmtKind::WaitFor(e)
                | StmtKind::WaitTime(e)
                | StmtKind::DwellTime(e)
                | StmtKind::DwellMaster(e) => self.expr(e),
                _ => {}
            }
        }
    }

    fn expr(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Name(n) => self.note(n, false),
            ExprKind::Unary(_, a) | ExprKind::Paren(a) => self.expr(a),
            ExprKind::Binary(_, a, b) => {
                self.expr(a);
                self.expr(b);
            }
            ExprKind::Call(_, args) | ExprKind::AxisSet(args) => {
                args.iter().for_each(|a| self.expr(a))
            }
            ExprKind::Number(_) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
        }
    }
}

/// Check a MotionBASIC program. `vars` holds every MotionBASIC program's variables.
pub fn check(ast: &ProgramAst, registry: &Registry, vars: &Variables) -> Vec<Problem> {
    let mut c = BasicChecker {
        registry,
        vars,
        labels: IndexMap::new(),
        problems: Vec::new(),
        warned: IndexSet::new(),
    };
    c.labels = super::label_map(&ast.body, &mut c.problems);
    c.stmts(&ast.body);
    c.problems
}

struct BasicChecker<'a> {
    registry: &'a Registry,
    vars: &'a Variables,
    /// Lower-case label → where and how it is written.
    labels: IndexMap<String, (Span, String)>,
    problems: Vec<Problem>,
    warned: IndexSet<String>,
}

/// A label's key: labels are case-insensitive.
pub fn label_key(text: &str) -> String {
    text.to_ascii_lowercase()
}

impl BasicChecker<'_> {
    fn report<T>(&mut self, r: Result<T, Problem>) -> Option<T> {
        super::keep(&mut self.problems, r)
    }

    fn want(&mut self, e: &Expr, ty: BasicTy, why: &str) {
        if let Some(t) = self.ty(e) {
            if t != ty {
                self.problems.push(
                    Problem::error(
                        "pacer::check::type",
                        e.span,
                        format!("{} is needed here, not {}", ty.word(), t.word()),
                        format!("this is {}", t.word()),
                    )
                    .with_help(why.to_string()),
                );
            }
        }
    }

    fn label_exists(&mut self, seg: &Segment) -> bool {
        self.labels.contains_key(&label_key(&seg.text))
    }

    fn unknown_label(&mut self, seg: &Segment, what: &str) {
        let names: Vec<&str> = self.labels.values().map(|(_, t)| t.as_str()).collect();
        let help = nearest(&seg.text, names).map(|n| format!("did you mean `{n}`?"));
        self.problems.push(
            Problem::error(
                "pacer::check::label",
                seg.span,
                format!("no label `{}` in this program", seg.text),
                what.to_string(),
            )
            .with_help_opt(help.or_else(|| {
                Some(format!(
                    "define it with `{}:` on a line of its own",
                    seg.text
                ))
            })),
        );
    }

    fn stmts(&mut self, body: &[Stmt]) {
        for s in body {
            self.stmt(s);
        }
    }

    fn stmt(&mut self, s: &Stmt) {
        match &s.kind {
            StmtKind::Assign { target, value } => {
                let Some(r) = self.report(resolve(self.registry, target)) else {
                    self.ty(value);
                    return;
                };
                if matches!(r.access, Access::Read) {
                    self.problems.push(Problem::error(
                        "pacer::check::read_only",
                        target.span,
                        format!("{} is read-only", r.name),
                        "cannot be assigned",
                    ));
                }
                let want = if r.kind == Kind::BasicVar {
                    var_type(&r.name).map_or(BasicTy::Num, |t| t.1)
                } else {
                    BasicTy::Num
                };
                self.want(
                    value,
                    want,
                    "the value must match the variable's type suffix",
                );
            }
            StmtKind::SetCall {
                target,
                args,
                value,
            } => {
                let Some(c) = controller(&target.text) else {
                    self.problems.push(unknown_controller(target));
                    return;
                };
                if !c.writable {
                    self.problems.push(Problem::error(
                        "pacer::check::read_only",
                        target.span,
                        format!("{}@ is read-only", c.name),
                        "cannot be assigned",
                    ));
                }
                self.axis_args(target, args);
                self.want(value, c.ty, "the value must match the controller variable");
            }
            StmtKind::Gosub(seg) => {
                if self.label_exists(seg) {
                    return;
                }
                let name = Name::from_token(&seg.text, seg.span.start);
                match self.registry.resolve(&name) {
                    Ok(r) if r.access == Access::Action => {}
                    _ => self.unknown_label(seg, "no such subroutine"),
                }
            }
            StmtKind::Goto(seg) => {
                if !self.label_exists(seg) {
                    self.unknown_label(seg, "no such label");
                }
            }
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                self.want(
                    cond,
                    BasicTy::Num,
                    "a condition is a number (non-zero is true)",
                );
                self.stmts(then_body);
                if let Some(e) = else_body {
                    self.stmts(e);
                }
            }
            StmtKind::DoWhile { cond, body } => {
                self.want(
                    cond,
                    BasicTy::Num,
                    "a condition is a number (non-zero is true)",
                );
                self.stmts(body);
            }
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => {
                if let Some(r) = self.report(resolve(self.registry, var)) {
                    if r.kind != Kind::BasicVar || r.ty == ValueType::Integer {
                        self.problems.push(Problem::error(
                            "pacer::check::for",
                            var.span,
                            format!("{} cannot count a FOR loop", r.name),
                            "not a numeric variable",
                        ));
                    }
                }
                for e in [Some(from), Some(to), step.as_ref()].into_iter().flatten() {
                    self.want(e, BasicTy::Num, "FOR bounds are numbers");
                }
                self.stmts(body);
            }
            StmtKind::Gear { axis, form } => {
                self.want(axis, BasicTy::Axis, "GEAR moves an axis: `GEAR knife~ …`");
                match form {
                    GearForm::At {
                        out,
                        inn,
                        pacer,
                        after,
                    } => {
                        for e in [Some(out), Some(inn), pacer.as_ref()].into_iter().flatten() {
                            self.want(e, BasicTy::Num, "ratios and distances are numbers");
                        }
                        if let Some(a) = after {
                            self.after_input(a);
                        }
                    }
                    GearForm::For { dist, pacer } => {
                        self.want(dist, BasicTy::Num, "distances are numbers");
                        self.want(pacer, BasicTy::Num, "distances are numbers");
                    }
                }
            }
            StmtKind::Move { axis, form } => {
                self.want(axis, BasicTy::Axis, "MOVE moves an axis: `MOVE web~ …`");
                let nums: Vec<&Expr> = match form {
                    MoveForm::At { speed, time } => {
                        std::iter::once(speed).chain(time.iter()).collect()
                    }
                    MoveForm::Position {
                        target,
                        speed,
                        time,
                        ..
                    } => std::iter::once(target)
                        .chain(speed.iter())
                        .chain(time.iter())
                        .collect(),
                };
                for e in nums {
                    self.want(e, BasicTy::Num, "positions, speeds and times are numbers");
                }
            }
            StmtKind::WaitFor(e) | StmtKind::WaitTime(e) => {
                self.want(e, BasicTy::Num, "a number");
            }
            StmtKind::Action { target, .. } => {
                self.report(self.registry.resolve(target));
            }
            StmtKind::Label(_) | StmtKind::Return | StmtKind::End => {}
            StmtKind::DwellTime(_) | StmtKind::DwellMaster(_) | StmtKind::Call(_) => {
                self.problems.push(Problem::error(
                    "pacer::check::dialect",
                    s.span,
                    "not a MotionBASIC statement",
                    "PowerTools only",
                ));
            }
        }
    }

    fn after_input(&mut self, e: &Expr) {
        let ok = match &e.kind {
            ExprKind::Name(n) => match self.registry.resolve(n) {
                Ok(r) => r.ty.is_bit() && !matches!(r.access, Access::Action | Access::Input),
                Err(p) => {
                    self.problems.push(p);
                    return;
                }
            },
            _ => false,
        };
        if !ok {
            self.problems.push(
                Problem::error(
                    "pacer::check::after",
                    e.span,
                    "AFTER needs an input",
                    "not an input",
                )
                .with_help("name a bit the gear starts on, e.g. `AFTER DriveInput.1`"),
            );
        }
    }

    fn axis_args(&mut self, target: &Segment, args: &[Expr]) {
        if args.len() != 1 {
            self.problems.push(Problem::error(
                "pacer::check::arguments",
                target.span,
                format!(
                    "{} takes one axis set, not {} arguments",
                    target.text,
                    args.len()
                ),
                "wrong number of arguments",
            ));
        }
        for a in args {
            self.want(
                a,
                BasicTy::Axis,
                "controller variables take an axis: `POS.ASEN@(web~)`",
            );
        }
    }

    fn ty(&mut self, e: &Expr) -> Option<BasicTy> {
        match &e.kind {
            ExprKind::Number(v) if !v.is_finite() => {
                self.problems.push(Problem::error(
                    "pacer::check::number",
                    e.span,
                    "this number is too large to represent",
                    "out of range",
                ));
                None
            }
            ExprKind::Number(_) | ExprKind::Bool(_) => Some(BasicTy::Num),
            ExprKind::Str(_) => Some(BasicTy::Str),
            ExprKind::Paren(a) => self.ty(a),
            ExprKind::AxisSet(items) => {
                for i in items {
                    if let Some(t) = self.ty(i) {
                        if t == BasicTy::Str {
                            self.want(
                                i,
                                BasicTy::Axis,
                                "an axis set holds axis numbers and axis sets",
                            );
                        }
                    }
                }
                Some(BasicTy::Axis)
            }
            ExprKind::Name(n) => {
                let r = self.report(resolve(self.registry, n))?;
                if matches!(r.access, Access::Action | Access::Input) {
                    self.problems.push(Problem::error(
                        "pacer::check::not_readable",
                        n.span,
                        format!("{} has no value to read", r.name),
                        "not readable",
                    ));
                    return None;
                }
                if r.kind == Kind::BasicVar {
                    self.never_assigned(&r.name, n.span);
                    return var_type(&r.name).map(|t| t.1);
                }
                Some(BasicTy::Num)
            }
            ExprKind::Unary(op, a) => {
                self.want(
                    a,
                    BasicTy::Num,
                    match op {
                        UnOp::Neg => "`-` needs a number",
                        UnOp::Not => "NOT needs a number",
                    },
                );
                Some(BasicTy::Num)
            }
            ExprKind::Binary(op, a, b) => {
                let ta = self.ty(a)?;
                let tb = self.ty(b)?;
                if matches!(op, BinOp::Eq | BinOp::Ne) && ta == tb {
                    return Some(BasicTy::Num);
                }
                if ta != BasicTy::Num || tb != BasicTy::Num {
                    let (bad, t) = if ta != BasicTy::Num { (a, ta) } else { (b, tb) };
                    self.problems.push(Problem::error(
                        "pacer::check::type",
                        bad.span,
                        format!("`{}` needs numbers, not {}", op.symbol(), t.word()),
                        format!("this is {}", t.word()),
                    ));
                    return None;
                }
                Some(BasicTy::Num)
            }
            ExprKind::Call(f, args) => {
                if let Some(c) = controller(&f.text) {
                    self.axis_args(f, args);
                    return Some(c.ty);
                }
                let found = functions::find(&f.text)
                    .map(|(_, n)| n)
                    .or_else(|| functions::find_kernel(&f.text).map(|(_, n)| n));
                let Some(arity) = found else {
                    let names = functions::FUNCTIONS
                        .iter()
                        .map(|f| f.0)
                        .chain(functions::KERNEL_FUNCTIONS.iter().map(|f| f.0))
                        .chain(CONTROLLERS.iter().map(|c| c.name));
                    self.problems.push(
                        Problem::error(
                            "pacer::check::unknown_function",
                            f.span,
                            format!("unknown function or controller variable `{}`", f.text),
                            "not known",
                        )
                        .with_help_opt(
                            nearest(&f.text, names).map(|n| format!("did you mean `{n}`?")),
                        ),
                    );
                    return None;
                };
                if args.len() != arity {
                    self.problems.push(Problem::error(
                        "pacer::check::arguments",
                        e.span,
                        format!(
                            "{} takes {arity} argument(s), not {}",
                            f.text.to_ascii_uppercase(),
                            args.len()
                        ),
                        "wrong number of arguments",
                    ));
                }
                for a in args {
                    self.want(a, BasicTy::Num, "function arguments are numbers");
                }
                Some(BasicTy::Num)
            }
        }
    }

    /// A variable read but assigned nowhere holds 0 (or an empty axis set) for ever: almost
    /// always a slip of the name.
    fn never_assigned(&mut self, name: &str, span: Span) {
        let key = name.to_ascii_uppercase();
        if self.vars.assigned.contains(&key) || !self.warned.insert(key) {
            return;
        }
        let candidates = self
            .vars
            .assigned
            .iter()
            .filter_map(|k| self.vars.all.get(k).map(|(w, _)| w.as_str()));
        let help = match nearest(name, candidates) {
            Some(n) => {
                format!("`{n}` is assigned: did you mean it? As written, {name} is always 0")
            }
            None => format!("assign it before it is read; as written, {name} is always 0"),
        };
        self.problems.push(
            Problem::warning(
                "pacer::check::never_assigned",
                span,
                format!("{name} is read but never assigned"),
                "never assigned",
            )
            .with_help(help),
        );
    }
}

fn unknown_controller(target: &Segment) -> Problem {
    let names = CONTROLLERS.iter().map(|c| c.name);
    Problem::error(
        "pacer::check::unknown_controller",
        target.span,
        format!("unknown controller variable `{}`", target.text),
        "not a controller variable",
    )
    .with_help_opt(
        nearest(target.text.trim_end_matches('@'), names).map(|n| format!("did you mean `{n}@`?")),
    )
}
