//! `CONST name = value, …` (MotionBASIC, as QuickBASIC writes it): each name is bound once to
//! a constant value, made of numbers, strings, other CONSTs declared before it and operators.
//! The statement becomes assignments of its values where it is written, so the checker and the
//! compiler see variables they know; this pass refuses what would make a CONST vary: a value
//! that is not constant, and any other assignment to the name (`LET`, `READ`, a `FOR` counter,
//! `SWAP`, the `MID$` statement, a second `CONST`), "Duplicate definition" in Microsoft
//! BASIC's words, and a read written above the `CONST` (which would find 0).
//!
//! It runs after `syntax::deftype`, so a name is compared with the suffix a DEF statement gave
//! it (after `DEFINT N`, `N` and `N%` are one CONST). A `DIM` bound may name a CONST declared
//! before it (`DIM A(N%)`, as QuickBASIC allows): its value is written in there, since pacer
//! sizes arrays before the run.

use super::ast::{Expr, ExprKind, GearForm, MoveForm, Name, Place, PrintItem, Stmt, StmtKind};
use crate::diag::Problem;
use crate::span::{LineIndex, Span};
use indexmap::IndexMap;
use std::collections::{HashMap, HashSet};

/// Check the program's CONSTs and make each an assignment of its value.
pub fn apply(body: &mut Vec<Stmt>, src: &str, problems: &mut Vec<Problem>) {
    let mut consts = IndexMap::new();
    collect(body, &mut consts);
    if consts.is_empty() {
        return;
    }
    let index = LineIndex::new(src);
    let mut pass = Pass {
        consts,
        declared: HashSet::new(),
        values: HashMap::new(),
        index: &index,
        problems,
    };
    pass.stmts(body);
}

/// The name a CONST or an assignment names, as compared (Microsoft BASIC names ignore case).
fn key(n: &Name) -> String {
    n.text().to_ascii_uppercase()
}

/// Each CONST name and where its first CONST names it, in source order.
fn collect(body: &[Stmt], consts: &mut IndexMap<String, Span>) {
    for s in body {
        match &s.kind {
            StmtKind::Const(items) => {
                for (n, _) in items {
                    consts.entry(key(n)).or_insert(n.span);
                }
            }
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => {
                collect(then_body, consts);
                if let Some(e) = else_body {
                    collect(e, consts);
                }
            }
            StmtKind::DoWhile { body, .. } | StmtKind::For { body, .. } => collect(body, consts),
            _ => {}
        }
    }
}

struct Pass<'a> {
    /// Every CONST of the program and where it is declared.
    consts: IndexMap<String, Span>,
    /// Those whose CONST the walk has passed, in source order.
    declared: HashSet<String>,
    /// The values of those declared without error, CONSTs in them written out.
    values: HashMap<String, Expr>,
    index: &'a LineIndex,
    problems: &'a mut Vec<Problem>,
}

