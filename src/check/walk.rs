//! The walk both dialects share: statements and blocks in order, labels collected and checked
//! once, jumps and subroutine calls checked against them, counted loops and conditions given
//! their shape. What a dialect decides — how names resolve, how expressions are typed, which
//! statements it has — is its [`Rules`]' business.

use super::typed::{self, StmtKind as T};
use crate::diag::{nearest, Problem};
use crate::registry::{Registry, Resolved};
use crate::span::Span;
use crate::syntax::ast::{self, Expr, Name, Segment, Stmt, StmtKind, Using};
use crate::syntax::Dialect;
use indexmap::IndexMap;

/// What the walker needs to know about the machine and the program's neighbours.
pub struct Machine<'a> {
    /// The object registry.
    pub registry: &'a Registry,
    /// Program numbers that have a loaded file.
    pub loaded_programs: &'a [u32],
    /// The loaded programs are all of the machine's (a folder or a machine file says which):
    /// a program referring to another is an error; checking loose files, only a warning.
    pub all_programs: bool,
}

/// A program's labels by lower-case name, with where and how each is written.
pub type Labels = IndexMap<String, (Span, String)>;

/// The problems found, and the labels of the program being checked.
pub struct Context<'a> {
    /// The machine.
    pub machine: &'a Machine<'a>,
    /// Every problem so far.
    pub problems: Vec<Problem>,
    /// The program's labels.
    pub labels: Labels,
}

impl Context<'_> {
    /// The value of `r`, or `None` with its problem recorded.
    pub fn keep<T>(&mut self, r: Result<T, Problem>) -> Option<T> {
        r.map_err(|p| self.problems.push(p)).ok()
    }

    /// Record a problem.
    pub fn push(&mut self, p: Problem) {
        self.problems.push(p);
    }

    /// The registry.
    pub fn registry(&self) -> &Registry {
        self.machine.registry
    }
}

/// What a dialect decides.
pub trait Rules {
    /// The dialect.
    fn dialect(&self) -> Dialect;

