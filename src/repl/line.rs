//! What a typed line is: statements to run, or an expression to print. The parser decides:
//! a line that parses as statements runs (a bare readable name, such as `Queue.0.QueueEmpty`,
//! is read rather than "run"); a line that does not, but parses as an expression, is evaluated.

use crate::check::motionbasic as basic;
use crate::diag::{Level, Problem};
use crate::registry::{Access, Registry, Resolved};
use crate::span::Span;
use crate::syntax::ast::{Expr, ExprKind, Name, ProgramAst, Stmt, StmtKind};
use crate::syntax::{parse_expr, parse_program_as, Dialect};

/// MotionBASIC has no expression entry point of its own: an expression is parsed as the value
/// of an assignment to this name, and problems are shifted back onto the typed text.
const MB_WRAP: &str = "REPL.VALUE = ";

/// A typed line, parsed.
#[derive(Debug, Clone, PartialEq)]
pub enum Parsed {
    /// Statements to run on the REPL task.
    Statements(ProgramAst),
    /// An expression to print.
    Expression(Expr),
}

/// Parse `text` in `dialect`. Err: the problems of the statement parse (an expression parse
/// that fails too adds nothing a user would want to read).
pub fn parse(text: &str, dialect: Dialect, registry: &Registry) -> Result<Parsed, Vec<Problem>> {
    let mut problems = Vec::new();
    let ast = parse_program_as(text, dialect, &mut problems);
    if !problems.iter().any(|p| p.level == Level::Error) {
        if let [stmt] = ast.body.as_slice() {
            if let Some(name) = bare_name(stmt) {
                if resolve(registry, &name, dialect).is_ok_and(|r| readable(&r)) {
                    let span = name.span;
                    return Ok(Parsed::Expression(Expr {
                        kind: ExprKind::Name(name),
                        span,
                    }));
                }
            }
        }
        return Ok(Parsed::Statements(ast));
    }
    if text.trim().contains('\n') {
        return Err(problems);
    }
    match expression(text, dialect) {
        Ok(e) => Ok(Parsed::Expression(e)),
        // A line no statement can start with (`1 +`) was meant as an expression: its
        // problems are the expression's.
        Err(expr_problems) if starts_badly(&problems, text) && !expr_problems.is_empty() => {
            Err(expr_problems)
        }
        Err(_) => Err(problems),
    }
}

/// The statement parse failed on the line's first token, and only there.
fn starts_badly(problems: &[Problem], text: &str) -> bool {
    let first = text.len() - text.trim_start().len();
    let mut errors = problems
        .iter()
        .filter(|p| p.level == Level::Error)
        .peekable();
    errors.peek().is_some() && errors.all(|p| p.code == "pacer::syntax" && p.span.start <= first)
}

/// `text` as one expression, or the problems of parsing it so. Spans point into `text`.
fn expression(text: &str, dialect: Dialect) -> Result<Expr, Vec<Problem>> {
    match dialect {
        Dialect::PowerTools => parse_expr(text).map_err(|p| vec![p]),
        Dialect::MotionBasic => {
            let wrapped = format!("{MB_WRAP}{text}");
            let mut problems = Vec::new();
            let ast = parse_program_as(&wrapped, dialect, &mut problems);
            if !problems.is_empty() {
                for p in &mut problems {
                    shift_span(&mut p.span, MB_WRAP.len());
                }
                return Err(problems);
            }
            match ast.body.as_slice() {
                [Stmt {
                    kind: StmtKind::Assign { value, .. },
                    ..
                }] => {
                    let mut e = value.clone();
                    shift_expr(&mut e, MB_WRAP.len());
                    Ok(e)
                }
                _ => Err(Vec::new()),
            }
        }
    }
}