impl Pass<'_> {
    fn stmts(&mut self, body: &mut Vec<Stmt>) {
        for mut s in std::mem::take(body) {
            // A CONST read above its CONST would find 0: QuickBASIC refuses it too.
            for e in heads(&s.kind) {
                self.early_reads(e);
            }
            match &mut s.kind {
                StmtKind::Const(items) => {
                    for (n, v) in std::mem::take(items) {
                        let k = key(&n);
                        let before = self.problems.len();
                        self.value(&v);
                        if self.problems.len() == before && !self.values.contains_key(&k) {
                            let mut written = v.clone();
                            self.inline(&mut written);
                            self.values.insert(k.clone(), written);
                        }
                        let first = self.consts.get(&k).copied();
                        if self.declared.contains(&k) || first.is_some_and(|at| at != n.span) {
                            self.duplicate(&n, "a second CONST of it");
                        }
                        self.declared.insert(k);
                        body.push(Stmt {
                            kind: StmtKind::Assign {
                                target: n,
                                value: v,
                            },
                            span: s.span,
                        });
                    }
                    continue;
                }
                StmtKind::Assign { target, .. } => self.write(target, "assigned here"),
                StmtKind::For { var, body, .. } => {
                    self.write(var, "counts this FOR");
                    self.stmts(body);
                }
                StmtKind::Read(places) => {
                    for p in places.iter() {
                        if let Place::Var(n) = p {
                            self.write(n, "read into here");
                        }
                    }
                }
                StmtKind::Swap(a, b) => {
                    for p in [&*a, &*b] {
                        if let Place::Var(n) = p {
                            self.write(n, "swapped here");
                        }
                    }
                }
                StmtKind::SetCall { target, args, .. }
                    if target.text.eq_ignore_ascii_case("MID$") =>
                {
                    if let Some(Expr {
                        kind: ExprKind::Name(n),
                        ..
                    }) = args.first()
                    {
                        self.write(n, "changed here");
                    }
                }
                StmtKind::If {
                    then_body,
                    else_body,
                    ..
                } => {
                    self.stmts(then_body);
                    if let Some(e) = else_body {
                        self.stmts(e);
                    }
                }
                StmtKind::DoWhile { body, .. } => self.stmts(body),
                StmtKind::Dim(arrays) => {
                    for (_, bounds) in arrays.iter_mut() {
                        bounds.iter_mut().for_each(|b| self.inline(b));
                    }
                }
                _ => {}
            }
            body.push(s);
        }
    }

    /// The CONSTs `e` reads before their CONST, reported.
    fn early_reads(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Name(n) => {
                let k = key(n);
                if let (false, Some(at)) = (self.declared.contains(&k), self.consts.get(&k)) {
                    let line = self.index.line(at.start);
                    self.problems.push(
                        Problem::error(
                            "pacer::check::const",
                            n.span,
                            format!("{} is used before its CONST at line {line}", n.text()),
                            "declared later",
                        )
                        .with_help("declare CONSTs at the top of the program, before their use"),
                    );
                }
            }
            ExprKind::Unary(_, a) | ExprKind::Paren(a) => self.early_reads(a),
            ExprKind::Binary(_, a, b) => {
                self.early_reads(a);
                self.early_reads(b);
            }
            ExprKind::Call(_, args) | ExprKind::AxisSet(args) => {
                args.iter().for_each(|a| self.early_reads(a));
            }
            ExprKind::Number(..) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
        }
    }

    /// `e` with the CONSTs declared so far written out as their values.
    fn inline(&self, e: &mut Expr) {
        match &mut e.kind {
            ExprKind::Name(n) => {
                if let Some(v) = self.values.get(&key(n)) {
                    e.kind = ExprKind::Paren(Box::new(v.clone()));
                }
            }
            ExprKind::Unary(_, a) | ExprKind::Paren(a) => self.inline(a),
            ExprKind::Binary(_, a, b) => {
                self.inline(a);
                self.inline(b);
            }
            ExprKind::Call(_, args) | ExprKind::AxisSet(args) => {
                args.iter_mut().for_each(|a| self.inline(a));
            }
            ExprKind::Number(..) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
        }
    }

    /// `n` stored into outside its CONST: refused when it is a CONST.
    fn write(&mut self, n: &Name, label: &str) {
        if self.consts.contains_key(&key(n)) {
            self.duplicate(n, label);
        }
    }

    fn duplicate(&mut self, n: &Name, label: &str) {
        let line = self
            .consts
            .get(&key(n))
            .map_or(0, |at| self.index.line(at.start));
        self.problems.push(
            Problem::error(
                "pacer::check::const",
                n.span,
                format!("Duplicate definition: {} is a CONST", n.text()),
                label.to_string(),
            )
            .with_help(format!(
                "the CONST at line {line} gives it its one value: use another variable here"
            )),
        );
    }

    /// A CONST's value: numbers, strings, CONSTs declared before it, operators.
    fn value(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Number(..) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
            ExprKind::Unary(_, a) | ExprKind::Paren(a) => self.value(a),
            ExprKind::Binary(_, a, b) => {
                self.value(a);
                self.value(b);
            }
            ExprKind::Name(n) => {
                let k = key(n);
                if self.declared.contains(&k) {
                    return;
                }
                let (message, label) = match self.consts.get(&k) {
                    Some(at) => (
                        format!(
                            "{} is used before its CONST at line {}",
                            n.text(),
                            self.index.line(at.start)
                        ),
                        "declared later",
                    ),
                    None => (
                        format!("a CONST's value cannot read the variable {}", n.text()),
                        "not a constant",
                    ),
                };
                self.not_constant(e.span, message, label);
            }
            ExprKind::Call(f, _) => {
                let message = format!("a CONST's value cannot call {}", f.text);
                self.not_constant(e.span, message, "not a constant");
            }
            ExprKind::AxisSet(_) => self.not_constant(
                e.span,
                "a CONST's value cannot be an axis set",
                "an axis set",
            ),
        }
    }

    fn not_constant(&mut self, span: Span, message: impl Into<String>, label: &str) {
        self.problems.push(
            Problem::error(
                "pacer::check::const",
                span,
                message.into(),
                label.to_string(),
            )
            .with_help(
                "a CONST's value is made of numbers, strings, CONSTs declared before it and \
                 operators, as in QuickBASIC",
            ),
        );
    }
}

