//! Assembles lines into nested statements: If/Else/Endif, Do While/Loop, For/Next.

use super::ast::{Stmt, StmtKind, Using};
use super::lines::{Line, LineKind, Modifier};
use super::span::Span;
use crate::diag::Problem;

enum Frame {
    If {
        cond: super::ast::Expr,
        span: Span,
        then_body: Vec<Stmt>,
        else_body: Option<(Span, Vec<Stmt>)>,
    },
    Do {
        cond: super::ast::Expr,
        span: Span,
        body: Vec<Stmt>,
    },
    For {
        var: super::ast::Name,
        from: super::ast::Expr,
        to: super::ast::Expr,
        step: Option<super::ast::Expr>,
        span: Span,
        body: Vec<Stmt>,
    },
}

impl Frame {
    fn body(&mut self) -> &mut Vec<Stmt> {
        match self {
            Frame::If {
                then_body,
                else_body,
                ..
            } => match else_body {
                Some((_, b)) => b,
                None => then_body,
            },
            Frame::Do { body, .. } | Frame::For { body, .. } => body,
        }
    }

    /// The statement this block makes once closed.
    fn into_stmt(self) -> Stmt {
        match self {
            Frame::If {
                cond,
                span,
                then_body,
                else_body,
            } => Stmt {
                kind: StmtKind::If {
                    cond,
                    then_body,
                    else_body: else_body.map(|(_, b)| b),
                },
                span,
            },
            Frame::Do { cond, span, body } => Stmt {
                kind: StmtKind::DoWhile { cond, body },
                span,
            },
            Frame::For {
                var,
                from,
                to,
                step,
                span,
                body,
            } => Stmt {
                kind: StmtKind::For {
                    var,
                    from,
                    to,
                    step,
                    body,
                },
                span,
            },
        }
    }

    fn describe(&self) -> (&'static str, &'static str, Span) {
        match self {
            Frame::If { span, .. } => ("If", "Endif", *span),
            Frame::Do { span, .. } => ("Do While", "Loop", *span),
            Frame::For { span, .. } => ("For", "Next", *span),
        }
    }
}

/// Deepest nesting of blocks accepted (keeps every later pass's recursion shallow).
pub const MAX_NESTING: usize = 64;

/// Turn the lines of a file into its statement tree, reporting unbalanced blocks.
pub fn assemble(lines: Vec<Line>, src: &str, problems: &mut Vec<Problem>) -> Vec<Stmt> {
    let mut top: Vec<Stmt> = Vec::new();
    let mut stack: Vec<Frame> = Vec::new();
    let index = super::span::LineIndex::new(src);
    let line_no = |span: Span| index.line(span.start);
    for line in lines {
        let span = line.span;
        let opens = matches!(
            line.kind,
            LineKind::If(_) | LineKind::DoWhile(_) | LineKind::For { .. }
        );
        if opens && stack.len() >= MAX_NESTING {
            problems.push(
                Problem::error(
                    "pacer::syntax::nesting",
                    span,
                    format!("blocks nested deeper than {MAX_NESTING}"),
                    "too deep",
                )
                .with_help("move the inner part into another program and `Call` it"),
            );
            return top;
        }
        match line.kind {
            LineKind::Simple(kind) => push(&mut stack, &mut top, Stmt { kind, span }),
            LineKind::Action { target, modifiers } => {
                let kind = action(target, modifiers, problems);
                push(&mut stack, &mut top, Stmt { kind, span });
            }
            LineKind::If(cond) => stack.push(Frame::If {
                cond,
                span,
                then_body: Vec::new(),
                else_body: None,
            }),
            LineKind::DoWhile(cond) => stack.push(Frame::Do {
                cond,
                span,
                body: Vec::new(),
            }),
            LineKind::For {
                var,
                from,
                to,
                step,
            } => stack.push(Frame::For {
                var,
                from,
                to,
                step,
                span,
                body: Vec::new(),
            }),
            LineKind::Else => match stack.last_mut() {
                Some(Frame::If {
                    else_body: else_body @ None,
                    ..
                }) => *else_body = Some((span, Vec::new())),
                Some(Frame::If {
                    else_body: Some((first, _)),
                    ..
                }) => {
                    let first_line = line_no(*first);
                    problems.push(
                        Problem::error(
                            "pacer::syntax::else",
                            span,
                            "a second Else in the same If",
                            "second Else",
                        )
                        .with_help(format!("this If already has its Else at line {first_line}")),
                    )
                }
                other => problems.push(mismatch(
                    "Else",
                    "If",
                    span,
                    other.map(|f| f.describe()),
                    &line_no,
                )),
            },
            LineKind::Endif => close(
                &mut stack,
                &mut top,
                |f| matches!(f, Frame::If { .. }),
                ("Endif", "If"),
                span,
                problems,
                &line_no,
            ),
            LineKind::Loop => close(
                &mut stack,
                &mut top,
                |f| matches!(f, Frame::Do { .. }),
                ("Loop", "Do While"),
                span,
                problems,
                &line_no,
            ),
            LineKind::Next(name) => {
                if let (Some(n), Some(Frame::For { var, .. })) = (&name, stack.last()) {
                    if !n.text().eq_ignore_ascii_case(&var.text()) {
                        problems.push(
                            Problem::error(
                                "pacer::syntax::next",
                                n.span,
                                format!("Next {} closes the loop over {}", n.text(), var.text()),
                                "not the loop variable",
                            )
                            .with_help(format!("write `Next {}` or just `Next`", var.text())),
                        );
                    }
                }
                close(
                    &mut stack,
                    &mut top,
                    |f| matches!(f, Frame::For { .. }),
                    ("Next", "For"),
                    span,
                    problems,
                    &line_no,
                )
            }
        }
    }
    // Report unclosed blocks, but keep their bodies so later passes still check them.
    while let Some(frame) = stack.pop() {
        let (open, close, span) = frame.describe();
        problems.push(
            Problem::error(
                "pacer::syntax::unclosed",
                span,
                format!("this {open} is never closed"),
                format!("{open} opened here"),
            )
            .with_help(format!("add `{close}` where the block ends")),
        );
        push(&mut stack, &mut top, frame.into_stmt());
    }
    top
}

