//! Assembles lines into nested statements: If/Else/Endif, Do While/Loop, For/Next, and
//! MotionBASIC's SELECT CASE made an IF … ELSEIF chain.

use super::ast::{BinOp, Expr, ExprKind, Name, Segment, Stmt, StmtKind, Using};
use super::lines::{CaseItem, Line, LineKind, Modifier};
use crate::diag::Problem;
use crate::span::Span;

/// The words a dialect opens and closes its blocks with, for messages.
#[derive(Debug)]
pub struct Words {
    /// Opens a conditional block.
    pub if_: &'static str,
    /// The alternative branch.
    pub else_: &'static str,
    /// An alternative with its own condition (MotionBASIC only).
    pub elseif: &'static str,
    /// Closes a conditional block.
    pub endif: &'static str,
    /// Opens a conditional loop.
    pub while_: &'static str,
    /// Closes it.
    pub wend: &'static str,
    /// Opens a loop whose `LOOP` may test (MotionBASIC's plain `DO`).
    pub do_: &'static str,
    /// Closes it.
    pub loop_: &'static str,
    /// Opens a counted loop.
    pub for_: &'static str,
    /// Closes it.
    pub next: &'static str,
    /// How a long block is split (help text).
    pub split_help: &'static str,
}

/// PowerTools block words.
pub const POWERTOOLS_WORDS: Words = Words {
    if_: "If",
    else_: "Else",
    elseif: "Elseif",
    endif: "Endif",
    while_: "Do While",
    wend: "Loop",
    do_: "Do While",
    loop_: "Loop",
    for_: "For",
    next: "Next",
    split_help: "move the inner part into another program and `Call` it",
};

/// MotionBASIC block words.
pub const MOTIONBASIC_WORDS: Words = Words {
    if_: "IF",
    else_: "ELSE",
    elseif: "ELSEIF",
    endif: "ENDIF",
    while_: "WHILE",
    wend: "WEND",
    do_: "DO",
    loop_: "LOOP",
    for_: "FOR",
    next: "NEXT",
    split_help: "move the inner part into a subroutine and call it",
};

enum Frame {
    If {
        cond: super::ast::Expr,
        span: Span,
        then_body: Vec<Stmt>,
        else_body: Option<(Span, Vec<Stmt>)>,
        /// Opened by an `ELSEIF`: the `END IF` that closes it closes the block it continues.
        chained: bool,
        /// Opened by a `CASE` (or `CASE ELSE`): only `END SELECT` closes it, and only `CASE`
        /// lines continue it.
        select: bool,
    },
    /// A `SELECT CASE` (its test already stored in `var`), until its first `CASE` opens the
    /// `If` chain the cases make.
    Select {
        span: Span,
        /// The made variable holding the tested value.
        var: Name,
        /// Labels before the first `CASE`, then the chain once `END SELECT` closes it.
        body: Vec<Stmt>,
        /// A `CASE` has opened the chain.
        cases: bool,
        /// A statement before the first `CASE` has been reported.
        stray: bool,
    },
    Do {
        cond: super::ast::Expr,
        span: Span,
        body: Vec<Stmt>,
        /// How it opened: a plain `DO` (its `LOOP` may test, `LOOP WHILE c`), a `DO WHILE`
        /// (`Some(false)`) or a `WHILE` (`None`).
        plain: Option<bool>,
        /// The label after the loop, once an `EXIT DO` jumps there.
        exit: Option<Segment>,
    },
    For {
        var: super::ast::Name,
        from: super::ast::Expr,
        to: super::ast::Expr,
        step: Option<super::ast::Expr>,
        span: Span,
        body: Vec<Stmt>,
        /// The label after the loop, once an `EXIT FOR` jumps there.
        exit: Option<Segment>,
    },
}