/// The subscripts of an element stored into.
fn place(p: &Place) -> Vec<&Expr> {
    match p {
        Place::Var(_) => Vec::new(),
        Place::Element(_, args, _) => args.iter().collect(),
    }
}

/// The values a PRINT prints.
fn items(items: &[PrintItem]) -> Vec<&Expr> {
    items
        .iter()
        .filter_map(|i| match i {
            PrintItem::Expr(e) => Some(e),
            _ => None,
        })
        .collect()
}

/// The expressions a statement computes itself (a block's head, not its body; a CONST's
/// values are checked as such).
fn heads(kind: &StmtKind) -> Vec<&Expr> {
    match kind {
        StmtKind::Assign { value, .. } => vec![value],
        StmtKind::DwellTime(e, _)
        | StmtKind::DwellMaster(e, _)
        | StmtKind::WaitTime(e)
        | StmtKind::WaitFor(e)
        | StmtKind::If { cond: e, .. }
        | StmtKind::DoWhile { cond: e, .. }
        | StmtKind::OptionBase(e) => vec![e],
        StmtKind::For { from, to, step, .. } => {
            let mut v = vec![from, to];
            v.extend(step.as_ref());
            v
        }
        StmtKind::SetCall { args, value, .. } => args.iter().chain([value]).collect(),
        StmtKind::Gear { axis, form } => {
            let mut v = vec![axis];
            match form {
                GearForm::At {
                    out,
                    inn,
                    pacer,
                    after,
                } => {
                    v.extend([out, inn]);
                    v.extend(pacer.iter().chain(after.iter()));
                }
                GearForm::For { dist, pacer } => v.extend([dist, pacer]),
            }
            v
        }
        StmtKind::Move { axis, form } => {
            let mut v = vec![axis];
            match form {
                MoveForm::At { speed, time } => {
                    v.push(speed);
                    v.extend(time.iter());
                }
                MoveForm::Position {
                    target,
                    speed,
                    time,
                    ..
                } => {
                    v.push(target);
                    v.extend(speed.iter().chain(time.iter()));
                }
            }
            v
        }
        StmtKind::Print(list) => items(list),
        StmtKind::PrintUsing(format, list) => {
            let mut v = vec![format];
            v.extend(items(list));
            v
        }
        StmtKind::Dim(arrays) => arrays.iter().flat_map(|(_, b)| b.iter()).collect(),
        StmtKind::Read(places) => places.iter().flat_map(place).collect(),
        StmtKind::Swap(a, b) => place(a).into_iter().chain(place(b)).collect(),
        StmtKind::Randomize(e) => e.iter().collect(),
        StmtKind::Const(_)
        | StmtKind::Action { .. }
        | StmtKind::Call(_)
        | StmtKind::Label(_)
        | StmtKind::Goto(_)
        | StmtKind::Exit { .. }
        | StmtKind::End
        | StmtKind::Gosub(_)
        | StmtKind::Return
        | StmtKind::Data(_)
        | StmtKind::Restore(_)
        | StmtKind::DefType { .. } => Vec::new(),
    }
}