/// The name a statement is, when it is nothing but a name (`Queue.0.QueueEmpty`,
/// MotionBASIC's `X&`).
fn bare_name(stmt: &Stmt) -> Option<Name> {
    match &stmt.kind {
        StmtKind::Action {
            target,
            using: None,
            profile: None,
        } => Some(target.clone()),
        // A bare name, not `GOSUB NAME`.
        StmtKind::Gosub(seg) if seg.span.start == stmt.span.start => {
            Some(Name::from_token(&seg.text, seg.span.start))
        }
        _ => None,
    }
}

/// Resolve a name as `dialect` does.
pub fn resolve(registry: &Registry, name: &Name, dialect: Dialect) -> Result<Resolved, Problem> {
    match dialect {
        Dialect::PowerTools => registry.resolve(name),
        Dialect::MotionBasic => basic::resolve(registry, name),
    }
}

/// A member a program may read.
pub fn readable(r: &Resolved) -> bool {
    matches!(r.access, Access::Read | Access::ReadWrite)
}

fn shift_span(s: &mut Span, by: usize) {
    *s = Span::new(s.start.saturating_sub(by), s.end.saturating_sub(by));
}

fn shift_name(n: &mut Name, by: usize) {
    shift_span(&mut n.span, by);
    for seg in &mut n.segments {
        shift_span(&mut seg.span, by);
    }
}

/// Move every span of `e` `by` bytes back (from the wrapped text onto the typed one).
fn shift_expr(e: &mut Expr, by: usize) {
    shift_span(&mut e.span, by);
    match &mut e.kind {
        ExprKind::Name(n) => shift_name(n, by),
        ExprKind::Unary(_, a) | ExprKind::Paren(a) => shift_expr(a, by),
        ExprKind::Binary(_, a, b) => {
            shift_expr(a, by);
            shift_expr(b, by);
        }
        ExprKind::Call(f, args) => {
            shift_span(&mut f.span, by);
            args.iter_mut().for_each(|a| shift_expr(a, by));
        }
        ExprKind::AxisSet(args) => args.iter_mut().for_each(|a| shift_expr(a, by)),
        ExprKind::Number(..) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::machine::MachineFile;
    use crate::registry::ValueType;

    fn registry() -> Registry {
        let (r, problems) = crate::config::registry(
            &MachineFile::default(),
            &[0],
            &[crate::registry::BasicVar::Scalar(
                "X&".into(),
                ValueType::Fixed(0),
            )],
        );
        assert!(problems.is_empty());
        r
    }

    fn kind(text: &str, dialect: Dialect) -> &'static str {
        match parse(text, dialect, &registry()) {
            Ok(Parsed::Statements(_)) => "statements",
            Ok(Parsed::Expression(_)) => "expression",
            Err(_) => "error",
        }
    }

    #[test]
    fn statements_run_and_expressions_print() {
        let pt = Dialect::PowerTools;
        assert_eq!(kind("Queue.0.QueueOffset = 12", pt), "statements");
        assert_eq!(kind("Queue.0.QueueEmpty", pt), "expression");
        assert_eq!(kind("Queue.0.QueueRemove", pt), "statements");
        assert_eq!(kind("Queue.0.QueueOffset + 1", pt), "expression");
        assert_eq!(kind("1 +", pt), "error");
        assert_eq!(kind("Wait For Time 0.5", pt), "statements");
        let mb = Dialect::MotionBasic;
        assert_eq!(kind("X& = 3", mb), "statements");
        assert_eq!(kind("X&", mb), "expression");
        assert_eq!(kind("X& * 2 + 1", mb), "expression");
        assert_eq!(kind("Queue.0.QueueEmpty", mb), "expression");
        assert_eq!(kind("X& = = 3", mb), "error");
    }

    #[test]
    fn wrapped_expressions_point_into_the_typed_text() {
        let Ok(Parsed::Expression(e)) = parse("X& * 2", Dialect::MotionBasic, &registry()) else {
            panic!("an expression")
        };
        assert_eq!(e.span, Span::new(0, 6));
    }
}