impl Frame {
    /// The label after this loop, made when an `EXIT` first needs it (`n`: labels made so
    /// far, `made_label`).
    fn exit_label(&mut self, n: &mut usize) -> Option<Segment> {
        let (exit, span) = match self {
            Frame::Do { exit, span, .. } | Frame::For { exit, span, .. } => (exit, *span),
            Frame::If { .. } | Frame::Select { .. } => return None,
        };
        Some(
            exit.get_or_insert_with(|| made_label("exit", n, span))
                .clone(),
        )
    }

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
            Frame::Do { body, .. } | Frame::For { body, .. } | Frame::Select { body, .. } => body,
        }
    }

    /// The statements this block makes once closed.
    fn into_stmts(self) -> Vec<Stmt> {
        let stmt = match self {
            Frame::Select { body, .. } => return body,
            Frame::If {
                cond,
                span,
                then_body,
                else_body,
                ..
            } => Stmt {
                kind: StmtKind::If {
                    cond,
                    then_body,
                    else_body: else_body.map(|(_, b)| b),
                },
                span,
            },
            Frame::Do {
                cond, span, body, ..
            } => Stmt {
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
                ..
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
        };
        vec![stmt]
    }

    fn describe(&self, w: &Words) -> (&'static str, &'static str, Span) {
        match self {
            Frame::If {
                span, select: true, ..
            } => ("CASE", END_SELECT, *span),
            Frame::If { span, .. } => (w.if_, w.endif, *span),
            Frame::Select { span, .. } => (SELECT, END_SELECT, *span),
            Frame::Do {
                span,
                plain: Some(_),
                ..
            } => (w.do_, w.loop_, *span),
            Frame::Do { span, .. } => (w.while_, w.wend, *span),
            Frame::For { span, .. } => (w.for_, w.next, *span),
        }
    }
}

/// How messages name the opening line of a `SELECT CASE` (MotionBASIC only).
const SELECT: &str = "SELECT CASE";

/// And its closing line.
const END_SELECT: &str = "END SELECT";

/// Deepest nesting of blocks accepted (keeps every later pass's recursion shallow).
pub const MAX_NESTING: usize = 64;

/// Deepest nesting of the tree, where each `ELSEIF` of a chain is one level deeper.
pub const MAX_DEPTH: usize = 256;

