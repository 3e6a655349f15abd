//! Lines as the grammar produces them, before block structure is assembled.

use super::ast::{BinOp, Expr, ExprKind, Name, Segment, StmtKind, Using};
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

/// A numeric literal spanning `l..r` (a literal too large for a double is infinite; the checker
/// reports it).
pub fn number(text: &str, l: usize, r: usize) -> Expr {
    Expr {
        kind: ExprKind::Number(text.parse::<f64>().unwrap_or(f64::NAN)),
        span: Span::new(l, r),
    }
}