    /// Resolve a name a program reads or writes.
    fn resolve(&mut self, cx: &mut Context<'_>, name: &Name) -> Result<Resolved, Problem>;

    /// An expression whose value is used as `want` says (`None`: any value); every problem of
    /// it recorded. `None` when it has an error.
    fn expr(&mut self, cx: &mut Context<'_>, e: &Expr, want: Want<'_>) -> Option<typed::Expr>;

    /// `target = value`.
    fn assign(&mut self, cx: &mut Context<'_>, target: &Name, value: &Expr) -> Option<T>;

    /// The counter of a counted loop.
    fn for_variable(&mut self, cx: &mut Context<'_>, var: &Name) -> Option<Resolved>;

    /// A bare action with its modifiers (`Index.0.Initiate Using Capture.1`).
    fn action(
        &mut self,
        cx: &mut Context<'_>,
        s: &Stmt,
        target: &Name,
        using: Option<&Using>,
        profile: Option<&Name>,
    ) -> Option<T> {
        let _ = (target, using, profile);
        not_here(cx, s, self.dialect())
    }

    /// `GOSUB name` (or a bare name) where `name` is no label of the program.
    fn gosub_unlabelled(&mut self, cx: &mut Context<'_>, seg: &Segment) -> Option<T> {
        unknown_label(cx, seg, "no such subroutine");
        None
    }

    /// A statement only some dialects have (dwells, waits, calls, controller variables, motion
    /// statements): `None` with a problem when this dialect has no such statement.
    fn other(&mut self, cx: &mut Context<'_>, s: &Stmt) -> Option<T> {
        not_here(cx, s, self.dialect())
    }
}

/// What an expression's value is wanted as.
#[derive(Debug, Clone, Copy)]
pub enum Want<'w> {
    /// Any value (an assignment checks it against its target).
    Any,
    /// A number, for the reason given (the help line when it is not one).
    Number(&'w str),
    /// A condition, for the reason given.
    Condition(&'w str),
}

/// The problem of a statement this dialect does not have.
pub fn not_here<R>(cx: &mut Context<'_>, s: &Stmt, dialect: Dialect) -> Option<R> {
    let (message, label) = match dialect {
        Dialect::PowerTools => ("not a PowerTools statement", "MotionBASIC only"),
        Dialect::MotionBasic => ("not a MotionBASIC statement", "PowerTools only"),
    };
    cx.push(Problem::error(
        "pacer::check::dialect",
        s.span,
        message,
        label,
    ));
    None
}

/// The labels of a program, each defined once (a second definition is a problem).
pub fn labels(body: &[Stmt], problems: &mut Vec<Problem>) -> Labels {
    let mut labels = IndexMap::new();
    for seg in ast::labels(body) {
        let key = label_key(&seg.text);
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

/// A label's key: labels are case-insensitive.
pub fn label_key(text: &str) -> String {
    text.to_ascii_lowercase()
}

/// The problem of a jump to a label the program does not have.
pub fn unknown_label(cx: &mut Context<'_>, seg: &Segment, what: &str) {
    let near = nearest(&seg.text, cx.labels.values().map(|(_, t)| t.as_str()))
        .map(|n| format!("did you mean `{n}`?"));
    let help = near.unwrap_or_else(|| match what {
        "unknown label" => format!("define it on a line of its own: `{}:`", seg.text),
        _ => format!("define it with `{}:` on a line of its own", seg.text),
    });
    cx.push(
        Problem::error(
            "pacer::check::label",
            seg.span,
            format!("no label `{}` in this program", seg.text),
            what.to_string(),
        )
        .with_help(help),
    );
}

/// Check `ast` with `rules`: the checked program and every problem.
pub fn check<R: Rules>(
    rules: &mut R,
    machine: &Machine<'_>,
    ast: &ast::ProgramAst,
) -> (typed::Program, Vec<Problem>) {
    let mut cx = Context {
        machine,
        problems: Vec::new(),
        labels: IndexMap::new(),
    };
    cx.labels = labels(&ast.body, &mut cx.problems);
    let body = block(rules, &mut cx, &ast.body);
    (typed::Program { body }, cx.problems)
}

fn block<R: Rules>(rules: &mut R, cx: &mut Context<'_>, body: &[Stmt]) -> Vec<typed::Stmt> {
    body.iter()
        .filter_map(|s| statement(rules, cx, s).map(|kind| typed::Stmt { kind, span: s.span }))
        .collect()
}

fn statement<R: Rules>(rules: &mut R, cx: &mut Context<'_>, s: &Stmt) -> Option<T> {
    let basic = rules.dialect() == Dialect::MotionBasic;
    match &s.kind {
        StmtKind::Assign { target, value } => rules.assign(cx, target, value),
        StmtKind::Action {
            target,
            using,
            profile,
        } => rules.action(cx, s, target, using.as_ref(), profile.as_ref()),
        StmtKind::If {
            cond,
            then_body,
            else_body,
        } => {
            let why = if basic {
                "a condition is a number (non-zero is true)"
            } else {
                "If needs a condition"
            };
            let cond = rules.expr(cx, cond, Want::Condition(why));
            let then_body = block(rules, cx, then_body);
            let else_body = else_body.as_ref().map(|e| block(rules, cx, e));
            Some(T::If {
                cond: cond?,
                then_body,
                else_body,
            })
        }
        StmtKind::DoWhile { cond, body } => {
            let why = if basic {
                "a condition is a number (non-zero is true)"
            } else {
                "Do While needs a condition"
            };
            let cond = rules.expr(cx, cond, Want::Condition(why));
            let body = block(rules, cx, body);
            Some(T::While { cond: cond?, body })
        }
        StmtKind::For {
            var,
            from,
            to,
            step,
            body,
        } => {
            let var = rules.for_variable(cx, var);
            let bounds = if basic {
                "FOR bounds are numbers"
            } else {
                "loop bounds are numbers"
            };
            let from = rules.expr(cx, from, Want::Number(bounds));
            let to = rules.expr(cx, to, Want::Number(bounds));
            let step = match step {
                None => Some(None),
                Some(st) => {
                    let why = if basic {
                        bounds
                    } else {
                        "the step is a number"
                    };
                    let checked = rules.expr(cx, st, Want::Number(why));
                    if !basic && matches!(st.kind, ast::ExprKind::Number(v, _) if v == 0.0) {
                        cx.push(Problem::error(
                            "pacer::check::step",
                            st.span,
                            "a Step of 0 never ends the loop",
                            "zero step",
                        ));
                    }
                    checked.map(Some)
                }
            };
            let body = block(rules, cx, body);
            Some(T::For {
                var: var?,
                from: from?,
                to: to?,
                step: step?,
                body,
            })
        }
        StmtKind::Label(seg) => Some(T::Label(label_key(&seg.text))),
        StmtKind::Goto(seg) => {
            let key = label_key(&seg.text);
            if !cx.labels.contains_key(&key) {
                let what = if basic {
                    "no such label"
                } else {
                    "unknown label"
                };
                unknown_label(cx, seg, what);
                return None;
            }
            Some(T::Goto(key))
        }
        StmtKind::Gosub(seg) => {
            let key = label_key(&seg.text);
            if cx.labels.contains_key(&key) {
                return Some(T::Gosub(key));
            }
            rules.gosub_unlabelled(cx, seg)
        }
        StmtKind::End => Some(T::End),
        // Left only where it leaves no loop, which `syntax::blocks` reported.
        StmtKind::Exit { .. } => None,
        // Made assignments by `syntax::consts` before any check.
        StmtKind::Const(_) => None,
        StmtKind::Return if basic => Some(T::Return),
        StmtKind::Return
        | StmtKind::DwellTime(..)
        | StmtKind::DwellMaster(..)
        | StmtKind::WaitTime(_)
        | StmtKind::WaitFor(_)
        | StmtKind::Call(_)
        | StmtKind::SetCall { .. }
        | StmtKind::Gear { .. }
        | StmtKind::Move { .. }
        | StmtKind::Print(_)
        | StmtKind::PrintUsing(..)
        | StmtKind::Dim(_)
        | StmtKind::Data(_)
        | StmtKind::Read(_)
        | StmtKind::Restore(_)
        | StmtKind::Swap(..)
        | StmtKind::Randomize(_)
        | StmtKind::DefType { .. }
        | StmtKind::OptionBase(_) => rules.other(cx, s),
    }
}