/// Turn the lines of a file into its statement tree, reporting unbalanced blocks.
pub fn assemble(lines: Vec<Line>, src: &str, problems: &mut Vec<Problem>, w: &Words) -> Vec<Stmt> {
    let mut top: Vec<Stmt> = Vec::new();
    let mut stack: Vec<Frame> = Vec::new();
    // Labels made for `EXIT` and `LOOP WHILE` (`exit 1`, `do 2`, …), and variables for
    // `SELECT CASE`.
    let mut made = 0usize;
    // The first letters `DEFSTR` has typed so far, for the type of a `SELECT CASE` test.
    let mut strings = [false; 26];
    let program = program_tag(src);
    let index = crate::span::LineIndex::new(src);
    let line_no = |span: Span| index.line(span.start);
    for line in lines {
        let span = line.span;
        let opens = matches!(
            line.kind,
            LineKind::If(_)
                | LineKind::DoWhile(_)
                | LineKind::DoTest(_)
                | LineKind::Do
                | LineKind::For { .. }
                | LineKind::Select(_)
        );
        // An ELSEIF nests its block in the ELSE of the one before: the tree has its own, larger
        // limit, which the blocks inside a chain count towards too. So does each CASE.
        let chains = matches!(
            line.kind,
            LineKind::ElseIf(_) | LineKind::Case(_) | LineKind::CaseElse
        );
        // A SELECT CASE's frame stands for the chain its CASEs make.
        let blocks = stack
            .iter()
            .filter(|f| {
                !matches!(
                    f,
                    Frame::If { chained: true, .. } | Frame::If { select: true, .. }
                )
            })
            .count();
        let too_deep = if opens && blocks >= MAX_NESTING {
            Some((
                format!("blocks nested deeper than {MAX_NESTING}"),
                w.split_help.to_string(),
            ))
        } else if (opens || chains) && stack.len() >= MAX_DEPTH {
            Some((
                format!("blocks and {}s nested deeper than {MAX_DEPTH}", w.elseif),
                format!(
                    "test the value once and jump (`ON … GOTO`), or split the {} chain",
                    w.if_
                ),
            ))
        } else {
            None
        };
        if let Some((message, help)) = too_deep {
            problems.push(
                Problem::error("pacer::syntax::nesting", span, message, "too deep").with_help(help),
            );
            return top;
        }
        if let Some(Frame::Select {
            cases: false,
            stray,
            span: at,
            ..
        }) = stack.last_mut()
        {
            // Closing lines out of place are reported as such when they are handled.
            let runs = matches!(
                line.kind,
                LineKind::Simple(_)
                    | LineKind::Action { .. }
                    | LineKind::If(_)
                    | LineKind::DoWhile(_)
                    | LineKind::DoTest(_)
                    | LineKind::Do
                    | LineKind::For { .. }
                    | LineKind::Select(_)
            ) && !matches!(line.kind, LineKind::Simple(StmtKind::Label(_)));
            if runs && !*stray {
                *stray = true;
                problems.push(
                    Problem::error(
                        "pacer::syntax::select",
                        span,
                        format!("a statement between {SELECT} and its first CASE"),
                        "under no CASE",
                    )
                    .with_help(format!(
                        "move it above the {SELECT} at line {}, or under a CASE",
                        line_no(*at)
                    )),
                );
            }
        }
        match line.kind {
            LineKind::Select(value) => {
                let string = string_valued(&value, &strings);
                made += 1;
                let seg = Segment {
                    text: format!("SELECT {made} {program}{}", if string { '$' } else { '#' }),
                    span: value.span,
                };
                let var = Name {
                    span: seg.span,
                    segments: vec![seg],
                };
                push(
                    &mut stack,
                    &mut top,
                    Stmt {
                        kind: StmtKind::Assign {
                            target: var.clone(),
                            value,
                        },
                        span,
                    },
                );
                stack.push(Frame::Select {
                    span,
                    var,
                    body: Vec::new(),
                    cases: false,
                    stray: false,
                });
            }
            LineKind::Case(items) => case(&mut stack, Some(items), span, problems, &line_no),
            LineKind::CaseElse => case(&mut stack, None, span, problems, &line_no),
            LineKind::EndSelect => end_select(&mut stack, &mut top, span, problems, &line_no, w),
            LineKind::Simple(StmtKind::DefType { suffix, ranges }) => {
                for (from, to) in &ranges {
                    let letter = |s: &Segment| {
                        let c = s.text.chars().next().filter(|_| s.text.len() == 1)?;
                        c.is_ascii_alphabetic()
                            .then(|| (c.to_ascii_uppercase() as u8 - b'A') as usize)
                    };
                    // A range that is not letters is reported by `syntax::deftype`.
                    let (Some(a), Some(b)) =
                        (letter(from), to.as_ref().map_or(letter(from), letter))
                    else {
                        continue;
                    };
                    for typed in strings.iter_mut().take(a.max(b) + 1).skip(a.min(b)) {
                        *typed = suffix == '$';
                    }
                }
                let kind = StmtKind::DefType { suffix, ranges };
                push(&mut stack, &mut top, Stmt { kind, span });
            }
            LineKind::Simple(kind) => {
                let mut stmt = Stmt { kind, span };
                resolve_exits(&mut stmt, &mut stack, &mut made, problems, w);
                push(&mut stack, &mut top, stmt);
            }
            LineKind::Action { target, modifiers } => {
                let kind = action(target, modifiers, problems);
                push(&mut stack, &mut top, Stmt { kind, span });
            }
            LineKind::If(cond) => stack.push(Frame::If {
                cond,
                span,
                then_body: Vec::new(),
                else_body: None,
                chained: false,
                select: false,
            }),
            LineKind::ElseIf(cond) => {
                if open_else(&mut stack, span, true, problems, &line_no, w) {
                    stack.push(Frame::If {
                        cond,
                        span,
                        then_body: Vec::new(),
                        else_body: None,
                        chained: true,
                        select: false,
                    });
                }
            }
            LineKind::DoWhile(cond) => stack.push(Frame::Do {
                cond,
                span,
                body: Vec::new(),
                plain: None,
                exit: None,
            }),
            LineKind::DoTest(cond) => stack.push(Frame::Do {
                cond,
                span,
                body: Vec::new(),
                plain: Some(false),
                exit: None,
            }),
            LineKind::Do => stack.push(Frame::Do {
                cond: super::ast::Expr {
                    kind: super::ast::ExprKind::Bool(true),
                    span,
                },
                span,
                body: Vec::new(),
                plain: Some(true),
                exit: None,
            }),
            LineKind::LoopWhile(cond) => match stack.pop() {
                Some(Frame::Do {
                    plain: Some(true),
                    body,
                    span: at,
                    exit,
                    ..
                }) => {
                    // The body, then out of the loop unless `cond` holds, and back to its
                    // start: a backward jump of its own, which the machine may run as a loop
                    // (`compile::body`) as it does a `WHILE`.
                    let start = made_label("do", &mut made, at);
                    let exit = exit.unwrap_or_else(|| made_label("exit", &mut made, at));
                    let stmt = |kind| Stmt { kind, span };
                    let mut out = vec![Stmt {
                        kind: StmtKind::Label(start.clone()),
                        span: at,
                    }];
                    out.extend(body);
                    out.push(stmt(StmtKind::If {
                        cond: super::lines::until(cond),
                        then_body: vec![stmt(StmtKind::Goto(exit.clone()))],
                        else_body: None,
                    }));
                    out.push(stmt(StmtKind::Goto(start)));
                    out.push(stmt(StmtKind::Label(exit)));
                    for s in out {
                        push(&mut stack, &mut top, s);
                    }
                }
                other => {
                    let open = other.as_ref().map(|f| f.describe(w));
                    let mut p = mismatch(w.loop_, w.do_, span, open, &line_no);
                    if let Some(Frame::Do {
                        plain: Some(false), ..
                    }) = other
                    {
                        p = p.with_help(format!(
                            "a `{} WHILE`/`UNTIL` tests at its start: close it with a plain `{}`",
                            w.do_, w.loop_
                        ));
                    }
                    problems.push(p);
                    if let Some(frame) = other {
                        stack.push(frame);
                    }
                }
            },
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
                exit: None,
            }),
            LineKind::Else => {
                open_else(&mut stack, span, false, problems, &line_no, w);
            }
            LineKind::Endif => close(
                &mut stack,
                &mut top,
                Closer::Endif,
                span,
                problems,
                &line_no,
                w,
            ),
            LineKind::Loop => close(
                &mut stack,
                &mut top,
                Closer::Loop,
                span,
                problems,
                &line_no,
                w,
            ),
            LineKind::Next(name) => {
                if let (Some(n), Some(Frame::For { var, .. })) = (&name, stack.last()) {
                    if !n.text().eq_ignore_ascii_case(&var.text()) {
                        problems.push(
                            Problem::error(
                                "pacer::syntax::next",
                                n.span,
                                format!(
                                    "{} {} closes the loop over {}",
                                    w.next,
                                    n.text(),
                                    var.text()
                                ),
                                "not the loop variable",
                            )
                            .with_help(format!(
                                "write `{} {}` or just `{}`",
                                w.next,
                                var.text(),
                                w.next
                            )),
                        );
                    }
                }
                close(
                    &mut stack,
                    &mut top,
                    Closer::Next,
                    span,
                    problems,
                    &line_no,
                    w,
                )
            }
        }
    }
    // Report unclosed blocks, but keep their bodies so later passes still check them.
    while let Some(frame) = stack.pop() {
        let (open, close, span) = frame.describe(w);
        // The block an ELSEIF continues reports it, and the SELECT CASE its CASEs.
        if matches!(
            frame,
            Frame::If { chained: true, .. } | Frame::If { select: true, .. }
        ) {
            push_all(&mut stack, &mut top, frame.into_stmts());
            continue;
        }
        problems.push(
            Problem::error(
                "pacer::syntax::unclosed",
                span,
                format!("this {open} is never closed"),
                format!("{open} opened here"),
            )
            .with_help(format!("add `{close}` where the block ends")),
        );
        push_all(&mut stack, &mut top, frame.into_stmts());
    }
    top
}

