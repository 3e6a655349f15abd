//! Lines as the grammar produces them, before block structure is assembled.

use super::ast::{BinOp, DataItem, Expr, ExprKind, Name, NumForm, Segment, Stmt, StmtKind, Using};
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
    /// `ELSEIF c THEN` (MotionBASIC, as in QuickBASIC): the rest of the block is an `ELSE`
    /// holding an `IF c THEN` that the same `END IF` closes.
    ElseIf(Expr),
    /// `Endif` / `End If`.
    Endif,
    /// `Do While c` (also MotionBASIC's `WHILE c`).
    DoWhile(Expr),
    /// MotionBASIC's `DO WHILE c` (and `DO UNTIL c` as its negation), closed by `LOOP`.
    DoTest(Expr),
    /// `Loop` (also MotionBASIC's `WEND`, `LOOP`).
    Loop,
    /// A plain `DO` (MotionBASIC): its `LOOP` may test (`LOOP WHILE c`, `LOOP UNTIL c`).
    Do,
    /// `LOOP WHILE c` (and `LOOP UNTIL c` as its negation) closing a plain `DO`.
    LoopWhile(Expr),
    /// `For v = a To b [Step s]`.
    For {
        var: Name,
        from: Expr,
        to: Expr,
        step: Option<Expr>,
    },
    /// `Next [v]`.
    Next(Option<Name>),
    /// `SELECT CASE e` (MotionBASIC, as QuickBASIC writes it).
    Select(Expr),
    /// `CASE item, …`: the items of one case of a `SELECT CASE`.
    Case(Vec<CaseItem>),
    /// `CASE ELSE`.
    CaseElse,
    /// `END SELECT`.
    EndSelect,
}

/// One item of a `CASE` line, compared with the value the `SELECT CASE` tests.
#[derive(Debug, Clone, PartialEq)]
pub enum CaseItem {
    /// `IS op value`; a bare `value` is `IS = value`. The span is the item's.
    Is(BinOp, Expr, Span),
    /// `lo TO hi`, both ends included.
    Range(Expr, Expr, Span),
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
                    kind: ExprKind::Number((i + 1) as f64, NumForm::Whole),
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

/// The condition that holds while `c` does not (`DO UNTIL c`, `LOOP UNTIL c`): `c = 0`, so that
/// any value other than 0 ends the loop, as in Microsoft BASIC (`NOT c` would be true of 5).
pub fn until(c: Expr) -> Expr {
    let span = c.span;
    Expr {
        kind: ExprKind::Binary(
            BinOp::Eq,
            Box::new(c),
            Box::new(Expr {
                kind: ExprKind::Number(0.0, NumForm::Whole),
                span,
            }),
        ),
        span,
    }
}

/// A numeric literal spanning `l..r` (a literal too large for a double is infinite; the checker
/// reports it, and a `%` or `&` literal out of its type's range).
pub fn number(text: &str, l: usize, r: usize) -> Expr {
    let (value, form) = literal(text);
    Expr {
        kind: ExprKind::Number(value, form),
        span: Span::new(l, r),
    }
}

/// The value and form of a numeric literal as Microsoft BASIC writes them: digits with an
/// optional point and exponent (`E`, or `D` for a DOUBLE), an optional type suffix (`%`, `&`,
/// `!`, `#`), or a hexadecimal (`&H1F`) or octal (`&O17`, `&17`) integer. A hexadecimal or octal
/// literal is the two's complement of its digits in 16 bits (`&HFFFF` is -1), in 32 bits when
/// it has more or ends with `&` (`&HFFFF&` is 65535); beyond 32 bits it is infinite.
pub fn literal(text: &str) -> (f64, NumForm) {
    if let Some(rest) = text.strip_prefix('&') {
        let (rest, long) = match rest.strip_suffix('&') {
            Some(r) => (r, true),
            None => (rest, false),
        };
        let (digits, radix) = match rest.as_bytes().first() {
            Some(b'h' | b'H') => (&rest[1..], 16),
            Some(b'o' | b'O') => (&rest[1..], 8),
            _ => (rest, 8),
        };
        let Ok(v) = u64::from_str_radix(digits, radix) else {
            return (f64::INFINITY, NumForm::Long);
        };
        return if !long && v <= 0xFFFF {
            (f64::from(v as u16 as i16), NumForm::Integer)
        } else if v <= 0xFFFF_FFFF {
            (f64::from(v as u32 as i32), NumForm::Long)
        } else {
            (f64::INFINITY, NumForm::Long)
        };
    }
    let (body, suffix) = match text.as_bytes().last() {
        Some(b'%') => (&text[..text.len() - 1], Some(NumForm::Integer)),
        Some(b'&') => (&text[..text.len() - 1], Some(NumForm::Long)),
        Some(b'!') => (&text[..text.len() - 1], Some(NumForm::Single)),
        Some(b'#') => (&text[..text.len() - 1], Some(NumForm::Double)),
        _ => (text, None),
    };
    let d_exponent = body.contains(['d', 'D']);
    let value = body
        .replace(['d', 'D'], "e")
        .parse::<f64>()
        .unwrap_or(f64::NAN);
    let form = suffix.unwrap_or(if d_exponent {
        NumForm::Double
    } else if body.contains(['.', 'e', 'E']) {
        NumForm::Real
    } else {
        NumForm::Whole
    });
    (value, form)
}

/// `DEFINT`/`DEFLNG`/`DEFSNG`/`DEFDBL`/`DEFSTR` (`word` as written) over its letter ranges.
pub fn def_type(word: &str, ranges: Vec<(Segment, Option<Segment>)>) -> StmtKind {
    let suffix = match word.get(3..).map(str::to_ascii_lowercase).as_deref() {
        Some("int") => '%',
        Some("lng") => '&',
        Some("dbl") => '#',
        Some("str") => '$',
        _ => '!',
    };
    StmtKind::DefType { suffix, ranges }
}

/// The items of a `DATA` statement whose token (`DATA` and its raw text) starts at byte `at`:
/// split at commas outside quotes; a quoted item is a string, an unquoted one is its text
/// trimmed (a number when it reads as one), as in Microsoft BASIC.
pub fn data_items(token: &str, at: usize) -> Vec<DataItem> {
    let body = token.get(4..).unwrap_or_default();
    let base = at + 4;
    let mut items = Vec::new();
    let mut start = 0;
    let mut quoted = false;
    let bytes = body.as_bytes();
    for i in 0..=bytes.len() {
        match bytes.get(i) {
            Some(b'"') => quoted = !quoted,
            Some(b',') if !quoted => {
                items.push(data_item(body, start, i, base));
                start = i + 1;
            }
            None => items.push(data_item(body, start, i, base)),
            _ => {}
        }
    }
    items
}

fn data_item(body: &str, from: usize, to: usize, base: usize) -> DataItem {
    let raw = body.get(from..to).unwrap_or_default();
    let lead = raw.len() - raw.trim_start().len();
    let text = raw.trim();
    let span = Span::new(base + from + lead, base + from + lead + text.len());
    match text.strip_prefix('"') {
        // A quoted item: what is inside the quotes (text after the closing quote is dropped,
        // as Microsoft BASIC does).
        Some(rest) => DataItem {
            text: rest.split('"').next().unwrap_or_default().to_string(),
            quoted: true,
            span,
        },
        None => DataItem {
            text: text.to_string(),
            quoted: false,
            span,
        },
    }
}
