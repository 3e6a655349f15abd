//! `DEFINT`/`DEFLNG`/`DEFSNG`/`DEFDBL`/`DEFSTR` (MotionBASIC): from the statement on, in source
//! order, a variable written without a type suffix whose first letter is in the statement's
//! ranges has that type. In Microsoft BASIC such a name *is* the suffixed variable (after
//! `DEFINT I`, `I` and `I%` are one variable), so this pass writes the suffix onto each such
//! name and every later stage sees the variable it means.
//!
//! Labels, subroutine names, functions, controller variables and objects of the machine keep
//! their names: only variables and arrays are typed.

use super::ast::{Expr, ExprKind, GearForm, MoveForm, Name, Place, PrintItem, Stmt, StmtKind};
use crate::diag::Problem;

/// The suffix each first letter gets, once a DEF statement has given one.
type Table = [Option<char>; 26];

/// Apply the program's DEF statements to the names after them; a range that is not letters
/// is reported.
pub fn apply(body: &mut [Stmt], problems: &mut Vec<Problem>) {
    if !any_def(body) {
        return;
    }
    let mut table: Table = [None; 26];
    stmts(body, &mut table, problems);
}

fn any_def(body: &[Stmt]) -> bool {
    body.iter().any(|s| match &s.kind {
        StmtKind::DefType { .. } => true,
        StmtKind::If {
            then_body,
            else_body,
            ..
        } => any_def(then_body) || else_body.as_deref().is_some_and(any_def),
        StmtKind::DoWhile { body, .. } | StmtKind::For { body, .. } => any_def(body),
        _ => false,
    })
}

fn letter(seg: &super::ast::Segment, problems: &mut Vec<Problem>) -> Option<usize> {
    let mut chars = seg.text.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) if c.is_ascii_alphabetic() => {
            Some((c.to_ascii_uppercase() as u8 - b'A') as usize)
        }
        _ => {
            problems.push(
                Problem::error(
                    "pacer::syntax::deftype",
                    seg.span,
                    format!("`{}` is not a letter", seg.text),
                    "one letter, or a range such as I-N",
                )
                .with_help("DEFINT I-N types every variable whose name starts with I to N"),
            );
            None
        }
    }
}

fn stmts(body: &mut [Stmt], table: &mut Table, problems: &mut Vec<Problem>) {
    for s in body {
        match &mut s.kind {
            StmtKind::DefType { suffix, ranges } => {
                for (from, to) in ranges.iter() {
                    let Some(a) = letter(from, problems) else {
                        continue;
                    };
                    let b = match to {
                        Some(to) => match letter(to, problems) {
                            Some(b) => b,
                            None => continue,
                        },
                        None => a,
                    };
                    for entry in table.iter_mut().take(a.max(b) + 1).skip(a.min(b)) {
                        *entry = Some(*suffix);
                    }
                }
            }
            StmtKind::Assign { target, value } => {
                name(target, table);
                expr(value, table);
            }
            StmtKind::Const(items) => {
                for (n, v) in items {
                    name(n, table);
                    expr(v, table);
                }
            }
            StmtKind::SetCall {
                target,
                args,
                value,
            } => {
                if is_variable_call(&target.text) {
                    seg_text(&mut target.text, table);
                }
                args.iter_mut().for_each(|a| expr(a, table));
                expr(value, table);
            }
            StmtKind::If {
                cond,
                then_body,
                else_body,
            } => {
                expr(cond, table);
                stmts(then_body, table, problems);
                if let Some(e) = else_body {
                    stmts(e, table, problems);
                }
            }
            StmtKind::DoWhile { cond, body } => {
                expr(cond, table);
                stmts(body, table, problems);
            }
            StmtKind::For {
                var,
                from,
                to,
                step,
                body,
            } => {
                name(var, table);
                expr(from, table);
                expr(to, table);
                if let Some(st) = step {
                    expr(st, table);
                }
                stmts(body, table, problems);
            }
            StmtKind::Gear { axis, form } => {
                expr(axis, table);
                match form {
                    GearForm::At {
                        out,
                        inn,
                        pacer,
                        after,
                    } => {
                        expr(out, table);
                        expr(inn, table);
                        pacer
                            .iter_mut()
                            .chain(after.iter_mut())
                            .for_each(|e| expr(e, table));
                    }
                    GearForm::For { dist, pacer } => {
                        expr(dist, table);
                        expr(pacer, table);
                    }
                }
            }
            StmtKind::Move { axis, form } => {
                expr(axis, table);
                match form {
                    MoveForm::At { speed, time } => {
                        expr(speed, table);
                        time.iter_mut().for_each(|e| expr(e, table));
                    }
                    MoveForm::Position {
                        target,
                        speed,
                        time,
                        ..
                    } => {
                        expr(target, table);
                        speed
                            .iter_mut()
                            .chain(time.iter_mut())
                            .for_each(|e| expr(e, table));
                    }
                }
            }
            StmtKind::WaitFor(e)
            | StmtKind::WaitTime(e)
            | StmtKind::DwellTime(e, _)
            | StmtKind::DwellMaster(e, _) => expr(e, table),
            StmtKind::Print(items) => {
                for item in items {
                    if let PrintItem::Expr(e) = item {
                        expr(e, table);
                    }
                }
            }
            StmtKind::PrintUsing(format, items) => {
                expr(format, table);
                for item in items {
                    if let PrintItem::Expr(e) = item {
                        expr(e, table);
                    }
                }
            }
            StmtKind::Dim(arrays) => {
                for (seg, bounds) in arrays {
                    seg_text(&mut seg.text, table);
                    bounds.iter_mut().for_each(|e| expr(e, table));
                }
            }
            StmtKind::Read(places) => places.iter_mut().for_each(|p| place(p, table)),
            StmtKind::Swap(a, b) => {
                place(a, table);
                place(b, table);
            }
            StmtKind::Randomize(e) => e.iter_mut().for_each(|e| expr(e, table)),
            StmtKind::Action { .. }
            | StmtKind::Call(_)
            | StmtKind::Label(_)
            | StmtKind::Goto(_)
            | StmtKind::Exit { .. }
            | StmtKind::Gosub(_)
            | StmtKind::Return
            | StmtKind::End
            | StmtKind::Data(_)
            | StmtKind::Restore(_)
            | StmtKind::OptionBase(_) => {}
        }
    }
}