/// The block a closing line closes.
#[derive(Clone, Copy)]
enum Closer {
    Endif,
    Loop,
    Next,
}

impl Closer {
    fn opens(self, f: &Frame) -> bool {
        matches!(
            (self, f),
            (Closer::Endif, Frame::If { select: false, .. })
                | (Closer::Loop, Frame::Do { .. })
                | (Closer::Next, Frame::For { .. })
        )
    }

    /// The closing word and the word of the block it closes.
    fn words(self, w: &Words) -> (&'static str, &'static str) {
        match self {
            Closer::Endif => (w.endif, w.if_),
            Closer::Loop => (w.wend, w.while_),
            Closer::Next => (w.next, w.for_),
        }
    }
}

/// A closing line: close the innermost block if it is the right kind, else report the mismatch.
fn close(
    stack: &mut Vec<Frame>,
    top: &mut Vec<Stmt>,
    closer: Closer,
    span: Span,
    problems: &mut Vec<Problem>,
    line_no: &dyn Fn(Span) -> usize,
    w: &Words,
) {
    let (word, opener) = closer.words(w);
    match stack.pop() {
        Some(mut frame) if closer.opens(&frame) => {
            let mut chained = matches!(frame, Frame::If { chained: true, .. });
            let exit = match &mut frame {
                Frame::Do { exit, .. } | Frame::For { exit, .. } => exit.take(),
                Frame::If { .. } | Frame::Select { .. } => None,
            };
            push_all(stack, top, frame.into_stmts());
            if let Some(exit) = exit {
                push(
                    stack,
                    top,
                    Stmt {
                        kind: StmtKind::Label(exit),
                        span,
                    },
                );
            }
            // An `ELSEIF`'s block sits in the ELSE of the block it continues: one END IF
            // closes them all.
            while chained {
                let Some(outer) = stack.pop() else { break };
                chained = matches!(outer, Frame::If { chained: true, .. });
                push_all(stack, top, outer.into_stmts());
            }
        }
        other => {
            problems.push(mismatch(
                word,
                opener,
                span,
                other.as_ref().map(|f| f.describe(w)),
                line_no,
            ));
            if let Some(frame) = other {
                stack.push(frame);
            }
        }
    }
}

