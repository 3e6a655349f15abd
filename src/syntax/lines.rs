//! Lines as the grammar produces them, before block structure is assembled.

use super::ast::{BinOp, Expr, ExprKind, Name, Segment, Stmt, StmtKind, Using};
use crate::span::Span;

/// A modifier written after an initiate.
#[derive(Debug, Clone, PartialEq)]
pub enum Modifier {
    /// `Using Last` or `Using Capture.N`.
    Using(Using),
    /// `On Profile.N`.
    Profile(Name),
}

/// One source line.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// What the line says.
    pub kind: LineKind,
    /// Where it is.
    pub span: Span,
}

/// What a line can say.
#[derive(Debug, Clone, PartialEq)]
pub enum LineKind {
    /// A statement that needs no block structure.
    Simple(StmtKind),
    /// A bare action with its modifiers in source order.
    Action {
        target: Name,
        modifiers: Vec<Modifier>,
    },
    /// `If c Then`.
    If(Expr),
    /// `Else`.
    Else,
    /// `Endif` / `End If`.
    Endif,
    /// `Do While c`.
    DoWhile(Expr),
    /// `Loop`.
    Loop,
    /// `For v = a To b [Step s]`.
    For {
        var: Name,
        from: Expr,
        to: Expr,
        step: Option<Expr>,
    },
    /// `Next [v]`.
    Next(Option<Name>),
}

/// Build a binary expression spanning `l..r`.
pub fn bin(op: BinOp, a: Expr, b: Expr, l: usize, r: usize) -> Expr {
    Expr {
        kind: ExprKind::Binary(op, Box::new(a), Box::new(b)),
        span: Span::new(l, r),
    }
}

/// A MotionBASIC line number used as a label (`100`, `GOTO 0100`): its digits without leading
/// zeros, so `100` and `0100` are the same line.
pub fn line_number(text: &str, l: usize, r: usize) -> Segment {
    let digits = text.trim_start_matches('0');
    Segment {
        text: if digits.is_empty() { "0" } else { digits }.to_string(),
        span: Span::new(l, r),
    }
}

/// `ON n GOTO a, b, …` / `ON n GOSUB a, b, …` as the statements it means: `n` rounded to an
/// integer (CINT) picks the target, 1 the first; any other value goes on with the next
/// statement (Microsoft BASIC). Built as a chain of single-line IFs, so the checker and the
/// compiler need nothing new; after a GOSUB's RETURN the program goes on after the ON.
pub fn on_jump(n: Expr, targets: Vec<Segment>, gosub: bool, span: Span) -> StmtKind {
    let mut chain: Option<StmtKind> = None;
    for (i, target) in targets.into_iter().enumerate().rev() {
        let picked = Expr {
            kind: ExprKind::Binary(
                BinOp::Eq,
                Box::new(Expr {
                    kind: ExprKind::Call(
                        Segment {
                            text: "CINT".into(),
                            span: n.span,
                        },
                        vec![n.clone()],
                    ),
                    span: n.span,
                }),
                Box::new(Expr {
                    kind: ExprKind::Number((i + 1) as f64),
                    span: n.span,
                }),
            ),
            span: n.span,
        };
        let jump = if gosub {
            StmtKind::Gosub(target)
        } else {
            StmtKind::Goto(target)
        };
        chain = Some(StmtKind::If {
            cond: picked,
            then_body: vec![Stmt { kind: jump, span }],
            else_body: chain.map(|kind| vec![Stmt { kind, span }]),
        });
    }
    chain.unwrap_or(StmtKind::If {
        cond: Expr {
            kind: ExprKind::Bool(false),
            span: n.span,
        },
        then_body: Vec::new(),
        else_body: None,
    })
}

/// The `If …` (`if_line`) or `Do While …` line at `l..r` whose condition did not parse (the
/// parse error is reported): it still opens its block, with a placeholder condition.
pub fn broken_opener(if_line: bool, l: usize, r: usize) -> Line {
    let cond = Expr {
        kind: ExprKind::Bool(true),
        span: Span::new(l, r),
    };
    Line {
        kind: if if_line {
            LineKind::If(cond)
        } else {
            LineKind::DoWhile(cond)
        },
        span: Span::new(l, r),
    }
}

/// A numeric literal spanning `l..r` (a literal too large for a double is infinite; the checker
/// reports it).
pub fn number(text: &str, l: usize, r: usize) -> Expr {
    Expr {
        kind: ExprKind::Number(text.parse::<f64>().unwrap_or(f64::NAN)),
        span: Span::new(l, r),
    }
}