fn place(p: &mut Place, table: &Table) {
    match p {
        Place::Var(n) => name(n, table),
        Place::Element(seg, args, _) => {
            seg_text(&mut seg.text, table);
            args.iter_mut().for_each(|a| expr(a, table));
        }
    }
}

fn expr(e: &mut Expr, table: &Table) {
    match &mut e.kind {
        ExprKind::Name(n) => name(n, table),
        ExprKind::Unary(_, a) | ExprKind::Paren(a) => expr(a, table),
        ExprKind::Binary(_, a, b) => {
            expr(a, table);
            expr(b, table);
        }
        ExprKind::Call(f, args) => {
            if is_variable_call(&f.text) {
                seg_text(&mut f.text, table);
            }
            args.iter_mut().for_each(|a| expr(a, table));
        }
        ExprKind::AxisSet(items) => items.iter_mut().for_each(|a| expr(a, table)),
        ExprKind::Number(..) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
    }
}

use crate::check::motionbasic::array_call as is_variable_call;

/// Names that read a value of the machine rather than a variable (`RND`, `TIMER`).
fn is_builtin_name(text: &str) -> bool {
    crate::check::motionbasic::builtin(text).is_some()
}

/// A one-segment name that is a variable: suffixed by the table when it has no suffix.
fn name(n: &mut Name, table: &Table) {
    // Dotted names are variables too (`PLEN.TMP`), unless the machine's catalog has an object
    // of that type (`Queue.0.QueueEmpty`).
    let Some(first) = n.segments.first().and_then(|s| s.text.chars().next()) else {
        return;
    };
    if crate::registry::catalog::find_type(&n.segments[0].text).is_some()
        || is_builtin_name(&n.text())
    {
        return;
    }
    // The suffix is not written in the source: the name's span stays what was written.
    if let Some(last) = n.segments.last_mut() {
        if let Some(suffix) = suffix_for(first, &last.text, table) {
            last.text.push(suffix);
        }
    }
}

fn seg_text(text: &mut String, table: &Table) {
    if let Some(suffix) = text.chars().next().and_then(|f| suffix_for(f, text, table)) {
        text.push(suffix);
    }
}

/// The suffix a name starting with `first` and ending as `text` does gets, if any.
fn suffix_for(first: char, text: &str, table: &Table) -> Option<char> {
    let last = text.chars().last()?;
    if !(last.is_ascii_alphanumeric() || last == '_') || !first.is_ascii_alphabetic() {
        return None;
    }
    table[(first.to_ascii_uppercase() as u8 - b'A') as usize]
}