/// A label for a jump the blocks make (`exit 3`, `do 4`; `n`: labels made so far): with a
/// space in it, it is none a program can write.
fn made_label(what: &str, n: &mut usize, span: Span) -> Segment {
    *n += 1;
    Segment {
        text: format!("{what} {n}"),
        span,
    }
}

/// An `ELSE` (or, `elseif`, an `ELSEIF`) at `span`: the innermost block, an `IF` without one
/// yet, takes its `ELSE` part (true); anything else is reported (false).
fn open_else(
    stack: &mut [Frame],
    span: Span,
    elseif: bool,
    problems: &mut Vec<Problem>,
    line_no: &dyn Fn(Span) -> usize,
    w: &Words,
) -> bool {
    let word = if elseif { w.elseif } else { w.else_ };
    match stack.last_mut() {
        Some(Frame::If {
            else_body: else_body @ None,
            select: false,
            ..
        }) => {
            *else_body = Some((span, Vec::new()));
            return true;
        }
        Some(Frame::If {
            else_body: Some((first, _)),
            select: false,
            ..
        }) => {
            let first_line = line_no(*first);
            let (message, label, help) = if elseif {
                (
                    format!("{word} after the {} of this {}", w.else_, w.if_),
                    format!("{word} after {}", w.else_),
                    format!(
                        "the {} at line {first_line} must come last: move this {word} above it",
                        w.else_
                    ),
                )
            } else {
                (
                    format!("a second {word} in the same {}", w.if_),
                    format!("second {word}"),
                    format!("this {} already has its {word} at line {first_line}", w.if_),
                )
            };
            problems
                .push(Problem::error("pacer::syntax::else", span, message, label).with_help(help));
        }
        other => problems.push(mismatch(
            word,
            w.if_,
            span,
            other.map(|f| f.describe(w)),
            line_no,
        )),
    }
    false
}