/// A closing line: close the innermost block if `opens` it, else report the mismatch.
fn close(
    stack: &mut Vec<Frame>,
    top: &mut Vec<Stmt>,
    opens: fn(&Frame) -> bool,
    (word, opener): (&str, &str),
    span: Span,
    problems: &mut Vec<Problem>,
    line_no: &dyn Fn(Span) -> usize,
) {
    match stack.pop() {
        Some(frame) if opens(&frame) => push(stack, top, frame.into_stmt()),
        other => {
            problems.push(mismatch(
                word,
                opener,
                span,
                other.as_ref().map(Frame::describe),
                line_no,
            ));
            if let Some(frame) = other {
                stack.push(frame);
            }
        }
    }
}

fn push(stack: &mut [Frame], top: &mut Vec<Stmt>, stmt: Stmt) {
    match stack.last_mut() {
        Some(frame) => frame.body().push(stmt),
        None => top.push(stmt),
    }
}

fn mismatch(
    word: &str,
    opener: &str,
    span: Span,
    open: Option<(&'static str, &'static str, Span)>,
    line_no: &dyn Fn(Span) -> usize,
) -> Problem {
    let p = Problem::error(
        "pacer::syntax::unbalanced",
        span,
        format!("{word} without a matching {opener}"),
        format!("no open {opener}"),
    );
    match open {
        Some((o, c, s)) => p.with_help(format!(
            "the innermost open block is the {o} at line {}, closed by `{c}`",
            line_no(s)
        )),
        None => p.with_help(format!(
            "remove this {word} or add the {opener} it belongs to"
        )),
    }
}

fn action(
    target: super::ast::Name,
    modifiers: Vec<Modifier>,
    problems: &mut Vec<Problem>,
) -> StmtKind {
    let mut using: Option<Using> = None;
    let mut profile = None;
    for m in modifiers {
        match m {
            Modifier::Using(u) => {
                if using.is_some() {
                    let span = match &u {
                        Using::Last(s) => *s,
                        Using::Capture(n) => n.span,
                    };
                    problems.push(Problem::error(
                        "pacer::syntax::modifier",
                        span,
                        "a second `Using`",
                        "only one Using per initiate",
                    ));
                } else {
                    using = Some(u);
                }
            }
            Modifier::Profile(p) => {
                if profile.is_some() {
                    problems.push(Problem::error(
                        "pacer::syntax::modifier",
                        p.span,
                        "a second `On Profile`",
                        "only one profile per initiate",
                    ));
                } else {
                    profile = Some(p);
                }
            }
        }
    }
    StmtKind::Action {
        target,
        using,
        profile,
    }
}