/// `EXIT FOR` / `EXIT DO` in `stmt` (a simple statement, or one in a single-line `IF`'s parts)
/// made a jump to the end of the innermost loop of its kind (`stack`); one outside any such
/// loop is a problem (and is dropped).
fn resolve_exits(
    stmt: &mut Stmt,
    stack: &mut [Frame],
    made: &mut usize,
    problems: &mut Vec<Problem>,
    w: &Words,
) {
    match &mut stmt.kind {
        StmtKind::Exit { for_ } => {
            let for_ = *for_;
            let frame = stack.iter_mut().rev().find(|f| match f {
                Frame::For { .. } => for_,
                Frame::Do { .. } => !for_,
                Frame::If { .. } | Frame::Select { .. } => false,
            });
            let (word, loop_) = if for_ {
                ("EXIT FOR", w.for_)
            } else {
                ("EXIT DO", "DO or WHILE")
            };
            match frame.and_then(|f| f.exit_label(made)) {
                Some(label) => stmt.kind = StmtKind::Goto(label),
                None => {
                    problems.push(
                        Problem::error(
                            "pacer::syntax::exit",
                            stmt.span,
                            format!("{word} outside a {loop_} loop"),
                            "no loop to leave",
                        )
                        .with_help("it leaves the innermost loop of its kind around it"),
                    );
                }
            }
        }
        StmtKind::If {
            then_body,
            else_body,
            ..
        } => {
            for s in then_body.iter_mut().chain(else_body.iter_mut().flatten()) {
                resolve_exits(s, stack, made, problems, w);
            }
        }
        _ => {}
    }
}

/// A `CASE` line (`items`; `None`: `CASE ELSE`) at `span`: the first opens the `If` chain of
/// the innermost `SELECT CASE`, each later one continues it as an `ELSEIF` (or its `ELSE`).
/// Anywhere else, or after the `CASE ELSE`, it is reported.
fn case(
    stack: &mut Vec<Frame>,
    items: Option<Vec<CaseItem>>,
    span: Span,
    problems: &mut Vec<Problem>,
    line_no: &dyn Fn(Span) -> usize,
) {
    let word = if items.is_some() { "CASE" } else { "CASE ELSE" };
    // The value the cases test: the innermost SELECT's, under the chain its CASEs made.
    let var = stack.iter().rev().find_map(|f| match f {
        Frame::Select { var, .. } => Some(var.clone()),
        _ => None,
    });
    match (stack.last_mut(), var) {
        (Some(Frame::Select { cases, .. }), Some(var)) if !*cases => {
            *cases = true;
            let (cond, else_body) = match items {
                Some(items) => (case_test(&var, items, span), None),
                // Nothing is tested: the ELSE part runs.
                None => (
                    Expr {
                        kind: ExprKind::Bool(false),
                        span,
                    },
                    Some((span, Vec::new())),
                ),
            };
            stack.push(Frame::If {
                cond,
                span,
                then_body: Vec::new(),
                else_body,
                chained: false,
                select: true,
            });
        }
        (
            Some(Frame::If {
                else_body: else_body @ None,
                select: true,
                ..
            }),
            Some(var),
        ) => {
            *else_body = Some((span, Vec::new()));
            if let Some(items) = items {
                stack.push(Frame::If {
                    cond: case_test(&var, items, span),
                    span,
                    then_body: Vec::new(),
                    else_body: None,
                    chained: true,
                    select: true,
                });
            }
        }
        (
            Some(Frame::If {
                else_body: Some((first, _)),
                select: true,
                ..
            }),
            _,
        ) => {
            let first_line = line_no(*first);
            let (message, label, help) = if items.is_some() {
                (
                    format!("CASE after the CASE ELSE of this {SELECT}"),
                    "CASE after CASE ELSE".to_string(),
                    format!(
                        "the CASE ELSE at line {first_line} must come last: move this CASE above it"
                    ),
                )
            } else {
                (
                    format!("a second CASE ELSE in the same {SELECT}"),
                    "second CASE ELSE".to_string(),
                    format!("this {SELECT} already has its CASE ELSE at line {first_line}"),
                )
            };
            problems
                .push(Problem::error("pacer::syntax::case", span, message, label).with_help(help));
        }
        (other, _) => {
            let open = other.map(|f| f.describe(&MOTIONBASIC_WORDS));
            problems.push(mismatch(word, SELECT, span, open, line_no));
        }
    }
}

/// `END SELECT` at `span`: closes the innermost block if it is a `SELECT CASE` (with the chain
/// its CASEs made), else the mismatch is reported.
fn end_select(
    stack: &mut Vec<Frame>,
    top: &mut Vec<Stmt>,
    span: Span,
    problems: &mut Vec<Problem>,
    line_no: &dyn Fn(Span) -> usize,
    w: &Words,
) {
    match stack.last() {
        Some(Frame::If { select: true, .. } | Frame::Select { .. }) => {
            // The CASEs of this SELECT are the `If` frames above it: a nested SELECT's sit
            // above their own `Select` frame, closed already.
            while let Some(Frame::If { select: true, .. }) = stack.last() {
                if let Some(frame) = stack.pop() {
                    push_all(stack, top, frame.into_stmts());
                }
            }
            if let Some(frame) = stack.pop() {
                push_all(stack, top, frame.into_stmts());
            }
        }
        other => {
            let open = other.map(|f| f.describe(w));
            problems.push(mismatch(END_SELECT, SELECT, span, open, line_no));
        }
    }
}

/// The test of a `CASE` line: any of its items holds for `var`, the made variable holding the
/// value of the `SELECT CASE`. Each comparison spans its item; the variable keeps the span of
/// the tested expression, so a string tested against a number is shown as that expression.
fn case_test(var: &Name, items: Vec<CaseItem>, span: Span) -> Expr {
    let compare = |op: BinOp, e: Expr, at: Span| Expr {
        kind: ExprKind::Binary(
            op,
            Box::new(Expr {
                kind: ExprKind::Name(var.clone()),
                span: var.span,
            }),
            Box::new(e),
        ),
        span: at,
    };
    let mut test: Option<Expr> = None;
    for item in items {
        let one = match item {
            CaseItem::Is(op, e, at) => compare(op, e, at),
            CaseItem::Range(lo, hi, at) => Expr {
                kind: ExprKind::Binary(
                    BinOp::And,
                    Box::new(compare(BinOp::Ge, lo, at)),
                    Box::new(compare(BinOp::Le, hi, at)),
                ),
                span: at,
            },
        };
        test = Some(match test {
            None => one,
            Some(t) => {
                let at = Span::new(t.span.start, one.span.end);
                Expr {
                    kind: ExprKind::Binary(BinOp::Or, Box::new(t), Box::new(one)),
                    span: at,
                }
            }
        });
    }
    test.unwrap_or(Expr {
        kind: ExprKind::Bool(false),
        span,
    })
}

/// Whether `e` is a string, as far as its words tell before the checker types it: a string
/// literal, a `$` name, variable or function (`LEFT$`), an unsuffixed variable of a `DEFSTR`
/// letter (`strings`), a string controller variable, or a `+` of such.
fn string_valued(e: &Expr, strings: &[bool; 26]) -> bool {
    let typed_str = |text: &str| {
        let Some(first) = text.chars().next() else {
            return false;
        };
        text.ends_with('$')
            || (text.ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_')
                && first.is_ascii_alphabetic()
                && strings[(first.to_ascii_uppercase() as u8 - b'A') as usize])
    };
    match &e.kind {
        ExprKind::Str(_) => true,
        ExprKind::Name(n) => {
            let text = n.text();
            crate::registry::catalog::find_type(&n.segments[0].text).is_none()
                && crate::check::motionbasic::builtin(&text.to_ascii_uppercase()).is_none()
                && typed_str(&text)
        }
        ExprKind::Call(f, _) => match crate::check::motionbasic::controller(&f.text) {
            Some(c) => c.ty == crate::check::typed::Ty::Str,
            None => {
                f.text.ends_with('$')
                    || (crate::check::motionbasic::array_call(&f.text) && typed_str(&f.text))
            }
        },
        ExprKind::Binary(BinOp::Add, a, b) => {
            string_valued(a, strings) || string_valued(b, strings)
        }
        ExprKind::Paren(a) => string_valued(a, strings),
        _ => false,
    }
}

/// A tag of the program's text, in the names of the variables its `SELECT CASE`s make: the
/// variables are the machine's, shared by all its MotionBASIC programs, and two programs'
/// SELECTs running at once must not share one.
fn program_tag(src: &str) -> String {
    // FNV-1a: stable from run to run and build to build, unlike the std hasher.
    let hash = src.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{:06X}", hash & 0xFF_FFFF)
}

fn push_all(stack: &mut [Frame], top: &mut Vec<Stmt>, stmts: Vec<Stmt>) {
    for s in stmts {
        push(stack, top, s);
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
